//! One shape for every segmentation method, in the spirit of linfa's checked hyper-parameters:
//!
//! * a [`Method`] has `Params` with the paper's defaults (serde, every field optional in JSON),
//!   a [`Method::check`] that turns them into the method's checked form or a human message
//!   naming the parameter and the accepted range (lower *and* upper bounds), and
//!   [`Method::run`] from a [`Motion`] and checked parameters to a [`Segmentation`] plus the
//!   method's own [`Details`] (pictures, per-frame scores), reporting progress to a
//!   [`Progress`] sink that can also ask it to stop;
//! * the registry ([`crate::methods::registry`]) lists the methods. The command line (`segment
//!   --method NAME --param k=v`), the web worker (one generic "segment" request) and the page (one
//!   generic method panel) only ever go through it, as [`DynMethod`]: parameters as JSON in, the
//!   same output out;
//! * a supervised method also declares its training and models ([`supervised`]);
//! * every method declares the [`Work`] a run needs per working frame, and every run is checked
//!   against the [`WorkLimits`] before it starts ([`work`]);
//! * a method may also declare that it annotates *any* segmentation of a take with per-segment
//!   qualities ([`Method::annotator`], [`Method::annotate`]: LMA gives each segment its Laban
//!   Effort, the paper's semantic layer over segments): the worker's one generic "annotate" request
//!   and the page's Effort bars under every row go through that declaration, never a method's name.
//!
//! Adding a method is one folder under `src/methods/` (its paper's modules plus a `method.rs`
//! implementing [`Method`]) and one line in the registry. This module knows no method.

pub mod bounds;
pub mod cards;
pub mod form;
pub mod plot;
pub mod shipped;
pub mod spec;
pub mod stages;
pub mod supervised;
pub mod unsupervised;
pub mod work;

use std::any::Any;
use std::sync::Arc;

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

use crate::motion::Motion;
use crate::segment::{Effort, Segment, Segmentation};
pub use spec::{ParamKind, ParamSpec};
pub use stages::Stages;
pub use supervised::{FittingModel, ModelStore, Supervised, Supervision, TakeFitReport};
pub use work::{Work, WorkLimits};

/// The caller asked a running method to stop (the method returns as soon as it next reports).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Cancelled;

impl std::fmt::Display for Cancelled {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("cancelled")
    }
}

impl std::error::Error for Cancelled {}

/// Where a running method reports how far it got, and learns whether to stop.
pub trait Progress {
    /// The method is at `stage`, `fraction` (0..1) of the whole run done.
    fn report(&mut self, stage: &str, fraction: f64);
    /// True when the caller wants the run to stop; the method then returns [`MethodError::Cancelled`].
    fn cancelled(&self) -> bool {
        false
    }
    /// [`Progress::report`], then `Err(Cancelled)` if the run should stop.
    fn step(&mut self, stage: &str, fraction: f64) -> Result<(), Cancelled> {
        self.report(stage, fraction);
        if self.cancelled() {
            Err(Cancelled)
        } else {
            Ok(())
        }
    }
}

/// Asked by a long loop, with the share of it done, whether it goes on (false: stop — a run's cancel reaching
/// code below [`Progress`], such as a k-NN's search or the decoder).
pub type Go<'a> = &'a mut dyn FnMut(f64) -> bool;

/// A progress sink that ignores every report and never cancels.
pub struct NoProgress;

impl Progress for NoProgress {
    fn report(&mut self, _: &str, _: f64) {}
}

/// Any `FnMut(stage, fraction)` is a progress sink that never cancels.
impl<F: FnMut(&str, f64)> Progress for F {
    fn report(&mut self, stage: &str, fraction: f64) {
        self(stage, fraction)
    }
}

