//! Feature bundling (Krüger et al. 2017, §III).
//!
//! Repetitions of one action trace nearby but distinct loops in feature space. Bundling moves
//! every point `F_i` *across* its trajectory towards the densest part of its neighbourhood, so
//! the loops of one action draw together:
//!
//! 1. the `k` nearest neighbours of `F_i` among all other frames (kiddo);
//! 2. the direction of movement `d_i`, the centred five-point derivative
//!    `(F_{i−2} − 8F_{i−1} + 8F_{i+1} − F_{i+2}) / 12` (ends extended linearly);
//! 3. a PCA of the neighbours keeping `variance` (97.5 %) of their variance, and in that local
//!    space an orthonormal basis of the subspace orthogonal to `d_i`, from a QR decomposition
//!    whose first column is `d_i` (the paper fills the other columns with random numbers; unit
//!    vectors are used here so the result is reproducible);
//! 4. the optimum of eq. (4) in that subspace ([`BundlingOptimum`]):
//!    * `Density` — the mode of the Gaussian kernel density of the neighbours with Scott's-rule
//!      bandwidth `h_l = σ_l·k^{−1/(d+4)}` (eq. 2), by mean-shift iterations restricted to the
//!      subspace (each step maximises the mean-shift bound exactly within it);
//!    * `GeometricMedian` — the geometric median of the neighbours in the subspace (Weiszfeld
//!      iterations). This is what the authors' code effectively computes: its kernel width is
//!      `σ = 1/mean(d)`, so `exp(−d²/2σ²)` vanishes for every neighbour and its objective
//!      `k·f − Σ f·exp(…)` with `f = mean(d)/√(2π)` reduces to `k·mean(d)/√(2π)`: the sum of
//!      distances to the neighbours. The test `authors_objective_is_minimised_by_the_median`
//!      checks this numerically;
//! 5. back-projection: `F̂_i = F_i + U·Δy` with `U` the local principal axes.
//!
//! The kNN search runs on the leading [`KNN_DIMS`] global principal coordinates with twice
//! the candidates, re-ranked by the full distance.

use std::num::NonZero;

use kiddo::immutable::float::kdtree::ImmutableKdTree;
use kiddo::SquaredEuclidean;
use nalgebra::{Cholesky, DMatrix, DVector, SymmetricEigen, QR};

use super::features::FeatureMatrix;
use super::params::BundlingOptimum;
use crate::features::pca::{principal_axes, rotate};
use crate::method::Cancelled;

/// Principal coordinates indexed by the bundling's kNN tree.
pub const KNN_DIMS: usize = 16;
const MAX_ITERATIONS: usize = 100;
/// Frames moved between two progress reports.
const PROGRESS_FRAMES: usize = 64;

/// Settings of the bundling (from the checked parameters).
#[derive(Debug, Clone, Copy)]
pub struct Bundling {
    pub k: usize,
    pub variance: f64,
    pub optimum: BundlingOptimum,
}

impl Bundling {
    /// The bundled features `F̂` (same shape as `features`).
    pub fn bundle(&self, features: &FeatureMatrix) -> FeatureMatrix {
        match self.bundle_with_progress(features, &mut |_| Ok(())) {
            Ok(out) => out,
            Err(Cancelled) => unreachable!("a callback that never cancels"),
        }
    }

    /// [`Self::bundle`], reporting the fraction of the frames moved (every 64 frames); stops
    /// as soon as `progress` returns `Err(Cancelled)`.
    pub fn bundle_with_progress(
        &self,
        features: &FeatureMatrix,
        progress: &mut dyn FnMut(f64) -> Result<(), Cancelled>,
    ) -> Result<FeatureMatrix, Cancelled> {
        let n = features.frames();
        let k = self.k.min(n.saturating_sub(1));
        let mut out = features.clone();
        if k < 2 {
            return Ok(out);
        }
        let neighbours = nearest_neighbours(features, k);
        let directions = directions(features);
        let d = features.dim();
        for i in 0..n {
            if i % PROGRESS_FRAMES == 0 {
                progress(i as f64 / n as f64)?;
            }
            let delta =
                self.displacement(features, i, &neighbours[i * k..(i + 1) * k], &directions[i * d..(i + 1) * d]);
            for (o, dv) in out.row_mut(i).iter_mut().zip(delta.iter()) {
                *o += *dv as f32;
            }
        }
        progress(1.0)?;
        Ok(out)
    }

