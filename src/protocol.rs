//! The page ↔ worker protocol: one [`Request`] enum and one [`Response`] enum (serde, tagged by
//! `type`), carried as a [`Packet`]: the message as JSON text plus its bulk data (file bytes,
//! joint positions, pixels) as separate byte buffers, which the web layer transfers between
//! threads instead of copying. Only the messages and their encoding: the worker's state and what
//! it does with each request are [`crate::worker`]'s. Pure Rust, so the encoding is tested
//! natively; the worker's glue and `crate::app` only move packets in and out of `postMessage`.
//!
//! Every request names the take it is about (`take`, chosen by the page for each file it loads).
//! The worker holds one take; a `segment` request for another take is refused with
//! [`FailureKind::NotLoaded`], and the page then sends the take it shows again (`restore`) and
//! repeats the request — so the page never segments a take other than the one on screen, even
//! after a load that lost a race or a worker replaced after a crash or a cancel.
//!
//! The worker also holds the models of the supervised methods (DT-FCN, the k-NN, LMA: any method
//! that declares [`crate::method::Supervision`]) in its [`crate::method::ModelStore`]: `use_model`
//! stores a model file the user loaded (or the page holds from a training) under its name, and the
//! page sends every model it holds to each new worker. `train` trains a model of any supervised
//! method **one step per message**: it prepares the training and runs step 1; each step answers
//! `training_step`, and while more steps are due [`crate::worker::WorkerState::next_step`] names
//! the `continue_training` request the worker's glue (`www/worker.js`) schedules to itself with
//! `setTimeout(0)`, so that a `stop_training` from the page is read between two steps. When the
//! run ends (its steps done, or stopped: the best model so far is kept), the worker stores the
//! model and answers `trained` with the model file as a buffer.
//!
//! `annotate` asks for per-segment qualities of any segmentation of the held take (any row's
//! frames) from a method that declares it annotates ([`crate::method::Annotator`]: LMA's Effort);
//! it is answered `annotated`, or `needs_model` / `refused` / `failed` as a `segment` run is.
//!
//! The library of takes (issue 26) has four requests that need no held take: `library_take`
//! (read a take, segment it, compute its [`crate::library::TakeFeatures`], let its frames go),
//! `library_cluster` (match the takes' features and segmentations into clusters shared across
//! takes), `library_transfer` (one take's labels carried to the others:
//! [`crate::library::transfer`]) and `library_clips` (several takes' files read again and cut
//! into one zip).

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::image::MotionImage;
use crate::method::supervised::{ModelInfo, StepReport, TrainingReport};
use crate::method::{Details, MethodOutput};
use crate::motion::{Motion, Units, UpAxis};
use crate::segment::Segmentation;

/// The page's number for a loaded file.
pub type TakeId = u32;
/// The page's number for a segmentation run.
pub type RunId = u32;

