//! The page's side of the worker: reads a dropped/picked file or fetches the bundled sample,
//! hands its bytes to the worker (transferred, not copied), asks for segmentations and turns the
//! worker's [`Response`]s into state.
//!
//! Every load gets a new take id; only the newest load counts. The page keeps a copy of the
//! bytes of the take on screen, and every `segment` request names that take: a worker that
//! holds another one (a load that lost a race with a failing one, or a new worker after a crash
//! or a cancel) answers `not_loaded`, and the page sends it the take on screen again and repeats
//! the request once. A worker whose wasm trapped, or whose run the user cancels, is replaced.

use super::{AppState, LoadState, MethodSlot, RunState};
use crate::protocol::{FailureKind, Request, Response, RunId, TakeId};
use crate::worker::{request_message, response_from_js};
use js_sys::ArrayBuffer;
use leptos::prelude::*;
use std::cell::{Cell, RefCell};
use std::rc::{Rc, Weak};
use std::sync::Arc;
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;
use wasm_bindgen_futures::JsFuture;
use web_sys::{Event, File, MessageEvent, Response as FetchResponse, Worker, WorkerOptions, WorkerType};

/// The largest file the page reads (the worker's memory budget then checks what it needs).
pub const MAX_FILE_BYTES: f64 = 512.0 * 1024.0 * 1024.0;

/// Where the worker script and the bundled sample are, relative to the page.
#[derive(Debug, Clone, PartialEq)]
pub struct Urls {
    pub worker: String,
    pub sample: String,
}

impl Urls {
    /// The defaults, overridden by the root element's `data-worker-url` / `data-sample-url`.
    pub fn from_root(root: &web_sys::Element) -> Urls {
        let get = |name: &str, default: &str| root.get_attribute(name).unwrap_or_else(|| default.to_string());
        Urls { worker: get("data-worker-url", "./www/worker.js"), sample: get("data-sample-url", "./www/sample.bvh") }
    }

    /// The file name at the end of the sample's URL.
    pub fn sample_name(&self) -> String {
        self.sample.rsplit('/').next().unwrap_or("sample.bvh").to_string()
    }
}

/// A worker event handler, kept alive as long as the worker it listens to.
type Handler = Closure<dyn FnMut(JsValue)>;

/// A take the page holds the bytes of (to send it to a worker again).
#[derive(Clone)]
struct Take {
    id: TakeId,
    name: String,
    bytes: ArrayBuffer,
}

/// A run asked of the worker: its request, and whether it was already repeated after a
/// `not_loaded` answer.
struct Run {
    id: RunId,
    method: String,
    params: serde_json::Value,
    retried: bool,
}

/// A handle on the worker; cheap to clone.
#[derive(Clone)]
pub struct Loader(Rc<Inner>);

struct Inner {
    state: AppState,
    urls: Urls,
    worker: RefCell<Option<Worker>>,
    /// Take and run ids come from one counter.
    next_id: Cell<u32>,
    /// Id of the newest load; messages about other loads are stale.
    current: Cell<TakeId>,
    /// The newest load while the worker works on it.
    pending: RefCell<Option<Take>>,
    /// The take on screen.
    shown: RefCell<Option<Take>>,
    /// The current run of each method (by registry name).
    runs: RefCell<Vec<Option<Run>>>,
    /// Keeps the worker's event handlers alive.
    handlers: RefCell<Vec<Handler>>,
}

impl Loader {
    pub fn new(state: AppState, urls: Urls) -> Loader {
        let inner = Rc::new(Inner {
            state,
            urls,
            worker: RefCell::new(None),
            next_id: Cell::new(0),
            current: Cell::new(0),
            pending: RefCell::new(None),
            shown: RefCell::new(None),
            runs: RefCell::new(state.methods.iter().map(|_| None).collect()),
            handlers: RefCell::new(Vec::new()),
        });
        spawn_worker(&inner);
        Loader(inner)
    }

