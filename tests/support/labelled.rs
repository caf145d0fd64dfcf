//! The two labelled takes kept in `tests/fixtures/`: CMU 13_30 (the page's bundled sample) and 13_31, each with its
//! mocap6 ground truth — what the accuracy floors and the library's tests measure on.

use std::path::Path;

use mocapseg::load::load_path;
use mocapseg::motion::Motion;
use mocapseg::segment::truth::{load_csv, Truth, TruthOptions};

/// The take `bvh` and its truth from `labels` (trial `trial`), both relative to the crate's root.
pub fn take(bvh: &str, labels: &str, trial: &str) -> (Motion, Truth) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let motion = load_path(&dir.join(bvh)).unwrap().motion;
    let text = std::fs::read_to_string(dir.join(labels)).unwrap();
    let truth = load_csv(&text, trial, TruthOptions::default()).unwrap();
    assert_eq!(truth.frames, motion.frames(), "{trial}: the labels are for this take");
    (motion, truth)
}

/// 13_30 and 13_31 with their truth, in that order.
pub fn takes() -> Vec<(Motion, Truth)> {
    vec![
        take("www/sample.bvh", "tests/fixtures/mocap6_13_30_gt.csv", "13_30"),
        take("tests/fixtures/13_31.bvh", "tests/fixtures/mocap6_13_31_gt.csv", "13_31"),
    ]
}
