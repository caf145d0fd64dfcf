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
//! | §3.1's premise read the other way: boundaries where the family's Effort changes, one chain over sparse candidates (the default search, chosen by held-out scores) | [`change`] |
//! | the registered `lma` method | [`method`] |
//! | §6 LMA as a semantic layer: the Effort of any segment of any method (`mocapseg effort`) | [`layer`] |
//! | training and family files behind the supervised shape | [`supervised`] |
//!
//! The trained family ships in `models/lma-effort.json` (made by `mocapseg train-lma`).

pub mod body;
pub mod change;
pub mod classifier;
pub mod corpus;
pub mod deviance;
pub mod effort;
pub mod features;
pub mod layer;
pub mod method;
pub mod network;
pub mod search;
pub mod supervised;
pub mod training;

use std::sync::Arc;

use classifier::EffortModel;

/// The shipped family's file in `models/` (built into the command line; fetched by the page
/// when `lma` first runs: [`crate::method::shipped`]).
pub const SHIPPED_FILE: &str = "lma-effort.json";

/// The shipped classifier family, read once by `models` (the runner's store); on the page
/// [`crate::method::MethodError::NeedsModel`] until its file was handed over.
pub fn shipped(models: &crate::method::ModelStore) -> Result<Arc<EffortModel>, crate::method::MethodError> {
    models.read_shipped(SHIPPED_FILE, |bytes| {
        std::str::from_utf8(bytes).map_err(|e| e.to_string()).and_then(EffortModel::from_json).map_err(|e| {
            crate::method::MethodError::Failed(format!(
                "the shipped LMA model is unusable ({e}); retrain it with `mocapseg train-lma`"
            ))
        })
    })
}

/// The shipped classifier family as a program outside a run reads it (an example, a test): with a store of its own.
pub fn shipped_model() -> Result<Arc<EffortModel>, String> {
    shipped(&crate::method::ModelStore::default()).map_err(|e| e.to_string())
}
