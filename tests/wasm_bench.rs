//! Benchmark: parse + forward-kinematics throughput of the core compiled
//! to wasm32, measured in headless Chromium. Not a timed test: it asserts only that the work
//! succeeded, and prints MB/s and frames/s.
//!
//! Run through `make bench-wasm` (or `make bench`), which sets `MOCAPSEG_BENCH_BVH` to the take
//! to embed (CMU 86_01 when the shared data is there) and passes `--nocapture` so that the
//! runner shows the printed numbers:
//!
//! ```sh
//! MOCAPSEG_BENCH_BVH=/abs/path/take.bvh cargo test --profile web --target wasm32-unknown-unknown \
//!     --test wasm_bench -- --nocapture
//! ```
//!
//! Compiled only for wasm32 (natively this file is empty).
#![cfg(target_arch = "wasm32")]

use mocapseg::bvh;
use mocapseg::motion::{fk, Motion};
use wasm_bindgen::prelude::*;
use wasm_bindgen_test::*;

#[path = "support/models.rs"]
mod models;

wasm_bindgen_test_configure!(run_in_browser);

/// Absolute path of the benchmarked take, fixed at compile time.
const PATH: &str =
    env!("MOCAPSEG_BENCH_BVH", "set MOCAPSEG_BENCH_BVH to the absolute path of a .bvh file (make bench-wasm does)");
const TEXT: &str = include_str!(env!("MOCAPSEG_BENCH_BVH"));

/// Minimum measuring time per benchmark, and the run-count bounds.
const MIN_TOTAL_MS: f64 = 3000.0;
const MIN_RUNS: usize = 3;
const MAX_RUNS: usize = 50;

#[wasm_bindgen]
extern "C" {
    /// `performance.now()`: milliseconds with sub-millisecond resolution (window or worker).
    #[wasm_bindgen(js_namespace = performance, js_name = now)]
    fn performance_now() -> f64;
}

/// Runs `work` once to warm up, then repeatedly (at least `MIN_RUNS` times and `MIN_TOTAL_MS`
/// in total, at most `MAX_RUNS`); returns the median duration of one run in milliseconds.
fn median_ms(mut work: impl FnMut()) -> (f64, usize) {
    work();
    let mut times = Vec::new();
    let started = performance_now();
    while times.len() < MAX_RUNS && (times.len() < MIN_RUNS || performance_now() - started < MIN_TOTAL_MS) {
        let t0 = performance_now();
        work();
        times.push(performance_now() - t0);
    }
    times.sort_by(|a, b| a.total_cmp(b));
    (times[times.len() / 2], times.len())
}

fn report(what: &str, ms: f64, runs: usize, mb: f64, frames: usize) {
    let s = ms / 1000.0;
    console_log!(
        "wasm bench | {what:<28} | {ms:9.1} ms | {:8.1} MB/s | {:10.0} frames/s | median of {runs} runs",
        mb / s,
        frames as f64 / s
    );
}

#[wasm_bindgen_test]
fn parse_and_fk_throughput() {
    let mb = TEXT.len() as f64 / 1e6;
    let bvh = bvh::parse(TEXT).unwrap_or_else(|e| panic!("{PATH}: {e}"));
    let frames = bvh.frames();
    assert!(frames > 0, "{PATH}: no frames");
    console_log!(
        "wasm bench | input {PATH}: {mb:.2} MB, {frames} frames, {} nodes, {:.3} fps",
        bvh.joints.len(),
        bvh.fps()
    );

    let (ms, runs) = median_ms(|| {
        let b = bvh::parse(TEXT).expect("parse");
        assert_eq!(b.frames(), frames);
    });
    report("parse", ms, runs, mb, frames);

    let (ms, runs) = median_ms(|| {
        let positions = fk::forward_kinematics(&bvh).expect("fk");
        assert_eq!(positions.len(), frames * bvh.joints.len());
    });
    report("forward kinematics", ms, runs, mb, frames);

    let (ms, runs) = median_ms(|| {
        let b = bvh::parse(TEXT).expect("parse");
        let m = Motion::from_bvh("bench", &b).expect("motion");
        assert_eq!(m.frames(), frames);
    });
    report("parse + Motion::from_bvh", ms, runs, mb, frames);
}

