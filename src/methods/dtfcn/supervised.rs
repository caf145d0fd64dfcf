//! DT-FCN and the k-NN as supervised methods ([`crate::method::supervised`]): their training
//! options as one table, reading model files, and a training from a label CSV and takes — an
//! epoch per step for the network, one fit for the k-NN — ending in a model file with its
//! provenance (the command that trains the same model natively).

use std::sync::Arc;

use super::augment::Augment;
use super::corpus::{class_labels, fit_knn_model, model_from, rows_without_takes, ModelMeta};
use super::method::{DEFAULT_THRESHOLD, MAX_MIN_DURATION_S, MAX_SWITCH_COST};
use super::model::{networks_of, ModelKind, Networks, KINDS};
use super::network::Padding;
use super::network::{DtFcn, DtFcnConfig};
use super::shipped;
use super::training::{EpochReport, TrainOptions, Trainer, TrainingTake, MAX_MASK_S};
use crate::labeller::decode::Decoding;
use crate::labeller::input::NetworkInput;
use crate::labeller::input::Standardise;
use crate::labeller::model::{data_hash, take_hashes, Model};
use crate::labels::same_file;
use crate::method::cards::ModelCard;
use crate::method::form::field_text;
use crate::method::supervised::{
    check_model_name, option_specs, option_values, read_option_rows, Loaded, ModelInfo, StepReport, Supervision,
    Trained, Training, TrainingAsk, TrainingOption, TrainingReport,
};
use crate::method::{counted, MethodError, ParamKind, ParamSpec, Progress};
use crate::motion::Motion;

/// The names of the shipped models, as the store and the forms want them.
pub fn shipped_names() -> Vec<String> {
    shipped::NAMES.iter().map(|s| s.to_string()).collect()
}

/// The augmentations the `augment` option can name.
const AUGMENTATIONS: [&str; 5] = ["mirror", "yaw", "warp", "scale", "jitter"];

/// The training options of a model of `kind` ([`OPTIONS`]): DT-FCN's are all of them, the k-NN's the decoding's.
fn rows(kind: ModelKind) -> &'static [TrainingOption<Choices>] {
    match kind {
        ModelKind::Dtfcn => &OPTIONS,
        ModelKind::Knn => &OPTIONS[NETWORK_ROWS..],
    }
}

/// The training options of a model of `kind`: the one table the page's form, the command line's
/// flags (`mocapseg train-dtfcn --NAME VALUE`), the model's provenance and [`options_from_json`] read.
pub fn training_specs(kind: ModelKind) -> Vec<ParamSpec> {
    option_specs(rows(kind))
}

/// What a labeller's training table reads: the trainer's options (DT-FCN's; the k-NN has none) and the decoding and
/// unknown threshold its model keeps.
#[derive(Debug, Clone, PartialEq)]
pub struct Choices {
    pub train: TrainOptions,
    pub min_duration_s: f64,
    pub switch_cost: f64,
    pub unknown_threshold: f64,
    /// With a validation take: the decoding and threshold are chosen on it instead ([`choose_on_validation`]).
    pub choose_decoding: bool,
}

impl Default for Choices {
    fn default() -> Self {
        Choices {
            train: TrainOptions::default(),
            min_duration_s: 0.0,
            switch_cost: 0.0,
            unknown_threshold: DEFAULT_THRESHOLD,
            choose_decoding: true,
        }
    }
}

/// An option's JSON value as a whole number, a number, a list of words (its row's check accepted it as one).
fn whole(v: &serde_json::Value) -> usize {
    v.as_u64().unwrap_or(0) as usize
}

fn number(v: &serde_json::Value) -> f64 {
    v.as_f64().unwrap_or(0.0)
}

fn words(v: &serde_json::Value) -> Vec<&str> {
    v.as_array().map_or(Vec::new(), |a| a.iter().filter_map(serde_json::Value::as_str).collect())
}

/// The rows of the network's options in DT-FCN's table (the first [`NETWORK_ROWS`] of [`OPTIONS`]).
const NETWORK_ROWS: usize = 17;

