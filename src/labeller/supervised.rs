//! Both labellers as supervised methods ([`crate::method::supervised`]), the part they share: the decoding's rows of
//! their training tables, reading model files, what the page and `model-info` show of a model, and a training's start
//! — a label CSV matched to the takes it names — and end: the decoding chosen on a validation take and the command
//! that trains the same model natively, for the model's provenance. Each method's own rows and training (an epoch per
//! step for the network, one fit for the k-NN) are its own (`methods/dtfcn/supervised.rs`,
//! `methods/knn/supervised.rs`).

use super::corpus::{class_labels, labels_at_another_rate, rows_without_takes, travel_of, ModelMeta};
use super::decode::Decoding;
use super::method::{label, Kind, DEFAULT_THRESHOLD, MAX_MIN_DURATION_S, MAX_SWITCH_COST};
use super::model::{data_hash, take_hashes, Model};
use super::shipped;
use crate::labels::same_file;
use crate::method::cards::ModelCard;
use crate::method::form::field_text;
use crate::method::supervised::{
    check_model_name, option_values, read_option_rows, Loaded, ModelInfo, Supervision, TrainingAsk, TrainingOption,
};
use crate::method::{counted, MethodError, ParamKind, Progress};
use crate::motion::Motion;

/// The names of the shipped models, as the store and the forms want them.
pub fn shipped_names() -> Vec<String> {
    shipped::NAMES.iter().map(|s| s.to_string()).collect()
}

/// What a labeller's training table reads: its trainer's options `T` (DT-FCN's; the k-NN has none) and the decoding
/// and unknown threshold its model keeps.
#[derive(Debug, Clone, PartialEq)]
pub struct Choices<T> {
    pub train: T,
    pub min_duration_s: f64,
    pub switch_cost: f64,
    pub unknown_threshold: f64,
    /// With a validation take: the decoding and threshold are chosen on it instead ([`choose_on_validation`]).
    pub choose_decoding: bool,
}

impl<T: Default> Default for Choices<T> {
    fn default() -> Self {
        Choices {
            train: T::default(),
            min_duration_s: 0.0,
            switch_cost: 0.0,
            unknown_threshold: DEFAULT_THRESHOLD,
            choose_decoding: true,
        }
    }
}

/// An option's JSON value as a whole number, a number, a list of words (its row's check accepted it as one).
pub fn whole(v: &serde_json::Value) -> usize {
    v.as_u64().unwrap_or(0) as usize
}

pub fn number(v: &serde_json::Value) -> f64 {
    v.as_f64().unwrap_or(0.0)
}

pub fn words(v: &serde_json::Value) -> Vec<&str> {
    v.as_array().map_or(Vec::new(), |a| a.iter().filter_map(serde_json::Value::as_str).collect())
}

/// The rows both labellers' tables end with, each declared once: the decoding and unknown threshold their model
/// keeps, and whether a validation take chooses them.
pub fn decoding_rows<T>() -> [TrainingOption<Choices<T>>; 4] {
    [
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
    ]
}

/// A training's options as read from its table: the trainer's, the decoding its model keeps, and
/// every row's value as read (what the model's provenance repeats).
#[derive(Debug, Clone, PartialEq)]
pub struct ModelOptions<T> {
    pub train: T,
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

/// Reads and checks training options against a labeller's table `rows` (`short` names the method): a refusal names
/// the option.
pub fn read_options<T: Default>(
    rows: &[TrainingOption<Choices<T>>],
    value: &serde_json::Value,
    short: &str,
) -> Result<ModelOptions<T>, MethodError> {
    let c: Choices<T> = read_option_rows(value, rows, short)?;
    Ok(ModelOptions {
        decoding: decoding_of(c.min_duration_s, c.switch_cost),
        unknown_threshold: c.unknown_threshold,
        choose_decoding: c.choose_decoding,
        read: option_values(rows, &c),
        train: c.train,
    })
}

/// The declaration of the labelling method of `kind`.
pub fn supervision(kind: &dyn Kind) -> Supervision {
    Supervision {
        labels_header: "file,start_frame,end_frame,label".into(),
        labels_help:
            "Frames of the file (0-based, inclusive), any label. Its rows for the take on screen and the takes \
                      you add train a model in this tab; the model then labels the take on screen."
                .into(),
        more_takes: true,
        model_extension: "model".into(),
        shipped: shipped_names(),
        training: kind.training_specs(),
        step_name: kind.step_name().into(),
        trains_on_my_labels: kind.trains_on_my_labels(),
        labels_classes: true,
        // DT-FCN: the epoch and the decoding; the k-NN: the decoding
        validation_take: true,
        without_labels: None,
    }
}

/// What the page and `model-info` show of `model`, stored as `name`.
pub fn model_info(kind: &dyn Kind, name: &str, model: &Model) -> ModelInfo {
    let h = &model.header;
    let p = &h.provenance;
    let mut origin = format!("{} ({})", counted(h.classes.len(), "class"), h.classes.join(", "));
    if !p.takes.is_empty() {
        origin += &format!(", trained on {} labelled frames of {}", p.frames, p.takes.join(", "));
    }
    if kind.has_epochs() && p.members.len() > 1 {
        let kept: Vec<String> =
            p.members.iter().map(|m| format!("seed {}: epoch {} of {}", m.seed, m.best_epoch, m.epochs_run)).collect();
        origin += &format!(
            ", an ensemble of {} networks (their probabilities averaged; {} kept)",
            p.members.len(),
            kept.join(", ")
        );
    } else if kind.has_epochs() && p.epochs_run > 0 {
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
            epochs_run: kind.has_epochs().then_some(p.epochs_run),
            best_epoch: kind.has_epochs().then_some(p.best_epoch),
            command: p.command.clone(),
            origin: String::new(),
            held_out: None,
        },
    }
}

