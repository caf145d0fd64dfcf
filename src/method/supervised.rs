//! What a supervised method adds to the one shape ([`super::Method`]): it learns from takes and
//! labels, its models are files, and its runs name the model they use.
//!
//! * A supervised method declares [`Supervision`] in its [`super::MethodInfo`]: the label file it
//!   reads (its CSV header), whether it trains on more takes than the one on screen, its model
//!   files' extension, the models it ships, and its training options as a parameter table
//!   ([`ParamSpec`]s, the same kind of table its run parameters have) — so the page's training
//!   form, the worker and the command line all come from what it declares, never from its name.
//! * It implements [`Supervised`] (reached through [`super::DynMethod::supervised`]): read a
//!   model file into a [`Loaded`] model, and start a [`Training`] that runs step by step (an epoch
//!   at a time, so a page can stop it between two steps) and ends in a [`Trained`] model with its
//!   file's bytes and a report.
//! * The models a process has (read from files, or trained) live in a [`ModelStore`] owned by who
//!   runs methods — the page's worker, one command-line run — and are looked up by method and
//!   name when parameters are checked ([`super::DynMethod::check_in`]). A supervised method's run
//!   parameters have a `model` field naming a shipped model or one in the store.

use std::any::Any;
use std::sync::{Arc, Mutex};

use serde::{Deserialize, Serialize};

use super::shipped::{FileBytes, Shipped};
use super::{MethodError, ParamKind, ParamSpec, Progress};

/// How a supervised method's run summary begins the sentence that says the take was one of its
/// model's training takes (the page's metrics panel finds it there and shows it beside the scores).
pub const IN_SAMPLE: &str = "in-sample:";

/// How a labelling model fits the take a run labelled, as data (the run's [`super::Details::take_fit`]):
/// the verdict, the measures it rests on, the reason in words, and — when the take does not fit —
/// which of the method's other models do. Made by the labelling methods' take fit
/// (`crate::labeller::fit`); every field has a default, so results written before it load.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(default)]
pub struct TakeFitReport {
    /// The model measured (the run's `model`).
    pub model: String,
    /// Its classes can describe the take (also when nothing could be measured).
    pub fits: bool,
    /// Share of the take's frames travelling faster than the model's training frames (`None`: not measured).
    pub travel_share: Option<f64>,
    /// The training travel limit, reference-body inches per second (`None`: not measured).
    pub travel_limit: Option<f32>,
    /// The take's median nearest-window distance over a new repetition's (`None`: not measured).
    pub pose_ratio: Option<f64>,
    /// Why the take does not fit, in words (empty when it fits).
    pub reason: String,
    /// When it does not fit: the method's other models (shipped, and the user's) whose classes fit
    /// the take, best first (lowest pose ratio); empty when none does, the take fits, or they were
    /// not measured.
    pub fitting: Vec<FittingModel>,
    /// The other models were measured (the run's `fit_others`, on a take the model does not fit).
    pub searched: bool,
}

/// A model a take fits, as [`TakeFitReport::fitting`] lists it.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(default)]
pub struct FittingModel {
    /// Its name (a value of the method's `model` parameter).
    pub name: String,
    pub travel_share: Option<f64>,
    pub pose_ratio: Option<f64>,
}

impl TakeFitReport {
    /// The names of [`TakeFitReport::fitting`], best first.
    pub fn fitting_names(&self) -> Vec<&str> {
        self.fitting.iter().map(|m| m.name.as_str()).collect()
    }

    /// What to do about a take that does not fit, in a phrase for a summary or the command line:
    /// "models that fit this take: cmu-actions, locomotion", or that none does (`None` when it fits).
    pub fn advice(&self) -> Option<String> {
        if self.fits {
            return None;
        }
        Some(if !self.searched {
            "its other models were not measured against this take (ask with fit_others=true)".to_string()
        } else if self.fitting.is_empty() {
            "no other model of this method fits this take either".to_string()
        } else {
            format!("models that fit this take: {}", self.fitting_names().join(", "))
        })
    }
}

