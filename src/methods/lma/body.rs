//! The normalised upper body the Effort classifiers see (Bouchard & Badler §4): "the marker
//! locations are translated such that the sternum marker is located at the origin and rotated
//! about the vertical axis so that the sagittal planes are aligned", then "scaled by a factor
//! estimated by averaging distances between joints that remain fairly constant, such as the elbow
//! and the shoulder".
//!
//! Here: the canonical chest joint is the sternum; the facing alignment is the one every method
//! shares ([`crate::features::end_effectors::canonical_joints`]); the scale is the mean length of
//! the upper arms and forearms over the take, so positions are in *arm bones* and speeds in arm
//! bones per second, whatever the skeleton's size or units.
//!
//! The paper segments each arm on its own and merges the two segmentations (§4.2). So that one
//! set of classifiers serves both arms, each arm is given as a right arm: the left arm is
//! mirrored through the sagittal plane (`x → −x`). Each arm holds its shoulder, elbow and hand,
//! and the upper body both arms share ("the upper body's joints", §4), as that arm sees it —
//! mirrored with it: the head relative to the sternum and the torso's direction (hips to chest).

use glam::DVec3;

use crate::features::end_effectors::{canonical_joints, EndEffectorError};
use crate::motion::joints::Canonical;
use crate::motion::Motion;

/// The joints of one arm, in order.
pub const ARM_JOINTS: [&str; 3] = ["shoulder", "elbow", "hand"];

/// Which arm.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Side {
    Left,
    Right,
}

impl Side {
    pub const BOTH: [Side; 2] = [Side::Left, Side::Right];

    pub fn name(self) -> &'static str {
        match self {
            Side::Left => "left",
            Side::Right => "right",
        }
    }
}

/// One arm's trajectories at the working rate: per joint of [`ARM_JOINTS`] one position per
/// frame, sternum-relative, facing-aligned, in arm bones, mirrored to a right arm; and the shared
/// upper body, mirrored alike.
#[derive(Debug, Clone, PartialEq)]
pub struct Arm {
    pub side: Side,
    pub joints: [Vec<DVec3>; 3],
    /// The head relative to the sternum (arm bones).
    pub head: Vec<DVec3>,
    /// The torso's direction, hips to chest (unit length; straight up where they coincide).
    pub torso: Vec<DVec3>,
}

impl Arm {
    /// Frames at the working rate.
    pub fn frames(&self) -> usize {
        self.joints[2].len()
    }

    /// The hand's trajectory.
    pub fn hand(&self) -> &[DVec3] {
        &self.joints[2]
    }
}

/// Both arms of a take at `fps` and the fractional file frame of every working frame.
#[derive(Debug, Clone, PartialEq)]
pub struct UpperBody {
    pub arms: [Arm; 2],
    pub source_frames: Vec<f64>,
    /// File units per arm bone.
    pub bone: f64,
}

const JOINTS: [Canonical; 9] = [
    Canonical::Chest,
    Canonical::LeftShoulder,
    Canonical::LeftElbow,
    Canonical::LeftHand,
    Canonical::RightShoulder,
    Canonical::RightElbow,
    Canonical::RightHand,
    Canonical::Head,
    Canonical::Hips,
];
const HEAD: usize = 7;
const HIPS: usize = 8;

/// The normalised arms of `motion` resampled to `fps` (see the module documentation).
pub fn upper_body(motion: &Motion, fps: f64) -> Result<UpperBody, EndEffectorError> {
    let f = canonical_joints(motion, fps, false, &JOINTS)?;
    let frames = f.base.frames();
    let at = |t: usize, k: usize| {
        let r = &f.base.row(t)[3 * k..3 * k + 3];
        DVec3::new(r[0] as f64, r[1] as f64, r[2] as f64)
    };
    // the mean upper-arm and forearm length over the take, both sides
    let mut bones = 0.0;
    for t in 0..frames {
        for first in [1, 4] {
            bones += at(t, first).distance(at(t, first + 1)) + at(t, first + 1).distance(at(t, first + 2));
        }
    }
    let bone = bones / (4 * frames) as f64;
    if !(bone.is_finite() && bone > 1e-9) {
        return Err(EndEffectorError::MissingJoints(format!(
            "the arms have no length (mean upper arm and forearm {bone}); cannot normalise the upper body"
        )));
    }
    let arm = |side: Side, first: usize| {
        let mirror = if side == Side::Left { DVec3::new(-1.0, 1.0, 1.0) } else { DVec3::ONE };
        let joints =
            std::array::from_fn(|k| (0..frames).map(|t| (at(t, first + k) - at(t, 0)) / bone * mirror).collect());
        let head = (0..frames).map(|t| (at(t, HEAD) - at(t, 0)) / bone * mirror).collect();
        let torso =
            (0..frames).map(|t| ((at(t, 0) - at(t, HIPS)) * mirror).try_normalize().unwrap_or(DVec3::Y)).collect();
        Arm { side, joints, head, torso }
    };
    Ok(UpperBody {
        arms: [arm(Side::Left, 1), arm(Side::Right, 4)],
        source_frames: f.source_frames,
        bone: bone / f.scale,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh;

    fn fixture() -> Motion {
        let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/35_01.bvh")).unwrap();
        Motion::from_bvh("35_01.bvh", &bvh::parse(&text).unwrap()).unwrap()
    }

    #[test]
    fn arms_are_sternum_relative_in_arm_bones_and_mirrored() {
        let body = upper_body(&fixture(), 30.0).unwrap();
        for arm in &body.arms {
            // upper arm + forearm average 2 bones over both sides
            let mean: f64 = (0..arm.frames())
                .map(|t| arm.joints[0][t].distance(arm.joints[1][t]) + arm.joints[1][t].distance(arm.joints[2][t]))
                .sum::<f64>()
                / arm.frames() as f64;
            assert!((mean - 2.0).abs() < 0.2, "{:?}: {mean}", arm.side);
            // both shoulders sit on the right of the sternum once the left arm is mirrored
            let x = arm.joints[0].iter().map(|p| p.x).sum::<f64>() / arm.frames() as f64;
            assert!(x < -0.1, "{:?}: shoulder x {x}", arm.side);
        }
        assert_eq!(body.source_frames.len(), body.arms[0].frames());
        // the shared upper body: the head above the sternum, the torso near upright, mirrored with each arm
        let [left, right] = &body.arms;
        for t in (0..left.frames()).step_by(17) {
            assert!(left.head[t].y > 0.2 && (left.torso[t].length() - 1.0).abs() < 1e-9 && left.torso[t].y > 0.7);
            assert!((left.head[t].x + right.head[t].x).abs() < 1e-12 && left.head[t].y == right.head[t].y);
            assert!((left.torso[t].x + right.torso[t].x).abs() < 1e-12 && left.torso[t].z == right.torso[t].z);
        }
    }
}