/// Every training option of the two labellers, each declared once: DT-FCN's table is all of them, the k-NN's the
/// decoding's rows after [`NETWORK_ROWS`].
pub const OPTIONS: [TrainingOption<Choices>; 21] = [
    TrainingOption {
        name: "epochs",
        help: "Most epochs; Stop ends earlier.",
        kind: || ParamKind::Integer { min: 1, max: 10_000 },
        unit: None,
        basic: true,
        get: |c| c.train.epochs.into(),
        set: |c, v| c.train.epochs = whole(v),
    },
    TrainingOption {
        name: "label_noise",
        help: "Share of training frames given a random label (the paper's Table 3), 0–1.",
        kind: || ParamKind::Number { min: 0.0, max: 1.0 },
        unit: None,
        basic: true,
        get: |c| c.train.label_noise.into(),
        set: |c, v| c.train.label_noise = number(v),
    },
    TrainingOption {
        name: "mask_s",
        help: "w_transition: the span around each label change whose loss is zeroed (the paper's Table 4: 0.15–0.43 s; 0 = none).",
        kind: || ParamKind::Number { min: 0.0, max: MAX_MASK_S },
        unit: Some("s"),
        basic: true,
        get: |c| c.train.mask_s.into(),
        set: |c, v| c.train.mask_s = number(v),
    },
    TrainingOption {
        name: "augment",
        help: "Augmentations of the training crops: mirror (left ↔ right), yaw ±15°, time warp 0.8–1.2×, scale 0.9–1.1×, jitter.",
        kind: || ParamKind::Flags { options: AUGMENTATIONS.iter().map(|s| s.to_string()).collect() },
        unit: None,
        basic: true,
        get: |c| augment_names(&c.train.augment).into(),
        set: |c, v| c.train.augment = Augment::parse(&words(v).join(",")).unwrap_or(c.train.augment),
    },
    TrainingOption {
        name: "width",
        help: "Kernel width w: with L layers the receptive field is w^L frames at 30 Hz (w = 3, 4 layers: 2.7 s; w = 2, 6 layers: 2.1 s).",
        kind: || ParamKind::Integer { min: 2, max: 3 },
        unit: None,
        basic: true,
        get: |c| c.train.width.into(),
        set: |c, v| c.train.width = whole(v),
    },
    TrainingOption {
        name: "filters",
        help: "Filters of each layer; their count is the layer count L (the paper's five: 64,64,128,256,512; the default four give w = 3 a receptive field of 2.7 s).",
        kind: || ParamKind::IntegerList { min: 1, max: 2048, max_len: 6 },
        unit: None,
        basic: false,
        get: |c| serde_json::json!(c.train.filters),
        set: |c, v| c.train.filters = v.as_array().map_or(Vec::new(), |a| a.iter().map(whole).collect()),
    },
    TrainingOption {
        name: "padding",
        help: "What the convolutions read beyond the take's ends: zero (the paper's) or edge (the end frames repeated, so the take's start cannot be told from a held pose).",
        kind: || ParamKind::Choice { options: vec!["zero".into(), "edge".into()] },
        unit: None,
        basic: false,
        get: |c| c.train.padding.name().into(),
        set: |c, v| c.train.padding = Padding::parse(v.as_str().unwrap_or("")).unwrap_or(c.train.padding),
    },
    TrainingOption {
        name: "image_rows",
        help: "The paper's input: the motion image resized to this many rows before layer 1 (224 gives the paper's 663,562 parameters); 0 = the image's own rows.",
        kind: || ParamKind::Integer { min: 0, max: 512 },
        unit: None,
        basic: false,
        get: |c| c.train.image_rows.unwrap_or(0).into(),
        set: |c, v| c.train.image_rows = Some(whole(v)).filter(|&r| r > 0),
    },
    TrainingOption {
        name: "crop_frames",
        help: "Frames of each training crop the loss is taken on.",
        kind: || ParamKind::Integer { min: 16, max: 4096 },
        unit: Some("frames"),
        basic: false,
        get: |c| c.train.crop_frames.into(),
        set: |c, v| c.train.crop_frames = whole(v),
    },
    TrainingOption {
        name: "batch",
        help: "Crops per optimiser step.",
        kind: || ParamKind::Integer { min: 1, max: 64 },
        unit: None,
        basic: false,
        get: |c| c.train.batch.into(),
        set: |c, v| c.train.batch = whole(v),
    },
    TrainingOption {
        name: "learning_rate",
        help: "Adam's learning rate.",
        kind: || ParamKind::Number { min: 1e-6, max: 0.5 },
        unit: None,
        basic: false,
        get: |c| c.train.learning_rate.into(),
        set: |c, v| c.train.learning_rate = number(v),
    },
    TrainingOption {
        name: "weight_decay",
        help: "Adam's L2 weight decay (0 = none).",
        kind: || ParamKind::Number { min: 0.0, max: 0.5 },
        unit: None,
        basic: false,
        get: |c| c.train.weight_decay.into(),
        set: |c, v| c.train.weight_decay = number(v),
    },
    TrainingOption {
        name: "seed",
        help: "Seed of the initial weights, crops and augmentations.",
        kind: || ParamKind::Integer { min: 0, max: 1 << 31 },
        unit: None,
        basic: false,
        get: |c| c.train.seed.into(),
        set: |c, v| c.train.seed = v.as_u64().unwrap_or(0),
    },
    TrainingOption {
        name: "patience",
        help: "With a validation take (the command line's --validation): epochs without a better validation loss before training stops.",
        kind: || ParamKind::Integer { min: 1, max: 10_000 },
        unit: Some("epochs"),
        basic: false,
        get: |c| c.train.patience.into(),
        set: |c, v| c.train.patience = whole(v),
    },
    TrainingOption {
        name: "average_last",
        help: "Without a validation take: keep the mean of the last this many epochs' weights (stochastic weight averaging; 0 = the last epoch's). Three seeds held out: 0.891–0.951 frame accuracy at 0, 0.921–0.941 at 10 (docs/methods/dtfcn.md).",
        kind: || ParamKind::Integer { min: 0, max: 10_000 },
        unit: Some("epochs"),
        basic: false,
        get: |c| c.train.average_last.into(),
        set: |c, v| c.train.average_last = whole(v),
    },
    TrainingOption {
        name: "members",
        help: "Networks trained, each with its own seed (seed, seed + 1, …), whose probabilities are averaged: a few-seed ensemble. Labelling takes as long per network; one network's held-out accuracy moves by ±0.03 with its seed (docs/methods/dtfcn.md).",
        kind: || ParamKind::Integer { min: 1, max: super::training::MAX_MEMBERS as i64 },
        unit: Some("networks"),
        basic: false,
        get: |c| c.train.members.into(),
        set: |c, v| c.train.members = whole(v),
    },
    TrainingOption {
        name: "centre_on_take",
        help: "Centre each take on its own median posture before the standardisation (not in the paper): a subject's stance and proportions no longer shift the input, only the movement does. The model keeps it; labelling a take then depends on the whole take's posture. Nested validation on the shared takes: better on the validation takes, +0.004 held out with worse segments, so off by default (docs/methods/dtfcn.md).",
        kind: || ParamKind::Bool,
        unit: None,
        basic: false,
        get: |c| c.train.centre_on_take.into(),
        set: |c, v| c.train.centre_on_take = v.as_bool().unwrap_or(false),
    },
    TrainingOption {
        name: "min_duration_s",
        help: "The model's decoding: the shortest run of one label its runs keep (0 with switch cost 0: the raw per-frame labels; the shipped exercises models: 2 s, chosen by nested validation).",
        kind: || ParamKind::Number { min: 0.0, max: MAX_MIN_DURATION_S },
        unit: Some("s"),
        basic: false,
        get: |c| c.min_duration_s.into(),
        set: |c, v| c.min_duration_s = number(v),
    },
    TrainingOption {
        name: "switch_cost",
        help: "The model's decoding: the cost of a change of label, in nats of summed log-probability (0 = free).",
        kind: || ParamKind::Number { min: 0.0, max: MAX_SWITCH_COST },
        unit: None,
        basic: false,
        get: |c| c.switch_cost.into(),
        set: |c, v| c.switch_cost = number(v),
    },
    TrainingOption {
        name: "unknown_threshold",
        help: "The model's unknown threshold: its runs call a frame (with a decoding, a whole run) unknown below this confidence unless they ask for another (the shipped exercises DT-FCN: 0.8, chosen with its decoding by nested validation).",
        kind: || ParamKind::Number { min: 0.0, max: 1.0 },
        unit: None,
        basic: false,
        get: |c| c.unknown_threshold.into(),
        set: |c, v| c.unknown_threshold = number(v),
    },
    TrainingOption {
        name: "choose_decoding",
        help: "With a validation take (the command line's --validation): choose the model's decoding and unknown threshold on it, in place of the three rows above — runs of 0–8 s, switch costs 0–150, thresholds 0, 0.5 and 0.8, the best mean of frame accuracy, edit and F1@50 on its labels (how make accuracy chooses the shipped models'). Without a validation take: the rows as given.",
        kind: || ParamKind::Bool,
        unit: None,
        basic: false,
        get: |c| c.choose_decoding.into(),
        set: |c, v| c.choose_decoding = v.as_bool().unwrap_or(true),
    },
];

/// The augmentations turned on, by name.
fn augment_names(a: &Augment) -> Vec<String> {
    [a.mirror, a.yaw, a.time_warp, a.scale, a.jitter]
        .iter()
        .zip(AUGMENTATIONS)
        .filter(|(on, _)| **on)
        .map(|(_, n)| n.to_string())
        .collect()
}

/// A training's options as read from its table: the trainer's, the decoding its model keeps, and
/// every row's value as read (what the model's provenance repeats).
#[derive(Debug, Clone, PartialEq)]
pub struct ModelOptions {
    pub train: TrainOptions,
    /// `None`: the model's runs label each frame by its most probable class.
    pub decoding: Option<Decoding>,
    /// The model's own unknown threshold (its header's; what its runs use unless they ask for another).
    pub unknown_threshold: f64,
    /// With a validation take: the decoding and threshold are chosen on it instead ([`choose_on_validation`]).
    pub choose_decoding: bool,
    pub read: serde_json::Value,
}

/// The decoding a model keeps, `None` for the raw labels.
fn decoding_of(min_duration_s: f64, switch_cost: f64) -> Option<Decoding> {
    (min_duration_s > 0.0 || switch_cost > 0.0).then_some(Decoding { min_duration_s, switch_cost })
}

/// Reads and checks the training options of a model of `kind` against [`training_specs`]: a
/// refusal names the option.
pub fn options_from_json(kind: ModelKind, value: &serde_json::Value) -> Result<ModelOptions, MethodError> {
    let rows = rows(kind);
    let c: Choices = read_option_rows(value, rows, kind_short(kind))?;
    if kind == ModelKind::Dtfcn {
        // what the table cannot say (learning rate below 1, …) is still the trainer's to refuse
        c.train.check().map_err(MethodError::params)?;
    }
    Ok(ModelOptions {
        decoding: decoding_of(c.min_duration_s, c.switch_cost),
        unknown_threshold: c.unknown_threshold,
        choose_decoding: c.choose_decoding,
        read: option_values(rows, &c),
        train: c.train,
    })
}

/// The declaration of the labelling method of `kind`.
pub fn supervision(kind: ModelKind) -> Supervision {
    Supervision {
        labels_header: "file,start_frame,end_frame,label".into(),
        labels_help:
            "Frames of the file (0-based, inclusive), any label. Its rows for the take on screen and the takes \
                      you add train a model in this tab; the model then labels the take on screen."
                .into(),
        more_takes: true,
        model_extension: "model".into(),
        shipped: shipped_names(),
        training: training_specs(kind),
        step_name: match kind {
            ModelKind::Dtfcn => "epoch".into(),
            ModelKind::Knn => "fit".into(),
        },
        trains_on_my_labels: kind == ModelKind::Dtfcn,
        labels_classes: true,
        // DT-FCN: the epoch and the decoding; the k-NN: the decoding
        validation_take: true,
        without_labels: None,
    }
}

