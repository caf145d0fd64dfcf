//! The k-NN as a supervised method: its training table (its window, votes and input, then the decoding's rows both
//! labellers share, [`crate::labeller::supervised::decoding_rows`]) and a training from a label CSV and takes — one
//! fit, then the open-set unknown chosen on folds that leave a class out — ending in a model file with its provenance.

use std::sync::Arc;

use super::training::fit_knn_model;
use super::{KnnInput, KnnParams};
use crate::labeller::model::Model;
use crate::labeller::supervised::{
    check_validation, choose_on_validation, decoding_rows, model_info, number, prepare, read_options, whole, Choices,
    ModelOptions, Prepared,
};
use crate::method::supervised::{
    option_specs, Loaded, StepReport, Trained, Training, TrainingAsk, TrainingOption, TrainingReport,
};
use crate::method::{MethodError, ParamKind, ParamSpec, Progress};
use crate::motion::Motion;

/// The k-NN's own rows of its training table, each declared once: the window a frame is described by, the votes,
/// and what a window's frame holds (issue 50: the scoreboard chooses all three by nested validation).
const KNN_OPTIONS: [TrainingOption<Choices<KnnParams>>; 3] = [
    TrainingOption {
        name: "half_window_s",
        help: "Half the window each frame is described by, in seconds, every 5th frame of it kept (±1 s: 13 frames at 30 Hz; rounded to a sixth of a second); the scoreboard's nested folds chose ±0.5 s in every fold (docs/methods/dtfcn.md).",
        kind: || ParamKind::Number { min: 0.0, max: 10.0 },
        unit: Some("s"),
        basic: false,
        get: |c| (c.train.half_window as f64 / c.train.fps).into(),
        set: |c, v| {
            let stride = c.train.stride.max(1) as f64;
            c.train.half_window = ((number(v) * c.train.fps / stride).round() * stride) as i32;
        },
    },
    TrainingOption {
        name: "k",
        help: "The nearest training windows whose labels vote for a frame's (the scoreboard's nested folds chose 9 in three folds of four).",
        kind: || ParamKind::Integer { min: 1, max: 100 },
        unit: None,
        basic: false,
        get: |c| c.train.k.into(),
        set: |c, v| c.train.k = whole(v),
    },
    TrainingOption {
        name: "input",
        help: "What a window's frame holds: joints (the 17 canonical joints, hip-relative, facing +Z) or network (DT-FCN's input: the joints with the root's velocity and turning, every channel standardised by the training frames).",
        kind: || ParamKind::Choice { options: vec!["joints".into(), "network".into()] },
        unit: None,
        basic: false,
        get: |c| c.train.input.name().into(),
        set: |c, v| c.train.input = if v.as_str() == Some("network") { KnnInput::Network } else { KnnInput::Joints },
    },
];

/// The k-NN's training table: its own rows, then the decoding's.
fn rows() -> Vec<TrainingOption<Choices<KnnParams>>> {
    let mut rows = KNN_OPTIONS.to_vec();
    rows.extend(decoding_rows());
    rows
}

/// The k-NN's training options: the one table the page's form, the command line's flags (`mocapseg train-knn
/// --NAME VALUE`), the model's provenance and [`options_from_json`] read.
pub fn training_specs() -> Vec<ParamSpec> {
    option_specs(&rows())
}

/// Reads and checks the k-NN's training options against [`training_specs`]: a refusal names the option.
pub fn options_from_json(value: &serde_json::Value) -> Result<ModelOptions<KnnParams>, MethodError> {
    let options = read_options(&rows(), value, "k-NN")?;
    options.train.check().map_err(|m| MethodError::param("half_window_s", m))?;
    Ok(options)
}

