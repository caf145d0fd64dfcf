//! The k-nearest-neighbour labeller the DT-FCN issue puts beside the network: each frame's label
//! is the majority of its `k` nearest training frames, a frame being the ±1 s window of the motion
//! image around it (the canonical joints at 30 Hz, hip-relative, facing-aligned, in inches of the
//! reference body), sampled every `stride` frames and rotated onto its leading principal axes
//! (nalgebra), searched by an exact scan ([`search`]) that finds the neighbours a kiddo kd-tree
//! finds, in the tree's order — the tree answers the rare query whose neighbours tie. The
//! confidence of a frame is the share of votes its label won.
//!
//! It is a registered method (`knn`, [`method`]): the labelling method both labellers share
//! ([`crate::labeller::method`]) over its model files ([`model`]: its payload and header field in the common model
//! file), fitted on label CSVs as the network is trained ([`supervised`], [`training`]).
//! `cargo run --release --example eval_knn` scores it leave-one-take-out on the shared takes.

mod lanes;
pub mod method;
pub mod model;
pub mod search;
pub mod supervised;
pub mod training;

use std::sync::OnceLock;

use kiddo::immutable::float::kdtree::ImmutableKdTree;
use kiddo::SquaredEuclidean;

use crate::features::end_effectors::canonical_joints;
use crate::features::pca::principal_axes;
use crate::features::{stack, FeatureMatrix};
use crate::labeller::probabilities::Probabilities;
use crate::method::Go;
use crate::motion::joints::Canonical;
use crate::motion::Motion;
use crate::segment::frames::WorkingFrames;
use lanes::F4;
use search::{Found, Scan};

/// Principal coordinates the tree searches.
pub const DIMS: usize = 32;

/// A scan's `k`-th and `(k+1)`-th neighbours must lie more than this fraction apart for its
/// neighbours to be taken for the tree's (see [`Knn::nearest_n`]): the tree's pruning bounds are
/// sums of the same squares in another order, so it can miss a point within rounding (at most
/// 31 · 2⁻²⁴ ≈ 2·10⁻⁶ of the distance) of its `k`-th.
const TIE_MARGIN: f32 = 1e-5;

/// How frames are described and voted on.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct KnnParams {
    pub fps: f64,
    /// Half the window, in working frames (30 = ±1 s at 30 Hz).
    pub half_window: i32,
    /// Every this many frames of the window are kept.
    pub stride: i32,
    pub k: usize,
    /// What a frame of the window holds ([`KnnInput`]); files without the field read the joints.
    #[serde(default, skip_serializing_if = "KnnInput::is_joints")]
    pub input: KnnInput,
}

/// The rows of the motion image a k-NN window is made of (issue 50: the k-NN read the hip-relative joints only, without
/// the root's velocity and turning rows that lifted DT-FCN's held-out accuracy from 0.877 to 0.951).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum KnnInput {
    /// The 17 canonical joints, hip-relative, facing +Z, in inches of the reference body, as they are.
    #[default]
    Joints,
    /// DT-FCN's input ([`crate::labeller::input::network_input`]): the joints, the hips row holding the root's velocity
    /// in the body frame and the turning row, every channel standardised by the training frames' mean and spread as
    /// the network's is. The standardisation is folded into the model's mean and axes (the file holds the same
    /// fields as a joints model's).
    Network,
}

impl KnnInput {
    fn is_joints(&self) -> bool {
        *self == KnnInput::Joints
    }

    /// Image rows a frame of the window holds (three values each).
    pub fn rows(self) -> usize {
        match self {
            KnnInput::Joints => Canonical::ALL.len(),
            KnnInput::Network => crate::labeller::input::JOINTS,
        }
    }

    /// The names of those rows, as a model file's header lists them.
    pub fn row_names(self) -> Vec<String> {
        match self {
            KnnInput::Joints => crate::labeller::input::canonical_names(),
            KnnInput::Network => crate::labeller::input::joint_names(),
        }
    }

    /// Its name in parameter lists.
    pub fn name(self) -> &'static str {
        match self {
            KnnInput::Joints => "joints",
            KnnInput::Network => "network",
        }
    }
}

impl Default for KnnParams {
    fn default() -> Self {
        KnnParams { fps: 30.0, half_window: 30, stride: 5, k: 5, input: KnnInput::Joints }
    }
}

impl KnnParams {
    /// Refuses windows and votes the labeller cannot use (as read from a model file).
    pub fn check(&self) -> Result<(), String> {
        if (self.fps - crate::labeller::input::NETWORK_FPS).abs() > 1e-9 {
            return Err(format!("k-NN at {} Hz; this mocapseg's k-NN works at 30 Hz", self.fps));
        }
        if !(0..=300).contains(&self.half_window) || !(1..=300).contains(&self.stride) {
            return Err(format!(
                "k-NN window ±{} frames every {}: expected 0 to 300 and 1 to 300",
                self.half_window, self.stride
            ));
        }
        if !(1..=100).contains(&self.k) {
            return Err(format!("k-NN k = {}: expected 1 to 100", self.k));
        }
        Ok(())
    }
}

/// A labelled take for fitting: the motion and one label index per file frame.
pub struct Labelled<'a> {
    pub motion: &'a Motion,
    pub labels: &'a [usize],
}

/// The fitted labeller.
pub struct Knn {
    params: KnnParams,
    mean: Vec<f32>,
    /// `DIMS × d` leading principal axes.
    axes: Vec<f32>,
    points: Vec<[f32; DIMS]>,
    /// The axes transposed, `DIMS` weights per window value (zero beyond the model's axes).
    columns: Vec<f32>,
    /// The model's axes (at most `DIMS`): the coordinates beyond are 0.
    axes_kept: usize,
    scan: Scan,
    /// The kd-tree, built the first time a query's neighbours tie ([`Knn::nearest_n`]).
    tree: OnceLock<ImmutableKdTree<f32, u32, DIMS, 32>>,
    labels: Vec<usize>,
    /// [`Knn::familiar_distances`] at the take fit's gap and step, measured once.
    familiar: std::sync::OnceLock<Vec<f32>>,
    /// [`Knn::class_familiar`] at the take fit's gap and step for every class of the windows, measured once.
    class_scales: std::sync::OnceLock<Vec<Option<f32>>>,
}

/// A long loop asks [`Go`] every this many frames (a few milliseconds of a wide window's projection).
const GO_EVERY: usize = 256;

/// What a loop that never stops cannot give: the error of the functions without a [`Go`].
const STOPPED: &str = "stopped";

/// The frame offsets of a window.
fn offsets(p: &KnnParams) -> Vec<i32> {
    (-p.half_window..=p.half_window).step_by(p.stride.max(1) as usize).collect()
}