/// Page → worker.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum Request {
    /// Parse `bytes` (the file `name`) as take `take`. With `restore` the page already shows
    /// the take and only wants the worker to hold it again: the reply is [`Response::Restored`].
    Load {
        take: TakeId,
        name: String,
        restore: bool,
        /// Buffer 0.
        #[serde(skip)]
        bytes: Vec<u8>,
        /// An AMC motion's ASF skeleton: its file name (`name` is the AMC's); its bytes are buffer 1.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        skeleton: Option<String>,
        #[serde(skip)]
        skeleton_bytes: Vec<u8>,
    },
    /// Hold `motion` as take `take` — the motion another worker made of the take's file, handed over
    /// as it is (the page's pool of workers: the take is parsed once, by the main worker, and every
    /// other worker gets its motion, not its file). Its positions are buffer 0. The reply is
    /// [`Response::Held`], or `failed` when the motion is not a whole take.
    Hold { take: TakeId, motion: Box<Motion> },
    /// Segment take `take` with `method` (a registry name) and `params` (JSON, fields optional).
    Segment { take: TakeId, run: RunId, method: String, params: serde_json::Value },
    /// Store the model file `file` (its bytes) of the supervised method `method` under the name
    /// it gives ([`crate::method::Supervised::read_model`]); refused with the method's message when
    /// the bytes are not such a model. Any worker accepts it, whatever take it holds.
    UseModel {
        take: TakeId,
        run: RunId,
        method: String,
        /// The file's name (messages name it).
        file: String,
        /// Buffer 0.
        #[serde(skip)]
        bytes: Vec<u8>,
    },
    /// Train a model `name` of the supervised method `method` on the label CSV `labels` (its
    /// text; the file `labels_name`) for the takes `takes` (file names; their bytes are the
    /// buffers, in order — the take on screen first) with `options` (JSON, the method's training
    /// table). Prepares the training and runs step 1 (answer: `training_step`); the steps after it
    /// come with `continue_training`. A refusal names the option, `labels`, `takes` or `name`.
    /// Any worker accepts it.
    Train {
        take: TakeId,
        run: RunId,
        method: String,
        name: String,
        labels_name: String,
        labels: String,
        takes: Vec<String>,
        options: serde_json::Value,
        /// Continue the training of this model of the user's (stored in the worker) for the
        /// epochs asked, instead of starting from random weights.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        continue_from: Option<String>,
        /// One of `takes` kept out of the training as its validation take (a method that declares
        /// one: it chooses the epoch and the model's decoding).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        validation: Option<String>,
        /// Buffers 0.., one per take.
        #[serde(skip)]
        bytes: Vec<Vec<u8>>,
    },
    /// Hand over the shipped model file `file` (its bytes as the page fetched them from beside
    /// itself, buffer 0) after a `needs_model` answer; checked against this build's SHA-256
    /// ([`crate::method::ModelStore::provide`]) — or, with `unavailable`, say why the page could not
    /// fetch it ([`crate::method::ModelStore::refuse`]; no bytes). Answer: `model_provided`, or
    /// `model_refused` naming the file; a refused file is not asked for again: the run asked again
    /// fails with why where it needs the file and goes on without it where it was one of several.
    /// `failed` for a file that is not a shipped one. Any worker accepts it, whatever take it holds.
    ProvideModel {
        take: TakeId,
        run: RunId,
        file: String,
        #[serde(skip)]
        bytes: Vec<u8>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        unavailable: Option<String>,
    },
    /// Runs the next step of the training `run` (the worker's glue sends it to its own worker
    /// when [`WorkerState::next_step`] says so). Ignored when that training is over.
    ContinueTraining { take: TakeId, run: RunId },
    /// Ends the training `run` after the steps so far: the best model so far is kept, stored
    /// and sent (`trained`, its report `stopped`). Ignored when that training is over.
    StopTraining { take: TakeId, run: RunId },
    /// Annotate the segments `spans` (first and last file frame of each, inclusive; any row's) of
    /// take `take` with `method`, a method that declares [`crate::method::Annotator`], and
    /// `params` (JSON, its [`crate::method::Annotator::params`]). Answer: `annotated`, one
    /// annotation per span in order — or `needs_model`, `refused`, `failed` as for `segment`.
    Annotate { take: TakeId, run: RunId, method: String, params: serde_json::Value, spans: Vec<(usize, usize)> },
    /// Cut the segments of `segmentation` (a run's result on take `take`) that `which` chooses
    /// as BVH clips of the held take ([`crate::clips::export`]): every clip in one zip, or with
    /// `only` (a segment's first and last frame) that segment's clip alone; `to_origin` starts
    /// each clip at the origin facing +Z. Answer: `clips`.
    Clips {
        take: TakeId,
        run: RunId,
        segmentation: Box<crate::segment::Segmentation>,
        which: crate::clips::Which,
        to_origin: bool,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        only: Option<(usize, usize)>,
    },
    /// A take of the library (issue 26): parse `bytes` (the file `name`; an AMC motion with its
    /// ASF `skeleton`, as `load` takes them), segment it with `method` and `params`, and answer
    /// `library_take` with its segmentation — without holding it: the take on screen stays the
    /// one the worker holds, and this one's frames are dropped once it is segmented. Progress is
    /// posted as run `run`'s.
    LibraryTake {
        take: TakeId,
        run: RunId,
        name: String,
        /// Buffer 0.
        #[serde(skip)]
        bytes: Vec<u8>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        skeleton: Option<String>,
        /// Buffer 1 when there is a skeleton.
        #[serde(skip)]
        skeleton_bytes: Vec<u8>,
        method: String,
        params: serde_json::Value,
    },
    /// Match the library's takes (`takes`: each one's name, features and segmentation, as
    /// `library_take` answered them) into clusters shared across takes
    /// ([`crate::library::cluster`], default parameters). Progress is posted as run `run`'s. Each take's
    /// features travel as two buffers (its values as f32, its frames' places as f64), in the takes' order.
    /// Answer: `library_clusters`.
    LibraryCluster { take: TakeId, run: RunId, takes: Vec<crate::library::LibraryTake> },
    /// Carry the per-frame labels `frame_labels` of take `labelled` (an index into `takes`, which
    /// are as `library_cluster` sends them) to every take of `takes` by `route`
    /// ([`crate::library::transfer`], [`crate::library::LibraryParams::for_route`]). Progress is
    /// posted as run `run`'s. The features travel as `library_cluster`'s do. Answer: `library_transferred`.
    LibraryTransfer {
        take: TakeId,
        run: RunId,
        takes: Vec<crate::library::LibraryTake>,
        labelled: usize,
        frame_labels: Vec<Option<String>>,
        route: crate::library::TransferRoute,
    },
    /// BVH clips of several takes of the library in one zip named `file`: each take of `takes` is
    /// parsed again from its bytes (buffers in order: each take's file, then its ASF skeleton's
    /// when it has one) and cut at its segmentation's segments, the clips going into the zip's
    /// folder `folder` of each segment's label. Answer: `clips`.
    LibraryClips {
        take: TakeId,
        run: RunId,
        file: String,
        takes: Vec<ClipTake>,
        to_origin: bool,
        #[serde(skip)]
        bytes: Vec<Vec<u8>>,
    },
}

/// A take whose clips a `library_clips` request cuts: its file's name, its ASF skeleton's name
/// for an AMC motion, and the segments to cut (each labelled with the folder its clip goes in).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ClipTake {
    pub name: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub skeleton: Option<String>,
    pub segmentation: Segmentation,
}

impl Request {
    /// The run id the request names (`None` for a load).
    pub fn run_id(&self) -> Option<RunId> {
        match self {
            Request::Load { .. } | Request::Hold { .. } => None,
            Request::Segment { run, .. }
            | Request::Annotate { run, .. }
            | Request::UseModel { run, .. }
            | Request::ProvideModel { run, .. }
            | Request::Train { run, .. }
            | Request::ContinueTraining { run, .. }
            | Request::StopTraining { run, .. }
            | Request::Clips { run, .. }
            | Request::LibraryTake { run, .. }
            | Request::LibraryCluster { run, .. }
            | Request::LibraryTransfer { run, .. }
            | Request::LibraryClips { run, .. } => Some(*run),
        }
    }

    /// The take the request is about.
    pub fn take(&self) -> TakeId {
        match self {
            Request::Load { take, .. }
            | Request::Hold { take, .. }
            | Request::Segment { take, .. }
            | Request::Annotate { take, .. }
            | Request::UseModel { take, .. }
            | Request::ProvideModel { take, .. }
            | Request::Train { take, .. }
            | Request::ContinueTraining { take, .. }
            | Request::StopTraining { take, .. }
            | Request::Clips { take, .. }
            | Request::LibraryTake { take, .. }
            | Request::LibraryCluster { take, .. }
            | Request::LibraryTransfer { take, .. }
            | Request::LibraryClips { take, .. } => *take,
        }
    }
}

/// Why a request failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FailureKind {
    /// The file or the parameters are bad; the message says where.
    Input,
    /// The worker does not hold the take the request is about.
    NotLoaded,
    /// The run was cancelled.
    Cancelled,
    /// The worker itself broke (a wasm trap): the page replaces it.
    Internal,
}

/// What the summary line shows about a loaded take.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// File name as given by the page.
    pub name: String,
    /// Joints that are not End Sites.
    pub joints: usize,
    pub end_sites: usize,
    pub frames: usize,
    /// Frames per second at full precision (1 / Frame Time).
    pub fps: f64,
    pub duration_s: f64,
    pub units: Units,
    pub up_axis: UpAxis,
    /// The parser's warnings and the unit / up-axis detection notes, as sentences.
    pub warnings: Vec<String>,
}