/// What can go wrong when a method is asked for or run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MethodError {
    #[error("unknown method `{name}`; available: {known}")]
    Unknown { name: String, known: String },
    /// A parameter is unknown, of the wrong type, or out of range; the message names it, and
    /// `param` is that parameter when it is one of the method's own (the page shows the message
    /// at its field, the command line names it): carried, never searched for in the text.
    #[error("{message}")]
    Params { param: Option<String>, message: String },
    /// The take cannot be segmented (too short, missing joints, too large, …).
    #[error("{0}")]
    Failed(String),
    #[error("cancelled")]
    Cancelled,
    /// The method needs a shipped model file this process does not hold yet (only on the page,
    /// which fetches it and asks again: [`shipped`]).
    #[error("the model file `{file}` is not loaded yet")]
    NeedsModel { file: String },
}

impl MethodError {
    /// The refusal of the method's parameter `param`.
    pub fn param(param: &str, message: impl Into<String>) -> MethodError {
        MethodError::Params { param: Some(param.to_string()), message: message.into() }
    }

    /// A refusal of the parameters as a whole (none of the method's own is to blame: an unknown
    /// name, a malformed override).
    pub fn params(message: impl Into<String>) -> MethodError {
        MethodError::Params { param: None, message: message.into() }
    }

    /// The parameter a refusal names, if any.
    pub fn param_name(&self) -> Option<&str> {
        match self {
            MethodError::Params { param, .. } => param.as_deref(),
            _ => None,
        }
    }
}

impl From<Cancelled> for MethodError {
    fn from(_: Cancelled) -> Self {
        MethodError::Cancelled
    }
}

/// Who a method is, for the command line's help and the page's panel.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MethodInfo {
    /// The name used on the command line, in files and in the protocol (`sssm`).
    pub name: String,
    /// Short name shown in messages and headings (`SSSM`).
    pub short: String,
    /// The paper, as cited in headings (`Krüger et al. 2017`).
    pub paper: String,
    /// One sentence on what the method finds.
    pub summary: String,
    /// The page runs it by itself after each load (with the form's parameters).
    pub auto_run: bool,
}

/// A picture a method draws of its work (the SSSM image, a score map), RGBA row-major.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Picture {
    /// Unique within the method (the page's element id is `<method>-<id>`).
    pub id: String,
    pub title: String,
    /// How to read it (axes, colours).
    pub caption: String,
    pub width: usize,
    pub height: usize,
    /// `width × height × 4` bytes; moved as a transferred buffer, not in the JSON.
    #[serde(skip)]
    pub rgba: Vec<u8>,
    /// For a picture of frame pairs (both axes the take's time, first frame top left, as the
    /// SSSM): how many of the file's frames one pixel spans, so that the page can turn a click
    /// into the pair of frames (pixel `p` starts at frame `⌊p × frames_per_pixel⌋`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frames_per_pixel: Option<f64>,
}

impl Picture {
    /// The file frame pixel `p` of a frame-pair picture starts at (`None` for other pictures),
    /// clamped to the take's `frames`.
    pub fn frame_at(&self, p: usize, frames: usize) -> Option<usize> {
        let per = self.frames_per_pixel.filter(|f| f.is_finite() && *f > 0.0)?;
        Some(((p as f64 * per).floor() as usize).min(frames.saturating_sub(1)))
    }

    /// The picture as a PNG file (what the page's "PNG" button under each picture saves).
    pub fn to_png(&self) -> Result<Vec<u8>, crate::image::ImageError> {
        crate::image::rgba_png(self.width, self.height, &self.rgba)
    }
}

/// A per-frame score (confidence, effort value, …) at the file's frame rate.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Curve {
    pub id: String,
    pub title: String,
    /// One value per file frame.
    pub values: Vec<f32>,
}

/// What a method shows besides its segments.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Details {
    /// One line that sums the result up ("5 actions · 3 transitions · …").
    pub summary: String,
    pub pictures: Vec<Picture>,
    pub curves: Vec<Curve>,
    /// A labelling run's verdict on whether its model fits the take (`None`: no fit check — the
    /// method has no models, or the check was off; left out of the JSON then, and old results
    /// without it load as `None`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub take_fit: Option<supervised::TakeFitReport>,
}

/// How a run should go besides its parameters.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RunOptions {
    /// Draw the method's pictures (the page wants them; a batch on the command line does not).
    pub pictures: bool,
    /// What the run may take ([`work`]): the page's and the command line's are the defaults; the
    /// fuzzer's are small.
    pub limits: WorkLimits,
}