/// One row per working frame of `motion` (three values per image row of `p.input`, the row's X, Y, Z in turn) and the
/// working frames' file positions.
fn frames(motion: &Motion, p: &KnnParams) -> Result<(FeatureMatrix, Vec<f64>), String> {
    match p.input {
        KnnInput::Joints => {
            let f =
                canonical_joints(motion, p.fps, true, &Canonical::ALL).map_err(|e| format!("{}: {e}", motion.name))?;
            Ok((f.base, f.source_frames))
        }
        KnnInput::Network => {
            use crate::labeller::input::{channel_of, network_input, JOINTS};
            let x = network_input(motion)?;
            let mut rows = Vec::with_capacity(x.frames * 3 * JOINTS);
            for t in 0..x.frames {
                for j in 0..JOINTS {
                    rows.extend((0..3).map(|axis| x.at(channel_of(axis, j), t)));
                }
            }
            let base = FeatureMatrix::new(x.frames, 3 * JOINTS, rows).map_err(|e| format!("{}: {e}", motion.name))?;
            Ok((base, x.source_frames))
        }
    }
}

/// The stacked window of every working frame of `motion` and the working frames' file positions (the tests'
/// reference for [`project_windows`]).
#[cfg(test)]
fn windows(motion: &Motion, p: &KnnParams) -> Result<(FeatureMatrix, Vec<f64>), String> {
    let (base, source) = frames(motion, p)?;
    Ok((stack(&base, &offsets(p)), source))
}

/// Per value of a frame (`base`'s columns): the mean and the spread (standard deviation; 1 for a value that never
/// varies) over every frame of `bases` — [`crate::labeller::input::Standardise::fit`] frame-major.
fn value_statistics(bases: &[FeatureMatrix]) -> (Vec<f32>, Vec<f32>) {
    let w = bases.first().map_or(0, FeatureMatrix::dim);
    let (mut sum, mut sq, mut n) = (vec![0f64; w], vec![0f64; w], 0f64);
    for b in bases {
        for i in 0..b.frames() {
            for (j, &v) in b.row(i).iter().enumerate() {
                sum[j] += v as f64;
                sq[j] += v as f64 * v as f64;
            }
        }
        n += b.frames() as f64;
    }
    crate::labeller::input::mean_and_spread(&sum, &sq, n)
}

/// [`project`] of the stacked window at `offsets` of every frame of `base`, without stacking
/// them: `columns` are the axes transposed (`DIMS` values per window value `j`: every axis's
/// weight of it) and each coordinate is summed in the same order, from the same `-0.0` (as
/// `Iterator::sum`), with the same `a · (x − m)` terms as [`project`], so bit for bit the same —
/// but the `DIMS` sums run side by side, four to a vector ([`lanes`]). Coordinates from `kept` on
/// are 0, as [`project`] gives them for a model with fewer axes.
fn project_windows(
    base: &FeatureMatrix,
    offsets: &[i32],
    mean: &[f32],
    columns: &[f32],
    kept: usize,
    go: Go,
) -> Option<Vec<[f32; DIMS]>> {
    let (n, w) = (base.frames(), base.dim());
    let values = (offsets.len() * w).min(mean.len()).min(columns.len() / DIMS);
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        if i % GO_EVERY == 0 && !go(i as f64 / n as f64) {
            return None;
        }
        let mut acc = [F4::splat(-0.0); DIMS / 4];
        for (o, &offset) in offsets.iter().enumerate() {
            let src = (i as i64 + offset as i64).clamp(0, n as i64 - 1) as usize;
            let j0 = o * w;
            let end = values.saturating_sub(j0).min(w);
            let row = &base.row(src)[..end];
            for ((&x, &m), a) in row.iter().zip(&mean[j0..j0 + end]).zip(columns[j0 * DIMS..].chunks_exact(DIMS)) {
                let v = F4::splat(x - m);
                for (s, a) in acc.iter_mut().zip(lanes::quads(a)) {
                    *s = s.add(F4::load(a).mul(v));
                }
            }
        }
        let mut q = [0.0f32; DIMS];
        for (s, out) in acc.iter().zip(q.chunks_exact_mut(4)) {
            s.store(out.try_into().expect("four floats"));
        }
        q[kept.min(DIMS)..].fill(0.0);
        out.push(q);
    }
    Some(out)
}

/// The axes (`DIMS × d`, or fewer) transposed: `d` groups of `DIMS` weights (0 beyond the
/// model's axes), and how many axes there are.
fn transpose(axes: &[f32], d: usize) -> (Vec<f32>, usize) {
    let kept = if d == 0 { 0 } else { (axes.len() / d).min(DIMS) };
    let columns = (0..d).flat_map(|j| (0..DIMS).map(move |k| if k < kept { axes[k * d + j] } else { 0.0 })).collect();
    (columns, kept)
}

/// The state a take's successive queries share: the last one's neighbours seed the next search.
#[derive(Default)]
struct Searching {
    seeds: Vec<u32>,
    found: Vec<Found>,
}

impl Searching {
    /// The next query's seeds: the points found and the ones after them (the next frames of their
    /// takes, most often).
    fn follow(&mut self) {
        self.seeds.clear();
        for f in &self.found {
            self.seeds.extend([f.item, f.item.saturating_add(1)]);
        }
    }
}

fn project(x: &[f32], mean: &[f32], axes: &[f32]) -> [f32; DIMS] {
    let d = mean.len();
    std::array::from_fn(|k| {
        axes.get(k * d..(k + 1) * d).map_or(0.0, |a| a.iter().zip(x).zip(mean).map(|((a, x), m)| a * (x - m)).sum())
    })
}

impl std::fmt::Debug for Knn {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Knn({} frames, {:?})", self.points.len(), self.params)
    }
}

impl Knn {
    /// Fits on `takes` (every working frame with the label of its file frame). With [`KnnInput::Network`] every value of
    /// a window is standardised by the training frames' statistics before the principal axes are found, and the
    /// standardisation is then folded into the mean and the axes: `a · ((x − μ)/σ − m) = (a/σ) · (x − (μ + σ·m))`, so
    /// a query is projected from its raw values, as a joints model's is.
    pub fn fit(takes: &[Labelled], params: KnnParams) -> Result<Knn, String> {
        let mut bases = Vec::with_capacity(takes.len());
        let mut label_rows = Vec::with_capacity(takes.len());
        for t in takes {
            let (base, source) = frames(t.motion, &params)?;
            let kept: Vec<(usize, usize)> = source
                .iter()
                .enumerate()
                .filter_map(|(i, &s)| {
                    let f = (s.round() as usize).min(t.labels.len().saturating_sub(1));
                    t.labels.get(f).map(|&l| (i, l))
                })
                .collect();
            bases.push(base);
            label_rows.push(kept);
        }
        let scale = match params.input {
            KnnInput::Joints => None,
            KnnInput::Network => Some(value_statistics(&bases)),
        };
        let offsets = offsets(&params);
        let mut rows: Vec<f32> = Vec::new();
        let mut raw: Vec<f32> = Vec::new();
        let mut labels = Vec::new();
        let mut dim = 0;
        for (base, kept) in bases.iter().zip(&label_rows) {
            let w = stack(base, &offsets);
            dim = w.dim();
            for &(i, l) in kept {
                match &scale {
                    None => rows.extend_from_slice(w.row(i)),
                    Some((mu, sigma)) => {
                        raw.extend_from_slice(w.row(i));
                        let v = base.dim();
                        rows.extend(w.row(i).iter().enumerate().map(|(j, &x)| (x - mu[j % v]) / sigma[j % v]));
                    }
                }
                labels.push(l);
            }
        }
        let all = FeatureMatrix::new(labels.len(), dim, rows).map_err(|e| format!("k-NN training frames: {e}"))?;
        let (mut mean, mut axes) = principal_axes(&all);
        let points: Vec<[f32; DIMS]> = match &scale {
            None => (0..all.frames()).map(|i| project(all.row(i), &mean, &axes)).collect(),
            Some((mu, sigma)) => {
                let v = bases.first().map_or(1, FeatureMatrix::dim).max(1);
                for (j, m) in mean.iter_mut().enumerate() {
                    *m = mu[j % v] + sigma[j % v] * *m;
                }
                if dim > 0 {
                    for (i, a) in axes.iter_mut().enumerate() {
                        *a /= sigma[(i % dim) % v];
                    }
                }
                // projected from the raw values, as every query is
                raw.chunks_exact(dim.max(1)).map(|x| project(x, &mean, &axes)).collect()
            }
        };
        Ok(Knn::assemble(params, mean, axes, points, labels))
    }

