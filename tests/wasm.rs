//! Everything that must also hold in a real browser, in one wasm test binary run in headless
//! Chromium: the core (BVH parser, forward kinematics, motion image), the SSSM, LMA and DT-FCN suites
//! (`tests/sssm.rs`, `tests/lma.rs`, `tests/dtfcn.rs`, included below) and the worker's `postMessage` glue of the protocol.
//!
//! Run: `make test-wasm`, i.e. `cargo test --profile web --target wasm32-unknown-unknown --features web
//! --test wasm` with `wasm-bindgen-test-runner` as the runner (.cargo/config.toml). One binary,
//! built in the `web` profile, reuses the library `make web` builds (a second profile or
//! feature set would build every dependency again). The fixtures are embedded with
//! `include_str!`: the browser has no file system.
//!
//! Compiled only for wasm32 with the `web` feature (natively this file is empty; the native tests
//! cover the same core and the protocol itself).
#![cfg(all(target_arch = "wasm32", feature = "web"))]

/// The SSSM suite, the same file as the native `tests/sssm.rs` (it configures the browser run).
#[path = "sssm.rs"]
mod sssm;

/// The LMA pipeline (the same file as the native `tests/lma.rs`): the shipped family, the
/// batched exhaustive map, both searches, training and a user's labels, in the browser.
#[path = "lma.rs"]
mod lma;

/// DT-FCN and the k-NN (the same file as the native `tests/dtfcn.rs`): training, reproducibility,
/// model files, the registered methods and every shipped model, in the browser.
#[path = "dtfcn.rs"]
mod dtfcn;

/// The worker's entry point and the page's decoding, through real JS values.
mod worker {
    use js_sys::{Array, Function, Uint8Array};
    use mocapseg::protocol::{FailureKind, Request, Response};
    use mocapseg::worker::{request_message, response_from_js, worker_handle};
    use std::cell::RefCell;
    use std::rc::Rc;
    use wasm_bindgen::prelude::*;
    use wasm_bindgen_test::wasm_bindgen_test;

    /// Hands `request` (with `bytes` as the file) to the worker's entry point the way
    /// `www/worker.js` does, and decodes everything it posts as the page does.
    fn ask(request: Request, bytes: Option<&[u8]>) -> Vec<Response> {
        let buffer = bytes.map(|b| Uint8Array::from(b).buffer());
        // a load's file, or the request's own buffers (a family's JSON text)
        let own = request.clone().into_packet().buffers.len();
        let (message, transfer) = request_message(&request, buffer.as_ref());
        assert_eq!(transfer.length() as usize, if bytes.is_some() { 1 } else { own }, "the buffers are transferred");
        let posted = Rc::new(RefCell::new(Vec::new()));
        let sink = posted.clone();
        let post = Closure::<dyn FnMut(JsValue, Array)>::new(move |m: JsValue, transfer: Array| {
            // every bulk buffer is in the transfer list
            let buffers: Array = js_sys::Reflect::get(&m, &"buffers".into()).unwrap().into();
            assert_eq!(buffers.length(), transfer.length());
            sink.borrow_mut().push(response_from_js(&m).expect("the page decodes what the worker posts"));
        });
        worker_handle(message, post.as_ref().unchecked_ref::<Function>());
        let out = posted.borrow().clone();
        out
    }

