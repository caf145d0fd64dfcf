//! Training the Effort classifier family (Bouchard & Badler §4.1), from a [`Corpus`]:
//!
//! 1. per factor, the segments are split three ways, stratified by that factor's class (the paper's
//!    validation set holds an indulging, a neutral and a condensing segment of each factor): the
//!    training segments, the validation segments that choose each network's stopping epoch and
//!    restart, and the test segments, held out from every choice, whose error and confusion are
//!    reported;
//! 2. with stand-in labels ([`Corpus::descriptors`]), the pool features that *tell* a factor's label
//!    are left out of its network: every feature whose rank correlation with the descriptor the
//!    label is a tercile of reaches `told` (the defining feature — Time is the hand's peak
//!    acceleration, in the pool as "hand acceleration, max" — and its near-duplicates); otherwise the
//!    network would learn a threshold on its own input and its deviance map would be a thresholded
//!    kinematic-change detector;
//! 3. **saliency** (Ruck et al. 1990): "the saliency of each feature is computed using the average
//!    saliency of the feature over many random subsets of the potential features" — small networks
//!    on random subsets of the standardised pool, each feature scored by the mean output
//!    sensitivity to it, averaged over the subsets it was drawn in; the most salient are kept;
//! 4. **PCA** of the kept features to 95 % of their variance;
//! 5. **hidden units** (Park et al. 1996, as the paper): a wide network is trained, and the hidden
//!    layer gets as many units as principal components of its hidden activations hold 98 % of
//!    their variance;
//! 6. the unshifted network: best validation error of `restarts` random initialisations, each
//!    stopped when its validation loss stops improving;
//! 7. every other shift (i, j): the same labels on the segments `start + i ..= end + j`, a network
//!    of its own trained from its own random initialisation (`shift_restarts` of them, the best on
//!    validation kept) — 121 classifiers that can disagree, as the paper's deviance needs, not one
//!    network's sensitivity to a shift (120 × 4 × 20 restarts would not fit a browser's patience:
//!    one restart each by default).

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
    /// Share of the segments kept for validation (stopping epochs, restarts).
    pub validation: f64,
    /// Share of the segments held out from every choice, to report errors on.
    pub test: f64,
    /// Stand-in labels: a pool feature whose rank correlation with a factor's descriptor reaches
    /// this is left out of that factor's network (1 keeps every feature).
    pub told: f64,
    pub options: TrainOptions,
    /// Training of each shifted network, and its random initialisations.
    pub shift_options: TrainOptions,
    pub shift_restarts: usize,
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
            saliency_rounds: 64,
            subset: 40,
            validation: 0.2,
            test: 0.2,
            told: 0.9,
            options: TrainOptions { max_epochs: 300, learning_rate: 0.02, weight_decay: 1e-4, patience: 25 },
            shift_options: TrainOptions { max_epochs: 150, learning_rate: 0.02, weight_decay: 1e-4, patience: 25 },
            shift_restarts: 1,
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
    /// The unshifted network's error on the training, validation and test segments (the paper's rule).
    pub train_error: f32,
    pub validation_error: f32,
    pub test_error: f32,
    /// Mean test error of the shifted networks on their shifted test segments.
    pub shifted_test_error: f32,
    /// The unshifted network on the test segments: `confusion[true][predicted]` over
    /// [`super::effort::Element::ALL`] (predicted: the largest output).
    pub confusion: [[usize; 3]; 3],
    /// Segments per class in the training, validation and test sets.
    pub split: [[usize; 3]; 3],
    /// The five most salient features, with their saliency.
    pub most_salient: Vec<(String, f64)>,
    /// The pool features left out because they tell the stand-in label (rank correlation ≥ `told`
    /// with its descriptor), most correlated first, with it.
    pub told: Vec<(String, f64)>,
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

/// Average ranks of `v` (ties share their mean rank).
fn ranks(v: &[f64]) -> Vec<f64> {
    let mut order: Vec<usize> = (0..v.len()).collect();
    order.sort_by(|&a, &b| v[a].total_cmp(&v[b]));
    let mut out = vec![0.0; v.len()];
    let mut k = 0;
    while k < order.len() {
        let mut end = k;
        while end + 1 < order.len() && v[order[end + 1]] == v[order[k]] {
            end += 1;
        }
        for &i in &order[k..=end] {
            out[i] = (k + end) as f64 / 2.0;
        }
        k = end + 1;
    }
    out
}

