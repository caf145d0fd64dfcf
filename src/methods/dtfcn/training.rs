//! Training (Cheema et al. 2019, §3): per-frame categorical cross-entropy, Adam, and the paper's
//! two experiments on imperfect labels — **label noise** (a share of the training frames given a
//! random label, Table 3) and **boundary masking** (the loss zeroed within a window of
//! `w_transition` frames around every label change, Table 4).
//!
//! burn-train does not build for wasm, so this is a plain loop (autodiff device, gradients,
//! Adam's `step`) that runs the same natively and in the browser's worker. Every random choice
//! (initial weights, noise, crops, augmentation) comes from one seed: the same seed and data
//! give the same model.
//!
//! An epoch: each training take is cut into random crops of `crop_frames` frames (plus the
//! receptive field's half on either side as context, where the take has it, outside the loss),
//! augmented ([`super::augment`]), and fed in batches. With validation takes, the model of the
//! epoch with the lowest validation loss is kept, and training stops after `patience` epochs
//! without a better one (early stopping, the epochs chosen on the validation takes and never on
//! a test take).

use burn::module::Module;
use burn::optim::decay::WeightDecayConfig;
use burn::optim::{AdamConfig, GradientsParams};
use burn::tensor::activation::log_softmax;
use burn::tensor::Tensor;
use serde::{Deserialize, Serialize};

use super::augment::{augment, mirror_classes, Augment};
use super::infer::predict_input;
use super::network::{paper_filters, DtFcn, DtFcnConfig, Padding};
use crate::labeller::input::{centred_on_take, network_input, NetworkInput, Standardise, CHANNELS, NETWORK_FPS};
use crate::motion::Motion;
use crate::segment::frames::WorkingFrames;
use crate::stats::Rng;

/// How to train (defaults: the paper's network and optimiser; crops, batches, augmentation and
/// early stopping are this implementation's choices for small data).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct TrainOptions {
    pub epochs: usize,
    pub learning_rate: f64,
    /// Adam's L2 weight decay (0 = none).
    pub weight_decay: f64,
    pub seed: u64,
    /// Share of training frames given a uniformly random label (Table 3's noise), 0–1.
    pub label_noise: f64,
    /// `w_transition` of Table 4 in seconds: the span around each label change whose loss is
    /// zeroed (0 = none; the paper's 11, 21, 31 frames at 72 Hz are 0.15, 0.29, 0.43 s).
    pub mask_s: f64,
    pub augment: Augment,
    /// Frames of each crop the loss is taken on.
    pub crop_frames: usize,
    /// Crops per optimiser step.
    pub batch: usize,
    /// Epochs without a lower validation loss before stopping (with validation takes).
    pub patience: usize,
    /// Kernel width `w`.
    pub width: usize,
    /// Filters per layer (their count is the layer count L: receptive field `w^L` frames).
    pub filters: Vec<usize>,
    /// What the convolutions read beyond the take's ends.
    pub padding: Padding,
    /// The motion image resized to this many rows before layer 1 (the paper's 224); None: as it is.
    pub image_rows: Option<usize>,
    /// Without a validation take: the kept weights are the mean of the last this many epochs' (stochastic weight
    /// averaging); 0 = the last epoch's.
    #[serde(skip_serializing_if = "is_zero")]
    pub average_last: usize,
    /// Networks trained, with seeds `seed`, `seed + 1`, …, whose class probabilities are averaged (a few-seed
    /// ensemble, not in the paper: one network's held-out accuracy moves by ±0.03 with its seed); 1 = one network.
    #[serde(skip_serializing_if = "is_one")]
    pub members: usize,
    /// Each take centred on its own median posture before the standardisation ([`Standardise::centre_on_take`];
    /// not in the paper). A resumed training keeps its model's.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub centre_on_take: bool,
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

fn is_one(n: &usize) -> bool {
    *n == 1
}

/// The most networks one model holds.
pub const MAX_MEMBERS: usize = 8;

/// The widest boundary mask, in seconds.
pub const MAX_MASK_S: f64 = 10.0;

impl Default for TrainOptions {
    fn default() -> Self {
        TrainOptions {
            epochs: 60,
            learning_rate: 1e-3,
            weight_decay: 1e-4,
            seed: 1,
            label_noise: 0.0,
            mask_s: 0.0,
            augment: Augment::all(),
            crop_frames: 128,
            batch: 2,
            patience: 12,
            // the paper's w = 3 with the layers that give its receptive field in seconds: 3⁴ = 81
            // frames = 2.7 s at 30 Hz (its 3⁵ = 243 frames were 3.4 s at 72 Hz)
            width: 3,
            filters: paper_filters(4),
            padding: Padding::Zero,
            image_rows: None,
            average_last: 0,
            members: 1,
            centre_on_take: false,
        }
    }
}

