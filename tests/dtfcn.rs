//! DT-FCN (Cheema et al. 2019) and its k-NN baseline end to end on fixture takes: a small
//! network overfits two short takes to 100 %, training is reproducible from its seed, a model
//! file saved and loaded labels identically, the paper's noise and masking do what Tables 3–4
//! describe, the registered methods label a take with a user's model, and the shipped models
//! load and label a walk.
//!
//! Runs natively (`cargo test --test dtfcn`) and, included by `tests/wasm.rs`, in headless
//! Chromium: the fixtures are embedded, and in wasm `#[test]` is wasm-bindgen-test's.

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use mocapseg::bvh;
use mocapseg::labeller::corpus::{class_labels, ModelMeta};
use mocapseg::labeller::method::label;
use mocapseg::labeller::model::Model;
use mocapseg::labeller::shipped;
use mocapseg::labeller::supervised::{model_info, shipped_names};
use mocapseg::labels::LabelRow;
use mocapseg::method::supervised::{check_model_name, Loaded};
use mocapseg::method::ModelStore;
use mocapseg::method::{NoProgress, RunOptions};
use mocapseg::methods::dtfcn::augment::Augment;
use mocapseg::methods::dtfcn::corpus::train_model;
use mocapseg::methods::dtfcn::infer::predict_input;
use mocapseg::methods::dtfcn::model::networks_of;
use mocapseg::methods::dtfcn::training::{boundary_mask, evaluate, noisy_labels, TrainOptions, TrainingTake};
use mocapseg::methods::find;
use mocapseg::methods::knn::training::{fit_knn_model, knn_fold};
use mocapseg::methods::LABELLERS as KINDS;
use mocapseg::motion::Motion;
use mocapseg::stats::Rng;

#[path = "support/models.rs"]
mod models;

const WALK: &str = include_str!("fixtures/02_01.bvh");
const OTHER: &str = include_str!("fixtures/35_01.bvh");

fn motion(name: &str, text: &str) -> Motion {
    Motion::from_bvh(name, &bvh::parse(text).unwrap()).unwrap()
}

/// A small network and no augmentation: quick enough for a test in any profile.
fn small(epochs: usize) -> TrainOptions {
    TrainOptions {
        epochs,
        filters: vec![16, 16, 32],
        augment: Augment::none(),
        crop_frames: 64,
        batch: 4,
        learning_rate: 5e-3,
        weight_decay: 0.0,
        ..TrainOptions::default()
    }
}

/// Two takes, each labelled `a` in its first half and `b` (walk) or `c` (other) after.
fn two_takes() -> (Vec<Motion>, Vec<String>, Vec<TrainingTake>) {
    let takes = vec![motion("02_01.bvh", WALK), motion("35_01.bvh", OTHER)];
    let rows: Vec<LabelRow> = takes
        .iter()
        .zip(["b", "c"])
        .flat_map(|(m, second)| {
            let half = m.frames() / 2;
            [
                LabelRow { file: m.name.clone(), start_frame: 0, end_frame: half - 1, label: "a".into() },
                LabelRow { file: m.name.clone(), start_frame: half, end_frame: m.frames() - 1, label: second.into() },
            ]
        })
        .collect();
    let refs: Vec<&Motion> = takes.iter().collect();
    let (classes, labels) = class_labels(&rows, &refs).unwrap();
    let training = takes.iter().zip(&labels).map(|(m, l)| TrainingTake::new(m, l).unwrap()).collect();
    (takes, classes, training)
}

fn meta() -> ModelMeta {
    ModelMeta {
        name: "test".into(),
        command: "tests/dtfcn.rs".into(),
        data_hash: "-".into(),
        decoding: None,
        travel: None,
        unknown_threshold: 0.5,
    }
}

#[test]
fn a_small_network_overfits_two_short_takes() {
    let (_, classes, takes) = two_takes();
    assert_eq!(classes, vec!["a", "b", "c"]);
    let model = train_model(&takes, &[], &classes, &small(80), &meta(), &mut |_| true).unwrap();
    let nets = &networks_of(&model).expect("a network").nets;
    let s = model.header.standardise.as_ref().unwrap();
    let (loss, accuracy) = evaluate(&nets[0], s, &takes, classes.len()).unwrap();
    assert_eq!(accuracy, 1.0, "loss {loss}");
}