/// Spearman's rank correlation of `a` and `b` (0 when either is constant).
pub fn rank_correlation(a: &[f64], b: &[f64]) -> f64 {
    let (ra, rb) = (ranks(a), ranks(b));
    let n = ra.len().max(1) as f64;
    let (ma, mb) = (ra.iter().sum::<f64>() / n, rb.iter().sum::<f64>() / n);
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for (x, y) in ra.iter().zip(&rb) {
        sab += (x - ma) * (y - mb);
        saa += (x - ma).powi(2);
        sbb += (y - mb).powi(2);
    }
    if saa > 0.0 && sbb > 0.0 {
        sab / (saa * sbb).sqrt()
    } else {
        0.0
    }
}

/// Indices of `samples` split into training, validation and test sets, stratified by the class of
/// `factor`: each class gives `validation` and `test` of its segments (rounded, at least one each
/// when it has three or more), in a seeded random order.
fn stratified_split(samples: &[Sample], factor: usize, validation: f64, test: f64, rng: &mut Rng) -> [Vec<usize>; 3] {
    let mut sets: [Vec<usize>; 3] = Default::default();
    for class in 0..3 {
        let mut members: Vec<usize> = (0..samples.len()).filter(|&k| samples[k].classes[factor] == class).collect();
        for k in (1..members.len()).rev() {
            members.swap(k, rng.below(k + 1));
        }
        let n = members.len();
        let take = |share: f64| if n >= 3 { ((n as f64 * share).round() as usize).max(1) } else { 0 };
        let (n_test, n_valid) = (take(test), take(validation));
        let n_valid = n_valid.min(n.saturating_sub(n_test + 1));
        sets[2].extend_from_slice(&members[..n_test]);
        sets[1].extend_from_slice(&members[n_test..n_test + n_valid]);
        sets[0].extend_from_slice(&members[n_test + n_valid..]);
    }
    sets
}

/// The unshifted network's test confusion, `[true][predicted]`.
fn confusion(net: &Net, data: &Data) -> [[usize; 3]; 3] {
    let mut out = vec![0.0; data.len() * net.outputs];
    net.forward_batch(data.x, &mut out);
    let mut m = [[0usize; 3]; 3];
    for (o, y) in out.chunks_exact(net.outputs).zip(data.y.chunks_exact(3)) {
        let arg = |v: &[f32]| (0..3).max_by(|&a, &b| v[a].total_cmp(&v[b])).unwrap_or(0);
        m[arg(y)][arg(o)] += 1;
    }
    m
}

/// Step 2 of [`train_family`]: the pool features that tell factor `f`'s stand-in label (their rank correlation
/// with its descriptor over the training samples `train_k` reaches `config.told`), most telling first — not the
/// network's to read. None when the corpus has real labels.
fn told_features(
    corpus: &Corpus,
    train_k: &[usize],
    pool_x: &[f32],
    f: usize,
    config: &TrainConfig,
) -> Vec<(usize, f64)> {
    let mut told = Vec::new();
    if corpus.descriptors.len() == corpus.samples.len() && config.told < 1.0 {
        let descriptor: Vec<f64> = train_k.iter().map(|&k| corpus.descriptors[k][f]).collect();
        for k in 0..POOL_SIZE {
            let column: Vec<f64> = pool_x.chunks_exact(POOL_SIZE).map(|r| r[k] as f64).collect();
            let rho = rank_correlation(&column, &descriptor);
            if rho.abs() >= config.told {
                told.push((k, rho));
            }
        }
        told.sort_by(|a, b| b.1.abs().total_cmp(&a.1.abs()));
    }
    told
}

/// Step 3 of [`train_family`]: each pool feature's mean sensitivity over `config.saliency_rounds` quick networks, each
/// trained on a random subset of the `usable` features of the standardised pool `pool_std`; `done(share)` after each
/// round.
fn saliency(
    pool_std: &[f32],
    usable: &[usize],
    y_train: &[f32],
    config: &TrainConfig,
    rng: &mut Rng,
    done: &mut dyn FnMut(f64) -> Result<(), String>,
) -> Result<Vec<f64>, String> {
    let mut saliency = vec![0.0f64; POOL_SIZE];
    let mut drawn = vec![0usize; POOL_SIZE];
    let subset = config.subset.min(usable.len());
    let samples = y_train.len() / 3;
    for round in 0..config.saliency_rounds {
        let mut pick = usable.to_vec();
        let n = pick.len();
        for k in 0..subset {
            pick.swap(k, k + rng.below(n - k));
        }
        let pick = &pick[..subset];
        let x: Vec<f32> = pool_std.chunks_exact(POOL_SIZE).flat_map(|r| pick.iter().map(move |&k| r[k])).collect();
        let quick = TrainOptions { max_epochs: 60, ..config.options };
        let (net, _) = train(Net::random(subset, 5, 3, rng), &data(&x, y_train), &data(&[], &[]), &quick);
        let mut sum = vec![0.0f64; subset];
        for row in x.chunks_exact(subset) {
            for (a, b) in sum.iter_mut().zip(net.sensitivity(row)) {
                *a += b as f64;
            }
        }
        for (&k, v) in pick.iter().zip(sum) {
            saliency[k] += v / samples as f64;
            drawn[k] += 1;
        }
        done((round + 1) as f64 / config.saliency_rounds as f64)?;
    }
    Ok(saliency.iter().zip(&drawn).map(|(s, &n)| if n > 0 { s / n as f64 } else { 0.0 }).collect())
}

