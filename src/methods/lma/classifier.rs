//! The LMA Effort classifier and its boundary-shifted family (Bouchard & Badler §4.1–4.2).
//!
//! One classifier is four small networks, one per Effort factor, each reading its own salient
//! features of the pool ([`super::features::Pool`]), standardised and rotated onto their
//! principal components to 95 % of the variance, through a sigmoid hidden layer to three sigmoid
//! outputs (indulging, neutral, condensing) — 12 outputs in all.
//!
//! The family: "one per start shift i and end shift j in [−s, s]", each trained on segments whose
//! boundaries were shifted by (i, j) while keeping their labels. At a candidate segment
//! `start..=end`, classifier (i, j) reads the segment `start + i ..= end + j`, the input it was
//! trained to expect around a true segment, so where the candidate *is* a segment they agree.
//! Their disagreement is the mean deviance (eq. 1–2): `d = 1/(2s+1)² Σ |m − x_ij|` with
//! `m` the mean output (Euclidean norm of the 12-vector).
//!
//! The four factors' feature selections and principal axes are shared by the whole family
//! (chosen once, on the unshifted segments), so a segment is projected once and then read by all
//! (2s+1)² networks of a factor — which is what makes the exhaustive search affordable.

use std::collections::HashMap;

use serde::{Deserialize, Serialize};

use super::effort::Factor;
use super::features::{Plan, Pool};
use super::network::Net;
use crate::segment::Effort;

/// One Effort factor's networks and the input they read.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FactorModel {
    /// The selected pool features (indices into the pool), most salient first.
    pub selected: Vec<u16>,
    /// Mean and standard deviation of each selected feature over the training segments.
    pub mean: Vec<f32>,
    pub scale: Vec<f32>,
    /// `components × selected` principal axes (rows) of the standardised features.
    pub projection: Vec<f32>,
    pub components: usize,
    /// One network per shift, index `(i + s)·(2s + 1) + (j + s)`.
    pub nets: Vec<Net>,
    /// The unshifted network's error on the validation segments (the paper's rule), the segments
    /// that chose its stopping epoch and its restart.
    pub validation_error: f32,
    /// Its error on the test segments, held out from every choice (absent in families trained
    /// before they were held out).
    #[serde(default)]
    pub test_error: Option<f32>,
}

impl FactorModel {
    /// This factor's fields against each other and the pool (`shifts`: the family's classifier count).
    fn validate(&self, shifts: usize) -> Result<(), String> {
        let n = self.selected.len();
        if n == 0 || n > super::features::POOL_SIZE {
            return Err(format!("selected: {n} features, expected 1 to {}", super::features::POOL_SIZE));
        }
        if let Some(k) = self.selected.iter().find(|&&k| k as usize >= super::features::POOL_SIZE) {
            return Err(format!("selected: feature {k}, expected below {}", super::features::POOL_SIZE));
        }
        if self.mean.len() != n || self.scale.len() != n {
            return Err(format!(
                "mean and scale: {} and {} values, expected one per selected feature ({n})",
                self.mean.len(),
                self.scale.len()
            ));
        }
        if let Some(v) = self.mean.iter().chain(&self.scale).find(|v| !v.is_finite()) {
            return Err(format!("mean and scale: {v}, expected finite numbers"));
        }
        if let Some(v) = self.scale.iter().find(|&&v| v <= 0.0) {
            return Err(format!("scale: {v}, expected above 0"));
        }
        if !(1..=n).contains(&self.components) {
            return Err(format!("components: {}, expected 1 to its {n} selected features", self.components));
        }
        if self.projection.len() != self.components * n {
            return Err(format!(
                "projection: {} values, expected components × selected = {} × {n}",
                self.projection.len(),
                self.components
            ));
        }
        if self.projection.iter().any(|v| !v.is_finite()) {
            return Err("projection: expected finite numbers".into());
        }
        if self.nets.len() != shifts {
            return Err(format!(
                "nets: {} networks, expected one per classifier ((2·max_shift + 1)² = {shifts})",
                self.nets.len()
            ));
        }
        for (i, net) in self.nets.iter().enumerate() {
            let shape = |what: &str, len: usize, want: usize| {
                (len != want).then(|| format!("nets[{i}].{what}: {len} values, expected {want}"))
            };
            if net.inputs != self.components || net.outputs != 3 || !(1..=MAX_HIDDEN).contains(&net.hidden) {
                return Err(format!(
                    "nets[{i}]: {} inputs, {} hidden, {} outputs; expected {} inputs (its components), 1 to {MAX_HIDDEN} \
                     hidden, 3 outputs",
                    net.inputs, net.hidden, net.outputs, self.components
                ));
            }
            let wrong = shape("w1", net.w1.len(), net.hidden * net.inputs)
                .or_else(|| shape("b1", net.b1.len(), net.hidden))
                .or_else(|| shape("w2", net.w2.len(), net.outputs * net.hidden))
                .or_else(|| shape("b2", net.b2.len(), net.outputs));
            if let Some(why) = wrong {
                return Err(why);
            }
            if net.w1.iter().chain(&net.b1).chain(&net.w2).chain(&net.b2).any(|v| !v.is_finite()) {
                return Err(format!("nets[{i}]: expected finite weights"));
            }
        }
        Ok(())
    }

