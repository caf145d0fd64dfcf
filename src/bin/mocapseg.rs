//! `mocapseg` — the native command line over the same core the page uses.
//!
//! ```text
//! mocapseg info FILE.bvh                      JSON summary of a take
//! mocapseg image FILE.bvh -o out.png          the motion image (DT-FCN §2) as PNG
//! mocapseg positions FILE.bvh [--fps F] -o out.csv   world joint positions per frame
//! mocapseg segment --method sssm FILE.bvh [--radius R] [--param NAME=VALUE]…   segmentation JSON
//! mocapseg eval-data [--data ../shared/data]  segment and score the labelled CMU takes
//! mocapseg bench-sssm                         SSSM time on 1×, 2×, 4× a 3000-frame take
//! mocapseg eval SEG.json --truth GT.csv [--trial ID]   scores against ground truth
//! mocapseg bench [FILE.bvh] [--reps N]        parse + forward-kinematics throughput
//! ```
//! Errors go to stderr as `error: FILE: line L, column C: what was expected`, exit code 1.

#[cfg(target_arch = "wasm32")]
fn main() {}

#[cfg(not(target_arch = "wasm32"))]
fn main() -> std::process::ExitCode {
    cli::main()
}

#[cfg(not(target_arch = "wasm32"))]
mod cli {
    use std::io::Write;
    use std::path::{Path, PathBuf};
    use std::process::ExitCode;
    use std::time::Instant;

    use clap::{Parser, Subcommand};
    use mocapseg::bvh;
    use mocapseg::image::MotionImage;
    use mocapseg::load::{load_path, Loaded};
    use mocapseg::motion::Motion;
    use mocapseg::segment::metrics::{evaluate, Tolerances};
    use mocapseg::segment::truth::{load_csv, Truth, TruthOptions};
    use mocapseg::segment::{Level, Segmentation};
    use mocapseg::sssm::{self, SssmParams};

    #[derive(Parser)]
    #[command(name = "mocapseg", version, about = "Motion-capture segmentation: BVH tools and segmenters")]
    struct Cli {
        #[command(subcommand)]
        command: Command,
    }

