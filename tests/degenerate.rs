//! Every registered method on degenerate takes (hardening): one frame, two frames, a take
//! shorter than any method's windows, a motionless take, a skeleton without arms or legs — each
//! gives a segmentation that fits the schema or a clear message (`MethodError::Failed`) that the
//! command line shows with the file's name, never a panic — and on ordinary walks at 24, 60, 120
//! and 23.976 fps, which every method must segment (a refusal there is a failure), with the
//! default parameters and with LMA's exhaustive search.
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

/// May a method refuse the take, or must it segment it?
#[derive(Debug, Clone, Copy, PartialEq)]
enum Kind {
    /// Too short, motionless or without the joints a method reads: a clear refusal is fine.
    Degenerate,
    /// An ordinary walk: every method must segment it.
    Ordinary,
}

/// The takes, named, with their kind and their BVH text.
fn takes() -> Vec<(String, Kind, String, Motion)> {
    let walk = rows(WALK);
    let still: Vec<&str> = vec![walk[10]; 600];
    let mut texts = vec![
        ("1 frame".to_string(), Kind::Degenerate, with_motion(WALK, &walk[..1], 1.0 / 120.0)),
        ("2 frames".to_string(), Kind::Degenerate, with_motion(WALK, &walk[..2], 1.0 / 120.0)),
        ("0.3 s".to_string(), Kind::Degenerate, with_motion(WALK, &walk[..36], 1.0 / 120.0)),
        ("motionless 5 s".to_string(), Kind::Degenerate, with_motion(WALK, &still, 1.0 / 120.0)),
        ("hips and head only".to_string(), Kind::Degenerate, HIPS_AND_HEAD.to_string()),
    ];
    for fps in [24.0, 60.0, 120.0, 23.976] {
        texts.push((format!("walk at {fps} fps"), Kind::Ordinary, with_motion(WALK, &walk, 1.0 / fps)));
    }
    texts
        .into_iter()
        .map(|(name, kind, text)| {
            let b = bvh::parse(&text).unwrap_or_else(|e| panic!("{name}: {e}"));
            let m = Motion::from_bvh(&name, &b).unwrap_or_else(|e| panic!("{name}: {e}"));
            (name, kind, text, m)
        })
        .collect()
}

#[test]
fn every_method_segments_degenerate_takes_or_says_why() {
    // (the name shown, the method, its parameters, the same run's extra command-line flags)
    let mut runs = Vec::new();
    for m in mocapseg::methods::registry() {
        runs.push((m.info().name, *m, serde_json::json!({}), None));
        if m.info().name == "lma" {
            runs.push(("lma exhaustive".into(), *m, serde_json::json!({"exhaustive": true}), Some("--exhaustive")));
        }
    }
    let folder = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("degenerate");
    std::fs::create_dir_all(&folder).unwrap();
    let mut failures = Vec::new();
    for (take, kind, text, motion) in takes() {
        for (name, m, params, flag) in &runs {
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
                    // LMA's segments are the arms' gestures, which a walk need not have (at 60 and
                    // 120 fps it finds none in this 4.4 s walk); every other method tiles the take
                    if kind == Kind::Ordinary && !name.starts_with("lma") && out.segmentation.segments.is_empty() {
                        failures.push(format!("{name} on {take}: no segment at all in an ordinary walk"));
                    }
                }
                Ok(Err(MethodError::Failed(message))) if kind == Kind::Ordinary => {
                    failures.push(format!("{name} refused {take}, an ordinary walk: {message}"));
                }
                Ok(Err(MethodError::Failed(message))) => {
                    // a message a user can act on: not empty, not a debug dump
                    if message.trim().len() < 10 || message.contains("panicked") || message.contains("{ ") {
                        failures.push(format!("{name} on {take}: unclear message `{message}`"));
                    }
                    // and the command line shows it after the file's name, once (the message may
                    // start with the take's name, which the command line replaces by the file's)
                    let file = folder.join(format!("{}.bvh", take.replace(' ', "_")));
                    std::fs::write(&file, &text).unwrap();
                    let out = std::process::Command::new(env!("CARGO_BIN_EXE_mocapseg"))
                        .args(["segment", "--method", m.info().name.as_str()])
                        .args(flag.iter())
                        .arg(&file)
                        .output()
                        .unwrap();
                    let stderr = String::from_utf8_lossy(&out.stderr);
                    let named = format!("error: {}: ", file.file_name().unwrap().to_string_lossy());
                    let own = message.strip_prefix(&format!("{take}: ")).unwrap_or(&message);
                    if out.status.code() != Some(1) || stderr.trim() != format!("{named}{}", own.trim()) {
                        failures.push(format!(
                            "{name} on {take}: the command line says ({:?}) `{}`, expected `{named}{own}`",
                            out.status.code(),
                            stderr.trim()
                        ));
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
    let (_, _, _, motion) = takes().into_iter().find(|(n, ..)| n == "hips and head only").unwrap();
    for name in ["lma", "velocity", "sssm"] {
        let err = mocapseg::methods::find(name)
            .unwrap()
            .run_json(&motion, &serde_json::json!({}), &RunOptions::default(), &mut NoProgress)
            .unwrap_err()
            .to_string();
        assert!(err.contains("missing (") && err.contains("LeftHand"), "{name}: {err}");
    }
}