/// The SSSM benchmark sequence: 12 000 frames at 30 Hz written by
/// `cargo run --release --example bench_sssm -- --write-bvh` (the CMU takes of the shared data one after another; make
/// bench-wasm builds it), so native and wasm time the same frames.
const SSSM_SEQUENCE: &str = include_str!(env!(
    "MOCAPSEG_BENCH_SSSM_BVH",
    "set MOCAPSEG_BENCH_SSSM_BVH to the sequence written by `cargo run --release --example bench_sssm -- --write-bvh` (make bench-wasm does)"
));

/// SSSM end to end (features → clusters) on 1×, 2× and 4× a length (the same
/// frames as `cargo run --example bench_sssm`): 3000 frames with the default parameters (the sequence's
/// 5211 distinct frames repeat from frame 5211 on), the same without the search horizon (the
/// paper's all-pairs SSSM), and 1300 frames (so that 4× is still distinct material).
#[wasm_bindgen_test]
async fn sssm_end_to_end() {
    use mocapseg::methods::sssm::SssmParams;
    let bvh = bvh::parse(SSSM_SEQUENCE).expect("the SSSM bench sequence parses");
    let full = Motion::from_bvh("bench sequence", &bvh).expect("motion");
    assert!((full.fps - 30.0).abs() < 1e-6, "the sequence is at 30 Hz");
    sssm_series(&full, 3000, &SssmParams::default(), "default parameters").await;
    sssm_series(&full, 3000, &SssmParams::default().horizon_s(0.0), "horizon_s 0 (all pairs)").await;
    sssm_series(&full, 1300, &SssmParams::default(), "default parameters, distinct frames").await;
}

/// Lets the browser run its event loop (the test runner talks to the page between runs).
async fn yield_to_browser() {
    let promise = js_sys::Promise::new(&mut |resolve, _| {
        let global = js_sys::global();
        let set_timeout = js_sys::Reflect::get(&global, &"setTimeout".into()).expect("setTimeout");
        let set_timeout: js_sys::Function = set_timeout.into();
        set_timeout.call2(&global, &resolve, &0.into()).expect("setTimeout call");
    });
    wasm_bindgen_futures::JsFuture::from(promise).await.expect("timeout promise");
}

async fn sssm_series(full: &Motion, frames: usize, params: &mocapseg::methods::sssm::SssmParams, what: &str) {
    use mocapseg::methods::sssm::segment_with_progress;
    use mocapseg::segment::Level;
    console_log!("wasm bench | sssm, {what}:");
    let mut base = None;
    for factor in [1usize, 2, 4] {
        let n = frames * factor;
        let seq = Motion::concatenate(std::slice::from_ref(full), n).expect("sequence");
        let mut summary = (0, 0, 0);
        let mut stages = String::new();
        // one warm-up, then SSSM_RUNS timed runs, yielding to the browser between runs
        let mut times = Vec::new();
        for run in 0..=SSSM_RUNS {
            yield_to_browser().await;
            let t0 = performance_now();
            // time between progress reports = the stage just finished
            let mut last = ("start".to_string(), t0);
            let mut these = Vec::new();
            let r = segment_with_progress(&seq, params, &mut |stage, _| {
                // a stage ends when the next one reports (a stage may report many times)
                if stage != last.0 {
                    let now = performance_now();
                    these.push(format!("{} {:.1}", std::mem::replace(&mut last.0, stage.to_string()), now - last.1));
                    last.1 = now;
                }
                Ok(())
            })
            .expect("sssm");
            if run > 0 {
                times.push(performance_now() - t0);
            }
            stages = these[1..].join(", ");
            let seg = &r.segmentation;
            summary = (r.outcome.sssm.entries(), seg.level(Level::Action).count(), seg.level(Level::Primitive).count());
        }
        times.sort_by(|a, b| a.total_cmp(b));
        let ms = times[times.len() / 2];
        assert!(summary.1 > 0 && summary.2 >= summary.1, "the sequence has actions and primitives");
        let growth = base.map(|b: f64| format!(" ({:.2}× the 1× time)", ms / b)).unwrap_or_default();
        base.get_or_insert(ms);
        console_log!(
            "wasm bench | sssm {factor}× {n:6} frames @30 Hz | {ms:9.1} ms{growth} | SSSM entries {} actions {} primitives {} | median of {SSSM_RUNS} runs",
            summary.0,
            summary.1,
            summary.2
        );
        console_log!("wasm bench |   stages (ms, last run): {stages}");
    }
}

/// Timed runs per length of the SSSM benchmark (after one warm-up run).
const SSSM_RUNS: usize = 5;