    fn assemble(
        params: KnnParams,
        mean: Vec<f32>,
        axes: Vec<f32>,
        points: Vec<[f32; DIMS]>,
        labels: Vec<usize>,
    ) -> Knn {
        let (columns, axes_kept) = transpose(&axes, mean.len());
        let scan = Scan::new(&points);
        Knn {
            params,
            mean,
            axes,
            points,
            columns,
            axes_kept,
            scan,
            tree: OnceLock::new(),
            labels,
            familiar: Default::default(),
            class_scales: Default::default(),
        }
    }

    fn tree(&self) -> &ImmutableKdTree<f32, u32, DIMS, 32> {
        self.tree.get_or_init(|| ImmutableKdTree::new_from_slice(&self.points))
    }

    /// Every working frame's window of `motion` in the principal coordinates, and the working
    /// frames' file positions.
    fn queries(&self, motion: &Motion) -> Result<(Vec<[f32; DIMS]>, Vec<f64>), String> {
        self.queries_going(motion, &mut |_| true)?.ok_or_else(|| STOPPED.to_string())
    }

    /// [`Knn::queries`], asking `go` (the share of the projection done) every [`GO_EVERY`] frames: `None` once it
    /// answers false.
    fn queries_going(&self, motion: &Motion, go: Go) -> Result<Option<(Vec<[f32; DIMS]>, Vec<f64>)>, String> {
        let p = &self.params;
        let (base, source) = frames(motion, p)?;
        let q = project_windows(&base, &offsets(p), &self.mean, &self.columns, self.axes_kept, go);
        Ok(q.map(|q| (q, source)))
    }