/// What a k-NN's fit with `params` holds: per working frame of its takes, every labelled frame's stacked window (f32)
/// and its projection, at 30 Hz — 8 bytes per window value, 4 more for DT-FCN's input (its raw and standardised rows);
/// besides, 8 MiB and the covariance of the window values and its decomposition (12 bytes per pair of values). The
/// default ±1 s of the joints (663 values): 5,304 bytes a frame. Measured by tests/limits.rs for ±0.5, ±1 and ±2 s and
/// both inputs on 6 000 and 24 000 frames (the k-NN's own part of ±2 s, 1,275 values: 9.4 kB a frame).
pub fn training_work(params: &KnnParams) -> crate::method::Work {
    let frames = (-params.half_window..=params.half_window).step_by(params.stride.max(1) as usize).count();
    let values = frames * params.input.rows() * 3;
    let per_value = if params.input == KnnInput::Network { 12 } else { 8 };
    crate::method::Work::memory(
        crate::labeller::input::NETWORK_FPS,
        per_value * values,
        (8 << 20) + 12 * values * values,
        "",
    )
}

/// Starts the fit of a k-NN model on `ask`.
pub fn start_training(ask: TrainingAsk, progress: &mut dyn Progress) -> Result<Box<dyn Training>, MethodError> {
    let options = options_from_json(&ask.options)?;
    let continued = ask.start_from.is_some();
    let prepared = prepare(ask, ("k-NN", training_work(&options.train)), progress)?;
    if prepared.validation.is_some() && !options.choose_decoding {
        return Err(MethodError::param(
            "validation",
            "a k-NN has no epochs for a validation take to choose, only its decoding (choose_decoding)",
        ));
    }
    check_validation(&prepared)?;
    if continued {
        return Err(MethodError::param("name", "a k-NN has no epochs to continue: train it again on all its takes"));
    }
    Ok(Box::new(KnnTraining { prepared, options, model: None, done: false, chosen: String::new() }))
}

/// A k-NN fit: one step.
struct KnnTraining {
    prepared: Prepared,
    options: ModelOptions<KnnParams>,
    model: Option<Model>,
    done: bool,
    /// What the validation take chose, for the summary.
    chosen: String,
}