    #[wasm_bindgen_test]
    fn a_load_and_a_run_reach_the_page_intact_and_other_takes_are_refused() {
        let take = include_bytes!("fixtures/12_01.bvh");
        let load = Request::Load {
            take: 7,
            name: "12_01.bvh".into(),
            restore: false,
            bytes: Vec::new(),
            skeleton: None,
            skeleton_bytes: Vec::new(),
        };
        let posted = ask(load, Some(take));
        assert!(posted
            .iter()
            .any(|r| matches!(r, Response::Progress { take: 7, run: None, fraction: Some(f), .. } if *f == 1.0)));
        let Some(Response::Loaded { take: 7, motion }) = posted.last() else { panic!("{:?}", posted.last()) };
        assert_eq!((motion.summary.name.as_str(), motion.summary.frames), ("12_01.bvh", 524));
        assert_eq!(motion.positions.len(), 524 * motion.nodes() * 3);
        assert_eq!(&motion.image.png[..8], b"\x89PNG\r\n\x1a\n");

        let run =
            Request::Segment { take: 7, run: 8, method: "sssm".into(), params: serde_json::json!({"radius": 15}) };
        let posted = ask(run, None);
        for stage in ["features", "neighbours", "activities", "primitives", "clusters"] {
            assert!(
                posted.iter().any(|r| matches!(r, Response::Progress { run: Some(8), stage: s, .. } if s == stage)),
                "{stage}"
            );
        }
        let Some(Response::Segmented { take: 7, run: 8, view }) = posted.last() else { panic!("{:?}", posted.last()) };
        assert_eq!(view.segmentation.params["radius"], 15.0);
        let picture = &view.details.pictures[0];
        assert_eq!(picture.rgba.len(), picture.width * picture.height * 4);

        let other = Request::Segment { take: 6, run: 9, method: "sssm".into(), params: serde_json::json!({}) };
        let posted = ask(other, None);
        assert!(matches!(posted.last(), Some(Response::Failed { take: 6, kind: FailureKind::NotLoaded, .. })));
    }

    #[wasm_bindgen_test]
    fn an_lma_family_trained_in_the_worker_reaches_the_page_and_goes_back_to_a_worker() {
        let take = include_bytes!("fixtures/12_01.bvh");
        ask(
            Request::Load {
                take: 11,
                name: "12_01.bvh".into(),
                restore: false,
                bytes: Vec::new(),
                skeleton: None,
                skeleton_bytes: Vec::new(),
            },
            Some(take),
        );
        let classes = ["indulging", "neutral", "condensing"];
        let mut labels = "file,start_frame,end_frame,space,time,weight,flow\n".to_string();
        for k in 0..12 {
            let c = |f: usize| classes[(k + f) % 3];
            labels += &format!("12_01.bvh,{},{},{},{},{},{}\n", 30 * k, 30 * k + 120, c(0), c(1), c(2), c(k));
        }
        labels += "35_01.bvh,0,90,neutral,neutral,neutral,neutral\n";
        // quick options (the defaults are the paper's 20 restarts), the take's file as a buffer
        let options = serde_json::json!({"restarts": 2, "saliency_rounds": 4, "max_epochs": 40, "shift_epochs": 3});
        let train = Request::Train {
            take: 11,
            run: 12,
            method: "lma".into(),
            name: "mine".into(),
            labels_name: "mine.csv".into(),
            labels,
            takes: vec!["12_01.bvh".into()],
            options,
            bytes: vec![take.to_vec()],
            continue_from: None,
            validation: None,
        };
        let posted = ask(train, None);
        assert!(posted
            .iter()
            .any(|r| matches!(r, Response::Progress { run: Some(12), stage, .. } if stage == "flow shifted networks")));
        let Some(Response::Trained { run: 12, model, report, bytes, .. }) = posted.last() else {
            panic!("{:?}", posted.last())
        };
        assert_eq!(report.rows.len(), 4);
        assert!(report.summary.contains("(1 row for another file left out)"), "{}", report.summary);
        let text = std::str::from_utf8(bytes).expect("the family arrives as text");
        let family =
            mocapseg::methods::lma::classifier::EffortModel::from_json(text).expect("the family arrives whole");
        assert_eq!((family.samples, &family.origin), (12, &model.origin));
        let lma_summary = |run, model: &str| {
            let params = serde_json::json!({ "model": model });
            let request = Request::Segment { take: 11, run, method: "lma".into(), params };
            let Some(Response::Segmented { view, .. }) = ask(request, None).pop() else { panic!("lma run {run}") };
            view.details.summary
        };
        let yours = format!("your classifiers ({})", model.origin);
        let summary = lma_summary(13, "mine");
        assert!(summary.ends_with(&yours), "{summary}");

        // the page hands the worker the shipped family's file (fetched from beside the page, as
        // it is not in the wasm); a damaged copy is refused naming the file
        let file = "lma-effort.json".to_string();
        let good = include_bytes!("../models/lma-effort.json").to_vec();
        let mut bad = good.clone();
        bad[10] ^= 1;
        let refused =
            ask(Request::ProvideModel { take: 11, run: 19, file: file.clone(), bytes: bad, unavailable: None }, None);
        assert!(
            matches!(refused.last(), Some(Response::ModelRefused { run: 19, message, .. }) if message.contains("models/lma-effort.json")),
            "{refused:?}"
        );
        let taken =
            ask(Request::ProvideModel { take: 11, run: 20, file: file.clone(), bytes: good, unavailable: None }, None);
        assert_eq!(taken.last(), Some(&Response::ModelProvided { take: 11, run: 20, file }));

        // the shipped family by its name, and the page's copy stored again, as in a new worker
        assert!(!lma_summary(15, "shipped").contains("your classifiers"));
        let stored = Request::UseModel {
            take: 0,
            run: 16,
            method: "lma".into(),
            file: "mine-again.json".into(),
            bytes: bytes.clone(),
        };
        let again = ask(stored, None);
        let Some(Response::ModelStored { take: 0, run: 16, model: info }) = again.last() else { panic!("{again:?}") };
        assert_eq!((info.name.as_str(), &info.origin), ("mine-again", &model.origin));
        assert!(lma_summary(17, "mine-again").ends_with(&yours));
    }

