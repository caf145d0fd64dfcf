//! The page's side of the workers, a transport: it starts the workers (the main worker and the pool's run
//! workers, [`pool`]), posts what the page's features ask, routes every reply by its run id to the feature that
//! sent the run ([`Jobs`]), and replaces a worker that trapped or died. It holds no feature's state: each feature
//! (the methods' runs, the models and trainings, the library, the Effort bars, the clip exports) keeps its own jobs
//! in its folder, registers them ([`Loader::register`]) and sends through [`Loader::send`] or, for a run that any
//! worker may do, [`Loader::place`].
//!
//! The loader also loads the take ([`take`]): a load gets a new take id and only the newest counts; the take on
//! screen is kept as a `Blob` and sent again to a worker that lost it ([`Loader::send_with_take`]). A take the user
//! opens may wait for a question a feature asks first ([`Loader::set_gate`]: a training under way).
//!
//! The shipped models are not in the wasm: a run that needs one the worker does not hold is answered `needs_model`,
//! and [`shipped`] fetches it, hands it over and has the run's feature ask again; every new worker gets every file
//! fetched so far.
//!
//! The files are layers, each using only those below it: [`jobs`] and [`urls`]; [`transport`] (the state, posting,
//! starting a worker); [`pool`] and [`shipped`]; [`take`]; [`dispatch`] (what the workers' messages and errors do);
//! this file, the handle the page holds.

mod dispatch;
mod jobs;
mod pool;
mod shipped;
mod take;
mod transport;
mod urls;

pub(crate) use jobs::{AfterDeath, Jobs};
pub use transport::Open;
pub use urls::Urls;

use crate::app::models::model_files::ModelFiles;
use crate::app::state::AppState;
use crate::protocol::{Request, RunId, TakeId};
use crate::worker::pool::{Placed, Pool, Slot, Stop};
use leptos::prelude::*;
use std::cell::{Cell, RefCell};
use std::collections::HashMap;
use std::rc::Rc;
use transport::{next_id, post, post_buffers_to, post_to, Inner};
use web_sys::{Blob, File};

/// The largest file the page reads (the worker's memory budget then checks what it needs).
pub const MAX_FILE_BYTES: f64 = crate::app::take::fetch::MAX_FILE_BYTES as f64;

/// A handle on the workers; cheap to clone.
#[derive(Clone)]
pub struct Loader(Rc<Inner>);

impl Loader {
    /// Starts the main worker and the pool's run workers.
    pub fn new(state: AppState, urls: Urls) -> Loader {
        let models = ModelFiles::new(&urls.models);
        let workers = pool::workers(urls.workers);
        let inner = Rc::new(Inner {
            state,
            urls,
            main: RefCell::new(None),
            helpers: RefCell::new((1..workers).map(|_| None).collect()),
            pool: RefCell::new(Pool::new(workers)),
            next_id: Cell::new(0),
            current: Cell::new(0),
            pending: RefCell::new(None),
            load_sends: Cell::new(0),
            shown: RefCell::new(None),
            src_take: RefCell::new(None),
            features: RefCell::new(Vec::new()),
            routes: RefCell::new(HashMap::new()),
            gate: RefCell::new(None),
            models,
            on_message: dispatch::on_message,
            on_error: dispatch::on_error,
        });
        transport::spawn_main(&inner);
        for slot in 1..workers {
            pool::spawn(&inner, slot);
        }
        Loader(inner)
    }

    /// Registers a feature's jobs: told when a worker starts or is replaced, when the take changes, when the main
    /// worker fails ([`Jobs`]).
    pub(crate) fn register(&self, jobs: Rc<dyn Jobs>) {
        self.0.features.borrow_mut().push(jobs);
    }

    /// Sets what holds a take the user opens until a question is answered (it gives the take back when it may open
    /// at once; [`Loader::open_now`] opens it later).
    pub(crate) fn set_gate(&self, gate: impl Fn(Open) -> Option<Open> + 'static) {
        *self.0.gate.borrow_mut() = Some(Rc::new(gate));
    }

