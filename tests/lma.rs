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
use mocapseg::methods::lma::classifier::effort;
use mocapseg::methods::lma::corpus::{parse_labels, Corpus, CorpusConfig, EffortLabel};
use mocapseg::methods::lma::deviance::{exhaustive, pruned};
use mocapseg::methods::lma::effort::Element;
use mocapseg::methods::lma::features::Pool;
use mocapseg::methods::lma::method::{segment_with, LmaParams};
use mocapseg::methods::lma::network::TrainOptions;
use mocapseg::methods::lma::training::{train_family, TrainConfig};
use mocapseg::motion::Motion;
use mocapseg::segment::Level;

#[path = "support/models.rs"]
mod models;

/// The shipped family, read by a store of the test's own (handed over first on the page's build).
fn shipped_model() -> Result<std::sync::Arc<mocapseg::methods::lma::classifier::EffortModel>, String> {
    mocapseg::methods::lma::shipped(&models::store()).map_err(|e| e.to_string())
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
    let model = &shipped_model().unwrap();
    assert_eq!(model.max_shift, 5);
    assert_eq!(model.shifts(), 121);
    assert_eq!((model.fps, model.min_len, model.max_len), (30.0, 20, 100));
    for f in &model.factors {
        assert_eq!(f.nets.len(), 121);
        assert!(f.components > 0 && f.components <= f.selected.len());
        // on segments held out from every choice, well below chance (a random net's 3-class error under the
        // paper's rule is about 0.67; measured 0.09-0.35 when the 630-feature family was trained, Space the worst)
        let test = f.test_error.expect("the shipped family reports its held-out error");
        assert!(test < 0.4, "a factor's test error is {test}");
        assert_differ(f);
    }
}

/// The 121 classifiers of a factor are networks of their own: none equals the unshifted one, and a typical one
/// differs from it by most of its weights' size (a fine-tuned copy differed by 2-12 %).
fn assert_differ(f: &mocapseg::methods::lma::classifier::FactorModel) {
    let weights = |n: &mocapseg::methods::lma::network::Net| -> Vec<f32> {
        n.w1.iter().chain(&n.b1).chain(&n.w2).chain(&n.b2).copied().collect()
    };
    let central = weights(&f.nets[f.nets.len() / 2]);
    let norm = central.iter().map(|v| v * v).sum::<f32>().sqrt();
    let mut differences: Vec<f32> = Vec::new();
    for (k, net) in f.nets.iter().enumerate().filter(|(k, _)| *k != f.nets.len() / 2) {
        let w = weights(net);
        assert!(w != central, "classifier {k} is the unshifted network");
        if w.len() == central.len() {
            differences.push(w.iter().zip(&central).map(|(a, b)| (a - b).powi(2)).sum::<f32>().sqrt() / norm);
        }
    }
    differences.sort_by(f32::total_cmp);
    let median = differences.get(differences.len() / 2).copied().unwrap_or(f32::INFINITY);
    assert!(median > 0.3, "the shifted networks differ from the unshifted one by a median {median}");
}

#[test]
fn the_batched_exhaustive_map_equals_the_classifiers_one_candidate_at_a_time() {
    let model = &shipped_model().unwrap();
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
    // and the pruned search's shared projections score a candidate as the family does, one at a time
    for &(s, e, x) in b.iter().step_by(97) {
        let direct = model.assess(&pool, s, e).0;
        assert!((x - direct).abs() < 1e-5, "{s}..={e}: pruned {x}, assessed alone {direct}");
    }
    for ((s, e, x), (s2, e2, y)) in a.into_iter().zip(b) {
        assert_eq!((s, e), (s2, e2));
        assert!((x - y).abs() < 1e-4, "{s}..={e}: batched {x}, direct {y}");
    }
}

