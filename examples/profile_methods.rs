//! Lab tool, not part of the product: where each method's time goes on a take of a given length —
//! issue 46's "measure before changing". Every registered method, with its default parameters and
//! the pictures the page asks for, on a 40 s and a 10-minute take at 120 fps (CMU takes of the
//! shared data laid end to end: 86_01, 13_29, 13_30, 13_31, 14_14, then again from the first, so
//! that the first 40 s are 86_01 alone and the 10 minutes hold every take about twice); for each,
//! the median of `--reps` runs after a warm-up, and the run's stages as the method reports them
//! (the time between one progress report and the next, named by the first), so that the stage that
//! dominates is in the table, not guessed. The loading of the take (parse, forward kinematics)
//! is timed once per length too.
//!
//! ```text
//! cargo run --release --example profile_methods -- [--data ../shared/data] [--seconds 40,600] [--reps 3] \
//!     [--methods knn,dtfcn] [--stages 0.05] [--out results.jsonl]
//! ```
//!
//! Without the shared data it says so and stops (the takes are too long for the fixtures).

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

    use mocapseg::method::{RunOptions, Stages};
    use mocapseg::motion::Motion;
    use serde_json::json;

    /// The takes laid end to end, in this order (each 120 fps, the same 31-joint skeleton).
    const TAKES: [&str; 5] = ["86/86_01", "mocap6/13_29", "mocap6/13_30", "mocap6/13_31", "mocap6/14_14"];
    /// The rate of the CMU takes (frames per second).
    const FPS: f64 = 120.0;

    #[derive(clap::Parser)]
    #[command(about = "Where each method's time goes: every method on a 40 s and a 10-minute take, by stage")]
    pub struct Args {
        /// The shared data (cmu/86, cmu/mocap6).
        #[arg(long, default_value = "../shared/data")]
        pub data: PathBuf,
        /// The lengths of the takes, in seconds (comma-separated).
        #[arg(long, default_value = "40,600")]
        pub seconds: String,
        /// Timed runs per method and length (after one warm-up); the median is reported.
        #[arg(long, default_value_t = 3)]
        pub reps: usize,
        /// Only these methods (comma-separated registry names; default every registered one).
        #[arg(long)]
        pub methods: Option<String>,
        /// Stages shorter than this share of the run are summed into "other stages".
        #[arg(long, default_value_t = 0.03)]
        pub stages: f64,
        /// Also append one JSON line per method and length here.
        #[arg(long)]
        pub out: Option<PathBuf>,
    }

    /// The files' frames laid end to end (cycling) to `frames` rows, written as one BVH file.
    fn long_file(files: &[mocapseg::bvh::Bvh], frames: usize) -> String {
        let mut bvh = files[0].clone();
        let c = bvh.channels_per_frame;
        bvh.values.clear();
        for f in files.iter().cycle() {
            let need = frames * c - bvh.values.len();
            if need == 0 {
                break;
            }
            bvh.values.extend_from_slice(&f.values[..need.min(f.values.len())]);
        }
        bvh.declared_frames = frames;
        mocapseg::bvh::write(&bvh)
    }

    fn median(mut v: Vec<f64>) -> f64 {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    }

    pub fn run(a: Args) -> Result<(), String> {
        if !a.data.join("cmu").is_dir() {
            return Err(format!(
                "{}: the shared data is absent (cmu/86, cmu/mocap6 are needed for the long takes); pass --data DIR",
                a.data.display()
            ));
        }
        let mut out = match &a.out {
            Some(p) => Some(
                std::fs::File::options()
                    .create(true)
                    .append(true)
                    .open(p)
                    .map_err(|e| format!("{}: {e}", p.display()))?,
            ),
            None => None,
        };
        let seconds: Vec<f64> = a
            .seconds
            .split(',')
            .map(|s| s.trim().parse::<f64>().map_err(|e| format!("--seconds {s}: {e}")))
            .collect::<Result<_, _>>()?;
        let mut takes = Vec::new();
        let mut files = Vec::new();
        for t in TAKES {
            let path = a.data.join(format!("cmu/{t}.bvh"));
            let loaded = mocapseg::load::load_path(&path).map_err(|e| format!("{}: {e}", path.display()))?;
            takes.push(loaded.motion);
            files.push(loaded.bvh);
        }
        let only: Option<Vec<String>> =
            a.methods.as_ref().map(|m| m.split(',').map(|s| s.trim().to_string()).collect());
        let options = RunOptions { pictures: true, ..RunOptions::default() };
        println!("profile_methods: every method with its default parameters and pictures, median of {} runs", a.reps);
        for &s in &seconds {
            let frames = (s * FPS).round() as usize;
            let take: Motion = Motion::concatenate(&takes, frames).map_err(|e| e.to_string())?;
            // the loading as the page does it: the take written as BVH, parsed, forward kinematics
            let text = long_file(&files, frames);
            let t0 = Instant::now();
            let loaded =
                mocapseg::load::load_bytes("profile.bvh", text.as_bytes(), &mut |_| {}).map_err(|e| e.to_string())?;
            let load_ms = t0.elapsed().as_secs_f64() * 1e3;
            println!(
                "\n## {s} s: {frames} frames at {FPS} fps ({:.1} MB as BVH; loading it: {load_ms:.0} ms)",
                text.len() as f64 / 1e6
            );
            drop(loaded);
            for m in mocapseg::methods::registry() {
                let info = m.info();
                if only.as_ref().is_some_and(|o| !o.contains(&info.name)) {
                    continue;
                }
                let checked = m.check_json(&serde_json::Value::Null).map_err(|e| format!("{}: {e}", info.name))?;
                let mut runs: Vec<(f64, Vec<(String, f64)>)> = Vec::new();
                let mut refused = None;
                for rep in 0..=a.reps.max(1) {
                    let clock = Instant::now();
                    let mut stages = Stages::new(|| clock.elapsed().as_secs_f64() * 1e3);
                    let o = match m.run_checked(&take, &checked, &options, &mut stages) {
                        Ok(o) => o,
                        Err(e) => {
                            refused = Some(e.to_string());
                            break;
                        }
                    };
                    let ms = stages.elapsed_ms();
                    std::hint::black_box(o);
                    if rep > 0 {
                        runs.push((ms, stages.durations(ms)));
                    }
                }
                if let Some(why) = refused {
                    println!("{:<9} refused: {why}", info.name);
                    if let Some(f) = out.as_mut() {
                        let v = json!({"side": "native", "what": "profile", "method": info.name, "seconds": s,
                            "frames": frames, "refused": why});
                        writeln!(f, "{v}").map_err(|e| e.to_string())?;
                    }
                    continue;
                }
                runs.sort_by(|x, y| x.0.total_cmp(&y.0));
                let (ms, stages) = runs[runs.len() / 2].clone();
                let all: Vec<f64> = runs.iter().map(|r| r.0).collect();
                println!(
                    "{:<9} {:>8.1} ms   (runs {})",
                    info.name,
                    median(all.clone()),
                    all.iter().map(|t| format!("{t:.0}")).collect::<Vec<_>>().join(" ")
                );
                let mut other = 0.0;
                for (stage, t) in &stages {
                    if *t >= a.stages * ms {
                        println!("            {:>7.1} ms {:>4.0} %  {stage}", t, 100.0 * t / ms);
                    } else {
                        other += t;
                    }
                }
                if other > 0.0 {
                    println!("            {:>7.1} ms {:>4.0} %  (other stages)", other, 100.0 * other / ms);
                }
                if let Some(f) = out.as_mut() {
                    let v = json!({"side": "native", "what": "profile", "method": info.name, "seconds": s,
                        "frames": frames, "ms": ms, "runs": all, "stages": stages});
                    writeln!(f, "{v}").map_err(|e| e.to_string())?;
                }
            }
        }
        Ok(())
    }
}
