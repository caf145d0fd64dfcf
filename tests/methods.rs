//! The method registry's round trip: every registered method checks its defaults, runs on a
//! fixture, returns a segmentation that fits the schema and echoes its parameters, refuses
//! parameters outside the bounds its specs announce, and stops when asked to; the worker's generic
//! `annotate` request answers with what the annotating method (LMA) gives any segments.
#![cfg(not(target_arch = "wasm32"))]

use mocapseg::load::load_bytes;
use mocapseg::method::{MethodError, NoProgress, ParamKind, Progress, RunOptions};
use mocapseg::motion::Motion;
use mocapseg::protocol::{FailureKind, Request, Response};
use mocapseg::segment::Segmentation;
use mocapseg::worker::WorkerState;

fn take() -> Motion {
    load_bytes("12_01.bvh", include_bytes!("fixtures/12_01.bvh"), &mut |_| {}).unwrap().motion
}

#[test]
fn every_method_runs_with_its_defaults_and_echoes_them() {
    let motion = take();
    for m in mocapseg::methods::registry() {
        let info = m.info();
        let defaults = m.defaults();
        let checked =
            m.check_json(&serde_json::json!({})).unwrap_or_else(|e| panic!("{}: defaults refused: {e}", info.name));
        assert!(
            mocapseg::method::echoes_defaults(checked.echo(), &defaults),
            "{}: the checked defaults echo the defaults: {} for {defaults}",
            info.name,
            checked.echo()
        );
        assert!(!mocapseg::method::echoes_defaults(&serde_json::json!({}), &defaults), "{}", info.name);
        // every spec names a parameter of the defaults, with its default value
        let specs = m.param_specs();
        assert_eq!(specs.len(), defaults.as_object().unwrap().len(), "{}: one spec per parameter", info.name);
        for s in &specs {
            assert_eq!(defaults[&s.name], s.default, "{}: spec {}", info.name, s.name);
        }
        let out = m
            .run_checked(&motion, &checked, &RunOptions { pictures: true, ..RunOptions::default() }, &mut NoProgress)
            .unwrap();
        let seg = &out.segmentation;
        seg.validate().unwrap();
        assert_eq!((seg.method.as_str(), seg.file.as_str(), seg.frames), (info.name.as_str(), "12_01.bvh", 524));
        assert_eq!(&seg.params, checked.echo(), "{}: parameters echoed", info.name);
        assert!(!seg.segments.is_empty(), "{}: no segments on a walk", info.name);
        // the JSON schema round trip
        assert_eq!(&Segmentation::from_json(&seg.to_json()).unwrap(), seg);
        assert!(!out.details.summary.is_empty());
        for p in &out.details.pictures {
            assert_eq!(p.rgba.len(), p.width * p.height * 4, "{}: picture {}", info.name, p.id);
            assert!(p.width > 0 && !p.caption.is_empty());
            // its PNG (the page's download) decodes to the same pixels
            let png = p.to_png().unwrap();
            let decoder = png::Decoder::new(&png[..]);
            let mut reader = decoder.read_info().unwrap();
            let mut pixels = vec![0; reader.output_buffer_size()];
            let frame = reader.next_frame(&mut pixels).unwrap();
            assert_eq!((frame.width as usize, frame.height as usize), (p.width, p.height), "{}: {}", info.name, p.id);
            assert_eq!(&pixels[..frame.buffer_size()], &p.rgba[..], "{}: picture {} as PNG", info.name, p.id);
        }
        for c in &out.details.curves {
            assert_eq!(c.values.len(), seg.frames, "{}: curve {}", info.name, c.id);
        }
        // without pictures asked for, none are drawn
        let out = m.run_checked(&motion, &checked, &RunOptions::default(), &mut NoProgress).unwrap();
        assert!(out.details.pictures.is_empty());
        assert_eq!(&out.segmentation, seg, "{}: same result with and without pictures", info.name);
    }
}

#[test]
fn sssm_on_the_registry_is_sssm_itself() {
    let motion = take();
    let direct = mocapseg::methods::sssm::segment(&motion, &mocapseg::methods::sssm::SssmParams::default())
        .unwrap()
        .segmentation;
    let m = mocapseg::methods::find("sssm").unwrap();
    let via = m.run_json(&motion, &serde_json::json!({}), &RunOptions::default(), &mut NoProgress).unwrap();
    assert_eq!(via.segmentation, direct);
}