/// LMA (Bouchard & Badler) on 25, 50 and 100 s of the same sequence at 30 Hz (750, 1500, 3000
/// frames, as `cargo run --release --example bench_lma`): both searches (the default Effort search
/// and the paper's deviance search), pruned (median of 3 runs) and exhaustive (one run each: it is
/// the slow one, and how it grows is the point).
#[wasm_bindgen_test]
async fn lma_end_to_end() {
    use mocapseg::method::{NoProgress, RunOptions};
    use mocapseg::methods::lma::method::{segment_with, LmaParams};
    let store = models::store();
    let model = mocapseg::methods::lma::shipped(&store).expect("the shipped LMA family");
    let bvh = bvh::parse(SSSM_SEQUENCE).expect("the bench sequence parses");
    let full = Motion::from_bvh("bench sequence", &bvh).expect("motion");
    for (search, exhaustive) in [("effort", false), ("effort", true), ("deviance", false), ("deviance", true)] {
        let params = LmaParams { exhaustive, search: search.into(), ..LmaParams::default() };
        let mut base = None;
        for frames in [750usize, 1500, 3000] {
            let seq = Motion::concatenate(std::slice::from_ref(&full), frames).expect("sequence");
            let runs = if exhaustive { 1 } else { 3 };
            let mut times = Vec::new();
            let mut found = 0;
            for _ in 0..runs {
                yield_to_browser().await;
                let t0 = performance_now();
                let out = segment_with(&model, &seq, &params, &RunOptions::default(), &mut NoProgress).expect("lma");
                times.push(performance_now() - t0);
                found = out.segmentation.segments.len();
            }
            times.sort_by(f64::total_cmp);
            let ms = times[times.len() / 2];
            let growth = base.map(|b: f64| format!(" ({:.2}× the 750-frame time)", ms / b)).unwrap_or_default();
            base.get_or_insert(ms);
            console_log!(
                "wasm bench | lma {search:8} {} {:5} frames @30 Hz ({:3.0} s) | {:9.1} ms{growth} | {found} segments | median of {runs}",
                if exhaustive { "exhaustive" } else { "pruned    " },
                frames,
                frames as f64 / 30.0,
                ms
            );
        }
    }
}

/// DT-FCN and k-NN: labelling 3000 frames at 30 Hz of the bench sequence with the shipped
/// `exercises` models (median of 5), and 20 epochs of training on 3682 frames (the exercises
/// set's size) with the shipped models' settings — the same work as `cargo run --release
/// --example bench_dtfcn`.
#[wasm_bindgen_test]
async fn dtfcn_end_to_end() {
    use mocapseg::methods::dtfcn::bench::{inference, trainer, EXERCISE_FRAMES};
    let store = models::store();
    let bvh = bvh::parse(SSSM_SEQUENCE).expect("the bench sequence parses");
    let full = Motion::from_bvh("bench sequence", &bvh).expect("motion");
    let take = Motion::concatenate(std::slice::from_ref(&full), 3000).expect("3000 frames");
    for kind in ["dtfcn", "knn"] {
        let shipped = mocapseg::methods::find(kind).unwrap().supervised().unwrap().shipped_model("exercises", &store);
        let loaded = shipped.expect("the shipped model");
        let model = loaded.model.downcast_ref::<mocapseg::labeller::model::Model>().unwrap();
        inference(&take, model).expect("warm-up");
        let mut times = Vec::new();
        let mut segments = 0;
        for _ in 0..5 {
            yield_to_browser().await;
            let t0 = performance_now();
            segments = inference(&take, model).expect("inference");
            times.push(performance_now() - t0);
        }
        times.sort_by(f64::total_cmp);
        console_log!(
            "wasm bench | {} inference, 3000 frames @30 Hz | {:9.1} ms | {segments} segments | median of 5",
            kind,
            times[2]
        );
    }
    let (mut trainer, _, _) = trainer(&full, 20).expect("trainer");
    let t0 = performance_now();
    while !trainer.done() {
        // one epoch per turn of the event loop, as the page's worker trains
        yield_to_browser().await;
        trainer.epoch().expect("epoch");
    }
    console_log!(
        "wasm bench | dtfcn training, 20 epochs on {EXERCISE_FRAMES} frames @30 Hz | {:9.1} s",
        (performance_now() - t0) / 1000.0
    );
}

/// Frames of "1× a CMU take" in `make bench`'s table (CMU 86_01 at 30 Hz, the first take of the
/// sequence), as `examples/bench_methods.rs` natively.
const TAKE_FRAMES: usize = 1145;