/// What a supervised method declares about its training and models.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Supervision {
    /// The label CSV's header (`file,start_frame,end_frame,label`).
    pub labels_header: String,
    /// How to read the label file, in a sentence or two (the training form shows it).
    pub labels_help: String,
    /// It can train on takes besides the one on screen (their files go with the request).
    pub more_takes: bool,
    /// Its model files' extension, without the dot (`model`, `json`).
    pub model_extension: String,
    /// The names of the models it ships (its `model` parameter's default is the first).
    pub shipped: Vec<String>,
    /// The training options, with their bounds and defaults (the form's fields, the command
    /// line's flags and the model file's provenance all read this table).
    pub training: Vec<ParamSpec>,
    /// What one training step is called in progress lines (`epoch`, `stage`).
    pub step_name: String,
    /// Whether the page trains on the user's labels of the take on screen ("my labels") with it.
    pub trains_on_my_labels: bool,
    /// Its runs label every frame with one of its model's classes (the page colours them by class).
    pub labels_classes: bool,
    /// It can keep one of its takes aside as a validation take whose loss chooses the epoch
    /// ([`TrainingAsk::validation`]; the command line's `--validation TAKE`).
    #[serde(default)]
    pub validation_take: bool,
    /// What it learns from when no label file is given (the command line's training without
    /// `--labels`), in words; `None`: labels are needed.
    #[serde(default)]
    pub without_labels: Option<String>,
}

/// A model as the page lists it and the command line describes it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModelInfo {
    /// The method it belongs to (a registry name).
    pub method: String,
    /// The name it is stored under: the value of that method's `model` parameter.
    pub name: String,
    /// The classes it labels, and their CSS colours (empty for a method without classes).
    pub classes: Vec<String>,
    pub colours: Vec<String>,
    /// Where it came from, in one line ("4 takes, 12,400 labelled frames, epoch 18 of 20").
    pub origin: String,
    /// Its provenance as labelled lines (the command that made it, the data's hash, …).
    pub provenance: Vec<(String, String)>,
    /// Its card: training takes (and their files' hashes), classes, command, held-out accuracy
    /// (never measured for a model read or trained here: only the scoreboard measures it).
    #[serde(default)]
    pub card: super::cards::ModelCard,
}

impl ModelInfo {
    /// Refuses an info whose classes and colours do not pair up (so views can index freely).
    pub fn check(&self) -> Result<(), String> {
        if self.classes.len() == self.colours.len() {
            Ok(())
        } else {
            Err(format!("model {} has {} classes but {} colours", self.name, self.classes.len(), self.colours.len()))
        }
    }

    /// The file name a model saves to (`NAME.EXT`, characters a file name cannot hold replaced).
    pub fn file_name(&self, extension: &str) -> String {
        model_file_name(&self.name, extension)
    }
}

/// `NAME.EXT` for a model called `name` (characters a file name cannot hold replaced).
pub fn model_file_name(name: &str, extension: &str) -> String {
    let safe: String =
        name.chars().map(|c| if c.is_control() || "/\\:*?\"<>|".contains(c) { '_' } else { c }).collect();
    format!("{}.{extension}", safe.trim_matches('.'))
}

/// A model ready for a [`ModelStore`]: what it is, and the method's own model value.
#[derive(Clone)]
pub struct Loaded {
    pub info: ModelInfo,
    pub model: Arc<dyn Any + Send + Sync>,
}

impl std::fmt::Debug for Loaded {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Loaded({} {})", self.info.method, self.info.name)
    }
}

/// The longest model name accepted.
pub const MAX_MODEL_NAME: usize = 64;

/// Refuses a name a user's model cannot be stored under (empty, too long, control characters, a
/// shipped model's).
pub fn check_model_name(name: &str, shipped: &[String]) -> Result<(), String> {
    if name.is_empty() {
        return Err("the model needs a name".into());
    }
    if name.chars().count() > MAX_MODEL_NAME {
        return Err(format!("the model name has {} characters; at most {MAX_MODEL_NAME}", name.chars().count()));
    }
    if name.chars().any(char::is_control) {
        return Err("the model name has a control character".into());
    }
    if shipped.iter().any(|s| s == name) {
        return Err(format!("`{name}` is the name of a shipped model; choose another name"));
    }
    Ok(())
}