    /// The projected input of the segment `start..=end` into `z` (`components` values), one pool
    /// feature at a time; `x` is scratch of `selected.len()`. The reference [`Projector`] is
    /// tested against; the searches use the projector.
    pub fn project(&self, pool: &Pool, start: usize, end: usize, x: &mut [f32], z: &mut [f32]) {
        pool.features(&self.selected, start, end, x);
        for ((v, m), s) in x.iter_mut().zip(&self.mean).zip(&self.scale) {
            *v = (*v - m) / s;
        }
        let n = self.selected.len();
        for (c, zc) in z.iter_mut().enumerate().take(self.components) {
            *zc = self.projection[c * n..(c + 1) * n].iter().zip(x.iter()).map(|(a, b)| a * b).sum();
        }
    }
}

/// Components the projector's rotation adds at once: four 128-bit vectors of f32, independent
/// running sums (one would wait on the previous addition's latency).
/// The frame rates a family may be trained at (the shipped one: 30 Hz).
pub const MIN_FPS: f64 = 5.0;
pub const MAX_FPS: f64 = 240.0;
/// The longest training segment a family may record, in its frames.
pub const MAX_LEN: usize = 100_000;
/// The largest boundary shift: `(2s + 1)²` classifiers assess every candidate (the shipped family: s = 5, 121).
pub const MAX_SHIFT: usize = 10;
/// The widest hidden layer of a classifier (training tries up to 10 units).
pub const MAX_HIDDEN: usize = 1000;
/// The longest `origin` text.
pub const MAX_ORIGIN_CHARS: usize = 2000;

const LANES: usize = 16;

/// Segments [`Projector::project_lanes`] projects side by side: their features in eight pairs of
/// f64 and their rotation in four vectors of f32 (as [`LANES`]), one segment per lane.
pub const SEGMENTS: usize = 16;

/// The family's projected inputs of any segment, fast: one [`Plan`] of every factor's selected
/// features (a feature two factors read is computed once; each series' range sums are read once
/// per segment), and scratch buffers reused from segment to segment. Made once per search.
pub struct Projector<'m> {
    model: &'m EffortModel,
    plan: Plan,
    /// Per factor, the plan's slot of each selected feature.
    slots: Vec<Vec<usize>>,
    /// Per factor, its principal axes with the features' scales folded in (`axis / scale`), so a
    /// feature is only centred before the rotation; in blocks of [`LANES`] components, each block
    /// per selected feature its weights on them (the rotation then adds whole vectors).
    axes: Vec<Vec<f32>>,
    /// Per factor, the same folded axes unpadded, one row of `selected` weights per component (the
    /// rotation of [`SEGMENTS`] segments at once).
    rows: Vec<Vec<f32>>,
    /// Scratch of the padded components of the widest factor.
    acc: Vec<f32>,
    values: Vec<[f64; 1]>,
    x: Vec<f32>,
    /// The features and centred inputs of [`SEGMENTS`] segments.
    lanes: Vec<[f64; SEGMENTS]>,
    xs: Vec<[f32; SEGMENTS]>,
    hidden: Vec<f32>,
}

