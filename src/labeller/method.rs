//! The labelling method both labellers are behind the common [`Method`] interface, parameterised by the [`Kind`]
//! each method gives (DT-FCN's in `methods/dtfcn/method.rs`, the k-NN's in `methods/knn/method.rs`; the registry
//! puts each together with the kinds it may meet): a model (shipped, or one the user trained or loaded) labels every
//! frame; runs of equal labels are the segments, each scored by its mean confidence; frames whose confidence is
//! below the threshold are labelled `unknown`. Pictures: the class probabilities over time, as the paper's figures draw
//! them. Curve: the confidence of every frame.

use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::decode::{file_labels_going, Decoding};
use super::model::{Labeller, Model, ModelHeader};
use super::probabilities::Probabilities;
use super::shipped;
use crate::method::supervised::{Loaded, Training, TrainingAsk, IN_SAMPLE};
use crate::method::{
    Curve, Details, FittingModel, Method, MethodError, MethodInfo, MethodOutput, ModelStore, ParamKind, ParamSpec,
    Picture, Progress, RunOptions, Supervised, Supervision, Work,
};
use crate::motion::Motion;
use crate::segment::frames::WorkingFrames;
use crate::segment::{Level, Segment, Segmentation, UNKNOWN};

/// Parameters of both labelling methods.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LabelParams {
    /// A shipped model's name, or the name a user model was installed under.
    pub model: String,
    /// Frames whose confidence is below this are `unknown` (0 = never); with a decoding, whole runs.
    /// `None` (the default): the model's own, its header's `unknown_threshold`.
    pub unknown_threshold: Option<f64>,
    /// The open-set unknown ([`super::openset`]): a labelled frame whose window lies farther than this from its
    /// class's training windows (over the class's own repeat distance, over the take's median of the same) is
    /// `unknown` (0: never). `None` (the default): the model's own, its header's `open_set` (none: never).
    pub unknown_ratio: Option<f64>,
    /// `model` (the decoding the model was made with — raw per-frame labels if none), `raw`, or `custom`
    /// (`min_duration_s` and `switch_cost`).
    pub decoding: String,
    /// With `decoding = "custom"`: shortest run of one label, in seconds ([`super::decode`]).
    pub min_duration_s: f64,
    /// With `decoding = "custom"`: cost of a change of label, in nats of summed log-probability.
    pub switch_cost: f64,
    /// Measure whether the take fits the model ([`super::fit`]) and, when it does not, label its
    /// unfamiliar frames unknown.
    pub fit_check: bool,
    /// With the fit check, on a take the model does not fit: also measure the method's other models
    /// against the take and name those that fit ([`Labelling::fitting_models`]). Off by default: each
    /// costs a search of its training windows, asked for only when the user wants another model.
    pub fit_others: bool,
}

/// The ways a run may decode its labels.
pub const DECODINGS: [&str; 3] = ["model", "raw", "custom"];

/// The unknown threshold a model is made with (its header's, in force unless a run asks otherwise): what every
/// fold of the scoreboard's nested validation chose for the k-NN, with the decoding (`make accuracy`,
/// docs/methods/dtfcn.md).
pub const DEFAULT_THRESHOLD: f64 = 0.5;

/// The warning a run on one of `header`'s own training takes carries: its scores there are not
/// what the model does on a take it has not seen.
pub fn in_sample_note(header: &ModelHeader, take: &str) -> Option<String> {
    let trained = header.provenance.takes.iter().find(|t| crate::labels::same_file(t, take))?;
    Some(format!(
        "{IN_SAMPLE} model `{}` was trained on this take ({trained}), so its labels and scores here are not what it \
         does on a take it has not seen (held-out scores: docs/accuracy.md)",
        header.name
    ))
}

/// The custom decoding's defaults (what most folds chose: a 2 s minimum run).
pub const CUSTOM_DECODING: Decoding = Decoding { min_duration_s: 2.0, switch_cost: 0.0 };

pub use super::decode::{MAX_MIN_DURATION_S, MAX_SWITCH_COST};

impl Default for LabelParams {
    fn default() -> Self {
        LabelParams {
            model: shipped::NAMES[0].into(),
            unknown_threshold: None,
            unknown_ratio: None,
            decoding: DECODINGS[0].into(),
            min_duration_s: CUSTOM_DECODING.min_duration_s,
            switch_cost: CUSTOM_DECODING.switch_cost,
            fit_check: true,
            fit_others: false,
        }
    }
}

/// Checked parameters: the model itself and the threshold in force.
pub struct Checked {
    /// As asked for (a shipped name, or the name a user model was installed under).
    name: String,
    model: Arc<Model>,
    threshold: f64,
    /// The open-set ratio in force (`None`: never) and the model whose windows measure it (a k-NN: the model
    /// itself; `None`: no such model, so no open-set unknown).
    ratio: Option<f64>,
    open_windows: Option<Arc<Model>>,
    /// As asked (`model`, `raw`, `custom`) and the custom setting, echoed as given.
    asked: String,
    custom: Decoding,
    /// The decoding in force.
    decoding: Decoding,
    /// With the fit check: the k-NN model of the model's own data, whose windows measure poses
    /// (the model itself for a k-NN; `None`: no such model, travel only).
    fit: Option<FitCheck>,
}

/// What a run measures the take's fit with.
struct FitCheck {
    windows: Option<Arc<Model>>,
    /// The models the run could name instead (the user's of this kind), measured against the take
    /// only when it does not fit the chosen one and `others` asks for it ([`Labelling::fitting_models`]).
    models: ModelStore,
    /// The run's `fit_others`.
    others: bool,
}

impl Labelling {
    /// The model whose windows measure a take's poses for `model` ([`super::fit`]): `model` itself when its labeller
    /// holds windows (a k-NN), else the model of the same name and the same data (the same data hash) of the kind
    /// whose models hold them — the user's, or the shipped one. On the page a shipped one is
    /// [`MethodError::NeedsModel`] until its file arrived.
    fn fit_windows(
        &self,
        model: &Arc<Model>,
        name: &str,
        models: &ModelStore,
    ) -> Result<Option<Arc<Model>>, MethodError> {
        if model.labeller.windows().is_some() {
            return Ok(Some(model.clone()));
        }
        let Some(kind) = self.windows_kind() else { return Ok(None) };
        let same = |m: &Arc<Model>| m.header.provenance.data_hash == model.header.provenance.data_hash;
        if let Some(m) = models.get::<Model>(kind.name(), name).filter(same) {
            return Ok(Some(m));
        }
        if shipped::NAMES.contains(&name) && models.get::<Model>(self.kind.name(), name).is_none() {
            return Ok(Some(shipped::model(kind, name, models, self.kinds)?).filter(same));
        }
        Ok(None)
    }