/// Steps 5 and 6 of [`train_family`]: the hidden units a wide network needs (Park et al.), then the unshifted network
/// of that many, best of `config.restarts` (seeded by `seed`); with the hidden units.
fn central_network(
    components: usize,
    train_data: &Data,
    valid_data: &Data,
    z_train: &[f32],
    config: &TrainConfig,
    rng: &mut Rng,
    seed: u64,
) -> (Net, usize) {
    let wide = Net::random(components, config.widest_hidden, 3, rng);
    let (wide, _) = train(wide, train_data, valid_data, &config.options);
    let hidden = hidden_units(&wide, z_train, config.hidden_variance).min(config.widest_hidden);
    let restarts = config.restarts.max(1);
    let (central, _) = train_restarts(components, hidden, 3, train_data, valid_data, &config.options, restarts, seed);
    (central, hidden)
}

/// The family of the four factors' models trained on `corpus`.
fn family(corpus: &Corpus, factors: Vec<FactorModel>) -> EffortModel {
    let c = corpus.config;
    EffortModel {
        fps: c.fps,
        max_shift: c.max_shift,
        min_len: c.min_len,
        max_len: c.max_len,
        origin: corpus.origin.clone(),
        samples: corpus.samples.len(),
        factors,
    }
}

/// Step 7 of [`train_family`]: a network of its own for every boundary shift `(i, j)` in `-s..=s` (the unshifted one
/// is `central`), trained on the `sets` (training, validation, test samples, with their one-hot labels `ys`) as
/// `z_of` projects them at that shift; with the mean test error over them all. `done(i)` after each row of shifts.
#[allow(clippy::too_many_arguments)]
fn shifted_networks(
    central: &Net,
    z_of: &dyn Fn(&[Sample], (isize, isize)) -> Vec<f32>,
    sets: [&[Sample]; 3],
    ys: [&[f32]; 3],
    (components, hidden): (usize, usize),
    s: isize,
    seed: u64,
    config: &TrainConfig,
    done: &mut dyn FnMut(isize) -> Result<(), String>,
) -> Result<(Vec<Net>, f32), String> {
    let mut nets = Vec::with_capacity(((2 * s + 1) * (2 * s + 1)) as usize);
    let mut shifted_error = 0.0;
    for i in -s..=s {
        for j in -s..=s {
            let ze = z_of(sets[2], (i, j));
            if i == 0 && j == 0 {
                nets.push(central.clone());
                shifted_error += classification_error(central, &data(&ze, ys[2]));
                continue;
            }
            let (zt, zv) = (z_of(sets[0], (i, j)), z_of(sets[1], (i, j)));
            let (td, vd, ed) = (data(&zt, ys[0]), data(&zv, ys[1]), data(&ze, ys[2]));
            let shift_seed = seed.wrapping_mul(131).wrapping_add(((i + s) * (2 * s + 1) + (j + s)) as u64 + 1);
            let restarts = config.shift_restarts.max(1);
            let (net, _) = train_restarts(components, hidden, 3, &td, &vd, &config.shift_options, restarts, shift_seed);
            shifted_error += classification_error(&net, &ed);
            nets.push(net);
        }
        done(i)?;
    }
    let n = nets.len() as f32;
    Ok((nets, shifted_error / n))
}

