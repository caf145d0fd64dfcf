//! The page's side of the worker: reads a dropped/picked file or fetches the bundled sample,
//! hands its bytes to the worker (transferred, not copied), asks for segmentations and turns the
//! worker's [`Response`]s into state.
//!
//! Every load gets a new take id; only the newest load counts. The page keeps the take on screen
//! as a `Blob` — the dropped `File` itself (a handle on the file, not its bytes), or what a
//! download read — never a second copy of its bytes: they are read from it each time they go to
//! a worker, and the worker holds the only copy. Every `segment` request names that take: a
//! worker that holds another one (or none: a load that failed lets the previous take go, and a
//! new worker after a crash or a cancel holds nothing) answers `not_loaded`, and the page sends
//! it the take on screen again and repeats the request once. A worker whose wasm trapped, or
//! whose run the user cancels, is replaced.
//!
//! The models of the supervised methods (any method that declares [`crate::method::Supervision`])
//! are the page's too: a model file is stored in the worker (`use_model`, its answer adds it to
//! the method's `model` choice and runs the method again), every model the page holds goes to
//! each new worker before anything else, and a model file request or a training under way is sent
//! again to a new worker (the training then starts again from its first step). A training runs
//! one step per message; Stop asks the worker to end it after the step under way and keep the
//! best model so far (before its first step, the worker is replaced). A take opened while a
//! training runs waits for the user's answer ([`Loader::switch_question`], [`Loader::answer_switch`]:
//! stop it, or keep it running bound to its own take, whose file a new worker is sent again).
//!
//! The shipped models are not in the wasm: a run that needs one the worker does not hold is
//! answered `needs_model`, and [`crate::app::models::model_files`] fetches it, hands it over and asks again.
//!
//! The library of takes ([`library`]) has the worker segment its takes one after another without
//! replacing the take it holds, and cut clips of several takes into one zip.
//!
//! A feature's own work in the main worker — the Effort bars' annotations
//! ([`crate::app::effort::jobs`]), the rows' clip exports ([`crate::app::timeline::clip_jobs`]) — is the
//! feature's: it registers its [`Jobs`] and sends its requests through [`Loader::send`], and the loader
//! routes every reply by its run id to the jobs that sent it, tells each registered feature when the
//! worker is replaced, and makes a run that needs a shipped model file wait for it whoever sent it.

mod library;
mod pool;
mod shipped;
mod training;

use crate::app::dom::js_message;
use crate::app::models::model_files::ModelFiles;
use crate::app::state::AppState;
use crate::app::state::LoadState;
use crate::app::state::MethodSlot;
use crate::app::state::RunState;
use crate::app::take::fetch::{blob_bytes, read_capped, ReadError};
use crate::load::Opening;
use crate::protocol::{FailureKind, Request, Response, RunId, TakeId};
use crate::worker::{request_message, response_from_js};
use js_sys::ArrayBuffer;
use leptos::prelude::*;
use std::cell::{Cell, RefCell};
use std::collections::HashMap;
use std::rc::{Rc, Weak};
use std::sync::Arc;
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;
use wasm_bindgen_futures::JsFuture;
use web_sys::{Blob, Event, File, MessageEvent, Response as FetchResponse, Worker, WorkerOptions, WorkerType};

/// The largest file the page reads (the worker's memory budget then checks what it needs).
pub const MAX_FILE_BYTES: f64 = crate::app::take::fetch::MAX_FILE_BYTES as f64;

/// Where the worker script, the bundled sample and the shipped models are, relative to the page.
#[derive(Debug, Clone, PartialEq)]
pub struct Urls {
    pub worker: String,
    pub sample: String,
    /// The folder of the shipped model files.
    pub models: String,
    /// How many workers the page may start (`data-workers`; `None`: one per core, at least two).
    pub workers: Option<usize>,
}

impl Urls {
    /// The defaults, overridden by the root element's `data-worker-url` / `data-sample-url` /
    /// `data-models-url`.
    pub fn from_root(root: &web_sys::Element) -> Urls {
        let get = |name: &str, default: &str| root.get_attribute(name).unwrap_or_else(|| default.to_string());
        Urls {
            worker: get("data-worker-url", "./www/worker.js"),
            // the sample packed (src/bvh/pack.rs: half the download of www/sample.bvh, the same bytes)
            sample: get("data-sample-url", "./www/sample.bvh.pack"),
            models: get("data-models-url", "./models/"),
            workers: root.get_attribute("data-workers").and_then(|n| n.trim().parse().ok()),
        }
    }

