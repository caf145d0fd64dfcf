//! The kinematic feature pool of Bouchard & Badler's LMA Effort classifiers (their §4, Fig. 1:
//! "features derived from the positions and orientations of the upper body's joints"): per-frame
//! series of an arm and the upper body it shares ([`SERIES`]: the shoulder's, elbow's, hand's and
//! head's positions and kinematic quantities — [`Kinematics`], shared with the other methods in
//! [`crate::features::kinematics`]: speed, acceleration, jerk, curvature, distance from the torso —
//! and the orientations of the arm, torso and head: angles and angular speeds), each weighted to
//! emphasise the beginning, middle or end of a candidate segment ([`Weighting`]) and reduced to one
//! scalar by a statistic ([`Stat`]: mean, sum, max, min, standard deviation).
//!
//! The segmentation scores every candidate segment between 0.67 s and 3.33 s — the exhaustive
//! search is tens of thousands of candidates per take — so a candidate's features must cost O(1)
//! each: [`Prefix`] keeps cumulative sums of `x`, `t·x`, `x²`, `t·x²` (every weighting here is
//! linear in `t` on each half of the segment, so its weighted sums follow from those) and sparse
//! tables for range maxima and minima. Weighted max / min are the max / min of the unweighted
//! values (a weight that varies along the segment has no O(1) range maximum); the paper leaves
//! which combinations its 4500 permutations hold unstated. A [`Plan`] groups the features a
//! classifier family reads by series, so that [`Pool::fill`] reads each series' range sums once
//! per segment and derives all of its statistics from them.

use glam::DVec3;

pub use crate::features::kinematics::Kinematics;

/// Which part of a segment a feature emphasises (`u` = 0 at its first frame, 1 at its last).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Weighting {
    /// Every frame alike.
    Uniform,
    /// `1 − u`: "the velocity of each frame scaled by its normalized distance from the last frame".
    Beginning,
    /// `1 − |2u − 1|`.
    Middle,
    /// `u`.
    End,
}

/// How a weighted feature becomes one scalar.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stat {
    /// Weighted mean `Σ w x / Σ w`.
    Mean,
    /// `Σ w x`.
    Sum,
    /// Largest value (unweighted, see the module docs).
    Max,
    /// Smallest value (unweighted).
    Min,
    /// Weighted standard deviation.
    Std,
}

/// Cumulative sums and range-extremum tables of one per-frame series, for O(1) segment statistics.
#[derive(Debug, Clone)]
pub struct Prefix {
    /// `c[i]` = Σ over frames `< i` of `x`, `t·x`, `x²`, `t·x²` (interleaved: one segment end is
    /// one cache line; the sums of `1` and `t` are closed forms, [`Sums::of`]).
    c: Vec<[f64; 4]>,
    max: Vec<Vec<f64>>,
    min: Vec<Vec<f64>>,
}

/// The range sums of one series over frames `a..b` from which every weighted statistic follows, of `L` segments at
/// once: lane `l` is the `l`-th segment's (the arithmetic then runs over every lane at once, in vectors).
#[derive(Debug, Clone, Copy)]
struct Sums<const L: usize> {
    /// Σ 1, Σ t, Σ x, Σ t·x, Σ x², Σ t·x².
    n: [f64; L],
    t: [f64; L],
    x: [f64; L],
    tx: [f64; L],
    x2: [f64; L],
    tx2: [f64; L],
}

/// Per lane, the frames `a..b` that range sums read.
type Ranges<const L: usize> = ([usize; L], [usize; L]);

/// Per lane, a weight `p + q·t` in the frame `t`.
type Line<const L: usize> = ([f64; L], [f64; L]);

impl<const L: usize> Sums<L> {
    fn of(c: &[[f64; 4]], (a, b): &Ranges<L>) -> Sums<L> {
        // Σ_{t<k} t = k(k − 1)/2: integers, exact in f64 like the prefix sums they replace
        let below = |k: usize| (k * k.saturating_sub(1) / 2) as f64;
        let mut s = Sums { n: [0.0; L], t: [0.0; L], x: [0.0; L], tx: [0.0; L], x2: [0.0; L], tx2: [0.0; L] };
        for l in 0..L {
            let (p, q) = (&c[a[l]], &c[b[l]]);
            s.n[l] = (b[l] - a[l]) as f64;
            s.t[l] = below(b[l]) - below(a[l]);
            s.x[l] = q[0] - p[0];
            s.tx[l] = q[1] - p[1];
            s.x2[l] = q[2] - p[2];
            s.tx2[l] = q[3] - p[3];
        }
        s
    }