/// The name a model read from `file` is stored under: the name inside it, or — when that is empty
/// or a shipped model's — the file's stem.
pub fn stored_name(inner: &str, file: &str, shipped: &[String]) -> Result<String, String> {
    let inner = inner.trim();
    if check_model_name(inner, shipped).is_ok() {
        return Ok(inner.to_string());
    }
    let base = file.rsplit(['/', '\\']).next().unwrap_or(file);
    let stem = base.rsplit_once('.').map_or(base, |(stem, _)| stem).trim().to_string();
    check_model_name(&stem, shipped)
        .map_err(|m| format!("{file}: the model is called `{inner}` and the file `{stem}`: {m}"))?;
    Ok(stem)
}

/// The models a runner holds, by method and name — the page's worker owns one, a command-line run another, a test
/// its own: the user's models installed in it, and the shipped files handed over to it with the shipped models read
/// from them ([`super::shipped::Shipped`], shared by the store's clones). Nothing is held process-wide.
#[derive(Default, Clone)]
pub struct ModelStore {
    models: Vec<Loaded>,
    shipped: Arc<Mutex<Shipped>>,
}

impl std::fmt::Debug for ModelStore {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.models.iter().map(|m| (&m.info.method, &m.info.name))).finish()
    }
}

impl ModelStore {
    pub fn new() -> ModelStore {
        ModelStore::default()
    }

    /// Stores `model` under its method and name, replacing one stored there before.
    pub fn install(&mut self, model: Loaded) {
        self.models.retain(|m| !(m.info.method == model.info.method && m.info.name == model.info.name));
        self.models.push(model);
    }

    /// The model of `method` called `name`, if stored and of type `T`.
    pub fn get<T: Any + Send + Sync>(&self, method: &str, name: &str) -> Option<Arc<T>> {
        let m = self.models.iter().find(|m| m.info.method == method && m.info.name == name)?;
        m.model.clone().downcast::<T>().ok()
    }

    /// What is stored for `method`, in the order it was stored.
    pub fn infos(&self, method: &str) -> Vec<&ModelInfo> {
        self.models.iter().filter(|m| m.info.method == method).map(|m| &m.info).collect()
    }

    /// The model of `method` called `name`, as stored.
    pub fn loaded(&self, method: &str, name: &str) -> Option<Loaded> {
        self.models.iter().find(|m| m.info.method == method && m.info.name == name).cloned()
    }

    /// The names stored for `method`.
    pub fn names(&self, method: &str) -> Vec<String> {
        self.infos(method).into_iter().map(|i| i.name.clone()).collect()
    }

    fn shipped(&self) -> std::sync::MutexGuard<'_, Shipped> {
        self.shipped.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// The bytes of the shipped file `file` (built in, or handed over to this store); [`MethodError::NeedsModel`]
    /// on the page until the page hands it over.
    pub fn shipped_bytes(&self, file: &str) -> Result<FileBytes, MethodError> {
        self.shipped().bytes(file)
    }

    /// Whether the bytes of the shipped file `file` are at hand.
    pub fn has_shipped(&self, file: &str) -> bool {
        self.shipped_bytes(file).is_ok()
    }

    /// Hands the shipped file `file` over to this store ([`Shipped::provide`]: checked against this build's).
    pub fn provide(&self, file: &str, bytes: Vec<u8>) -> Result<(), String> {
        self.shipped().provide(file, bytes)
    }

    /// The page could not get the shipped file `file` ([`Shipped::refuse`]).
    pub fn refuse(&self, file: &str, why: String) -> Result<(), String> {
        self.shipped().refuse(file, why)
    }

