//! From labelled takes to DT-FCN models and scores, the same for the command line and the browser: training a
//! DT-FCN into a model file, and leave-one-take-out cross-validation with the epochs chosen inside the training takes
//! (nested: the held-out take never chooses anything), with the labeller its caller puts beside it on the same folds
//! (the k-NN, `crate::methods::knn::training::knn_fold`: the held-out comparison of docs/methods/dtfcn.md).
//! Matching label rows to takes is [`crate::labeller::corpus`]'s.

use super::model::Networks;
use super::training::{train, EpochReport, TrainOptions, Trained, TrainingTake};
use crate::labeller::corpus::{header, FoldLabels, FoldTakes, ModelMeta};
use crate::labeller::model::{Json, MemberRun, Model, Provenance};
use crate::motion::Motion;
use crate::segment::labelling::{self, LabellingScores};

/// Trains a DT-FCN model on `takes` (early stopping on `validation` when given): `options.members`
/// networks, one after the other, each with its own seed ([`TrainOptions::member`]).
pub fn train_model(
    takes: &[TrainingTake],
    validation: &[TrainingTake],
    classes: &[String],
    options: &TrainOptions,
    meta: &ModelMeta,
    on_epoch: &mut dyn FnMut(&EpochReport) -> bool,
) -> Result<Model, String> {
    let trained = (0..options.members.max(1))
        .map(|m| train(takes, validation, classes, &options.member(m), &mut *on_epoch))
        .collect::<Result<Vec<_>, _>>()?;
    model_from(trained, takes, classes, options, meta)
}

/// The model file's contents for finished training runs on `takes` (one per network of an ensemble,
/// in the order of their seeds; [`train`] results or [`super::training::Trainer::finish`]'s). The
/// provenance's epochs are the first network's; an ensemble's lists every network's.
pub fn model_from(
    trained: Vec<Trained>,
    takes: &[TrainingTake],
    classes: &[String],
    options: &TrainOptions,
    meta: &ModelMeta,
) -> Result<Model, String> {
    let first = &trained[0];
    let members = if trained.len() > 1 {
        trained
            .iter()
            .enumerate()
            .map(|(m, t)| MemberRun {
                seed: options.member(m).seed,
                epochs_run: t.reports.len(),
                best_epoch: t.best_epoch,
            })
            .collect()
    } else {
        Vec::new()
    };
    let provenance = Provenance {
        command: meta.command.clone(),
        data_hash: meta.data_hash.clone(),
        takes: takes.iter().map(|t| t.name.clone()).collect(),
        frames: takes.iter().map(|t| t.labels.iter().flatten().count()).sum(),
        // the networks it holds (a continued ensemble keeps its own count; a stopped one, those trained)
        options: Json::of(&TrainOptions { members: trained.len(), ..options.clone() })?,
        epochs_run: first.reports.len(),
        best_epoch: first.best_epoch,
        take_sha256: Vec::new(),
        members,
    };
    let mut h = header(&super::method::DTFCN, classes, meta, provenance);
    h.network = Some(Json::of(&first.network)?);
    h.standardise = Some(first.standardise.clone());
    let config = first.network.clone();
    Ok(Model { header: h, labeller: Box::new(Networks { config, nets: trained.into_iter().map(|t| t.net).collect() }) })
}

/// Per-file-frame labels as the k-NN is given them under `options`' label noise and boundary
/// masking (the mask's width converted from network frames to the file's rate).
pub fn imperfect_labels(
    labels: &[Option<usize>],
    fps: f64,
    classes: usize,
    options: &TrainOptions,
    salt: u64,
) -> Vec<Option<usize>> {
    let mut rng = crate::stats::Rng::new(options.seed ^ (salt.wrapping_mul(0x9e37_79b9)));
    let mut out = super::training::noisy_labels(labels, classes, options.label_noise, &mut rng);
    let w = (options.mask_s * fps).round() as usize;
    let mask = super::training::boundary_mask(labels, w);
    for (l, m) in out.iter_mut().zip(mask) {
        if m == 0.0 {
            *l = None;
        }
    }
    out
}

/// The labeller compared with the network on the same folds ([`predict_held_out`]): the k-NN's
/// `crate::methods::knn::training::knn_fold`, given by the caller so that DT-FCN's folder trains only the network.
pub type Beside<'f, M> = &'f dyn Fn(&FoldTakes) -> Result<FoldLabels<M>, String>;