#[test]
fn the_same_seed_trains_the_same_model_and_another_seed_another() {
    let (_, classes, takes) = two_takes();
    let bytes = |seed| {
        let o = TrainOptions { seed, augment: Augment::all(), ..small(2) };
        train_model(&takes, &[], &classes, &o, &meta(), &mut |_| true).unwrap().to_bytes().unwrap()
    };
    let a = bytes(5);
    assert_eq!(a, bytes(5));
    assert_ne!(a, bytes(6));
}

/// Stochastic weight averaging (`average_last`): the kept weights are the mean of the last epochs' — the same
/// weights as the shorter runs of the same seed end with — one epoch is the last epoch's, and a window longer than
/// the run takes every epoch.
#[test]
fn weight_averaging_keeps_the_mean_of_the_last_epochs() {
    use mocapseg::methods::dtfcn::training::weights_of;
    let (_, classes, takes) = two_takes();
    let after = |epochs, average_last| {
        let o = TrainOptions { average_last, ..small(epochs) };
        let model = train_model(&takes, &[], &classes, &o, &meta(), &mut |_| true).unwrap();
        let nets = &networks_of(&model).expect("a network").nets;
        weights_of(&nets[0])
    };
    let epochs: Vec<Vec<Vec<f32>>> = (1..=3).map(|e| after(e, 0)).collect();
    assert_ne!(epochs[1], epochs[2], "the weights move from epoch to epoch");
    assert_eq!(after(3, 1), epochs[2]);
    let mean_of = |from: usize| -> Vec<Vec<f32>> {
        let n = (epochs.len() - from) as f32;
        (0..epochs[2].len())
            .map(|p| (0..epochs[2][p].len()).map(|i| epochs[from..].iter().map(|e| e[p][i]).sum::<f32>() / n).collect())
            .collect()
    };
    for (averaged, from) in [(after(3, 2), 1), (after(3, 10), 0)] {
        let expected = mean_of(from);
        assert_eq!(averaged.len(), expected.len());
        for (a, e) in averaged.iter().flatten().zip(expected.iter().flatten()) {
            assert!((a - e).abs() <= 1e-5 * (1.0 + e.abs()), "{a} vs {e} (epochs {}..=3)", from + 1);
        }
    }
}

#[test]
fn a_saved_model_loads_and_labels_exactly_as_before() {
    let (motions, classes, takes) = two_takes();
    let model = train_model(&takes, &[], &classes, &small(3), &meta(), &mut |_| true).unwrap();
    let bytes = model.to_bytes().unwrap();
    let back = Model::from_bytes(&bytes, "test.model", &KINDS).unwrap();
    let a = label(&model, &motions[0], &mut NoProgress).unwrap();
    let b = label(&back, &motions[0], &mut NoProgress).unwrap();
    assert_eq!(a.probabilities, b.probabilities);
    assert_eq!(a.per_file_frame.len(), motions[0].frames());
    // blockwise inference gives the whole take's result
    let (Some(networks), Some(s)) = (networks_of(&model), model.header.standardise.as_ref()) else { panic!() };
    let nets = &networks.nets;
    let whole = predict_input(&nets[0], s, &takes[0].input, 3);
    let blocks =
        mocapseg::methods::dtfcn::infer::predict_members(nets, s, &takes[0].input, 3, 17, &mut |_| true).unwrap();
    for (x, y) in whole.values.iter().zip(&blocks.values) {
        assert!((x - y).abs() < 1e-5, "{x} vs {y}");
    }
}