    /// The Effort bars' request through the glue: a take's spans annotated by the method that
    /// declares it (LMA), the shipped family fetched first when this worker does not hold it, and
    /// the answer equal to `layer::effort_of` on the same segments.
    #[wasm_bindgen_test]
    fn an_annotate_request_gives_any_rows_segments_the_effort_of_the_shipped_family() {
        let take = include_bytes!("fixtures/12_01.bvh");
        let load = Request::Load {
            take: 21,
            name: "12_01.bvh".into(),
            restore: false,
            bytes: Vec::new(),
            skeleton: None,
            skeleton_bytes: Vec::new(),
        };
        assert!(matches!(ask(load, Some(take)).last(), Some(Response::Loaded { take: 21, .. })));
        let spans = vec![(0, 150), (151, 152), (153, 523)];
        let annotate = || Request::Annotate {
            take: 21,
            run: 22,
            method: "lma".into(),
            params: serde_json::json!({}),
            spans: spans.clone(),
        };
        let mut posted = ask(annotate(), None);
        if let Some(Response::NeedsModel { file, .. }) = posted.last().cloned() {
            assert_eq!(file, "lma-effort.json");
            let bytes = include_bytes!("../models/lma-effort.json").to_vec();
            ask(Request::ProvideModel { take: 21, run: 23, file, bytes, unavailable: None }, None);
            posted = ask(annotate(), None);
        }
        let Some(Response::Annotated { take: 21, run: 22, annotations }) = posted.last() else { panic!("{posted:?}") };
        let motion = mocapseg::load::load_bytes("12_01.bvh", take, &mut |_| {}).unwrap().motion;
        let segments: Vec<mocapseg::segment::Segment> = spans
            .iter()
            .map(|&(start, end)| mocapseg::segment::Segment {
                start,
                end,
                label: String::new(),
                level: mocapseg::segment::Level::Action,
                cluster: None,
                score: None,
                mirror_of: None,
                effort: None,
            })
            .collect();
        let store = mocapseg::method::ModelStore::new();
        store.provide("lma-effort.json", include_bytes!("../models/lma-effort.json").to_vec()).unwrap();
        let model = mocapseg::methods::lma::shipped(&store).unwrap();
        let expected = mocapseg::methods::lma::layer::effort_of(&model, &motion, &segments).unwrap();
        assert_eq!(annotations.segments.iter().map(|a| a.effort).collect::<Vec<_>>(), expected);
        assert!(expected[0].is_some() && expected[1].is_none(), "{expected:?}");
    }

