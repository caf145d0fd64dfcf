//! The projection error of a growing window frame after frame, without a full eigen-decomposition
//! of its `D × D` covariance at every frame.
//!
//! The error `e` is the sum of the covariance's eigenvalues beyond the `r` largest: its trace less
//! the `r` largest eigenvalues. Adding a frame `x` changes the covariance by a rank-one term
//! (`(n−1)/n · δδᵀ`, `δ = x − x̄` of the window before it), so the leading eigenvectors move little
//! from one frame to the next. [`Leading`] keeps an orthonormal basis of the previous frame's
//! leading [`Leading::size`] eigenvectors and, each frame, finds the new ones by Rayleigh–Ritz on
//! that basis plus `δ`, adding the residuals `C u − θ u` of the `r` leading Ritz vectors and
//! repeating (one or two rounds on motion) until their Ritz values are known to [`TOLERANCE`] of
//! the trace: a Ritz value lies within its residual's length of an eigenvalue, and within its
//! square over the gap to the rest of the spectrum (estimated by the next Ritz value and its
//! residual). Ritz values never exceed the eigenvalues they approach, so `e` is the full
//! eigen-decomposition's to about 10⁻¹³ of the window's variance (the tests compare the two on
//! the fixtures' takes: the same cuts, the same curves). Where the rounds do not converge (a
//! jump in the data, a spectrum without a gap after the `r`-th value) the frame gets the full
//! symmetric eigen-decomposition, which also restarts the basis. A round costs `D²` multiply-adds per new
//! search direction (`size + 1`, then `r`) and a small eigenproblem, instead of the
//! decomposition's `≈ 4/3 D³` and its iterations: on the 10-minute take 2.7 s became about 1 s.

use nalgebra::{DMatrix, SymmetricEigen};

use super::{projection_error, Window};

/// The rounds stop when the `r` leading Ritz values' estimated error (their residuals' squared
/// lengths over the gap to the next Ritz value) is at most this fraction of the trace.
pub const TOLERANCE: f64 = 1e-13;

/// …and every one of those residuals at most this fraction of the trace (a Ritz value lies within
/// its residual of an eigenvalue whatever the gap).
const RESIDUAL: f64 = 1e-7;

/// Extra leading directions the basis keeps beyond the `r` the error needs: they let a direction
/// that grows past the `r`-th be followed without a restart, and speed up convergence.
const EXTRA: usize = 6;

/// Rayleigh–Ritz rounds before a frame falls back to the full decomposition.
const MAX_ROUNDS: usize = 6;

/// The projection error of a growing [`Window`] onto its `r` leading directions, tracked frame
/// after frame (see the module documentation).
#[derive(Debug, Clone)]
pub struct Leading {
    d: usize,
    r: usize,
    /// Orthonormal rows (`d` values each) spanning the last frame's leading eigenvectors, best
    /// first; empty before the first frame and after a fallback that found nothing to keep.
    basis: Vec<f64>,
    /// The covariance (`d × d`, both triangles).
    cov: Vec<f64>,
    /// Scratch: the search rows, their images under the covariance, the Ritz vectors and theirs.
    rows: Vec<f64>,
    images: Vec<f64>,
    ritz: Vec<f64>,
    ritz_images: Vec<f64>,
    /// Frames that fell back to the full decomposition (for tests and profiling).
    pub fallbacks: usize,
    /// Frames tracked, by rounds taken (for tests and profiling).
    pub rounds: [usize; MAX_ROUNDS + 1],
}

impl Leading {
    /// A tracker of the error beyond `r` directions in `d` dimensions.
    pub fn new(d: usize, r: usize) -> Self {
        Leading {
            d,
            r: r.min(d),
            basis: Vec::new(),
            cov: vec![0.0; d * d],
            rows: Vec::new(),
            images: Vec::new(),
            ritz: Vec::new(),
            ritz_images: Vec::new(),
            fallbacks: 0,
            rounds: [0; MAX_ROUNDS + 1],
        }
    }

