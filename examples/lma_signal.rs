//! Lab tool, not part of the product: what tells LMA's segments from the rest, on spliced takes whose boundaries are
//! known (`mocapseg::splice`, seeds 1–2, 40 pieces of the five labelled takes of the shared data).
//!
//! * **Deviance** (the paper's criterion): among the pruned search's candidate segments, do the ones whose both ends
//!   lie within 0.5 s of a true piece's have a lower mean deviance than the rest? (AUC: 0.5 = no.)
//! * **Effort change** (the default search, `methods::lma::change`): at each pruned candidate boundary, is the change
//!   of the family's mean output between the `L` frames before and after larger near a true boundary (within 0.5 s)
//!   than elsewhere? Beside it the same for a change of the raw pool features (relative differences).
//!
//! Prints one line per splice and arm. Says so and fails when the shared data is absent.
//!
//! ```text
//! cargo run --release --example lma_signal -- [--data ../shared/data]
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

    use mocapseg::bvh;
    use mocapseg::method::NoProgress;
    use mocapseg::methods::lma::body::upper_body;
    use mocapseg::methods::lma::features::{Pool, POOL_SIZE};
    use mocapseg::methods::lma::method::{analyse, LmaParams};
    use mocapseg::motion::Motion;
    use mocapseg::splice::{splice, Source, SpliceOptions};

    #[derive(clap::Parser)]
    #[command(about = "Does LMA's deviance, or its Effort change, tell true segments on spliced takes?")]
    pub struct Args {
        #[arg(long, default_value = "../shared/data")]
        data: PathBuf,
    }

    /// The share of (positive, negative) pairs in which the positive scores higher (ties half).
    fn auc(positive: &[f64], negative: &[f64]) -> f64 {
        let mut c = 0.0;
        for x in positive {
            for y in negative {
                c += if x > y {
                    1.0
                } else if x == y {
                    0.5
                } else {
                    0.0
                };
            }
        }
        c / (positive.len() * negative.len()).max(1) as f64
    }

    pub fn run(args: Args) -> Result<(), String> {
        let mut loaded = Vec::new();
        for t in crate::common::labelled_takes(&args.data)? {
            let text = std::fs::read_to_string(&t.bvh).map_err(|e| format!("{}: {e}", t.bvh.display()))?;
            loaded.push((t.trial.to_string(), bvh::parse(&text).map_err(|e| e.to_string())?, t.truth.clone()));
        }
        let sources: Vec<Source> = loaded.iter().map(|(n, b, t)| Source { name: n, bvh: b, truth: t }).collect();
        let model = &mocapseg::methods::lma::shipped_model()?;
        let tolerance = 0.5 * model.fps;
        let all: Vec<u16> = (0..POOL_SIZE as u16).collect();
        for seed in 1..=2u64 {
            let s = splice(&sources, &SpliceOptions { pieces: 40, seed, ..Default::default() })
                .map_err(|e| e.to_string())?;
            let motion = Motion::from_bvh("splice", &s.bvh).map_err(|e| e.to_string())?;
            let params = LmaParams { search: "deviance".into(), ..Default::default() };
            let analysis = analyse(model, &motion, &params, &mut NoProgress).map_err(|e| e.to_string())?;
            let ratio = model.fps / motion.fps;
            let pieces: Vec<(f64, f64)> =
                s.pieces.iter().map(|p| (p.start as f64 * ratio, p.end as f64 * ratio)).collect();
            let body = upper_body(&motion, model.fps).map_err(|e| e.to_string())?;
            for ((side, map), arm) in analysis.maps.iter().zip(&body.arms) {
                let (mut matched, mut other) = (Vec::new(), Vec::new());
                for (a, b, d) in map.candidates() {
                    let hit = pieces
                        .iter()
                        .any(|&(ps, pe)| (a as f64 - ps).abs() <= tolerance && (b as f64 - pe).abs() <= tolerance);
                    // low deviance = agreement: scored as −d
                    if hit {
                        matched.push(-d as f64)
                    } else {
                        other.push(-d as f64)
                    }
                }
                println!(
                    "seed {seed}, {side:?} arm: {} candidate segments, {} match a piece; deviance AUC {:.3}",
                    matched.len() + other.len(),
                    matched.len(),
                    auc(&matched, &other)
                );
                let pool = Pool::of(arm, model.fps, map.max_len + 2 * model.max_shift + 1);
                let mut boundaries: Vec<usize> = map.candidates().map(|c| c.0).collect();
                boundaries.sort_unstable();
                boundaries.dedup();
                for window in [20usize, 30, 45] {
                    let (mut near, mut far) = ((Vec::new(), Vec::new()), (Vec::new(), Vec::new()));
                    for &b in boundaries.iter().filter(|&&b| b > window + 6 && b + window + 6 < pool.frames()) {
                        let (before, after) =
                            (model.assess(&pool, b - window, b).1, model.assess(&pool, b, b + window).1);
                        let effort =
                            before.iter().zip(&after).map(|(x, y)| ((x - y) as f64).powi(2)).sum::<f64>().sqrt();
                        let (mut fb, mut fa) = (vec![0f32; POOL_SIZE], vec![0f32; POOL_SIZE]);
                        pool.features(&all, b - window, b, &mut fb);
                        pool.features(&all, b, b + window, &mut fa);
                        let raw = fb
                            .iter()
                            .zip(&fa)
                            .map(|(x, y)| ((x - y) / (x.abs() + y.abs() + 1e-3)).powi(2) as f64)
                            .sum::<f64>()
                            .sqrt();
                        let target = if pieces.iter().any(|&(ps, _)| (b as f64 - ps).abs() <= tolerance) {
                            &mut near
                        } else {
                            &mut far
                        };
                        target.0.push(effort);
                        target.1.push(raw);
                    }
                    println!(
                        "    window {window} frames: Effort change AUC {:.3}, raw feature change AUC {:.3} ({} of {} boundaries near a true one)",
                        auc(&near.0, &far.0),
                        auc(&near.1, &far.1),
                        near.0.len(),
                        near.0.len() + far.0.len()
                    );
                }
            }
        }
        Ok(())
    }
}
