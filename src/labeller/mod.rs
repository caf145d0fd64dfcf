//! What both labellers share — the DT-FCN network ([`crate::methods::dtfcn`]) and the k-NN beside it
//! ([`crate::methods::knn`]) — and neither owns: the motion image and the windows both read, the class
//! probabilities a labeller gives, their decoding into labels, and the take-fit check.
//!
//! | part | module |
//! |---|---|
//! | Cheema et al. 2019, §2: the motion image ("rows joints, RGB the scaled XYZ"), the canonical joints at 30 Hz | [`input`] |
//! | a labeller's class probabilities per working frame | [`probabilities`] |
//! | (not in the paper) labels as one path with a minimum duration, not per-frame argmax | [`decode`] |
//! | (not in the paper) whether a take fits a model: its travel, its poses against training windows | [`fit`] |
//! | model files: the framing, the header every labeller's file has, a labeller's payload ([`model::Labeller`]) | [`model`] |
//!
//! Nothing here names a method: a method folder reaches this module, never the reverse.

pub mod decode;
pub mod fit;
pub mod input;
pub mod model;
pub mod probabilities;
