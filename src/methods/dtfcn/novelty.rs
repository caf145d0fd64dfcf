//! Novelty: how far a frame lies from what the network was trained on, in the network's own
//! feature space (not in the paper, whose labels are max-softmax only).
//!
//! A softmax is confident about what it never saw, and NormReLU (which divides each frame's
//! features by their largest) removes the activation size that max-softmax and energy scores
//! rely on. The score here is therefore taken **before** NormReLU, on the last layer's ReLU
//! activations: the Mahalanobis distance of a frame's features to the nearest class mean under
//! the classes' shared covariance (Lee et al. 2018, "A simple unified framework for detecting
//! out-of-distribution samples"), in the covariance's `rank` leading principal directions
//! (whitened; nalgebra's symmetric eigen-decomposition), so a model keeps a few thousand numbers,
//! not `features²`.
//!
//! Scores are returned relative to the training frames': a score of 1 is the training frames'
//! 95th percentile ([`Novelty::scale`]), so a threshold means the same for every model.
//!
//! **Measured, and not used by runs**: in the leave-one-class-out experiment (`cargo run --release
//! --example eval_dtfcn -- unseen`, docs/methods/dtfcn.md) it ranks never-seen-class frames *below*
//! new takes of known classes (AUROC 0.36; max-softmax 0.71), so the labels' unknown stays
//! max-softmax. Kept for that experiment and the next attempt.

use nalgebra::{DMatrix, SymmetricEigen};
use serde::{Deserialize, Serialize};

/// Principal directions kept by default.
pub const RANK: usize = 32;

/// The training frames' percentile a relative score of 1 stands for.
pub const SCALE_PERCENTILE: f64 = 0.95;

/// A fitted novelty score (see the module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Novelty {
    /// Features per frame.
    pub features: usize,
    /// Directions kept.
    pub rank: usize,
    /// `rank × features`, row `k` the `k`-th principal direction divided by the square root of its
    /// variance (the whitening).
    pub projection: Vec<f32>,
    /// `classes × rank`: each class's mean feature, projected.
    pub centres: Vec<f32>,
    /// The training frames' [`SCALE_PERCENTILE`] raw score (distances are divided by it).
    pub scale: f32,
}

impl Novelty {
    /// Fits on the features of labelled training frames (`rows` frame-major, `features` values
    /// each; `labels[i]` the class of row `i`).
    pub fn fit(
        rows: &[f32],
        features: usize,
        labels: &[usize],
        classes: usize,
        rank: usize,
    ) -> Result<Novelty, String> {
        let n = labels.len();
        if features == 0 || rows.len() != n * features {
            return Err(format!("{} feature values for {n} frames of {features}", rows.len()));
        }
        if n < 2 {
            return Err("novelty needs at least 2 training frames".into());
        }
        // class means
        let mut means = vec![0f64; classes * features];
        let mut counts = vec![0usize; classes];
        for (i, &c) in labels.iter().enumerate() {
            if c >= classes {
                return Err(format!("label {c} of frame {i}: expected fewer than {classes} classes"));
            }
            counts[c] += 1;
            for (m, &x) in means[c * features..(c + 1) * features].iter_mut().zip(&rows[i * features..]) {
                *m += x as f64;
            }
        }
        for c in 0..classes {
            let k = counts[c].max(1) as f64;
            means[c * features..(c + 1) * features].iter_mut().for_each(|m| *m /= k);
        }
        // the shared (within-class) covariance
        let mut residuals = DMatrix::<f64>::zeros(n, features);
        for (i, &c) in labels.iter().enumerate() {
            for j in 0..features {
                residuals[(i, j)] = rows[i * features + j] as f64 - means[c * features + j];
            }
        }
        let cov = residuals.transpose() * &residuals / n as f64;
        let trace = cov.trace().max(1e-12);
        let eig = SymmetricEigen::new(cov);
        let mut order: Vec<usize> = (0..features).collect();
        order.sort_by(|&a, &b| eig.eigenvalues[b].total_cmp(&eig.eigenvalues[a]));
        let rank = rank.clamp(1, features);
        // a floor on the variances: directions the training frames never move along would
        // otherwise make every new frame infinitely far
        let floor = 1e-3 * trace / features as f64;
        let mut projection = vec![0f32; rank * features];
        for (k, &e) in order.iter().take(rank).enumerate() {
            let scale = 1.0 / eig.eigenvalues[e].max(floor).sqrt();
            for j in 0..features {
                projection[k * features + j] = (eig.eigenvectors[(j, e)] * scale) as f32;
            }
        }
        let mut novelty = Novelty { features, rank, projection, centres: vec![0f32; classes * rank], scale: 1.0 };
        let centres: Vec<f32> = (0..classes)
            .flat_map(|c| {
                if counts[c] == 0 {
                    // a class without frames can never be nearest
                    return vec![f32::INFINITY; rank];
                }
                let mean: Vec<f32> = means[c * features..(c + 1) * features].iter().map(|&m| m as f32).collect();
                novelty.project(&mean)
            })
            .collect();
        novelty.centres = centres;
        let mut raw: Vec<f32> = rows.chunks(features).map(|f| novelty.raw(f)).collect();
        raw.sort_by(f32::total_cmp);
        let at = ((n - 1) as f64 * SCALE_PERCENTILE).round() as usize;
        novelty.scale = raw[at].max(1e-12);
        Ok(novelty)
    }

