//! What both labellers share — the DT-FCN network ([`crate::methods::dtfcn`]) and the k-NN beside it
//! ([`crate::methods::knn`]) — and neither owns: the motion image and the windows both read, the class
//! probabilities a labeller gives, their decoding into labels, the take-fit check, the model file, and the labelling
//! method itself — shipped models, the unknown threshold, the class-probability picture, training from a label CSV —
//! parameterised by the [`method::Kind`] each method gives (the registry, `crate::methods`, puts them together).
//!
//! | part | module |
//! |---|---|
//! | Cheema et al. 2019, §2: the motion image ("rows joints, RGB the scaled XYZ"), the canonical joints at 30 Hz | [`input`] |
//! | a labeller's class probabilities per working frame | [`probabilities`] |
//! | (not in the paper) labels as one path with a minimum duration, not per-frame argmax | [`decode`] |
//! | (not in the paper) whether a take fits a model: its travel, its poses against training windows | [`fit`] |
//! | (not in the paper) the open-set objective an unknown threshold is chosen on, folds leaving a class out | [`openset`] |
//! | model files: the framing, the header every labeller's file has, a labeller's payload ([`model::Labeller`]) | [`model`] |
//! | the labelling method: a model labels every frame; runs of a label are segments ([`method::Labelling`]) | [`method`] |
//! | the models shipped with the app, one of each kind per name | [`shipped`] |
//! | a label CSV matched to takes: the classes and each take's per-frame labels | [`corpus`] |
//! | training from a label CSV: the decoding's rows, reading model files, a model's card and provenance | [`supervised`] |
//!
//! Nothing here names a method: a method folder reaches this module, never the reverse.

pub mod corpus;
pub mod decode;
pub mod fit;
pub mod input;
pub mod method;
pub mod model;
pub mod openset;
pub mod probabilities;
pub mod shipped;
pub mod supervised;
