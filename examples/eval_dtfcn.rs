//! Lab tool, not part of the product: the DT-FCN experiments of docs/methods/dtfcn.md on the four mocap6
//! exercise takes of the shared data, every one leave-one-take-out with the epochs chosen on an
//! inner validation take (never on the held-out take), the k-NN beside the network under the same
//! labels:
//!
//! * `noise` — training-label noise 0–90 % (the paper's Table 3);
//! * `mask` — boundary masking w_transition 0/11/21/31 frames (Table 4, lower half);
//! * `unseen` — leave one class out: each fold's held-out take's largest class is removed from
//!   training; mean confidence on its frames (never seen) against the other frames, and how well
//!   each unknown threshold separates them (what chose the default threshold).
//!
//! ```text
//! cargo run --release --example eval_dtfcn -- noise|mask|unseen [--data ../shared/data] [--width 2] …
//! ```
//! Says so and fails when the shared data is absent.

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

    use mocapseg::labels::{from_truth_csv, LabelRow};
    use mocapseg::methods::dtfcn::augment::Augment;
    use mocapseg::methods::dtfcn::corpus::{class_labels, leave_one_take_out, predict_held_out};
    use mocapseg::methods::dtfcn::training::TrainOptions;
    use mocapseg::motion::Motion;
    use mocapseg::segment::truth::TruthOptions;

    #[derive(clap::Parser)]
    #[command(about = "DT-FCN experiments (noise, masking, unseen classes) on the mocap6 takes")]
    pub struct Args {
        /// noise, mask or unseen.
        experiment: String,
        #[arg(long, default_value = "../shared/data")]
        data: PathBuf,
        #[arg(long, default_value_t = 60)]
        epochs: usize,
        #[arg(long, default_value_t = 2)]
        width: usize,
        #[arg(long, default_value_t = 2)]
        batch: usize,
        #[arg(long, default_value_t = 128)]
        crop: usize,
        #[arg(long, default_value = "all")]
        augment: String,
        #[arg(long, default_value_t = 1)]
        seed: u64,
    }

    fn takes(data: &std::path::Path) -> Result<(Vec<Motion>, Vec<LabelRow>), String> {
        let truth = data.join("labels/mocap6_gt.csv");
        let text = std::fs::read_to_string(&truth).map_err(|e| {
            format!("{}: {e} — the shared data (../shared/data) is needed for this experiment", truth.display())
        })?;
        let (rows, _) = from_truth_csv(&text, TruthOptions::default())?;
        let mut motions = Vec::new();
        for trial in ["13_29", "13_30", "13_31", "14_14"] {
            let path = data.join(format!("cmu/mocap6/{trial}.bvh"));
            let loaded = mocapseg::load::load_path(&path).map_err(|e| e.to_string())?;
            motions.push(loaded.motion);
        }
        Ok((motions, rows))
    }

    pub fn run(args: Args) -> Result<(), String> {
        let (motions, rows) = takes(&args.data)?;
        let refs: Vec<&Motion> = motions.iter().collect();
        let (classes, labels) = class_labels(&rows, &refs)?;
        let base = TrainOptions {
            epochs: args.epochs,
            width: args.width,
            batch: args.batch,
            crop_frames: args.crop,
            augment: Augment::parse(&args.augment)?,
            seed: args.seed,
            ..TrainOptions::default()
        };
        println!(
            "mocap6, 4 takes, leave one take out (epochs ≤ {} chosen on an inner validation take, then retrained on all \
             training takes); w = {}, batch {}, crops {}, augmentation {}, seed {}",
            base.epochs,
            base.width,
            base.batch,
            base.crop_frames,
            base.augment.describe(),
            base.seed
        );
        match args.experiment.as_str() {
            "noise" | "mask" => {
                let noise = args.experiment == "noise";
                let levels: Vec<f64> =
                    if noise { (0..10).map(|i| i as f64 / 10.0).collect() } else { vec![0.0, 11.0, 21.0, 31.0] };
                println!(
                    "| {} | DT-FCN acc | edit | F1@10 | F1@25 | F1@50 | k-NN acc | edit | F1@10 | F1@25 | F1@50 |",
                    if noise { "label noise" } else { "w_transition (frames, masked)" }
                );
                println!("|---|---|---|---|---|---|---|---|---|---|---|");
                for level in levels {
                    let options = if noise {
                        TrainOptions { label_noise: level, ..base.clone() }
                    } else {
                        TrainOptions { mask_frames: level as usize, ..base.clone() }
                    };
                    let folds = leave_one_take_out(&motions, &labels, &classes, &options, &mut |_, _| true)?;
                    let n = folds.len() as f64;
                    let m = |f: &dyn Fn(&mocapseg::methods::dtfcn::corpus::Fold) -> f64| {
                        folds.iter().map(f).sum::<f64>() / n
                    };
                    println!(
                        "| {} | {:.3} | {:.1} | {:.1} | {:.1} | {:.1} | {:.3} | {:.1} | {:.1} | {:.1} | {:.1} |",
                        if noise { format!("{:.0} %", level * 100.0) } else { format!("{level}") },
                        m(&|f| f.network.frame_accuracy),
                        m(&|f| f.network.edit),
                        m(&|f| f.network.f1[0]),
                        m(&|f| f.network.f1[1]),
                        m(&|f| f.network.f1[2]),
                        m(&|f| f.knn.frame_accuracy),
                        m(&|f| f.knn.edit),
                        m(&|f| f.knn.f1[0]),
                        m(&|f| f.knn.f1[1]),
                        m(&|f| f.knn.f1[2]),
                    );
                }
                Ok(())
            }
            "unseen" => unseen(&motions, &labels, &classes, &base),
            other => Err(format!("unknown experiment `{other}`: noise, mask or unseen")),
        }
    }

    /// Leave one class out (see the module docs).
    fn unseen(
        motions: &[Motion],
        labels: &[Vec<Option<usize>>],
        classes: &[String],
        base: &TrainOptions,
    ) -> Result<(), String> {
        let thresholds: Vec<f32> = (2..=19).map(|i| i as f32 * 0.05).collect();
        // per method: (confidence, unseen?) of every held-out frame
        let mut pooled: [Vec<(f32, bool)>; 2] = [Vec::new(), Vec::new()];
        println!(
            "| held-out take | class left out | DT-FCN confidence unseen / seen | k-NN vote share unseen / seen |"
        );
        println!("|---|---|---|---|");
        for held in 0..motions.len() {
            let mut counts = vec![0usize; classes.len()];
            labels[held].iter().flatten().for_each(|&c| counts[c] += 1);
            let gone = (0..classes.len()).max_by_key(|&c| counts[c]).unwrap_or(0);
            let without: Vec<Vec<Option<usize>>> =
                labels.iter().map(|l| l.iter().map(|x| x.filter(|&c| c != gone)).collect()).collect();
            let p = predict_held_out(motions, &without, held, classes, base, &mut |_| true)?;
            let (per_file, kp) = (p.network, p.knn);
            let mut line = format!("| {} | {} |", motions[held].name, classes[gone]);
            for (m, pred) in [per_file.as_slice(), kp.as_slice()].iter().enumerate() {
                let (mut u, mut nu, mut s, mut ns) = (0.0, 0, 0.0, 0);
                for (f, l) in labels[held].iter().enumerate() {
                    let Some(l) = l else { continue };
                    let c = pred[f].1;
                    pooled[m].push((c, *l == gone));
                    if *l == gone {
                        u += c as f64;
                        nu += 1;
                    } else {
                        s += c as f64;
                        ns += 1;
                    }
                }
                line += &format!(" {:.2} / {:.2} |", u / nu.max(1) as f64, s / ns.max(1) as f64);
            }
            println!("{line}");
        }
        println!();
        println!("Frames called `unknown` (confidence below the threshold), all folds pooled:");
        println!("| threshold | DT-FCN: unseen called unknown | seen called unknown | k-NN: unseen called unknown | seen called unknown |");
        println!("|---|---|---|---|---|");
        let mut best = [(0.0f64, 0.0f32); 2];
        // the default: the most unseen frames caught while at most 10 % of seen frames are lost
        let mut default = [(0.0f64, 0.0f32); 2];
        for &t in &thresholds {
            let mut line = format!("| {t:.2} |");
            for m in 0..2 {
                let unseen: Vec<&(f32, bool)> = pooled[m].iter().filter(|p| p.1).collect();
                let seen: Vec<&(f32, bool)> = pooled[m].iter().filter(|p| !p.1).collect();
                let tpr = unseen.iter().filter(|p| p.0 < t).count() as f64 / unseen.len().max(1) as f64;
                let fpr = seen.iter().filter(|p| p.0 < t).count() as f64 / seen.len().max(1) as f64;
                let balanced = (tpr + 1.0 - fpr) / 2.0;
                if balanced > best[m].0 {
                    best[m] = (balanced, t);
                }
                if fpr <= 0.10 && tpr > default[m].0 {
                    default[m] = (tpr, t);
                }
                line += &format!(" {:.0} % | {:.0} % |", tpr * 100.0, fpr * 100.0);
            }
            println!("{line}");
        }
        println!(
            "Best balanced accuracy of `unknown`: DT-FCN {:.2} at threshold {:.2}; k-NN {:.2} at {:.2}",
            best[0].0, best[0].1, best[1].0, best[1].1
        );
        println!(
            "Most unseen frames called unknown while at most 10 % of seen frames are: DT-FCN threshold {:.2} ({:.0} %); \
             k-NN {:.2} ({:.0} %)",
            default[0].1,
            default[0].0 * 100.0,
            default[1].1,
            default[1].0 * 100.0
        );
        Ok(())
    }
}
