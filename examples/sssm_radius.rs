//! Does SSSM's best radius follow the take? (issue 21, "a radius from the take's own neighbour-distance
//! quantiles"). For each labelled take of the shared data: SSSM's action scores (F1@1s, covering) at a ladder of
//! generalized radii, and the take's own scale of repetition — the quantiles of every working frame's distance to its
//! nearest neighbour outside the diagonal band, in the radius's units (inches per stacked pose) — so a radius set as
//! a multiple of a quantile can be compared with the fixed one.
//!
//!     cargo run --release --example sssm_radius [-- --data ../shared/data]

#[cfg(target_arch = "wasm32")]
fn main() {}

#[cfg(not(target_arch = "wasm32"))]
#[allow(dead_code)] // each example uses part of it
mod common;

#[cfg(not(target_arch = "wasm32"))]
fn main() -> std::process::ExitCode {
    common::exit(lab::run())
}

#[cfg(not(target_arch = "wasm32"))]
mod lab {
    use std::path::PathBuf;

    use mocapseg::method::{NoProgress, RunOptions};
    use mocapseg::methods::sssm::features::from_motion;
    use mocapseg::methods::sssm::SssmParams;
    use mocapseg::segment::metrics::{evaluate, Tolerances};
    use mocapseg::similarity::neighbours::stacked::StackedSearch;

    const RADII: [f64; 9] = [10.0, 13.0, 16.0, 19.0, 22.0, 25.0, 28.0, 31.0, 35.0];
    const QUANTILES: [f64; 5] = [0.1, 0.25, 0.5, 0.75, 0.9];

    pub fn run() -> Result<(), String> {
        let args: Vec<String> = std::env::args().collect();
        let data = args
            .iter()
            .position(|a| a == "--data")
            .and_then(|i| args.get(i + 1))
            .map_or("../shared/data", String::as_str);
        let takes = crate::common::labelled_takes(&PathBuf::from(data))?;
        let sssm = mocapseg::methods::find("sssm").map_err(|e| e.to_string())?;
        let valid = SssmParams::default().check().map_err(|e| e.to_string())?;
        let band = valid.band_frames();
        let per_pose = (valid.params().offsets.len() as f64).sqrt();
        println!(
            "take | nearest-neighbour distance quantiles {QUANTILES:?} (inches per pose) | radius: F1@1s / covering"
        );
        for take in &takes {
            let text = std::fs::read(&take.bvh).map_err(|e| format!("{}: {e}", take.bvh.display()))?;
            let name = take.bvh.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
            let motion = mocapseg::load::load_bytes(&name, &text, &mut |_| {}).map_err(|e| e.to_string())?.motion;
            // the take's own scale: nearest neighbour outside the band, at a radius wide enough for nearly every frame
            let features = from_motion(&motion, &valid).map_err(|e| e.to_string())?;
            let search =
                StackedSearch::new(&features.base, &valid.params().offsets, None).map_err(|e| e.to_string())?;
            let (s, _) = search.similarities((60.0 * per_pose) as f32, 400);
            let mut nearest: Vec<f64> = (0..s.frames())
                .filter_map(|i| {
                    let (cols, dists) = s.row(i);
                    cols.iter()
                        .zip(dists)
                        .filter(|(&j, _)| (j as usize).abs_diff(i) >= band)
                        .map(|(_, &d)| d as f64 / per_pose)
                        .min_by(f64::total_cmp)
                })
                .collect();
            nearest.sort_by(f64::total_cmp);
            let q: Vec<String> = QUANTILES
                .iter()
                .map(|&q| {
                    format!(
                        "{:.1}",
                        nearest.get(((nearest.len() as f64 - 1.0) * q).round() as usize).copied().unwrap_or(f64::NAN)
                    )
                })
                .collect();
            let covered = nearest.len() as f64 / s.frames().max(1) as f64;
            let mut cells = Vec::new();
            for r in RADII {
                let out = sssm
                    .run_json(
                        &motion,
                        &serde_json::json!({ "radius": r, "primitive_radius": r.min(13.0) }),
                        &RunOptions::default(),
                        &mut NoProgress,
                    )
                    .map_err(|e| format!("{name} radius {r}: {e}"))?;
                let scores =
                    evaluate(&out.segmentation, &take.truth, &Tolerances::default()).map_err(|e| e.to_string())?;
                let f1 =
                    scores.boundaries.iter().find(|b| (b.tolerance_s - 1.0).abs() < 1e-9).map_or(f64::NAN, |b| b.f1);
                cells.push(format!("{r:.0}: {f1:.2}/{:.2}", scores.covering));
            }
            println!(
                "{} | {} ({:.0} % of frames have one) | {}",
                take.trial,
                q.join(" "),
                100.0 * covered,
                cells.join("  ")
            );
        }
        Ok(())
    }
}
