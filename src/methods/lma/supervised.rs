//! LMA as a supervised method ([`crate::method::supervised`]): its families are JSON files, a
//! training reads an Effort label CSV for the take on screen (§4's training data: the user's
//! own labels) and trains the whole family in one step ([`super::training::train_family`]),
//! reporting each factor's networks.

use std::sync::Arc;

use super::classifier::EffortModel;
use super::corpus::{parse_labels, Corpus, CorpusConfig, EffortLabel, Sample};
use super::method::SHIPPED_NAME;
use super::training::{train_family, FactorReport, TrainConfig};
use crate::labels::same_file;
use crate::method::supervised::{
    check_model_name, option_specs, read_option_rows, Loaded, ModelInfo, StepReport, Supervision, Trained, Training,
    TrainingAsk, TrainingOption, TrainingReport,
};
use crate::method::{counted, MethodError, ParamKind, ParamSpec, Progress};

/// The family `name` names: the shipped one, or one of `models`; and whether it is the shipped one.
pub fn resolve(name: &str, models: &crate::method::ModelStore) -> Result<(Arc<EffortModel>, bool), MethodError> {
    if name == SHIPPED_NAME {
        return super::shipped(models).map(|m| (m, true));
    }
    models.get::<EffortModel>("lma", name).map(|m| (m, false)).ok_or_else(|| {
        let mut known = vec![SHIPPED_NAME.to_string()];
        known.extend(models.names("lma"));
        MethodError::param("model", format!("model: no LMA family called `{name}`; known: {}", known.join(", ")))
    })
}

/// An option's JSON value as a whole number (its row's check accepted it as one).
fn whole(v: &serde_json::Value) -> usize {
    v.as_u64().unwrap_or(0) as usize
}

/// LMA's training options, each declared once (the trainer's defaults are the paper's where it gives them).
pub const OPTIONS: [TrainingOption<TrainConfig>; 9] = [
    TrainingOption {
        name: "restarts",
        help: "Random initialisations of each unshifted network (the paper: 20).",
        kind: || ParamKind::Integer { min: 1, max: 50 },
        unit: None,
        basic: true,
        get: |c| c.restarts.into(),
        set: |c, v| c.restarts = whole(v),
    },
    TrainingOption {
        name: "validation",
        help: "Share of the labelled segments (per factor, stratified by class) that choose each network's stopping \
               epoch and restart.",
        kind: || ParamKind::Number { min: 0.0, max: 0.5 },
        unit: None,
        basic: false,
        get: |c| c.validation.into(),
        set: |c, v| c.validation = v.as_f64().unwrap_or(c.validation),
    },
    TrainingOption {
        name: "test",
        help: "Share of the labelled segments held out from every choice, to report each factor's error and confusion \
               on.",
        kind: || ParamKind::Number { min: 0.0, max: 0.5 },
        unit: None,
        basic: false,
        get: |c| c.test.into(),
        set: |c, v| c.test = v.as_f64().unwrap_or(c.test),
    },
    TrainingOption {
        name: "told",
        help:
            "Stand-in labels only: a pool feature whose rank correlation with the descriptor a factor's label is cut \
               from reaches this is left out of that factor's networks (1 keeps every feature).",
        kind: || ParamKind::Number { min: 0.5, max: 1.0 },
        unit: None,
        basic: false,
        get: |c| c.told.into(),
        set: |c, v| c.told = v.as_f64().unwrap_or(c.told),
    },
    TrainingOption {
        name: "saliency_rounds",
        help: "Random feature subsets the saliency ranks features on.",
        kind: || ParamKind::Integer { min: 1, max: 200 },
        unit: None,
        basic: false,
        get: |c| c.saliency_rounds.into(),
        set: |c, v| c.saliency_rounds = whole(v),
    },
    TrainingOption {
        name: "max_epochs",
        help: "Most epochs of each unshifted network.",
        kind: || ParamKind::Integer { min: 1, max: 5000 },
        unit: None,
        basic: false,
        get: |c| c.options.max_epochs.into(),
        set: |c, v| c.options.max_epochs = whole(v),
    },
    TrainingOption {
        name: "shift_epochs",
        help: "Most epochs of each boundary-shifted network (each trained from its own random start).",
        kind: || ParamKind::Integer { min: 1, max: 1000 },
        unit: None,
        basic: false,
        get: |c| c.shift_options.max_epochs.into(),
        set: |c, v| c.shift_options.max_epochs = whole(v),
    },
    TrainingOption {
        name: "shift_restarts",
        help: "Random initialisations of each boundary-shifted network (the best on validation kept).",
        kind: || ParamKind::Integer { min: 1, max: 20 },
        unit: None,
        basic: false,
        get: |c| c.shift_restarts.into(),
        set: |c, v| c.shift_restarts = whole(v),
    },
    TrainingOption {
        name: "seed",
        help: "Seed of the validation and test splits and the networks' initial weights.",
        kind: || ParamKind::Integer { min: 0, max: 1 << 31 },
        unit: None,
        basic: false,
        get: |c| c.seed.into(),
        set: |c, v| c.seed = v.as_u64().unwrap_or(c.seed),
    },
];

