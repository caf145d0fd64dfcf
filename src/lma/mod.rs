//! LMA Effort segmentation (Bouchard & Badler, "Segmenting Motion Capture Data Using a Qualitative
//! Analysis"): Laban Effort classifiers whose agreement under boundary shifts finds segment
//! boundaries. From the paper to the code:
//!
//! | paper | module |
//! |---|---|
//! | §4 normalisation: sternum origin, sagittal planes aligned, scaled by stable bone lengths | [`body`] |
//! | §4 / Fig. 1 feature pool: kinematic features × temporal weightings × statistics | [`features`] |
//! | §4 training data (here: stand-in labels from computable Effort descriptors, or a user's) | [`effort`], [`corpus`] |
//! | §4.1 saliency, PCA, sigmoid networks, best of 20 restarts | [`network`], [`training`] |
//! | §4.2 the 121 boundary-shifted classifiers, mean deviance (eq. 1–2) | [`classifier`] |
//! | §4.2 / Fig. 5 deviance map, pruned and exhaustive | [`deviance`] |
//! | §4.2 / Fig. 6 profiles, troughs, culling, start–end pairing, arm merging | [`search`] |
//! | the registered `lma` method | [`method`] |
//!
//! The trained family ships in `models/lma-effort.json` (made by `mocapseg train-lma`).

pub mod body;
pub mod classifier;
pub mod corpus;
pub mod deviance;
pub mod effort;
pub mod features;
pub mod method;
pub mod network;
pub mod search;
pub mod training;

use std::sync::OnceLock;

use classifier::EffortModel;

/// The shipped classifier family (built into the binary; read once).
pub fn shipped_model() -> Result<&'static EffortModel, String> {
    static MODEL: OnceLock<Result<EffortModel, String>> = OnceLock::new();
    MODEL
        .get_or_init(|| {
            EffortModel::from_json(include_str!("../../models/lma-effort.json"))
                .map_err(|e| format!("the shipped LMA model is unusable ({e}); retrain it with `mocapseg train-lma`"))
        })
        .as_ref()
        .map_err(Clone::clone)
}
