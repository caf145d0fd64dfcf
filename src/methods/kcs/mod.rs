//! Kinematic Centroid Segmentation (Jenkins & Matarić 2003, 2004), one of the kinematic
//! baselines Bouchard & Badler compare LMA with (their §5.1: "an in-line approach that
//! correlates segment boundaries to locally maximum hand displacement from the torso").
//!
//! Each limb is treated as a pendulum: its *kinematic centroid* is the mean position of its
//! joints (arm: shoulder, elbow, hand; leg: hip, knee, foot), hip-relative and facing-aligned,
//! in inches of the reference body, at 30 Hz ([`crate::features::end_effectors::canonical_joints`]).
//! Scanning forward from a segment's first frame, the centroid's distance from where it was at
//! that frame grows while the limb swings out; the segment ends at the farthest point of the
//! swing, recognised once the distance has dropped `drop` inches below its maximum (a hysteresis
//! that ignores jitter), provided the segment is at least `min_segment_s` long. The next segment
//! starts there. The limbs' cuts are merged where they lie within `merge_s` of each other
//! ([`crate::segment::cuts::merge`]). Arms only by default (the comparison is about gestures);
//! `legs` adds both legs.
//!
//! The defaults come from the sizes involved, not from tuning on labelled takes: 2 inches (5 cm)
//! is above marker jitter and well below a gesture's reach; 0.2 s is the shortest stroke.

pub mod method;

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::features::FeatureMatrix;
use crate::method::bounds::{self, NumberParam, Valid};
use crate::method::unsupervised::Checkable;
use crate::method::{Cancelled, MethodError};
use crate::segment::cuts;

/// Parameters of the kinematic centroid segmentation (see the module documentation).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct KcsParams {
    /// Frame rate the method works at; takes are resampled to it.
    pub fps: f64,
    /// Scale every take to the reference body size (distances in reference inches).
    pub body_scale: bool,
    /// A swing ends once the centroid has come back this many inches from its farthest point.
    pub drop: f64,
    /// Segments shorter than this (seconds) are not cut.
    pub min_segment_s: f64,
    /// Cuts of different limbs closer than this (seconds) are merged into one.
    pub merge_s: f64,
    /// Segment the legs too (not only the arms).
    pub legs: bool,
}

impl Default for KcsParams {
    fn default() -> Self {
        KcsParams { fps: 30.0, body_scale: true, drop: 2.0, min_segment_s: 0.2, merge_s: 0.2, legs: false }
    }
}

/// [`KcsParams`] that passed [`KcsParams::check`].
pub type ValidParams = Valid<KcsParams>;

/// Every numeric parameter: range, unit, help.
pub const PARAMS: [NumberParam; 4] = [
    bounds::WORKING_FPS,
    NumberParam {
        name: "drop",
        min: 0.1,
        max: 100.0,
        unit: "in",
        help: "A swing ends once the limb's centroid has come back this far from its farthest point.",
        basic: true,
    },
    NumberParam {
        name: "min_segment_s",
        min: 0.0,
        max: 10.0,
        unit: "s",
        help: "Segments shorter than this are not cut.",
        basic: true,
    },
    NumberParam {
        name: "merge_s",
        min: 0.0,
        max: 2.0,
        unit: "s",
        help: "Cuts of different limbs closer than this are merged into one.",
        basic: false,
    },
];

impl KcsParams {
    pub(crate) fn value(&self, name: &str) -> f64 {
        match name {
            "fps" => self.fps,
            "drop" => self.drop,
            "min_segment_s" => self.min_segment_s,
            _ => self.merge_s,
        }
    }
}

/// Validates every parameter; the method only ever runs on the result.
impl Checkable for KcsParams {
    type Valid = ValidParams;

    fn check(self) -> Result<ValidParams, MethodError> {
        bounds::check("KCS", &PARAMS, |n| self.value(n))?;
        Ok(Valid::checked(self))
    }
}

/// The mean of the `joints` 3-column points from column `first` on of `features`, in every
/// frame (a limb's kinematic centroid).
pub fn centroid(features: &FeatureMatrix, first: usize, joints: usize) -> Vec<Vec3> {
    (0..features.frames())
        .map(|i| {
            let r = &features.row(i)[first..first + 3 * joints];
            r.chunks_exact(3).map(Vec3::from_slice).sum::<Vec3>() / joints as f32
        })
        .collect()
}