    #[wasm_bindgen_test]
    fn bad_files_and_parameters_come_back_as_messages_naming_them() {
        let bad = include_bytes!("fixtures/bad.bvh");
        let posted = ask(
            Request::Load {
                take: 1,
                name: "bad.bvh".into(),
                restore: false,
                bytes: Vec::new(),
                skeleton: None,
                skeleton_bytes: Vec::new(),
            },
            Some(bad),
        );
        let Some(Response::Failed { kind: FailureKind::Input, message, .. }) = posted.last() else { panic!() };
        assert!(message.starts_with("bad.bvh: line 9, column 34"), "{message}");
        // a Latin-1 file decodes through the shared loader, with its warning
        let mut latin1 = include_bytes!("fixtures/12_01.bvh").to_vec();
        let at = latin1.windows(4).position(|w| w == b"Hips").unwrap();
        latin1[at + 1] = 0xe4;
        let posted = ask(
            Request::Load {
                take: 2,
                name: "l1.bvh".into(),
                restore: false,
                bytes: Vec::new(),
                skeleton: None,
                skeleton_bytes: Vec::new(),
            },
            Some(&latin1),
        );
        let Some(Response::Loaded { motion, .. }) = posted.last() else { panic!("{:?}", posted.last()) };
        assert!(motion.skeleton.names.iter().any(|n| n == "H\u{e4}ps"), "{:?}", &motion.skeleton.names[..3]);
        assert!(motion.summary.warnings.iter().any(|w| w.contains("Latin-1")), "{:?}", motion.summary.warnings);
        let run = Request::Segment { take: 2, run: 3, method: "sssm".into(), params: serde_json::json!({"radus": 3}) };
        let Some(Response::Refused { message, param, .. }) = ask(run, None).pop() else { panic!() };
        assert!(message.starts_with("SSSM parameters: unknown field `radus`"), "{message}");
        assert_eq!(param, None, "an unknown name is none of the method's parameters");
        let run =
            Request::Segment { take: 2, run: 4, method: "sssm".into(), params: serde_json::json!({"radius": -3}) };
        let Some(Response::Refused { message, param, .. }) = ask(run, None).pop() else { panic!() };
        assert!(message.contains("radius = -3"), "{message}");
        assert_eq!(param.as_deref(), Some("radius"), "the refusal names its parameter, through real JS values");
    }
}

/// The work check in wasm (where the worker is one thread and a frozen method freezes the
/// page's results): the 200-frame file with `Frame Time: 100` — 5.5 hours, 597,000
/// frames at 30 Hz — is refused by every method at once, naming its Frame Time; the same frames
/// at Frame Time 1 (under a minute at 1 Hz) run to the end in every method.
mod work {
    use mocapseg::method::{MethodError, NoProgress, RunOptions};
    use wasm_bindgen_test::wasm_bindgen_test;

    fn with_frame_time(frames: usize, frame_time: &str) -> Vec<u8> {
        let text = include_str!("fixtures/35_01.bvh");
        let (head, motion) = text.split_at(text.find("MOTION").unwrap());
        let rows: Vec<&str> = motion.lines().skip(3).take(frames).collect();
        format!("{head}MOTION\nFrames: {}\nFrame Time: {frame_time}\n{}\n", rows.len(), rows.join("\n")).into_bytes()
    }

    /// The shipped model files the default parameters name (the page fetches them; here they are built in).
    fn provide(store: &mocapseg::method::ModelStore, file: &str) {
        let bytes: &[u8] = match file {
            "lma-effort.json" => include_bytes!("../models/lma-effort.json"),
            "knn-exercises.model" => include_bytes!("../models/knn-exercises.model"),
            "dtfcn-exercises.model" => include_bytes!("../models/dtfcn-exercises.model"),
            other => panic!("a default names {other}"),
        };
        store.provide(file, bytes.to_vec()).unwrap();
    }

    #[wasm_bindgen_test]
    fn a_slow_frame_time_is_refused_by_every_method_and_a_slow_one_runs() {
        for (frame_time, frames, refused) in [("100", 200, true), ("1", 61, false)] {
            let file = format!("ft{frame_time}.bvh");
            let bytes = with_frame_time(frames, frame_time);
            let motion = mocapseg::load::load_bytes(&file, &bytes, &mut |_| {}).unwrap().motion;
            let store = mocapseg::method::ModelStore::new();
            for m in mocapseg::methods::registry() {
                let name = m.info().name;
                let checked = match m.check_json_in(&serde_json::json!({}), &store) {
                    Err(MethodError::NeedsModel { file }) => {
                        provide(&store, &file);
                        m.check_json_in(&serde_json::json!({}), &store).unwrap()
                    }
                    other => other.unwrap(),
                };
                let out = m.run_checked(&motion, &checked, &RunOptions::default(), &mut NoProgress);
                if refused {
                    let message = out.err().unwrap_or_else(|| panic!("{name} ran on {file}")).to_string();
                    assert!(message.starts_with("Frame Time 100 s is 0.01 frames per second"), "{name}: {message}");
                } else {
                    let out = out.unwrap_or_else(|e| panic!("{name} on {file}: {e}"));
                    assert_eq!(out.segmentation.frames, 61, "{name}");
                }
            }
        }
    }
}