    /// `[Σ w, Σ w x, Σ w x²]` for the weight `w(t) = p + q·t` of each lane.
    fn linear(&self, (p, q): &Line<L>) -> [[f64; L]; 3] {
        let mut out = [[0.0; L]; 3];
        for l in 0..L {
            out[0][l] = p[l] * self.n[l] + q[l] * self.t[l];
            out[1][l] = p[l] * self.x[l] + q[l] * self.tx[l];
            out[2][l] = p[l] * self.x2[l] + q[l] * self.tx2[l];
        }
        out
    }
}

/// The weightings of `L` segments `start..=end` as lines in the frame `t` (every weighting is linear in `t` on
/// `[start, mid]` and `[mid, end]`, with `u(t) = (t − start) / span`), and the frames their sums read: computed once
/// per segment and read by every series.
#[derive(Debug, Clone, Copy)]
struct Lines<const L: usize> {
    /// `1`.
    uniform: Line<L>,
    /// `u`.
    end: Line<L>,
    /// `1 − u`.
    beginning: Line<L>,
    /// The middle weighting's halves: `2u` on `start..=mid`, `2 − 2u` on `mid + 1..=end` (the middle frame in the
    /// first).
    rise: Line<L>,
    fall: Line<L>,
    /// The whole segment `start..end + 1` and the halves `start..mid + 1`, `mid + 1..end + 1`.
    all: Ranges<L>,
    first: Ranges<L>,
    second: Ranges<L>,
}

impl<const L: usize> Lines<L> {
    fn of(segments: [(usize, usize); L]) -> Lines<L> {
        let (line, range) = (([0.0; L], [0.0; L]), ([0; L], [0; L]));
        let mut lines = Lines {
            uniform: line,
            end: line,
            beginning: line,
            rise: line,
            fall: line,
            all: range,
            first: range,
            second: range,
        };
        for (l, (start, end)) in segments.into_iter().enumerate() {
            let span = (end - start).max(1) as f64;
            let s = start as f64;
            let mid = start + (end - start) / 2;
            (lines.uniform.0[l], lines.uniform.1[l]) = (1.0, 0.0);
            (lines.end.0[l], lines.end.1[l]) = (-s / span, 1.0 / span);
            (lines.beginning.0[l], lines.beginning.1[l]) = (1.0 + s / span, -1.0 / span);
            (lines.rise.0[l], lines.rise.1[l]) = (-2.0 * s / span, 2.0 / span);
            (lines.fall.0[l], lines.fall.1[l]) = (2.0 + 2.0 * s / span, -2.0 / span);
            (lines.all.0[l], lines.all.1[l]) = (start, end + 1);
            (lines.first.0[l], lines.first.1[l]) = (start, mid + 1);
            (lines.second.0[l], lines.second.1[l]) = (mid + 1, end + 1);
        }
        lines
    }
}

impl Prefix {
    /// Tables for segments of any length.
    pub fn new(x: &[f64]) -> Prefix {
        Prefix::up_to(x, x.len())
    }

    /// Tables for segments of at most `longest` frames (the extremum tables then hold
    /// `log2(longest)` levels instead of `log2(frames)`: a long take's memory stays linear).
    pub fn up_to(x: &[f64], longest: usize) -> Prefix {
        let n = x.len();
        let mut c = vec![[0.0; 4]; n + 1];
        for (t, &v) in x.iter().enumerate() {
            let tf = t as f64;
            let terms = [v, tf * v, v * v, tf * v * v];
            for k in 0..4 {
                c[t + 1][k] = c[t][k] + terms[k];
            }
        }
        // level k: the extremum of each 2^k frames (a generic `pick`, so that it inlines and the level vectorises)
        fn table(x: &[f64], longest: usize, pick: impl Fn(f64, f64) -> f64) -> Vec<Vec<f64>> {
            let mut levels = vec![x.to_vec()];
            let mut width = 1;
            while 2 * width <= x.len().min(longest.max(1)) {
                let prev = &levels[levels.len() - 1];
                let next: Vec<f64> = prev.iter().zip(&prev[width..]).map(|(&a, &b)| pick(a, b)).collect();
                levels.push(next);
                width *= 2;
            }
            levels
        }
        Prefix { c, max: table(x, longest, f64::max), min: table(x, longest, f64::min) }
    }

    /// Bytes per frame of the tables for segments of at most `longest` frames: the four sums and
    /// one value per extremum table level, in f64.
    pub fn bytes_per_frame(longest: usize) -> usize {
        let levels = (usize::BITS - longest.max(1).leading_zeros()) as usize;
        (4 + 2 * levels) * 8
    }

    fn extremum(levels: &[Vec<f64>], a: usize, b: usize, pick: impl Fn(f64, f64) -> f64) -> f64 {
        let len = b - a;
        let level = ((usize::BITS - 1 - len.leading_zeros()) as usize).min(levels.len() - 1);
        if len > 2 << level {
            // longer than the tables were built for: fold the range in steps of the top level
            let width = 1 << level;
            let mut v = levels[level][a];
            let mut i = a + width;
            while i + width < b {
                v = pick(v, levels[level][i]);
                i += width;
            }
            return pick(v, levels[level][b - width]);
        }
        pick(levels[level][a], levels[level][b - (1 << level)])
    }