#[test]
fn values_outside_the_announced_bounds_are_refused_by_name() {
    for m in mocapseg::methods::registry() {
        let name = m.info().name;
        for s in m.param_specs() {
            let outside: Vec<serde_json::Value> = match &s.kind {
                ParamKind::Number { min, max } => vec![(min - 1.0).into(), (max * 2.0 + 1.0).into(), 1e300.into()],
                ParamKind::Integer { min, max } => {
                    let mut v = vec![serde_json::json!(max.saturating_add(1))];
                    if *min > 0 {
                        v.push(serde_json::json!(min - 1));
                    }
                    v
                }
                ParamKind::Choice { .. } => vec!["no-such-choice".into()],
                ParamKind::Bool => vec!["maybe".into()],
                ParamKind::Flags { .. } => vec![serde_json::json!(["no-such-flag"])],
                ParamKind::IntegerList { max, max_len, .. } => {
                    vec![serde_json::json!([max + 1]), serde_json::json!(vec![0; max_len + 1])]
                }
            };
            for v in outside {
                let params = serde_json::json!({ s.name.clone(): v.clone() });
                match m.check_json(&params) {
                    Ok(_) => panic!("{name}: {} = {v} accepted, outside {:?}", s.name, s.kind),
                    Err(e) => {
                        assert!(matches!(e, MethodError::Params { .. }), "{name}: {e:?}");
                        assert_eq!(
                            e.param_name(),
                            Some(s.name.as_str()),
                            "{name}: the refusal carries its parameter: {e:?}"
                        );
                        let text = e.to_string();
                        assert!(text.contains(&s.name), "{name}: {} = {v}: {text}", s.name);
                    }
                }
            }
        }
        let unknown = m.check_json(&serde_json::json!({"no_such_parameter": 1})).unwrap_err();
        assert_eq!(unknown.param_name(), None, "{name}: an unknown name is none of the method's parameters");
        let unknown = unknown.to_string();
        assert!(unknown.contains("no_such_parameter"), "{name}: {unknown}");
    }
}

/// Cancels as soon as the run reports a stage after `after` reports.
struct CancelAfter {
    reports: usize,
    after: usize,
    stages: Vec<String>,
}

impl Progress for CancelAfter {
    fn report(&mut self, stage: &str, _: f64) {
        self.reports += 1;
        self.stages.push(stage.to_string());
    }
    fn cancelled(&self) -> bool {
        self.reports > self.after
    }
}

#[test]
fn every_method_stops_when_cancelled() {
    let motion = take();
    for m in mocapseg::methods::registry() {
        let checked = m.check_json(&serde_json::json!({})).unwrap();
        for after in [0, 2] {
            let mut progress = CancelAfter { reports: 0, after, stages: Vec::new() };
            let result = m.run_checked(&motion, &checked, &RunOptions::default(), &mut progress);
            assert_eq!(result.err(), Some(MethodError::Cancelled), "{}: after {after} reports", m.info().name);
            assert!(
                progress.reports <= after + 1,
                "{}: went on after the cancel: {:?}",
                m.info().name,
                progress.stages
            );
        }
    }
}

#[test]
fn a_take_too_short_to_repeat_a_movement_says_why_sssm_found_no_action() {
    let whole = take();
    let short = whole.slice(0, (whole.fps * 0.8) as usize); // under a second: no movement comes back
    let m = mocapseg::methods::find("sssm").unwrap();
    let out = m.run_json(&short, &serde_json::json!({}), &RunOptions::default(), &mut NoProgress).unwrap();
    assert!(out.segmentation.segments.iter().all(|s| s.level != mocapseg::segment::Level::Action));
    let summary = &out.details.summary;
    assert!(summary.starts_with("0 actions · "), "{summary}");
    assert!(summary.contains("no action found: SSSM finds an action where the movement repeats"), "{summary}");
    // on the whole walk it finds actions and says nothing of the kind
    let out = m.run_json(&whole, &serde_json::json!({}), &RunOptions::default(), &mut NoProgress).unwrap();
    assert!(!out.details.summary.contains("no action found"), "{}", out.details.summary);
}

