//! The loader's state and its lowest layer: the workers it started (the main worker, slot 0, and the pool's run
//! workers), posting a request to one of them, starting one, the route of each run to the feature that sent it,
//! and the take each load made. Nothing here knows a page feature: features are [`Jobs`] behind run ids, and a
//! worker's messages go to the handlers the loader was built with ([`Inner::on_message`], [`Inner::on_error`]), so
//! that this layer calls no layer above it.

use crate::app::dom::js_message;
use crate::app::loader::jobs::Jobs;
use crate::app::loader::urls::Urls;
use crate::app::models::model_files::ModelFiles;
use crate::app::state::AppState;
use crate::protocol::{Request, RunId, TakeId};
use crate::worker::pool::{Pool, Slot};
use js_sys::{Array, ArrayBuffer};
use std::cell::{Cell, RefCell};
use std::collections::HashMap;
use std::rc::{Rc, Weak};
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;
use web_sys::{Blob, Event, File, MessageEvent, Worker, WorkerOptions, WorkerType};

/// A worker event handler, kept alive as long as the worker it listens to.
type Handler = Closure<dyn FnMut(JsValue)>;

/// A worker and the handlers that keep its messages flowing; dropping it terminates the worker.
pub(super) struct Started {
    worker: Worker,
    handlers: Option<[Handler; 2]>,
}

impl Drop for Started {
    /// Terminates the worker, unhooks its handlers and lets them go once the task under way has ended: a worker is
    /// often dropped from inside one of its own handlers (it failed, or trapped), which must not be freed while it
    /// runs.
    fn drop(&mut self) {
        self.worker.set_onmessage(None);
        self.worker.set_onerror(None);
        self.worker.terminate();
        if let Some(handlers) = self.handlers.take() {
            wasm_bindgen_futures::spawn_local(async move { drop(handlers) });
        }
    }
}

/// A take the page can send to a worker again: its file as a `Blob` (its bytes are read from it
/// for each send, and transferred).
#[derive(Clone)]
pub(super) struct Take {
    pub id: TakeId,
    pub name: String,
    pub file: Blob,
    /// An AMC motion's ASF skeleton: its name and bytes.
    pub skeleton: Option<(String, Vec<u8>)>,
    /// The bundled sample's.
    pub sample: bool,
}

/// A take the user asked to open.
pub enum Open {
    /// Files dropped or picked ([`crate::app::loader::Loader::load_files`]).
    Files(Vec<File>),
    /// The bundled sample.
    Sample,
}

/// What may hold a take the user opened until they answer a question ([`crate::app::loader::Loader::set_gate`]):
/// gives the take back when it may open at once.
pub(super) type Gate = Rc<dyn Fn(Open) -> Option<Open>>;

/// The loader's state: the workers, the pool's placing of runs, the routes of runs to features, the loads.
pub(super) struct Inner {
    pub state: AppState,
    pub urls: Urls,
    /// The main worker (slot 0): loads the take, trains, annotates, cuts clips, and runs like the others.
    pub main: RefCell<Option<Started>>,
    /// The pool's run workers (slots 1…; `None`: one that could not be started).
    pub helpers: RefCell<Vec<Option<Started>>>,
    /// Which worker runs which run, and what waits ([`crate::worker::pool`]).
    pub pool: RefCell<Pool>,
    /// Take and run ids come from one counter.
    pub next_id: Cell<u32>,
    /// Id of the newest load; messages about other loads are stale.
    pub current: Cell<TakeId>,
    /// The newest load while the worker works on it.
    pub pending: RefCell<Option<Take>>,
    /// Counts the sends of loads: a send whose file was read after a newer send began (a worker
    /// replaced meanwhile sends the pending load again) is dropped, so that no worker gets a
    /// load twice.
    pub load_sends: Cell<u32>,
    /// The take on screen.
    pub shown: RefCell<Option<Take>>,
    /// The load of the page's `src=` file and its URL (a failure to parse it names the URL).
    pub src_take: RefCell<Option<(TakeId, String)>>,
    /// The features' jobs registered ([`crate::app::loader::Loader::register`]), in that order.
    pub features: RefCell<Vec<Rc<dyn Jobs>>>,
    /// Which feature's jobs sent each run under way: its replies go there.
    pub routes: RefCell<HashMap<RunId, Rc<dyn Jobs>>>,
    /// What holds a take the user opens (a training under way asks first), if any.
    pub gate: RefCell<Option<Gate>>,
    /// The shipped model files fetched, and the runs waiting for one.
    pub models: ModelFiles,
    /// What a message from worker `slot` does (the loader's top layer).
    pub on_message: fn(&Rc<Inner>, Slot, JsValue),
    /// What an error of worker `slot` (outside any request) does.
    pub on_error: fn(&Rc<Inner>, Slot, Event),
}

