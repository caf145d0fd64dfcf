//! DT-FCN — "Dilated Temporal Fully-Convolutional Network for Semantic Segmentation of Motion
//! Capture Data" (Cheema, Hosseini et al., 2019): per-frame semantic labels from a network that
//! reads the take's motion image and convolves in time only, with dilations that grow as `w^l`.
//!
//! | paper | module |
//! |---|---|
//! | §2 motion image ("rows joints, RGB the scaled XYZ") | [`crate::labeller::input`] (the k-NN reads it too) |
//! | §2 / Fig. 1 the network: full-height first kernel, four dilated acausal layers, `d = w^(l−1)` | [`network`] |
//! | §2 NormReLU before the softmax | [`normrelu`] |
//! | §3 training: cross-entropy, Adam, label noise (Table 3), boundary masking (Table 4) | [`training`] |
//! | (not in the paper) augmentation for small labelled sets | [`augment`] |
//! | labelling a take, blockwise | [`infer`] |
//! | (not in the paper) an unknown in feature space: Mahalanobis distance before NormReLU | [`novelty`] |
//! | (not in the paper) labels as one path with a minimum duration, not per-frame argmax | [`crate::labeller::decode`] |
//! | (not in the paper) whether a take fits the model | [`crate::labeller::fit`] |
//! | model files: the network's shape and weights in the common model file ([`crate::labeller::model`]) | [`model`] |
//! | training a model and the nested held-out protocol (the k-NN beside it on the same folds) | [`corpus`] |
//! | the registered `dtfcn` method: the common labelling method ([`crate::labeller::method`]) over its models | [`method`] |
//! | its training table and training behind the supervised shape | [`supervised`] |

pub mod augment;
pub mod bench;
pub mod corpus;
pub mod infer;
pub mod method;
pub mod model;
pub mod network;
pub mod normrelu;
pub mod novelty;
pub mod supervised;
pub mod training;

/// The device every DT-FCN tensor lives on: burn's ndarray backend, as the user asked (burn
/// 0.22 deprecates it in favour of its newer `flex` CPU backend, which we have not measured;
/// the ndarray backend builds for wasm32 and is what the numbers in docs/methods/dtfcn.md are for).
#[allow(deprecated)]
pub fn device() -> burn::tensor::Device {
    burn::tensor::Device::ndarray()
}