    /// The model in the shipped file `file`, read by `read` the first time this store (or a clone of it) is asked.
    pub fn read_shipped<T: Any + Send + Sync>(
        &self,
        file: &str,
        read: impl FnOnce(&[u8]) -> Result<T, MethodError>,
    ) -> Result<Arc<T>, MethodError> {
        if let Some(model) = self.shipped().read::<T>(file) {
            return Ok(model);
        }
        // read outside the lock: reading a large model takes a while, and `read` may ask the store for another
        let bytes = self.shipped_bytes(file)?;
        let model = Arc::new(read(&bytes)?);
        self.shipped().keep(file, model.clone());
        Ok(model)
    }
}

/// Reads `value` (a JSON object; missing fields take their defaults) as the training options `T`
/// that the table `specs` describes, and checks every field against its row's bounds: a refusal
/// names the option (`what` names the method in a message about the object as a whole).
pub fn read_options<T: serde::de::DeserializeOwned + Serialize>(
    value: &serde_json::Value,
    specs: &[ParamSpec],
    what: &str,
) -> Result<T, MethodError> {
    let value = if value.is_null() { serde_json::json!({}) } else { value.clone() };
    let options: T = serde_json::from_value(value.clone()).map_err(|e| {
        // serde's message names no field: find the one that is not of its kind
        let culprit = value.as_object().and_then(|fields| {
            fields.iter().find(|(name, v)| {
                specs.iter().any(|s| s.name == **name)
                    && serde_json::from_value::<T>(serde_json::json!({ name.as_str(): v })).is_err()
            })
        });
        match culprit {
            Some((name, v)) => MethodError::param(name, format!("{name} = {v}: {e}")),
            None => MethodError::params(format!("{what} training options: {e}")),
        }
    })?;
    let read = serde_json::to_value(&options).map_err(|e| MethodError::params(e.to_string()))?;
    for spec in specs {
        if let Some(v) = read.get(&spec.name) {
            check_option(spec, v)?;
        }
    }
    Ok(options)
}

/// One training option of the options `T`, declared once: its row of the method's table (the page's form field, the
/// command line's flag: name, help, kind, unit, whether the basic form shows it), its default (read from
/// `T::default()`), and how its value is read from and written into `T` — the JSON the page sends, the flags the
/// command line reads and the options a model's provenance repeats all go through it.
pub struct TrainingOption<T> {
    pub name: &'static str,
    pub help: &'static str,
    pub kind: fn() -> ParamKind,
    pub unit: Option<&'static str>,
    pub basic: bool,
    /// The option's value in `T`, as JSON.
    pub get: fn(&T) -> serde_json::Value,
    /// Sets the option in `T` to a value [`check_option`] accepted for its row.
    pub set: fn(&mut T, &serde_json::Value),
}

impl<T> Clone for TrainingOption<T> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<T> Copy for TrainingOption<T> {}

/// The table of `options` (each row's default from `T::default()`).
pub fn option_specs<T: Default>(options: &[TrainingOption<T>]) -> Vec<ParamSpec> {
    let d = T::default();
    options
        .iter()
        .map(|o| ParamSpec {
            name: o.name.into(),
            help: o.help.into(),
            kind: (o.kind)(),
            default: (o.get)(&d),
            unit: o.unit.map(Into::into),
            basic: o.basic,
            at_most: None,
        })
        .collect()
}

/// Reads `value` (a JSON object, `null` for none; a missing field keeps its default) as the options `T` declared by
/// `options`: a field no row declares is refused (`what` names the method), a value outside its row's bounds is
/// refused naming the option.
pub fn read_option_rows<T: Default>(
    value: &serde_json::Value,
    options: &[TrainingOption<T>],
    what: &str,
) -> Result<T, MethodError> {
    let mut read = T::default();
    let empty = serde_json::Map::new();
    let fields = match value {
        serde_json::Value::Null => &empty,
        serde_json::Value::Object(fields) => fields,
        other => {
            return Err(MethodError::params(format!("{what} training options: expected an object, found {other}")))
        }
    };
    let specs = option_specs(options);
    for (name, v) in fields {
        let Some(k) = options.iter().position(|o| o.name == name) else {
            let known: Vec<&str> = options.iter().map(|o| o.name).collect();
            return Err(MethodError::params(format!(
                "{what} training options: unknown field `{name}`, expected one of {}",
                known.join(", ")
            )));
        };
        check_option(&specs[k], v)?;
        (options[k].set)(&mut read, v);
    }
    Ok(read)
}

