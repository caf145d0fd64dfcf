//! The worker's side of the protocol ([`crate::protocol`]): the take it holds, the models it
//! stores, the training under way, and each request's work — pure Rust, tested natively;
//! `super::glue` (feature `web`) only converts `postMessage` packets. It knows methods only
//! through the registry ([`crate::method`]): a supervised method's training and model files come
//! from what it declares, never from its name.

use crate::bvh::Bvh;
use crate::image::MotionImage;
use crate::method::supervised::{Training, TrainingAsk};
use crate::method::{MethodError, ModelStore, Progress, RunOptions};
use crate::motion::Motion;
use crate::protocol::*;

/// The worker's side of the protocol: holds the take loaded last, the models the page gave it or
/// it trained, and answers requests. Pure Rust (the wasm entry point in `super::glue` only
/// converts packets), so the take checks are tested natively.
#[derive(Debug, Default)]
pub struct WorkerState {
    /// The take loaded last: its id, its motion and its parsed file (clips are cut from it).
    /// A motion handed over by another worker ([`Request::Hold`]) comes without its file: clips are
    /// cut by the worker that parsed it.
    held: Option<(TakeId, Motion, Option<Bvh>)>,
    /// The models of the supervised methods besides the shipped ones.
    models: ModelStore,
    /// The training under way (one at a time: a new one replaces it).
    job: Option<Job>,
}

/// A training under way in the worker, between two steps.
struct Job {
    take: TakeId,
    run: RunId,
    method: String,
    training: Box<dyn Training>,
}

impl std::fmt::Debug for Job {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Job({} training, run {} of take {})", self.method, self.run, self.take)
    }
}

/// Progress posted as `run`'s; it never cancels (a page stops a training between two steps, and
/// anything else by replacing the worker).
struct Posting<'a> {
    take: TakeId,
    run: RunId,
    post: &'a mut dyn FnMut(Response),
}

impl Progress for Posting<'_> {
    fn report(&mut self, stage: &str, fraction: f64) {
        (self.post)(Response::Progress {
            take: self.take,
            run: Some(self.run),
            stage: stage.into(),
            fraction: Some(fraction),
        })
    }
}

impl WorkerState {
    /// The request the worker should send itself next (after a `setTimeout(0)`, so that the
    /// page's messages are read first): the next step of the training under way.
    pub fn next_step(&self) -> Option<Request> {
        let job = self.job.as_ref()?;
        (!job.training.done()).then_some(Request::ContinueTraining { take: job.take, run: job.run })
    }

    /// The take the worker holds.
    pub fn held(&self) -> Option<TakeId> {
        self.held.as_ref().map(|(t, _, _)| *t)
    }

    /// The models stored so far.
    pub fn models(&self) -> &ModelStore {
        &self.models
    }

    /// The held take if it is `take`, else the `not_loaded` message.
    fn motion(&self, take: TakeId) -> Result<&Motion, String> {
        self.held_take(take).map(|(motion, _)| motion)
    }

    /// The held take's motion and file (`None`: a motion handed over) if it is `take`, else the
    /// `not_loaded` message.
    fn held_take(&self, take: TakeId) -> Result<(&Motion, Option<&Bvh>), String> {
        match &self.held {
            Some((held, motion, bvh)) if *held == take => Ok((motion, bvh.as_ref())),
            Some((held, _, _)) => Err(format!("take {take} is not loaded in the worker (it holds take {held})")),
            None => Err(format!("take {take} is not loaded in the worker (it holds none)")),
        }
    }

    /// Answers `request`, posting progress and the final response through `post`.
    pub fn handle(&mut self, request: Request, post: &mut dyn FnMut(Response)) {
        match request {
            Request::Load { take, name, restore, bytes, skeleton, skeleton_bytes } => {
                let asf = skeleton.as_deref().map(|n| (n, &skeleton_bytes[..]));
                let response = self.load_request(take, &name, restore, &bytes, asf, post);
                post(response);
            }
            Request::Hold { take, motion } => {
                // the previous take goes first, as with a load: one take at a time
                self.held = None;
                self.held = Some((take, *motion, None));
                post(Response::Held { take });
            }
            Request::Segment { take, run, method, params } => {
                let response = self.segment(take, run, &method, &params, post);
                post(response);
            }
            Request::Annotate { take, run, method, params, spans } => {
                let response = self.annotate(take, run, &method, &params, &spans, post);
                post(response);
            }
            Request::ProvideModel { take, run, file, bytes, unavailable } => {
                post(provide_model(&self.models, (take, run), file, bytes, unavailable))
            }
            Request::UseModel { take, run, method, file, bytes } => {
                post(self.use_model(take, run, &method, &file, &bytes))
            }
            Request::Train {
                take,
                run,
                method,
                name,
                labels_name,
                labels,
                takes,
                options,
                continue_from,
                validation,
                bytes,
            } => {
                let ask = TrainRequest { name, labels_name, labels, takes, options, continue_from, validation, bytes };
                if let Err(e) = self.train_request(take, run, &method, ask, post) {
                    post(refusal(take, run, &method, e))
                }
            }
            Request::ContinueTraining { run, .. } => {
                if self.job.as_ref().is_some_and(|j| j.run == run) {
                    self.training_step(post);
                }
            }
            Request::StopTraining { run, .. } => {
                if let Some(job) = self.job.as_mut().filter(|j| j.run == run) {
                    job.training.stop();
                    self.finish_training(post);
                }
            }
            Request::Clips { take, run, segmentation, which, to_origin, only } => {
                post(self.clips(take, run, &segmentation, crate::clips::ClipOptions { which, to_origin }, only))
            }
            Request::LibraryTake { take, run, name, bytes, skeleton, skeleton_bytes, method, params } => {
                let asf = skeleton.as_deref().map(|n| (n, &skeleton_bytes[..]));
                let response = self.library_take(take, run, &name, &bytes, asf, &method, &params, post);
                post(response)
            }
            Request::LibraryCluster { take, run, takes } => {
                let response = library_cluster(take, run, &takes, post);
                post(response)
            }
            Request::LibraryTransfer { take, run, takes, labelled, frame_labels, route } => {
                let kb = crate::library::KnowledgeBase { take: labelled, frame_labels };
                let response = library_transfer(take, run, &takes, &kb, route, post);
                post(response)
            }
            Request::LibraryClips { take, run, file, takes, to_origin, bytes } => {
                post(library_clips(take, run, file, &takes, to_origin, bytes))
            }
        }
    }

    /// A `Load` request's answer: the take read and held (`Restored` only, when it restores a take the page shows
    /// already).
    fn load_request(
        &mut self,
        take: TakeId,
        name: &str,
        restore: bool,
        bytes: &[u8],
        asf: Option<(&str, &[u8])>,
        post: &mut dyn FnMut(Response),
    ) -> Response {
        let mut progress =
            |f: f64| post(Response::Progress { take, run: None, stage: "parsing".into(), fraction: Some(f) });
        match self.load(take, name, bytes, asf, &mut progress) {
            Ok(motion) if restore => {
                drop(motion);
                Response::Restored { take }
            }
            Ok(motion) => Response::Loaded { take, motion },
            Err(message) => Response::Failed { take, run: None, message, kind: FailureKind::Input, param: None },
        }
    }

    /// Starts the training a `Train` request asks for and takes its first step; a refusal before it starts.
    fn train_request(
        &mut self,
        take: TakeId,
        run: RunId,
        method: &str,
        ask: TrainRequest,
        post: &mut dyn FnMut(Response),
    ) -> Result<(), MethodError> {
        // buffer 0 is the take on screen; the others are what the training adds
        crate::protocol::extra_takes_total(ask.bytes.iter().skip(1).map(|b| b.len() as u64))
            .map_err(|message| MethodError::param("takes", message))?;
        let start_from = match ask.continue_from {
            None => None,
            Some(from) => Some(self.models.loaded(method, &from).ok_or_else(|| {
                MethodError::param("name", format!("no model `{from}` of yours to continue training (train it first)"))
            })?),
        };
        let training = TrainingAsk {
            name: ask.name,
            labels_name: ask.labels_name,
            labels: ask.labels,
            takes: ask.takes.into_iter().zip(ask.bytes).collect(),
            options: ask.options,
            command: None,
            start_from,
            validation: ask.validation,
            to_file: false,
            limits: Default::default(),
        };
        self.start_training(take, run, method, training, post)?;
        self.training_step(post);
        Ok(())
    }

    /// A take of the library read from `bytes`, segmented by `method` and its features for the
    /// shared clusters computed, the take held staying held; its motion is dropped before the
    /// answer goes.
    #[allow(clippy::too_many_arguments)]
    fn library_take(
        &self,
        take: TakeId,
        run: RunId,
        name: &str,
        bytes: &[u8],
        asf: Option<(&str, &[u8])>,
        method: &str,
        params: &serde_json::Value,
        post: &mut dyn FnMut(Response),
    ) -> Response {
        let fail =
            |message: String| Response::Failed { take, run: Some(run), message, kind: FailureKind::Input, param: None };
        let m = match crate::methods::find(method) {
            Ok(m) => m,
            Err(e) => return fail(e.to_string()),
        };
        let motion = {
            let mut reading = |f: f64| {
                post(Response::Progress { take, run: Some(run), stage: "reading".into(), fraction: Some(f * 0.2) })
            };
            match read_take(name, bytes, asf, &mut reading) {
                Ok(motion) => motion,
                Err(message) => return fail(message),
            }
        };
        let short = m.info().short;
        let output = m.check_json_in(params, &self.models).and_then(|checked| {
            let mut progress = Posting { take, run, post };
            m.run_checked(&motion, &checked, &RunOptions { pictures: false, ..RunOptions::default() }, &mut progress)
        });
        match output {
            Ok(output) => Response::LibraryTake {
                take,
                run,
                frames: motion.frames(),
                duration_s: motion.duration_s(),
                misfit: output.details.take_fit.filter(|f| !f.fits).map(|f| f.reason),
                segmentation: Box::new(output.segmentation),
                features: crate::library::TakeFeatures::of(&motion, &crate::library::LibraryParams::default())
                    .map(Box::new)
                    .map_err(|e| e.to_string()),
            },
            Err(e) => run_failure(take, run, &short, &motion.name, e),
        }
    }