    /// The `k` training points nearest to `q`, nearest first: what the kd-tree's `nearest_n` gives,
    /// in its order. The scan finds the `k + 1` nearest; unless the `k`-th and the `(k+1)`-th
    /// lie within [`TIE_MARGIN`] of each other (which one the tree keeps depends on its order of
    /// visit and, within rounding, on its pruning) or two of the `k` of different labels lie at
    /// the same distance (their order in the tree's answer is its own), those are the tree's `k`
    /// in the tree's order, the votes they cast the same. Otherwise the tree is asked.
    fn nearest_n<'s>(&self, q: &[f32; DIMS], k: usize, s: &'s mut Searching) -> &'s [Found] {
        if k < self.points.len() && q.iter().all(|v| v.is_finite()) {
            self.scan.nearest(&self.points, q, k + 1, &s.seeds, |_| true, &mut s.found);
            s.follow();
            let f = &s.found;
            let clear = f.len() == k + 1
                && f[k].distance.is_finite()
                && f[k].distance > f[k - 1].distance + TIE_MARGIN * f[k - 1].distance
                && f[..k].windows(2).all(|w| {
                    w[0].distance < w[1].distance || self.labels[w[0].item as usize] == self.labels[w[1].item as usize]
                });
            if clear {
                s.found.truncate(k);
                return &s.found;
            }
        }
        let k = std::num::NonZero::new(k).unwrap_or(std::num::NonZero::<usize>::MIN);
        let found = self.tree().nearest_n::<SquaredEuclidean>(q, k);
        s.found.clear();
        s.found.extend(found.iter().map(|n| Found { distance: n.distance, item: n.item }));
        s.follow();
        &s.found
    }

    /// The squared distance from `q` to the nearest training point: what the kd-tree's
    /// `nearest_one` gives (asked when the two nearest lie within [`TIE_MARGIN`] of each other,
    /// see [`Knn::nearest_n`]).
    fn nearest_one(&self, q: &[f32; DIMS], s: &mut Searching) -> f32 {
        if self.points.len() >= 2 && q.iter().all(|v| v.is_finite()) {
            self.scan.nearest(&self.points, q, 2, &s.seeds, |_| true, &mut s.found);
            s.follow();
            let f = &s.found;
            if f.len() == 2
                && f[1].distance.is_finite()
                && (f[1].distance == f[0].distance || f[1].distance > f[0].distance + TIE_MARGIN * f[0].distance)
            {
                return f[0].distance;
            }
        }
        self.tree().nearest_one::<SquaredEuclidean>(q).distance
    }

    /// The fitted labeller as bytes (the payload of its model file): frames `n` and window
    /// values `d` (u32 LE each), the mean (`d` f32), the axes (`DIMS × d` f32), the projected
    /// training frames (`n × DIMS` f32) and their labels (`n` u32).
    pub fn to_bytes(&self) -> Vec<u8> {
        let (n, d) = (self.points.len(), self.mean.len());
        let mut out = Vec::with_capacity(8 + 4 * (d + self.axes.len() + n * (DIMS + 1)));
        out.extend_from_slice(&(n as u32).to_le_bytes());
        out.extend_from_slice(&(d as u32).to_le_bytes());
        // only the leading DIMS axes are used (the fit keeps them all); fewer axes than DIMS
        // (windows of fewer values) are padded with zero axes, which `project` gives 0 for
        let mut axes = self.axes.iter().copied().take(DIMS * d).collect::<Vec<f32>>();
        axes.resize(DIMS * d, 0.0);
        let floats = self.mean.iter().chain(&axes).chain(self.points.iter().flatten());
        for v in floats {
            out.extend_from_slice(&v.to_le_bytes());
        }
        for &l in &self.labels {
            out.extend_from_slice(&(l as u32).to_le_bytes());
        }
        out
    }

    /// Reads [`Knn::to_bytes`] back, checking sizes, values and that labels are below `classes`.
    ///
    /// The sizes are checked in `u64`: the file's counts are u32, and on wasm32 (a 32-bit `usize`)
    /// `n × (DIMS + 1)` words of a frame count near 2³⁰ wrap around, so a crafted header could pass
    /// a `usize` check and make `Vec::with_capacity(n)` panic, trapping the worker. Once the bytes
    /// are known to hold every word, every index below fits in `usize`.
    pub fn from_bytes(bytes: &[u8], params: KnnParams, classes: usize) -> Result<Knn, String> {
        params.check()?;
        let word = |i: usize| -> Result<[u8; 4], String> {
            bytes.get(4 * i..4 * i + 4).and_then(|b| b.try_into().ok()).ok_or_else(|| "k-NN data truncated".to_string())
        };
        let n = u64::from(u32::from_le_bytes(word(0)?));
        let d = u64::from(u32::from_le_bytes(word(1)?));
        let offsets = (2 * params.half_window / params.stride + 1) as u64;
        let expected_d = offsets * 3 * params.input.rows() as u64;
        if d != expected_d {
            return Err(format!("k-NN windows of {d} values, but its parameters make {expected_d}"));
        }
        let dims = DIMS as u64;
        // at most 2 + 33 · 30 651 + 33 · (2³² − 1) words (d ≤ 601 offsets · 51): no overflow in u64
        let words = 2 + d + dims * d + n * dims + n;
        if n == 0 || bytes.len() as u64 != 4 * words {
            return Err(format!("k-NN data of {} bytes, expected {} for {n} frames", bytes.len(), 4 * words));
        }
        // bytes.len() = 4 · words, so n, d and every word index fit in usize
        let (n, d) = (n as usize, d as usize);
        let float = |i: usize| word(i).map(f32::from_le_bytes);
        let mut floats = Vec::with_capacity(d + DIMS * d + n * DIMS);
        for i in 2..2 + d + DIMS * d + n * DIMS {
            let v = float(i)?;
            if !v.is_finite() {
                return Err("k-NN data holds a non-finite value".into());
            }
            floats.push(v);
        }
        let mean = floats[..d].to_vec();
        let axes = floats[d..d + DIMS * d].to_vec();
        let points: Vec<[f32; DIMS]> =
            floats[d + DIMS * d..].chunks_exact(DIMS).map(|c| std::array::from_fn(|k| c[k])).collect();
        let mut labels = Vec::with_capacity(n);
        for i in 0..n {
            let l = u32::from_le_bytes(word(2 + d + DIMS * d + n * DIMS + i)?) as usize;
            if l >= classes {
                return Err(format!("k-NN frame {i} has label {l}, but the model has {classes} classes"));
            }
            labels.push(l);
        }
        Ok(Knn::assemble(params, mean, axes, points, labels))
    }

    /// The window and vote this labeller was fitted with.
    pub fn params(&self) -> KnnParams {
        self.params
    }

    /// Per working frame (at the labeller's rate) of `motion`: each of `classes` classes' share
    /// of the `k` votes, plus 1e-4 · (k − rank) / k for each vote so that a tie goes to the
    /// label whose nearest vote is nearer (shares stay within 1e-4 of the vote counts).
    pub fn probabilities(&self, motion: &Motion, classes: usize) -> Result<Probabilities, String> {
        self.probabilities_at(motion, classes).map(|(p, _)| p)
    }

    /// [`Knn::probabilities`] and the file position of each working frame.
    pub fn probabilities_at(&self, motion: &Motion, classes: usize) -> Result<(Probabilities, Vec<f64>), String> {
        self.vote(motion, classes, &mut |_| true)?.ok_or_else(|| STOPPED.to_string())
    }

    /// [`Knn::probabilities_at`], asking `go` (the share done: the windows' projection its first half, the search
    /// its second) every [`GO_EVERY`] frames: `None` once it answers false.
    pub fn probabilities_going(
        &self,
        motion: &Motion,
        classes: usize,
        go: Go,
    ) -> Result<Option<(Probabilities, Vec<f64>)>, String> {
        self.vote(motion, classes, go)
    }

    fn vote(&self, motion: &Motion, classes: usize, go: Go) -> Result<Option<(Probabilities, Vec<f64>)>, String> {
        let Some((queries, source)) = self.queries_going(motion, &mut |f| go(f / 2.0))? else { return Ok(None) };
        let k = self.params.k.max(1);
        let mut values = vec![0f32; queries.len() * classes];
        let mut searching = Searching::default();
        for (i, q) in queries.iter().enumerate() {
            if i % GO_EVERY == 0 && !go(0.5 + i as f64 / queries.len() as f64 / 2.0) {
                return Ok(None);
            }
            let found = self.nearest_n(q, k, &mut searching);
            let share = 1.0 / found.len().max(1) as f32;
            for (rank, n) in found.iter().enumerate() {
                let l = self.labels[n.item as usize];
                if l < classes {
                    values[i * classes + l] += share + 1e-4 * (k - rank) as f32 / (k * k) as f32;
                }
            }
        }
        Ok(Some((Probabilities { frames: queries.len(), classes, values }, source)))
    }

    /// Per file frame of `motion`: the distance of its window to the nearest training window (in the
    /// principal coordinates) — how unlike anything taught the frame is.
    pub fn nearest_distances(&self, motion: &Motion) -> Result<Vec<f32>, String> {
        self.nearest_distances_going(motion, &mut |_| true)?.ok_or_else(|| STOPPED.to_string())
    }

    /// [`Knn::nearest_distances`], asking `go` as [`Knn::probabilities_going`] does.
    pub fn nearest_distances_going(&self, motion: &Motion, go: Go) -> Result<Option<Vec<f32>>, String> {
        let Some((queries, source)) = self.queries_going(motion, &mut |f| go(f / 2.0))? else { return Ok(None) };
        let mut searching = Searching::default();
        let mut working = Vec::with_capacity(queries.len());
        for (i, q) in queries.iter().enumerate() {
            if i % GO_EVERY == 0 && !go(0.5 + i as f64 / queries.len() as f64 / 2.0) {
                return Ok(None);
            }
            working.push(self.nearest_one(q, &mut searching).sqrt());
        }
        let frames = WorkingFrames { source: &source, file_frames: motion.frames() };
        Ok(Some((0..motion.frames()).map(|f| working[frames.working_frame(f)]).collect()))
    }

    /// Per file frame of `motion`, per class `0..classes`: the distance of its window to the nearest
    /// training window of that class (in the principal coordinates; infinite for a class with no
    /// window). By brute force over the training windows.
    pub fn class_distances(&self, motion: &Motion, classes: usize) -> Result<Vec<Vec<f32>>, String> {
        let (queries, source) = self.queries(motion)?;
        let working: Vec<Vec<f32>> = queries
            .iter()
            .map(|&q| {
                let mut best = vec![f32::INFINITY; classes];
                for (p, &l) in self.points.iter().zip(&self.labels) {
                    if l < classes {
                        let d: f32 = p.iter().zip(&q).map(|(a, b)| (a - b) * (a - b)).sum();
                        best[l] = best[l].min(d);
                    }
                }
                best.iter().map(|d| d.sqrt()).collect()
            })
            .collect();
        let frames = WorkingFrames { source: &source, file_frames: motion.frames() };
        Ok((0..motion.frames()).map(|f| working[frames.working_frame(f)].clone()).collect())
    }

    /// Per class `0..classes`: the median distance from a training window of the class to the
    /// nearest training window *of the same class* at least `gap` working frames away, over at most
    /// `samples` evenly spaced windows of the class (`None` for a class without two such windows):
    /// how tightly a class's own repetitions lie.
    pub fn class_familiar(&self, classes: usize, gap: usize, samples: usize) -> Vec<Option<f32>> {
        (0..classes)
            .map(|c| {
                let own: Vec<usize> = (0..self.points.len()).filter(|&i| self.labels[i] == c).collect();
                let step = own.len().div_ceil(samples.max(1)).max(1);
                let mut d: Vec<f32> = own
                    .iter()
                    .step_by(step)
                    .filter_map(|&i| {
                        own.iter()
                            .filter(|&&j| j.abs_diff(i) > gap)
                            .map(|&j| {
                                self.points[i].iter().zip(&self.points[j]).map(|(a, b)| (a - b) * (a - b)).sum::<f32>()
                            })
                            .min_by(f32::total_cmp)
                            .map(f32::sqrt)
                    })
                    .collect();
                crate::stats::median(&mut d)
            })
            .collect()
    }

    /// The open-set unknown's score ([`crate::labeller::openset`], issue 50): per file frame of `motion` given class
    /// `labels[f]`, the distance of its window to the nearest training window *of that class*, over the class's own
    /// repeat distance ([`Knn::class_familiar`] at the take fit's gap and samples), over the take's median of the
    /// same — how much farther the frame lies from its class's repetitions than the take's frames usually do. NaN for
    /// a frame without a label, infinite for a class the windows do not hold; `None` once `go` answers false.
    /// Measured on folds that leave a class out (`cargo run --release --example eval_knn -- unseen`), the score that
    /// tells a never-taught class best at the fewest taught frames called unknown.
    pub fn voted_ratios_going(
        &self,
        motion: &Motion,
        labels: &[Option<usize>],
        go: Go,
    ) -> Result<Option<Vec<f32>>, String> {
        use crate::labeller::fit::{FAMILIAR_GAP, FAMILIAR_SAMPLES};
        let Some((queries, source)) = self.queries_going(motion, &mut |f| go(f / 2.0))? else { return Ok(None) };
        let classes = self.labels.iter().max().map_or(0, |m| m + 1);
        let scales = self.class_scales.get_or_init(|| self.class_familiar(classes, FAMILIAR_GAP, FAMILIAR_SAMPLES));
        let frames = WorkingFrames { source: &source, file_frames: motion.frames() };
        let (mut found, mut last): (Vec<Found>, Option<(usize, usize, f32)>) = (Vec::new(), None);
        let mut ratios = Vec::with_capacity(motion.frames());
        for f in 0..motion.frames() {
            if f % GO_EVERY == 0 && !go(0.5 + f as f64 / motion.frames().max(1) as f64 / 2.0) {
                return Ok(None);
            }
            let Some(c) = labels.get(f).copied().flatten() else {
                ratios.push(f32::NAN);
                continue;
            };
            let w = frames.working_frame(f);
            let d = match last {
                Some((lw, lc, d)) if (lw, lc) == (w, c) => d,
                _ => {
                    self.scan.nearest(&self.points, &queries[w], 1, &[], |j| self.labels[j as usize] == c, &mut found);
                    let d = found.first().map_or(f32::INFINITY, |x| x.distance.sqrt());
                    last = Some((w, c, d));
                    d
                }
            };
            ratios.push(match scales.get(c).copied().flatten() {
                Some(s) if s > 0.0 => d / s,
                _ => f32::INFINITY,
            });
        }
        let mut finite: Vec<f32> = ratios.iter().copied().filter(|r| r.is_finite()).collect();
        let m = crate::stats::median(&mut finite).filter(|m| *m > 0.0).unwrap_or(1.0);
        Ok(Some(ratios.into_iter().map(|r| r / m).collect()))
    }

    /// How far training windows lie from the training windows at least `gap` working frames away
    /// from them (another repetition of the movement, or another take), for at most `samples`
    /// evenly spaced training windows, sorted: what the nearest distance of a frame of a *new* take
    /// of the taught classes looks like, without holding a take out (a model file does not say
    /// which take a window came from; windows within `gap` of each other overlap and would call
    /// every frame familiar). By brute force, `samples × n` distances; the take fit's measurement
    /// is kept once made.
    pub fn familiar_distances(&self, gap: usize, samples: usize) -> Vec<f32> {
        use crate::labeller::fit::{FAMILIAR_GAP, FAMILIAR_SAMPLES};
        if (gap, samples) == (FAMILIAR_GAP, FAMILIAR_SAMPLES) {
            return self.familiar.get_or_init(|| self.measure_familiar(gap, samples)).clone();
        }
        self.measure_familiar(gap, samples)
    }

    /// The scan's nearest window at least `gap` away: the smallest of the same sums (a minimum does
    /// not depend on the order it is taken in); by brute force when none is finite.
    fn measure_familiar(&self, gap: usize, samples: usize) -> Vec<f32> {
        let n = self.points.len();
        let step = n.div_ceil(samples.max(1)).max(1);
        let mut found = Vec::new();
        let mut out: Vec<f32> = (0..n)
            .step_by(step)
            .filter_map(|i| {
                let p = &self.points[i];
                let seeds = [i + gap + 1, i.wrapping_sub(gap + 1)].map(|j| j.min(u32::MAX as usize) as u32);
                self.scan.nearest(&self.points, p, 1, &seeds, |j| (j as usize).abs_diff(i) > gap, &mut found);
                if let Some(f) = found.first() {
                    return Some(f.distance.sqrt());
                }
                (0..n)
                    .filter(|&j| j.abs_diff(i) > gap)
                    .map(|j| p.iter().zip(&self.points[j]).map(|(a, b)| (a - b) * (a - b)).sum::<f32>())
                    .min_by(f32::total_cmp)
                    .map(f32::sqrt)
            })
            .collect();
        out.sort_by(f32::total_cmp);
        out
    }

    /// Per file frame of `motion`: the voted label and the share of the `k` votes it won.
    pub fn predict(&self, motion: &Motion) -> Result<Vec<(usize, f32)>, String> {
        let classes = self.labels.iter().max().map_or(1, |m| m + 1);
        let (p, source) = self.probabilities_at(motion, classes)?;
        let frames = WorkingFrames { source: &source, file_frames: motion.frames() };
        Ok((0..motion.frames())
            .map(|f| {
                let (c, share) = p.best(frames.working_frame(f));
                (c, (share * self.params.k as f32).round() / self.params.k as f32)
            })
            .collect())
    }
}

