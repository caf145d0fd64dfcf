//! Length units and up axis of a take, detected from the size and geometry of the body
//! (CMU units, centimetres, metres or inches; Y-up or Z-up).
//!
//! BVH files carry no unit field, so the units are inferred from how big a human body is in
//! them:
//!
//! * **Body measure.** If the skeleton maps onto the canonical joints ([`super::joints`]) the
//!   measure is the *leg length*: the bone lengths from hip to knee to ankle, averaged over both
//!   legs (bone lengths are OFFSET norms, so the pose does not matter). An adult's is about
//!   [`NOMINAL_LEG_M`] = 0.85 m (a standing hip height of about 0.95 m). Otherwise it is the
//!   *body extent*: the largest axis-aligned extent of all nodes, median over up to 32 frames
//!   spread over the take, compared with [`NOMINAL_EXTENT_M`] = 1.7 m (height or arm span).
//! * **Units.** Each candidate unit turns the measure into metres; the one whose result is
//!   closest to the nominal size on a log scale wins. With the leg length the decision
//!   boundaries are (in file units): metres < 3.6 ≤ CMU ASF units (1 unit = 0.056444 m, hip
//!   height ≈ 17.5) < 22.4 ≤ inches < 53.3 ≤ centimetres < 269 ≤ millimetres. A result more
//!   than 1.6× away from the nominal size adds a warning (unusual body size or unknown units).
//! * **Up axis.** With canonical joints: the vector from the midpoint of the two feet to the
//!   head, median per axis over the sampled frames; the larger of its |Y| and |Z| components is
//!   up (the body extends along the vertical, gravity keeps the head above the feet). A
//!   negative component (upside down) or a dominant X component adds a warning. Without
//!   canonical joints: the larger of the median Y and Z extents, with a warning that it is a
//!   guess.

use super::joints::{map_joints, JointMap};
use super::Skeleton;
use glam::Vec3;
use serde::{Deserialize, Serialize};

/// Metres per CMU ASF length unit: (1/0.45) inch = 2.54/45 m = 0.056444 m (CMU mocap FAQ;
/// and the data README).
pub const CMU_ASF_METRES: f64 = 0.056444;
/// Typical adult leg length (hip joint → knee → ankle), metres.
pub const NOMINAL_LEG_M: f64 = 0.85;
/// Typical adult height or arm span, metres.
pub const NOMINAL_EXTENT_M: f64 = 1.7;
/// A measured body size further than this factor from nominal triggers a warning.
pub const UNUSUAL_FACTOR: f64 = 1.6;
/// Number of frames (evenly spread over the take) examined for geometry.
pub const SAMPLE_FRAMES: usize = 32;

/// Length units of a BVH file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Units {
    /// CMU ASF units: 1 unit = 0.056444 m (standing hip height ≈ 17.5 units).
    CmuAsf,
    Millimetres,
    Centimetres,
    Metres,
    Inches,
}

impl Units {
    pub const ALL: [Units; 5] = [Units::Metres, Units::CmuAsf, Units::Inches, Units::Centimetres, Units::Millimetres];

    /// Length of one unit in metres.
    pub fn metres_per_unit(self) -> f64 {
        match self {
            Units::CmuAsf => CMU_ASF_METRES,
            Units::Millimetres => 0.001,
            Units::Centimetres => 0.01,
            Units::Metres => 1.0,
            Units::Inches => 0.0254,
        }
    }

    /// Stable identifier, identical to the serde form (`"cmu_asf"`, `"centimetres"`, …).
    pub fn name(self) -> &'static str {
        match self {
            Units::CmuAsf => "cmu_asf",
            Units::Millimetres => "millimetres",
            Units::Centimetres => "centimetres",
            Units::Metres => "metres",
            Units::Inches => "inches",
        }
    }

    /// Human-readable name for summaries.
    pub fn label(self) -> &'static str {
        match self {
            Units::CmuAsf => "CMU ASF units (1 unit = 0.056444 m)",
            Units::Millimetres => "millimetres",
            Units::Centimetres => "centimetres",
            Units::Metres => "metres",
            Units::Inches => "inches",
        }
    }

    /// Parse a [`Units::name`].
    pub fn from_name(s: &str) -> Option<Units> {
        Units::ALL.into_iter().find(|u| u.name() == s)
    }
}