    /// The kind among those this method meets whose models hold the windows a take's fit is measured against.
    fn windows_kind(&self) -> Option<&'static dyn Kind> {
        self.kinds.iter().copied().find(|k| k.has_windows())
    }
}

/// The windows of a fit check's windows model.
fn windows_of(model: Option<&Model>) -> Option<&dyn super::fit::Windows> {
    model.and_then(|m| m.labeller.windows())
}

/// What labelling a take with `model` holds besides the `base` bytes a working frame of its method: computed from
/// the model, so that a model file cannot ask for more than its run declares ([`crate::method::work`] checks it
/// before the run starts). Per class and working frame: each network's probabilities (an ensemble keeps all of them
/// until it averages them), their mean or the k-NN's votes, the decoded copy and the decoding's back-pointers
/// (a u16 and a flag); besides, whatever the length: the decoding's two score rows (classes × its minimum run in
/// frames, [`super::decode::viterbi`]) and what the labeller holds whatever the length ([`Labeller::fixed_bytes`]:
/// one block of a network's inference), 4 MiB for the rest.
///
/// Its time too, in multiply-adds a working frame: the labeller's ([`Labeller::ops_per_frame`]: the k-NN's window
/// projected and its training frames scanned, the networks' convolutions), the decoding's (classes × its minimum run,
/// [`Decoding::ops_per_frame`]) and, when the take's fit is measured (`fit`: the model whose windows measure it), that
/// search's, with its familiar distances besides.
pub fn model_work(model: &Model, decoding: &Decoding, base: usize, fit: Option<&Model>) -> Work {
    let classes = model.header.classes.len();
    let (members, block) = (model.labeller.members(), model.labeller.fixed_bytes());
    let per_class = 4 * (members + 2) + 3;
    let scores = 2 * 4 * classes * decoding.min_frames(model.header.fps);
    let (fit_ops, familiar_ops) = windows_of(fit).map_or((0.0, 0.0), |w| w.search_ops());
    Work {
        fps: model.header.fps,
        bytes_per_frame: base + per_class * classes,
        fixed_bytes: (4 << 20) + scores + block,
        advice: "",
        ops_per_frame: model.labeller.ops_per_frame(classes)
            + decoding.ops_per_frame(classes, model.header.fps)
            + fit_ops,
        fixed_ops: familiar_ops,
    }
}

impl Labelling {
    /// The models of this method other than `chosen` whose classes fit `motion`, best first
    /// ([`super::fit::rank_fitting`]): the shipped ones and the user's (`models`). Only their fit is
    /// measured, never their labels: a shipped model by its k-NN file of the same name (the same
    /// data as its DT-FCN file: its travel and its windows, a fraction of the network's size), a
    /// user's by its own travel and the k-NN windows of its data ([`fit_windows`]). A model nothing
    /// can be measured of is not offered, nor one whose file the page could not get (damaged, or
    /// not served: [`crate::method::shipped::refuse`]). On the page a shipped k-NN file not held
    /// yet is [`MethodError::NeedsModel`] (fetched once, then the run is asked again).
    ///
    /// Their searches share `ops` multiply-adds (what the run's budget leaves after its own work): a model whose
    /// search would pass what is left is not measured (a kept file with a window or training set that wide would
    /// otherwise cost every take it is measured against minutes).
    fn fitting_models(
        &self,
        motion: &Motion,
        chosen: &str,
        models: &ModelStore,
        mut ops: f64,
        progress: &mut dyn Progress,
    ) -> Result<Vec<FittingModel>, MethodError> {
        let windows = self.windows_kind();
        let mut names: Vec<String> = shipped::NAMES.iter().map(|n| n.to_string()).collect();
        for name in models.names(self.kind.name()) {
            if !names.contains(&name) {
                names.push(name);
            }
        }
        let mut fitting = Vec::new();
        for name in names.iter().filter(|n| n.as_str() != chosen) {
            let found = match (models.get::<Model>(self.kind.name(), name), windows) {
                (Some(model), _) => self.fit_windows(&model, name, models).map(|w| (model.header.travel, w)),
                (None, Some(kind)) => {
                    shipped::model(kind, name, models, self.kinds).map(|knn| (knn.header.travel, Some(knn)))
                }
                (None, None) => continue,
            };
            let (travel, windows) = match found {
                Ok(found) => found,
                // on the page: fetched, then the run is asked again
                Err(e @ MethodError::NeedsModel { .. }) => return Err(e),
                // a file the page could not get (damaged, not served): that model is not offered,
                // the run goes on (a run that needs it as its own model says why)
                Err(_) => continue,
            };
            let search = windows_of(windows.as_deref());
            if let Some(w) = search {
                let (per_frame, fixed) = w.search_ops();
                let frames = Work::at(super::input::NETWORK_FPS).frames(motion);
                let cost = frames as f64 * per_frame + fixed;
                if cost > ops {
                    continue;
                }
                ops -= cost;
            }
            let fit = super::fit::TakeFit::assess_going(motion, travel.as_ref(), search, &mut |_| {
                progress.step("take fit", 0.05).is_ok()
            })
            .map_err(MethodError::Failed)?
            .ok_or(MethodError::Cancelled)?;
            if fit.measured() && fit.fits() {
                fitting.push(FittingModel {
                    name: name.clone(),
                    travel_share: fit.travel_share,
                    pose_ratio: fit.pose_ratio,
                });
            }
        }
        Ok(super::fit::rank_fitting(fitting))
    }
}

