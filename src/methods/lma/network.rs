//! The small neural networks of Bouchard & Badler's LMA Effort classifiers (their §4, "Method"):
//! per Effort factor "two layers of feedforward sigmoid units with three output nodes" (indulging,
//! neutral, condensing), trained by backpropagation towards targets in 0..1, stopped early on a
//! validation set, the best of 20 random restarts kept; a sample counts as correct "if the correct
//! output is greater than the sum of the other two outputs". Features are ranked by the saliency of
//! Ruck et al. (1990): how much the outputs change for a change of the feature ([`Net::sensitivity`]).
//!
//! Choices the paper leaves open: Glorot-uniform initial weights, full-batch Adam on the mean binary
//! cross-entropy with L2 weight decay, and early stopping on the validation *loss* with a patience
//! (the paper stops when the validation error rate rises; its restarts are ranked by that error).
//!
//! The logistic function is computed here from `+ − × ÷` only (no libm `exp`), so the forward pass
//! vectorises and gives the same bits natively and in wasm32; its relative error is below 1e-6.

use serde::{Deserialize, Serialize};

use crate::stats::Rng;

/// Samples per block of [`Net::forward_batch`]: four 128-bit vectors (SSE2, wasm simd128).
const BLOCK: usize = 16;

/// `1 / (1 + e^−z)`, with `e^x` by Cody–Waite range reduction (`x = n ln2 + f`, `|f| ≤ ln2 / 2`)
/// and a degree-6 Taylor polynomial; `z` is clamped to ±80, so no input gives NaN but NaN itself.
#[inline(always)]
fn sigmoid(z: f32) -> f32 {
    const SHIFT: f32 = 12_582_912.0; // 1.5·2²³: adding it rounds to an integer, kept in the low bits
    const LN2_HI: f32 = 0.693_359_4; // ln 2 split so that n·LN2_HI is exact for |n| < 512
    const LN2_LO: f32 = -2.121_944_4e-4;
    let x = (-z).clamp(-80.0, 80.0);
    let r = x * std::f32::consts::LOG2_E + SHIFT;
    let n = r - SHIFT;
    let f = x - n * LN2_HI - n * LN2_LO;
    let p = 1.0 + f * (1.0 + f * (0.5 + f * (1.0 / 6.0 + f * (1.0 / 24.0 + f * (1.0 / 120.0 + f * (1.0 / 720.0))))));
    let two_n = f32::from_bits(((r.to_bits() as i32 - SHIFT.to_bits() as i32 + 127) << 23) as u32);
    1.0 / (1.0 + p * two_n)
}

/// Row `i` of a row-major buffer with rows of `width`.
fn row(buffer: &[f32], i: usize, width: usize) -> &[f32] {
    &buffer[i * width..(i + 1) * width]
}

/// A two-layer sigmoid network `y = σ(W2 σ(W1 x + b1) + b2)`, weights row-major.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Net {
    /// Input count.
    pub inputs: usize,
    /// Hidden unit count.
    pub hidden: usize,
    /// Output count.
    pub outputs: usize,
    /// Hidden weights, `hidden × inputs`.
    pub w1: Vec<f32>,
    /// Hidden biases.
    pub b1: Vec<f32>,
    /// Output weights, `outputs × hidden`.
    pub w2: Vec<f32>,
    /// Output biases.
    pub b2: Vec<f32>,
}

impl Net {
    /// A net with Glorot-uniform weights (`±√(6 / (fan_in + fan_out))`, `w1` then `w2` drawn from
    /// `rng` in row-major order) and zero biases.
    pub fn random(inputs: usize, hidden: usize, outputs: usize, rng: &mut Rng) -> Net {
        let mut layer = |fan_in: usize, fan_out: usize| {
            let limit = (6.0 / (fan_in + fan_out).max(1) as f32).sqrt();
            (0..fan_in * fan_out).map(|_| (2.0 * rng.next_f32() - 1.0) * limit).collect()
        };
        let (w1, w2) = (layer(inputs, hidden), layer(hidden, outputs));
        Net { inputs, hidden, outputs, w1, b1: vec![0.0; hidden], w2, b2: vec![0.0; outputs] }
    }

    /// The same shape with every parameter zero (gradient and Adam moment buffers).
    fn zeros_like(&self) -> Net {
        let zero = |v: &Vec<f32>| vec![0.0; v.len()];
        Net { w1: zero(&self.w1), b1: zero(&self.b1), w2: zero(&self.w2), b2: zero(&self.b2), ..*self }
    }