/// The method's name for a model kind, as headings show it.
pub fn kind_short(kind: ModelKind) -> &'static str {
    match kind {
        ModelKind::Dtfcn => "DT-FCN",
        ModelKind::Knn => "k-NN",
    }
}

/// What the page and `model-info` show of `model`, stored as `name`.
pub fn model_info(name: &str, model: &Model) -> ModelInfo {
    let h = &model.header;
    let p = &h.provenance;
    let mut origin = format!("{} ({})", counted(h.classes.len(), "class"), h.classes.join(", "));
    if !p.takes.is_empty() {
        origin += &format!(", trained on {} labelled frames of {}", p.frames, p.takes.join(", "));
    }
    if h.kind == ModelKind::Dtfcn.name() && p.members.len() > 1 {
        let kept: Vec<String> =
            p.members.iter().map(|m| format!("seed {}: epoch {} of {}", m.seed, m.best_epoch, m.epochs_run)).collect();
        origin += &format!(
            ", an ensemble of {} networks (their probabilities averaged; {} kept)",
            p.members.len(),
            kept.join(", ")
        );
    } else if h.kind == ModelKind::Dtfcn.name() && p.epochs_run > 0 {
        origin += &format!(", epoch {} of {} kept", p.best_epoch, p.epochs_run);
    }
    ModelInfo {
        method: h.kind.clone(),
        name: name.into(),
        classes: h.classes.clone(),
        colours: h.colours.clone(),
        origin,
        provenance: vec![
            ("takes".into(), p.takes.join(", ")),
            ("unknown below".into(), format!("{:.2}", h.unknown_threshold)),
            (
                "decoding".into(),
                h.decoding.map_or_else(
                    || "raw per-frame labels".to_string(),
                    |d| format!("runs ≥ {} s, switch cost {}", d.min_duration_s, d.switch_cost),
                ),
            ),
            ("command".into(), p.command.clone()),
            ("data hash".into(), p.data_hash.clone()),
        ],
        card: ModelCard {
            method: h.kind.clone(),
            name: name.into(),
            takes: p.takes.clone(),
            take_sha256: p.take_sha256.clone(),
            classes: h.classes.clone(),
            frames: Some(p.frames),
            epochs_run: (h.kind == ModelKind::Dtfcn.name()).then_some(p.epochs_run),
            best_epoch: (h.kind == ModelKind::Dtfcn.name()).then_some(p.best_epoch),
            command: p.command.clone(),
            origin: String::new(),
            held_out: None,
        },
    }
}

/// A model's header as `mocapseg model-info` prints it: without the input's standardisation,
/// with the network's parameter count and receptive field.
pub fn header_json(model: &Model) -> serde_json::Value {
    let mut h = serde_json::to_value(&model.header).unwrap_or_default();
    if let Some(o) = h.as_object_mut() {
        o.remove("standardise");
        if let Some(nets) = networks_of(model) {
            let (n, networks) = (&nets.config, nets.nets.len());
            o.insert("parameters".into(), (networks * n.parameter_count()).into());
            if networks > 1 {
                o.insert("networks".into(), networks.into());
                o.insert("parameters_per_network".into(), n.parameter_count().into());
            }
            o.insert("receptive_field_frames".into(), n.receptive_field().into());
        }
    }
    h
}

/// Reads a model file of `kind` (`file` names it): stored under the name inside it, or its stem.
pub fn read_model(kind: ModelKind, file: &str, bytes: &[u8]) -> Result<Loaded, MethodError> {
    let model = Model::from_bytes(bytes, file, &KINDS).map_err(MethodError::Failed)?;
    if model.header.kind != kind.name() {
        let theirs = if kind == ModelKind::Dtfcn { ModelKind::Knn } else { ModelKind::Dtfcn };
        return Err(MethodError::Failed(format!(
            "{file} holds a {} model, not a {} model: use it with the {} method ({})",
            kind_short(theirs),
            kind_short(kind),
            kind_short(theirs),
            model.header.kind
        )));
    }
    let name = crate::method::supervised::stored_name(&model.header.name, file, &shipped_names())
        .map_err(MethodError::Failed)?;
    Ok(Loaded { info: model_info(&name, &model), model: Arc::new(model) })
}

/// `text` as one shell word (quoted when it holds a space), as the command line's provenance shows it.
fn shell_word(text: &str) -> String {
    if text.is_empty() || text.contains(|c: char| c.is_whitespace() || "'\"$`\\".contains(c)) {
        format!("'{}'", text.replace('\'', "'\\''"))
    } else {
        text.to_string()
    }
}

/// The `mocapseg train-dtfcn` (`train-knn`) command that trains the same model natively: a flag per
/// row of the table that is basic or not at its default, as `read` holds it.
pub fn train_command(kind: ModelKind, takes: &[String], labels: &str, name: &str, read: &serde_json::Value) -> String {
    let mut words = vec![format!("mocapseg train-{} --bvh", kind.name())];
    words.extend(takes.iter().map(|t| shell_word(t)));
    words.push(format!("--labels {}", shell_word(labels)));
    for spec in training_specs(kind) {
        let Some(value) = read.get(&spec.name) else { continue };
        if spec.basic || *value != spec.default {
            words.push(format!("--{} {}", spec.name.replace('_', "-"), shell_word(&field_text(value))));
        }
    }
    words.push(format!("--name {} -o {}", shell_word(name), shell_word(&format!("{name}.model"))));
    words.join(" ") + " (trained in the browser)"
}

/// Why a label CSV gives nothing to train on from the takes `takes`: its rows (naming `files`)
/// name none of them.
fn no_rows_for_takes(name: &str, takes: &[String], files: &[&str]) -> String {
    let mut named: Vec<&str> = Vec::new();
    for f in files {
        if !named.contains(f) {
            named.push(f);
        }
    }
    const SHOWN: usize = 5;
    let mut list = named.iter().take(SHOWN).map(|f| format!("`{f}`")).collect::<Vec<_>>().join(", ");
    if named.len() > SHOWN {
        list += &format!(" and {} more", named.len() - SHOWN);
    }
    let given = match takes {
        [] => "no take is given".to_string(),
        [one] => format!("no row is for the loaded take `{one}`"),
        [first, rest @ ..] => format!(
            "no row is for the loaded take `{first}` or the other takes given ({})",
            rest.iter().map(|t| format!("`{t}`")).collect::<Vec<_>>().join(", ")
        ),
    };
    format!("{name}: {given}; its rows name {list}")
}

/// A label CSV matched to the takes it names: what both trainings start from.
struct Prepared {
    name: String,
    /// The command that asked for the training, if not the page.
    command: Option<String>,
    labels_name: String,
    motions: Vec<Motion>,
    classes: Vec<String>,
    labels_per_take: Vec<Vec<Option<usize>>>,
    data_hash: String,
    /// The SHA-256 of each take's file, in the order of `motions` (the model's provenance).
    take_sha256: Vec<String>,
    used_rows: usize,
    left_out: Vec<String>,
    /// The take kept aside to choose the epoch (one of `motions`), if any.
    validation: Option<String>,
}