impl Labelling {
    /// The model of this method called `name`: one of `models` (a user's, trained or loaded) first, else a
    /// shipped one (on the page, [`MethodError::NeedsModel`] until its file was fetched).
    pub fn resolve(&self, name: &str, models: &ModelStore) -> Result<Arc<Model>, MethodError> {
        if let Some(m) = models.get::<Model>(self.kind.name(), name) {
            return Ok(m);
        }
        shipped::model(self.kind, name, models, self.kinds)
    }
}

impl Supervised for Labelling {
    fn read_model(&self, file: &str, bytes: &[u8]) -> Result<Loaded, MethodError> {
        super::supervised::read_model(self.kind, self.kinds, file, bytes)
    }

    fn start_training(&self, ask: TrainingAsk, progress: &mut dyn Progress) -> Result<Box<dyn Training>, MethodError> {
        self.kind.start_training(self.kinds, ask, progress)
    }

    fn training_work(&self, options: &serde_json::Value) -> Result<crate::method::Work, MethodError> {
        self.kind.training_work(options)
    }

    fn shipped_model(&self, name: &str, models: &ModelStore) -> Result<Loaded, MethodError> {
        let model = shipped::model(self.kind, name, models, self.kinds)?;
        Ok(Loaded { info: super::supervised::model_info(self.kind, name, &model), model })
    }

    fn model_details(&self, model: &Loaded) -> serde_json::Value {
        let model = model.model.downcast_ref::<Model>();
        model.map_or(serde_json::Value::Null, |m| super::supervised::header_json(self.kind, m))
    }
}

/// What a labelling method gives the common labelling: its name and words, its model files' own header fields and
/// payload, what a run of it holds, and its training. Each labeller's method implements it; the registry puts it
/// into a [`Labelling`].
pub trait Kind: Sync {
    /// The method's name, the `kind` of its models' headers (`dtfcn`).
    fn name(&self) -> &'static str;
    /// Its name as headings show it (`DT-FCN`).
    fn short(&self) -> &'static str;
    fn info(&self) -> MethodInfo;
    /// The rows of the motion image its models read, by name (the header's `joints`).
    fn joint_names(&self) -> Vec<String>;
    /// The rows a model with `header` must have been trained on: [`Kind::joint_names`], unless the method's own
    /// fields choose its input (the k-NN's `input`).
    fn header_joints(&self, header: &ModelHeader) -> Vec<String> {
        let _ = header;
        self.joint_names()
    }
    /// What its own fields of `header` must say, beyond what every model's header must
    /// ([`super::model::check_header`]).
    fn check_header(&self, header: &ModelHeader) -> Result<(), String>;
    /// Its labeller from a model file's payload; its own fields of `header` (and the training's options) put in the
    /// one form it writes them.
    fn read(&self, header: &mut ModelHeader, payload: &[u8]) -> Result<Box<dyn Labeller>, String>;
    /// Whether its models hold the training windows a take's fit is measured against ([`super::fit::Windows`]).
    fn has_windows(&self) -> bool {
        false
    }
    /// Bytes a working frame of a run holds besides the class arrays (`windows`: the fit check measures the take's
    /// poses with a windows model).
    fn frame_bytes(&self, windows: bool) -> usize;
    /// What one step of its training is called (`epoch`).
    fn step_name(&self) -> &'static str;
    /// Whether it trains on the labels the user draws on the take.
    fn trains_on_my_labels(&self) -> bool;
    /// Whether its models record the epochs they were trained for.
    fn has_epochs(&self) -> bool;
    /// Its training options' table ([`crate::method::supervised::TrainingOption`]).
    fn training_specs(&self) -> Vec<ParamSpec>;
    /// Starts a training on `ask` (`kinds`: the kinds of model file it may be asked to continue from).
    fn start_training(
        &self,
        kinds: &[&'static dyn Kind],
        ask: TrainingAsk,
        progress: &mut dyn Progress,
    ) -> Result<Box<dyn Training>, MethodError>;
    /// What its training with `options` holds per working frame ([`Supervised::training_work`]).
    fn training_work(&self, options: &serde_json::Value) -> Result<crate::method::Work, MethodError>;
    /// What `mocapseg model-info` adds to the header of `model` (DT-FCN: the network's parameters).
    fn details(&self, _model: &Model, _out: &mut serde_json::Map<String, serde_json::Value>) {}
}

/// A labelling method over the models of one kind; `kinds` are the kinds of model file it may meet (a file of
/// another method's, the windows models of the fit check): every labelling method's, as the registry lists them.
#[derive(Clone, Copy)]
pub struct Labelling {
    kind: &'static dyn Kind,
    kinds: &'static [&'static dyn Kind],
}

impl Labelling {
    /// The labelling method over models of `kind`, among `kinds`.
    pub const fn new(kind: &'static dyn Kind, kinds: &'static [&'static dyn Kind]) -> Labelling {
        Labelling { kind, kinds }
    }
}

impl std::fmt::Debug for Labelling {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Labelling({})", self.kind.name())
    }
}

impl Method for Labelling {
    type Params = LabelParams;
    type Checked = Checked;

    fn info(&self) -> MethodInfo {
        self.kind.info()
    }