    /// `[Σ w, Σ w x, Σ w x²]` of `weighting` over the segments of `lines`, from the range sums of
    /// the whole segments (`all`) and, for [`Weighting::Middle`], of their halves.
    fn weighted<const L: usize>(&self, lines: &Lines<L>, weighting: Weighting, all: &Sums<L>) -> [[f64; L]; 3] {
        match weighting {
            Weighting::Uniform => all.linear(&lines.uniform),
            Weighting::End => all.linear(&lines.end),
            Weighting::Beginning => all.linear(&lines.beginning),
            Weighting::Middle => {
                let first = Sums::of(&self.c, &lines.first).linear(&lines.rise);
                let second = Sums::of(&self.c, &lines.second).linear(&lines.fall);
                let mut out = first;
                for (o, s) in out.iter_mut().zip(second) {
                    for l in 0..L {
                        o[l] += s[l];
                    }
                }
                out
            }
        }
    }

    /// A mean, sum or standard deviation from its weighted sums.
    fn reduce(stat: Stat, (w, wx, wx2): (f64, f64, f64)) -> f64 {
        match stat {
            Stat::Sum => wx,
            Stat::Mean if w > 0.0 => wx / w,
            Stat::Std if w > 0.0 => (wx2 / w - (wx / w).powi(2)).max(0.0).sqrt(),
            _ => 0.0,
        }
    }

    /// The statistic `stat` of the series weighted by `weighting` over the segment of frames
    /// `start..=end` (`start ≤ end` inside the series), in O(1).
    pub fn stat(&self, start: usize, end: usize, weighting: Weighting, stat: Stat) -> f64 {
        let (a, b) = (start, end + 1);
        match stat {
            Stat::Max => Self::extremum(&self.max, a, b, f64::max),
            Stat::Min => Self::extremum(&self.min, a, b, f64::min),
            _ => {
                let lines = Lines::of([(start, end)]);
                let [w, wx, wx2] = self.weighted(&lines, weighting, &Sums::of(&self.c, &lines.all));
                Self::reduce(stat, (w[0], wx[0], wx2[0]))
            }
        }
    }
}

/// The per-frame quantities of every joint of an arm and of the head (Fig. 1's "kinematic
/// features"): its position (`x` lateral, `y` up, `z` forward), distance from the sternum, speed,
/// acceleration, jerk and `ln(1 + curvature)` (curvature spikes where the joint nearly stops; the
/// logarithm keeps one spike from dominating a segment's statistics).
pub const QUANTITIES: [&str; 8] = ["x", "y", "z", "distance", "speed", "acceleration", "jerk", "curvature"];

/// The orientations of the arm (radians, rad/s), after the joints' quantities: the elbow's
/// flexion (angle between upper arm and forearm, 0 straight) and its rate of change; the
/// elevation of the upper arm at the shoulder and of the forearm (angle from hanging straight down);
/// how fast the upper arm and the forearm turn (angle between their directions one frame before
/// and one after, per second).
pub const ARM_ORIENTATIONS: [&str; 6] = [
    "elbow flexion",
    "elbow flexion speed",
    "shoulder elevation",
    "forearm elevation",
    "upper arm angular speed",
    "forearm angular speed",
];

/// The torso's and head's orientations (radians, rad/s), after the head's quantities: the torso's
/// lean from upright, forwards (signed, + forwards) and sideways (signed, + towards this arm), how
/// fast it turns, its twist (this shoulder forward of the sternum, +), the head's tilt from the
/// torso's direction and how fast the head (sternum to head) turns.
pub const TORSO_ORIENTATIONS: [&str; 7] = [
    "torso lean",
    "torso forward lean",
    "torso side lean",
    "torso angular speed",
    "torso twist",
    "head tilt",
    "head angular speed",
];

/// Per-frame series of an arm's pool, in order: the shoulder's, elbow's and hand's
/// [`QUANTITIES`] (the pool of families trained before the orientations: their feature indices
/// keep their meaning), the [`ARM_ORIENTATIONS`], the head's [`QUANTITIES`], the
/// [`TORSO_ORIENTATIONS`].
pub const SERIES: usize = 3 * QUANTITIES.len() + ARM_ORIENTATIONS.len() + QUANTITIES.len() + TORSO_ORIENTATIONS.len();

