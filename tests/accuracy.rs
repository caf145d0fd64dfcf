//! Accuracy floors: every registered method with its defaults, and every shipped model, on two labelled takes kept
//! in `tests/fixtures/` (CMU 13_30 — the page's bundled sample — and 13_31, with the mocap6 labels), scored as
//! `mocapseg eval` scores them. Each floor sits a margin below the figure measured when it was set (printed by this
//! test, `cargo test --test accuracy -- --nocapture`), so a change that makes a method worse fails CI instead of
//! passing silently. The scoreboard (`make accuracy`, docs/scoreboard.md) says how good the methods are; this says
//! they did not get worse. The metrics themselves are checked against hand-computed values in
//! `src/segment/metrics.rs`.

use mocapseg::method::{self, NoProgress, RunOptions};
use mocapseg::motion::Motion;
use mocapseg::segment::metrics::{evaluate, Scores};
use mocapseg::segment::reference::{chance_scores, prior};
use mocapseg::segment::truth::Truth;
use mocapseg::segment::Level;

#[path = "support/labelled.rs"]
mod labelled;
use labelled::takes;

/// A floor: the method, its parameters as `NAME=VALUE` overrides, and per take the least F1@1s, covering and (for
/// labellers trained on these classes) frame accuracy it must reach.
struct Floor {
    method: &'static str,
    overrides: &'static [&'static str],
    /// (F1@1s, covering, frame accuracy) on 13_30 and on 13_31.
    least: [(f64, f64, f64); 2],
}