    /// Stores the model file `file` of `method`.
    fn use_model(&mut self, take: TakeId, run: RunId, method: &str, file: &str, bytes: &[u8]) -> Response {
        let read = supervised_method(method).and_then(|m| {
            m.supervised()
                .ok_or_else(|| MethodError::Failed(format!("{method} has no models")))?
                .read_model(file, bytes)
        });
        match read {
            Ok(loaded) => {
                let model = loaded.info.clone();
                self.models.install(loaded);
                Response::ModelStored { take, run, model }
            }
            Err(e) => refusal(take, run, method, e),
        }
    }

    /// Checks a training request and prepares its training (the job under way from now on).
    fn start_training(
        &mut self,
        take: TakeId,
        run: RunId,
        method: &str,
        ask: TrainingAsk,
        post: &mut dyn FnMut(Response),
    ) -> Result<(), MethodError> {
        // a new training replaces the one under way
        self.job = None;
        let m = supervised_method(method)?;
        let supervised = m.supervised().ok_or_else(|| MethodError::Failed(format!("{method} does not train")))?;
        let training = supervised.start_training(ask, &mut Posting { take, run, post })?;
        self.job = Some(Job { take, run, method: m.info().name, training });
        Ok(())
    }

    /// Runs the next step of the training under way and answers with its report; ends the run
    /// when it was the last.
    fn training_step(&mut self, post: &mut dyn FnMut(Response)) {
        let Some(job) = self.job.as_mut() else { return };
        let (take, run) = (job.take, job.run);
        match job.training.step(&mut Posting { take, run, post }) {
            Ok(report) => {
                let more = !job.training.done();
                post(Response::TrainingStep { take, run, report, more });
                if !more {
                    self.finish_training(post);
                }
            }
            Err(e) => {
                let method = job.method.clone();
                self.job = None;
                post(refusal(take, run, &method, e));
            }
        }
    }

    /// Ends the training under way: its model (the best so far) is stored and sent.
    fn finish_training(&mut self, post: &mut dyn FnMut(Response)) {
        let Some(job) = self.job.take() else { return };
        let (take, run) = (job.take, job.run);
        let response = match job.training.finish() {
            Ok(trained) => {
                let model = trained.model.info.clone();
                self.models.install(trained.model);
                Response::Trained { take, run, model, report: trained.report, bytes: trained.bytes }
            }
            Err(e) => refusal(take, run, &job.method, e),
        };
        post(response);
    }

    fn load(
        &mut self,
        take: TakeId,
        name: &str,
        bytes: &[u8],
        asf: Option<(&str, &[u8])>,
        progress: &mut dyn FnMut(f64),
    ) -> Result<Box<LoadedMotion>, String> {
        // the previous take goes first: a tab never holds two takes at once (the memory budget
        // bounds one), and a load that fails leaves none — a run on the take on screen is then
        // answered `not_loaded`, and the page sends that take again
        self.held = None;
        let loaded = read_take_file(name, bytes, asf, progress)?;
        let crate::load::Loaded { bvh, motion } = loaded;
        let image = MotionImage::from_motion(&motion);
        let png = image.try_to_png().map_err(|e| format!("{name}: motion image: {e}"))?;
        let view = Box::new(LoadedMotion::new(&motion, &image, png));
        self.held = Some((take, motion, Some(bvh)));
        Ok(view)
    }

    /// Clips of the held take `take` cut at the segments of `segmentation`.
    fn clips(
        &self,
        take: TakeId,
        run: RunId,
        segmentation: &crate::segment::Segmentation,
        options: crate::clips::ClipOptions,
        only: Option<(usize, usize)>,
    ) -> Response {
        let fail = |message: String, kind| Response::Failed { take, run: Some(run), message, kind, param: None };
        let (motion, bvh) = match self.held_take(take) {
            Ok((motion, Some(bvh))) => (motion, bvh),
            // a worker given the motion only (the page cuts clips with its main worker)
            Ok((_, None)) => {
                return fail(format!("take {take}: this worker holds its motion, not its file"), FailureKind::NotLoaded)
            }
            Err(message) => return fail(message, FailureKind::NotLoaded),
        };
        if let Err(e) = segmentation.validate() {
            return fail(format!("clips: {e}"), FailureKind::Input);
        }
        let stem = crate::clips::stem_of(&segmentation.file);
        match crate::clips::export(bvh, motion, segmentation, &stem, &options, only) {
            Ok(e) => Response::Clips { take, run, file: e.file, clips: e.clips, bytes: e.bytes },
            Err(e) => fail(format!("clips of {}: {e}", segmentation.file), FailureKind::Input),
        }
    }

    /// The annotations of the segments `spans` of the held take `take` by `method` (a method that
    /// declares [`crate::method::Annotator`]), answered as a segment run is when it cannot.
    /// The loaded take `take` and the registered method `method`, or the failure to answer `run` with.
    fn take_and_method(
        &self,
        take: TakeId,
        run: RunId,
        method: &str,
    ) -> Result<(&Motion, &'static dyn crate::method::DynMethod), Response> {
        let fail = |message: String, kind| Response::Failed { take, run: Some(run), message, kind, param: None };
        let motion = self.motion(take).map_err(|message| fail(message, FailureKind::NotLoaded))?;
        let m = crate::methods::find(method).map_err(|e| fail(e.to_string(), FailureKind::Input))?;
        Ok((motion, m))
    }

    fn annotate(
        &self,
        take: TakeId,
        run: RunId,
        method: &str,
        params: &serde_json::Value,
        spans: &[(usize, usize)],
        post: &mut dyn FnMut(Response),
    ) -> Response {
        let fail = |message: String, kind| Response::Failed { take, run: Some(run), message, kind, param: None };
        let (motion, m) = match self.take_and_method(take, run, method) {
            Ok(found) => found,
            Err(failed) => return failed,
        };
        let short = m.info().short;
        if m.annotator().is_none() {
            return fail(format!("{short} does not annotate segments"), FailureKind::Input);
        }
        let segments: Vec<crate::segment::Segment> = spans
            .iter()
            .map(|&(start, end)| crate::segment::Segment {
                start,
                end,
                label: String::new(),
                level: crate::segment::Level::Action,
                cluster: None,
                score: None,
                mirror_of: None,
                effort: None,
            })
            .collect();
        let mut progress = Posting { take, run, post };
        let annotated = m.check_json_in(params, &self.models).and_then(|checked| {
            m.annotate_checked(motion, &checked, &segments, &RunOptions::default().limits, &mut progress)
        });
        match annotated {
            Ok(annotations) => Response::Annotated { take, run, annotations },
            Err(e) => run_failure(take, run, &short, &motion.name, e),
        }
    }

    fn segment(
        &self,
        take: TakeId,
        run: RunId,
        method: &str,
        params: &serde_json::Value,
        post: &mut dyn FnMut(Response),
    ) -> Response {
        let (motion, m) = match self.take_and_method(take, run, method) {
            Ok(found) => found,
            Err(failed) => return failed,
        };
        let short = m.info().short;
        let mut progress = Posting { take, run, post };
        let output = m.check_json_in(params, &self.models).and_then(|checked| {
            m.run_checked(motion, &checked, &RunOptions { pictures: true, ..RunOptions::default() }, &mut progress)
        });
        match output {
            Ok(output) => Response::Segmented { take, run, view: Box::new(output.into()) },
            Err(e) => run_failure(take, run, &short, &motion.name, e),
        }
    }
}

/// A take's file (an AMC motion with its ASF skeleton) read into its motion and parsed file, or
/// the parser's message naming it.
fn read_take_file(
    name: &str,
    bytes: &[u8],
    asf: Option<(&str, &[u8])>,
    progress: &mut dyn FnMut(f64),
) -> Result<crate::load::Loaded, String> {
    match asf {
        None => crate::load::load_bytes(name, bytes, progress),
        Some(asf) => crate::load::load_asf_amc(asf, (name, bytes), &crate::load::MemoryBudget::default()),
    }
    .map_err(|e| e.to_string())
}

/// A take's motion read from its file ([`read_take_file`]).
fn read_take(
    name: &str,
    bytes: &[u8],
    asf: Option<(&str, &[u8])>,
    progress: &mut dyn FnMut(f64),
) -> Result<Motion, String> {
    read_take_file(name, bytes, asf, progress).map(|loaded| loaded.motion)
}

/// What a `Train` request asks, but the take and run it is about.
struct TrainRequest {
    name: String,
    labels_name: String,
    labels: String,
    takes: Vec<String>,
    options: serde_json::Value,
    continue_from: Option<String>,
    validation: Option<String>,
    bytes: Vec<Vec<u8>>,
}