/// The name of series `k` (of [`SERIES`]): `hand speed`, `elbow flexion`, `head y`.
pub fn series_name(k: usize) -> String {
    let joints = 3 * QUANTITIES.len();
    let arm = joints + ARM_ORIENTATIONS.len();
    let head = arm + QUANTITIES.len();
    if k < joints {
        format!("{} {}", super::body::ARM_JOINTS[k / QUANTITIES.len()], QUANTITIES[k % QUANTITIES.len()])
    } else if k < arm {
        ARM_ORIENTATIONS[k - joints].to_string()
    } else if k < head {
        format!("head {}", QUANTITIES[k - arm])
    } else {
        TORSO_ORIENTATIONS[k - head].to_string()
    }
}

/// The angle between two directions (0 where either has no length).
fn angle(a: DVec3, b: DVec3) -> f64 {
    if a.length_squared() > 1e-18 && b.length_squared() > 1e-18 {
        a.angle_between(b)
    } else {
        0.0
    }
}

/// How fast the directions `d` turn (rad/s at `fps`): the angle between the direction a frame
/// before and a frame after, over the two frames (one-sided at the ends), as
/// [`crate::features::kinematics::derivative`] differentiates positions.
fn angular_speed(d: &[DVec3], fps: f64) -> Vec<f64> {
    let n = d.len();
    (0..n)
        .map(|i| match (i.checked_sub(1), (i + 1 < n).then_some(i + 1)) {
            (Some(a), Some(b)) => angle(d[a], d[b]) * fps / 2.0,
            (None, Some(b)) => angle(d[i], d[b]) * fps,
            (Some(a), None) => angle(d[a], d[i]) * fps,
            (None, None) => 0.0,
        })
        .collect()
}

/// The rate of change of a scalar series, by the same differences (absolute, per second).
fn rate(x: &[f64], fps: f64) -> Vec<f64> {
    let points: Vec<DVec3> = x.iter().map(|&v| DVec3::new(v, 0.0, 0.0)).collect();
    crate::features::kinematics::derivative(&points, fps).iter().map(|v| v.x.abs()).collect()
}

/// A joint's [`QUANTITIES`], in order.
fn quantities(joint: &[DVec3], fps: f64) -> [Vec<f64>; 8] {
    let k = Kinematics::of(joint, fps);
    let axis = |a: usize| joint.iter().map(|p| p[a]).collect::<Vec<f64>>();
    let curvature: Vec<f64> = k.curvature.iter().map(|c| c.ln_1p()).collect();
    [axis(0), axis(1), axis(2), k.distance, k.speed, k.acceleration, k.jerk, curvature]
}

/// Every series of `arm`'s pool (see [`SERIES`]), one value per frame.
pub fn series_of(arm: &super::body::Arm, fps: f64) -> Vec<Vec<f64>> {
    let [shoulder, elbow, hand] = &arm.joints;
    let mut out: Vec<Vec<f64>> = Vec::with_capacity(SERIES);
    for joint in &arm.joints {
        out.extend(quantities(joint, fps));
    }
    let bone = |from: &[DVec3], to: &[DVec3]| from.iter().zip(to).map(|(a, b)| *b - *a).collect::<Vec<DVec3>>();
    let (upper, fore) = (bone(shoulder, elbow), bone(elbow, hand));
    let flexion: Vec<f64> = upper.iter().zip(&fore).map(|(u, f)| angle(*u, *f)).collect();
    let flexion_speed = rate(&flexion, fps);
    let elevation = |d: &[DVec3]| d.iter().map(|v| angle(*v, DVec3::NEG_Y)).collect::<Vec<f64>>();
    out.extend([flexion, flexion_speed, elevation(&upper), elevation(&fore)]);
    out.extend([angular_speed(&upper, fps), angular_speed(&fore, fps)]);
    out.extend(quantities(&arm.head, fps));
    let torso = &arm.torso;
    let each = |f: &dyn Fn(&DVec3) -> f64| torso.iter().map(f).collect::<Vec<f64>>();
    out.push(each(&|d| angle(*d, DVec3::Y)));
    out.push(each(&|d| f64::atan2(d.z, d.y)));
    // the arm's side is −x (a right arm, or a left one mirrored): + towards it
    out.push(each(&|d| f64::atan2(-d.x, d.y)));
    out.push(angular_speed(torso, fps));
    out.push(shoulder.iter().map(|p| f64::atan2(p.z, -p.x)).collect());
    out.push(arm.head.iter().zip(torso).map(|(h, d)| angle(*h, *d)).collect());
    out.push(angular_speed(&arm.head, fps));
    debug_assert_eq!(out.len(), SERIES);
    out
}

/// The statistics taken of every quantity: mean, sum and standard deviation under each of the four
/// weightings, and the (unweighted) maximum and minimum.
pub const STATISTICS: [(Weighting, Stat); 14] = [
    (Weighting::Uniform, Stat::Mean),
    (Weighting::Beginning, Stat::Mean),
    (Weighting::Middle, Stat::Mean),
    (Weighting::End, Stat::Mean),
    (Weighting::Uniform, Stat::Sum),
    (Weighting::Beginning, Stat::Sum),
    (Weighting::Middle, Stat::Sum),
    (Weighting::End, Stat::Sum),
    (Weighting::Uniform, Stat::Std),
    (Weighting::Beginning, Stat::Std),
    (Weighting::Middle, Stat::Std),
    (Weighting::End, Stat::Std),
    (Weighting::Uniform, Stat::Max),
    (Weighting::Uniform, Stat::Min),
];