/// Measured when set (F1@1s / covering / frame accuracy on 13_30 and 13_31) minus a margin of about 0.05.
const FLOORS: &[Floor] = &[
    // measured 1.000 / 0.976 / 0.988 · 0.800 / 0.646 / 0.742 (with pose merging, which joins 13_31's Twist and
    // KneeRaise: 0.833 / 0.709 / 0.775 without)
    // (13_31's covering floor 0.62, not 0.59: chance covers 0.614 of it, and a floor must stand above chance)
    Floor { method: "sssm", overrides: &[], least: [(0.95, 0.92, 0.93), (0.75, 0.62, 0.69)] },
    // measured 0.889 / 0.885 / 0.924 · 0.769 / 0.731 / 0.749
    Floor { method: "pca", overrides: &[], least: [(0.83, 0.83, 0.87), (0.71, 0.68, 0.69)] },
    // measured 0.200 / 0.433 / 0.248 · 0.500 / 0.646 / 0.223
    Floor { method: "velocity", overrides: &[], least: [(0.15, 0.38, 0.19), (0.45, 0.59, 0.17)] },
    // measured 0.258 / 0.269 / 0.248 · 0.293 / 0.309 / 0.223
    Floor { method: "kcs", overrides: &[], least: [(0.20, 0.21, 0.19), (0.24, 0.25, 0.17)] },
    // LMA's gestures scored as actions, with the 630-feature family. The default Effort search (quantile 0.6,
    // pruned): measured 0.364 / 0.418 / 0.298 · 0.429 / 0.397 / 0.253
    Floor { method: "lma", overrides: &[], least: [(0.31, 0.36, 0.25), (0.37, 0.34, 0.20)] },
    // The paper's deviance search: measured 0.364 / 0.318 / 0.256 · 0.471 / 0.237 / 0.206 (the 336-feature family
    // gave 0.182 / 0.276 / 0.220 · 0.400 / 0.417 / 0.325; the fine-tuned family pruned below 1 arm bone/s gave
    // 0.333 / 0.067 / 0.067 and found nothing on 13_31)
    Floor { method: "lma", overrides: &["search=\"deviance\""], least: [(0.31, 0.26, 0.20), (0.42, 0.18, 0.15)] },
    // measured 1.000 / 0.977 / 0.988 · 1.000 / 0.972 / 0.985 (w = 3, four layers, the 18-row image with the root's
    // vertical velocity; the model's decoding: runs ≥ 2 s, switch cost 150. The w = 2, 17-row network gave
    // 1.000 / 0.962 / 0.981 · 0.909 / 0.816 / 0.875)
    Floor { method: "dtfcn", overrides: &["model=\"exercises\""], least: [(0.95, 0.92, 0.93), (0.95, 0.92, 0.93)] },
    // measured 1.000 / 0.980 / 0.989 · 1.000 / 0.982 / 0.991 (decoded as the DT-FCN's)
    Floor { method: "knn", overrides: &["model=\"exercises\""], least: [(0.95, 0.93, 0.94), (0.95, 0.93, 0.94)] },
    // The models of other classes than the takes' are scored with the take fit off (with it, they label both takes
    // unknown: `models_of_other_classes_call_the_takes_unknown`), as a floor on their cuts as such. Their labels name
    // classes the takes do not have, so by name (as a labeller is scored since issue 50) every frame is wrong: their
    // frame accuracy must be 0 (`OTHER_CLASSES`). Measured F1@1s / covering 0.400 / 0.607 · 0.400 / 0.561 (raw
    // per-frame labels, threshold 0.5; the frame accuracies 0.465 · 0.384 then were walk, jump, punch and kick
    // Hungarian-matched to exercises. The w = 2, 17-row network gave 0.667 / 0.837 · 0.421 / 0.596)
    Floor {
        method: "dtfcn",
        overrides: &["model=\"cmu-actions\"", "fit_check=false"],
        least: [(0.35, 0.55, 0.0), (0.35, 0.51, 0.0)],
    },
    // measured 0.286 / 0.351 · 0.316 / 0.477 (Hungarian frame accuracies were 0.593 · 0.394)
    Floor {
        method: "knn",
        overrides: &["model=\"cmu-actions\"", "fit_check=false"],
        least: [(0.23, 0.30, 0.0), (0.26, 0.42, 0.0)],
    },
    // measured 0.133 / 0.365 · 0.185 / 0.365 (gait labels on exercises: outside the model's classes; Hungarian
    // frame accuracies were 0.368 · 0.292; the w = 2, 17-row network gave 0.200 / 0.297 · 0.316 / 0.376)
    Floor {
        method: "dtfcn",
        overrides: &["model=\"locomotion\"", "fit_check=false"],
        least: [(0.08, 0.31, 0.0), (0.13, 0.31, 0.0)],
    },
    // measured 0.190 / 0.371 · 0.250 / 0.446 (Hungarian frame accuracies were 0.398 · 0.446)
    Floor {
        method: "knn",
        overrides: &["model=\"locomotion\"", "fit_check=false"],
        least: [(0.14, 0.32, 0.0), (0.20, 0.39, 0.0)],
    },
];

fn score(name: &str, overrides: &[&str], motion: &Motion, truth: &Truth) -> Scores {
    let m = mocapseg::methods::find(name).unwrap();
    let overrides: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    let params = method::params_from_overrides(m, &overrides).unwrap();
    let out = m.run_json(motion, &params, &RunOptions::default(), &mut NoProgress).unwrap();
    evaluate(&out.segmentation, truth, &mocapseg::methods::scoring(name)).unwrap()
}

/// The shipped models whose classes are not the takes' (none of their names is an exercise).
const OTHER_CLASSES: [&str; 2] = ["model=\"cmu-actions\"", "model=\"locomotion\""];

