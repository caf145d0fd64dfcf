//! Lab tool, not part of the product: times SSSM end to end (with per-stage times) on 1×, 2× and
//! 4× a 30 Hz sequence built from CMU takes (by default every CMU take of `../shared/data` on the
//! common skeleton, else the bundled sample and fixtures, cycled), and writes that sequence as a
//! BVH for the wasm benchmark (`tests/wasm_bench.rs`). `make bench` runs it.
//!
//! ```text
//! cargo run --release --example bench_sssm -- [TAKES…] [--frames 3000] [--reps 5] [--write-bvh seq.bvh] [--param NAME=VALUE]…
//! ```

#[cfg(target_arch = "wasm32")]
fn main() {}

#[cfg(not(target_arch = "wasm32"))]
#[allow(dead_code)] // each example uses part of it
mod common;

#[cfg(not(target_arch = "wasm32"))]
fn main() -> std::process::ExitCode {
    use clap::Parser;
    let a = lab::Args::parse();
    common::exit(lab::bench_sssm(a.files, a.frames, a.reps, a.write_bvh, &a.params))
}

#[cfg(not(target_arch = "wasm32"))]
mod lab {
    use std::path::{Path, PathBuf};
    use std::time::Instant;

    use mocapseg::bvh;
    use mocapseg::method;
    use mocapseg::methods::sssm::{self, SssmParams};
    use mocapseg::motion::Motion;
    use mocapseg::segment::Level;

    #[derive(clap::Parser)]
    #[command(about = "Time SSSM end to end on 1×, 2× and 4× a 30 Hz sequence built from CMU takes")]
    pub struct Args {
        /// Takes to build the sequence from, same skeleton, 30 Hz or a multiple.
        pub files: Vec<PathBuf>,
        /// Also write the 4× sequence as a 30 Hz BVH (the wasm benchmark embeds it).
        #[arg(long)]
        pub write_bvh: Option<PathBuf>,
        /// Frames at 30 Hz of the 1× sequence.
        #[arg(long, default_value_t = 3000)]
        pub frames: usize,
        #[arg(long, default_value_t = 5)]
        pub reps: usize,
        /// Parameter overrides as NAME=VALUE (JSON value); repeatable.
        #[arg(long = "param", value_name = "NAME=VALUE")]
        pub params: Vec<String>,
    }

    fn median(mut v: Vec<f64>) -> f64 {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    }

    /// The default SSSM bench material: the CMU takes of the shared data on the common CMU skeleton
    /// (distinct material: 5206 frames at 30 Hz; the 131_* takes have another skeleton), else the bundled sample and the fixtures (cycled).
    fn default_sssm_bench_files() -> Vec<PathBuf> {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let shared = root.join("../shared/data/cmu");
        let names = [
            "86/86_01",
            "mocap6/13_29",
            "mocap6/14_14",
            "mocap6/13_30",
            "mocap6/13_31",
            "locomotion/02_01",
            "locomotion/02_02",
            "locomotion/12_01",
            "locomotion/35_01",
        ];
        let all: Vec<PathBuf> = names.iter().map(|n| shared.join(format!("{n}.bvh"))).collect();
        if all.iter().all(|p| p.exists()) {
            return all;
        }
        eprintln!("note: ../shared/data/cmu is absent; benchmarking the bundled sample and fixtures (cycled)");
        ["www/sample.bvh", "tests/fixtures/02_01.bvh", "tests/fixtures/35_01.bvh", "tests/fixtures/12_01.bvh"]
            .iter()
            .map(|f| root.join(f))
            .collect()
    }

    /// The takes' frame rows at 30 Hz one after another, as one BVH on the first take's skeleton
    /// (all takes must have the same joints and channels, at a whole multiple of 30 Hz), cycled to
    /// `frames` rows. The same frames feed the native and the wasm benchmark.
    /// Also returns the number of distinct rows (before cycling).
    fn bench_sequence(files: &[PathBuf], frames: usize) -> Result<(bvh::Bvh, usize), String> {
        let mut takes = Vec::new();
        for f in files {
            let text = std::fs::read_to_string(f).map_err(|e| format!("{}: {e}", f.display()))?;
            takes.push(bvh::parse(&text).map_err(|e| format!("{}: {e}", f.display()))?);
        }
        let first = takes.first().ok_or("no takes to benchmark")?.clone();
        let layout = |b: &bvh::Bvh| b.joints.iter().map(|j| (j.name.clone(), j.channels.clone())).collect::<Vec<_>>();
        let mut rows: Vec<&[f64]> = Vec::new();
        for (b, f) in takes.iter().zip(files) {
            if layout(b) != layout(&first) {
                return Err(format!("{}: its joints or channels differ from {}", f.display(), files[0].display()));
            }
            let step = (b.fps() / 30.0).round().max(1.0) as usize;
            if (b.fps() / step as f64 - 30.0).abs() > 0.5 {
                return Err(format!("{}: {} fps is not a whole multiple of 30", f.display(), b.fps()));
            }
            rows.extend((0..b.frames()).step_by(step).map(|i| b.frame(i)));
        }
        let distinct = rows.len();
        let mut seq = first;
        seq.values = rows.iter().cycle().take(frames).flat_map(|r| r.iter().copied()).collect();
        seq.frame_time = 1.0 / 30.0;
        seq.declared_frames = frames;
        seq.warnings.clear();
        Ok((seq, distinct))
    }

