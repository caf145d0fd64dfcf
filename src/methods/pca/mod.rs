//! PCA segmentation: the in-line baseline Bouchard & Badler compare LMA with (their §5.1, "the
//! Principal Component Analysis (PCA) segmentation method from Barbič et al. [2004] … an in-line
//! method that finds the largest segments with the smallest PCA projection error"), after Barbič,
//! Safonova, Pan, Faloutsos, Hodgins & Pollard, "Segmenting Motion Capture Data into Distinct
//! Behaviors" (Graphics Interface 2004), PCA-SVD approach.
//!
//! 1. [`poses`]: every frame is a point `x_j` in a pose space: the 16 canonical joints other
//!    than the hips ([`crate::motion::joints::Canonical`]), hip-relative, facing-aligned, divided
//!    by the body size ([`crate::motion::normalize::body_scaled`]), at the working rate (30 Hz):
//!    48 numbers per frame;
//! 2. [`scan`]: from frame `start` (0, then each cut), the dimension `r` of the segment is the
//!    smallest number of principal directions of its first `k` frames (`window_s`) that keep a
//!    fraction ≥ `tau` of their variance. For the growing window `start..=start + i` the
//!    projection error onto the best `r`-dimensional hyperplane (mean + top-`r` principal
//!    directions) is `e_i`, the sum of the scatter matrix's eigenvalues beyond the `r` largest.
//!    Inside one behaviour `e_i` rises steadily; when a new behaviour begins it rises faster. With
//!    `d_i = e_i − e_{i−ℓ}` (`ℓ` = `lag_s`), a cut is declared at the first `i ≥ k` where
//!    `d_i > mean + k_σ · std` of the `d_j` (`ℓ ≤ j < i`) of this segment so far; the search
//!    restarts at the cut, so cuts are at least `k` frames apart. The window is kept as a running
//!    sum and scatter (`Σ x xᵀ`, about the segment's first frame): each step is one rank-one
//!    update, never an SVD of the growing window, and the error follows the leading eigenvectors
//!    from one frame to the next ([`leading`]) rather than solving the D×D symmetric eigenvalue
//!    problem at every frame (that full solution is kept for a segment's first frames and as the
//!    fallback);
//! 3. one segment (level `action`, labels `B1`, `B2`, … for "behaviour") per cut, its `score` the
//!    cut's `d_i / (mean + k_σ · std)` (none for the first segment).
//!
//! Deviations from Barbič et al.:
//! * **Pose space.** Barbič used joint angles; we use the canonical joints' positions,
//!   normalised as above, so that every skeleton gives the same 48 coordinates with the same
//!   meaning (and no angle wrap-around or quaternion sign to handle).
//! * **Working rate.** The parameters are in seconds (`k` = 2 s, `ℓ` = 0.5 s) and the take is
//!   resampled to 30 Hz, whatever its own rate (Barbič worked on the 120 Hz frames).
//! * **Statistics.** "So far" is read as the derivatives before `i` (`ℓ ≤ j < i`), as in Barbič.
//! * **Flat data.** A derivative also has to exceed 10⁻⁹ of the window's total variance to cut
//!   ([`ROUNDING`]), so that rounding noise on perfectly flat (or perfectly `r`-dimensional)
//!   data is not taken for a new behaviour.
//! * **Short remainders.** When fewer than `k` frames are left after a cut, `r` comes from all of
//!   them and no further cut is sought; a take shorter than `k` frames is one segment.

pub mod leading;
pub mod method;

use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};

use crate::method::bounds::{self, NumberParam, Valid};
use crate::method::unsupervised::Checkable;
use crate::method::{Cancelled, MethodError};
use crate::motion::joints::Canonical;
use crate::motion::normalize::body_scaled;
use crate::motion::resample::source_positions;
use crate::motion::Motion;
use leading::Leading;

/// A derivative must exceed this fraction of the window's total variance to cut (see the module
/// documentation, "flat data").
pub const ROUNDING: f64 = 1e-9;

/// Report progress every this many frames of the scan.
const REPORT_EVERY: usize = 64;

