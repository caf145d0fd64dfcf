//! Every registered method on degenerate takes (hardening): one frame, two frames, a take
//! shorter than any method's windows, a motionless take, a skeleton without arms or legs, and
//! frame rates of 24, 60, 120 and 23.976 fps — each gives a segmentation that fits the schema or
//! a clear message (`MethodError::Failed`), never a panic, with the default parameters and with
//! LMA's exhaustive search.
#![cfg(not(target_arch = "wasm32"))]

use mocapseg::bvh;
use mocapseg::method::{MethodError, NoProgress, RunOptions};
use mocapseg::motion::Motion;

const WALK: &str = include_str!("fixtures/12_01.bvh");
const HIPS_AND_HEAD: &str = include_str!("fixtures/pybvh_full_precision_frame_time.bvh");

/// The hierarchy of `text` with the motion rows `rows` and frame time `frame_time`.
fn with_motion(text: &str, rows: &[&str], frame_time: f64) -> String {
    let (head, _) = text.split_once("MOTION").unwrap();
    let mut out = format!("{head}MOTION\nFrames: {}\nFrame Time: {frame_time}\n", rows.len());
    for r in rows {
        out += r;
        out.push('\n');
    }
    out
}

fn rows(text: &str) -> Vec<&str> {
    let (_, motion) = text.split_once("MOTION").unwrap();
    motion.lines().map(str::trim).filter(|l| !l.is_empty()).skip(2).collect()
}

/// The degenerate takes, named.
fn takes() -> Vec<(String, Motion)> {
    let walk = rows(WALK);
    let still: Vec<&str> = vec![walk[10]; 600];
    let mut texts = vec![
        ("1 frame".to_string(), with_motion(WALK, &walk[..1], 1.0 / 120.0)),
        ("2 frames".to_string(), with_motion(WALK, &walk[..2], 1.0 / 120.0)),
        ("0.3 s".to_string(), with_motion(WALK, &walk[..36], 1.0 / 120.0)),
        ("motionless 5 s".to_string(), with_motion(WALK, &still, 1.0 / 120.0)),
        ("hips and head only".to_string(), HIPS_AND_HEAD.to_string()),
    ];
    for fps in [24.0, 60.0, 120.0, 23.976] {
        texts.push((format!("walk at {fps} fps"), with_motion(WALK, &walk, 1.0 / fps)));
    }
    texts
        .into_iter()
        .map(|(name, text)| {
            let b = bvh::parse(&text).unwrap_or_else(|e| panic!("{name}: {e}"));
            let m = Motion::from_bvh(&name, &b).unwrap_or_else(|e| panic!("{name}: {e}"));
            (name, m)
        })
        .collect()
}

#[test]
fn every_method_segments_degenerate_takes_or_says_why() {
    let mut runs = Vec::new();
    for m in mocapseg::methods::registry() {
        runs.push((m.info().name, *m, serde_json::json!({})));
        if m.info().name == "lma" {
            runs.push(("lma exhaustive".into(), *m, serde_json::json!({"exhaustive": true})));
        }
    }
    let mut failures = Vec::new();
    for (take, motion) in takes() {
        for (name, m, params) in &runs {
            let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                m.run_json(&motion, params, &RunOptions { pictures: true, ..RunOptions::default() }, &mut NoProgress)
            }));
            match outcome {
                Err(_) => failures.push(format!("{name} panicked on {take}")),
                Ok(Ok(out)) => {
                    if let Err(e) = out.segmentation.validate() {
                        failures.push(format!("{name} on {take}: output breaks the schema: {e}"));
                    }
                    assert_eq!(out.segmentation.frames, motion.frames(), "{name} on {take}");
                }
                Ok(Err(MethodError::Failed(message))) => {
                    // a message a user can act on: not empty, not a debug dump
                    if message.trim().len() < 10 || message.contains("panicked") || message.contains("{ ") {
                        failures.push(format!("{name} on {take}: unclear message `{message}`"));
                    }
                }
                Ok(Err(e)) => failures.push(format!("{name} on {take}: unexpected error kind: {e}")),
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn a_skeleton_without_arms_is_refused_by_name() {
    let (_, motion) = takes().into_iter().find(|(n, _)| n == "hips and head only").unwrap();
    for name in ["lma", "velocity", "sssm"] {
        let err = mocapseg::methods::find(name)
            .unwrap()
            .run_json(&motion, &serde_json::json!({}), &RunOptions::default(), &mut NoProgress)
            .unwrap_err()
            .to_string();
        assert!(err.contains("missing (") && err.contains("LeftHand"), "{name}: {err}");
    }
}