    /// The move of frame `i` (a `dim`-vector) given its neighbours and direction.
    fn displacement(&self, f: &FeatureMatrix, i: usize, neighbours: &[u32], direction: &[f64]) -> DVector<f64> {
        let d = f.dim();
        let zero = DVector::zeros(d);
        let Some(local) = LocalSpace::new(f, i, neighbours, direction, self.variance) else {
            return zero;
        };
        let Some(basis) = local.orthogonal_basis() else {
            return zero;
        };
        let target = match self.optimum {
            BundlingOptimum::Density => local.density_mode(&basis),
            BundlingOptimum::GeometricMedian => local.geometric_median(&basis),
        };
        &local.axes * (target - &local.point)
    }
}

/// A frame's neighbourhood in its local principal coordinates.
struct LocalSpace {
    /// `dim × d'` local principal axes (orthonormal columns).
    axes: DMatrix<f64>,
    /// `d' × k` neighbour coordinates.
    samples: DMatrix<f64>,
    /// Coordinates of the frame itself.
    point: DVector<f64>,
    /// Direction of movement in local coordinates.
    direction: DVector<f64>,
    /// Standard deviation of the samples along each local axis.
    sigma: DVector<f64>,
}

impl LocalSpace {
    fn new(f: &FeatureMatrix, i: usize, neighbours: &[u32], direction: &[f64], variance: f64) -> Option<Self> {
        let (d, k) = (f.dim(), neighbours.len());
        let mut mean = DVector::<f64>::zeros(d);
        for &j in neighbours {
            for (m, &x) in mean.iter_mut().zip(f.row(j as usize)) {
                *m += x as f64;
            }
        }
        mean /= k as f64;
        let centred = DMatrix::from_fn(d, k, |r, c| f.row(neighbours[c] as usize)[r] as f64 - mean[r]);
        // PCA through the k × k Gram matrix: cheaper than d × d when k < d.
        let eig = SymmetricEigen::new(centred.transpose() * &centred);
        let mut order: Vec<usize> = (0..k).collect();
        order.sort_by(|&a, &b| eig.eigenvalues[b].total_cmp(&eig.eigenvalues[a]));
        let total: f64 = eig.eigenvalues.iter().map(|l| l.max(0.0)).sum();
        if total <= 1e-12 {
            return None;
        }
        let mut kept = Vec::new();
        let mut acc = 0.0;
        for &c in &order {
            let l = eig.eigenvalues[c];
            if l <= total * 1e-12 {
                break;
            }
            kept.push(c);
            acc += l;
            if acc >= variance * total {
                break;
            }
        }
        let dl = kept.len();
        let mut axes = DMatrix::<f64>::zeros(d, dl);
        let mut samples = DMatrix::<f64>::zeros(dl, k);
        let mut sigma = DVector::<f64>::zeros(dl);
        for (l, &c) in kept.iter().enumerate() {
            let s = eig.eigenvalues[c].sqrt();
            let v = eig.eigenvectors.column(c);
            axes.set_column(l, &((&centred * v) / s));
            for j in 0..k {
                samples[(l, j)] = s * v[j];
            }
            sigma[l] = (eig.eigenvalues[c] / (k as f64 - 1.0).max(1.0)).sqrt();
        }
        let x = DVector::from_iterator(d, f.row(i).iter().map(|&v| v as f64)) - &mean;
        let point = axes.transpose() * x;
        let direction = axes.transpose() * DVector::from_column_slice(direction);
        Some(LocalSpace { axes, samples, point, direction, sigma })
    }