/// A new take or run id (take and run ids come from one counter).
pub(super) fn next_id(inner: &Inner) -> u32 {
    let id = inner.next_id.get().wrapping_add(1).max(1);
    inner.next_id.set(id);
    id
}

/// The feature's jobs that sent run `run`, if one did and still wants its replies.
pub(super) fn route(inner: &Inner, run: RunId) -> Option<Rc<dyn Jobs>> {
    inner.routes.borrow().get(&run).cloned()
}

/// The features registered, in their order (a copy: a feature may register or post while it is told).
pub(super) fn features(inner: &Inner) -> Vec<Rc<dyn Jobs>> {
    inner.features.borrow().clone()
}

/// The id of the take on screen (0: none).
pub(super) fn shown_id(inner: &Inner) -> TakeId {
    inner.shown.borrow().as_ref().map_or(0, |t| t.id)
}

/// Starts the worker of `slot`, its messages and errors wired to the loader's handlers, and gives it the wasm the
/// page compiled.
fn start(inner: &Rc<Inner>, slot: Slot) -> Result<Started, String> {
    let options = WorkerOptions::new();
    options.set_type(WorkerType::Module);
    let worker = Worker::new_with_options(&inner.urls.worker, &options).map_err(|e| js_message(&e))?;
    let weak = Rc::downgrade(inner);
    let on_message = Handler::new(move |event: JsValue| {
        if let Some(inner) = Weak::upgrade(&weak) {
            (inner.on_message)(&inner, slot, event.unchecked_into::<MessageEvent>().data());
        }
    });
    let weak = Rc::downgrade(inner);
    let on_error = Handler::new(move |event: JsValue| {
        if let Some(inner) = Weak::upgrade(&weak) {
            (inner.on_error)(&inner, slot, event.unchecked_into());
        }
    });
    worker.set_onmessage(Some(on_message.as_ref().unchecked_ref()));
    worker.set_onerror(Some(on_error.as_ref().unchecked_ref()));
    give_compiled_wasm(&worker);
    Ok(Started { worker, handlers: Some([on_message, on_error]) })
}

/// Gives `worker` the wasm the page compiled (www/main.js), so that it need not fetch and compile
/// it again.
fn give_compiled_wasm(worker: &Worker) {
    if let Ok(module) = js_sys::Reflect::get(&js_sys::global(), &"__mocapsegWasm".into()) {
        if module.is_instance_of::<js_sys::WebAssembly::Module>() {
            let message = js_sys::Object::new();
            if js_sys::Reflect::set(&message, &"wasmModule".into(), &module).is_ok() {
                let _ = worker.post_message(&message);
            }
        }
    }
}

/// Starts (or restarts) the main worker and gives it what it must hold before anything else.
pub(super) fn spawn_main(inner: &Rc<Inner>) {
    inner.main.borrow_mut().take(); // terminates the old one
    match start(inner, 0) {
        Ok(started) => *inner.main.borrow_mut() = Some(started),
        Err(message) => return inner.state.show_error(format!("the worker could not be started: {message}")),
    }
    give_models(inner, 0);
}