    /// Directions the basis keeps.
    pub fn size(&self) -> usize {
        (self.r + EXTRA).min(self.d)
    }

    /// The projection error of `window` (whose newest frame is `newest`) onto its `r` leading
    /// directions, and its total variance (the trace): what [`projection_error`] of
    /// [`Window::eigenvalues`] and their sum give, to [`TOLERANCE`].
    pub fn error(&mut self, window: &Window, newest: &[f64]) -> (f64, f64) {
        let d = self.d;
        window.covariance_into(&mut self.cov);
        let trace: f64 = (0..d).map(|a| self.cov[a * d + a]).sum();
        if self.r == d {
            // every direction kept: no error (as `projection_error` gives it)
            let _ = newest;
            return (0.0, self.decompose(trace).1);
        }
        // the first two frames (and a frame whose rounds do not converge) get the decomposition,
        // which seeds the basis; from then on the basis holds the data's span while it is smaller
        // than the basis (the span grows by the new offset alone), so a young window's Ritz values
        // are its eigenvalues
        if window.len() > 2 && self.basis.len() == self.size() * d {
            if let Some(top) = self.track(window, newest, trace) {
                return ((trace - top).max(0.0), trace);
            }
            self.fallbacks += 1;
        }
        self.decompose(trace)
    }

    /// The full decomposition: the error as [`Window::eigenvalues`] gives it, and a new basis.
    fn decompose(&mut self, trace: f64) -> (f64, f64) {
        let d = self.d;
        if d == 0 {
            return (0.0, trace);
        }
        let eig = SymmetricEigen::new(DMatrix::from_row_slice(d, d, &self.cov));
        let mut order: Vec<usize> = (0..d).collect();
        order.sort_by(|&a, &b| eig.eigenvalues[b].total_cmp(&eig.eigenvalues[a]));
        let values: Vec<f64> = order.iter().map(|&i| eig.eigenvalues[i].max(0.0)).collect();
        self.basis.clear();
        for &i in order.iter().take(self.size()) {
            self.basis.extend(eig.eigenvectors.column(i).iter());
        }
        (projection_error(&values, self.r), values.iter().sum())
    }