    /// Opens `open`, unless the gate holds it.
    fn open(&self, open: Open) {
        let gate = self.0.gate.borrow().clone();
        let open = match gate {
            Some(gate) => gate(open),
            None => Some(open),
        };
        if let Some(open) = open {
            take::open_now(&self.0, open);
        }
    }

    /// Opens `open` at once (the answer to the gate's question).
    pub fn open_now(&self, open: Open) {
        take::open_now(&self.0, open);
    }

    /// Loads the bundled sample (unless the gate holds it).
    pub fn load_sample(&self) {
        self.0.state.library.open.set(None);
        self.open(Open::Sample);
    }

    /// Loads the files the user dropped or picked at once: one take's file, or an ASF skeleton
    /// with its AMC motion ([`crate::load::opening`] says which, or why neither) — unless the gate holds them.
    pub fn load_files(&self, files: Vec<File>) {
        self.open(Open::Files(files));
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
        take::open_src(&self.0, url, name, fetch);
    }

    /// Loads `file` as the take `name` (with an AMC motion's ASF `skeleton`: its name and bytes), as a dropped file
    /// loads (a take kept in this browser).
    pub fn load_blob(&self, name: &str, file: Blob, skeleton: Option<(String, Vec<u8>)>) {
        take::open_blob(&self.0, name, file, skeleton);
    }

    /// The take on screen as it can be kept: its name, file, skeleton (an AMC motion's ASF: name, bytes), and whether
    /// it is the bundled sample.
    pub fn shown_take_files(&self) -> Option<(String, Blob, Option<(String, Vec<u8>)>, bool)> {
        self.0.shown.borrow().as_ref().map(|t| (t.name.clone(), t.file.clone(), t.skeleton.clone(), t.sample))
    }

    /// The name of the bundled sample's file.
    pub fn sample_name(&self) -> String {
        self.0.urls.sample_name()
    }

    /// The URL of `file` beside the shipped model files (`models/cards.json`).
    pub fn model_url(&self, file: &str) -> String {
        self.0.models.url(file)
    }

    /// The take on screen (the one a request names), if any.
    pub(crate) fn shown_take(&self) -> Option<TakeId> {
        self.0.shown.borrow().as_ref().map(|t| t.id)
    }

    /// The file of the take on screen (its bytes are read when asked).
    pub fn shown_file(&self) -> Option<(String, Blob)> {
        self.0.shown.borrow().as_ref().map(|t| (t.name.clone(), t.file.clone()))
    }

    /// The newest load's take id (the take on screen, or the one loading).
    pub(crate) fn current_take(&self) -> TakeId {
        self.0.current.get()
    }

    /// A new run id (take and run ids come from one counter).
    pub(crate) fn new_run(&self) -> RunId {
        next_id(&self.0)
    }
}

impl Loader {
    /// Routes the replies about `request`'s run to `jobs` and posts it with `posted`; not routed when it could not be
    /// posted.
    fn routed(
        &self,
        jobs: Rc<dyn Jobs>,
        run: Option<RunId>,
        posted: impl FnOnce() -> Result<(), String>,
    ) -> Result<(), String> {
        if let Some(run) = run {
            self.0.routes.borrow_mut().insert(run, jobs);
        }
        let sent = posted();
        if let (Err(_), Some(run)) = (&sent, run) {
            self.forget(run);
        }
        sent
    }

    /// Posts `request` to the main worker, its replies routed to `jobs` until [`Loader::forget`] (a model file it is
    /// given goes to the run workers too).
    pub(crate) fn send(&self, jobs: Rc<dyn Jobs>, request: &Request) -> Result<(), String> {
        self.routed(jobs, request.run_id(), || post(&self.0, request, None))
    }

    /// [`Loader::send`] with `buffers` (JS `ArrayBuffer`s: files read again) transferred.
    pub(crate) fn send_buffers(
        &self,
        jobs: Rc<dyn Jobs>,
        request: &Request,
        buffers: js_sys::Array,
    ) -> Result<(), String> {
        self.routed(jobs, request.run_id(), || post_buffers_to(&self.0, 0, request, buffers))
    }