/// Starts run worker `slot` (1…) in place of the one there, given what it must hold; `false` when it could not be.
pub(super) fn spawn_helper(inner: &Rc<Inner>, slot: Slot) -> bool {
    inner.helpers.borrow_mut()[slot - 1] = None; // terminates the old one
    match start(inner, slot) {
        Ok(started) => inner.helpers.borrow_mut()[slot - 1] = Some(started),
        Err(message) => {
            // the pool goes on with the workers it has
            web_sys::console::warn_1(&format!("a run worker could not be started: {message}").into());
            return false;
        }
    }
    give_models(inner, slot);
    true
}

/// Gives worker `slot`, just started, every shipped model file the page fetched (a worker starts with none), and
/// whatever the features give a new worker (the user's models).
fn give_models(inner: &Rc<Inner>, slot: Slot) {
    let take = shown_id(inner);
    for (file, bytes) in inner.models.all() {
        let run = next_id(inner);
        let request = Request::ProvideModel { take, run, file, bytes: bytes.to_vec(), unavailable: None };
        // (a model file the main worker is given goes to the run workers too, and they were given it when they began)
        let _ = if slot == 0 { post_main(inner, &request, None, false) } else { post_to(inner, slot, request) };
    }
    for jobs in features(inner) {
        jobs.worker_started(slot);
    }
}

/// The main worker, started if there is none (it failed outside a request, and was dropped).
fn main_worker(inner: &Rc<Inner>) -> Result<std::cell::Ref<'_, Started>, String> {
    if inner.main.borrow().is_none() {
        spawn_main(inner);
    }
    std::cell::Ref::filter_map(inner.main.borrow(), Option::as_ref)
        .map_err(|_| "the worker could not be started".into())
}

/// Posts `request` to the main worker (with `bytes` transferred for a load); a model file it is given goes to the
/// run workers too when `share`.
fn post_main(inner: &Rc<Inner>, request: &Request, bytes: Option<&ArrayBuffer>, share: bool) -> Result<(), String> {
    if share {
        share_model(inner, request);
    }
    let (message, transfer) = crate::worker::request_message(request, bytes);
    main_worker(inner)?.worker.post_message_with_transfer(&message, &transfer).map_err(|e| js_message(&e))
}

/// Posts `request` to the main worker (with `bytes` transferred for a load); a model file it is given goes to the
/// pool's run workers too.
pub(super) fn post(inner: &Rc<Inner>, request: &Request, bytes: Option<&ArrayBuffer>) -> Result<(), String> {
    post_main(inner, request, bytes, true)
}

/// Posts `request` with `buffers` (JS `ArrayBuffer`s: a take's files) transferred to worker `slot`.
pub(super) fn post_buffers_to(inner: &Rc<Inner>, slot: Slot, request: &Request, buffers: Array) -> Result<(), String> {
    let (message, transfer) = crate::worker::request_with_buffers(request, buffers);
    if slot == 0 {
        return main_worker(inner)?.worker.post_message_with_transfer(&message, &transfer).map_err(|e| js_message(&e));
    }
    let helpers = inner.helpers.borrow();
    let worker = helpers.get(slot - 1).and_then(Option::as_ref).ok_or("the worker could not be started")?;
    worker.worker.post_message_with_transfer(&message, &transfer).map_err(|e| js_message(&e))
}

/// Posts `request` to worker `slot` (0: the main worker), its own buffers moved out of it rather than copied.
pub(super) fn post_to(inner: &Rc<Inner>, slot: Slot, request: Request) -> Result<(), String> {
    let (message, transfer): (JsValue, Array) = crate::worker::packet_to_js(request.into_packet());
    if slot == 0 {
        return main_worker(inner)?.worker.post_message_with_transfer(&message, &transfer).map_err(|e| js_message(&e));
    }
    let helpers = inner.helpers.borrow();
    let worker = helpers.get(slot - 1).and_then(Option::as_ref).ok_or("the worker could not be started")?;
    worker.worker.post_message_with_transfer(&message, &transfer).map_err(|e| js_message(&e))
}

/// Gives every run worker a model file the main worker is given too (its answers are the main
/// worker's to give).
fn share_model(inner: &Rc<Inner>, request: &Request) {
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
