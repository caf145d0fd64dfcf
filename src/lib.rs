//! mocapseg — motion-capture segmentation that runs in the browser.
//!
//! The core (`bvh`, `motion`, `image`, `segment`) is pure Rust: it compiles natively and to
//! `wasm32-unknown-unknown` and never touches the DOM. The leptos page (`app`) and the worker
//! entry points (`worker`) sit on top of it behind the `web` feature.
//!
//! Data flow: BVH text → [`bvh::Bvh`] (hierarchy + channel values) → [`motion::Motion`]
//! (skeleton + world joint positions per frame) → motion image / segmentations.

pub mod asfamc;
pub mod bvh;
pub mod clips;
pub mod features;
pub mod image;
pub mod labeller;
pub mod labels;
pub mod library;
pub mod load;
pub mod method;
pub mod methods;
pub mod motion;
pub mod parallel;
pub mod protocol;
pub mod segment;
pub mod similarity;
pub mod splice;
pub mod stats;

pub mod app;
pub mod worker;
