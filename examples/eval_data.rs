//! Lab tool, not part of the product: segments the labelled takes of the shared data folder
//! (CMU 86_01 with Barbič/Zhou labels, the four mocap6 takes with Fox/Hughes labels, then the
//! mocap6 takes joined into one 2-minute take) with any registered method and prints the scores
//! as one table with their mean. Says so and fails when the folder is absent.
//!
//! ```text
//! cargo run --release --example eval_data -- [--data ../shared/data] [--method sssm] [--param NAME=VALUE]… [--json]
//! ```

#[cfg(target_arch = "wasm32")]
fn main() {}

#[cfg(not(target_arch = "wasm32"))]
fn main() -> std::process::ExitCode {
    use clap::Parser;
    match lab::eval_data(lab::Args::parse()) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            std::process::ExitCode::FAILURE
        }
    }
}

#[cfg(not(target_arch = "wasm32"))]
mod lab {
    use std::path::{Path, PathBuf};
    use std::time::Instant;

    use mocapseg::load::load_path;
    use mocapseg::method::{self, NoProgress, RunOptions};
    use mocapseg::motion::Motion;
    use mocapseg::segment::metrics::{evaluate, Tolerances};
    use mocapseg::segment::report::{self, Row};
    use mocapseg::segment::truth::{load_csv, Truth, TruthOptions};
    use mocapseg::segment::Level;

    #[derive(clap::Parser)]
    #[command(about = "Segment and score the labelled takes of the shared data folder")]
    pub struct Args {
        /// The shared data folder (with cmu/ and labels/).
        #[arg(long, default_value = "../shared/data")]
        data: PathBuf,
        #[arg(long, default_value = "sssm")]
        method: String,
        /// Parameter overrides as NAME=VALUE (JSON value); repeatable.
        #[arg(long = "param", value_name = "NAME=VALUE")]
        params: Vec<String>,
        /// Print JSON instead of a markdown table.
        #[arg(long)]
        json: bool,
    }

    /// The labelled takes of the shared data: (BVH path, ground-truth CSV, trial id).
    fn labelled_takes(data: &Path) -> Vec<(PathBuf, PathBuf, &'static str)> {
        let cmu86 = data.join("labels/cmu86_zhou_gt.csv");
        let mocap6 = data.join("labels/mocap6_gt.csv");
        let mut takes = vec![(data.join("cmu/86/86_01.bvh"), cmu86, "86_01")];
        for t in ["13_29", "13_30", "13_31", "14_14"] {
            takes.push((data.join(format!("cmu/mocap6/{t}.bvh")), mocap6.clone(), t));
        }
        takes
    }

    pub fn eval_data(args: Args) -> Result<(), String> {
        let data = &args.data;
        if !data.join("labels").is_dir() {
            return Err(format!(
                "{}: no shared data here (expected labels/ and cmu/ as in ../shared/data); pass --data DIR",
                data.display()
            ));
        }
        let method = method::find(&args.method).map_err(|e| e.to_string())?;
        let params = method::params_from_overrides(method, &args.params).map_err(|e| e.to_string())?;
        let checked = method.check_json(&params).map_err(|e| e.to_string())?;
        let score = |motion: &Motion, truth: &Truth| -> Result<Row, String> {
            let started = Instant::now();
            let output = method
                .run_checked(motion, &checked, &RunOptions::default(), &mut NoProgress)
                .map_err(|e| format!("{}: {e}", motion.name))?;
            let seconds = started.elapsed().as_secs_f64();
            let seg = output.segmentation;
            let scores = evaluate(&seg, truth, &Tolerances::default()).map_err(|e| format!("{}: {e}", truth.trial))?;
            Ok(Row { scores, found_actions: seg.level(Level::Action).count(), seconds: Some(seconds) })
        };
        let mut rows = Vec::new();
        let mut mocap6 = Vec::new();
        for (bvh_path, truth_path, trial) in labelled_takes(data) {
            if !bvh_path.exists() {
                eprintln!("skipping {trial}: {} is absent", bvh_path.display());
                continue;
            }
            let loaded = load_path(&bvh_path).map_err(|e| e.to_string())?;
            let text = std::fs::read_to_string(&truth_path).map_err(|e| format!("{}: {e}", truth_path.display()))?;
            let truth = load_csv(&text, trial, TruthOptions::default())
                .map_err(|e| format!("{}: {e}", truth_path.display()))?;
            rows.push(score(&loaded.motion, &truth)?);
            if trial != "86_01" {
                mocap6.push((loaded.motion, truth));
            }
        }
        if rows.is_empty() {
            return Err(format!("{}: none of the labelled takes is present", data.display()));
        }
        // The mocap6 takes one after another: one long take (about 2 minutes) whose activities
        // recur across the parts, so kinds are scored across far-apart actions too.
        let mut joined_rows = Vec::new();
        if mocap6.len() > 1 {
            let motions: Vec<Motion> = mocap6.iter().map(|(m, _)| m.clone()).collect();
            let truths: Vec<Truth> = mocap6.iter().map(|(_, t)| t.clone()).collect();
            let frames = motions.iter().map(Motion::frames).sum();
            let name = truths.iter().map(|t| t.trial.as_str()).collect::<Vec<_>>().join("+");
            let mut joined = Motion::concatenate(&motions, frames).map_err(|e| format!("{name}: {e}"))?;
            joined.name = name.clone();
            joined_rows.push(score(&joined, &Truth::concatenate(&name, &truths))?);
        }
        if args.json {
            let list: Vec<_> = rows.iter().chain(&joined_rows).map(|r| &r.scores).collect();
            println!("{}", serde_json::to_string_pretty(&list).map_err(|e| e.to_string())?);
        } else {
            print!("{}", report::markdown(&rows, &joined_rows));
        }
        Ok(())
    }
}