/// Checks the name, reads the label CSV and the takes it names; a refusal names `name`, `labels`
/// or `takes`.
fn prepare(ask: TrainingAsk, progress: &mut dyn Progress) -> Result<Prepared, MethodError> {
    let TrainingAsk { name, labels_name, labels, takes, command, validation, to_file, .. } = ask;
    let name = name.trim().to_string();
    let taken = if to_file { Vec::new() } else { shipped_names() };
    check_model_name(&name, &taken).map_err(|m| MethodError::param("name", m))?;
    let bad_labels = |m: String| MethodError::param("labels", m);
    let bad_takes = |m: String| MethodError::param("takes", m);
    let rows = crate::labels::read_csv(&labels, &labels_name).map_err(bad_labels)?;
    if rows.is_empty() {
        return Err(bad_labels(format!("{labels_name} has no rows, only its header")));
    }
    let names: Vec<String> = takes.iter().map(|(n, _)| n.clone()).collect();
    for (i, a) in names.iter().enumerate() {
        if names[..i].iter().any(|b| same_file(a, b)) {
            return Err(bad_takes(format!("{a} is given twice")));
        }
    }
    let named: Vec<usize> = (0..names.len()).filter(|&i| rows.iter().any(|r| same_file(&r.file, &names[i]))).collect();
    if named.is_empty() {
        let files: Vec<&str> = rows.iter().map(|r| r.file.as_str()).collect();
        return Err(bad_labels(no_rows_for_takes(&labels_name, &names, &files)));
    }
    let mut motions: Vec<Motion> = Vec::new();
    let mut hashed: Vec<(String, Vec<u8>)> = Vec::new();
    let mut takes: Vec<Option<(String, Vec<u8>)>> = takes.into_iter().map(Some).collect();
    for (k, &i) in named.iter().enumerate() {
        progress.step(&format!("reading {}", names[i]), k as f64 / named.len() as f64 * 0.5)?;
        let (file_name, bytes) = takes[i].take().unwrap_or_default();
        let loaded = crate::load::load_bytes(&file_name, &bytes, &mut |_| {}).map_err(|e| bad_takes(e.to_string()))?;
        motions.push(loaded.motion);
        // kept for the data hash of the model's provenance
        hashed.push((file_name, bytes));
    }
    let refs: Vec<&Motion> = motions.iter().collect();
    let left_out = rows_without_takes(&rows, &refs);
    let used_rows = rows.iter().filter(|r| refs.iter().any(|m| same_file(&m.name, &r.file))).count();
    let (classes, labels_per_take) =
        class_labels(&rows, &refs).map_err(|m| bad_labels(format!("{labels_name}: {m}")))?;
    Ok(Prepared {
        name,
        command,
        take_sha256: take_hashes(&motions.iter().map(|m| m.name.clone()).collect::<Vec<_>>(), &hashed),
        data_hash: data_hash(&hashed, labels.as_bytes()),
        labels_name,
        motions,
        classes,
        labels_per_take,
        used_rows,
        left_out,
        validation,
    })
}

impl Prepared {
    fn meta(&self, kind: ModelKind, options: &ModelOptions) -> ModelMeta {
        let takes: Vec<String> = self.motions.iter().map(|m| m.name.clone()).collect();
        ModelMeta {
            name: self.name.clone(),
            command: self
                .command
                .clone()
                .unwrap_or_else(|| train_command(kind, &takes, &self.labels_name, &self.name, &options.read)),
            data_hash: self.data_hash.clone(),
            decoding: options.decoding,
            unknown_threshold: options.unknown_threshold,
            // measured on what the model is taught (a validation take is not)
            travel: super::corpus::travel_of(
                &self
                    .motions
                    .iter()
                    .zip(&self.labels_per_take)
                    .filter(|(m, _)| !self.is_validation(&m.name))
                    .map(|(m, l)| (m, &l[..]))
                    .collect::<Vec<_>>(),
            ),
        }
    }

    /// `take` is the validation take.
    fn is_validation(&self, take: &str) -> bool {
        self.validation.as_deref().is_some_and(|v| same_file(v, take))
    }

    /// The SHA-256 of the files trained on (a validation take only chooses, it is not trained on).
    fn trained_sha256(&self) -> Vec<String> {
        self.motions
            .iter()
            .zip(&self.take_sha256)
            .filter(|(m, _)| !self.is_validation(&m.name))
            .map(|(_, h)| h.clone())
            .collect()
    }

    /// The status line of the finished training (`how`: "20 epochs", "stopped after 3 of 20 epochs").
    fn summary(&self, kind: ModelKind, how: &str, kept: Option<usize>) -> String {
        let left = if self.left_out.is_empty() {
            String::new()
        } else {
            format!(" (rows for {} left out: not loaded)", self.left_out.join(", "))
        };
        let kept = match (kept, &self.validation) {
            (Some(e), Some(v)) => format!(", the weights of epoch {e} kept (the best validation loss on {v})"),
            (Some(e), None) => format!(", the weights of epoch {e} kept"),
            (None, _) => String::new(),
        };
        let refs: Vec<&Motion> = self.motions.iter().collect();
        let rates: String = super::corpus::labels_at_another_rate(&refs, &self.labels_per_take)
            .into_iter()
            .map(|w| format!(" Warning: {w}"))
            .collect();
        format!(
            "Trained `{}` on {} of {}{left}: {} ({}), {how}{kept}. {} labels the take with it now.{rates}",
            self.name,
            counted(self.used_rows, "row"),
            self.labels_name,
            counted(self.classes.len(), "class"),
            self.classes.join(", "),
            kind_short(kind)
        )
    }
}

/// Starts the training of a model of `kind` on `ask`.
pub fn start_training(
    kind: ModelKind,
    ask: TrainingAsk,
    progress: &mut dyn Progress,
) -> Result<Box<dyn Training>, MethodError> {
    let options = options_from_json(kind, &ask.options)?;
    let start_from = ask.start_from.clone();
    let mut prepared = prepare(ask, progress)?;
    if let Some(v) = &prepared.validation {
        if kind == ModelKind::Knn && !options.choose_decoding {
            return Err(MethodError::param(
                "validation",
                "a k-NN has no epochs for a validation take to choose, only its decoding (choose_decoding)",
            ));
        }
        let names: Vec<&str> = prepared.motions.iter().map(|m| m.name.as_str()).collect();
        if !names.iter().any(|n| same_file(v, n)) {
            return Err(MethodError::param(
                "validation",
                format!("{v}: not among the takes trained on ({})", names.join(", ")),
            ));
        }
        if names.len() < 2 {
            return Err(MethodError::param(
                "validation",
                format!("{v} is the only take: nothing would be left to train on"),
            ));
        }
    }
    let start = match (&start_from, kind) {
        (None, _) => None,
        (Some(_), ModelKind::Knn) => {
            return Err(MethodError::param(
                "name",
                "a k-NN has no epochs to continue: train it again on all its takes",
            ));
        }
        (Some(from), ModelKind::Dtfcn) => Some(continued(from, &mut prepared)?),
    };
    match kind {
        ModelKind::Knn => {
            Ok(Box::new(KnnTraining { prepared, options, model: None, done: false, chosen: String::new() }))
        }
        ModelKind::Dtfcn => {
            let bad_option = |m: String| MethodError::params(m);
            if start.is_none() {
                options.train.network(prepared.classes.len()).check().map_err(bad_option)?;
            }
            progress.step("motion images", 0.5)?;
            let mut training = Vec::with_capacity(prepared.motions.len());
            let mut validation = Vec::new();
            for (m, l) in prepared.motions.iter().zip(&prepared.labels_per_take) {
                let take =
                    TrainingTake::new(m, l).map_err(|e| MethodError::param("takes", format!("{}: {e}", m.name)))?;
                if prepared.is_validation(&m.name) {
                    validation.push(take);
                } else {
                    training.push(take);
                }
            }
            let light: Vec<TrainingTake> = training
                .iter()
                .map(|t| TrainingTake {
                    name: t.name.clone(),
                    input: NetworkInput { values: Vec::new(), frames: 0, source_frames: Vec::new() },
                    labels: t.labels.clone(),
                })
                .collect();
            // a model continued keeps its networks (one, or an ensemble's), each trained on from its own weights
            let (starts, previous) = match start {
                None => ((0..options.train.members).map(|_| None).collect(), None),
                Some(((config, standardise, nets), previous)) => (
                    nets.into_iter().map(|n| Some((config.clone(), standardise.clone(), n))).collect::<Vec<_>>(),
                    Some(previous),
                ),
            };
            let mut members = Members { planned: starts.len(), starts, training, validation, next: 0 };
            let trainer = members
                .trainer(&prepared.classes, &options.train)
                .map_err(|m| MethodError::param("labels", format!("{}: {m}", prepared.labels_name)))?;
            progress.step("epoch 1", 0.0)?;
            Ok(Box::new(DtfcnTraining {
                prepared,
                trainer,
                members,
                finished: Vec::new(),
                takes: light,
                options,
                largest_loss: 0.0,
                previous,
            }))
        }
    }
}

