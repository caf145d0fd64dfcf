//! The loader's top layer: what each worker's messages and errors do. A load's answers go to the take's loads
//! ([`take`]); an answer about a run goes to the feature that sent it, by run id, after the pool frees the worker
//! of a run's last answer; a run that needs a shipped model file waits for it ([`shipped`]); a worker whose wasm
//! trapped, or that died, is replaced — the main worker with everything it was doing (the pending load, its run,
//! and each feature's requests, [`Jobs::resend`]).

use crate::app::loader::jobs::{AfterDeath, Jobs};
use crate::app::loader::transport::{features, route, spawn_main, Inner};
use crate::app::loader::{pool, shipped, take};
use crate::protocol::{FailureKind, Response, RunId};
use crate::worker::pool::Slot;
use crate::worker::response_from_js;
use std::rc::Rc;
use wasm_bindgen::prelude::*;
use web_sys::Event;

/// A message from worker `slot`.
pub(super) fn on_message(inner: &Rc<Inner>, slot: Slot, data: JsValue) {
    if slot > 0 {
        return on_run_worker_message(inner, slot, data);
    }
    let response = match response_from_js(&data) {
        Ok(r) => r,
        Err(message) => return take::fail_load(inner, inner.current.get(), message),
    };
    if let Response::Failed { take, run: None, message, kind, .. } = response {
        take::fail_load(inner, take, message);
        if kind == FailureKind::Internal {
            replace_main(inner);
        }
        return;
    }
    if let Some(response) = take::on_load_reply(inner, response) {
        answer(inner, 0, response);
    }
}

/// A message from run worker `slot`: only answers about the run it is busy with count.
fn on_run_worker_message(inner: &Rc<Inner>, slot: Slot, data: JsValue) {
    let Ok(response) = response_from_js(&data) else { return };
    let run = match &response {
        Response::Progress { run: Some(run), .. }
        | Response::Segmented { run, .. }
        | Response::Refused { run, .. }
        | Response::NeedsModel { run, .. }
        | Response::Failed { run: Some(run), .. }
        | Response::LibraryTake { run, .. } => *run,
        _ => return, // the take's and the models' acknowledgements: the main worker answers for those
    };
    if !inner.pool.borrow().accepts(slot, run) {
        return; // stale: the run was stopped or moved
    }
    answer(inner, slot, response);
}

/// Whether `response` is the last answer about its run from the worker that runs it (a result, a refusal, a
/// failure, or a wait for a model file, after which the run is asked again): the pool frees the worker. A worker
/// that lost the take (`not_loaded`) is asked again by the run's feature — unless nobody wants the run any longer.
fn is_last(response: &Response, wanted: bool) -> bool {
    match response {
        Response::Failed { kind: FailureKind::NotLoaded, .. } => !wanted,
        Response::Segmented { .. }
        | Response::NeedsModel { .. }
        | Response::Refused { .. }
        | Response::LibraryTake { .. }
        | Response::Failed { .. } => true,
        _ => false,
    }
}

/// An answer from worker `slot` (0: the main worker) about a run: the worker freed after the run's last answer,
/// the answer handed to the feature that sent the run (a wait for a model file to the shipped models), and a
/// worker whose wasm trapped replaced.
fn answer(inner: &Rc<Inner>, slot: Slot, response: Response) {
    let Some(run) = response.run_id() else { return };
    let jobs = route(inner, run);
    if is_last(&response, jobs.is_some()) {
        pool::release(inner, slot, run);
    }
    let trapped = matches!(response, Response::Failed { kind: FailureKind::Internal, .. });
    match (response, jobs) {
        (Response::NeedsModel { run, file, .. }, _) => shipped::need_model(inner, run, file),
        (response, Some(jobs)) => jobs.reply(slot, response),
        (_, None) => {} // about a run nobody wants any longer
    }
    if trapped {
        replace_slot(inner, slot);
    }
}

/// An error of worker `slot` outside any request.
pub(super) fn on_error(inner: &Rc<Inner>, slot: Slot, event: Event) {
    event.prevent_default();
    if slot > 0 {
        return pool::died(inner, slot);
    }
    on_main_error(inner, event);
}

/// The main worker's script could not load, or it threw outside a request (out of memory, say). Under a run for
/// which its feature wants another try: replaced, the run asked again. Else the load and its run fail, every
/// feature is told ([`Jobs::worker_failed`]) and the worker is dropped (the next request starts a new one).
fn on_main_error(inner: &Rc<Inner>, event: Event) {
    // A script that fails to load fires a plain `Event`; an exception fires an `ErrorEvent`.
    let message = js_sys::Reflect::get(&event, &"message".into())
        .ok()
        .and_then(|m| m.as_string())
        .filter(|m| !m.is_empty())
        .unwrap_or_else(|| format!("could not load {}", inner.urls.worker));
    let failed = format!("the worker failed: {message}");
    let run = inner.pool.borrow().running(0);
    let jobs: Option<(RunId, Rc<dyn Jobs>)> = run.and_then(|run| route(inner, run).map(|jobs| (run, jobs)));
    if let Some((run, jobs)) = &jobs {
        if jobs.died(*run) == AfterDeath::RunAgain {
            web_sys::console::warn_1(&format!("the worker stopped ({message}): started again").into());
            return replace_main(inner);
        }
    }
    // dropped first: what is asked of the main worker from here on (the next waiting run, once the pool frees its
    // place) starts a new one
    inner.main.borrow_mut().take(); // terminates it
    take::fail_load(inner, inner.current.get(), failed.clone());
    // the run it was busy with fails (the run workers' go on)
    if let Some((run, jobs)) = jobs {
        inner.routes.borrow_mut().remove(&run);
        jobs.fail(run, failed.clone());
    }
    if let Some(run) = run {
        pool::release(inner, 0, run);
    }
    for jobs in features(inner) {
        jobs.worker_failed(&failed);
    }
}

/// Replaces worker `slot` (0: the main worker, with everything it was doing).
pub(super) fn replace_slot(inner: &Rc<Inner>, slot: Slot) {
    if slot == 0 {
        replace_main(inner);
    } else {
        pool::replace(inner, slot);
    }
}

/// A new main worker in place of the old one, given the work the old one had: the pending load, its run of the
/// pool (unless nobody wants it any longer, then the next waiting one), and each feature's requests.
pub(super) fn replace_main(inner: &Rc<Inner>) {
    spawn_main(inner);
    take::send_pending(inner);
    let run = inner.pool.borrow().running(0);
    let wanted = run.is_some_and(|run| route(inner, run).is_some());
    let next = inner.pool.borrow_mut().replaced(0, !wanted);
    if let Some(run) = next {
        pool::post_run(inner, run);
    }
    for jobs in features(inner) {
        jobs.resend();
    }
}
