//! The SSSM's features (Krüger et al. 2017, §IV-A). The per-frame [`FeatureMatrix`], its
//! stacking over frame offsets and its [`MirrorMap`] (§V) are shared with other methods and live
//! in [`crate::features`] (re-exported here).
//!
//! The method itself only sees a [`FeatureMatrix`]; [`from_motion`] builds the paper's mocap
//! features from a [`Motion`]: the take resampled to the working rate, then per frame the
//! positions of both hands, both feet and the head relative to the hips, rotated about the
//! vertical so the body faces +Z ([`end_effector_features`]), in inches — the unit the
//! generalized radius `R = 19` was tuned in (CMU ASF lengths ÷ 0.45). With `body_scale` on,
//! they are further scaled so the body has the size of CMU subject 86, on whom `R` was tuned
//! ([`REFERENCE_BODY_INCHES`]): a child or a file in the wrong units then gets the same
//! neighbourhoods as an adult.

pub use crate::features::{stack, FeatureMatrix, MirrorMap};

use super::params::ValidParams;
use super::SssmError;
use crate::motion::normalize::{body_size, end_effector_features, to_inches};
use crate::motion::resample::source_positions;
use crate::motion::Motion;

/// Body size (leg length + trunk length, [`body_size`]) of CMU subject 86 in inches, measured
/// on `86_01.bvh`: the body the generalized radius was tuned on.
pub const REFERENCE_BODY_INCHES: f64 = 56.07;

/// The features of a take, ready for the method.
#[derive(Debug, Clone, PartialEq)]
pub struct MotionFeatures {
    /// End-effector features at the working rate (15 per frame, before stacking).
    pub base: FeatureMatrix,
    /// Their mirror map (§V).
    pub mirror: MirrorMap,
    /// Fractional file frame of each working frame.
    pub source_frames: Vec<f64>,
    /// Factor from file units to feature units (inches × body-size scale).
    pub scale: f64,
}

/// The paper's end-effector features of `motion` at the working rate (see the module docs).
pub fn from_motion(motion: &Motion, params: &ValidParams) -> Result<MotionFeatures, SssmError> {
    if motion.frames() == 0 {
        return Err(SssmError::NoFrames);
    }
    let map = motion.joint_map().map_err(|e| SssmError::MissingJoints(e.to_string()))?;
    let source_frames = source_positions(motion.frames(), motion.fps, params.fps)?;
    let working = motion.resample(params.fps)?;
    let inches = to_inches(motion.units);
    let mut scale = inches;
    if params.body_scale {
        let body = body_size(&motion.skeleton, &map) * inches;
        if !(body.is_finite() && body > 0.0) {
            return Err(SssmError::BadFeatures(format!(
                "the skeleton's body size is {body} inches; cannot scale it to the reference body"
            )));
        }
        scale *= REFERENCE_BODY_INCHES / body;
    }
    let rows = end_effector_features(&working, &map);
    let data: Vec<f32> = rows.iter().flat_map(|r| r.iter().map(|&v| (v as f64 * scale) as f32)).collect();
    let base = FeatureMatrix::new(rows.len(), 15, data)?;
    Ok(MotionFeatures { base, mirror: MirrorMap::end_effectors(), source_frames, scale })
}