/// The networks of a DT-FCN training (one, or an ensemble's), trained one after the other.
struct Members {
    /// Per network: the weights it continues from (none: a new network).
    starts: Vec<Option<(DtFcnConfig, Standardise, DtFcn)>>,
    /// What every network trains and validates on (motion images kept for the next network).
    training: Vec<TrainingTake>,
    validation: Vec<TrainingTake>,
    /// The network the next [`Members::trainer`] starts.
    next: usize,
    /// The networks asked for (a stop may leave some untrained).
    planned: usize,
}

impl Members {
    fn count(&self) -> usize {
        self.starts.len()
    }

    /// The trainer of the next network, with its own seed ([`TrainOptions::member`]).
    fn trainer(&mut self, classes: &[String], options: &TrainOptions) -> Result<Trainer, String> {
        let m = self.next;
        let start = self.starts.get_mut(m).ok_or("every network is trained")?.take();
        self.next += 1;
        let (training, validation) = if self.next == self.count() {
            (std::mem::take(&mut self.training), std::mem::take(&mut self.validation))
        } else {
            (self.training.clone(), self.validation.clone())
        };
        let options = options.member(m);
        match start {
            None => Trainer::new(training, validation, classes.to_vec(), options),
            Some(weights) => Trainer::resume(training, validation, classes.to_vec(), options, weights),
        }
    }

    /// No network is left to train (after a stop, none is started).
    fn stop(&mut self) {
        self.starts.truncate(self.next);
    }
}

/// A DT-FCN training: one epoch per step, the networks of an ensemble one after the other.
struct DtfcnTraining {
    prepared: Prepared,
    /// The network being trained.
    trainer: Trainer,
    members: Members,
    /// The networks trained before it.
    finished: Vec<super::training::Trained>,
    /// The takes trained on, without their motion images (what the model's provenance needs).
    takes: Vec<TrainingTake>,
    options: ModelOptions,
    largest_loss: f64,
    /// The model this training continues: its name and provenance.
    previous: Option<(String, crate::labeller::model::Provenance)>,
}

/// The weights, network and input scaling of the model `from` to continue training, and its
/// name and provenance; `prepared`'s classes put in the model's order (the labels may name them
/// in another order, or only some of them). Refused, naming `name` or `labels`, when `from` is
/// not a DT-FCN network or the labels have a class it does not know.
fn continued(
    from: &Loaded,
    prepared: &mut Prepared,
) -> Result<((DtFcnConfig, Standardise, Vec<DtFcn>), (String, crate::labeller::model::Provenance)), MethodError> {
    let name = &from.info.name;
    let model = from
        .model
        .downcast_ref::<Model>()
        .ok_or_else(|| MethodError::param("name", format!("`{name}` is not a DT-FCN model")))?;
    let h = &model.header;
    let (Some(Networks { config: network, nets }), Some(standardise)) = (networks_of(model), &h.standardise) else {
        return Err(MethodError::param("name", format!("`{name}` is not a DT-FCN network: nothing to continue")));
    };
    let unknown: Vec<&String> = prepared.classes.iter().filter(|c| !h.classes.contains(c)).collect();
    if !unknown.is_empty() {
        return Err(MethodError::param(
            "labels",
            format!(
                "{}: class{} {} not among `{name}`'s ({}): continuing keeps the model's classes; train a new model",
                prepared.labels_name,
                if unknown.len() == 1 { "" } else { "es" },
                unknown.iter().map(|c| format!("`{c}`")).collect::<Vec<_>>().join(", "),
                h.classes.join(", ")
            ),
        ));
    }
    let to_model: Vec<usize> =
        prepared.classes.iter().map(|c| h.classes.iter().position(|m| m == c).unwrap_or(0)).collect();
    for labels in &mut prepared.labels_per_take {
        for l in labels.iter_mut().flatten() {
            *l = to_model[*l];
        }
    }
    prepared.classes = h.classes.clone();
    Ok(((network.clone(), standardise.clone(), nets.clone()), (name.clone(), h.provenance.clone())))
}

/// With a validation take and `choose_decoding`: the model's decoding and unknown threshold chosen on the
/// validation take's labels by the model ([`crate::labeller::decode::choose`]; the take was not trained on), written into its
/// header; a sentence for the training's summary (empty when nothing was chosen).
fn choose_on_validation(model: &mut Model, prepared: &Prepared, options: &ModelOptions) -> Result<String, MethodError> {
    use crate::labeller::decode::{choose, Judged};
    let Some(v) = prepared.validation.as_deref().filter(|_| options.choose_decoding) else {
        return Ok(String::new());
    };
    let Some(i) = prepared.motions.iter().position(|m| same_file(v, &m.name)) else {
        return Ok(String::new());
    };
    let (motion, truth) = (&prepared.motions[i], &prepared.labels_per_take[i]);
    let labelled = super::method::label(model, motion, &mut crate::method::NoProgress)?;
    let judged = Judged { probabilities: &labelled.probabilities, source: &labelled.source, fps: labelled.fps, truth };
    let Some(c) = choose(std::slice::from_ref(&judged)) else {
        return Ok(String::new());
    };
    let raw = crate::segment::labelling::score(&judged.labels(&Decoding::RAW, DEFAULT_THRESHOLD), truth);
    let decoding = (!c.decoding.is_raw(labelled.fps)).then_some(c.decoding);
    model.header.decoding = decoding;
    model.header.unknown_threshold = c.threshold as f32;
    let how = decoding.map_or_else(
        || "the raw per-frame labels".to_string(),
        |d| format!("runs ≥ {} s, switch cost {}", d.min_duration_s, d.switch_cost),
    );
    let scores = |s: &crate::segment::labelling::LabellingScores| {
        format!("frame accuracy {:.0} %, edit {:.0}, F1@50 {:.0}", 100.0 * s.frame_accuracy, s.edit, s.f1[2])
    };
    Ok(format!(
        " Decoding chosen on {}: {how}, unknown below {} ({} there; the raw labels at {DEFAULT_THRESHOLD}: {}).",
        motion.name,
        c.threshold,
        scores(&c.scores),
        scores(&raw)
    ))
}

/// An epoch's report as a step's: of network `member` (0-based) of `members`.
fn epoch_step(r: &EpochReport, largest_loss: f64, member: usize, members: usize) -> StepReport {
    let network = if members > 1 { format!("Network {} of {members} · ", member + 1) } else { String::new() };
    StepReport {
        step: member * r.epochs + r.epoch,
        steps: members * r.epochs,
        line: format!(
            "{network}Epoch {} of {} · loss {:.3} · accuracy {:.0} %{}",
            r.epoch,
            r.epochs,
            r.loss,
            100.0 * r.train_accuracy,
            match (r.validation_loss, r.validation_accuracy) {
                (Some(l), Some(a)) =>
                    format!(" · validation loss {l:.3} · accuracy {:.0} %{}", 100.0 * a, if r.best { " *" } else { "" }),
                _ => String::new(),
            }
        ),
        values: vec![
            ("loss".into(), if largest_loss > 0.0 { r.loss / largest_loss } else { 0.0 }),
            ("accuracy".into(), r.train_accuracy),
        ],
        best: r.best,
    }
}

impl Training for DtfcnTraining {
    fn step(&mut self, _progress: &mut dyn Progress) -> Result<StepReport, MethodError> {
        if self.trainer.done() && self.members.next < self.members.count() {
            // the next network of the ensemble
            let next = self
                .members
                .trainer(&self.prepared.classes, &self.options.train)
                .map_err(|m| MethodError::param("labels", format!("{}: {m}", self.prepared.labels_name)))?;
            let done = std::mem::replace(&mut self.trainer, next);
            self.finished.push(done.finish().map_err(MethodError::Failed)?);
            self.largest_loss = 0.0;
        }
        let report = self.trainer.epoch().map_err(MethodError::Failed)?;
        if report.loss.is_finite() {
            self.largest_loss = self.largest_loss.max(report.loss);
        }
        Ok(epoch_step(&report, self.largest_loss, self.members.next - 1, self.members.count()))
    }