/// `centre_on_take`: training centres each whole take on its own median posture before fitting the standardisation,
/// the model file keeps the flag, labelling centres the whole take the same way, and a resumed training keeps its
/// model's centring whatever its options say; without the option nothing is centred.
#[test]
fn a_model_centred_on_each_take_is_trained_kept_and_run_on_centred_takes() {
    use mocapseg::labeller::input::{centred_on_take, NetworkInput, Standardise};
    use mocapseg::methods::dtfcn::training::Trainer;
    let (motions, classes, takes) = two_takes();
    let options = TrainOptions { centre_on_take: true, ..small(2) };
    let model = train_model(&takes, &[], &classes, &options, &meta(), &mut |_| true).unwrap();
    let s = model.header.standardise.clone().unwrap();
    assert!(s.centre_on_take);
    // its statistics are the centred takes'
    let centred: Vec<NetworkInput> = takes.iter().map(|t| centred_on_take(&t.input)).collect();
    assert_eq!(Standardise::fit(&centred.iter().collect::<Vec<_>>()).centring(true), s);
    // the file keeps it, and a run labels with the network on the centred take
    let back = Model::from_bytes(&model.to_bytes().unwrap(), "centred.model", &KINDS).unwrap();
    assert_eq!(back.header.standardise.as_ref(), Some(&s));
    let run = label(&back, &motions[0], &mut NoProgress).unwrap();
    let networks = networks_of(&back).expect("a network");
    let nets = &networks.nets;
    let direct = predict_input(&nets[0], &s.clone().centring(false), &centred[0], classes.len());
    for (x, y) in run.probabilities.values.iter().zip(&direct.values) {
        assert!((x - y).abs() < 1e-5, "{x} vs {y}");
    }
    // not centred, the same takes give other statistics and another labelling
    let plain = train_model(&takes, &[], &classes, &small(2), &meta(), &mut |_| true).unwrap();
    let p = plain.header.standardise.clone().unwrap();
    assert!(!p.centre_on_take && p.mean != s.mean);
    // resumed without the option, the model still centres
    let start = (networks.config.clone(), s.clone(), nets[0].clone());
    let mut resumed = Trainer::resume(takes.clone(), vec![], classes.clone(), small(1), start).unwrap();
    resumed.epoch().unwrap();
    assert!(resumed.finish().unwrap().standardise.centre_on_take);
}

/// A few-seed ensemble (`members`): its networks are the single networks of seeds `seed`, `seed + 1`, … trained
/// alone, it labels with the mean of their probabilities, and its file reads back byte for byte (a header whose
/// networks' byte counts do not add up to the weights is refused by name).
#[test]
fn an_ensemble_holds_its_seeds_networks_and_labels_with_their_mean() {
    use mocapseg::methods::dtfcn::training::weights_of;
    let (motions, classes, takes) = two_takes();
    let train = |o: TrainOptions| train_model(&takes, &[], &classes, &o, &meta(), &mut |_| true).unwrap();
    let ensemble = train(TrainOptions { seed: 7, members: 3, ..small(2) });
    let alone: Vec<Model> = (7..10).map(|seed| train(TrainOptions { seed, ..small(2) })).collect();
    let nets = &networks_of(&ensemble).expect("a network").nets;
    assert_eq!(nets.len(), 3);
    for (net, single) in nets.iter().zip(&alone) {
        let one = &networks_of(single).expect("a network").nets;
        assert_eq!(one.len(), 1);
        assert_eq!(weights_of(net), weights_of(&one[0]), "each network is its seed's network trained alone");
    }
    assert_ne!(weights_of(&nets[0]), weights_of(&nets[1]), "the seeds differ");
    let p = &ensemble.header.provenance;
    assert_eq!(p.members.iter().map(|m| m.seed).collect::<Vec<_>>(), vec![7, 8, 9]);
    assert_eq!(p.options.read::<TrainOptions>().unwrap().members, 3);
    assert_eq!(ensemble.header.standardise, alone[0].header.standardise, "one input scaling for all");
    // labels: every class's probability the mean of the three networks'
    let mean = label(&ensemble, &motions[1], &mut NoProgress).unwrap().probabilities;
    let each: Vec<_> = alone.iter().map(|m| label(m, &motions[1], &mut NoProgress).unwrap().probabilities).collect();
    assert_eq!((mean.frames, mean.classes), (each[0].frames, 3));
    for (i, v) in mean.values.iter().enumerate() {
        let expected = each.iter().map(|p| p.values[i]).sum::<f32>() / 3.0;
        assert!((v - expected).abs() < 1e-5, "value {i}: {v} vs the members' mean {expected}");
    }
    assert!(each.iter().all(|p| p.values != mean.values), "the mean is none of the networks alone");
    // the file: three networks' weights, read back and written again byte for byte
    let bytes = ensemble.to_bytes().unwrap();
    let back = Model::from_bytes(&bytes, "e.model", &KINDS).unwrap();
    assert_eq!(back.header.member_bytes.len(), 3);
    assert_eq!(back.to_bytes().unwrap(), bytes);
    assert_eq!(label(&back, &motions[1], &mut NoProgress).unwrap().probabilities, mean);
    let mut lying = back.header.clone();
    lying.member_bytes[0] += 4;
    lying.member_bytes[1] -= 4;
    let moved = Model::replace_header(&bytes, "e.model", &lying, &KINDS).unwrap();
    let e = Model::from_bytes(&moved, "e.model", &KINDS).unwrap_err();
    assert!(e.starts_with("e.model: the weights (network 2 of 3) are not a burn record"), "{e}");
    lying.member_bytes[0] += 4;
    let e = Model::from_bytes(&Model::replace_header(&bytes, "e.model", &lying, &KINDS).unwrap(), "e.model", &KINDS)
        .unwrap_err();
    assert!(e.contains("3 networks hold") && e.contains("bytes of weights"), "{e}");
    // a single network's file says nothing of members (the files made before ensembles read the same)
    let single = alone[0].to_bytes().unwrap();
    assert!(Model::from_bytes(&single, "s.model", &KINDS).unwrap().header.member_bytes.is_empty());
    assert!(!String::from_utf8_lossy(&single).contains("member"), "no member fields in a one-network header");
}