/// Every option of `options` as it stands in `read`, as JSON (what a model's provenance repeats).
pub fn option_values<T>(options: &[TrainingOption<T>], read: &T) -> serde_json::Value {
    serde_json::Value::Object(options.iter().map(|o| (o.name.to_string(), (o.get)(read))).collect())
}

/// Refuses `value` of the option `spec` when it is outside the row's bounds, naming it.
pub fn check_option(spec: &ParamSpec, value: &serde_json::Value) -> Result<(), MethodError> {
    let words = spec.name.replace('_', " ");
    let refuse = |expected: String| {
        let shown = match value {
            serde_json::Value::Array(items) => items
                .iter()
                .map(|i| i.as_str().map_or_else(|| i.to_string(), str::to_string))
                .collect::<Vec<_>>()
                .join(","),
            other => other.to_string(),
        };
        Err(MethodError::param(&spec.name, format!("{words} {shown}: expected {expected}")))
    };
    match &spec.kind {
        ParamKind::Number { min, max } => match value.as_f64() {
            Some(v) if v.is_finite() && (*min..=*max).contains(&v) => Ok(()),
            _ => refuse(format!("a number from {min} to {max}")),
        },
        ParamKind::Integer { min, max } => match value.as_i64() {
            Some(v) if (*min..=*max).contains(&v) => Ok(()),
            _ => refuse(format!("a whole number from {min} to {max}")),
        },
        ParamKind::IntegerList { min, max, max_len } => {
            let items = value.as_array().map(|a| a.iter().map(serde_json::Value::as_i64).collect::<Option<Vec<_>>>());
            match items.flatten() {
                Some(list)
                    if !list.is_empty() && list.len() <= *max_len && list.iter().all(|v| (min..=max).contains(&v)) =>
                {
                    Ok(())
                }
                _ => refuse(format!("1 to {max_len} whole numbers from {min} to {max}, separated by commas")),
            }
        }
        ParamKind::Flags { options } => {
            let items = value.as_array().map(|a| a.iter().map(serde_json::Value::as_str).collect::<Option<Vec<_>>>());
            match items.flatten() {
                Some(list) if list.iter().all(|v| options.iter().any(|o| o == v)) => Ok(()),
                _ => refuse(format!("any of {}", options.join(", "))),
            }
        }
        ParamKind::Choice { options } => match value.as_str() {
            Some(v) if options.iter().any(|o| o == v) => Ok(()),
            _ => refuse(format!("one of {}", options.join(", "))),
        },
        ParamKind::Bool => match value.as_bool() {
            Some(_) => Ok(()),
            None => refuse("true or false".into()),
        },
    }
}

/// What a training is asked to learn from.
#[derive(Debug, Clone, Default)]
pub struct TrainingAsk {
    /// The model's name (checked: not empty, not a shipped model's).
    pub name: String,
    /// The label file's name and text.
    pub labels_name: String,
    pub labels: String,
    /// The takes' files (name, bytes), the one on screen first.
    pub takes: Vec<(String, Vec<u8>)>,
    /// The training options as JSON (missing fields take the declared defaults).
    pub options: serde_json::Value,
    /// The command that asked for it, for the model's provenance (the command line as typed);
    /// `None` on the page: the method writes the command that trains the same model natively.
    pub command: Option<String>,
    /// A model of the user's to continue training (its weights, classes and input scaling kept)
    /// instead of starting from random weights; a method that cannot continue refuses it.
    pub start_from: Option<Loaded>,
    /// One of `takes` kept out of the training: its loss chooses the epoch (early stopping). Only
    /// for a method that declares [`Supervision::validation_take`]; refused, naming `validation`,
    /// when no take has that name.
    pub validation: Option<String>,
    /// The model goes to a file (the command line), not into the page's store beside the shipped
    /// models: it may carry a shipped model's name (how the shipped models are made).
    pub to_file: bool,
    /// What the training may hold: its takes and its arrays ([`crate::method::work::TrainingHold`]; the page's and
    /// the command line's: 1 GiB).
    pub limits: crate::method::WorkLimits,
}

