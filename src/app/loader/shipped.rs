//! The shipped model files' jobs: a run that needs a file the worker does not hold waits for it;
//! the page fetches it once (with progress), hands it over and asks again; a new worker gets every
//! file fetched so far.

use crate::app::loader::post;
use crate::app::loader::{fail_run, next_id, route, run_index, send_run, Inner};
use crate::app::models::model_files;
use crate::app::state::RunState;
use crate::protocol::{Request, RunId};
use leptos::prelude::*;
use std::rc::{Rc, Weak};

/// Hands a worker just started every shipped model file the page fetched (a worker starts with
/// none), before any other request.
pub(super) fn send_model_files(inner: &Rc<Inner>) {
    for (file, bytes) in inner.models.all() {
        let run = next_id(inner);
        give_model(inner, run, &file, &bytes);
    }
}

/// Hands the shipped model file `file` to the worker; a refusal is the answer to `run`.
pub(super) fn give_model(inner: &Rc<Inner>, run: RunId, file: &str, bytes: &[u8]) {
    let take = inner.shown.borrow().as_ref().map_or(0, |t| t.id);
    let request = Request::ProvideModel { take, run, file: file.to_string(), bytes: bytes.to_vec(), unavailable: None };
    if let Err(message) = post(inner, &request, None) {
        fail_waiting(inner, run, message);
    }
}

/// The worker needs the shipped model file `file` for `run` (a method's run or an Effort bars'
/// annotation): fetched once, handed over, and `run` asked again.
pub(super) fn need_model(inner: &Rc<Inner>, run: RunId, file: String) {
    if run_index(inner, run).is_none() && route(inner, run).is_none() {
        return; // superseded
    }
    if let Some(bytes) = inner.models.held(&file) {
        // fetched while this worker was starting: hand it over and ask again
        give_model(inner, run, &file, &bytes);
        return ask_again(inner, run);
    }
    let size = crate::method::shipped::find(&file).map_or(0, |(_, f)| f.size);
    show_fetching(inner, run, &file, size, 0.0);
    if !inner.models.wait(run, &file) {
        return; // on its way
    }
    let url = inner.models.url(&file);
    let weak = Rc::downgrade(inner);
    wasm_bindgen_futures::spawn_local(async move {
        let progress = |fraction: f64| {
            if let Some(inner) = Weak::upgrade(&weak) {
                for run in inner.models.waiting_for(&file) {
                    show_fetching(&inner, run, &file, size, fraction);
                }
            }
        };
        let fetched = model_files::fetch(&url, size, progress).await;
        let Some(inner) = Weak::upgrade(&weak) else { return };
        match fetched {
            Ok(bytes) => {
                let bytes = Rc::new(bytes);
                for run in inner.models.arrived(&file, bytes.clone()) {
                    give_model(&inner, run, &file, &bytes);
                    ask_again(&inner, run);
                }
            }
            Err(message) => {
                // the worker is told why, and each run asked again: one that needs the file fails
                // with why, one that could do without it (a model a take fit offers) goes on
                let why = format!("could not fetch the model {url}: {message}");
                let take = inner.shown.borrow().as_ref().map_or(0, |t| t.id);
                for run in inner.models.take_waiting(&file) {
                    let refused = Request::ProvideModel {
                        take,
                        run,
                        file: file.clone(),
                        bytes: Vec::new(),
                        unavailable: Some(why.clone()),
                    };
                    match post(&inner, &refused, None) {
                        Ok(()) => ask_again(&inner, run),
                        Err(e) => fail_waiting(&inner, run, format!("{why} ({e})")),
                    }
                }
            }
        }
    });
}

/// Shows on whatever `run` is that `file` is coming.
pub(super) fn show_fetching(inner: &Inner, run: RunId, file: &str, size: u64, fraction: f64) {
    let stage = model_files::fetching_stage(file, size);
    if let Some(index) = run_index(inner, run) {
        inner.state.methods[index].run.set(RunState::Running { stage, fraction });
    } else if let Some(jobs) = route(inner, run) {
        jobs.stage(run, &stage, fraction);
    }
}

/// Sends `run` (a method's run or an annotation) again.
pub(super) fn ask_again(inner: &Rc<Inner>, run: RunId) {
    if let Some(index) = run_index(inner, run) {
        if let Err(message) = send_run(inner, index) {
            fail_run(inner, index, message);
        }
    } else if let Some(jobs) = route(inner, run) {
        jobs.send_again(run);
    }
}

/// `run` cannot have its model file.
pub(super) fn fail_waiting(inner: &Rc<Inner>, run: RunId, message: String) {
    if let Some(index) = run_index(inner, run) {
        fail_run(inner, index, message);
    } else if let Some(jobs) = route(inner, run) {
        jobs.fail(run, message);
    }
}