impl TrainOptions {
    /// Refuses settings training cannot use, naming the setting.
    pub fn check(&self) -> Result<(), String> {
        if self.epochs == 0 || self.epochs > 10_000 {
            return Err(format!("epochs {}: expected 1 to 10000", self.epochs));
        }
        if !(self.learning_rate > 0.0 && self.learning_rate < 1.0) {
            return Err(format!("learning rate {}: expected more than 0 and less than 1", self.learning_rate));
        }
        if !(0.0..1.0).contains(&self.weight_decay) {
            return Err(format!("weight decay {}: expected 0 to 1", self.weight_decay));
        }
        if !(0.0..=1.0).contains(&self.label_noise) {
            return Err(format!("label noise {}: expected a share from 0 to 1", self.label_noise));
        }
        if !(0.0..=MAX_MASK_S).contains(&self.mask_s) {
            return Err(format!("mask {} s: expected 0 to {MAX_MASK_S} s", self.mask_s));
        }
        self.network(2).check()?;
        if !(16..=4096).contains(&self.crop_frames) {
            return Err(format!("crop {} frames: expected 16 to 4096", self.crop_frames));
        }
        if !(1..=64).contains(&self.batch) {
            return Err(format!("batch {}: expected 1 to 64 crops", self.batch));
        }
        if !(1..=MAX_MEMBERS).contains(&self.members) {
            return Err(format!("members {}: expected 1 to {MAX_MEMBERS} networks", self.members));
        }
        Ok(())
    }

    /// The network these options train for `classes` classes.
    pub fn network(&self, classes: usize) -> DtFcnConfig {
        DtFcnConfig {
            channels: CHANNELS,
            classes,
            width: self.width,
            filters: self.filters.clone(),
            padding: self.padding,
            image_rows: self.image_rows,
        }
    }

    /// The options member `m` (0-based) of an ensemble trains with: its own seed, one network.
    pub fn member(&self, m: usize) -> TrainOptions {
        TrainOptions { seed: self.seed.wrapping_add(m as u64), members: 1, ..self.clone() }
    }

    /// `w_transition` in the network's frames.
    pub fn mask_frames(&self) -> usize {
        (self.mask_s * NETWORK_FPS).round() as usize
    }
}

/// A labelled take ready for training: its motion image and the label of each working frame.
#[derive(Debug, Clone, PartialEq)]
pub struct TrainingTake {
    pub name: String,
    pub input: NetworkInput,
    /// Per working frame; `None` where the take is not labelled.
    pub labels: Vec<Option<usize>>,
}

impl TrainingTake {
    /// `motion` with one label per file frame (`None` = unlabelled).
    pub fn new(motion: &Motion, file_labels: &[Option<usize>]) -> Result<TrainingTake, String> {
        let input = network_input(motion)?;
        let labels = input
            .source_frames
            .iter()
            .map(|&s| {
                file_labels
                    .get((s.round().max(0.0) as usize).min(file_labels.len().saturating_sub(1)))
                    .copied()
                    .flatten()
            })
            .collect();
        Ok(TrainingTake { name: motion.name.clone(), input, labels })
    }

    /// Per-file-frame labels of `predicted` working frames (for scoring at the file's rate).
    pub fn to_file_frames<T: Copy>(source_frames: &[f64], file_frames: usize, working: &[T]) -> Vec<T> {
        let frames = WorkingFrames { source: source_frames, file_frames };
        (0..file_frames).map(|f| working[frames.working_frame(f)]).collect()
    }
}

/// What one epoch did.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EpochReport {
    /// 1-based.
    pub epoch: usize,
    pub epochs: usize,
    /// Mean masked cross-entropy over the epoch's batches (on the labels trained on).
    pub loss: f64,
    /// Share of the crops' frames whose most probable class is their true (noise-free) label.
    pub train_accuracy: f64,
    pub validation_loss: Option<f64>,
    pub validation_accuracy: Option<f64>,
    /// This epoch's model is the best so far (lowest validation loss; the last one without).
    pub best: bool,
}