/// LMA's training table ([`OPTIONS`]).
pub fn training_specs() -> Vec<ParamSpec> {
    option_specs(&OPTIONS)
}

/// Reads and checks the training options: a refusal names the option.
pub fn config_from_json(value: &serde_json::Value) -> Result<TrainConfig, MethodError> {
    read_option_rows(value, &OPTIONS, "LMA")
}

/// LMA's declaration.
pub fn supervision() -> Supervision {
    Supervision {
        labels_header: "file,start_frame,end_frame,space,time,weight,flow".into(),
        labels_help: "Frames of the file (0-based, inclusive) and each Effort factor's element (indirect / direct, \
                      sustained / sudden, light / strong, free / bound, or neutral). Its rows for the take on screen \
                      train the 121 classifiers of each factor in this tab; LMA then runs with them."
            .into(),
        more_takes: false,
        model_extension: "json".into(),
        shipped: vec![SHIPPED_NAME.into()],
        training: training_specs(),
        step_name: "training".into(),
        trains_on_my_labels: false,
        labels_classes: false,
        validation_take: false,
        without_labels: Some(
            "the stand-in Effort descriptors' terciles over the takes' segments between hand-speed minima (how \
             models/lma-effort.json is made) — functions of LMA's own features: for trying it out, not for \
             measuring it"
                .into(),
        ),
    }
}

/// What the page and `model-info` show of the family `model`, stored as `name`.
pub fn model_info(name: &str, model: &EffortModel) -> ModelInfo {
    ModelInfo {
        method: "lma".into(),
        name: name.into(),
        classes: Vec::new(),
        colours: Vec::new(),
        origin: model.origin.clone(),
        provenance: vec![("segments".into(), model.samples.to_string()), ("rate".into(), format!("{} Hz", model.fps))],
        // the family file names its takes only inside its origin line: the card says that line
        card: crate::method::cards::ModelCard {
            method: "lma".into(),
            name: name.into(),
            origin: model.origin.clone(),
            ..Default::default()
        },
    }
}