#[test]
fn every_method_and_shipped_model_stays_above_its_floor() {
    let takes = takes();
    // every registered method has a floor with its defaults
    for m in mocapseg::methods::registry() {
        let name = m.info().name;
        assert!(FLOORS.iter().any(|f| f.method == name), "no accuracy floor for `{name}`");
    }
    // every shipped model has one
    for model in mocapseg::labeller::shipped::NAMES {
        for kind in ["dtfcn", "knn"] {
            let wanted = format!("model=\"{model}\"");
            assert!(
                FLOORS.iter().any(|f| f.method == kind && f.overrides.contains(&wanted.as_str())),
                "no accuracy floor for the shipped {kind} model `{model}`"
            );
        }
    }
    let mut failures = Vec::new();
    for floor in FLOORS {
        for (k, (motion, truth)) in takes.iter().enumerate() {
            let s = score(floor.method, floor.overrides, motion, truth);
            let got = (s.boundaries[1].f1, s.covering, s.labelling.frame_accuracy);
            let least = floor.least[k];
            let what = format!("{} {} on {}", floor.method, floor.overrides.join(" "), truth.trial);
            eprintln!("{what}: F1@1s {:.3}, covering {:.3}, frame accuracy {:.3}", got.0, got.1, got.2);
            for (name, g, l) in
                [("F1@1s", got.0, least.0), ("covering", got.1, least.1), ("frame accuracy", got.2, least.2)]
            {
                if g < l {
                    failures.push(format!("{what}: {name} {g:.3} is below its floor {l:.3}"));
                }
            }
            // a model of other classes names none of the take's: by name it is never right
            if floor.overrides.iter().any(|o| OTHER_CLASSES.contains(o)) && got.2 != 0.0 {
                failures.push(format!("{what}: frame accuracy {:.3} with names the take does not have", got.2));
            }
        }
    }
    assert!(failures.is_empty(), "accuracy fell:\n{}", failures.join("\n"));
}