    /// Loads the bundled sample.
    pub fn load_sample(&self) {
        let inner = self.0.clone();
        let (url, name) = (inner.urls.sample.clone(), inner.urls.sample_name());
        let id = begin(&inner, &name);
        wasm_bindgen_futures::spawn_local(async move {
            match fetch_bytes(&url).await {
                Ok(bytes) => send_load(&inner, id, &name, &bytes),
                Err(message) => fail_load(&inner, id, format!("{name}: could not load the sample: {message}")),
            }
        });
    }

    /// Loads a file the user dropped or picked.
    pub fn load_file(&self, file: File) {
        let inner = self.0.clone();
        let name = file.name();
        let id = begin(&inner, &name);
        if file.size() > MAX_FILE_BYTES {
            let mib = file.size() / 1024.0 / 1024.0;
            return fail_load(
                &inner,
                id,
                format!("{name}: {mib:.0} MiB is more than the page reads (512 MiB); cut the take"),
            );
        }
        wasm_bindgen_futures::spawn_local(async move {
            match JsFuture::from(file.array_buffer()).await {
                Ok(bytes) => send_load(&inner, id, &name, bytes.unchecked_ref()),
                Err(e) => fail_load(&inner, id, format!("{name}: could not read the file: {}", js_message(&e))),
            }
        });
    }

    /// Runs method `index` of the registry on the take on screen with the parameters of its form.
    pub fn run(&self, index: usize) {
        start_run(&self.0, index);
    }

    /// Stops method `index`'s run: the worker is replaced (a wasm worker cannot be interrupted),
    /// and the other methods' runs start again on the new one.
    pub fn cancel(&self, index: usize) {
        let inner = &self.0;
        if inner.runs.borrow_mut()[index].take().is_none() {
            return;
        }
        inner.state.methods[index].run.set(RunState::Cancelled);
        replace_worker(inner);
    }
}

fn next_id(inner: &Inner) -> u32 {
    let id = inner.next_id.get().wrapping_add(1).max(1);
    inner.next_id.set(id);
    id
}

/// Starts a new load: it becomes the current one.
fn begin(inner: &Inner, name: &str) -> TakeId {
    let id = next_id(inner);
    inner.current.set(id);
    inner.state.load.set(LoadState::Loading { name: name.to_string(), stage: "reading".into(), fraction: None });
    id
}

/// Posts `request` (with `bytes` transferred for a load), starting a worker if there is none.
fn post(inner: &Rc<Inner>, request: &Request, bytes: Option<&ArrayBuffer>) -> Result<(), String> {
    if inner.worker.borrow().is_none() {
        spawn_worker(inner);
    }
    let worker = inner.worker.borrow();
    let worker = worker.as_ref().ok_or("the worker could not be started")?;
    let (message, transfer) = request_message(request, bytes);
    worker.post_message_with_transfer(&message, &transfer).map_err(|e| js_message(&e))
}

/// Sends a load of `bytes` as take `id` (the page keeps a copy, to send it again if needed).
fn send_load(inner: &Rc<Inner>, id: TakeId, name: &str, bytes: &ArrayBuffer) {
    if inner.current.get() != id {
        return;
    }
    let take = Take { id, name: name.to_string(), bytes: bytes.slice(0) };
    *inner.pending.borrow_mut() = Some(take);
    let request = Request::Load { take: id, name: name.to_string(), restore: false, bytes: Vec::new() };
    if let Err(e) = post(inner, &request, Some(bytes)) {
        fail_load(inner, id, format!("{name}: {e}"));
    }
}

/// Sends the take on screen to the worker again (it answers `restored`).
fn restore(inner: &Rc<Inner>) -> Result<(), String> {
    let take = inner.shown.borrow().clone().ok_or("no take is loaded")?;
    let request = Request::Load { take: take.id, name: take.name.clone(), restore: true, bytes: Vec::new() };
    post(inner, &request, Some(&take.bytes.slice(0)))
}

fn fail_load(inner: &Inner, id: TakeId, message: String) {
    if inner.current.get() == id {
        *inner.pending.borrow_mut() = None;
        inner.state.show_error(message);
        inner.state.load.set(LoadState::Failed);
    }
}

