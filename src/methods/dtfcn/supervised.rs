//! DT-FCN as a supervised method: its training table (the network's rows, then the decoding's rows both labellers
//! share, [`crate::labeller::supervised::decoding_rows`]), and a training from a label CSV and takes — an epoch per
//! step, the networks of an ensemble one after the other, a model of the user's trained on from its own weights —
//! ending in a model file with its provenance.

use std::sync::Arc;

use super::augment::Augment;
use super::corpus::model_from;
use super::model::{networks_of, Networks};
use super::network::Padding;
use super::network::{DtFcn, DtFcnConfig};
use super::training::{EpochReport, TrainOptions, Trainer, TrainingTake, MAX_MASK_S};
use crate::labeller::input::{NetworkInput, Standardise};
use crate::labeller::model::{Model, Provenance};
use crate::labeller::supervised::{
    check_validation, choose_on_validation, decoding_rows, model_info, number, prepare, read_options, whole, words,
    Choices, ModelOptions, Prepared,
};
use crate::method::supervised::{
    option_specs, Loaded, StepReport, Trained, Training, TrainingAsk, TrainingOption, TrainingReport,
};
use crate::method::{MethodError, ParamKind, ParamSpec, Progress};

/// The augmentations the `augment` option can name.
const AUGMENTATIONS: [&str; 5] = ["mirror", "yaw", "warp", "scale", "jitter"];

/// The network's rows of DT-FCN's training table, each declared once.
const NETWORK_OPTIONS: [TrainingOption<Choices<TrainOptions>>; 17] = [
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
];

/// DT-FCN's training table: the network's rows, then the decoding's.
fn rows() -> Vec<TrainingOption<Choices<TrainOptions>>> {
    let mut rows = NETWORK_OPTIONS.to_vec();
    rows.extend(decoding_rows());
    rows
}

/// DT-FCN's training options: the one table the page's form, the command line's flags (`mocapseg train-dtfcn
/// --NAME VALUE`), the model's provenance and [`options_from_json`] read.
pub fn training_specs() -> Vec<ParamSpec> {
    option_specs(&rows())
}

/// The augmentations turned on, by name.
fn augment_names(a: &Augment) -> Vec<String> {
    [a.mirror, a.yaw, a.time_warp, a.scale, a.jitter]
        .iter()
        .zip(AUGMENTATIONS)
        .filter(|(on, _)| **on)
        .map(|(_, n)| n.to_string())
        .collect()
}

/// Reads and checks DT-FCN's training options against [`training_specs`]: a refusal names the option.
pub fn options_from_json(value: &serde_json::Value) -> Result<ModelOptions<TrainOptions>, MethodError> {
    let options = read_options(&rows(), value, "DT-FCN")?;
    // what the table cannot say (learning rate below 1, …) is still the trainer's to refuse
    options.train.check().map_err(MethodError::params)?;
    Ok(options)
}

/// What a DT-FCN training with `train` holds: per working frame of its takes the motion image and labels (1.2 kB
/// measured at the defaults, tests/limits.rs); besides, whatever the takes' length, the networks (each member's
/// weights kept, the one training with its gradients and Adam's two moments) and one batch of crops through every
/// layer with its gradients — bounded from the options with the most classes a model may have.
pub fn training_work(train: &TrainOptions) -> crate::method::Work {
    let config = train.network(crate::labeller::model::MAX_CLASSES);
    let params = config.parameter_count();
    let weights = params.saturating_mul(4).saturating_mul(4 + train.members);
    let per_crop_frame = config.first_layer_inputs() + config.filters.iter().sum::<usize>() + config.classes;
    let batch = train.batch.saturating_mul(train.crop_frames).saturating_mul(per_crop_frame).saturating_mul(4 * 8);
    crate::method::Work::memory(
        crate::labeller::input::NETWORK_FPS,
        2_000,
        (16usize << 20).saturating_add(weights).saturating_add(batch),
        "fewer or narrower layers (filters), a smaller batch or shorter crops",
    )
}