/// The skeleton as the player draws it: one entry per node (End Sites included), file order.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Skeleton {
    pub names: Vec<String>,
    pub parents: Vec<Option<usize>>,
    pub is_end_site: Vec<bool>,
    /// Each node's OFFSET from its parent, in file units (what, with the positions, makes the
    /// worker's [`Motion`] again: [`LoadedMotion::motion`]).
    #[serde(default)]
    pub offsets: Vec<[f64; 3]>,
}

/// The box every joint stays inside over the whole take (file units and axes).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Bounds {
    pub min: [f32; 3],
    pub max: [f32; 3],
}

impl Bounds {
    /// The bounds of a set of points (a unit box around the origin if there are none).
    pub fn of(points: &[Vec3]) -> Bounds {
        let finite = points.iter().filter(|p| p.is_finite());
        let (min, max) = finite
            .fold((Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
        if min.cmple(max).all() {
            Bounds { min: min.to_array(), max: max.to_array() }
        } else {
            Bounds { min: [-0.5; 3], max: [0.5; 3] }
        }
    }

    pub fn min(&self) -> Vec3 {
        Vec3::from_array(self.min)
    }

    pub fn max(&self) -> Vec3 {
        Vec3::from_array(self.max)
    }
}

/// The motion image as the page draws it (see [`MotionImage`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ImageData {
    /// One column per frame.
    pub width: usize,
    /// One row per joint.
    pub height: usize,
    /// Name of the joint each row shows.
    pub rows: Vec<String>,
    /// `width × height` RGBA pixels, row-major (buffer 1 of a `loaded` packet).
    #[serde(skip)]
    pub rgba: Vec<u8>,
    /// The same image encoded as PNG, for download (buffer 2).
    #[serde(skip)]
    pub png: Vec<u8>,
}

/// A loaded take, as the page receives it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LoadedMotion {
    pub summary: Summary,
    pub skeleton: Skeleton,
    pub bounds: Bounds,
    /// World positions, `frames × nodes × 3` floats (End Sites included), file units (buffer 0).
    #[serde(skip)]
    pub positions: Vec<f32>,
    pub image: ImageData,
}

impl LoadedMotion {
    /// What the page needs of `motion` and its motion image.
    pub fn new(motion: &Motion, image: &MotionImage, png: Vec<u8>) -> LoadedMotion {
        let end_sites = motion.skeleton.is_end_site.iter().filter(|e| **e).count();
        LoadedMotion {
            summary: Summary {
                name: motion.name.clone(),
                joints: motion.joints() - end_sites,
                end_sites,
                frames: motion.frames(),
                fps: motion.fps,
                duration_s: motion.duration_s(),
                units: motion.units,
                up_axis: motion.up_axis,
                warnings: motion.warnings.clone(),
            },
            skeleton: Skeleton {
                names: motion.skeleton.names.clone(),
                parents: motion.skeleton.parents.clone(),
                is_end_site: motion.skeleton.is_end_site.clone(),
                offsets: motion.skeleton.offsets.clone(),
            },
            bounds: Bounds::of(&motion.positions),
            positions: motion.positions.iter().flat_map(|p| p.to_array()).collect(),
            image: ImageData {
                width: image.width,
                height: image.height,
                rows: image.rows.clone(),
                rgba: image.rgba.clone(),
                png,
            },
        }
    }

    /// The worker's motion again, exactly (the positions are the same `f32`s, the rest is in the
    /// summary and the skeleton): what the page hands the other workers of its pool
    /// ([`Request::Hold`]), so that the take is parsed once.
    pub fn motion(&self) -> Motion {
        Motion {
            name: self.summary.name.clone(),
            skeleton: crate::motion::Skeleton {
                names: self.skeleton.names.clone(),
                parents: self.skeleton.parents.clone(),
                offsets: self.skeleton.offsets.clone(),
                is_end_site: self.skeleton.is_end_site.clone(),
            },
            fps: self.summary.fps,
            positions: self.positions.chunks_exact(3).map(|p| Vec3::new(p[0], p[1], p[2])).collect(),
            units: self.summary.units,
            up_axis: self.summary.up_axis,
            warnings: self.summary.warnings.clone(),
        }
    }

    /// Number of nodes per frame (End Sites included).
    pub fn nodes(&self) -> usize {
        self.skeleton.names.len()
    }

    /// The positions of every node in frame `i` (clamped to the last frame).
    pub fn frame(&self, i: usize) -> impl Iterator<Item = Vec3> + '_ {
        let n = self.nodes();
        let i = i.min(self.summary.frames.saturating_sub(1));
        self.positions[i * n * 3..(i + 1) * n * 3].chunks_exact(3).map(Vec3::from_slice)
    }

    /// Refuses a take whose arrays do not match its own counts (so views can index freely).
    fn check_shapes(&self) -> Result<(), String> {
        let nodes = self.nodes();
        let consistent = self.skeleton.parents.len() == nodes
            && self.skeleton.is_end_site.len() == nodes
            && self.skeleton.parents.iter().enumerate().all(|(i, p)| p.is_none_or(|p| p < i))
            && self.summary.frames.checked_mul(nodes * 3) == Some(self.positions.len())
            && self.summary.frames > 0
            && self.image.width.checked_mul(self.image.height).and_then(|p| p.checked_mul(4))
                == Some(self.image.rgba.len());
        if consistent {
            Ok(())
        } else {
            Err("worker message: array sizes do not match the summary".into())
        }
    }
}

/// A finished segmentation, as the page receives it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MethodView {
    pub method: String,
    pub segmentation: Segmentation,
    /// Pictures' pixels are the packet's buffers, in order.
    pub details: Details,
}

impl From<MethodOutput> for MethodView {
    fn from(o: MethodOutput) -> Self {
        MethodView { method: o.segmentation.method.clone(), segmentation: o.segmentation, details: o.details }
    }
}