#[test]
fn both_searches_segment_a_take_into_gestures_with_their_effort() {
    let model = &shipped_model().unwrap();
    let m = motion("131_01.bvh", WALK);
    for (search, exhaustive) in [("effort", false), ("effort", true), ("deviance", false), ("deviance", true)] {
        let params = LmaParams { exhaustive, search: search.into(), ..LmaParams::default() };
        let out =
            segment_with(model, &m, &params, &RunOptions { pictures: true, ..RunOptions::default() }, &mut NoProgress)
                .unwrap();
        let seg = &out.segmentation;
        seg.validate().unwrap();
        assert_eq!(seg.method, "lma");
        assert_eq!((&seg.params["exhaustive"], &seg.params["search"]), (&exhaustive.into(), &search.into()));
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
        let curves: Vec<&str> = out.details.curves.iter().map(|c| c.id.as_str()).collect();
        if search == "deviance" {
            assert_eq!((&ids[..], &curves[..]), (&["deviance-left", "deviance-right", "effort"][..], &[][..]));
        } else {
            // the Effort search draws no map (it assesses no candidate segment), but its Effort change along the take
            assert_eq!((&ids[..], &curves[..]), (&["effort-change", "effort"][..], &["effort-change"][..]));
            let curve = &out.details.curves[0].values;
            assert!(curve.len() == m.frames() && curve.iter().any(|&v| v > 0.0) && curve.iter().all(|v| v.is_finite()));
        }
        for p in &out.details.pictures {
            assert_eq!(p.rgba.len(), p.width * p.height * 4);
            // both searches fill their maps (the pruned one at every hand-speed minimum of both hands)
            let distinct: std::collections::HashSet<&[u8]> = p.rgba.chunks(4).collect();
            assert!(distinct.len() > 3, "{} is nearly blank (exhaustive {exhaustive})", p.id);
        }
        assert!(!seg.segments.is_empty(), "{search}, exhaustive {exhaustive}: nothing found in {} s", m.duration_s());
    }
}

/// Boundaries of `found` within `tolerance` frames of one of `truth`'s (each matched once), over `truth`.
fn recall(found: &[usize], truth: &[usize], tolerance: usize) -> f64 {
    let mut used = vec![false; found.len()];
    let hit = truth
        .iter()
        .filter(|&&t| {
            let k = (0..found.len())
                .filter(|&k| !used[k] && found[k].abs_diff(t) <= tolerance)
                .min_by_key(|&k| found[k].abs_diff(t));
            k.map(|k| used[k] = true).is_some()
        })
        .count();
    hit as f64 / truth.len().max(1) as f64
}

/// A walk, a run and another walk (02_01, 35_01, 02_02), each one labelled segment: what the planted-boundary tests
/// splice (with moving seams, so the boundaries are known).
fn walk_run_takes() -> Vec<(&'static str, bvh::Bvh, mocapseg::segment::truth::Truth)> {
    use mocapseg::segment::truth::{Truth, TruthSegment};
    let texts = [
        ("02_01", include_str!("fixtures/02_01.bvh")),
        ("35_01", OTHER),
        ("02_02", include_str!("fixtures/02_02.bvh")),
    ];
    texts
        .iter()
        .map(|&(name, text)| {
            let b = bvh::parse(text).unwrap();
            let frames = b.frames();
            let segments = vec![TruthSegment { start: 0, end: frames - 1, label: name.to_string(), end_window: None }];
            (name, b, Truth { trial: name.to_string(), frames, segments })
        })
        .collect()
}

/// The boundaries of `segments` as `eval` reads gestures as given: where a segment starts and the frame after one ends.
fn boundaries_of(segments: &[mocapseg::segment::Segment], frames: usize) -> Vec<usize> {
    let mut bounds: Vec<usize> =
        segments.iter().flat_map(|s| [s.start, s.end + 1]).filter(|&b| b > 0 && b < frames).collect();
    bounds.sort_unstable();
    bounds.dedup();
    bounds
}

/// Boundary F1 of `found` against `truth` within `tolerance` frames, each matched once.
fn boundary_f1(found: &[usize], truth: &[usize], tolerance: usize) -> f64 {
    let (r, p) = (recall(found, truth, tolerance), recall(truth, found, tolerance));
    if p + r > 0.0 {
        2.0 * p * r / (p + r)
    } else {
        0.0
    }
}