    fn done(&self) -> bool {
        self.trainer.done() && self.members.next >= self.members.count()
    }

    fn stop(&mut self) {
        self.trainer.stop();
        self.members.stop();
    }

    fn finish(self: Box<Self>) -> Result<Trained, MethodError> {
        let DtfcnTraining { prepared, trainer, mut finished, takes, options, previous, members, .. } = *self;
        finished.push(trainer.finish().map_err(MethodError::Failed)?);
        let trained = finished;
        let networks = trained.len();
        let (ran, best) = (trained[0].reports.len(), trained[0].best_epoch);
        let stopped = trained.iter().any(|t| t.stopped) || networks < members.planned;
        let per_network: Vec<String> = trained.iter().map(|t| t.reports.len().to_string()).collect();
        let meta = prepared.meta(ModelKind::Dtfcn, &options);
        let mut model =
            model_from(trained, &takes, &prepared.classes, &options.train, &meta).map_err(MethodError::Failed)?;
        let p = &mut model.header.provenance;
        // the files of the takes trained on (a validation take only chose the epoch)
        p.take_sha256 = prepared.trained_sha256();
        let mut how = if members.planned > 1 {
            // an ensemble: each network's epochs, and whether a stop left some untrained
            let of = if networks < members.planned {
                format!(" (stopped: {networks} of {} networks)", members.planned)
            } else if stopped {
                " (stopped)".into()
            } else {
                String::new()
            };
            format!("an ensemble of {networks} networks of {} epochs{of}", per_network.join(", "))
        } else if stopped {
            format!("stopped after {ran} of {} epochs", options.train.epochs)
        } else {
            format!("{ran} epoch{}", if ran == 1 { "" } else { "s" })
        };
        if let Some((from, before)) = &previous {
            // the model's history goes on: its epochs before, and every take it has seen
            how = format!("{how} more (continued from `{from}`, {} epochs before)", before.epochs_run);
            p.continued_from(from, before);
        }
        let chosen = choose_on_validation(&mut model, &prepared, &options)?;
        let bytes = model.to_bytes().map_err(MethodError::Failed)?;
        let network = networks_of(&model)
            .map(|n| format!(" The {}.", n.config.describe(crate::labeller::input::NETWORK_FPS)))
            .unwrap_or_default();
        let report = TrainingReport {
            summary: format!("{}{network}{chosen}", prepared.summary(ModelKind::Dtfcn, &how, Some(best))),
            columns: Vec::new(),
            rows: Vec::new(),
            stopped,
        };
        Ok(Trained {
            model: Loaded { info: model_info(&prepared.name, &model), model: Arc::new(model) },
            bytes,
            report,
        })
    }
}

/// A k-NN fit: one step.
struct KnnTraining {
    prepared: Prepared,
    options: ModelOptions,
    model: Option<Model>,
    done: bool,
    /// What the validation take chose, for the summary.
    chosen: String,
}

impl Training for KnnTraining {
    fn step(&mut self, _progress: &mut dyn Progress) -> Result<StepReport, MethodError> {
        let p = &self.prepared;
        // the validation take, if any, only chooses the decoding: it is not among the windows
        let takes: Vec<(&Motion, &[Option<usize>])> = p
            .motions
            .iter()
            .zip(&p.labels_per_take)
            .filter(|(m, _)| !p.is_validation(&m.name))
            .map(|(m, l)| (m, &l[..]))
            .collect();
        let meta = p.meta(ModelKind::Knn, &self.options);
        let mut model = fit_knn_model(&takes, &p.classes, &meta)
            .map_err(|m| MethodError::param("labels", format!("{}: {m}", p.labels_name)))?;
        model.header.provenance.take_sha256 = p.trained_sha256();
        self.chosen = choose_on_validation(&mut model, p, &self.options)?;
        let frames = model.header.provenance.frames;
        self.model = Some(model);
        self.done = true;
        Ok(StepReport {
            step: 1,
            steps: 1,
            line: format!("Fitted on {frames} labelled frames"),
            values: Vec::new(),
            best: true,
        })
    }

    fn done(&self) -> bool {
        self.done
    }

    fn stop(&mut self) {
        self.done = true;
    }