    /// The hidden activations into `hidden` and the output pre-activations (logits) into `z`.
    fn logits(&self, x: &[f32], hidden: &mut [f32], z: &mut [f32]) {
        debug_assert!(x.len() == self.inputs && hidden.len() == self.hidden && z.len() == self.outputs);
        for (j, h) in hidden.iter_mut().enumerate() {
            let w = row(&self.w1, j, self.inputs);
            *h = sigmoid(w.iter().zip(x).fold(self.b1[j], |acc, (w, x)| acc + w * x));
        }
        for (o, z) in z.iter_mut().enumerate() {
            let w = row(&self.w2, o, self.hidden);
            *z = w.iter().zip(&*hidden).fold(self.b2[o], |acc, (w, h)| acc + w * h);
        }
    }

    /// `σ(W2 σ(W1 x + b1) + b2)` for one input into `out` (`hidden`: scratch of `self.hidden`).
    pub fn forward(&self, x: &[f32], hidden: &mut [f32], out: &mut [f32]) {
        self.logits(x, hidden, out);
        out.iter_mut().for_each(|y| *y = sigmoid(*y));
    }

    /// The outputs for one input.
    pub fn predict(&self, x: &[f32]) -> Vec<f32> {
        let (mut hidden, mut out) = (vec![0.0; self.hidden], vec![0.0; self.outputs]);
        self.forward(x, &mut hidden, &mut out);
        out
    }

    /// [`Net::forward`] of every row of `x` (`n × inputs`) into `out` (`n × outputs`), bit-identical
    /// to it. Rows go in blocks of [`BLOCK`], transposed so that every sum runs over a block at once
    /// (vectorised, no reductions); one scratch allocation per call, so pass many rows per call.
    pub fn forward_batch(&self, x: &[f32], out: &mut [f32]) {
        self.forward_batch_with(x, out, &mut Vec::new());
    }

    /// [`Net::forward_batch`] with its scratch in `scratch` (grown as needed, reused across calls).
    pub fn forward_batch_with(&self, x: &[f32], out: &mut [f32], scratch: &mut Vec<f32>) {
        let (ni, nh, no) = (self.inputs, self.hidden, self.outputs);
        let n = out.len().checked_div(no).unwrap_or(0);
        debug_assert!(out.len() == n * no && x.len() == n * ni);
        if scratch.len() < (ni + nh) * BLOCK {
            scratch.resize((ni + nh) * BLOCK, 0.0);
        }
        let (xt, ht) = scratch[..(ni + nh) * BLOCK].split_at_mut(ni * BLOCK);
        for start in (0..n).step_by(BLOCK) {
            let rows = BLOCK.min(n - start);
            let xb = &x[start * ni..(start + rows) * ni];
            let mut quads = xb.chunks_exact(4 * ni.max(1));
            for (q, quad) in quads.by_ref().enumerate() {
                let (r01, r23) = quad.split_at(2 * ni);
                let ((r0, r1), (r2, r3)) = (r01.split_at(ni), r23.split_at(ni));
                for ((((col, &a), &b), &c), &d) in xt.chunks_exact_mut(BLOCK).zip(r0).zip(r1).zip(r2).zip(r3) {
                    col[4 * q..4 * q + 4].copy_from_slice(&[a, b, c, d]);
                }
            }
            let done = rows / 4 * 4;
            for (s, xs) in quads.remainder().chunks_exact(ni.max(1)).enumerate() {
                xs.iter().enumerate().for_each(|(k, &v)| xt[k * BLOCK + done + s] = v);
            }
            for (j, h) in ht.chunks_exact_mut(BLOCK).enumerate() {
                let mut acc = [self.b1[j]; BLOCK];
                for (&w, col) in row(&self.w1, j, ni).iter().zip(xt.chunks_exact(BLOCK)) {
                    acc.iter_mut().zip(col).for_each(|(a, &c)| *a += w * c);
                }
                h.iter_mut().zip(acc).for_each(|(h, a)| *h = sigmoid(a));
            }
            for o in 0..no {
                let mut acc = [self.b2[o]; BLOCK];
                for (&w, col) in row(&self.w2, o, nh).iter().zip(ht.chunks_exact(BLOCK)) {
                    acc.iter_mut().zip(col).for_each(|(a, &c)| *a += w * c);
                }
                acc.iter_mut().for_each(|a| *a = sigmoid(*a));
                (0..rows).for_each(|s| out[(start + s) * no + o] = acc[s]);
            }
        }
    }