impl Training for KnnTraining {
    fn step(&mut self, progress: &mut dyn Progress) -> Result<StepReport, MethodError> {
        let p = &self.prepared;
        // the validation take, if any, only chooses the decoding: it is not among the windows
        let takes: Vec<(&Motion, &[Option<usize>])> = p
            .motions
            .iter()
            .zip(&p.labels_per_take)
            .filter(|(m, _)| !p.is_validation(&m.name))
            .map(|(m, l)| (m, &l[..]))
            .collect();
        let meta = p.meta(&super::method::KNN, &self.options);
        let mut model = fit_knn_model(&takes, &p.classes, &meta, self.options.train)
            .map_err(|m| MethodError::param("labels", format!("{}: {m}", p.labels_name)))?;
        model.header.provenance.take_sha256 = p.trained_sha256();
        self.chosen = choose_on_validation(&mut model, p, &self.options)?;
        // the open-set unknown, on folds of every labelled take (the validation take too) that leave a class out,
        // decoded as the model now is
        let all: Vec<(&Motion, &[Option<usize>])> =
            p.motions.iter().zip(&p.labels_per_take).map(|(m, l)| (m, &l[..])).collect();
        let decoding = model.header.decoding.unwrap_or(crate::labeller::decode::Decoding::RAW);
        let threshold = model.header.unknown_threshold as f64;
        let choice = super::training::choose_open_set_unknown(
            &all,
            p.classes.len(),
            self.options.train,
            &decoding,
            threshold,
            &mut |f| progress.step("open-set unknown", f).is_ok(),
        )
        .map_err(|m| MethodError::param("labels", format!("{}: {m}", p.labels_name)))?;
        if progress.cancelled() {
            return Err(MethodError::Cancelled);
        }
        if let Some(c) = choice {
            model.header.open_set = c.unknown();
            self.chosen.push_str(&c.describe());
        }
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
            summary: format!("{}{chosen}", prepared.summary(&super::method::KNN, "fitted", None)),
            columns: Vec::new(),
            rows: Vec::new(),
            stopped: false,
        };
        Ok(Trained {
            model: Loaded { info: model_info(&super::method::KNN, &prepared.name, &model), model: Arc::new(model) },
            bytes,
            report,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::method::KNN;
    use super::*;
    use crate::labeller::decode::Decoding;
    use crate::labeller::method::DEFAULT_THRESHOLD;
    use crate::labeller::supervised::train_command;

    /// The k-NN's own rows make its window, votes and input (what the scoreboard chooses by nested validation): the
    /// window in seconds, rounded to its stride; out of range, refused by name; the defaults the shipped models'.
    #[test]
    fn the_window_votes_and_input_are_rows_of_the_table() {
        let o = options_from_json(&serde_json::json!({})).unwrap();
        assert_eq!(o.train, KnnParams::default());
        let o = options_from_json(&serde_json::json!({"half_window_s": 0.5, "k": 9, "input": "network"})).unwrap();
        assert_eq!(o.train, KnnParams { half_window: 15, k: 9, input: KnnInput::Network, ..KnnParams::default() });
        assert_eq!((o.read["half_window_s"].as_f64(), o.read["k"].as_u64()), (Some(0.5), Some(9)));
        assert_eq!(o.read["input"], "network");
        // rounded to the stride (every 5th frame): 0.6 s is 18 frames, 20 kept
        assert_eq!(options_from_json(&serde_json::json!({"half_window_s": 0.6})).unwrap().train.half_window, 20);
        for (bad, name) in [
            (serde_json::json!({"half_window_s": 11}), "half_window_s"),
            (serde_json::json!({"half_window_s": -1}), "half_window_s"),
            (serde_json::json!({"k": 0}), "k"),
            (serde_json::json!({"k": 101}), "k"),
            (serde_json::json!({"input": "pixels"}), "input"),
        ] {
            let e = options_from_json(&bad).unwrap_err();
            assert_eq!(e.param_name(), Some(name), "{bad}: {e}");
        }
        // a wider window, DT-FCN's input: more declared per frame
        let work = |o: serde_json::Value| training_work(&options_from_json(&o).unwrap().train).bytes_per_frame;
        assert_eq!(work(serde_json::json!({})), 5_304);
        assert!(work(serde_json::json!({"half_window_s": 2})) > work(serde_json::json!({})));
        assert!(work(serde_json::json!({"input": "network"})) > work(serde_json::json!({})));
        assert!(work(serde_json::json!({"half_window_s": 0.5})) < work(serde_json::json!({})));
    }

    /// The decoding rows make the k-NN model's decoding; it has no network rows.
    #[test]
    fn the_options_table_is_the_decodings_rows() {
        let defaults: serde_json::Map<String, serde_json::Value> =
            training_specs().into_iter().map(|s| (s.name, s.default)).collect();
        let defaults = serde_json::Value::Object(defaults);
        let read = options_from_json(&defaults).unwrap();
        assert_eq!((read.decoding, &read.read), (None, &defaults));
        assert_eq!(options_from_json(&serde_json::json!({})).unwrap(), read);
        let o = options_from_json(&serde_json::json!({"min_duration_s": 2, "switch_cost": 150})).unwrap();
        assert_eq!(o.decoding, Some(Decoding { min_duration_s: 2.0, switch_cost: 150.0 }));
        // the model's unknown threshold (its runs' unless they ask for another), 0.5 unless given, for both kinds
        assert_eq!(o.unknown_threshold, DEFAULT_THRESHOLD);
        let o = options_from_json(&serde_json::json!({"unknown_threshold": 0.8})).unwrap();
        assert_eq!(o.unknown_threshold, 0.8);
        let e = options_from_json(&serde_json::json!({"epochs": 3})).unwrap_err();
        assert!(e.to_string().contains("epochs"), "{e}");
    }

    #[test]
    fn the_provenance_command_repeats_every_basic_row_as_its_flag() {
        let read = options_from_json(&serde_json::json!({})).unwrap().read;
        assert_eq!(
            train_command(&KNN, &["t.bvh".into()], "l.csv", "k", &read),
            "mocapseg train-knn --bvh t.bvh --labels l.csv --name k -o k.model (trained in the browser)"
        );
    }
}