    /// The sum of the `r` leading eigenvalues by Rayleigh–Ritz on the basis and the newest frame's
    /// offset from the mean, `None` when the rounds do not converge.
    fn track(&mut self, window: &Window, newest: &[f64], trace: f64) -> Option<f64> {
        let (d, r, m) = (self.d, self.r, self.size());

        self.rows.clear();
        self.rows.extend_from_slice(&self.basis);
        let mean = window.mean();
        let offset: Vec<f64> = newest.iter().zip(&mean).map(|(x, m)| x - m).collect();
        append_orthogonal(&mut self.rows, &offset, d);
        // the rows whose images are known (none yet: the covariance changed)
        let mut known = 0;
        self.images.clear();
        for round in 0..MAX_ROUNDS {
            let k = self.rows.len() / d;
            if k < m {
                return None;
            }
            // the other rows' images under the covariance (C symmetric: C b = Σ_b b[b] · row b of C)
            self.images.truncate(known * d);
            self.images.resize(k * d, 0.0);
            for (row, image) in self.rows.chunks_exact(d).zip(self.images.chunks_exact_mut(d)).skip(known) {
                for (&s, c) in row.iter().zip(self.cov.chunks_exact(d)) {
                    image.iter_mut().zip(c).for_each(|(w, &c)| *w += s * c);
                }
            }
            let h = DMatrix::from_fn(k, k, |i, j| {
                let (bi, bj) = (&self.rows[i * d..(i + 1) * d], &self.rows[j * d..(j + 1) * d]);
                let (wi, wj) = (&self.images[i * d..(i + 1) * d], &self.images[j * d..(j + 1) * d]);
                0.5 * (dot(bi, wj) + dot(bj, wi))
            });
            let eig = SymmetricEigen::new(h);
            let mut order: Vec<usize> = (0..k).collect();
            order.sort_by(|&a, &b| eig.eigenvalues[b].total_cmp(&eig.eigenvalues[a]));
            // the leading Ritz vectors and their images
            let keep = m;
            self.ritz.clear();
            self.ritz.resize(keep * d, 0.0);
            self.ritz_images.clear();
            self.ritz_images.resize(keep * d, 0.0);
            for (j, &o) in order.iter().take(keep).enumerate() {
                let (u, cu) = (&mut self.ritz[j * d..(j + 1) * d], &mut self.ritz_images[j * d..(j + 1) * d]);
                for i in 0..k {
                    let y = eig.eigenvectors[(i, o)];
                    u.iter_mut().zip(&self.rows[i * d..(i + 1) * d]).for_each(|(u, &b)| *u += y * b);
                    cu.iter_mut().zip(&self.images[i * d..(i + 1) * d]).for_each(|(w, &c)| *w += y * c);
                }
            }
            let theta: Vec<f64> = order.iter().take(keep).map(|&o| eig.eigenvalues[o]).collect();
            // residuals of the r leading ones and of the next (whose value bounds the gap)
            let mut residuals = Vec::with_capacity((r + 1) * d);
            let mut lengths = [0.0f64; 2];
            let (mut squares, mut largest) = (0.0f64, 0.0f64);
            for j in 0..=r {
                let start = residuals.len();
                residuals.extend(
                    self.ritz_images[j * d..(j + 1) * d]
                        .iter()
                        .zip(&self.ritz[j * d..(j + 1) * d])
                        .map(|(&cu, &u)| cu - theta[j] * u),
                );
                let square = dot(&residuals[start..], &residuals[start..]);
                if j < r {
                    squares += square;
                    largest = largest.max(square.sqrt());
                } else {
                    lengths[1] = square.sqrt();
                }
            }
            lengths[0] = largest;
            let gap = theta[r - 1] - theta[r] - lengths[1];
            if lengths[0] <= RESIDUAL * trace && (squares == 0.0 || gap > 0.0 && squares <= TOLERANCE * trace * gap) {
                self.rounds[round + 1] += 1;
                self.basis.clear();
                self.basis.extend_from_slice(&self.ritz);
                return Some(theta[..r].iter().sum());
            }
            residuals.truncate(r * d);
            // search again on the leading Ritz vectors (orthonormal to rounding, their images known)
            // and their residuals
            self.rows.clear();
            self.rows.extend_from_slice(&self.ritz);
            self.images.clear();
            self.images.extend_from_slice(&self.ritz_images);
            known = m;
            for res in residuals.chunks_exact(d) {
                append_orthogonal(&mut self.rows, res, d);
            }
        }
        None
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    // four running sums, so that the loop vectorises
    let mut acc = [0.0f64; 4];
    let (ca, cb) = (a.chunks_exact(4), b.chunks_exact(4));
    let tail: f64 = ca.remainder().iter().zip(cb.remainder()).map(|(x, y)| x * y).sum();
    for (x, y) in ca.zip(cb) {
        for l in 0..4 {
            acc[l] += x[l] * y[l];
        }
    }
    acc[0] + acc[1] + acc[2] + acc[3] + tail
}

/// Appends `v` to the orthonormal rows `rows` (`d` values each) after removing its components
/// along them (twice, for orthogonality to rounding), unless little of it is left.
fn append_orthogonal(rows: &mut Vec<f64>, v: &[f64], d: usize) {
    let norm = dot(v, v).sqrt();
    if !(norm > 0.0) || rows.len() / d >= d {
        return;
    }
    let mut w = v.to_vec();
    for _ in 0..2 {
        for q in rows.chunks_exact(d) {
            let s = dot(q, &w);
            w.iter_mut().zip(q).for_each(|(w, &q)| *w -= s * q);
        }
    }
    let left = dot(&w, &w).sqrt();
    if left > 1e-8 * norm {
        rows.extend(w.iter().map(|x| x / left));
    }
}