    /// The file name at the end of the sample's URL (of the file a pack holds, for a pack).
    pub fn sample_name(&self) -> String {
        let name = self.sample.rsplit('/').next().unwrap_or("sample.bvh");
        crate::bvh::unpacked_name(name).unwrap_or(name).to_string()
    }

    /// Whether the sample's URL names a pack (`NAME.bvh.pack`), which the page unpacks.
    fn sample_is_packed(&self) -> bool {
        let name = self.sample.rsplit('/').next().unwrap_or_default();
        crate::bvh::unpacked_name(name).is_some()
    }
}

/// A worker event handler, kept alive as long as the worker it listens to.
type Handler = Closure<dyn FnMut(JsValue)>;

/// A take the page can send to a worker again: its file as a `Blob` (its bytes are read from it
/// for each send, and transferred).
#[derive(Clone)]
struct Take {
    id: TakeId,
    name: String,
    file: Blob,
    /// An AMC motion's ASF skeleton: its name and bytes.
    skeleton: Option<(String, Vec<u8>)>,
}

/// A run asked of the worker: its request, whether it was already repeated after a
/// `not_loaded` answer, and whether a worker died under it already (it is asked again once).
struct Run {
    id: RunId,
    method: String,
    params: serde_json::Value,
    retried: bool,
    crashed: bool,
}

/// A feature's work in the main worker: the loader hands it every reply to a run it sent
/// ([`Loader::send`]), and asks it to send again what waits when the worker is replaced. A run that needs a shipped
/// model file waits for it ([`shipped`]), its progress shown by [`Jobs::stage`], then is sent again
/// ([`Jobs::send_again`]) or fails ([`Jobs::fail`]).
pub(crate) trait Jobs {
    /// A reply about one of the runs this feature sent (never `needs_model`: the loader fetches the file).
    fn reply(&self, response: Response);
    /// A new worker replaced the one that had this feature's requests: send again what still waits.
    fn resend(&self) {}
    /// Run `run` waits for a shipped model file (`stage` says which, `fraction` how far).
    fn stage(&self, _run: RunId, _stage: &str, _fraction: f64) {}
    /// Run `run` can be asked again (the model file it waited for is in the worker).
    fn send_again(&self, _run: RunId) {}
    /// Run `run` cannot have the model file it waited for.
    fn fail(&self, _run: RunId, _message: String) {}
}

/// A handle on the worker; cheap to clone.
#[derive(Clone)]
pub struct Loader(Rc<Inner>);