/// One held-out take's result in cross-validation.
#[derive(Debug, Clone)]
pub struct Fold {
    pub take: String,
    pub network: LabellingScores,
    pub knn: LabellingScores,
    /// The k-NN's k, chosen on the validation take.
    pub knn_k: usize,
    /// Mean confidence the network gave the held-out frames.
    pub confidence: f64,
    /// Epoch chosen on the inner validation take.
    pub best_epoch: usize,
    pub epochs_run: usize,
    pub validation_take: String,
    /// Frame accuracy on the inner validation take at the kept epoch (what may choose settings).
    pub validation_accuracy: f64,
    pub seconds: f64,
}

/// The held-out take's labels in one fold of the nested protocol, by the network and the labeller beside it (the
/// k-NN, whose model is an `M`).
pub struct FoldPrediction<M> {
    /// Per file frame of the held-out take: class and confidence (network) / vote share (k-NN).
    pub network: Vec<(usize, f32)>,
    pub knn: Vec<(usize, f32)>,
    /// The k-NN's k, chosen on the validation take like the network's epoch.
    pub knn_k: usize,
    /// The epoch the validation take chose, of how many run.
    pub best_epoch: usize,
    pub epochs_run: usize,
    /// Frame accuracy on the validation take at that epoch.
    pub validation_accuracy: f64,
    /// The validation take's index.
    pub validation: usize,
    /// Per file frame of the validation take: class and confidence of the network trained without it (the
    /// early-stopped one), so that settings applied after the network — the unknown threshold — can be chosen on it.
    pub validation_labels: Vec<(usize, f32)>,
    /// The same network's class probabilities per working frame of the validation take, and their file positions
    /// (what a decoding is chosen on).
    pub validation_probabilities: crate::labeller::probabilities::Probabilities,
    pub validation_source: Vec<f64>,
    /// The held-out take's class probabilities per working frame by the network trained on all other takes, and
    /// their file positions.
    pub network_probabilities: crate::labeller::probabilities::Probabilities,
    pub network_source: Vec<f64>,
    /// The early-stopped network (trained without the validation take) and the one retrained on every take but
    /// the held-out one, and the k-NN that labelled the held-out take: what an experiment measures further
    /// (the leave-one-class-out's unknowns) without the protocol doing that work for every caller.
    pub validation_network: Trained,
    pub final_network: Trained,
    pub knn_model: M,
}

/// The novelty score ([`super::novelty`]) of every working frame of `motion` under `trained`, fitted on the
/// labelled frames of `takes` (what it was trained on).
pub fn novelty_scores(
    trained: &Trained,
    takes: &[TrainingTake],
    classes: usize,
    motion: &Motion,
) -> Result<Vec<f32>, String> {
    use super::infer::predict_with_features;
    let mut rows = Vec::new();
    let mut labels = Vec::new();
    let mut width = 0;
    for t in takes {
        let (_, f) = predict_with_features(&trained.net, &trained.standardise, &t.input, classes);
        width = f.len() / t.input.frames.max(1);
        for (i, l) in t.labels.iter().enumerate() {
            if let Some(l) = l {
                rows.extend_from_slice(&f[i * width..(i + 1) * width]);
                labels.push(*l);
            }
        }
    }
    let novelty = super::novelty::Novelty::fit(&rows, width, &labels, classes, super::novelty::RANK)?;
    let input = crate::labeller::input::network_input(motion)?;
    let (_, f) = predict_with_features(&trained.net, &trained.standardise, &input, classes);
    Ok(novelty.scores(&f))
}

/// Per working frame of `motion`: the class probabilities under a trained network, and the frames' file positions.
fn probabilities(
    trained: &Trained,
    motion: &Motion,
    classes: usize,
) -> Result<(crate::labeller::probabilities::Probabilities, Vec<f64>), String> {
    let input = crate::labeller::input::network_input(motion)?;
    let probs = super::infer::predict_input(&trained.net, &trained.standardise, &input, classes);
    Ok((probs, input.source_frames))
}

/// Per file frame of `motion`: the most probable class under `trained` and its probability (what the library's
/// label transfer compares with: a network trained on one labelled take).
pub fn label_frames(trained: &Trained, motion: &Motion, classes: usize) -> Result<Vec<(usize, f32)>, String> {
    let (probs, source) = probabilities(trained, motion, classes)?;
    Ok(file_frames_of(&probs, &source, motion))
}

