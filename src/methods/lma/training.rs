//! Training the Effort classifier family (Bouchard & Badler §4.1), from a [`Corpus`]:
//!
//! 1. a share of the segments is set aside for validation (seeded);
//! 2. **saliency** (Ruck et al. 1990): "the saliency of each feature is computed using the average
//!    saliency of the feature over many random subsets of the potential features" — small networks
//!    on random subsets of the standardised pool, each feature scored by the mean output
//!    sensitivity to it, averaged over the subsets it was drawn in; the most salient are kept;
//! 3. **PCA** of the kept features to 95 % of their variance;
//! 4. **hidden units** (Park et al. 1996, as the paper): a wide network is trained, and the hidden
//!    layer gets as many units as principal components of its hidden activations hold 98 % of
//!    their variance;
//! 5. the unshifted network: best validation error of `restarts` random initialisations, each
//!    stopped when its validation loss stops improving;
//! 6. every other shift (i, j): the same labels on the segments `start + i ..= end + j`, trained
//!    from the unshifted network's weights (one fine-tuning each instead of 20 restarts: the
//!    family then shares one solution and differs where the shift matters — and 120 × 4 × 20
//!    restarts would not fit a browser's patience).

use nalgebra::{DMatrix, SymmetricEigen};

use super::classifier::{EffortModel, FactorModel};
use super::corpus::{Corpus, Sample};
use super::effort::Factor;
use super::features::{Pool, POOL_SIZE};
use super::network::{classification_error, train, train_restarts, Data, Net, TrainOptions};
use crate::method::Cancelled;
use crate::stats::Rng;

/// How the family is trained (defaults: the paper's where it gives them).
#[derive(Debug, Clone, PartialEq)]
pub struct TrainConfig {
    pub seed: u64,
    /// Random initialisations of each unshifted network (paper: 20).
    pub restarts: usize,
    /// Most salient features kept per factor (paper: 57–84).
    pub selected: usize,
    /// Variance the principal components keep (paper: 95 %).
    pub variance: f64,
    /// Variance of the hidden activations the hidden units keep (paper: 98 %), and the widest layer tried.
    pub hidden_variance: f64,
    pub widest_hidden: usize,
    /// Random feature subsets for the saliency, and their size.
    pub saliency_rounds: usize,
    pub subset: usize,
    /// Share of the segments kept for validation.
    pub validation: f64,
    pub options: TrainOptions,
    /// Fine-tuning of the shifted networks.
    pub shift_options: TrainOptions,
}

impl Default for TrainConfig {
    fn default() -> Self {
        TrainConfig {
            seed: 1,
            restarts: 20,
            selected: 60,
            variance: 0.95,
            hidden_variance: 0.98,
            widest_hidden: 10,
            saliency_rounds: 24,
            subset: 40,
            validation: 0.2,
            options: TrainOptions { max_epochs: 300, learning_rate: 0.02, weight_decay: 1e-4, patience: 25 },
            shift_options: TrainOptions { max_epochs: 40, learning_rate: 0.01, weight_decay: 1e-4, patience: 8 },
        }
    }
}

/// What training found, per factor.
#[derive(Debug, Clone, PartialEq)]
pub struct FactorReport {
    pub factor: Factor,
    pub selected: usize,
    pub components: usize,
    pub hidden: usize,
    /// The unshifted network's error on the training and validation segments (the paper's rule).
    pub train_error: f32,
    pub validation_error: f32,
    /// Mean validation error of the shifted networks on their shifted segments.
    pub shifted_validation_error: f32,
    /// The five most salient features.
    pub most_salient: Vec<String>,
}

/// Features `which` of `samples` (shifted by `(i, j)`), row-major.
fn features(corpus: &Corpus, samples: &[Sample], which: &[u16], (i, j): (isize, isize)) -> Vec<f32> {
    let mut out = vec![0.0; samples.len() * which.len()];
    for (row, s) in out.chunks_exact_mut(which.len().max(1)).zip(samples) {
        let pool: &Pool = &corpus.sources[s.source].pool;
        let (a, b) = super::classifier::shifted(s.start, s.end, i, j, pool.frames());
        pool.features(which, a, b, row);
    }
    out
}

/// Inputs and their one-hot targets over the three Effort elements.
fn data<'a>(x: &'a [f32], y: &'a [f32]) -> Data<'a> {
    Data { x, y, outputs: 3 }
}

fn one_hot(samples: &[Sample], factor: usize) -> Vec<f32> {
    samples.iter().flat_map(|s| (0..3).map(move |c| if s.classes[factor] == c { 1.0 } else { 0.0 })).collect()
}

/// Column means and standard deviations of a row-major `n × d` matrix (a constant column gets 1).
fn moments(x: &[f32], d: usize) -> (Vec<f32>, Vec<f32>) {
    let n = (x.len() / d.max(1)).max(1) as f64;
    let mut mean = vec![0.0f64; d];
    let mut sq = vec![0.0f64; d];
    for row in x.chunks_exact(d) {
        for k in 0..d {
            mean[k] += row[k] as f64 / n;
            sq[k] += (row[k] as f64).powi(2) / n;
        }
    }
    let scale = mean.iter().zip(&sq).map(|(m, s)| (s - m * m).max(0.0).sqrt()).map(|s| if s > 1e-9 { s } else { 1.0 });
    (mean.iter().map(|&m| m as f32).collect(), scale.map(|s| s as f32).collect())
}