/// A trained network with what it needs to label new takes.
pub struct Trained {
    pub network: DtFcnConfig,
    /// On the plain (non-autodiff) device.
    pub net: DtFcn,
    pub standardise: Standardise,
    pub reports: Vec<EpochReport>,
    /// Epoch (1-based) of the kept weights.
    pub best_epoch: usize,
    /// The run was stopped by the caller before its last epoch (the best model so far is kept).
    pub stopped: bool,
}

/// The training labels after the paper's noise: each labelled frame, with probability `share`,
/// gets a class drawn uniformly from all `classes` (which may be its own).
pub fn noisy_labels(labels: &[Option<usize>], classes: usize, share: f64, rng: &mut Rng) -> Vec<Option<usize>> {
    labels
        .iter()
        .map(|l| {
            let draw = rng.next_f32() as f64;
            let class = rng.below(classes);
            l.map(|l| if draw < share { class } else { l })
        })
        .collect()
}

/// 0 on every frame within `w_transition / 2` frames of a change of `labels` (between two
/// labelled frames, or labelled and unlabelled), 1 elsewhere — and 0 on unlabelled frames.
pub fn boundary_mask(labels: &[Option<usize>], w_transition: usize) -> Vec<f32> {
    let mut mask: Vec<f32> = labels.iter().map(|l| if l.is_some() { 1.0 } else { 0.0 }).collect();
    if w_transition == 0 {
        return mask;
    }
    let half = w_transition / 2;
    let n = labels.len();
    for t in 1..n {
        if labels[t] != labels[t - 1] {
            // the change lies between t−1 and t: w_transition frames centred on it
            let lo = t.saturating_sub(half.max(1));
            let hi = (t + w_transition - half.max(1)).min(n);
            mask[lo..hi].iter_mut().for_each(|m| *m = 0.0);
        }
    }
    mask
}

/// One crop of a take with its context: the frames fed, the labels trained on, the true
/// labels, and which frames the loss is taken on.
struct Crop {
    input: NetworkInput,
    labels: Vec<Option<usize>>,
    clean: Vec<Option<usize>>,
    weight: Vec<f32>,
}

/// Masked mean cross-entropy of `logits` `[b, k, t]` against one-hot `target` with per-frame
/// `weight` `[b, 1, t]`.
fn masked_cross_entropy(logits: Tensor<3>, target: Tensor<3>, weight: Tensor<3>, total: f32) -> Tensor<1> {
    let lp = log_softmax(logits, 1);
    lp.mul(target).mul(weight).sum().neg().div_scalar(total.max(1.0))
}

/// Trains a network on `takes` (labels per working frame, classes `0..classes.len()`),
/// choosing the epoch on `validation` when given. `on_epoch` sees every epoch's report and
/// returns `false` to stop (the best model so far is kept).
pub fn train(
    takes: &[TrainingTake],
    validation: &[TrainingTake],
    classes: &[String],
    options: &TrainOptions,
    on_epoch: &mut dyn FnMut(&EpochReport) -> bool,
) -> Result<Trained, String> {
    let mut trainer = Trainer::new(takes.to_vec(), validation.to_vec(), classes.to_vec(), options.clone())?;
    while !trainer.done() {
        let report = trainer.epoch()?;
        if !on_epoch(&report) {
            trainer.stop();
        }
    }
    trainer.finish()
}

/// A training run one epoch at a time, so that a caller that cannot be interrupted (the
/// browser's worker) can take messages — a stop, say — between epochs.
pub struct Trainer {
    takes: Vec<TrainingTake>,
    validation: Vec<TrainingTake>,
    classes: usize,
    options: TrainOptions,
    network: DtFcnConfig,
    standardise: Standardise,
    mirror_of: Vec<usize>,
    rng: Rng,
    device: burn::tensor::Device,
    net: Option<DtFcn>,
    optim: burn::optim::ModuleOptimizer,
    trained_labels: Vec<Vec<Option<usize>>>,
    masks: Vec<Vec<f32>>,
    margin: usize,
    reports: Vec<EpochReport>,
    best: Option<(f64, DtFcn, usize)>,
    since_best: usize,
    stopped: bool,
    /// The summed weights of the epochs averaged so far, and how many ([`TrainOptions::average_last`]).
    averaged: Option<(Vec<Vec<f32>>, usize)>,
}

