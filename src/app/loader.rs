//! The page's side of the worker: reads a dropped/picked file or fetches the bundled sample,
//! hands its bytes to the worker (transferred, not copied) and turns the worker's messages
//! ([`WorkerEvent`]) into state. Only the newest load counts: messages about an older one are
//! ignored. A worker whose wasm trapped is replaced by a fresh one.

use super::{AppState, LoadState, SssmState};
use crate::worker::{load_request, sssm_request, transfer_list, WorkerEvent};
use js_sys::ArrayBuffer;
use leptos::prelude::*;
use std::cell::{Cell, RefCell};
use std::rc::{Rc, Weak};
use std::sync::Arc;
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;
use wasm_bindgen_futures::JsFuture;
use web_sys::{Event, File, MessageEvent, Response, Worker, WorkerOptions, WorkerType};

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

/// A handle on the worker; cheap to clone.
#[derive(Clone)]
pub struct Loader(Rc<Inner>);

struct Inner {
    state: AppState,
    urls: Urls,
    worker: RefCell<Option<Worker>>,
    /// Id of the newest load; messages with another id are stale.
    current: Cell<u32>,
    /// Id of the newest SSSM run (its own numbering).
    sssm_current: Cell<u32>,
    /// Keeps the worker's event handlers alive.
    handlers: RefCell<Vec<Handler>>,
}

impl Loader {
    pub fn new(state: AppState, urls: Urls) -> Loader {
        let inner = Rc::new(Inner {
            state,
            urls,
            worker: RefCell::new(None),
            current: Cell::new(0),
            sssm_current: Cell::new(0),
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
                Ok(bytes) => send(&inner, id, &name, &bytes),
                Err(message) => fail(&inner, id, format!("{name}: could not load the sample: {message}")),
            }
        });
    }

    /// Runs the SSSM on the take on screen with `params_json` (see [`crate::worker::worker_sssm`]).
    pub fn run_sssm(&self, params_json: &str) {
        run_sssm(&self.0, params_json);
    }

    /// Loads a file the user dropped or picked.
    pub fn load_file(&self, file: File) {
        let inner = self.0.clone();
        let name = file.name();
        let id = begin(&inner, &name);
        wasm_bindgen_futures::spawn_local(async move {
            match JsFuture::from(file.array_buffer()).await {
                Ok(bytes) => send(&inner, id, &name, bytes.unchecked_ref()),
                Err(e) => fail(&inner, id, format!("{name}: could not read the file: {}", js_message(&e))),
            }
        });
    }
}

/// Starts a new load: it becomes the current one.
fn begin(inner: &Inner, name: &str) -> u32 {
    let id = inner.current.get().wrapping_add(1);
    inner.current.set(id);
    inner.state.load.set(LoadState::Loading { name: name.to_string(), stage: "reading".into(), fraction: None });
    id
}

fn send(inner: &Rc<Inner>, id: u32, name: &str, bytes: &ArrayBuffer) {
    if inner.current.get() != id {
        return;
    }
    if inner.worker.borrow().is_none() {
        spawn_worker(inner);
    }
    let posted = match (&*inner.worker.borrow(), load_request(id, name, bytes)) {
        (Some(worker), Ok(message)) => worker.post_message_with_transfer(&message, &transfer_list(bytes)),
        (None, _) => Err(JsValue::from_str("the worker could not be started")),
        (_, Err(e)) => Err(e),
    };
    if let Err(e) = posted {
        fail(inner, id, format!("{name}: {}", js_message(&e)));
    }
}

fn run_sssm(inner: &Rc<Inner>, params_json: &str) {
    let id = inner.sssm_current.get().wrapping_add(1);
    inner.sssm_current.set(id);
    inner.state.sssm.set(SssmState::Running { stage: "starting".into(), fraction: 0.0 });
    if inner.worker.borrow().is_none() {
        spawn_worker(inner);
    }
    let posted = match (&*inner.worker.borrow(), sssm_request(id, params_json)) {
        (Some(worker), Ok(message)) => worker.post_message(&message),
        (None, _) => Err(JsValue::from_str("the worker could not be started")),
        (_, Err(e)) => Err(e),
    };
    if let Err(e) = posted {
        fail_sssm(inner, id, format!("SSSM: {}", js_message(&e)));
    }
}

fn fail_sssm(inner: &Inner, id: u32, message: String) {
    if inner.sssm_current.get() == id {
        inner.state.error.set(Some(message));
        inner.state.sssm.set(SssmState::Failed);
    }
}

fn fail(inner: &Inner, id: u32, message: String) {
    if inner.current.get() == id {
        inner.state.error.set(Some(message));
        inner.state.load.set(LoadState::Failed);
    }
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
            inner.state.error.set(Some(format!("the worker could not be started: {}", js_message(&e))));
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

/// The worker script could not load or threw outside a load: report it and drop the worker
/// (the next load starts a new one).
fn on_worker_error(inner: &Inner, event: Event) {
    event.prevent_default();
    // A script that fails to load fires a plain `Event`; an exception fires an `ErrorEvent`.
    let message = js_sys::Reflect::get(&event, &"message".into())
        .ok()
        .and_then(|m| m.as_string())
        .filter(|m| !m.is_empty())
        .unwrap_or_else(|| format!("could not load {}", inner.urls.worker));
    fail(inner, inner.current.get(), format!("the worker failed: {message}"));
    if let Some(worker) = inner.worker.borrow_mut().take() {
        worker.terminate();
    }
}

fn on_message(inner: &Rc<Inner>, data: JsValue) {
    let state = inner.state;
    let event = match WorkerEvent::from_js(&data) {
        Ok(event) => event,
        Err(message) => return fail(inner, inner.current.get(), message),
    };
    match event {
        WorkerEvent::Progress { id, stage, fraction } if id == inner.current.get() => {
            state.load.update(|load| {
                if let LoadState::Loading { stage: s, fraction: f, .. } = load {
                    *s = stage;
                    *f = fraction;
                }
            });
        }
        WorkerEvent::Done { id, motion } if id == inner.current.get() => {
            state.playing.set(false);
            state.play_until.set(None);
            state.frame.set(0);
            state.sssm_view.set(None);
            state.motion.set(Some(Arc::new(*motion)));
            state.error.set(None);
            state.load.set(LoadState::Ready);
            run_sssm(inner, "{}");
        }
        WorkerEvent::SssmProgress { id, stage, fraction } if id == inner.sssm_current.get() => {
            state.sssm.set(SssmState::Running { stage, fraction: fraction.unwrap_or(0.0) });
        }
        WorkerEvent::SssmDone { id, view } if id == inner.sssm_current.get() => {
            state.sssm_view.set(Some(Arc::new(*view)));
            if state.error.with_untracked(|e| e.as_deref().is_some_and(|m| m.contains("SSSM"))) {
                state.error.set(None);
            }
            state.sssm.set(SssmState::Done);
        }
        WorkerEvent::SssmError { id, message, fatal } => {
            fail_sssm(inner, id, message);
            if fatal {
                if let Some(worker) = inner.worker.borrow_mut().take() {
                    worker.terminate();
                }
            }
        }
        WorkerEvent::Error { id, message, fatal } => {
            fail(inner, id, message);
            if fatal {
                // The next load starts a fresh worker (not from inside this handler).
                if let Some(worker) = inner.worker.borrow_mut().take() {
                    worker.terminate();
                }
            }
        }
        _ => {} // a message about a load that has been superseded
    }
}

async fn fetch_bytes(url: &str) -> Result<ArrayBuffer, String> {
    let window = web_sys::window().ok_or("no window")?;
    let response: Response =
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