#[test]
fn noise_replaces_the_share_asked_and_masking_blanks_the_boundaries() {
    let labels: Vec<Option<usize>> = (0..10_000).map(|f| Some(f / 1000 % 4)).collect();
    let noisy = noisy_labels(&labels, 4, 0.8, &mut Rng::new(1));
    let changed = labels.iter().zip(&noisy).filter(|(a, b)| a != b).count() as f64 / labels.len() as f64;
    // 80 % drawn at random, a quarter of which land on the true label: 60 % changed
    assert!((changed - 0.6).abs() < 0.02, "{changed}");
    assert_eq!(noisy_labels(&labels, 4, 0.0, &mut Rng::new(1)), labels);

    let labels: Vec<Option<usize>> = (0..40).map(|f| Some(usize::from(f >= 20))).chain([None, None]).collect();
    let mask = boundary_mask(&labels, 11);
    let zeros: Vec<usize> = (0..mask.len()).filter(|&f| mask[f] == 0.0).collect();
    // 11 frames centred on the change between 19 and 20, 11 before the unlabelled end, and the
    // unlabelled frames themselves
    assert_eq!(&zeros[..11], &(15..26).collect::<Vec<_>>()[..]);
    assert!(zeros.contains(&40) && zeros.contains(&41) && zeros.contains(&35));
    assert_eq!(boundary_mask(&labels, 0).iter().filter(|&&m| m == 0.0).count(), 2);
}