/// Better than chance, precision counted (issue 50: on one splice random boundaries reach a recall of 0.74–0.82, so
/// recall alone could not fail): on five splices of walks and runs (seeds 2–6, 14 pieces each) both searches' mean
/// boundary F1 at 0.5 s lies above the 95th percentile of the mean F1 of as many boundaries drawn at random on each
/// splice (400 draws). Measured with the shipped family: pruned 0.55, exhaustive 0.51, against random medians 0.42 /
/// 0.41 and 95th percentiles 0.48 / 0.44 (printed with `--nocapture`; on the one splice of the test below alone the
/// pruned search's 0.56 was at random's 95th percentile, 0.56 — one splice cannot tell).
#[test]
fn the_searches_find_planted_boundaries_better_than_random_ones() {
    use mocapseg::splice::{splice, Source, SpliceOptions};
    let takes = walk_run_takes();
    let sources: Vec<Source> = takes.iter().map(|(name, b, t)| Source { name, bvh: b, truth: t }).collect();
    let model = &shipped_model().unwrap();
    const DRAWS: usize = 400;
    for exhaustive in [false, true] {
        let params = LmaParams { exhaustive, ..LmaParams::default() };
        let (mut got, mut random) = (Vec::new(), vec![0.0; DRAWS]);
        let mut rng = mocapseg::stats::Rng::new(50);
        let seeds = 2..=6;
        for seed in seeds.clone() {
            let spliced = splice(&sources, &SpliceOptions { pieces: 14, seed, ..Default::default() }).unwrap();
            let m = Motion::from_bvh("planted", &spliced.bvh).unwrap();
            let planted: Vec<usize> = spliced.pieces[1..].iter().map(|p| p.start).collect();
            let out = segment_with(model, &m, &params, &RunOptions::default(), &mut NoProgress).unwrap();
            let bounds = boundaries_of(&out.segmentation.segments, m.frames());
            let tolerance = (0.5 * m.fps) as usize;
            got.push(boundary_f1(&bounds, &planted, tolerance));
            for r in random.iter_mut() {
                let mut b: Vec<usize> = (0..bounds.len()).map(|_| rng.below(m.frames())).collect();
                b.sort_unstable();
                b.dedup();
                *r += boundary_f1(&b, &planted, tolerance) / seeds.clone().count() as f64;
            }
        }
        random.sort_by(f64::total_cmp);
        let mean = got.iter().sum::<f64>() / got.len() as f64;
        let (median, p95) = (random[DRAWS / 2], random[DRAWS * 95 / 100]);
        eprintln!(
            "exhaustive {exhaustive}: boundary F1 {mean:.2} (per splice {got:.2?}); random: median {median:.2}, 95th \
             percentile {p95:.2}"
        );
        assert!(mean > p95, "exhaustive {exhaustive}: F1 {mean:.2} is within chance's (95th percentile {p95:.2})");
    }
}

#[test]
fn pruned_and_exhaustive_find_the_planted_boundaries() {
    // pieces of a walk, a run and another walk spliced with moving seams: the planted boundaries are known
    use mocapseg::splice::{splice, Source, SpliceOptions};
    let takes = walk_run_takes();
    let sources: Vec<Source> = takes.iter().map(|(name, b, t)| Source { name, bvh: b, truth: t }).collect();
    let spliced = splice(&sources, &SpliceOptions { pieces: 14, seed: 2, ..Default::default() }).unwrap();
    let m = Motion::from_bvh("planted", &spliced.bvh).unwrap();
    let planted: Vec<usize> = spliced.pieces[1..].iter().map(|p| p.start).collect();
    let model = &shipped_model().unwrap();
    let mut found = Vec::new();
    for exhaustive in [false, true] {
        let params = LmaParams { exhaustive, ..LmaParams::default() };
        let out = segment_with(model, &m, &params, &RunOptions::default(), &mut NoProgress).unwrap();
        let mut bounds: Vec<usize> = out.segmentation.segments.iter().flat_map(|s| [s.start, s.end]).collect();
        bounds.sort_unstable();
        bounds.dedup();
        // measured: 13 of 13 planted boundaries within 0.5 s both ways, 18 (pruned) and 23 (exhaustive) segments
        let r = recall(&bounds, &planted, (0.5 * m.fps) as usize);
        let n = out.segmentation.segments.len();
        assert!(r >= 0.8, "exhaustive {exhaustive}: {r:.2} of the {} planted boundaries found", planted.len());
        assert!(
            n <= 2 * spliced.pieces.len(),
            "exhaustive {exhaustive}: {n} segments for {} pieces",
            spliced.pieces.len()
        );
        found.push(bounds);
    }
    // pruning (hand-speed minima only) keeps most of what every frame finds (measured 0.78)
    let agree = recall(&found[0], &found[1], (0.5 * m.fps) as usize);
    assert!(agree >= 0.65, "pruned finds {agree:.2} of the exhaustive search's boundaries");
}

#[test]
fn the_pruned_search_finds_gestures_in_boxing() {
    let model = &shipped_model().unwrap();
    let m = motion("boxing.bvh", BOXING);
    let out = segment_with(model, &m, &LmaParams::default(), &RunOptions::default(), &mut NoProgress).unwrap();
    out.segmentation.validate().unwrap();
    assert!(!out.segmentation.segments.is_empty(), "{}", out.details.summary);
    assert!(out.details.summary.contains("Effort search (pruned)"), "{}", out.details.summary);
}

