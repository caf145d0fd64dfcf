//! The page's other workers: the run workers of the pool ([`crate::worker::pool`] decides; this
//! carries it out). The main worker (`Inner::worker`, slot 0) loads the take, trains, annotates and
//! cuts clips as before; the run workers, one per further core, only run methods. Each is handed the
//! take on screen as the motion the main worker made of it (`hold`: parsed once, not once per
//! worker), every model file the page holds (shipped or the user's, as the main worker gets them),
//! and then one method's run at a time. Their answers about anything but the run they are busy with
//! (the models' and the take's acknowledgements, a stale run's result) are dropped: the main worker
//! answers for the models.
//!
//! A run worker that traps fails its run (the same run would trap again) and is replaced; one that
//! dies without saying which run (its script failed, it ran out of memory) is replaced and its run
//! asked again once. Cancelling a run replaces the worker that runs it, and a new take replaces every
//! run worker still busy with the old take's runs, so that none computes a result nobody reads.

use std::rc::{Rc, Weak};

use js_sys::Array;
use leptos::prelude::*;
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;
use web_sys::{Event, MessageEvent, Worker, WorkerOptions, WorkerType};

use crate::app::dom::js_message;
use crate::app::loader::{fail_run, next_id, on_run_response, run_index, send_run, Handler, Inner};
use crate::protocol::{Request, Response, RunId};
use crate::worker::pool::Slot;
use crate::worker::{packet_to_js, response_from_js};

/// A run worker of the pool and the handlers that keep its messages flowing.
pub(super) struct RunWorker {
    worker: Worker,
    _handlers: [Handler; 2],
}

impl Drop for RunWorker {
    fn drop(&mut self) {
        self.worker.terminate();
    }
}

/// How many workers this page starts: the root element's `data-workers` when it gives a number (an
/// embedding page may want one), else one per logical processor the browser reports
/// ([`crate::worker::pool::workers_for`]: at least two, at most four).
pub(super) fn workers(root_workers: Option<usize>) -> usize {
    if let Some(n) = root_workers {
        return n.clamp(1, crate::worker::pool::MAX_WORKERS);
    }
    let cores = js_sys::Reflect::get(&js_sys::global(), &"navigator".into())
        .and_then(|n| js_sys::Reflect::get(&n, &"hardwareConcurrency".into()))
        .ok()
        .and_then(|c| c.as_f64())
        .map_or(0, |c| c as usize);
    crate::worker::pool::workers_for(cores)
}

/// Starts run worker `slot` (1…), replacing the one there: gives it the compiled wasm, every model
/// file the page holds and the take on screen.
pub(super) fn spawn(inner: &Rc<Inner>, slot: Slot) {
    let options = WorkerOptions::new();
    options.set_type(WorkerType::Module);
    let worker = match Worker::new_with_options(&inner.urls.worker, &options) {
        Ok(worker) => worker,
        Err(e) => {
            // the pool goes on with the workers it has
            web_sys::console::warn_1(&format!("a run worker could not be started: {}", js_message(&e)).into());
            return out_of_pool(inner, slot);
        }
    };
    let weak = Rc::downgrade(inner);
    let on_message = Handler::new(move |event: JsValue| {
        if let Some(inner) = Weak::upgrade(&weak) {
            on_message(&inner, slot, event.unchecked_into::<MessageEvent>().data());
        }
    });
    let weak = Rc::downgrade(inner);
    let on_error = Handler::new(move |event: JsValue| {
        if let Some(inner) = Weak::upgrade(&weak) {
            let event: Event = event.unchecked_into();
            event.prevent_default();
            died(&inner, slot);
        }
    });
    worker.set_onmessage(Some(on_message.as_ref().unchecked_ref()));
    worker.set_onerror(Some(on_error.as_ref().unchecked_ref()));
    crate::app::loader::give_compiled_wasm(&worker);
    inner.helpers.borrow_mut()[slot - 1] = Some(RunWorker { worker, _handlers: [on_message, on_error] });
    for request in models(inner) {
        let _ = post_to(inner, slot, request);
    }
    hold(inner, slot);
    let waiting = inner.pool.borrow_mut().up(slot);
    if let Some(run) = waiting {
        post_run(inner, run);
    }
}