/// Worker → page.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum Response {
    /// A load (`run: None`) or a run is at `stage`; `fraction` is `None` when the stage cannot
    /// measure itself.
    Progress {
        take: TakeId,
        run: Option<RunId>,
        stage: String,
        fraction: Option<f64>,
    },
    Loaded {
        take: TakeId,
        motion: Box<LoadedMotion>,
    },
    Restored {
        take: TakeId,
    },
    /// The worker holds the motion handed over with [`Request::Hold`].
    Held {
        take: TakeId,
    },
    Segmented {
        take: TakeId,
        run: RunId,
        view: Box<MethodView>,
    },
    /// An `annotate` request's answer: one annotation per span asked, in order.
    Annotated {
        take: TakeId,
        run: RunId,
        annotations: crate::method::Annotations,
    },
    /// A `use_model`: the model is stored, its method's runs may name it now.
    ModelStored {
        take: TakeId,
        run: RunId,
        model: ModelInfo,
    },
    /// One step of the training `run` is done; `more`: the worker goes on with the next.
    TrainingStep {
        take: TakeId,
        run: RunId,
        report: StepReport,
        more: bool,
    },
    /// The training `run` ended (every step ran, or it was stopped: the best model so far is
    /// kept); the model is stored as `model.name`.
    Trained {
        take: TakeId,
        run: RunId,
        model: ModelInfo,
        report: TrainingReport,
        /// Buffer 0: the model file.
        #[serde(skip)]
        bytes: Vec<u8>,
    },
    /// The run `run` (a segment or annotate run) needs the
    /// shipped model file `file`, which this worker does not hold yet: the page fetches it
    /// (`models/FILE` beside the page), sends `provide_model` and asks again.
    NeedsModel {
        take: TakeId,
        run: RunId,
        file: String,
    },
    /// The run `run` was refused its parameters (nothing ran): `message` says why, and `param`
    /// is the method's parameter to blame, when one is (the page shows the message at that
    /// field; it never searches the text for a name).
    Refused {
        take: TakeId,
        run: RunId,
        message: String,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        param: Option<String>,
    },
    /// A `provide_model`: the worker holds the file now.
    ModelProvided {
        take: TakeId,
        run: RunId,
        file: String,
    },
    /// A `provide_model` whose file was damaged or could not be fetched (`message`, naming it):
    /// the worker will not ask for it again (the run, asked again, says what it means for it).
    ModelRefused {
        take: TakeId,
        run: RunId,
        file: String,
        message: String,
    },
    /// A `clips` request's file: `file` to save, `clips` clips in it; its bytes are buffer 0.
    Clips {
        take: TakeId,
        run: RunId,
        file: String,
        clips: usize,
        #[serde(skip)]
        bytes: Vec<u8>,
    },
    /// A `library_take`: the take's length, its segmentation and the features its clusters are
    /// matched with across takes (or why the take has none: it lacks hands, feet, head or hips).
    LibraryTake {
        take: TakeId,
        run: RunId,
        frames: usize,
        duration_s: f64,
        segmentation: Box<Segmentation>,
        features: Result<Box<crate::library::TakeFeatures>, String>,
        /// Why the take does not fit the run's model, when a supervised method's fit check says so (every frame
        /// is then unknown); `None` when it fits or no check was made.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        misfit: Option<String>,
    },
    /// A `library_cluster`: the clusters shared across the takes, in the order they were sent.
    LibraryClusters {
        take: TakeId,
        run: RunId,
        clusters: Box<crate::library::SharedClusters>,
    },
    /// A `library_transfer`: every take's labels, in the order the takes were sent (the labelled
    /// take keeps its own).
    LibraryTransferred {
        take: TakeId,
        run: RunId,
        transfer: Box<crate::library::Transfer>,
    },
    /// A load (`run: None`) or a run failed.
    Failed {
        take: TakeId,
        run: Option<RunId>,
        message: String,
        kind: FailureKind,
        /// The input of the request that is wrong, when it is one of several (a training's
        /// `labels`, `takes`, `name`, or one of its options by name); left out otherwise.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        param: Option<String>,
    },
}

/// A message as it crosses `postMessage`: JSON text and the bulk buffers it refers to.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Packet {
    pub json: String,
    pub buffers: Vec<Vec<u8>>,
}

fn f32_bytes(values: &[f32]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
}

fn bytes_f32(bytes: &[u8], what: &str) -> Result<Vec<f32>, String> {
    if bytes.len() % 4 != 0 {
        return Err(format!("worker message: {what} are not whole floats"));
    }
    Ok(bytes.chunks_exact(4).map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect())
}

fn f64_bytes(values: &[f64]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
}

fn bytes_f64(bytes: &[u8], what: &str) -> Result<Vec<f64>, String> {
    if bytes.len() % 8 != 0 {
        return Err(format!("worker message: {what} are not whole doubles"));
    }
    Ok(bytes.chunks_exact(8).map(|c| f64::from_le_bytes(c.try_into().unwrap_or([0; 8]))).collect())
}

/// A library take's features travel as two buffers — the values as f32, the frames' places as f64 — instead of
/// JSON numbers (a library of 200 three-minute takes holds some 16 million values: as JSON text, hundreds of MB
/// written and parsed at every matching).
fn features_to_buffers(f: &mut crate::library::TakeFeatures, buffers: &mut Vec<Vec<u8>>) {
    buffers.push(f32_bytes(&std::mem::take(&mut f.values)));
    buffers.push(f64_bytes(&std::mem::take(&mut f.source_frames)));
}

/// The features' buffers put back (see [`features_to_buffers`]), their sizes checked; errors begin with `side`
/// ("worker request", "worker message").
fn features_from_buffers(
    f: &mut crate::library::TakeFeatures,
    next: &mut dyn FnMut(&str) -> Result<Vec<u8>, String>,
    side: &str,
) -> Result<(), String> {
    f.values = bytes_f32(&next("a library take's features")?, "a library take's features")?;
    f.source_frames = bytes_f64(&next("a library take's frames")?, "a library take's frames")?;
    if f.dim == 0 || f.values.len() != f.dim * f.source_frames.len() {
        return Err(format!(
            "{side}: a library take's features hold {} values for {} frames of {}",
            f.values.len(),
            f.source_frames.len(),
            f.dim
        ));
    }
    Ok(())
}