/// Size of the feature pool: series × statistics.
pub const POOL_SIZE: usize = SERIES * STATISTICS.len();

/// Bytes per frame of one arm's pool for segments of at most `longest` frames.
pub fn pool_bytes_per_frame(longest: usize) -> usize {
    SERIES * Prefix::bytes_per_frame(longest)
}

/// The feature pool of one arm of a take: every feature of any segment in O(1).
#[derive(Debug, Clone)]
pub struct Pool {
    series: Vec<Prefix>,
    frames: usize,
}

impl Pool {
    /// The pool of `arm` at `fps`, for segments of at most `longest` frames.
    pub fn of(arm: &super::body::Arm, fps: f64, longest: usize) -> Pool {
        let series = series_of(arm, fps).iter().map(|values| Prefix::up_to(values, longest)).collect();
        Pool { series, frames: arm.frames() }
    }

    /// Frames of the take.
    pub fn frames(&self) -> usize {
        self.frames
    }

    /// Feature `index` (of [`POOL_SIZE`]) of the segment `start..=end`.
    pub fn feature(&self, index: usize, start: usize, end: usize) -> f64 {
        let (weighting, stat) = STATISTICS[index % STATISTICS.len()];
        self.series[index / STATISTICS.len()].stat(start, end, weighting, stat)
    }

    /// The features `which` (indices into the pool) of the segment `start..=end`, into `out`.
    pub fn features(&self, which: &[u16], start: usize, end: usize, out: &mut [f32]) {
        for (o, &k) in out.iter_mut().zip(which) {
            *o = self.feature(k as usize, start, end) as f32;
        }
    }

    /// The features of `plan` of `L` segments `start..=end` into `out` (one per slot of the plan,
    /// [`Plan::len`], lane `l` the `l`-th segment's): each series' range sums read once and every
    /// statistic of it derived from them — the same values as [`Pool::feature`] of each, at a
    /// fraction of the reads; the segments side by side in vectors, each lane's bits those of the
    /// segment alone (`L` = 1).
    pub fn fill<const L: usize>(&self, plan: &Plan, segments: [(usize, usize); L], out: &mut [[f64; L]]) {
        let lines = Lines::of(segments);
        let (a, b) = lines.all;
        // per weighting: sum, mean, standard deviation, as Prefix::reduce computes them (0 without weight); each
        // series writes those its slots read (sum and mean of the weightings it needs, the deviation where asked)
        // before they read them, so the values another series left are never read
        let mut values = [[0.0f64; L]; 12];
        for g in &plan.groups {
            let p = &self.series[g.series];
            let all = Sums::of(&p.c, &lines.all);
            for (k, weighting) in WEIGHTINGS.into_iter().enumerate() {
                if g.weightings & (1 << k) != 0 {
                    let [w, wx, wx2] = p.weighted(&lines, weighting, &all);
                    values[3 * k] = wx;
                    let mut mean = [0.0; L];
                    for l in 0..L {
                        mean[l] = wx[l] / w[l];
                        values[3 * k + 1][l] = if w[l] > 0.0 { mean[l] } else { 0.0 };
                    }
                    if g.deviations & (1 << k) != 0 {
                        for l in 0..L {
                            let deviation = (wx2[l] / w[l] - mean[l] * mean[l]).max(0.0).sqrt();
                            values[3 * k + 2][l] = if w[l] > 0.0 { deviation } else { 0.0 };
                        }
                    }
                }
            }
            for (slot, &op) in g.slots.clone().zip(&plan.ops[g.slots.clone()]) {
                let out = &mut out[slot];
                match op {
                    Plan::MAX => (0..L).for_each(|l| out[l] = Prefix::extremum(&p.max, a[l], b[l], f64::max)),
                    Plan::MIN => (0..L).for_each(|l| out[l] = Prefix::extremum(&p.min, a[l], b[l], f64::min)),
                    k => *out = values[k as usize],
                }
            }
        }
    }

    /// The name of feature `index`: `hand speed, max`, `elbow y, mean (beginning)` or
    /// `torso lean, std (end)`.
    pub fn name(index: usize) -> String {
        let (weighting, stat) = STATISTICS[index % STATISTICS.len()];
        let series = series_name(index / STATISTICS.len());
        let stat = format!("{stat:?}").to_lowercase();
        match (stat.as_str(), weighting) {
            ("max" | "min", _) | (_, Weighting::Uniform) => format!("{series}, {stat}"),
            _ => format!("{series}, {stat} ({})", format!("{weighting:?}").to_lowercase()),
        }
    }
}

