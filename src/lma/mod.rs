//! LMA Effort segmentation (Bouchard & Badler, "Semantic segmentation of motion capture using
//! Laban Movement Analysis", 2007): Effort classifiers whose agreement under boundary shifts finds
//! segment boundaries.
//!
//! What exists so far are the first steps of the paper's pipeline: its feature pool (§4, Fig. 1),
//! [`features`] — the per-frame kinematic quantities of a joint and their weighted statistics over
//! any candidate segment in O(1) — and [`effort`], the computable Effort descriptors that stand in
//! for the paper's expert labels when training the classifiers. The Effort classifiers, the 121
//! boundary-shifted classifiers, the deviance map and its minima search, and the registered `lma`
//! method build on them.

pub mod body;
pub mod effort;
pub mod features;
pub mod search;
