//! LMA Effort segmentation (Bouchard & Badler, "Semantic segmentation of motion capture using
//! Laban Movement Analysis", 2007): Effort classifiers whose agreement under boundary shifts finds
//! segment boundaries.
//!
//! What exists so far is the first step of the paper's pipeline, its feature pool (§4, Fig. 1):
//! [`features`], the per-frame kinematic quantities of a joint and their weighted statistics over
//! any candidate segment in O(1). The Effort classifiers, the 121 boundary-shifted classifiers,
//! the deviance map and its minima search, and the registered `lma` method build on it.

pub mod features;