/// The four weightings in the order of their discriminants.
const WEIGHTINGS: [Weighting; 4] = [Weighting::Uniform, Weighting::Beginning, Weighting::Middle, Weighting::End];

/// Which statistics of which series a set of pool features needs, grouped by series, so that
/// [`Pool::fill`] reads each series' range sums once per segment however many of its statistics
/// (and however many factors) ask for them. Made once per classifier family.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// The distinct pool features, one slot each, ordered by series.
    features: Vec<u16>,
    /// What each slot reads: `3·w + {0 sum, 1 mean, 2 std}` for weighting `w` of [`WEIGHTINGS`],
    /// or [`Plan::MAX`] / [`Plan::MIN`].
    ops: Vec<u8>,
    groups: Vec<Group>,
}

/// One series a plan reads: the weightings whose sums it needs (bit `k` for [`WEIGHTINGS`]`[k]`),
/// those of them whose standard deviation it needs, and its slots.
#[derive(Debug, Clone, PartialEq)]
struct Group {
    series: usize,
    weightings: u8,
    deviations: u8,
    slots: std::ops::Range<usize>,
}

impl Plan {
    /// The plan of `features` (pool indices; repeats share a slot).
    pub fn new(features: impl IntoIterator<Item = u16>) -> Plan {
        let mut features: Vec<u16> = features.into_iter().collect();
        features.sort_unstable();
        features.dedup();
        let mut groups: Vec<Group> = Vec::new();
        let mut ops = Vec::with_capacity(features.len());
        for (slot, &k) in features.iter().enumerate() {
            let series = k as usize / STATISTICS.len();
            let (weighting, stat) = STATISTICS[k as usize % STATISTICS.len()];
            if groups.last().is_none_or(|g| g.series != series) {
                groups.push(Group { series, weightings: 0, deviations: 0, slots: slot..slot });
            }
            let g = groups.last_mut().expect("just pushed");
            g.slots.end = slot + 1;
            let w = weighting as u8;
            ops.push(match stat {
                Stat::Max => Plan::MAX,
                Stat::Min => Plan::MIN,
                Stat::Sum => 3 * w,
                Stat::Mean => 3 * w + 1,
                Stat::Std => 3 * w + 2,
            });
            if !matches!(stat, Stat::Max | Stat::Min) {
                g.weightings |= 1 << w;
            }
            if stat == Stat::Std {
                g.deviations |= 1 << w;
            }
        }
        Plan { features, ops, groups }
    }

    const MAX: u8 = 12;
    const MIN: u8 = 13;

    /// Slots (distinct features).
    pub fn len(&self) -> usize {
        self.features.len()
    }

    pub fn is_empty(&self) -> bool {
        self.features.is_empty()
    }

    /// The slot of pool feature `feature`, if the plan holds it.
    pub fn slot(&self, feature: u16) -> Option<usize> {
        self.features.binary_search(&feature).ok()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stats::Rng;

    pub(super) fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol * (1.0 + b.abs())
    }

    /// The statistic computed frame by frame, as the definition reads.
    fn direct(x: &[f64], start: usize, end: usize, weighting: Weighting, stat: Stat) -> f64 {
        let span = (end - start).max(1) as f64;
        let w = |t: usize| {
            let u = (t - start) as f64 / span;
            match weighting {
                Weighting::Uniform => 1.0,
                Weighting::Beginning => 1.0 - u,
                Weighting::End => u,
                Weighting::Middle => 1.0 - (2.0 * u - 1.0).abs(),
            }
        };
        let frames = start..=end;
        let sw: f64 = frames.clone().map(w).sum();
        let swx: f64 = frames.clone().map(|t| w(t) * x[t]).sum();
        let swx2: f64 = frames.clone().map(|t| w(t) * x[t] * x[t]).sum();
        match stat {
            Stat::Sum => swx,
            Stat::Mean | Stat::Std if sw == 0.0 => 0.0,
            Stat::Mean => swx / sw,
            Stat::Std => (swx2 / sw - (swx / sw).powi(2)).max(0.0).sqrt(),
            Stat::Max => frames.map(|t| x[t]).fold(f64::MIN, f64::max),
            Stat::Min => frames.map(|t| x[t]).fold(f64::MAX, f64::min),
        }
    }

