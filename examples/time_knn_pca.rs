//! Lab tool, not part of the product: times the k-NN labeller (`knn`) and the PCA baseline (`pca`)
//! on long takes made of the mocap6 and 86_01 CMU takes (all 120 fps, one skeleton) cycled to a
//! given length — 4794 frames = 40 s, 72000 frames = 10 min — and can write each run's whole
//! output (segments, curves, summary, take fit, a hash of every picture) to a folder, so that a
//! speed change can be checked to leave the output as it was (`diff -r` two folders).
//!
//! ```text
//! cargo run --release --example time_knn_pca -- [--frames 4794,72000] [--methods knn,pca]
//!     [--knn-models exercises,cmu-actions,locomotion] [--reps 3] [--pictures] [--dump DIR]
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
    use std::path::PathBuf;
    use std::time::Instant;

    use mocapseg::method::{NoProgress, RunOptions};
    use mocapseg::motion::Motion;
    use sha2::{Digest, Sha256};

    #[derive(clap::Parser)]
    #[command(about = "Times knn and pca on long CMU takes; optionally writes their outputs for comparison")]
    pub struct Args {
        /// The shared data folder (cmu/mocap6, cmu/86).
        #[arg(long, default_value = "/work/shared/data")]
        pub data: PathBuf,
        /// Take lengths in 120 fps frames, comma-separated.
        #[arg(long, default_value = "4794,72000")]
        pub frames: String,
        /// Methods, comma-separated (knn, pca).
        #[arg(long, default_value = "knn,pca")]
        pub methods: String,
        /// The k-NN's shipped models to run, comma-separated.
        #[arg(long, default_value = "exercises")]
        pub knn_models: String,
        /// Timed runs per measurement (the median is printed).
        #[arg(long, default_value_t = 3)]
        pub reps: usize,
        /// Draw the pictures, as the page does.
        #[arg(long)]
        pub pictures: bool,
        /// Write every run's output here (one JSON file per method, model and length).
        #[arg(long)]
        pub dump: Option<PathBuf>,
    }

    pub fn run(a: Args) -> Result<(), String> {
        let mut takes = Vec::new();
        for t in ["13_29", "13_30", "13_31", "14_14"] {
            takes.push(a.data.join(format!("cmu/mocap6/{t}.bvh")));
        }
        takes.push(a.data.join("cmu/86/86_01.bvh"));
        let motions: Vec<Motion> = takes
            .iter()
            .map(|p| mocapseg::load::load_path(p).map(|l| l.motion).map_err(|e| format!("{}: {e}", p.display())))
            .collect::<Result<_, _>>()?;
        if let Some(dir) = &a.dump {
            std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        }
        let options = RunOptions { pictures: a.pictures, ..RunOptions::default() };
        for frames in a.frames.split(',').map(|s| s.trim().parse::<usize>().map_err(|e| format!("{s}: {e}"))) {
            let frames = frames?;
            let take = Motion::concatenate(&motions, frames).map_err(|e| e.to_string())?;
            for method in a.methods.split(',').map(str::trim) {
                let m = mocapseg::methods::find(method).map_err(|e| e.to_string())?;
                let models: Vec<Option<&str>> = if method == "knn" || method == "dtfcn" {
                    a.knn_models.split(',').map(|s| Some(s.trim())).collect()
                } else {
                    vec![None]
                };
                for model in models {
                    let params = model.map_or(serde_json::Value::Null, |m| serde_json::json!({ "model": m }));
                    let checked = m.check_json(&params).map_err(|e| format!("{method}: {e}"))?;
                    let mut times = Vec::new();
                    let mut last = None;
                    for _ in 0..a.reps.max(1) {
                        let t0 = Instant::now();
                        let o = m
                            .run_checked(&take, &checked, &options, &mut NoProgress)
                            .map_err(|e| format!("{method}: {e}"))?;
                        times.push(t0.elapsed().as_secs_f64() * 1e3);
                        last = Some(o);
                    }
                    let mut sorted = times.clone();
                    sorted.sort_by(f64::total_cmp);
                    let o = last.expect("at least one run");
                    println!(
                        "{method}{} {frames} frames: median {:.1} ms of {:?} · {} segments",
                        model.map_or(String::new(), |m| format!(" ({m})")),
                        sorted[sorted.len() / 2],
                        times.iter().map(|t| (t * 10.0).round() / 10.0).collect::<Vec<_>>(),
                        o.segmentation.segments.len()
                    );
                    if let Some(dir) = &a.dump {
                        let pictures: Vec<serde_json::Value> = o
                            .details
                            .pictures
                            .iter()
                            .map(|p| {
                                let hash: String = Sha256::digest(&p.rgba).iter().map(|b| format!("{b:02x}")).collect();
                                serde_json::json!({"id": p.id, "width": p.width, "height": p.height,
                                    "caption": p.caption, "sha256": hash})
                            })
                            .collect();
                        let out = serde_json::json!({
                            "segmentation": o.segmentation,
                            "summary": o.details.summary,
                            "curves": o.details.curves,
                            "take_fit": o.details.take_fit,
                            "pictures": pictures,
                        });
                        let file = dir.join(format!("{method}-{}-{frames}.json", model.unwrap_or("default")));
                        let text = serde_json::to_string_pretty(&out).map_err(|e| e.to_string())?;
                        std::fs::write(&file, text).map_err(|e| format!("{}: {e}", file.display()))?;
                    }
                }
            }
        }
        Ok(())
    }
}
