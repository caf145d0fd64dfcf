//! Effort descriptors that can be computed from motion, the training labels of the Effort
//! classifiers here: Bouchard & Badler trained on an expert-labelled corpus that is not public,
//! so their labels are replaced by published computable Laban descriptors (Larboulette & Gibet
//! 2015; Samadani et al. 2013), each cut into three classes by terciles over a corpus of segments.
//!
//! | factor | descriptor of a segment | condensing (high) | indulging (low) |
//! |---|---|---|---|
//! | Weight | peak kinetic energy of the hands (unit masses) | Strong | Light |
//! | Time | peak hand acceleration | Sudden | Sustained |
//! | Space | directness of the more travelled hand: chord / path length | Direct | Indirect |
//! | Flow | mean hand jerk | Bound | Free |
//!
//! Reading high mean jerk as Bound (restrained, interrupted) and low as Free (fluent) is this
//! module's convention; the other three follow the factors' definitions. Every descriptor of any
//! candidate segment costs O(1) from [`Prefix`] tables built once per take.

use glam::DVec3;

use super::features::{Kinematics, Prefix, Stat, Weighting};

/// The four Effort factors.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Factor {
    Space,
    Time,
    Weight,
    Flow,
}

impl Factor {
    pub const ALL: [Factor; 4] = [Factor::Space, Factor::Time, Factor::Weight, Factor::Flow];

    pub fn name(self) -> &'static str {
        match self {
            Factor::Space => "space",
            Factor::Time => "time",
            Factor::Weight => "weight",
            Factor::Flow => "flow",
        }
    }
}

/// An Effort element of one factor.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Element {
    Indulging,
    Neutral,
    Condensing,
}

impl Element {
    pub const ALL: [Element; 3] = [Element::Indulging, Element::Neutral, Element::Condensing];

    /// Reads `indulging`, `neutral` or `condensing` (any case).
    pub fn parse(text: &str) -> Option<Element> {
        Element::ALL.into_iter().find(|e| e.name().eq_ignore_ascii_case(text.trim()))
    }

    pub fn name(self) -> &'static str {
        match self {
            Element::Indulging => "indulging",
            Element::Neutral => "neutral",
            Element::Condensing => "condensing",
        }
    }
}

/// The four descriptors of a segment (see the module table).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Descriptors {
    pub space: f64,
    pub time: f64,
    pub weight: f64,
    pub flow: f64,
}

/// One hand's tables: kinetic energy, acceleration, jerk, step lengths, and its positions.
struct Hand {
    energy: Prefix,
    acceleration: Prefix,
    jerk: Prefix,
    /// `steps[t]` = distance from frame `t − 1` to `t` (0 at frame 0).
    steps: Prefix,
    positions: Vec<DVec3>,
}

impl Descriptors {
    /// The descriptors in the order of [`Factor::ALL`].
    pub fn values(&self) -> [f64; 4] {
        [self.space, self.time, self.weight, self.flow]
    }
}

/// Descriptor tables of a take: both hands' trajectories (relative to the torso) at `fps`.
pub struct EffortTables {
    hands: Vec<Hand>,
    frames: usize,
}

impl EffortTables {
    /// Tables for the hands' trajectories (each one position per frame, all as long).
    pub fn new(hands: &[Vec<DVec3>], fps: f64) -> EffortTables {
        let frames = hands.iter().map(Vec::len).min().unwrap_or(0);
        let hands = hands
            .iter()
            .map(|p| {
                let k = Kinematics::of(p, fps);
                let energy: Vec<f64> = k.speed.iter().map(|v| 0.5 * v * v).collect();
                let steps: Vec<f64> =
                    (0..p.len()).map(|t| if t == 0 { 0.0 } else { p[t].distance(p[t - 1]) }).collect();
                Hand {
                    energy: Prefix::new(&energy),
                    acceleration: Prefix::new(&k.acceleration),
                    jerk: Prefix::new(&k.jerk),
                    steps: Prefix::new(&steps),
                    positions: p.clone(),
                }
            })
            .collect();
        EffortTables { hands, frames }
    }

    /// Number of frames.
    pub fn frames(&self) -> usize {
        self.frames
    }

