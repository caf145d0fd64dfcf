//! The page's side of the worker: reads a dropped/picked file or fetches the bundled sample,
//! hands its bytes to the worker (transferred, not copied), asks for segmentations and turns the
//! worker's [`Response`]s into state.
//!
//! Every load gets a new take id; only the newest load counts. The page keeps a copy of the
//! bytes of the take on screen, and every `segment` request names that take: a worker that
//! holds another one (a load that lost a race with a failing one, or a new worker after a crash
//! or a cancel) answers `not_loaded`, and the page sends it the take on screen again and repeats
//! the request once. A worker whose wasm trapped, or whose run the user cancels, is replaced.
//!
//! The LMA family works the same way: a training on the user's labels or a switch of family is
//! one request under way at a time (repeated once after `not_loaded`, sent again to a new
//! worker), and every worker the page starts first gets the user's family the page holds — a
//! new worker starts with the shipped one, and LMA must not silently go back to it.

use super::lma_training::{self, TrainingState, UserFamily};
use super::{AppState, LoadState, MethodSlot, RunState};
use crate::protocol::{FactorSummary, FailureKind, Request, Response, RunId, TakeId};
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

/// What the user asked of the LMA family.
#[derive(Clone)]
enum LmaAsk {
    /// Train on the labels file `name` (its text).
    Train { name: String, labels: String },
    /// Use a family file's (name, JSON), or the shipped family (`None`).
    Use(Option<(String, String)>),
}

/// The LMA family request under way.
struct LmaJob {
    id: RunId,
    ask: LmaAsk,
    retried: bool,
    /// The take it was last sent for.
    take_name: String,
    /// `performance.now()` when it was asked.
    started: f64,
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
    /// The LMA family request under way.
    lma_job: RefCell<Option<LmaJob>>,
    /// The request that gave the newest worker the user's family (its answer is checked).
    family_sync: Cell<Option<RunId>>,
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
            lma_job: RefCell::new(None),
            family_sync: Cell::new(None),
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

    /// Trains the LMA family on the labels file `name` (its text) for the take on screen.
    pub fn train_lma(&self, name: String, labels: String) {
        let lma = self.0.state.lma;
        lma.state.set(TrainingState::Training { stage: "starting".into(), fraction: 0.0 });
        lma.status.set(format!("Training on the rows of {name} for the take on screen…"));
        start_lma_job(&self.0, LmaAsk::Train { name, labels });
    }

    /// Makes the family of the file `name` (its JSON text) the one LMA runs with, or the shipped
    /// family (`None`).
    pub fn use_lma_model(&self, model: Option<(String, String)>) {
        self.0.state.lma.state.set(TrainingState::Switching);
        start_lma_job(&self.0, LmaAsk::Use(model));
    }