impl<'m> Projector<'m> {
    pub fn new(model: &'m EffortModel) -> Projector<'m> {
        let plan = Plan::new(model.factors.iter().flat_map(|f| f.selected.iter().copied()));
        let slots = model
            .factors
            .iter()
            .map(|f| f.selected.iter().map(|&k| plan.slot(k).expect("the plan holds every selected feature")).collect())
            .collect();
        let padded = |f: &FactorModel| f.components.div_ceil(LANES) * LANES;
        let axes = model
            .factors
            .iter()
            .map(|f| {
                let (n, width) = (f.selected.len(), padded(f));
                let mut t = vec![0.0; n * width];
                for c in 0..f.components {
                    for k in 0..n {
                        t[((c / LANES) * n + k) * LANES + c % LANES] = f.projection[c * n + k] / f.scale[k];
                    }
                }
                t
            })
            .collect();
        let rows = model
            .factors
            .iter()
            .map(|f| {
                let n = f.selected.len();
                (0..f.components * n).map(|i| f.projection[i] / f.scale[i % n]).collect()
            })
            .collect();
        let acc = vec![0.0; model.factors.iter().map(padded).max().unwrap_or(0)];
        let widest = model.factors.iter().map(|f| f.selected.len()).max().unwrap_or(0);
        let hidden = model.factors.iter().flat_map(|f| f.nets.iter().map(|n| n.hidden)).max().unwrap_or(0);
        Projector {
            model,
            values: vec![[0.0]; plan.len()],
            lanes: vec![[0.0; SEGMENTS]; plan.len()],
            plan,
            slots,
            axes,
            rows,
            acc,
            x: vec![0.0; widest],
            xs: vec![[0.0; SEGMENTS]; widest],
            hidden: vec![0.0; hidden],
        }
    }

    /// The four factors' projected inputs of `start..=end`, concatenated into `z`
    /// ([`EffortModel::width`]): [`EffortModel::project`]'s values up to float rounding.
    pub fn project(&mut self, pool: &Pool, start: usize, end: usize, z: &mut [f32]) {
        pool.fill(&self.plan, [(start, end)], &mut self.values);
        let mut at = 0;
        for ((f, slots), axes) in self.model.factors.iter().zip(&self.slots).zip(&self.axes) {
            let n = slots.len();
            let x = &mut self.x[..n];
            for ((v, &slot), m) in x.iter_mut().zip(slots).zip(&f.mean) {
                *v = self.values[slot][0] as f32 - m;
            }
            let width = axes.len() / n.max(1);
            for (chunk, out) in axes.chunks_exact((n * LANES).max(1)).zip(self.acc[..width].chunks_exact_mut(LANES)) {
                let mut acc = [[0.0f32; 4]; LANES / 4];
                for (w, &v) in chunk.chunks_exact(LANES).zip(x.iter()) {
                    for (a, w) in acc.iter_mut().zip(w.chunks_exact(4)) {
                        for k in 0..4 {
                            a[k] += w[k] * v;
                        }
                    }
                }
                out.copy_from_slice(acc.as_flattened());
            }
            z[at..at + f.components].copy_from_slice(&self.acc[..f.components]);
            at += f.components;
        }
    }

    /// [`Projector::project`] of [`SEGMENTS`] segments at once into `z`, one row of
    /// [`EffortModel::width`] per segment: their features from one pass over the plan, side by side,
    /// and each component summed over the segments side by side (none padded) — the same bits, each
    /// segment's sums taken in the same order.
    pub fn project_lanes(&mut self, pool: &Pool, segments: [(usize, usize); SEGMENTS], z: &mut [f32]) {
        pool.fill(&self.plan, segments, &mut self.lanes);
        let width = self.model.width();
        let mut at = 0;
        for ((f, slots), rows) in self.model.factors.iter().zip(&self.slots).zip(&self.rows) {
            let n = slots.len();
            let xs = &mut self.xs[..n];
            for ((x, &slot), m) in xs.iter_mut().zip(slots).zip(&f.mean) {
                for (x, &v) in x.iter_mut().zip(&self.lanes[slot]) {
                    *x = v as f32 - m;
                }
            }
            for (c, axis) in rows.chunks_exact(n.max(1)).enumerate() {
                let mut acc = [0.0f32; SEGMENTS];
                for (&w, x) in axis.iter().zip(xs.iter()) {
                    for (a, &x) in acc.iter_mut().zip(x) {
                        *a += w * x;
                    }
                }
                for (l, a) in acc.into_iter().enumerate() {
                    z[l * width + at + c] = a;
                }
            }
            at += f.components;
        }
    }

    /// The 12 outputs of classifier `shift` on projected inputs `z` into `out` (no allocation).
    pub fn classify(&mut self, shift: usize, z: &[f32], out: &mut Outputs) {
        let mut at = 0;
        for (k, f) in self.model.factors.iter().enumerate() {
            let net = &f.nets[shift];
            net.forward(&z[at..at + f.components], &mut self.hidden[..net.hidden], &mut out[3 * k..3 * k + 3]);
            at += f.components;
        }
    }
}

/// The trained family of Effort classifiers and how it was made.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EffortModel {
    /// Frame rate of the segments it was trained on (takes are resampled to it).
    pub fps: f64,
    /// The largest boundary shift `s` (frames): `(2s + 1)²` classifiers.
    pub max_shift: usize,
    /// Shortest and longest training segment (frames).
    pub min_len: usize,
    pub max_len: usize,
    /// Where the labels came from (descriptor terciles over which takes, or a user's file).
    pub origin: String,
    /// Training and validation segments.
    pub samples: usize,
    /// Space, Time, Weight, Flow.
    pub factors: Vec<FactorModel>,
}