struct Inner {
    state: AppState,
    urls: Urls,
    worker: RefCell<Option<Worker>>,
    /// The pool's run workers (slots 1…; `None`: one that could not be started) ([`pool`]).
    helpers: RefCell<Vec<Option<pool::RunWorker>>>,
    /// Which worker runs which method's run, and what waits ([`crate::worker::pool`]).
    pool: RefCell<crate::worker::pool::Pool>,
    /// Take and run ids come from one counter.
    next_id: Cell<u32>,
    /// Id of the newest load; messages about other loads are stale.
    current: Cell<TakeId>,
    /// The newest load while the worker works on it.
    pending: RefCell<Option<Take>>,
    /// Counts the sends of loads: a send whose file was read after a newer send began (a worker
    /// replaced meanwhile sends the pending load again) is dropped, so that no worker gets a
    /// load twice.
    load_sends: Cell<u32>,
    /// The take on screen.
    shown: RefCell<Option<Take>>,
    /// The current run of each method (by registry name).
    runs: RefCell<Vec<Option<Run>>>,
    /// Model files being stored (one per method at a time).
    model_jobs: RefCell<Vec<training::ModelJob>>,
    /// The requests that gave the newest worker the user's models: run, method slot and name.
    model_sync: RefCell<Vec<(RunId, usize, String)>>,
    /// The training under way (one at a time).
    train_job: RefCell<Option<training::TrainJob>>,
    /// Models kept in this browser being given to the worker after a reload: run, file, bytes.
    restoring: RefCell<Vec<(RunId, String, Arc<Vec<u8>>)>>,
    /// The take the user opened during a training, waiting for their answer to `switch`.
    asked_open: RefCell<Option<training::Open>>,
    switch: RwSignal<Option<training::SwitchAsk>>,
    /// Keeps the worker's event handlers alive.
    handlers: RefCell<Vec<Handler>>,
    /// The features' jobs registered ([`Loader::register`]): told when the worker is replaced.
    features: RefCell<Vec<Rc<dyn Jobs>>>,
    /// Which feature's jobs sent each run under way ([`Loader::send`]): its replies go there.
    routes: RefCell<HashMap<RunId, Rc<dyn Jobs>>>,
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
        let workers = pool::workers(urls.workers);
        let inner = Rc::new(Inner {
            state,
            urls,
            worker: RefCell::new(None),
            helpers: RefCell::new((1..workers).map(|_| None).collect()),
            pool: RefCell::new(crate::worker::pool::Pool::new(workers)),
            next_id: Cell::new(0),
            current: Cell::new(0),
            pending: RefCell::new(None),
            load_sends: Cell::new(0),
            shown: RefCell::new(None),
            runs: RefCell::new(state.methods.iter().map(|_| None).collect()),
            model_jobs: RefCell::new(Vec::new()),
            model_sync: RefCell::new(Vec::new()),
            train_job: RefCell::new(None),
            restoring: RefCell::new(Vec::new()),
            asked_open: RefCell::new(None),
            switch: RwSignal::new(None),
            handlers: RefCell::new(Vec::new()),
            features: RefCell::new(Vec::new()),
            routes: RefCell::new(HashMap::new()),
            auto_run: RefCell::new(None),
            src_take: RefCell::new(None),
            models,
        });
        spawn_worker(&inner);
        for slot in 1..workers {
            pool::spawn(&inner, slot);
        }
        let loader = Loader(inner);
        loader.restore_kept_models();
        loader
    }

    /// Loads the bundled sample — after asking, when a training is under way
    /// ([`Loader::switch_question`]).
    pub fn load_sample(&self) {
        self.0.state.library.open.set(None);
        if let Some(open) = training::ask_before_opening(&self.0, training::Open::Sample) {
            open_now(&self.0, open);
        }
    }

    /// The question on screen while a take the user opened waits for their answer about the
    /// training under way (`None`: nothing asked).
    pub fn switch_question(&self) -> RwSignal<Option<training::SwitchAsk>> {
        self.0.switch
    }

    /// Opens the take that waits for the question's answer: `stop` stops the training first (its
    /// best model so far is then offered for its own take); else it keeps running, bound to its take.
    pub fn answer_switch(&self, stop: bool) {
        let Some(open) = training::answered(&self.0) else { return };
        if stop {
            // (the borrow ends before Stop, which may replace the worker)
            let index = self.0.train_job.borrow().as_ref().map(training::TrainJob::index);
            if let Some(index) = index {
                self.stop_training(index);
            }
        }
        open_now(&self.0, open);
    }

    /// Withdraws the take the question was about (Esc): nothing opens, the training goes on.
    pub fn cancel_switch(&self) {
        drop(training::answered(&self.0));
    }
}

impl Loader {
    /// Registers a feature's jobs: told when the worker is replaced ([`Jobs::resend`]).
    pub(crate) fn register(&self, jobs: Rc<dyn Jobs>) {
        self.0.features.borrow_mut().push(jobs);
    }

    /// The take on screen (the one a request names), if any.
    pub(crate) fn shown_take(&self) -> Option<TakeId> {
        self.0.shown.borrow().as_ref().map(|t| t.id)
    }

    /// A new run id (take and run ids come from one counter).
    pub(crate) fn new_run(&self) -> RunId {
        next_id(&self.0)
    }

    /// Posts `request` to the main worker, its replies routed to `jobs` until [`Loader::forget`] (not routed when it
    /// could not be posted).
    pub(crate) fn send(&self, jobs: Rc<dyn Jobs>, request: &Request) -> Result<(), String> {
        let run = request.run_id();
        if let Some(run) = run {
            self.0.routes.borrow_mut().insert(run, jobs);
        }
        let sent = post(&self.0, request, None);
        if let (Err(_), Some(run)) = (&sent, run) {
            self.forget(run);
        }
        sent
    }