    /// Ruck et al.'s saliency of each input at `x`: `Σ_o |∂y_o / ∂x_k|`, analytic through both
    /// sigmoids.
    pub fn sensitivity(&self, x: &[f32]) -> Vec<f32> {
        let (mut hidden, mut z) = (vec![0.0; self.hidden], vec![0.0; self.outputs]);
        self.logits(x, &mut hidden, &mut z);
        let (mut saliency, mut dy_dx) = (vec![0.0; self.inputs], vec![0.0; self.inputs]);
        for (o, &z) in z.iter().enumerate() {
            let y = sigmoid(z);
            dy_dx.fill(0.0);
            for (j, (&w2, &h)) in row(&self.w2, o, self.hidden).iter().zip(&hidden).enumerate() {
                let d = y * (1.0 - y) * w2 * h * (1.0 - h);
                dy_dx.iter_mut().zip(row(&self.w1, j, self.inputs)).for_each(|(g, w1)| *g += d * w1);
            }
            saliency.iter_mut().zip(&dy_dx).for_each(|(s, g)| *s += g.abs());
        }
        saliency
    }
}

/// A labelled sample set: inputs `x` (`n × inputs`) and one-hot targets `y` (`n × outputs`).
#[derive(Debug, Clone, Copy)]
pub struct Data<'a> {
    /// Inputs, row-major.
    pub x: &'a [f32],
    /// Targets in {0, 1}, row-major.
    pub y: &'a [f32],
    /// Outputs (target columns) per sample.
    pub outputs: usize,
}

impl Data<'_> {
    /// The number of samples.
    pub fn len(&self) -> usize {
        self.y.len().checked_div(self.outputs).unwrap_or(0)
    }

    /// Whether there are no samples.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// Settings of [`train`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TrainOptions {
    /// Upper bound on full-batch epochs.
    pub max_epochs: usize,
    /// Adam step size.
    pub learning_rate: f32,
    /// L2 penalty `λ/2 · Σ w²` on the weights (not the biases).
    pub weight_decay: f32,
    /// Epochs without a lower validation loss before stopping (0 acts as 1).
    pub patience: usize,
}

impl Default for TrainOptions {
    /// 400 epochs, learning rate 0.01, weight decay 1e-4, patience 30.
    fn default() -> Self {
        TrainOptions { max_epochs: 400, learning_rate: 0.01, weight_decay: 1e-4, patience: 30 }
    }
}

/// How a [`train`] run went, measured on the returned net.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Report {
    /// Epochs run (including those after the best one).
    pub epochs: usize,
    /// [`loss`] on the training set.
    pub train_loss: f32,
    /// [`loss`] on the validation set (0 if empty).
    pub valid_loss: f32,
    /// [`classification_error`] on the validation set (0 if empty).
    pub valid_error: f32,
}

/// The gradient of `loss(net, data) + λ/2 · Σ w²` (λ = `weight_decay`), shaped like `net`.
fn gradient(net: &Net, data: &Data, weight_decay: f32) -> Net {
    let (ni, nh, no) = (net.inputs, net.hidden, net.outputs);
    let mut g = net.zeros_like();
    let scale = 1.0 / (data.len() * no).max(1) as f32;
    let (mut h, mut z, mut dh) = (vec![0.0; nh], vec![0.0; no], vec![0.0; nh]);
    for i in 0..data.len() {
        let x = row(data.x, i, ni);
        net.logits(x, &mut h, &mut z);
        dh.fill(0.0);
        for (o, (&z, &t)) in z.iter().zip(row(data.y, i, no)).enumerate() {
            let d = (sigmoid(z) - t) * scale; // ∂BCE/∂logit
            g.b2[o] += d;
            let (gw, w) = (&mut g.w2[o * nh..(o + 1) * nh], row(&net.w2, o, nh));
            for ((gw, &w), (&h, dh)) in gw.iter_mut().zip(w).zip(h.iter().zip(&mut dh)) {
                *gw += d * h;
                *dh += d * w;
            }
        }
        for (j, (&h, &dh)) in h.iter().zip(&dh).enumerate() {
            let d = dh * h * (1.0 - h);
            g.b1[j] += d;
            g.w1[j * ni..(j + 1) * ni].iter_mut().zip(x).for_each(|(g, &x)| *g += d * x);
        }
    }
    for (g, w) in [(&mut g.w1, &net.w1), (&mut g.w2, &net.w2)] {
        g.iter_mut().zip(w).for_each(|(g, &w)| *g += weight_decay * w);
    }
    g
}

