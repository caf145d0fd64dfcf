//! The shipped model files: a run that needs a file the worker does not hold waits for it;
//! the page fetches it once (with progress), hands it over and has the run's feature ask again; a new worker gets
//! every file fetched so far ([`crate::app::loader::transport`]).

use crate::app::loader::transport::{post, route, shown_id, Inner};
use crate::app::models::model_files;
use crate::protocol::{Request, RunId};
use std::rc::{Rc, Weak};

/// Hands the shipped model file `file` to the worker; a refusal is the answer to `run`.
fn give_model(inner: &Rc<Inner>, run: RunId, file: &str, bytes: &[u8]) {
    let take = shown_id(inner);
    let request = Request::ProvideModel { take, run, file: file.to_string(), bytes: bytes.to_vec(), unavailable: None };
    if let Err(message) = post(inner, &request, None) {
        fail_waiting(inner, run, message);
    }
}

/// The worker needs the shipped model file `file` for `run` (a method's run or an Effort bars'
/// annotation): fetched once, handed over, and `run` asked again.
pub(super) fn need_model(inner: &Rc<Inner>, run: RunId, file: String) {
    match route(inner, run) {
        None => return, // superseded
        Some(jobs) if !jobs.needs_model(run, &file) => return,
        Some(_) => {}
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
                let take = shown_id(&inner);
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
fn show_fetching(inner: &Inner, run: RunId, file: &str, size: u64, fraction: f64) {
    if let Some(jobs) = route(inner, run) {
        jobs.stage(run, &model_files::fetching_stage(file, size), fraction);
    }
}

/// Has `run`'s feature send it again.
fn ask_again(inner: &Rc<Inner>, run: RunId) {
    if let Some(jobs) = route(inner, run) {
        jobs.send_again(run);
    }
}

/// `run` cannot have its model file.
fn fail_waiting(inner: &Rc<Inner>, run: RunId, message: String) {
    if let Some(jobs) = route(inner, run) {
        jobs.fail(run, message);
    }
}