    /// Orthonormal basis (columns) of the local subspace orthogonal to the direction of
    /// movement, by QR of `[d, e_1, …]`; `None` if that subspace is empty.
    fn orthogonal_basis(&self) -> Option<DMatrix<f64>> {
        let dl = self.point.len();
        let norm = self.direction.norm();
        if norm < 1e-9 {
            return Some(DMatrix::identity(dl, dl));
        }
        if dl < 2 {
            return None;
        }
        let u = &self.direction / norm;
        let pivot = u.iamax();
        let mut a = DMatrix::<f64>::zeros(dl, dl);
        a.set_column(0, &u);
        for (col, e) in (1..).zip((0..dl).filter(|&e| e != pivot)) {
            a[(e, col)] = 1.0;
        }
        let q = QR::new(a).q();
        Some(q.columns(1, dl - 1).into_owned())
    }

    /// Mode of the Gaussian KDE (Scott's bandwidth) on `point + basis·w`, by restricted
    /// mean shift.
    fn density_mode(&self, basis: &DMatrix<f64>) -> DVector<f64> {
        let (dl, k) = self.samples.shape();
        let factor = (k as f64).powf(-1.0 / (dl as f64 + 4.0));
        let inv_h2 = DVector::from_iterator(dl, self.sigma.iter().map(|s| 1.0 / (s * factor).max(1e-9).powi(2)));
        let weighted_basis = DMatrix::from_fn(dl, basis.ncols(), |r, c| basis[(r, c)] * inv_h2[r]);
        let Some(system) = Cholesky::new(basis.transpose() * &weighted_basis) else {
            return self.point.clone();
        };
        let mut y = self.point.clone();
        let mut weights = vec![0f64; k];
        for _ in 0..MAX_ITERATIONS {
            for (j, w) in weights.iter_mut().enumerate() {
                *w = (0..dl).map(|l| (y[l] - self.samples[(l, j)]).powi(2) * inv_h2[l]).sum::<f64>();
            }
            let min = weights.iter().copied().fold(f64::INFINITY, f64::min);
            weights.iter_mut().for_each(|w| *w = (-0.5 * (*w - min)).exp());
            let m = weighted_mean(&self.samples, &weights);
            let w = system.solve(&(weighted_basis.transpose() * (m - &self.point)));
            let next = &self.point + basis * w;
            let step = (&next - &y).norm();
            y = next;
            if step < 1e-7 * (1.0 + self.sigma.norm()) {
                break;
            }
        }
        y
    }

    /// Geometric median of the samples on `point + basis·w` (orthonormal basis), by Weiszfeld.
    fn geometric_median(&self, basis: &DMatrix<f64>) -> DVector<f64> {
        let (dl, k) = self.samples.shape();
        let mut y = self.point.clone();
        let mut weights = vec![0f64; k];
        let eps = 1e-9 * (1.0 + self.sigma.norm());
        for _ in 0..MAX_ITERATIONS {
            for (j, w) in weights.iter_mut().enumerate() {
                let d2: f64 = (0..dl).map(|l| (y[l] - self.samples[(l, j)]).powi(2)).sum();
                *w = 1.0 / d2.sqrt().max(eps);
            }
            let m = weighted_mean(&self.samples, &weights);
            let next = &self.point + basis * (basis.transpose() * (m - &self.point));
            let step = (&next - &y).norm();
            y = next;
            if step < 1e-7 * (1.0 + self.sigma.norm()) {
                break;
            }
        }
        y
    }
}

fn weighted_mean(samples: &DMatrix<f64>, weights: &[f64]) -> DVector<f64> {
    let total: f64 = weights.iter().sum();
    let mut m = DVector::zeros(samples.nrows());
    for (j, &w) in weights.iter().enumerate() {
        m.axpy(w / total, &samples.column(j), 1.0);
    }
    m
}