#[test]
fn the_registered_methods_label_a_take_with_a_users_models() {
    let (motions, classes, takes) = two_takes();
    let net = train_model(&takes, &[], &classes, &small(3), &meta(), &mut |_| true).unwrap();
    // the models a run may name are the caller's: a store, as the page's worker and a CLI run own
    let mut store = ModelStore::new();
    let kind = |m: &Model| *KINDS.iter().find(|k| k.name() == m.header.kind).unwrap();
    let stored = |m: Model| Loaded { info: model_info(kind(&m), "my-test-model", &m), model: std::sync::Arc::new(m) };
    store.install(stored(net));
    let labels: Vec<Vec<Option<usize>>> = takes
        .iter()
        .zip(&motions)
        .map(|(t, m)| TrainingTake::to_file_frames(&t.input.source_frames, m.frames(), &t.labels))
        .collect();
    let knn_takes: Vec<(&Motion, &[Option<usize>])> =
        motions.iter().zip(&labels).map(|(m, l)| (m, l.as_slice())).collect();
    store.install(stored(fit_knn_model(&knn_takes, &classes, &meta(), Default::default()).unwrap()));
    // the same models made with another unknown threshold, which a run uses unless it asks for its own
    let strict = |mut m: Model| {
        m.header.unknown_threshold = 1.0;
        Loaded { info: model_info(kind(&m), "strict-model", &m), model: std::sync::Arc::new(m) }
    };
    store.install(strict(train_model(&takes, &[], &classes, &small(3), &meta(), &mut |_| true).unwrap()));
    store.install(strict(fit_knn_model(&knn_takes, &classes, &meta(), Default::default()).unwrap()));
    for name in ["dtfcn", "knn"] {
        let m = find(name).unwrap();
        let run = |params: serde_json::Value, options: &RunOptions| {
            let checked = m.check_json_in(&params, &store)?;
            m.run_checked(&motions[0], &checked, options, &mut NoProgress)
        };
        let params = serde_json::json!({ "model": "my-test-model", "unknown_threshold": 0.0 });
        let out = run(params, &RunOptions { pictures: true, ..RunOptions::default() }).unwrap();
        let s = &out.segmentation;
        s.validate().unwrap();
        assert_eq!(s.segments.first().unwrap().start, 0);
        assert_eq!(s.segments.last().unwrap().end, motions[0].frames() - 1);
        assert!(s.segments.windows(2).all(|w| w[0].end + 1 == w[1].start), "{name}: segments tile the take");
        assert!(s.segments.iter().all(|g| classes.contains(&g.label)), "{name}");
        assert_eq!(out.details.curves[0].values.len(), motions[0].frames());
        assert_eq!(out.details.pictures[0].height % 3, 0);
        // a threshold of 1 leaves nothing certain enough
        let params = serde_json::json!({ "model": "my-test-model", "unknown_threshold": 1.0 });
        let out = run(params, &RunOptions::default()).unwrap();
        assert!(out.segmentation.segments.iter().any(|g| g.label == "unknown"), "{name}");
        // no threshold asked: the model's own (1 for the strict model, as 1 asked; the header's 0.5 for the other,
        // as 0.5 asked), and the run says which it used
        let own =
            run(serde_json::json!({ "model": "strict-model", "fit_check": false }), &RunOptions::default()).unwrap();
        let one = serde_json::json!({ "model": "strict-model", "fit_check": false, "unknown_threshold": 1.0 });
        assert_eq!(own.segmentation.segments, run(one, &RunOptions::default()).unwrap().segmentation.segments);
        assert!(own.segmentation.segments.iter().any(|g| g.label == "unknown"), "{name}");
        assert_eq!(own.segmentation.params["unknown_threshold"], 1.0, "{name}");
        let asked = serde_json::json!({ "model": "strict-model", "fit_check": false, "unknown_threshold": 0.0 });
        let asked = run(asked, &RunOptions::default()).unwrap();
        assert!(asked.segmentation.segments.iter().all(|g| g.label != "unknown"), "{name}");
        let plain = |t: serde_json::Value| {
            let p = serde_json::json!({ "model": "my-test-model", "fit_check": false, "unknown_threshold": t });
            run(p, &RunOptions::default()).unwrap().segmentation
        };
        let (implied, half) = (plain(serde_json::Value::Null), plain(serde_json::json!(0.5)));
        assert_eq!(implied.segments, half.segments, "{name}");
        assert_eq!(implied.params["unknown_threshold"], 0.5, "{name}");
        // a model that does not exist is refused by name, listing the shipped ones
        let err = run(serde_json::json!({ "model": "nope" }), &RunOptions::default()).err().unwrap();
        assert_eq!(err.param_name(), Some("model"));
        let err = err.to_string();
        assert!(err.contains("`nope`") && err.contains("exercises"), "{err}");
        // without the store (another process) the user's model is unknown
        assert!(m.check_json(&serde_json::json!({ "model": "my-test-model" })).is_err(), "{name}");
    }
    // a shipped model's name cannot be taken
    assert!(check_model_name("exercises", &shipped_names()).unwrap_err().contains("shipped"));
}

#[test]
fn every_shipped_model_loads_and_labels_a_walk() {
    let store = models::store();
    let walk = motion("02_01.bvh", WALK);
    for kind in ["dtfcn", "knn"] {
        let m = find(kind).unwrap();
        for name in shipped::NAMES {
            let out = m
                .check_json_in(&serde_json::json!({ "model": name }), &store)
                .and_then(|checked| m.run_checked(&walk, &checked, &RunOptions::default(), &mut NoProgress))
                .unwrap_or_else(|e| panic!("{kind} {name}: {e}"));
            out.segmentation.validate().unwrap();
            assert!(!out.segmentation.segments.is_empty());
        }
    }
}