    fn finish(self: Box<Self>) -> Result<Trained, MethodError> {
        let KnnTraining { prepared, model, chosen, .. } = *self;
        let model = model.ok_or_else(|| MethodError::Failed("the k-NN was stopped before its fit".into()))?;
        let bytes = model.to_bytes().map_err(MethodError::Failed)?;
        let report = TrainingReport {
            summary: format!("{}{chosen}", prepared.summary(ModelKind::Knn, "fitted", None)),
            columns: Vec::new(),
            rows: Vec::new(),
            stopped: false,
        };
        Ok(Trained {
            model: Loaded { info: model_info(&prepared.name, &model), model: Arc::new(model) },
            bytes,
            report,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_options_table_reads_its_own_defaults_and_names_what_it_refuses() {
        let options_from_json = |v: &serde_json::Value| options_from_json(ModelKind::Dtfcn, v).map(|o| o.train);
        for kind in [ModelKind::Dtfcn, ModelKind::Knn] {
            let defaults: serde_json::Map<String, serde_json::Value> =
                training_specs(kind).into_iter().map(|s| (s.name, s.default)).collect();
            let defaults = serde_json::Value::Object(defaults);
            let read = super::options_from_json(kind, &defaults).unwrap();
            assert_eq!((&read.train, read.decoding, &read.read), (&TrainOptions::default(), None, &defaults));
            assert_eq!(super::options_from_json(kind, &serde_json::json!({})).unwrap(), read);
        }
        for (json, param) in [
            (serde_json::json!({"epochs": 0}), "epochs"),
            (serde_json::json!({"label_noise": 2}), "label_noise"),
            (serde_json::json!({"mask_s": 400}), "mask_s"),
            (serde_json::json!({"padding": "mirror"}), "padding"),
            (serde_json::json!({"image_rows": 1000}), "image_rows"),
            (serde_json::json!({"width": 5}), "width"),
            (serde_json::json!({"filters": []}), "filters"),
            (serde_json::json!({"filters": [8, 0]}), "filters"),
            (serde_json::json!({"crop_frames": 8}), "crop_frames"),
            (serde_json::json!({"batch": 0}), "batch"),
            (serde_json::json!({"augment": ["spin"]}), "augment"),
            (serde_json::json!({"epochs": "many"}), "epochs"),
            (serde_json::json!({"patience": 0}), "patience"),
            (serde_json::json!({"average_last": -1}), "average_last"),
            (serde_json::json!({"min_duration_s": 31}), "min_duration_s"),
            (serde_json::json!({"switch_cost": -1}), "switch_cost"),
            (serde_json::json!({"unknown_threshold": 1.5}), "unknown_threshold"),
        ] {
            let e = options_from_json(&json).unwrap_err();
            assert_eq!(e.param_name(), Some(param), "{json}: {e}");
            assert!(e.to_string().contains(&param.replace('_', " ")) || param == "augment", "{e}");
        }
        let e = options_from_json(&serde_json::json!({"nope": 1})).unwrap_err();
        assert_eq!(e.param_name(), None);
        let o = options_from_json(&serde_json::json!({"augment": ["mirror", "warp"], "filters": [8, 8]})).unwrap();
        assert!(o.augment.mirror && o.augment.time_warp && !o.augment.yaw);
        assert_eq!(o.filters, vec![8, 8]);
        let o = options_from_json(&serde_json::json!({"padding": "edge", "image_rows": 224})).unwrap();
        assert_eq!((o.padding, o.image_rows), (Padding::Edge, Some(224)));
        assert_eq!(o.network(7).first_layer_inputs(), 672);
        assert_eq!(options_from_json(&serde_json::json!({"average_last": 10})).unwrap().average_last, 10);
        // the decoding rows make the model's decoding, for the k-NN too; it has no network rows
        let o = super::options_from_json(ModelKind::Knn, &serde_json::json!({"min_duration_s": 2, "switch_cost": 150}))
            .unwrap();
        assert_eq!(o.decoding, Some(Decoding { min_duration_s: 2.0, switch_cost: 150.0 }));
        // the model's unknown threshold (its runs' unless they ask for another), 0.5 unless given, for both kinds
        assert_eq!(o.unknown_threshold, DEFAULT_THRESHOLD);
        for kind in [ModelKind::Dtfcn, ModelKind::Knn] {
            let o = super::options_from_json(kind, &serde_json::json!({"unknown_threshold": 0.8})).unwrap();
            assert_eq!(o.unknown_threshold, 0.8, "{kind:?}");
        }
        let e = super::options_from_json(ModelKind::Knn, &serde_json::json!({"epochs": 3})).unwrap_err();
        assert!(e.to_string().contains("epochs"), "{e}");
    }

    /// A model trained here records the SHA-256 of each training take's file, in its provenance
    /// and its card, so the page can tell a training take by its content (a renamed copy too).
    #[test]
    fn a_trained_model_records_each_takes_file_hash() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures");
        let takes: Vec<(String, Vec<u8>)> =
            ["35_01.bvh", "02_01.bvh"].iter().map(|f| (f.to_string(), std::fs::read(dir.join(f)).unwrap())).collect();
        let expected: Vec<String> = takes.iter().map(|(_, b)| crate::labeller::model::sha256_hex(b)).collect();
        let ask = TrainingAsk {
            name: "hashed".into(),
            labels_name: "l.csv".into(),
            labels: "file,start_frame,end_frame,label\n35_01.bvh,0,199,stand\n35_01.bvh,200,357,reach\n\
                     02_01.bvh,0,150,walk\n02_01.bvh,151,342,stand\n"
                .into(),
            takes,
            options: serde_json::json!({}),
            command: None,
            start_from: None,
            validation: None,
            to_file: false,
        };
        let mut training = start_training(ModelKind::Knn, ask, &mut crate::method::NoProgress).unwrap();
        while !training.done() {
            training.step(&mut crate::method::NoProgress).unwrap();
        }
        let trained = training.finish().unwrap();
        let card = &trained.model.info.card;
        assert_eq!(card.takes, vec!["35_01.bvh".to_string(), "02_01.bvh".to_string()]);
        assert_eq!(card.take_sha256, expected);
        assert!(card.held_out.is_none(), "a model trained here has no held-out figure");
        let back = Model::from_bytes(&trained.bytes, "hashed.model", &KINDS).unwrap();
        assert_eq!(back.header.provenance.take_sha256, expected, "in the file too");
    }

    /// A shipped model's name: refused for the page's store (it would hide the shipped model), taken for a
    /// model that goes to a file (how the shipped models are made on the command line).
    #[test]
    fn a_shipped_name_is_refused_for_the_store_and_taken_for_a_file() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures");
        let ask = |to_file| TrainingAsk {
            name: "exercises".into(),
            labels_name: "l.csv".into(),
            labels: "file,start_frame,end_frame,label\n35_01.bvh,0,199,stand\n35_01.bvh,200,357,reach\n".into(),
            takes: vec![("35_01.bvh".into(), std::fs::read(dir.join("35_01.bvh")).unwrap())],
            to_file,
            ..TrainingAsk::default()
        };
        let refused = start_training(ModelKind::Knn, ask(false), &mut crate::method::NoProgress).err().unwrap();
        assert_eq!(refused.param_name(), Some("name"), "{refused}");
        let mut training = start_training(ModelKind::Knn, ask(true), &mut crate::method::NoProgress).unwrap();
        while !training.done() {
            training.step(&mut crate::method::NoProgress).unwrap();
        }
        assert_eq!(training.finish().unwrap().model.info.name, "exercises");
    }

    /// Continuing a DT-FCN training keeps the model's classes (in its order, whatever the labels'
    /// order), network and input scaling, counts the epochs on, and refuses a class it does not know.
    #[test]
    fn a_dtfcn_training_continues_from_a_model_of_the_users() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures");
        let take = || vec![("35_01.bvh".to_string(), std::fs::read(dir.join("35_01.bvh")).unwrap())];
        let ask = |labels: &str, start_from: Option<Loaded>| TrainingAsk {
            name: "mine".into(),
            labels_name: "l.csv".into(),
            labels: format!("file,start_frame,end_frame,label\n{labels}"),
            takes: take(),
            options: serde_json::json!({"epochs": 1, "filters": [4, 4], "width": 2}),
            command: None,
            start_from,
            validation: None,
            to_file: false,
        };
        let train = |ask: TrainingAsk| {
            let mut t = start_training(ModelKind::Dtfcn, ask, &mut crate::method::NoProgress)?;
            while !t.done() {
                t.step(&mut crate::method::NoProgress)?;
            }
            t.finish()
        };
        let first = train(ask("35_01.bvh,0,199,stand\n35_01.bvh,200,357,reach\n", None)).unwrap();
        assert_eq!(first.model.info.card.epochs_run, Some(1));
        // the labels name the classes in the other order: the model's order is kept
        let more = train(ask("35_01.bvh,0,157,reach\n35_01.bvh,158,357,stand\n", Some(first.model.clone()))).unwrap();
        let card = &more.model.info.card;
        assert_eq!(card.classes, vec!["stand".to_string(), "reach".to_string()]);
        assert_eq!((card.epochs_run, card.best_epoch), (Some(2), Some(2)));
        // both runs labelled all 358 frames of the take: the continued model learnt from both
        let once = first.model.info.card.frames.unwrap();
        assert!(once > 0);
        assert_eq!(card.frames, Some(2 * once), "the earlier model's frames are the continued one's too");
        assert!(card.command.contains("continued from `mine` after its 1 epochs"), "{}", card.command);
        assert!(more.report.summary.contains("continued from `mine`"), "{}", more.report.summary);
        let (a, b) =
            (first.model.model.downcast_ref::<Model>().unwrap(), more.model.model.downcast_ref::<Model>().unwrap());
        assert_eq!(a.header.standardise, b.header.standardise, "the input scaling is the model's");
        assert_eq!(a.header.network, b.header.network);
        assert_ne!(first.bytes, more.bytes, "the weights moved");
        let e = train(ask("35_01.bvh,0,199,stand\n35_01.bvh,200,357,jump\n", Some(first.model.clone()))).err().unwrap();
        assert_eq!(e.param_name(), Some("labels"));
        assert!(e.to_string().contains("`jump` not among `mine`'s (stand, reach)"), "{e}");
        let knn_ask = TrainingAsk {
            options: serde_json::json!({}),
            ..ask("35_01.bvh,0,199,stand\n35_01.bvh,200,357,reach\n", Some(first.model))
        };
        let knn = start_training(ModelKind::Knn, knn_ask, &mut crate::method::NoProgress);
        assert_eq!(knn.err().unwrap().param_name(), Some("name"));
    }