/// One limb's cuts: each segment ends at the farthest point of its centroid's swing from where
/// the segment began, once the distance has dropped `drop` below that farthest point and the
/// segment has at least `min_frames` frames. Also returns, per frame, the distance from the
/// start of the segment it belongs to.
pub fn limb_cuts(centroid: &[Vec3], drop: f32, min_frames: usize) -> (Vec<usize>, Vec<f32>) {
    let n = centroid.len();
    let mut cuts = Vec::new();
    let mut displacement = vec![0.0f32; n];
    let mut start = 0;
    let (mut far, mut far_at) = (0.0f32, 0);
    let mut t = 1;
    while t < n {
        let d = centroid[t].distance(centroid[start]);
        displacement[t] = d;
        if d > far {
            (far, far_at) = (d, t);
        } else if far - d >= drop && far_at - start >= min_frames.max(1) {
            cuts.push(far_at);
            start = far_at;
            (far, far_at) = (0.0, start);
            t = start;
        }
        t += 1;
    }
    (cuts, displacement)
}

/// The cuts of every limb's centroid merged, with each limb's displacement curve.
pub fn segment_limbs(
    centroids: &[Vec<Vec3>],
    params: &ValidParams,
    progress: &mut dyn FnMut(&str, f64) -> Result<(), Cancelled>,
) -> Result<(Vec<usize>, Vec<Vec<f32>>), Cancelled> {
    let min_frames = (params.min_segment_s * params.fps).round() as usize;
    let mut all = Vec::new();
    let mut curves = Vec::new();
    for (k, c) in centroids.iter().enumerate() {
        progress("swings", 0.4 + 0.5 * k as f64 / centroids.len().max(1) as f64)?;
        let (limb, displacement) = limb_cuts(c, params.drop as f32, min_frames);
        all.extend(limb);
        curves.push(displacement);
    }
    let merge = (params.merge_s * params.fps).round() as usize;
    let n = centroids.first().map_or(0, Vec::len);
    Ok((cuts::merge(all, merge).into_iter().filter(|&c| c > 0 && c < n).collect(), curves))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stats::Rng;

    /// A limb swinging out and back along x: `amplitude · |sin(π t / 30)|`, extremes every 15 frames.
    fn swings(frames: usize, amplitude: f32) -> Vec<Vec3> {
        (0..frames)
            .map(|t| Vec3::new(amplitude * (std::f32::consts::PI * t as f32 / 30.0).sin().abs(), 10.0, 0.0))
            .collect()
    }

    #[test]
    fn a_pendulum_is_cut_at_the_far_end_of_every_swing() {
        let (cuts, displacement) = limb_cuts(&swings(91, 12.0), 2.0, 6);
        // out to the far point (15), back to the start (30: farthest from 15), out again (45), …
        assert_eq!(cuts, vec![15, 30, 45, 60, 75]);
        assert!((displacement[15] - 12.0).abs() < 1e-4 && displacement[16] < 12.0);
    }

    #[test]
    fn jitter_below_the_drop_and_short_segments_cut_nothing() {
        let mut rng = Rng::new(5);
        let still: Vec<Vec3> = (0..200).map(|_| Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32())).collect();
        assert!(limb_cuts(&still, 2.0, 6).0.is_empty(), "jitter of 1 inch");
        // swings of 15 frames cannot be cut into segments of at least 20
        let (cuts, _) = limb_cuts(&swings(91, 12.0), 2.0, 20);
        assert!(cuts.windows(2).all(|w| w[1] - w[0] >= 20), "{cuts:?}");
        assert!(cuts.first().is_none_or(|&c| c >= 20), "{cuts:?}");
    }

    #[test]
    fn the_centroid_is_the_mean_of_the_joints() {
        let m = FeatureMatrix::from_rows(&[[9.0f32, 0.0, 0.0, 0.0, 2.0, 4.0, 6.0, 4.0, 2.0, 0.0]]).unwrap();
        assert_eq!(centroid(&m, 1, 3), vec![Vec3::splat(2.0)]);
    }

    #[test]
    fn limbs_merge_and_a_cancel_stops() {
        let p = KcsParams::default().check().unwrap();
        let limbs = vec![swings(91, 12.0), swings(91, 12.0)];
        let (cuts, curves) = segment_limbs(&limbs, &p, &mut |_, _| Ok(())).unwrap();
        assert_eq!(cuts, vec![15, 30, 45, 60, 75]);
        assert_eq!(curves.len(), 2);
        assert_eq!(segment_limbs(&limbs, &p, &mut |_, _| Err(Cancelled)).err(), Some(Cancelled));
    }

    #[test]
    fn parameters_are_checked_on_both_sides() {
        let bad = |p: KcsParams| p.check().unwrap_err().to_string();
        assert!(bad(KcsParams { drop: 0.0, ..Default::default() }).contains("drop = 0"));
        assert!(bad(KcsParams { drop: 1e300, ..Default::default() }).contains("drop = 1e300"));
        assert!(bad(KcsParams { merge_s: -1.0, ..Default::default() }).contains("0 to 2 s"));
        assert!(bad(KcsParams { fps: f64::INFINITY, ..Default::default() }).contains("fps"));
    }
}
