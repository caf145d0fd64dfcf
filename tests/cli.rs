//! The `mocapseg` command line, run as a user would run it.
#![cfg(not(target_arch = "wasm32"))]

use std::path::PathBuf;
use std::process::{Command, Output};

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures").join(name)
}

fn out_dir() -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("cli");
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_mocapseg")).args(args).output().expect("run mocapseg")
}

fn stdout_json(out: &Output) -> serde_json::Value {
    assert!(out.status.success(), "failed: {}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).expect("JSON on stdout")
}

#[test]
fn info_reports_frames_fps_units_and_warnings() {
    let v = stdout_json(&run(&["info", fixture("02_01.bvh").to_str().unwrap()]));
    assert_eq!(v["file"], "02_01.bvh");
    assert_eq!(v["joints"], 31);
    assert_eq!(v["end_sites"], 7);
    assert_eq!(v["frames"], 343);
    assert_eq!(v["frame_time"], 0.0083333);
    assert!((v["fps"].as_f64().unwrap() - 120.0).abs() < 1e-3);
    assert!((v["duration_s"].as_f64().unwrap() - 343.0 * 0.0083333).abs() < 1e-6);
    assert_eq!(v["units"], "cmu_asf");
    assert_eq!(v["up_axis"], "Y");
    assert_eq!(v["warnings"].as_array().unwrap().len(), 0);

    // The assimp file declares 3069 frames but holds 3070 rows: the rows win, with a warning.
    let v = stdout_json(&run(&["info", fixture("assimp_Boxing_Toes_100fps.bvh").to_str().unwrap()]));
    assert_eq!(v["frames"], 3070);
    assert_eq!(v["declared_frames"], 3069);
    assert_eq!(v["fps"], 100.0);
    let warnings = v["warnings"].as_array().unwrap();
    assert!(warnings.iter().any(|w| w.as_str().unwrap().contains("3069")), "{warnings:?}");
    assert_eq!(warnings.len(), 1, "the mismatch is reported once: {warnings:?}");

    // 23.976 fps stays 23.976.
    let v = stdout_json(&run(&["info", fixture("pybvh_full_precision_frame_time.bvh").to_str().unwrap()]));
    assert_eq!(v["frame_time"], 0.0417083750417);
    assert!((v["fps"].as_f64().unwrap() - 23.976).abs() < 1e-6);
}

#[test]
fn bad_files_fail_with_file_line_and_column() {
    let out = run(&["info", fixture("bad.bvh").to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.starts_with("error: bad.bvh: line 9, column 34:"), "{err}");
    let out = run(&["info", "/definitely/not/here.bvh"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("/definitely/not/here.bvh"));
}

#[test]
fn a_declared_frame_count_without_data_is_one_frame_not_a_huge_image() {
    // every joint has CHANNELS 0 and the file declares 2^25 frames
    let path = out_dir().join("no-channels.bvh");
    std::fs::write(
        &path,
        "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 0\n  CHANNELS 0\n  End Site\n  {\n    OFFSET 0 1 0\n  }\n}\nMOTION\nFrames: 33554432\nFrame Time: 0.0333333\n",
    )
    .unwrap();
    let v = stdout_json(&run(&["info", path.to_str().unwrap()]));
    assert_eq!((v["frames"].as_u64(), v["declared_frames"].as_u64()), (Some(1), Some(33554432)));
    let frames_warnings = v["warnings"].as_array().unwrap().iter().filter(|w| w.as_str().unwrap().contains("Frames:"));
    assert_eq!(frames_warnings.count(), 1, "{v}");
    let png = out_dir().join("no-channels.png");
    let out = run(&["image", path.to_str().unwrap(), "-o", png.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(std::fs::metadata(&png).unwrap().len() < 1000, "a one-column image");
}

#[test]
fn image_writes_a_png_one_column_per_frame() {
    let path = out_dir().join("02_01.png");
    let out = run(&["image", fixture("02_01.bvh").to_str().unwrap(), "-o", path.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&path).unwrap()));
    let reader = decoder.read_info().unwrap();
    let info = reader.info();
    assert_eq!((info.width, info.height), (343, 31));
}

#[test]
fn positions_csv_has_a_row_per_frame_and_xyz_per_joint() {
    let path = out_dir().join("02_01.csv");
    let out = run(&["positions", fixture("02_01.bvh").to_str().unwrap(), "--fps", "30", "-o", path.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = std::fs::read_to_string(&path).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let header: Vec<&str> = lines[0].split(',').collect();
    assert_eq!(&header[..5], &["frame", "time_s", "Hips_x", "Hips_y", "Hips_z"]);
    assert_eq!(header.len(), 2 + 31 * 3);
    // 343 frames at 120 Hz = frames 0, 4, …, 340 at 30 Hz.
    assert_eq!(lines.len() - 1, 86);
    let row: Vec<f64> = lines[2].split(',').map(|v| v.parse().unwrap()).collect();
    assert_eq!(row[0], 1.0);
    assert!((row[1] - 1.0 / 30.0).abs() < 1e-9);
    // Root height of a CMU take is 16–18 units.
    assert!((15.0..19.0).contains(&row[3]), "root y {}", row[3]);
}

#[test]
fn segment_prints_the_schema_and_echoes_overridden_params() {
    let file = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("www/sample.bvh");
    let out = run(&[
        "segment",
        "--method",
        "sssm",
        file.to_str().unwrap(),
        "--param",
        "radius=17",
        "--param",
        "stop_window=6",
    ]);
    let v = stdout_json(&out);
    assert_eq!(v["method"], "sssm");
    assert_eq!(v["frames"], 2465);
    assert_eq!(v["params"]["radius"], 17.0);
    assert_eq!(v["params"]["stop_window"], 6);
    let segs = v["segments"].as_array().unwrap();
    let actions: Vec<_> = segs.iter().filter(|s| s["level"] == "action").collect();
    assert!(actions.len() >= 2, "13_30 holds five exercises, found {} actions", actions.len());
    for s in segs {
        assert!(s["start"].as_u64().unwrap() <= s["end"].as_u64().unwrap());
        assert!(s["end"].as_u64().unwrap() < 2465);
    }

    let out = run(&["segment", file.to_str().unwrap(), "--param", "no_such=1"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("unknown SSSM parameter `no_such`"));
    let out = run(&["segment", file.to_str().unwrap(), "--param", "radius=-1"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("radius"));
    let out = run(&["segment", "--method", "nope", file.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("unknown method `nope`; available: sssm"));
}

/// The registry as `mocapseg methods --json` lists it: every method with its parameters.
fn methods() -> Vec<serde_json::Value> {
    stdout_json(&run(&["methods", "--json"])).as_array().unwrap().clone()
}

#[test]
fn methods_lists_every_method_with_help_and_bounds() {
    let list = methods();
    assert!(list.iter().any(|m| m["info"]["name"] == "sssm"));
    for m in &list {
        let params = m["params"].as_array().unwrap();
        assert!(!params.is_empty(), "{m}");
        for p in params {
            assert!(!p["help"].as_str().unwrap().is_empty() && p["kind"]["type"].is_string(), "{p}");
        }
    }
    let text = run(&["methods"]);
    assert!(text.status.success());
    let text = String::from_utf8_lossy(&text.stdout);
    assert!(text.contains("sssm") && text.contains("radius"), "{text}");
}

#[test]
fn segment_runs_every_registered_method_with_its_defaults_and_an_override() {
    let file = fixture("02_01.bvh");
    for m in methods() {
        let name = m["info"]["name"].as_str().unwrap();
        let v = stdout_json(&run(&["segment", "--method", name, file.to_str().unwrap()]));
        assert_eq!(v["method"], name);
        assert_eq!(v["frames"], 343);
        // every parameter is echoed with its default; a `null` default (the method decides: a labeller's
        // threshold is its model's) with what was decided
        for p in m["params"].as_array().unwrap() {
            let echoed = &v["params"][p["name"].as_str().unwrap()];
            if p["default"].is_null() {
                assert!(echoed.is_number(), "{name}: {p} decided as {echoed}");
            } else {
                assert_eq!(echoed, &p["default"], "{name}: {p}");
            }
        }
        // an override (the first numeric parameter at its upper bound) is echoed
        let numeric = m["params"].as_array().unwrap().iter().find(|p| p["kind"]["type"] == "integer");
        if let Some(p) = numeric {
            let (pname, max) = (p["name"].as_str().unwrap(), &p["kind"]["max"]);
            let out = run(&["segment", "--method", name, file.to_str().unwrap(), "--param", &format!("{pname}={max}")]);
            if out.status.success() {
                let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
                assert_eq!(&v["params"][pname], max, "{name}");
            } else {
                // the largest value may be refused for this take, but never with a panic
                let err = String::from_utf8_lossy(&out.stderr);
                assert!(err.starts_with("error: ") && !err.contains("panicked"), "{name}: {err}");
            }
        }
    }
}

#[test]
fn batch_segments_a_folder_and_skips_a_broken_file() {
    let input = out_dir().join("batch-in");
    let output = out_dir().join("batch-out");
    let _ = std::fs::remove_dir_all(&input);
    let _ = std::fs::remove_dir_all(&output);
    std::fs::create_dir_all(input.join("sub")).unwrap();
    for f in ["02_01.bvh", "35_01.bvh", "bad.bvh"] {
        std::fs::copy(fixture(f), input.join(f)).unwrap();
    }
    std::fs::copy(fixture("12_01.bvh"), input.join("sub/12_01.bvh")).unwrap();
    std::fs::write(input.join("notes.txt"), "not a take").unwrap();
    let out = run(&["segment", "--method", "sssm", input.to_str().unwrap(), "--out", output.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "some takes failed: exit code 2\n{stdout}\n{stderr}");
    // one summary line per take, the broken one with the parser's message
    assert_eq!(stdout.lines().filter(|l| l.starts_with("ok ")).count(), 3, "{stdout}");
    let fail: Vec<&str> = stdout.lines().filter(|l| l.starts_with("FAIL")).collect();
    assert_eq!(fail.len(), 1, "{stdout}");
    let bad = input.join("bad.bvh");
    assert!(fail[0].starts_with(&format!("FAIL  {}: line 9, column 34", bad.display())), "{}", fail[0]);
    assert!(stderr.contains("3 of 4 takes segmented, 1 failed") && stderr.contains("takes/s"), "{stderr}");
    // the summary names the failed take and why, and the exit code's meaning
    assert!(stderr.contains(&format!("failed (not written):\n  {}: line 9, column 34", bad.display())), "{stderr}");
    assert!(stderr.trim_end().ends_with("exit code 2: some takes failed, the rest written"), "{stderr}");
    // one valid segmentation per good take
    for (name, frames) in [("02_01", 343), ("35_01", 358), ("12_01", 524)] {
        let text = std::fs::read_to_string(output.join(format!("{name}.json"))).unwrap();
        let seg = mocapseg::segment::Segmentation::from_json(&text).unwrap();
        assert_eq!((seg.frames, seg.method.as_str()), (frames, "sssm"), "{name}");
        assert_eq!(seg.file, format!("{name}.bvh"));
    }
    assert!(!output.join("bad.json").exists());

    // several takes need --out
    let out = run(&["segment", fixture("02_01.bvh").to_str().unwrap(), fixture("35_01.bvh").to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--out"));
    // a usage error is 1 as well (clap's own code, 2, would read as "some takes failed")
    let out = run(&["segment", "--no-such-flag", input.to_str().unwrap(), "--out", output.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--no-such-flag"));
    assert!(run(&["segment", "--help"]).status.success());
}

/// `segment --method METHOD DIR --out OUT` on one thread with `env` set; its exit code, stdout and stderr.
fn batch_run(
    method: &str,
    input: &std::path::Path,
    output: &std::path::Path,
    env: &[(&str, &str)],
) -> (Option<i32>, String, String) {
    let mut command = Command::new(env!("CARGO_BIN_EXE_mocapseg"));
    command.args(["segment", "--method", method, "--jobs", "1"]).arg(input).arg("--out").arg(output);
    command.envs(env.iter().copied());
    let out = command.output().expect("run mocapseg");
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A fresh input folder named `name` holding `takes` (fixture name, name in the folder).
fn batch_input(name: &str, takes: &[(&str, &str)]) -> (PathBuf, PathBuf) {
    let input = out_dir().join(format!("{name}-in"));
    let output = out_dir().join(format!("{name}-out"));
    let _ = std::fs::remove_dir_all(&input);
    let _ = std::fs::remove_dir_all(&output);
    for (fixture_name, as_name) in takes {
        let to = input.join(as_name);
        std::fs::create_dir_all(to.parent().unwrap()).unwrap();
        std::fs::copy(fixture(fixture_name), to).unwrap();
    }
    (input, output)
}

#[test]
fn a_batch_with_a_panicking_take_writes_the_rest_and_says_which_panicked() {
    let (input, output) = batch_input(
        "batch-panic",
        &[("02_01.bvh", "a.bvh"), ("35_01.bvh", "b.bvh"), ("12_01.bvh", "c.bvh"), ("bad.bvh", "d.bvh")],
    );
    // b's output of an earlier run: b no longer gives one, so it goes
    std::fs::create_dir_all(&output).unwrap();
    std::fs::write(output.join("b.json"), "an earlier run's").unwrap();
    // the debug build's test hook makes the take b.bvh panic; one thread, so the takes after b
    // run on the thread that panicked
    let (code, stdout, stderr) = batch_run("velocity", &input, &output, &[("MOCAPSEG_TEST_PANIC_ON", "b.bvh")]);
    assert_eq!(code, Some(3), "a take panicked: exit code 3\n{stdout}\n{stderr}");
    let b = input.join("b.bvh");
    let panic_line = format!(
        "PANIC {}: panicked: MOCAPSEG_TEST_PANIC_ON: a panic on {} asked for by the test (at src/bin/mocapseg.rs:",
        b.display(),
        b.display()
    );
    assert!(
        stdout.lines().any(|l| l.starts_with(&panic_line) && l.ends_with("b.json of an earlier run removed)")),
        "{stdout}"
    );
    assert_eq!(stdout.lines().filter(|l| l.starts_with("ok ")).count(), 2, "{stdout}");
    assert!(
        stdout.lines().any(|l| l.starts_with(&format!("FAIL  {}: line 9", input.join("d.bvh").display()))),
        "{stdout}"
    );
    for (name, frames) in [("a", 343), ("c", 524)] {
        let seg = mocapseg::segment::Segmentation::from_json(
            &std::fs::read_to_string(output.join(format!("{name}.json"))).unwrap(),
        )
        .unwrap();
        assert_eq!(seg.frames, frames, "{name}");
    }
    assert!(!output.join("b.json").exists() && !output.join("d.json").exists());
    // the summary: counts, then the failed and the panicked take with why, then the exit code
    assert!(stderr.contains("2 of 4 takes segmented, 1 failed, 1 panicked in "), "{stderr}");
    assert!(
        stderr.contains(&format!("failed (not written):\n  {}: line 9, column 34", input.join("d.bvh").display())),
        "{stderr}"
    );
    assert!(
        stderr.contains(&format!(
            "panicked (not written; a bug in mocapseg, please report it):\n  {}: panicked: MOCAPSEG_TEST_PANIC_ON",
            b.display()
        )),
        "{stderr}"
    );
    assert!(stderr.trim_end().ends_with("exit code 3: some take panicked, the rest written"), "{stderr}");
    assert!(!stderr.contains("thread '"), "the take's panic is reported once, not by the default hook too:\n{stderr}");
}

#[test]
fn a_take_that_now_fails_loses_its_earlier_output() {
    let (input, output) = batch_input("batch-stale", &[("02_01.bvh", "a.bvh"), ("35_01.bvh", "b.bvh")]);
    let (code, stdout, stderr) = batch_run("velocity", &input, &output, &[]);
    assert_eq!(code, Some(0), "{stdout}\n{stderr}");
    assert!(stderr.trim_end().ends_with("exit code 0: every take written"), "{stderr}");
    assert!(output.join("a.json").is_file() && output.join("b.json").is_file());
    // b is damaged now: its segmentation of the first run would read as this run's
    std::fs::copy(fixture("bad.bvh"), input.join("b.bvh")).unwrap();
    let (code, stdout, stderr) = batch_run("velocity", &input, &output, &[]);
    assert_eq!(code, Some(2), "{stdout}\n{stderr}");
    assert!(!output.join("b.json").exists(), "b's earlier output left behind as if current");
    assert!(output.join("a.json").is_file());
    let removed = format!("({} of an earlier run removed)", output.join("b.json").display());
    assert!(stdout.lines().any(|l| l.starts_with("FAIL  ") && l.ends_with(&removed)), "{stdout}");
    assert!(
        stderr.contains(&format!("failed (not written):\n  {}: line 9", input.join("b.bvh").display())),
        "{stderr}"
    );
    assert!(stderr.contains(&removed), "{stderr}");
}

#[test]
fn takes_of_one_name_get_files_of_their_own() {
    let (input, output) = batch_input(
        "batch-names",
        &[
            ("02_01.bvh", "p/x.bvh"),
            ("35_01.bvh", "q/p/x.bvh"),
            ("12_01.bvh", "p_x_2.bvh"),
            ("02_01.bvh", "Walk.bvh"),
            ("35_01.bvh", "walk.bvh"),
            ("12_01.bvh", "walk.BVH"),
            ("02_01.bvh", "02_01.bvh"),
            ("02_01.amc", "02_01.amc"),
            ("02.asf", "02.asf"),
        ],
    );
    // the folder (its .bvh files) and the AMC named beside it
    let out = run(&[
        "segment",
        "--method",
        "velocity",
        input.to_str().unwrap(),
        input.join("02_01.amc").to_str().unwrap(),
        "--out",
        output.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{stdout}\n{}", String::from_utf8_lossy(&out.stderr));
    // each take's line: `ok    <take>  … → <output>`
    let mut written: Vec<(String, String)> = stdout
        .lines()
        .filter_map(|l| l.strip_prefix("ok    "))
        .map(|l| {
            let take =
                l.split("  ").next().unwrap().strip_prefix(&format!("{}/", input.display())).unwrap().to_string();
            let file =
                l.rsplit(" → ").next().unwrap().strip_prefix(&format!("{}/", output.display())).unwrap().to_string();
            (take, file)
        })
        .collect();
    written.sort();
    let expected = [
        ("02_01.amc", "02_01_amc.json"),
        ("02_01.bvh", "02_01_bvh.json"),
        ("Walk.bvh", "Walk.json"),
        ("p/x.bvh", "p_x.json"),
        ("p_x_2.bvh", "p_x_2.json"),
        ("q/p/x.bvh", "q_p_x.json"),
        ("walk.BVH", "walk_2.json"),
        ("walk.bvh", "walk_3.json"),
    ];
    assert_eq!(written, expected.map(|(a, b)| (a.to_string(), b.to_string())), "{stdout}");
    // one file per take, none alike even ignoring case, each that take's segmentation
    let mut names: Vec<String> =
        std::fs::read_dir(&output).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().to_lowercase()).collect();
    names.sort();
    names.dedup();
    assert_eq!(names.len(), expected.len(), "{names:?}");
    for (take, file) in expected {
        let seg =
            mocapseg::segment::Segmentation::from_json(&std::fs::read_to_string(output.join(file)).unwrap()).unwrap();
        assert_eq!(seg.file, std::path::Path::new(take).file_name().unwrap().to_string_lossy(), "{file}");
    }
}

/// A write that fails part way (here the file-size limit, `ulimit -f`, with SIGXFSZ ignored so the
/// write returns EFBIG instead of killing the process) leaves neither a part of a segmentation nor a
/// temporary file, and the earlier run's output is removed rather than left to read as this run's.
#[cfg(unix)]
#[test]
fn a_write_that_fails_part_way_leaves_no_partial_file() {
    let (input, output) = batch_input("batch-atomic", &[("02_01.bvh", "a.bvh")]);
    std::fs::create_dir_all(&output).unwrap();
    std::fs::write(output.join("a.json"), "an earlier run's").unwrap();
    // 1 block of 512 bytes: SSSM's segmentation JSON of the take is longer (checked at the end)
    let out = Command::new("sh")
        .arg("-c")
        .arg("ulimit -f 1 && trap '' XFSZ && exec \"$0\" \"$@\"")
        .arg(env!("CARGO_BIN_EXE_mocapseg"))
        .args(["segment", "--method", "sssm", input.to_str().unwrap(), "--out", output.to_str().unwrap()])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stdout}\n{stderr}");
    let a = output.join("a.json");
    assert!(stdout.starts_with(&format!("FAIL  {}: ", a.display())), "the write's failure names the file: {stdout}");
    let left: Vec<String> =
        std::fs::read_dir(&output).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    assert!(left.is_empty(), "left in the output folder: {left:?}\n{stdout}");
    assert!(stdout.trim_end().ends_with(&format!("({} of an earlier run removed)", a.display())), "{stdout}");
    // without the limit the same batch writes it whole
    let (code, stdout, stderr) = batch_run("sssm", &input, &output, &[]);
    assert_eq!(code, Some(0), "{stdout}\n{stderr}");
    let seg = mocapseg::segment::Segmentation::from_json(&std::fs::read_to_string(&a).unwrap()).unwrap();
    assert_eq!(seg.frames, 343);
    assert!(std::fs::metadata(&a).unwrap().len() > 512, "the limit above was below the file's size");
}

#[test]
fn eval_scores_a_folder_of_predictions_in_one_table() {
    let dir = out_dir().join("eval-folder");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let seg = |file: &str, cut: usize| {
        serde_json::json!({
            "file": file, "fps": 10.0, "frames": 100, "method": "hand", "params": {},
            "segments": [
                {"start": 0, "end": cut - 1, "label": "a", "level": "action", "cluster": 0, "score": null},
                {"start": cut, "end": 99, "label": "b", "level": "action", "cluster": 1, "score": null}
            ]
        })
        .to_string()
    };
    std::fs::write(dir.join("a.json"), seg("a.bvh", 50)).unwrap();
    std::fs::write(dir.join("b.json"), seg("b.bvh", 80)).unwrap();
    let truth = dir.join("truth.csv");
    std::fs::write(
        &truth,
        "trial,label,start_frame,end_frame,trial_frames\na,walk,1,50,100\na,jump,51,100,100\nb,walk,1,50,100\nb,jump,51,100,100\n",
    )
    .unwrap();
    let out = run(&["eval", dir.to_str().unwrap(), "--truth", truth.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let table = String::from_utf8_lossy(&out.stdout);
    let lines: Vec<&str> = table.lines().collect();
    assert_eq!(lines.len(), 7, "{table}");
    assert_eq!(lines[6], "Scored as actions as a tiling of the take (transitions split at their middle, gaps stretched to the neighbours).");
    assert!(lines[2].starts_with("| a | 2 / 2 | 1.00 | 1.00 | 1.00 | 1.00 |"), "{table}");
    // b's boundary is 3 s off: no boundary match; covering ½·50/80 + ½·20/50 = 0.51
    assert!(lines[3].starts_with("| b | 2 / 2 | 0.00 | 0.00 | 0.51 |"), "{table}");
    assert!(lines[4].starts_with("| **mean** | | **0.50** | **0.50** | **0.76** |"), "{table}");
    let v = stdout_json(&run(&["eval", dir.to_str().unwrap(), "--truth", truth.to_str().unwrap(), "--json"]));
    assert_eq!(v.as_array().unwrap().len(), 2);
}

#[test]
fn eval_scores_a_segmentation_against_truth() {
    let dir = out_dir();
    let seg = serde_json::json!({
        "file": "take.bvh", "fps": 10.0, "frames": 100, "method": "hand", "params": {},
        "segments": [
            {"start": 0, "end": 49, "label": "a", "level": "action", "cluster": 0, "score": null},
            {"start": 50, "end": 99, "label": "b", "level": "action", "cluster": 1, "score": null}
        ]
    });
    let seg_path = dir.join("take.json");
    std::fs::write(&seg_path, seg.to_string()).unwrap();
    let truth_path = dir.join("truth.csv");
    std::fs::write(
        &truth_path,
        "trial,label,start_frame,end_frame,trial_frames\ntake,walk,1,50,100\ntake,jump,51,100,100\n",
    )
    .unwrap();
    let v = stdout_json(&run(&["eval", seg_path.to_str().unwrap(), "--truth", truth_path.to_str().unwrap()]));
    assert_eq!(v["trial"], "take");
    assert_eq!(v["boundaries"][0]["f1"], 1.0);
    assert_eq!(v["covering"], 1.0);
    assert_eq!(v["hungarian_accuracy"], 1.0);
}

#[test]
fn eval_reads_simple_csv_and_json_truth_with_the_pages_choices() {
    let dir = out_dir().join("eval-import");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    // a 120 fps take of 400 frames cut at frame 200
    let seg = serde_json::json!({
        "file": "take.bvh", "fps": 120.0, "frames": 400, "method": "hand", "params": {},
        "segments": [
            {"start": 0, "end": 199, "label": "walk", "level": "action", "cluster": 0, "score": null},
            {"start": 200, "end": 399, "label": "jump", "level": "action", "cluster": 1, "score": null}
        ]
    });
    let seg_path = dir.join("take.json");
    std::fs::write(&seg_path, seg.to_string()).unwrap();
    let eval = |truth: &std::path::Path, flags: &[&str]| {
        run(&[&["eval", seg_path.to_str().unwrap(), "--truth", truth.to_str().unwrap()][..], flags].concat())
    };
    // labels at 30 fps, 0-based: frame 50 at 30 fps is take frame 200
    let spans = dir.join("spans.csv");
    std::fs::write(&spans, "start_frame,end_frame,label\n0,49,walk\n50,99,jump\n").unwrap();
    let out = eval(&spans, &["--first-frame", "0", "--label-fps", "30"]);
    let v = stdout_json(&out);
    assert_eq!((v["trial"].as_str(), v["true_boundaries"].as_u64()), (Some("take"), Some(1)));
    assert_eq!((v["boundaries"][0]["f1"].as_f64(), v["covering"].as_f64()), (Some(1.0), Some(1.0)));
    assert!(String::from_utf8_lossy(&out.stderr).contains("labels at 30 fps converted to the take's 120 fps"));
    // read 1-based (the default) frame 0 does not exist
    let out = eval(&spans, &["--label-fps", "30"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("line 2: `start_frame` = 0 is before the first frame 1"));
    // … and 1-based numbers one higher score the same, boundary for boundary
    std::fs::write(&spans, "start_frame,end_frame,label\n1,50,walk\n51,100,jump\n").unwrap();
    let v = stdout_json(&eval(&spans, &["--label-fps", "30"]));
    assert_eq!((v["boundaries"][0]["f1"].as_f64(), v["covering"].as_f64()), (Some(1.0), Some(1.0)));
    // a label past the take's end names its line
    std::fs::write(&spans, "0,49,walk\n50,100,jump\n").unwrap();
    let out = eval(&spans, &["--first-frame", "0", "--label-fps", "30"]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("spans.csv: ground truth CSV line 2: `end_frame` = 100 (at 30 fps: take frame 400 counting from 0) is past the end"),
        "{err}"
    );
    // a segmentation JSON as the truth: scored against itself, perfect
    let v = stdout_json(&eval(&seg_path, &[]));
    assert_eq!((v["hungarian_accuracy"].as_f64(), v["segments"]["similarity"].as_f64()), (Some(1.0), Some(2.0)));
}

#[test]
fn splice_writes_a_take_and_its_ground_truth_that_eval_reads() {
    let dir = out_dir().join("splice");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let labels = dir.join("labels.csv");
    std::fs::write(
        &labels,
        "trial,label,start_frame,end_frame,trial_frames\n02_01,walk,1,170,343\n02_01,\"walk, later\",171,343,343\n\
         35_01,run,1,358,358\n",
    )
    .unwrap();
    let out = dir.join("mix.bvh");
    let (a, b) = (fixture("02_01.bvh"), fixture("35_01.bvh"));
    let args = ["splice", "--bvh", a.to_str().unwrap(), b.to_str().unwrap(), "--labels", labels.to_str().unwrap()];
    let run_splice = |seed: &str| {
        let r = run(&[&args[..], &["--pieces", "6", "--seed", seed, "-o", out.to_str().unwrap()]].concat());
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        (std::fs::read_to_string(&out).unwrap(), std::fs::read_to_string(dir.join("mix.csv")).unwrap())
    };
    let (bvh1, csv1) = run_splice("4");
    assert_eq!(run_splice("4"), (bvh1.clone(), csv1.clone()), "the same seed gives the same take");
    assert_ne!(run_splice("5").0, bvh1, "another seed another take");
    let (_, csv) = run_splice("4");
    assert_eq!(csv.lines().count(), 7, "a header and 6 pieces:\n{csv}");
    let mut reader = csv::Reader::from_reader(csv.as_bytes());
    let found: Vec<String> = reader.records().map(|r| r.unwrap()[1].to_string()).collect();
    assert!(found.iter().all(|l| ["walk", "walk, later", "run"].contains(&l.as_str())), "{found:?}");
    assert!(found.windows(2).all(|w| w[0] != w[1]), "no label twice in a row: {found:?}");
    // segment the spliced take and score it against its ground truth
    let seg = dir.join("mix.json");
    let r = run(&["segment", "--method", "pca", out.to_str().unwrap()]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    std::fs::write(&seg, &r.stdout).unwrap();
    let v = stdout_json(&run(&["eval", seg.to_str().unwrap(), "--truth", dir.join("mix.csv").to_str().unwrap()]));
    assert_eq!(v["trial"], "mix");
    assert_eq!(v["true_boundaries"], 5);
    // s = matched − (unmatched found + unmatched true) / 2, the true pieces being the 6 of the CSV
    let scores = &v["segments"];
    let count = |k: &str| scores[k].as_u64().unwrap_or_else(|| panic!("{k}: {scores}")) as f64;
    assert_eq!(count("matched") + count("unmatched_true"), 6.0, "{scores}");
    let s = count("matched") - (count("unmatched_found") + count("unmatched_true")) / 2.0;
    assert_eq!(scores["similarity"].as_f64(), Some(s), "{scores}");
    // the ground truth itself, as a segmentation (1-based rows made 0-based): all 6 matched, s = 6
    let take = stdout_json(&run(&["info", out.to_str().unwrap()]));
    let mut reader = csv::Reader::from_reader(csv.as_bytes());
    let segments: Vec<serde_json::Value> = reader
        .records()
        .enumerate()
        .map(|(i, r)| {
            let r = r.unwrap();
            let frame = |k: usize| r[k].parse::<usize>().unwrap() - 1;
            serde_json::json!({"start": frame(2), "end": frame(3), "label": &r[1], "level": "action", "cluster": i, "score": null})
        })
        .collect();
    let exact = serde_json::json!({"file": "mix.bvh", "fps": take["fps"], "frames": take["frames"], "method": "truth",
        "params": {}, "segments": segments});
    let exact_path = dir.join("exact.json");
    std::fs::write(&exact_path, exact.to_string()).unwrap();
    let v = stdout_json(&run(&[
        "eval",
        exact_path.to_str().unwrap(),
        "--truth",
        dir.join("mix.csv").to_str().unwrap(),
        "--trial",
        "mix",
    ]));
    assert_eq!(v["segments"]["matched"], 6, "{v}");
    assert_eq!(v["segments"]["similarity"], 6.0, "{v}");
    // a take without labels is named
    let r = run(&[
        "splice",
        "--bvh",
        fixture("12_01.bvh").to_str().unwrap(),
        "--labels",
        labels.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(r.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&r.stderr).contains("no labels for trial `12_01`"));
}

/// A lab example built next to the test binaries (`cargo test` builds the examples).
fn example(name: &str) -> PathBuf {
    let deps = std::env::current_exe().unwrap().parent().unwrap().to_path_buf();
    deps.parent().unwrap().join("examples").join(name)
}

#[test]
fn eval_data_says_clearly_when_the_data_is_absent() {
    for name in ["eval_data", "eval_splice", "accuracy"] {
        let out = Command::new(example(name)).args(["--data", "/no/such/folder"]).output().unwrap();
        assert_eq!(out.status.code(), Some(1), "{name}");
        assert!(String::from_utf8_lossy(&out.stderr).contains("no shared data here"), "{name}");
    }
    let out = Command::new(example("eval_data")).args(["--data", "/no/such/folder"]).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("no shared data here"));
}

#[test]
fn gait_labels_tile_a_walk_as_a_label_csv() {
    let out = run(&["gait", fixture("35_01.bvh").to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("file,start_frame,end_frame,label"));
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    // consecutive rows tile the take's 358 frames
    let mut next = 0;
    for r in &rows {
        assert_eq!(r[0], "35_01.bvh");
        assert_eq!(r[1].parse::<usize>().unwrap(), next, "{rows:?}");
        next = r[2].parse::<usize>().unwrap() + 1;
    }
    assert_eq!(next, 358);
    // a walk: it has steps of both feet
    assert!(rows.iter().any(|r| r[3].contains("left step")) && rows.iter().any(|r| r[3].contains("right step")));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("ok ") && stderr.contains("segments"), "{stderr}");
    // a take without feet is reported, and nothing could be labelled
    let out = run(&["gait", fixture("bvh_anim_test_simple.bvh").to_str().unwrap()]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("FAIL"));
}

/// The paper's network to the parameter (five layers, the image resized to 224 rows) and edge padding: the flags
/// reach the model file, and the training's summary gives the shape and the paper's 663,562.
#[test]
fn train_dtfcn_builds_the_papers_network_and_other_shapes_from_its_flags() {
    let dir = out_dir().join("dtfcn-shapes");
    std::fs::create_dir_all(&dir).unwrap();
    let labels = dir.join("labels.csv");
    std::fs::write(
        &labels,
        "file,start_frame,end_frame,label
02_01.bvh,0,170,start
02_01.bvh,171,342,walk
",
    )
    .unwrap();
    let model = dir.join("paper.model");
    let walk = fixture("02_01.bvh");
    let args = |extra: &[&str]| {
        let mut a = vec!["train-dtfcn", "--bvh", walk.to_str().unwrap(), "--labels", labels.to_str().unwrap()];
        a.extend_from_slice(&["--epochs", "1", "--out", model.to_str().unwrap()]);
        a.extend_from_slice(extra);
        a.into_iter().map(str::to_string).collect::<Vec<_>>()
    };
    let owned = args(&["--filters", "64,64,128,256,512", "--image-rows", "224", "--padding", "edge"]);
    let out = run(&owned.iter().map(String::as_str).collect::<Vec<_>>());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("receptive field 243 frames = 8.10 s")
            && err.contains("layer 1 reads 672 values per frame (the image resized to 224 rows)"),
        "{err}"
    );
    assert!(err.contains("(663562 with the paper's 10 classes"), "{err}");
    let info = stdout_json(&run(&["model-info", model.to_str().unwrap()]));
    let network = &info["network"];
    assert_eq!((network["image_rows"].as_u64(), network["padding"].as_str()), (Some(224), Some("edge")), "{info}");
    assert_eq!(network["filters"], serde_json::json!([64, 64, 128, 256, 512]));
    // it labels a take (the resize and the edge padding at inference too)
    let seg = stdout_json(&run(&[
        "segment",
        "--method",
        "dtfcn",
        "--model",
        model.to_str().unwrap(),
        walk.to_str().unwrap(),
    ]));
    assert!(!seg["segments"].as_array().unwrap().is_empty());
    // refusals name the flag
    for (bad, says) in
        [(vec!["--filters", "64,0"], "--filters"), (vec!["--padding", "mirror"], "--padding: padding \"mirror\"")]
    {
        let owned = args(&bad);
        let out = run(&owned.iter().map(String::as_str).collect::<Vec<_>>());
        assert!(!out.status.success());
        assert!(String::from_utf8_lossy(&out.stderr).contains(says), "{}", String::from_utf8_lossy(&out.stderr));
    }
}

#[test]
fn train_dtfcn_writes_a_model_that_segment_and_model_info_read_and_bad_models_are_named() {
    let dir = out_dir().join("dtfcn");
    std::fs::create_dir_all(&dir).unwrap();
    // two walks, each labelled in halves (0-based inclusive BVH rows); a row for a take not given
    let labels = dir.join("labels.csv");
    std::fs::write(
        &labels,
        "file,start_frame,end_frame,label\n02_01.bvh,0,170,start\n02_01.bvh,171,342,walk\n\
         35_01.bvh,0,178,start\n35_01.bvh,179,357,walk\nelsewhere.bvh,0,10,jump\n",
    )
    .unwrap();
    let model = dir.join("walk.model");
    let (a, b) = (fixture("02_01.bvh"), fixture("35_01.bvh"));
    for method in ["dtfcn", "knn"] {
        let command = format!("train-{method}");
        let mut args = vec![
            command.as_str(),
            "--bvh",
            a.to_str().unwrap(),
            b.to_str().unwrap(),
            "--labels",
            labels.to_str().unwrap(),
        ];
        // the network's flags are rows of DT-FCN's table only: the k-NN's refuses them
        let network = ["--epochs", "2", "--width", "2"];
        if method == "dtfcn" {
            args.extend(network);
        } else {
            let refused = run(&[args.clone(), network.to_vec()].concat());
            assert!(!refused.status.success());
            assert!(String::from_utf8_lossy(&refused.stderr).contains("--epochs"), "{refused:?}");
        }
        args.extend(["--out", model.to_str().unwrap()]);
        let out = run(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{method}: {err}");
        assert!(err.contains("elsewhere.bvh"), "the row of a take not given is said: {err}");
        if method == "dtfcn" {
            // the shape, with the receptive field in seconds and the parameters beside the paper's
            assert!(
                err.contains("receptive field 16 frames = 0.53 s at 30 Hz")
                    && err
                        .contains("352962 parameters (357066 with the paper's 10 classes; the paper's network: 663562"),
                "{err}"
            );
        }
        let info = stdout_json(&run(&["model-info", model.to_str().unwrap()]));
        assert_eq!(info["kind"], method);
        assert_eq!(info["classes"], serde_json::json!(["start", "walk"]));
        assert!(info["provenance"]["command"].as_str().unwrap().starts_with(&format!("mocapseg {command}")));
        let seg = stdout_json(&run(&[
            "segment",
            "--method",
            method,
            "--model",
            model.to_str().unwrap(),
            "--param",
            "unknown_threshold=0",
            a.to_str().unwrap(),
        ]));
        assert_eq!(seg["method"], method);
        let segments = seg["segments"].as_array().unwrap();
        assert!(segments.iter().all(|s| s["label"] == "start" || s["label"] == "walk"), "{seg}");
        assert_eq!(segments.last().unwrap()["end"], 342);
    }
    // a damaged model file: refused with its name and what is wrong, exit code 1
    let bytes = std::fs::read(&model).unwrap();
    let broken = dir.join("broken.model");
    std::fs::write(&broken, &bytes[..bytes.len() / 2]).unwrap();
    let out = run(&["segment", "--method", "knn", "--model", broken.to_str().unwrap(), a.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("broken.model") && err.contains("truncated"), "{err}");
    // a model of the other kind
    let out = run(&["segment", "--method", "dtfcn", "--model", model.to_str().unwrap(), a.to_str().unwrap()]);
    assert!(
        String::from_utf8_lossy(&out.stderr)
            .contains("holds a k-NN model, not a DT-FCN model: use it with the k-NN method (knn)"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// A folder `name` under the test output with `labels.csv` labelling the walks 02_01 and 35_01 in halves
/// (`start`, `walk`; 0-based inclusive rows), and the two takes' paths.
fn two_labelled_walks(name: &str) -> (PathBuf, PathBuf, PathBuf, PathBuf) {
    let dir = out_dir().join(name);
    std::fs::create_dir_all(&dir).unwrap();
    let labels = dir.join("labels.csv");
    std::fs::write(
        &labels,
        "file,start_frame,end_frame,label\n02_01.bvh,0,170,start\n02_01.bvh,171,342,walk\n\
         35_01.bvh,0,178,start\n35_01.bvh,179,357,walk\n",
    )
    .unwrap();
    (dir, labels, fixture("02_01.bvh"), fixture("35_01.bvh"))
}

/// `--validation TAKE` (DT-FCN and the k-NN declare a validation take): the take is kept out of the training, its
/// loss chooses DT-FCN's epoch and its labels the model's decoding and unknown threshold (unless
/// `--choose-decoding false`), through the same training the page runs; a k-NN told not to choose its decoding has
/// nothing for it to do and refuses it, naming it; and without `--labels` LMA (which declares what it learns from
/// instead) trains on every take given, said so.
#[test]
fn a_validation_take_and_training_without_labels_are_what_the_method_declares() {
    let (dir, labels, a, b) = two_labelled_walks("train-declared");
    let (a, b, labels_arg) = (a.to_str().unwrap(), b.to_str().unwrap(), labels.to_str().unwrap());
    let model = dir.join("val.model");
    let out = run(&[
        "train-dtfcn",
        "--bvh",
        a,
        b,
        "--labels",
        labels_arg,
        "--validation",
        "35_01.bvh",
        "--epochs",
        "3",
        "--filters",
        "8,8",
        "--out",
        model.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("validation loss"), "every epoch line gives the validation take's loss: {err}");
    assert!(err.contains("(the best validation loss on 35_01.bvh)"), "{err}");
    assert!(err.contains("Decoding chosen on 35_01.bvh: "), "{err}");
    let info = stdout_json(&run(&["model-info", model.to_str().unwrap()]));
    assert_eq!(info["provenance"]["takes"], serde_json::json!(["02_01.bvh"]), "trained on the other take only: {info}");
    let threshold = info["unknown_threshold"].as_f64().unwrap();
    assert!([0.0, 0.5, 0.8].iter().any(|t| (t - threshold).abs() < 1e-6), "a threshold of the grid: {info}");
    // the k-NN: the validation take is not among its windows, and chooses its decoding
    let knn = dir.join("val-knn.model");
    let out = run(&[
        "train-knn",
        "--bvh",
        a,
        b,
        "--labels",
        labels_arg,
        "--validation",
        "35_01.bvh",
        "--out",
        knn.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success() && err.contains("Decoding chosen on 35_01.bvh: "), "{err}");
    let info = stdout_json(&run(&["model-info", knn.to_str().unwrap()]));
    assert_eq!(info["provenance"]["takes"], serde_json::json!(["02_01.bvh"]), "fitted on the other take only: {info}");
    // told not to choose: the rows as given
    let kept = dir.join("val-kept.model");
    let out = run(&[
        "train-dtfcn",
        "--bvh",
        a,
        b,
        "--labels",
        labels_arg,
        "--validation",
        "35_01.bvh",
        "--epochs",
        "1",
        "--filters",
        "8,8",
        "--choose-decoding",
        "false",
        "--min-duration-s",
        "3",
        "--unknown-threshold",
        "0.25",
        "--out",
        kept.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success() && !err.contains("Decoding chosen"), "{err}");
    let info = stdout_json(&run(&["model-info", kept.to_str().unwrap()]));
    assert_eq!(
        (info["decoding"]["min_duration_s"].as_f64(), info["unknown_threshold"].as_f64()),
        (Some(3.0), Some(0.25)),
        "{info}"
    );
    for (args, says) in [
        (
            vec!["train-dtfcn", "--bvh", a, b, "--labels", labels_arg, "--validation", "nope.bvh"],
            "nope.bvh: not among the takes",
        ),
        (vec!["train-dtfcn", "--bvh", a, "--labels", labels_arg, "--validation", "02_01.bvh"], "the only take"),
        (
            vec![
                "train",
                "--method",
                "knn",
                a,
                b,
                "--labels",
                labels_arg,
                "--validation",
                "35_01.bvh",
                "--option",
                "choose_decoding=false",
            ],
            "a k-NN has no epochs for a validation take to choose, only its decoding (choose_decoding)",
        ),
        (vec!["train-dtfcn", "--bvh", a], "--labels"),
    ] {
        let out = run(&[args, vec!["-o", "/dev/null"]].concat());
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && err.contains(says), "{says}: {err}");
    }
    // LMA without labels: the stand-in descriptors over every take given, the one path the page trains by
    let family = dir.join("stand-in.json");
    let out = run(&[
        "train-lma",
        "--bvh",
        fixture("12_01.bvh").to_str().unwrap(),
        fixture("131_01.bvh").to_str().unwrap(),
        "--restarts",
        "2",
        "--saliency-rounds",
        "4",
        "--max-epochs",
        "40",
        "--shift-epochs",
        "3",
        "--out",
        family.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("no --labels: LMA learns from the stand-in Effort descriptors"), "{err}");
    assert!(
        err.contains("Trained on the stand-in Effort descriptors' terciles over")
            && err.contains("12_01.bvh, 131_01.bvh"),
        "{err}"
    );
    let seg = stdout_json(&run(&["segment", "--method", "lma", "--model", family.to_str().unwrap(), a]));
    assert_eq!(seg["params"]["model"], "stand-in");
}

/// `mocapseg features`: the 15 end-effector values SSSM starts from, one row per 30 Hz frame,
/// equal to the library's (what `bench/peers/run.py` feeds the other libraries).
#[test]
fn features_writes_the_end_effector_features_at_the_working_rate() {
    let take = fixture("02_01.bvh");
    let path = out_dir().join("02_01-features.csv");
    let out = run(&["features", take.to_str().unwrap(), "--fps", "30", "-o", path.to_str().unwrap()]);
    assert!(out.status.success(), "failed: {}", String::from_utf8_lossy(&out.stderr));
    let text = std::fs::read_to_string(&path).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(header.len(), 17);
    assert_eq!(&header[..3], &["frame", "source_frame", "lhand_x"]);
    assert_eq!(header[16], "head_z");
    let rows: Vec<Vec<f64>> = lines.map(|l| l.split(',').map(|v| v.parse().unwrap()).collect()).collect();

    let motion = mocapseg::load::load_path(&take).unwrap().motion;
    let lib = mocapseg::features::end_effectors::end_effectors(&motion, 30.0, true).unwrap();
    // 343 frames at 120 Hz are 2.85 s: 86 frames at 30 Hz, every fourth file frame
    assert_eq!(rows.len(), 86);
    assert_eq!(lib.base.frames(), rows.len());
    for (i, row) in rows.iter().enumerate() {
        assert_eq!(row.len(), 17, "row {i}");
        assert_eq!(row[0], i as f64);
        assert!((row[1] - 4.0 * i as f64).abs() < 1e-9, "row {i}: source frame {}", row[1]);
        for (c, v) in row[2..].iter().enumerate() {
            assert_eq!(*v as f32, lib.base.row(i)[c], "row {i} column {}", header[c + 2]);
        }
        // a walking body: the head above the hips, both feet below them, the hands between
        let (lhand_y, rhand_y, lfoot_y, rfoot_y, head_y) = (row[3], row[6], row[9], row[12], row[15]);
        assert!(head_y > 15.0 && head_y < 35.0, "row {i}: head {head_y} in above the hips");
        assert!(lfoot_y < -25.0 && rfoot_y < -25.0, "row {i}: feet {lfoot_y} {rfoot_y}");
        assert!(lhand_y < head_y && rhand_y < head_y && lhand_y > lfoot_y && rhand_y > rfoot_y, "row {i}: hands");
        // the left hand is on the left (+x), the right on the right
        assert!(row[2] > row[5], "row {i}: left hand x {} right hand x {}", row[2], row[5]);
    }

    // a rate that is no rate is refused with the file's name
    let out = run(&["features", take.to_str().unwrap(), "--fps", "0", "-o", path.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("02_01.bvh"), "{}", String::from_utf8_lossy(&out.stderr));
}

#[test]
fn clips_cuts_each_action_as_a_bvh_that_reads_back_as_its_frames() {
    let take = fixture("131_03.bvh");
    let dir = out_dir().join("clips");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let seg_path = dir.join("seg.json");
    let seg = run(&["segment", "--method", "velocity", take.to_str().unwrap()]);
    assert!(seg.status.success(), "{}", String::from_utf8_lossy(&seg.stderr));
    std::fs::write(&seg_path, &seg.stdout).unwrap();
    let segmentation = mocapseg::segment::Segmentation::from_json(std::str::from_utf8(&seg.stdout).unwrap()).unwrap();
    let level = mocapseg::segment::metrics::scored_level(&segmentation);
    let expected: Vec<_> = segmentation.level(level).cloned().collect();
    assert!(expected.len() >= 2, "velocity finds gestures on 131_03");
    let which = if level == mocapseg::segment::Level::Action { "action" } else { "primitive" };
    let out = run(&[
        "clips",
        seg_path.to_str().unwrap(),
        take.to_str().unwrap(),
        "--out",
        dir.to_str().unwrap(),
        "--level",
        which,
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let listed = String::from_utf8_lossy(&out.stdout).lines().count();
    assert_eq!(listed, expected.len());
    let whole = mocapseg::load::load_path(&take).unwrap().motion;
    let mut clips: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "bvh"))
        .collect();
    clips.sort();
    assert_eq!(clips.len(), expected.len());
    for (path, s) in clips.iter().zip(&expected) {
        assert!(path.file_name().unwrap().to_string_lossy().starts_with("131_03_"), "{}", path.display());
        let clip = mocapseg::load::load_path(path).unwrap().motion;
        let j = whole.joints();
        assert_eq!(clip.positions, whole.positions[s.start * j..(s.end + 1) * j], "{}", path.display());
    }
    // a zip and an error for a segmentation of another take
    let out = run(&[
        "clips",
        seg_path.to_str().unwrap(),
        take.to_str().unwrap(),
        "--out",
        dir.to_str().unwrap(),
        "--level",
        which,
        "--zip",
        "--origin",
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(dir.join("131_03_clips.zip").is_file());
    let out = run(&[
        "clips",
        seg_path.to_str().unwrap(),
        fixture("02_01.bvh").to_str().unwrap(),
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("take of 1102 frames, this take has 343"), "{err}");
}

#[test]
fn an_amc_take_is_read_with_its_asf() {
    let v = stdout_json(&run(&["info", fixture("02_01.amc").to_str().unwrap()]));
    assert_eq!((v["frames"].as_u64(), v["joints"].as_u64(), v["end_sites"].as_u64()), (Some(343), Some(31), Some(7)));
    assert_eq!(v["units"], "cmu_asf");
    assert!(v["warnings"].to_string().contains("120 fps (the CMU rate) assumed"), "{v}");
}

#[test]
fn model_info_reads_shipped_names_and_segment_takes_an_lma_family_file() {
    // a shipped name, as `segment --model exercises` takes it: both kinds, or one
    let both = stdout_json(&run(&["model-info", "exercises"]));
    let kinds: Vec<&str> = both.as_array().unwrap().iter().map(|h| h["kind"].as_str().unwrap()).collect();
    assert_eq!(kinds, ["knn", "dtfcn"], "every method that ships an `exercises`, in the registry's order");
    assert!(both.as_array().unwrap().iter().all(|h| h["name"] == "exercises"));
    let knn = stdout_json(&run(&["model-info", "exercises", "--method", "knn"]));
    assert_eq!((knn["kind"].as_str(), knn["name"].as_str()), (Some("knn"), Some("exercises")));
    let file = stdout_json(&run(&["model-info", "dtfcn-locomotion.model"]));
    assert_eq!((file["kind"].as_str(), file["name"].as_str()), (Some("dtfcn"), Some("locomotion")));
    assert!(file["parameters"].as_u64().unwrap() > 0);
    let out = run(&["model-info", "nope"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(err.contains("nope: no such file, nor a shipped model") && err.contains("cmu-actions"), "{err}");
    // LMA's family too: the shipped one by name, a file by path (the same reader the page's worker uses)
    let lma = stdout_json(&run(&["model-info", "shipped", "--method", "lma"]));
    assert_eq!((lma["kind"].as_str(), lma["factors"].as_u64()), (Some("lma"), Some(4)));
    let lma_file = stdout_json(&run(&["model-info", concat!(env!("CARGO_MANIFEST_DIR"), "/models/lma-effort.json")]));
    assert_eq!((lma_file["name"].as_str(), &lma_file["samples"]), (Some("lma-effort"), &lma["samples"]));
    let out = run(&["model-info", "exercises", "--method", "sssm"]);
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("not a method with models"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );

    // --lma-model: a family file is read (the shipped one is a valid file); a bad one is named
    let take = fixture("12_01.bvh");
    let family = concat!(env!("CARGO_MANIFEST_DIR"), "/models/lma-effort.json");
    let seg = stdout_json(&run(&["segment", "--method", "lma", "--lma-model", family, take.to_str().unwrap()]));
    assert_eq!(seg["method"], "lma");
    let dir = out_dir().join("lma-model");
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("bad-family.json");
    std::fs::write(&bad, "{\"not\": \"a family\"}").unwrap();
    let out = run(&["segment", "--method", "lma", "--lma-model", bad.to_str().unwrap(), take.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("bad-family.json"), "{err}");
    let out = run(&["segment", "--method", "sssm", "--lma-model", family, take.to_str().unwrap()]);
    assert!(String::from_utf8_lossy(&out.stderr).contains("--lma-model is for --method lma"));
}

/// `mocapseg train --method M`: any method with models trains from what it declares — the label
/// CSV, the training options as `--option NAME=VALUE` checked against its table — as the page's
/// worker trains it, and `segment --model FILE` and `model-info` read the file it writes.
#[test]
fn train_trains_any_method_with_models_from_its_declared_options() {
    let (dir, labels, a, b) = two_labelled_walks("train");
    let arg = |p: &std::path::Path| p.to_str().unwrap().to_string();
    for (method, options) in [("knn", vec![]), ("dtfcn", vec!["--option", "epochs=2", "--option", "filters=8,8"])] {
        let model = dir.join(format!("mine-{method}.model"));
        let mut args = vec!["train".to_string(), "--method".into(), method.into(), arg(&a), arg(&b)];
        args.extend(["--labels".into(), arg(&labels), "-o".into(), arg(&model)]);
        args.extend(options.iter().map(|s| s.to_string()));
        let refs: Vec<&str> = args.iter().map(String::as_str).collect();
        let out = run(&refs);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{method}: {err}");
        assert!(err.contains(&format!("Trained `mine-{method}` on 4 rows of labels.csv")), "{err}");
        let info = stdout_json(&run(&["model-info", model.to_str().unwrap()]));
        assert_eq!((info["kind"].as_str(), info["name"].as_str()), (Some(method), Some(&*format!("mine-{method}"))));
        assert!(info["provenance"]["command"].as_str().unwrap().contains("train --method"), "{info}");
        if method == "dtfcn" {
            assert_eq!(info["provenance"]["epochs_run"], 2);
            assert_eq!(info["network"]["filters"], serde_json::json!([8, 8]));
        }
        let seg = stdout_json(&run(&["segment", "--method", method, "--model", &arg(&model), &arg(&a)]));
        assert_eq!(seg["params"]["model"], format!("mine-{method}"));
    }
    // labels counted in 30 Hz frames for these 120 Hz takes end a quarter of the way: trained, and told why
    let quarter = dir.join("quarter.csv");
    std::fs::write(&quarter, "file,start_frame,end_frame,label\n02_01.bvh,0,42,start\n02_01.bvh,43,85,walk\n").unwrap();
    let model = dir.join("quarter.model");
    let out = run(&["train", "--method", "knn", &arg(&a), "--labels", &arg(&quarter), "-o", &arg(&model)]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("Warning: the labels of 02_01.bvh end at frame 86 of 343 (25 %)"), "{err}");
    assert!(err.contains("is the label file at 30 Hz?"), "{err}");
    // LMA: its own CSV and options; the family file segments a take
    let effort = dir.join("effort.csv");
    let mut rows = "file,start_frame,end_frame,space,time,weight,flow\n".to_string();
    let classes = ["indulging", "neutral", "condensing"];
    for k in 0..12 {
        let c = |f: usize| classes[(k + f) % 3];
        rows += &format!("12_01.bvh,{},{},{},{},{},{}\n", 30 * k, 30 * k + 120, c(0), c(1), c(2), c(k));
    }
    std::fs::write(&effort, rows).unwrap();
    let family = dir.join("family.json");
    let take = fixture("12_01.bvh");
    let out = run(&[
        "train",
        "--method",
        "lma",
        &arg(&take),
        "--labels",
        &arg(&effort),
        "-o",
        &arg(&family),
        "--option",
        "restarts=2",
        "--option",
        "saliency_rounds=4",
        "--option",
        "max_epochs=40",
        "--option",
        "shift_epochs=3",
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("Trained on 12 rows of effort.csv for 12_01.bvh") && err.contains("space |"), "{err}");
    let seg = stdout_json(&run(&["segment", "--method", "lma", "--model", &arg(&family), &arg(&take)]));
    assert_eq!(seg["params"]["model"], "family");
    // what is wrong is named: an option not in the table, one out of its range, a method without models
    let out = run(&[
        "train",
        "--method",
        "knn",
        &arg(&a),
        "--labels",
        &arg(&labels),
        "-o",
        "/dev/null",
        "--option",
        "epochs=2",
    ]);
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("not a k-NN training option"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let out = run(&[
        "train",
        "--method",
        "dtfcn",
        &arg(&a),
        "--labels",
        &arg(&labels),
        "-o",
        "/dev/null",
        "--option",
        "width=9",
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("width: width 9: expected a whole number from 2 to 3"), "{err}");
    let out = run(&["train", "--method", "sssm", &arg(&a), "--labels", &arg(&labels), "-o", "/dev/null"]);
    assert!(String::from_utf8_lossy(&out.stderr).contains("SSSM has no models to train"));
}

/// `train-dtfcn`, `train-knn`, `train-lma`: a flag for every row of the method's training table (the page's form
/// rows), with the row's help, bounds and default in `--help`, and a bad value refused naming the flag — the
/// flags are made from the table, so a row added to it is a flag without a line here.
#[test]
fn every_training_option_is_a_flag_of_its_train_command() {
    let mut seen = 0;
    for m in mocapseg::methods::registry() {
        let Some(decl) = m.supervision() else { continue };
        let command = format!("train-{}", m.info().name);
        let out = run(&[&command, "--help"]);
        let help = String::from_utf8_lossy(&out.stdout);
        assert!(out.status.success(), "{command}: {}", String::from_utf8_lossy(&out.stderr));
        for spec in &decl.training {
            let flag = format!("--{} <VALUE>", spec.name.replace('_', "-"));
            assert!(help.contains(&flag), "{command} --help lacks {flag}:\n{help}");
            let default = format!("default {}", mocapseg::method::form::field_text(&spec.default));
            assert!(help.contains(&default), "{command} --help lacks {default}:\n{help}");
        }
        seen += 1;
    }
    assert_eq!(seen, 3, "dtfcn, knn and lma have models");
    let labels = fixture("12_01.bvh");
    let out = run(&[
        "train-dtfcn",
        "--bvh",
        labels.to_str().unwrap(),
        "--labels",
        "x.csv",
        "--epochs",
        "many",
        "-o",
        "/dev/null",
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("--epochs"), "{err}");
    let out = run(&["train-lma", "--bvh", labels.to_str().unwrap(), "--restarts", "0", "-o", "/dev/null"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("restarts"), "{err}");
}

/// `mocapseg effort`: LMA as a semantic layer (the paper's §6) — every segment of another method's segmentation gets
/// an Effort in [-1, 1] per factor, the rest of the JSON unchanged; a segmentation of another take is refused naming
/// both.
#[test]
fn effort_gives_every_segment_of_any_method_its_laban_effort() {
    let dir = out_dir().join("effort");
    std::fs::create_dir_all(&dir).unwrap();
    let take = fixture("131_01.bvh");
    let seg_path = dir.join("pca.json");
    let out = run(&["segment", "--method", "pca", take.to_str().unwrap()]);
    let before = stdout_json(&out);
    std::fs::write(&seg_path, &out.stdout).unwrap();
    let out = run(&["effort", seg_path.to_str().unwrap(), take.to_str().unwrap()]);
    let after = stdout_json(&out);
    let segments = after["segments"].as_array().unwrap();
    assert!(!segments.is_empty());
    assert_eq!(segments.len(), before["segments"].as_array().unwrap().len());
    for (s, b) in segments.iter().zip(before["segments"].as_array().unwrap()) {
        assert_eq!((&s["start"], &s["end"], &s["label"]), (&b["start"], &b["end"], &b["label"]));
        for factor in ["space", "time", "weight", "flow"] {
            let v = s["effort"][factor].as_f64().unwrap_or_else(|| panic!("no {factor} in {s}"));
            assert!((-1.0..=1.0).contains(&v), "{s}");
        }
    }
    assert!(String::from_utf8_lossy(&out.stderr).contains(&format!(
        "{} of {} segments",
        segments.len(),
        segments.len()
    )));
    let other = fixture("12_01.bvh");
    let out = run(&["effort", seg_path.to_str().unwrap(), other.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("pca.json") && err.contains("12_01.bvh"), "{err}");
    // a family from a file (the shipped one is a valid file) gives the same Effort as the shipped family
    let family = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("models/lma-effort.json");
    let out =
        run(&["effort", seg_path.to_str().unwrap(), take.to_str().unwrap(), "--lma-model", family.to_str().unwrap()]);
    assert_eq!(stdout_json(&out), after);
    // the effort command goes through LMA's annotator, which checks the take as a run is: the 200 frames
    // with `Frame Time: 100` (5.5 hours, ~600,000 frames at the family's 30 Hz) and one segment over all of them is
    // refused at once, naming the Frame Time, instead of resampling the take and pooling every frame of it
    let text = std::fs::read_to_string(fixture("35_01.bvh")).unwrap();
    let (head, motion) = text.split_at(text.find("MOTION").unwrap());
    let rows: Vec<&str> = motion.lines().skip(3).take(200).collect();
    let slow = dir.join("ft100.bvh");
    std::fs::write(&slow, format!("{head}MOTION\nFrames: 200\nFrame Time: 100\n{}\n", rows.join("\n"))).unwrap();
    let whole = serde_json::json!({"file": "ft100.bvh", "fps": 0.01, "frames": 200, "method": "hand", "params": {},
        "segments": [{"start": 0, "end": 199, "label": "all", "level": "action", "cluster": null, "score": null}]});
    let whole_path = dir.join("ft100.json");
    std::fs::write(&whole_path, whole.to_string()).unwrap();
    let out = run(&["effort", whole_path.to_str().unwrap(), slow.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("ft100.bvh: Frame Time 100 s is ") && err.contains("1 Hz or more"), "{err}");
}

/// A labelling model whose classes do not fit the take says so on stderr, with the models that
/// do when asked (`fit_others=true`; else how to ask: the JSON on stdout has every frame
/// `unknown`); a model that fits says nothing more. A batch says it on the take's line.
#[test]
fn segment_names_the_models_that_fit_a_take_its_model_does_not() {
    let walk = fixture("02_01.bvh");
    let out = run(&["segment", "--method", "knn", walk.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.trim_end().ends_with(
            "every frame is labelled unknown; its other models were not measured against this take (ask with \
             fit_others=true)"
        ),
        "{err}"
    );
    let out = run(&["segment", "--method", "knn", "--param", "fit_others=true", walk.to_str().unwrap()]);
    let v = stdout_json(&out);
    assert!(v["segments"].as_array().unwrap().iter().all(|s| s["label"] == "unknown"), "{v}");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("02_01.bvh: model `exercises` does not fit this take (100 % of its frames travel faster")
            && err.trim_end().ends_with("every frame is labelled unknown; models that fit this take: locomotion"),
        "{err}"
    );
    let fits = run(&["segment", "--method", "knn", "--param", "model=locomotion", walk.to_str().unwrap()]);
    let v = stdout_json(&fits);
    assert!(v["segments"].as_array().unwrap().iter().any(|s| s["label"] != "unknown"), "{v}");
    assert!(!String::from_utf8_lossy(&fits.stderr).contains("fit"), "{}", String::from_utf8_lossy(&fits.stderr));
    let (input, output) = batch_input("fit", &[("02_01.bvh", "02_01.bvh")]);
    let (code, stdout, stderr) = batch_run("dtfcn", &input, &output, &[]);
    assert_eq!(code, Some(0), "{stderr}");
    let all = format!("{stdout}{stderr}");
    let line = all.lines().find(|l| l.starts_with("ok") && l.contains("02_01.bvh")).unwrap_or_else(|| panic!("{all}"));
    assert!(
        line.contains("— model `exercises` does not fit this take")
            && line.ends_with("its other models were not measured against this take (ask with fit_others=true)"),
        "{line}"
    );
}

/// A library folder: the bundled sample (13_30), 13_31 and a file that is not a BVH.
fn library_folder(name: &str) -> PathBuf {
    let dir = out_dir().join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    std::fs::copy(root.join("www/sample.bvh"), dir.join("13_30.bvh")).unwrap();
    std::fs::copy(fixture("13_31.bvh"), dir.join("13_31.bvh")).unwrap();
    std::fs::write(dir.join("broken.bvh"), "not a bvh\n").unwrap();
    dir
}

#[test]
fn cluster_shares_ids_across_takes_and_skips_a_bad_file() {
    let lib = library_folder("library-in");
    let out = out_dir().join("library-clusters");
    let _ = std::fs::remove_dir_all(&out);
    let r = run(&["cluster", lib.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(2), "some take failed: {stderr}");
    assert!(stderr.contains("broken.bvh: line 1, column 1: expected `HIERARCHY`"), "{stderr}");
    assert!(stderr.contains("2 of 3 takes clustered"), "{stderr}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("clusters.json")).unwrap()).unwrap();
    assert_eq!(summary["takes"], serde_json::json!(["13_30", "13_31"]));
    assert_eq!(summary["failed"].as_array().unwrap().len(), 1);
    let takes: Vec<mocapseg::segment::Segmentation> = ["13_30", "13_31"]
        .iter()
        .map(|t| {
            mocapseg::segment::Segmentation::from_json(&std::fs::read_to_string(out.join(format!("{t}.json"))).unwrap())
                .unwrap()
        })
        .collect();
    // clusters in both takes, each occurrence the segment of that take carrying its id, longest first
    let clusters = summary["clusters"].as_array().unwrap();
    let both: Vec<&serde_json::Value> = clusters.iter().filter(|c| c["takes"] == 2).collect();
    assert!(both.len() >= 3, "{} clusters in both takes", both.len());
    let seconds: Vec<f64> = clusters.iter().map(|c| c["seconds"].as_f64().unwrap()).collect();
    assert!(seconds.windows(2).all(|w| w[0] >= w[1]));
    for c in clusters {
        let id = c["id"].as_u64().unwrap() as usize;
        for o in c["occurrences"].as_array().unwrap() {
            let t = usize::from(o["take"] == "13_31");
            let s = &takes[t].segments[o["segment"].as_u64().unwrap() as usize];
            assert_eq!(
                (s.cluster, s.start as u64, s.end as u64),
                (Some(id), o["start"].as_u64().unwrap(), o["end"].as_u64().unwrap())
            );
            assert_eq!(s.label, format!("C{id}"));
        }
    }
}

/// `mocapseg` with `args` and `env`: its exit code, stdout and stderr.
fn run_env(args: &[&str], env: &[(&str, &str)]) -> (Option<i32>, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_mocapseg")).args(args).envs(env.iter().copied()).output().unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// The files in `dir`, sorted.
fn listing(dir: &std::path::Path) -> Vec<String> {
    let mut names: Vec<String> =
        std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    names
}

/// `cluster` and `transfer` keep `segment`'s guarantees: a take that panics is reported as a panic (exit code 3, not
/// a failure's 2) while the rest are matched and written; a take that fails or panics leaves no output of an earlier
/// run behind; a take called `clusters.bvh` does not overwrite the summary; and a write that fails part way leaves the
/// earlier file whole and no temporary file.
#[test]
fn cluster_and_transfer_keep_the_batch_guarantees() {
    let lib = library_folder("library-guarantees-in");
    std::fs::rename(lib.join("13_31.bvh"), lib.join("clusters.bvh")).unwrap();
    std::fs::copy(fixture("02_01.bvh"), lib.join("boom.bvh")).unwrap();
    let out = out_dir().join("library-guarantees");
    let _ = std::fs::remove_dir_all(&out);
    std::fs::create_dir_all(&out).unwrap();
    for earlier in ["boom.json", "broken.json"] {
        std::fs::write(out.join(earlier), "an earlier run's").unwrap();
    }
    let panic_on = [("MOCAPSEG_TEST_PANIC_ON", "boom.bvh")];
    let (code, stdout, stderr) =
        run_env(&["cluster", lib.to_str().unwrap(), "--out", out.to_str().unwrap(), "--jobs", "1"], &panic_on);
    assert_eq!(code, Some(3), "a take panicked: exit code 3\n{stdout}\n{stderr}");
    let removed = |name: &str| format!("({} of an earlier run removed)", out.join(name).display());
    let boom = lib.join("boom.bvh");
    assert!(
        stdout.lines().any(|l| l.starts_with(&format!("PANIC {}: panicked: MOCAPSEG_TEST_PANIC_ON", boom.display()))
            && l.ends_with(&removed("boom.json"))),
        "{stdout}"
    );
    assert!(
        stdout.lines().any(|l| l.starts_with(&format!("FAIL  {}", lib.join("broken.bvh").display()))
            && l.ends_with(&removed("broken.json"))),
        "{stdout}"
    );
    assert!(stderr.contains("panicked (left out of the library; a bug in mocapseg, please report it):"), "{stderr}");
    assert!(!stderr.contains("thread '"), "the panic is reported once, not by the default hook too:\n{stderr}");
    assert_eq!(listing(&out), ["13_30.json", "clusters.json", "clusters_2.json"], "{stdout}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("clusters.json")).unwrap()).unwrap();
    assert_eq!(summary["takes"], serde_json::json!(["13_30", "clusters_2"]));
    assert_eq!(summary["failed"].as_array().unwrap().len(), 2);
    let take =
        mocapseg::segment::Segmentation::from_json(&std::fs::read_to_string(out.join("clusters_2.json")).unwrap())
            .unwrap();
    assert_eq!(take.file, "clusters.bvh");

    // transfer: the same guarantees, the labelled take's labels carried to the take that did not panic
    let labels = out_dir().join("library-guarantees-labels.csv");
    let r = run(&["labels", fixture("mocap6_13_30_gt.csv").to_str().unwrap(), "-o", labels.to_str().unwrap()]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let moved = out_dir().join("library-guarantees-transfer");
    let _ = std::fs::remove_dir_all(&moved);
    std::fs::create_dir_all(&moved).unwrap();
    std::fs::write(moved.join("boom.json"), "an earlier run's").unwrap();
    let from = lib.join("13_30.bvh");
    let args =
        ["transfer", lib.to_str().unwrap(), "--labels", labels.to_str().unwrap(), "--from", from.to_str().unwrap()];
    let (code, stdout, stderr) =
        run_env(&[&args[..], &["--out", moved.to_str().unwrap(), "--jobs", "1"]].concat(), &panic_on);
    assert_eq!(code, Some(3), "{stdout}\n{stderr}");
    assert!(stdout.contains(&format!("({} of an earlier run removed)", moved.join("boom.json").display())), "{stdout}");
    assert_eq!(listing(&moved), ["13_30.json", "clusters.json", "labels.csv"], "{stdout}");
    let csv = std::fs::read_to_string(moved.join("labels.csv")).unwrap();
    assert!(mocapseg::labels::read_csv(&csv, "labels.csv").unwrap().iter().any(|r| r.file == "clusters.bvh"));

    // a write that fails part way (the file-size limit, SIGXFSZ ignored): the command fails naming the file, the
    // earlier summary stays whole, no temporary file is left
    #[cfg(unix)]
    {
        let before = std::fs::read_to_string(out.join("clusters.json")).unwrap();
        let r = Command::new("sh")
            .arg("-c")
            .arg("ulimit -f 1 && trap '' XFSZ && exec \"$0\" \"$@\"")
            .arg(env!("CARGO_BIN_EXE_mocapseg"))
            .args(["cluster", lib.to_str().unwrap(), "--out", out.to_str().unwrap(), "--jobs", "1"])
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(1), "{stderr}");
        assert!(stderr.contains(&format!("{}: ", out.join("13_30.json").display())), "names the file: {stderr}");
        assert_eq!(listing(&out), ["13_30.json", "clusters.json", "clusters_2.json"]);
        assert_eq!(std::fs::read_to_string(out.join("clusters.json")).unwrap(), before);
        let seg = std::fs::read_to_string(out.join("13_30.json")).unwrap();
        assert!(mocapseg::segment::Segmentation::from_json(&seg).is_ok(), "the earlier 13_30.json is whole");
    }
}

#[test]
fn transfer_carries_one_takes_labels_to_the_other() {
    let lib = library_folder("library-transfer-in");
    std::fs::remove_file(lib.join("broken.bvh")).unwrap();
    let labels = out_dir().join("library-13_30-labels.csv");
    let r = run(&["labels", fixture("mocap6_13_30_gt.csv").to_str().unwrap(), "-o", labels.to_str().unwrap()]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let out = out_dir().join("library-transfer");
    let _ = std::fs::remove_dir_all(&out);
    let from = lib.join("13_30.bvh");
    for route in ["nearest", "clusters"] {
        let r = run(&[
            "transfer",
            lib.to_str().unwrap(),
            "--labels",
            labels.to_str().unwrap(),
            "--from",
            from.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--route",
            route,
        ]);
        assert!(r.status.success(), "{route}: {}", String::from_utf8_lossy(&r.stderr));
        let csv = std::fs::read_to_string(out.join("labels.csv")).unwrap();
        let rows = mocapseg::labels::read_csv(&csv, "labels.csv").unwrap();
        // the other take got labels of the labelled take's classes only; the labelled take its own
        let classes = ["Jog", "JumpJack", "KneeRaise", "Squat", "Twist"];
        let other: Vec<_> = rows.iter().filter(|r| r.file == "13_31.bvh").collect();
        assert!(other.len() >= 3, "{route}: {other:?}");
        assert!(other.iter().all(|r| classes.contains(&r.label.as_str())), "{route}: {other:?}");
        assert!(rows.iter().any(|r| r.file == "13_30.bvh" && r.start_frame == 0 && r.label == "JumpJack"));
        let seg = mocapseg::segment::Segmentation::from_json(&std::fs::read_to_string(out.join("13_31.json")).unwrap())
            .unwrap();
        assert_eq!(seg.method, "transfer");
        assert!(seg.segments.iter().all(|s| s.score.is_some_and(|c| (0.0..=1.0).contains(&c))));
    }
    // labels that do not name the labelled take, a route that does not exist
    let r = run(&[
        "transfer",
        lib.to_str().unwrap(),
        "--labels",
        labels.to_str().unwrap(),
        "--from",
        lib.join("13_31.bvh").to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(r.status.code(), Some(1));
    assert!(
        String::from_utf8_lossy(&r.stderr).contains("no row names the labelled take 13_31"),
        "{}",
        String::from_utf8_lossy(&r.stderr)
    );
    let r = run(&[
        "transfer",
        lib.to_str().unwrap(),
        "--labels",
        labels.to_str().unwrap(),
        "--from",
        from.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--route",
        "sideways",
    ]);
    assert!(String::from_utf8_lossy(&r.stderr).contains("--route sideways: expected nearest or clusters"));
}

#[path = "support/hostile.rs"]
mod hostile;

/// A k-NN file asking for the widest window (issue 49: ±300 frames every frame, 46× the shipped window's work a
/// frame) runs on a short take, and on a long one (7000 frames at 1 Hz: 1.9 h, 210 k working frames) is refused
/// before it starts with the multiply-adds it would take and the duration that fits — exit code 1, no panic; the
/// shipped model runs that long take's check (its segmentation is not needed here: `--params` asks for nothing).
#[test]
fn a_wide_window_model_file_runs_within_its_time_or_is_refused() {
    let dir = out_dir().join("wide-window");
    std::fs::create_dir_all(&dir).unwrap();
    let model = dir.join("wide.model");
    std::fs::write(&model, hostile::wide_knn_file("wide", 500)).unwrap();
    let text = std::fs::read_to_string(fixture("35_01.bvh")).unwrap();
    let (head, motion) = text.split_at(text.find("MOTION").unwrap());
    let rows: Vec<&str> = motion.lines().skip(3).filter(|l| !l.trim().is_empty()).collect();
    let bvh = |frames: usize, frame_time: &str| {
        let body: Vec<&str> = rows.iter().copied().cycle().take(frames).collect();
        format!("{head}MOTION\nFrames: {frames}\nFrame Time: {frame_time}\n{}\n", body.join("\n"))
    };
    let short = dir.join("short.bvh");
    std::fs::write(&short, bvh(358, "0.0083333")).unwrap();
    let long = dir.join("long.bvh");
    std::fs::write(&long, bvh(7000, "1")).unwrap();
    let segment = |take: &std::path::Path| {
        run(&["segment", "--method", "knn", "--model", model.to_str().unwrap(), take.to_str().unwrap()])
    };
    let out = segment(&short);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let out = segment(&long);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("long.bvh") && err.contains("multiply-adds") && err.contains("more than the budget"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

/// A model file from anyone (issue 49): the shipped k-NN file with a hostile header — its payload and
/// checksum untouched, framed as the format frames it (magic, format byte, header length, JSON,
/// payload length, payload) — is refused with the field named and exit code 1, not a panic (exit
/// 101), and not the 33 s `min_duration_s = 9e4` took before the header's decoding was checked.
#[test]
fn a_model_file_with_a_hostile_header_is_refused_naming_the_field() {
    let bytes = std::fs::read(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("models/knn-exercises.model")).unwrap();
    let magic = b"mocapseg-model\n".len();
    let len = u32::from_le_bytes(bytes[magic + 1..magic + 5].try_into().unwrap()) as usize;
    let json_at = magic + 5;
    let header: serde_json::Value = serde_json::from_slice(&bytes[json_at..json_at + len]).unwrap();
    let rest = &bytes[json_at + len..]; // payload length and payload
    let dir = out_dir().join("hostile-models");
    std::fs::create_dir_all(&dir).unwrap();
    let take = fixture("13_31.bvh");
    for (field, value, wanted) in [
        ("min_duration_s", serde_json::json!(1e300), "min_duration_s = 1e300"),
        ("min_duration_s", serde_json::json!(9e4), "min_duration_s = 90000"),
        ("switch_cost", serde_json::json!(-1.0), "switch_cost = -1"),
    ] {
        let mut h = header.clone();
        h["decoding"][field] = value;
        let json = serde_json::to_vec(&h).unwrap();
        let mut file = bytes[..magic + 1].to_vec();
        file.extend_from_slice(&(json.len() as u32).to_le_bytes());
        file.extend_from_slice(&json);
        file.extend_from_slice(rest);
        let path = dir.join(format!("hostile-{field}.model"));
        std::fs::write(&path, &file).unwrap();
        let out = run(&["segment", "--method", "knn", "--model", path.to_str().unwrap(), take.to_str().unwrap()]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{err}");
        assert!(err.contains(&format!("hostile-{field}.model")) && err.contains(wanted), "{err}");
        assert!(!err.contains("panicked"), "{err}");
    }
}