use mocapseg::bvh::{self, Channel, JointKind};
use mocapseg::image::MotionImage;
use mocapseg::motion::{Motion, Units, UpAxis};
use wasm_bindgen_test::*;

wasm_bindgen_test_configure!(run_in_browser);

const WALK_02_01: &str = include_str!("fixtures/02_01.bvh");
const CGSPEED_12_01: &str = include_str!("fixtures/12_01.bvh");
const FULL_PRECISION: &str = include_str!("fixtures/pybvh_full_precision_frame_time.bvh");
const SIMPLE: &str = include_str!("fixtures/bvh_anim_test_simple.bvh");
const BAD: &str = include_str!("fixtures/bad.bvh");

// ---- small independent rotation maths (degrees, right-handed, column vectors) -----------------

type M3 = [[f64; 3]; 3];

fn axis_matrix(axis: usize, degrees: f64) -> M3 {
    let (s, c) = degrees.to_radians().sin_cos();
    match axis {
        0 => [[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]],
        1 => [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]],
        _ => [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]],
    }
}

fn mul(a: &M3, b: &M3) -> M3 {
    let mut m = [[0.0; 3]; 3];
    for (i, row) in m.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            *v = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    m
}

fn apply(m: &M3, v: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| (0..3).map(|k| m[i][k] * v[k]).sum())
}

/// Rotation of rotation channels applied in the order they are listed (M = R1·R2·R3).
fn euler(order: [usize; 3], degrees: [f64; 3]) -> M3 {
    let m = mul(&axis_matrix(order[0], degrees[0]), &axis_matrix(order[1], degrees[1]));
    mul(&m, &axis_matrix(order[2], degrees[2]))
}

fn close(a: [f32; 3], b: [f64; 3], tol: f64) -> bool {
    (0..3).all(|i| (a[i] as f64 - b[i]).abs() <= tol)
}

fn walk() -> (bvh::Bvh, Motion) {
    let b = bvh::parse(WALK_02_01).expect("02_01.bvh parses");
    let m = Motion::from_bvh("02_01.bvh", &b).expect("02_01.bvh gives a Motion");
    (b, m)
}

// ---- parser --------------------------------------------------------------------------------

#[wasm_bindgen_test]
fn parses_cmu_walk_hierarchy_and_motion() {
    let b = bvh::parse(WALK_02_01).expect("02_01.bvh parses");
    assert_eq!(b.frames(), 343);
    assert_eq!(b.declared_frames, 343);
    assert_eq!(b.frame_time, 0.0083333, "Frame Time kept exactly as written");
    assert_eq!(b.joints.len(), 38, "31 joints + 7 End Sites");
    assert_eq!(b.joint_indices().count(), 31);
    assert_eq!(b.joints.iter().filter(|j| j.kind == JointKind::EndSite).count(), 7);
    assert_eq!(b.channels_per_frame, 96);
    assert_eq!(b.values.len(), 343 * 96);
    assert!(b.warnings.is_empty(), "unexpected warnings: {:?}", b.warnings);

    let root = &b.joints[0];
    assert_eq!((root.name.as_str(), root.kind, root.parent), ("Hips", JointKind::Root, None));
    use Channel::*;
    assert_eq!(root.channels, vec![Xposition, Yposition, Zposition, Zrotation, Yrotation, Xrotation]);
    let upleg = b.joints.iter().find(|j| j.name == "LeftUpLeg").expect("LeftUpLeg");
    assert_eq!(upleg.offset, [1.65674, -1.80282, 0.62477], "line 12 of 02_01.bvh");
    assert_eq!(b.joints[upleg.parent.unwrap()].name, "LHipJoint");
    // First value of the first frame row, as printed in the file.
    let first_row = WALK_02_01.lines().skip_while(|l| !l.starts_with("Frame Time")).nth(1).unwrap();
    let x0: f64 = first_row.split_whitespace().next().unwrap().parse().unwrap();
    assert_eq!(b.frame(0)[0], x0);
    assert!(b.values.iter().all(|v| v.is_finite()));
}