/// Per file frame of `motion`: the most probable class and its probability, from [`probabilities`].
fn file_frames_of(
    probs: &crate::labeller::probabilities::Probabilities,
    source: &[f64],
    motion: &Motion,
) -> Vec<(usize, f32)> {
    let working: Vec<(usize, f32)> = (0..probs.frames).map(|f| probs.best(f)).collect();
    TrainingTake::to_file_frames(source, motion.frames(), &working)
}

/// More training data a protocol makes from the takes a network is trained on (issue 50's data levers: segments
/// spliced into new takes, a subject played on other bones): given the indices of those takes, the takes to train on
/// beside them, each a motion with a label per file frame. Never the held-out or the validation take's motion: the
/// protocol makes them from the indices it is given. [`NO_EXTRA`] adds none.
pub type Extra<'a> = &'a dyn Fn(&[usize]) -> Result<Vec<(Motion, Vec<Option<usize>>)>, String>;

/// No takes beside the labelled ones.
pub const NO_EXTRA: Extra<'static> = &|_| Ok(Vec::new());

/// The training takes of a network trained on `fit` (indices into `motions`) with `extra`'s takes beside them, each
/// take's labels as `prepare` makes them (`i`: a take's index, its extra takes numbered after the labelled ones).
fn training_takes(
    motions: &[Motion],
    labels: &[Vec<Option<usize>>],
    fit: &[usize],
    extra: Extra,
    prepare: &dyn Fn(&Motion, &[Option<usize>], usize) -> Vec<Option<usize>>,
) -> Result<Vec<TrainingTake>, String> {
    let mut out: Vec<TrainingTake> = fit
        .iter()
        .map(|&i| TrainingTake::new(&motions[i], &prepare(&motions[i], &labels[i], i)))
        .collect::<Result<_, _>>()?;
    for (k, (m, l)) in extra(fit)?.iter().enumerate() {
        out.push(TrainingTake::new(m, &prepare(m, l, motions.len() + k))?);
    }
    Ok(out)
}

/// One fold of the nested protocol: take `held` is held out; of the others, the next one in turn
/// is the validation take that chooses the epoch (early stopping); the network is then trained
/// again on all the others for that many epochs and labels the held-out take; `beside` (the k-NN,
/// `crate::methods::knn::training::knn_fold`), fitted on the same takes under the same label noise and masking,
/// labels it too, its setting chosen on the same validation take. The validation take's labels carry the same noise and
/// masking as the training takes' — a user validates on the labels they have. `labels` are the
/// clean labels (per file frame) of every take; the held-out take's are not used.
/// `extra` ([`NO_EXTRA`]: none): takes made from each training's own takes, beside them in both of the network's
/// trainings (`beside` is fitted on the labelled takes alone).
#[allow(clippy::too_many_arguments)]
pub fn predict_held_out<M>(
    motions: &[Motion],
    labels: &[Vec<Option<usize>>],
    held: usize,
    classes: &[String],
    options: &TrainOptions,
    beside: Beside<M>,
    extra: Extra,
    on_epoch: &mut dyn FnMut(&EpochReport) -> bool,
) -> Result<FoldPrediction<M>, String> {
    let n = motions.len();
    if n < 3 {
        return Err(format!("the nested protocol needs at least 3 takes (train, validation, held out); {n} given"));
    }
    let val = (held + 1) % n;
    let imperfect: Vec<Vec<Option<usize>>> =
        (0..n).map(|i| imperfect_labels(&labels[i], motions[i].fps, classes.len(), options, i as u64)).collect();
    let chosen = early_stopped(motions, labels, held, val, classes, options, extra, &mut *on_epoch)?;
    let (validation_probabilities, validation_source) = probabilities(&chosen, &motions[val], classes.len())?;
    let validation_labels = file_frames_of(&validation_probabilities, &validation_source, &motions[val]);
    let trained = retrained(motions, labels, held, classes, options, chosen.best_epoch, extra, on_epoch)?;
    let (network_probabilities, network_source) = probabilities(&trained, &motions[held], classes.len())?;
    let network = file_frames_of(&network_probabilities, &network_source, &motions[held]);
    // the labeller beside the network, fitted on the same takes under the same label noise and masking
    let with_labels = |i: usize| (&motions[i], imperfect[i].as_slice());
    let takes = FoldTakes {
        inner: (0..n).filter(|&i| i != held && i != val).map(with_labels).collect(),
        validation: with_labels(val),
        train: (0..n).filter(|&i| i != held).map(with_labels).collect(),
        held: &motions[held],
    };
    let beside = beside(&takes)?;
    let validation_accuracy =
        chosen.reports.iter().find(|r| r.epoch == chosen.best_epoch).and_then(|r| r.validation_accuracy).unwrap_or(0.0);
    Ok(FoldPrediction {
        network,
        knn: beside.labels,
        knn_k: beside.setting,
        best_epoch: chosen.best_epoch,
        epochs_run: chosen.reports.len(),
        validation_accuracy,
        validation: val,
        validation_labels,
        validation_probabilities,
        validation_source,
        network_probabilities,
        network_source,
        validation_network: chosen,
        final_network: trained,
        knn_model: beside.model,
    })
}