/// The answer to a `ProvideModel` request: the shipped file's bytes checked and kept, or why not (a file the page
/// could not fetch is remembered as refused).
fn provide_model(
    models: &ModelStore,
    (take, run): (TakeId, RunId),
    file: String,
    bytes: Vec<u8>,
    unavailable: Option<String>,
) -> Response {
    if let Err(message) = crate::method::shipped::find(&file) {
        return input_failure(take, Some(run), message);
    }
    let given = match unavailable {
        Some(why) => models.refuse(&file, why.clone()).and(Err(why)),
        None => models.provide(&file, bytes),
    };
    match given {
        Ok(()) => Response::ModelProvided { take, run, file },
        Err(message) => Response::ModelRefused { take, run, file, message },
    }
}

/// A request refused for what it was given (a file, a take, labels), with why.
fn input_failure(take: TakeId, run: Option<RunId>, message: String) -> Response {
    Response::Failed { take, run, message, kind: FailureKind::Input, param: None }
}

/// The answer to a `LibraryCluster` request: the clusters shared by the library's `takes`.
fn library_cluster(
    take: TakeId,
    run: RunId,
    takes: &[crate::library::LibraryTake],
    post: &mut dyn FnMut(Response),
) -> Response {
    let mut progress = |f: f64| {
        post(Response::Progress { take, run: Some(run), stage: "matching".into(), fraction: Some(f) });
        Ok(())
    };
    match crate::library::cluster(takes, &crate::library::LibraryParams::default(), &mut progress) {
        Ok(clusters) => Response::LibraryClusters { take, run, clusters: Box::new(clusters) },
        Err(e) => input_failure(take, Some(run), format!("matching the library's takes: {e}")),
    }
}

/// The answer to a `LibraryTransfer` request: the labels of `kb` carried to the library's `takes` by `route`.
fn library_transfer(
    take: TakeId,
    run: RunId,
    takes: &[crate::library::LibraryTake],
    kb: &crate::library::KnowledgeBase,
    route: crate::library::TransferRoute,
    post: &mut dyn FnMut(Response),
) -> Response {
    let mut progress = |f: f64| {
        post(Response::Progress { take, run: Some(run), stage: "carrying".into(), fraction: Some(f) });
        Ok(())
    };
    let params = crate::library::LibraryParams::for_route(route);
    match crate::library::transfer(takes, kb, route, &params, &mut progress) {
        Ok(transfer) => Response::LibraryTransferred { take, run, transfer: Box::new(transfer) },
        Err(e) => input_failure(take, Some(run), format!("carrying the labels: {e}")),
    }
}

/// The clips of several takes in one zip `file` (a `library_clips` request): each take read
/// again from its bytes, one after another (only one take's frames at a time), cut at its
/// segments, each clip in the folder of its segment's label.
fn library_clips(
    take: TakeId,
    run: RunId,
    file: String,
    takes: &[ClipTake],
    to_origin: bool,
    bytes: Vec<Vec<u8>>,
) -> Response {
    let fail =
        |message: String| Response::Failed { take, run: Some(run), message, kind: FailureKind::Input, param: None };
    let mut buffers = bytes.into_iter();
    let mut all = Vec::new();
    for t in takes {
        let (Some(motion_bytes), skeleton) = (buffers.next(), t.skeleton.as_ref().map(|_| buffers.next())) else {
            return fail(format!("clips: the bytes of {} are missing", t.name));
        };
        let skeleton_bytes = skeleton.flatten().unwrap_or_default();
        let asf = t.skeleton.as_deref().map(|n| (n, &skeleton_bytes[..]));
        let crate::load::Loaded { bvh, motion } = match read_take_file(&t.name, &motion_bytes, asf, &mut |_| {}) {
            Ok(loaded) => loaded,
            Err(message) => return fail(format!("clips: {message}")),
        };
        if let Err(e) = t.segmentation.validate() {
            return fail(format!("clips of {}: {e}", t.name));
        }
        let options = crate::clips::ClipOptions { which: crate::clips::Which::All, to_origin };
        let stem = crate::clips::stem_of(&t.name);
        match crate::clips::clips(&bvh, &motion, &t.segmentation, &stem, &options) {
            Ok(clips) => all.extend(clips.into_iter().map(|mut c| {
                c.file = format!("{}/{}", crate::app::library::takes::folder_name(&c.segment.label), c.file);
                c
            })),
            Err(e) => return fail(format!("clips of {}: {e}", t.name)),
        }
    }
    if all.is_empty() {
        return fail("clips: no segment to cut".into());
    }
    let mut names: Vec<String> = all.iter().map(|c| c.file.clone()).collect();
    crate::app::library::takes::make_unique(&mut names);
    for (clip, name) in all.iter_mut().zip(names) {
        clip.file = name;
    }
    match crate::clips::zip(&all) {
        Ok(bytes) => Response::Clips { take, run, file, clips: all.len(), bytes },
        Err(e) => fail(format!("clips: {e}")),
    }
}

/// How a run of the method `short` on the take `name` (a segment or annotate request) that did not
/// finish is answered: cancelled, its parameters refused (naming the one to blame), a shipped model
/// file needed, or failed with the method's message.
fn run_failure(take: TakeId, run: RunId, short: &str, name: &str, e: MethodError) -> Response {
    let fail = |message: String, kind| Response::Failed { take, run: Some(run), message, kind, param: None };
    match e {
        MethodError::Cancelled => fail(format!("{short}: cancelled"), FailureKind::Cancelled),
        MethodError::Params { param, message } => Response::Refused { take, run, message, param },
        MethodError::NeedsModel { file } => Response::NeedsModel { take, run, file },
        e => fail(format!("{short} on {name}: {e}"), FailureKind::Input),
    }
}

/// The supervised method called `method`.
fn supervised_method(method: &str) -> Result<&'static dyn crate::method::DynMethod, MethodError> {
    let m = crate::methods::find(method)?;
    if m.supervised().is_none() {
        return Err(MethodError::Failed(format!("{} is not a supervised method: it has no models", m.info().short)));
    }
    Ok(m)
}

