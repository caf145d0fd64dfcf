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
//!
//! So do the user's DT-FCN and k-NN models: a model file is installed in the worker
//! (`use_label_model`, its answer adds it to the method's model choice and runs the method again),
//! every model the page holds goes to each new worker before anything else, and a model file
//! request or a DT-FCN training under way is sent again to a new worker (the training then starts
//! again from its first epoch). A training runs one epoch per message; Stop asks the worker to end
//! it after the epoch under way and keep the best model so far.
//!
//! The shipped models are not in the wasm: a run that needs one the worker does not hold is
//! answered `needs_model`, and [`super::model_files`] fetches it, hands it over and asks again.

use super::dtfcn_training::{model_file_name, TrainAsk, TrainState, TrainedFile};
use super::js_message;
use super::label_models::{describe, kind_of, LoadStatus, UserModel};
use super::lma_training::{self, TrainingState, UserFamily};
use super::model_files::{self, ModelFiles};
use super::motion_image::download;
use super::{AppState, LoadState, MethodSlot, RunState};
use crate::dtfcn::model::ModelKind;
use crate::dtfcn::training::EpochReport;
use crate::load::Opening;
use crate::protocol::{
    kind_short, FactorSummary, FailureKind, LabelModelInfo, Request, Response, RunId, TakeId, TrainField,
};
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

/// Where the worker script, the bundled sample and the shipped models are, relative to the page.
#[derive(Debug, Clone, PartialEq)]
pub struct Urls {
    pub worker: String,
    pub sample: String,
    /// The folder of the shipped model files.
    pub models: String,
}

impl Urls {
    /// The defaults, overridden by the root element's `data-worker-url` / `data-sample-url` /
    /// `data-models-url`.
    pub fn from_root(root: &web_sys::Element) -> Urls {
        let get = |name: &str, default: &str| root.get_attribute(name).unwrap_or_else(|| default.to_string());
        Urls {
            worker: get("data-worker-url", "./www/worker.js"),
            sample: get("data-sample-url", "./www/sample.bvh"),
            models: get("data-models-url", "./models/"),
        }
    }

    /// The file name at the end of the sample's URL.
    pub fn sample_name(&self) -> String {
        self.sample.rsplit('/').next().unwrap_or("sample.bvh").to_string()
    }
}

/// A row's export status line: (failed, message).
type ExportStatus = RwSignal<Option<(bool, String)>>;

/// A worker event handler, kept alive as long as the worker it listens to.
type Handler = Closure<dyn FnMut(JsValue)>;