/// Three takes for a fold of the nested protocol (held out, validation, training), each labelled `a` in its first
/// half and `b` or `c` after, per file frame.
fn three_takes() -> (Vec<Motion>, Vec<String>, Vec<Vec<Option<usize>>>) {
    let takes = vec![motion("02_01.bvh", WALK), motion("35_01.bvh", OTHER), motion("02_01-copy.bvh", WALK)];
    let classes: Vec<String> = ["a", "b", "c"].iter().map(|s| s.to_string()).collect();
    let labels: Vec<Vec<Option<usize>>> = takes
        .iter()
        .enumerate()
        .map(|(i, m)| (0..m.frames()).map(|f| Some(if f < m.frames() / 2 { 0 } else { 1 + i % 2 })).collect())
        .collect();
    (takes, classes, labels)
}

/// The fold that chooses `average_last` (`corpus::averaged_fold`) retrains the fold's networks for the chosen epochs
/// without a validation take: keeping the last epoch's weights it gives exactly the fold's early-stopped network on
/// the validation take and its final network on the held-out take (so the settings compete on equal terms), and
/// averaging the last epochs gives other networks on both.
#[test]
fn the_averaging_fold_retrains_the_folds_networks() {
    use mocapseg::methods::dtfcn::corpus::{averaged_fold, predict_held_out, NO_EXTRA};
    let (takes, classes, labels) = three_takes();
    let options = small(3);
    let fold = predict_held_out(&takes, &labels, 0, &classes, &options, &knn_fold, NO_EXTRA, &mut |_| true).unwrap();
    let last = averaged_fold(&takes, &labels, 0, &classes, &options, fold.best_epoch, true, NO_EXTRA).unwrap();
    assert_eq!(last.validation, fold.validation);
    assert_eq!(last.validation_probabilities, fold.validation_probabilities);
    assert_eq!(last.validation_source, fold.validation_source);
    assert_eq!(last.network.as_ref().map(|n| &n.0), Some(&fold.network_probabilities));
    let three = averaged_fold(&takes, &labels, 0, &classes, &options, 3, true, NO_EXTRA).unwrap();
    let averaged = TrainOptions { average_last: 3, ..options };
    let mean = averaged_fold(&takes, &labels, 0, &classes, &averaged, 3, true, NO_EXTRA).unwrap();
    assert_ne!(mean.validation_probabilities, three.validation_probabilities);
    assert_ne!(mean.network.map(|n| n.0), three.network.map(|n| n.0));
    assert_eq!(mean.validation_source, three.validation_source);
}

/// A data lever's takes (`corpus::Extra`, issue 50) join a fold's trainings made from the fold's training takes alone:
/// the early-stopped network is asked for takes from every take but the held-out and the validation one, the retrained
/// one from every take but the held-out one (so nothing is made from a take it is scored on); none made is the fold
/// without a lever, and a take made and added changes the networks.
#[test]
fn a_levers_takes_are_made_from_the_folds_training_takes_alone() {
    use mocapseg::methods::dtfcn::corpus::{averaged_fold, predict_held_out, NO_EXTRA};
    let (takes, classes, labels) = three_takes();
    let options = small(2);
    let asked = std::cell::RefCell::new(Vec::new());
    let none = |fit: &[usize]| {
        asked.borrow_mut().push(fit.to_vec());
        Ok(Vec::new())
    };
    let plain = predict_held_out(&takes, &labels, 0, &classes, &options, &knn_fold, NO_EXTRA, &mut |_| true).unwrap();
    let with_none = predict_held_out(&takes, &labels, 0, &classes, &options, &knn_fold, &none, &mut |_| true).unwrap();
    assert_eq!(with_none.network_probabilities, plain.network_probabilities);
    assert_eq!(with_none.validation_probabilities, plain.validation_probabilities);
    let inner: Vec<usize> = (0..3).filter(|&i| i != 0 && i != plain.validation).collect();
    assert_eq!(*asked.borrow(), vec![inner.clone(), vec![1, 2]], "early stopping, then the retraining");
    asked.borrow_mut().clear();
    averaged_fold(&takes, &labels, 0, &classes, &options, 2, true, &none).unwrap();
    assert_eq!(*asked.borrow(), vec![inner, vec![1, 2]]);
    // a copy of the first training take, its labels all `a`: other networks
    let copy = |fit: &[usize]| Ok(vec![(takes[fit[0]].clone(), vec![Some(0); takes[fit[0]].frames()])]);
    let with_copy = predict_held_out(&takes, &labels, 0, &classes, &options, &knn_fold, &copy, &mut |_| true).unwrap();
    assert_ne!(with_copy.network_probabilities, plain.network_probabilities);
    // a lever that cannot make its takes stops the fold with its message
    let broken = |_: &[usize]| Err("no carrier".to_string());
    let e = predict_held_out(&takes, &labels, 0, &classes, &options, &knn_fold, &broken, &mut |_| true);
    assert_eq!(e.err().as_deref(), Some("no carrier"));
}