/// The 12 outputs of one classifier: per factor indulging, neutral, condensing.
pub type Outputs = [f32; 12];

impl EffortModel {
    /// Classifiers in the family.
    pub fn shifts(&self) -> usize {
        (2 * self.max_shift + 1).pow(2)
    }

    /// Index of the classifier for start shift `i` and end shift `j`.
    pub fn shift_index(&self, i: isize, j: isize) -> usize {
        let s = self.max_shift as isize;
        ((i + s) * (2 * s + 1) + (j + s)) as usize
    }

    /// Reads a model file, checking that it is complete.
    pub fn from_json(text: &str) -> Result<EffortModel, String> {
        let model: EffortModel = serde_json::from_str(text).map_err(|e| format!("not an LMA effort model: {e}"))?;
        model.validate()?;
        Ok(model)
    }

    pub fn to_json(&self) -> String {
        serde_json::to_string(self).expect("a model always serialises")
    }

    /// Every field of the family within what this build reads and can run in bounded work (a family from anyone is
    /// opened): the frame rate and lengths, the shift count (the work of a run grows with `(2s + 1)²`), each factor's
    /// features, standardisation and projection, each network's shape and weights; a refusal names the field, its
    /// value and what was expected.
    fn validate(&self) -> Result<(), String> {
        let bad = |what: String| Err(format!("LMA effort model: {what}"));
        if self.factors.len() != 4 {
            return bad(format!("{} factors, expected 4 (space, time, weight, flow)", self.factors.len()));
        }
        if !(self.fps.is_finite() && (MIN_FPS..=MAX_FPS).contains(&self.fps)) {
            let shown = if self.fps.abs() < 1e6 { self.fps.to_string() } else { format!("{:e}", self.fps) };
            return bad(format!("fps {shown}: expected {MIN_FPS} to {MAX_FPS} frames per second"));
        }
        if self.min_len < 2 || self.max_len < self.min_len || self.max_len > MAX_LEN {
            return bad(format!(
                "min_len {} and max_len {}: expected 2 ≤ min_len ≤ max_len ≤ {MAX_LEN} frames",
                self.min_len, self.max_len
            ));
        }
        if self.max_shift > MAX_SHIFT {
            return bad(format!(
                "max_shift {}: expected at most {MAX_SHIFT} frames ((2·{MAX_SHIFT} + 1)² = {} classifiers; the shipped family \
                 has 5)",
                self.max_shift,
                (2 * MAX_SHIFT + 1).pow(2)
            ));
        }
        if self.origin.chars().count() > MAX_ORIGIN_CHARS || self.origin.chars().any(char::is_control) {
            return bad(format!("origin: expected at most {MAX_ORIGIN_CHARS} characters and no control characters"));
        }
        for (f, m) in Factor::ALL.iter().zip(&self.factors) {
            m.validate(self.shifts()).or_else(|why| bad(format!("the {f:?} factor's {why}")))?;
        }
        Ok(())
    }
    /// Total projected inputs over the four factors.
    pub fn width(&self) -> usize {
        self.factors.iter().map(|f| f.components).sum()
    }