/// A model's header as `mocapseg model-info` prints it: without the input's standardisation, with what its kind
/// adds ([`Kind::details`]: the network's parameter count and receptive field).
pub fn header_json(kind: &dyn Kind, model: &Model) -> serde_json::Value {
    let mut h = serde_json::to_value(&model.header).unwrap_or_default();
    if let Some(o) = h.as_object_mut() {
        o.remove("standardise");
        kind.details(model, o);
    }
    h
}

/// Reads a model file of `kind` (`file` names it; `kinds`: the kinds a model file may be of, so that one of another
/// kind is named): stored under the name inside it, or its stem.
pub fn read_model(kind: &dyn Kind, kinds: &[&dyn Kind], file: &str, bytes: &[u8]) -> Result<Loaded, MethodError> {
    let model = Model::from_bytes(bytes, file, kinds).map_err(MethodError::Failed)?;
    if model.header.kind != kind.name() {
        let theirs = kinds.iter().find(|k| k.name() == model.header.kind).map_or("", |k| k.short());
        return Err(MethodError::Failed(format!(
            "{file} holds a {theirs} model, not a {} model: use it with the {theirs} method ({})",
            kind.short(),
            model.header.kind
        )));
    }
    let name = crate::method::supervised::stored_name(&model.header.name, file, &shipped_names())
        .map_err(MethodError::Failed)?;
    Ok(Loaded { info: model_info(kind, &name, &model), model: std::sync::Arc::new(model) })
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
pub fn train_command(kind: &dyn Kind, takes: &[String], labels: &str, name: &str, read: &serde_json::Value) -> String {
    let mut words = vec![format!("mocapseg train-{} --bvh", kind.name())];
    words.extend(takes.iter().map(|t| shell_word(t)));
    words.push(format!("--labels {}", shell_word(labels)));
    for spec in kind.training_specs() {
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
pub struct Prepared {
    pub name: String,
    /// The command that asked for the training, if not the page.
    pub command: Option<String>,
    pub labels_name: String,
    pub motions: Vec<Motion>,
    pub classes: Vec<String>,
    pub labels_per_take: Vec<Vec<Option<usize>>>,
    pub data_hash: String,
    /// The SHA-256 of each take's file, in the order of `motions` (the model's provenance).
    pub take_sha256: Vec<String>,
    pub used_rows: usize,
    pub left_out: Vec<String>,
    /// The take kept aside to choose the epoch (one of `motions`), if any.
    pub validation: Option<String>,
}

/// Checks the name, reads the label CSV and the takes it names; a refusal names `name`, `labels`
/// or `takes`.
pub fn prepare(
    ask: TrainingAsk,
    (method, work): (&str, crate::method::Work),
    progress: &mut dyn Progress,
) -> Result<Prepared, MethodError> {
    let TrainingAsk { name, labels_name, labels, takes, command, validation, to_file, limits, .. } = ask;
    // every take's file, motion and the method's arrays, held at once: checked as each is read (issue 49)
    let mut hold = crate::method::work::TrainingHold::new(method, work, limits);
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
        hold.add(&loaded.motion, bytes.len())?;
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
    /// What to call the model of `kind` and how it was made, with the options `options` read.
    pub fn meta<T>(&self, kind: &dyn Kind, options: &ModelOptions<T>) -> ModelMeta {
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
            travel: travel_of(
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
    pub fn is_validation(&self, take: &str) -> bool {
        self.validation.as_deref().is_some_and(|v| same_file(v, take))
    }

    /// The SHA-256 of the files trained on (a validation take only chooses, it is not trained on).
    pub fn trained_sha256(&self) -> Vec<String> {
        self.motions
            .iter()
            .zip(&self.take_sha256)
            .filter(|(m, _)| !self.is_validation(&m.name))
            .map(|(_, h)| h.clone())
            .collect()
    }

    /// The status line of the finished training (`how`: "20 epochs", "stopped after 3 of 20 epochs").
    pub fn summary(&self, kind: &dyn Kind, how: &str, kept: Option<usize>) -> String {
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
        let rates: String = labels_at_another_rate(&refs, &self.labels_per_take)
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
            kind.short()
        )
    }
}

/// Refuses a validation take that is not one of the takes given, or the only one.
pub fn check_validation(prepared: &Prepared) -> Result<(), MethodError> {
    if let Some(v) = &prepared.validation {
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
    Ok(())
}

/// With a validation take and `choose_decoding`: the model's decoding and unknown threshold chosen on the
/// validation take's labels by the model ([`crate::labeller::decode::choose`]; the take was not trained on), written into its
/// header; a sentence for the training's summary (empty when nothing was chosen).
pub fn choose_on_validation<T>(
    model: &mut Model,
    prepared: &Prepared,
    options: &ModelOptions<T>,
) -> Result<String, MethodError> {
    use crate::labeller::decode::{choose, Judged};
    let Some(v) = prepared.validation.as_deref().filter(|_| options.choose_decoding) else {
        return Ok(String::new());
    };
    let Some(i) = prepared.motions.iter().position(|m| same_file(v, &m.name)) else {
        return Ok(String::new());
    };
    let (motion, truth) = (&prepared.motions[i], &prepared.labels_per_take[i]);
    let labelled = label(model, motion, &mut crate::method::NoProgress)?;
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::method::supervised::Training;

    /// Starts a training of the registry's labelling method `method` on `ask`.
    fn start(method: &str, ask: TrainingAsk) -> Result<Box<dyn Training>, MethodError> {
        let supervised = crate::methods::find(method).unwrap().supervised().unwrap();
        supervised.start_training(ask, &mut crate::method::NoProgress)
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
            limits: Default::default(),
        };
        let mut training = start("knn", ask).unwrap();
        while !training.done() {
            training.step(&mut crate::method::NoProgress).unwrap();
        }
        let trained = training.finish().unwrap();
        let card = &trained.model.info.card;
        assert_eq!(card.takes, vec!["35_01.bvh".to_string(), "02_01.bvh".to_string()]);
        assert_eq!(card.take_sha256, expected);
        assert!(card.held_out.is_none(), "a model trained here has no held-out figure");
        let (back, _) = super::super::model::read_header(&trained.bytes, "hashed.model").unwrap();
        assert_eq!(back.provenance.take_sha256, expected, "in the file too");
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
        let refused = start("knn", ask(false)).err().unwrap();
        assert_eq!(refused.param_name(), Some("name"), "{refused}");
        let mut training = start("knn", ask(true)).unwrap();
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
            limits: Default::default(),
        };
        let train = |ask: TrainingAsk| {
            let mut t = start("dtfcn", ask)?;
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
        let knn = start("knn", knn_ask);
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
            limits: Default::default(),
        };
        let train = |kind, options| {
            let mut t = start(kind, ask(options))?;
            while !t.done() {
                t.step(&mut crate::method::NoProgress)?;
            }
            t.finish()
        };
        let validation = crate::load::load_bytes("35_01.bvh", &file("35_01.bvh").1, &mut |_| {}).unwrap().motion;
        let truth: Vec<Option<usize>> = (0..validation.frames()).map(|f| Some(usize::from(f >= 200))).collect();
        for kind in ["dtfcn", "knn"] {
            let options = serde_json::json!({"epochs": 2, "filters": [4, 4], "width": 2, "min_duration_s": 3});
            let options = if kind == "knn" { serde_json::json!({"min_duration_s": 3}) } else { options };
            let trained = train(kind, options.clone()).unwrap();
            let model = trained.model.model.downcast_ref::<Model>().unwrap();
            let labelled = label(model, &validation, &mut crate::method::NoProgress).unwrap();
            let judged = Judged {
                probabilities: &labelled.probabilities,
                source: &labelled.source,
                fps: labelled.fps,
                truth: &truth,
            };
            let c = choose(&[judged]).unwrap();
            let h = &model.header;
            assert_eq!(h.decoding, (!c.decoding.is_raw(labelled.fps)).then_some(c.decoding), "{kind}");
            assert_eq!(h.unknown_threshold, c.threshold as f32, "{kind}");
            assert!(trained.report.summary.contains("Decoding chosen on 35_01.bvh: "), "{}", trained.report.summary);
            assert_eq!(h.provenance.takes, vec!["02_01.bvh".to_string()], "the validation take is not trained on");
            // not chosen: the rows
            let mut off = options;
            off["choose_decoding"] = false.into();
            if kind == "knn" {
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
}