/// Run worker `slot` is out of the pool (terminated, not replaced): its run is asked of another.
fn out_of_pool(inner: &Rc<Inner>, slot: Slot) {
    inner.helpers.borrow_mut()[slot - 1] = None; // terminates it
    let run = inner.pool.borrow_mut().down(slot);
    if let Some(run) = run {
        post_run(inner, run);
    }
}

/// The model files the page holds, as the requests that give them to a new run worker: the shipped
/// ones fetched so far and the user's (their answers are the main worker's to give).
fn models(inner: &Rc<Inner>) -> Vec<Request> {
    let take = inner.shown.borrow().as_ref().map_or(0, |t| t.id);
    let mut requests = Vec::new();
    for (file, bytes) in inner.models.all() {
        requests.push(Request::ProvideModel {
            take,
            run: next_id(inner),
            file,
            bytes: bytes.to_vec(),
            unavailable: None,
        });
    }
    for slot in inner.state.methods {
        let Some(s) = slot.supervised.as_ref() else { continue };
        for m in s.models.get_untracked() {
            requests.push(Request::UseModel {
                take,
                run: next_id(inner),
                method: slot.info.name.clone(),
                file: m.file.clone(),
                bytes: (*m.bytes).clone(),
            });
        }
    }
    requests
}

/// Hands run worker `slot` the take on screen (the main worker's motion of it), if there is one.
pub(super) fn hold(inner: &Rc<Inner>, slot: Slot) {
    let Some(take) = inner.shown.borrow().as_ref().map(|t| t.id) else { return };
    let Some(motion) = inner.state.motion.get_untracked() else { return };
    let _ = post_to(inner, slot, Request::Hold { take, motion: Box::new(motion.motion()) });
}

/// Hands every run worker the take now on screen, replacing those still busy with the old take's
/// runs (the new take's runs are not asked yet: the page asks them once every worker has it).
pub(super) fn new_take(inner: &Rc<Inner>) {
    // the library's takes are not the take on screen's: they go on
    let stale = inner.pool.borrow_mut().supersede(|run| crate::app::loader::library::owns(inner, run));
    let workers = inner.pool.borrow().workers();
    for slot in 1..workers {
        if stale.contains(&slot) {
            replace(inner, slot);
        } else {
            hold(inner, slot);
        }
    }
}

/// Posts `request` to worker `slot` (0: the main worker), its buffers transferred.
pub(super) fn post_to(inner: &Rc<Inner>, slot: Slot, request: Request) -> Result<(), String> {
    if slot == 0 {
        return crate::app::loader::post_request(inner, request);
    }
    let helpers = inner.helpers.borrow();
    let worker = helpers.get(slot - 1).and_then(Option::as_ref).ok_or("the worker could not be started")?;
    let (message, transfer): (JsValue, Array) = packet_to_js(request.into_packet());
    worker.worker.post_message_with_transfer(&message, &transfer).map_err(|e| js_message(&e))
}

/// Posts `request` to worker `slot` with `buffers` (a library take's files) transferred.
pub(super) fn post_buffers_to(inner: &Rc<Inner>, slot: Slot, request: &Request, buffers: Array) -> Result<(), String> {
    if slot == 0 {
        return crate::app::loader::post_buffers(inner, request, buffers);
    }
    let helpers = inner.helpers.borrow();
    let worker = helpers.get(slot - 1).and_then(Option::as_ref).ok_or("the worker could not be started")?;
    let (message, transfer) = crate::worker::request_with_buffers(request, buffers);
    worker.worker.post_message_with_transfer(&message, &transfer).map_err(|e| js_message(&e))
}

/// Whether the page still wants run `run`: a row's current run, or a take of the library under way.
pub(super) fn wanted(inner: &Inner, run: RunId) -> bool {
    run_index(inner, run).is_some() || crate::app::loader::library::owns(inner, run)
}