fn json_error(what: &str, e: serde_json::Error) -> String {
    format!("{what}: {e}")
}

impl Request {
    /// The JSON and buffers of this request (the file's bytes move into buffer 0).
    pub fn into_packet(mut self) -> Packet {
        let mut features = Vec::new();
        if let Request::LibraryCluster { takes, .. } | Request::LibraryTransfer { takes, .. } = &mut self {
            for t in takes.iter_mut() {
                features_to_buffers(&mut t.features, &mut features);
            }
        }
        // a held motion's positions go as a buffer, not as JSON
        let mut positions = Vec::new();
        if let Request::Hold { motion, .. } = &mut self {
            positions = std::mem::take(&mut motion.positions).iter().flat_map(|p| p.to_array()).collect();
        }
        let json = serde_json::to_string(&self).unwrap_or_default();
        let buffers = match self {
            Request::Load { bytes, skeleton_bytes, skeleton, .. } => {
                if skeleton.is_some() {
                    vec![bytes, skeleton_bytes]
                } else {
                    vec![bytes]
                }
            }
            Request::UseModel { bytes, .. } | Request::ProvideModel { bytes, .. } => vec![bytes],
            Request::Hold { .. } => vec![f32_bytes(&positions)],
            Request::Train { bytes, .. } | Request::LibraryClips { bytes, .. } => bytes,
            Request::LibraryTake { bytes, skeleton_bytes, skeleton, .. } => {
                if skeleton.is_some() {
                    vec![bytes, skeleton_bytes]
                } else {
                    vec![bytes]
                }
            }
            Request::Segment { .. }
            | Request::Annotate { .. }
            | Request::ContinueTraining { .. }
            | Request::StopTraining { .. }
            | Request::Clips { .. } => Vec::new(),
            Request::LibraryCluster { .. } | Request::LibraryTransfer { .. } => features,
        };
        Packet { json, buffers }
    }

    /// The request a packet carries.
    pub fn from_packet(packet: Packet) -> Result<Request, String> {
        let mut request: Request = serde_json::from_str(&packet.json).map_err(|e| json_error("worker request", e))?;
        let mut buffers = packet.buffers.into_iter();
        match &mut request {
            Request::Load { bytes, skeleton, skeleton_bytes, .. }
            | Request::LibraryTake { bytes, skeleton, skeleton_bytes, .. } => {
                *bytes = buffers.next().ok_or("worker request: a load without the file's bytes")?;
                if skeleton.is_some() {
                    *skeleton_bytes =
                        buffers.next().ok_or("worker request: an AMC without its ASF skeleton's bytes")?;
                }
            }
            Request::UseModel { bytes, .. } | Request::ProvideModel { bytes, .. } => {
                *bytes = buffers.next().ok_or("worker request: a model file without its bytes")?;
            }
            Request::Hold { motion, .. } => {
                let floats =
                    bytes_f32(&buffers.next().ok_or("worker request: a motion without its positions")?, "positions")?;
                let nodes = motion.skeleton.names.len();
                let s = &motion.skeleton;
                if nodes == 0
                    || s.parents.len() != nodes
                    || s.offsets.len() != nodes
                    || s.is_end_site.len() != nodes
                    || floats.len() % (3 * nodes) != 0
                    || floats.is_empty()
                {
                    return Err(format!(
                        "worker request: a motion of {nodes} nodes ({} parents, {} offsets) with {} position values, not whole frames",
                        s.parents.len(),
                        s.offsets.len(),
                        floats.len()
                    ));
                }
                if floats.len() / 3 > crate::motion::MAX_POSITIONS {
                    return Err(format!(
                        "worker request: a motion of {} joint positions, more than the {} a take may hold",
                        floats.len() / 3,
                        crate::motion::MAX_POSITIONS
                    ));
                }
                motion.positions = floats.chunks_exact(3).map(|p| Vec3::new(p[0], p[1], p[2])).collect();
            }
            Request::Train { takes, bytes, .. } => {
                *bytes = buffers.by_ref().take(takes.len()).collect();
                if bytes.len() != takes.len() {
                    return Err(format!(
                        "worker request: a training with {} takes but the bytes of {}",
                        takes.len(),
                        bytes.len()
                    ));
                }
            }
            Request::LibraryCluster { takes, .. } | Request::LibraryTransfer { takes, .. } => {
                let mut next =
                    |what: &str| buffers.next().ok_or_else(|| format!("worker request: no buffer for {what}"));
                for t in takes.iter_mut() {
                    features_from_buffers(&mut t.features, &mut next, "worker request")?;
                }
            }
            Request::LibraryClips { takes, bytes, .. } => {
                let wanted: usize = takes.iter().map(|t| 1 + usize::from(t.skeleton.is_some())).sum();
                *bytes = buffers.by_ref().take(wanted).collect();
                if bytes.len() != wanted {
                    return Err(format!(
                        "worker request: clips of {} takes that need {wanted} files but carry {}",
                        takes.len(),
                        bytes.len()
                    ));
                }
            }
            Request::Segment { .. }
            | Request::Annotate { .. }
            | Request::ContinueTraining { .. }
            | Request::StopTraining { .. }
            | Request::Clips { .. } => {}
        }
        Ok(request)
    }
}

impl Response {
    /// The run this response is about (`None`: about a load, or a message about no run).
    pub fn run_id(&self) -> Option<RunId> {
        match self {
            Response::Progress { run, .. } | Response::Failed { run, .. } => *run,
            Response::Loaded { .. } | Response::Restored { .. } | Response::Held { .. } => None,
            Response::Segmented { run, .. }
            | Response::Annotated { run, .. }
            | Response::ModelStored { run, .. }
            | Response::TrainingStep { run, .. }
            | Response::Trained { run, .. }
            | Response::NeedsModel { run, .. }
            | Response::Refused { run, .. }
            | Response::ModelProvided { run, .. }
            | Response::ModelRefused { run, .. }
            | Response::Clips { run, .. }
            | Response::LibraryTake { run, .. }
            | Response::LibraryClusters { run, .. }
            | Response::LibraryTransferred { run, .. } => Some(*run),
        }
    }

