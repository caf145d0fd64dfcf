//! Benchmark of DT-FCN and its k-NN baseline, native (the same workloads as `make bench-wasm`
//! times in Chromium, `mocapseg::methods::dtfcn::bench`): labelling 3000 frames at 30 Hz with the shipped
//! `exercises` models, 20 epochs of training on 3682 frames (the exercises set's size), and —
//! when the shared data is there — training the shipped exercises model itself. Prints times,
//! not a test.
//!
//! ```text
//! cargo run --release --example bench_dtfcn -- target/bench/sssm-sequence-30hz.bvh [--reps 5] [--data ../shared/data]
//! ```

#[cfg(target_arch = "wasm32")]
fn main() {}

#[cfg(not(target_arch = "wasm32"))]
fn main() -> std::process::ExitCode {
    match run() {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}

#[cfg(not(target_arch = "wasm32"))]
fn run() -> Result<(), String> {
    use mocapseg::methods::dtfcn::bench::{inference, train_epochs, EXERCISE_FRAMES};
    use mocapseg::motion::Motion;
    use std::time::Instant;

    let args: Vec<String> = std::env::args().skip(1).collect();
    let path = args.iter().find(|a| a.ends_with(".bvh")).ok_or("give the benchmark sequence (.bvh, 30 Hz)")?;
    let reps: usize = match args.iter().position(|a| a == "--reps") {
        Some(k) => args.get(k + 1).and_then(|r| r.parse().ok()).ok_or("--reps N")?,
        None => 5,
    };
    let data = match args.iter().position(|a| a == "--data") {
        Some(k) => args.get(k + 1).cloned().ok_or("--data DIR")?,
        None => "../shared/data".into(),
    };
    let text = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
    let bvh = mocapseg::bvh::parse(&text).map_err(|e| format!("{path}: {e}"))?;
    let full = Motion::from_bvh("bench sequence", &bvh).map_err(|e| e.to_string())?;
    let take = Motion::concatenate(std::slice::from_ref(&full), 3000).map_err(|e| e.to_string())?;
    let store = mocapseg::method::ModelStore::new();
    for kind in ["dtfcn", "knn"] {
        let shipped = mocapseg::methods::find(kind).unwrap().supervised().unwrap().shipped_model("exercises", &store);
        let loaded = shipped.map_err(|e| e.to_string())?;
        let model = loaded.model.downcast_ref::<mocapseg::labeller::model::Model>().unwrap();
        inference(&take, model)?; // warm-up (reads the model)
        let mut times = Vec::new();
        let mut segments = 0;
        for _ in 0..reps.max(1) {
            let t0 = Instant::now();
            segments = inference(&take, model)?;
            times.push(t0.elapsed().as_secs_f64() * 1000.0);
        }
        times.sort_by(f64::total_cmp);
        println!(
            "native bench | {} inference, 3000 frames @30 Hz | {:9.1} ms | {segments} segments | median of {}",
            kind,
            times[times.len() / 2],
            times.len()
        );
    }
    let t0 = Instant::now();
    let bytes = train_epochs(&full, 20)?;
    println!(
        "native bench | dtfcn training, 20 epochs on {EXERCISE_FRAMES} frames @30 Hz | {:9.1} s | model {bytes} bytes",
        t0.elapsed().as_secs_f64()
    );
    let labels = std::path::Path::new("models/labels/mocap6.csv");
    let takes = std::path::Path::new(&data).join("cmu/mocap6");
    if takes.is_dir() && labels.is_file() {
        let exe = std::env::current_exe().map_err(|e| e.to_string())?;
        let cli = exe.parent().and_then(|d| d.parent()).map(|d| d.join("mocapseg")).ok_or("no mocapseg binary")?;
        let t0 = Instant::now();
        let status = std::process::Command::new(&cli)
            .args(["train-dtfcn", "--bvh"])
            .arg(&takes)
            .args(["--labels", "models/labels/mocap6.csv", "--epochs", "33", "--name", "exercises"])
            .args(["--out", "target/bench/dtfcn-exercises.model"])
            .stderr(std::process::Stdio::null())
            .status()
            .map_err(|e| format!("{}: {e}", cli.display()))?;
        if !status.success() {
            return Err("training the exercises model failed".into());
        }
        println!(
            "native bench | dtfcn training of the shipped exercises model (33 epochs, 4 takes) | {:9.1} s",
            t0.elapsed().as_secs_f64()
        );
    } else {
        println!("native bench | note: {} is absent: the exercises model's training is not timed", takes.display());
    }
    Ok(())
}