/// The k-NN's windows are what a take's fit is measured against ([`crate::labeller::fit::Windows`]).
impl crate::labeller::fit::Windows for Knn {
    fn nearest_distances(&self, motion: &Motion, go: Go) -> Result<Option<Vec<f32>>, String> {
        Knn::nearest_distances_going(self, motion, go)
    }
    fn familiar_distances(&self, gap: usize, samples: usize) -> Vec<f32> {
        Knn::familiar_distances(self, gap, samples)
    }
    fn voted_ratios(&self, motion: &Motion, labels: &[Option<usize>], go: Go) -> Result<Option<Vec<f32>>, String> {
        Knn::voted_ratios_going(self, motion, labels, go)
    }
    fn search_ops(&self) -> (f64, f64) {
        let samples = crate::labeller::fit::FAMILIAR_SAMPLES.min(self.points.len()) as f64;
        (self.search_ops_per_frame(), samples * self.scan_ops())
    }
}

impl Knn {
    /// Multiply-adds of a scan of every training window, the most one query costs ([`search`] prunes most of them).
    fn scan_ops(&self) -> f64 {
        (self.points.len() * DIMS) as f64
    }

    /// Multiply-adds of one working frame's query, at most: its window projected onto the axes (window values ×
    /// [`DIMS`]; a window of ±300 frames every frame is 30,651 values, 46× the default's) and the training windows
    /// scanned.
    pub fn search_ops_per_frame(&self) -> f64 {
        (self.mean.len() * DIMS) as f64 + self.scan_ops()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh;

    fn motion(name: &str, text: &str) -> Motion {
        Motion::from_bvh(name, &bvh::parse(text).unwrap()).unwrap()
    }

    #[test]
    fn a_take_is_labelled_as_its_copy_in_other_units_was_taught() {
        let taught = motion("131_01.bvh", include_str!("../../../tests/fixtures/131_01.bvh"));
        // the same take written in metres: the reference-body scaling makes it the same frames
        let asked = motion("metres.bvh", include_str!("../../../tests/fixtures/cmu_131_01_scaled_meters.bvh"));
        let half = taught.frames() / 2;
        let labels: Vec<usize> = (0..taught.frames()).map(|f| usize::from(f >= half)).collect();
        let knn = Knn::fit(&[Labelled { motion: &taught, labels: &labels }], KnnParams::default()).unwrap();
        let predicted = knn.predict(&asked).unwrap();
        assert_eq!(predicted.len(), asked.frames());
        let right = predicted.iter().zip(&labels).filter(|(p, &l)| p.0 == l).count() as f64 / labels.len() as f64;
        assert!(right > 0.95, "{right}");
        // far from the change of label, all five votes agree
        assert_eq!(predicted[50].1, 1.0);
        // written and read back (its model file's payload), it votes the same
        let back = Knn::from_bytes(&knn.to_bytes(), knn.params(), 2).unwrap();
        assert_eq!(back.predict(&asked).unwrap(), predicted);
        assert!(Knn::from_bytes(&knn.to_bytes(), knn.params(), 1).unwrap_err().contains("label 1"));
        assert!(Knn::from_bytes(&knn.to_bytes()[..100], knn.params(), 2).is_err());
        // a take without the canonical joints is refused by name
        let stick = motion("stick.bvh", include_str!("../../../tests/fixtures/bvh_anim_test_simple.bvh"));
        assert!(knn.predict(&stick).unwrap_err().starts_with("stick.bvh:"));
        // the copy lies on the taught windows; a walk of another subject lies far from them
        let near = knn.nearest_distances(&asked).unwrap();
        assert_eq!(near.len(), asked.frames());
        let walk = motion("02_01.bvh", include_str!("../../../tests/fixtures/02_01.bvh"));
        let far = knn.nearest_distances(&walk).unwrap();
        let median = |v: &[f32]| {
            let mut v = v.to_vec();
            v.sort_by(f32::total_cmp);
            v[v.len() / 2]
        };
        assert!(median(&near) < 1e-2 * median(&far).max(1e-6) + 1e-3, "{} vs {}", median(&near), median(&far));
        assert!(median(&far) > 0.0);
    }

    /// `motion` with its whole body carried along world +Z at `speed` file units a second (the poses unchanged).
    fn gliding(motion: &Motion, speed: f32) -> Motion {
        let mut m = motion.clone();
        let joints = m.joints();
        for (i, p) in m.positions.iter_mut().enumerate() {
            p.z += speed * (i / joints) as f32 / m.fps as f32;
        }
        m
    }

    /// With DT-FCN's input ([`KnnInput::Network`]) the k-NN reads the root's motion: a take and its copy carried along
    /// the floor have the same hip-relative poses, so the joints alone cannot tell them apart (about half right) and
    /// the root's velocity row can (most). The standardisation folded into the mean and axes projects a query
    /// from its raw values as the training windows were; the model file lists the network's rows and reads back the
    /// same votes.
    #[test]
    fn the_network_input_tells_a_gliding_copy_from_the_take() {
        // exercises in place (13_30, the bundled sample): jumping jacks, twists, knee raises
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/www/sample.bvh");
        let take = motion("13_30.bvh", &std::fs::read_to_string(path).unwrap());
        let (a, b) = (take.slice(0, 700), take.slice(700, 1400));
        // taught: the first half as it is (0), then gliding (1); asked: the second half gliding, then as it is
        let taught = Motion::concatenate(&[a.clone(), gliding(&a, 60.0)], 2 * a.frames()).unwrap();
        let asked = Motion::concatenate(&[gliding(&b, 60.0), b.clone()], 2 * b.frames()).unwrap();
        let taught_labels: Vec<usize> = (0..taught.frames()).map(|f| usize::from(f >= a.frames())).collect();
        let asked_labels: Vec<usize> = (0..asked.frames()).map(|f| usize::from(f < b.frames())).collect();
        let right = |input| {
            let params = KnnParams { input, ..KnnParams::default() };
            let knn = Knn::fit(&[Labelled { motion: &taught, labels: &taught_labels }], params).unwrap();
            let predicted = knn.predict(&asked).unwrap();
            let back = Knn::from_bytes(&knn.to_bytes(), params, 2).unwrap();
            assert_eq!(back.predict(&asked).unwrap(), predicted, "{input:?}: read back, the same votes");
            // the training windows lie where the model projects them: each one's nearest training window is itself
            let near = knn.nearest_distances(&taught).unwrap();
            assert!(near.iter().all(|&d| d < 1e-2), "{input:?}: {:?}", near.iter().copied().fold(0.0, f32::max));
            predicted.iter().zip(&asked_labels).filter(|(p, &l)| p.0 == l).count() as f64 / asked_labels.len() as f64
        };
        let (joints, network) = (right(KnnInput::Joints), right(KnnInput::Network));
        // measured 0.815 and 0.497: standardised, the root's rows are 4 of 54 channels, each as heavy as a joint's, and
        // the 32 principal axes do not always keep the glide's — it wins most frames, not all
        assert!(network > 0.75, "with the root's rows: {network}");
        assert!(joints < 0.6, "the joints alone: {joints}");
        // a joints model's window is 17 rows, a network one's 18
        let w = |input| {
            let params = KnnParams { input, ..KnnParams::default() };
            Knn::fit(&[Labelled { motion: &taught, labels: &taught_labels }], params).unwrap().mean.len()
        };
        assert_eq!((w(KnnInput::Joints), w(KnnInput::Network)), (13 * 51, 13 * 54));
        assert!(Knn::from_bytes(
            &Knn::fit(&[Labelled { motion: &taught, labels: &taught_labels }], KnnParams::default())
                .unwrap()
                .to_bytes(),
            KnnParams { input: KnnInput::Network, ..KnnParams::default() },
            2
        )
        .unwrap_err()
        .contains("663 values"));
    }

    #[test]
    fn each_class_has_its_own_nearest_window_and_repeat_distance() {
        let taught = motion("131_01.bvh", include_str!("../../../tests/fixtures/131_01.bvh"));
        let half = taught.frames() / 2;
        let labels: Vec<usize> = (0..taught.frames()).map(|f| usize::from(f >= half)).collect();
        let knn = Knn::fit(&[Labelled { motion: &taught, labels: &labels }], KnnParams::default()).unwrap();
        // three classes asked, the third never taught
        let by_class = knn.class_distances(&taught, 3).unwrap();
        let nearest = knn.nearest_distances(&taught).unwrap();
        assert_eq!(by_class.len(), taught.frames());
        for (f, d) in by_class.iter().enumerate() {
            assert!(d[2].is_infinite(), "frame {f}: no window of class 2, {d:?}");
            // the nearest window of any class is the nearest of the nearest per class
            assert!(
                (d[0].min(d[1]) - nearest[f]).abs() <= 1e-3 * nearest[f].max(1.0),
                "frame {f}: {d:?} vs {}",
                nearest[f]
            );
        }
        // a taught frame lies on a window of its own class, away from the frames of the other
        let (early, late) = (half / 4, half + half / 2);
        assert!(by_class[early][0] < 1e-3 && by_class[early][1] > 0.1, "{:?}", by_class[early]);
        assert!(by_class[late][1] < 1e-3 && by_class[late][0] > 0.1, "{:?}", by_class[late]);
        // each class's own repeat distance; none for a class without windows
        let own = knn.class_familiar(3, 30, 200);
        assert!(own[0].is_some_and(|d| d > 0.0) && own[1].is_some_and(|d| d > 0.0), "{own:?}");
        assert_eq!(own[2], None);
        // one class holding every window: the median of the model's familiar distances
        let one =
            Knn::fit(&[Labelled { motion: &taught, labels: &vec![0; taught.frames()] }], KnnParams::default()).unwrap();
        let mut all = one.familiar_distances(30, 200);
        assert_eq!(one.class_familiar(1, 30, 200)[0], crate::stats::median(&mut all));
    }

    /// The labeller as it was before the scan: every window stacked and projected, every query
    /// answered by the kd-tree.
    struct Reference<'a>(&'a Knn);