/// The two halves of a nested fold (`corpus::validation_fold`, `final_fold`) are `predict_held_out`'s own networks
/// when the validation take is the one it uses; another inner take validates another network; and neither reads the
/// held-out take's labels.
#[test]
fn a_fold_validates_on_any_inner_take() {
    use mocapseg::methods::dtfcn::corpus::{final_fold, predict_held_out, validation_fold, NO_EXTRA};
    let (takes, classes, labels) = three_takes();
    let options = small(3);
    let fold = predict_held_out(&takes, &labels, 0, &classes, &options, &knn_fold, NO_EXTRA, &mut |_| true).unwrap();
    let (p, source, epoch) = validation_fold(&takes, &labels, 0, fold.validation, &classes, &options).unwrap();
    assert_eq!(
        (p, source, epoch),
        (fold.validation_probabilities.clone(), fold.validation_source.clone(), fold.best_epoch)
    );
    let (p, source) = final_fold(&takes, &labels, 0, &classes, &options, fold.best_epoch).unwrap();
    assert_eq!((p, source), (fold.network_probabilities.clone(), fold.network_source.clone()));
    let other = 3 - fold.validation; // the other inner take (takes 1 and 2 are the inner ones)
    let (p, _, _) = validation_fold(&takes, &labels, 0, other, &classes, &options).unwrap();
    let frames = mocapseg::labeller::input::network_input(&takes[other]).unwrap().frames;
    assert_eq!(p.frames, frames, "the take asked is the one labelled");
    assert_ne!(p, fold.validation_probabilities);
    let mut scrambled = labels.clone();
    scrambled[0] = scrambled[0].iter().map(|l| l.map(|c| (c + 1) % 3)).collect();
    assert_eq!(validation_fold(&takes, &scrambled, 0, other, &classes, &options).unwrap().0, p);
    assert!(validation_fold(&takes, &labels, 1, 1, &classes, &options).is_err(), "held out and validation differ");
}

/// The nested protocol never reads the held-out take's labels (issue 23): the same fold with that take's labels
/// scrambled — shifted by half the take, and a class no other take has — trains the same networks and the same k-NN,
/// and predicts exactly the same probabilities for the held-out take and its validation take.
#[test]
fn scrambling_the_held_out_takes_labels_changes_no_prediction() {
    use mocapseg::methods::dtfcn::corpus::{predict_held_out, NO_EXTRA};
    let (takes, classes, labels) = three_takes();
    let options = small(2);
    let before = predict_held_out(&takes, &labels, 0, &classes, &options, &knn_fold, NO_EXTRA, &mut |_| true).unwrap();
    let mut scrambled = labels.clone();
    let n = scrambled[0].len();
    scrambled[0] = (0..n).map(|f| Some(if (f + n / 2) % n < n / 3 { 2 } else { 0 })).collect();
    scrambled[0][5] = None;
    assert_ne!(scrambled[0], labels[0]);
    let after =
        predict_held_out(&takes, &scrambled, 0, &classes, &options, &knn_fold, NO_EXTRA, &mut |_| true).unwrap();
    assert_eq!(before.network_probabilities, after.network_probabilities);
    assert_eq!(before.validation_probabilities, after.validation_probabilities);
    assert_eq!(before.network, after.network);
    assert_eq!(before.knn, after.knn);
    assert_eq!(before.best_epoch, after.best_epoch);
    // the validation take's labels do matter (they choose the epoch and are what it is scored on): the fold is
    // not blind to everything
    let mut other = labels.clone();
    // (all one class the take does not have: a rotation of its classes could leave a constant guess as right as
    // before)
    other[before.validation] = other[before.validation].iter().map(|_| Some(1)).collect();
    let moved = predict_held_out(&takes, &other, 0, &classes, &options, &knn_fold, NO_EXTRA, &mut |_| true).unwrap();
    assert_ne!(before.validation_accuracy, moved.validation_accuracy);
}