    #[derive(Subcommand)]
    enum Command {
        /// Print a JSON summary: joints, frames, fps, duration, units, up axis, warnings.
        Info { file: PathBuf },
        /// Write the motion image (one column per frame, one row per joint, RGB = root-relative XYZ) as PNG.
        Image {
            file: PathBuf,
            #[arg(short, long)]
            output: PathBuf,
        },
        /// Write world joint positions per frame as CSV (file units): frame,time_s,<joint>_x,<joint>_y,<joint>_z,…
        Positions {
            file: PathBuf,
            /// Resample to this frame rate first (linear interpolation at exact times).
            #[arg(long)]
            fps: Option<f64>,
            /// Also write the End Site positions.
            #[arg(long)]
            end_sites: bool,
            #[arg(short, long)]
            output: PathBuf,
        },
        /// Segment a take and print the segmentation JSON (parameters echoed in `params`).
        Segment {
            file: PathBuf,
            /// The method: `sssm` (Krüger et al. 2017).
            #[arg(long, default_value = "sssm")]
            method: String,
            /// Generalized radius R in inches.
            #[arg(long, allow_negative_numbers = true)]
            radius: Option<f64>,
            /// Stacked frame offsets at 30 Hz, e.g. `-10,-5,0,5,10`.
            #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
            offsets: Option<Vec<i32>>,
            /// Feature bundling (§III) on or off.
            #[arg(long)]
            bundling: Option<bool>,
            /// Mirrored features (§V) on or off.
            #[arg(long)]
            mirror: Option<bool>,
            /// Any other parameter as NAME=VALUE (JSON value), e.g. `--param stop_window=8`; repeatable.
            #[arg(long = "param", value_name = "NAME=VALUE")]
            params: Vec<String>,
        },
        /// Segment the labelled CMU takes in a data folder and print the scores per take and their mean.
        EvalData {
            /// The shared data folder (with cmu/ and labels/).
            #[arg(long, default_value = "../shared/data")]
            data: PathBuf,
            #[arg(long, default_value = "sssm")]
            method: String,
            /// Parameter overrides as NAME=VALUE (JSON value); repeatable.
            #[arg(long = "param", value_name = "NAME=VALUE")]
            params: Vec<String>,
            /// Print JSON instead of a markdown table.
            #[arg(long)]
            json: bool,
        },
        /// Time SSSM end to end on 1×, 2× and 4× a 3000-frame (30 Hz) sequence built from CMU takes.
        BenchSssm {
            /// Takes to build the sequence from, same skeleton, 30 Hz or a multiple (default: every CMU
            /// take of ../shared/data, else the bundled sample and fixtures).
            files: Vec<PathBuf>,
            /// Also write the 4× sequence as a 30 Hz BVH (the wasm benchmark embeds it).
            #[arg(long)]
            write_bvh: Option<PathBuf>,
            /// Frames at 30 Hz of the 1× sequence.
            #[arg(long, default_value_t = 3000)]
            frames: usize,
            #[arg(long, default_value_t = 5)]
            reps: usize,
            /// Parameter overrides as NAME=VALUE (JSON value); repeatable.
            #[arg(long = "param", value_name = "NAME=VALUE")]
            params: Vec<String>,
        },
        /// Score a segmentation JSON against ground truth CSV (boundary P/R/F1 at 0.5 s and 1 s, covering,
        /// Hungarian frame accuracy, strict/tolerant accuracy); prints JSON.
        Eval {
            /// Segmentation JSON (the schema every method prints).
            segmentation: PathBuf,
            /// Ground truth CSV with columns trial,label,start_frame,end_frame[,trial_frames,end_window_lo,end_window_hi].
            #[arg(long)]
            truth: PathBuf,
            /// Trial id in the CSV (default: the segmentation's file name without extension).
            #[arg(long)]
            trial: Option<String>,
            /// The number the CSV gives the first frame (1 for CMU AMC frame numbers).
            #[arg(long, default_value_t = 1)]
            first_frame: usize,
            /// BVH rows before the CSV's first frame (1 when the BVH prepends a T-pose row).
            #[arg(long, default_value_t = 0)]
            row_offset: usize,
        },
        /// Measure parse and forward-kinematics throughput (MB/s, frames/s) on a take.
        Bench {
            /// The take to measure (default: ../shared/data/cmu/86/86_01.bvh, else the bundled sample).
            file: Option<PathBuf>,
            /// Repetitions; the median is reported.
            #[arg(long, default_value_t = 7)]
            reps: usize,
        },
    }

    pub fn main() -> ExitCode {
        let cli = Cli::parse();
        match run(cli.command) {
            Ok(()) => ExitCode::SUCCESS,
            Err(message) => {
                eprintln!("error: {message}");
                ExitCode::FAILURE
            }
        }
    }

    fn run(command: Command) -> Result<(), String> {
        match command {
            Command::Info { file } => info(&file),
            Command::Image { file, output } => image(&file, &output),
            Command::Positions { file, fps, end_sites, output } => positions(&file, fps, end_sites, &output),
            Command::Bench { file, reps } => bench(file, reps),
            Command::Segment { file, method, radius, offsets, bundling, mirror, params } => {
                let mut overrides = params;
                let named = [
                    ("radius", radius.map(|v| v.to_string())),
                    ("offsets", offsets.map(|v| format!("{v:?}"))),
                    ("bundling", bundling.map(|v| v.to_string())),
                    ("mirror", mirror.map(|v| v.to_string())),
                ];
                overrides.extend(named.into_iter().filter_map(|(k, v)| v.map(|v| format!("{k}={v}"))));
                segment(&file, &method, &overrides)
            }
            Command::EvalData { data, method, params, json } => eval_data(&data, &method, &params, json),
            Command::BenchSssm { files, frames, reps, write_bvh, params } => {
                bench_sssm(files, frames, reps, write_bvh, &params)
            }
            Command::Eval { segmentation, truth, trial, first_frame, row_offset } => {
                eval(&segmentation, &truth, trial, TruthOptions { first_frame, bvh_row_offset: row_offset })
            }
        }
    }

    fn load(file: &Path) -> Result<Loaded, String> {
        load_path(file).map_err(|e| e.to_string())
    }

