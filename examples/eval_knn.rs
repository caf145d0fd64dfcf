//! Lab tool, not part of the product: the k-NN labeller (`mocapseg::methods::knn`, the baseline the DT-FCN
//! must beat) scored leave-one-take-out on the four mocap6 exercise takes of the shared data:
//! fit on three, label the fourth, score its frames against the ground truth (frame accuracy,
//! edit, F1@{10,25,50}, mean vote share). Nothing is tuned: the window (±1 s, every 5th frame),
//! k = 5 and 32 principal coordinates are the issue's prototype's. Says so and fails when the
//! shared data is absent.
//!
//! ```text
//! cargo run --release --example eval_knn -- [--data ../shared/data]
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

    use mocapseg::methods::knn::{Knn, KnnParams, Labelled};
    use mocapseg::motion::Motion;
    use mocapseg::segment::labelling;

    #[derive(clap::Parser)]
    #[command(about = "Score the k-NN labeller leave-one-take-out on the mocap6 takes")]
    pub struct Args {
        #[arg(long, default_value = "../shared/data")]
        data: PathBuf,
    }

    pub fn run(args: Args) -> Result<(), String> {
        let takes: Vec<_> =
            crate::common::labelled_takes(&args.data)?.into_iter().filter(|t| t.trial != "86_01").collect();
        if takes.len() < 2 {
            return Err("need at least two mocap6 takes".into());
        }
        let mut names: Vec<String> = Vec::new();
        let mut loaded: Vec<(String, Motion, Vec<usize>)> = Vec::new();
        for t in takes {
            let text = std::fs::read_to_string(&t.bvh).map_err(|e| format!("{}: {e}", t.bvh.display()))?;
            let b = mocapseg::bvh::parse(&text).map_err(|e| format!("{}: {e}", t.bvh.display()))?;
            let motion = Motion::from_bvh(t.trial, &b).map_err(|e| e.to_string())?;
            let mut labels = vec![0usize; motion.frames()];
            for s in &t.truth.segments {
                let k = names.iter().position(|n| *n == s.label).unwrap_or_else(|| {
                    names.push(s.label.clone());
                    names.len() - 1
                });
                for l in labels.iter_mut().take(s.end + 1).skip(s.start) {
                    *l = k;
                }
            }
            loaded.push((t.trial.to_string(), motion, labels));
        }
        println!("k-NN (k 5, ±1 s window every 5th frame, 32 principal coordinates), leave one take out:");
        println!("| held-out take | frame accuracy | edit | F1@10 | F1@25 | F1@50 | mean vote share | fit + label |");
        println!("|---|---|---|---|---|---|---|---|");
        let mut sums = [0.0; 6];
        for k in 0..loaded.len() {
            let started = Instant::now();
            let train: Vec<Labelled> = loaded
                .iter()
                .enumerate()
                .filter(|(i, _)| *i != k)
                .map(|(_, (_, m, l))| Labelled { motion: m, labels: l })
                .collect();
            let knn = Knn::fit(&train, KnnParams::default())?;
            let (name, motion, truth) = &loaded[k];
            let predicted = knn.predict(motion)?;
            let pred: Vec<Option<usize>> = predicted.iter().map(|p| Some(p.0)).collect();
            let truth: Vec<Option<usize>> = truth.iter().map(|&t| Some(t)).collect();
            let s = labelling::score(&pred, &truth);
            let confidence = predicted.iter().map(|p| p.1 as f64).sum::<f64>() / predicted.len().max(1) as f64;
            let row = [s.frame_accuracy, s.edit, s.f1[0], s.f1[1], s.f1[2], confidence];
            for (a, b) in sums.iter_mut().zip(row) {
                *a += b / loaded.len() as f64;
            }
            println!(
                "| {name} | {:.3} | {:.1} | {:.1} | {:.1} | {:.1} | {:.2} | {:.1} s |",
                row[0],
                row[1],
                row[2],
                row[3],
                row[4],
                row[5],
                started.elapsed().as_secs_f64()
            );
        }
        println!(
            "| **mean** | **{:.3}** | **{:.1}** | **{:.1}** | **{:.1}** | **{:.1}** | **{:.2}** | |",
            sums[0], sums[1], sums[2], sums[3], sums[4], sums[5]
        );
        Ok(())
    }
}
