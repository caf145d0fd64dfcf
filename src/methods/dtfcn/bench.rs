//! The DT-FCN benchmark's workloads, shared by the native benchmark (`cargo run --release
//! --example bench_dtfcn`) and the wasm one (`tests/wasm_bench.rs`) so both time the same work:
//! labelling 3000 frames at 30 Hz with a shipped model, and training epochs on a take as large
//! as the exercises set (3682 frames at 30 Hz, seven classes in 500-frame blocks), with the
//! shipped models' settings.

use super::corpus::model_from;
use super::training::{TrainOptions, Trainer, TrainingTake};
use crate::labeller::corpus::ModelMeta;
use crate::labeller::method::label;
use crate::labeller::model::Model;
use crate::method::NoProgress;
use crate::motion::Motion;

/// Frames of the exercises set at 30 Hz (13_29, 13_30, 13_31, 14_14).
pub const EXERCISE_FRAMES: usize = 3682;

/// Labels every frame of `take` with `model` (a shipped model of either labeller, as the registry's method reads
/// it); the number of segments.
pub fn inference(take: &Motion, model: &Model) -> Result<usize, String> {
    let labelled = label(model, take, &mut NoProgress).map_err(|e| e.to_string())?;
    Ok(labelled.per_file_frame.windows(2).filter(|w| w[0].0 != w[1].0).count() + 1)
}

/// The shipped models' training settings: the defaults (w = 3, four layers, batch 2, crops of 128,
/// every augmentation).
pub fn shipped_options(epochs: usize) -> TrainOptions {
    TrainOptions { epochs, ..TrainOptions::default() }
}

/// A training take of `take`'s first [`EXERCISE_FRAMES`] frames (at 30 Hz) labelled in 500-frame
/// blocks of 7 classes.
pub fn training_take(take: &Motion) -> Result<(TrainingTake, Vec<String>), String> {
    if (take.fps - 30.0).abs() > 1e-6 {
        return Err(format!("the benchmark take must be at 30 Hz, not {}", take.fps));
    }
    let part = take.slice(0, EXERCISE_FRAMES);
    let labels: Vec<Option<usize>> = (0..part.frames()).map(|f| Some(f / 500 % 7)).collect();
    let classes = (0..7).map(|c| format!("class {c}")).collect();
    Ok((TrainingTake::new(&part, &labels)?, classes))
}

/// A trainer for `epochs` epochs on [`training_take`].
pub fn trainer(take: &Motion, epochs: usize) -> Result<(Trainer, TrainingTake, Vec<String>), String> {
    let (t, classes) = training_take(take)?;
    let trainer = Trainer::new(vec![t.clone()], Vec::new(), classes.clone(), shipped_options(epochs))?;
    Ok((trainer, t, classes))
}

/// Trains `epochs` epochs on [`training_take`] and writes the model file; its size in bytes.
pub fn train_epochs(take: &Motion, epochs: usize) -> Result<usize, String> {
    let (mut trainer, t, classes) = trainer(take, epochs)?;
    while !trainer.done() {
        trainer.epoch()?;
    }
    let trained = trainer.finish()?;
    let meta = ModelMeta {
        name: "bench".into(),
        command: "bench".into(),
        data_hash: "-".into(),
        decoding: None,
        travel: None,
        unknown_threshold: 0.5,
    };
    let model = model_from(vec![trained], &[t], &classes, &shipped_options(epochs), &meta)?;
    Ok(model.to_bytes()?.len())
}
