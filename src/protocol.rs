//! The page ↔ worker protocol: one [`Request`] enum and one [`Response`] enum (serde, tagged by
//! `type`), carried as a [`Packet`]: the message as JSON text plus its bulk data (file bytes,
//! joint positions, pixels) as separate byte buffers, which the web layer transfers between
//! threads instead of copying. Pure Rust, so the encoding is tested natively; `crate::worker`
//! and `crate::app` only move packets in and out of `postMessage`.
//!
//! Every request names the take it is about (`take`, chosen by the page for each file it loads).
//! The worker holds one take; a `segment` request for another take is refused with
//! [`FailureKind::NotLoaded`], and the page then sends the take it shows again (`restore`) and
//! repeats the request — so the page never segments a take other than the one on screen, even
//! after a load that lost a race or a worker replaced after a crash or a cancel.
//!
//! The worker also holds the LMA classifier family its `lma` runs use: `train_lma` trains one on
//! the user's Effort labels for the held take, `use_lma_model` loads one the user saved (or goes
//! back to the shipped family). A worker starts with the shipped family, so the page sends the
//! family it holds to every new worker before anything else.

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::image::MotionImage;
use crate::lma::classifier::EffortModel;
use crate::lma::corpus::{parse_labels, Corpus, CorpusConfig, EffortLabel, Sample};
use crate::lma::training::{train_family, FactorReport, TrainConfig};
use crate::method::{Details, MethodError, MethodOutput, RunOptions};
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
    },
    /// Segment take `take` with `method` (a registry name) and `params` (JSON, fields optional).
    Segment { take: TakeId, run: RunId, method: String, params: serde_json::Value },
    /// Train the LMA classifier family on the rows of `labels` (the text of the Effort labels CSV
    /// `name`, `file,start_frame,end_frame,space,time,weight,flow`) that name take `take`; rows
    /// for other files are counted and left out. The family then serves every later `lma` run.
    TrainLma { take: TakeId, run: RunId, name: String, labels: String },
    /// Make `model` (a family's JSON text, as `Trained` sends it or a user saved it) the family
    /// of every later `lma` run; `None`: the shipped family again. Any worker accepts it, whatever
    /// take it holds (`take` and `run` only name the answer).
    UseLmaModel {
        take: TakeId,
        run: RunId,
        /// Buffer 0 when present (UTF-8); no buffer means the shipped family.
        #[serde(skip)]
        model: Option<String>,
    },
}