/// The inner half of a nested fold with any inner take as the validation take: a network trained on every take but
/// `held` and `val`, its epoch chosen on `val` (early stopping; `val`'s labels with the options' noise and masking,
/// as [`predict_held_out`] gives them), and `val`'s class probabilities per working frame by it, their file positions
/// and the epoch kept. [`predict_held_out`] validates on the take after `held` alone; this lets a protocol validate
/// on every inner take in turn.
pub fn validation_fold(
    motions: &[Motion],
    labels: &[Vec<Option<usize>>],
    held: usize,
    val: usize,
    classes: &[String],
    options: &TrainOptions,
) -> Result<(crate::labeller::probabilities::Probabilities, Vec<f64>, usize), String> {
    let n = motions.len();
    if n < 3 || held >= n || val >= n || held == val {
        return Err(format!(
            "a validation fold needs 3 or more takes and two different ones of them; {n}, {held}, {val}"
        ));
    }
    let chosen = early_stopped(motions, labels, held, val, classes, options, NO_EXTRA, &mut |_| true)?;
    let (p, source) = probabilities(&chosen, &motions[val], classes.len())?;
    Ok((p, source, chosen.best_epoch))
}

/// The network trained on every take but `held` and `val` (their clean labels: the trainer adds the options'
/// noise) and `extra`'s takes made from them, its epoch chosen on `val`'s labels with the options' noise and masking.
#[allow(clippy::too_many_arguments)]
fn early_stopped(
    motions: &[Motion],
    labels: &[Vec<Option<usize>>],
    held: usize,
    val: usize,
    classes: &[String],
    options: &TrainOptions,
    extra: Extra,
    on_epoch: &mut dyn FnMut(&EpochReport) -> bool,
) -> Result<Trained, String> {
    let fit: Vec<usize> = (0..motions.len()).filter(|&i| i != held && i != val).collect();
    let inner = training_takes(motions, labels, &fit, extra, &|_, l, _| l.to_vec())?;
    let imperfect = imperfect_labels(&labels[val], motions[val].fps, classes.len(), options, val as u64);
    let validation = TrainingTake::new(&motions[val], &imperfect)?;
    train(&inner, &[validation], classes, options, on_epoch)
}

/// The network trained for `epochs` on every take but `held` and `extra`'s takes made from them.
#[allow(clippy::too_many_arguments)]
fn retrained(
    motions: &[Motion],
    labels: &[Vec<Option<usize>>],
    held: usize,
    classes: &[String],
    options: &TrainOptions,
    epochs: usize,
    extra: Extra,
    on_epoch: &mut dyn FnMut(&EpochReport) -> bool,
) -> Result<Trained, String> {
    let fit: Vec<usize> = (0..motions.len()).filter(|&i| i != held).collect();
    let all = training_takes(motions, labels, &fit, extra, &|_, l, _| l.to_vec())?;
    train(&all, &[], classes, &TrainOptions { epochs, ..options.clone() }, on_epoch)
}

/// The outer half of a nested fold: a network trained for `epochs` on every take but `held`, and `held`'s class
/// probabilities per working frame by it with their file positions.
pub fn final_fold(
    motions: &[Motion],
    labels: &[Vec<Option<usize>>],
    held: usize,
    classes: &[String],
    options: &TrainOptions,
    epochs: usize,
) -> Result<(crate::labeller::probabilities::Probabilities, Vec<f64>), String> {
    let trained = retrained(motions, labels, held, classes, options, epochs, NO_EXTRA, &mut |_| true)?;
    probabilities(&trained, &motions[held], classes.len())
}