    fn param_specs(&self) -> Vec<ParamSpec> {
        // the shipped models; a page adds the ones it stored
        let options: Vec<String> = shipped::NAMES.iter().map(|s| s.to_string()).collect();
        vec![
            ParamSpec {
                name: "model".into(),
                help: "The model that labels the take: one shipped with the app (exercises, CMU actions, locomotion \
                       phases) or one you trained or loaded."
                    .into(),
                kind: ParamKind::Choice { options },
                default: serde_json::json!(shipped::NAMES[0]),
                unit: None,
                basic: true,
                at_most: None,
            },
            ParamSpec {
                name: "unknown_threshold".into(),
                help: "Frames whose confidence is below this are labelled `unknown` (0: never; unset: the model's \
                       own: 0.8 for the shipped exercises DT-FCN, 0.5 for the other shipped models)."
                    .into(),
                kind: ParamKind::Number { min: 0.0, max: 1.0 },
                default: serde_json::Value::Null,
                unit: None,
                basic: true,
                at_most: None,
            },
            ParamSpec {
                name: "unknown_ratio".into(),
                help: "The open-set unknown: a labelled frame whose ±1 s window lies farther than this from its \
                       class's training windows — over the class's own repeat distance, over the take's median of \
                       the same — is labelled `unknown` (0: never; unset: the model's own, chosen when it was made on \
                       folds that leave a class out; the shipped exercises k-NN's: docs/methods/dtfcn.md)."
                    .into(),
                kind: ParamKind::Number { min: 0.0, max: super::openset::MAX_RATIO as f64 },
                default: serde_json::Value::Null,
                unit: None,
                basic: false,
                at_most: None,
            },
            ParamSpec {
                name: "decoding".into(),
                help: "How per-frame probabilities become labels: `model` — as the model was validated to (one path \
                       through the classes whose runs last at least its minimum, a semi-Markov Viterbi, so a few \
                       wavering frames do not cut a segment; each frame's own label if the model has none), `raw` — \
                       each frame's most probable class, `custom` — the minimum run and switch cost below."
                    .into(),
                kind: ParamKind::Choice { options: DECODINGS.iter().map(|s| s.to_string()).collect() },
                default: serde_json::json!(DECODINGS[0]),
                unit: None,
                basic: true,
                at_most: None,
            },
            ParamSpec {
                name: "fit_check".into(),
                help: "Measure whether the take is one the model's classes can describe (how fast it travels and how \
                       far its poses lie from the training takes'); when it is not, say so and label the take \
                       unknown instead of painting confident wrong labels."
                    .into(),
                kind: ParamKind::Bool,
                default: serde_json::json!(true),
                unit: None,
                basic: true,
                at_most: None,
            },
            ParamSpec {
                name: "fit_others".into(),
                help: "When the take does not fit the model: also measure this method's other models (shipped and \
                       yours) against the take and offer those that fit (each costs a search of its training \
                       windows, so it is asked for, not done on every run)."
                    .into(),
                kind: ParamKind::Bool,
                default: serde_json::json!(false),
                unit: None,
                basic: false,
                at_most: None,
            },
            ParamSpec {
                name: "min_duration_s".into(),
                help: "With the custom decoding: shortest run of one label (0 with a switch cost of 0: raw labels)."
                    .into(),
                kind: ParamKind::Number { min: 0.0, max: MAX_MIN_DURATION_S },
                default: serde_json::json!(CUSTOM_DECODING.min_duration_s),
                unit: Some("s".into()),
                basic: false,
                at_most: None,
            },
            ParamSpec {
                name: "switch_cost".into(),
                help: "With the custom decoding: what a change of label costs the path, in nats of summed \
                       log-probability (higher: fewer, longer segments)."
                    .into(),
                kind: ParamKind::Number { min: 0.0, max: MAX_SWITCH_COST },
                default: serde_json::json!(CUSTOM_DECODING.switch_cost),
                unit: None,
                basic: false,
                at_most: None,
            },
        ]
    }

    fn check(&self, params: LabelParams) -> Result<Checked, MethodError> {
        self.check_in(params, &ModelStore::default())
    }

    fn check_in(&self, params: LabelParams, models: &ModelStore) -> Result<Checked, MethodError> {
        let model = self.resolve(params.model.trim(), models)?;
        let threshold = match params.unknown_threshold {
            Some(t) if !(0.0..=1.0).contains(&t) => {
                return Err(MethodError::param(
                    "unknown_threshold",
                    format!("unknown_threshold = {t}: expected a confidence from 0 to 1"),
                ))
            }
            Some(t) => t,
            // the header's f32 as written (0.8, not 0.800000011920929)
            None => model.header.unknown_threshold.to_string().parse().unwrap_or(DEFAULT_THRESHOLD),
        };
        let ratio = match params.unknown_ratio {
            Some(r) if !(0.0..=super::openset::MAX_RATIO as f64).contains(&r) => {
                return Err(MethodError::param(
                    "unknown_ratio",
                    format!("unknown_ratio = {r}: expected a ratio from 0 (never) to {}", super::openset::MAX_RATIO),
                ))
            }
            Some(r) => (r > 0.0).then_some(r),
            // the header's f32 as written (2.02, not 2.0199999809265137)
            None => model.header.open_set.map(|o| o.ratio.to_string().parse().unwrap_or(o.ratio as f64)),
        };
        let (d, cost) = (params.min_duration_s, params.switch_cost);
        if !(0.0..=MAX_MIN_DURATION_S).contains(&d) {
            return Err(MethodError::param(
                "min_duration_s",
                format!("min_duration_s = {d}: expected seconds from 0 to {MAX_MIN_DURATION_S}"),
            ));
        }
        if !(0.0..=MAX_SWITCH_COST).contains(&cost) {
            return Err(MethodError::param(
                "switch_cost",
                format!("switch_cost = {cost}: expected a cost from 0 to {MAX_SWITCH_COST}"),
            ));
        }
        let decoding = match params.decoding.trim() {
            "model" => model.header.decoding.unwrap_or(Decoding::RAW),
            "raw" => Decoding::RAW,
            "custom" => Decoding { min_duration_s: d, switch_cost: cost },
            other => {
                return Err(MethodError::param(
                    "decoding",
                    format!("decoding = `{other}`: expected one of {}", DECODINGS.join(", ")),
                ))
            }
        };
        let open_windows = match ratio {
            Some(_) => self.fit_windows(&model, params.model.trim(), models)?,
            None => None,
        };
        let fit = if params.fit_check {
            Some(FitCheck {
                windows: self.fit_windows(&model, params.model.trim(), models)?,
                models: models.clone(),
                others: params.fit_others,
            })
        } else {
            None
        };
        Ok(Checked {
            fit,
            name: params.model.trim().to_string(),
            model,
            threshold,
            ratio,
            open_windows,
            asked: params.decoding.trim().to_string(),
            custom: Decoding { min_duration_s: d, switch_cost: cost },
            decoding,
        })
    }

    fn supervision(&self) -> Option<Supervision> {
        Some(super::supervised::supervision(self.kind))
    }

    fn supervised(&self) -> Option<&dyn Supervised> {
        Some(self)
    }