    /// The descriptors of frames `start..=end` (`start < end < frames`), in O(1).
    pub fn descriptors(&self, start: usize, end: usize) -> Descriptors {
        let max = |p: &Prefix| p.stat(start, end, Weighting::Uniform, Stat::Max);
        let weight = self.hands.iter().map(|h| max(&h.energy)).sum();
        let time = self.hands.iter().map(|h| max(&h.acceleration)).fold(0.0, f64::max);
        let flow = self.hands.iter().map(|h| h.jerk.stat(start, end, Weighting::Uniform, Stat::Mean)).sum::<f64>()
            / self.hands.len().max(1) as f64;
        // the path from `start` to `end` is the sum of the steps into frames start+1..=end
        let path = |h: &Hand| h.steps.stat(start + 1, end, Weighting::Uniform, Stat::Sum);
        let space = self.hands.iter().max_by(|a, b| path(a).total_cmp(&path(b))).map_or(1.0, |h| {
            let p = path(h);
            if p > 1e-9 {
                (h.positions[end].distance(h.positions[start]) / p).min(1.0)
            } else {
                1.0
            }
        });
        Descriptors { space, time, weight, flow }
    }
}

/// The two terciles of `values` (the values a third and two thirds of the way up), `None` if empty.
pub fn terciles(values: &[f64]) -> Option<(f64, f64)> {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let at = |q: f64| v[((v.len() - 1) as f64 * q).round() as usize];
    Some((at(1.0 / 3.0), at(2.0 / 3.0)))
}

/// The element of `value` given the terciles: below the first indulging, above the second condensing.
pub fn element(value: f64, (low, high): (f64, f64)) -> Element {
    if value < low {
        Element::Indulging
    } else if value > high {
        Element::Condensing
    } else {
        Element::Neutral
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const FPS: f64 = 30.0;

    fn still(frames: usize) -> Vec<DVec3> {
        vec![DVec3::new(0.1, 0.2, 0.3); frames]
    }

    #[test]
    fn a_straight_stroke_is_direct_and_an_arc_is_not() {
        let line: Vec<DVec3> = (0..31).map(|t| DVec3::new(t as f64 / 30.0, 0.0, 0.0)).collect();
        let arc: Vec<DVec3> = (0..31)
            .map(|t| std::f64::consts::PI * t as f64 / 30.0)
            .map(|a| DVec3::new(0.5 * (1.0 - a.cos()), 0.5 * a.sin(), 0.0))
            .collect();
        let straight = EffortTables::new(&[line, still(31)], FPS).descriptors(0, 30);
        assert!((straight.space - 1.0).abs() < 1e-9, "{straight:?}");
        let round = EffortTables::new(&[arc, still(31)], FPS).descriptors(0, 30);
        // a half circle of diameter 1: chord 1, path π/2 (to the polygon's precision)
        assert!((round.space - 2.0 / std::f64::consts::PI).abs() < 1e-3, "{round:?}");
    }

    #[test]
    fn faster_harder_and_jerkier_motion_scores_higher() {
        let stroke = |speed: f64| (0..61).map(|t| DVec3::new(speed * t as f64 / FPS, 0.0, 0.0)).collect::<Vec<_>>();
        let slow = EffortTables::new(&[stroke(1.0), still(61)], FPS).descriptors(5, 55);
        let fast = EffortTables::new(&[stroke(2.0), still(61)], FPS).descriptors(5, 55);
        assert!((slow.weight - 0.5).abs() < 1e-9 && (fast.weight - 2.0).abs() < 1e-9, "{slow:?} {fast:?}");
        // a sudden start (a step in speed) against a constant speed
        let mut sudden = stroke(1.0);
        for p in sudden.iter_mut().skip(30) {
            p.x += (p.x - 1.0) * 2.0;
        }
        let calm = EffortTables::new(&[stroke(1.0), still(61)], FPS).descriptors(5, 55);
        let jolt = EffortTables::new(&[sudden, still(61)], FPS).descriptors(5, 55);
        assert!(jolt.time > calm.time + 10.0, "{calm:?} {jolt:?}");
        assert!(jolt.flow > calm.flow, "{calm:?} {jolt:?}");
        assert!(calm.time.abs() < 1e-9 && calm.flow.abs() < 1e-9);
    }

    #[test]
    fn terciles_cut_three_classes() {
        let values: Vec<f64> = (0..9).map(f64::from).collect();
        let t = terciles(&values).unwrap();
        assert_eq!(t, (3.0, 5.0));
        assert_eq!(element(1.0, t), Element::Indulging);
        assert_eq!(element(4.0, t), Element::Neutral);
        assert_eq!(element(8.0, t), Element::Condensing);
        assert_eq!(terciles(&[]), None);
        assert_eq!(terciles(&[f64::NAN, 2.0]), Some((2.0, 2.0)));
    }
}