/// Every float parameter of `net`, in the order burn visits them.
pub fn weights_of(net: &DtFcn) -> Vec<Vec<f32>> {
    use burn::module::{ModuleVisitor, Param};
    struct Collect(Vec<Vec<f32>>);
    impl ModuleVisitor for Collect {
        fn visit_float<const D: usize>(&mut self, param: &Param<Tensor<D>>) {
            self.0.push(param.val().into_data().convert::<f32>().try_to_vec::<f32>().unwrap_or_default());
        }
    }
    let mut c = Collect(Vec::new());
    net.visit(&mut c);
    c.0
}

/// `net` with every float parameter set to `values` (in [`weights_of`]'s order) times `scale`.
fn with_weights(net: DtFcn, values: &[Vec<f32>], scale: f32) -> DtFcn {
    use burn::module::{ModuleMapper, Param};
    struct Put<'a> {
        values: &'a [Vec<f32>],
        at: usize,
        scale: f32,
    }
    impl ModuleMapper for Put<'_> {
        fn map_float<const D: usize>(&mut self, param: Param<Tensor<D>>) -> Param<Tensor<D>> {
            let v: Vec<f32> = self.values[self.at].iter().map(|x| x * self.scale).collect();
            self.at += 1;
            param.map(|t| {
                let (shape, device) = (t.shape(), t.device());
                Tensor::<1>::from_floats(v.as_slice(), &device).reshape(shape)
            })
        }
    }
    net.map(&mut Put { values, at: 0, scale })
}

impl Trainer {
    /// Checks the data and options and prepares the network, noisy labels and masks.
    pub fn new(
        takes: Vec<TrainingTake>,
        validation: Vec<TrainingTake>,
        classes: Vec<String>,
        options: TrainOptions,
    ) -> Result<Trainer, String> {
        Trainer::starting_from(takes, validation, classes, options, None)
    }

    /// As [`Trainer::new`], but from the weights of `start` (a network of `classes.len()` classes
    /// and the input scaling it was trained with, both kept: the options' network shape is not
    /// used) for `options.epochs` more epochs; Adam's moments start afresh.
    pub fn resume(
        takes: Vec<TrainingTake>,
        validation: Vec<TrainingTake>,
        classes: Vec<String>,
        options: TrainOptions,
        start: (DtFcnConfig, Standardise, DtFcn),
    ) -> Result<Trainer, String> {
        Trainer::starting_from(takes, validation, classes, options, Some(start))
    }

    fn starting_from(
        takes: Vec<TrainingTake>,
        validation: Vec<TrainingTake>,
        classes: Vec<String>,
        options: TrainOptions,
        start: Option<(DtFcnConfig, Standardise, DtFcn)>,
    ) -> Result<Trainer, String> {
        options.check()?;
        let k = classes.len();
        let network = match &start {
            Some((config, _, _)) => config.clone(),
            None => options.network(k),
        };
        network.check()?;
        if network.classes != k {
            return Err(format!("the network labels {} classes, the labels have {k}", network.classes));
        }
        if takes.is_empty() {
            return Err("no training takes".into());
        }
        for t in takes.iter().chain(&validation) {
            if let Some(bad) = t.labels.iter().flatten().find(|&&l| l >= k) {
                return Err(format!("{}: label index {bad} but only {k} classes", t.name));
            }
        }
        if takes.iter().all(|t| t.labels.iter().all(Option::is_none)) {
            return Err("the training takes have no labelled frame".into());
        }
        let mirror_of = mirror_classes(&classes);
        let mut rng = Rng::new(options.seed);
        let device = super::device().autodiff();
        // a resumed model centres (or not) as it was trained to
        let centre = start.as_ref().map_or(options.centre_on_take, |(_, s, _)| s.centre_on_take);
        // whole takes centred before augmentation and crops (a crop's own median is not its take's)
        let takes: Vec<TrainingTake> = if centre {
            takes.into_iter().map(|t| TrainingTake { input: centred_on_take(&t.input), ..t }).collect()
        } else {
            takes
        };
        let (standardise, net) = match start {
            // the weights kept, made trainable again (autodiff, gradients as configured)
            Some((_, standardise, net)) => (standardise, net.train()),
            None => (
                Standardise::fit(&takes.iter().map(|t| &t.input).collect::<Vec<_>>()).centring(centre),
                network.init_seeded(&device, options.seed ^ 0x5eed_d7fc_u64),
            ),
        };
        let optim = AdamConfig::new()
            .with_weight_decay(
                (options.weight_decay > 0.0).then(|| WeightDecayConfig::new(options.weight_decay as f32)),
            )
            .init();
        // the paper's noisy labels are drawn once, as a noisy annotation would be
        let trained_labels: Vec<Vec<Option<usize>>> =
            takes.iter().map(|t| noisy_labels(&t.labels, k, options.label_noise, &mut rng)).collect();
        let masks: Vec<Vec<f32>> = takes.iter().map(|t| boundary_mask(&t.labels, options.mask_frames())).collect();
        let margin = network.receptive_field() / 2;
        Ok(Trainer {
            takes,
            validation,
            classes: k,
            options,
            network,
            standardise,
            mirror_of,
            rng,
            device,
            net: Some(net),
            optim,
            trained_labels,
            masks,
            margin,
            reports: Vec::new(),
            best: None,
            since_best: 0,
            averaged: None,
            stopped: false,
        })
    }

