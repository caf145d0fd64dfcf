//! LMA Effort segmentation (Bouchard & Badler) end to end on fixture takes: the shipped
//! classifier family, the batched exhaustive deviance map against the classifiers run one
//! candidate at a time, the pipeline's output, a take too short for any segment, training
//! (reproducible from a seed) and a user's label file.
//!
//! Runs natively (`cargo test --release --test lma`) and, included by `tests/wasm.rs`, in headless
//! Chromium: the fixtures are embedded, and in wasm `#[test]` is wasm-bindgen-test's.

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use mocapseg::bvh;
use mocapseg::method::{NoProgress, RunOptions};
use mocapseg::methods::lma::body::upper_body;
use mocapseg::methods::lma::corpus::{parse_labels, Corpus, CorpusConfig};
use mocapseg::methods::lma::deviance::{exhaustive, pruned};
use mocapseg::methods::lma::features::Pool;
use mocapseg::methods::lma::method::{segment_with, LmaParams};
use mocapseg::methods::lma::network::TrainOptions;
use mocapseg::methods::lma::training::{train_family, TrainConfig};
use mocapseg::motion::Motion;
use mocapseg::segment::Level;

#[path = "support/models.rs"]
mod models;

/// The shipped family (handed over first on the page's build).
fn shipped_model() -> Result<&'static mocapseg::methods::lma::classifier::EffortModel, String> {
    models::provide();
    mocapseg::methods::lma::shipped_model()
}

const WALK: &str = include_str!("fixtures/131_01.bvh");
const OTHER: &str = include_str!("fixtures/35_01.bvh");
/// 30 s of boxing (another exporter, 100 Hz): gestures of the arms.
const BOXING: &str = include_str!("fixtures/assimp_Boxing_Toes_100fps.bvh");

fn motion(name: &str, text: &str) -> Motion {
    Motion::from_bvh(name, &bvh::parse(text).unwrap()).unwrap()
}

/// The first `frames` frames of a BVH text.
fn truncated(text: &str, frames: usize) -> String {
    let (head, motion) = text.split_once("MOTION").unwrap();
    let mut lines = motion.lines().filter(|l| !l.trim().is_empty());
    let mut out = format!("{head}MOTION\n");
    lines.next(); // Frames:
    out += &format!("Frames: {frames}\n");
    out += &format!("{}\n", lines.next().unwrap()); // Frame Time:
    for l in lines.take(frames) {
        out += l;
        out.push('\n');
    }
    out
}

#[test]
fn the_shipped_family_is_the_papers_shape() {
    let model = shipped_model().unwrap();
    assert_eq!(model.max_shift, 5);
    assert_eq!(model.shifts(), 121);
    assert_eq!((model.fps, model.min_len, model.max_len), (30.0, 20, 100));
    for f in &model.factors {
        assert_eq!(f.nets.len(), 121);
        assert!(f.components > 0 && f.components <= f.selected.len());
        assert!(f.validation_error < 0.5, "a factor's validation error is {}", f.validation_error);
    }
}

#[test]
fn the_batched_exhaustive_map_equals_the_classifiers_one_candidate_at_a_time() {
    let model = shipped_model().unwrap();
    let m = motion("131_01.bvh", WALK);
    let body = upper_body(&m, model.fps).unwrap();
    let arm = &body.arms[1];
    let pool = Pool::of(arm, model.fps, 100 + 11);
    let lengths = (20, 60);
    let fast = exhaustive(model, &pool, lengths, &mut |_| Ok(())).unwrap();
    // every frame a boundary: the pruned search assesses every candidate on its own
    let every: Vec<usize> = (0..pool.frames()).collect();
    let slow = pruned(model, &pool, &every, lengths, &mut |_| Ok(())).unwrap();
    let a: Vec<_> = fast.candidates().collect();
    let b: Vec<_> = slow.candidates().collect();
    assert_eq!(a.len(), b.len());
    assert!(a.len() > 1000, "{} candidates", a.len());
    for ((s, e, x), (s2, e2, y)) in a.into_iter().zip(b) {
        assert_eq!((s, e), (s2, e2));
        assert!((x - y).abs() < 1e-4, "{s}..={e}: batched {x}, direct {y}");
    }
}