/// The four parameter buffers of a net, in a fixed order.
fn params_mut(net: &mut Net) -> [&mut Vec<f32>; 4] {
    [&mut net.w1, &mut net.b1, &mut net.w2, &mut net.b2]
}

/// Trains `net` by full-batch Adam on the mean binary cross-entropy plus `λ/2 · Σ w²`, measuring
/// the validation loss before training and after every epoch; returns the net of the lowest one,
/// stopping once `patience` epochs in a row brought no improvement (or after `max_epochs`). With
/// an empty validation set it trains `max_epochs` and returns the last net.
pub fn train(mut net: Net, train: &Data, valid: &Data, options: &TrainOptions) -> (Net, Report) {
    const BETA1: f32 = 0.9;
    const BETA2: f32 = 0.999;
    const EPSILON: f32 = 1e-8;
    let (mut m, mut v) = (net.zeros_like(), net.zeros_like());
    let mut best = (!valid.is_empty()).then(|| (loss(&net, valid), net.clone()));
    let (mut epochs, mut stale, mut beta1_t, mut beta2_t) = (0, 0, 1.0f32, 1.0f32);
    while epochs < options.max_epochs && stale < options.patience.max(1) {
        let mut g = gradient(&net, train, options.weight_decay);
        epochs += 1;
        beta1_t *= BETA1;
        beta2_t *= BETA2;
        let step = options.learning_rate * (1.0 - beta2_t).sqrt() / (1.0 - beta1_t);
        for (((p, g), m), v) in
            params_mut(&mut net).into_iter().zip(params_mut(&mut g)).zip(params_mut(&mut m)).zip(params_mut(&mut v))
        {
            for (((p, &g), m), v) in p.iter_mut().zip(g.iter()).zip(m.iter_mut()).zip(v.iter_mut()) {
                *m = BETA1 * *m + (1.0 - BETA1) * g;
                *v = BETA2 * *v + (1.0 - BETA2) * g * g;
                *p -= step * *m / (v.sqrt() + EPSILON);
            }
        }
        if let Some((best_loss, best_net)) = &mut best {
            let l = loss(&net, valid);
            if l < *best_loss {
                (*best_loss, *best_net, stale) = (l, net.clone(), 0);
            } else {
                stale += 1;
            }
        }
    }
    let net = best.map_or(net, |(_, best_net)| best_net);
    let report = Report {
        epochs,
        train_loss: loss(&net, train),
        valid_loss: loss(&net, valid),
        valid_error: classification_error(&net, valid),
    };
    (net, report)
}

/// Trains `restarts` (at least one) nets from [`Net::random`], all drawn in turn from one
/// `Rng::new(seed)`, and keeps the one of the lowest validation classification error, ties broken
/// by the lower validation loss, then by the earlier restart. The same seed gives the same bits.
#[allow(clippy::too_many_arguments)]
pub fn train_restarts(
    inputs: usize,
    hidden: usize,
    outputs: usize,
    train_set: &Data,
    valid: &Data,
    options: &TrainOptions,
    restarts: usize,
    seed: u64,
) -> (Net, Report) {
    let mut rng = Rng::new(seed);
    let mut best: Option<(Net, Report)> = None;
    for _ in 0..restarts.max(1) {
        let (net, report) = train(Net::random(inputs, hidden, outputs, &mut rng), train_set, valid, options);
        let key = |r: &Report| (r.valid_error, r.valid_loss);
        if best.as_ref().is_none_or(|(_, b)| key(&report) < key(b)) {
            best = Some((net, report));
        }
    }
    best.expect("at least one restart")
}

/// The share of samples the paper counts as wrong: the output of the target class (the largest
/// target) must exceed the sum of the other outputs. 0 for an empty set.
pub fn classification_error(net: &Net, data: &Data) -> f32 {
    let (n, no) = (data.len(), net.outputs);
    let mut out = vec![0.0; n * no];
    net.forward_batch(data.x, &mut out);
    let wrong = (0..n)
        .filter(|&i| {
            let (y, t) = (row(&out, i, no), row(data.y, i, no));
            let class = (0..no).fold(0, |c, o| if t[o] > t[c] { o } else { c });
            y[class] <= y.iter().enumerate().filter(|&(o, _)| o != class).map(|(_, y)| y).sum::<f32>()
        })
        .count();
    wrong as f32 / n.max(1) as f32
}