/// Parameters of the PCA segmentation (see the module documentation).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PcaParams {
    /// Frame rate the method works at; takes are resampled to it.
    pub fps: f64,
    /// Fraction of the variance of a segment's first `window_s` that its `r` directions keep.
    pub tau: f64,
    /// `k`: seconds that fix a segment's dimension, and the shortest segment.
    pub window_s: f64,
    /// `ℓ`: seconds between the two errors of the derivative `d_i = e_i − e_{i−ℓ}`.
    pub lag_s: f64,
    /// A cut where the derivative exceeds its mean by this many standard deviations.
    pub k_sigma: f64,
}

impl Default for PcaParams {
    fn default() -> Self {
        PcaParams { fps: 30.0, tau: 0.9, window_s: 2.0, lag_s: 0.5, k_sigma: 3.0 }
    }
}

/// [`PcaParams`] that passed [`PcaParams::check`].
pub type ValidParams = Valid<PcaParams>;

/// Every parameter: range, unit, help.
pub const PARAMS: [NumberParam; 5] = [
    bounds::WORKING_FPS,
    NumberParam {
        name: "tau",
        min: 0.5,
        max: 0.999,
        unit: "",
        help: "Fraction of the variance of a segment's first frames its principal directions must keep.",
        basic: true,
    },
    NumberParam {
        name: "window_s",
        min: 1.0,
        max: 20.0,
        unit: "s",
        help: "Seconds that fix a segment's dimension; also the shortest segment.",
        basic: true,
    },
    NumberParam {
        name: "lag_s",
        min: 0.1,
        max: 5.0,
        unit: "s",
        help: "The error's derivative is taken over this many seconds (at most half of window_s).",
        basic: false,
    },
    NumberParam {
        name: "k_sigma",
        min: 0.5,
        max: 10.0,
        unit: "",
        help: "A cut where the error's derivative exceeds its mean by this many standard deviations.",
        basic: true,
    },
];

impl PcaParams {
    pub(crate) fn value(&self, name: &str) -> f64 {
        match name {
            "fps" => self.fps,
            "tau" => self.tau,
            "window_s" => self.window_s,
            "lag_s" => self.lag_s,
            _ => self.k_sigma,
        }
    }
}

/// Validates every parameter; the method only ever runs on the result.
impl Checkable for PcaParams {
    type Valid = ValidParams;

    fn check(self) -> Result<ValidParams, MethodError> {
        bounds::check("PCA", &PARAMS, |n| self.value(n))?;
        if self.lag_s > self.window_s / 2.0 {
            let expected = format!("at most half of window_s ({})", self.window_s / 2.0);
            return Err(bounds::refuse("PCA", "lag_s", self.lag_s, &expected));
        }
        Ok(Valid::checked(self))
    }
}

impl ValidParams {
    /// `k` in working frames.
    pub fn window(&self) -> usize {
        (self.window_s * self.fps).round().max(2.0) as usize
    }

    /// `ℓ` in working frames.
    pub fn lag(&self) -> usize {
        (self.lag_s * self.fps).round().max(1.0) as usize
    }
}

/// Why a take has no pose space.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PoseError {
    #[error("the take has no frames")]
    NoFrames,
    #[error("{0}")]
    MissingJoints(String),
    #[error("{0}")]
    Motion(#[from] crate::motion::MotionError),
    #[error("the take has a joint position that is not a finite number (working frame {0})")]
    NotFinite(usize),
}

/// The frames of a take as points of the pose space (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct Poses {
    /// `dim` values per working frame, frame-major.
    pub data: Vec<f64>,
    pub dim: usize,
    /// Fractional file frame of each working frame.
    pub source_frames: Vec<f64>,
}

impl Poses {
    pub fn frames(&self) -> usize {
        self.data.len() / self.dim.max(1)
    }
}