    impl Reference<'_> {
        fn projected(&self, motion: &Motion) -> Vec<[f32; DIMS]> {
            let (w, _) = windows(motion, &self.0.params).unwrap();
            (0..w.frames()).map(|i| project(w.row(i), &self.0.mean, &self.0.axes)).collect()
        }

        fn values(&self, motion: &Motion, classes: usize) -> Vec<f32> {
            let knn = self.0;
            let k = knn.params.k.max(1);
            let queries = self.projected(motion);
            let mut values = vec![0f32; queries.len() * classes];
            for (i, q) in queries.iter().enumerate() {
                let found = knn.tree().nearest_n::<SquaredEuclidean>(q, std::num::NonZero::new(k).unwrap());
                let share = 1.0 / found.len().max(1) as f32;
                for (rank, n) in found.iter().enumerate() {
                    let l = knn.labels[n.item as usize];
                    if l < classes {
                        values[i * classes + l] += share + 1e-4 * (k - rank) as f32 / (k * k) as f32;
                    }
                }
            }
            values
        }

        fn nearest(&self, motion: &Motion) -> Vec<f32> {
            self.projected(motion)
                .iter()
                .map(|q| self.0.tree().nearest_one::<SquaredEuclidean>(q).distance.sqrt())
                .collect()
        }