    fn project(&self, f: &[f32]) -> Vec<f32> {
        (0..self.rank)
            .map(|k| {
                self.projection[k * self.features..(k + 1) * self.features].iter().zip(f).map(|(p, x)| p * x).sum()
            })
            .collect()
    }

    /// Whitened distance to the nearest class centre (classes without training frames are at infinity).
    fn raw(&self, f: &[f32]) -> f32 {
        let z = self.project(f);
        self.centres
            .chunks(self.rank.max(1))
            .map(|m| m.iter().zip(&z).map(|(m, v)| (v - m) * (v - m)).sum::<f32>())
            .fold(f32::INFINITY, f32::min)
            .sqrt()
    }

    /// The score of one frame's features: its whitened distance to the nearest class mean over the
    /// training frames' 95th percentile (1 = as far as the farthest 5 % of training frames).
    pub fn score(&self, f: &[f32]) -> f32 {
        self.raw(f) / self.scale
    }

    /// Scores of every frame of `rows` (frame-major).
    pub fn scores(&self, rows: &[f32]) -> Vec<f32> {
        rows.chunks(self.features).map(|f| self.score(f)).collect()
    }
}

/// Area under the ROC curve of a score that should be higher for `positive` frames: the chance
/// that a random positive frame scores above a random negative one (ties count half).
pub fn auroc(scores: &[(f32, bool)]) -> f64 {
    let mut sorted: Vec<(f32, bool)> = scores.to_vec();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
    let positives = sorted.iter().filter(|s| s.1).count() as f64;
    let negatives = sorted.len() as f64 - positives;
    if positives == 0.0 || negatives == 0.0 {
        return 0.5;
    }
    // rank sum of the positives (average ranks over ties)
    let mut rank_sum = 0.0;
    let mut i = 0;
    while i < sorted.len() {
        let mut j = i;
        while j < sorted.len() && sorted[j].0 == sorted[i].0 {
            j += 1;
        }
        let average = (i + j + 1) as f64 / 2.0; // ranks i+1 … j
        rank_sum += average * sorted[i..j].iter().filter(|s| s.1).count() as f64;
        i = j;
    }
    (rank_sum - positives * (positives + 1.0) / 2.0) / (positives * negatives)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stats::Rng;

    fn normal(r: &mut Rng) -> f32 {
        let (u, v) = (r.next_f32().max(1e-7), r.next_f32());
        (-2.0 * u.ln()).sqrt() * (2.0 * std::f32::consts::PI * v).cos()
    }

    /// Two classes in 6 dimensions, each a spread-out cloud along its own direction; a frame from a third
    /// place scores far, frames like the training ones near.
    #[test]
    fn frames_unlike_any_class_score_far_and_training_like_frames_near() {
        let mut r = Rng::new(4);
        let d = 6;
        let mut rows = Vec::new();
        let mut labels = Vec::new();
        for i in 0..400 {
            let c = i % 2;
            let mut f: Vec<f32> = (0..d).map(|_| 0.3 * normal(&mut r)).collect();
            f[c] += 5.0;
            f[2] += 2.0 * normal(&mut r); // a direction both classes vary along a lot
            rows.extend(f);
            labels.push(c);
        }
        let n = Novelty::fit(&rows, d, &labels, 3, d).unwrap();
        let train = n.scores(&rows);
        let within = train.iter().filter(|&&s| s <= 1.0).count() as f64 / train.len() as f64;
        assert!((within - 0.95).abs() < 0.01, "{within}");
        // the classes' own means are near; a point off along a direction they never vary is far, even
        // though it is closer in plain distance than the large variation along direction 2
        let mut a = vec![0f32; d];
        a[0] = 5.0;
        assert!(n.score(&a) < 0.5, "{}", n.score(&a));
        let mut along = a.clone();
        along[2] = 3.0;
        let mut off = a.clone();
        off[4] = 3.0; // ten of the spreads the classes have along direction 4
        assert!(n.score(&along) < 1.0 && n.score(&off) > 2.0, "{} {}", n.score(&along), n.score(&off));
        // class 2 had no frames: it is never the nearest
        assert!(n.centres[2 * d].is_infinite());
        // fewer directions kept: still a score, of the leading ones
        let few = Novelty::fit(&rows, d, &labels, 3, 2).unwrap();
        assert_eq!(few.projection.len(), 2 * d);
        assert!(few.score(&along) < 1.0);
        assert!(Novelty::fit(&rows[..5], d, &labels[..1], 2, 4).is_err());
    }

    #[test]
    fn auroc_counts_pairs_and_ties() {
        assert_eq!(auroc(&[(1.0, false), (2.0, true)]), 1.0);
        assert_eq!(auroc(&[(2.0, false), (1.0, true)]), 0.0);
        assert_eq!(auroc(&[(1.0, false), (1.0, true)]), 0.5);
        // 2 positives × 2 negatives: pairs won 1 + 2 of 4
        assert_eq!(auroc(&[(1.0, false), (2.0, true), (3.0, false), (4.0, true)]), 0.75);
        assert_eq!(auroc(&[(1.0, true)]), 0.5);
    }
}