    fn echo(&self, params: &Checked) -> serde_json::Value {
        // the parameters as asked (segments carry the class names; a class's colour is
        // `segment::palette::class_colour(cluster)`, as in every model file)
        serde_json::json!({
            "model": params.name,
            "unknown_threshold": params.threshold,
            "unknown_ratio": params.ratio.unwrap_or(0.0),
            "decoding": params.asked,
            "min_duration_s": params.custom.min_duration_s,
            "switch_cost": params.custom.switch_cost,
            "fit_check": params.fit.is_some(),
            "fit_others": params.fit.as_ref().is_some_and(|f| f.others),
        })
    }

    fn work(&self, params: &Checked) -> Work {
        // measured in tests/limits.rs: the motion image and the labeller's own per-frame arrays — the k-NN's
        // windows (2.9 kB a frame), or the network's input (+ 3 kB a frame when the fit check measures the take's
        // poses with the k-NN's windows)
        let windows = params.fit.as_ref().and_then(|f| f.windows.as_deref());
        let base = self.kind.frame_bytes(windows.is_some());
        let work = model_work(&params.model, &params.decoding, base, windows);
        // the open-set unknown: one search of its class's windows per working frame, the classes' repeat distances
        // once; held besides: each working frame's projected window (128 bytes) and each file frame's label and ratio
        // (20 bytes, up to four file frames a working frame at 120 Hz): 256 bytes (tests/limits.rs)
        let (open_ops, open_fixed) = windows_of(params.open_windows.as_deref().filter(|_| params.ratio.is_some()))
            .map_or((0.0, 0.0), |w| w.search_ops());
        Work {
            fps: params.model.header.fps,
            advice: "",
            ops_per_frame: work.ops_per_frame + open_ops,
            fixed_ops: work.fixed_ops + open_fixed,
            bytes_per_frame: work.bytes_per_frame + if open_ops > 0.0 { 256 } else { 0 },
            ..work
        }
    }

    fn run(
        &self,
        motion: &Motion,
        params: &Checked,
        options: &RunOptions,
        progress: &mut dyn Progress,
    ) -> Result<MethodOutput, MethodError> {
        let header = &params.model.header;
        // the take's fit first (cheap): when it does not fit and the run asks (`fit_others`), the
        // method's other models are measured against it, and on the page a shipped one's file is
        // asked for before the labeller runs
        let fit = match &params.fit {
            Some(check) => {
                progress.step("take fit", 0.0)?;
                let fit = super::fit::TakeFit::assess_going(
                    motion,
                    header.travel.as_ref(),
                    windows_of(check.windows.as_deref()),
                    &mut |f| progress.step("take fit", 0.05 * f).is_ok(),
                )
                .map_err(MethodError::Failed)?
                .ok_or(MethodError::Cancelled)?;
                // the other models only when asked: each is a search of its windows, and most runs
                // keep their model; together within what the run's budget leaves
                let fitting = if fit.fits() || !check.others {
                    None
                } else {
                    let work = Method::work(self, params);
                    let left = options.limits.max_ops - work.ops(work.frames(motion));
                    Some(self.fitting_models(motion, &params.name, &check.models, left, progress)?)
                };
                Some((fit, fitting))
            }
            None => None,
        };
        progress.step("motion image", 0.0)?;
        let labelled = label(&params.model, motion, progress)?;
        // after the labeller's share (the k-NN's search ends at 0.9, DT-FCN's blocks at 0.95): never backwards
        progress.step("decoding", 0.95)?;
        let mut file = file_labels_going(
            &labelled.probabilities,
            &labelled.source,
            labelled.fps,
            motion.frames(),
            &params.decoding,
            params.threshold,
            &mut |f| progress.step("decoding", 0.95 + 0.02 * f).is_ok(),
        )
        .ok_or(MethodError::Cancelled)?;
        let open_unknown = open_set_unknown(params, motion, &mut file, progress)?;
        // a take the classes cannot describe gets no labels at all: its familiar-looking frames are
        // as wrong as the others (86_01 under `exercises`: half its frames are unfamiliar, the rest
        // "Jog" and "Twist"); `fit_check = false` shows them anyway
        if fit.as_ref().is_some_and(|(f, _)| !f.fits()) {
            file.iter_mut().for_each(|f| f.0 = None);
        }
        let segments = runs(&file, &header.classes);
        let segmentation = Segmentation {
            file: motion.name.clone(),
            fps: motion.fps,
            frames: motion.frames(),
            method: self.info().name,
            params: self.echo(params),
            segments,
        };
        let unfit = fit.as_ref().is_some_and(|(f, _)| !f.fits());
        let confidence = confidence_sentence(&file, params.threshold, unfit, open_unknown);
        let summary = format!(
            "{} · {} of model `{}` · {confidence} · {}",
            crate::method::counted(segmentation.segments.len(), "segment"),
            crate::method::counted(header.classes.len(), "class"),
            header.name,
            if params.decoding.is_raw(labelled.fps) {
                "raw per-frame labels".to_string()
            } else {
                format!(
                    "decoded: runs ≥ {} s, switch cost {}",
                    params.decoding.min_duration_s, params.decoding.switch_cost
                )
            }
        );
        let summary = match in_sample_note(header, &motion.name) {
            Some(note) => format!("{summary} · {note}"),
            None => summary,
        };
        // a take the model does not fit is said first, with the models that do: it is what a reader
        // must know before the labels
        let take_fit = fit.as_ref().map(|(f, fitting)| f.report(&params.name, fitting.clone()));
        let summary = match (fit.as_ref().map(|(f, _)| f).filter(|f| f.measured()), &take_fit) {
            (Some(f), Some(report)) if !f.fits() => {
                let advice = report.advice().unwrap_or_default();
                format!("{} · {advice} · {summary}", f.describe(&header.name))
            }
            (Some(f), _) => format!("{summary} · {}", f.describe(&header.name)),
            _ => summary,
        };
        let curves = vec![Curve {
            id: "confidence".into(),
            title: "confidence (probability of the frame's label)".into(),
            values: file.iter().map(|f| f.1).collect(),
        }];
        let mut pictures = Vec::new();
        if options.pictures {
            pictures.push(probability_picture(&labelled.probabilities, &header.colours, &header.classes));
        }
        progress.step("done", 1.0)?;
        Ok(MethodOutput { segmentation, details: Details { summary, pictures, curves, take_fit } })
    }
}