    /// Stops a training: the worker is replaced, and the new one gets the family the page holds.
    pub fn cancel_lma_training(&self) {
        let inner = &self.0;
        if inner.lma_job.borrow_mut().take().is_none() {
            return;
        }
        let lma = inner.state.lma;
        let (state, status) = match lma.family.get_untracked() {
            Some(f) => {
                (TrainingState::Done, format!("Training cancelled; LMA still uses your classifiers ({}).", f.origin))
            }
            None => (TrainingState::Idle, "Training cancelled; LMA still uses the shipped classifiers.".to_string()),
        };
        lma.status.set(status);
        lma.state.set(state);
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
    send_family(inner);
}

/// Gives a worker just started the user's family the page holds (a worker starts with the
/// shipped one), before any other request.
fn send_family(inner: &Rc<Inner>) {
    inner.family_sync.set(None);
    let Some(family) = inner.state.lma.family.get_untracked() else { return };
    let id = next_id(inner);
    inner.family_sync.set(Some(id));
    let take = inner.shown.borrow().as_ref().map_or(0, |t| t.id);
    let request = Request::UseLmaModel { take, run: id, model: Some(family.json.clone()) };
    if let Err(message) = post(inner, &request, None) {
        drop_family(inner, message);
    }
}

/// The worker would not take the user's family: the page drops it (so that no worker is asked
/// again) and says so; LMA runs with the shipped family.
fn drop_family(inner: &Inner, message: String) {
    inner.family_sync.set(None);
    let lma = inner.state.lma;
    lma.family.set(None);
    lma.report.set(Vec::new());
    lma.status.set(format!("The worker could not take your classifiers ({message}); LMA uses the shipped ones."));
    lma.state.set(TrainingState::Failed);
}

fn start_lma_job(inner: &Rc<Inner>, ask: LmaAsk) {
    let id = next_id(inner);
    let started = now();
    *inner.lma_job.borrow_mut() = Some(LmaJob { id, ask, retried: false, take_name: String::new(), started });
    if let Err(message) = send_lma_job(inner) {
        fail_lma_job(inner, message);
    }
}

/// Posts the LMA family request under way, for the take on screen.
fn send_lma_job(inner: &Rc<Inner>) -> Result<(), String> {
    let (take, take_name) = inner.shown.borrow().as_ref().map(|t| (t.id, t.name.clone())).unzip();
    let request = {
        let mut job = inner.lma_job.borrow_mut();
        let job = job.as_mut().ok_or("no LMA request")?;
        job.take_name = take_name.unwrap_or_default();
        match &job.ask {
            LmaAsk::Train { name, labels } => Request::TrainLma {
                take: take.ok_or("load a take before training")?,
                run: job.id,
                name: name.clone(),
                labels: labels.clone(),
            },
            LmaAsk::Use(model) => Request::UseLmaModel {
                take: take.unwrap_or(0),
                run: job.id,
                model: model.as_ref().map(|(_, json)| json.clone()),
            },
        }
    };
    post(inner, &request, None)
}

/// The LMA family request under way failed: the status line says why; the family in use stays.
fn fail_lma_job(inner: &Inner, message: String) {
    let job = inner.lma_job.borrow_mut().take();
    let message = match job.map(|j| j.ask) {
        Some(LmaAsk::Use(Some((name, _)))) => format!("{name}: {message}"),
        _ => message,
    };
    let lma = inner.state.lma;
    lma.status.set(message);
    lma.state.set(TrainingState::Failed);
}

/// Whether `run` is the LMA family request under way.
fn is_lma_job(inner: &Inner, run: RunId) -> bool {
    inner.lma_job.borrow().as_ref().is_some_and(|j| j.id == run)
}

/// LMA runs again on the take on screen (after its family changed).
fn rerun_lma(inner: &Rc<Inner>) {
    let index = inner.state.methods.iter().position(|m| m.info.name == lma_training::METHOD);
    if let (Some(index), true) = (index, inner.shown.borrow().is_some()) {
        start_run(inner, index);
    }
}

/// The worker trained the user's family and uses it.
fn on_trained(inner: &Rc<Inner>, model: String, report: Vec<FactorSummary>, origin: String, rows: (usize, usize)) {
    let Some(job) = inner.lma_job.borrow_mut().take() else { return };
    let seconds = (now() - job.started) / 1000.0;
    let file = match &job.ask {
        LmaAsk::Train { name, .. } => name.clone(),
        LmaAsk::Use(_) => String::new(),
    };
    let (used, ignored) = rows;
    let left_out = match ignored {
        0 => String::new(),
        1 => " (1 row for another file left out)".to_string(),
        n => format!(" ({n} rows for other files left out)"),
    };
    let lma = inner.state.lma;
    lma.family.set(Some(Arc::new(UserFamily { json: model, origin, trained_on: Some(job.take_name.clone()) })));
    lma.report.set(report);
    lma.status.set(format!(
        "Trained on {used} rows of {file} for {} in {seconds:.2} s{left_out}. LMA runs with your classifiers now.",
        job.take_name
    ));
    lma.state.set(TrainingState::Done);
    rerun_lma(inner);
}

/// The worker switched to the family the user asked for.
fn on_model_in_use(inner: &Rc<Inner>, origin: String, shipped: bool) {
    let Some(job) = inner.lma_job.borrow_mut().take() else { return };
    let lma = inner.state.lma;
    lma.report.set(Vec::new());
    match job.ask {
        LmaAsk::Use(Some((name, json))) if !shipped => {
            lma.status.set(format!("Loaded {name}: LMA runs with your classifiers ({origin})."));
            lma.family.set(Some(Arc::new(UserFamily { json, origin, trained_on: None })));
            lma.state.set(TrainingState::Done);
        }
        _ => {
            lma.family.set(None);
            lma.status
                .set("Back to the shipped classifiers (trained on stand-in labels); LMA runs with them now.".into());
            lma.state.set(TrainingState::Idle);
        }
    }
    rerun_lma(inner);
}

fn on_lma_job_failed(inner: &Rc<Inner>, message: String, kind: FailureKind) {
    match kind {
        FailureKind::NotLoaded => {
            let first = inner.lma_job.borrow_mut().as_mut().is_some_and(|j| !std::mem::replace(&mut j.retried, true));
            let resent = first && restore(inner).and_then(|()| send_lma_job(inner)).is_ok();
            if !resent {
                fail_lma_job(inner, message);
            }
        }
        FailureKind::Internal => {
            fail_lma_job(inner, message);
            replace_worker(inner);
        }
        FailureKind::Input | FailureKind::Cancelled => fail_lma_job(inner, message),
    }
}

/// Milliseconds since the page started.
fn now() -> f64 {
    web_sys::window().and_then(|w| w.performance()).map_or(0.0, |p| p.now())
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
    let asked = inner.lma_job.borrow().is_some();
    if asked {
        if let Err(message) = send_lma_job(inner) {
            fail_lma_job(inner, message);
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
    if inner.lma_job.borrow().is_some() {
        fail_lma_job(inner, format!("the worker failed: {message}"));
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
            } else if is_lma_job(inner, run) {
                state.lma.state.set(TrainingState::Training { stage, fraction: fraction.unwrap_or(0.0) });
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
        Response::Trained { run, model, report, origin, used_rows, ignored_rows, .. } if is_lma_job(inner, run) => {
            on_trained(inner, model, report, origin, (used_rows, ignored_rows));
        }
        Response::ModelInUse { run, origin, shipped, .. } if is_lma_job(inner, run) => {
            on_model_in_use(inner, origin, shipped);
        }
        Response::ModelInUse { run, .. } if inner.family_sync.get() == Some(run) => inner.family_sync.set(None),
        Response::Failed { run: Some(run), message, kind, .. } if is_lma_job(inner, run) => {
            on_lma_job_failed(inner, message, kind);
        }
        Response::Failed { run: Some(run), message, kind, .. } if inner.family_sync.get() == Some(run) => {
            drop_family(inner, message);
            if kind == FailureKind::Internal {
                replace_worker(inner);
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