/// What a method that annotates segments declares ([`Method::annotator`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Annotator {
    /// What it gives each segment, as the page names it ("Effort").
    pub quality: String,
    /// The parameters of the method an annotation reads (LMA: `model`, the classifier family);
    /// the others are its segmentation's. The page sends these, from the method's form.
    pub params: Vec<String>,
}

/// One segment's annotation: its Effort, or why it has none.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Annotated {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub effort: Option<Effort>,
    /// Why there is no Effort (a segment too short to read), when there is none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub why: Option<String>,
}

/// The annotations of a segmentation's segments, in the order asked.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Annotations {
    pub segments: Vec<Annotated>,
    /// The segment lengths (seconds, shortest and longest) the annotator learnt from: what a
    /// segment outside them gets is an extrapolation.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub learnt_s: Option<[f64; 2]>,
    /// Who annotated, for a legend ("LMA, shipped family").
    pub by: String,
}

/// A method's result on one take.
#[derive(Debug, Clone, PartialEq)]
pub struct MethodOutput {
    /// At the file's frame rate, parameters echoed in `params`.
    pub segmentation: Segmentation,
    pub details: Details,
}

/// A segmentation method, typed (see the module documentation).
pub trait Method: Send + Sync + 'static {
    /// The parameters with the paper's defaults; JSON fields are all optional.
    type Params: Serialize + DeserializeOwned + Default + Clone + Send + Sync + 'static;
    /// The parameters after [`Method::check`]: the method only ever runs on these.
    type Checked: Send + Sync + 'static;

    fn info(&self) -> MethodInfo;
    /// Every parameter with its help, bounds and default.
    fn param_specs(&self) -> Vec<ParamSpec>;
    /// Validates `params`; the message of a refusal names the parameter and what is accepted.
    fn check(&self, params: Self::Params) -> Result<Self::Checked, MethodError>;
    /// [`Method::check`] where the parameters may name a model of `models` (a supervised
    /// method's `model`); the others ignore the store.
    fn check_in(&self, params: Self::Params, models: &ModelStore) -> Result<Self::Checked, MethodError> {
        let _ = models;
        self.check(params)
    }
    /// What a supervised method declares about its training and models (`None`: unsupervised).
    fn supervision(&self) -> Option<Supervision> {
        None
    }
    /// Training and model files, for a method that declares [`Method::supervision`].
    fn supervised(&self) -> Option<&dyn Supervised> {
        None
    }
    /// The checked parameters as they are echoed in a segmentation's `params`.
    fn echo(&self, params: &Self::Checked) -> serde_json::Value;
    /// What a run with `params` needs per working frame: checked against [`WorkLimits`] before
    /// [`Method::run`] is called ([`crate::method::work`]), so `run` never starts on a take it cannot hold.
    fn work(&self, params: &Self::Checked) -> Work;
    /// Segments `motion`; draws the method's pictures only if `options.pictures`.
    fn run(
        &self,
        motion: &Motion,
        params: &Self::Checked,
        options: &RunOptions,
        progress: &mut dyn Progress,
    ) -> Result<MethodOutput, MethodError>;
    /// What annotating `segments` of `motion` with `params` holds ([`Method::annotate`]): checked against the same
    /// limits as a run before the annotation starts. The run's own work unless the method says otherwise.
    fn annotation_work(&self, params: &Self::Checked, motion: &Motion, segments: &[Segment]) -> Work {
        let _ = (motion, segments);
        self.work(params)
    }
    /// Whether the method annotates any segmentation of a take with per-segment qualities
    /// ([`Method::annotate`]), and what that reads (`None`: it does not).
    fn annotator(&self) -> Option<Annotator> {
        None
    }
    /// The annotation of each of `segments` (file frames of `motion`, inclusive), in order, for a
    /// method that declares [`Method::annotator`]; reports progress and stops when asked.
    fn annotate(
        &self,
        motion: &Motion,
        params: &Self::Checked,
        segments: &[Segment],
        progress: &mut dyn Progress,
    ) -> Result<Annotations, MethodError> {
        let _ = (motion, params, segments, progress);
        Err(MethodError::Failed(format!("{} does not annotate segments", self.info().short)))
    }
}

