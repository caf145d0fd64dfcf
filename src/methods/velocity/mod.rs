//! Hand-speed segmentation: the kinematic baseline Bouchard & Badler compare LMA with (their
//! §5.1, "the velocity method from Osaki et al. [2000] and Shiratori et al. [2003] … defines
//! boundaries as hand linear velocity local minima below some threshold and segment maximal
//! velocity above another threshold").
//!
//! 1. [`crate::features::end_effectors`]: both hands relative to the hips, facing-aligned, in
//!    inches of the reference body, at the working rate (30 Hz);
//! 2. [`hand_speed`]: each hand's linear speed (central differences), Gaussian-smoothed;
//! 3. [`boundaries`]: per hand, every local speed minimum below `low_speed` is a candidate; a
//!    candidate is kept when the hand was faster than `high_speed` somewhere since the last kept
//!    boundary (so every segment holds a real movement); the two hands' boundaries are merged
//!    where they lie within `merge_s` of each other ([`crate::segment::cuts::merge`]);
//! 4. one segment (level `primitive`, label `gesture`) between consecutive boundaries, its
//!    `score` the highest hand speed inside it (inches per second, reference body).
//!
//! The thresholds are in speeds of a body the size of CMU subject 86 (`body_scale`), so they
//! mean the same for every skeleton and unit. Their defaults come from what hands do, not from
//! tuning on labelled takes: at rest a hand drifts below 0.3 m/s (12 in/s); a gesture's stroke
//! passes 0.75 m/s (30 in/s).

pub mod method;

use serde::{Deserialize, Serialize};

use crate::features::kinematics::{points, Kinematics};
use crate::features::FeatureMatrix;
use crate::method::bounds::{self, NumberParam, Valid};
use crate::method::unsupervised::Checkable;
use crate::method::{Cancelled, MethodError};
use crate::segment::cuts;

/// Parameters of the hand-speed segmentation (see the module documentation).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct VelocityParams {
    /// Frame rate the method works at; takes are resampled to it.
    pub fps: f64,
    /// Scale every take to the reference body size (thresholds in reference inches per second).
    pub body_scale: bool,
    /// Standard deviation (seconds) of the Gaussian that smooths the speeds (0 = none).
    pub smooth_s: f64,
    /// A local speed minimum below this (inches per second) is a boundary candidate.
    pub low_speed: f64,
    /// A segment must reach this hand speed (inches per second) somewhere.
    pub high_speed: f64,
    /// Boundaries (of either hand) closer than this many seconds are merged into one.
    pub merge_s: f64,
}

impl Default for VelocityParams {
    fn default() -> Self {
        VelocityParams { fps: 30.0, body_scale: true, smooth_s: 0.1, low_speed: 12.0, high_speed: 30.0, merge_s: 0.3 }
    }
}

/// [`VelocityParams`] that passed [`VelocityParams::check`].
pub type ValidParams = Valid<VelocityParams>;

/// Every numeric parameter: range, unit, help.
pub const PARAMS: [NumberParam; 5] = [
    bounds::WORKING_FPS,
    NumberParam {
        name: "smooth_s",
        min: 0.0,
        max: 1.0,
        unit: "s",
        help: "Standard deviation of the Gaussian that smooths the hand speeds (0 = none).",
        basic: false,
    },
    NumberParam {
        name: "low_speed",
        min: 0.1,
        max: 1000.0,
        unit: "in/s",
        help: "A local minimum of a hand's speed below this is a boundary candidate.",
        basic: true,
    },
    NumberParam {
        name: "high_speed",
        min: 0.1,
        max: 2000.0,
        unit: "in/s",
        help: "A segment must reach this hand speed somewhere (at least low_speed).",
        basic: true,
    },
    NumberParam {
        name: "merge_s",
        min: 0.0,
        max: 2.0,
        unit: "s",
        help: "Boundaries of either hand closer than this are merged into one.",
        basic: true,
    },
];

impl VelocityParams {
    pub(crate) fn value(&self, name: &str) -> f64 {
        match name {
            "fps" => self.fps,
            "smooth_s" => self.smooth_s,
            "low_speed" => self.low_speed,
            "high_speed" => self.high_speed,
            _ => self.merge_s,
        }
    }
}

/// Validates every parameter; the method only ever runs on the result.
impl Checkable for VelocityParams {
    type Valid = ValidParams;

    fn check(self) -> Result<ValidParams, MethodError> {
        bounds::check("velocity", &PARAMS, |n| self.value(n))?;
        if self.high_speed < self.low_speed {
            let expected = format!("at least low_speed ({})", self.low_speed);
            return Err(bounds::refuse("velocity", "high_speed", self.high_speed, &expected));
        }
        Ok(Valid::checked(self))
    }
}

/// The linear speed (feature units per second) of the point in columns `col..col + 3` of
/// `features` at `fps`: central differences, one-sided at the ends, then a Gaussian of `sigma_s`
/// seconds (none below half a frame).
pub fn hand_speed(features: &FeatureMatrix, col: usize, fps: f64, sigma_s: f64) -> Vec<f32> {
    let raw = Kinematics::speed(&points(features, col), fps);
    crate::stats::gaussian_smooth(&raw, sigma_s * fps).into_iter().map(|v| v as f32).collect()
}