/// The pose space of `motion` at `fps`: the canonical joints but the hips, hip-relative,
/// facing-aligned, in body sizes.
pub fn poses(motion: &Motion, fps: f64) -> Result<Poses, PoseError> {
    if motion.frames() == 0 {
        return Err(PoseError::NoFrames);
    }
    let map = motion.joint_map().map_err(|e| PoseError::MissingJoints(e.to_string()))?;
    let source_frames = source_positions(motion.frames(), motion.fps, fps)?;
    let working = motion.resample(fps)?;
    let joints: Vec<usize> = Canonical::ALL.iter().filter(|&&c| c != Canonical::Hips).map(|&c| map.get(c)).collect();
    let scaled = body_scaled(&working, &map);
    let per_frame = working.joints();
    let dim = 3 * joints.len();
    let mut data = Vec::with_capacity(working.frames() * dim);
    for (f, frame) in scaled.chunks_exact(per_frame).enumerate() {
        for &j in &joints {
            let p = frame[j];
            if !p.is_finite() {
                return Err(PoseError::NotFinite(f));
            }
            data.extend([p.x as f64, p.y as f64, p.z as f64]);
        }
    }
    Ok(Poses { data, dim, source_frames })
}

/// A growing window of frames: its count, running sum and scatter (`Σ (x − o)(x − o)ᵀ` about
/// the origin `o`, the window's first frame, so that nothing large cancels).
#[derive(Debug, Clone)]
pub struct Window {
    origin: Vec<f64>,
    count: usize,
    sum: Vec<f64>,
    scatter: DMatrix<f64>,
    centred: Vec<f64>,
}

impl Window {
    /// An empty window about `origin` (any point near the data; its first frame).
    pub fn new(origin: &[f64]) -> Self {
        let d = origin.len();
        Window {
            origin: origin.to_vec(),
            count: 0,
            sum: vec![0.0; d],
            scatter: DMatrix::zeros(d, d),
            centred: vec![0.0; d],
        }
    }

    pub fn len(&self) -> usize {
        self.count
    }

    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// Adds one frame (a rank-one update of the upper triangle).
    pub fn push(&mut self, x: &[f64]) {
        let d = self.origin.len();
        for ((c, &v), &o) in self.centred.iter_mut().zip(x).zip(&self.origin) {
            *c = v - o;
        }
        for a in 0..d {
            let ca = self.centred[a];
            self.sum[a] += ca;
            if ca == 0.0 {
                continue;
            }
            for b in a..d {
                self.scatter[(a, b)] += ca * self.centred[b];
            }
        }
        self.count += 1;
    }

    /// The window's mean.
    pub fn mean(&self) -> Vec<f64> {
        let n = self.count.max(1) as f64;
        self.origin.iter().zip(&self.sum).map(|(o, s)| o + s / n).collect()
    }

    /// The window's scatter about its mean (`Σ (x − x̄)(x − x̄)ᵀ`) into `out` (`d × d`, both
    /// triangles; zero for an empty window).
    pub fn covariance_into(&self, out: &mut [f64]) {
        let d = self.origin.len();
        if self.count == 0 {
            out[..d * d].fill(0.0);
            return;
        }
        let n = self.count as f64;
        for a in 0..d {
            for b in a..d {
                let v = self.scatter[(a, b)] - self.sum[a] * self.sum[b] / n;
                out[a * d + b] = v;
                out[b * d + a] = v;
            }
        }
    }

    /// Eigenvalues of the window's scatter about its mean (`Σ (x − x̄)(x − x̄)ᵀ`), largest
    /// first, negative rounding clamped to 0.
    pub fn eigenvalues(&self) -> Vec<f64> {
        let d = self.origin.len();
        if self.count == 0 {
            return vec![0.0; d];
        }
        let mut c = vec![0.0; d * d];
        self.covariance_into(&mut c);
        let mut eig: Vec<f64> =
            DMatrix::from_row_slice(d, d, &c).symmetric_eigenvalues().iter().map(|&v| v.max(0.0)).collect();
        eig.sort_by(|a, b| b.total_cmp(a));
        eig
    }
}

/// The smallest `r` whose largest `r` of `eigenvalues` (largest first) hold at least `tau` of
/// their sum (1 when the sum is 0).
pub fn intrinsic_dim(eigenvalues: &[f64], tau: f64) -> usize {
    let total: f64 = eigenvalues.iter().sum();
    if total <= 0.0 {
        return 1.min(eigenvalues.len());
    }
    let mut kept = 0.0;
    for (r, &v) in eigenvalues.iter().enumerate() {
        kept += v;
        if kept >= tau * total {
            return r + 1;
        }
    }
    eigenvalues.len()
}