    /// [`Loader::send`] once the take on screen is sent to the worker again (it answered `not_loaded`).
    pub(crate) async fn send_with_take(&self, jobs: Rc<dyn Jobs>, request: &Request) -> Result<(), String> {
        restore(&self.0).await?;
        self.send(jobs, request)
    }

    /// Stops routing `run`'s replies (its job is over).
    pub(crate) fn forget(&self, run: RunId) {
        self.0.routes.borrow_mut().remove(&run);
    }

    /// Replaces the main worker (it trapped), with everything it was doing.
    pub(crate) fn replace_worker(&self) {
        replace_worker(&self.0)
    }
}

/// The feature's jobs that sent run `run`, if a feature sent it.
fn route(inner: &Inner, run: RunId) -> Option<Rc<dyn Jobs>> {
    inner.routes.borrow().get(&run).cloned()
}

/// Opens `open` at once.
fn open_now(inner: &Rc<Inner>, open: training::Open) {
    match open {
        training::Open::Sample => open_sample(inner),
        training::Open::Files(files) => open_files(inner, files),
    }
}

/// Loads the bundled sample.
fn open_sample(inner: &Rc<Inner>) {
    let inner = inner.clone();
    let (url, name, packed) = (inner.urls.sample.clone(), inner.urls.sample_name(), inner.urls.sample_is_packed());
    let id = begin(&inner, &name);
    wasm_bindgen_futures::spawn_local(async move {
        let file = match fetch_blob(&url).await {
            Ok(file) if packed => unpack_blob(&file).await,
            fetched => fetched,
        };
        match file {
            Ok(file) => send_load(&inner, id, &name, file, None),
            Err(message) => fail_load(&inner, id, format!("{name}: could not load the sample: {message}")),
        }
    });
}

impl Loader {
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
        fetch: impl std::future::Future<Output = Result<(Blob, Option<(String, Vec<u8>)>), String>> + 'static,
    ) {
        let inner = self.0.clone();
        let id = begin(&inner, &name);
        *inner.src_take.borrow_mut() = Some((id, url));
        wasm_bindgen_futures::spawn_local(async move {
            match fetch.await {
                Ok((file, skeleton)) => send_load(&inner, id, &name, file, skeleton),
                Err(message) => {
                    inner.src_take.borrow_mut().take();
                    fail_load(&inner, id, message)
                }
            }
        });
    }

    /// Loads the files the user dropped or picked at once: one take's file, or an ASF skeleton
    /// with its AMC motion ([`crate::load::opening`] says which, or why neither) — after asking,
    /// when a training is under way ([`Loader::switch_question`]).
    pub fn load_files(&self, files: Vec<File>) {
        if let Some(open) = training::ask_before_opening(&self.0, training::Open::Files(files)) {
            open_now(&self.0, open);
        }
    }
}

/// Loads the files `files` (see [`Loader::load_files`]).
fn open_files(inner: &Rc<Inner>, files: Vec<File>) {
    let inner = inner.clone();
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
        // the File itself: its bytes are read when it is sent, and not kept
        send_load(&inner, id, &name, Blob::from(motion), skeleton);
    });
}

impl Loader {
    /// Runs method `index` of the registry on the take on screen with the parameters of its form.
    pub fn run(&self, index: usize) {
        start_run(&self.0, index);
    }

    /// Runs method `index` again because its model choice changed (on its row or in its panel),
    /// unless no take is on screen or the run under way already uses that model.
    pub fn rerun_with_model(&self, index: usize) {
        let inner = &self.0;
        if inner.shown.borrow().is_none() {
            return;
        }
        let Some((value, _)) = inner.state.methods[index].param("model") else { return };
        let model = value.get_untracked();
        let underway = inner.runs.borrow()[index]
            .as_ref()
            .is_some_and(|r| r.params.get("model").and_then(|m| m.as_str()) == Some(model.as_str()));
        if !underway {
            start_run(inner, index);
        }
    }