    fn info(file: &Path) -> Result<(), String> {
        let loaded = load(file)?;
        let m = &loaded.motion;
        let joints = m.skeleton.is_end_site.iter().filter(|e| !**e).count();
        let summary = serde_json::json!({
            "file": m.name,
            "joints": joints,
            "end_sites": m.joints() - joints,
            "frames": m.frames(),
            "declared_frames": loaded.bvh.declared_frames,
            "frame_time": loaded.bvh.frame_time,
            "fps": m.fps,
            "duration_s": m.duration_s(),
            "channels": loaded.bvh.channels_per_frame,
            "units": m.units,
            "up_axis": m.up_axis,
            "root": m.skeleton.names.first(),
            "warnings": loaded.warnings(),
        });
        println!("{}", serde_json::to_string_pretty(&summary).map_err(|e| e.to_string())?);
        Ok(())
    }

    fn image(file: &Path, output: &Path) -> Result<(), String> {
        let loaded = load(file)?;
        let img = MotionImage::from_motion(&loaded.motion);
        let png = img.to_png();
        std::fs::write(output, &png).map_err(|e| format!("{}: {e}", output.display()))?;
        eprintln!("wrote {} ({}×{} px, {} bytes)", output.display(), img.width, img.height, png.len());
        Ok(())
    }

    /// CSV field: quoted when the joint name holds a comma, quote or whitespace.
    fn csv_field(name: &str) -> String {
        if name.contains([',', '"', ' ', '\t']) {
            format!("\"{}\"", name.replace('"', "\"\""))
        } else {
            name.to_string()
        }
    }

    fn positions(file: &Path, fps: Option<f64>, end_sites: bool, output: &Path) -> Result<(), String> {
        let loaded = load(file)?;
        let motion: Motion = match fps {
            Some(f) => loaded.motion.resample(f).map_err(|e| format!("{}: {e}", file.display()))?,
            None => loaded.motion,
        };
        let cols: Vec<usize> = (0..motion.joints()).filter(|&j| end_sites || !motion.skeleton.is_end_site[j]).collect();
        let out = std::fs::File::create(output).map_err(|e| format!("{}: {e}", output.display()))?;
        let mut w = std::io::BufWriter::new(out);
        let io = |e: std::io::Error| format!("{}: {e}", output.display());
        write!(w, "frame,time_s").map_err(io)?;
        for &j in &cols {
            let n = &motion.skeleton.names[j];
            for axis in ["x", "y", "z"] {
                write!(w, ",{}", csv_field(&format!("{n}_{axis}"))).map_err(io)?;
            }
        }
        writeln!(w).map_err(io)?;
        for f in 0..motion.frames() {
            write!(w, "{f},{}", f as f64 / motion.fps).map_err(io)?;
            let frame = motion.frame(f);
            for &j in &cols {
                let p = frame[j];
                write!(w, ",{},{},{}", p.x, p.y, p.z).map_err(io)?;
            }
            writeln!(w).map_err(io)?;
        }
        w.flush().map_err(io)?;
        eprintln!(
            "wrote {} ({} frames at {} fps, {} joints)",
            output.display(),
            motion.frames(),
            motion.fps,
            cols.len()
        );
        Ok(())
    }