fn standardise(x: &mut [f32], mean: &[f32], scale: &[f32]) {
    for row in x.chunks_exact_mut(mean.len().max(1)) {
        for ((v, m), s) in row.iter_mut().zip(mean).zip(scale) {
            *v = (*v - m) / s;
        }
    }
}

/// Principal axes of the rows of `x` (`n × d`, centred) keeping `share` of the variance: `(k, k × d axes)`.
fn principal_axes(x: &[f32], d: usize, share: f64) -> (usize, Vec<f32>) {
    let n = x.len() / d.max(1);
    let m = DMatrix::from_row_slice(n, d, &x.iter().map(|&v| v as f64).collect::<Vec<_>>());
    let cov = (m.transpose() * &m) / (n.max(2) - 1) as f64;
    let eig = SymmetricEigen::new(cov);
    let mut order: Vec<usize> = (0..d).collect();
    order.sort_by(|&a, &b| eig.eigenvalues[b].total_cmp(&eig.eigenvalues[a]));
    let total: f64 = eig.eigenvalues.iter().map(|v| v.max(0.0)).sum();
    let mut kept = 0.0;
    let mut k = 0;
    while k < d && (k == 0 || kept < share * total) {
        kept += eig.eigenvalues[order[k]].max(0.0);
        k += 1;
    }
    let axes = order[..k]
        .iter()
        .flat_map(|&c| eig.eigenvectors.column(c).iter().map(|&v| v as f32).collect::<Vec<_>>())
        .collect();
    (k, axes)
}

/// `z = axes · x` for every row.
fn project(x: &[f32], d: usize, axes: &[f32], k: usize) -> Vec<f32> {
    x.chunks_exact(d.max(1))
        .flat_map(|row| (0..k).map(move |c| axes[c * d..(c + 1) * d].iter().zip(row).map(|(a, b)| a * b).sum::<f32>()))
        .collect()
}

/// Hidden units by Park et al.: principal components of a wide network's hidden activations to `share`.
fn hidden_units(net: &Net, x: &[f32], share: f64) -> usize {
    let h = net.hidden;
    let mut acts = Vec::with_capacity(x.len() / net.inputs.max(1) * h);
    let mut hidden = vec![0.0; h];
    let mut out = vec![0.0; net.outputs];
    for row in x.chunks_exact(net.inputs.max(1)) {
        net.forward(row, &mut hidden, &mut out);
        acts.extend_from_slice(&hidden);
    }
    let (mean, _) = moments(&acts, h);
    for row in acts.chunks_exact_mut(h) {
        for (v, m) in row.iter_mut().zip(&mean) {
            *v -= m;
        }
    }
    principal_axes(&acts, h, share).0.max(2)
}