/// The projection error onto the best `r`-dimensional hyperplane: the sum of `eigenvalues`
/// (largest first) beyond the `r` largest.
pub fn projection_error(eigenvalues: &[f64], r: usize) -> f64 {
    eigenvalues.iter().skip(r).sum()
}

/// A cut between two behaviours.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cut {
    /// First working frame of the new behaviour.
    pub frame: usize,
    /// `d_i / (mean + k_σ · std)` at the cut (above 1).
    pub ratio: f64,
}

/// What [`scan`] finds, per working frame.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Scan {
    /// `e_i`: projection error of the window from its segment's first frame to this one.
    pub error: Vec<f64>,
    /// `d_i = e_i − e_{i−ℓ}` (0 for the first `ℓ` frames of a segment).
    pub derivative: Vec<f64>,
    /// `d_i / (mean + k_σ · std)` where the cut test ran (from the `k`-th frame of a segment on),
    /// else 0.
    pub ratio: Vec<f64>,
    pub cuts: Vec<Cut>,
    /// `r` of every segment, in order.
    pub dims: Vec<usize>,
}

/// The PCA segmentation of `frames` (`dim` finite values per frame; [`poses`] checks that),
/// reporting progress (stage "scan", fractions `0.1..0.9`) every [`REPORT_EVERY`] frames.
pub fn scan(
    frames: &[f64],
    dim: usize,
    params: &ValidParams,
    progress: &mut dyn FnMut(&str, f64) -> Result<(), Cancelled>,
) -> Result<Scan, Cancelled> {
    scan_with(frames, dim, params, progress, false)
}