/// The `k` nearest other frames of every frame (frame-major, `n × k`).
fn nearest_neighbours(f: &FeatureMatrix, k: usize) -> Vec<u32> {
    let (n, d) = (f.frames(), f.dim());
    let (mean, axes) = principal_axes(f);
    let rotated = rotate(f, &mean, &axes);
    let leading = |x: &[f32]| {
        let mut p = [0f32; KNN_DIMS];
        let m = x.len().min(KNN_DIMS);
        p[..m].copy_from_slice(&x[..m]);
        p
    };
    let points: Vec<[f32; KNN_DIMS]> = rotated.chunks_exact(d).map(leading).collect();
    let tree: ImmutableKdTree<f32, u32, KNN_DIMS, 32> = ImmutableKdTree::new_from_slice(&points);
    let want = NonZero::new((2 * k + 1).min(n)).expect("n ≥ 1");
    let mut out = Vec::with_capacity(n * k);
    let mut cand: Vec<(f32, u32)> = Vec::with_capacity(2 * k + 1);
    for i in 0..n {
        let q = &rotated[i * d..(i + 1) * d];
        cand.clear();
        for c in tree.nearest_n::<SquaredEuclidean>(&points[i], want) {
            if c.item as usize != i {
                let other = &rotated[c.item as usize * d..(c.item as usize + 1) * d];
                let d2: f32 = q.iter().zip(other).map(|(a, b)| (a - b) * (a - b)).sum();
                cand.push((d2, c.item));
            }
        }
        cand.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        // min(2k + 1, n) ≥ k + 1 candidates were requested and at most one is i itself
        debug_assert!(cand.len() >= k);
        out.extend(cand.iter().take(k).map(|c| c.1));
    }
    out
}