/// Starts the training of a DT-FCN model on `ask` (continued from the model `ask.start_from` names, when it does).
pub fn start_training(ask: TrainingAsk, progress: &mut dyn Progress) -> Result<Box<dyn Training>, MethodError> {
    let options = options_from_json(&ask.options)?;
    let start_from = ask.start_from.clone();
    let mut prepared = prepare(ask, ("DT-FCN", training_work(&options.train)), progress)?;
    check_validation(&prepared)?;
    let start = match &start_from {
        None => None,
        Some(from) => Some(continued(from, &mut prepared)?),
    };
    let bad_option = |m: String| MethodError::params(m);
    if start.is_none() {
        options.train.network(prepared.classes.len()).check().map_err(bad_option)?;
    }
    progress.step("motion images", 0.5)?;
    let mut training = Vec::with_capacity(prepared.motions.len());
    let mut validation = Vec::new();
    for (m, l) in prepared.motions.iter().zip(&prepared.labels_per_take) {
        let take = TrainingTake::new(m, l).map_err(|e| MethodError::param("takes", format!("{}: {e}", m.name)))?;
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
    options: ModelOptions<TrainOptions>,
    largest_loss: f64,
    /// The model this training continues: its name and provenance.
    previous: Option<(String, Provenance)>,
}

/// The weights, network and input scaling of the model `from` to continue training, and its
/// name and provenance; `prepared`'s classes put in the model's order (the labels may name them
/// in another order, or only some of them). Refused, naming `name` or `labels`, when `from` is
/// not a DT-FCN network or the labels have a class it does not know.
fn continued(
    from: &Loaded,
    prepared: &mut Prepared,
) -> Result<((DtFcnConfig, Standardise, Vec<DtFcn>), (String, Provenance)), MethodError> {
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
        let meta = prepared.meta(&super::method::DTFCN, &options);
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
            summary: format!("{}{network}{chosen}", prepared.summary(&super::method::DTFCN, &how, Some(best))),
            columns: Vec::new(),
            rows: Vec::new(),
            stopped,
        };
        Ok(Trained {
            model: Loaded { info: model_info(&super::method::DTFCN, &prepared.name, &model), model: Arc::new(model) },
            bytes,
            report,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::method::DTFCN;
    use super::*;
    use crate::labeller::supervised::train_command;

    #[test]
    fn the_options_table_reads_its_own_defaults_and_names_what_it_refuses() {
        let options_from_json = |v: &serde_json::Value| options_from_json(v).map(|o| o.train);
        let defaults: serde_json::Map<String, serde_json::Value> =
            training_specs().into_iter().map(|s| (s.name, s.default)).collect();
        let defaults = serde_json::Value::Object(defaults);
        let read = super::options_from_json(&defaults).unwrap();
        assert_eq!((&read.train, read.decoding, &read.read), (&TrainOptions::default(), None, &defaults));
        assert_eq!(super::options_from_json(&serde_json::json!({})).unwrap(), read);
        let o = super::options_from_json(&serde_json::json!({"unknown_threshold": 0.8})).unwrap();
        assert_eq!(o.unknown_threshold, 0.8);
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
            limits: Default::default(),
        };
        let options = |seed: u64, members: usize| serde_json::json!({"epochs": 2, "filters": [4, 4], "width": 2, "seed": seed, "members": members});
        let train = |ask: TrainingAsk, stop_after: usize| {
            let mut t = start_training(ask, &mut crate::method::NoProgress).unwrap();
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
        let json = crate::labeller::supervised::header_json(&DTFCN, two.model.model.downcast_ref::<Model>().unwrap());
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
            &serde_json::json!({"epochs": 2, "filters": [8, 8], "switch_cost": 10, "augment": ["mirror"]}),
        )
        .unwrap()
        .read;
        let command = train_command(&DTFCN, &["a b.bvh".into()], "l.csv", "m", &read);
        assert_eq!(
            command,
            "mocapseg train-dtfcn --bvh 'a b.bvh' --labels l.csv --epochs 2 --label-noise 0.0 --mask-s 0.0 --augment mirror \
             --width 3 --filters 8,8 --switch-cost 10.0 --name m -o m.model (trained in the browser)"
        );
    }
}