/// [`scan`], with every frame's error from the full eigen-decomposition when `exact` (the
/// scan as it was before [`leading`]; the tests compare the two).
fn scan_with(
    frames: &[f64],
    dim: usize,
    params: &ValidParams,
    progress: &mut dyn FnMut(&str, f64) -> Result<(), Cancelled>,
    exact: bool,
) -> Result<Scan, Cancelled> {
    let n = frames.len().checked_div(dim).unwrap_or(0);
    let row = |i: usize| &frames[i * dim..(i + 1) * dim];
    let (k, lag) = (params.window(), params.lag());
    let mut out =
        Scan { error: vec![0.0; n], derivative: vec![0.0; n], ratio: vec![0.0; n], cuts: Vec::new(), dims: Vec::new() };
    let mut start = 0;
    let mut next_report = 0;
    while start < n {
        // r from the segment's first k frames (or all that are left)
        let first = k.min(n - start);
        let mut head = Window::new(row(start));
        (start..start + first).for_each(|i| head.push(row(i)));
        let r = intrinsic_dim(&head.eigenvalues(), params.tau);
        out.dims.push(r);
        let mut window = Window::new(row(start));
        let mut leading = Leading::new(dim, r);
        let (mut sum, mut sum_sq, mut count) = (0.0f64, 0.0f64, 0usize);
        let mut cut = None;
        for t in start..n {
            if t >= next_report {
                progress("scan", 0.1 + 0.8 * t as f64 / n as f64)?;
                next_report = t + REPORT_EVERY;
            }
            window.push(row(t));
            let (e, total) = if exact {
                let eig = window.eigenvalues();
                (projection_error(&eig, r), eig.iter().sum::<f64>())
            } else {
                leading.error(&window, row(t))
            };
            out.error[t] = e;
            let i = t - start;
            if i < lag {
                continue;
            }
            let d = e - out.error[t - lag];
            out.derivative[t] = d;
            if i >= k && count >= 2 && first == k {
                let mean = sum / count as f64;
                let var = (sum_sq / count as f64 - mean * mean).max(0.0);
                let threshold = mean + params.k_sigma * var.sqrt();
                let floor = ROUNDING * total;
                if threshold > 0.0 {
                    out.ratio[t] = d / threshold;
                }
                if d > threshold && d > floor {
                    cut = Some(Cut { frame: t, ratio: if threshold > 0.0 { d / threshold } else { f64::INFINITY } });
                    break;
                }
            }
            sum += d;
            sum_sq += d * d;
            count += 1;
        }
        match cut {
            Some(c) => {
                out.cuts.push(c);
                start = c.frame;
            }
            None => break,
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stats::Rng;
    use nalgebra::SymmetricEigen;

    fn noise(rng: &mut Rng, sigma: f64) -> f64 {
        // sum of 4 uniforms, centred and scaled to the standard deviation sigma
        let s: f64 = (0..4).map(|_| rng.next_f32() as f64).sum::<f64>() - 2.0;
        s * sigma * 3f64.sqrt()
    }

    /// The error of frames `a..=b` computed from scratch: covariance about the mean, eigenvalues.
    fn direct_error(frames: &[f64], dim: usize, a: usize, b: usize, r: usize) -> f64 {
        let m = b - a + 1;
        let x = DMatrix::from_fn(m, dim, |i, j| frames[(a + i) * dim + j]);
        let mean = x.row_mean();
        let centred = DMatrix::from_fn(m, dim, |i, j| x[(i, j)] - mean[j]);
        let eig = SymmetricEigen::new(centred.transpose() * &centred);
        let mut values: Vec<f64> = eig.eigenvalues.iter().copied().collect();
        values.sort_by(|p, q| q.total_cmp(p));
        values.iter().skip(r).map(|v| v.max(0.0)).sum()
    }

    fn params() -> ValidParams {
        PcaParams::default().check().unwrap()
    }

    #[test]
    fn the_incremental_error_is_the_direct_one() {
        let mut rng = Rng::new(7);
        let dim = 9;
        let mut x = vec![0.0; dim];
        let mut frames = Vec::new();
        for _ in 0..200 {
            x.iter_mut().for_each(|v| *v += noise(&mut rng, 0.05) + 0.01);
            frames.extend(x.iter().map(|v| v + 100.0));
        }
        for r in [1, 3] {
            let mut w = Window::new(&frames[..dim]);
            for t in 0..200 {
                w.push(&frames[t * dim..(t + 1) * dim]);
                let fast = projection_error(&w.eigenvalues(), r);
                let slow = direct_error(&frames, dim, 0, t, r);
                assert!((fast - slow).abs() <= 1e-9 * (1.0 + slow), "r {r} frame {t}: {fast} vs {slow}");
            }
        }
        // and scan's e_i is that error, with r from the first k frames
        let s = scan(&frames, dim, &params(), &mut |_, _| Ok(())).unwrap();
        let first = s.cuts.first().map_or(200, |c| c.frame);
        let r = s.dims[0];
        for t in [0, 10, 59, 60, first - 1] {
            let slow = direct_error(&frames, dim, 0, t, r);
            assert!((s.error[t] - slow).abs() <= 1e-9 * (1.0 + slow), "frame {t}");
        }
    }

    /// [`scan`] (the error tracked from frame to frame) against the scan with every frame's full
    /// eigen-decomposition, as it was: the same cuts and dimensions, and every error and ratio
    /// within rounding of the old ones.
    fn same_as_exact(frames: &[f64], dim: usize, params: &ValidParams, what: &str) {
        let fast = scan(frames, dim, params, &mut |_, _| Ok(())).unwrap();
        let exact = scan_with(frames, dim, params, &mut |_, _| Ok(()), true).unwrap();
        assert_eq!(fast.cuts.len(), exact.cuts.len(), "{what}: {:?} vs {:?}", fast.cuts, exact.cuts);
        // a ratio over a threshold of rounding noise (after flat data) is itself noise: huge, or 0
        // where the noise came out exactly 0
        let noise = |r: f64| r == 0.0 || r.abs() > 1e6;
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-6 * b.abs().max(1e-3) || noise(a) && noise(b);
        for (a, b) in fast.cuts.iter().zip(&exact.cuts) {
            assert_eq!(a.frame, b.frame, "{what}: {:?} vs {:?}", fast.cuts, exact.cuts);
            assert!(close(a.ratio, b.ratio), "{what}: {a:?} vs {b:?}");
        }
        assert_eq!(fast.dims, exact.dims, "{what}");
        // the error to 1e-9 of the largest in its segment (the window's variance grows with it), or
        // to rounding (1e-12 of data of order 1) in a flat segment
        let bounds: Vec<usize> = std::iter::once(0)
            .chain(exact.cuts.iter().map(|c| c.frame))
            .chain(std::iter::once(exact.error.len()))
            .collect();
        for w in bounds.windows(2) {
            let top = exact.error[w[0]..w[1]].iter().fold(0.0f64, |a, &b| a.max(b));
            for t in w[0]..w[1] {
                let (a, b) = (fast.error[t], exact.error[t]);
                assert!((a - b).abs() <= 1e-9 * top + 1e-12, "{what} frame {t}: {a} vs {b} (top {top})");
                let (a, b) = (fast.ratio[t], exact.ratio[t]);
                assert!(close(a, b), "{what} frame {t}: ratio {a} vs {b}");
            }
        }
    }

    #[test]
    fn the_tracked_error_cuts_the_takes_as_the_full_decomposition_did() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures");
        let mut takes = 0;
        for name in [
            "13_31.bvh",
            "86_01.bvh",
            "131_01.bvh",
            "131_03.bvh",
            "02_01.bvh",
            "12_01.bvh",
            "35_01.bvh",
            "assimp_Boxing_Toes_100fps.bvh",
            "mixamo_names_freebvh.bvh",
        ] {
            let motion = crate::load::load_path(&dir.join(name)).unwrap().motion;
            let Ok(p) = poses(&motion, 30.0) else { continue };
            for params in [
                params(),
                PcaParams { tau: 0.95, k_sigma: 2.0, ..Default::default() }.check().unwrap(),
                PcaParams { tau: 0.99, window_s: 1.0, lag_s: 0.2, ..Default::default() }.check().unwrap(),
            ] {
                same_as_exact(&p.data, p.dim, &params, name);
            }
            takes += 1;
        }
        assert!(takes >= 8, "{takes} takes compared");
    }

    #[test]
    fn the_tracked_error_is_the_full_decompositions_on_synthetic_behaviours() {
        for seed in 1..6 {
            let mut rng = Rng::new(seed);
            let dim = 12;
            let d = directions(&mut rng, dim);
            let mut frames = behaviour(&mut rng, &d[0], &d[1], 150, 0.01);
            frames.extend(behaviour(&mut rng, &d[2], &d[3], 150, 0.01));
            frames.extend(vec![0.5; 12 * 100]);
            frames.extend(behaviour(&mut rng, &d[1], &d[3], 150, 0.0));
            same_as_exact(&frames, dim, &params(), &format!("seed {seed}"));
        }
    }

    /// `len` frames of `dim` values going round a flat ellipse: along the unit direction `u` and
    /// a fifth as far along `w` (orthogonal), plus noise. The ellipse, not only noise, leaves the
    /// best line: in real motion the residual beyond `r` is the movement's own shape; on pure
    /// white noise the 3σ test fires now and then at its false-alarm rate (a few per cent of
    /// 300-frame takes with 12 dimensions and σ = 0.05 of the amplitude; none with the ellipse).
    fn behaviour(rng: &mut Rng, u: &[f64], w: &[f64], len: usize, sigma: f64) -> Vec<f64> {
        let mut out = Vec::new();
        for t in 0..len {
            let phase = 2.0 * std::f64::consts::PI * t as f64 / 37.0;
            let (a, b) = (phase.sin(), 0.2 * phase.cos());
            out.extend(u.iter().zip(w).map(|(&cu, &cw)| a * cu + b * cw + noise(rng, sigma)));
        }
        out
    }

    /// Four orthonormal random directions in `dim` dimensions (Gram–Schmidt).
    fn directions(rng: &mut Rng, dim: usize) -> Vec<Vec<f64>> {
        let mut out: Vec<Vec<f64>> = Vec::new();
        while out.len() < 4 {
            let mut v: Vec<f64> = (0..dim).map(|_| noise(rng, 1.0)).collect();
            for u in &out {
                let dot: f64 = u.iter().zip(&v).map(|(a, b)| a * b).sum();
                v.iter_mut().zip(u).for_each(|(c, a)| *c -= dot * a);
            }
            let l = v.iter().map(|c| c * c).sum::<f64>().sqrt();
            v.iter_mut().for_each(|c| *c /= l);
            out.push(v);
        }
        out
    }

    #[test]
    fn two_behaviours_are_cut_once_near_the_change() {
        for seed in 1..11 {
            let mut rng = Rng::new(seed);
            let dim = 12;
            let d = directions(&mut rng, dim);
            let mut frames = behaviour(&mut rng, &d[0], &d[1], 150, 0.01);
            frames.extend(behaviour(&mut rng, &d[2], &d[3], 150, 0.01));
            let s = scan(&frames, dim, &params(), &mut |_, _| Ok(())).unwrap();
            assert_eq!(s.cuts.len(), 1, "seed {seed}: {:?}", s.cuts);
            assert!(s.cuts[0].frame.abs_diff(150) <= 10, "seed {seed}: {:?}", s.cuts);
            assert!(s.cuts[0].ratio > 1.0);
            assert_eq!(s.dims, vec![1, 1], "seed {seed}");
            assert_eq!(s.error.len(), 300);
        }
    }

    #[test]
    fn one_behaviour_is_not_cut() {
        for seed in 1..11 {
            let mut rng = Rng::new(seed);
            let dim = 12;
            let d = directions(&mut rng, dim);
            let frames = behaviour(&mut rng, &d[0], &d[1], 300, 0.01);
            let s = scan(&frames, dim, &params(), &mut |_, _| Ok(())).unwrap();
            assert!(s.cuts.is_empty(), "seed {seed}: {:?}", s.cuts);
        }
        // perfectly still, and shorter than k: one segment, no cut
        let still = vec![0.5; 12 * 100];
        assert!(scan(&still, 12, &params(), &mut |_, _| Ok(())).unwrap().cuts.is_empty());
        let short = vec![0.5; 12 * 20];
        let s = scan(&short, 12, &params(), &mut |_, _| Ok(())).unwrap();
        assert!(s.cuts.is_empty() && s.error.len() == 20);
    }

    #[test]
    fn intrinsic_dimension_keeps_tau_of_the_variance() {
        assert_eq!(intrinsic_dim(&[8.0, 1.0, 1.0], 0.9), 2);
        assert_eq!(intrinsic_dim(&[9.0, 0.5, 0.5], 0.9), 1);
        assert_eq!(intrinsic_dim(&[0.0, 0.0], 0.9), 1);
        assert_eq!(projection_error(&[8.0, 1.0, 0.5], 1), 1.5);
    }

    #[test]
    fn parameters_are_checked_on_both_sides() {
        assert!(PcaParams::default().check().is_ok());
        let bad = |p: PcaParams| p.check().unwrap_err().to_string();
        assert_eq!(
            bad(PcaParams { tau: 1.5, ..Default::default() }),
            "invalid PCA parameter tau = 1.5: expected 0.5 to 0.999"
        );
        assert!(bad(PcaParams { tau: 0.1, ..Default::default() }).contains("tau"));
        assert!(bad(PcaParams { k_sigma: 1e300, ..Default::default() }).contains("k_sigma = 1e300"));
        assert!(bad(PcaParams { window_s: f64::NAN, ..Default::default() }).contains("window_s"));
        assert!(bad(PcaParams { fps: 5.0, ..Default::default() }).contains("10 to 240 Hz"));
        assert!(bad(PcaParams { lag_s: 0.0, ..Default::default() }).contains("lag_s"));
        assert!(bad(PcaParams { lag_s: 1.5, ..Default::default() }).contains("at most half of window_s"));
        let p = params();
        assert_eq!((p.window(), p.lag()), (60, 15));
    }

    #[test]
    fn a_cancel_stops_the_scan() {
        let mut rng = Rng::new(3);
        let d = directions(&mut rng, 6);
        let frames = behaviour(&mut rng, &d[0], &d[1], 300, 0.01);
        assert_eq!(scan(&frames, 6, &params(), &mut |_, _| Err(Cancelled)), Err(Cancelled));
        // cancelled half-way: after the first reports
        let mut reports = 0;
        let r = scan(&frames, 6, &params(), &mut |_, _| {
            reports += 1;
            if reports > 2 {
                Err(Cancelled)
            } else {
                Ok(())
            }
        });
        assert_eq!((r, reports), (Err(Cancelled), 3));
    }
}