    /// The four factors' projected inputs of `start..=end`, concatenated into `z` ([`Self::width`]),
    /// one pool feature at a time (the reference; [`Projector::project`] is the fast path).
    pub fn project(&self, pool: &Pool, start: usize, end: usize, z: &mut [f32]) {
        let mut x = vec![0.0; self.factors.iter().map(|f| f.selected.len()).max().unwrap_or(0)];
        let mut at = 0;
        for f in &self.factors {
            f.project(pool, start, end, &mut x[..f.selected.len()], &mut z[at..at + f.components]);
            at += f.components;
        }
    }

    /// The 12 outputs of classifier `shift` on projected inputs `z`.
    pub fn classify(&self, shift: usize, z: &[f32]) -> Outputs {
        let mut out = [0.0; 12];
        let mut at = 0;
        for (k, f) in self.factors.iter().enumerate() {
            let net = &f.nets[shift];
            let mut hidden = vec![0.0; net.hidden];
            net.forward(&z[at..at + f.components], &mut hidden, &mut out[3 * k..3 * k + 3]);
            at += f.components;
        }
        out
    }

    /// Mean deviance and mean output of the family at the candidate `start..=end` of `pool`
    /// (shifted segments clamped to the take).
    pub fn assess(&self, pool: &Pool, start: usize, end: usize) -> (f32, Outputs) {
        self.assess_with(&mut Projector::new(self), pool, start, end)
    }

    /// [`Self::assess`] with a projector made once for many segments (`Projector::new(self)`).
    pub fn assess_with(&self, projector: &mut Projector, pool: &Pool, start: usize, end: usize) -> (f32, Outputs) {
        let s = self.max_shift as isize;
        let mut z = vec![0.0; self.width()];
        let mut outputs = vec![[0.0; 12]; self.shifts()];
        for i in -s..=s {
            for j in -s..=s {
                let (a, b) = shifted(start, end, i, j, pool.frames());
                projector.project(pool, a, b, &mut z);
                let shift = self.shift_index(i, j);
                projector.classify(shift, &z, &mut outputs[shift]);
            }
        }
        deviance(&outputs)
    }
}

/// Candidates an [`Assessor`] reads at once (more go in turns): its scratch stays a few MB however
/// many it is given.
const CANDIDATES: usize = 64;

/// [`EffortModel::assess`] of many candidate segments of one pool at once, bit for bit: a shifted
/// segment that several candidates read (candidates a few frames apart share most of theirs) is
/// projected once, [`SEGMENTS`] side by side ([`Projector::project_lanes`]), each classifier reads
/// every candidate's input in one batch per factor ([`Net::forward_batch_with`], bit-identical to
/// one at a time), and each candidate's outputs go through [`deviance`] as they would alone. The
/// scratch is reused from call to call; made once per search.
pub struct Assessor<'m> {
    projector: Projector<'m>,
    /// The distinct shifted segments the current candidates read, and the row of each.
    segments: Vec<(usize, usize)>,
    rows: HashMap<(usize, usize), u32>,
    /// Per candidate and shift (candidate-major, shifts in [`EffortModel::shift_index`] order), the
    /// row of the segment it reads.
    reads: Vec<u32>,
    /// The projected inputs of the segments, [`EffortModel::width`] per row.
    z: Vec<f32>,
    /// One classifier's inputs and outputs for every candidate, and its networks' scratch.
    x: Vec<f32>,
    y: Vec<f32>,
    scratch: Vec<f32>,
    /// Every classifier's outputs per candidate (candidate-major, shifts in order).
    outputs: Vec<Outputs>,
}