    /// The JSON and buffers of this response (positions, pixels and PNG move into buffers).
    pub fn into_packet(self) -> Packet {
        let mut buffers = Vec::new();
        let mut this = self;
        match &mut this {
            Response::Loaded { motion, .. } => {
                buffers.push(f32_bytes(&std::mem::take(&mut motion.positions)));
                buffers.push(std::mem::take(&mut motion.image.rgba));
                buffers.push(std::mem::take(&mut motion.image.png));
            }
            Response::Segmented { view, .. } => {
                for p in &mut view.details.pictures {
                    buffers.push(std::mem::take(&mut p.rgba));
                }
            }
            Response::Trained { bytes, .. } => buffers.push(std::mem::take(bytes)),
            Response::Clips { bytes, .. } => buffers.push(std::mem::take(bytes)),
            Response::LibraryTake { features: Ok(f), .. } => features_to_buffers(f, &mut buffers),
            _ => {}
        }
        Packet { json: serde_json::to_string(&this).unwrap_or_default(), buffers }
    }

    /// The response a packet carries, with its buffers back in place and every size checked.
    pub fn from_packet(packet: Packet) -> Result<Response, String> {
        let mut response: Response = serde_json::from_str(&packet.json).map_err(|e| json_error("worker message", e))?;
        let mut buffers = packet.buffers.into_iter();
        let mut next = |what: &str| buffers.next().ok_or_else(|| format!("worker message: no buffer for {what}"));
        match &mut response {
            Response::Loaded { motion, .. } => {
                motion.positions = bytes_f32(&next("positions")?, "positions")?;
                motion.image.rgba = next("the motion image")?;
                motion.image.png = next("the PNG")?;
                motion.check_shapes()?;
            }
            Response::Segmented { view, .. } => {
                view.segmentation.validate().map_err(|e| format!("worker message: {e}"))?;
                for p in &mut view.details.pictures {
                    p.rgba = next(&p.id)?;
                    if p.width.checked_mul(p.height).and_then(|n| n.checked_mul(4)) != Some(p.rgba.len()) {
                        return Err(format!("worker message: picture {} is not {}×{} pixels", p.id, p.width, p.height));
                    }
                }
                if let Some(c) = view.details.curves.iter().find(|c| c.values.len() != view.segmentation.frames) {
                    return Err(format!("worker message: curve {} does not have one value per frame", c.id));
                }
            }
            Response::Trained { bytes, model, .. } => {
                *bytes = next("the trained model")?;
                model.check().map_err(|e| format!("worker message: {e}"))?;
            }
            Response::ModelStored { model, .. } => model.check().map_err(|e| format!("worker message: {e}"))?,
            Response::LibraryTake { segmentation, features, .. } => {
                segmentation.validate().map_err(|e| format!("worker message: {e}"))?;
                if let Ok(f) = features {
                    features_from_buffers(f, &mut next, "worker message")?;
                }
            }
            Response::LibraryClusters { clusters, .. } => {
                for s in &clusters.takes {
                    s.validate().map_err(|e| format!("worker message: {e}"))?;
                }
                let fits = clusters
                    .clusters
                    .iter()
                    .flat_map(|c| &c.occurrences)
                    .all(|o| clusters.takes.get(o.take).is_some_and(|s| o.start <= o.end && o.end < s.frames));
                if !fits {
                    return Err("worker message: a cluster's occurrence is not inside its take".into());
                }
            }
            Response::LibraryTransferred { transfer, .. } => {
                for t in &transfer.takes {
                    t.segmentation.validate().map_err(|e| format!("worker message: {e}"))?;
                    if t.frame_labels.len() != t.segmentation.frames {
                        return Err("worker message: transferred labels do not cover their take".into());
                    }
                }
            }
            Response::Clips { bytes, .. } => *bytes = next("the clips")?,
            _ => {}
        }
        Ok(response)
    }
}

/// The most bytes of takes a training may bring besides the take on screen: with that take (at
/// most the 512 MiB the page reads) a training stays within what one tab can hold. The page
/// refuses more when the user picks them ([`extra_takes_total`]), the worker when a request
/// brings more.
pub const MAX_EXTRA_TAKES_BYTES: u64 = 256 * 1024 * 1024;