    /// [`Loader::send`] with `request`'s own buffers moved out of it rather than copied (the library's features).
    pub(crate) fn send_own(&self, jobs: Rc<dyn Jobs>, request: Request) -> Result<(), String> {
        let run = request.run_id();
        self.routed(jobs, run, || post_to(&self.0, 0, request))
    }

    /// [`Loader::send`] once the take on screen is sent to the main worker again (it answered `not_loaded`).
    pub(crate) async fn send_with_take(&self, jobs: Rc<dyn Jobs>, request: &Request) -> Result<(), String> {
        self.restore().await?;
        self.send(jobs, request)
    }

    /// Sends the take on screen to the main worker again.
    pub(crate) async fn restore(&self) -> Result<(), String> {
        take::restore(&self.0).await
    }

    /// Stops routing `run`'s replies (its job is over; a run of the pool is then no longer wanted).
    pub(crate) fn forget(&self, run: RunId) {
        self.0.routes.borrow_mut().remove(&run);
    }

    /// Asks the pool for a worker for `run`, its replies routed to `jobs`: [`Placed::Now`] names the worker to post
    /// it to ([`Loader::post_to`]); a run that waits is given one later ([`Jobs::post_pooled`]). A run placed again
    /// (a retry) keeps its worker or its place.
    pub(crate) fn place(&self, jobs: Rc<dyn Jobs>, run: RunId) -> Placed {
        self.0.routes.borrow_mut().insert(run, jobs);
        self.0.pool.borrow_mut().place(run)
    }

    /// Posts `request` to worker `slot` (0: the main worker), its own buffers moved.
    pub(crate) fn post_to(&self, slot: Slot, request: Request) -> Result<(), String> {
        post_to(&self.0, slot, request)
    }

    /// Posts `request` to worker `slot` with `buffers` (a take's files) transferred.
    pub(crate) fn post_buffers_to(&self, slot: Slot, request: &Request, buffers: js_sys::Array) -> Result<(), String> {
        post_buffers_to(&self.0, slot, request, buffers)
    }

    /// Hands run worker `slot` the take on screen again (it answered `not_loaded`).
    pub(crate) fn hold(&self, slot: Slot) {
        pool::hold(&self.0, slot)
    }

    /// Frees whichever worker runs `run` (the run ended on the page: failed, refused), for the next waiting run.
    pub(crate) fn release(&self, run: RunId) {
        pool::release_run(&self.0, run)
    }

    /// Takes `run` out of the pool: dropped where it waits ([`Stop::Dequeued`]), or the worker that runs it
    /// named ([`Stop::Replace`]: the caller replaces it, [`Loader::replace_slot`], or lets the main worker finish).
    pub(crate) fn stop(&self, run: RunId) -> Stop {
        self.0.pool.borrow_mut().stop(run)
    }

    /// Whether `run` is in the pool away from the main worker (waiting, or on a run worker).
    pub(crate) fn away_from_main(&self, run: RunId) -> bool {
        let pool = self.0.pool.borrow();
        pool.is_queued(run) || pool.slot_of(run).is_some_and(|slot| slot > 0)
    }

    /// The worker the pool gave `run`, if it runs.
    pub(crate) fn worker_of(&self, run: RunId) -> Option<Slot> {
        self.0.pool.borrow().slot_of(run)
    }

    /// How many workers the pool has (the main worker included).
    pub(crate) fn workers(&self) -> usize {
        self.0.pool.borrow().workers()
    }

    /// Replaces worker `slot` (0: the main worker, with everything it was doing).
    pub(crate) fn replace_slot(&self, slot: Slot) {
        dispatch::replace_slot(&self.0, slot)
    }

    /// Replaces the main worker (it trapped, or its work was cancelled), with everything it was doing.
    pub(crate) fn replace_worker(&self) {
        dispatch::replace_main(&self.0)
    }
}
