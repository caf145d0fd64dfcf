//! The k-NN as a supervised method: its training table (the decoding's rows both labellers share,
//! [`crate::labeller::supervised::decoding_rows`]: the k-NN has no trainer's options) and a training from a label CSV
//! and takes — one fit — ending in a model file with its provenance.

use std::sync::Arc;

use super::training::fit_knn_model;
use crate::labeller::model::Model;
use crate::labeller::supervised::{
    check_validation, choose_on_validation, decoding_rows, model_info, prepare, read_options, Choices, ModelOptions,
    Prepared,
};
use crate::method::supervised::{
    option_specs, Loaded, StepReport, Trained, Training, TrainingAsk, TrainingOption, TrainingReport,
};
use crate::method::{MethodError, ParamSpec, Progress};
use crate::motion::Motion;

/// The k-NN's training table: the decoding's rows.
fn rows() -> [TrainingOption<Choices<()>>; 4] {
    decoding_rows()
}

/// The k-NN's training options: the one table the page's form, the command line's flags (`mocapseg train-knn
/// --NAME VALUE`), the model's provenance and [`options_from_json`] read.
pub fn training_specs() -> Vec<ParamSpec> {
    option_specs(&rows())
}

/// Reads and checks the k-NN's training options against [`training_specs`]: a refusal names the option.
pub fn options_from_json(value: &serde_json::Value) -> Result<ModelOptions<()>, MethodError> {
    read_options(&rows(), value, "k-NN")
}

/// What a k-NN's fit holds per working frame of its takes: every labelled frame's stacked window (13 frames of the
/// joints, f32) and its projection, at 30 Hz — 4.1 kB measured on 6 000 and 24 000 frames (tests/limits.rs).
pub fn training_work() -> crate::method::Work {
    crate::method::Work::memory(crate::labeller::input::NETWORK_FPS, 5_000, 8 << 20, "")
}

/// Starts the fit of a k-NN model on `ask`.
pub fn start_training(ask: TrainingAsk, progress: &mut dyn Progress) -> Result<Box<dyn Training>, MethodError> {
    let options = options_from_json(&ask.options)?;
    let continued = ask.start_from.is_some();
    let prepared = prepare(ask, ("k-NN", training_work()), progress)?;
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
    options: ModelOptions<()>,
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
        let mut model = fit_knn_model(&takes, &p.classes, &meta, super::KnnParams::default())
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
            super::KnnParams::default(),
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