/// Gives every run worker a model file the main worker is given too (its answers are the main
/// worker's to give).
pub(super) fn share_model(inner: &Rc<Inner>, request: &Request) {
    if !matches!(request, Request::UseModel { .. } | Request::ProvideModel { .. }) {
        return;
    }
    let workers = inner.pool.borrow().workers();
    for slot in 1..workers {
        if inner.helpers.borrow().get(slot - 1).is_some_and(Option::is_some) {
            let _ = post_to(inner, slot, request.clone());
        }
    }
}

/// Replaces run worker `slot` and posts it the run the pool gives it: its own run again if the page
/// still wants it (not cancelled, failed or of an old take), else the oldest waiting run.
pub(super) fn replace(inner: &Rc<Inner>, slot: Slot) {
    inner.helpers.borrow_mut()[slot - 1] = None; // terminates it
    spawn(inner, slot);
    let wanted = inner.pool.borrow().running(slot).is_some_and(|run| wanted(inner, run));
    let next = inner.pool.borrow_mut().replaced(slot, !wanted);
    if let Some(run) = next {
        post_run(inner, run);
    }
}

/// Posts run `run` (a method's current run, or a take of the library) to the worker the pool gave
/// it; a run the page no longer wants frees its worker for the next.
pub(super) fn post_run(inner: &Rc<Inner>, run: RunId) {
    match run_index(inner, run) {
        Some(index) => {
            if let Err(message) = send_run(inner, index) {
                fail_run(inner, index, message);
            }
        }
        None if crate::app::loader::library::post_run(inner, run) => {}
        None => {
            let slot = inner.pool.borrow().slot_of(run);
            if let Some(slot) = slot {
                release(inner, slot, run);
            }
        }
    }
}

/// Worker `slot` is done with `run` (its last answer came, or the run ended on the page): the next
/// waiting run goes to it.
pub(super) fn release(inner: &Rc<Inner>, slot: Slot, run: RunId) {
    let next = inner.pool.borrow_mut().finished(slot, run);
    if let Some(next) = next {
        post_run(inner, next);
    }
}

/// Frees whichever worker runs `run` (a run that ended on the page: failed, refused).
pub(super) fn release_run(inner: &Rc<Inner>, run: RunId) {
    let slot = inner.pool.borrow().slot_of(run);
    if let Some(slot) = slot {
        release(inner, slot, run);
    }
}

/// A run worker died without an answer (`onerror`: its script failed to load, or it ran out of
/// memory). Busy with a run for the first time: replaced, and the run asked again on the new worker.
/// Idle (a script that cannot load would fail again, and again), or dying under the same run twice:
/// the run fails and the slot stays empty — its runs go to the main worker.
fn died(inner: &Rc<Inner>, slot: Slot) {
    let run = inner.pool.borrow().running(slot);
    if let Some(run) = run.filter(|&run| crate::app::loader::library::owns(inner, run)) {
        // a take of the library: it fails, naming why; the worker is replaced for the next
        crate::app::loader::library::died(inner, run);
        return replace(inner, slot);
    }
    let index = run.and_then(|run| run_index(inner, run));
    let again = index.is_some_and(|index| crate::app::loader::first_time(inner, index, |r| &mut r.crashed));
    if again {
        return replace(inner, slot);
    }
    if let Some(index) = index {
        fail_run(inner, index, "the worker running it stopped twice (out of memory?)".into());
    }
    out_of_pool(inner, slot);
}

/// A message from run worker `slot`: only answers about the run it is busy with count.
fn on_message(inner: &Rc<Inner>, slot: Slot, data: JsValue) {
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
        return; // stale: the run was cancelled or moved
    }
    if crate::app::loader::library::owns(inner, run) {
        let _ = crate::app::loader::library::handle(inner, response);
        return;
    }
    on_run_response(inner, slot, response);
}

/// Run worker `slot` does not hold the take of method `index`'s run: it is handed the take
/// again and asked once more; failed the second time.
pub(super) fn not_loaded(inner: &Rc<Inner>, slot: Slot, index: usize, message: String) {
    let first = crate::app::loader::first_time(inner, index, |r| &mut r.retried);
    if !first {
        return fail_run(inner, index, message);
    }
    hold(inner, slot);
    if let Err(e) = send_run(inner, index) {
        fail_run(inner, index, format!("{message} ({e})"));
    }
}