/// One step of a training done.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StepReport {
    /// 1-based, of `steps` at most.
    pub step: usize,
    pub steps: usize,
    /// The step in a line ("epoch 3 of 20 · loss 0.412 · accuracy 81 %").
    pub line: String,
    /// Named values a page can plot over the steps, each in `[0, 1]` after dividing by the
    /// largest of its kind so far (`loss`, `accuracy`).
    pub values: Vec<(String, f64)>,
    /// The model as of this step is the one kept so far.
    pub best: bool,
}

/// How a training went, as the page shows it when it ends.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct TrainingReport {
    /// The status line ("Trained on 14 rows of effort.csv · 1 row for another file left out").
    pub summary: String,
    /// A table of results (one row per class or factor), if the method has one.
    pub columns: Vec<String>,
    pub rows: Vec<Vec<String>>,
    /// It was stopped before its last step (the best model so far is kept).
    pub stopped: bool,
}

/// A finished training: the model (to store), its file's bytes (to save) and its report.
#[derive(Debug, Clone)]
pub struct Trained {
    pub model: Loaded,
    pub bytes: Vec<u8>,
    pub report: TrainingReport,
}

/// A training under way, between two steps.
pub trait Training: Send {
    /// Runs the next step.
    fn step(&mut self, progress: &mut dyn Progress) -> Result<StepReport, MethodError>;
    /// No step is left (every step ran, or [`Training::stop`]).
    fn done(&self) -> bool;
    /// Ends the training after the steps so far (the best model so far is kept).
    fn stop(&mut self);
    /// The model and its report (after the last step, or a stop).
    fn finish(self: Box<Self>) -> Result<Trained, MethodError>;
}