/// Trains the family on `corpus`; reports `(stage, fraction)` and stops when asked.
pub fn train_family(
    corpus: &Corpus,
    config: &TrainConfig,
    progress: &mut dyn FnMut(&str, f64) -> Result<(), Cancelled>,
) -> Result<(EffortModel, Vec<FactorReport>), String> {
    let cancelled = |_: Cancelled| "cancelled".to_string();
    let s = corpus.config.max_shift as isize;
    let mut rng = Rng::new(config.seed);
    let all: Vec<u16> = (0..POOL_SIZE as u16).collect();
    let steps = 4.0;
    let mut factors = Vec::new();
    let mut reports = Vec::new();
    for (f, factor) in Factor::ALL.into_iter().enumerate() {
        let base = f as f64 / steps;
        // 1. the three sets, stratified by this factor's class
        let [train_k, valid_k, test_k] = stratified_split(&corpus.samples, f, config.validation, config.test, &mut rng);
        let pick = |ks: &[usize]| ks.iter().map(|&k| corpus.samples[k]).collect::<Vec<Sample>>();
        let (train_set, valid, test) = (pick(&train_k), pick(&valid_k), pick(&test_k));
        if train_set.len() < 6 {
            return Err(format!(
                "{} segments are too few to train on ({} for training after the validation and test shares; at least 6)",
                corpus.samples.len(),
                train_set.len()
            ));
        }
        let split = [&train_set, &valid, &test].map(|set| {
            let mut n = [0usize; 3];
            set.iter().for_each(|x| n[x.classes[f]] += 1);
            n
        });
        let pool_x = features(corpus, &train_set, &all, (0, 0));
        let (pool_mean, pool_scale) = moments(&pool_x, POOL_SIZE);
        let mut pool_std = pool_x.clone();
        standardise(&mut pool_std, &pool_mean, &pool_scale);
        // 2. the features that tell a stand-in label are not the network's to read
        let told = told_features(corpus, &train_k, &pool_x, f, config);
        let usable: Vec<usize> = (0..POOL_SIZE).filter(|k| !told.iter().any(|t| t.0 == *k)).collect();
        if usable.is_empty() {
            return Err(format!(
                "every pool feature tells the stand-in {} label: nothing is left to learn it from",
                factor.name()
            ));
        }
        let y_train = one_hot(&train_set, f);
        let y_valid = one_hot(&valid, f);
        let y_test = one_hot(&test, f);
        // 3. saliency over random subsets of the usable features
        progress(&format!("{} saliency", factor.name()), base).map_err(cancelled)?;
        let score = saliency(&pool_std, &usable, &y_train, config, &mut rng, &mut |done| {
            progress(&format!("{} saliency", factor.name()), base + 0.3 / steps * done).map_err(cancelled)
        })?;
        let mut ranked: Vec<u16> = usable.iter().map(|&k| k as u16).collect();
        ranked.sort_by(|&a, &b| score[b as usize].total_cmp(&score[a as usize]));
        let selected: Vec<u16> = ranked[..config.selected.clamp(1, ranked.len())].to_vec();
        // 4. PCA of the selected, standardised features
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
        let z_test = project(&inputs(&test, (0, 0)), n_sel, &axes, components);
        let train_data = data(&z_train, &y_train);
        let valid_data = data(&z_valid, &y_valid);
        let test_data = data(&z_test, &y_test);
        // 5. hidden units (Park et al.)
        progress(&format!("{} network", factor.name()), base + 0.35 / steps).map_err(cancelled)?;
        let seed = config.seed.wrapping_mul(1000).wrapping_add(f as u64);
        let (central, hidden) = central_network(components, &train_data, &valid_data, &z_train, config, &mut rng, seed);
        // 7. every shifted classifier a network of its own
        let z_of =
            |samples: &[Sample], shift: (isize, isize)| project(&inputs(samples, shift), n_sel, &axes, components);
        let sets = [&train_set[..], &valid[..], &test[..]];
        let ys = [&y_train[..], &y_valid[..], &y_test[..]];
        let (nets, shifted_error) =
            shifted_networks(&central, &z_of, sets, ys, (components, hidden), s, seed, config, &mut |i| {
                let fraction = base + (0.45 + 0.55 * (i + s + 1) as f64 / (2 * s + 1) as f64) / steps;
                progress(&format!("{} shifted networks", factor.name()), fraction).map_err(cancelled)
            })?;
        let validation_error = classification_error(&central, &valid_data);
        let test_error = classification_error(&central, &test_data);
        reports.push(FactorReport {
            factor,
            selected: n_sel,
            components,
            hidden,
            train_error: classification_error(&central, &train_data),
            validation_error,
            test_error,
            shifted_test_error: shifted_error,
            confusion: confusion(&central, &test_data),
            split,
            most_salient: selected.iter().take(5).map(|&k| (Pool::name(k as usize), score[k as usize])).collect(),
            told: told.iter().map(|&(k, rho)| (Pool::name(k), rho)).collect(),
        });
        factors.push(FactorModel {
            selected,
            mean,
            scale,
            projection: axes,
            components,
            nets,
            validation_error,
            test_error: Some(test_error),
        });
    }
    Ok((family(corpus, factors), reports))
}
