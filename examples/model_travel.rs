//! Lab tool, not part of the product: writes the travel profile of the take fit
//! (`mocapseg::labeller::fit`) into the header of a model made before it was measured,
//! from the model's own training data — the same BVH files and label CSV its provenance command
//! names, checked against its data hash — keeping the weights byte for byte. Models trained since
//! carry the profile from their training (`train-dtfcn`, `train-knn`, the page).
//!
//! ```text
//! cargo run --release --example model_travel -- MODEL --labels CSV BVH...
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

    use mocapseg::labeller::corpus::{class_labels, travel_of};
    use mocapseg::labeller::model::{data_hash, Model};
    use mocapseg::labels::read_csv;
    use mocapseg::labels::same_file;
    use mocapseg::methods::LABELLERS as KINDS;
    use mocapseg::motion::Motion;

    #[derive(clap::Parser)]
    #[command(about = "Write the take fit's travel profile into a model file made before it existed")]
    pub struct Args {
        /// The model file (rewritten in place).
        model: PathBuf,
        /// The label CSV it was trained on.
        #[arg(long)]
        labels: PathBuf,
        /// The BVH files (or folders) it was trained on.
        bvh: Vec<PathBuf>,
    }

    pub fn run(args: Args) -> Result<(), String> {
        let bytes = std::fs::read(&args.model).map_err(|e| format!("{}: {e}", args.model.display()))?;
        let source = args.model.display().to_string();
        let model = Model::from_bytes(&bytes, &source, &KINDS)?;
        let label_bytes = std::fs::read(&args.labels).map_err(|e| format!("{}: {e}", args.labels.display()))?;
        let rows = read_csv(&String::from_utf8_lossy(&label_bytes), &args.labels.display().to_string())?;
        let files = mocapseg::load::collect_files(&args.bvh, "bvh")?;
        let mut motions: Vec<Motion> = Vec::new();
        let mut hashed: Vec<(String, Vec<u8>)> = Vec::new();
        for f in files {
            let name = f.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
            if !rows.iter().any(|r| same_file(&r.file, &name)) {
                continue;
            }
            let loaded = mocapseg::load::load_path(&f).map_err(|e| e.to_string())?;
            hashed.push((name, std::fs::read(&f).map_err(|e| format!("{}: {e}", f.display()))?));
            motions.push(loaded.motion);
        }
        let hash = data_hash(&hashed, &label_bytes);
        if hash != model.header.provenance.data_hash {
            return Err(format!(
                "{source}: these takes and labels hash to {hash}, the model was made from {}: not its training data",
                model.header.provenance.data_hash
            ));
        }
        let refs: Vec<&Motion> = motions.iter().collect();
        let (_, labels) = class_labels(&rows, &refs)?;
        let taught: Vec<(&Motion, &[Option<usize>])> = motions.iter().zip(&labels).map(|(m, l)| (m, &l[..])).collect();
        let travel = travel_of(&taught).ok_or("the travel of these takes cannot be measured")?;
        let mut header = model.header.clone();
        header.travel = Some(travel);
        let out = Model::replace_header(&bytes, &source, &header, &KINDS)?;
        Model::from_bytes(&out, &source, &KINDS)?;
        std::fs::write(&args.model, &out).map_err(|e| format!("{}: {e}", args.model.display()))?;
        println!("{source}: travel median {:.1}, limit {:.1} in/s", travel.median, travel.limit);
        Ok(())
    }
}