    /// Stops method `index`'s run: the worker is replaced (a wasm worker cannot be interrupted),
    /// and the other methods' runs start again on the new one.
    pub fn cancel(&self, index: usize) {
        let inner = &self.0;
        let Some(run) = inner.runs.borrow_mut()[index].take() else { return };
        inner.state.methods[index].run.set(RunState::Cancelled);
        let stop = inner.pool.borrow_mut().stop(run.id);
        match stop {
            crate::worker::pool::Stop::Replace(slot) => replace_slot(inner, slot),
            crate::worker::pool::Stop::Dequeued | crate::worker::pool::Stop::Unknown => {}
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
    // a model file the main worker is given goes to the pool's run workers too
    pool::share_model(inner, request);
    if inner.worker.borrow().is_none() {
        spawn_worker(inner);
    }
    let worker = inner.worker.borrow();
    let worker = worker.as_ref().ok_or("the worker could not be started")?;
    let (message, transfer) = request_message(request, bytes);
    worker.post_message_with_transfer(&message, &transfer).map_err(|e| js_message(&e))
}

/// Posts `request` with `buffers` (JS `ArrayBuffer`s, transferred), starting a worker if there is
/// none.
/// Posts `request` with its own buffers (a library's features), moved out of it rather than copied.
fn post_request(inner: &Rc<Inner>, request: Request) -> Result<(), String> {
    if inner.worker.borrow().is_none() {
        spawn_worker(inner);
    }
    let worker = inner.worker.borrow();
    let worker = worker.as_ref().ok_or("the worker could not be started")?;
    let (message, transfer) = crate::worker::packet_to_js(request.into_packet());
    worker.post_message_with_transfer(&message, &transfer).map_err(|e| js_message(&e))
}

fn post_buffers(inner: &Rc<Inner>, request: &Request, buffers: js_sys::Array) -> Result<(), String> {
    if inner.worker.borrow().is_none() {
        spawn_worker(inner);
    }
    let worker = inner.worker.borrow();
    let worker = worker.as_ref().ok_or("the worker could not be started")?;
    let (message, transfer) = crate::worker::request_with_buffers(request, buffers);
    worker.post_message_with_transfer(&message, &transfer).map_err(|e| js_message(&e))
}

/// Sends a load of `file` as take `id`, with its ASF `skeleton` (name, bytes) for an AMC motion
/// (`None` for any other file); the page keeps the `Blob`, to send it again if needed. One
/// function for both, so that no path (a worker restart) can send an AMC without its skeleton.
fn send_load(inner: &Rc<Inner>, id: TakeId, name: &str, file: Blob, skeleton: Option<(String, Vec<u8>)>) {
    if inner.current.get() != id {
        return;
    }
    let take = Take { id, name: name.to_string(), file, skeleton };
    *inner.pending.borrow_mut() = Some(take.clone());
    let send = inner.load_sends.get().wrapping_add(1);
    inner.load_sends.set(send);
    let inner = inner.clone();
    wasm_bindgen_futures::spawn_local(async move {
        let bytes = blob_bytes(&take.file).await.map_err(|e| format!("could not read the file: {e}"));
        // a newer load, or a newer send of this one, is the one to post
        let newest = inner.load_sends.get() == send && inner.pending.borrow().as_ref().is_some_and(|t| t.id == take.id);
        if !newest {
            return;
        }
        let sent = bytes.and_then(|bytes| post(&inner, &load_request(&take, false), Some(&bytes)));
        if let Err(e) = sent {
            fail_load(&inner, take.id, format!("{}: {e}", take.name));
        }
    });
}

/// The load request of `take` (its bytes go as the transferred buffer).
fn load_request(take: &Take, restore: bool) -> Request {
    let (skeleton, skeleton_bytes) = match &take.skeleton {
        Some((name, bytes)) => (Some(name.clone()), bytes.clone()),
        None => (None, Vec::new()),
    };
    Request::Load { take: take.id, name: take.name.clone(), restore, bytes: Vec::new(), skeleton, skeleton_bytes }
}

/// Sends the take on screen to the worker again (it answers `restored`); its bytes are read from
/// its `Blob` first.
async fn restore(inner: &Rc<Inner>) -> Result<(), String> {
    let take = inner.shown.borrow().clone().ok_or("no take is loaded")?;
    let bytes =
        blob_bytes(&take.file).await.map_err(|e| format!("{}: could not read the file again: {e}", take.name))?;
    post(inner, &load_request(&take, true), Some(&bytes))
}

fn fail_load(inner: &Inner, id: TakeId, message: String) {
    let message = match inner.src_take.borrow().as_ref() {
        Some((take, url)) if *take == id => crate::app::embed::url_params::load_failed(url, &message),
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
    // a run asked again replaces the one under way: its worker is replaced, or it stops waiting
    let previous = inner.runs.borrow_mut()[index].replace(Run {
        id,
        method: slot.info.name.clone(),
        params,
        retried: false,
        crashed: false,
    });
    if let Some(previous) = previous {
        stop_in_pool(inner, previous.id);
    }
    slot.run.set(RunState::Running { stage: "starting".into(), fraction: 0.0 });
    if let Err(message) = send_run(inner, index) {
        fail_run(inner, index, format!("{}: {message}", slot.info.short));
    }
}

/// Stops run `run` wherever the pool has it: a waiting run is dropped, a run worker running it is
/// replaced; the main worker finishes it (it holds more than the run), its answer dropped.
fn stop_in_pool(inner: &Rc<Inner>, run: RunId) {
    let stop = inner.pool.borrow_mut().stop(run);
    if let crate::worker::pool::Stop::Replace(slot) = stop {
        if slot > 0 {
            pool::replace(inner, slot);
        }
    }
}

/// Posts the current run of method `index` for the take on screen to the worker the pool gives it
/// (or leaves it waiting for one, "waiting for a worker" on its row).
fn send_run(inner: &Rc<Inner>, index: usize) -> Result<(), String> {
    let take = inner.shown.borrow().as_ref().map(|t| t.id).ok_or("no take is loaded")?;
    let request = {
        let runs = inner.runs.borrow();
        let run = runs[index].as_ref().ok_or("no run")?;
        Request::Segment { take, run: run.id, method: run.method.clone(), params: run.params.clone() }
    };
    let run = request.run_id().unwrap_or_default();
    let placed = inner.pool.borrow_mut().place(run);
    match placed {
        crate::worker::pool::Placed::Now(slot) => pool::post_to(inner, slot, request),
        crate::worker::pool::Placed::Queued => {
            inner.state.methods[index]
                .run
                .set(RunState::Running { stage: "waiting for a worker".into(), fraction: 0.0 });
            Ok(())
        }
    }
}

/// A run failed: a refusal that names one of the method's parameters shows at that field, any
/// other message in the banner.
fn fail_run(inner: &Rc<Inner>, index: usize, message: String) {
    refuse_run(inner, index, message, None)
}

/// A run failed or was refused: a refusal of one of the method's parameters (`param`, as the
/// method named it) shows at that field, any other message in the banner.
fn refuse_run(inner: &Rc<Inner>, index: usize, message: String, param: Option<String>) {
    let run = inner.runs.borrow_mut()[index].take();
    if let Some(run) = run {
        pool::release_run(inner, run.id);
    }
    let slot = &inner.state.methods[index];
    slot.run.set(RunState::Failed);
    match param.filter(|p| slot.specs.iter().any(|s| s.name == *p)) {
        Some(param) => slot.field_error.set(Some((param, message))),
        None => {
            slot.failure.set(Some(message.clone()));
            inner.state.show_run_error(no_method_can_read(&inner.state).unwrap_or(message));
        }
    }
}

/// One banner for all when every method that ran on the take (two or more) failed on it: what
/// each said, the shared reason once ([`crate::app::take::run_failures`]); `None` while one is still
/// running or has a result.
fn no_method_can_read(state: &AppState) -> Option<String> {
    let mut failures = Vec::new();
    for slot in state.methods {
        match slot.run.get_untracked() {
            RunState::Idle | RunState::Cancelled => {}
            RunState::Failed => failures.push((slot.info.short.clone(), slot.failure.get_untracked()?)),
            RunState::Running { .. } | RunState::Done => return None,
        }
    }
    let failures: Vec<(&str, &str)> = failures.iter().map(|(m, f)| (m.as_str(), f.as_str())).collect();
    (failures.len() >= 2).then(|| crate::app::take::run_failures::no_method_can_read(&failures))
}

/// Whether method `index`'s current run meets something for the first time (`flag`: it was asked again
/// after `not_loaded`, or after its worker died), noting that it has: each is allowed once.
fn first_time(inner: &Inner, index: usize, flag: impl FnOnce(&mut Run) -> &mut bool) -> bool {
    inner.runs.borrow_mut()[index].as_mut().is_some_and(|r| !std::mem::replace(flag(r), true))
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
    give_compiled_wasm(&worker);
    *inner.handlers.borrow_mut() = vec![on_message, on_error];
    *inner.worker.borrow_mut() = Some(worker);
    training::send_models(inner);
    shipped::send_model_files(inner);
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

/// A new worker in place of the old one, given the work the old one had: the pending load and
/// every run still under way (each first gets `not_loaded`, then the take on screen).
fn replace_worker(inner: &Rc<Inner>) {
    spawn_worker(inner);
    // the pending load as it was asked: an AMC motion with its ASF skeleton
    let pending = inner.pending.borrow().clone();
    if let Some(take) = pending {
        send_load(inner, take.id, &take.name, take.file, take.skeleton);
    }
    // the main worker's run (unless it was the one cancelled or failed), else the next waiting one
    let run = inner.pool.borrow().running(0);
    let wanted = run.is_some_and(|run| pool::wanted(inner, run));
    let next = inner.pool.borrow_mut().replaced(0, !wanted);
    if let Some(run) = next {
        pool::post_run(inner, run);
    }
    training::resend(inner);
    let features = inner.features.borrow().clone();
    for jobs in features {
        jobs.resend();
    }
    library::resend(inner);
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
    // dead under a method's run (out of memory, say) for the first time: replaced, the run asked again
    let run = inner.pool.borrow().running(0);
    let again =
        run.and_then(|run| run_index(inner, run)).is_some_and(|index| first_time(inner, index, |r| &mut r.crashed));
    if again {
        web_sys::console::warn_1(&format!("the worker stopped ({message}): started again").into());
        return replace_worker(inner);
    }
    fail_load(inner, inner.current.get(), format!("the worker failed: {message}"));
    // the run it was busy with (the run workers' go on)
    if let Some(index) = run.and_then(|run| run_index(inner, run)) {
        fail_run(inner, index, format!("the worker failed: {message}"));
    } else if let Some(run) = run {
        pool::release(inner, 0, run);
    }
    training::fail_all(inner, &format!("the worker failed: {message}"));
    if let Some(worker) = inner.worker.borrow_mut().take() {
        worker.terminate();
    }
    library::fail_all(inner, &format!("the worker failed: {message}"));
}

fn on_message(inner: &Rc<Inner>, data: JsValue) {
    let response = match response_from_js(&data) {
        Ok(r) => r,
        Err(message) => return fail_load(inner, inner.current.get(), message),
    };
    // the answers to the library's jobs and the supervised methods' jobs are theirs, and a feature's
    // replies go to the jobs that sent the run (but a run that needs a model file waits for it here)
    let Some(response) = library::handle(inner, response) else { return };
    let routed = match &response {
        Response::NeedsModel { .. } => None,
        other => other.run_id().and_then(|run| route(inner, run)),
    };
    if let Some(jobs) = routed {
        return jobs.reply(response);
    }
    let Some(response) = training::handle(inner, response) else { return };
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
            // every run worker gets the take (the main worker's motion of it) before its first run
            pool::new_take(inner);
            let auto_run = inner.auto_run.borrow().clone();
            for (index, slot) in state.methods.iter().enumerate() {
                let wanted = auto_run.as_ref().map_or(slot.info.auto_run, |names| names.contains(&slot.info.name));
                if wanted {
                    start_run(inner, index);
                }
            }
        }
        Response::Failed { take, run: None, message, kind, .. } => {
            fail_load(inner, take, message);
            if kind == FailureKind::Internal {
                replace_worker(inner);
            }
        }
        response @ (Response::Progress { run: Some(_), .. }
        | Response::Segmented { .. }
        | Response::NeedsModel { .. }
        | Response::Refused { .. }
        | Response::Failed { run: Some(_), .. }) => on_run_response(inner, 0, response),
        _ => {} // about a load that has been superseded
    }
}

/// An answer from worker `slot` (0: the main worker) about a method's run: its progress, its result,
/// its refusal or failure, or its wait for a model file. Any answer but progress and `not_loaded`
/// (after which the take is sent again and the run asked again of the same worker) frees the worker
/// for the next waiting run.
fn on_run_response(inner: &Rc<Inner>, slot: crate::worker::pool::Slot, response: Response) {
    let state = inner.state;
    let last = match &response {
        // the worker does not hold the run's take: asked again of it — unless the page no longer wants
        // the run (a previous take's, posted just before the next take's load): then the worker is free
        Response::Failed { kind: FailureKind::NotLoaded, run: Some(run), .. } => {
            run_index(inner, *run).is_none().then_some(*run)
        }
        Response::Progress { .. } | Response::Failed { kind: FailureKind::NotLoaded, .. } => None,
        Response::Segmented { run, .. }
        | Response::NeedsModel { run, .. }
        | Response::Refused { run, .. }
        | Response::Failed { run: Some(run), .. } => Some(*run),
        _ => None,
    };
    if let Some(run) = last {
        pool::release(inner, slot, run);
    }
    match response {
        Response::Progress { run: Some(run), stage, fraction, .. } => {
            if let Some(index) = run_index(inner, run) {
                state.methods[index].run.set(RunState::Running { stage, fraction: fraction.unwrap_or(0.0) });
            } else if slot == 0 {
                training::progress(inner, run, stage, fraction);
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
        Response::NeedsModel { run, file, .. } => shipped::need_model(inner, run, file),
        Response::Refused { run, message, param, .. } => {
            if let Some(index) = run_index(inner, run) {
                refuse_run(inner, index, message, param);
            }
        }
        Response::Failed { run: Some(run), message, kind, .. } => {
            let Some(index) = run_index(inner, run) else {
                if kind == FailureKind::Internal {
                    replace_slot(inner, slot);
                }
                return;
            };
            match kind {
                FailureKind::NotLoaded if slot > 0 => pool::not_loaded(inner, slot, index, message),
                FailureKind::NotLoaded => {
                    let first = first_time(inner, index, |r| &mut r.retried);
                    if !first {
                        return fail_run(inner, index, message);
                    }
                    let inner = inner.clone();
                    wasm_bindgen_futures::spawn_local(async move {
                        let restored = restore(&inner).await;
                        // the run may have been cancelled, or replaced, while the file was read
                        if run_index(&inner, run) != Some(index) {
                            return;
                        }
                        if let Err(e) = restored.and_then(|()| send_run(&inner, index)) {
                            fail_run(&inner, index, format!("{message} ({e})"));
                        }
                    });
                }
                FailureKind::Internal => {
                    // the run trapped: it fails (it would trap again) and its worker is replaced
                    fail_run(inner, index, message);
                    replace_slot(inner, slot);
                }
                FailureKind::Cancelled => {
                    inner.runs.borrow_mut()[index] = None;
                    state.methods[index].run.set(RunState::Cancelled);
                }
                FailureKind::Input => fail_run(inner, index, message),
            }
        }
        _ => {}
    }
}

/// Replaces worker `slot` (0: the main worker, with everything it was doing).
fn replace_slot(inner: &Rc<Inner>, slot: crate::worker::pool::Slot) {
    if slot == 0 {
        replace_worker(inner);
    } else {
        pool::replace(inner, slot);
    }
}

/// The file a packed file holds (`crate::bvh::unpack`: the same bytes as the file packed), as a
/// `Blob` the page keeps as the take.
async fn unpack_blob(packed: &Blob) -> Result<Blob, String> {
    let bytes = js_sys::Uint8Array::new(&blob_bytes(packed).await?.into()).to_vec();
    let file = crate::bvh::unpack(&bytes).map_err(|e| e.to_string())?;
    Blob::new_with_u8_array_sequence(&js_sys::Array::of1(&js_sys::Uint8Array::from(file.as_slice())))
        .map_err(|e| js_message(&e))
}

/// The file at `url` (the bundled sample), held to the cap of every take.
async fn fetch_blob(url: &str) -> Result<Blob, String> {
    let window = web_sys::window().ok_or("no window")?;
    let response: FetchResponse =
        JsFuture::from(window.fetch_with_str(url)).await.map_err(|e| js_message(&e))?.unchecked_into();
    if !response.ok() {
        return Err(format!("HTTP {} {} for {url}", response.status(), response.status_text()));
    }
    read_capped(&response, crate::app::take::fetch::MAX_FILE_BYTES).await.map_err(|e| match e {
        ReadError::TooLarge { .. } => format!("{url} is larger than the page reads (512 MiB)"),
        ReadError::Failed(e) => e,
    })
}