/// The summary's words on confidence and unknowns: the labelled frames' mean confidence and the share unknown — below
/// `threshold`, and of those the open-set unknown called (`open`: its ratio and count) — or why every frame is unknown.
fn confidence_sentence(
    file: &[(Option<usize>, f32)],
    threshold: f64,
    unfit: bool,
    open: Option<(f64, usize)>,
) -> String {
    let unknown = file.iter().filter(|f| f.0.is_none()).count();
    // the confidence of the frames that got a label (a model that does not fit labels none: its frames'
    // confidences say nothing then, and "mean confidence 0.92 · 100 % unknown" read as a contradiction)
    let confidences: Vec<f64> = file.iter().filter(|f| f.0.is_some()).map(|f| f.1 as f64).collect();
    let open = open.map_or(String::new(), |(r, called)| {
        format!(
            "; {:.0} % far from their class's training windows (open-set ratio above {r:.2})",
            100.0 * called as f64 / file.len().max(1) as f64
        )
    });
    match (confidences.len(), unfit) {
        (_, true) => "every frame unknown: the model does not fit this take".to_string(),
        (0, false) => format!("every frame unknown (below {threshold:.2}{open})"),
        (n, false) => format!(
            "labelled frames' mean confidence {:.2} · {:.0} % unknown (below {threshold:.2}{open})",
            confidences.iter().sum::<f64>() / n as f64,
            100.0 * unknown as f64 / file.len().max(1) as f64,
        ),
    }
}

/// The open-set unknown in force for `params` ([`super::openset`]): the labelled frames of `file` lying farther than its
/// ratio from their class's training windows made unknown; the ratio and how many frames it called (`None`: no ratio
/// in force, or no windows to measure it with).
fn open_set_unknown(
    params: &Checked,
    motion: &Motion,
    file: &mut [(Option<usize>, f32)],
    progress: &mut dyn Progress,
) -> Result<Option<(f64, usize)>, MethodError> {
    let (Some(r), Some(w)) = (params.ratio, windows_of(params.open_windows.as_deref())) else { return Ok(None) };
    let labels: Vec<Option<usize>> = file.iter().map(|f| f.0).collect();
    let ratios = w
        .voted_ratios(motion, &labels, &mut |f| progress.step("open-set unknown", 0.97 + 0.03 * f).is_ok())
        .map_err(MethodError::Failed)?
        .ok_or(MethodError::Cancelled)?;
    let mut called = 0;
    for (f, q) in file.iter_mut().zip(&ratios) {
        if f.0.is_some() && *q as f64 > r {
            f.0 = None;
            called += 1;
        }
    }
    Ok(Some((r, called)))
}

/// A take labelled by a model.
pub struct Labelled {
    /// Per working frame (30 Hz): every class's probability (a vote share for k-NN).
    pub probabilities: Probabilities,
    /// The file position of each working frame.
    pub source: Vec<f64>,
    /// The working frames' rate.
    pub fps: f64,
    /// Per file frame: the most probable class and its probability (the raw labels).
    pub per_file_frame: Vec<(usize, f32)>,
}

/// Labels every frame of `motion` with `model`.
pub fn label(model: &Model, motion: &Motion, progress: &mut dyn Progress) -> Result<Labelled, MethodError> {
    let (probabilities, source, fps) = model.labeller.label(&model.header, motion, progress)?;
    if probabilities.frames == 0 || source.len() != probabilities.frames {
        return Err(MethodError::Failed(format!(
            "{}: {} working frames labelled for {} file positions",
            motion.name,
            probabilities.frames,
            source.len()
        )));
    }
    let frames = WorkingFrames { source: &source, file_frames: motion.frames() };
    let per_file = (0..motion.frames())
        .map(|f| probabilities.best(frames.working_frame(f).min(probabilities.frames - 1)))
        .collect();
    Ok(Labelled { probabilities, source, fps, per_file_frame: per_file })
}

/// One segment per run of equal labels (`None` = unknown), scored by mean confidence.
pub fn runs(frames: &[(Option<usize>, f32)], classes: &[String]) -> Vec<Segment> {
    let mut out = Vec::new();
    let mut start = 0;
    for f in 1..=frames.len() {
        if f == frames.len() || frames[f].0 != frames[start].0 {
            let run = &frames[start..f];
            let mean = run.iter().map(|r| r.1 as f64).sum::<f64>() / run.len() as f64;
            let class = frames[start].0;
            out.push(Segment {
                start,
                end: f - 1,
                label: class.and_then(|c| classes.get(c).cloned()).unwrap_or_else(|| UNKNOWN.to_string()),
                level: Level::Action,
                cluster: class,
                score: Some((mean * 1000.0).round() / 1000.0),
                mirror_of: None,
                effort: None,
            });
            start = f;
        }
    }
    out
}

/// Parses `#rrggbb` (grey when it is not).
fn rgb(css: &str) -> [u8; 3] {
    let h = css.trim_start_matches('#');
    let c = |i: usize| h.get(i..i + 2).and_then(|s| u8::from_str_radix(s, 16).ok()).unwrap_or(128);
    if h.len() == 6 {
        [c(0), c(2), c(4)]
    } else {
        [128, 128, 128]
    }
}