        fn familiar(&self, gap: usize, samples: usize) -> Vec<f32> {
            let points = &self.0.points;
            let n = points.len();
            let step = n.div_ceil(samples.max(1)).max(1);
            let mut out: Vec<f32> = (0..n)
                .step_by(step)
                .filter_map(|i| {
                    (0..n)
                        .filter(|&j| j.abs_diff(i) > gap)
                        .map(|j| points[i].iter().zip(&points[j]).map(|(a, b)| (a - b) * (a - b)).sum::<f32>())
                        .min_by(f32::total_cmp)
                        .map(f32::sqrt)
                })
                .collect();
            out.sort_by(f32::total_cmp);
            out
        }
    }

    fn bits(v: &[f32]) -> Vec<u32> {
        v.iter().map(|x| x.to_bits()).collect()
    }

    /// Votes, nearest distances and familiar distances bit for bit as the kd-tree gave them.
    fn same_as_the_tree(knn: &Knn, motion: &Motion, classes: usize, what: &str) {
        let reference = Reference(knn);
        let (queries, _) = knn.queries(motion).unwrap();
        let projected = reference.projected(motion);
        assert_eq!(queries.len(), projected.len(), "{what}");
        for (a, b) in queries.iter().zip(&projected) {
            assert_eq!(bits(a), bits(b), "{what}: projection");
        }
        let p = knn.probabilities(motion, classes).unwrap();
        assert_eq!(bits(&p.values), bits(&reference.values(motion, classes)), "{what}: votes");
        let near = knn.nearest_distances(motion).unwrap();
        let (w, source) = windows(motion, &knn.params).unwrap();
        let frames = WorkingFrames { source: &source, file_frames: motion.frames() };
        let old = reference.nearest(motion);
        assert_eq!(w.frames(), old.len());
        let old: Vec<f32> = (0..motion.frames()).map(|f| old[frames.working_frame(f)]).collect();
        assert_eq!(bits(&near), bits(&old), "{what}: nearest distances");
    }

    fn fixture(name: &str) -> Motion {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures").join(name);
        crate::load::load_path(&path).unwrap().motion
    }

    #[cfg(not(target_arch = "wasm32"))]
    #[test]
    fn the_scan_finds_the_trees_neighbours_for_the_shipped_models() {
        let takes: Vec<Motion> =
            ["13_31.bvh", "86_01.bvh", "131_03.bvh", "02_01.bvh", "35_01.bvh", "assimp_Boxing_Toes_100fps.bvh"]
                .iter()
                .map(|n| fixture(n))
                .collect();
        for name in ["exercises", "cmu-actions", "locomotion"] {
            let file = format!("knn-{name}.model");
            let bytes = crate::method::ModelStore::default().shipped_bytes(&file).unwrap().to_vec();
            let model = crate::labeller::model::Model::from_bytes(&bytes, &file, &[&method::KNN]).unwrap();
            let knn = model::knn_of(&model).unwrap_or_else(|| panic!("{name}: not a k-NN model"));
            let classes = model.header.classes.len();
            for take in &takes {
                same_as_the_tree(knn, take, classes, &format!("{name} on {}", take.name));
            }
            let reference = Reference(knn);
            for (gap, samples) in [(60, 400), (30, 1000), (0, 50)] {
                assert_eq!(
                    bits(&knn.measure_familiar(gap, samples)),
                    bits(&reference.familiar(gap, samples)),
                    "{name}: familiar distances at {gap}, {samples}"
                );
            }
        }
    }

    /// The open-set score: per frame, its window's distance to the nearest training window of the class it is given,
    /// over the class's repeat distance, over the take's median of the same. A take given its own labels lies on its
    /// class's windows (0 on the frames a training window was taken at, and a median far below the same frames given
    /// the other class); an unlabelled frame is NaN, a class without windows infinite.
    #[test]
    fn the_voted_ratio_measures_a_frame_against_its_own_class() {
        let taught = fixture("131_01.bvh");
        let half = taught.frames() / 2;
        let split: Vec<usize> = (0..taught.frames()).map(|f| usize::from(f >= half)).collect();
        let knn = Knn::fit(&[Labelled { motion: &taught, labels: &split }], KnnParams::default()).unwrap();
        let scales = knn.class_familiar(2, crate::labeller::fit::FAMILIAR_GAP, crate::labeller::fit::FAMILIAR_SAMPLES);
        let by_class = knn.class_distances(&taught, 2).unwrap();
        let mut medians = Vec::new();
        for given in [0, 1] {
            // given = 0: the take's own labels; 1: the other half's
            let class = |f: usize| if given == 0 { split[f] } else { 1 - split[f] };
            let labels: Vec<Option<usize>> = (0..taught.frames()).map(|f| Some(class(f))).collect();
            let ratios = knn.voted_ratios_going(&taught, &labels, &mut |_| true).unwrap().unwrap();
            assert_eq!(ratios.len(), taught.frames());
            let raw: Vec<f32> =
                (0..taught.frames()).map(|f| by_class[f][class(f)] / scales[class(f)].unwrap()).collect();
            let median = crate::stats::median(&mut raw.clone()).unwrap();
            for (f, (a, r)) in ratios.iter().zip(&raw).enumerate() {
                let want = r / if median > 0.0 { median } else { 1.0 };
                assert!((a - want).abs() <= 1e-4 * (1.0 + a.abs()), "given {given}, frame {f}: {a} against {want}");
            }
            if given == 0 {
                assert!(ratios.iter().filter(|&&r| r == 0.0).count() >= taught.frames() / 10);
            }
            medians.push(median);
        }
        assert!(medians[1] > 3.0 * medians[0], "{medians:?}");
        // unlabelled, and a class the windows do not hold
        let odd: Vec<Option<usize>> = (0..taught.frames()).map(|f| if f % 2 == 0 { None } else { Some(7) }).collect();
        let odd = knn.voted_ratios_going(&taught, &odd, &mut |_| true).unwrap().unwrap();
        assert!(odd.iter().step_by(2).all(|r| r.is_nan()) && odd.iter().skip(1).step_by(2).all(|r| r.is_infinite()));
        // a stop is honoured
        let own: Vec<Option<usize>> = split.iter().map(|&l| Some(l)).collect();
        assert!(knn.voted_ratios_going(&taught, &own, &mut |f| f < 0.6).unwrap().is_none());
    }

    #[cfg(not(target_arch = "wasm32"))]
    #[test]
    fn tied_neighbours_are_the_trees_in_its_order() {
        // every training window twice, once of each label: every query's neighbours tie, and
        // the tree (asked then) orders them its own way
        let taught = fixture("131_01.bvh");
        let (zeros, ones) = (vec![0; taught.frames()], vec![1; taught.frames()]);
        let half = taught.frames() / 2;
        let split: Vec<usize> = (0..taught.frames()).map(|f| usize::from(f >= half)).collect();
        for k in [1, 2, 5, 6] {
            let params = KnnParams { k, ..KnnParams::default() };
            let twice = Knn::fit(
                &[Labelled { motion: &taught, labels: &zeros }, Labelled { motion: &taught, labels: &ones }],
                params,
            )
            .unwrap();
            same_as_the_tree(&twice, &taught, 2, &format!("twice, k {k}"));
            same_as_the_tree(&twice, &fixture("131_03.bvh"), 2, &format!("twice on another take, k {k}"));
            // and the same take taught once, asked in other units (near, not equal, windows)
            let once = Knn::fit(&[Labelled { motion: &taught, labels: &split }], params).unwrap();
            same_as_the_tree(&once, &fixture("cmu_131_01_scaled_meters.bvh"), 3, &format!("metres, k {k}"));
            let reference = Reference(&once);
            assert_eq!(bits(&once.measure_familiar(30, 200)), bits(&reference.familiar(30, 200)));
        }
        // fewer training windows than k: the tree answers with all of them
        let short = fixture("pybvh_bvh_test1.bvh");
        if let Ok(few) = Knn::fit(
            &[Labelled { motion: &short, labels: &vec![0; short.frames()] }],
            KnnParams { k: 100, ..KnnParams::default() },
        ) {
            same_as_the_tree(&few, &short, 1, "k above the windows");
        }
    }

    #[test]
    fn the_scan_skips_nothing_that_could_enter() {
        // random points in clusters: the scan's k nearest are a brute force's, for many k, with
        // and without seeds, with a filter
        let mut rng = crate::stats::Rng::new(11);
        let points: Vec<[f32; DIMS]> = (0..1000)
            .map(|i| {
                let c = (i % 7) as f32;
                std::array::from_fn(|k| c * (k as f32 * 0.1).cos() + rng.next_f32() * 0.3 / (1.0 + k as f32))
            })
            .collect();
        let scan = Scan::new(&points);
        let mut found = Vec::new();
        for (t, q) in points.iter().step_by(37).enumerate() {
            let q: [f32; DIMS] = std::array::from_fn(|k| q[k] + 0.01 * (t as f32 + k as f32).sin());
            let mut all: Vec<(f32, u32)> =
                points.iter().enumerate().map(|(j, p)| (search::distance(p, &q), j as u32)).collect();
            all.sort_by(|a, b| a.0.total_cmp(&b.0));
            for count in [1, 2, 6, 40] {
                for seeds in [vec![], vec![0, 999, 5, 5, 4000]] {
                    scan.nearest(&points, &q, count, &seeds, |_| true, &mut found);
                    let got: Vec<f32> = found.iter().map(|f| f.distance).collect();
                    let want: Vec<f32> = all[..count].iter().map(|a| a.0).collect();
                    assert_eq!(got, want, "query {t}, count {count}");
                    assert!(found.iter().all(|f| search::distance(&points[f.item as usize], &q) == f.distance));
                }
                scan.nearest(&points, &q, count, &[], |j| j % 3 == 0, &mut found);
                let want: Vec<f32> = all.iter().filter(|a| a.1 % 3 == 0).take(count).map(|a| a.0).collect();
                assert_eq!(found.iter().map(|f| f.distance).collect::<Vec<_>>(), want);
            }
        }
    }

    /// A payload of the default window claiming `n` frames but holding the words of one.
    fn claiming(n: u32) -> Vec<u8> {
        let p = KnnParams::default();
        let d = (2 * p.half_window / p.stride + 1) as usize * 3 * Canonical::ALL.len();
        let mut bytes = Vec::new();
        bytes.extend_from_slice(&n.to_le_bytes());
        bytes.extend_from_slice(&(d as u32).to_le_bytes());
        bytes.resize(4 * (2 + d + DIMS * d + DIMS + 1), 0);
        bytes
    }

    #[test]
    fn frame_counts_whose_sizes_wrap_around_in_32_bits_are_refused() {
        // 4 · (2 + 33 d + 33 n) bytes for n frames: n = 2³⁰ + 1 wraps around to one frame's size in
        // 32-bit arithmetic (tests/wasm.rs runs this on wasm32, where it trapped); n = 2³² − 1
        // makes every product of the check overflow 32 bits
        let p = KnnParams::default();
        assert_eq!(Knn::from_bytes(&claiming(1), p, 2).map(|k| k.points.len()), Ok(1));
        for n in [(1u32 << 30) + 1, u32::MAX, 1 << 27] {
            let e = Knn::from_bytes(&claiming(n), p, 2).unwrap_err();
            assert!(e.starts_with("k-NN data of ") && e.contains(&format!("for {n} frames")), "{n}: {e}");
        }
    }
}