    pub fn bench_sssm(
        files: Vec<PathBuf>,
        frames: usize,
        reps: usize,
        write_bvh: Option<PathBuf>,
        overrides: &[String],
    ) -> Result<(), String> {
        let files = if files.is_empty() { default_sssm_bench_files() } else { files };
        let (longest, distinct) = bench_sequence(&files, 4 * frames)?;
        if let Some(path) = &write_bvh {
            std::fs::write(path, bvh::write(&longest)).map_err(|e| format!("{}: {e}", path.display()))?;
            println!("wrote the 4× sequence ({} frames at 30 Hz) to {}", longest.frames(), path.display());
        }
        let full = Motion::from_bvh("bench sequence", &longest).map_err(|e| e.to_string())?;
        let method = mocapseg::methods::find("sssm").map_err(|e| e.to_string())?;
        let json = method::params_from_overrides(method, overrides).map_err(|e| e.to_string())?;
        let params: SssmParams = serde_json::from_value(json).map_err(|e| format!("SSSM parameters: {e}"))?;
        let names: Vec<String> =
            files.iter().map(|f| f.file_stem().unwrap_or_default().to_string_lossy().into()).collect();
        println!(
            "bench sssm native: takes {} at 30 Hz one after another ({distinct} distinct frames, cycled when longer), \
         {}, median of {reps}",
            names.join(", "),
            if overrides.is_empty() { "default parameters".to_string() } else { overrides.join(" ") }
        );
        let mut base_ms = None;
        for factor in [1usize, 2, 4] {
            let n = frames * factor;
            let seq = Motion::concatenate(std::slice::from_ref(&full), n).map_err(|e| e.to_string())?;
            let mut times = Vec::new();
            let mut summary = (0, 0, 0, 0);
            let mut stages: Vec<(String, f64)> = Vec::new();
            for _ in 0..reps.max(1) {
                let t0 = Instant::now();
                let mut last = (String::from("start"), Instant::now());
                let mut these = Vec::new();
                let r = sssm::segment_with_progress(&seq, &params, &mut |stage, _| {
                    // a stage ends when the next one reports (a stage may report many times)
                    if stage != last.0 {
                        let ms = last.1.elapsed().as_secs_f64() * 1e3;
                        these.push((std::mem::replace(&mut last.0, stage.to_string()), ms));
                        last.1 = Instant::now();
                    }
                    Ok(())
                })
                .map_err(|e| e.to_string())?;
                times.push(t0.elapsed().as_secs_f64() * 1e3);
                stages = these;
                let seg = &r.segmentation;
                summary = (
                    seg.level(Level::Action).count(),
                    seg.level(Level::Primitive).count(),
                    r.outcome.clusters.len(),
                    r.outcome.sssm.entries(),
                );
            }
            let ms = median(times);
            let growth = base_ms.map(|b: f64| format!("  ({:.2}× the 1× time)", ms / b)).unwrap_or_default();
            base_ms.get_or_insert(ms);
            // repeated material has more neighbours per frame (every copy neighbours the others)
            let repeats = if n > distinct {
                format!("   [{:.2}× the {distinct} distinct frames]", n as f64 / distinct as f64)
            } else {
                String::new()
            };
            println!(
            "  {factor}× {n:6} frames  {ms:8.1} ms{growth}   SSSM entries {} actions {} primitives {} clusters {}{repeats}",
            summary.3, summary.0, summary.1, summary.2
        );
            let parts: Vec<String> = stages.iter().skip(1).map(|(s, ms)| format!("{s} {ms:.1}")).collect();
            println!("      stages (ms, last run): {}", parts.join(", "));
        }
        Ok(())
    }
}