    /// Every epoch ran, early stopping ended the run, or [`Trainer::stop`] was called.
    pub fn done(&self) -> bool {
        self.stopped
            || self.reports.len() >= self.options.epochs
            || (!self.validation.is_empty() && self.since_best >= self.options.patience)
    }

    /// Ends the run after the epochs so far (the best model so far is kept).
    pub fn stop(&mut self) {
        self.stopped = true;
    }

    /// Reports of the epochs so far.
    pub fn reports(&self) -> &[EpochReport] {
        &self.reports
    }

    /// Random crops of every take, augmented.
    fn crops(&mut self) -> Vec<Crop> {
        let options = &self.options;
        let mut crops = Vec::new();
        for (ti, t) in self.takes.iter().enumerate() {
            let n = t.input.frames;
            let count = n.div_ceil(options.crop_frames).max(1);
            for _ in 0..count {
                let core = options.crop_frames.min(n);
                let start = self.rng.below(n - core + 1);
                let (lo, hi) = (start.saturating_sub(self.margin), (start + core + self.margin).min(n));
                let input = slice_input(&t.input, lo, hi);
                let weight: Vec<f32> = (lo..hi)
                    .map(|f| if (start..start + core).contains(&f) { self.masks[ti][f] } else { 0.0 })
                    .collect();
                let a = augment(input, &options.augment, &mut self.rng);
                crops.push(Crop {
                    labels: a.labels(&self.trained_labels[ti][lo..hi], &self.mirror_of),
                    clean: a.labels(&t.labels[lo..hi], &self.mirror_of),
                    weight: a.carry(&weight),
                    input: a.input,
                });
            }
        }
        shuffle(&mut crops, &mut self.rng);
        crops
    }