#[test]
fn both_searches_segment_a_take_into_gestures_with_their_effort() {
    let model = shipped_model().unwrap();
    let m = motion("131_01.bvh", WALK);
    for exhaustive in [false, true] {
        let params = LmaParams { exhaustive, ..LmaParams::default() };
        let out = segment_with(model, &m, &params, &RunOptions { pictures: true }, &mut NoProgress).unwrap();
        let seg = &out.segmentation;
        seg.validate().unwrap();
        assert_eq!(seg.method, "lma");
        assert_eq!(seg.params["exhaustive"], exhaustive);
        for s in &seg.segments {
            assert_eq!(s.level, Level::Primitive);
            let seconds = (s.end - s.start) as f64 / m.fps;
            assert!((0.6..=3.4).contains(&seconds), "{s:?} lasts {seconds} s");
            let e = s.effort.expect("every LMA segment has its effort");
            for v in [e.space, e.time, e.weight, e.flow] {
                assert!((-1.0..=1.0).contains(&v), "{e:?}");
            }
            assert!(["left arm", "right arm", "both arms"].contains(&s.label.as_str()));
        }
        let ids: Vec<&str> = out.details.pictures.iter().map(|p| p.id.as_str()).collect();
        assert_eq!(ids, ["deviance-left", "deviance-right", "effort"]);
        for p in &out.details.pictures {
            assert_eq!(p.rgba.len(), p.width * p.height * 4);
            // the pruned search may find no slow-hand frames in a walk: its maps may stay empty
            let distinct: std::collections::HashSet<&[u8]> = p.rgba.chunks(4).collect();
            assert!(!exhaustive || distinct.len() > 3, "{} is nearly blank", p.id);
        }
        if exhaustive {
            assert!(!seg.segments.is_empty(), "the exhaustive search found nothing in {} s", m.duration_s());
        }
    }
}

#[test]
fn the_pruned_search_finds_gestures_in_boxing() {
    let model = shipped_model().unwrap();
    let m = motion("boxing.bvh", BOXING);
    let out = segment_with(model, &m, &LmaParams::default(), &RunOptions::default(), &mut NoProgress).unwrap();
    out.segmentation.validate().unwrap();
    assert!(!out.segmentation.segments.is_empty(), "{}", out.details.summary);
    assert!(out.details.summary.contains("pruned search"), "{}", out.details.summary);
}

#[test]
fn a_take_shorter_than_the_shortest_segment_gives_none() {
    let model = shipped_model().unwrap();
    // 60 frames at 120 Hz: half a second
    let m = motion("short.bvh", &truncated(WALK, 60));
    for exhaustive in [false, true] {
        let params = LmaParams { exhaustive, ..LmaParams::default() };
        let out = segment_with(model, &m, &params, &RunOptions { pictures: true }, &mut NoProgress).unwrap();
        assert!(out.segmentation.segments.is_empty());
    }
}

/// A quick family (few restarts, short training) on two fixture takes.
fn quick(corpus: &Corpus, seed: u64) -> mocapseg::methods::lma::classifier::EffortModel {
    let options = TrainOptions { max_epochs: 40, learning_rate: 0.02, weight_decay: 1e-4, patience: 10 };
    let config = TrainConfig {
        seed,
        restarts: 2,
        saliency_rounds: 4,
        options,
        shift_options: TrainOptions { max_epochs: 3, ..options },
        ..TrainConfig::default()
    };
    train_family(corpus, &config, &mut |_, _| Ok(())).unwrap().0
}

#[test]
fn training_is_reproducible_and_reads_user_labels() {
    let takes = [motion("131_01.bvh", WALK), motion("35_01.bvh", OTHER)];
    let refs: Vec<&Motion> = takes.iter().collect();
    let corpus = Corpus::from_descriptors(&refs, CorpusConfig::default()).unwrap();
    assert!(corpus.samples.len() >= 20, "{} segments", corpus.samples.len());
    let a = quick(&corpus, 7);
    assert_eq!(a, quick(&corpus, 7), "same seed, same family");
    assert_ne!(a, quick(&corpus, 8));
    assert_eq!(a.shifts(), 121);
    // the family it made segments a take
    let out = segment_with(&a, &takes[0], &LmaParams::default(), &RunOptions::default(), &mut NoProgress).unwrap();
    out.segmentation.validate().unwrap();
    // a user's labels: rows of both takes, by file name
    let csv = "file,start_frame,end_frame,space,time,weight,flow\n\
               131_01.bvh,0,200,direct,sudden,strong,bound\n"
        .replace("direct,sudden,strong,bound", "condensing,condensing,condensing,condensing");
    let mut rows = parse_labels(&csv, "mine.csv").unwrap();
    for k in 0..11 {
        let start = 20 * k;
        let class = ["indulging", "neutral", "condensing"][k % 3];
        let line = format!(
            "file,start_frame,end_frame,space,time,weight,flow\n35_01,{start},{},{class},{class},{class},{class}\n",
            start + 80
        );
        rows.extend(parse_labels(&line, "mine.csv").unwrap());
    }
    let corpus = Corpus::from_labels(&refs, &rows, CorpusConfig::default()).unwrap();
    assert_eq!(corpus.samples.len(), 12);
    assert!(corpus.origin.contains("12 user-labelled segments"));
    let mine = quick(&corpus, 1);
    assert_eq!(mine.samples, 12);
    // a row naming a take that is not loaded is refused with its line
    let stray = parse_labels(
        "file,start_frame,end_frame,space,time,weight,flow\nnope.bvh,0,50,neutral,neutral,neutral,neutral\n",
        "mine.csv",
    )
    .unwrap();
    let err = Corpus::from_labels(&refs, &stray, CorpusConfig::default()).err().unwrap();
    assert!(err.contains("line 2") && err.contains("nope.bvh"), "{err}");
}