fn start_run(inner: &Rc<Inner>, index: usize) {
    let slot: &MethodSlot = &inner.state.methods[index];
    let params = match slot.params() {
        Ok(p) => p,
        Err(message) => return fail_run(inner, index, message),
    };
    let id = next_id(inner);
    inner.runs.borrow_mut()[index] = Some(Run { id, method: slot.info.name.clone(), params, retried: false });
    slot.run.set(RunState::Running { stage: "starting".into(), fraction: 0.0 });
    if let Err(message) = send_run(inner, index) {
        fail_run(inner, index, format!("{}: {message}", slot.info.short));
    }
}

/// Posts the current run of method `index` for the take on screen.
fn send_run(inner: &Rc<Inner>, index: usize) -> Result<(), String> {
    let take = inner.shown.borrow().as_ref().map(|t| t.id).ok_or("no take is loaded")?;
    let request = {
        let runs = inner.runs.borrow();
        let run = runs[index].as_ref().ok_or("no run")?;
        Request::Segment { take, run: run.id, method: run.method.clone(), params: run.params.clone() }
    };
    post(inner, &request, None)
}

fn fail_run(inner: &Inner, index: usize, message: String) {
    inner.runs.borrow_mut()[index] = None;
    inner.state.show_run_error(message);
    inner.state.methods[index].run.set(RunState::Failed);
}

/// The method whose current run is `run`.
fn run_index(inner: &Inner, run: RunId) -> Option<usize> {
    inner.runs.borrow().iter().position(|r| r.as_ref().is_some_and(|r| r.id == run))
}

/// Starts (or restarts) the worker and wires its messages to the state.
fn spawn_worker(inner: &Rc<Inner>) {
    if let Some(old) = inner.worker.borrow_mut().take() {
        old.terminate();
    }
    let options = WorkerOptions::new();
    options.set_type(WorkerType::Module);
    let worker = match Worker::new_with_options(&inner.urls.worker, &options) {
        Ok(worker) => worker,
        Err(e) => {
            inner.state.show_error(format!("the worker could not be started: {}", js_message(&e)));
            return;
        }
    };
    let weak = Rc::downgrade(inner);
    let on_message = Handler::new(move |event: JsValue| {
        if let Some(inner) = Weak::upgrade(&weak) {
            on_message(&inner, event.unchecked_into::<MessageEvent>().data());
        }
    });
    let weak = Rc::downgrade(inner);
    let on_error = Handler::new(move |event: JsValue| {
        if let Some(inner) = Weak::upgrade(&weak) {
            on_worker_error(&inner, event.unchecked_into());
        }
    });
    worker.set_onmessage(Some(on_message.as_ref().unchecked_ref()));
    worker.set_onerror(Some(on_error.as_ref().unchecked_ref()));
    *inner.handlers.borrow_mut() = vec![on_message, on_error];
    *inner.worker.borrow_mut() = Some(worker);
}

/// A new worker in place of the old one, given the work the old one had: the pending load and
/// every run still under way (each first gets `not_loaded`, then the take on screen).
fn replace_worker(inner: &Rc<Inner>) {
    spawn_worker(inner);
    let pending = inner.pending.borrow().clone();
    if let Some(take) = pending {
        send_load(inner, take.id, &take.name, &take.bytes);
    }
    for index in 0..inner.state.methods.len() {
        let running = inner.runs.borrow()[index].is_some();
        if running {
            if let Err(message) = send_run(inner, index) {
                fail_run(inner, index, message);
            }
        }
    }
}

/// The worker script could not load or threw outside a request: report it and drop the worker
/// (the next request starts a new one).
fn on_worker_error(inner: &Rc<Inner>, event: Event) {
    event.prevent_default();
    // A script that fails to load fires a plain `Event`; an exception fires an `ErrorEvent`.
    let message = js_sys::Reflect::get(&event, &"message".into())
        .ok()
        .and_then(|m| m.as_string())
        .filter(|m| !m.is_empty())
        .unwrap_or_else(|| format!("could not load {}", inner.urls.worker));
    fail_load(inner, inner.current.get(), format!("the worker failed: {message}"));
    for index in 0..inner.state.methods.len() {
        if inner.runs.borrow()[index].is_some() {
            fail_run(inner, index, format!("the worker failed: {message}"));
        }
    }
    if let Some(worker) = inner.worker.borrow_mut().take() {
        worker.terminate();
    }
}