/// Checked parameters of some method (from [`DynMethod::check_json`]); check once, run on many takes.
#[derive(Clone)]
pub struct CheckedParams {
    method: String,
    echo: serde_json::Value,
    inner: Arc<dyn Any + Send + Sync>,
}

impl CheckedParams {
    /// Every parameter's value (defaults filled in), as echoed in the output.
    pub fn echo(&self) -> &serde_json::Value {
        &self.echo
    }
}

impl std::fmt::Debug for CheckedParams {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "CheckedParams({} {})", self.method, self.echo)
    }
}

/// A method behind the registry: parameters as JSON.
pub trait DynMethod: Send + Sync {
    fn info(&self) -> MethodInfo;
    fn param_specs(&self) -> Vec<ParamSpec>;
    /// The default parameters as a JSON object.
    fn defaults(&self) -> serde_json::Value;
    /// Reads `params` (a JSON object; missing fields take their defaults, unknown ones are
    /// refused) and checks them.
    fn check_json(&self, params: &serde_json::Value) -> Result<CheckedParams, MethodError> {
        self.check_json_in(params, &ModelStore::default())
    }
    /// [`DynMethod::check_json`] where a `model` parameter may name a model of `models`.
    fn check_json_in(&self, params: &serde_json::Value, models: &ModelStore) -> Result<CheckedParams, MethodError>;
    /// What a supervised method declares (`None`: unsupervised).
    fn supervision(&self) -> Option<Supervision>;
    /// Its training and model files, when it is supervised.
    fn supervised(&self) -> Option<&dyn Supervised>;
    /// What a run with `params` (from [`DynMethod::check_json`] of this method) needs.
    fn work(&self, params: &CheckedParams) -> Result<Work, MethodError>;
    /// What annotating `segments` of `motion` with `params` needs ([`Method::annotation_work`]).
    fn annotation_work(
        &self,
        params: &CheckedParams,
        motion: &Motion,
        segments: &[Segment],
    ) -> Result<Work, MethodError>;
    /// Runs on `motion` with parameters from [`DynMethod::check_json`] of this method.
    fn run_checked(
        &self,
        motion: &Motion,
        params: &CheckedParams,
        options: &RunOptions,
        progress: &mut dyn Progress,
    ) -> Result<MethodOutput, MethodError>;
    /// What the method declares about annotating segments (`None`: it does not).
    fn annotator(&self) -> Option<Annotator>;
    /// Annotates `segments` of `motion` with parameters from [`DynMethod::check_json`] of this
    /// method (its [`Annotator::params`] are the ones read), after checking what it will hold
    /// ([`Method::annotation_work`]) against `limits`, as a run is.
    fn annotate_checked(
        &self,
        motion: &Motion,
        params: &CheckedParams,
        segments: &[Segment],
        limits: &WorkLimits,
        progress: &mut dyn Progress,
    ) -> Result<Annotations, MethodError>;
    /// [`DynMethod::check_json`] then [`DynMethod::run_checked`].
    fn run_json(
        &self,
        motion: &Motion,
        params: &serde_json::Value,
        options: &RunOptions,
        progress: &mut dyn Progress,
    ) -> Result<MethodOutput, MethodError> {
        let checked = self.check_json(params)?;
        self.run_checked(motion, &checked, options, progress)
    }
}

impl<M: Method> DynMethod for M {
    fn info(&self) -> MethodInfo {
        Method::info(self)
    }

    fn param_specs(&self) -> Vec<ParamSpec> {
        Method::param_specs(self)
    }

    fn defaults(&self) -> serde_json::Value {
        serde_json::to_value(M::Params::default()).unwrap_or(serde_json::Value::Null)
    }

    fn supervision(&self) -> Option<Supervision> {
        Method::supervision(self)
    }

    fn supervised(&self) -> Option<&dyn Supervised> {
        Method::supervised(self)
    }