/// Direction of movement of every frame (frame-major, `n × dim`, unit length or zero): the
/// centred five-point derivative, with the sequence extended linearly past both ends.
fn directions(f: &FeatureMatrix) -> Vec<f64> {
    let (n, d) = (f.frames(), f.dim());
    let mut out = vec![0f64; n * d];
    if n < 2 {
        return out;
    }
    let value = |t: i64, c: usize| -> f64 {
        let x = |i: usize| f.row(i)[c] as f64;
        if t < 0 {
            x(0) + t as f64 * (x(1) - x(0))
        } else if t >= n as i64 {
            let last = n - 1;
            x(last) + (t - last as i64) as f64 * (x(last) - x(last - 1))
        } else {
            x(t as usize)
        }
    };
    for i in 0..n {
        let t = i as i64;
        let row = &mut out[i * d..(i + 1) * d];
        for (c, r) in row.iter_mut().enumerate() {
            *r = (value(t - 2, c) - 8.0 * value(t - 1, c) + 8.0 * value(t + 1, c) - value(t + 2, c)) / 12.0;
        }
        let norm = row.iter().map(|v| v * v).sum::<f64>().sqrt();
        if norm > 1e-12 {
            row.iter_mut().for_each(|v| *v /= norm);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `loops` circles of radius 10 in the x-y plane, 60 frames each, the loop `l` lifted to
    /// z = l − (loops−1)/2: repetitions that differ across the direction of movement.
    fn stacked_loops(loops: usize) -> FeatureMatrix {
        let mut rows = Vec::new();
        for l in 0..loops {
            for t in 0..60 {
                let a = t as f32 / 60.0 * std::f32::consts::TAU;
                rows.push([10.0 * a.cos(), 10.0 * a.sin(), l as f32 - (loops as f32 - 1.0) / 2.0]);
            }
        }
        FeatureMatrix::from_rows(&rows).unwrap()
    }

    fn mean_abs_z(f: &FeatureMatrix) -> f32 {
        (0..f.frames()).map(|i| f.row(i)[2].abs()).sum::<f32>() / f.frames() as f32
    }

    #[test]
    fn five_point_derivative_of_a_line_is_its_direction() {
        let rows: Vec<[f32; 2]> = (0..10).map(|i| [i as f32 * 3.0, i as f32 * 4.0]).collect();
        let dirs = directions(&FeatureMatrix::from_rows(&rows).unwrap());
        for i in 0..10 {
            assert!((dirs[2 * i] - 0.6).abs() < 1e-9 && (dirs[2 * i + 1] - 0.8).abs() < 1e-9, "frame {i}");
        }
    }

    #[test]
    fn nearest_neighbours_are_exact_on_a_line() {
        let rows: Vec<[f32; 1]> = (0..50).map(|i| [(i * i) as f32]).collect();
        let nn = nearest_neighbours(&FeatureMatrix::from_rows(&rows).unwrap(), 3);
        assert_eq!(&nn[10 * 3..11 * 3], &[9, 11, 8]);
        assert_eq!(&nn[0..3], &[1, 2, 3]);
    }

    #[test]
    fn bundling_draws_repetitions_together_across_the_direction_of_movement() {
        let f = stacked_loops(5);
        let before = mean_abs_z(&f);
        for optimum in [BundlingOptimum::Density, BundlingOptimum::GeometricMedian] {
            let b = Bundling { k: 32, variance: 0.975, optimum }.bundle(&f);
            let after = mean_abs_z(&b);
            assert!(after < 0.7 * before, "{optimum:?}: mean |z| {before} → {after}");
            // points move across, not along, their loop: the angle on the circle is kept
            // (except next to the jumps from one loop to the next, where the derivative sees
            // the jump)
            for i in (0..f.frames()).filter(|i| (2..58).contains(&(i % 60))) {
                let (a0, a1) = (f.row(i)[1].atan2(f.row(i)[0]), b.row(i)[1].atan2(b.row(i)[0]));
                let diff = (a1 - a0 + std::f32::consts::PI).rem_euclid(std::f32::consts::TAU) - std::f32::consts::PI;
                assert!(diff.abs() < 0.05, "{optimum:?} frame {i}: angle moved by {diff}");
            }
        }
    }

    #[test]
    fn a_single_straight_pass_is_not_moved() {
        let rows: Vec<[f32; 3]> = (0..80).map(|i| [i as f32, 2.0 * i as f32, -(i as f32)]).collect();
        let f = FeatureMatrix::from_rows(&rows).unwrap();
        let b = Bundling { k: 8, variance: 0.975, optimum: BundlingOptimum::Density }.bundle(&f);
        for i in 0..80 {
            for c in 0..3 {
                assert!((b.row(i)[c] - f.row(i)[c]).abs() < 1e-3, "frame {i}");
            }
        }
    }

    #[test]
    fn tiny_inputs_are_returned_unchanged() {
        let f = FeatureMatrix::from_rows(&[[1.0f32, 2.0], [3.0, 4.0]]).unwrap();
        assert_eq!(Bundling { k: 32, variance: 0.975, optimum: BundlingOptimum::Density }.bundle(&f), f);
    }

    /// The authors' objective (computeGaussian_local): `k·f − Σ f·exp(−d²/(2σ²))` with
    /// `σ = 1/mean(d)` and `f = 1/(σ√(2π))`.
    fn authors_objective(x: &[f64], samples: &[[f64; 2]]) -> f64 {
        let d: Vec<f64> = samples.iter().map(|s| ((x[0] - s[0]).powi(2) + (x[1] - s[1]).powi(2)).sqrt()).collect();
        let mean = d.iter().sum::<f64>() / d.len() as f64;
        let sigma = 1.0 / mean;
        let f = 1.0 / (sigma * (2.0 * std::f64::consts::PI).sqrt());
        f * d.len() as f64 - d.iter().map(|di| f * (-(di * di) / (2.0 * sigma * sigma)).exp()).sum::<f64>()
    }

    #[test]
    fn authors_objective_is_minimised_by_the_median() {
        // neighbours spread over a few inches, as in feature space
        let samples: Vec<[f64; 2]> = (0..32)
            .map(|j| {
                let a = j as f64 * 2.4;
                [3.0 + 4.0 * a.cos() * (1.0 + (j % 3) as f64), -2.0 + 2.5 * a.sin()]
            })
            .collect();
        // Weiszfeld in 2-D
        let mut y = [0.0f64, 0.0];
        for _ in 0..500 {
            let (mut num, mut den) = ([0.0, 0.0], 0.0);
            for s in &samples {
                let w = 1.0 / ((y[0] - s[0]).hypot(y[1] - s[1])).max(1e-12);
                num[0] += w * s[0];
                num[1] += w * s[1];
                den += w;
            }
            y = [num[0] / den, num[1] / den];
        }
        let at_median = authors_objective(&y, &samples);
        for k in 0..16 {
            let a = k as f64 * std::f64::consts::TAU / 16.0;
            for r in [0.05, 0.3, 1.0] {
                let p = [y[0] + r * a.cos(), y[1] + r * a.sin()];
                assert!(authors_objective(&p, &samples) > at_median, "{p:?} beats the median");
            }
        }
    }
}
