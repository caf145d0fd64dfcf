//! Lab tool, not part of the product: does a labelling model's class set describe a take?
//! Measures, for the shipped k-NN models and k-NN models fitted leave-one-take-out on the
//! mocap6 takes, each take's nearest-training-window distances against the model's own
//! familiar distances (`Knn::familiar_distances`): the share of the take's frames farther than
//! the familiar distances' 95th percentile. Says so and fails when the shared data is absent.
//!
//! ```text
//! cargo run --release --example take_fit -- [--data ../shared/data]
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

    use mocapseg::labeller::fit::{TakeFit, TravelProfile};
    use mocapseg::labeller::shipped;
    use mocapseg::methods::knn::model::knn_of;
    use mocapseg::methods::knn::{Knn, KnnParams, Labelled};
    use mocapseg::motion::Motion;

    #[derive(clap::Parser)]
    #[command(about = "Measure how a take's windows lie from a k-NN model's training windows")]
    pub struct Args {
        #[arg(long, default_value = "../shared/data")]
        data: PathBuf,
    }

    fn load(path: &std::path::Path) -> Result<Motion, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let b = mocapseg::bvh::parse(&text).map_err(|e| format!("{}: {e}", path.display()))?;
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        Motion::from_bvh(&name, &b).map_err(|e| e.to_string())
    }

    fn row(model: &str, knn: &Knn, travel: &TravelProfile, takes: &[Motion]) -> Result<(), String> {
        for t in takes {
            let fit = TakeFit::assess(t, Some(travel), Some(knn))?;
            let unfamiliar = fit.unfamiliar.iter().filter(|&&u| u).count() as f64 / t.frames() as f64;
            println!(
                "| {model} | {} | {:.1} | {:.0} % | {:.2} | {:.0} % | {} |",
                t.name,
                travel.limit,
                100.0 * fit.travel_share.unwrap_or(0.0),
                fit.pose_ratio.unwrap_or(0.0),
                100.0 * unfamiliar,
                if fit.fits() { "fits" } else { "**does not fit**" }
            );
        }
        Ok(())
    }

    pub fn run(args: Args) -> Result<(), String> {
        let labelled = crate::common::labelled_takes(&args.data)?;
        let mut takes = Vec::new();
        for t in &labelled {
            takes.push(load(&t.bvh)?);
        }
        let loco = args.data.join("cmu/locomotion");
        let mut files: Vec<_> = std::fs::read_dir(&loco)
            .map_err(|e| format!("{}: {e}", loco.display()))?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "bvh"))
            .collect();
        files.sort();
        for f in files {
            takes.push(load(&f)?);
        }
        println!(
            "| model | take | travel limit (in/s) | frames beyond it | pose ratio | unfamiliar frames | verdict |"
        );
        println!("|---|---|---|---|---|---|---|");
        let store = mocapseg::method::ModelStore::new();
        for name in shipped::NAMES {
            let model =
                shipped::model(&mocapseg::methods::knn::method::KNN, name, &store, &mocapseg::methods::LABELLERS)
                    .map_err(|e| e.to_string())?;
            // the travel of the model's own training takes (the shipped headers predate the profile)
            let trained: Vec<&Motion> =
                takes.iter().filter(|t| model.header.provenance.takes.iter().any(|n| *n == t.name)).collect();
            let travel = match &model.header.travel {
                Some(t) => *t,
                None => TravelProfile::fit(&trained.iter().map(|m| (*m, None)).collect::<Vec<_>>())?,
            };
            if let Some(knn) = knn_of(&model) {
                row(name, knn, &travel, &takes)?;
            }
        }
        // leave one mocap6 take out: the held-out take is new but of the taught classes
        let mocap6: Vec<usize> =
            labelled.iter().enumerate().filter(|(_, t)| t.trial != "86_01").map(|(i, _)| i).collect();
        for &held in &mocap6 {
            let train: Vec<Vec<usize>> =
                mocap6.iter().filter(|&&i| i != held).map(|&i| vec![0; takes[i].frames()]).collect();
            let fit: Vec<Labelled> = mocap6
                .iter()
                .filter(|&&i| i != held)
                .zip(&train)
                .map(|(&i, l)| Labelled { motion: &takes[i], labels: l })
                .collect();
            let knn = Knn::fit(&fit, KnnParams::default())?;
            let travel = TravelProfile::fit(&fit.iter().map(|l| (l.motion, None)).collect::<Vec<_>>())?;
            let name = format!("mocap6 without {}", takes[held].name);
            row(&name, &knn, &travel, &takes[held..held + 1])?;
            row(&name, &knn, &travel, &takes[..1])?;
            row(&name, &knn, &travel, &takes[5..])?;
        }
        Ok(())
    }
}