impl<'m> Assessor<'m> {
    pub fn new(model: &'m EffortModel) -> Assessor<'m> {
        Assessor {
            projector: Projector::new(model),
            segments: Vec::new(),
            rows: HashMap::new(),
            reads: Vec::new(),
            z: Vec::new(),
            x: Vec::new(),
            y: Vec::new(),
            scratch: Vec::new(),
            outputs: Vec::new(),
        }
    }

    /// Mean deviance and mean output of the family at each of `candidates` (`start..=end`) of
    /// `pool`, in order, into `out`: [`EffortModel::assess_with`]'s of each, the same bits.
    pub fn assess(&mut self, pool: &Pool, candidates: &[(usize, usize)], out: &mut Vec<(f32, Outputs)>) {
        out.clear();
        for some in candidates.chunks(CANDIDATES) {
            self.assess_some(pool, some, out);
        }
    }

    fn assess_some(&mut self, pool: &Pool, candidates: &[(usize, usize)], out: &mut Vec<(f32, Outputs)>) {
        let model = self.projector.model;
        let (s, shifts, width) = (model.max_shift as isize, model.shifts(), model.width());
        // every distinct shifted segment, projected once
        self.segments.clear();
        self.rows.clear();
        self.reads.clear();
        for &(start, end) in candidates {
            for i in -s..=s {
                for j in -s..=s {
                    let segment = shifted(start, end, i, j, pool.frames());
                    let row = *self.rows.entry(segment).or_insert_with(|| {
                        self.segments.push(segment);
                        (self.segments.len() - 1) as u32
                    });
                    self.reads.push(row);
                }
            }
        }
        self.z.resize(self.segments.len().div_ceil(SEGMENTS) * SEGMENTS * width, 0.0);
        for (chunk, z) in self.segments.chunks(SEGMENTS).zip(self.z.chunks_exact_mut(SEGMENTS * width)) {
            // the last chunk filled up with its last segment (rows never read)
            let lanes = std::array::from_fn(|l| chunk[l.min(chunk.len() - 1)]);
            self.projector.project_lanes(pool, lanes, z);
        }
        // each classifier on every candidate at once
        self.outputs.resize(candidates.len() * shifts, [0.0; 12]);
        let mut at = 0;
        for (k, f) in model.factors.iter().enumerate() {
            let c = f.components;
            for (shift, net) in f.nets.iter().enumerate() {
                self.x.clear();
                for reads in self.reads.chunks_exact(shifts) {
                    let row = reads[shift] as usize * width + at;
                    self.x.extend_from_slice(&self.z[row..row + c]);
                }
                self.y.resize(candidates.len() * 3, 0.0);
                net.forward_batch_with(&self.x, &mut self.y, &mut self.scratch);
                for (outputs, y) in self.outputs.chunks_exact_mut(shifts).zip(self.y.chunks_exact(3)) {
                    outputs[shift][3 * k..3 * k + 3].copy_from_slice(y);
                }
            }
            at += c;
        }
        out.extend(self.outputs.chunks_exact(shifts).map(deviance));
    }
}

/// The segment `start + i ..= end + j` kept inside `frames` frames and at least two frames long.
pub fn shifted(start: usize, end: usize, i: isize, j: isize, frames: usize) -> (usize, usize) {
    let last = frames.saturating_sub(1) as isize;
    let b = (end as isize + j).clamp(1, last.max(1)) as usize;
    let a = (start as isize + i).clamp(0, b as isize - 1) as usize;
    (a, b)
}

/// Eq. 1–2: the mean output `m` of the family and the mean Euclidean distance of each output to it.
pub fn deviance(outputs: &[Outputs]) -> (f32, Outputs) {
    let n = outputs.len().max(1) as f32;
    let mut m = [0.0f32; 12];
    for x in outputs {
        for (a, b) in m.iter_mut().zip(x) {
            *a += b / n;
        }
    }
    let d = outputs.iter().map(|x| x.iter().zip(&m).map(|(a, b)| (a - b).powi(2)).sum::<f32>().sqrt()).sum::<f32>() / n;
    (d, m)
}

/// A segment's Effort from the family's mean output: per factor condensing − indulging, in [−1, 1].
pub fn effort(m: &Outputs) -> Effort {
    let factor = |k: usize| ((m[3 * k + 2] - m[3 * k]) as f64).clamp(-1.0, 1.0);
    Effort { space: factor(0), time: factor(1), weight: factor(2), flow: factor(3) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identical_classifiers_deviate_by_nothing() {
        let x: Outputs = [0.1, 0.8, 0.1, 0.9, 0.05, 0.05, 0.2, 0.2, 0.6, 0.3, 0.3, 0.4];
        let (d, m) = deviance(&vec![x; 121]);
        assert!(d.abs() < 1e-5, "{d}");
        assert!(m.iter().zip(&x).all(|(a, b)| (a - b).abs() < 1e-5));
        // two classifiers that disagree on one output by 1: each is 0.5 from the mean
        let mut y = x;
        y[0] += 1.0;
        let (d, _) = deviance(&[x, y]);
        assert!((d - 0.5).abs() < 1e-6, "{d}");
    }

    #[test]
    fn effort_runs_from_indulging_to_condensing() {
        let mut m = [0.0f32; 12];
        m[0] = 1.0; // space fully indulging
        m[5] = 1.0; // time fully condensing
        m[7] = 1.0; // weight neutral
        let e = effort(&m);
        assert_eq!((e.space, e.time, e.weight, e.flow), (-1.0, 1.0, 0.0, 0.0));
    }

    #[test]
    fn broken_model_files_are_refused_with_what_is_wrong() {
        let shipped: &EffortModel = &crate::methods::lma::shipped_model().unwrap();
        assert_eq!(EffortModel::from_json(&shipped.to_json()).as_ref(), Ok(shipped));
        let mut bad = shipped.clone();
        bad.factors[1].nets[7].w1.pop();
        assert!(EffortModel::from_json(&bad.to_json()).unwrap_err().contains("the Time factor's nets[7].w1"));
        let mut bad = shipped.clone();
        bad.factors[2].nets[0].b2[0] = f32::NAN;
        // NaN is written as null by JSON: the file no longer reads as a model
        assert!(EffortModel::from_json(&bad.to_json()).is_err());
        let mut bad = shipped.clone();
        bad.max_shift = 1_000_000;
        assert!(EffortModel::from_json(&bad.to_json()).unwrap_err().contains("max_shift"));
        // every field a family from anyone may get wrong is named, with what was expected
        let refused = |change: &dyn Fn(&mut EffortModel)| {
            let mut bad = shipped.clone();
            change(&mut bad);
            EffortModel::from_json(&bad.to_json()).unwrap_err()
        };
        assert!(refused(&|m| m.fps = 1e300).contains("fps 1e300: expected 5 to 240"));
        assert!(refused(&|m| m.fps = 0.5).contains("fps 0.5"));
        assert!(refused(&|m| m.max_shift = 11).contains("max_shift 11: expected at most 10"));
        assert!(refused(&|m| m.max_len = 1).contains("min_len 20 and max_len 1"));
        assert!(refused(&|m| m.origin = "a\u{7}".into()).contains("origin"));
        assert!(refused(&|m| m.factors[0].components = 10_000).contains("the Space factor's components: 10000"));
        assert!(refused(&|m| m.factors[3].scale[0] = 0.0).contains("the Flow factor's scale: 0"));
        assert!(refused(&|m| m.factors[2].selected[0] = 9999).contains("the Weight factor's selected: feature 9999"));
        assert!(refused(&|m| m.factors[1].nets.truncate(3))
            .contains("the Time factor's nets: 3 networks, expected one per classifier"));
        assert!(refused(&|m| m.factors[1].nets[2].hidden = 5000).contains("nets[2]: "));
        let err = EffortModel::from_json("{\"fps\": 30}").unwrap_err();
        assert!(err.starts_with("not an LMA effort model"), "{err}");
    }

    /// The projector (one plan of every factor's features, scales folded into the axes, blocked
    /// rotation) gives the per-feature projection's inputs, on random segments of a take; and
    /// [`SEGMENTS`] segments projected side by side get each the bits of the segment alone.
    #[test]
    fn the_projector_equals_the_projection_one_feature_at_a_time() {
        let model = &crate::methods::lma::shipped_model().unwrap();
        let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/35_01.bvh")).unwrap();
        let motion = crate::motion::Motion::from_bvh("35_01.bvh", &crate::bvh::parse(&text).unwrap()).unwrap();
        let body = crate::methods::lma::body::upper_body(&motion, model.fps).unwrap();
        let mut rng = crate::stats::Rng::new(31);
        let mut projector = Projector::new(model);
        let (mut fast, mut slow) = (vec![0.0; model.width()], vec![0.0; model.width()]);
        let mut worst = 0.0f32;
        let width = model.width();
        let mut lanes = vec![0.0; SEGMENTS * width];
        for arm in &body.arms {
            let pool = Pool::of(arm, model.fps, 111);
            let n = pool.frames();
            let mut segments = Vec::new();
            for _ in 0..300 {
                let start = rng.below(n - 2);
                let end = (start + 1 + rng.below(110)).min(n - 1);
                projector.project(&pool, start, end, &mut fast);
                model.project(&pool, start, end, &mut slow);
                for (a, b) in fast.iter().zip(&slow) {
                    worst = worst.max((a - b).abs() / b.abs().max(1.0));
                }
                segments.push((start, end, fast.clone()));
            }
            for chunk in segments.chunks_exact(SEGMENTS) {
                projector.project_lanes(&pool, std::array::from_fn(|l| (chunk[l].0, chunk[l].1)), &mut lanes);
                for ((start, end, alone), side_by_side) in chunk.iter().zip(lanes.chunks_exact(width)) {
                    let bits = |z: &[f32]| z.iter().map(|v| v.to_bits()).collect::<Vec<u32>>();
                    assert_eq!(bits(side_by_side), bits(alone), "{start}..={end}");
                }
            }
        }
        assert!(worst < 1e-5, "largest difference {worst} (relative, or absolute below 1)");
    }

    /// The assessor's deviances and mean outputs are the family's, one candidate at a time, bit for bit: random
    /// candidates of a real take (short and long, at its ends where the shifted segments are clamped, repeated,
    /// overlapping), more than it reads at once, in calls of different sizes one after another (the scratch of one
    /// call never leaks into the next).
    #[test]
    fn the_assessor_is_the_family_assessed_one_candidate_at_a_time() {
        let model = &crate::methods::lma::shipped_model().unwrap();
        let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/35_01.bvh")).unwrap();
        let motion = crate::motion::Motion::from_bvh("35_01.bvh", &crate::bvh::parse(&text).unwrap()).unwrap();
        let body = crate::methods::lma::body::upper_body(&motion, model.fps).unwrap();
        let mut rng = crate::stats::Rng::new(37);
        let (mut projector, mut assessor) = (Projector::new(model), Assessor::new(model));
        let mut assessed = Vec::new();
        for arm in &body.arms {
            let pool = Pool::of(arm, model.fps, 111);
            let n = pool.frames();
            for count in [CANDIDATES + 9, 1, 0, 17] {
                let mut candidates: Vec<(usize, usize)> = (0..count)
                    .map(|_| {
                        let start = rng.below(n - 2);
                        (start, (start + 1 + rng.below(60)).min(n - 1))
                    })
                    .collect();
                if count > 1 {
                    candidates.extend([(0, 1), (0, 25), (n - 2, n - 1), (n - 30, n - 1), candidates[0]]);
                }
                assessor.assess(&pool, &candidates, &mut assessed);
                assert_eq!(assessed.len(), candidates.len());
                for (&(start, end), (d, m)) in candidates.iter().zip(&assessed) {
                    let (one_d, one_m) = model.assess_with(&mut projector, &pool, start, end);
                    assert_eq!(d.to_bits(), one_d.to_bits(), "{start}..={end}");
                    assert_eq!(m.map(f32::to_bits), one_m.map(f32::to_bits), "{start}..={end}");
                }
            }
        }
    }

    #[test]
    fn shifted_segments_stay_inside_the_take() {
        assert_eq!(shifted(10, 40, -5, 5, 100), (5, 45));
        assert_eq!(shifted(2, 40, -5, 5, 100), (0, 45));
        assert_eq!(shifted(60, 98, 5, 5, 100), (65, 99));
        assert_eq!(shifted(0, 1, 5, -5, 100), (0, 1));
    }
}