/// Reads a family file (`file` names it): stored under the file's stem.
pub fn read_model(file: &str, bytes: &[u8]) -> Result<Loaded, MethodError> {
    let text = std::str::from_utf8(bytes)
        .map_err(|_| MethodError::Failed(format!("{file}: not an LMA effort model (not text)")))?;
    let model = EffortModel::from_json(text).map_err(|m| MethodError::Failed(format!("{file}: {m}")))?;
    let name =
        crate::method::supervised::stored_name("", file, &[SHIPPED_NAME.to_string()]).map_err(MethodError::Failed)?;
    Ok(Loaded { info: model_info(&name, &model), model: Arc::new(model) })
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

/// Starts a training of the family on the rows of `ask`'s labels for its takes (the page sends the
/// take on screen; the command line every take given), or — with no label file — on the stand-in
/// descriptors' terciles ([`Supervision::without_labels`]). Takes without rows, or without arms, are
/// left out and said.
/// What an LMA family's training holds per working frame of its takes: both arms' feature pools over its corpus of
/// candidate segments and the segments' inputs, at its 30 Hz — 11.4 kB measured on 6 000 and 24 000 frames
/// (tests/limits.rs); the networks are small.
pub fn training_work() -> crate::method::Work {
    crate::method::Work::memory(CorpusConfig::default().fps, 14_000, 16 << 20, "")
}

pub fn start_training(ask: TrainingAsk, progress: &mut dyn Progress) -> Result<Box<dyn Training>, MethodError> {
    if ask.start_from.is_some() {
        return Err(MethodError::param("name", "an LMA family has no epochs to continue: train it again"));
    }
    if ask.validation.is_some() {
        return Err(MethodError::param(
            "validation",
            "an LMA family's stopping points are chosen on a share of its segments (the validation option), not on a take",
        ));
    }
    let config = config_from_json(&ask.options)?;
    let name = ask.name.trim().to_string();
    let taken = if ask.to_file { Vec::new() } else { vec![SHIPPED_NAME.to_string()] };
    check_model_name(&name, &taken).map_err(|m| MethodError::param("name", m))?;
    let bad_labels = |m: String| MethodError::param("labels", m);
    let first =
        ask.takes.first().map(|(n, _)| n.clone()).ok_or_else(|| MethodError::param("takes", "no take to train on"))?;
    let stand_in = ask.labels_name.is_empty() && ask.labels.trim().is_empty();
    let rows = if stand_in { Vec::new() } else { parse_labels(&ask.labels, &ask.labels_name).map_err(bad_labels)? };
    let corpus_config = CorpusConfig::default();
    let count = ask.takes.len();
    // every take's file, motion and pools held at once: checked as each is read (issue 49)
    let mut hold = crate::method::work::TrainingHold::new("LMA", training_work(), ask.limits);
    let mut motions = Vec::new();
    let mut skipped = Vec::new();
    for (k, (take_name, bytes)) in ask.takes.into_iter().enumerate() {
        if !stand_in && !rows.iter().any(|row| same_file(&row.file, &take_name)) {
            skipped.push(format!("{take_name} (no rows)"));
            continue;
        }
        progress.step(&format!("reading {take_name}"), k as f64 / count as f64 * 0.1)?;
        let motion = match crate::load::load_bytes(&take_name, &bytes, &mut |_| {}) {
            Ok(loaded) => loaded.motion,
            // one of several takes that does not load is left out, and said
            Err(e) if count > 1 => {
                skipped.push(e.to_string());
                continue;
            }
            Err(e) => return Err(MethodError::param("takes", e.to_string())),
        };
        hold.add(&motion, bytes.len())?;
        match super::body::upper_body(&motion, corpus_config.fps) {
            Ok(_) => motions.push(motion),
            Err(e) if count > 1 => skipped.push(format!("{take_name} ({e})")),
            Err(e) => return Err(MethodError::param("takes", format!("{take_name}: {e}"))),
        }
    }
    if motions.is_empty() {
        return Err(if stand_in || skipped.iter().all(|s| !s.ends_with("(no rows)")) {
            MethodError::param("takes", format!("no take to learn from: {}", skipped.join(", ")))
        } else {
            bad_labels(no_rows_for(&ask.labels_name, &first, &rows))
        });
    }
    let refs: Vec<&crate::motion::Motion> = motions.iter().collect();
    let (used, ignored): (Vec<EffortLabel>, Vec<EffortLabel>) =
        rows.into_iter().partition(|row| refs.iter().any(|m| same_file(&row.file, &m.name)));
    let takes = refs.iter().map(|m| m.name.as_str()).collect::<Vec<_>>().join(", ");
    let corpus = if stand_in {
        Corpus::from_descriptors(&refs, corpus_config).map_err(|m| MethodError::param("takes", m))?
    } else {
        let mut corpus = Corpus::from_labels(&refs, &used, corpus_config)
            .map_err(|m| bad_labels(format!("{}: {m}", ask.labels_name)))?;
        corpus.origin = format!("{} segments of {takes} labelled in {}", corpus.samples.len(), ask.labels_name);
        corpus
    };
    Ok(Box::new(LmaTraining {
        name,
        labels_name: ask.labels_name,
        takes,
        corpus,
        config,
        used: used.len(),
        ignored: ignored.len(),
        skipped,
        trained: None,
        stopped: false,
    }))
}

/// The family's training: one step.
struct LmaTraining {
    name: String,
    /// Empty for the stand-in labels.
    labels_name: String,
    /// The takes learnt from, named.
    takes: String,
    corpus: Corpus,
    config: TrainConfig,
    used: usize,
    ignored: usize,
    /// Takes given but not learnt from, each with why.
    skipped: Vec<String>,
    trained: Option<(EffortModel, Vec<FactorReport>)>,
    stopped: bool,
}

/// `share` as a whole percentage.
fn percent(share: f32) -> String {
    format!("{:.0} %", 100.0 * share)
}

/// A confusion matrix in one cell: per true class (indulging, neutral, condensing), the counts
/// predicted as each.
pub fn confusion_text(m: &[[usize; 3]; 3]) -> String {
    m.iter().map(|r| format!("{}/{}/{}", r[0], r[1], r[2])).collect::<Vec<_>>().join(" · ")
}

/// One report row per factor: its segments per class, hidden units and errors.
fn factor_row(report: &FactorReport, samples: &[Sample], factor: usize) -> Vec<String> {
    let mut segments = [0usize; 3];
    for s in samples {
        if let Some(n) = segments.get_mut(s.classes[factor]) {
            *n += 1;
        }
    }
    vec![
        report.factor.name().to_string(),
        format!("{} / {} / {}", segments[0], segments[1], segments[2]),
        report.hidden.to_string(),
        percent(report.train_error),
        percent(report.validation_error),
        percent(report.test_error),
        percent(report.shifted_test_error),
        confusion_text(&report.confusion),
        if report.told.is_empty() { "—".into() } else { report.told.len().to_string() },
        report.most_salient.iter().map(|(name, v)| format!("{name} ({v:.3})")).collect::<Vec<_>>().join("; "),
    ]
}

impl Training for LmaTraining {
    fn step(&mut self, progress: &mut dyn Progress) -> Result<StepReport, MethodError> {
        let mut report = |stage: &str, fraction: f64| progress.step(stage, fraction);
        let trained = train_family(&self.corpus, &self.config, &mut report).map_err(|m| {
            if m == "cancelled" {
                MethodError::Cancelled
            } else {
                MethodError::param("labels", format!("{}: {m}", self.labels_name))
            }
        })?;
        self.trained = Some(trained);
        Ok(StepReport {
            step: 1,
            steps: 1,
            line: format!("Trained on {} labelled segments", self.corpus.samples.len()),
            values: Vec::new(),
            best: true,
        })
    }

    fn done(&self) -> bool {
        self.trained.is_some() || self.stopped
    }

    fn stop(&mut self) {
        self.stopped = true;
    }

    fn finish(self: Box<Self>) -> Result<Trained, MethodError> {
        let LmaTraining { name, labels_name, takes, corpus, config, used, ignored, skipped, trained, .. } = *self;
        let (model, reports) =
            trained.ok_or_else(|| MethodError::Failed("the training was stopped before it ran".into()))?;
        let left_out = match ignored {
            0 => String::new(),
            1 => " (1 row for another file left out)".to_string(),
            n => format!(" ({n} rows for other files left out)"),
        };
        let skipped = match skipped.len() {
            0 => String::new(),
            _ => format!(" (not learnt from: {})", skipped.join(", ")),
        };
        let learnt = if labels_name.is_empty() {
            format!("the stand-in Effort descriptors' terciles over {} segments of {takes}", corpus.samples.len())
        } else {
            format!("{} of {labels_name} for {takes}{left_out}", counted(used, "row"))
        };
        let report = TrainingReport {
            summary: format!(
                "Trained on {learnt}{skipped}; per factor {}% of them chose the networks' stopping points and {}% \
                 were held out to measure the errors. LMA runs with your classifiers now.",
                (100.0 * config.validation).round(),
                (100.0 * config.test).round()
            ),
            columns: [
                "factor",
                "segments (indulging / neutral / condensing)",
                "hidden units",
                "training error",
                "validation error",
                "test error",
                "shifted networks' test error",
                "test confusion (true indulging · neutral · condensing → predicted i/n/c)",
                "features left out (they tell the label)",
                "most salient features (saliency)",
            ]
            .iter()
            .map(|s| s.to_string())
            .collect(),
            rows: reports.iter().enumerate().map(|(f, r)| factor_row(r, &corpus.samples, f)).collect(),
            stopped: false,
        };
        let bytes = model.to_json().into_bytes();
        Ok(Trained { model: Loaded { info: model_info(&name, &model), model: Arc::new(model) }, bytes, report })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_options_table_reads_its_defaults_and_names_what_it_refuses() {
        let defaults: serde_json::Map<String, serde_json::Value> =
            training_specs().into_iter().map(|s| (s.name, s.default)).collect();
        assert_eq!(config_from_json(&serde_json::Value::Object(defaults)).unwrap(), TrainConfig::default());
        for (json, param) in [
            (serde_json::json!({"restarts": 0}), "restarts"),
            (serde_json::json!({"validation": 0.9}), "validation"),
            (serde_json::json!({"max_epochs": "x"}), "max_epochs"),
        ] {
            assert_eq!(config_from_json(&json).unwrap_err().param_name(), Some(param), "{json}");
        }
        assert_eq!(config_from_json(&serde_json::json!({"nope": 1})).unwrap_err().param_name(), None);
    }

    #[test]
    fn a_family_file_is_read_under_its_stem_and_a_bad_one_is_named() {
        let shipped = crate::method::ModelStore::default().shipped_bytes(super::super::SHIPPED_FILE).unwrap();
        let loaded = read_model("dir/my-family.json", &shipped).unwrap();
        assert_eq!(loaded.info.name, "my-family");
        assert_eq!(loaded.info.method, "lma");
        let e = read_model("broken.json", b"{\"fps\": 30}").unwrap_err().to_string();
        assert!(e.starts_with("broken.json: not an LMA effort model"), "{e}");
    }
}