impl std::fmt::Display for Units {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.label())
    }
}

/// Which file axis points up.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum UpAxis {
    Y,
    Z,
}

impl UpAxis {
    pub fn name(self) -> &'static str {
        match self {
            UpAxis::Y => "Y",
            UpAxis::Z => "Z",
        }
    }

    /// Index of the axis (1 = Y, 2 = Z).
    pub fn index(self) -> usize {
        match self {
            UpAxis::Y => 1,
            UpAxis::Z => 2,
        }
    }
}

impl std::fmt::Display for UpAxis {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// What [`detect`] found and how.
#[derive(Debug, Clone, PartialEq)]
pub struct UnitDetection {
    pub units: Units,
    pub up_axis: UpAxis,
    /// The body measure in file units (leg length or body extent, see `measure_is_leg`).
    pub measure: f64,
    /// True if `measure` is the leg length, false if it is the body extent.
    pub measure_is_leg: bool,
    /// Warnings worth showing the user (guesses, unusual sizes).
    pub notes: Vec<String>,
}

/// Indices of up to [`SAMPLE_FRAMES`] frames spread evenly over `frames`.
pub fn sample_frames(frames: usize) -> Vec<usize> {
    if frames <= SAMPLE_FRAMES {
        return (0..frames).collect();
    }
    (0..SAMPLE_FRAMES).map(|k| k * (frames - 1) / (SAMPLE_FRAMES - 1)).collect()
}

/// The median (the mean of the two middle values for an even count; 0 if empty).
fn median(mut v: Vec<f64>) -> f64 {
    crate::stats::median_midpoint(&mut v).unwrap_or(0.0)
}

/// The unit that makes `measure` (file units) closest to `nominal_m` metres on a log scale.
pub fn units_for_measure(measure: f64, nominal_m: f64) -> Units {
    let score = |u: Units| (measure * u.metres_per_unit() / nominal_m).ln().abs();
    Units::ALL.into_iter().min_by(|a, b| score(*a).total_cmp(&score(*b))).unwrap_or(Units::Metres)
}

/// Mean leg length (hip → knee → ankle bone lengths) in file units.
pub fn leg_length(skeleton: &Skeleton, map: &JointMap) -> f64 {
    let left = skeleton.chain_length(map.left_hip, map.left_foot);
    let right = skeleton.chain_length(map.right_hip, map.right_foot);
    0.5 * (left + right)
}

/// Median over the sampled frames of the largest axis-aligned extent of all nodes.
fn body_extent(positions: &[Vec3], joints: usize) -> (f64, [f64; 3]) {
    let frames = positions.len().checked_div(joints).unwrap_or(0);
    let mut per_axis: [Vec<f64>; 3] = Default::default();
    for f in sample_frames(frames) {
        let frame = &positions[f * joints..(f + 1) * joints];
        let (lo, hi) =
            frame.iter().fold((Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
        let ext = hi - lo;
        for a in 0..3 {
            per_axis[a].push(ext[a] as f64);
        }
    }
    let med = per_axis.map(median);
    (med[0].max(med[1]).max(med[2]), med)
}

/// Median over the sampled frames of (head − mid-feet), per axis.
fn head_over_feet(positions: &[Vec3], joints: usize, map: &JointMap) -> [f64; 3] {
    let frames = positions.len() / joints;
    let mut per_axis: [Vec<f64>; 3] = Default::default();
    for f in sample_frames(frames) {
        let p = |j: usize| positions[f * joints + j];
        let v = p(map.head) - 0.5 * (p(map.left_foot) + p(map.right_foot));
        for a in 0..3 {
            per_axis[a].push(v[a] as f64);
        }
    }
    per_axis.map(median)
}

fn up_from_vector(v: [f64; 3], notes: &mut Vec<String>) -> UpAxis {
    let up = if v[2].abs() > v[1].abs() { UpAxis::Z } else { UpAxis::Y };
    let a = up.index();
    if v[0].abs() > v[a].abs() {
        notes.push(format!(
            "up axis: the body extends mostly along X (head − feet = {:.3}, {:.3}, {:.3}); assuming {up} up",
            v[0], v[1], v[2]
        ));
    }
    if v[a] < 0.0 {
        notes.push(format!("up axis: the head is below the feet along +{up}; the take may be upside down"));
    }
    up
}

/// Detect units and up axis from the skeleton and the world positions of its frames
/// (frame-major, `skeleton.len()` per frame). See the module documentation for the heuristic.
pub fn detect(skeleton: &Skeleton, positions: &[Vec3]) -> UnitDetection {
    let joints = skeleton.len();
    let mut notes = Vec::new();
    let map = map_joints(skeleton).ok();
    let leg = map.as_ref().map(|m| leg_length(skeleton, m)).filter(|l| *l > 0.0);
    let (extent, extents) = body_extent(positions, joints);
    let (measure, nominal, measure_is_leg) = match leg {
        Some(l) => (l, NOMINAL_LEG_M, true),
        None => (extent, NOMINAL_EXTENT_M, false),
    };
    let units = if measure > 0.0 && measure.is_finite() {
        units_for_measure(measure, nominal)
    } else {
        notes.push("units: the skeleton has no size (all offsets and positions zero); assuming metres".into());
        Units::Metres
    };
    if measure > 0.0 && measure.is_finite() {
        let metres = measure * units.metres_per_unit();
        let what = if measure_is_leg { "leg length" } else { "body extent" };
        if !measure_is_leg {
            notes.push(format!(
                "units: joint names not recognised, guessed {} from the body extent ({measure:.3} file units)",
                units.name()
            ));
        }
        if (metres / nominal).ln().abs() > UNUSUAL_FACTOR.ln() {
            notes.push(format!(
                "units: {what} of {measure:.3} file units is {metres:.2} m in {} — unusual for an adult (≈ {nominal} m); units may be wrong",
                units.name()
            ));
        }
    }
    let up_axis = match &map {
        Some(m) if joints > 0 && !positions.is_empty() => {
            up_from_vector(head_over_feet(positions, joints, m), &mut notes)
        }
        _ => {
            notes.push(format!(
                "up axis: joint names not recognised, guessed from the body's extent (Y {:.3}, Z {:.3})",
                extents[1], extents[2]
            ));
            if extents[2] > extents[1] {
                UpAxis::Z
            } else {
                UpAxis::Y
            }
        }
    };
    UnitDetection { units, up_axis, measure, measure_is_leg, notes }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn leg_length_decision_boundaries() {
        let u = |leg: f64| units_for_measure(leg, NOMINAL_LEG_M);
        assert_eq!(u(0.85), Units::Metres);
        assert_eq!(u(3.5), Units::Metres);
        assert_eq!(u(3.7), Units::CmuAsf);
        assert_eq!(u(15.0), Units::CmuAsf);
        assert_eq!(u(22.0), Units::CmuAsf);
        assert_eq!(u(23.0), Units::Inches);
        assert_eq!(u(33.0), Units::Inches);
        assert_eq!(u(53.0), Units::Inches);
        assert_eq!(u(54.0), Units::Centimetres);
        assert_eq!(u(85.0), Units::Centimetres);
        assert_eq!(u(268.0), Units::Centimetres);
        assert_eq!(u(270.0), Units::Millimetres);
        assert_eq!(u(850.0), Units::Millimetres);
    }

    #[test]
    fn sampled_frames_span_the_take() {
        assert_eq!(sample_frames(3), vec![0, 1, 2]);
        let s = sample_frames(1000);
        assert_eq!(s.len(), SAMPLE_FRAMES);
        assert_eq!((s[0], s[SAMPLE_FRAMES - 1]), (0, 999));
        assert!(s.windows(2).all(|w| w[0] < w[1]));
    }

    #[test]
    fn median_of_even_and_odd() {
        assert_eq!(median(vec![3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(vec![4.0, 1.0, 2.0, 3.0]), 2.5);
        assert_eq!(median(vec![]), 0.0);
    }
}