/// What a supervised method can do besides running (see the module documentation).
pub trait Supervised: Send + Sync {
    /// Reads a model file (`file` names it in messages) of this method.
    fn read_model(&self, file: &str, bytes: &[u8]) -> Result<Loaded, MethodError>;
    /// The shipped model `name` (one of [`Supervision::shipped`]); on the page
    /// [`MethodError::NeedsModel`] until its file was handed over.
    fn shipped_model(&self, name: &str, models: &ModelStore) -> Result<Loaded, MethodError>;
    /// Everything about `model` but its weights, as `mocapseg model-info` prints it.
    fn model_details(&self, model: &Loaded) -> serde_json::Value;
    /// Checks `ask` and prepares its training (reading the takes and labels, reporting to
    /// `progress`); a refusal names the option, or `labels`, `takes` or `name`.
    fn start_training(&self, ask: TrainingAsk, progress: &mut dyn Progress) -> Result<Box<dyn Training>, MethodError>;
    /// What a training with `options` holds per working frame of its takes besides the takes themselves (an upper
    /// bound, measured in tests/limits.rs), checked as it reads them ([`crate::method::work::TrainingHold`]).
    fn training_work(&self, options: &serde_json::Value) -> Result<crate::method::Work, MethodError>;
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Options declared as rows: the table's defaults are `T::default()`'s, a value is read into its field through
    /// the row that declares it, checked against the row's bounds first, and a field no row declares is refused.
    #[test]
    fn options_declared_once_give_the_table_the_reading_and_the_values() {
        #[derive(Default, Debug, PartialEq)]
        struct Toy {
            epochs: usize,
            rate: f64,
        }
        let rows: [TrainingOption<Toy>; 2] = [
            TrainingOption {
                name: "epochs",
                help: "Epochs.",
                kind: || ParamKind::Integer { min: 1, max: 9 },
                unit: None,
                basic: true,
                get: |t| t.epochs.into(),
                set: |t, v| t.epochs = v.as_u64().unwrap_or(0) as usize,
            },
            TrainingOption {
                name: "rate",
                help: "Rate.",
                kind: || ParamKind::Number { min: 0.0, max: 1.0 },
                unit: Some("1/s"),
                basic: false,
                get: |t| t.rate.into(),
                set: |t, v| t.rate = v.as_f64().unwrap_or(0.0),
            },
        ];
        let specs = option_specs(&rows);
        assert_eq!(
            (specs[0].name.as_str(), &specs[0].default, specs[0].basic),
            ("epochs", &serde_json::json!(0), true)
        );
        assert_eq!((specs[1].unit.as_deref(), &specs[1].default), (Some("1/s"), &serde_json::json!(0.0)));
        let read = read_option_rows(&serde_json::json!({"epochs": 3, "rate": 0.5}), &rows, "Toy").unwrap();
        assert_eq!(read, Toy { epochs: 3, rate: 0.5 });
        assert_eq!(option_values(&rows, &read), serde_json::json!({"epochs": 3, "rate": 0.5}));
        assert_eq!(read_option_rows(&serde_json::Value::Null, &rows, "Toy").unwrap(), Toy::default());
        let out_of_range = read_option_rows(&serde_json::json!({"epochs": 10}), &rows, "Toy").unwrap_err();
        assert_eq!(out_of_range.param_name(), Some("epochs"), "{out_of_range}");
        let wrong_kind = read_option_rows(&serde_json::json!({"rate": "fast"}), &rows, "Toy").unwrap_err();
        assert_eq!(wrong_kind.param_name(), Some("rate"), "{wrong_kind}");
        let unknown = read_option_rows(&serde_json::json!({"nope": 1}), &rows, "Toy").unwrap_err();
        assert!(unknown.param_name().is_none() && unknown.to_string().contains("unknown field `nope`"), "{unknown}");
        assert!(read_option_rows(&serde_json::json!([1]), &rows, "Toy").is_err());
    }

    fn info(method: &str, name: &str) -> ModelInfo {
        ModelInfo {
            method: method.into(),
            name: name.into(),
            classes: vec![],
            colours: vec![],
            origin: String::new(),
            provenance: vec![],
            card: Default::default(),
        }
    }

    #[test]
    fn the_store_holds_models_by_method_and_name_and_replaces_them() {
        let mut store = ModelStore::new();
        store.install(Loaded { info: info("a", "m"), model: Arc::new(1u32) });
        store.install(Loaded { info: info("b", "m"), model: Arc::new(2u32) });
        store.install(Loaded { info: info("a", "m"), model: Arc::new(3u32) });
        assert_eq!(store.get::<u32>("a", "m").as_deref(), Some(&3));
        assert_eq!(store.get::<u32>("b", "m").as_deref(), Some(&2));
        assert!(store.get::<u64>("a", "m").is_none(), "of another type");
        assert!(store.get::<u32>("a", "x").is_none());
        assert_eq!(store.names("a"), vec!["m".to_string()]);
    }

    #[test]
    fn model_names_are_checked_and_files_give_their_stem() {
        let shipped = vec!["exercises".to_string()];
        assert!(check_model_name("", &shipped).is_err());
        assert!(check_model_name("exercises", &shipped).unwrap_err().contains("shipped"));
        assert!(check_model_name(&"x".repeat(65), &shipped).is_err());
        assert!(check_model_name("a\u{7}", &shipped).is_err());
        assert_eq!(stored_name("mine", "f.model", &shipped).unwrap(), "mine");
        assert_eq!(stored_name("exercises", "dir/walks.model", &shipped).unwrap(), "walks");
        assert!(stored_name("", "exercises.model", &shipped).unwrap_err().contains("shipped"));
        assert_eq!(model_file_name("a/b", "model"), "a_b.model");
    }
}
