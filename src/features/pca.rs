//! Principal axes of a feature matrix and the rotation onto them. The SSSM's kd-tree search
//! (Krüger et al. 2017, §IV-A) indexes the leading principal coordinates of the stacked
//! features, and its feature bundling (§III) finds each frame's nearest neighbours the same way;
//! other methods (a PCA baseline) reuse them.

use nalgebra::{DMatrix, SymmetricEigen};

use super::FeatureMatrix;

/// At most this many frames are used to estimate the principal axes (a subsample is enough:
/// any rotation gives exact distances, the axes only make a tree prune better).
pub const PCA_SAMPLE: usize = 1024;

/// Mean and principal axes (rows, by decreasing variance) of the frames of `features`,
/// estimated on an even subsample of at most [`PCA_SAMPLE`] frames.
pub fn principal_axes(features: &FeatureMatrix) -> (Vec<f32>, Vec<f32>) {
    let n = features.frames();
    let d = features.dim();
    let step = n.div_ceil(PCA_SAMPLE).max(1);
    let sample: Vec<usize> = (0..n).step_by(step).collect();
    let mut mean = vec![0f64; d];
    for &i in &sample {
        for (m, &x) in mean.iter_mut().zip(features.row(i)) {
            *m += x as f64;
        }
    }
    mean.iter_mut().for_each(|m| *m /= sample.len() as f64);
    let mut cov = DMatrix::<f64>::zeros(d, d);
    let mut c = vec![0f64; d];
    for &i in &sample {
        for ((ck, &x), &m) in c.iter_mut().zip(features.row(i)).zip(&mean) {
            *ck = x as f64 - m;
        }
        for a in 0..d {
            let ca = c[a];
            if ca == 0.0 {
                continue;
            }
            for b in a..d {
                cov[(a, b)] += ca * c[b];
            }
        }
    }
    for a in 0..d {
        for b in 0..a {
            cov[(a, b)] = cov[(b, a)];
        }
    }
    let eig = SymmetricEigen::new(cov);
    let mut order: Vec<usize> = (0..d).collect();
    order.sort_by(|&a, &b| eig.eigenvalues[b].total_cmp(&eig.eigenvalues[a]));
    let mut axes = Vec::with_capacity(d * d);
    for &k in &order {
        axes.extend(eig.eigenvectors.column(k).iter().map(|&v| v as f32));
    }
    (mean.iter().map(|&m| m as f32).collect(), axes)
}

/// Rotates `features` onto `axes` (rows) about `mean`.
pub fn rotate(features: &FeatureMatrix, mean: &[f32], axes: &[f32]) -> Vec<f32> {
    let d = features.dim();
    let mut out = vec![0f32; features.frames() * d];
    let mut centred = vec![0f32; d];
    for (i, o) in out.chunks_exact_mut(d).enumerate() {
        for ((c, &x), &m) in centred.iter_mut().zip(features.row(i)).zip(mean) {
            *c = x - m;
        }
        for (k, ok) in o.iter_mut().enumerate() {
            *ok = dot(&axes[k * d..(k + 1) * d], &centred);
        }
    }
    out
}

fn dot(a: &[f32], b: &[f32]) -> f32 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}