impl Request {
    /// The take the request is about.
    pub fn take(&self) -> TakeId {
        match self {
            Request::Load { take, .. }
            | Request::Segment { take, .. }
            | Request::TrainLma { take, .. }
            | Request::UseLmaModel { take, .. } => *take,
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

/// How a trained LMA family did on one Effort factor (from the trainer's [`FactorReport`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FactorSummary {
    /// `space`, `time`, `weight` or `flow`.
    pub factor: String,
    /// The labelled segments per class: indulging, neutral, condensing.
    pub segments: [usize; 3],
    /// Hidden units of its networks.
    pub hidden: usize,
    /// The unshifted network's error rate on the training and the held-out validation segments.
    pub train_error: f32,
    pub validation_error: f32,
    /// Mean validation error of the boundary-shifted networks on their shifted segments.
    pub shifted_validation_error: f32,
}

impl FactorSummary {
    fn new(report: &FactorReport, samples: &[Sample], factor: usize) -> FactorSummary {
        let mut segments = [0; 3];
        for s in samples {
            if let Some(n) = segments.get_mut(s.classes[factor]) {
                *n += 1;
            }
        }
        FactorSummary {
            factor: report.factor.name().to_string(),
            segments,
            hidden: report.hidden,
            train_error: report.train_error,
            validation_error: report.validation_error,
            shifted_validation_error: report.shifted_validation_error,
        }
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
    Segmented {
        take: TakeId,
        run: RunId,
        view: Box<MethodView>,
    },
    /// A `train_lma` run finished: `model` is the family's JSON (for the page to save and to send
    /// to a new worker), now in use. `used_rows` named the take, `ignored_rows` other files.
    Trained {
        take: TakeId,
        run: RunId,
        /// Buffer 0 (UTF-8).
        #[serde(skip)]
        model: String,
        /// Space, Time, Weight, Flow.
        report: Vec<FactorSummary>,
        /// Where the labels came from, in words (as the `lma` summary shows it).
        origin: String,
        used_rows: usize,
        ignored_rows: usize,
    },
    /// The family `lma` runs use now (after `use_lma_model`).
    ModelInUse {
        take: TakeId,
        run: RunId,
        origin: String,
        shipped: bool,
    },
    /// A load (`run: None`) or a run failed.
    Failed {
        take: TakeId,
        run: Option<RunId>,
        message: String,
        kind: FailureKind,
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

fn bytes_f32(bytes: &[u8]) -> Result<Vec<f32>, String> {
    if bytes.len() % 4 != 0 {
        return Err("worker message: positions are not whole floats".into());
    }
    Ok(bytes.chunks_exact(4).map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect())
}

fn utf8(bytes: Vec<u8>, what: &str) -> Result<String, String> {
    String::from_utf8(bytes).map_err(|e| format!("worker message: {what} is not UTF-8 text ({e})"))
}

fn json_error(what: &str, e: serde_json::Error) -> String {
    format!("{what}: {e}")
}

impl Request {
    /// The JSON and buffers of this request (the file's bytes move into buffer 0).
    pub fn into_packet(self) -> Packet {
        let json = serde_json::to_string(&self).unwrap_or_default();
        let buffers = match self {
            Request::Load { bytes, .. } => vec![bytes],
            Request::UseLmaModel { model, .. } => model.into_iter().map(String::into_bytes).collect(),
            Request::Segment { .. } | Request::TrainLma { .. } => Vec::new(),
        };
        Packet { json, buffers }
    }

    /// The request a packet carries.
    pub fn from_packet(packet: Packet) -> Result<Request, String> {
        let mut request: Request = serde_json::from_str(&packet.json).map_err(|e| json_error("worker request", e))?;
        let mut buffers = packet.buffers.into_iter();
        match &mut request {
            Request::Load { bytes, .. } => {
                *bytes = buffers.next().ok_or("worker request: a load without the file's bytes")?;
            }
            Request::UseLmaModel { model, .. } => {
                *model = buffers.next().map(|b| utf8(b, "the LMA family")).transpose()?;
            }
            Request::Segment { .. } | Request::TrainLma { .. } => {}
        }
        Ok(request)
    }
}

impl Response {
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
            Response::Trained { model, .. } => buffers.push(std::mem::take(model).into_bytes()),
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
                motion.positions = bytes_f32(&next("positions")?)?;
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
            Response::Trained { model, .. } => *model = utf8(next("the trained family")?, "the trained family")?,
            _ => {}
        }
        Ok(response)
    }
}

/// The worker's side of the protocol: holds the take loaded last and answers requests. Pure
/// Rust (the wasm entry point in `crate::worker` only converts packets), so the take checks
/// are tested natively.
#[derive(Debug, Default)]
pub struct WorkerState {
    held: Option<(TakeId, Motion)>,
    /// How `train_lma` trains (the trainer's defaults).
    training: TrainConfig,
}

impl WorkerState {
    /// A worker that trains LMA families with `training` instead of the defaults.
    pub fn with_training(training: TrainConfig) -> WorkerState {
        WorkerState { held: None, training }
    }

    /// The take the worker holds.
    pub fn held(&self) -> Option<TakeId> {
        self.held.as_ref().map(|(t, _)| *t)
    }

    /// The held take if it is `take`, else the `not_loaded` message.
    fn motion(&self, take: TakeId) -> Result<&Motion, String> {
        match &self.held {
            Some((held, motion)) if *held == take => Ok(motion),
            Some((held, _)) => Err(format!("take {take} is not loaded in the worker (it holds take {held})")),
            None => Err(format!("take {take} is not loaded in the worker (it holds none)")),
        }
    }

    /// Answers `request`, posting progress and the final response through `post`.
    pub fn handle(&mut self, request: Request, post: &mut dyn FnMut(Response)) {
        match request {
            Request::Load { take, name, restore, bytes } => {
                let mut progress =
                    |f: f64| post(Response::Progress { take, run: None, stage: "parsing".into(), fraction: Some(f) });
                let response = match self.load(take, &name, &bytes, &mut progress) {
                    Ok(motion) if restore => {
                        drop(motion);
                        Response::Restored { take }
                    }
                    Ok(motion) => Response::Loaded { take, motion },
                    Err(message) => Response::Failed { take, run: None, message, kind: FailureKind::Input },
                };
                post(response);
            }
            Request::Segment { take, run, method, params } => {
                let response = self.segment(take, run, &method, &params, post);
                post(response);
            }
            Request::TrainLma { take, run, name, labels } => {
                let response = self.train_lma(take, run, &name, &labels, post);
                post(response);
            }
            Request::UseLmaModel { take, run, model } => post(use_lma_model(take, run, model.as_deref())),
        }
    }

    fn load(
        &mut self,
        take: TakeId,
        name: &str,
        bytes: &[u8],
        progress: &mut dyn FnMut(f64),
    ) -> Result<Box<LoadedMotion>, String> {
        let loaded = crate::load::load_bytes(name, bytes, progress).map_err(|e| e.to_string())?;
        let motion = loaded.motion;
        let image = MotionImage::from_motion(&motion);
        let png = image.try_to_png().map_err(|e| format!("{name}: motion image: {e}"))?;
        let view = Box::new(LoadedMotion::new(&motion, &image, png));
        self.held = Some((take, motion));
        Ok(view)
    }

    fn segment(
        &self,
        take: TakeId,
        run: RunId,
        method: &str,
        params: &serde_json::Value,
        post: &mut dyn FnMut(Response),
    ) -> Response {
        let fail = |message: String, kind| Response::Failed { take, run: Some(run), message, kind };
        let motion = match self.motion(take) {
            Ok(motion) => motion,
            Err(message) => return fail(message, FailureKind::NotLoaded),
        };
        let m = match crate::method::find(method) {
            Ok(m) => m,
            Err(e) => return fail(e.to_string(), FailureKind::Input),
        };
        let short = m.info().short;
        let mut progress = |stage: &str, fraction: f64| {
            post(Response::Progress { take, run: Some(run), stage: stage.into(), fraction: Some(fraction) })
        };
        match m.run_json(motion, params, &RunOptions { pictures: true }, &mut progress) {
            Ok(output) => Response::Segmented { take, run, view: Box::new(output.into()) },
            Err(MethodError::Cancelled) => fail(format!("{short}: cancelled"), FailureKind::Cancelled),
            Err(e @ MethodError::Params(_)) => fail(e.to_string(), FailureKind::Input),
            Err(e) => fail(format!("{short} on {}: {e}", motion.name), FailureKind::Input),
        }
    }

    /// Trains the LMA family on the rows of the labels file `name` that name the held take (the
    /// others are counted), reporting progress as run `run`, and makes it the family in use.
    /// Like a segment run it is stopped by replacing the worker, so its progress never cancels.
    fn train_lma(
        &self,
        take: TakeId,
        run: RunId,
        name: &str,
        labels: &str,
        post: &mut dyn FnMut(Response),
    ) -> Response {
        let fail = |message: String, kind| Response::Failed { take, run: Some(run), message, kind };
        let motion = match self.motion(take) {
            Ok(motion) => motion,
            Err(message) => return fail(message, FailureKind::NotLoaded),
        };
        let rows = match parse_labels(labels, name) {
            Ok(rows) => rows,
            Err(message) => return fail(message, FailureKind::Input),
        };
        let (used, ignored): (Vec<EffortLabel>, Vec<EffortLabel>) =
            rows.into_iter().partition(|row| crate::lma::corpus::same_file(&row.file, &motion.name));
        if used.is_empty() {
            return fail(no_rows_for(name, &motion.name, &ignored), FailureKind::Input);
        }
        let mut corpus = match Corpus::from_labels(&[motion], &used, CorpusConfig::default()) {
            Ok(corpus) => corpus,
            Err(message) => return fail(format!("{name}: {message}"), FailureKind::Input),
        };
        corpus.origin = format!("{} segments of {} labelled in {name}", corpus.samples.len(), motion.name);
        let mut progress = |stage: &str, fraction: f64| {
            post(Response::Progress { take, run: Some(run), stage: stage.into(), fraction: Some(fraction) });
            Ok(())
        };
        let (model, reports) = match train_family(&corpus, &self.training, &mut progress) {
            Ok(trained) => trained,
            Err(message) => return fail(format!("{name}: {message}"), FailureKind::Input),
        };
        let report = reports.iter().enumerate().map(|(f, r)| FactorSummary::new(r, &corpus.samples, f)).collect();
        let json = model.to_json();
        let origin = model.origin.clone();
        crate::lma::use_model(Some(model));
        Response::Trained { take, run, model: json, report, origin, used_rows: used.len(), ignored_rows: ignored.len() }
    }
}

/// Makes the family `model` (JSON text; `None`: the shipped one) the one `lma` runs use.
fn use_lma_model(take: TakeId, run: RunId, model: Option<&str>) -> Response {
    let fail = |message: String| Response::Failed { take, run: Some(run), message, kind: FailureKind::Input };
    match model.map(EffortModel::from_json).transpose() {
        Ok(model) => crate::lma::use_model(model),
        Err(message) => return fail(message),
    }
    match crate::lma::model_in_use() {
        Ok((model, shipped)) => Response::ModelInUse { take, run, origin: model.origin.clone(), shipped },
        Err(message) => fail(message),
    }
}

/// Why a labels file gives nothing to learn from the take `take`: no rows at all, or only rows
/// for other files (a few of which it names).
fn no_rows_for(name: &str, take: &str, others: &[EffortLabel]) -> String {
    if others.is_empty() {
        return format!("{name} has no rows, only its header");
    }
    let mut files: Vec<&str> = Vec::new();
    for row in others {
        if !files.contains(&row.file.as_str()) {
            files.push(&row.file);
        }
    }
    const SHOWN: usize = 5;
    let mut named = files.iter().take(SHOWN).map(|f| format!("`{f}`")).collect::<Vec<_>>().join(", ");
    if files.len() > SHOWN {
        named += &format!(" and {} more", files.len() - SHOWN);
    }
    format!("{name}: no row is for the loaded take `{take}`; its rows name {named}")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::load::load_bytes;
    use crate::method::{self, NoProgress, RunOptions};

    fn walk() -> Motion {
        load_bytes("12_01.bvh", include_bytes!("../tests/fixtures/12_01.bvh"), &mut |_| {}).unwrap().motion
    }

    #[test]
    fn requests_round_trip_with_their_bytes_in_a_buffer() {
        let load = Request::Load { take: 3, name: "a b.bvh".into(), restore: true, bytes: b"HIERARCHY".to_vec() };
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

        let no_bytes =
            Packet { json: r#"{"type":"load","take":1,"name":"x","restore":false}"#.into(), buffers: vec![] };
        assert!(Request::from_packet(no_bytes).unwrap_err().contains("without the file's bytes"));
        let unknown = Packet { json: r#"{"type":"explode","take":1}"#.into(), buffers: vec![] };
        assert!(Request::from_packet(unknown).unwrap_err().contains("unknown variant `explode`"));
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
        let m = method::find("sssm").unwrap();
        let output =
            m.run_json(&motion, &serde_json::json!({}), &RunOptions { pictures: true }, &mut NoProgress).unwrap();
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
            },
            Response::Failed { take: 1, run: None, message: "x.bvh: line 3".into(), kind: FailureKind::Input },
            Response::ModelInUse {
                take: 2,
                run: 6,
                origin: "12 segments of a.bvh labelled in e.csv".into(),
                shipped: false,
            },
        ] {
            let packet = r.clone().into_packet();
            assert!(packet.buffers.is_empty());
            assert_eq!(Response::from_packet(packet).unwrap(), r);
        }
        let v: serde_json::Value = serde_json::from_str(&Response::Restored { take: 8 }.into_packet().json).unwrap();
        assert_eq!(v, serde_json::json!({"type": "restored", "take": 8}));
    }

    fn take_bytes() -> Vec<u8> {
        include_bytes!("../tests/fixtures/12_01.bvh").to_vec()
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

    #[test]
    fn the_worker_segments_only_the_take_a_request_names() {
        let mut w = WorkerState::default();
        let none = ask(&mut w, segment(1, 1));
        assert!(matches!(&none[..], [Response::Failed { kind: FailureKind::NotLoaded, run: Some(1), .. }]), "{none:?}");

        let load =
            ask(&mut w, Request::Load { take: 1, name: "12_01.bvh".into(), restore: false, bytes: take_bytes() });
        assert!(matches!(load.first(), Some(Response::Progress { take: 1, run: None, .. })));
        assert!(matches!(load.last(), Some(Response::Loaded { take: 1, .. })));
        assert_eq!(w.held(), Some(1));

        // a bad file (take 2) fails and leaves take 1 held
        let bad = ask(
            &mut w,
            Request::Load { take: 2, name: "bad.bvh".into(), restore: false, bytes: b"HIERARCHY\nROOT".to_vec() },
        );
        let Some(Response::Failed { take: 2, run: None, message, kind: FailureKind::Input }) = bad.last() else {
            panic!("{bad:?}")
        };
        assert!(message.starts_with("bad.bvh: line "), "{message}");
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
        let restored =
            ask(&mut w, Request::Load { take: 4, name: "12_01.bvh".into(), restore: true, bytes: take_bytes() });
        assert_eq!(restored.last(), Some(&Response::Restored { take: 4 }));
        let bad = ask(
            &mut w,
            Request::Segment { take: 4, run: 5, method: "sssm".into(), params: serde_json::json!({"radius": -1}) },
        );
        let Some(Response::Failed { kind: FailureKind::Input, message, .. }) = bad.last() else { panic!("{bad:?}") };
        assert!(message.contains("radius = -1"), "{message}");
        let unknown =
            ask(&mut w, Request::Segment { take: 4, run: 6, method: "nope".into(), params: serde_json::json!({}) });
        assert!(matches!(unknown.last(), Some(Response::Failed { kind: FailureKind::Input, .. })));
    }

    #[test]
    fn lma_families_travel_as_buffers_and_labels_as_text() {
        let train = Request::TrainLma { take: 2, run: 3, name: "e.csv".into(), labels: "file,start_frame\n".into() };
        let packet = train.clone().into_packet();
        assert!(packet.buffers.is_empty());
        assert_eq!(Request::from_packet(packet).unwrap(), train);
        assert_eq!(train.take(), 2);

        let family = r#"{"fps": 30.0, "factors": []}"#.to_string();
        let mine = Request::UseLmaModel { take: 2, run: 4, model: Some(family.clone()) };
        let packet = mine.clone().into_packet();
        assert_eq!(packet.buffers, vec![family.clone().into_bytes()]);
        assert!(!packet.json.contains("factors"), "the family travels as a buffer: {}", packet.json);
        assert_eq!(Request::from_packet(packet).unwrap(), mine);
        let shipped = Request::UseLmaModel { take: 2, run: 5, model: None };
        let packet = shipped.clone().into_packet();
        assert!(packet.buffers.is_empty(), "no buffer: the shipped family");
        assert_eq!(Request::from_packet(packet).unwrap(), shipped);
        let garbled =
            Packet { json: r#"{"type":"use_lma_model","take":2,"run":5}"#.into(), buffers: vec![vec![0xff, 0xfe]] };
        assert!(Request::from_packet(garbled).unwrap_err().contains("the LMA family is not UTF-8"));

        let report = vec![FactorSummary {
            factor: "space".into(),
            segments: [4, 5, 3],
            hidden: 3,
            train_error: 0.1,
            validation_error: 0.5,
            shifted_validation_error: 0.45,
        }];
        let trained = Response::Trained {
            take: 2,
            run: 3,
            model: family.clone(),
            report,
            origin: "12 segments".into(),
            used_rows: 12,
            ignored_rows: 1,
        };
        let packet = trained.clone().into_packet();
        assert_eq!(packet.buffers, vec![family.into_bytes()]);
        assert!(!packet.json.contains("factors"), "{}", packet.json);
        let v: serde_json::Value = serde_json::from_str(&packet.json).unwrap();
        assert_eq!((v["type"].as_str(), v["report"][0]["segments"][1].as_u64()), (Some("trained"), Some(5)));
        assert_eq!(Response::from_packet(packet.clone()).unwrap(), trained);
        let mut missing = packet;
        missing.buffers.clear();
        assert!(Response::from_packet(missing).unwrap_err().contains("no buffer for the trained family"));
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

    fn train(take: TakeId, run: RunId, labels: String) -> Request {
        Request::TrainLma { take, run, name: "mine.csv".into(), labels }
    }

    fn failure(posted: Vec<Response>) -> (FailureKind, String) {
        match posted.last() {
            Some(Response::Failed { kind, message, .. }) => (*kind, message.clone()),
            other => panic!("expected a failure, got {other:?}"),
        }
    }

    fn lma_summary(worker: &mut WorkerState, take: TakeId, run: RunId) -> String {
        let posted = ask(worker, Request::Segment { take, run, method: "lma".into(), params: serde_json::json!({}) });
        let Some(Response::Segmented { view, .. }) = posted.last() else { panic!("{:?}", posted.last()) };
        view.details.summary.clone()
    }

    /// The only test in this process that changes the LMA family in use (it is per process,
    /// as it is per worker in the browser).
    #[test]
    fn the_worker_trains_an_lma_family_on_the_rows_for_its_take_and_uses_it_until_told_otherwise() {
        let quick =
            crate::lma::network::TrainOptions { max_epochs: 40, learning_rate: 0.02, weight_decay: 1e-4, patience: 10 };
        let config = TrainConfig {
            restarts: 2,
            saliency_rounds: 4,
            options: quick,
            shift_options: crate::lma::network::TrainOptions { max_epochs: 3, ..quick },
            ..TrainConfig::default()
        };
        let mut w = WorkerState::with_training(config);
        let mine = format!("{HEADER}{}", label_rows("12_01.bvh", 12, 30, 120));
        assert_eq!(failure(ask(&mut w, train(1, 1, mine.clone()))).0, FailureKind::NotLoaded);
        ask(&mut w, Request::Load { take: 1, name: "12_01.bvh".into(), restore: false, bytes: take_bytes() });

        // what the user gets wrong is named: the line, the take and the files the rows name, too few rows
        let typo = mine.replacen("neutral", "nuetral", 1);
        let (kind, message) = failure(ask(&mut w, train(1, 2, typo)));
        assert_eq!(kind, FailureKind::Input);
        assert!(message.contains("mine.csv line 2") && message.contains("`nuetral`"), "{message}");
        let elsewhere = format!("{HEADER}{}{}", label_rows("35_01.bvh", 9, 20, 90), label_rows("nope", 1, 0, 50));
        let (kind, message) = failure(ask(&mut w, train(1, 3, elsewhere)));
        assert_eq!(kind, FailureKind::Input);
        assert!(message.contains("loaded take `12_01.bvh`") && message.contains("`35_01.bvh`, `nope`"), "{message}");
        let (_, message) = failure(ask(&mut w, train(1, 4, HEADER.to_string())));
        assert!(message.contains("no rows"), "{message}");
        let (_, message) = failure(ask(&mut w, train(1, 5, format!("{HEADER}{}", label_rows("12_01", 5, 30, 120)))));
        assert!(message.contains("too few to train on"), "{message}");
        let long =
            format!("{HEADER}{}12_01,400,600,neutral,neutral,neutral,neutral\n", label_rows("12_01", 9, 30, 120));
        let (_, message) = failure(ask(&mut w, train(1, 6, long)));
        assert!(message.contains("line 11") && message.contains("do not fit"), "{message}");
        assert!(!lma_summary(&mut w, 1, 7).contains("your classifiers"), "failed trainings leave the shipped family");

        // rows for the take (named in any case, with or without folder and extension) train the
        // family; the other file's rows are counted and left out
        let rows = label_rows("12_01.bvh", 12, 30, 120).replacen("12_01.bvh", "takes/12_01.BVH", 1).replacen(
            "12_01.bvh",
            "12_01",
            1,
        );
        let labels = format!("{HEADER}{rows}{}", label_rows("35_01.bvh", 3, 20, 90));
        let posted = ask(&mut w, train(1, 8, labels));
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
        let Some(Response::Trained { take: 1, run: 8, model, report, origin, used_rows: 12, ignored_rows: 3 }) =
            posted.last()
        else {
            panic!("{:?}", posted.last())
        };
        assert_eq!(report.iter().map(|r| r.factor.as_str()).collect::<Vec<_>>(), ["space", "time", "weight", "flow"]);
        for r in report {
            assert_eq!(r.segments.iter().sum::<usize>(), 12, "{r:?}");
            assert!((0.0..=1.0).contains(&r.validation_error) && r.hidden >= 1, "{r:?}");
        }
        assert_eq!(report[0].segments, [4, 4, 4]);
        assert_eq!(origin, "12 segments of 12_01.bvh labelled in mine.csv");
        let family = EffortModel::from_json(model).unwrap();
        assert_eq!((family.samples, &family.origin), (12, origin));
        let yours = format!(" · your classifiers ({origin})");
        assert!(lma_summary(&mut w, 1, 9).ends_with(&yours), "{}", lma_summary(&mut w, 1, 9));

        // a bad family file is refused with what is wrong, and the family in use stays
        let not_json = ask(&mut w, Request::UseLmaModel { take: 1, run: 10, model: Some("{\"fps\": 30".into()) });
        let (kind, message) = failure(not_json);
        assert!(kind == FailureKind::Input && message.contains("not an LMA effort model"), "{message}");
        let mut three: serde_json::Value = serde_json::from_str(model).unwrap();
        three["factors"].as_array_mut().unwrap().pop();
        let short = ask(&mut w, Request::UseLmaModel { take: 1, run: 11, model: Some(three.to_string()) });
        assert!(failure(short).1.contains("3 factors, expected 4"));
        assert!(lma_summary(&mut w, 1, 12).ends_with(&yours));

        // back to the shipped family, and the saved one again (whatever take the worker holds)
        let shipped = ask(&mut w, Request::UseLmaModel { take: 1, run: 13, model: None });
        let Some(Response::ModelInUse { shipped: true, origin: shipped_origin, .. }) = shipped.last() else {
            panic!("{shipped:?}")
        };
        assert!(shipped_origin.starts_with("stand-in labels"), "{shipped_origin}");
        assert!(!lma_summary(&mut w, 1, 14).contains("your classifiers"));
        let again = ask(&mut w, Request::UseLmaModel { take: 99, run: 15, model: Some(model.clone()) });
        assert_eq!(
            again.last(),
            Some(&Response::ModelInUse { take: 99, run: 15, origin: origin.clone(), shipped: false })
        );
        assert!(lma_summary(&mut w, 1, 16).ends_with(&yours));
        ask(&mut w, Request::UseLmaModel { take: 1, run: 17, model: None });
    }

    #[test]
    fn bounds_of_points() {
        let b = Bounds::of(&[Vec3::new(1.0, -2.0, 3.0), Vec3::new(-1.0, 5.0, 0.0)]);
        assert_eq!((b.min, b.max), ([-1.0, -2.0, 0.0], [1.0, 5.0, 3.0]));
        assert_eq!(Bounds::of(&[]).min, [-0.5; 3]);
    }
}
