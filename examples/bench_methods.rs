//! Lab tool, not part of the product: the native half of `make bench`'s one table. Measures
//! parse (MB/s) and forward kinematics (frames/s) on a take, every registered method with its
//! default parameters on 1×, 2×, 4× and 16× a CMU take (with the stages the median run reported:
//! where its time goes), and the batch rate (takes/s of `mocapseg segment --out` on all cores),
//! and appends one JSON line per measurement to a
//! results file that `bench_table` reads beside the wasm side's (`tests/wasm_bench.rs`, the
//! `methods_table` test, prints the same records).
//!
//! "1× a CMU take" is the first 1145 frames of the 30 Hz benchmark sequence (written by
//! `bench_sssm --write-bvh`): CMU 86_01 at 30 Hz exactly, when the shared data is present; 2× and
//! 4× carry on into the next takes of the sequence (13_29, 14_14, …), so the longer inputs are
//! distinct material, not copies; 16× (10.2 minutes at 30 Hz) repeats the sequence.
//!
//! ```text
//! cargo run --release --example bench_methods -- --parse TAKE.bvh --sequence SEQ.bvh \
//!     [--batch DATA_DIR --cli target/release/mocapseg] [--reps 5] --out results-native.jsonl
//! ```

#[cfg(target_arch = "wasm32")]
fn main() {}

#[cfg(not(target_arch = "wasm32"))]
#[allow(dead_code)] // each example uses part of it
mod common;

#[cfg(not(target_arch = "wasm32"))]
fn main() -> std::process::ExitCode {
    use clap::Parser;
    common::exit(lab::run(lab::Args::parse()))
}

#[cfg(not(target_arch = "wasm32"))]
mod lab {
    use std::io::Write;
    use std::path::PathBuf;
    use std::time::Instant;

    use mocapseg::bvh;
    use mocapseg::method::{Progress, RunOptions, Stages};
    use mocapseg::motion::{fk, Motion};
    use serde_json::json;

    /// Frames of "1× a CMU take" (CMU 86_01: 4579 frames at 120 Hz = 1145 at 30 Hz).
    pub const TAKE_FRAMES: usize = 1145;
    /// The lengths measured, in takes: 1×, 2×, 4× (distinct material) and 16× (18,320 frames at 30 Hz,
    /// 10.2 minutes: the sequence repeated, the long take of issue 46).
    const FACTORS: [usize; 4] = [1, 2, 4, 16];

    #[derive(clap::Parser)]
    #[command(about = "Native half of make bench's table: parse, FK, every method at 1×/2×/4×/16× a take, batch")]
    pub struct Args {
        /// The take whose parse and forward kinematics are timed (CMU 86_01 in make bench).
        #[arg(long)]
        pub parse: PathBuf,
        /// The 30 Hz benchmark sequence (`bench_sssm --write-bvh`).
        #[arg(long)]
        pub sequence: PathBuf,
        /// Folder of takes for the batch rate (the shared data); no batch row without it.
        #[arg(long)]
        pub batch: Option<PathBuf>,
        /// The mocapseg binary the batch runs (release build).
        #[arg(long, default_value = "target/release/mocapseg")]
        pub cli: PathBuf,
        /// Timed runs per measurement (after one warm-up); the median is reported. Methods that take
        /// more than a second per run get 3.
        #[arg(long, default_value_t = 5)]
        pub reps: usize,
        /// Only these methods (comma-separated; default every registered one).
        #[arg(long)]
        pub methods: Option<String>,
        /// The JSON-lines file the results are written to (replaced).
        #[arg(long)]
        pub out: PathBuf,
    }

    fn median(mut v: Vec<f64>) -> f64 {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    }

    /// One warm-up, then `reps` timed runs (3 when the warm-up took over a second); median ms.
    fn time_ms(reps: usize, mut work: impl FnMut() -> Result<(), String>) -> Result<(f64, usize), String> {
        let t0 = Instant::now();
        work()?;
        let reps = if t0.elapsed().as_secs_f64() > 1.0 { reps.min(3) } else { reps }.max(1);
        let mut times = Vec::with_capacity(reps);
        for _ in 0..reps {
            let t0 = Instant::now();
            work()?;
            times.push(t0.elapsed().as_secs_f64() * 1e3);
        }
        Ok((median(times), reps))
    }

    /// A method's runs: one warm-up, then `reps` timed runs (3 when the warm-up took over a second),
    /// each profiled by the stages it reports; the median run's time and stages, and `work`'s count
    /// (segments).
    fn time_stages(
        reps: usize,
        mut work: impl FnMut(&mut dyn Progress) -> Result<usize, String>,
    ) -> Result<(f64, usize, Vec<(String, f64)>, usize), String> {
        let mut profiled = || -> Result<(f64, Vec<(String, f64)>, usize), String> {
            let clock = Instant::now();
            let mut stages = Stages::new(|| clock.elapsed().as_secs_f64() * 1e3);
            let count = work(&mut stages)?;
            let ms = stages.elapsed_ms();
            Ok((ms, stages.durations(ms), count))
        };
        let (warm_up, _, _) = profiled()?;
        let reps = if warm_up > 1000.0 { reps.min(3) } else { reps }.max(1);
        let mut runs = (0..reps).map(|_| profiled()).collect::<Result<Vec<_>, _>>()?;
        runs.sort_by(|x, y| x.0.total_cmp(&y.0));
        let (ms, stages, count) = runs.swap_remove(runs.len() / 2);
        Ok((ms, reps, stages, count))
    }

