//! Lab tool, not part of the product: chooses the LMA search's granularity parameters the way
//! Bouchard & Badler did (a grid search on the segment similarity `s`), but **without tuning on
//! the takes it reports**: leave one source take out. For each of the five labelled takes of the
//! shared data (86_01, 13_29, 13_30, 13_31, 14_14), the grid is scored on takes spliced from the
//! other four ([`mocapseg::splice`], seeds 1 and 2), the best setting is applied to a take
//! spliced from the held-out one alone, and that held-out `s` is printed beside the in-sample
//! one (best setting on splices of all five, scored on them). Pruned and exhaustive searches are
//! tuned separately. Says so and fails when the shared data is absent.
//!
//! ```text
//! cargo run --release --example tune_lma -- [--data ../shared/data]
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
    use mocapseg::method::NoProgress;
    use mocapseg::methods::lma::classifier::EffortModel;
    use mocapseg::methods::lma::method::{analyse, Analysis, LmaParams};
    use mocapseg::motion::Motion;
    use mocapseg::segment::metrics::{evaluate, Tolerances};
    use mocapseg::segment::truth::{load_csv, Truth, TruthOptions};
    use mocapseg::segment::Segmentation;
    use mocapseg::splice::{splice, Source, SpliceOptions};

    #[derive(clap::Parser)]
    #[command(about = "Tune the LMA search by leave-one-source-take-out on spliced takes")]
    pub struct Args {
        #[arg(long, default_value = "../shared/data")]
        data: PathBuf,
    }

    /// A spliced take, its ground truth, and its analyses (one per prune speed for the pruned search).
    struct Take {
        truth: Truth,
        fps: f64,
        pieces: usize,
        analyses: Vec<Analysis>,
    }

    /// The grid: (prune speeds — each needs its own analysis — , min_rise, smooth_s, merge_s).
    fn grid(exhaustive: bool) -> (Vec<f64>, Vec<LmaParams>) {
        let speeds = if exhaustive { vec![1.0] } else { vec![1.0, 2.0, 4.0, 8.0] };
        let mut settings = Vec::new();
        for &prune_speed in &speeds {
            for min_rise in [0.1, 0.2, 0.4, 0.6, 0.8] {
                for smooth_s in [0.1, 0.2] {
                    for merge_s in [0.33, 0.67] {
                        settings.push(LmaParams {
                            exhaustive,
                            prune_speed,
                            min_rise,
                            smooth_s,
                            merge_s,
                            ..LmaParams::default()
                        });
                    }
                }
            }
        }
        (speeds, settings)
    }

    fn make(
        model: &EffortModel,
        sources: &[Source],
        seed: u64,
        pieces: usize,
        exhaustive: bool,
    ) -> Result<Take, String> {
        let spliced =
            splice(sources, &SpliceOptions { pieces, seed, ..Default::default() }).map_err(|e| e.to_string())?;
        let name = format!("splice{seed}");
        let truth = load_csv(&spliced.truth_csv(&name), &name, TruthOptions::default()).map_err(|e| e.to_string())?;
        let motion = Motion::from_bvh(&name, &spliced.bvh).map_err(|e| e.to_string())?;
        let (speeds, _) = grid(exhaustive);
        let analyses = speeds
            .iter()
            .map(|&prune_speed| {
                let p = LmaParams { exhaustive, prune_speed, ..LmaParams::default() };
                analyse(model, &motion, &p, &mut NoProgress).map_err(|e| e.to_string())
            })
            .collect::<Result<_, _>>()?;
        Ok(Take { truth, fps: motion.fps, pieces, analyses })
    }

    /// Bouchard & Badler's `s` at 0.5 s of one setting on one take.
    fn score(model: &EffortModel, take: &Take, params: &LmaParams) -> Result<f64, String> {
        let (speeds, _) = grid(params.exhaustive);
        let k = speeds.iter().position(|&s| s == params.prune_speed).unwrap_or(0);
        let analysis = &take.analyses[k];
        let segments = analysis.to_file(&analysis.find(model, params));
        if segments.is_empty() {
            // nothing found: every true segment is missed
            return Ok(-(take.pieces as f64) / 2.0);
        }
        let seg = Segmentation {
            file: "splice".into(),
            fps: take.fps,
            frames: analysis.file_frames,
            method: "lma".into(),
            params: serde_json::Value::Null,
            segments,
        };
        Ok(evaluate(&seg, &take.truth, &Tolerances::default()).map_err(|e| e.to_string())?.segments.similarity)
    }

    /// The setting with the best mean `s` over `takes`, and that mean.
    fn best(model: &EffortModel, takes: &[Take], exhaustive: bool) -> Result<(LmaParams, f64), String> {
        let mut top: Option<(LmaParams, f64)> = None;
        for p in grid(exhaustive).1 {
            let mut sum = 0.0;
            for t in takes {
                sum += score(model, t, &p)?;
            }
            let mean = sum / takes.len().max(1) as f64;
            if top.as_ref().is_none_or(|(_, m)| mean > *m) {
                top = Some((p, mean));
            }
        }
        top.ok_or_else(|| "empty grid".into())
    }

    fn describe(p: &LmaParams) -> String {
        if p.exhaustive {
            format!("min_rise {} smooth_s {} merge_s {}", p.min_rise, p.smooth_s, p.merge_s)
        } else {
            format!(
                "prune_speed {} min_rise {} smooth_s {} merge_s {}",
                p.prune_speed, p.min_rise, p.smooth_s, p.merge_s
            )
        }
    }

    pub fn run(args: Args) -> Result<(), String> {
        let model = &mocapseg::methods::lma::shipped_model()?;
        let mut loaded: Vec<(&str, Bvh, Truth)> = Vec::new();
        for take in crate::common::labelled_takes(&args.data)? {
            let text = std::fs::read_to_string(&take.bvh).map_err(|e| format!("{}: {e}", take.bvh.display()))?;
            let b = bvh::parse(&text).map_err(|e| format!("{}: {e}", take.bvh.display()))?;
            loaded.push((take.trial, b, take.truth));
        }
        let sources: Vec<Source> = loaded.iter().map(|(n, b, t)| Source { name: n, bvh: b, truth: t }).collect();
        for exhaustive in [false, true] {
            let mode = if exhaustive { "exhaustive" } else { "pruned" };
            println!("\nLMA {mode}: leave one source take out (tune on splices of the other takes, seeds 1–2, 30 pieces; test on a splice of the held-out take, 20 pieces)");
            println!(
                "| held-out take | chosen on the others | s on the others (mean) | held-out s | held-out s, defaults |"
            );
            println!("|---|---|---|---|---|");
            let defaults = LmaParams { exhaustive, ..LmaParams::default() };
            let (mut held, mut held_default) = (0.0, 0.0);
            for k in 0..sources.len() {
                let others: Vec<Source> =
                    sources.iter().enumerate().filter(|(i, _)| *i != k).map(|(_, s)| Source { ..*s }).collect();
                let tuning = [1, 2]
                    .iter()
                    .map(|&seed| make(model, &others, seed, 30, exhaustive))
                    .collect::<Result<Vec<_>, _>>()?;
                let (chosen, inner) = best(model, &tuning, exhaustive)?;
                let test = make(model, &sources[k..=k], 1, 20, exhaustive)?;
                let (s, s0) = (score(model, &test, &chosen)?, score(model, &test, &defaults)?);
                held += s;
                held_default += s0;
                println!("| {} | {} | {inner:.1} | {s:.1} | {s0:.1} |", sources[k].name, describe(&chosen));
            }
            let n = sources.len() as f64;
            println!("| mean | | | {:.1} | {:.1} |", held / n, held_default / n);
            // in-sample: the best setting on the benchmark's own splices of all five takes
            let all = [1, 2, 3]
                .iter()
                .map(|&seed| make(model, &sources, seed, 40, exhaustive))
                .collect::<Result<Vec<_>, _>>()?;
            let (chosen, inner) = best(model, &all, exhaustive)?;
            let mut d = 0.0;
            for t in &all {
                d += score(model, t, &defaults)?;
            }
            println!(
                "in-sample (the eval_splice takes: seeds 1–3, 40 pieces, all five sources): best {} s = {inner:.1}; defaults s = {:.1}",
                describe(&chosen),
                d / all.len() as f64
            );
        }
        Ok(())
    }
}