/// The mean binary cross-entropy over every output of every sample, from the logits
/// (`max(z, 0) − z·t + ln(1 + e^−|z|)`, finite whenever the logits are). 0 for an empty set.
pub fn loss(net: &Net, data: &Data) -> f32 {
    let (mut h, mut z) = (vec![0.0; net.hidden], vec![0.0; net.outputs]);
    let mut total = 0.0f64;
    for i in 0..data.len() {
        net.logits(row(data.x, i, net.inputs), &mut h, &mut z);
        for (&z, &t) in z.iter().zip(row(data.y, i, net.outputs)) {
            total += f64::from(z.max(0.0) - z * t + (-z.abs()).exp().ln_1p());
        }
    }
    (total / (data.len() * net.outputs).max(1) as f64) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    const EMPTY: Data = Data { x: &[], y: &[], outputs: 3 };

    fn data(set: &(Vec<f32>, Vec<f32>)) -> Data<'_> {
        Data { x: &set.0, y: &set.1, outputs: 3 }
    }

    fn gaussian(rng: &mut Rng) -> f32 {
        let (u, v) = (1.0 - rng.next_f32(), rng.next_f32());
        (-2.0 * u.ln()).sqrt() * (std::f32::consts::TAU * v).cos()
    }

    /// XOR-like three classes in 2-D: class 0 around ±(1.5, 1.5), class 1 around ±(1.5, −1.5),
    /// class 2 around the origin (σ = 0.3); inputs and one-hot targets.
    fn xor_blobs(n: usize, rng: &mut Rng) -> (Vec<f32>, Vec<f32>) {
        let (mut x, mut y) = (Vec::new(), Vec::new());
        for i in 0..n {
            let (class, sign) = (i % 3, if rng.below(2) == 0 { 1.5 } else { -1.5 });
            let centre = [[sign, sign], [sign, -sign], [0.0, 0.0]][class];
            x.extend(centre.map(|c| c + 0.3 * gaussian(rng)));
            y.extend((0..3).map(|o| if o == class { 1.0 } else { 0.0 }));
        }
        (x, y)
    }

    /// Uniform inputs in [−1, 1) and random one-hot targets.
    fn noise(n: usize, inputs: usize, rng: &mut Rng) -> (Vec<f32>, Vec<f32>) {
        let x = (0..n * inputs).map(|_| 2.0 * rng.next_f32() - 1.0).collect();
        let classes: Vec<usize> = (0..n).map(|_| rng.below(3)).collect();
        (x, classes.iter().flat_map(|&c| (0..3).map(move |o| if o == c { 1.0 } else { 0.0 })).collect())
    }

    fn random_net(inputs: usize, hidden: usize, rng: &mut Rng) -> Net {
        let net = Net::random(inputs, hidden, 3, rng);
        Net { b1: (0..hidden).map(|_| gaussian(rng)).collect(), b2: vec![-0.4, 0.2, 0.5], ..net }
    }

    fn flat(net: &Net) -> Vec<f64> {
        [&net.w1, &net.b1, &net.w2, &net.b2].into_iter().flatten().map(|&v| f64::from(v)).collect()
    }

    /// The net's outputs in f64 with its parameters replaced by `p` (`w1, b1, w2, b2` flattened).
    fn forward64(net: &Net, p: &[f64], x: &[f64]) -> Vec<f64> {
        let (ni, nh) = (net.inputs, net.hidden);
        let (w1, rest) = p.split_at(nh * ni);
        let (b1, rest) = rest.split_at(nh);
        let (w2, b2) = rest.split_at(net.outputs * nh);
        let s = |z: f64| 1.0 / (1.0 + (-z).exp());
        let h: Vec<f64> = (0..nh).map(|j| s(b1[j] + (0..ni).map(|k| w1[j * ni + k] * x[k]).sum::<f64>())).collect();
        b2.iter().enumerate().map(|(o, b)| s(b + (0..nh).map(|j| w2[o * nh + j] * h[j]).sum::<f64>())).collect()
    }

    #[test]
    fn the_sigmoid_is_accurate_and_finite_everywhere() {
        for i in -8000..=8000 {
            let z = i as f32 * 0.01;
            let exact = 1.0 / (1.0 + (-f64::from(z)).exp());
            assert!((f64::from(sigmoid(z)) - exact).abs() <= 1e-6 * exact, "σ({z})");
        }
        for z in [-1e30, -100.0, 100.0, f32::MAX, f32::INFINITY, f32::NEG_INFINITY] {
            assert!((0.0..=1.0).contains(&sigmoid(z)) && (sigmoid(z) - 0.5).abs() > 0.49);
        }
    }

    #[test]
    fn the_training_gradient_matches_finite_differences() {
        let mut rng = Rng::new(3);
        let net = random_net(4, 3, &mut rng);
        let set = noise(12, 4, &mut rng);
        let (data, (x, y)) = (data(&set), &set);
        let decay = 0.05;
        let g = gradient(&net, &data, decay);
        let analytic: Vec<f32> = [g.w1, g.b1, g.w2, g.b2].concat();
        let is_weight = |i: usize| i < 12 || (15..24).contains(&i);
        let objective = |p: &[f64]| {
            let mut bce = 0.0;
            for i in 0..data.len() {
                let out = forward64(&net, p, &row(x, i, 4).iter().map(|&v| v.into()).collect::<Vec<_>>());
                for (o, &t) in out.iter().zip(row(y, i, 3)) {
                    bce -= if t == 1.0 { o.ln() } else { (1.0 - o).ln() };
                }
            }
            let l2: f64 = p.iter().enumerate().filter(|&(i, _)| is_weight(i)).map(|(_, w)| w * w).sum();
            bce / (3 * data.len()) as f64 + 0.5 * f64::from(decay) * l2
        };
        let p = flat(&net);
        assert_eq!(analytic.len(), p.len());
        for (i, &a) in analytic.iter().enumerate() {
            let (mut plus, mut minus) = (p.clone(), p.clone());
            plus[i] += 1e-6;
            minus[i] -= 1e-6;
            let numeric = (objective(&plus) - objective(&minus)) / 2e-6;
            assert!((f64::from(a) - numeric).abs() <= 1e-2 * numeric.abs() + 1e-6, "parameter {i}: {a} vs {numeric}");
        }
    }

    #[test]
    fn sensitivity_matches_finite_differences_of_the_outputs() {
        let mut rng = Rng::new(5);
        let net = random_net(5, 4, &mut rng);
        let x: Vec<f32> = (0..5).map(|_| gaussian(&mut rng)).collect();
        let (p, x64): (Vec<f64>, Vec<f64>) = (flat(&net), x.iter().map(|&v| v.into()).collect());
        for (k, s) in net.sensitivity(&x).into_iter().enumerate() {
            let (mut plus, mut minus) = (x64.clone(), x64.clone());
            plus[k] += 1e-6;
            minus[k] -= 1e-6;
            let (yp, ym) = (forward64(&net, &p, &plus), forward64(&net, &p, &minus));
            let numeric: f64 = yp.iter().zip(&ym).map(|(a, b)| ((a - b) / 2e-6).abs()).sum();
            assert!(numeric > 1e-4 && (f64::from(s) - numeric).abs() <= 1e-3 * numeric, "input {k}: {s} vs {numeric}");
        }
    }

    #[test]
    fn forward_batch_equals_forward_per_row() {
        let mut rng = Rng::new(9);
        let net = random_net(7, 5, &mut rng);
        let (x, _) = noise(37, 7, &mut rng);
        let mut out = vec![0.0; 37 * 3];
        net.forward_batch(&x, &mut out);
        for i in 0..37 {
            assert_eq!(row(&out, i, 3), net.predict(row(&x, i, 7)));
            let reference = forward64(&net, &flat(&net), &row(&x, i, 7).iter().map(|&v| v.into()).collect::<Vec<_>>());
            assert!(row(&out, i, 3).iter().zip(reference).all(|(&a, b)| (f64::from(a) - b).abs() < 1e-6));
        }
        net.forward_batch(&[], &mut []);
    }

    #[test]
    fn training_learns_xor_like_blobs() {
        let mut rng = Rng::new(11);
        let (train_set, valid, test) = (xor_blobs(300, &mut rng), xor_blobs(90, &mut rng), xor_blobs(300, &mut rng));
        let (net, report) = train_restarts(2, 6, 3, &data(&train_set), &data(&valid), &TrainOptions::default(), 5, 1);
        let test_error = classification_error(&net, &data(&test));
        assert!(report.valid_error < 0.05 && test_error < 0.05, "{report:?}, test error {test_error}");
    }

    #[test]
    fn early_stopping_returns_the_net_of_the_best_validation_loss() {
        let mut rng = Rng::new(13);
        let (train_set, valid) = (noise(20, 3, &mut rng), noise(20, 3, &mut rng));
        let (train_set, valid) = (data(&train_set), data(&valid));
        let options = TrainOptions { max_epochs: 300, learning_rate: 0.05, weight_decay: 0.0, patience: 10 };
        let start = Net::random(3, 8, 3, &mut rng);
        let (net, report) = train(start.clone(), &train_set, &valid, &options);
        assert!(report.epochs < options.max_epochs, "{report:?}");
        // the same trajectory, cut after e epochs (an empty validation set returns the last net)
        let nets: Vec<Net> = (0..=report.epochs)
            .map(|e| train(start.clone(), &train_set, &EMPTY, &TrainOptions { max_epochs: e, ..options }).0)
            .collect();
        assert!(nets.iter().all(|n| report.valid_loss <= loss(n, &valid)));
        assert_eq!(nets.iter().position(|n| *n == net), Some(report.epochs - options.patience));
        assert_eq!(report.valid_loss, loss(&net, &valid));
    }

    #[test]
    fn restarts_are_reproducible_by_seed() {
        let mut rng = Rng::new(17);
        let (train_set, valid) = (xor_blobs(60, &mut rng), xor_blobs(30, &mut rng));
        let (train_set, valid) = (data(&train_set), data(&valid));
        let options = TrainOptions { max_epochs: 50, ..TrainOptions::default() };
        let run = |seed| train_restarts(2, 4, 3, &train_set, &valid, &options, 3, seed);
        assert_eq!(run(7), run(7));
        assert_ne!(run(7).0, run(8).0);
    }

    #[test]
    fn nets_round_trip_through_json() {
        let net = random_net(4, 3, &mut Rng::new(19));
        assert_eq!(serde_json::from_str::<Net>(&serde_json::to_string(&net).unwrap()).unwrap(), net);
    }

    #[test]
    fn classification_follows_the_papers_rule() {
        // constant outputs: w = 0, b2 = logit(p)
        let constant = |p: [f32; 3]| Net {
            inputs: 1,
            hidden: 1,
            outputs: 3,
            w1: vec![0.0],
            b1: vec![0.0],
            w2: vec![0.0; 3],
            b2: p.map(|p| (p / (1.0 - p)).ln()).to_vec(),
        };
        let x = [0.0; 4];
        let y = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0];
        let (all, class0) = (Data { x: &x, y: &y, outputs: 3 }, Data { x: &x[..1], y: &y[..3], outputs: 3 });
        // 0.6 > 0.1 + 0.1 is right for class 0 (twice), wrong for classes 1 and 2
        assert_eq!(classification_error(&constant([0.6, 0.1, 0.1]), &all), 0.5);
        // 0.5 < 0.3 + 0.3: wrong although class 0 has the largest output; 0.5 > 0.2 + 0.2 is right
        assert_eq!(classification_error(&constant([0.5, 0.3, 0.3]), &class0), 1.0);
        assert_eq!(classification_error(&constant([0.5, 0.2, 0.2]), &class0), 0.0);
    }

    #[test]
    fn empty_data_and_extreme_inputs_give_finite_results() {
        let net = random_net(3, 4, &mut Rng::new(23));
        assert_eq!((loss(&net, &EMPTY), classification_error(&net, &EMPTY)), (0.0, 0.0));
        let (trained, report) =
            train(net.clone(), &EMPTY, &EMPTY, &TrainOptions { max_epochs: 5, ..TrainOptions::default() });
        assert_eq!((report.epochs, report.train_loss, report.valid_error), (5, 0.0, 0.0));
        assert!(flat(&trained).iter().all(|v| v.is_finite()));
        let huge = Net { w1: net.w1.iter().map(|w| w * 1e6).collect(), ..net };
        let x = [1e30, -1e30, f32::MAX];
        assert!(huge.predict(&x).iter().chain(&huge.sensitivity(&x)).all(|v| v.is_finite()));
        assert!(loss(&huge, &Data { x: &x, y: &[0.0, 1.0, 0.0], outputs: 3 }).is_finite());
    }
}