#[wasm_bindgen_test]
fn crlf_and_leading_dot_frame_time() {
    // cgspeed file: mixed CRLF/LF line ends, `Frame Time: .0083333`, T-pose row 0.
    let b = bvh::parse(CGSPEED_12_01).expect("12_01.bvh parses");
    assert_eq!(b.frames(), 524);
    assert_eq!(b.frame_time, 0.0083333);
    assert_eq!(b.joint_indices().count(), 31);
}

#[wasm_bindgen_test]
fn frame_time_keeps_full_precision() {
    let b = bvh::parse(FULL_PRECISION).expect("parses");
    assert_eq!(b.frame_time, 0.0417083750417);
    assert!((b.fps() - 23.976).abs() < 1e-3, "fps {} is not 23.976", b.fps());
    assert_ne!(b.fps().round(), b.fps(), "23.976 fps must not become 24");
}

#[wasm_bindgen_test]
fn frames_count_mismatch_is_a_warning() {
    let text = SIMPLE.replace("Frames: 2", "Frames: 5");
    let b = bvh::parse(&text).expect("a wrong Frames: count is not fatal");
    assert_eq!(b.frames(), 2, "the data rows win");
    assert_eq!(b.declared_frames, 5);
    assert!(!b.warnings.is_empty(), "a Frames: count that disagrees with the data must warn");
}

#[wasm_bindgen_test]
fn error_names_line_and_column() {
    // tests/fixtures/bad.bvh line 9: `\t\tCHANNELS 3 Zrotation Yrotation Wrotation`.
    let err = bvh::parse(BAD).expect_err("Wrotation is not a channel");
    assert_eq!(err.line, 9, "{err}");
    assert_eq!(err.column, 34, "{err}");
    let shown = err.to_string();
    assert!(shown.contains("line 9") && shown.contains("Wrotation"), "{shown}");
}

#[wasm_bindgen_test]
fn bad_inputs_are_errors_not_panics() {
    let cut = &WALK_02_01[..WALK_02_01.find("MOTION").unwrap() - 20];
    let inputs = [
        "",
        "HIERARCHY",
        "MOTION\nFrames: 1\nFrame Time: 0.1\n",
        "HIERARCHY\nROOT a\n{\nOFFSET 1 2\n}\n",
        "\u{0}\u{1}garbage",
        cut,
        &SIMPLE.replace("Frame Time: 0.033333333", "Frame Time: fast"),
    ];
    for input in inputs {
        let err = bvh::parse(input).expect_err("malformed input must be an error");
        assert!(err.line >= 1 && err.column >= 1, "{err:?}");
        assert!(!err.message.is_empty());
    }
}

#[wasm_bindgen_test]
fn write_then_parse_round_trips() {
    let b = bvh::parse(WALK_02_01).unwrap();
    let again = bvh::parse(&bvh::write(&b)).expect("written file parses");
    assert_eq!(again.joints.len(), b.joints.len());
    assert_eq!(again.frames(), b.frames());
    assert_eq!(again.frame_time, b.frame_time);
    for (x, y) in b.values.iter().zip(&again.values) {
        assert!((x - y).abs() <= 1e-6 * x.abs().max(1.0), "{x} vs {y}");
    }
}

// ---- forward kinematics --------------------------------------------------------------------