    /// Runs the next epoch.
    pub fn epoch(&mut self) -> Result<EpochReport, String> {
        let epoch = self.reports.len() + 1;
        let k = self.classes;
        let crops = self.crops();
        let (mut loss_sum, mut batches, mut right, mut counted) = (0.0, 0, 0usize, 0usize);
        for batch in crops.chunks(self.options.batch) {
            let len = batch.iter().map(|c| c.input.frames).max().unwrap_or(1);
            let b = batch.len();
            let mut x = vec![0f32; b * CHANNELS * len];
            let mut target = vec![0f32; b * k * len];
            let mut weight = vec![0f32; b * len];
            for (i, c) in batch.iter().enumerate() {
                // the takes were centred whole (if at all): a crop is only scaled
                let z = self.standardise.scale(&c.input);
                let n = c.input.frames;
                for ch in 0..CHANNELS {
                    let at = (i * CHANNELS + ch) * len;
                    x[at..at + n].copy_from_slice(&z[ch * n..(ch + 1) * n]);
                }
                for t in 0..n {
                    if let (Some(l), true) = (c.labels[t], c.weight[t] > 0.0) {
                        target[(i * k + l) * len + t] = 1.0;
                        weight[i * len + t] = c.weight[t];
                    }
                }
            }
            let total: f32 = weight.iter().sum();
            if total == 0.0 {
                continue;
            }
            let ad = &self.device;
            let xt = Tensor::<1>::from_floats(x.as_slice(), ad).reshape([b, CHANNELS, len]);
            let tt = Tensor::<1>::from_floats(target.as_slice(), ad).reshape([b, k, len]);
            let wt = Tensor::<1>::from_floats(weight.as_slice(), ad).reshape([b, 1, len]);
            let net = self.net.take().ok_or("the network was lost in a failed step")?;
            let logits = net.logits(xt);
            let loss = masked_cross_entropy(logits.clone(), tt, wt, total);
            let loss_value: f32 = loss.clone().into_scalar();
            if !loss_value.is_finite() {
                return Err(format!("epoch {epoch}: the loss became {loss_value} (learning rate too high?)"));
            }
            let grads = GradientsParams::from_grads(loss.backward(), &net);
            self.net = Some(self.optim.step(self.options.learning_rate, net, grads));
            loss_sum += loss_value as f64;
            batches += 1;
            // accuracy on the crops' true labels, where the loss was taken
            let arg: Vec<i64> =
                logits.inner().argmax(1).into_data().convert::<i64>().try_to_vec::<i64>().unwrap_or_default();
            for (i, c) in batch.iter().enumerate() {
                for t in 0..c.input.frames {
                    if let (Some(truth), true) = (c.clean[t], c.weight[t] > 0.0) {
                        counted += 1;
                        right += usize::from(arg.get(i * len + t).copied() == Some(truth as i64));
                    }
                }
            }
        }
        let valid = self.net.as_ref().ok_or("no network")?.valid();
        let averaging = self.options.average_last;
        if self.validation.is_empty() && averaging > 0 && epoch + averaging > self.options.epochs {
            let w = weights_of(&valid);
            self.averaged = Some(match self.averaged.take() {
                None => (w, 1),
                Some((mut sum, n)) => {
                    sum.iter_mut().zip(&w).for_each(|(s, x)| s.iter_mut().zip(x).for_each(|(a, b)| *a += b));
                    (sum, n + 1)
                }
            });
        }
        let (validation_loss, validation_accuracy) = if self.validation.is_empty() {
            (None, None)
        } else {
            let (l, a) = evaluate(&valid, &self.standardise, &self.validation, k)?;
            (Some(l), Some(a))
        };
        let score = validation_loss.unwrap_or(-(epoch as f64));
        let is_best = self.best.as_ref().is_none_or(|(b, _, _)| score < *b);
        if is_best {
            self.best = Some((score, valid, epoch));
            self.since_best = 0;
        } else {
            self.since_best += 1;
        }
        let report = EpochReport {
            epoch,
            epochs: self.options.epochs,
            loss: loss_sum / batches.max(1) as f64,
            train_accuracy: right as f64 / counted.max(1) as f64,
            validation_loss,
            validation_accuracy,
            best: is_best,
        };
        self.reports.push(report.clone());
        Ok(report)
    }

    /// The kept network (the best epoch's with validation takes, else the last's).
    pub fn finish(self) -> Result<Trained, String> {
        let stopped = self.stopped && self.reports.len() < self.options.epochs;
        let (_, net, best_epoch) = self.best.ok_or("training ran no epoch")?;
        let net = match &self.averaged {
            Some((sum, n)) if !stopped => with_weights(net, sum, 1.0 / *n as f32),
            _ => net,
        };
        Ok(Trained {
            network: self.network,
            net,
            standardise: self.standardise,
            reports: self.reports,
            best_epoch,
            stopped,
        })
    }
}

/// Mean cross-entropy and frame accuracy of `net` on the labelled frames of `takes`.
pub fn evaluate(
    net: &DtFcn,
    standardise: &Standardise,
    takes: &[TrainingTake],
    classes: usize,
) -> Result<(f64, f64), String> {
    let (mut loss, mut right, mut n) = (0.0, 0usize, 0usize);
    for t in takes {
        let probs = predict_input(net, standardise, &t.input, classes);
        for (f, l) in t.labels.iter().enumerate() {
            if let Some(l) = *l {
                let p = probs.prob(f, l).max(1e-12);
                loss -= (p as f64).ln();
                right += usize::from(probs.best(f).0 == l);
                n += 1;
            }
        }
    }
    if n == 0 {
        return Err("the validation takes have no labelled frame".into());
    }
    Ok((loss / n as f64, right as f64 / n as f64))
}

/// Frames `lo..hi` of `input`.
fn slice_input(input: &NetworkInput, lo: usize, hi: usize) -> NetworkInput {
    let n = input.frames;
    let m = hi - lo;
    let mut values = Vec::with_capacity(CHANNELS * m);
    for c in 0..CHANNELS {
        values.extend_from_slice(&input.values[c * n + lo..c * n + hi]);
    }
    NetworkInput { values, frames: m, source_frames: input.source_frames[lo..hi].to_vec() }
}

/// Fisher–Yates.
fn shuffle<T>(items: &mut [T], rng: &mut Rng) {
    for i in (1..items.len()).rev() {
        let j = rng.below(i + 1);
        items.swap(i, j);
    }
}