/// Trains the family on `corpus`; reports `(stage, fraction)` and stops when asked.
pub fn train_family(
    corpus: &Corpus,
    config: &TrainConfig,
    progress: &mut dyn FnMut(&str, f64) -> Result<(), Cancelled>,
) -> Result<(EffortModel, Vec<FactorReport>), String> {
    let cancelled = |_: Cancelled| "cancelled".to_string();
    let s = corpus.config.max_shift as isize;
    // 1. the validation share
    let mut rng = Rng::new(config.seed);
    let mut order: Vec<usize> = (0..corpus.samples.len()).collect();
    for k in (1..order.len()).rev() {
        order.swap(k, rng.below(k + 1));
    }
    let cut = ((corpus.samples.len() as f64 * config.validation).round() as usize).min(corpus.samples.len() / 2);
    let valid: Vec<Sample> = order[..cut].iter().map(|&k| corpus.samples[k]).collect();
    let train_set: Vec<Sample> = order[cut..].iter().map(|&k| corpus.samples[k]).collect();
    if train_set.len() < 6 {
        return Err(format!("{} segments are too few to train on (at least 8)", corpus.samples.len()));
    }
    let all: Vec<u16> = (0..POOL_SIZE as u16).collect();
    let pool_x = features(corpus, &train_set, &all, (0, 0));
    let (pool_mean, pool_scale) = moments(&pool_x, POOL_SIZE);
    let mut pool_std = pool_x.clone();
    standardise(&mut pool_std, &pool_mean, &pool_scale);
    let steps = 4.0;
    let mut factors = Vec::new();
    let mut reports = Vec::new();
    for (f, factor) in Factor::ALL.into_iter().enumerate() {
        let base = f as f64 / steps;
        let y_train = one_hot(&train_set, f);
        let y_valid = one_hot(&valid, f);
        // 2. saliency over random subsets
        progress(&format!("{} saliency", factor.name()), base).map_err(cancelled)?;
        let mut saliency = vec![0.0f64; POOL_SIZE];
        let mut drawn = vec![0usize; POOL_SIZE];
        let subset = config.subset.min(POOL_SIZE);
        for round in 0..config.saliency_rounds {
            let mut pick: Vec<usize> = (0..POOL_SIZE).collect();
            for k in 0..subset {
                pick.swap(k, k + rng.below(POOL_SIZE - k));
            }
            let pick = &pick[..subset];
            let x: Vec<f32> = pool_std.chunks_exact(POOL_SIZE).flat_map(|r| pick.iter().map(move |&k| r[k])).collect();
            let quick = TrainOptions { max_epochs: 60, ..config.options };
            let (net, _) = train(Net::random(subset, 5, 3, &mut rng), &data(&x, &y_train), &data(&[], &[]), &quick);
            let mut sum = vec![0.0f64; subset];
            for row in x.chunks_exact(subset) {
                for (a, b) in sum.iter_mut().zip(net.sensitivity(row)) {
                    *a += b as f64;
                }
            }
            for (&k, v) in pick.iter().zip(sum) {
                saliency[k] += v / train_set.len() as f64;
                drawn[k] += 1;
            }
            let fraction = base + 0.3 / steps * (round + 1) as f64 / config.saliency_rounds as f64;
            progress(&format!("{} saliency", factor.name()), fraction).map_err(cancelled)?;
        }
        let score: Vec<f64> =
            saliency.iter().zip(&drawn).map(|(s, &n)| if n > 0 { s / n as f64 } else { 0.0 }).collect();
        let mut ranked: Vec<u16> = (0..POOL_SIZE as u16).collect();
        ranked.sort_by(|&a, &b| score[b as usize].total_cmp(&score[a as usize]));
        let selected: Vec<u16> = ranked[..config.selected.clamp(1, POOL_SIZE)].to_vec();
        // 3. PCA of the selected, standardised features
        let n_sel = selected.len();
        let (mean, scale) = (
            selected.iter().map(|&k| pool_mean[k as usize]).collect::<Vec<_>>(),
            selected.iter().map(|&k| pool_scale[k as usize]).collect::<Vec<_>>(),
        );
        let inputs = |samples: &[Sample], shift: (isize, isize)| {
            let mut x = features(corpus, samples, &selected, shift);
            standardise(&mut x, &mean, &scale);
            x
        };
        let x_train = inputs(&train_set, (0, 0));
        let (components, axes) = principal_axes(&x_train, n_sel, config.variance);
        let z_train = project(&x_train, n_sel, &axes, components);
        let z_valid = project(&inputs(&valid, (0, 0)), n_sel, &axes, components);
        let train_data = data(&z_train, &y_train);
        let valid_data = data(&z_valid, &y_valid);
        // 4. hidden units (Park et al.)
        progress(&format!("{} network", factor.name()), base + 0.35 / steps).map_err(cancelled)?;
        let (wide, _) = train(
            Net::random(components, config.widest_hidden, 3, &mut rng),
            &train_data,
            &valid_data,
            &config.options,
        );
        let hidden = hidden_units(&wide, &z_train, config.hidden_variance).min(config.widest_hidden);
        // 5. the unshifted network, best of the restarts
        let seed = config.seed.wrapping_mul(1000).wrapping_add(f as u64);
        let (central, _) = train_restarts(
            components,
            hidden,
            3,
            &train_data,
            &valid_data,
            &config.options,
            config.restarts.max(1),
            seed,
        );
        // 6. the shifted family, fine-tuned from it
        let mut nets = Vec::with_capacity(((2 * s + 1) * (2 * s + 1)) as usize);
        let mut shifted_error = 0.0;
        for i in -s..=s {
            for j in -s..=s {
                if i == 0 && j == 0 {
                    nets.push(central.clone());
                    shifted_error += classification_error(&central, &valid_data);
                    continue;
                }
                let zt = project(&inputs(&train_set, (i, j)), n_sel, &axes, components);
                let zv = project(&inputs(&valid, (i, j)), n_sel, &axes, components);
                let (td, vd) = (data(&zt, &y_train), data(&zv, &y_valid));
                let (net, _) = train(central.clone(), &td, &vd, &config.shift_options);
                shifted_error += classification_error(&net, &vd);
                nets.push(net);
            }
            let fraction = base + (0.45 + 0.55 * (i + s + 1) as f64 / (2 * s + 1) as f64) / steps;
            progress(&format!("{} shifted networks", factor.name()), fraction).map_err(cancelled)?;
        }
        let validation_error = classification_error(&central, &valid_data);
        reports.push(FactorReport {
            factor,
            selected: n_sel,
            components,
            hidden,
            train_error: classification_error(&central, &train_data),
            validation_error,
            shifted_validation_error: shifted_error / nets.len() as f32,
            most_salient: selected.iter().take(5).map(|&k| Pool::name(k as usize)).collect(),
        });
        factors.push(FactorModel { selected, mean, scale, projection: axes, components, nets, validation_error });
    }
    let c = corpus.config;
    let model = EffortModel {
        fps: c.fps,
        max_shift: c.max_shift,
        min_len: c.min_len,
        max_len: c.max_len,
        origin: corpus.origin.clone(),
        samples: corpus.samples.len(),
        factors,
    };
    Ok((model, reports))
}