#[wasm_bindgen_test]
fn fk_matches_hand_computed_positions() {
    // Hips at (0, 90, 0) rotated ZYX (1°, 2°, 3°); Head +12 Y rotated ZYX (4°, 5°, 6°); End +3 Y.
    let b = bvh::parse(FULL_PRECISION).unwrap();
    let m = Motion::from_bvh("fp", &b).unwrap();
    assert_eq!((m.frames(), m.joints()), (3, 3));
    let zyx = [2, 1, 0];
    let r_hips = euler(zyx, [1.0, 2.0, 3.0]);
    let hips = [0.0, 90.0, 0.0];
    let head_off = apply(&r_hips, [0.0, 12.0, 0.0]);
    let head = [0, 1, 2].map(|i| hips[i] + head_off[i]);
    let r_head = mul(&r_hips, &euler(zyx, [4.0, 5.0, 6.0]));
    let end_off = apply(&r_head, [0.0, 3.0, 0.0]);
    let end = [0, 1, 2].map(|i| head[i] + end_off[i]);
    let got = m.frame(0);
    assert!(close(got[0].to_array(), hips, 1e-4), "hips {:?}", got[0]);
    assert!(close(got[1].to_array(), head, 1e-4), "head {:?} vs {head:?}", got[1]);
    assert!(close(got[2].to_array(), end, 1e-4), "end site {:?} vs {end:?}", got[2]);
}

#[wasm_bindgen_test]
fn fk_keeps_bone_lengths() {
    let (_, m) = walk();
    for f in [0, 100, 342] {
        let p = m.frame(f);
        for (i, parent) in m.skeleton.parents.iter().enumerate() {
            if let Some(parent) = *parent {
                let len = p[i].distance(p[parent]) as f64;
                let want = m.skeleton.bone_length(i);
                assert!((len - want).abs() < 1e-3 * want.max(1.0), "frame {f} node {i}: {len} vs {want}");
            }
        }
    }
}

#[wasm_bindgen_test]
fn fk_cmu_walk_stands_on_the_floor() {
    let (b, m) = walk();
    assert_eq!((m.frames(), m.joints()), (343, b.joints.len()));
    assert_eq!(m.positions.len(), 343 * 38);
    assert!(m.positions.iter().all(|p| p.is_finite()));
    assert_eq!(m.units, Units::CmuAsf);
    assert_eq!(m.up_axis, UpAxis::Y);
    assert!((m.fps - 1.0 / 0.0083333).abs() < 1e-9);

    // Root (hip) height of a standing/walking adult: 16–18 CMU units (≈ 0.9–1.0 m).
    let root = m.root();
    let mean_root_y = (0..m.frames()).map(|f| m.position(f, root).y as f64).sum::<f64>() / m.frames() as f64;
    assert!((16.0..=18.0).contains(&mean_root_y), "mean root height {mean_root_y}");

    // Each frame's lowest point (a foot or toe) is on the floor, y ≈ 0 (1 unit ≈ 5.6 cm).
    let mut lowest: Vec<f64> =
        (0..m.frames()).map(|f| m.frame(f).iter().map(|p| p.y as f64).fold(f64::INFINITY, f64::min)).collect();
    lowest.sort_by(|a, b| a.total_cmp(b));
    let median = lowest[lowest.len() / 2];
    assert!(median.abs() < 1.0, "median lowest point {median}");
    assert!(lowest[0] > -2.0 && lowest[lowest.len() - 1] < 3.0, "lowest point range {lowest:?}");

    // The walk goes somewhere: the root travels 50+ units (≈ 3 m) in the horizontal plane.
    let (a, z) = (m.position(0, root), m.position(m.frames() - 1, root));
    let travelled = ((z.x - a.x).powi(2) + (z.z - a.z).powi(2)).sqrt();
    assert!(travelled > 50.0, "root travelled only {travelled}");
}

// ---- motion image ----------------------------------------------------------------------------

#[wasm_bindgen_test]
fn motion_image_size_values_and_png() {
    let (_, m) = walk();
    let img = MotionImage::from_motion(&m);
    assert_eq!(img.width, m.frames(), "one column per frame");
    assert_eq!(img.height, 31, "one row per joint (End Sites excluded)");
    assert_eq!(img.rows.len(), 31);
    assert_eq!(img.rows[0], "Hips");
    assert_eq!(img.rgba.len(), img.width * img.height * 4);
    // RGB = root-relative X/Y/Z scaled 0–255 per axis over the take: each axis uses the full range.
    for axis in 0..3 {
        let values = img.rgba.iter().skip(axis).step_by(4);
        let (lo, hi) = values.fold((u8::MAX, u8::MIN), |(lo, hi), &v| (lo.min(v), hi.max(v)));
        assert_eq!((lo, hi), (0, 255), "axis {axis} not scaled over the full 0–255 range");
    }
    assert!(img.rgba.iter().skip(3).step_by(4).all(|&a| a == 255), "alpha must be opaque");
    let distinct: std::collections::HashSet<&[u8]> = img.rgba.chunks(4).collect();
    assert!(distinct.len() > 100, "only {} distinct colours", distinct.len());

    let png = img.try_to_png().expect("encodes");
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    assert_eq!(&png[12..16], b"IHDR");
    let be = |o: usize| u32::from_be_bytes(png[o..o + 4].try_into().unwrap()) as usize;
    assert_eq!((be(16), be(20)), (img.width, img.height));
}

