//! `mocapseg` — the native command line over the same core the page uses.
//!
//! ```text
//! mocapseg info FILE.bvh                      JSON summary of a take
//! mocapseg image FILE.bvh -o out.png          the motion image (DT-FCN §2) as PNG
//! mocapseg positions FILE.bvh [--fps F] -o out.csv   world joint positions per frame
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
    use mocapseg::segment::truth::{load_csv, TruthOptions};
    use mocapseg::segment::Segmentation;

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
        let cols: Vec<usize> =
            (0..motion.joints()).filter(|&j| end_sites || !motion.skeleton.is_end_site[j]).collect();
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
        eprintln!("wrote {} ({} frames at {} fps, {} joints)", output.display(), motion.frames(), motion.fps, cols.len());
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
        let truth = load_csv(&read_text(truth_path)?, &trial, options).map_err(|e| format!("{}: {e}", truth_path.display()))?;
        let scores = evaluate(&seg, &truth, &Tolerances::default()).map_err(|e| format!("{}: {e}", seg_path.display()))?;
        println!("{}", serde_json::to_string_pretty(&scores).map_err(|e| e.to_string())?);
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
        println!("  parse+fk      {:8.2} ms  {:8.1} MB/s  {:10.0} frames/s", (p + f) * 1e3, mb / (p + f), frames as f64 / (p + f));
        println!("  motion image  {:8.2} ms", i * 1e3);
        Ok(())
    }
}
