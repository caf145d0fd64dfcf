//! Benchmark of the LMA segmentation (Bouchard & Badler), native: the pruned and the exhaustive
//! search on 25, 50 and 100 s at 30 Hz of the benchmark sequence (the CMU takes one after another,
//! written by `cargo run --release --example bench_sssm -- --write-bvh`; `make bench` does both),
//! so that `make bench-wasm` times the same frames in Chromium. Prints times, not a test.
//!
//! ```text
//! cargo run --release --example bench_lma -- target/bench/sssm-sequence-30hz.bvh [--reps 3] [--only pruned|exhaustive]
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
    use mocapseg::method::{NoProgress, RunOptions};
    use mocapseg::methods::lma::method::{segment_with, LmaParams};
    use mocapseg::motion::Motion;
    use std::time::Instant;

    let args: Vec<String> = std::env::args().skip(1).collect();
    let path = args.iter().find(|a| a.ends_with(".bvh")).ok_or("give the benchmark sequence (.bvh)")?;
    let reps: usize = match args.iter().position(|a| a == "--reps") {
        Some(k) => args.get(k + 1).and_then(|r| r.parse().ok()).ok_or("--reps N")?,
        None => 3,
    };
    let only = match args.iter().position(|a| a == "--only") {
        Some(k) => match args.get(k + 1).map(String::as_str) {
            Some("pruned") => Some(false),
            Some("exhaustive") => Some(true),
            _ => return Err("--only pruned|exhaustive".into()),
        },
        None => None,
    };
    let text = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
    let bvh = mocapseg::bvh::parse(&text).map_err(|e| format!("{path}: {e}"))?;
    let full = Motion::from_bvh("bench sequence", &bvh).map_err(|e| e.to_string())?;
    let model = &mocapseg::methods::lma::shipped_model()?;
    let runs = [("effort", false), ("effort", true), ("deviance", false), ("deviance", true)];
    for (search, exhaustive) in runs.into_iter().filter(|&(_, e)| only.is_none_or(|o| o == e)) {
        let params = LmaParams { exhaustive, search: search.into(), ..LmaParams::default() };
        let mut base = None;
        for frames in [750usize, 1500, 3000] {
            let seq = Motion::concatenate(std::slice::from_ref(&full), frames).map_err(|e| e.to_string())?;
            let mut times = Vec::new();
            let mut found = 0;
            // the exhaustive search once per length, as in wasm: it is the slow one, and how it grows is the point
            let reps = if exhaustive { 1 } else { reps.max(1) };
            for _ in 0..reps {
                let t0 = Instant::now();
                let out = segment_with(model, &seq, &params, &RunOptions::default(), &mut NoProgress)
                    .map_err(|e| e.to_string())?;
                times.push(t0.elapsed().as_secs_f64() * 1000.0);
                found = out.segmentation.segments.len();
            }
            times.sort_by(f64::total_cmp);
            let ms = times[times.len() / 2];
            let growth = base.map(|b: f64| format!(" ({:.2}× the 750-frame time)", ms / b)).unwrap_or_default();
            base.get_or_insert(ms);
            println!(
                "native bench | lma {search:8} {} {frames:5} frames @30 Hz ({:3.0} s) | {ms:9.1} ms{growth} | {found} segments | median of {reps}",
                if exhaustive { "exhaustive" } else { "pruned    " },
                frames as f64 / 30.0
            );
        }
    }
    Ok(())
}