    #[test]
    fn prefix_statistics_equal_the_direct_computation() {
        let mut rng = Rng::new(11);
        let x: Vec<f64> = (0..300).map(|_| rng.next_f32() as f64 * 10.0 - 3.0).collect();
        let prefix = Prefix::new(&x);
        for _ in 0..400 {
            let start = rng.below(290);
            let end = start + 1 + rng.below(299 - start);
            for weighting in [Weighting::Uniform, Weighting::Beginning, Weighting::Middle, Weighting::End] {
                for stat in [Stat::Mean, Stat::Sum, Stat::Max, Stat::Min, Stat::Std] {
                    let (fast, slow) =
                        (prefix.stat(start, end, weighting, stat), direct(&x, start, end, weighting, stat));
                    // a standard deviation near 0 is the square root of a difference of sums: its
                    // rounding shows (1e-5 on values of 10); everything else agrees to 1e-9
                    let ok = match stat {
                        Stat::Std => (fast - slow).abs() < 1e-4,
                        _ => close(fast, slow, 1e-9),
                    };
                    assert!(ok, "{start}..={end} {weighting:?} {stat:?}: {fast} vs {slow}");
                }
            }
        }
        // tables built for short segments still answer long ones
        let short = Prefix::up_to(&x, 20);
        for (start, end) in [(0, 299), (3, 90), (17, 40), (5, 25), (100, 100)] {
            for stat in [Stat::Max, Stat::Min] {
                assert_eq!(
                    short.stat(start, end, Weighting::Uniform, stat),
                    direct(&x, start, end, Weighting::Uniform, stat)
                );
            }
        }
        // a one-frame segment: its value, whatever the weighting's shape
        assert_eq!(prefix.stat(7, 7, Weighting::Uniform, Stat::Mean), x[7]);
        assert_eq!(prefix.stat(7, 7, Weighting::Uniform, Stat::Max), x[7]);
    }
}

#[cfg(test)]
mod pool_tests {
    use super::tests::close;
    use super::*;
    use crate::methods::lma::body::{Arm, Side};
    use glam::DVec3;

    #[test]
    fn the_pool_reads_an_analytic_stroke() {
        // the hand moves along x at 2 bones/s, the elbow stays, the shoulder sits 1 bone up
        let frames = 61;
        let hand: Vec<DVec3> = (0..frames).map(|t| DVec3::new(2.0 * t as f64 / 30.0, 0.0, 0.5)).collect();
        let arm = Arm {
            side: Side::Right,
            joints: [vec![DVec3::Y; frames], vec![DVec3::ZERO; frames], hand],
            head: vec![DVec3::Y * 1.5; frames],
            torso: vec![DVec3::Y; frames],
        };
        let pool = Pool::of(&arm, 30.0, 40);
        let index = |joint: usize, quantity: &str, stat: (Weighting, Stat)| {
            let q = QUANTITIES.iter().position(|&n| n == quantity).unwrap();
            let s = STATISTICS.iter().position(|&x| x == stat).unwrap();
            (joint * QUANTITIES.len() + q) * STATISTICS.len() + s
        };
        let speed_max = index(2, "speed", (Weighting::Uniform, Stat::Max));
        assert!((pool.feature(speed_max, 10, 50) - 2.0).abs() < 1e-9);
        assert_eq!(Pool::name(speed_max), "hand speed, max");
        let x_end = index(2, "x", (Weighting::End, Stat::Mean));
        assert_eq!(Pool::name(x_end), "hand x, mean (end)");
        // the end-weighted mean of a linear ramp lies past its middle
        let mid = 2.0 * 30.0 / 30.0;
        assert!(pool.feature(x_end, 10, 50) > mid + 0.1);
        let shoulder_height = index(0, "y", (Weighting::Middle, Stat::Std));
        assert!(pool.feature(shoulder_height, 0, 60).abs() < 1e-6);
        let mut out = vec![0.0f32; 2];
        pool.features(&[speed_max as u16, x_end as u16], 10, 50, &mut out);
        assert_eq!(out[0], pool.feature(speed_max, 10, 50) as f32);
        assert_eq!(POOL_SIZE, 45 * 14);
    }

    /// The plan's batched statistics are the per-feature ones: random feature sets (repeats and
    /// all four weightings of a series among them), random segments of a random arm.
    #[test]
    fn a_plan_fills_the_features_one_at_a_time_would_give() {
        let mut rng = crate::stats::Rng::new(29);
        let frames = 400;
        let mut walk = |scale: f64| {
            let mut p = DVec3::ZERO;
            (0..frames)
                .map(|_| {
                    p += DVec3::new(
                        rng.next_f32() as f64 - 0.5,
                        rng.next_f32() as f64 - 0.5,
                        rng.next_f32() as f64 - 0.5,
                    ) * scale;
                    p
                })
                .collect::<Vec<_>>()
        };
        let arm = Arm {
            side: Side::Right,
            joints: [walk(0.01), walk(0.05), walk(0.1)],
            head: walk(0.02),
            torso: walk(0.01).iter().map(|d| (*d + DVec3::Y).normalize()).collect(),
        };
        let pool = Pool::of(&arm, 30.0, 111);
        for round in 0..20 {
            let count = 1 + rng.below(if round == 0 { POOL_SIZE } else { 120 });
            let which: Vec<u16> = if round == 0 {
                (0..POOL_SIZE as u16).collect()
            } else {
                (0..count).map(|_| rng.below(POOL_SIZE) as u16).collect()
            };
            let plan = Plan::new(which.iter().copied());
            let mut out = vec![[f64::NAN]; plan.len()];
            for _ in 0..50 {
                let start = rng.below(frames - 2);
                let end = (start + rng.below(120)).min(frames - 1);
                pool.fill(&plan, [(start, end)], &mut out);
                for &k in &which {
                    let (fast, slow) = (out[plan.slot(k).unwrap()][0], pool.feature(k as usize, start, end));
                    assert!(
                        close(fast, slow, 1e-12),
                        "{} of {start}..={end}: {fast} vs {slow}",
                        Pool::name(k as usize)
                    );
                }
            }
        }
        assert_eq!(Plan::new([5, 5, 3]).len(), 2);
        assert_eq!(Plan::new([5, 5, 3]).slot(4), None);
    }

