//! Lab tool, not part of the product: the gesture-level benchmark. Splices the labelled takes of
//! the shared data (CMU 86_01, the mocap6 takes) into takes with known boundaries
//! ([`mocapseg::splice`], one per seed), segments each with every registered method (default
//! parameters; SSSM also scored on its primitives alone) and prints one table: segments found,
//! Bouchard & Badler's matched segments and similarity s at 0.5 s, boundary F1 and recall at
//! 0.5 s, each the mean over the seeds. Says so and fails when the shared data is absent.
//!
//! ```text
//! cargo run --release --example eval_splice -- [--data ../shared/data] [--seeds 1,2,3] [--pieces 40]
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

    use mocapseg::bvh::{self, Bvh};
    use mocapseg::method::{self, NoProgress, RunOptions};
    use mocapseg::motion::Motion;
    use mocapseg::segment::metrics::evaluate;
    use mocapseg::segment::truth::{load_csv, Truth, TruthOptions};
    use mocapseg::segment::{Level, Segmentation};
    use mocapseg::splice::{splice, Source, SpliceOptions};

    #[derive(clap::Parser)]
    #[command(about = "Score every method on spliced takes with known boundaries")]
    pub struct Args {
        /// The shared data folder (with cmu/ and labels/).
        #[arg(long, default_value = "../shared/data")]
        data: PathBuf,
        /// One spliced take per seed.
        #[arg(long, value_delimiter = ',', default_value = "1,2,3")]
        seeds: Vec<u64>,
        #[arg(long, default_value_t = 40)]
        pieces: usize,
    }

    /// Sums of one method's scores over the seeds.
    #[derive(Default)]
    struct Sums {
        found: f64,
        matched: f64,
        similarity: f64,
        f1: f64,
        recall: f64,
    }

    pub fn run(args: Args) -> Result<(), String> {
        let mut loaded: Vec<(&str, Bvh, Truth)> = Vec::new();
        for take in crate::common::labelled_takes(&args.data)? {
            let text = std::fs::read_to_string(&take.bvh).map_err(|e| format!("{}: {e}", take.bvh.display()))?;
            let b = bvh::parse(&text).map_err(|e| format!("{}: {e}", take.bvh.display()))?;
            loaded.push((take.trial, b, take.truth));
        }
        let sources: Vec<Source> = loaded.iter().map(|(n, b, t)| Source { name: n, bvh: b, truth: t }).collect();
        // every method with its defaults, LMA's exhaustive search, and SSSM's primitives on their own
        let mut runs: Vec<(String, &dyn method::DynMethod, serde_json::Value)> =
            mocapseg::methods::registry().iter().map(|&m| (m.info().name, m, serde_json::json!({}))).collect();
        runs.push((
            "lma exhaustive".into(),
            mocapseg::methods::find("lma").map_err(|e| e.to_string())?,
            serde_json::json!({"exhaustive": true}),
        ));
        let mut rows: Vec<(String, Sums)> = runs.iter().map(|r| (r.0.clone(), Sums::default())).collect();
        rows.push(("sssm primitives".into(), Sums::default()));
        let mut seconds = 0.0;
        for &seed in &args.seeds {
            let options = SpliceOptions { pieces: args.pieces, seed, ..Default::default() };
            let spliced = splice(&sources, &options).map_err(|e| e.to_string())?;
            let name = format!("splice{seed}");
            let truth =
                load_csv(&spliced.truth_csv(&name), &name, TruthOptions::default()).map_err(|e| e.to_string())?;
            let motion = Motion::from_bvh(&name, &spliced.bvh).map_err(|e| e.to_string())?;
            seconds += motion.duration_s();
            for (k, (name, m, params)) in runs.iter().enumerate() {
                let out = m
                    .run_json(&motion, params, &RunOptions::default(), &mut NoProgress)
                    .map_err(|e| format!("{name}: {e}"))?;
                add(&mut rows[k].1, &out.segmentation, &truth)?;
                if name == "sssm" {
                    let mut prims = out.segmentation.clone();
                    prims.segments.retain(|s| s.level == Level::Primitive);
                    let last = rows.len() - 1;
                    add(&mut rows[last].1, &prims, &truth)?;
                }
            }
        }
        let n = args.seeds.len().max(1) as f64;
        println!(
            "{} spliced takes (seeds {:?}, {} pieces each, {:.0} s in all), default parameters, mean per take:",
            args.seeds.len(),
            args.seeds,
            args.pieces,
            seconds
        );
        println!(
            "| method | segments found (of {}) | matched segments | s@0.5s | boundary F1@0.5s | boundary recall@0.5s |",
            args.pieces
        );
        println!("|---|---|---|---|---|---|");
        for (name, s) in &rows {
            println!(
                "| {name} | {:.1} | {:.1} | {:.1} | {:.2} | {:.2} |",
                s.found / n,
                s.matched / n,
                s.similarity / n,
                s.f1 / n,
                s.recall / n
            );
        }
        // the real takes: how many of their action boundaries each method's boundaries recall
        println!();
        println!(
            "Real takes (86_01, mocap6): recall of the labelled action boundaries within 0.5 s, default parameters:"
        );
        println!("| method | {} | mean |", loaded.iter().map(|l| l.0).collect::<Vec<_>>().join(" | "));
        println!("|---|{}---|", "---|".repeat(loaded.len()));
        for (name, m, params) in &runs {
            let mut recalls = Vec::new();
            for (trial, b, truth) in &loaded {
                let motion = Motion::from_bvh(trial, b).map_err(|e| e.to_string())?;
                let out = m
                    .run_json(&motion, params, &RunOptions::default(), &mut NoProgress)
                    .map_err(|e| format!("{name}: {e}"))?;
                // a method that finds nothing recalls nothing (the scorer refuses empty segmentations)
                if out.segmentation.segments.is_empty() {
                    recalls.push(0.0);
                    continue;
                }
                let s = evaluate(&out.segmentation, truth, &mocapseg::methods::scoring(&out.segmentation.method))
                    .map_err(|e| format!("{name}: {e}"))?;
                recalls.push(s.boundaries[0].recall);
            }
            let mean = recalls.iter().sum::<f64>() / recalls.len().max(1) as f64;
            println!(
                "| {name} | {} | {mean:.2} |",
                recalls.iter().map(|r| format!("{r:.2}")).collect::<Vec<_>>().join(" | ")
            );
        }
        Ok(())
    }

    fn add(sums: &mut Sums, seg: &Segmentation, truth: &Truth) -> Result<(), String> {
        let s = evaluate(seg, truth, &mocapseg::methods::scoring(&seg.method))
            .map_err(|e| format!("{}: {e}", seg.method))?;
        sums.found += (s.predicted_boundaries + 1) as f64;
        sums.matched += s.segments.matched as f64;
        sums.similarity += s.segments.similarity;
        sums.f1 += s.boundaries[0].f1;
        sums.recall += s.boundaries[0].recall;
        Ok(())
    }
}
