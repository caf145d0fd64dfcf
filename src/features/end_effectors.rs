//! The end-effector features several methods start from (SSSM, Krüger et al. 2017 §IV-A; the
//! kinematic baselines of Bouchard & Badler): the take resampled to a working rate, then per frame
//! the positions of both hands, both feet and the head relative to the hips, rotated about the
//! vertical so the body faces +Z, in inches; optionally scaled so the body has the size of CMU
//! subject 86 ([`REFERENCE_BODY_INCHES`]), so that thresholds and radii tuned in inches hold for
//! children, giants and files in the wrong units alike.
//!
//! Columns: left hand, right hand, left foot, right foot, head, each `x, y, z` (x lateral with the
//! left side at +x, y up, z forward).

use super::{FeatureError, FeatureMatrix};
use crate::motion::joints::Canonical;
use crate::motion::normalize::{body_size, end_effector_features, facing_aligned, to_inches};
use crate::motion::resample::source_positions;
use crate::motion::{Motion, MotionError};

/// Body size (leg length + trunk length, [`body_size`]) of CMU subject 86 in inches, measured
/// on `86_01.bvh`: the reference body of every threshold in inches.
pub const REFERENCE_BODY_INCHES: f64 = 56.07;

/// Column of the left hand's `x` (then `y`, `z`); the right hand follows at 3.
pub const LEFT_HAND: usize = 0;
/// Column of the right hand's `x`.
pub const RIGHT_HAND: usize = 3;

/// Joint positions of a take at a working rate (the end effectors, or any canonical joints).
#[derive(Debug, Clone, PartialEq)]
pub struct JointFeatures {
    /// 3 values per joint per working frame (15 for the end effectors, see the module docs).
    pub base: FeatureMatrix,
    /// Fractional file frame of each working frame.
    pub source_frames: Vec<f64>,
    /// Factor from file units to feature units (inches × body-size scale).
    pub scale: f64,
}

/// Why the end-effector features of a take cannot be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EndEffectorError {
    #[error("the take has no frames")]
    NoFrames,
    /// Hands, feet, head or hips could not be found among the joints.
    #[error("{0}")]
    MissingJoints(String),
    #[error("{0}")]
    Motion(#[from] MotionError),
    #[error("the skeleton's body size is {0} inches; cannot scale it to the reference body")]
    BadBody(f64),
    #[error("{0}")]
    Features(#[from] FeatureError),
}

/// Which positions [`features`] extracts.
enum Select<'a> {
    EndEffectors,
    Joints(&'a [Canonical]),
}

/// The end-effector features of `motion` at `fps` (see the module docs).
pub fn end_effectors(motion: &Motion, fps: f64, body_scale: bool) -> Result<JointFeatures, EndEffectorError> {
    features(motion, fps, body_scale, Select::EndEffectors)
}

/// The positions of the canonical `joints` of `motion` at `fps`, hip-relative, facing-aligned,
/// in inches (of the reference body with `body_scale`): 3 columns per joint, in order.
pub fn canonical_joints(
    motion: &Motion,
    fps: f64,
    body_scale: bool,
    joints: &[Canonical],
) -> Result<JointFeatures, EndEffectorError> {
    features(motion, fps, body_scale, Select::Joints(joints))
}

fn features(motion: &Motion, fps: f64, body_scale: bool, select: Select) -> Result<JointFeatures, EndEffectorError> {
    if motion.frames() == 0 {
        return Err(EndEffectorError::NoFrames);
    }
    let map = motion.joint_map().map_err(|e| EndEffectorError::MissingJoints(e.to_string()))?;
    let source_frames = source_positions(motion.frames(), motion.fps, fps)?;
    let working = motion.resample(fps)?;
    let inches = to_inches(motion.units);
    let mut scale = inches;
    if body_scale {
        let body = body_size(&motion.skeleton, &map) * inches;
        if !(body.is_finite() && body > 0.0) {
            return Err(EndEffectorError::BadBody(body));
        }
        scale *= REFERENCE_BODY_INCHES / body;
    }
    let (dim, data): (usize, Vec<f32>) = match select {
        Select::EndEffectors => {
            let rows = end_effector_features(&working, &map);
            (15, rows.iter().flat_map(|r| r.iter().map(|&v| (v as f64 * scale) as f32)).collect())
        }
        Select::Joints(joints) => {
            let idx: Vec<usize> = joints.iter().map(|&c| map.get(c)).collect();
            let aligned = facing_aligned(&working, &map);
            let data = aligned
                .chunks_exact(working.joints().max(1))
                .flat_map(|frame| idx.iter().flat_map(move |&j| frame[j].to_array()))
                .map(|v| (v as f64 * scale) as f32)
                .collect();
            (3 * joints.len(), data)
        }
    };
    let base = FeatureMatrix::new(working.frames(), dim, data)?;
    Ok(JointFeatures { base, source_frames, scale })
}
