//! Native integration tests of the BVH parser and writer:
//! every fixture against independently established facts, every quirk of the format, every
//! error message (line, column, content), parse → write → parse round trips, limits, progress,
//! and a deterministic fuzz test (mutated and truncated fixtures, random bytes) that no input
//! panics.
//!
//! Run: `cargo test --test bvh`. Throughput: `cargo test --release --test bvh -- --ignored --nocapture`
//! (file from `MOCAPSEG_BENCH_BVH`, default `tests/fixtures/131_03.bvh`).

use std::path::{Path, PathBuf};

use mocapseg::bvh::{self, Bvh, BvhError, Channel, JointKind, ParseLimits};

// ---------------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------------

fn fixtures_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures")
}

fn fixture(name: &str) -> String {
    let path = fixtures_dir().join(name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn parse_ok(text: &str) -> Bvh {
    match bvh::parse(text) {
        Ok(b) => {
            check_invariants(&b);
            b
        }
        Err(e) => panic!("unexpected error: {e}\n--- input ---\n{text}"),
    }
}

fn parse_err(text: &str) -> BvhError {
    match bvh::parse(text) {
        Ok(b) => {
            panic!("expected an error, parsed {} joints / {} frames\n--- input ---\n{text}", b.joints.len(), b.frames())
        }
        Err(e) => e,
    }
}

/// Asserts an error at `line`:`column` whose message contains every one of `parts`.
#[track_caller]
fn assert_err(text: &str, line: usize, column: usize, parts: &[&str]) {
    let e = parse_err(text);
    assert_eq!((e.line, e.column), (line, column), "wrong position: {e}");
    for p in parts {
        assert!(e.message.contains(p), "message lacks {p:?}: {e}");
    }
    assert!(e.to_string().starts_with(&format!("line {line}, column {column}: ")), "{e}");
}

/// What every successful parse must satisfy.
#[track_caller]
fn check_invariants(b: &Bvh) {
    assert!(!b.joints.is_empty());
    let mut channels = 0;
    for (i, j) in b.joints.iter().enumerate() {
        match j.parent {
            None => assert_eq!(j.kind, JointKind::Root, "{}", j.name),
            Some(p) => {
                assert!(p < i, "parent after child: {}", j.name);
                assert_ne!(j.kind, JointKind::Root);
                assert_ne!(b.joints[p].kind, JointKind::EndSite, "End Site with children");
            }
        }
        if j.kind == JointKind::EndSite {
            assert!(j.channels.is_empty());
            assert!(j.name.starts_with(&format!("{}_End", b.joints[j.parent.unwrap()].name)), "{}", j.name);
        } else {
            assert_eq!(j.channel_start, channels, "{}", j.name);
            channels += j.channels.len();
        }
        assert!(j.offset.iter().all(|v| v.is_finite()));
    }
    assert_eq!(b.channels_per_frame, channels);
    if channels > 0 {
        assert_eq!(b.values.len() % channels, 0);
        assert_eq!(b.values.len(), b.frames() * channels);
    } else {
        assert!(b.values.is_empty());
    }
    assert!(b.values.iter().all(|v| v.is_finite()));
    assert!(b.frame_time.is_finite() && b.frame_time > 0.0);
}

fn root_channels(b: &Bvh) -> String {
    b.joints[0].channels.iter().map(|c| c.name()).collect::<Vec<_>>().join(" ")
}

/// A small file: ROOT `Hips` with `root_channels`, JOINT `Spine` with `joint_channels`, an
/// End Site, then `Frames: frames` and `rows`.
fn small(root_channels: &str, joint_channels: &str, frames: usize, rows: &str) -> String {
    let rc = root_channels.split_whitespace().count();
    let jc = joint_channels.split_whitespace().count();
    format!(
        "HIERARCHY\nROOT Hips\n{{\n\tOFFSET 0 0 0\n\tCHANNELS {rc} {root_channels}\n\tJOINT Spine\n\t{{\n\t\tOFFSET 0 5 0\n\t\tCHANNELS {jc} {joint_channels}\n\t\tEnd Site\n\t\t{{\n\t\t\tOFFSET 0 3 0\n\t\t}}\n\t}}\n}}\nMOTION\nFrames: {frames}\nFrame Time: 0.0333333\n{rows}"
    )
}

const P6: &str = "Xposition Yposition Zposition Zrotation Yrotation Xrotation";
const R3: &str = "Zrotation Yrotation Xrotation";

/// The standard 2-joint, 9-channel file with two rows (lines 19 and 20).
fn simple9() -> String {
    small(P6, R3, 2, "1 2 3 4 5 6 7 8 9\n10 11 12 13 14 15 16 17 18\n")
}

// ---------------------------------------------------------------------------------------------
// Every fixture against its facts
// ---------------------------------------------------------------------------------------------

struct Fact {
    file: &'static str,
    root: &'static str,
    /// Nodes that are not End Sites.
    joints: usize,
    end_sites: usize,
    channels: usize,
    root_channels: &'static str,
    frames_header: usize,
    data_rows: usize,
    frame_time: f64,
    crlf_lines: usize,
}

/// Copied from /work/shared/data/manifest.json (fields `root`, `joints`, `end_sites`, `channels`,
/// `root_channels`, `frames_header`, `data_rows`, `frame_time`, `crlf_lines`), which an
/// independent checker produced for the same files (tests/fixtures/SOURCES.md gives origins).
const FACTS: &[Fact] = &[
    Fact {
        file: "02_01.bvh",
        root: "Hips",
        joints: 31,
        end_sites: 7,
        channels: 96,
        root_channels: "Xposition Yposition Zposition Zrotation Yrotation Xrotation",
        frames_header: 343,
        data_rows: 343,
        frame_time: 0.0083333,
        crlf_lines: 0,
    },
    Fact {
        file: "02_02.bvh",
        root: "Hips",
        joints: 31,
        end_sites: 7,
        channels: 96,
        root_channels: "Xposition Yposition Zposition Zrotation Yrotation Xrotation",
        frames_header: 298,
        data_rows: 298,
        frame_time: 0.0083333,
        crlf_lines: 0,
    },
    Fact {
        file: "12_01.bvh",
        root: "Hips",
        joints: 31,
        end_sites: 7,
        channels: 96,
        root_channels: "Xposition Yposition Zposition Zrotation Yrotation Xrotation",
        frames_header: 524,
        data_rows: 524,
        frame_time: 0.0083333,
        crlf_lines: 707,
    },
    Fact {
        file: "131_01.bvh",
        root: "Hips",
        joints: 31,
        end_sites: 7,
        channels: 96,
        root_channels: "Xposition Yposition Zposition Zrotation Yrotation Xrotation",
        frames_header: 994,
        data_rows: 994,
        frame_time: 0.0083333,
        crlf_lines: 160,
    },
    Fact {
        file: "131_03.bvh",
        root: "Hips",
        joints: 31,
        end_sites: 7,
        channels: 96,
        root_channels: "Xposition Yposition Zposition Zrotation Yrotation Xrotation",
        frames_header: 1102,
        data_rows: 1102,
        frame_time: 0.0083333,
        crlf_lines: 160,
    },
    Fact {
        file: "86_01.bvh",
        root: "Hips",
        joints: 31,
        end_sites: 7,
        channels: 96,
        root_channels: "Xposition Yposition Zposition Zrotation Yrotation Xrotation",
        frames_header: 4579,
        data_rows: 4579,
        frame_time: 0.0083333,
        crlf_lines: 0,
    },
    Fact {
        file: "13_31.bvh",
        root: "Hips",
        joints: 31,
        end_sites: 7,
        channels: 96,
        root_channels: "Xposition Yposition Zposition Zrotation Yrotation Xrotation",
        frames_header: 3017,
        data_rows: 3017,
        frame_time: 0.0083333,
        crlf_lines: 0,
    },
    Fact {
        file: "35_01.bvh",
        root: "Hips",
        joints: 31,
        end_sites: 7,
        channels: 96,
        root_channels: "Xposition Yposition Zposition Zrotation Yrotation Xrotation",
        frames_header: 358,
        data_rows: 358,
        frame_time: 0.0083333,
        crlf_lines: 0,
    },
    Fact {
        file: "assimp_Boxing_Toes_100fps.bvh",
        root: "Hips",
        joints: 21,
        end_sites: 5,
        channels: 66,
        root_channels: "Xposition Yposition Zposition Zrotation Xrotation Yrotation",
        frames_header: 3069,
        data_rows: 3070,
        frame_time: 0.01,
        crlf_lines: 0,
    },
    Fact {
        file: "bvh_anim_test_simple.bvh",
        root: "Base",
        joints: 2,
        end_sites: 1,
        channels: 9,
        root_channels: "Xposition Yposition Zposition Zrotation Xrotation Yrotation",
        frames_header: 2,
        data_rows: 2,
        frame_time: 0.033333333,
        crlf_lines: 0,
    },
    Fact {
        file: "cmu_131_01_scaled_meters.bvh",
        root: "Hips",
        joints: 31,
        end_sites: 7,
        channels: 96,
        root_channels: "Xposition Yposition Zposition Zrotation Yrotation Xrotation",
        frames_header: 995,
        data_rows: 995,
        frame_time: 0.008333,
        crlf_lines: 0,
    },
    Fact {
        file: "gpmat_Swagger2_1frame.bvh",
        root: "root",
        joints: 22,
        end_sites: 5,
        channels: 69,
        root_channels: "Xposition Yposition Zposition Zrotation Xrotation Yrotation",
        frames_header: 1,
        data_rows: 1,
        frame_time: 0.008333,
        crlf_lines: 135,
    },
    Fact {
        file: "mixamo_names_freebvh.bvh",
        root: "mixamorig:Hips",
        joints: 55,
        end_sites: 15,
        channels: 168,
        root_channels: "Xposition Yposition Zposition Zrotation Yrotation Xrotation",
        frames_header: 69,
        data_rows: 69,
        frame_time: 0.0333333,
        crlf_lines: 0,
    },
    Fact {
        file: "pybvh_bvh_test1.bvh",
        root: "Hips",
        joints: 24,
        end_sites: 5,
        channels: 75,
        root_channels: "Xposition Yposition Zposition Xrotation Zrotation Yrotation",
        frames_header: 75,
        data_rows: 75,
        frame_time: 0.033333,
        crlf_lines: 0,
    },
    Fact {
        file: "pybvh_bvh_test2.bvh",
        root: "Hips",
        joints: 23,
        end_sites: 5,
        channels: 72,
        root_channels: "Xposition Yposition Zposition Yrotation Xrotation Zrotation",
        frames_header: 61,
        data_rows: 61,
        frame_time: 0.008333,
        crlf_lines: 199,
    },
    Fact {
        file: "pybvh_bvh_test3.bvh",
        root: "Hips",
        joints: 60,
        end_sites: 13,
        channels: 183,
        root_channels: "Xposition Yposition Zposition Xrotation Yrotation Zrotation",
        frames_header: 100,
        data_rows: 100,
        frame_time: 0.008333,
        crlf_lines: 455,
    },
    Fact {
        file: "pybvh_full_precision_frame_time.bvh",
        root: "Hips",
        joints: 2,
        end_sites: 1,
        channels: 9,
        root_channels: "Xposition Yposition Zposition Zrotation Yrotation Xrotation",
        frames_header: 3,
        data_rows: 3,
        frame_time: 0.0417083750417,
        crlf_lines: 0,
    },
    Fact {
        file: "pybvh_standard_skeleton_1frame.bvh",
        root: "Hips",
        joints: 24,
        end_sites: 5,
        channels: 75,
        root_channels: "Xposition Yposition Zposition Zrotation Yrotation Xrotation",
        frames_header: 1,
        data_rows: 1,
        frame_time: 0.008333,
        crlf_lines: 0,
    },
];

/// Fixtures that are invalid on purpose, with the error they must give: (file, line, column, words).
/// `bad.bvh` (used by the e2e and wasm tests) has `Wrotation` on line 9, column 34.
const INVALID: &[(&str, usize, usize, &str)] = &[("bad.bvh", 9, 34, "`Wrotation`")];

#[test]
fn every_fixture_file_is_covered() {
    let mut seen = Vec::new();
    for entry in std::fs::read_dir(fixtures_dir()).expect("fixtures dir") {
        let name = entry.expect("entry").file_name().to_string_lossy().into_owned();
        if name.ends_with(".bvh") {
            let known = FACTS.iter().any(|f| f.file == name) || INVALID.iter().any(|i| i.0 == name);
            assert!(known, "tests/fixtures/{name} has no facts in tests/bvh.rs");
            seen.push(name);
        }
    }
    assert_eq!(seen.len(), FACTS.len() + INVALID.len());
}

#[test]
fn every_fixture_matches_its_facts() {
    for f in FACTS {
        let text = fixture(f.file);
        assert_eq!(text.matches("\r\n").count(), f.crlf_lines, "{}: CRLF count (sanity check of the copy)", f.file);
        let b = parse_ok(&text);
        let end_sites = b.joints.iter().filter(|j| j.kind == JointKind::EndSite).count();
        assert_eq!(b.joints[0].name, f.root, "{}", f.file);
        assert_eq!(b.joint_indices().count(), f.joints, "{}: joints", f.file);
        assert_eq!(end_sites, f.end_sites, "{}: End Sites", f.file);
        assert_eq!(b.channels_per_frame, f.channels, "{}: channels", f.file);
        assert_eq!(root_channels(&b), f.root_channels, "{}: root channels", f.file);
        assert_eq!(b.declared_frames, f.frames_header, "{}: Frames:", f.file);
        assert_eq!(b.frames(), f.data_rows, "{}: rows", f.file);
        assert_eq!(b.frame_time.to_bits(), f.frame_time.to_bits(), "{}: frame time {}", f.file, b.frame_time);
        if f.frames_header == f.data_rows {
            assert!(b.warnings.is_empty(), "{}: {:?}", f.file, b.warnings);
        }
    }
}

#[test]
fn invalid_fixtures_give_their_error() {
    for &(file, line, column, words) in INVALID {
        assert_err(&fixture(file), line, column, &[words]);
    }
}

#[test]
fn first_and_last_rows_equal_the_file_text() {
    for f in FACTS {
        let text = fixture(f.file);
        let b = parse_ok(&text);
        let rows: Vec<&str> = text.lines().map(str::trim).filter(|l| !l.is_empty()).collect();
        let last: Vec<f64> = rows[rows.len() - 1].split_whitespace().map(|t| t.parse().unwrap()).collect();
        let first: Vec<f64> = rows[rows.len() - f.data_rows].split_whitespace().map(|t| t.parse().unwrap()).collect();
        assert_eq!(b.frame(b.frames() - 1), &last[..], "{}", f.file);
        assert_eq!(b.frame(0), &first[..], "{}", f.file);
    }
}

#[test]
fn assimp_frames_mismatch_warns_and_keeps_all_3070_rows() {
    // shared/data/README.md: "`Frames: 3069` but 3070 data rows" — the independent checker
    // counted 3070 complete rows of 66 values, so the rows are right and the header is off by one.
    let b = parse_ok(&fixture("assimp_Boxing_Toes_100fps.bvh"));
    assert_eq!(b.declared_frames, 3069);
    assert_eq!(b.frames(), 3070);
    assert_eq!(b.warnings.len(), 1, "{:?}", b.warnings);
    let w = &b.warnings[0];
    assert_eq!(w.line, 128, "the Frames: line");
    assert!(w.message.contains("3069") && w.message.contains("3070"), "{w}");
    assert_eq!(b.fps(), 100.0);
}

#[test]
fn full_precision_frame_time_is_kept_exactly() {
    let b = parse_ok(&fixture("pybvh_full_precision_frame_time.bvh"));
    assert_eq!(b.frame_time, 0.0417083750417);
    assert_eq!(b.frame_time.to_bits(), "0.0417083750417".parse::<f64>().unwrap().to_bits());
    assert!((b.fps() - 23.976).abs() < 1e-3, "{}", b.fps());
    assert!((b.fps() - 24.0).abs() > 0.02, "23.976 fps must not become 24");
    assert!(bvh::write(&b).contains("Frame Time: 0.0417083750417\n"));
}

#[test]
fn cgspeed_leading_dot_frame_time_and_mixed_line_endings() {
    let text = fixture("12_01.bvh");
    assert!(text.contains("Frame Time: .0083333"));
    let b = parse_ok(&text);
    assert_eq!(b.frame_time, 0.0083333);
    assert_eq!(b.frames(), 524);
}

#[test]
fn mixamo_names_keep_their_colons() {
    let b = parse_ok(&fixture("mixamo_names_freebvh.bvh"));
    assert_eq!(b.joints[0].name, "mixamorig:Hips");
    let top = b.joints.iter().position(|j| j.name == "mixamorig:HeadTop_End").expect("HeadTop_End joint");
    assert_eq!(b.joints[top].kind, JointKind::Joint);
    let end = &b.joints[top + 1];
    assert_eq!((end.name.as_str(), end.kind, end.parent), ("mixamorig:HeadTop_End_End", JointKind::EndSite, Some(top)));
}

#[test]
fn gpmat_tab_separated_frames_line_and_crlf() {
    let text = fixture("gpmat_Swagger2_1frame.bvh");
    assert!(text.contains("Frames:\t1\r\n"));
    let b = parse_ok(&text);
    assert_eq!(b.frames(), 1);
    assert_eq!(b.joints[1].name, "lowerback");
}

#[test]
fn bundled_web_sample_parses() {
    // www/sample.bvh is a copy of shared/data/cmu/mocap6/13_30.bvh; manifest.json: 2465 frames,
    // 31 joints, 96 channels, frame time 0.0083333.
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("www/sample.bvh");
    let b = parse_ok(&std::fs::read_to_string(path).expect("www/sample.bvh"));
    assert_eq!((b.frames(), b.joint_indices().count(), b.channels_per_frame), (2465, 31, 96));
    assert_eq!(b.frame_time, 0.0083333);
}

// ---------------------------------------------------------------------------------------------
// Round trip
// ---------------------------------------------------------------------------------------------

#[test]
fn write_then_parse_round_trips_every_fixture() {
    for f in FACTS {
        let b = parse_ok(&fixture(f.file));
        let written = bvh::write(&b);
        let again = parse_ok(&written);
        assert_eq!(again.joints, b.joints, "{}", f.file);
        assert_eq!(again.frame_time.to_bits(), b.frame_time.to_bits(), "{}", f.file);
        assert_eq!(again.frames(), b.frames(), "{}", f.file);
        assert_eq!(again.declared_frames, b.frames(), "{}: the writer declares the rows present", f.file);
        assert!(again.warnings.is_empty(), "{}: {:?}", f.file, again.warnings);
        // Required: equal within print precision (1e-6 relative). Shortest round-trip printing
        // in fact gives the identical f64 values.
        for (k, (x, y)) in b.values.iter().zip(&again.values).enumerate() {
            assert!((x - y).abs() <= 1e-6 * x.abs().max(1.0), "{}: value {k}: {x} vs {y}", f.file);
            assert_eq!(x.to_bits(), y.to_bits(), "{}: value {k}", f.file);
        }
        assert_eq!(bvh::write(&again), written, "{}: writing is stable", f.file);
    }
}

#[test]
fn written_file_uses_tabs_and_standard_keywords() {
    let written = bvh::write(&parse_ok(&fixture("bvh_anim_test_simple.bvh")));
    let expected = "HIERARCHY\nROOT Base\n{\n\tOFFSET 0 0 0\n\tCHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n\tJOINT End\n\t{\n\t\tOFFSET 0 0 15\n\t\tCHANNELS 3 Zrotation Xrotation Yrotation\n\t\tEnd Site\n\t\t{\n\t\t\tOFFSET 0 0 30\n\t\t}\n\t}\n}\nMOTION\nFrames: 2\nFrame Time: 0.033333333\n0 0 0 0 0 0 0 0 0\n1 1 1 1 1 1 1 1 1\n";
    assert_eq!(written, expected);
}

// ---------------------------------------------------------------------------------------------
// Quirks of the format
// ---------------------------------------------------------------------------------------------

#[test]
fn rotation_before_position_root_keeps_file_order() {
    let text = small(
        "Zrotation Xrotation Yrotation Xposition Yposition Zposition",
        "Yrotation Zrotation Xrotation",
        1,
        "1 2 3 4 5 6 7 8 9\n",
    );
    let b = parse_ok(&text);
    use Channel::*;
    assert_eq!(b.joints[0].channels, [Zrotation, Xrotation, Yrotation, Xposition, Yposition, Zposition]);
    assert_eq!(b.joints[1].channels, [Yrotation, Zrotation, Xrotation]);
    assert_eq!(b.joints[1].channel_start, 6);
    assert_eq!(b.frame(0)[3], 4.0, "Xposition is the 4th value");
}

#[test]
fn position_channels_on_a_non_root_joint_and_rotation_only_root() {
    let text = small(R3, P6, 1, "1 2 3 4 5 6 7 8 9\n");
    let b = parse_ok(&text);
    assert_eq!(b.joints[0].channels.len(), 3);
    assert_eq!(b.joints[1].channels.len(), 6);
    assert_eq!(b.joints[1].channel_start, 3);
    assert_eq!(b.joints[1].channels[0], Channel::Xposition);
    assert_eq!(b.channels_per_frame, 9);
}

#[test]
fn lf_crlf_lone_cr_and_mixed_line_endings_parse_identically() {
    let lf = simple9();
    let reference = parse_ok(&lf);
    let crlf = lf.replace('\n', "\r\n");
    let cr = lf.replace('\n', "\r");
    let mixed: String =
        lf.split('\n').enumerate().map(|(i, l)| format!("{l}{}", ["\n", "\r\n", "\r"][i % 3])).collect();
    for text in [&crlf, &cr, &mixed] {
        assert_eq!(parse_ok(text), reference);
    }
    // Line numbers count each LF, CRLF or CR once: a bad value on line 20 is reported there.
    let bad = lf.replace("10 11 12 13", "10 11 oops 13");
    for text in [bad.clone(), bad.replace('\n', "\r\n"), bad.replace('\n', "\r")] {
        assert_err(&text, 20, 7, &["`oops`"]);
    }
}

#[test]
fn scientific_notation_in_offsets_values_and_frame_time() {
    let text = simple9()
        .replace("OFFSET 0 5 0", "OFFSET 1.5e-3 -2E+2 3e0")
        .replace("Frame Time: 0.0333333", "Frame Time: 8.3333E-3")
        .replace("1 2 3 4", "1e2 -2.5E-1 3.0e+0 4");
    let b = parse_ok(&text);
    assert_eq!(b.joints[1].offset, [0.0015, -200.0, 3.0]);
    assert_eq!(b.frame_time, 0.0083333);
    assert_eq!(&b.frame(0)[..4], &[100.0, -0.25, 3.0, 4.0]);
}

#[test]
fn utf8_bom_is_skipped() {
    let b = parse_ok(&format!("\u{feff}{}", simple9()));
    assert_eq!(b, parse_ok(&simple9()));
    // columns on line 1 do not count the BOM
    assert_err("\u{feff}HIERARCHX", 1, 1, &["expected `HIERARCHY`"]);
}

#[test]
fn tabs_and_runs_of_spaces_anywhere() {
    let text = simple9()
        .replace("OFFSET 0 5 0", "OFFSET\t0 \t 5\t\t0   ")
        .replace("CHANNELS 3 Zrotation", "CHANNELS   3\tZrotation")
        .replace("Frames: 2", "Frames:\t\t2")
        .replace("1 2 3", "  1\t2    3");
    let b = parse_ok(&text);
    assert_eq!(b.joints[1].offset, [0.0, 5.0, 0.0]);
    assert_eq!(&b.frame(0)[..3], &[1.0, 2.0, 3.0]);
}

#[test]
fn names_with_colons_and_spaces() {
    let text = simple9().replace("ROOT Hips", "ROOT mixamorig:Hips").replace("JOINT Spine", "JOINT  Left Up Leg \t");
    let b = parse_ok(&text);
    assert_eq!(b.joints[0].name, "mixamorig:Hips");
    assert_eq!(b.joints[1].name, "Left Up Leg");
    assert_eq!(b.joints[2].name, "Left Up Leg_End");
    assert_eq!(b.joints[2].parent, Some(1));
}

#[test]
fn frames_and_frame_time_label_variants() {
    for (frames, time, expect) in [
        ("Frames:\t2", "Frame Time:\t0.0333333", 0.0333333),
        ("Frames:2", "Frame Time:.0083333", 0.0083333),
        ("Frames : 2", "Frame Time : 0.01", 0.01),
        ("FRAMES: 2", "frame time: 0.0417083750417", 0.0417083750417),
        ("Frames:    2", "Frame  Time:    0.010000", 0.01),
    ] {
        let text = simple9().replace("Frames: 2", frames).replace("Frame Time: 0.0333333", time);
        let b = parse_ok(&text);
        assert_eq!((b.frames(), b.frame_time), (2, expect), "{frames} / {time}");
    }
}

#[test]
fn keywords_and_channel_names_in_any_case_and_braces_on_the_same_line() {
    let text = "hierarchy\nRoot Hips {\n offset 0 0 0\n channels 3 xposition YPOSITION Zposition\n End Site {\n  OFFSET 0 1 0 }\n}\nmotion\nFrames: 1\nFrame Time: 0.5\n1 2 3\n";
    let b = parse_ok(text);
    assert_eq!(b.joints[0].name, "Hips");
    assert_eq!(b.joints[0].channels, [Channel::Xposition, Channel::Yposition, Channel::Zposition]);
    assert_eq!(b.joints[1].name, "Hips_End");
    assert_eq!(b.joints[1].offset, [0.0, 1.0, 0.0]);
}

#[test]
fn channels_may_come_before_offset() {
    let text = simple9().replace(
        "\t\tOFFSET 0 5 0\n\t\tCHANNELS 3 Zrotation Yrotation Xrotation",
        "\t\tCHANNELS 3 Zrotation Yrotation Xrotation\n\t\tOFFSET 0 5 0",
    );
    assert_eq!(parse_ok(&text), parse_ok(&simple9()));
}

#[test]
fn multiple_roots_share_the_frame_row() {
    let text = "HIERARCHY\nROOT A\n{\n\tOFFSET 0 0 0\n\tCHANNELS 3 Xposition Yposition Zposition\n\tEnd Site\n\t{\n\t\tOFFSET 0 1 0\n\t}\n}\nROOT B\n{\n\tOFFSET 5 0 0\n\tCHANNELS 2 Yrotation Xposition\n}\nMOTION\nFrames: 1\nFrame Time: 0.1\n1 2 3 4 5\n";
    let b = parse_ok(text);
    let roots: Vec<&str> = b.joints.iter().filter(|j| j.kind == JointKind::Root).map(|j| j.name.as_str()).collect();
    assert_eq!(roots, ["A", "B"]);
    assert_eq!(b.joints[2].channel_start, 3);
    assert_eq!(b.channels_per_frame, 5);
    assert_eq!(parse_ok(&bvh::write(&b)), b);
}

#[test]
fn several_end_sites_get_distinct_names() {
    let text = "HIERARCHY\nROOT Hand\n{\n OFFSET 0 0 0\n CHANNELS 1 Zrotation\n End Site\n {\n  OFFSET 1 0 0\n }\n End Site\n {\n  OFFSET 0 1 0\n }\n}\nMOTION\nFrames: 1\nFrame Time: 0.1\n7\n";
    let b = parse_ok(text);
    let names: Vec<&str> = b.joints.iter().map(|j| j.name.as_str()).collect();
    assert_eq!(names, ["Hand", "Hand_End", "Hand_End2"]);
}

#[test]
fn duplicate_joint_names_warn() {
    let text = simple9().replace("JOINT Spine", "JOINT Hips");
    let b = parse_ok(&text);
    assert_eq!(b.warnings.len(), 1);
    assert_eq!(b.warnings[0].line, 6);
    assert!(b.warnings[0].message.contains("`Hips`") && b.warnings[0].message.contains("line 2"), "{}", b.warnings[0]);
}

#[test]
fn trailing_blank_lines_whitespace_and_no_final_newline() {
    let a = parse_ok(&format!("{}\n\n  \t\n\r\n\n", simple9()));
    let b = parse_ok(simple9().trim_end());
    assert_eq!(a.frames(), 2);
    assert_eq!(a, b);
    assert!(a.warnings.is_empty());
}

#[test]
fn blank_lines_between_rows_are_skipped() {
    let b = parse_ok(&small(P6, R3, 2, "\n1 2 3 4 5 6 7 8 9\n\n   \n10 11 12 13 14 15 16 17 18\n"));
    assert_eq!(b.frames(), 2);
    assert!(b.warnings.is_empty());
}

#[test]
fn frames_count_larger_or_smaller_than_rows_warns_with_both_numbers() {
    for (declared, word) in [(5, "5"), (1, "1")] {
        let b = parse_ok(&small(P6, R3, declared, "1 2 3 4 5 6 7 8 9\n10 11 12 13 14 15 16 17 18\n"));
        assert_eq!((b.frames(), b.declared_frames), (2, declared));
        assert_eq!(b.warnings.len(), 1);
        let w = &b.warnings[0];
        assert_eq!(w.line, 17);
        assert!(
            w.message.contains(&format!("`Frames:` says {word}")) && w.message.contains("2 complete data rows"),
            "{w}"
        );
        assert_eq!(w.to_string(), format!("line 17: {}", w.message));
    }
}

#[test]
fn huge_declared_frame_count_is_only_a_warning_and_allocates_by_the_input() {
    let b = parse_ok(&small(P6, R3, 4_000_000_000, "1 2 3 4 5 6 7 8 9\n"));
    assert_eq!(b.frames(), 1);
    assert!(b.values.capacity() < 1000, "capacity {}", b.values.capacity());
    assert!(b.warnings[0].message.contains("4000000000"));
}

#[test]
fn incomplete_last_row_is_dropped_with_a_warning() {
    // Decision: a truncated last row (the usual end of a cut download) keeps every complete row
    // and warns; an incomplete row anywhere else is an error (see `too_few_values_in_a_row`).
    let b = parse_ok(&small(P6, R3, 3, "1 2 3 4 5 6 7 8 9\n10 11 12 13 14 15 16 17 18\n19 20 21 2\n\n"));
    assert_eq!(b.frames(), 2);
    assert_eq!(b.values.len(), 18);
    assert_eq!(b.warnings.len(), 2, "{:?}", b.warnings);
    assert_eq!(b.warnings[0].line, 21);
    assert!(b.warnings[0].message.contains("4 of 9 values"), "{}", b.warnings[0]);
    assert!(
        b.warnings[1].message.contains("says 3") && b.warnings[1].message.contains("2 complete"),
        "{}",
        b.warnings[1]
    );
}

#[test]
fn zero_frames_and_zero_channels() {
    let b = parse_ok(&small(P6, R3, 0, ""));
    assert_eq!((b.frames(), b.values.len()), (0, 0));
    assert!(b.warnings.is_empty());
    let text = "HIERARCHY\nROOT A\n{\nOFFSET 0 0 0\nCHANNELS 0\n}\nMOTION\nFrames: 1\nFrame Time: 0.1\n";
    let b = parse_ok(text);
    assert_eq!((b.channels_per_frame, b.frames()), (0, 1));
    assert!(b.warnings.is_empty(), "{:?}", b.warnings);
    assert_eq!(parse_ok(&bvh::write(&b)), b);
    let b = parse_ok(&text.replace("Frames: 1", "Frames: 0"));
    assert_eq!((b.frames(), b.warnings.len()), (0, 0));
}

#[test]
fn zero_channels_give_one_frame_whatever_frames_declares() {
    // Decision: a hierarchy with no channels has no data rows, so `Frames:` has nothing behind
    // it. It describes one pose (the rest pose): 1 frame and a warning naming the `Frames:` line,
    // like any other `Frames:` / rows mismatch. Before, this 100-byte file became 2^25 frames.
    let text = "HIERARCHY\nROOT Pelvis\n{\n\tOFFSET 0 0 0\n\tCHANNELS 0\n}\nMOTION\nFrames: 33554432\nFrame Time: 0.008333333\n";
    assert_eq!(text.len(), 100);
    let b = parse_ok(text);
    assert_eq!((b.channels_per_frame, b.declared_frames, b.frames()), (0, 33_554_432, 1));
    assert_eq!(b.warnings.len(), 1, "{:?}", b.warnings);
    let w = &b.warnings[0];
    assert_eq!(w.line, 8, "the Frames: line");
    assert!(
        w.message.contains("33554432") && w.message.contains("no channels") && w.message.contains("1 frame"),
        "{w}"
    );
    // Written back, it says what it holds.
    let again = parse_ok(&bvh::write(&b));
    assert_eq!((again.declared_frames, again.frames()), (1, 1));
    assert!(again.warnings.is_empty());
    // Joints and End Sites without channels: the same.
    let text = "HIERARCHY\nROOT A\n{\nOFFSET 0 0 0\nCHANNELS 0\nJOINT B\n{\nOFFSET 0 1 0\nCHANNELS 0\nEnd Site\n{\nOFFSET 0 1 0\n}\n}\n}\nMOTION\nFrames: 3\nFrame Time: 0.1\n";
    let b = parse_ok(text);
    assert_eq!((b.joints.len(), b.frames(), b.warnings.len()), (3, 1, 1));
}

#[test]
fn progress_is_reported_in_steps_up_to_one() {
    let text = fixture("131_03.bvh");
    let mut seen = Vec::new();
    let b = bvh::parse_with_progress(&text, &ParseLimits::default(), &mut |p| seen.push(p)).expect("parses");
    assert_eq!(b.frames(), 1102);
    assert!(seen.len() >= 20, "only {} progress reports", seen.len());
    assert!(seen.windows(2).all(|w| w[0] <= w[1]), "{seen:?}");
    assert!(seen.iter().all(|p| (0.0..=1.0).contains(p)));
    assert_eq!(seen.last(), Some(&1.0));
    let gaps = seen.windows(2).map(|w| w[1] - w[0]).fold(0.0, f64::max);
    assert!(gaps <= 0.05, "largest gap {gaps}");
}

// ---------------------------------------------------------------------------------------------
// Errors: line, column, message
// ---------------------------------------------------------------------------------------------

#[test]
fn empty_file_and_missing_hierarchy() {
    assert_err("", 1, 1, &["expected `HIERARCHY`", "empty"]);
    assert_err("  \n\n", 3, 1, &["expected `HIERARCHY`", "end of file"]);
    assert_err("\n  ROOT Hips", 2, 3, &["expected `HIERARCHY`", "found `ROOT`"]);
}

#[test]
fn missing_brace_after_joint_name() {
    let text = simple9().replace("\tJOINT Spine\n\t{\n", "\tJOINT Spine\n");
    assert_err(&text, 7, 3, &["expected `{` after JOINT name, found `OFFSET`"]);
    let text = simple9().replace("ROOT Hips\n{\n", "ROOT Hips\n");
    assert_err(&text, 3, 2, &["expected `{` after ROOT name, found `OFFSET`"]);
    let text = simple9().replace("\t\tEnd Site\n\t\t{\n", "\t\tEnd Site\n");
    assert_err(&text, 11, 4, &["expected `{` after `End Site`, found `OFFSET`"]);
}

#[test]
fn missing_joint_name() {
    assert_err(&simple9().replace("JOINT Spine", "JOINT"), 6, 7, &["expected a joint name after `JOINT`"]);
    assert_err(&simple9().replace("ROOT Hips", "ROOT {"), 2, 6, &["expected a joint name after `ROOT`"]);
}

#[test]
fn truncated_files() {
    let full = simple9();
    // in the hierarchy: cut after "\t\tCHANNELS 3 Zrotation" (line 9)
    let cut = &full[..full.find("Zrotation Yrotation Xrotation\n\t\tEnd").unwrap() + 9];
    assert_err(cut, 9, 23, &["`CHANNELS 3` of joint `Spine` needs 3 channel names", "found end of file after 1"]);
    let cut = &full[..full.find("\t}\n}\nMOTION").unwrap()];
    assert_err(cut, 14, 1, &["expected `}` closing JOINT `Spine`", "end of file"]);
    // cut after the hierarchy: a skeleton with no motion (0 frames, with a warning), which the
    // loader refuses at the end of the file because it needs a frame
    let cut = &full[..full.find("MOTION").unwrap()];
    let b = parse_ok(cut);
    assert_eq!((b.joints.len(), b.frames(), b.declared_frames), (3, 0, 0));
    assert_eq!(b.warnings.len(), 1, "{:?}", b.warnings);
    assert_eq!(b.warnings[0].line, 16);
    assert!(b.warnings[0].message.contains("no `MOTION` section): a skeleton with no motion"), "{:?}", b.warnings);
    let limits = ParseLimits { min_frames: 1, ..ParseLimits::default() };
    let e = bvh::parse_with_progress(cut, &limits, &mut |_| {}).unwrap_err();
    assert_eq!((e.line, e.column), (16, 1), "{e}");
    assert!(e.message.contains("nothing to play or segment"), "{e}");
    let cut = &full[..full.find("Frames").unwrap()];
    assert_err(cut, 17, 1, &["expected `Frames:` after `MOTION`", "end of file"]);
    let cut = &full[..full.find("Frame Time").unwrap()];
    assert_err(cut, 18, 1, &["expected `Frame Time:` after `Frames:`", "end of file"]);
    let cut = &full[..full.find("0.0333333").unwrap()];
    assert_err(cut, 18, 13, &["expected a value after `Frame Time:`", "end of file"]);
    let cut = &full[..full.find("1 2 3").unwrap()];
    assert_err(cut, 19, 1, &["`Frames:` declares 2 frames but the file has no complete frame row"]);
    let cut = &full[..full.find("OFFSET 0 3 0").unwrap() + 9];
    assert_err(cut, 12, 13, &["expected 3 numbers after `OFFSET`", "end of file after 1"]);
}

#[test]
fn unbalanced_braces() {
    // a missing `}`: MOTION arrives while Hips is still open
    let text = simple9().replace("\t}\n}\nMOTION", "\t}\nMOTION");
    assert_err(&text, 15, 1, &["unbalanced braces", "found `MOTION`", "joint `Hips` is still open"]);
    // an extra `}`
    let text = simple9().replace("}\nMOTION", "}\n}\nMOTION");
    assert_err(&text, 16, 1, &["unbalanced braces", "`}` closes nothing"]);
    // a second `{`
    let text = simple9().replace("\t\tOFFSET 0 5 0", "\t\t{\n\t\tOFFSET 0 5 0");
    assert_err(&text, 8, 3, &["unknown keyword `{` in joint `Spine`"]);
}

#[test]
fn unknown_keyword() {
    let text = simple9().replace("\t\tCHANNELS 3", "\t\tROTATION 1 2\n\t\tCHANNELS 3");
    assert_err(
        &text,
        9,
        3,
        &["unknown keyword `ROTATION` in joint `Spine`", "expected `OFFSET`, `CHANNELS`, `JOINT`, `End Site` or `}`"],
    );
    let text = simple9().replace("\t\t\tOFFSET 0 3 0", "\t\t\tOFFSET 0 3 0\n\t\t\tCHANNELS 0");
    assert_err(&text, 13, 4, &["expected `OFFSET` or `}` in the End Site of `Spine`, found `CHANNELS`"]);
    assert_err(&simple9().replace("End Site", "End Sight"), 10, 7, &["expected `Site` after `End`, found `Sight`"]);
    assert_err(&simple9().replace("ROOT Hips", "ROOTS Hips"), 2, 1, &["expected `ROOT`, found `ROOTS`"]);
    assert_err(&simple9().replace("MOTION", "MOTIONS"), 16, 1, &["expected `ROOT` or `MOTION`, found `MOTIONS`"]);
}

#[test]
fn wrong_channel_count() {
    // fewer names than the count
    let text = simple9().replace("CHANNELS 3 Zrotation Yrotation Xrotation", "CHANNELS 3 Zrotation Yrotation");
    assert_err(&text, 10, 3, &["`CHANNELS 3` of joint `Spine` needs 3 channel names", "found `End` after 2"]);
    // more names than the count
    let text =
        simple9().replace("CHANNELS 3 Zrotation Yrotation Xrotation", "CHANNELS 2 Zrotation Yrotation Xrotation");
    assert_err(&text, 9, 34, &["`CHANNELS 2` of joint `Spine` is followed by more channel names than 2: `Xrotation`"]);
    // impossible counts
    assert_err(&simple9().replace("CHANNELS 3", "CHANNELS 7"), 9, 12, &["channel count from 0 to 6", "found `7`"]);
    assert_err(&simple9().replace("CHANNELS 3", "CHANNELS -1"), 9, 12, &["channel count from 0 to 6", "found `-1`"]);
    assert_err(&simple9().replace("CHANNELS 3", "CHANNELS Zrotation"), 9, 12, &["channel count", "found `Zrotation`"]);
    // a channel twice, an unknown channel
    assert_err(
        &simple9().replace("Zrotation Yrotation Xrotation\n\t\tEnd", "Zrotation Zrotation Xrotation\n\t\tEnd"),
        9,
        24,
        &["channel `Zrotation` listed twice for joint `Spine`"],
    );
    assert_err(
        &simple9().replace("Zrotation Yrotation Xrotation\n\t\tEnd", "Zrotation Yrotation Wrotation\n\t\tEnd"),
        9,
        34,
        &["found `Wrotation` after 2"],
    );
}

#[test]
fn frame_rows_must_match_the_channel_count() {
    // too many values: the column of the first extra value
    let text = small(P6, R3, 2, "1 2 3 4 5 6 7 8 9\n10 11 12 13 14 15 16 17 18 19\n");
    assert_err(&text, 20, 28, &["too many values in frame row: expected 9"]);
}

#[test]
fn too_few_values_in_a_row_that_is_not_the_last() {
    let text = small(P6, R3, 3, "1 2 3 4 5 6 7 8 9\n10 11 12\n1 2 3 4 5 6 7 8 9\n");
    assert_err(&text, 20, 9, &["too few values in frame row: expected 9, found 3"]);
}

#[test]
fn non_numeric_values_name_line_and_column() {
    let text = small(P6, R3, 2, "1 2 3 4 5 6 7 8 9\n10 11 12 13 x14 15 16 17 18\n");
    assert_err(&text, 20, 13, &["expected a number (value 5 of 9 in the frame row), found `x14`"]);
    let text = small(P6, R3, 1, "1 2 3 4 5 6 7 8 1,5\n");
    assert_err(&text, 19, 17, &["found `1,5`"]);
    let text = simple9().replace("OFFSET 0 5 0", "OFFSET 0 five 0");
    assert_err(&text, 8, 12, &["expected 3 numbers after `OFFSET`, found `five` after 1"]);
    let text = simple9().replace("OFFSET 0 5 0", "OFFSET 0 5");
    assert_err(&text, 9, 3, &["expected 3 numbers after `OFFSET`, found `CHANNELS` after 2"]);
    let text = simple9().replace("OFFSET 0 5 0", "OFFSET 0 5 0 7");
    assert_err(&text, 8, 16, &["unexpected number `7` in joint `Spine`"]);
}

#[test]
fn nan_and_infinite_values_are_rejected() {
    for bad in ["nan", "NaN", "inf", "-infinity", "1e999"] {
        let text = small(P6, R3, 1, &format!("1 2 {bad} 4 5 6 7 8 9\n"));
        assert_err(&text, 19, 5, &[&format!("value `{bad}` is not a finite number")]);
        let text = simple9().replace("OFFSET 0 5 0", &format!("OFFSET 0 {bad} 0"));
        assert_err(&text, 8, 12, &["`OFFSET` value", "is not a finite number"]);
    }
}

#[test]
fn frame_time_must_be_a_positive_finite_number() {
    for (bad, words) in [
        ("0", "positive finite"),
        ("0.0", "positive finite"),
        ("-0.01", "positive finite"),
        ("inf", "positive finite"),
        ("NaN", "positive finite"),
        ("fast", "expected seconds per frame"),
    ] {
        let text = simple9().replace("Frame Time: 0.0333333", &format!("Frame Time: {bad}"));
        assert_err(&text, 18, 13, &[words, &format!("`{bad}`")]);
    }
}

#[test]
fn frames_must_be_a_whole_number() {
    assert_err(
        &simple9().replace("Frames: 2", "Frames: -2"),
        17,
        9,
        &["whole number of frames", "must not be negative", "`-2`"],
    );
    assert_err(&simple9().replace("Frames: 2", "Frames: 2.5"), 17, 9, &["whole number of frames", "`2.5`"]);
    assert_err(&simple9().replace("Frames: 2", "Frames: 99999999999999999999999"), 17, 9, &["too large"]);
    assert_err(&simple9().replace("Frames: 2", "Frames 2"), 17, 8, &["expected `:` after `Frames`, found `2`"]);
    assert_err(
        &simple9().replace("Frames: 2", "Frame: 2"),
        17,
        1,
        &["expected `Frames:` after `MOTION`, found `Frame:`"],
    );
}

#[test]
fn no_joints() {
    assert_err("HIERARCHY\nMOTION\nFrames: 0\nFrame Time: 0.1\n", 2, 1, &["the hierarchy has no joints"]);
    assert_err("HIERARCHY\n", 2, 1, &["expected `ROOT`", "end of file"]);
}

#[test]
fn missing_offset() {
    let text = simple9().replace("\t\tOFFSET 0 5 0\n", "");
    assert_err(&text, 9, 3, &["expected `OFFSET` in JOINT `Spine` before `End`"]);
    let text = simple9().replace("\t\t\tOFFSET 0 3 0\n", "");
    assert_err(&text, 12, 3, &["expected `OFFSET` in the End Site of `Spine` before `}`"]);
    let text = simple9().replace("\tCHANNELS 6", "\tOFFSET 1 1 1\n\tCHANNELS 6");
    assert_err(&text, 5, 2, &["second `OFFSET` in joint `Hips`"]);
}

#[test]
fn limits_are_enforced() {
    let limits = ParseLimits { max_joints: 2, ..ParseLimits::default() };
    let e = bvh::parse_with_progress(&simple9(), &limits, &mut |_| {}).expect_err("3 nodes > 2");
    assert_eq!((e.line, e.column), (10, 3), "{e}");
    assert!(e.message.contains("too many joints: the limit is 2"), "{e}");
    let limits = ParseLimits { max_values: 10, ..ParseLimits::default() };
    let e = bvh::parse_with_progress(&simple9(), &limits, &mut |_| {}).expect_err("18 values > 10");
    assert_eq!((e.line, e.column), (20, 1), "{e}");
    assert!(e.message.contains("too many frame values: the limit is 10"), "{e}");
    let limits = ParseLimits { max_values: 18, max_joints: 3, ..ParseLimits::default() };
    assert!(bvh::parse_with_progress(&simple9(), &limits, &mut |_| {}).is_ok());
}

#[test]
fn deep_nesting_is_not_a_stack_overflow() {
    let mut text = String::from("HIERARCHY\nROOT r\n{\nOFFSET 0 0 0\nCHANNELS 0\n");
    for i in 0..50_000 {
        text.push_str(&format!("JOINT j{i}\n{{\nOFFSET 0 0 0\n"));
    }
    let e = parse_err(&text);
    assert!(e.message.contains("the hierarchy nests too deep: the limit is 256 levels"), "{e}");
    // the 256th JOINT opens level 257: its keyword is on line 6 + 3 × 255
    assert_eq!((e.line, e.column), (6 + 3 * 255, 1), "{e}");
    let limits = ParseLimits { max_depth: usize::MAX, ..ParseLimits::default() };
    let e = bvh::parse_with_progress(&text, &limits, &mut |_| {}).expect_err("too many joints");
    assert!(e.message.contains("too many joints"), "{e}");
    let limits = ParseLimits { max_joints: 100_000, max_depth: 100_000, ..ParseLimits::default() };
    let e = bvh::parse_with_progress(&text, &limits, &mut |_| {}).expect_err("never closed");
    assert!(e.message.contains("expected `}` closing JOINT `j49999`"), "{e}");
}

#[test]
fn long_and_odd_tokens_are_shown_short_and_escaped() {
    let long = "y".repeat(5000);
    let e = parse_err(&format!("{long}\n"));
    assert!(e.message.len() < 200, "{}", e.message.len());
    let e = parse_err("HIERARCHY\nROOT a\n{\n\u{0}\u{7}\n");
    assert!(e.message.contains("`\\0\\u{7}`"), "{e}");
    assert_eq!((e.line, e.column), (4, 1));
}

// ---------------------------------------------------------------------------------------------
// Fuzz: no input panics, hangs or breaks the invariants
// ---------------------------------------------------------------------------------------------

use mocapseg::stats::Rng;

/// Parses any bytes (lossily decoded); must give Ok with the invariants or an Err with a sane
/// position. A panic fails the test naming the input. Returns whether it parsed.
fn check_any(bytes: &[u8], what: &str) -> bool {
    let text = String::from_utf8_lossy(bytes);
    let limits = ParseLimits { max_joints: 2_000, max_values: 1 << 20, ..ParseLimits::default() };
    let result = std::panic::catch_unwind(|| {
        bvh::parse_with_progress(&text, &limits, &mut |p| assert!((0.0..=1.0).contains(&p)))
    });
    match result {
        Err(_) => panic!("parser panicked on {what}"),
        Ok(Ok(b)) => {
            check_invariants(&b);
            true
        }
        Ok(Err(e)) => {
            let lines = text.split(['\n', '\r']).count() + 1;
            assert!(e.line >= 1 && e.line <= lines, "{what}: line {} of {lines}: {e}", e.line);
            assert!(e.column >= 1, "{what}: {e}");
            assert!(!e.message.is_empty());
            false
        }
    }
}

fn env_number(name: &str, default: u64) -> u64 {
    std::env::var(name).ok().and_then(|v| v.parse().ok()).unwrap_or(default)
}

/// The hierarchy and the first rows of a fixture (so the fuzz loop stays fast).
fn head(text: &str, rows: usize) -> String {
    let motion = text.find("MOTION").unwrap_or(text.len());
    let mut end = motion;
    for _ in 0..rows + 3 {
        match text[end..].find('\n') {
            Some(n) => end += n + 1,
            None => return text.to_string(),
        }
    }
    text[..end].to_string()
}

#[rustfmt::skip]
const SPICE: &[&str] = &[
    "{", "}", "{{", "}}", "JOINT", "End Site", "End", "ROOT", "MOTION", "HIERARCHY", "OFFSET", "CHANNELS",
    "CHANNELS 6", "CHANNELS 99999999999999999999", "Frames:", "Frame Time:", "nan", "-inf", "1e999", "-", ".",
    "1e", "99999999999", "\r", "\n", "\r\n", "\t", "\u{feff}", "é", "\u{0}", "Xposition", "-0",
    "Frames: 4294967296",
];

fn mutate(rng: &mut Rng, base: &[u8]) -> Vec<u8> {
    let mut b = base.to_vec();
    for _ in 0..1 + rng.below(3) {
        let at = rng.below(b.len() + 1);
        match rng.below(6) {
            0 => b.truncate(at),
            1 if at < b.len() => b[at] = rng.next_u64() as u8,
            2 => {
                let len = rng.below(64).min(b.len() - at);
                b.drain(at..at + len);
            }
            3 => {
                let len = rng.below(256).min(b.len() - at);
                let copy: Vec<u8> = b[at..at + len].to_vec();
                let to = rng.below(b.len() + 1);
                b.splice(to..to, copy);
            }
            _ => {
                let s = SPICE[rng.below(SPICE.len())];
                b.splice(at..at, s.bytes());
            }
        }
    }
    b
}

#[test]
fn fuzz_mutated_and_truncated_fixtures_never_panic() {
    // MOCAPSEG_FUZZ_ROUNDS / MOCAPSEG_FUZZ_SEED run a longer or different campaign.
    let rounds = env_number("MOCAPSEG_FUZZ_ROUNDS", 300) as usize;
    let mut rng = Rng::new(env_number("MOCAPSEG_FUZZ_SEED", 0x5eed_b0a7));
    let mut total_parsed = 0;
    for f in FACTS {
        let text = fixture(f.file);
        let base = head(&text, 4);
        let bytes = base.as_bytes();
        // truncation at 200 spread positions and at every position of the first 300 bytes
        for k in 0..200 {
            check_any(&bytes[..bytes.len() * k / 200], &format!("{} cut at {}", f.file, bytes.len() * k / 200));
        }
        for cut in 0..bytes.len().min(300) {
            check_any(&bytes[..cut], &format!("{} cut at {cut}", f.file));
        }
        let mut parsed = 0;
        for i in 0..rounds {
            let m = mutate(&mut rng, bytes);
            parsed += usize::from(check_any(&m, &format!("{} mutation {i}", f.file)));
        }
        assert!(parsed < rounds, "{}: every mutation parsed", f.file);
        total_parsed += parsed;
    }
    // The mutations must reach past the first error into valid files too (about 5 % do).
    assert!(total_parsed >= rounds / 3, "only {total_parsed} mutated files parsed");
}

#[test]
fn fuzz_truncated_full_files_keep_complete_rows_or_fail_cleanly() {
    let text = fixture("bvh_anim_test_simple.bvh");
    for cut in 0..=text.len() {
        check_any(&text.as_bytes()[..cut], &format!("cut at {cut}"));
    }
    // cutting inside the last row keeps the first row
    let cut = &text[..text.len() - 6];
    let b = parse_ok(cut);
    assert_eq!(b.frames(), 1);
    assert!(b.warnings.iter().any(|w| w.message.contains("truncated")));
}

#[test]
fn fuzz_random_bytes_and_token_soup_never_panic() {
    let mut rng = Rng::new(42);
    for i in 0..2000 {
        let len = rng.below(400);
        let bytes: Vec<u8> = (0..len).map(|_| rng.next_u64() as u8).collect();
        check_any(&bytes, &format!("random bytes {i}"));
    }
    #[rustfmt::skip]
    const WORDS: &[&str] = &[
        "HIERARCHY", "ROOT", "JOINT", "End", "Site", "{", "}", "OFFSET", "CHANNELS", "3", "6", "0", "1.5", "-2e3",
        "Xposition", "Zrotation", "Yrotation", "MOTION", "Frames:", "Frame", "Time:", "0.01", "a:b", "\n", "\r", "\t",
    ];
    for i in 0..3000 {
        let mut s = String::from("HIERARCHY\nROOT r\n{\nOFFSET 0 0 0\n");
        for _ in 0..rng.below(200) {
            s.push_str(WORDS[rng.below(WORDS.len())]);
            s.push(' ');
        }
        check_any(s.as_bytes(), &format!("token soup {i}: {s:?}"));
    }
}

// ---------------------------------------------------------------------------------------------
// Throughput (not a timed test: run explicitly)
// ---------------------------------------------------------------------------------------------

#[test]
#[ignore = "throughput measurement; run with --release -- --ignored --nocapture"]
fn parse_throughput() {
    let path =
        std::env::var("MOCAPSEG_BENCH_BVH").map(PathBuf::from).unwrap_or_else(|_| fixtures_dir().join("131_03.bvh"));
    let text = std::fs::read_to_string(&path).expect("bench file");
    let mut best = f64::INFINITY;
    for _ in 0..10 {
        let t = std::time::Instant::now();
        let b = bvh::parse(&text).expect("parses");
        best = best.min(t.elapsed().as_secs_f64());
        std::hint::black_box(b);
    }
    let b = bvh::parse(&text).unwrap();
    println!(
        "{}: {:.1} MB in {:.2} ms (best of 10) = {:.0} MB/s, {:.0} frames/s",
        path.display(),
        text.len() as f64 / 1e6,
        best * 1e3,
        text.len() as f64 / 1e6 / best,
        b.frames() as f64 / best
    );
    let t = std::time::Instant::now();
    let written = bvh::write(&b);
    println!("write: {:.0} MB/s", written.len() as f64 / 1e6 / t.elapsed().as_secs_f64());
}