/// The class probabilities over time, one row per class (class colour × probability on white),
/// one column per working frame, as the paper's figures show them.
fn probability_picture(p: &Probabilities, colours: &[String], classes: &[String]) -> Picture {
    let row_h = 6;
    let (w, h) = (p.frames.max(1), p.classes * row_h);
    let mut rgba = vec![255u8; w * h * 4];
    for c in 0..p.classes {
        let col = rgb(colours.get(c).map_or("", |s| s.as_str()));
        for f in 0..p.frames {
            let a = p.prob(f, c).clamp(0.0, 1.0);
            let px = [0, 1, 2].map(|k| (255.0 - a * (255.0 - col[k] as f32)).round() as u8);
            for y in c * row_h..(c + 1) * row_h {
                let i = (y * w + f) * 4;
                rgba[i..i + 3].copy_from_slice(&px);
            }
        }
    }
    Picture {
        id: "probabilities".into(),
        title: "Class probabilities".into(),
        caption: format!(
            "Time across (30 Hz), one row per class from the top: {}. The stronger the colour, the more probable the \
             class.",
            classes.join(", ")
        ),
        width: w,
        height: h,
        rgba,
        frames_per_pixel: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::method::DynMethod;

    #[test]
    fn runs_of_labels_become_segments_with_mean_confidence_and_unknowns() {
        let classes = vec!["walk".to_string(), "jump".to_string()];
        let frames = [(Some(0), 0.9), (Some(0), 0.7), (None, 0.2), (Some(1), 1.0)];
        let s = runs(&frames, &classes);
        assert_eq!(s.len(), 3);
        assert_eq!((s[0].start, s[0].end, s[0].label.as_str(), s[0].score), (0, 1, "walk", Some(0.8)));
        assert_eq!((s[1].label.as_str(), s[1].cluster), (UNKNOWN, None));
        assert_eq!((s[2].start, s[2].end, s[2].label.as_str()), (3, 3, "jump"));
        assert!(runs(&[], &classes).is_empty());
        assert_eq!(rgb("#ff8000"), [255, 128, 0]);
    }

    fn motion(name: &str, text: &str) -> Motion {
        Motion::from_bvh(name, &crate::bvh::parse(text).unwrap()).unwrap()
    }

    fn run(method: &dyn DynMethod, motion: &Motion, params: serde_json::Value) -> MethodOutput {
        let checked = method.check_json(&params).unwrap();
        method.run_checked(motion, &checked, &RunOptions::default(), &mut crate::method::NoProgress).unwrap()
    }

    /// Both labelling methods, as the registry gives them.
    fn labellers() -> [&'static dyn DynMethod; 2] {
        ["dtfcn", "knn"].map(|name| crate::methods::find(name).unwrap())
    }

    /// A walk is nothing the `exercises` models were taught (they were taught exercises on the
    /// spot): both labellers say so and label it unknown instead of Jog at a confidence near 1;
    /// without the check they paint their classes, as before. The sample (a take of the taught
    /// exercises) fits and keeps its labels.
    #[test]
    fn a_take_the_models_classes_cannot_describe_is_called_so() {
        let walk = motion("02_01.bvh", include_str!("../../tests/fixtures/02_01.bvh"));
        let sample = motion("13_30.bvh", include_str!("../../www/sample.bvh"));
        for method in labellers() {
            let out = run(method, &walk, serde_json::json!({"model": "exercises"}));
            let segments = &out.segmentation.segments;
            assert!(segments.iter().all(|s| s.label == UNKNOWN && s.cluster.is_none()), "{segments:?}");
            assert!(
                out.details.summary.starts_with("model `exercises` does not fit this take: 100 % of its frames travel"),
                "{}",
                out.details.summary
            );
            assert_eq!(out.segmentation.params["fit_check"], true);
            // no "mean confidence 0.92 · 100 % unknown": the frames labelled none say so, with why
            assert!(
                out.details.summary.contains("every frame unknown: the model does not fit this take")
                    && !out.details.summary.contains("mean confidence"),
                "{}",
                out.details.summary
            );
            let unchecked = run(method, &walk, serde_json::json!({"model": "exercises", "fit_check": false}));
            assert!(unchecked.segmentation.segments.iter().any(|s| s.label != UNKNOWN));
            assert!(!unchecked.details.summary.contains("fit"), "{}", unchecked.details.summary);
            assert!(
                unchecked.details.summary.contains("labelled frames' mean confidence"),
                "{}",
                unchecked.details.summary
            );
            let own = run(method, &sample, serde_json::json!({"model": "exercises"}));
            let labelled = own
                .segmentation
                .segments
                .iter()
                .filter(|s| s.label != UNKNOWN)
                .map(|s| s.end + 1 - s.start)
                .sum::<usize>();
            assert!(labelled as f64 > 0.9 * sample.frames() as f64, "{labelled} of {}", sample.frames());
            assert!(own.details.summary.contains("the take fits model `exercises`"), "{}", own.details.summary);
            // the walk is one of the locomotion models' training takes: it fits them
            let gait = run(method, &walk, serde_json::json!({"model": "locomotion"}));
            assert!(gait.details.summary.contains("the take fits model `locomotion`"), "{}", gait.details.summary);
        }
    }

    /// The verdict travels as data (`Details::take_fit`), with the method's other models that fit
    /// the take, best first, measured on real takes (docs/methods/dtfcn.md, "Take fit"): CMU 86_01
    /// (walk, jump, punch, kick) does not fit `exercises`, fits `cmu-actions` (its training take) and
    /// `locomotion` (pose ratio 1.6), in that order; a walk (02_01) fits `locomotion` only (it
    /// travels past `cmu-actions`' training takes too); the sample (13_30, exercises on the spot)
    /// fits `exercises` and is said to fit nothing else when `cmu-actions` is asked for.
    #[test]
    fn a_take_that_does_not_fit_names_the_models_that_do() {
        let actions = motion(
            "86_01.bvh",
            &std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/86_01.bvh")).unwrap(),
        );
        let walk = motion("02_01.bvh", include_str!("../../tests/fixtures/02_01.bvh"));
        let sample = motion("13_30.bvh", include_str!("../../www/sample.bvh"));
        for method in labellers() {
            // by default the other models are not measured: the verdict, and how to ask for them
            let out = run(method, &actions, serde_json::json!({"model": "exercises"}));
            let fit = out.details.take_fit.clone().expect("a fit check's report");
            assert!(!fit.fits && !fit.searched && fit.fitting.is_empty(), "{fit:?}");
            assert!(out.details.summary.contains("not measured against this take (ask with fit_others=true"));
            assert_eq!(out.segmentation.params["fit_others"], false);
            let out = run(method, &actions, serde_json::json!({"model": "exercises", "fit_others": true}));
            assert_eq!(out.segmentation.params["fit_others"], true);
            let fit = out.details.take_fit.clone().expect("a fit check's report");
            assert!(!fit.fits && fit.searched && fit.model == "exercises", "{fit:?}");
            assert!(
                fit.travel_share.unwrap() > 0.25 && fit.travel_limit.is_some() && fit.pose_ratio.is_some(),
                "{fit:?}"
            );
            assert!(fit.reason.contains("% of its frames travel faster"), "{}", fit.reason);
            assert_eq!(fit.fitting_names(), ["cmu-actions", "locomotion"], "{fit:?}");
            assert!(fit.fitting[0].pose_ratio.unwrap() < fit.fitting[1].pose_ratio.unwrap(), "best first: {fit:?}");
            assert!(
                out.details.summary.contains("· models that fit this take: cmu-actions, locomotion ·"),
                "{}",
                out.details.summary
            );
            assert!(out.segmentation.segments.iter().all(|s| s.label == UNKNOWN));
            // the model it names fits, and labels: no report of others, its classes on the row
            let better = run(method, &actions, serde_json::json!({"model": "cmu-actions", "fit_others": true}));
            let fit = better.details.take_fit.clone().unwrap();
            assert!(fit.fits && fit.fitting.is_empty() && !fit.searched && fit.reason.is_empty(), "{fit:?}");
            assert!(better.segmentation.segments.iter().any(|s| s.label != UNKNOWN));
            // a walk: locomotion only
            let out = run(method, &walk, serde_json::json!({"model": "exercises", "fit_others": true}));
            assert_eq!(out.details.take_fit.unwrap().fitting_names(), ["locomotion"]);
            // exercises on the spot under the action model: only `exercises` fits
            let out = run(method, &sample, serde_json::json!({"model": "cmu-actions", "fit_others": true}));
            let fit = out.details.take_fit.unwrap();
            assert!(!fit.fits && fit.pose_ratio.unwrap() > 2.0 && fit.reason.contains("poses lie"), "{fit:?}");
            assert_eq!(fit.fitting_names(), ["exercises"]);
            // no check, no report (and no word of fit in the JSON)
            let off = run(method, &walk, serde_json::json!({"model": "exercises", "fit_check": false}));
            assert!(off.details.take_fit.is_none());
            assert!(!serde_json::to_string(&off.details).unwrap().contains("take_fit"));
        }
    }

    /// A user's model of the method is measured too, and offered when the take fits it; a model
    /// nothing can be measured of is not.
    #[test]
    fn a_users_model_that_fits_the_take_is_offered() {
        let walk = motion("02_01.bvh", include_str!("../../tests/fixtures/02_01.bvh"));
        let knn = crate::methods::find("knn").unwrap();
        let mut store = ModelStore::default();
        // the shipped locomotion k-NN, installed under a name of the user's
        let bytes = crate::method::ModelStore::default().shipped_bytes("knn-locomotion.model").unwrap().to_vec();
        let mut loaded = knn.supervised().unwrap().read_model("mine.model", &bytes).unwrap();
        loaded.info.name = "my-walks".into();
        store.install(loaded);
        let params = serde_json::json!({"model": "exercises", "fit_others": true});
        let checked = knn.check_json_in(&params, &store).unwrap();
        let out = knn.run_checked(&walk, &checked, &RunOptions::default(), &mut crate::method::NoProgress).unwrap();
        let fit = out.details.take_fit.unwrap();
        let mut names = fit.fitting_names();
        names.sort();
        assert_eq!(names, ["locomotion", "my-walks"], "{fit:?}");
        // ranking: by pose ratio, then travel, then name
        let m = |name: &str, pose: Option<f64>, travel: f64| FittingModel {
            name: name.into(),
            pose_ratio: pose,
            travel_share: Some(travel),
        };
        let ranked = super::super::fit::rank_fitting(vec![
            m("c", None, 0.0),
            m("b", Some(1.5), 0.0),
            m("a", Some(0.5), 0.2),
            m("d", Some(0.5), 0.1),
        ]);
        assert_eq!(ranked.iter().map(|m| m.name.as_str()).collect::<Vec<_>>(), ["d", "a", "b", "c"]);
    }

    /// A result written before the report existed loads without it; one with it reads back whole.
    #[test]
    fn details_without_a_take_fit_load() {
        let old: Details = serde_json::from_str(r#"{"summary": "s", "pictures": [], "curves": []}"#).unwrap();
        assert!(old.take_fit.is_none());
        let report = crate::method::TakeFitReport {
            model: "exercises".into(),
            fits: false,
            travel_share: Some(0.43),
            travel_limit: Some(10.9),
            pose_ratio: Some(1.3),
            reason: "43 % of its frames travel".into(),
            fitting: vec![FittingModel { name: "cmu-actions".into(), travel_share: Some(0.01), pose_ratio: Some(0.0) }],
            searched: true,
        };
        let details = Details { take_fit: Some(report.clone()), ..old };
        let back: Details = serde_json::from_str(&serde_json::to_string(&details).unwrap()).unwrap();
        assert_eq!(back.take_fit, Some(report.clone()));
        assert_eq!(report.advice().unwrap(), "models that fit this take: cmu-actions");
        let none = crate::method::TakeFitReport { fitting: Vec::new(), ..report };
        assert_eq!(none.advice().unwrap(), "no other model of this method fits this take either");
        let unsearched = crate::method::TakeFitReport { searched: false, ..none.clone() };
        assert!(unsearched.advice().unwrap().contains("ask with fit_others=true"));
        // a report missing fields (a later or earlier writer) still loads
        let partial: crate::method::TakeFitReport = serde_json::from_str(r#"{"model": "x", "fits": true}"#).unwrap();
        assert!(partial.fits && partial.fitting.is_empty() && partial.advice().is_none());
    }

    /// The bundled sample (13_30) is one of the `exercises` models' training takes: a run on it says so;
    /// on a take they were not trained on (86_01), nothing is said.
    #[test]
    fn a_run_on_a_training_take_says_it_is_in_sample() {
        let header = |file: &str| {
            let bytes = ModelStore::default().shipped_bytes(file).unwrap().to_vec();
            super::super::model::read_header(&bytes, file).unwrap().0
        };
        let model = header("dtfcn-exercises.model");
        let note = in_sample_note(&model, "13_30.bvh").unwrap();
        assert!(note.starts_with(IN_SAMPLE) && note.contains("`exercises`") && note.contains("13_30"), "{note}");
        assert!(in_sample_note(&model, "86_01.bvh").is_none());
        let cmu = header("knn-cmu-actions.model");
        assert!(in_sample_note(&cmu, "86_01.bvh").is_some());
        assert!(in_sample_note(&cmu, "13_30.bvh").is_none());
    }
}