// ---- model files read with a 32-bit usize ----------------------------------------------------

/// A k-NN payload (default window) that claims `n` frames but holds the words of one.
fn knn_payload_claiming(n: u32, params: mocapseg::methods::knn::KnnParams) -> Vec<u8> {
    use mocapseg::methods::knn::DIMS;
    let d = (2 * params.half_window / params.stride + 1) as usize * 3 * mocapseg::motion::joints::Canonical::ALL.len();
    let mut bytes = Vec::new();
    bytes.extend_from_slice(&n.to_le_bytes());
    bytes.extend_from_slice(&(d as u32).to_le_bytes());
    // the mean, the axes, one frame's point and its label (0), all zero
    bytes.resize(4 * (2 + d + DIMS * d + DIMS + 1), 0);
    bytes
}

/// 2³⁰ + 1 frames make the k-NN payload's size, 4 · (2 + 33 d + 33 n) bytes, wrap around in 32-bit
/// arithmetic to the size of one frame's payload: wasm32's reader once took the payload for that and
/// `Vec::with_capacity(2³⁰ + 1)` trapped the worker. Refused with a message, directly and inside a
/// model file (as the worker reads a dropped model).
#[wasm_bindgen_test]
fn a_knn_payload_whose_size_wraps_around_in_32_bits_is_refused() {
    use mocapseg::labeller::model::{sha256_hex, Model, MAGIC};
    use mocapseg::methods::knn::{Knn, KnnParams};
    use mocapseg::methods::LABELLERS as KINDS;
    let n: u32 = (1 << 30) + 1;
    let e = Knn::from_bytes(&knn_payload_claiming(n, KnnParams::default()), KnnParams::default(), 2).unwrap_err();
    assert!(e.contains("expected") && e.contains(&format!("for {n} frames")), "{e}");

    // the same payload in a k-NN model file with a matching checksum
    let file = include_bytes!("fixtures/xss-knn.model");
    let at = MAGIC.len() + 1;
    let len = u32::from_le_bytes(file[at..at + 4].try_into().unwrap()) as usize;
    let mut header: serde_json::Value = serde_json::from_slice(&file[at + 4..at + 4 + len]).unwrap();
    let params: KnnParams = serde_json::from_value(header["knn"].clone()).unwrap();
    let payload = knn_payload_claiming(n, params);
    header["payload_sha256"] = sha256_hex(&payload).into();
    let json = serde_json::to_vec(&header).unwrap();
    let mut crafted = file[..at].to_vec();
    crafted.extend_from_slice(&(json.len() as u32).to_le_bytes());
    crafted.extend_from_slice(&json);
    crafted.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    crafted.extend_from_slice(&payload);
    let e = Model::from_bytes(&crafted, "crafted.model", &KINDS).unwrap_err();
    assert!(e.starts_with("crafted.model: k-NN data of ") && e.contains(&format!("for {n} frames")), "{e}");

    // the file's payload length is a u64: 2³² bytes more than the file holds is not the
    // length modulo 2³² (what `as usize` would make of it on wasm32)
    let mut longer = crafted.clone();
    let plen_at = at + 4 + json.len();
    let claimed = (1u64 << 32) + payload.len() as u64;
    longer[plen_at..plen_at + 8].copy_from_slice(&claimed.to_le_bytes());
    let e = Model::from_bytes(&longer, "longer.model", &KINDS).unwrap_err();
    assert!(e.starts_with(&format!("longer.model: weights of {claimed} bytes")) && e.contains("damaged"), "{e}");
}