    fn check_json_in(&self, params: &serde_json::Value, models: &ModelStore) -> Result<CheckedParams, MethodError> {
        let info = Method::info(self);
        let params = if params.is_null() { serde_json::json!({}) } else { params.clone() };
        let typed: M::Params =
            serde_json::from_value(params.clone()).map_err(|e| misread::<M::Params>(&info.short, &params, e))?;
        let checked = self.check_in(typed, models)?;
        Ok(CheckedParams { method: info.name, echo: self.echo(&checked), inner: Arc::new(checked) })
    }

    fn work(&self, params: &CheckedParams) -> Result<Work, MethodError> {
        Ok(Method::work(self, self.downcast(params)?))
    }

    fn annotation_work(
        &self,
        params: &CheckedParams,
        motion: &Motion,
        segments: &[Segment],
    ) -> Result<Work, MethodError> {
        Ok(Method::annotation_work(self, self.downcast(params)?, motion, segments))
    }

    fn annotator(&self) -> Option<Annotator> {
        Method::annotator(self)
    }

    fn annotate_checked(
        &self,
        motion: &Motion,
        params: &CheckedParams,
        segments: &[Segment],
        limits: &WorkLimits,
        progress: &mut dyn Progress,
    ) -> Result<Annotations, MethodError> {
        let checked = self.downcast(params)?;
        if progress.cancelled() {
            return Err(MethodError::Cancelled);
        }
        let last = motion.frames().saturating_sub(1);
        if let Some((i, s)) = segments.iter().enumerate().find(|(_, s)| s.start > s.end || s.end > last) {
            return Err(MethodError::Failed(format!(
                "segment {} (frames {}–{}) is not inside {} (frames 0–{last})",
                i + 1,
                s.start,
                s.end,
                motion.name
            )));
        }
        Method::annotation_work(self, checked, motion, segments).check(&Method::info(self).short, motion, limits)?;
        Method::annotate(self, motion, checked, segments, progress)
    }

    fn run_checked(
        &self,
        motion: &Motion,
        params: &CheckedParams,
        options: &RunOptions,
        progress: &mut dyn Progress,
    ) -> Result<MethodOutput, MethodError> {
        let checked = self.downcast(params)?;
        if progress.cancelled() {
            return Err(MethodError::Cancelled);
        }
        Method::work(self, checked).check(&Method::info(self).short, motion, &options.limits)?;
        self.run(motion, checked, options, progress)
    }
}

/// A registered method's own checked parameters.
trait Downcast: Method {
    fn downcast<'p>(&self, params: &'p CheckedParams) -> Result<&'p Self::Checked, MethodError> {
        params.inner.downcast_ref::<Self::Checked>().ok_or_else(|| {
            MethodError::params(format!("parameters of `{}` given to `{}`", params.method, Method::info(self).name))
        })
    }
}

impl<M: Method> Downcast for M {}

/// Why `params` could not be read as `P`, naming the parameter whose value is of the wrong kind
/// (serde's own message names no field); unknown fields keep serde's message, which lists the
/// known ones.
fn misread<P: DeserializeOwned>(short: &str, params: &serde_json::Value, e: serde_json::Error) -> MethodError {
    let culprit = params.as_object().and_then(|fields| {
        fields.iter().find_map(|(name, value)| {
            let alone = serde_json::json!({ name.clone(): value.clone() });
            serde_json::from_value::<P>(alone).err().map(|e| (name, value, e))
        })
    });
    match culprit {
        Some((name, value, e)) if !e.to_string().starts_with("unknown field") => {
            MethodError::param(name, format!("invalid {short} parameter {name} = {value}: {e}"))
        }
        _ => MethodError::params(format!("{short} parameters: {e}")),
    }
}