/// Every supervised method's training options, from its declared table: the defaults read back
/// through the page's form reader are accepted, and every value outside a row's bounds is refused
/// naming that option — before any take or label is read.
#[test]
fn every_training_option_is_read_from_the_declared_table_and_refused_by_name() {
    use mocapseg::method::form::{field_text, params_from_form};
    use mocapseg::method::supervised::TrainingAsk;
    let mut supervised = 0;
    for m in mocapseg::methods::registry() {
        let (Some(s), Some(decl)) = (m.supervised(), m.supervision()) else { continue };
        supervised += 1;
        let name = m.info().name;
        assert!(!decl.shipped.is_empty() && !decl.labels_header.is_empty(), "{name}: {decl:?}");
        let ask = |options: serde_json::Value| TrainingAsk { options, ..TrainingAsk::default() };
        // the defaults, as the form shows and reads them: the options pass; the empty ask fails later, at its name
        let texts: Vec<String> = decl.training.iter().map(|o| field_text(&o.default)).collect();
        let options = params_from_form(&m.info().short, &decl.training, &texts).unwrap();
        let e = s.start_training(ask(options), &mut NoProgress).err().expect("an empty ask trains nothing");
        assert_eq!(e.param_name(), Some("name"), "{name}: the defaults pass, the missing name is refused: {e}");
        for o in &decl.training {
            let outside: Vec<serde_json::Value> = match &o.kind {
                ParamKind::Number { min, max } => vec![(min - 1.0).into(), (max + 1.0).into()],
                ParamKind::Integer { min, max } => vec![serde_json::json!(max + 1), serde_json::json!(min - 1)],
                ParamKind::IntegerList { max, max_len, .. } => {
                    vec![serde_json::json!([max + 1]), serde_json::json!(vec![1; max_len + 1]), serde_json::json!([])]
                }
                ParamKind::Flags { .. } => vec![serde_json::json!(["no-such-flag"])],
                ParamKind::Choice { .. } => vec!["no-such-choice".into()],
                ParamKind::Bool => vec!["maybe".into()],
            };
            for v in outside {
                let e = s.start_training(ask(serde_json::json!({ o.name.clone(): v.clone() })), &mut NoProgress);
                let e = e.err().unwrap_or_else(|| panic!("{name}: {} = {v} accepted", o.name));
                assert_eq!(e.param_name(), Some(o.name.as_str()), "{name}: {} = {v}: {e}", o.name);
            }
        }
        let e = s.start_training(ask(serde_json::json!({"no_such_option": 1})), &mut NoProgress).err().unwrap();
        assert_eq!(e.param_name(), None, "{name}: an unknown option is none of the table's: {e}");
    }
    assert_eq!(supervised, 3, "LMA, the k-NN and DT-FCN declare their training");
}

/// The floor plan's rule (issue 22): the page, the worker and the message types reach methods only through the
/// registry, so no file under `src/app/`, `src/worker/` or `src/protocol.rs` names a method's module
/// (`methods::dtfcn`, `methods::lma::…`) — tests included. A new method then needs no line there.
#[test]
fn the_page_and_the_worker_name_no_method_module() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = vec![root.join("protocol.rs")];
    for dir in ["app", "worker"] {
        let mut stack = vec![root.join(dir)];
        while let Some(d) = stack.pop() {
            for entry in std::fs::read_dir(&d).unwrap() {
                let path = entry.unwrap().path();
                if path.is_dir() {
                    stack.push(path);
                } else if path.extension().is_some_and(|e| e == "rs") {
                    files.push(path);
                }
            }
        }
    }
    assert!(files.len() > 5, "the page's and the worker's sources were not found: {files:?}");
    let modules: Vec<String> =
        mocapseg::methods::registry().iter().map(|m| format!("methods::{}", m.info().name)).collect();
    let mut found = Vec::new();
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        for (n, line) in text.lines().enumerate() {
            for module in &modules {
                // `methods::knn` but not `methods::knnx`; `methods::registry` is not a method
                let hit = line
                    .match_indices(module.as_str())
                    .any(|(at, _)| !line[at + module.len()..].starts_with(|c: char| c.is_alphanumeric() || c == '_'));
                if hit {
                    found.push(format!("{}:{}: {}", file.display(), n + 1, line.trim()));
                }
            }
        }
    }
    assert!(found.is_empty(), "files of the page / worker name a method's module:\n{}", found.join("\n"));
}

/// Runs `request` on `worker`, returning everything it posted.
fn ask(worker: &mut WorkerState, request: Request) -> Vec<Response> {
    let mut posted = Vec::new();
    worker.handle(request, &mut |r| posted.push(r));
    posted
}

/// The last answer, a failure of the input: its message and the input it names.
fn refusal(posted: Vec<Response>) -> (String, Option<String>) {
    match posted.last() {
        Some(Response::Failed { kind: FailureKind::Input, message, param, .. }) => (message.clone(), param.clone()),
        other => panic!("expected a refusal, got {other:?}"),
    }
}