/// One hand's boundaries: local minima of `speed` below `low`, each kept when the speed passed
/// `high` since the last kept one (or the start).
pub fn hand_boundaries(speed: &[f32], low: f32, high: f32) -> Vec<usize> {
    let mut kept = Vec::new();
    let mut peak = 0.0f32;
    for t in 0..speed.len() {
        peak = peak.max(speed[t]);
        let is_min = t > 0 && t + 1 < speed.len() && speed[t] <= speed[t - 1] && speed[t] < speed[t + 1];
        if is_min && speed[t] < low && peak >= high {
            kept.push(t);
            peak = speed[t];
        }
    }
    kept
}

/// The segmentation of hand-speed curves (one per hand, same length): the boundaries (first frames
/// of every segment after the first), reporting progress.
pub fn boundaries(
    speeds: &[Vec<f32>],
    params: &ValidParams,
    progress: &mut dyn FnMut(&str, f64) -> Result<(), Cancelled>,
) -> Result<Vec<usize>, Cancelled> {
    let mut all = Vec::new();
    for (k, s) in speeds.iter().enumerate() {
        progress("boundaries", 0.5 + 0.4 * k as f64 / speeds.len().max(1) as f64)?;
        all.extend(hand_boundaries(s, params.low_speed as f32, params.high_speed as f32));
    }
    let merge = (params.merge_s * params.fps).round() as usize;
    let frames = speeds.first().map_or(0, Vec::len);
    Ok(cuts::merge(all, merge).into_iter().filter(|&b| b > 0 && b < frames).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn speed_of_a_point_at_constant_speed_is_that_speed() {
        // 2 inches per frame along x at 30 Hz = 60 in/s, with and without smoothing
        let rows: Vec<[f32; 3]> = (0..40).map(|i| [2.0 * i as f32, 5.0, -1.0]).collect();
        let m = FeatureMatrix::from_rows(&rows).unwrap();
        for sigma in [0.0, 0.1] {
            let s = hand_speed(&m, 0, 30.0, sigma);
            assert_eq!(s.len(), 40);
            assert!(s.iter().all(|v| (v - 60.0).abs() < 1e-3), "{s:?}");
        }
        // uniform acceleration: the central difference is exact at every inner frame
        let rows: Vec<[f32; 3]> = (0..20).map(|i| [0.0, 0.5 * (i * i) as f32, 0.0]).collect();
        let s = hand_speed(&FeatureMatrix::from_rows(&rows).unwrap(), 0, 10.0, 0.0);
        for (t, v) in s.iter().enumerate().take(19).skip(1) {
            assert!((v - 10.0 * t as f32).abs() < 1e-3, "frame {t}: {v}");
        }
    }

    /// Three strokes (speed bumps up to `peak`) separated by near-stops at frames 30 and 60.
    fn strokes(peak: f32, stop: f32) -> Vec<f32> {
        (0..90)
            .map(|t| {
                let phase = (t % 30) as f32 / 30.0;
                stop + (peak - stop) * (std::f32::consts::PI * phase).sin()
            })
            .collect()
    }

    #[test]
    fn minima_below_low_after_a_peak_above_high_are_boundaries() {
        assert_eq!(hand_boundaries(&strokes(50.0, 2.0), 12.0, 30.0), vec![30, 60]);
        // stops that are not slow enough, or strokes that are not fast enough, cut nothing
        assert!(hand_boundaries(&strokes(50.0, 15.0), 12.0, 30.0).is_empty());
        assert!(hand_boundaries(&strokes(25.0, 2.0), 12.0, 30.0).is_empty());
        // a slow wiggle instead of the second stroke: its minima (and the stop at 60) follow no fast
        // movement, so only the first stop cuts
        let mut s = strokes(50.0, 2.0);
        s[33..59].iter_mut().enumerate().for_each(|(k, v)| *v = 3.0 + 5.0 * (k as f32 * 0.5).sin().abs());
        assert_eq!(hand_boundaries(&s, 12.0, 30.0), vec![30]);
    }

    #[test]
    fn parameters_are_checked_on_both_sides() {
        assert!(VelocityParams::default().check().is_ok());
        let bad = |p: VelocityParams| p.check().unwrap_err().to_string();
        assert!(bad(VelocityParams { low_speed: 0.0, ..Default::default() }).contains("low_speed"));
        assert!(bad(VelocityParams { high_speed: 1e300, ..Default::default() }).contains("high_speed = 1e300"));
        assert!(bad(VelocityParams { high_speed: 5.0, ..Default::default() }).contains("at least low_speed"));
        assert!(bad(VelocityParams { smooth_s: f64::NAN, ..Default::default() }).contains("smooth_s"));
        assert!(bad(VelocityParams { fps: 5.0, ..Default::default() }).contains("10 to 240 Hz"));
    }

    #[test]
    fn a_cancel_stops_the_boundary_search() {
        let p = VelocityParams::default().check().unwrap();
        let speeds = vec![strokes(50.0, 2.0), strokes(50.0, 2.0)];
        let r = boundaries(&speeds, &p, &mut |_, _| Err(Cancelled));
        assert_eq!(r, Err(Cancelled));
        let r = boundaries(&speeds, &p, &mut |_, _| Ok(())).unwrap();
        assert_eq!(r, vec![30, 60]);
    }
}