    fn read_text(path: &Path) -> Result<String, String> {
        std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))
    }

    fn eval(seg_path: &Path, truth_path: &Path, trial: Option<String>, options: TruthOptions) -> Result<(), String> {
        let seg = Segmentation::from_json(&read_text(seg_path)?).map_err(|e| format!("{}: {e}", seg_path.display()))?;
        let trial = trial.unwrap_or_else(|| {
            Path::new(&seg.file).file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default()
        });
        let truth =
            load_csv(&read_text(truth_path)?, &trial, options).map_err(|e| format!("{}: {e}", truth_path.display()))?;
        let scores =
            evaluate(&seg, &truth, &Tolerances::default()).map_err(|e| format!("{}: {e}", seg_path.display()))?;
        println!("{}", serde_json::to_string_pretty(&scores).map_err(|e| e.to_string())?);
        Ok(())
    }

    /// The method's parameters: its defaults with `NAME=VALUE` overrides applied (values are JSON).
    fn sssm_params(overrides: &[String]) -> Result<SssmParams, String> {
        let mut json = serde_json::to_value(SssmParams::default()).map_err(|e| e.to_string())?;
        let map = json.as_object_mut().ok_or("parameters are not a JSON object")?;
        for o in overrides {
            let (name, raw) = o.split_once('=').ok_or_else(|| format!("`{o}`: expected NAME=VALUE"))?;
            let name = name.trim().replace('-', "_");
            if !map.contains_key(&name) {
                let known: Vec<&str> = map.keys().map(String::as_str).collect();
                return Err(format!("unknown SSSM parameter `{name}`; known: {}", known.join(", ")));
            }
            let value =
                serde_json::from_str(raw.trim()).unwrap_or_else(|_| serde_json::Value::String(raw.trim().to_string()));
            map.insert(name, value);
        }
        serde_json::from_value(json).map_err(|e| format!("invalid SSSM parameters: {e}"))
    }

    fn run_method(motion: &Motion, method: &str, overrides: &[String]) -> Result<Segmentation, String> {
        match method {
            "sssm" => {
                let params = sssm_params(overrides)?;
                let result = sssm::segment(motion, &params).map_err(|e| format!("{}: {e}", motion.name))?;
                Ok(result.segmentation)
            }
            other => Err(format!("unknown method `{other}`; available: sssm")),
        }
    }

    fn segment(file: &Path, method: &str, overrides: &[String]) -> Result<(), String> {
        let loaded = load(file)?;
        let seg = run_method(&loaded.motion, method, overrides)?;
        println!("{}", seg.to_json());
        Ok(())
    }

    /// The labelled takes of the shared data: (BVH path, ground-truth CSV, trial id).
    fn labelled_takes(data: &Path) -> Vec<(PathBuf, PathBuf, &'static str)> {
        let cmu86 = data.join("labels/cmu86_zhou_gt.csv");
        let mocap6 = data.join("labels/mocap6_gt.csv");
        let mut takes = vec![(data.join("cmu/86/86_01.bvh"), cmu86, "86_01")];
        for t in ["13_29", "13_30", "13_31", "14_14"] {
            takes.push((data.join(format!("cmu/mocap6/{t}.bvh")), mocap6.clone(), t));
        }
        takes
    }

    fn eval_data(data: &Path, method: &str, overrides: &[String], json: bool) -> Result<(), String> {
        if !data.join("labels").is_dir() {
            return Err(format!(
                "{}: no shared data here (expected labels/ and cmu/ as in ../shared/data); pass --data DIR",
                data.display()
            ));
        }
        let mut rows = Vec::new();
        let mut score = |motion: &Motion, truth: &Truth| -> Result<(), String> {
            let started = Instant::now();
            let seg = run_method(motion, method, overrides)?;
            let seconds = started.elapsed().as_secs_f64();
            let scores = evaluate(&seg, truth, &Tolerances::default()).map_err(|e| format!("{}: {e}", truth.trial))?;
            rows.push((scores, seg.level(Level::Action).count(), seconds));
            Ok(())
        };
        let mut mocap6 = Vec::new();
        let mut joined_rows = 0;
        for (bvh_path, truth_path, trial) in labelled_takes(data) {
            if !bvh_path.exists() {
                eprintln!("skipping {trial}: {} is absent", bvh_path.display());
                continue;
            }
            let loaded = load(&bvh_path)?;
            let truth = load_csv(&read_text(&truth_path)?, trial, TruthOptions::default())
                .map_err(|e| format!("{}: {e}", truth_path.display()))?;
            score(&loaded.motion, &truth)?;
            if trial != "86_01" {
                mocap6.push((loaded.motion, truth));
            }
        }
        // The mocap6 takes one after another: one long take (about 2 minutes) whose activities
        // recur across the parts, so kinds are scored across far-apart actions too.
        if mocap6.len() > 1 {
            let motions: Vec<Motion> = mocap6.iter().map(|(m, _)| m.clone()).collect();
            let truths: Vec<Truth> = mocap6.iter().map(|(_, t)| t.clone()).collect();
            let frames = motions.iter().map(Motion::frames).sum();
            let names: Vec<&str> = truths.iter().map(|t| t.trial.as_str()).collect();
            let name = names.join("+");
            let mut joined = Motion::concatenate(&motions, frames).map_err(|e| format!("{name}: {e}"))?;
            joined.name = name.clone();
            score(&joined, &Truth::concatenate(&name, &truths))?;
            joined_rows = 1;
        }
        if rows.is_empty() {
            return Err(format!("{}: none of the labelled takes is present", data.display()));
        }
        if json {
            let list: Vec<_> = rows.iter().map(|(s, _, _)| s).collect();
            println!("{}", serde_json::to_string_pretty(&list).map_err(|e| e.to_string())?);
            return Ok(());
        }
        println!(
            "| take | true / found actions | F1@0.5s | F1@1s | covering | Hungarian acc. | strict | tolerant | time |"
        );
        println!("|---|---|---|---|---|---|---|---|---|");
        // the single takes, their mean, then the joined take (not in the mean)
        let single = rows.len() - joined_rows;
        let n = single as f64;
        let mut mean = [0.0f64; 6];
        let line = |s: &mocapseg::segment::metrics::Scores, actions: usize, secs: f64| {
            let v = [
                s.boundaries[0].f1,
                s.boundaries[1].f1,
                s.covering,
                s.hungarian_accuracy,
                s.strict_accuracy,
                s.tolerant_accuracy,
            ];
            println!(
                "| {} | {} / {} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.0} ms |",
                s.trial,
                s.true_boundaries + 1,
                actions,
                v[0],
                v[1],
                v[2],
                v[3],
                v[4],
                v[5],
                secs * 1e3
            );
            v
        };
        for (s, actions, secs) in &rows[..single] {
            let v = line(s, *actions, *secs);
            for (m, x) in mean.iter_mut().zip(v) {
                *m += x / n;
            }
        }
        println!(
            "| **mean** | | **{:.2}** | **{:.2}** | **{:.2}** | **{:.2}** | **{:.2}** | **{:.2}** | |",
            mean[0], mean[1], mean[2], mean[3], mean[4], mean[5]
        );
        for (s, actions, secs) in &rows[single..] {
            line(s, *actions, *secs);
        }
        Ok(())
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

    fn bench_sssm(
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
        let params = sssm_params(overrides)?;
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

    fn default_bench_file() -> Result<PathBuf, String> {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let candidates = [root.join("../shared/data/cmu/86/86_01.bvh"), root.join("www/sample.bvh")];
        candidates
            .into_iter()
            .find(|p| p.exists())
            .ok_or_else(|| "no bench file: pass one, e.g. mocapseg bench take.bvh".to_string())
    }

    fn median(mut v: Vec<f64>) -> f64 {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    }

    fn bench(file: Option<PathBuf>, reps: usize) -> Result<(), String> {
        let file = match file {
            Some(f) => f,
            None => default_bench_file()?,
        };
        let bytes = std::fs::read(&file).map_err(|e| format!("{}: {e}", file.display()))?;
        let text = std::str::from_utf8(&bytes).map_err(|e| format!("{}: not UTF-8: {e}", file.display()))?;
        let reps = reps.max(1);
        let (mut parse_s, mut fk_s, mut image_s) = (Vec::new(), Vec::new(), Vec::new());
        let mut frames = 0;
        for _ in 0..reps {
            let t0 = Instant::now();
            let parsed = bvh::parse(text).map_err(|e| format!("{}: {e}", file.display()))?;
            let t1 = Instant::now();
            let motion = Motion::from_bvh("bench", &parsed).map_err(|e| format!("{}: {e}", file.display()))?;
            let t2 = Instant::now();
            let img = MotionImage::from_motion(&motion);
            let t3 = Instant::now();
            std::hint::black_box(&img);
            frames = motion.frames();
            parse_s.push((t1 - t0).as_secs_f64());
            fk_s.push((t2 - t1).as_secs_f64());
            image_s.push((t3 - t2).as_secs_f64());
        }
        let mb = bytes.len() as f64 / 1e6;
        let (p, f, i) = (median(parse_s), median(fk_s), median(image_s));
        println!("bench native: {} ({:.2} MB, {} frames), median of {} runs", file.display(), mb, frames, reps);
        println!("  parse         {:8.2} ms  {:8.1} MB/s  {:10.0} frames/s", p * 1e3, mb / p, frames as f64 / p);
        println!("  fk            {:8.2} ms  {:21.0} frames/s", f * 1e3, frames as f64 / f);
        println!(
            "  parse+fk      {:8.2} ms  {:8.1} MB/s  {:10.0} frames/s",
            (p + f) * 1e3,
            mb / (p + f),
            frames as f64 / (p + f)
        );
        println!("  motion image  {:8.2} ms", i * 1e3);
        Ok(())
    }
}