/// `annotate` on the held take: any row's spans get the Effort `layer::effort_of` gives the same
/// segments (the shipped family by default, a too-short span none with why), the lengths the
/// family learnt, and the answer crosses `postMessage` whole; a method that does not annotate,
/// spans past the take, another take and an unknown family are answered as a run is.
#[test]
fn the_worker_annotates_any_rows_segments_with_the_effort_of_the_shipped_family() {
    let mut w = WorkerState::default();
    let load = Request::Load {
        take: 1,
        name: "12_01.bvh".into(),
        restore: false,
        bytes: include_bytes!("fixtures/12_01.bvh").to_vec(),
        skeleton: None,
        skeleton_bytes: Vec::new(),
    };
    assert!(matches!(ask(&mut w, load).last(), Some(Response::Loaded { .. })));
    let spans = vec![(0, 119), (120, 121), (122, 400), (401, 523)];
    let request =
        |run, method: &str, params, spans| Request::Annotate { take: 1, run, method: method.into(), params, spans };
    let asked = request(2, "lma", serde_json::json!({}), spans.clone());
    assert_eq!(Request::from_packet(asked.clone().into_packet()).unwrap(), asked);
    let posted = ask(&mut w, asked);
    assert!(posted.iter().any(|r| matches!(r, Response::Progress { run: Some(2), stage, .. } if stage == "effort")));
    let Some(Response::Annotated { take: 1, run: 2, annotations }) = posted.last() else { panic!("{posted:?}") };
    let packet = posted.last().unwrap().clone().into_packet();
    assert!(packet.buffers.is_empty());
    assert_eq!(Response::from_packet(packet).as_ref(), Ok(posted.last().unwrap()));

    let motion = take();
    let segments: Vec<mocapseg::segment::Segment> = spans
        .iter()
        .map(|&(start, end)| mocapseg::segment::Segment {
            start,
            end,
            label: "x".into(),
            level: mocapseg::segment::Level::Primitive,
            cluster: Some(3),
            score: None,
            mirror_of: None,
            effort: None,
        })
        .collect();
    let expected =
        mocapseg::methods::lma::layer::effort_of(&mocapseg::methods::lma::shipped_model().unwrap(), &motion, &segments)
            .unwrap();
    let got: Vec<_> = annotations.segments.iter().map(|a| a.effort).collect();
    assert_eq!(got, expected);
    assert!(expected[0].is_some() && expected[1].is_none() && expected[3].is_some(), "{expected:?}");
    assert!(annotations.segments[1].why.as_deref().is_some_and(|w| w.starts_with("shorter than")));
    assert!(annotations.segments[0].why.is_none());
    let [lo, hi] = annotations.learnt_s.unwrap();
    assert!((lo - 0.67).abs() < 0.05 && (hi - 3.33).abs() < 0.05, "{lo} {hi}");
    assert_eq!(annotations.by, "LMA, shipped family");

    // the family named explicitly: the same; one that does not exist: refused at `model`
    let named = ask(&mut w, request(3, "lma", serde_json::json!({"model": "shipped"}), spans.clone()));
    assert!(matches!(named.last(), Some(Response::Annotated { annotations: a, .. }) if a == annotations));
    let unknown = ask(&mut w, request(4, "lma", serde_json::json!({"model": "nope"}), spans.clone()));
    let Some(Response::Refused { param, message, .. }) = unknown.last() else { panic!("{unknown:?}") };
    assert_eq!(param.as_deref(), Some("model"), "{message}");
    // a method that does not annotate; a span past the take; another take
    let (message, _) = refusal(ask(&mut w, request(5, "sssm", serde_json::json!({}), spans.clone())));
    assert_eq!(message, "SSSM does not annotate segments");
    let (message, _) = refusal(ask(&mut w, request(6, "lma", serde_json::json!({}), vec![(0, 10), (500, 524)])));
    assert!(message.contains("segment 2 (frames 500–524) is not inside 12_01.bvh (frames 0–523)"), "{message}");
    let other =
        ask(&mut w, Request::Annotate { take: 9, run: 7, method: "lma".into(), params: serde_json::json!({}), spans });
    assert!(matches!(other.last(), Some(Response::Failed { kind: FailureKind::NotLoaded, run: Some(7), .. })));
    // no spans: nothing to read, an empty answer
    let none = ask(&mut w, request(8, "lma", serde_json::json!({}), Vec::new()));
    assert!(matches!(none.last(), Some(Response::Annotated { annotations: a, .. }) if a.segments.is_empty()));
}