/// The total size of the takes a training adds (`sizes`, in bytes), or why they are refused,
/// naming the cap.
pub fn extra_takes_total(sizes: impl IntoIterator<Item = u64>) -> Result<u64, String> {
    let total = sizes.into_iter().fold(0u64, u64::saturating_add);
    if total > MAX_EXTRA_TAKES_BYTES {
        const MIB: f64 = 1024.0 * 1024.0;
        return Err(format!(
            "the added takes come to {:.0} MiB, more than the {:.0} MiB a training may add besides the take on \
             screen: remove some, or cut them",
            (total as f64 / MIB).ceil(),
            MAX_EXTRA_TAKES_BYTES as f64 / MIB
        ));
    }
    Ok(total)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::load::load_bytes;
    use crate::method::{NoProgress, RunOptions};

    fn walk() -> Motion {
        load_bytes("12_01.bvh", include_bytes!("../tests/fixtures/12_01.bvh"), &mut |_| {}).unwrap().motion
    }

    /// The page's loader routes a reply by its run id to the feature that sent the run: a reply about a run names
    /// it, a load's progress, failure or answer names none.
    #[test]
    fn a_reply_names_the_run_it_answers() {
        let clips = Response::Clips { take: 1, run: 7, file: "a.zip".into(), clips: 2, bytes: Vec::new() };
        assert_eq!(clips.run_id(), Some(7));
        let refused = Response::Refused { take: 1, run: 8, message: "no".into(), param: None };
        assert_eq!(refused.run_id(), Some(8));
        let progress = |run| Response::Progress { take: 1, run, stage: "s".into(), fraction: None };
        assert_eq!(progress(Some(9)).run_id(), Some(9));
        assert_eq!(progress(None).run_id(), None);
        let failed =
            |run| Response::Failed { take: 1, run, message: "m".into(), kind: FailureKind::NotLoaded, param: None };
        assert_eq!(failed(Some(3)).run_id(), Some(3));
        assert_eq!(failed(None).run_id(), None);
        assert_eq!(Response::Restored { take: 1 }.run_id(), None);
    }

    #[test]
    fn the_takes_a_training_adds_are_capped_in_total_and_the_refusal_names_the_cap() {
        let mib = 1024 * 1024;
        assert_eq!(extra_takes_total([]), Ok(0));
        assert_eq!(extra_takes_total([100 * mib, 156 * mib]), Ok(MAX_EXTRA_TAKES_BYTES));
        let e = extra_takes_total([100 * mib, 156 * mib, 1]).unwrap_err();
        assert!(e.contains("257 MiB") && e.contains("256 MiB"), "{e}");
        let e = extra_takes_total([u64::MAX, u64::MAX]).unwrap_err();
        assert!(e.contains("more than the 256 MiB"), "no overflow: {e}");
    }

    #[test]
    fn requests_round_trip_with_their_bytes_in_a_buffer() {
        let load = Request::Load {
            take: 3,
            name: "a b.bvh".into(),
            restore: true,
            bytes: b"HIERARCHY".to_vec(),
            skeleton: None,
            skeleton_bytes: Vec::new(),
        };
        let packet = load.clone().into_packet();
        assert_eq!(packet.buffers, vec![b"HIERARCHY".to_vec()]);
        assert!(!packet.json.contains("HIERARCHY"), "bytes travel as a buffer: {}", packet.json);
        let v: serde_json::Value = serde_json::from_str(&packet.json).unwrap();
        assert_eq!(
            (v["type"].as_str(), v["take"].as_u64(), v["restore"].as_bool()),
            (Some("load"), Some(3), Some(true))
        );
        assert_eq!(Request::from_packet(packet).unwrap(), load);

        let seg =
            Request::Segment { take: 3, run: 9, method: "sssm".into(), params: serde_json::json!({"radius": 15}) };
        assert_eq!(Request::from_packet(seg.clone().into_packet()).unwrap(), seg);
        assert_eq!(seg.take(), 3);

        let train = Request::Train {
            take: 3,
            run: 10,
            method: "dtfcn".into(),
            name: "mine".into(),
            labels_name: "l.csv".into(),
            labels: "file,start_frame,end_frame,label\n".into(),
            takes: vec!["a.bvh".into(), "b.bvh".into()],
            options: serde_json::json!({"epochs": 3}),
            continue_from: Some("older".into()),
            validation: Some("b.bvh".into()),
            bytes: vec![b"A".to_vec(), b"B".to_vec()],
        };
        let packet = train.clone().into_packet();
        assert_eq!(packet.buffers, vec![b"A".to_vec(), b"B".to_vec()]);
        assert_eq!(Request::from_packet(packet.clone()).unwrap(), train);
        let mut short = packet;
        short.buffers.pop();
        assert!(Request::from_packet(short).unwrap_err().contains("2 takes but the bytes of 1"));
        let trained = Response::Trained {
            take: 3,
            run: 10,
            model: crate::method::supervised::ModelInfo {
                method: "dtfcn".into(),
                name: "mine".into(),
                classes: vec!["a".into(), "b".into()],
                colours: vec!["#000000".into(), "#ffffff".into()],
                origin: "2 classes".into(),
                provenance: vec![("takes".into(), "a.bvh".into())],
                card: crate::method::cards::ModelCard {
                    takes: vec!["a.bvh".into()],
                    take_sha256: vec!["00ff".into()],
                    ..Default::default()
                },
            },
            report: TrainingReport { summary: "Trained".into(), ..TrainingReport::default() },
            bytes: b"MODEL".to_vec(),
        };
        let packet = trained.clone().into_packet();
        assert_eq!(packet.buffers, vec![b"MODEL".to_vec()]);
        assert_eq!(Response::from_packet(packet).unwrap(), trained);

        let no_bytes =
            Packet { json: r#"{"type":"load","take":1,"name":"x","restore":false}"#.into(), buffers: vec![] };
        assert!(Request::from_packet(no_bytes).unwrap_err().contains("without the file's bytes"));
        let unknown = Packet { json: r#"{"type":"explode","take":1}"#.into(), buffers: vec![] };
        assert!(Request::from_packet(unknown).unwrap_err().contains("unknown variant `explode`"));
    }

    /// A library's features go as buffers (values f32, frames f64), never as JSON numbers, both ways; a buffer of
    /// the wrong size is refused with what it held.
    #[test]
    fn a_librarys_features_travel_in_buffers() {
        let motion = walk();
        let features = crate::library::TakeFeatures::of(&motion, &crate::library::LibraryParams::default()).unwrap();
        let segmentation = crate::methods::find("velocity")
            .unwrap()
            .run_json(&motion, &serde_json::json!({}), &RunOptions::default(), &mut NoProgress)
            .unwrap()
            .segmentation;
        let take = crate::library::LibraryTake { name: "12_01.bvh".into(), features: features.clone(), segmentation };
        let request = Request::LibraryCluster { take: 0, run: 2, takes: vec![take.clone(), take.clone()] };
        let packet = request.clone().into_packet();
        assert_eq!(packet.buffers.len(), 4, "two buffers a take");
        assert_eq!(packet.buffers[0].len(), features.values.len() * 4);
        assert_eq!(packet.buffers[1].len(), features.source_frames.len() * 8);
        let v: serde_json::Value = serde_json::from_str(&packet.json).unwrap();
        assert_eq!(v["takes"][0]["features"]["values"], serde_json::json!([]), "no feature value in the JSON");
        assert!(packet.json.len() < 20_000, "{} bytes of JSON", packet.json.len());
        assert_eq!(Request::from_packet(packet.clone()).unwrap(), request);
        let mut short = packet;
        short.buffers[2].truncate(8);
        let e = Request::from_packet(short).unwrap_err();
        assert!(e.starts_with("worker request: a library take's features hold 2 values for"), "{e}");

        let answer = Response::LibraryTake {
            take: 0,
            run: 3,
            frames: motion.frames(),
            duration_s: motion.duration_s(),
            segmentation: Box::new(take.segmentation.clone()),
            features: Ok(Box::new(features.clone())),
            misfit: None,
        };
        let packet = answer.clone().into_packet();
        assert_eq!(packet.buffers.len(), 2);
        assert_eq!(Response::from_packet(packet.clone()).unwrap(), answer);
        let mut lost = packet;
        lost.buffers.pop();
        assert_eq!(Response::from_packet(lost).unwrap_err(), "worker message: no buffer for a library take's frames");
        // a take without features sends no buffer
        let mut none = answer;
        if let Response::LibraryTake { features, .. } = &mut none {
            *features = Err("no hands".into());
        }
        assert!(none.clone().into_packet().buffers.is_empty());
        assert_eq!(Response::from_packet(none.clone().into_packet()).unwrap(), none);
    }

    #[test]
    fn a_label_transfer_travels_as_json_alone() {
        let request = Request::LibraryTransfer {
            take: 0,
            run: 4,
            takes: Vec::new(),
            labelled: 1,
            frame_labels: vec![None, Some("walk".into())],
            route: crate::library::TransferRoute::Clusters,
        };
        let packet = request.clone().into_packet();
        assert!(packet.buffers.is_empty());
        let v: serde_json::Value = serde_json::from_str(&packet.json).unwrap();
        assert_eq!(
            (v["type"].as_str(), v["labelled"].as_u64(), v["route"].as_str(), &v["frame_labels"]),
            (Some("library_transfer"), Some(1), Some("clusters"), &serde_json::json!([null, "walk"]))
        );
        assert_eq!((request.run_id(), request.take()), (Some(4), 0));
        assert_eq!(Request::from_packet(packet).unwrap(), request);
        let answer = Response::LibraryTransferred {
            take: 0,
            run: 4,
            transfer: Box::new(crate::library::Transfer {
                route: crate::library::TransferRoute::Nearest,
                takes: Vec::new(),
            }),
        };
        let v: serde_json::Value = serde_json::from_str(&answer.clone().into_packet().json).unwrap();
        assert_eq!(
            (v["type"].as_str(), v["transfer"]["route"].as_str()),
            (Some("library_transferred"), Some("nearest"))
        );
        assert_eq!(Response::from_packet(answer.clone().into_packet()).unwrap(), answer);
    }

    #[test]
    fn a_loaded_take_round_trips_with_positions_and_pixels_in_buffers() {
        let motion = walk();
        let image = MotionImage::from_motion(&motion);
        let png = image.try_to_png().unwrap();
        let loaded = LoadedMotion::new(&motion, &image, png);
        assert_eq!(loaded.positions.len(), motion.frames() * motion.joints() * 3);
        let response = Response::Loaded { take: 5, motion: Box::new(loaded.clone()) };
        let packet = response.clone().into_packet();
        assert_eq!(packet.buffers.len(), 3);
        assert_eq!(packet.buffers[0].len(), loaded.positions.len() * 4);
        assert!(packet.json.len() < 10_000, "no bulk data in the JSON ({} bytes)", packet.json.len());
        assert_eq!(Response::from_packet(packet.clone()).unwrap(), response);
        // a frame's positions survive bit for bit
        let Response::Loaded { motion: back, .. } = Response::from_packet(packet.clone()).unwrap() else { panic!() };
        assert_eq!(back.frame(100).collect::<Vec<_>>(), loaded.frame(100).collect::<Vec<_>>());

        // buffers that do not fit the summary are refused
        let mut short = packet.clone();
        short.buffers[0].truncate(12);
        assert!(Response::from_packet(short).unwrap_err().contains("array sizes"));
        let mut missing = packet;
        missing.buffers.pop();
        assert!(Response::from_packet(missing).unwrap_err().contains("no buffer for the PNG"));
    }

    #[test]
    fn a_segmentation_round_trips_with_its_pictures_in_buffers() {
        let motion = walk();
        let m = crate::methods::find("sssm").unwrap();
        let output = m
            .run_json(
                &motion,
                &serde_json::json!({}),
                &RunOptions { pictures: true, ..RunOptions::default() },
                &mut NoProgress,
            )
            .unwrap();
        let picture_bytes: Vec<usize> = output.details.pictures.iter().map(|p| p.rgba.len()).collect();
        assert!(!picture_bytes.is_empty());
        let response = Response::Segmented { take: 2, run: 7, view: Box::new(output.into()) };
        let packet = response.clone().into_packet();
        assert_eq!(packet.buffers.iter().map(Vec::len).collect::<Vec<_>>(), picture_bytes);
        assert_eq!(Response::from_packet(packet.clone()).unwrap(), response);
        let mut bad = packet;
        bad.buffers[0].pop();
        assert!(Response::from_packet(bad).unwrap_err().contains("picture image"));
    }

    #[test]
    fn small_responses_round_trip() {
        for r in [
            Response::Progress { take: 1, run: None, stage: "parsing".into(), fraction: Some(0.5) },
            Response::Progress { take: 1, run: Some(4), stage: "neighbours".into(), fraction: None },
            Response::Restored { take: 8 },
            Response::Failed {
                take: 1,
                run: Some(2),
                message: "take 1 is not loaded".into(),
                kind: FailureKind::NotLoaded,
                param: None,
            },
            Response::Failed {
                take: 1,
                run: None,
                message: "x.bvh: line 3".into(),
                kind: FailureKind::Input,
                param: Some("labels".into()),
            },
            Response::TrainingStep {
                take: 2,
                run: 6,
                report: StepReport {
                    step: 2,
                    steps: 5,
                    line: "epoch 2".into(),
                    values: vec![("loss".into(), 0.5)],
                    best: true,
                },
                more: true,
            },
        ] {
            let packet = r.clone().into_packet();
            assert!(packet.buffers.is_empty());
            assert_eq!(Response::from_packet(packet).unwrap(), r);
        }
        let v: serde_json::Value = serde_json::from_str(&Response::Restored { take: 8 }.into_packet().json).unwrap();
        assert_eq!(v, serde_json::json!({"type": "restored", "take": 8}));
    }

    #[test]
    fn bounds_of_points() {
        let b = Bounds::of(&[Vec3::new(1.0, -2.0, 3.0), Vec3::new(-1.0, 5.0, 0.0)]);
        assert_eq!((b.min, b.max), ([-1.0, -2.0, 0.0], [1.0, 5.0, 3.0]));
        assert_eq!(Bounds::of(&[]).min, [-0.5; 3]);
    }
}