    /// A validation take chooses the model's decoding and unknown threshold on its labels by the finished model, for
    /// both kinds (the header holds what [`crate::labeller::decode::choose`] chooses there); `choose_decoding` off, the
    /// rows as given.
    #[test]
    fn a_validation_take_chooses_the_models_decoding() {
        use crate::labeller::decode::{choose, Judged};
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures");
        let file = |n: &str| (n.to_string(), std::fs::read(dir.join(n)).unwrap());
        let ask = |options: serde_json::Value| TrainingAsk {
            name: "mine".into(),
            labels_name: "l.csv".into(),
            labels: "file,start_frame,end_frame,label\n35_01.bvh,0,199,stand\n35_01.bvh,200,357,reach\n\
                     02_01.bvh,0,150,stand\n02_01.bvh,151,342,reach\n"
                .into(),
            takes: vec![file("02_01.bvh"), file("35_01.bvh")],
            options,
            command: None,
            start_from: None,
            validation: Some("35_01.bvh".into()),
            to_file: false,
        };
        let train = |kind, options| {
            let mut t = start_training(kind, ask(options), &mut crate::method::NoProgress)?;
            while !t.done() {
                t.step(&mut crate::method::NoProgress)?;
            }
            t.finish()
        };
        let validation = crate::load::load_bytes("35_01.bvh", &file("35_01.bvh").1, &mut |_| {}).unwrap().motion;
        let truth: Vec<Option<usize>> = (0..validation.frames()).map(|f| Some(usize::from(f >= 200))).collect();
        for kind in [ModelKind::Dtfcn, ModelKind::Knn] {
            let options = serde_json::json!({"epochs": 2, "filters": [4, 4], "width": 2, "min_duration_s": 3});
            let options = if kind == ModelKind::Knn { serde_json::json!({"min_duration_s": 3}) } else { options };
            let trained = train(kind, options.clone()).unwrap();
            let model = trained.model.model.downcast_ref::<Model>().unwrap();
            let labelled = super::super::method::label(model, &validation, &mut crate::method::NoProgress).unwrap();
            let judged = Judged {
                probabilities: &labelled.probabilities,
                source: &labelled.source,
                fps: labelled.fps,
                truth: &truth,
            };
            let c = choose(&[judged]).unwrap();
            let h = &model.header;
            assert_eq!(h.decoding, (!c.decoding.is_raw(labelled.fps)).then_some(c.decoding), "{kind:?}");
            assert_eq!(h.unknown_threshold, c.threshold as f32, "{kind:?}");
            assert!(trained.report.summary.contains("Decoding chosen on 35_01.bvh: "), "{}", trained.report.summary);
            assert_eq!(h.provenance.takes, vec!["02_01.bvh".to_string()], "the validation take is not trained on");
            // not chosen: the rows
            let mut off = options;
            off["choose_decoding"] = false.into();
            if kind == ModelKind::Knn {
                let e = train(kind, off).err().unwrap();
                assert_eq!(e.param_name(), Some("validation"), "{e}");
                continue;
            }
            let kept = train(kind, off).unwrap();
            let h = &kept.model.model.downcast_ref::<Model>().unwrap().header;
            assert_eq!(
                (h.decoding, h.unknown_threshold),
                (Some(Decoding { min_duration_s: 3.0, switch_cost: 0.0 }), DEFAULT_THRESHOLD as f32)
            );
            assert!(!kept.report.summary.contains("Decoding chosen"), "{}", kept.report.summary);
        }
    }

    /// An ensemble trains its networks one after the other (steps counted over all of them, each line naming its
    /// network), each the network its seed trains alone; continued, every network trains on from its own weights;
    /// stopped during the first network, the model holds the networks trained and says that it was stopped.
    #[test]
    fn an_ensemble_trains_its_networks_in_turn_and_continues_each() {
        use super::super::training::weights_of;
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures");
        let ask = |options: serde_json::Value, start_from: Option<Loaded>| TrainingAsk {
            name: "mine".into(),
            labels_name: "l.csv".into(),
            labels: "file,start_frame,end_frame,label\n35_01.bvh,0,199,stand\n35_01.bvh,200,357,reach\n".into(),
            takes: vec![("35_01.bvh".to_string(), std::fs::read(dir.join("35_01.bvh")).unwrap())],
            options,
            command: None,
            start_from,
            validation: None,
            to_file: false,
        };
        let options = |seed: u64, members: usize| serde_json::json!({"epochs": 2, "filters": [4, 4], "width": 2, "seed": seed, "members": members});
        let train = |ask: TrainingAsk, stop_after: usize| {
            let mut t = start_training(ModelKind::Dtfcn, ask, &mut crate::method::NoProgress).unwrap();
            let mut steps = Vec::new();
            while !t.done() {
                steps.push(t.step(&mut crate::method::NoProgress).unwrap());
                if steps.len() == stop_after {
                    t.stop();
                }
            }
            (t.finish().unwrap(), steps)
        };
        let nets = |t: &Trained| {
            let nets = networks_of(t.model.model.downcast_ref::<Model>().unwrap()).unwrap();
            nets.nets.iter().map(weights_of).collect::<Vec<_>>()
        };
        let (two, steps) = train(ask(options(4, 2), None), usize::MAX);
        assert_eq!(steps.iter().map(|s| (s.step, s.steps)).collect::<Vec<_>>(), vec![(1, 4), (2, 4), (3, 4), (4, 4)]);
        assert!(steps[0].line.starts_with("Network 1 of 2 · Epoch 1 of 2"), "{}", steps[0].line);
        assert!(steps[3].line.starts_with("Network 2 of 2 · Epoch 2 of 2"), "{}", steps[3].line);
        let alone: Vec<Vec<Vec<f32>>> =
            [4, 5].iter().flat_map(|&seed| nets(&train(ask(options(seed, 1), None), usize::MAX).0)).collect();
        assert_eq!(nets(&two), alone, "each network is its seed's trained alone");
        assert!(two.report.summary.contains("an ensemble of 2 networks of 2, 2 epochs"), "{}", two.report.summary);
        assert!(two.model.info.origin.contains("an ensemble of 2 networks"), "{}", two.model.info.origin);
        let json = header_json(two.model.model.downcast_ref::<Model>().unwrap());
        assert_eq!(
            (json["networks"].as_u64(), json["parameters"].as_u64()),
            (Some(2), json["parameters_per_network"].as_u64().map(|p| 2 * p))
        );
        let header = &two.model.model.downcast_ref::<Model>().unwrap().header;
        assert_eq!(
            header.provenance.members.iter().map(|m| (m.seed, m.epochs_run)).collect::<Vec<_>>(),
            [(4, 2), (5, 2)]
        );
        assert!(header.provenance.command.contains("--members 2"), "{}", header.provenance.command);
        // continued (the table's members ignored, as its network shape is): both networks train on
        let (more, steps) = train(ask(options(4, 1), Some(two.model.clone())), usize::MAX);
        assert_eq!(steps.len(), 4);
        let (before, after) = (nets(&two), nets(&more));
        assert_eq!(after.len(), 2);
        assert!(before.iter().zip(&after).all(|(b, a)| b != a), "every network moved");
        let p = &more.model.model.downcast_ref::<Model>().unwrap().header.provenance;
        assert_eq!(p.members.iter().map(|m| m.epochs_run).collect::<Vec<_>>(), [4, 4], "each counts on from its own");
        // stopped in the first network: the second is never started
        let (stopped, steps) = train(ask(options(4, 2), None), 1);
        assert_eq!(steps.len(), 1);
        assert_eq!(nets(&stopped).len(), 1);
        assert!(stopped.report.stopped);
        assert!(stopped.report.summary.contains("stopped: 1 of 2 networks"), "{}", stopped.report.summary);
    }

    #[test]
    fn the_provenance_command_repeats_every_basic_row_and_every_changed_one_as_its_flag() {
        let read = options_from_json(
            ModelKind::Dtfcn,
            &serde_json::json!({"epochs": 2, "filters": [8, 8], "switch_cost": 10, "augment": ["mirror"]}),
        )
        .unwrap()
        .read;
        let command = train_command(ModelKind::Dtfcn, &["a b.bvh".into()], "l.csv", "m", &read);
        assert_eq!(
            command,
            "mocapseg train-dtfcn --bvh 'a b.bvh' --labels l.csv --epochs 2 --label-noise 0.0 --mask-s 0.0 --augment mirror \
             --width 3 --filters 8,8 --switch-cost 10.0 --name m -o m.model (trained in the browser)"
        );
        let read = options_from_json(ModelKind::Knn, &serde_json::json!({})).unwrap().read;
        assert_eq!(
            train_command(ModelKind::Knn, &["t.bvh".into()], "l.csv", "k", &read),
            "mocapseg train-knn --bvh t.bvh --labels l.csv --name k -o k.model (trained in the browser)"
        );
    }
}
