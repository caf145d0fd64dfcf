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

pub use crate::features::end_effectors::REFERENCE_BODY_INCHES;

use super::params::ValidParams;
use super::SssmError;
use crate::features::end_effectors::{end_effectors, EndEffectorError};
use crate::motion::Motion;

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
    let e = end_effectors(motion, params.fps, params.body_scale).map_err(|e| match e {
        EndEffectorError::NoFrames => SssmError::NoFrames,
        EndEffectorError::MissingJoints(m) => SssmError::MissingJoints(m),
        EndEffectorError::Motion(m) => SssmError::Motion(m),
        EndEffectorError::BadBody(_) => SssmError::BadFeatures(e.to_string()),
        EndEffectorError::Features(f) => f.into(),
    })?;
    Ok(MotionFeatures {
        base: e.base,
        mirror: MirrorMap::end_effectors(),
        source_frames: e.source_frames,
        scale: e.scale,
    })
}