/// A take the page holds the bytes of (to send it to a worker again).
#[derive(Clone)]
struct Take {
    id: TakeId,
    name: String,
    bytes: ArrayBuffer,
    /// An AMC motion's ASF skeleton: its name and bytes.
    skeleton: Option<(String, Vec<u8>)>,
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

/// A model file the worker is asked to install.
struct LabelJob {
    id: RunId,
    kind: ModelKind,
    file: String,
    bytes: Arc<Vec<u8>>,
}

/// The DT-FCN training under way.
struct DtfcnJob {
    id: RunId,
    ask: TrainAsk,
    /// `performance.now()` when it was (last) sent.
    started: f64,
    /// The take on screen it was sent with.
    take_name: String,
    /// Stop was pressed.
    stopping: bool,
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
    /// Model files being installed (one per method at a time).
    label_jobs: RefCell<Vec<LabelJob>>,
    /// The requests that gave the newest worker the user's models: run, kind and name.
    model_sync: RefCell<Vec<(RunId, ModelKind, String)>>,
    /// The DT-FCN training under way.
    dtfcn_job: RefCell<Option<DtfcnJob>>,
    /// Keeps the worker's event handlers alive.
    handlers: RefCell<Vec<Handler>>,
    /// Clip exports asked of the worker: the request (sent again once after `not_loaded`), the
    /// status line of the row that asked, and whether it was sent again already.
    clip_jobs: RefCell<Vec<(Request, ExportStatus, bool)>>,
    /// The methods that run after each load (URL parameter `methods`); `None`: those whose
    /// `auto_run` is set.
    auto_run: RefCell<Option<Vec<String>>>,
    /// The load of the page's `src=` file and its URL (a failure to parse it names the URL).
    src_take: RefCell<Option<(TakeId, String)>>,
    /// The shipped model files fetched, and the runs waiting for one.
    models: ModelFiles,
}

impl Loader {
    pub fn new(state: AppState, urls: Urls) -> Loader {
        let models = ModelFiles::new(&urls.models);
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
            label_jobs: RefCell::new(Vec::new()),
            model_sync: RefCell::new(Vec::new()),
            dtfcn_job: RefCell::new(None),
            handlers: RefCell::new(Vec::new()),
            clip_jobs: RefCell::new(Vec::new()),
            auto_run: RefCell::new(None),
            src_take: RefCell::new(None),
            models,
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

    /// Runs only the methods named (registry names) after each load, instead of those whose
    /// `auto_run` is set (the URL parameter `methods`).
    pub fn set_auto_run(&self, methods: Vec<String>) {
        *self.0.auto_run.borrow_mut() = Some(methods);
    }

    /// Loads the file at `url` (the URL parameter `src`), shown as `name`: `fetch` gets its bytes
    /// (and, for an AMC motion, its ASF skeleton's name and bytes: the parameter `asf`) or the
    /// message to show (naming the URL); the parser's refusal is shown naming the URL too.
    pub fn load_src(
        &self,
        url: String,
        name: String,
        fetch: impl std::future::Future<Output = Result<(ArrayBuffer, Option<(String, Vec<u8>)>), String>> + 'static,
    ) {
        let inner = self.0.clone();
        let id = begin(&inner, &name);
        *inner.src_take.borrow_mut() = Some((id, url));
        wasm_bindgen_futures::spawn_local(async move {
            match fetch.await {
                Ok((bytes, skeleton)) => send_load_with(&inner, id, &name, &bytes, skeleton),
                Err(message) => {
                    inner.src_take.borrow_mut().take();
                    fail_load(&inner, id, message)
                }
            }
        });
    }

    /// Loads the files the user dropped or picked at once: one take's file, or an ASF skeleton
    /// with its AMC motion ([`crate::load::opening`] says which, or why neither).
    pub fn load_files(&self, files: Vec<File>) {
        let inner = self.0.clone();
        let names: Vec<String> = files.iter().map(File::name).collect();
        let refs: Vec<&str> = names.iter().map(String::as_str).collect();
        let opening = crate::load::opening(&refs);
        let (motion, skeleton) = match opening {
            Ok(Opening::One(i)) => (files[i].clone(), None),
            Ok(Opening::AsfAmc { asf, amc }) => (files[amc].clone(), Some(files[asf].clone())),
            Err(message) => {
                let id = begin(&inner, names.first().map_or("", String::as_str));
                return fail_load(&inner, id, message);
            }
        };
        let name = motion.name();
        let id = begin(&inner, &name);
        if let Some(big) = files.iter().find(|f| f.size() > MAX_FILE_BYTES) {
            let mib = big.size() / 1024.0 / 1024.0;
            return fail_load(
                &inner,
                id,
                format!("{}: {mib:.0} MiB is more than the page reads (512 MiB); cut the take", big.name()),
            );
        }
        wasm_bindgen_futures::spawn_local(async move {
            let skeleton = match skeleton {
                None => None,
                Some(asf) => match JsFuture::from(asf.array_buffer()).await {
                    Ok(b) => Some((asf.name(), js_sys::Uint8Array::new(&b).to_vec())),
                    Err(e) => {
                        let message = format!("{}: could not read the file: {}", asf.name(), js_message(&e));
                        return fail_load(&inner, id, message);
                    }
                },
            };
            match JsFuture::from(motion.array_buffer()).await {
                Ok(bytes) => send_load_with(&inner, id, &name, bytes.unchecked_ref(), skeleton),
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

    /// Cuts the take on screen at the segments `which` chooses of method `index`'s last run and
    /// saves the clips (a zip, or with `only` that segment's BVH); the panel's export status says
    /// how it went.
    pub fn export_clips(
        &self,
        index: usize,
        which: crate::clips::Which,
        to_origin: bool,
        only: Option<(usize, usize)>,
    ) {
        let slot = &self.0.state.methods[index];
        match slot.view.get_untracked() {
            Some(view) => self.export_clips_of(&view.segmentation, which, to_origin, only, slot.export_status),
            None => slot.export_status.set(Some((true, "run the method on a take first".into()))),
        }
    }

    /// Cuts the take on screen at the segments `which` chooses of `segmentation` (any row's) and
    /// saves the clips; `status` says how it went.
    pub fn export_clips_of(
        &self,
        segmentation: &crate::segment::Segmentation,
        which: crate::clips::Which,
        to_origin: bool,
        only: Option<(usize, usize)>,
        status: ExportStatus,
    ) {
        let inner = &self.0;
        let Some(take) = inner.shown.borrow().as_ref().map(|t| t.id) else {
            return status.set(Some((true, "no take is loaded".into())));
        };
        let run = next_id(inner);
        let segmentation = Box::new(segmentation.clone());
        let request = Request::Clips { take, run, segmentation, which, to_origin, only };
        status.set(Some((false, "cutting the clips…".into())));
        match post(inner, &request, None) {
            Ok(()) => inner.clip_jobs.borrow_mut().push((request, status, false)),
            Err(message) => status.set(Some((true, message))),
        }
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

impl Loader {
    /// Installs the model file `file` (its bytes) for the method of `kind`; on success it becomes
    /// the method's model and the method runs again on the take on screen.
    pub fn use_label_model(&self, kind: ModelKind, file: String, bytes: Vec<u8>) {
        let inner = &self.0;
        let input = inner.state.labels.input(kind);
        input.state.set(LoadStatus::Loading);
        input.status.set(format!("Checking {file}…"));
        let id = next_id(inner);
        inner.label_jobs.borrow_mut().retain(|j| j.kind != kind);
        inner.label_jobs.borrow_mut().push(LabelJob { id, kind, file, bytes: Arc::new(bytes) });
        if let Err(message) = send_label_job(inner, id) {
            fail_label_job(inner, id, message);
        }
    }

    /// Trains a DT-FCN in the worker on the take on screen (and the takes the ask adds).
    pub fn train_dtfcn(&self, ask: TrainAsk) {
        let inner = &self.0;
        let t = inner.state.dtfcn;
        t.errors.set(Vec::new());
        t.reports.set(Vec::new());
        t.state.set(TrainState::Training { stage: "starting".into(), epoch: 0, epochs: ask.options.epochs });
        t.status.set(format!("Training `{}` on the rows of {}…", ask.name, ask.labels_name));
        let id = next_id(inner);
        *inner.dtfcn_job.borrow_mut() =
            Some(DtfcnJob { id, ask, started: now(), take_name: String::new(), stopping: false });
        if let Err(message) = send_dtfcn_job(inner) {
            fail_dtfcn_job(inner, message, None);
        }
    }

    /// Asks the worker to end the training after the epoch under way (the best model so far is
    /// kept and sent).
    pub fn stop_dtfcn_training(&self) {
        let inner = &self.0;
        let id = {
            let mut job = inner.dtfcn_job.borrow_mut();
            let Some(job) = job.as_mut().filter(|j| !j.stopping) else { return };
            job.stopping = true;
            job.id
        };
        inner.state.dtfcn.state.set(TrainState::Stopping);
        let take = inner.shown.borrow().as_ref().map_or(0, |t| t.id);
        if let Err(message) = post(inner, &Request::StopTraining { take, run: id }, None) {
            fail_dtfcn_job(inner, message, None);
        }
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
    send_load_with(inner, id, name, bytes, None);
}

/// [`send_load`] of an AMC motion with its ASF `skeleton` (name, bytes), or of any file without.
fn send_load_with(inner: &Rc<Inner>, id: TakeId, name: &str, bytes: &ArrayBuffer, skeleton: Option<(String, Vec<u8>)>) {
    if inner.current.get() != id {
        return;
    }
    let take = Take { id, name: name.to_string(), bytes: bytes.slice(0), skeleton };
    let request = load_request(&take, false);
    *inner.pending.borrow_mut() = Some(take);
    if let Err(e) = post(inner, &request, Some(bytes)) {
        fail_load(inner, id, format!("{name}: {e}"));
    }
}

/// The load request of `take` (its bytes go as the transferred buffer).
fn load_request(take: &Take, restore: bool) -> Request {
    let (skeleton, skeleton_bytes) = match &take.skeleton {
        Some((name, bytes)) => (Some(name.clone()), bytes.clone()),
        None => (None, Vec::new()),
    };
    Request::Load { take: take.id, name: take.name.clone(), restore, bytes: Vec::new(), skeleton, skeleton_bytes }
}

/// Sends the take on screen to the worker again (it answers `restored`).
fn restore(inner: &Rc<Inner>) -> Result<(), String> {
    let take = inner.shown.borrow().clone().ok_or("no take is loaded")?;
    post(inner, &load_request(&take, true), Some(&take.bytes.slice(0)))
}

fn fail_load(inner: &Inner, id: TakeId, message: String) {
    let message = match inner.src_take.borrow().as_ref() {
        Some((take, url)) if *take == id => crate::view::url_params::load_failed(url, &message),
        _ => message,
    };
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
        Err(e) => return refuse_run(inner, index, e.to_string(), e.param_name().map(str::to_string)),
    };
    slot.field_error.set(None);
    slot.failure.set(None);
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

/// A run failed: a refusal that names one of the method's parameters shows at that field, any
/// other message in the banner.
fn fail_run(inner: &Inner, index: usize, message: String) {
    refuse_run(inner, index, message, None)
}

/// A run failed or was refused: a refusal of one of the method's parameters (`param`, as the
/// method named it) shows at that field, any other message in the banner.
fn refuse_run(inner: &Inner, index: usize, message: String, param: Option<String>) {
    inner.runs.borrow_mut()[index] = None;
    let slot = &inner.state.methods[index];
    match param.filter(|p| slot.specs.iter().any(|s| s.name == *p)) {
        Some(param) => slot.field_error.set(Some((param, message))),
        None => {
            slot.failure.set(Some(message.clone()));
            inner.state.show_run_error(message);
        }
    }
    slot.run.set(RunState::Failed);
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
    send_label_models(inner);
    send_model_files(inner);
}

/// Hands a worker just started every shipped model file the page fetched (a worker starts with
/// none), before any other request.
fn send_model_files(inner: &Rc<Inner>) {
    for (file, bytes) in inner.models.all() {
        let run = next_id(inner);
        give_model(inner, run, &file, &bytes);
    }
}

/// Hands the shipped model file `file` to the worker; a refusal is the answer to `run`.
fn give_model(inner: &Rc<Inner>, run: RunId, file: &str, bytes: &[u8]) {
    let take = inner.shown.borrow().as_ref().map_or(0, |t| t.id);
    let request = Request::ProvideModel { take, run, file: file.to_string(), bytes: bytes.to_vec() };
    if let Err(message) = post(inner, &request, None) {
        fail_waiting(inner, run, message);
    }
}

/// The worker needs the shipped model file `file` for `run` (a method's run or the LMA family
/// request): fetched once, handed over, and `run` asked again.
fn need_model(inner: &Rc<Inner>, run: RunId, file: String) {
    if inner.family_sync.get() == Some(run) {
        // a new worker told to use the shipped family: it does, and fetches nothing until a run
        inner.family_sync.set(None);
        return;
    }
    if run_index(inner, run).is_none() && !is_lma_job(inner, run) {
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
                for run in inner.models.take_waiting(&file) {
                    fail_waiting(&inner, run, format!("could not fetch the model {url}: {message}"));
                }
            }
        }
    });
}

/// Shows on whatever `run` is that `file` is coming.
fn show_fetching(inner: &Inner, run: RunId, file: &str, size: u64, fraction: f64) {
    let stage = model_files::fetching_stage(file, size);
    if let Some(index) = run_index(inner, run) {
        inner.state.methods[index].run.set(RunState::Running { stage, fraction });
    } else if is_lma_job(inner, run) {
        inner.state.lma.state.set(TrainingState::Training { stage, fraction });
    }
}

/// Sends `run` (a method's run or the LMA family request) again.
fn ask_again(inner: &Rc<Inner>, run: RunId) {
    if let Some(index) = run_index(inner, run) {
        if let Err(message) = send_run(inner, index) {
            fail_run(inner, index, message);
        }
    } else if is_lma_job(inner, run) {
        if let Err(message) = send_lma_job(inner) {
            fail_lma_job(inner, message);
        }
    }
}

/// `run` cannot have its model file.
fn fail_waiting(inner: &Inner, run: RunId, message: String) {
    if let Some(index) = run_index(inner, run) {
        fail_run(inner, index, message);
    } else if is_lma_job(inner, run) {
        fail_lma_job(inner, message);
    }
}

/// Gives a worker just started every DT-FCN and k-NN model the page holds (a worker knows only
/// the shipped ones), before any other request.
fn send_label_models(inner: &Rc<Inner>) {
    inner.model_sync.borrow_mut().clear();
    let take = inner.shown.borrow().as_ref().map_or(0, |t| t.id);
    for m in inner.state.labels.models.get_untracked() {
        let id = next_id(inner);
        inner.model_sync.borrow_mut().push((id, m.info.kind, m.info.name.clone()));
        let request = Request::UseLabelModel {
            take,
            run: id,
            kind: m.info.kind,
            file: m.file.clone(),
            bytes: (*m.bytes).clone(),
        };
        if let Err(message) = post(inner, &request, None) {
            drop_model(inner, id, message);
        }
    }
}

/// The worker would not take one of the user's models: the page drops it (so that no worker is
/// asked again) and says so next to its method's file input.
fn drop_model(inner: &Inner, run: RunId, message: String) {
    let entry = {
        let mut sync = inner.model_sync.borrow_mut();
        let at = sync.iter().position(|(id, _, _)| *id == run);
        at.map(|at| sync.remove(at))
    };
    let Some((_, kind, name)) = entry else { return };
    inner.state.labels.remove(kind, &name);
    let input = inner.state.labels.input(kind);
    input.status.set(format!("The worker could not take your model `{name}` ({message}); it was dropped."));
    input.state.set(LoadStatus::Failed);
}

/// Posts the model file request `id`.
fn send_label_job(inner: &Rc<Inner>, id: RunId) -> Result<(), String> {
    let take = inner.shown.borrow().as_ref().map_or(0, |t| t.id);
    let request = {
        let jobs = inner.label_jobs.borrow();
        let job = jobs.iter().find(|j| j.id == id).ok_or("no model file request")?;
        Request::UseLabelModel { take, run: id, kind: job.kind, file: job.file.clone(), bytes: (*job.bytes).clone() }
    };
    post(inner, &request, None)
}

/// The model file request `id` failed: its message shows next to the method's file input; the
/// models the method had stay.
fn fail_label_job(inner: &Inner, id: RunId, message: String) {
    let job = {
        let mut jobs = inner.label_jobs.borrow_mut();
        let at = jobs.iter().position(|j| j.id == id);
        at.map(|at| jobs.remove(at))
    };
    let Some(job) = job else { return };
    let input = inner.state.labels.input(job.kind);
    input.status.set(message);
    input.state.set(LoadStatus::Failed);
}

/// The model `name` of `kind` becomes its method's model (added to the choice if new), and the
/// method runs again on the take on screen.
fn select_model(inner: &Rc<Inner>, kind: ModelKind, name: &str) {
    let Some(index) = inner.state.methods.iter().position(|m| kind_of(&m.info.name) == Some(kind)) else { return };
    let slot = &inner.state.methods[index];
    if let Some((value, choices)) = slot.param("model") {
        choices.update(|c| {
            if !c.iter().any(|o| o == name) {
                c.push(name.to_string());
            }
        });
        value.set(name.to_string());
    }
    if inner.shown.borrow().is_some() {
        start_run(inner, index);
    }
}

/// The worker installed a model file the user loaded.
fn on_label_model(inner: &Rc<Inner>, run: RunId, info: LabelModelInfo) {
    let job = {
        let mut jobs = inner.label_jobs.borrow_mut();
        let at = jobs.iter().position(|j| j.id == run);
        at.map(|at| jobs.remove(at))
    };
    let Some(job) = job else { return };
    let input = inner.state.labels.input(job.kind);
    let name = info.name.clone();
    input.status.set(format!(
        "Loaded {}: {} model `{name}`, {}. {} labels the take with it now.",
        job.file,
        kind_short(info.kind),
        describe(&info),
        kind_short(info.kind)
    ));
    input.state.set(LoadStatus::Done);
    inner.state.labels.add(UserModel { info, file: job.file, bytes: job.bytes });
    select_model(inner, job.kind, &name);
}

/// Posts the DT-FCN training under way: the take on screen first, then the takes the user added.
fn send_dtfcn_job(inner: &Rc<Inner>) -> Result<(), String> {
    let shown = inner.shown.borrow().clone().ok_or("load a take before training")?;
    let request = {
        let mut job = inner.dtfcn_job.borrow_mut();
        let job = job.as_mut().ok_or("no training")?;
        job.take_name = shown.name.clone();
        job.started = now();
        let ask = &job.ask;
        let mut takes = vec![shown.name.clone()];
        let mut bytes = vec![js_sys::Uint8Array::new(&shown.bytes).to_vec()];
        for (name, b) in &ask.extra {
            takes.push(name.clone());
            bytes.push((**b).clone());
        }
        Request::TrainDtfcn {
            take: shown.id,
            run: job.id,
            name: ask.name.clone(),
            labels_name: ask.labels_name.clone(),
            labels: ask.labels.clone(),
            takes,
            options: ask.options.clone(),
            bytes,
        }
    };
    post(inner, &request, None)
}

fn is_dtfcn_job(inner: &Inner, run: RunId) -> bool {
    inner.dtfcn_job.borrow().as_ref().is_some_and(|j| j.id == run)
}

/// The DT-FCN training under way failed or was refused: the message shows at `field` (or in the
/// status line); the model in use stays.
fn fail_dtfcn_job(inner: &Inner, message: String, field: Option<TrainField>) {
    inner.dtfcn_job.borrow_mut().take();
    let t = inner.state.dtfcn;
    match field {
        Some(field) => {
            t.refuse(field, message);
            t.status.set("Not trained: see the message at the input marked below.".into());
        }
        None => t.status.set(format!("Not trained: {message}")),
    }
    t.state.set(TrainState::Failed);
}

/// One more epoch of the training under way.
fn on_training_epoch(inner: &Inner, report: EpochReport) {
    let stopping = inner.dtfcn_job.borrow().as_ref().is_some_and(|j| j.stopping);
    let t = inner.state.dtfcn;
    let (epoch, epochs) = (report.epoch, report.epochs);
    t.reports.update(|r| {
        // a training started again on a new worker begins with epoch 1
        r.retain(|old| old.epoch < epoch);
        r.push(report);
    });
    if !stopping {
        t.state.set(TrainState::Training { stage: "training".into(), epoch, epochs });
    }
}

/// The DT-FCN training ended with a model, installed in the worker: the page keeps it (for the
/// download and for new workers), makes it DT-FCN's model and runs DT-FCN again.
fn on_dtfcn_trained(inner: &Rc<Inner>, trained: Trained) {
    let Some(job) = inner.dtfcn_job.borrow_mut().take() else { return };
    let seconds = (now() - job.started) / 1000.0;
    let Trained { model, reports, best_epoch, stopped, used_rows, left_out, bytes } = trained;
    let bytes = Arc::new(bytes);
    let name = model.name.clone();
    let t = inner.state.dtfcn;
    let ran = reports.len();
    t.reports.set(reports);
    t.trained.set(Some(TrainedFile { name: name.clone(), bytes: bytes.clone() }));
    let how = if stopped {
        format!("stopped after {ran} of {} epochs", job.ask.options.epochs)
    } else {
        format!("{ran} epochs")
    };
    let left = if left_out.is_empty() {
        String::new()
    } else {
        format!(" (rows for {} left out: not loaded)", left_out.join(", "))
    };
    t.status.set(format!(
        "Trained `{name}` on {used_rows} rows of {}{left}: {} classes ({}), {how} in {seconds:.1} s, the weights of epoch \
         {best_epoch} kept. DT-FCN labels {} with it now.",
        job.ask.labels_name,
        model.classes.len(),
        model.classes.join(", "),
        job.take_name
    ));
    t.state.set(TrainState::Done);
    inner.state.labels.add(UserModel { file: model_file_name(&name), info: model, bytes });
    select_model(inner, ModelKind::Dtfcn, &name);
}

/// What `dtfcn_trained` brings.
struct Trained {
    model: LabelModelInfo,
    reports: Vec<EpochReport>,
    best_epoch: usize,
    stopped: bool,
    used_rows: usize,
    left_out: Vec<String>,
    bytes: Vec<u8>,
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
    let label_jobs: Vec<RunId> = inner.label_jobs.borrow().iter().map(|j| j.id).collect();
    for id in label_jobs {
        if let Err(message) = send_label_job(inner, id) {
            fail_label_job(inner, id, message);
        }
    }
    let training = inner.dtfcn_job.borrow().as_ref().map(|j| j.stopping);
    match training {
        Some(true) => {
            fail_dtfcn_job(inner, "the worker was replaced before it sent the stopped model; train again".into(), None)
        }
        Some(false) => {
            let t = inner.state.dtfcn;
            t.reports.set(Vec::new());
            let epochs = inner.dtfcn_job.borrow().as_ref().map_or(1, |j| j.ask.options.epochs);
            t.state.set(TrainState::Training { stage: "starting again".into(), epoch: 0, epochs });
            t.status
                .set("The worker was replaced (a cancel or a crash): the training starts again from epoch 1.".into());
            if let Err(message) = send_dtfcn_job(inner) {
                fail_dtfcn_job(inner, message, None);
            }
        }
        None => {}
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
    let label_jobs: Vec<RunId> = inner.label_jobs.borrow().iter().map(|j| j.id).collect();
    for id in label_jobs {
        fail_label_job(inner, id, format!("the worker failed: {message}"));
    }
    if inner.dtfcn_job.borrow().is_some() {
        fail_dtfcn_job(inner, format!("the worker failed: {message}"), None);
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
            } else if is_dtfcn_job(inner, run) && !inner.dtfcn_job.borrow().as_ref().is_some_and(|j| j.stopping) {
                state.dtfcn.state.update(|s| {
                    if let TrainState::Training { stage: st, .. } = s {
                        *st = stage;
                    }
                });
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
                slot.export_status.set(None);
                slot.failure.set(None);
                slot.field_error.set(None);
            }
            inner.runs.borrow_mut().iter_mut().for_each(|r| *r = None);
            state.motion.set(Some(Arc::new(*motion)));
            state.error.set(None);
            state.load.set(LoadState::Ready);
            let auto_run = inner.auto_run.borrow().clone();
            for (index, slot) in state.methods.iter().enumerate() {
                let wanted = auto_run.as_ref().map_or(slot.info.auto_run, |names| names.contains(&slot.info.name));
                if wanted {
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
        Response::Clips { run, file, clips, bytes, .. } => {
            if let Some((_, status, _)) = take_clip_job(inner, run) {
                let said = match download(&bytes, clip_mime(&file), &file) {
                    Ok(()) => (false, format!("saved {file} ({})", crate::method::counted(clips, "clip"))),
                    Err(e) => (true, format!("could not save {file}: {}", js_message(&e))),
                };
                status.set(Some(said));
            }
        }
        Response::Failed { run: Some(run), message, kind, .. }
            if inner.clip_jobs.borrow().iter().any(|(r, _, _)| r.run_id() == Some(run)) =>
        {
            let Some((request, status, retried)) = take_clip_job(inner, run) else { return };
            match kind {
                FailureKind::NotLoaded if !retried => {
                    let sent = restore(inner).and_then(|()| post(inner, &request, None));
                    match sent {
                        Ok(()) => inner.clip_jobs.borrow_mut().push((request, status, true)),
                        Err(e) => status.set(Some((true, e))),
                    }
                }
                _ => {
                    status.set(Some((true, message)));
                    if kind == FailureKind::Internal {
                        replace_worker(inner);
                    }
                }
            }
        }
        Response::NeedsModel { run, file, .. } => need_model(inner, run, file),
        Response::Refused { run, message, param, .. } => {
            if let Some(index) = run_index(inner, run) {
                refuse_run(inner, index, message, param);
            }
        }
        Response::Trained { run, model, report, origin, used_rows, ignored_rows, .. } if is_lma_job(inner, run) => {
            on_trained(inner, model, report, origin, (used_rows, ignored_rows));
        }
        Response::ModelInUse { run, origin, shipped, .. } if is_lma_job(inner, run) => {
            on_model_in_use(inner, origin, shipped);
        }
        Response::ModelInUse { run, .. } if inner.family_sync.get() == Some(run) => inner.family_sync.set(None),
        Response::LabelModelInUse { run, model, .. } => {
            let synced = {
                let mut sync = inner.model_sync.borrow_mut();
                let before = sync.len();
                sync.retain(|(id, _, _)| *id != run);
                sync.len() != before
            };
            if !synced {
                on_label_model(inner, run, model);
            }
        }
        Response::TrainingEpoch { run, report, .. } if is_dtfcn_job(inner, run) => on_training_epoch(inner, report),
        Response::DtfcnTrained { run, model, reports, best_epoch, stopped, used_rows, left_out, bytes, .. }
            if is_dtfcn_job(inner, run) =>
        {
            on_dtfcn_trained(inner, Trained { model, reports, best_epoch, stopped, used_rows, left_out, bytes });
        }
        Response::Failed { run: Some(run), message, kind, field, .. } if is_dtfcn_job(inner, run) => {
            fail_dtfcn_job(inner, message, field);
            if kind == FailureKind::Internal {
                replace_worker(inner);
            }
        }
        Response::Failed { run: Some(run), message, kind, .. }
            if inner.label_jobs.borrow().iter().any(|j| j.id == run) =>
        {
            fail_label_job(inner, run, message);
            if kind == FailureKind::Internal {
                replace_worker(inner);
            }
        }
        Response::Failed { run: Some(run), message, kind, .. }
            if inner.model_sync.borrow().iter().any(|(id, _, _)| *id == run) =>
        {
            drop_model(inner, run, message);
            if kind == FailureKind::Internal {
                replace_worker(inner);
            }
        }
        Response::Failed { run: Some(run), message, kind, .. } if is_lma_job(inner, run) => {
            on_lma_job_failed(inner, message, kind);
        }
        Response::Failed { run: Some(run), message, kind, .. } if inner.family_sync.get() == Some(run) => {
            drop_family(inner, message);
            if kind == FailureKind::Internal {
                replace_worker(inner);
            }
        }
        Response::Failed { take, run: None, message, kind, .. } => {
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

/// Removes and returns the clip export `run`.
fn take_clip_job(inner: &Inner, run: RunId) -> Option<(Request, ExportStatus, bool)> {
    let mut jobs = inner.clip_jobs.borrow_mut();
    let i = jobs.iter().position(|(r, _, _)| r.run_id() == Some(run))?;
    Some(jobs.remove(i))
}

/// The type of a clip export's file.
fn clip_mime(file: &str) -> &'static str {
    if file.ends_with(".zip") {
        "application/zip"
    } else {
        "application/octet-stream"
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