fn on_message(inner: &Rc<Inner>, data: JsValue) {
    let response = match response_from_js(&data) {
        Ok(r) => r,
        Err(message) => return fail_load(inner, inner.current.get(), message),
    };
    let state = inner.state;
    match response {
        Response::Progress { take, run: None, stage, fraction } if take == inner.current.get() => {
            state.load.update(|load| {
                if let LoadState::Loading { stage: s, fraction: f, .. } = load {
                    *s = stage;
                    *f = fraction;
                }
            });
        }
        Response::Progress { run: Some(run), stage, fraction, .. } => {
            if let Some(index) = run_index(inner, run) {
                state.methods[index].run.set(RunState::Running { stage, fraction: fraction.unwrap_or(0.0) });
            }
        }
        Response::Loaded { take, motion } if take == inner.current.get() => {
            *inner.shown.borrow_mut() = inner.pending.borrow_mut().take();
            state.playing.set(false);
            state.play_until.set(None);
            state.frame.set(0);
            for slot in state.methods {
                slot.view.set(None);
                slot.run.set(RunState::Idle);
            }
            inner.runs.borrow_mut().iter_mut().for_each(|r| *r = None);
            state.motion.set(Some(Arc::new(*motion)));
            state.error.set(None);
            state.load.set(LoadState::Ready);
            for (index, slot) in state.methods.iter().enumerate() {
                if slot.info.auto_run {
                    start_run(inner, index);
                }
            }
        }
        Response::Segmented { take, run, view } => {
            let shown = inner.shown.borrow().as_ref().map(|t| t.id);
            if let (Some(index), true) = (run_index(inner, run), shown == Some(take)) {
                inner.runs.borrow_mut()[index] = None;
                let slot = &state.methods[index];
                slot.view.set(Some(Arc::new(*view)));
                if state.error_is_run.get_untracked() {
                    state.error.set(None);
                }
                slot.run.set(RunState::Done);
            }
        }
        Response::Failed { take, run: None, message, kind } => {
            fail_load(inner, take, message);
            if kind == FailureKind::Internal {
                replace_worker(inner);
            }
        }
        Response::Failed { run: Some(run), message, kind, .. } => {
            let Some(index) = run_index(inner, run) else {
                if kind == FailureKind::Internal {
                    replace_worker(inner);
                }
                return;
            };
            match kind {
                FailureKind::NotLoaded => {
                    let first = inner.runs.borrow_mut()[index]
                        .as_mut()
                        .is_some_and(|r| !std::mem::replace(&mut r.retried, true));
                    let resent = first && restore(inner).and_then(|()| send_run(inner, index)).is_ok();
                    if !resent {
                        fail_run(inner, index, message);
                    }
                }
                FailureKind::Internal => {
                    fail_run(inner, index, message);
                    replace_worker(inner);
                }
                FailureKind::Cancelled => {
                    inner.runs.borrow_mut()[index] = None;
                    state.methods[index].run.set(RunState::Cancelled);
                }
                FailureKind::Input => fail_run(inner, index, message),
            }
        }
        _ => {} // about a load that has been superseded
    }
}

async fn fetch_bytes(url: &str) -> Result<ArrayBuffer, String> {
    let window = web_sys::window().ok_or("no window")?;
    let response: FetchResponse =
        JsFuture::from(window.fetch_with_str(url)).await.map_err(|e| js_message(&e))?.unchecked_into();
    if !response.ok() {
        return Err(format!("HTTP {} {} for {url}", response.status(), response.status_text()));
    }
    let body = response.array_buffer().map_err(|e| js_message(&e))?;
    JsFuture::from(body).await.map(JsCast::unchecked_into).map_err(|e| js_message(&e))
}

/// The message of a JS error (or the value itself, as text).
fn js_message(value: &JsValue) -> String {
    value
        .dyn_ref::<js_sys::Error>()
        .map(|e| String::from(e.message()))
        .or_else(|| value.as_string())
        .unwrap_or_else(|| format!("{value:?}"))
}