    /// The orientations of an analytic pose: the upper arm hanging, the forearm swinging forwards
    /// and up about the elbow at 1 rad/s, the torso leaning 0.3 rad forwards and the head tilted.
    #[test]
    fn the_pool_reads_the_orientations_of_the_arm_and_the_upper_body() {
        let (frames, fps) = (61, 30.0);
        let turn = |t: usize| t as f64 / fps; // the forearm's angle from hanging, 1 rad/s
        let shoulder = DVec3::new(-0.8, 0.0, 0.0);
        let elbow = shoulder - DVec3::Y;
        let hand: Vec<DVec3> = (0..frames).map(|t| elbow + DVec3::new(0.0, -turn(t).cos(), turn(t).sin())).collect();
        let lean = DVec3::new(0.0, 0.3f64.cos(), 0.3f64.sin());
        let arm = Arm {
            side: Side::Right,
            joints: [vec![shoulder; frames], vec![elbow; frames], hand],
            head: vec![lean * 1.5 + DVec3::new(-0.2, 0.0, 0.0); frames],
            torso: vec![lean; frames],
        };
        let pool = Pool::of(&arm, fps, 40);
        let index = |series: &str, stat: (Weighting, Stat)| {
            let k = (0..SERIES).position(|k| series_name(k) == series).unwrap();
            k * STATISTICS.len() + STATISTICS.iter().position(|&x| x == stat).unwrap()
        };
        let read = |series: &str, stat: (Weighting, Stat)| pool.feature(index(series, stat), 10, 50);
        let (mean, max) = ((Weighting::Uniform, Stat::Mean), (Weighting::Uniform, Stat::Max));
        // the flexion is the forearm's angle from the upper arm's line: 10/30 ..= 50/30 rad, 1 rad/s
        assert!((read("elbow flexion", mean) - 1.0).abs() < 1e-9);
        assert!((read("elbow flexion", max) - 50.0 / 30.0).abs() < 1e-9);
        assert!((read("elbow flexion speed", mean) - 1.0).abs() < 1e-6);
        assert!((read("forearm angular speed", mean) - 1.0).abs() < 1e-3);
        assert!((read("forearm elevation", mean) - 1.0).abs() < 1e-9);
        assert!(read("shoulder elevation", max).abs() < 1e-9 && read("upper arm angular speed", max).abs() < 1e-9);
        assert!((read("torso lean", mean) - 0.3).abs() < 1e-9 && (read("torso forward lean", mean) - 0.3).abs() < 1e-9);
        assert!(read("torso side lean", max).abs() < 1e-9 && read("torso angular speed", max).abs() < 1e-9);
        // the head sits off the torso's line towards this arm (−x); the shoulder level with the sternum
        assert!(read("head tilt", mean) > 0.05 && read("head x", mean) < -0.1);
        assert!(read("torso twist", mean).abs() < 1e-9);
        let name = Pool::name(index("elbow flexion", (Weighting::Beginning, Stat::Mean)));
        assert_eq!(name, "elbow flexion, mean (beginning)");
        assert_eq!(Pool::name(index("head y", max)), "head y, max");
        // leaning towards this arm's side (−x) and its shoulder forwards are positive
        let side = DVec3::new(-0.2f64.sin(), 0.2f64.cos(), 0.0);
        let turned = Arm {
            torso: vec![side; frames],
            joints: [vec![DVec3::new(-0.8, 0.0, 0.3); frames], arm.joints[1].clone(), arm.joints[2].clone()],
            ..arm
        };
        let pool = Pool::of(&turned, fps, 40);
        assert!((pool.feature(index("torso side lean", mean), 0, 60) - 0.2).abs() < 1e-9);
        assert!((pool.feature(index("torso twist", mean), 0, 60) - 0.3f64.atan2(0.8)).abs() < 1e-9);
    }
}