/// The floors measured against chance on the same takes (issue 50: floors that sit below chance cannot say a method
/// works). Every floor of an action segmenter or a labeller of these classes lies above chance: F1@1s and covering
/// above the chance row's (cuts at the mean true segment length from random phases, 20 seeds), and a labeller's frame
/// accuracy above chance's labels read by name. (A segmenter's frame accuracy matches its clusters one-to-one to the
/// labels, and so does any cut: equal parts matched that way reach 0.73–0.77 here, SSSM and PCA measure 0.74–0.99 —
/// no floor with a margin fits between; their cuts are what F1 and covering judge.) The floors that are not above
/// chance are named in [`BELOW_CHANCE`]: the gesture cutters scored against action labels and the models of other
/// classes, kept only as did-not-get-worse floors; a floor that rises above chance or falls below it must move.
#[test]
fn floors_stand_against_chance() {
    let mut wrong = Vec::new();
    for (k, (motion, truth)) in takes().iter().enumerate() {
        let chance = chance_scores(truth, motion.fps, &prior(&[truth]), Level::Action, 20).unwrap();
        eprintln!(
            "{}: chance F1@1s {:.3}, covering {:.3}, frame accuracy by name {:.3}",
            truth.trial, chance.f1_1, chance.covering, chance.frame_accuracy
        );
        for floor in FLOORS {
            let (f1, covering, accuracy) = floor.least[k];
            let labeller =
                mocapseg::methods::scoring(floor.method).naming == mocapseg::segment::metrics::Naming::ByName;
            let above =
                f1 > chance.f1_1 && covering > chance.covering && (!labeller || accuracy > chance.frame_accuracy);
            let what = [floor.method].iter().chain(floor.overrides).copied().collect::<Vec<_>>().join(" ");
            let listed = BELOW_CHANCE.contains(&what.as_str());
            if above == listed {
                wrong.push(format!(
                    "{what} on {}: floors {f1} / {covering} / {accuracy} against chance {:.3} / {:.3} / {:.3} — {}",
                    truth.trial,
                    chance.f1_1,
                    chance.covering,
                    chance.frame_accuracy,
                    if listed { "above chance now: take it off BELOW_CHANCE" } else { "below chance" }
                ));
            }
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

/// The floors below chance on these takes (method and overrides as listed in [`FLOORS`]): what a floor of theirs can
/// and cannot say is in [`floors_stand_against_chance`].
const BELOW_CHANCE: &[&str] = &[
    // velocity, KCS and LMA cut gestures, finer than actions: against action labels they are below chance (their
    // gesture floors: tests/lma.rs `the_searches_find_planted_boundaries_better_than_random_ones` for LMA; velocity and
    // KCS have none above chance — docs/accuracy.md's gesture table has them below it too)
    "velocity",
    "kcs",
    "lma",
    "lma search=\"deviance\"",
    // the models of other classes name nothing of these takes; their cuts too are below chance
    "dtfcn model=\"cmu-actions\" fit_check=false",
    "knn model=\"cmu-actions\" fit_check=false",
    "dtfcn model=\"locomotion\" fit_check=false",
    "knn model=\"locomotion\" fit_check=false",
];

/// The take fit (`src/methods/dtfcn/fit.rs`): the CMU-actions and locomotion models, taught no exercise, say the two
/// exercise takes do not fit them and label every frame unknown; the exercises models' takes fit (their floors above
/// are met with the check on).
#[test]
fn models_of_other_classes_call_the_takes_unknown() {
    for (motion, truth) in takes() {
        for kind in ["dtfcn", "knn"] {
            for model in ["cmu-actions", "locomotion"] {
                let m = mocapseg::methods::find(kind).unwrap();
                let params = method::params_from_overrides(m, &[format!("model=\"{model}\"")]).unwrap();
                let out = m.run_json(&motion, &params, &RunOptions::default(), &mut NoProgress).unwrap();
                let what = format!("{kind} {model} on {}", truth.trial);
                assert!(out.segmentation.segments.iter().all(|s| s.label == "unknown"), "{what}");
                let summary = &out.details.summary;
                assert!(summary.starts_with(&format!("model `{model}` does not fit this take")), "{what}: {summary}");
            }
        }
    }
}

/// The chance reference on the same takes: what cutting blind scores. A method's floor well above it shows the floor
/// means something; chance itself is checked to behave (more seeds do not move it much, it is far from perfect).
#[test]
fn chance_on_the_fixtures_is_far_below_a_perfect_score() {
    for (motion, truth) in takes() {
        let p = prior(&[&truth]);
        let c = chance_scores(&truth, motion.fps, &p, Level::Action, 20).unwrap();
        eprintln!(
            "chance on {}: F1@1s {:.3}, covering {:.3}, frame accuracy {:.3}",
            truth.trial, c.f1_1, c.covering, c.frame_accuracy
        );
        assert!(c.f1_1 < 0.7 && c.covering < 0.8, "{c:?}");
        assert!((c.segments - truth.segments.len() as f64).abs() <= 1.5, "about as many segments as the truth: {c:?}");
    }
}

/// Labels that do not flicker (issue 23): the shipped `exercises` labellers' own decoding (stored in the model file,
/// `labeller::decode`, the default `decoding=model`) cuts each take into at most twice its true segments, never
/// more than the raw per-frame labels (`decoding=raw`), at an edit score no lower and about the same frame accuracy,
/// and no run but the last is shorter than the model's minimum.
#[test]
fn decoded_labels_cut_a_take_into_at_most_twice_its_true_segments() {
    for (motion, truth) in takes() {
        let n = truth.segments.len();
        for kind in ["dtfcn", "knn"] {
            let m = mocapseg::methods::find(kind).unwrap();
            let run = |extra: &[&str]| {
                let mut o = vec!["model=\"exercises\""];
                o.extend_from_slice(extra);
                let overrides: Vec<String> = o.iter().map(|s| s.to_string()).collect();
                let params = method::params_from_overrides(m, &overrides).unwrap();
                let out = m.run_json(&motion, &params, &RunOptions::default(), &mut NoProgress).unwrap();
                let s = evaluate(&out.segmentation, &truth, &mocapseg::methods::scoring(kind)).unwrap();
                (out.segmentation, s)
            };
            let (raw, raw_s) = run(&["decoding=\"raw\""]);
            let (dec, dec_s) = run(&[]);
            let what = format!("{kind} exercises on {}", truth.trial);
            eprintln!(
                "{what}: raw {} segments, edit {:.1}, F1@50 {:.1}, frame acc. {:.3}; decoded {} segments, edit {:.1}, \
                 F1@50 {:.1}, frame acc. {:.3} ({n} true)",
                raw.segments.len(),
                raw_s.labelling.edit,
                raw_s.labelling.f1[2],
                raw_s.labelling.frame_accuracy,
                dec.segments.len(),
                dec_s.labelling.edit,
                dec_s.labelling.f1[2],
                dec_s.labelling.frame_accuracy
            );
            assert_eq!(dec.params["decoding"], "model");
            assert!(dec.segments.len() <= 2 * n, "{what}: {} segments for {n} true", dec.segments.len());
            assert!(dec.segments.len() <= raw.segments.len(), "{what}");
            assert!(dec_s.labelling.edit >= raw_s.labelling.edit, "{what}");
            assert!(dec_s.labelling.frame_accuracy >= raw_s.labelling.frame_accuracy - 0.02, "{what}");
            // the model's minimum run (less the half working frame a run's ends may move by when mapped to the
            // file's frames); the segments tile the take
            let supervised = mocapseg::methods::find(kind).unwrap().supervised().unwrap();
            let shipped = supervised.shipped_model("exercises", &mocapseg::method::ModelStore::default()).unwrap();
            let decoding = shipped
                .model
                .downcast_ref::<mocapseg::labeller::model::Model>()
                .unwrap()
                .header
                .decoding
                .expect("the shipped exercises models carry their decoding");
            dec.validate().unwrap();
            let least = decoding.min_duration_s * motion.fps - motion.fps / 30.0;
            let short = dec.segments[..dec.segments.len() - 1]
                .iter()
                .filter(|g| g.label != "unknown" && ((g.end + 1 - g.start) as f64) < least)
                .count();
            assert_eq!(short, 0, "{what}: {:?}", dec.segments);
        }
    }
}

/// Out-of-sample floors (issue 50): the floors above are in-sample for the shipped labellers (trained on these very
/// takes); here each labeller is trained in the test on one fixture take and run, as a user runs a model of their
/// own, on the other, which it never saw (13_31 → 13_30, 13_30 → 13_31; 13_30 has a Squat 13_31 never teaches, 13_31 a
/// ToeTouchOneHand and an ArmCircle 13_30 never teaches: those frames can only be wrong by name). The k-NN with its
/// defaults; DT-FCN a small network (three layers of 32, w = 3, 25 epochs, no augmentation: quick in the test profile).
/// Both decode as the shipped exercises models do (runs ≥ 2 s, switch cost 150). Each must stay above its floor
/// (measured minus a margin, printed) and above chance on the same take — chance's labels drawn from the training
/// take's classes, scored by name as the labeller is.
#[test]
fn labellers_trained_on_one_take_label_the_other_above_chance() {
    use mocapseg::labeller::corpus::ModelMeta;
    use mocapseg::labeller::decode::Decoding;
    use mocapseg::labeller::supervised::model_info;
    use mocapseg::labels::LabelRow;
    use mocapseg::method::supervised::Loaded;
    use mocapseg::methods::dtfcn::augment::Augment;
    use mocapseg::methods::dtfcn::corpus::train_model;
    use mocapseg::methods::dtfcn::training::{TrainOptions, TrainingTake};
    use mocapseg::methods::knn::training::fit_knn_model;

    let takes = takes();
    let meta = ModelMeta {
        name: "out-of-sample".into(),
        command: "tests/accuracy.rs".into(),
        data_hash: "-".into(),
        decoding: Some(Decoding { min_duration_s: 2.0, switch_cost: 150.0 }),
        travel: None,
        unknown_threshold: 0.5,
    };
    // (labeller, trained on, scored on) → least F1@1s, covering, frame accuracy by name
    // measured 0.857 / 0.743 / 0.777 · 0.909 / 0.756 / 0.617 (k-NN); 1.000 / 0.951 / 0.778 · 0.909 / 0.787 / 0.596
    // (DT-FCN, 2–3 s of training): the frame accuracies near their ceilings 0.791 and 0.642 (the taught classes' share)
    let floors: [(&str, usize, usize, (f64, f64, f64)); 4] = [
        ("knn", 1, 0, (0.80, 0.69, 0.72)),
        ("knn", 0, 1, (0.85, 0.70, 0.56)),
        ("dtfcn", 1, 0, (0.95, 0.90, 0.72)),
        ("dtfcn", 0, 1, (0.85, 0.73, 0.54)),
    ];
    let mut wrong = Vec::new();
    for (method, train, test, (f1, covering, accuracy)) in floors {
        let (tm, tt) = &takes[train];
        let (motion, truth) = &takes[test];
        let mut classes = Vec::new();
        let labels = tt.class_frames(&mut classes);
        let started = std::time::Instant::now();
        let model = if method == "knn" {
            fit_knn_model(&[(tm, &labels[..])], &classes, &meta, Default::default()).unwrap()
        } else {
            let rows: Vec<LabelRow> = tt
                .segments
                .iter()
                .map(|s| LabelRow {
                    file: tm.name.clone(),
                    start_frame: s.start,
                    end_frame: s.end,
                    label: s.label.clone(),
                })
                .collect();
            let (classes_again, per_take) = mocapseg::labeller::corpus::class_labels(&rows, &[tm]).unwrap();
            assert_eq!(classes_again, classes);
            let training = [TrainingTake::new(tm, &per_take[0]).unwrap()];
            let options = TrainOptions {
                epochs: 300,
                width: 3,
                filters: vec![32, 32, 32],
                augment: Augment::none(),
                crop_frames: 128,
                batch: 4,
                learning_rate: 3e-3,
                ..TrainOptions::default()
            };
            train_model(&training, &[], &classes, &options, &meta, &mut |_| true).unwrap()
        };
        let trained_s = started.elapsed().as_secs_f64();
        let m = mocapseg::methods::find(method).unwrap();
        let kind = *mocapseg::methods::LABELLERS.iter().find(|k| k.name() == method).unwrap();
        let mut store = mocapseg::method::ModelStore::new();
        store.install(Loaded { info: model_info(kind, "out-of-sample", &model), model: std::sync::Arc::new(model) });
        let checked = m.check_json_in(&serde_json::json!({ "model": "out-of-sample" }), &store).unwrap();
        let out = m.run_checked(motion, &checked, &RunOptions::default(), &mut NoProgress).unwrap();
        let s = evaluate(&out.segmentation, truth, &mocapseg::methods::scoring(method)).unwrap();
        // by name, the frames of a class never taught cannot be right
        let taught =
            truth.segments.iter().filter(|g| classes.contains(&g.label)).map(|g| g.end + 1 - g.start).sum::<usize>()
                as f64
                / truth.frames as f64;
        assert!(
            s.labelling.frame_accuracy <= taught + 1e-9,
            "{method}: {} above the taught share {taught}",
            s.labelling.frame_accuracy
        );
        let chance = chance_scores(truth, motion.fps, &prior(&[tt]), Level::Action, 20).unwrap();
        let got = (s.boundaries[1].f1, s.covering, s.labelling.frame_accuracy);
        eprintln!(
            "{method} trained on {} ({trained_s:.1} s), scored on {}: F1@1s {:.3} covering {:.3} frame accuracy {:.3} \
             (chance {:.3} / {:.3} / {:.3}; ceiling {taught:.3})",
            tt.trial, truth.trial, got.0, got.1, got.2, chance.f1_1, chance.covering, chance.frame_accuracy
        );
        let what = format!("{method} {} → {}", tt.trial, truth.trial);
        if !(got.0 >= f1 && got.1 >= covering && got.2 >= accuracy) {
            wrong.push(format!("{what}: {got:?} below its floor {:?}", (f1, covering, accuracy)));
        }
        if !(f1 > chance.f1_1 && covering > chance.covering && accuracy > chance.frame_accuracy) {
            wrong.push(format!(
                "{what}: floor {:?} not above chance {:.3} / {:.3} / {:.3}",
                (f1, covering, accuracy),
                chance.f1_1,
                chance.covering,
                chance.frame_accuracy
            ));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

/// The open-set unknown (issue 50, `src/labeller/openset.rs`): a k-NN trained on 13_31 never sees 13_30's Squat. Its
/// ratio is the one `choose_open_set_unknown` picks on the two fixture takes' folds (each class left out in turn, each
/// take holding it scored by a k-NN fitted on the other without it; 13_30 among them, so the ratio is not out of
/// sample here — the held-out figures are `cargo run --release --example eval_knn -- unseen`, docs/methods/dtfcn.md).
/// Run on 13_30 with it, the Squat frames are called unknown far more than the taught ones; `unknown_ratio = 0` gives
/// the labels of a model without one; a ratio out of range is refused by name.
#[test]
fn the_open_set_unknown_calls_a_class_never_taught_unknown() {
    use mocapseg::labeller::corpus::ModelMeta;
    use mocapseg::labeller::decode::Decoding;
    use mocapseg::labeller::supervised::model_info;
    use mocapseg::method::supervised::Loaded;
    use mocapseg::methods::knn::training::{choose_open_set_unknown, fit_knn_model};
    use mocapseg::methods::knn::KnnParams;

    let takes = takes();
    let decoding = Decoding { min_duration_s: 2.0, switch_cost: 150.0 };
    // both takes' classes, one index each
    let mut classes = Vec::new();
    let per_take: Vec<Vec<Option<usize>>> = takes.iter().map(|(_, t)| t.class_frames(&mut classes)).collect();
    let folds_expected: usize =
        (0..classes.len()).map(|c| per_take.iter().filter(|l| l.contains(&Some(c))).count()).sum();
    let both: Vec<(&Motion, &[Option<usize>])> = takes.iter().zip(&per_take).map(|((m, _), l)| (m, &l[..])).collect();
    let choice = choose_open_set_unknown(&both, classes.len(), KnnParams::default(), &decoding, 0.5, &mut |_| true)
        .unwrap()
        .expect("folds to choose on");
    eprintln!("open-set choice on the fixture takes' folds: {choice:?}");
    assert_eq!(choice.folds, folds_expected);
    // on the folds it was chosen on, never worse than never saying unknown
    assert!(choice.accuracy >= choice.never, "{choice:?}");
    // measured: ratio 2.02 on 11 folds, open-set frame accuracy 0.551 there against 0.533 never, gain over the two takes
    // +0.020 [+0.012, +0.027]: sure, so kept
    let unknown = choice.unknown().expect("a finite ratio: on these folds calling unknown pays");
    assert!(choice.gain.is_some_and(|(_, lo, _)| lo > 0.0), "{choice:?}");

    // a training from a label CSV of both takes (the page's, `train-knn`'s) holds that choice
    let csv: String = std::iter::once("file,start_frame,end_frame,label\n".to_string())
        .chain(takes.iter().flat_map(|(_, t)| {
            t.segments.iter().map(move |s| format!("{}.bvh,{},{},{}\n", t.trial, s.start, s.end, s.label))
        }))
        .collect();
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let ask = mocapseg::method::supervised::TrainingAsk {
        name: "both".into(),
        labels_name: "both.csv".into(),
        labels: csv,
        takes: vec![
            ("13_30.bvh".into(), std::fs::read(root.join("www/sample.bvh")).unwrap()),
            ("13_31.bvh".into(), std::fs::read(root.join("tests/fixtures/13_31.bvh")).unwrap()),
        ],
        options: serde_json::json!({"min_duration_s": 2, "switch_cost": 150}),
        ..Default::default()
    };
    let supervised = mocapseg::methods::find("knn").unwrap().supervised().unwrap();
    let mut training = supervised.start_training(ask, &mut NoProgress).unwrap();
    while !training.done() {
        training.step(&mut NoProgress).unwrap();
    }
    let trained = training.finish().unwrap();
    let header = &trained.model.model.downcast_ref::<mocapseg::labeller::model::Model>().unwrap().header;
    assert_eq!(header.open_set, Some(unknown));
    assert!(trained.report.summary.contains("Open-set unknown chosen on 11 folds"), "{}", trained.report.summary);

    // the k-NN taught 13_31's classes only (no Squat), with and without the open-set unknown
    let (m31, t31) = &takes[1];
    let (m30, t30) = &takes[0];
    let meta = ModelMeta {
        name: "open-set".into(),
        command: "tests/accuracy.rs".into(),
        data_hash: "-".into(),
        decoding: Some(decoding),
        travel: None,
        unknown_threshold: 0.5,
    };
    let mut taught_classes = Vec::new();
    let labels = t31.class_frames(&mut taught_classes);
    assert!(!taught_classes.iter().any(|c| c == "Squat") && t30.segments.iter().any(|s| s.label == "Squat"));
    let m = mocapseg::methods::find("knn").unwrap();
    let kind = *mocapseg::methods::LABELLERS.iter().find(|k| k.name() == "knn").unwrap();
    let mut store = mocapseg::method::ModelStore::new();
    for (name, open_set) in [("open-set", Some(unknown)), ("closed", None)] {
        let mut model = fit_knn_model(&[(m31, &labels[..])], &taught_classes, &meta, Default::default()).unwrap();
        model.header.open_set = open_set;
        model.header.name = name.into();
        store.install(Loaded { info: model_info(kind, name, &model), model: std::sync::Arc::new(model) });
    }
    let run = |params: serde_json::Value| {
        let checked = m.check_json_in(&params, &store).unwrap();
        m.run_checked(m30, &checked, &RunOptions::default(), &mut NoProgress).unwrap()
    };
    // per file frame: called unknown
    let unknown_frames = |out: &method::MethodOutput| {
        let mut u = vec![false; m30.frames()];
        for s in out.segmentation.segments.iter().filter(|s| s.label == mocapseg::segment::UNKNOWN) {
            u[s.start..=s.end].iter_mut().for_each(|x| *x = true);
        }
        u
    };
    let share = |u: &[bool], squat: bool| {
        let frames: Vec<bool> = t30
            .segments
            .iter()
            .filter(|s| (s.label == "Squat") == squat && (squat || taught_classes.contains(&s.label)))
            .flat_map(|s| u[s.start..=s.end].to_vec())
            .collect();
        frames.iter().filter(|&&x| x).count() as f64 / frames.len().max(1) as f64
    };
    let open = run(serde_json::json!({ "model": "open-set" }));
    let u = unknown_frames(&open);
    let (squat, taught) = (share(&u, true), share(&u, false));
    eprintln!(
        "open-set ratio {:.2}: Squat frames unknown {squat:.3}, taught frames unknown {taught:.3}; {}",
        unknown.ratio, open.details.summary
    );
    // measured 0.721 / 0.022 at the ratio chosen (2.02; 11 folds, open-set frame accuracy 0.551 there, 0.533 never)
    assert!(squat >= 0.65 && taught <= 0.07, "Squat {squat:.3}, taught {taught:.3}");
    assert!(open.details.summary.contains("open-set ratio above"), "{}", open.details.summary);
    // off: the closed model's labels, frame for frame
    let off = run(serde_json::json!({ "model": "open-set", "unknown_ratio": 0 }));
    let closed = run(serde_json::json!({ "model": "closed" }));
    let labels_of = |o: &method::MethodOutput| {
        o.segmentation.segments.iter().map(|s| (s.start, s.end, s.label.clone())).collect::<Vec<_>>()
    };
    assert_eq!(labels_of(&off), labels_of(&closed));
    assert!(share(&unknown_frames(&closed), true) < squat);
    // the closed model given a ratio at run time: the open-set unknown without one in the file
    let asked = run(serde_json::json!({ "model": "closed", "unknown_ratio": unknown.ratio }));
    assert_eq!(labels_of(&asked), labels_of(&open));
    for bad in [-1.0, 1e6] {
        let e = m.check_json_in(&serde_json::json!({ "model": "closed", "unknown_ratio": bad }), &store).err().unwrap();
        assert!(e.to_string().contains("unknown_ratio"), "{e}");
    }
}
