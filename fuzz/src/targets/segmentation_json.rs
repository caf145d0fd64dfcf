//! The segmentation JSON importer (`Segmentation::from_json`: serde, then the schema's checks),
//! which `mocapseg eval` reads predictions with, and then what `eval` does with one: score it
//! against a ground truth of the same length (`metrics::evaluate`) and count its segments.
//!
//! A segmentation that reads must write back and read to the same value; its scores must be
//! finite and within their ranges.

use mocapseg::method::{NoProgress, RunOptions};
use mocapseg::motion::Motion;
use mocapseg::segment::metrics::{evaluate, Tolerances};
use mocapseg::segment::report;
use mocapseg::segment::truth::{Truth, TruthSegment};
use mocapseg::segment::Segmentation;

/// Longest segmentation scored (the scores allocate per frame).
const MAX_SCORED: usize = 100_000;

pub fn seeds() -> Vec<(String, Vec<u8>)> {
    // what the methods write, on 4 s of a walk
    let take = crate::small_take("12_01.bvh", 480);
    let motion = Motion::from_bvh("12_01.bvh", &take).expect("the fixture's motion");
    let mut out = Vec::new();
    for m in mocapseg::methods::registry() {
        if let Ok(o) = m.run_json(&motion, &serde_json::Value::Null, &RunOptions::default(), &mut NoProgress) {
            out.push((format!("{}.json", m.info().name), o.segmentation.to_json().into_bytes()));
        }
    }
    out
}

/// A ground truth of `frames` frames: three labelled thirds, the last with an uncertainty window.
fn truth(frames: usize) -> Truth {
    let third = (frames / 3).max(1);
    let mut segments = Vec::new();
    let mut start = 0;
    for (i, label) in ["walk", "turn", "walk"].iter().enumerate() {
        if start >= frames {
            break;
        }
        let end = if i == 2 { frames - 1 } else { (start + third - 1).min(frames - 1) };
        let end_window = (i == 2).then_some((end.saturating_sub(2), end));
        segments.push(TruthSegment { start, end, label: label.to_string(), end_window });
        start = end + 1;
    }
    Truth { trial: "fuzz".into(), frames, segments }
}

/// One input of the target (what `fuzz_targets/segmentation_json.rs` hands libFuzzer's bytes to).
pub fn run(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let Ok(seg) = Segmentation::from_json(&text) else { return };
    seg.validate().expect("from_json validated it");
    let again = Segmentation::from_json(&seg.to_json()).unwrap_or_else(|e| panic!("its own JSON does not read: {e}"));
    assert_eq!(seg, again);
    let _ = report::scored_segments(&seg);
    if seg.frames == 0 || seg.frames > MAX_SCORED {
        return;
    }
    if let Ok(scores) = evaluate(&seg, &truth(seg.frames), &Tolerances::default()) {
        let unit = [scores.covering, scores.hungarian_accuracy, scores.strict_accuracy, scores.tolerant_accuracy];
        assert!(unit.iter().all(|v| (0.0..=1.0).contains(v)), "{scores:?}");
        for b in &scores.boundaries {
            assert!([b.precision, b.recall, b.f1].iter().all(|v| (0.0..=1.0).contains(v)), "{b:?}");
        }
        assert!(scores.segments.similarity.is_finite());
    }
}
