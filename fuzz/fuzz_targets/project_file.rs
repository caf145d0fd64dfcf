//! libFuzzer's entry to `mocapseg_fuzz::targets::project_file` (what it checks is written there; `cargo test` runs
//! the same code on its seeds and their mutations: tests/fuzz_targets.rs).
#![no_main]

use mocapseg_fuzz::targets::project_file as target;

libfuzzer_sys::fuzz_target!(init: mocapseg_fuzz::init(target::seeds), |data: &[u8]| target::run(data));