#[test]
fn a_take_shorter_than_the_shortest_segment_gives_none() {
    let model = &shipped_model().unwrap();
    // 60 frames at 120 Hz: half a second
    let m = motion("short.bvh", &truncated(WALK, 60));
    for exhaustive in [false, true] {
        let params = LmaParams { exhaustive, ..LmaParams::default() };
        let out =
            segment_with(model, &m, &params, &RunOptions { pictures: true, ..RunOptions::default() }, &mut NoProgress)
                .unwrap();
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
    for f in &a.factors {
        assert_differ(f);
    }
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
    // the labels are what is learnt: the same segments with indulging and condensing swapped give a family
    // whose Effort on them agrees less with these labels
    let swap = |e: Element| match e {
        Element::Indulging => Element::Condensing,
        Element::Condensing => Element::Indulging,
        Element::Neutral => Element::Neutral,
    };
    let swapped: Vec<_> = rows.iter().map(|r| EffortLabel { classes: r.classes.map(swap), ..r.clone() }).collect();
    let theirs = quick(&Corpus::from_labels(&refs, &swapped, CorpusConfig::default()).unwrap(), 1);
    let agreement = |family: &mocapseg::methods::lma::classifier::EffortModel| {
        let mut agree = 0;
        for x in &corpus.samples {
            let (_, mean) = family.assess(&corpus.sources[x.source].pool, x.start, x.end);
            let e = effort(&mean);
            for (f, v) in [e.space, e.time, e.weight, e.flow].into_iter().enumerate() {
                agree += usize::from((x.classes[f] == 2 && v > 0.0) || (x.classes[f] == 0 && v < 0.0));
            }
        }
        agree
    };
    let (ours, swapped_agree) = (agreement(&mine), agreement(&theirs));
    assert!(ours > swapped_agree + 4, "agreement with the labels: {ours} learnt from them, {swapped_agree} swapped");
    // a row naming a take that is not loaded is refused with its line
    let stray = parse_labels(
        "file,start_frame,end_frame,space,time,weight,flow\nnope.bvh,0,50,neutral,neutral,neutral,neutral\n",
        "mine.csv",
    )
    .unwrap();
    let err = Corpus::from_labels(&refs, &stray, CorpusConfig::default()).err().unwrap();
    assert!(err.contains("line 2") && err.contains("nope.bvh"), "{err}");
}

/// Stand-in labels are terciles of descriptors computed from the hand's trajectory; the features that tell them (the
/// defining one and its near-duplicates, rank correlation >= `told`) are not the networks' to read, and the report
/// says which were left out. With `told` = 1 nothing is left out and the defining feature is learnt from.
#[test]
fn the_features_that_tell_a_stand_in_label_are_left_out() {
    let takes = [motion("131_01.bvh", WALK), motion("35_01.bvh", OTHER)];
    let refs: Vec<&Motion> = takes.iter().collect();
    let corpus = Corpus::from_descriptors(&refs, CorpusConfig::default()).unwrap();
    assert_eq!(corpus.descriptors.len(), corpus.samples.len());
    let options = TrainOptions { max_epochs: 30, learning_rate: 0.02, weight_decay: 1e-4, patience: 10 };
    let config = TrainConfig {
        restarts: 1,
        saliency_rounds: 4,
        options,
        shift_options: TrainOptions { max_epochs: 2, ..options },
        ..TrainConfig::default()
    };
    let (model, reports) = train_family(&corpus, &config, &mut |_, _| Ok(())).unwrap();
    let index = |name: &str| (0..mocapseg::methods::lma::features::POOL_SIZE).find(|&k| Pool::name(k) == name).unwrap();
    // Time is the tercile of the hand's peak acceleration, Weight of its peak kinetic energy (speed), Flow of its mean jerk
    for (f, defining) in [(1, "hand acceleration, max"), (2, "hand speed, max"), (3, "hand jerk, mean")] {
        let r = &reports[f];
        assert!(r.told.iter().any(|(n, rho)| n == defining && *rho > 0.99), "{:?}: {:?}", r.factor, r.told);
        for (name, rho) in &r.told {
            assert!(rho.abs() >= config.told, "{name}: {rho}");
            assert!(!model.factors[f].selected.contains(&(index(name) as u16)), "{name} is read by {:?}", r.factor);
        }
        // the test confusion counts every held-out segment once
        let counted: usize = r.confusion.iter().flatten().sum();
        assert_eq!(counted, r.split[2].iter().sum::<usize>());
    }
    // Space (directness) has no near-duplicate in the pool; with told = 1 nothing is left out
    let (_, all) = train_family(&corpus, &TrainConfig { told: 1.0, ..config }, &mut |_, _| Ok(())).unwrap();
    assert!(all.iter().all(|r| r.told.is_empty()));
    // a user's labels are not descriptors: nothing is left out of them either
    let rows = parse_labels(
        &(0..12)
            .map(|k| format!("35_01,{},{},neutral,condensing,indulging,neutral\n", 20 * k, 20 * k + 80))
            .fold("file,start_frame,end_frame,space,time,weight,flow\n".to_string(), |a, b| a + &b),
        "mine.csv",
    )
    .unwrap();
    let mine = Corpus::from_labels(&refs, &rows, CorpusConfig::default()).unwrap();
    assert!(mine.descriptors.is_empty());
}