    pub fn run(a: Args) -> Result<(), String> {
        if let Some(dir) = a.out.parent() {
            std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        }
        let mut out = std::fs::File::create(&a.out).map_err(|e| format!("{}: {e}", a.out.display()))?;
        let mut emit = |v: serde_json::Value| -> Result<(), String> {
            println!("  {v}");
            writeln!(out, "{v}").map_err(|e| format!("{}: {e}", a.out.display()))
        };

        // parse and forward kinematics
        let text = std::fs::read_to_string(&a.parse).map_err(|e| format!("{}: {e}", a.parse.display()))?;
        let parsed = bvh::parse(&text).map_err(|e| format!("{}: {e}", a.parse.display()))?;
        let frames = parsed.frames();
        let name = a.parse.file_name().unwrap_or_default().to_string_lossy().to_string();
        println!(
            "bench methods native: parse + FK on {} ({:.2} MB, {frames} frames)",
            a.parse.display(),
            text.len() as f64 / 1e6
        );
        let (ms, runs) = time_ms(a.reps.max(7), || {
            std::hint::black_box(bvh::parse(&text).map_err(|e| e.to_string())?);
            Ok(())
        })?;
        emit(
            json!({"side": "native", "what": "parse", "input": name, "bytes": text.len(), "frames": frames, "ms": ms, "runs": runs}),
        )?;
        let (ms, runs) = time_ms(a.reps.max(7), || {
            std::hint::black_box(fk::forward_kinematics(&parsed).map_err(|e| e.to_string())?);
            Ok(())
        })?;
        emit(
            json!({"side": "native", "what": "fk", "input": name, "bytes": text.len(), "frames": frames, "ms": ms, "runs": runs}),
        )?;

        // every registered method at 1×, 2×, 4×, 16× a take
        let seq_text = std::fs::read_to_string(&a.sequence).map_err(|e| format!("{}: {e}", a.sequence.display()))?;
        let seq_bvh = bvh::parse(&seq_text).map_err(|e| format!("{}: {e}", a.sequence.display()))?;
        let full = Motion::from_bvh("bench sequence", &seq_bvh).map_err(|e| e.to_string())?;
        if full.frames() < 4 * TAKE_FRAMES {
            return Err(format!("{}: {} frames, fewer than 4 × {TAKE_FRAMES}", a.sequence.display(), full.frames()));
        }
        let only: Option<Vec<String>> =
            a.methods.as_ref().map(|m| m.split(',').map(|s| s.trim().to_string()).collect());
        println!(
            "bench methods native: every method, default parameters, on 1×, 2×, 4×, 16× {TAKE_FRAMES} frames @30 Hz of {}",
            a.sequence.display()
        );
        for m in mocapseg::methods::registry() {
            let info = m.info();
            if only.as_ref().is_some_and(|o| !o.contains(&info.name)) {
                continue;
            }
            let checked = m.check_json(&serde_json::Value::Null).map_err(|e| format!("{}: {e}", info.name))?;
            for factor in FACTORS {
                let n = factor * TAKE_FRAMES;
                let take = Motion::concatenate(std::slice::from_ref(&full), n).map_err(|e| e.to_string())?;
                let (ms, runs, stages, segments) = time_stages(a.reps, |progress| {
                    let o = m
                        .run_checked(&take, &checked, &RunOptions::default(), progress)
                        .map_err(|e| format!("{}: {e}", info.name))?;
                    Ok(o.segmentation.segments.len())
                })?;
                emit(json!({"side": "native", "what": "method", "method": info.name, "factor": factor,
                    "frames": n, "ms": ms, "runs": runs, "segments": segments, "stages": stages}))?;
            }
        }

        // the batch: mocapseg segment over a folder on all cores, wall clock (median of 3)
        match &a.batch {
            Some(dir) if dir.is_dir() => {
                let threads = std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1);
                let mut times = Vec::new();
                let (mut ok, mut failed) = (0, 0);
                for _ in 0..3 {
                    let scratch = std::env::temp_dir().join(format!("mocapseg-bench-batch-{}", std::process::id()));
                    let _ = std::fs::remove_dir_all(&scratch);
                    let t0 = Instant::now();
                    let o = std::process::Command::new(&a.cli)
                        .args(["segment", "--method", "sssm"])
                        .arg(dir)
                        .arg("--out")
                        .arg(&scratch)
                        .output()
                        .map_err(|e| {
                            format!("{}: {e} (build it: cargo build --release --bin mocapseg)", a.cli.display())
                        })?;
                    times.push(t0.elapsed().as_secs_f64());
                    let _ = std::fs::remove_dir_all(&scratch);
                    let stdout = String::from_utf8_lossy(&o.stdout);
                    ok = stdout.lines().filter(|l| l.starts_with("ok ")).count();
                    failed = stdout.lines().filter(|l| l.starts_with("FAIL")).count();
                    if ok == 0 {
                        return Err(format!(
                            "batch over {}: nothing segmented: {}",
                            dir.display(),
                            String::from_utf8_lossy(&o.stderr)
                        ));
                    }
                }
                let s = median(times);
                emit(json!({"side": "native", "what": "batch", "input": dir.display().to_string(), "method": "sssm",
                    "takes": ok, "failed": failed, "threads": threads, "s": s}))?;
            }
            Some(dir) => println!("  note: {} is absent: no batch row", dir.display()),
            None => {}
        }
        println!("bench methods native: results in {}", a.out.display());
        Ok(())
    }
}