/// Median of `reps` timed runs after one warm-up (3 when the warm-up took over a second), in ms,
/// yielding to the browser before each run.
async fn time_ms(reps: usize, mut work: impl FnMut()) -> (f64, usize) {
    yield_to_browser().await;
    let t0 = performance_now();
    work();
    let reps = if performance_now() - t0 > 1000.0 { reps.min(3) } else { reps };
    let mut times = Vec::new();
    for _ in 0..reps {
        yield_to_browser().await;
        let t0 = performance_now();
        work();
        times.push(performance_now() - t0);
    }
    times.sort_by(f64::total_cmp);
    (times[times.len() / 2], reps)
}

/// A method's runs as `examples/bench_methods.rs` times them natively: one warm-up, then `reps`
/// timed runs (3 when the warm-up took over a second), each profiled by the stages it reports
/// ([`mocapseg::method::Stages`] on `performance.now()`); the median run's time and stages, the
/// runs, and `work`'s count (segments). Yields to the browser before each run.
async fn time_stages(
    reps: usize,
    work: &mut dyn FnMut(&mut dyn mocapseg::method::Progress) -> usize,
) -> (f64, usize, Vec<(String, f64)>, usize) {
    let mut profiled = || {
        let mut stages = mocapseg::method::Stages::new(performance_now);
        let count = work(&mut stages);
        let ms = stages.elapsed_ms();
        (ms, stages.durations(ms), count)
    };
    yield_to_browser().await;
    let (warm_up, _, _) = profiled();
    let reps = if warm_up > 1000.0 { reps.min(3) } else { reps }.max(1);
    let mut runs = Vec::with_capacity(reps);
    for _ in 0..reps {
        yield_to_browser().await;
        runs.push(profiled());
    }
    runs.sort_by(|x, y| x.0.total_cmp(&y.0));
    let (ms, stages, count) = runs.swap_remove(runs.len() / 2);
    (ms, reps, stages, count)
}

/// The wasm half of `make bench`'s one table: parse and forward kinematics of the take, and every
/// registered method with its default parameters on 1×, 2×, 4×, 16× a CMU take (and where each run's time goes) — the same work as
/// `cargo run --release --example bench_methods`, printed as `BENCHJSON {…}` lines that the
/// Makefile collects from the runner's output for `bench_table`. It asserts only that the work
/// succeeded (a method may rightly find no segment in some material: LMA's pruned search often does).
#[wasm_bindgen_test]
async fn methods_table() {
    use mocapseg::method::RunOptions;
    use serde_json::json;
    let emit = |v: serde_json::Value| console_log!("BENCHJSON {v}");
    let name = PATH.rsplit('/').next().unwrap_or(PATH);
    let parsed = bvh::parse(TEXT).expect("the take parses");
    let frames = parsed.frames();
    let (ms, runs) = time_ms(7, || {
        let b = bvh::parse(TEXT).expect("parse");
        assert_eq!(b.frames(), frames);
    })
    .await;
    emit(
        json!({"side": "wasm", "what": "parse", "input": name, "bytes": TEXT.len(), "frames": frames, "ms": ms, "runs": runs}),
    );
    let (ms, runs) = time_ms(7, || {
        let p = fk::forward_kinematics(&parsed).expect("fk");
        assert_eq!(p.len(), frames * parsed.joints.len());
    })
    .await;
    emit(
        json!({"side": "wasm", "what": "fk", "input": name, "bytes": TEXT.len(), "frames": frames, "ms": ms, "runs": runs}),
    );

    let seq = bvh::parse(SSSM_SEQUENCE).expect("the bench sequence parses");
    let full = Motion::from_bvh("bench sequence", &seq).expect("motion");
    assert!(full.frames() >= 4 * TAKE_FRAMES, "the sequence holds 4 × {TAKE_FRAMES} frames");
    let store = models::store();
    for m in mocapseg::methods::registry() {
        let info = m.info();
        let checked = m.check_json_in(&serde_json::Value::Null, &store).expect("default parameters");
        for factor in [1usize, 2, 4, 16] {
            let n = factor * TAKE_FRAMES;
            let take = Motion::concatenate(std::slice::from_ref(&full), n).expect("sequence");
            let (ms, runs, stages, segments) = time_stages(5, &mut |progress| {
                let o = m.run_checked(&take, &checked, &RunOptions::default(), progress).expect(&info.name);
                o.segmentation.segments.len()
            })
            .await;
            emit(json!({"side": "wasm", "what": "method", "method": info.name, "factor": factor,
                "frames": n, "ms": ms, "runs": runs, "segments": segments, "stages": stages}));
        }
    }
}