/// A training's or a model file's failure as the page gets it: the message, and the input to
/// blame when there is one.
fn refusal(take: TakeId, run: RunId, method: &str, e: MethodError) -> Response {
    let param = e.param_name().map(str::to_string);
    let kind = if e == MethodError::Cancelled { FailureKind::Cancelled } else { FailureKind::Input };
    let message = match e {
        MethodError::Cancelled => format!("{method}: cancelled"),
        e => e.to_string(),
    };
    Response::Failed { take, run: Some(run), message, kind, param }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn take_bytes() -> Vec<u8> {
        include_bytes!("../../tests/fixtures/12_01.bvh").to_vec()
    }

    /// Runs `request` on `worker`, returning everything it posted.
    fn ask(worker: &mut WorkerState, request: Request) -> Vec<Response> {
        let mut posted = Vec::new();
        worker.handle(request, &mut |r| posted.push(r));
        posted
    }

    fn segment(take: TakeId, run: RunId) -> Request {
        Request::Segment { take, run, method: "sssm".into(), params: serde_json::json!({}) }
    }

    /// The page hands a shipped model file over as buffer 0 (or says it could not fetch it); the
    /// worker checks it against this build's SHA-256 and answers `model_provided`, or
    /// `model_refused` naming the file (`failed` for a file that is not a shipped one).
    #[test]
    fn a_shipped_model_file_crosses_as_a_buffer_and_is_checked() {
        let file = "knn-cmu-actions.model".to_string();
        let good = std::fs::read(concat!(env!("CARGO_MANIFEST_DIR"), "/models/knn-cmu-actions.model")).unwrap();
        let request =
            Request::ProvideModel { take: 3, run: 4, file: file.clone(), bytes: good.clone(), unavailable: None };
        let packet = request.clone().into_packet();
        assert_eq!(packet.buffers, vec![good.clone()]);
        assert!(!packet.json.contains("bytes"), "the bytes travel as a buffer, not in the JSON");
        assert_eq!(Request::from_packet(packet).unwrap(), request);
        let mut worker = WorkerState::default();
        assert_eq!(ask(&mut worker, request), vec![Response::ModelProvided { take: 3, run: 4, file: file.clone() }]);
        let mut bad = good;
        bad.truncate(1000);
        let refused = ask(
            &mut worker,
            Request::ProvideModel { take: 3, run: 5, file: file.clone(), bytes: bad, unavailable: None },
        );
        assert!(
            matches!(&refused[..], [Response::ModelRefused { run: 5, message, .. }]
                if message.starts_with("models/knn-cmu-actions.model: 1000 bytes")),
            "{refused:?}"
        );
        // a file the page could not fetch: refused with the page's reason, no bytes
        let why = "could not fetch the model models/knn-locomotion.model: HTTP 404".to_string();
        let missing = Request::ProvideModel {
            take: 3,
            run: 7,
            file: "knn-locomotion.model".into(),
            bytes: vec![],
            unavailable: Some(why.clone()),
        };
        let packet = missing.clone().into_packet();
        assert_eq!(Request::from_packet(packet).unwrap(), missing);
        assert_eq!(
            ask(&mut worker, missing),
            vec![Response::ModelRefused { take: 3, run: 7, file: "knn-locomotion.model".into(), message: why }]
        );
        let unknown = ask(
            &mut worker,
            Request::ProvideModel { take: 3, run: 6, file: "x.model".into(), bytes: vec![], unavailable: None },
        );
        assert!(
            matches!(&unknown[..], [Response::Failed { message, .. }] if message.contains("not a shipped model file"))
        );
    }

    #[test]
    fn an_amc_load_carries_its_asf_skeleton_as_a_second_buffer_and_the_worker_cuts_clips_of_it() {
        let asf = include_bytes!("../../tests/fixtures/02.asf").to_vec();
        let amc = include_bytes!("../../tests/fixtures/02_01.amc").to_vec();
        let load = Request::Load {
            take: 1,
            name: "02_01.amc".into(),
            restore: false,
            bytes: amc.clone(),
            skeleton: Some("02.asf".into()),
            skeleton_bytes: asf.clone(),
        };
        let packet = load.clone().into_packet();
        assert_eq!(packet.buffers, vec![amc.clone(), asf]);
        assert_eq!(Request::from_packet(packet.clone()).unwrap(), load);
        let lost = Packet { buffers: vec![amc], ..packet };
        assert!(Request::from_packet(lost).unwrap_err().contains("without its ASF skeleton's bytes"));

        let mut w = WorkerState::default();
        let Some(Response::Loaded { take: 1, motion }) = ask(&mut w, load).pop() else { panic!("not loaded") };
        let frames = motion.summary.frames;
        let Some(Response::Segmented { view, .. }) = ask(&mut w, segment(1, 2)).pop() else { panic!("not segmented") };
        let seg = view.segmentation.clone();
        assert!(seg.level(crate::segment::Level::Action).count() >= 1, "{seg:?}");
        let clips = |take, which, only| Request::Clips {
            take,
            run: 3,
            segmentation: Box::new(seg.clone()),
            which,
            to_origin: false,
            only,
        };
        // the request travels (no buffers), the answer's bytes in buffer 0
        let asked = clips(1, crate::clips::Which::Actions, None);
        assert_eq!(Request::from_packet(asked.clone().into_packet()).unwrap(), asked);
        let Some(zipped) = ask(&mut w, asked).pop() else { panic!() };
        let back = Response::from_packet(zipped.clone().into_packet()).unwrap();
        assert_eq!(back, zipped);
        let Response::Clips { file, clips: n, bytes, .. } = zipped else { panic!("{zipped:?}") };
        assert_eq!((file.as_str(), n), ("02_01_actions_clips.zip", seg.level(crate::segment::Level::Action).count()));
        assert!(bytes.starts_with(b"PK\x03\x04"));
        // one segment: its BVH, as many frames as it spans
        let first = seg.level(crate::segment::Level::Action).min_by_key(|s| s.start).unwrap().clone();
        let Some(Response::Clips { file, bytes, clips: 1, .. }) =
            ask(&mut w, clips(1, crate::clips::Which::Actions, Some((first.start, first.end)))).pop()
        else {
            panic!("no clip")
        };
        assert!(file.starts_with("02_01_01_") && file.ends_with(".bvh"), "{file}");
        let clip = crate::bvh::parse(std::str::from_utf8(&bytes).unwrap()).unwrap();
        assert_eq!(clip.frames(), first.end - first.start + 1);
        // another take: not loaded; frames no segment has: a message
        let other = ask(&mut w, clips(9, crate::clips::Which::Actions, None));
        assert!(matches!(other.last(), Some(Response::Failed { kind: FailureKind::NotLoaded, run: Some(3), .. })));
        let none = ask(&mut w, clips(1, crate::clips::Which::Actions, Some((0, frames - 1))));
        let Some(Response::Failed { kind: FailureKind::Input, message, .. }) = none.last() else { panic!("{none:?}") };
        assert!(
            message.starts_with("clips of 02_01.amc: the segmentation has no action segment at frames 0–"),
            "{message}"
        );
    }

    #[test]
    fn library_takes_are_segmented_without_replacing_the_held_take_and_their_clips_zipped_together() {
        let mut w = WorkerState::default();
        load_walk(&mut w, 1);
        let library = |take, run, name: &str, bytes: Vec<u8>, skeleton: Option<(&str, Vec<u8>)>| Request::LibraryTake {
            take,
            run,
            name: name.into(),
            bytes,
            skeleton: skeleton.as_ref().map(|(n, _)| n.to_string()),
            skeleton_bytes: skeleton.map(|(_, b)| b).unwrap_or_default(),
            method: "sssm".into(),
            params: serde_json::json!({}),
        };
        let bvh = library(5, 6, "02_02.bvh", include_bytes!("../../tests/fixtures/02_02.bvh").to_vec(), None);
        // the request travels with its file as buffer 0 (and an AMC's skeleton as buffer 1)
        assert_eq!(Request::from_packet(bvh.clone().into_packet()).unwrap(), bvh);
        let amc = library(
            7,
            8,
            "02_01.amc",
            include_bytes!("../../tests/fixtures/02_01.amc").to_vec(),
            Some(("02.asf", include_bytes!("../../tests/fixtures/02.asf").to_vec())),
        );
        assert_eq!(amc.clone().into_packet().buffers.len(), 2);
        assert_eq!(Request::from_packet(amc.clone().into_packet()).unwrap(), amc);
        let mut took = Vec::new();
        let mut features = Vec::new();
        for (request, name) in [(bvh, "02_02.bvh"), (amc, "02_01.amc")] {
            let posted = ask(&mut w, request);
            assert!(posted.iter().any(|r| matches!(r, Response::Progress { run: Some(_), .. })), "progress is posted");
            let Some(Response::LibraryTake { frames, duration_s, segmentation, features: f, .. }) =
                posted.last().cloned()
            else {
                panic!("{:?}", posted.last())
            };
            let back = Response::from_packet(posted.last().unwrap().clone().into_packet()).unwrap();
            assert_eq!(&back, posted.last().unwrap());
            assert_eq!((segmentation.file.as_str(), segmentation.frames), (name, frames));
            assert!(duration_s > 1.0 && !segmentation.segments.is_empty());
            took.push(segmentation);
            features.push(f);
        }
        assert_eq!(w.held(), Some(1), "the take on screen stays held");
        // a supervised method whose model does not fit a take says why beside its (all unknown) labels; SSSM has no
        // such check, and a run with the check off labels the take as it is
        let walk = || include_bytes!("../../tests/fixtures/02_02.bvh").to_vec();
        let labelled = |run, with| {
            let mut request = library(5, run, "02_02.bvh", walk(), None);
            if let Request::LibraryTake { method, params, .. } = &mut request {
                (*method, *params) = ("dtfcn".into(), with);
            }
            request
        };
        let mut misfit = |request| match ask(&mut w, request).pop() {
            Some(Response::LibraryTake { misfit, segmentation, .. }) => (misfit, segmentation),
            other => panic!("{other:?}"),
        };
        let (why, segmentation) = misfit(labelled(9, serde_json::json!({"model": "exercises"})));
        assert!(why.as_deref().is_some_and(|w| w.contains("travel faster")), "{why:?}");
        assert!(segmentation.segments.iter().all(|s| s.label == "unknown"));
        let (why, segmentation) = misfit(labelled(10, serde_json::json!({"model": "exercises", "fit_check": false})));
        assert_eq!(why, None);
        assert!(segmentation.segments.iter().any(|s| s.label != "unknown"));
        assert!(took.iter().all(|s| s.method == "sssm"));
        // the two takes matched: clusters shared across them, occurrences inside their takes
        let matched: Vec<crate::library::LibraryTake> = features
            .into_iter()
            .zip(&took)
            .map(|(f, s)| crate::library::LibraryTake {
                name: s.file.clone(),
                features: *f.expect("a CMU take has the end effectors"),
                segmentation: (**s).clone(),
            })
            .collect();
        let request = Request::LibraryCluster { take: 0, run: 12, takes: matched.clone() };
        assert_eq!(Request::from_packet(request.clone().into_packet()).unwrap(), request);
        let posted = ask(&mut w, request);
        assert!(posted.iter().any(|r| matches!(r, Response::Progress { run: Some(12), .. })));
        let Some(Response::LibraryClusters { run: 12, clusters, .. }) = posted.last().cloned() else {
            panic!("{:?}", posted.last())
        };
        assert_eq!(
            Response::from_packet(posted.last().unwrap().clone().into_packet()).unwrap(),
            *posted.last().unwrap()
        );
        assert_eq!(clusters.takes.len(), 2);
        assert!(clusters.shared().count() >= 1, "the two walks share a cluster: {:?}", clusters.clusters);
        // the labels of the second take carried to the first, by both routes
        let labels = |n: usize| (0..n).map(|f| Some(if f < n / 2 { "walk" } else { "stride" }.to_string())).collect();
        let transfer = |run, frame_labels, route| Request::LibraryTransfer {
            take: 0,
            run,
            takes: matched.clone(),
            labelled: 1,
            frame_labels,
            route,
        };
        let mut last = None;
        for (run, route) in
            [(13, crate::library::TransferRoute::Nearest), (14, crate::library::TransferRoute::Clusters)]
        {
            let request = transfer(run, labels(took[1].frames), route);
            assert_eq!(Request::from_packet(request.clone().into_packet()).unwrap(), request);
            let posted = ask(&mut w, request);
            assert!(posted.iter().any(|r| matches!(r, Response::Progress { run: Some(r), .. } if *r == run)));
            let Some(Response::LibraryTransferred { run: answered, transfer, .. }) = posted.last().cloned() else {
                panic!("{:?}", posted.last())
            };
            assert_eq!((answered, transfer.route, transfer.takes.len()), (run, route, 2));
            let back = Response::from_packet(posted.last().unwrap().clone().into_packet()).unwrap();
            assert_eq!(&back, posted.last().unwrap());
            // the labelled take keeps its own; the other one has labels of its classes, one per frame
            assert_eq!(transfer.takes[1].frame_labels, labels(took[1].frames));
            let carried = &transfer.takes[0];
            assert_eq!(carried.frame_labels.len(), took[0].frames);
            assert!(carried.frame_labels.iter().flatten().all(|l| l == "walk" || l == "stride"));
            assert!(carried.frame_labels.iter().any(Option::is_some), "{route:?}: some walk frames get a label");
            last = Some(transfer);
        }
        // labels of the wrong length, or none: failed with the core's message
        let short = ask(&mut w, transfer(15, labels(10), crate::library::TransferRoute::Nearest));
        let Some(Response::Failed { message, kind: FailureKind::Input, run: Some(15), .. }) = short.last() else {
            panic!("{short:?}")
        };
        assert_eq!(
            message,
            &format!(
                "carrying the labels: take 02_01.amc: the labels cover 10 frames, the take has {}",
                took[1].frames
            )
        );
        let none = ask(&mut w, transfer(16, vec![None; took[1].frames], crate::library::TransferRoute::Clusters));
        let Some(Response::Failed { message, run: Some(16), .. }) = none.last() else { panic!("{none:?}") };
        assert_eq!(message, "carrying the labels: take 02_01.amc: no frame of it is labelled");
        // a transfer that does not cover its take is refused on the page's side
        let mut bad = last.expect("a transfer");
        bad.takes[0].frame_labels.pop();
        let packet = Response::LibraryTransferred { take: 0, run: 17, transfer: bad }.into_packet();
        assert!(Response::from_packet(packet).unwrap_err().contains("do not cover their take"));
        // a bad file: failed, naming it; the held take still there
        let bad = ask(&mut w, library(9, 10, "bad.bvh", include_bytes!("../../tests/fixtures/bad.bvh").to_vec(), None));
        let Some(Response::Failed { message, kind: FailureKind::Input, run: Some(10), .. }) = bad.last() else {
            panic!("{bad:?}")
        };
        assert!(message.contains("bad.bvh"), "{message}");
        assert_eq!(w.held(), Some(1));

        // one segment of each take, labelled as its cluster's folder, cut into one zip
        let pick = |seg: &crate::segment::Segmentation, label: &str| {
            let mut one = seg.clone();
            one.segments.truncate(1);
            one.segments[0].label = label.into();
            one
        };
        let takes = vec![
            ClipTake { name: "02_02.bvh".into(), skeleton: None, segmentation: pick(&took[0], "walk cycle") },
            ClipTake {
                name: "02_01.amc".into(),
                skeleton: Some("02.asf".into()),
                segmentation: pick(&took[1], "walk cycle"),
            },
        ];
        let bytes = vec![
            include_bytes!("../../tests/fixtures/02_02.bvh").to_vec(),
            include_bytes!("../../tests/fixtures/02_01.amc").to_vec(),
            include_bytes!("../../tests/fixtures/02.asf").to_vec(),
        ];
        let clips =
            Request::LibraryClips { take: 0, run: 11, file: "library.zip".into(), takes, to_origin: true, bytes };
        let packet = clips.clone().into_packet();
        assert_eq!(Request::from_packet(packet.clone()).unwrap(), clips);
        let short = Packet { buffers: packet.buffers[..2].to_vec(), ..packet };
        assert!(Request::from_packet(short).unwrap_err().contains("need 3 files but carry 2"));
        let Some(Response::Clips { file, clips: 2, bytes, .. }) = ask(&mut w, clips).pop() else { panic!("no zip") };
        assert_eq!(file, "library.zip");
        let mut archive = zip::ZipArchive::new(std::io::Cursor::new(bytes)).unwrap();
        let mut names: Vec<String> =
            (0..archive.len()).map(|i| archive.by_index(i).unwrap().name().unwrap().to_string()).collect();
        names.sort();
        assert_eq!(names, ["walk_cycle/02_01_01_walk_cycle.bvh", "walk_cycle/02_02_01_walk_cycle.bvh"]);
        let mut text = String::new();
        std::io::Read::read_to_string(&mut archive.by_name(&names[0]).unwrap(), &mut text).unwrap();
        let clip = crate::bvh::parse(&text).unwrap();
        let s = &took[1].segments[0];
        assert_eq!(clip.frames(), s.end - s.start + 1);
    }

    /// The page's pool: the main worker parses the take, the page makes the worker's motion again from
    /// what it received (`LoadedMotion::motion`) and hands it over (`hold`, through the packets the
    /// messages are) to another worker, which then gives every method exactly the main worker's
    /// result, without the file — and says so when asked to cut clips from it.
    #[test]
    fn a_motion_handed_over_segments_exactly_as_the_parsed_take() {
        let mut main = WorkerState::default();
        let load = Request::Load {
            take: 1,
            name: "12_01.bvh".into(),
            restore: false,
            bytes: take_bytes(),
            skeleton: None,
            skeleton_bytes: Vec::new(),
        };
        let loaded = ask(&mut main, load);
        let packet = loaded.last().unwrap().clone().into_packet();
        let Ok(Response::Loaded { take: 1, motion: view }) = Response::from_packet(packet) else {
            panic!("{loaded:?}")
        };
        let motion = view.motion();
        assert_eq!(Some(&motion), main.held.as_ref().map(|h| &h.1), "the page has the worker's motion again, exactly");

        let hold = Request::Hold { take: 1, motion: Box::new(motion) };
        let hold = Request::from_packet(hold.into_packet()).expect("a hold crosses as JSON and one buffer");
        let mut helper = WorkerState::default();
        assert_eq!(ask(&mut helper, hold), vec![Response::Held { take: 1 }]);
        assert_eq!(helper.held.as_ref().map(|h| &h.1), main.held.as_ref().map(|h| &h.1));
        for (run, method) in ["sssm", "velocity", "kcs", "pca"].into_iter().enumerate() {
            let ask_for = |run| Request::Segment { take: 1, run, method: method.into(), params: serde_json::json!({}) };
            let (a, b) = (ask(&mut main, ask_for(run as u32)), ask(&mut helper, ask_for(run as u32)));
            assert!(matches!(a.last(), Some(Response::Segmented { .. })), "{method}: {:?}", a.last());
            assert_eq!(a.last(), b.last(), "{method}: the helper's result is the main worker's");
        }
        let clips = Request::Clips {
            take: 1,
            run: 9,
            segmentation: Box::new(crate::segment::Segmentation {
                file: "12_01.bvh".into(),
                fps: 120.0,
                frames: 10,
                method: "sssm".into(),
                params: serde_json::json!({}),
                segments: Vec::new(),
            }),
            which: crate::clips::Which::All,
            to_origin: false,
            only: None,
        };
        let Some(Response::Failed { kind: FailureKind::NotLoaded, message, .. }) = ask(&mut helper, clips).pop() else {
            panic!("clips from a motion without its file")
        };
        assert!(message.contains("not its file"), "{message}");

        // a motion whose positions are not whole frames is refused as the packet is read
        let mut bad = Request::Hold { take: 2, motion: Box::new(view.motion()) }.into_packet();
        let len = bad.buffers[0].len();
        bad.buffers[0].truncate(len - 4);
        let refused = Request::from_packet(bad).expect_err("ragged positions");
        assert!(refused.contains("not whole frames"), "{refused}");
    }

    #[test]
    fn the_worker_segments_only_the_take_a_request_names() {
        let mut w = WorkerState::default();
        let none = ask(&mut w, segment(1, 1));
        assert!(matches!(&none[..], [Response::Failed { kind: FailureKind::NotLoaded, run: Some(1), .. }]), "{none:?}");

        let load = ask(
            &mut w,
            Request::Load {
                take: 1,
                name: "12_01.bvh".into(),
                restore: false,
                bytes: take_bytes(),
                skeleton: None,
                skeleton_bytes: Vec::new(),
            },
        );
        assert!(matches!(load.first(), Some(Response::Progress { take: 1, run: None, .. })));
        assert!(matches!(load.last(), Some(Response::Loaded { take: 1, .. })));
        assert_eq!(w.held(), Some(1));

        // a bad file (take 2) fails; take 1 was let go before it was read (the worker never holds
        // two takes), so a run on take 1 is answered `not_loaded` until the page sends it again
        let bad = ask(
            &mut w,
            Request::Load {
                take: 2,
                name: "bad.bvh".into(),
                restore: false,
                bytes: b"HIERARCHY\nROOT".to_vec(),
                skeleton: None,
                skeleton_bytes: Vec::new(),
            },
        );
        let Some(Response::Failed { take: 2, run: None, message, kind: FailureKind::Input, .. }) = bad.last() else {
            panic!("{bad:?}")
        };
        assert!(message.starts_with("bad.bvh: line "), "{message}");
        assert_eq!(w.held(), None, "the previous take is released before the next one is parsed");
        let gone = ask(&mut w, segment(1, 2));
        assert!(
            matches!(gone.last(), Some(Response::Failed { take: 1, kind: FailureKind::NotLoaded, .. })),
            "{gone:?}"
        );
        let again = ask(
            &mut w,
            Request::Load {
                take: 1,
                name: "12_01.bvh".into(),
                restore: true,
                bytes: take_bytes(),
                skeleton: None,
                skeleton_bytes: Vec::new(),
            },
        );
        assert_eq!(again.last(), Some(&Response::Restored { take: 1 }));
        assert_eq!(w.held(), Some(1));

        // a segment request for another take is refused, for the held one answered
        let other = ask(&mut w, segment(3, 2));
        assert!(matches!(other.last(), Some(Response::Failed { take: 3, kind: FailureKind::NotLoaded, .. })));
        let done = ask(&mut w, segment(1, 3));
        assert!(done.iter().any(|r| matches!(r, Response::Progress { run: Some(3), .. })));
        let Some(Response::Segmented { take: 1, run: 3, view }) = done.last() else { panic!("{:?}", done.last()) };
        assert_eq!(view.segmentation.file, "12_01.bvh");
        assert_eq!(view.details.pictures.len(), 1);

        // a restore answers without the bulk data; a bad parameter names itself
        let restored = ask(
            &mut w,
            Request::Load {
                take: 4,
                name: "12_01.bvh".into(),
                restore: true,
                bytes: take_bytes(),
                skeleton: None,
                skeleton_bytes: Vec::new(),
            },
        );
        assert_eq!(restored.last(), Some(&Response::Restored { take: 4 }));
        let bad = ask(
            &mut w,
            Request::Segment { take: 4, run: 5, method: "sssm".into(), params: serde_json::json!({"radius": -1}) },
        );
        let Some(Response::Refused { run: 5, message, param, .. }) = bad.last() else { panic!("{bad:?}") };
        assert!(message.contains("radius = -1"), "{message}");
        assert_eq!(param.as_deref(), Some("radius"), "the refusal names its parameter, as data");
        let packet = bad.last().unwrap().clone().into_packet();
        assert_eq!(Response::from_packet(packet).as_ref(), Ok(bad.last().unwrap()));
        let unknown =
            ask(&mut w, Request::Segment { take: 4, run: 6, method: "nope".into(), params: serde_json::json!({}) });
        assert!(matches!(unknown.last(), Some(Response::Failed { kind: FailureKind::Input, .. })));
    }

    /// Effort labels CSV rows `file,start,end,class×4`, classes cycling through the three elements.
    fn label_rows(file: &str, rows: usize, step: usize, length: usize) -> String {
        (0..rows)
            .map(|k| {
                let classes = [0, 1, 2, k].map(|f| ["indulging", "neutral", "condensing"][(k + f) % 3]).join(",");
                format!("{file},{},{},{classes}\n", step * k, step * k + length)
            })
            .collect()
    }

    const HEADER: &str = "file,start_frame,end_frame,space,time,weight,flow\n";

    /// A training of `method`'s model `name` on `labels` (the file `labels.csv`) and `takes`.
    fn train(
        method: &str,
        run: RunId,
        name: &str,
        labels: String,
        options: serde_json::Value,
        takes: Vec<(&str, Vec<u8>)>,
    ) -> Request {
        let (names, bytes): (Vec<String>, Vec<Vec<u8>>) = takes.into_iter().map(|(n, b)| (n.to_string(), b)).unzip();
        Request::Train {
            take: 1,
            run,
            method: method.into(),
            name: name.into(),
            labels_name: "labels.csv".into(),
            labels,
            takes: names,
            options,
            continue_from: None,
            validation: None,
            bytes,
        }
    }

    /// LMA's options that train in a second (the defaults are the paper's 20 restarts).
    fn quick_lma() -> serde_json::Value {
        serde_json::json!({"restarts": 2, "saliency_rounds": 4, "max_epochs": 40, "shift_epochs": 3})
    }

    /// The last answer, a refusal: its message and the input it names.
    fn refusal(posted: Vec<Response>) -> (String, Option<String>) {
        match posted.last() {
            Some(Response::Failed { kind: FailureKind::Input, message, param, .. }) => (message.clone(), param.clone()),
            other => panic!("expected a refusal, got {other:?}"),
        }
    }

    fn load_walk(w: &mut WorkerState, take: TakeId) {
        let posted = ask(
            w,
            Request::Load {
                take,
                name: "12_01.bvh".into(),
                restore: false,
                bytes: take_bytes(),
                skeleton: None,
                skeleton_bytes: Vec::new(),
            },
        );
        assert!(matches!(posted.last(), Some(Response::Loaded { .. })), "{:?}", posted.last());
    }

    /// What `model-info` shows of a model file of `method`, read through the registry.
    fn model_details(method: &str, bytes: &[u8], file: &str) -> serde_json::Value {
        let supervised = crate::methods::find(method).unwrap().supervised().unwrap();
        supervised.model_details(&supervised.read_model(file, bytes).unwrap())
    }

    fn run_method(w: &mut WorkerState, run: RunId, method: &str, params: serde_json::Value) -> Box<MethodView> {
        let posted = ask(w, Request::Segment { take: 1, run, method: method.into(), params });
        let Some(Response::Segmented { view, .. }) = posted.last() else { panic!("{:?}", posted.last()) };
        view.clone()
    }

    /// A labelling run's take fit reaches the page as data: the walk does not fit `exercises`, the
    /// report says why and names `locomotion`, and it crosses `postMessage` whole (the JSON of a
    /// `segmented` packet); a run with the check off carries none.
    #[test]
    fn a_take_fit_report_crosses_to_the_page() {
        let mut w = WorkerState::default();
        load_walk(&mut w, 1);
        let view = run_method(&mut w, 2, "knn", serde_json::json!({"model": "exercises", "fit_others": true}));
        let fit = view.details.take_fit.clone().expect("the k-NN's fit check");
        assert!(!fit.fits && fit.reason.contains("travel faster") && fit.model == "exercises", "{fit:?}");
        assert_eq!(fit.fitting_names(), ["locomotion"]);
        let response = Response::Segmented { take: 1, run: 2, view: view.clone() };
        let packet = response.clone().into_packet();
        assert!(packet.json.contains(r#""take_fit":{"model":"exercises","fits":false"#), "{}", packet.json);
        let Response::Segmented { view: back, .. } = Response::from_packet(packet).unwrap() else { panic!() };
        assert_eq!(back.details.take_fit, Some(fit));
        let off = run_method(&mut w, 3, "knn", serde_json::json!({"model": "exercises", "fit_check": false}));
        assert!(off.details.take_fit.is_none());
        assert!(run_method(&mut w, 4, "sssm", serde_json::json!({})).details.take_fit.is_none());
    }

    /// Trains through the worker as the page does: the request, then every `continue_training`
    /// the worker asks for, until it asks for none.
    fn train_to_the_end(w: &mut WorkerState, request: Request) -> Vec<Response> {
        let mut posted = ask(w, request);
        while let Some(next) = w.next_step() {
            assert!(matches!(next, Request::ContinueTraining { .. }), "{next:?}");
            posted.extend(ask(w, next));
        }
        posted
    }

    #[test]
    fn the_worker_trains_an_lma_family_on_the_rows_for_its_take_stores_it_and_runs_it_by_name() {
        let mut w = WorkerState::default();
        load_walk(&mut w, 1);
        let mine = format!("{HEADER}{}", label_rows("12_01.bvh", 12, 30, 120));
        let walk = || vec![("12_01.bvh", take_bytes())];

        // what the user gets wrong is named: the line, the take and the files the rows name, too few rows
        let typo = mine.replacen("neutral", "nuetral", 1);
        let (message, param) = refusal(ask(&mut w, train("lma", 2, "mine", typo, quick_lma(), walk())));
        assert!(message.contains("labels.csv line 2") && message.contains("`nuetral`"), "{message}");
        assert_eq!(param.as_deref(), Some("labels"));
        let elsewhere = format!("{HEADER}{}{}", label_rows("35_01.bvh", 9, 20, 90), label_rows("nope", 1, 0, 50));
        let (message, _) = refusal(ask(&mut w, train("lma", 3, "mine", elsewhere, quick_lma(), walk())));
        assert!(message.contains("loaded take `12_01.bvh`") && message.contains("`35_01.bvh`, `nope`"), "{message}");
        let (message, _) = refusal(ask(&mut w, train("lma", 4, "mine", HEADER.to_string(), quick_lma(), walk())));
        assert!(message.contains("no rows"), "{message}");
        let few = format!("{HEADER}{}", label_rows("12_01", 5, 30, 120));
        let (message, _) = refusal(train_to_the_end(&mut w, train("lma", 5, "mine", few, quick_lma(), walk())));
        assert!(message.contains("too few to train on"), "{message}");
        let long =
            format!("{HEADER}{}12_01,400,600,neutral,neutral,neutral,neutral\n", label_rows("12_01", 9, 30, 120));
        let (message, _) = refusal(ask(&mut w, train("lma", 6, "mine", long, quick_lma(), walk())));
        assert!(message.contains("line 11") && message.contains("do not fit"), "{message}");
        let (message, param) =
            refusal(ask(&mut w, train("lma", 6, "mine", mine.clone(), serde_json::json!({"restarts": 0}), walk())));
        assert_eq!(param.as_deref(), Some("restarts"), "{message}");
        let (_, param) = refusal(ask(&mut w, train("lma", 6, "shipped", mine.clone(), quick_lma(), walk())));
        assert_eq!(param.as_deref(), Some("name"));
        assert!(!run_method(&mut w, 7, "lma", serde_json::json!({})).details.summary.contains("your classifiers"));

        // rows for the take (named in any case, with or without folder and extension) train the
        // family; the other file's rows are counted and left out
        let rows = label_rows("12_01.bvh", 12, 30, 120).replacen("12_01.bvh", "takes/12_01.BVH", 1).replacen(
            "12_01.bvh",
            "12_01",
            1,
        );
        let labels = format!("{HEADER}{rows}{}", label_rows("35_01.bvh", 3, 20, 90));
        let posted = train_to_the_end(&mut w, train("lma", 8, "mine", labels, quick_lma(), walk()));
        let stages: Vec<&str> = posted
            .iter()
            .filter_map(|r| match r {
                Response::Progress { run: Some(8), stage, fraction: Some(f), .. } if (0.0..=1.0).contains(f) => {
                    Some(stage.as_str())
                }
                _ => None,
            })
            .collect();
        assert!(stages.contains(&"space saliency") && stages.contains(&"flow shifted networks"), "{stages:?}");
        let Some(Response::Trained { take: 1, run: 8, model, report, bytes }) = posted.last() else {
            panic!("{:?}", posted.last())
        };
        assert!(
            report
                .summary
                .starts_with("Trained on 12 rows of labels.csv for 12_01.bvh (3 rows for other files left out)"),
            "{}",
            report.summary
        );
        assert_eq!(report.rows.iter().map(|r| r[0].as_str()).collect::<Vec<_>>(), ["space", "time", "weight", "flow"]);
        assert_eq!(report.rows[0][1], "4 / 4 / 4");
        assert_eq!((model.method.as_str(), model.name.as_str()), ("lma", "mine"));
        assert_eq!(model.origin, "12 segments of 12_01.bvh labelled in labels.csv");
        assert_eq!(model_details("lma", bytes, "mine.json")["samples"], 12);
        let yours = format!(" · your classifiers ({})", model.origin);
        let view = run_method(&mut w, 9, "lma", serde_json::json!({"model": "mine"}));
        assert!(view.details.summary.ends_with(&yours), "{}", view.details.summary);
        assert_eq!(view.segmentation.params["model"], "mine");
        assert!(!run_method(&mut w, 10, "lma", serde_json::json!({})).details.summary.contains("your classifiers"));
        let unknown = ask(
            &mut w,
            Request::Segment { take: 1, run: 11, method: "lma".into(), params: serde_json::json!({"model": "nope"}) },
        );
        let Some(Response::Refused { param, message, .. }) = unknown.last() else { panic!("{unknown:?}") };
        assert_eq!(param.as_deref(), Some("model"));
        assert!(message.contains("known: shipped, mine"), "{message}");

        // the file loads back in a new worker under its stem; a bad file is refused naming it
        let mut fresh = WorkerState::default();
        let stored = ask(
            &mut fresh,
            Request::UseModel {
                take: 9,
                run: 12,
                method: "lma".into(),
                file: "saved-family.json".into(),
                bytes: bytes.clone(),
            },
        );
        let Some(Response::ModelStored { take: 9, run: 12, model: info }) = stored.last() else { panic!("{stored:?}") };
        assert_eq!((info.name.as_str(), info.origin.as_str()), ("saved-family", model.origin.as_str()));
        assert_eq!(fresh.models().names("lma"), vec!["saved-family"]);
        let (message, _) = refusal(ask(
            &mut fresh,
            Request::UseModel {
                take: 9,
                run: 13,
                method: "lma".into(),
                file: "broken.json".into(),
                bytes: b"{\"fps\": 30}".to_vec(),
            },
        ));
        assert!(message.starts_with("broken.json: not an LMA effort model"), "{message}");
        let mut three: serde_json::Value = serde_json::from_slice(bytes).unwrap();
        three["factors"].as_array_mut().unwrap().pop();
        let (message, _) = refusal(ask(
            &mut fresh,
            Request::UseModel {
                take: 9,
                run: 14,
                method: "lma".into(),
                file: "three.json".into(),
                bytes: three.to_string().into_bytes(),
            },
        ));
        assert!(message.contains("3 factors, expected 4"), "{message}");
        // methods without models are said to have none
        let (message, _) = refusal(ask(
            &mut fresh,
            Request::UseModel { take: 9, run: 15, method: "sssm".into(), file: "x".into(), bytes: vec![] },
        ));
        assert!(message.contains("SSSM is not a supervised method"), "{message}");
    }

    // ---- DT-FCN / k-NN models and training ------------------------------------------------

    fn tiny_options(epochs: usize) -> serde_json::Value {
        serde_json::json!({"filters": [8, 8], "crop_frames": 64, "epochs": epochs})
    }

    const LABELS_HEADER: &str = "file,start_frame,end_frame,label\n";

    /// Label rows for 12_01.bvh (524 frames): three classes in turn.
    fn walk_labels() -> String {
        format!("{LABELS_HEADER}12_01.bvh,0,179,stand\n12_01.bvh,180,359,walk\n12_01.bvh,360,523,<b>turn</b>\n")
    }

    #[test]
    fn the_worker_trains_a_dtfcn_one_epoch_per_message_stores_it_and_sends_the_file() {
        let mut w = WorkerState::default();
        assert!(w.next_step().is_none(), "nothing to continue before a training");
        let labels = format!("{}86_01.bvh,0,99,walk\n", walk_labels());
        let first =
            ask(&mut w, train("dtfcn", 7, "tiny-trained", labels, tiny_options(2), vec![("12_01.bvh", take_bytes())]));
        // epoch 1 answers, and the worker asks for epoch 2 (it does not run it by itself)
        let Some(Response::TrainingStep { take: 1, run: 7, report, more: true }) = first.last() else {
            panic!("{first:?}")
        };
        assert_eq!((report.step, report.steps), (1, 2));
        assert!(report.line.starts_with("Epoch 1 of 2 · loss "), "{}", report.line);
        assert!(report.values.iter().all(|(_, v)| (0.0..=1.0).contains(v)), "{report:?}");
        assert!(first.iter().any(|r| matches!(r, Response::Progress { run: Some(7), .. })));
        assert_eq!(w.next_step(), Some(Request::ContinueTraining { take: 1, run: 7 }));
        // a continue for another training is ignored
        assert!(ask(&mut w, Request::ContinueTraining { take: 1, run: 99 }).is_empty());
        let second = ask(&mut w, Request::ContinueTraining { take: 1, run: 7 });
        assert!(
            matches!(&second[0], Response::TrainingStep { run: 7, more: false, report, .. } if report.step == 2),
            "{second:?}"
        );
        let Some(Response::Trained { run: 7, model, report, bytes, .. }) = second.last() else { panic!("{second:?}") };
        assert!(w.next_step().is_none(), "the training is over");
        assert!(!report.stopped);
        assert!(
            report.summary.starts_with("Trained `tiny-trained` on 3 rows of labels.csv (rows for 86_01.bvh left out: not loaded): 3 classes (stand, walk, <b>turn</b>), 2 epochs, the weights of epoch 2 kept."),
            "{}",
            report.summary
        );
        assert_eq!((model.name.as_str(), model.method.as_str()), ("tiny-trained", "dtfcn"));
        assert_eq!(model.classes, vec!["stand", "walk", "<b>turn</b>"]);
        assert_eq!(model.colours.len(), 3);
        let command = &model.provenance.iter().find(|(k, _)| k == "command").unwrap().1;
        assert!(
            command.starts_with("mocapseg train-dtfcn --bvh 12_01.bvh --labels labels.csv --epochs 2"),
            "{command}"
        );
        assert!(command.contains("filters 8,8"), "{command}");
        assert!(bytes.starts_with(b"mocapseg-model\n"));
        let back = model_details("dtfcn", bytes, "tiny-trained.model");
        assert_eq!(back["classes"], serde_json::json!(model.classes));
        assert_eq!(back["provenance"]["epochs_run"], 2);

        // the stored model labels the held take by its name
        load_walk(&mut w, 1);
        let view = run_method(&mut w, 8, "dtfcn", serde_json::json!({"model": "tiny-trained"}));
        assert_eq!(view.segmentation.params["model"], "tiny-trained");
        for s in &view.segmentation.segments {
            let label = s.cluster.map_or("unknown", |c| model.classes[c].as_str());
            assert_eq!(s.label, label, "{s:?}");
        }
        assert!(view.details.pictures.iter().any(|p| p.id == "probabilities"));

        // the file loads back (under the name in it), not as a k-NN model
        let again = ask(
            &mut w,
            Request::UseModel {
                take: 5,
                run: 9,
                method: "dtfcn".into(),
                file: "renamed.model".into(),
                bytes: bytes.clone(),
            },
        );
        let Some(Response::ModelStored { take: 5, run: 9, model: loaded }) = again.last() else { panic!("{again:?}") };
        assert_eq!(loaded, model);
        let (message, _) = refusal(ask(
            &mut w,
            Request::UseModel {
                take: 5,
                run: 10,
                method: "knn".into(),
                file: "renamed.model".into(),
                bytes: bytes.clone(),
            },
        ));
        assert!(message.contains("renamed.model holds a DT-FCN model, not a k-NN model"), "{message}");

        // bad files are refused with the core's message, and the worker goes on answering
        let truncated = bytes[..bytes.len() / 2].to_vec();
        let json = br#"{"fps": 30.0, "factors": []}"#.to_vec();
        let mut rng = crate::stats::Rng::new(5);
        let random: Vec<u8> = (0..4096).map(|_| rng.below(256) as u8).collect();
        for (file, bad, says) in [
            ("half.model", truncated, "half.model: truncated"),
            ("family.json", json, "family.json: not a mocapseg model file"),
            ("noise.bin", random, "noise.bin: not a mocapseg model file"),
            ("empty.model", Vec::new(), "empty.model: not a mocapseg model file"),
        ] {
            let (message, param) = refusal(ask(
                &mut w,
                Request::UseModel { take: 5, run: 11, method: "dtfcn".into(), file: file.into(), bytes: bad },
            ));
            assert!(message.starts_with(says), "{message}");
            assert_eq!(param, None);
        }
        let view =
            run_method(&mut w, 12, "dtfcn", serde_json::json!({"model": "tiny-trained", "unknown_threshold": 0.99}));
        assert!(!view.segmentation.segments.is_empty());
    }

    #[test]
    fn the_worker_fits_a_knn_in_one_step_from_the_same_shape() {
        let mut w = WorkerState::default();
        let posted = train_to_the_end(
            &mut w,
            train("knn", 2, "my-knn", walk_labels(), serde_json::json!({}), vec![("12_01.bvh", take_bytes())]),
        );
        let steps = posted.iter().filter(|r| matches!(r, Response::TrainingStep { .. })).count();
        assert_eq!(steps, 1, "{posted:?}");
        let Some(Response::Trained { model, report, .. }) = posted.last() else { panic!("{:?}", posted.last()) };
        assert_eq!((model.method.as_str(), model.name.as_str()), ("knn", "my-knn"));
        assert!(report.summary.contains("k-NN labels the take with it now"), "{}", report.summary);
        load_walk(&mut w, 1);
        let view = run_method(&mut w, 3, "knn", serde_json::json!({"model": "my-knn"}));
        assert!(view.segmentation.segments.iter().any(|s| s.label == "walk"), "{:?}", view.segmentation.segments);
        let (message, param) = refusal(ask(
            &mut w,
            train("knn", 4, "k", walk_labels(), serde_json::json!({"epochs": 3}), vec![("12_01.bvh", take_bytes())]),
        ));
        assert_eq!(param, None);
        assert!(message.contains("unknown field `epochs`"), "{message}");
        // its table is the decoding's rows: the model keeps them
        let posted = train_to_the_end(
            &mut w,
            train(
                "knn",
                5,
                "decoded",
                walk_labels(),
                serde_json::json!({"min_duration_s": 1.5, "switch_cost": 20}),
                vec![("12_01.bvh", take_bytes())],
            ),
        );
        let Some(Response::Trained { model, .. }) = posted.last() else { panic!("{:?}", posted.last()) };
        let decoding = &model.provenance.iter().find(|(k, _)| k == "decoding").unwrap().1;
        assert_eq!(decoding, "runs ≥ 1.5 s, switch cost 20", "{:?}", model.provenance);
    }

    #[test]
    fn a_stopped_training_keeps_the_model_of_its_epochs_so_far() {
        let mut w = WorkerState::default();
        let first = ask(
            &mut w,
            train("dtfcn", 3, "tiny-stopped", walk_labels(), tiny_options(50), vec![("12_01.bvh", take_bytes())]),
        );
        assert!(matches!(first.last(), Some(Response::TrainingStep { more: true, .. })), "{first:?}");
        // the page's stop is read before the worker's own continue
        assert!(
            ask(&mut w, Request::StopTraining { take: 1, run: 99 }).is_empty(),
            "another training's stop is ignored"
        );
        let stopped = ask(&mut w, Request::StopTraining { take: 1, run: 3 });
        let [Response::Trained { report, bytes, .. }] = &stopped[..] else { panic!("{stopped:?}") };
        assert!(report.stopped);
        assert!(
            report.summary.contains("stopped after 1 of 50 epochs, the weights of epoch 1 kept"),
            "{}",
            report.summary
        );
        assert_eq!(model_details("dtfcn", bytes, "s.model")["provenance"]["epochs_run"], 1);
        assert!(w.next_step().is_none());
        assert!(
            ask(&mut w, Request::ContinueTraining { take: 1, run: 3 }).is_empty(),
            "the continue after a stop is ignored"
        );
        assert!(ask(&mut w, Request::StopTraining { take: 1, run: 3 }).is_empty(), "a second stop is ignored");
        // and the stopped model is stored
        load_walk(&mut w, 1);
        run_method(&mut w, 4, "dtfcn", serde_json::json!({"model": "tiny-stopped"}));
        // a whole run after a stop: a new request replaces nothing left over
        let posted = train_to_the_end(
            &mut w,
            train("dtfcn", 5, "tiny-stopped", walk_labels(), tiny_options(1), vec![("12_01.bvh", take_bytes())]),
        );
        assert!(
            matches!(posted.last(), Some(Response::Trained { run: 5, report, .. }) if !report.stopped),
            "{:?}",
            posted.last()
        );
    }

    #[test]
    fn training_refusals_name_the_input_that_is_wrong() {
        let mut w = WorkerState::default();
        let walk = || vec![("12_01.bvh", take_bytes())];
        let mut check = |request: Request, param: &str, says: &[&str]| {
            let (message, p) = refusal(ask(&mut w, request));
            assert_eq!(p.as_deref(), Some(param), "{message}");
            for s in says {
                assert!(message.contains(s), "{message} should say {s}");
            }
            assert!(w.next_step().is_none(), "no training after a refusal");
        };
        let t = |labels: String, options: serde_json::Value| train("dtfcn", 1, "m", labels, options, walk());
        let bad_line = walk_labels().replace("180,359", "180,abc");
        check(t(bad_line, tiny_options(2)), "labels", &["labels.csv line 3", "`abc`"]);
        let elsewhere = format!("{LABELS_HEADER}86_01.bvh,0,99,walk\n86_01.bvh,100,199,run\n");
        check(t(elsewhere, tiny_options(2)), "labels", &["no row is for the loaded take `12_01.bvh`", "`86_01.bvh`"]);
        check(t(LABELS_HEADER.into(), tiny_options(2)), "labels", &["no rows"]);
        let one = format!("{LABELS_HEADER}12_01.bvh,0,523,walk\n");
        check(t(one, tiny_options(2)), "labels", &["1 class", "at least 2"]);
        let past = format!("{LABELS_HEADER}12_01.bvh,0,99,walk\n12_01.bvh,100,900,run\n");
        check(t(past, tiny_options(2)), "labels", &["past the take's last frame 523"]);
        check(t(walk_labels(), tiny_options(0)), "epochs", &["epochs 0"]);
        check(t(walk_labels(), serde_json::json!({"label_noise": 2.0})), "label_noise", &["label noise 2"]);
        check(t(walk_labels(), serde_json::json!({"mask_s": 1000.0})), "mask_s", &["mask s 1000", "0 to 10"]);
        check(t(walk_labels(), serde_json::json!({"width": 1})), "width", &["width 1"]);
        check(t(walk_labels(), serde_json::json!({"filters": [8, 0]})), "filters", &["filters 8,0"]);
        check(train("dtfcn", 1, "  ", walk_labels(), tiny_options(2), walk()), "name", &["needs a name"]);
        check(train("dtfcn", 1, "exercises", walk_labels(), tiny_options(2), walk()), "name", &["shipped model"]);
        let broken = vec![("12_01.bvh", b"HIERARCHY\nROOT".to_vec())];
        check(train("dtfcn", 1, "m", walk_labels(), tiny_options(2), broken), "takes", &["12_01.bvh: line"]);
        let twice = vec![("12_01.bvh", take_bytes()), ("takes/12_01.BVH", take_bytes())];
        check(train("dtfcn", 1, "m", walk_labels(), tiny_options(2), twice), "takes", &["given twice"]);
        // the takes a training adds are capped in total (their bytes zeroed by the allocator, never read)
        let big = (crate::protocol::MAX_EXTRA_TAKES_BYTES / 2 + 1) as usize;
        let heavy = vec![("12_01.bvh", take_bytes()), ("a.bvh", vec![0u8; big]), ("b.bvh", vec![0u8; big])];
        check(train("dtfcn", 1, "m", walk_labels(), tiny_options(2), heavy), "takes", &["257 MiB", "256 MiB"]);
        // a method that does not train is said so, naming no input
        let (message, param) =
            refusal(ask(&mut w, train("sssm", 1, "m", walk_labels(), serde_json::json!({}), walk())));
        assert!(message.contains("SSSM is not a supervised method") && param.is_none(), "{message}");
    }

    #[test]
    fn a_refusal_names_its_input_as_data_and_the_glue_s_own_failure_none() {
        let failed =
            Response::Failed { take: 1, run: None, message: "x".into(), kind: FailureKind::Input, param: None };
        assert!(!failed.into_packet().json.contains("param"), "no param: left out");
        let named = Response::Failed {
            take: 1,
            run: Some(2),
            message: "x".into(),
            kind: FailureKind::Input,
            param: Some("label_noise".into()),
        };
        let v: serde_json::Value = serde_json::from_str(&named.clone().into_packet().json).unwrap();
        assert_eq!(v["param"], "label_noise");
        assert_eq!(Response::from_packet(named.clone().into_packet()).unwrap(), named);
        // worker.js's own failure message has no param
        let glue = Packet {
            json: r#"{"type":"failed","take":0,"run":7,"message":"internal error: x","kind":"internal"}"#.into(),
            buffers: vec![],
        };
        assert!(matches!(
            Response::from_packet(glue).unwrap(),
            Response::Failed { param: None, kind: FailureKind::Internal, .. }
        ));
        let mut odd = crate::method::supervised::ModelInfo {
            method: "dtfcn".into(),
            name: "mine".into(),
            classes: vec!["a".into(), "b".into()],
            colours: vec!["#ff0000".into(), "#00ff00".into()],
            origin: String::new(),
            provenance: Vec::new(),
            card: Default::default(),
        };
        odd.colours.pop();
        let bad = Response::ModelStored { take: 1, run: 2, model: odd }.into_packet();
        assert!(Response::from_packet(bad).unwrap_err().contains("2 classes but 1 colours"));
    }
}