/// The fold of [`predict_held_out`] with its trainings' weights averaged over their last epochs
/// ([`TrainOptions::average_last`], stochastic weight averaging): what the nested protocol compares
/// `average_last` settings by. Both trainings run `epochs` epochs (the epoch the fold's early stopping chose)
/// with no validation take, so both keep the mean of their last `options.average_last` epochs' weights:
/// one on the inner takes (every take but `held` and the validation take, as the early-stopped network was
/// trained), which labels the validation take — what `average_last` is chosen on — and one on every take but
/// `held`, which labels the held-out take (only when `held_out`: a comparison needs it for the setting it
/// chooses alone). `average_last` = 0 keeps the last epoch's weights: with the same seed, the early-stopped
/// network itself and [`predict_held_out`]'s final one.
///
/// `extra`'s takes (a data lever's; [`NO_EXTRA`]: none) join the training takes of both its trainings.
#[allow(clippy::too_many_arguments)]
pub fn averaged_fold(
    motions: &[Motion],
    labels: &[Vec<Option<usize>>],
    held: usize,
    classes: &[String],
    options: &TrainOptions,
    epochs: usize,
    held_out: bool,
    extra: Extra,
) -> Result<AveragedFold, String> {
    let n = motions.len();
    if n < 3 {
        return Err(format!("the nested protocol needs at least 3 takes (train, validation, held out); {n} given"));
    }
    let val = (held + 1) % n;
    let again = TrainOptions { epochs, ..options.clone() };
    let taken = |keep: &dyn Fn(usize) -> bool| -> Result<Vec<TrainingTake>, String> {
        let fit: Vec<usize> = (0..n).filter(|&i| keep(i)).collect();
        training_takes(motions, labels, &fit, extra, &|m, l, i| {
            imperfect_labels(l, m.fps, classes.len(), options, i as u64)
        })
    };
    let inner = train(&taken(&|i| i != held && i != val)?, &[], classes, &again, &mut |_| true)?;
    let (validation_probabilities, validation_source) = probabilities(&inner, &motions[val], classes.len())?;
    let network = if held_out {
        let all = train(&taken(&|i| i != held)?, &[], classes, &again, &mut |_| true)?;
        Some(probabilities(&all, &motions[held], classes.len())?)
    } else {
        None
    };
    Ok(AveragedFold { validation: val, validation_probabilities, validation_source, network })
}

/// What [`averaged_fold`] predicts: the validation take's class probabilities per working frame (and their file
/// positions) by the inner takes' averaged network, and the held-out take's (when asked for) by the averaged
/// network of every other take.
pub struct AveragedFold {
    pub validation: usize,
    pub validation_probabilities: crate::labeller::probabilities::Probabilities,
    pub validation_source: Vec<f64>,
    pub network: Option<(crate::labeller::probabilities::Probabilities, Vec<f64>)>,
}

/// Leave-one-take-out with [`predict_held_out`] for every take, scored on the held-out take's
/// file frames.
pub fn leave_one_take_out<M>(
    motions: &[Motion],
    labels: &[Vec<Option<usize>>],
    classes: &[String],
    options: &TrainOptions,
    beside: Beside<M>,
    on_epoch: &mut dyn FnMut(&str, &EpochReport) -> bool,
) -> Result<Vec<Fold>, String> {
    let mut folds = Vec::new();
    for held in 0..motions.len() {
        let started = web_time_now();
        let name = motions[held].name.clone();
        let p =
            predict_held_out(motions, labels, held, classes, options, beside, NO_EXTRA, &mut |r| on_epoch(&name, r))?;
        let truth = &labels[held];
        let score = |pred: &[(usize, f32)]| {
            // only where the held-out take is labelled (86_01's walks, say)
            let pred: Vec<Option<usize>> = pred.iter().zip(truth).map(|(p, t)| t.map(|_| p.0)).collect();
            labelling::score(&pred, truth)
        };
        folds.push(Fold {
            take: name,
            network: score(&p.network),
            knn: score(&p.knn),
            knn_k: p.knn_k,
            confidence: p.network.iter().map(|p| p.1 as f64).sum::<f64>() / p.network.len().max(1) as f64,
            best_epoch: p.best_epoch,
            epochs_run: p.epochs_run,
            validation_take: motions[p.validation].name.clone(),
            validation_accuracy: p.validation_accuracy,
            seconds: web_time_now() - started,
        });
    }
    Ok(folds)
}

/// Seconds on a monotonic clock where there is one (0 in wasm, where the caller times itself).
fn web_time_now() -> f64 {
    #[cfg(not(target_arch = "wasm32"))]
    {
        use std::sync::OnceLock;
        use std::time::Instant;
        static START: OnceLock<Instant> = OnceLock::new();
        START.get_or_init(Instant::now).elapsed().as_secs_f64()
    }
    #[cfg(target_arch = "wasm32")]
    {
        0.0
    }
}