/// `n` and the English noun `word` in its number, as summaries print counts: "1 action",
/// Whether a checked run's parameters (`echo`) are a method's `defaults`: equal, except that a
/// `null` default — the method decides, as a labeller's threshold is its model's own — stands for
/// whatever value the echo names in its place (never `null`: the run says what it decided).
pub fn echoes_defaults(echo: &serde_json::Value, defaults: &serde_json::Value) -> bool {
    let (Some(e), Some(d)) = (echo.as_object(), defaults.as_object()) else { return echo == defaults };
    e.len() == d.len()
        && d.iter().all(|(name, default)| {
            e.get(name).is_some_and(|v| if default.is_null() { !v.is_null() } else { v == default })
        })
}

/// "3 actions", "1 boundary", "2 boundaries", "1 class", "4 classes".
pub fn counted(n: usize, word: &str) -> String {
    if n == 1 {
        return format!("1 {word}");
    }
    let consonant_y = word.ends_with('y') && !word.ends_with(['a', 'e', 'i', 'o', 'u']) && {
        let before = word.chars().rev().nth(1);
        before.is_some_and(|c| !"aeiou".contains(c))
    };
    if consonant_y {
        format!("{n} {}ies", &word[..word.len() - 1])
    } else if word.ends_with("s") || word.ends_with("sh") || word.ends_with("ch") || word.ends_with('x') {
        format!("{n} {word}es")
    } else {
        format!("{n} {word}s")
    }
}

/// Applies `NAME=VALUE` overrides (values as JSON; anything that is not JSON is a string) to
/// the defaults of `method`, naming the known parameters when one is unknown.
pub fn params_from_overrides(method: &dyn DynMethod, overrides: &[String]) -> Result<serde_json::Value, MethodError> {
    let info = method.info();
    let mut params = serde_json::Map::new();
    let specs = method.param_specs();
    for o in overrides {
        let (name, raw) =
            o.split_once('=').ok_or_else(|| MethodError::params(format!("`{o}`: expected NAME=VALUE")))?;
        let name = name.trim().replace('-', "_");
        if !specs.iter().any(|s| s.name == name) {
            let known: Vec<&str> = specs.iter().map(|s| s.name.as_str()).collect();
            return Err(MethodError::params(format!(
                "unknown {} parameter `{name}`; known: {}",
                info.short,
                known.join(", ")
            )));
        }
        let value =
            serde_json::from_str(raw.trim()).unwrap_or_else(|_| serde_json::Value::String(raw.trim().to_string()));
        params.insert(name, value);
    }
    Ok(serde_json::Value::Object(params))
}

#[cfg(test)]
mod tests {
    #[test]
    fn counts_are_in_the_noun_s_number() {
        use super::counted;
        assert_eq!(counted(1, "action"), "1 action");
        assert_eq!(counted(0, "action"), "0 actions");
        assert_eq!(counted(2, "boundary"), "2 boundaries");
        assert_eq!(counted(1, "boundary"), "1 boundary");
        assert_eq!(counted(3, "class"), "3 classes");
        assert_eq!(counted(5, "day"), "5 days");
        assert_eq!(counted(7, "search"), "7 searches");
    }

    use super::*;

    use crate::methods::{find, registry};

    #[test]
    fn names_are_unique_and_found_case_insensitively() {
        let names: Vec<String> = registry().iter().map(|m| m.info().name).collect();
        let mut sorted = names.clone();
        sorted.sort();
        sorted.dedup();
        assert_eq!(sorted.len(), names.len(), "{names:?}");
        assert_eq!(find("SSSM").unwrap().info().name, "sssm");
        let err = find("nope").err().unwrap().to_string();
        assert!(err.contains("unknown method `nope`") && err.contains("sssm"), "{err}");
    }

    #[test]
    fn overrides_are_json_and_unknown_names_list_the_known_ones() {
        let m = find("sssm").unwrap();
        let p = params_from_overrides(m, &["radius=17".into(), "boundary-rule=paper".into()]).unwrap();
        assert_eq!(p["radius"], 17);
        assert_eq!(p["boundary_rule"], "paper");
        let err = params_from_overrides(m, &["no_such=1".into()]).unwrap_err().to_string();
        assert!(err.contains("unknown SSSM parameter `no_such`") && err.contains("radius"), "{err}");
        assert!(params_from_overrides(m, &["radius".into()]).is_err());
    }
}
