//! The fuzz targets' code: each module's `run` takes one input (libFuzzer's bytes) and its `seeds` are its
//! starting corpus. `fuzz_targets/*.rs` hand them to libFuzzer; `tests/fuzz_targets.rs` (the main crate's
//! `cargo test`) compiles the same files and runs them on the seeds and mutations of them, so they cannot rot.

pub mod asf_amc;
pub mod bvh_grammar;
pub mod bvh_parse;
pub mod labels_import;
pub mod load_pipeline;
pub mod long_takes;
pub mod model_file;
pub mod project_file;
pub mod segmentation_json;
