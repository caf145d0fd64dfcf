//! `mocapseg` — the native command line over the same core the page uses.
//!
//! ```text
//! mocapseg info FILE.bvh                      JSON summary of a take
//! mocapseg image FILE.bvh -o out.png          the motion image (Cheema et al. 2019, §2) as PNG
//! mocapseg positions FILE.bvh [--fps F] -o out.csv   world joint positions per frame
//! mocapseg features FILE.bvh [--fps 30] -o out.csv    the 15 end-effector features SSSM starts from
//! mocapseg methods                            the segmentation methods and their parameters
//! mocapseg segment --method NAME [--param NAME=VALUE]… FILE.bvh      segmentation JSON on stdout
//! mocapseg segment --method NAME [--param NAME=VALUE]… DIR_OR_FILES… --out DIR   batch, all cores
//!                                             (exit 0 all written, 2 some failed, 3 some panicked)
//! mocapseg eval SEG.json… --truth GT.csv|GT.json [--first-frame 0|1] [--label-fps F] [--trial T]
//!                                             scores against ground truth (one table for many)
//! mocapseg splice --bvh TAKES… --labels GT.csv… -o OUT.bvh   a take with known gesture boundaries
//! mocapseg cluster DIR_OR_FILES… --out DIR [--method sssm]   clusters shared across takes (one JSON per
//!                                             take + clusters.json; exit 0 all, 2 some failed, 3 one panicked)
//! mocapseg transfer DIR_OR_FILES… --labels L.csv --from TAKE.bvh --out DIR [--route nearest|clusters]
//!                                             one take's labels carried to the others (JSON per take, labels.csv)
//! mocapseg clips SEG.json TAKE.bvh --out DIR [--level action|primitive|all] [--origin] [--zip]
//!                                             each segment as a BVH clip of its own
//! mocapseg bench [FILE.bvh] [--reps N]        parse + forward-kinematics throughput
//! ```
//! Errors go to stderr as `error: FILE: line L, column C: what was expected`, exit code 1 (usage
//! errors too).
//! The lab's own tools (scores on the shared labelled takes, SSSM benchmarks) are examples:
//! `cargo run --release --example eval_data`, `--example bench_sssm`.

#[cfg(target_arch = "wasm32")]
fn main() {}

#[cfg(not(target_arch = "wasm32"))]
fn main() -> std::process::ExitCode {
    cli::main()
}

#[cfg(not(target_arch = "wasm32"))]
#[path = "mocapseg/model_info.rs"]
mod model_info;

#[cfg(not(target_arch = "wasm32"))]
#[path = "mocapseg/library_cli.rs"]
mod library_cli;

#[cfg(not(target_arch = "wasm32"))]
mod cli {
    use std::collections::HashMap;
    use std::path::{Path, PathBuf};
    use std::process::ExitCode;
    use std::sync::atomic::{AtomicUsize, Ordering};
    use std::time::Instant;

    use clap::{Parser, Subcommand};
    use indicatif::{ProgressBar, ProgressStyle};
    use mocapseg::bvh;
    use mocapseg::image::MotionImage;
    use mocapseg::load::{load_path, Loaded};
    use mocapseg::method::{self, CheckedParams, DynMethod, NoProgress, ParamKind, RunOptions};
    use mocapseg::motion::{write_positions_csv, Motion};
    use mocapseg::segment::metrics::evaluate;
    use mocapseg::segment::report::{self, Row};
    use mocapseg::segment::truth::{load_csv, TruthOptions};
    use mocapseg::segment::truth_import::{import_truth, ImportOptions, Take, TrialChoice};
    use mocapseg::segment::{Level, Segmentation};
    use mocapseg::splice::{Source, SpliceOptions};
    use mocapseg::stats;
    use rayon::prelude::*;

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
        /// Write the 15 end-effector features per working frame as CSV (what SSSM, velocity and
        /// others start from, `src/features/end_effectors.rs`): hands, feet and head relative to the
        /// hips, facing-aligned, in inches scaled to the reference body:
        /// frame,source_frame,lhand_x,lhand_y,lhand_z,rhand_…,lfoot_…,rfoot_…,head_x,head_y,head_z
        /// (`source_frame` = the fractional file frame of the working frame).
        Features {
            file: PathBuf,
            /// Working frame rate (SSSM's default 30).
            #[arg(long, default_value_t = 30.0)]
            fps: f64,
            /// Keep inches of the file's own body instead of scaling to the reference body.
            #[arg(long)]
            no_body_scale: bool,
            #[arg(short, long)]
            output: PathBuf,
        },
        /// List the segmentation methods with their parameters, defaults and accepted ranges.
        Methods {
            /// Print JSON instead of text.
            #[arg(long)]
            json: bool,
        },
        /// Segment takes. One file without --out: the segmentation JSON on stdout. Folders (searched
        /// for .bvh files) or several files: one JSON per take in --out, in parallel on every core,
        /// a line per take and a summary at the end; a take that fails or panics is reported and
        /// skipped, and an earlier run's JSON of it is removed.
        ///
        /// Each JSON is written whole or not at all (a temporary file in --out, then renamed), and no
        /// two takes share one (takes of one name are told apart by their folders, their extension,
        /// then a number; case is ignored, as macOS and Windows folders ignore it).
        ///
        /// Exit code: 0 every take segmented and written; 1 nothing segmented (a bad argument,
        /// parameter or model, no takes found, an output folder that cannot be made); 2 some takes
        /// failed (each named with why, the rest written); 3 some take panicked — a bug in mocapseg
        /// (each named with the panic's message, the rest written).
        Segment {
            /// BVH files and/or folders.
            #[arg(required = true)]
            inputs: Vec<PathBuf>,
            /// The method (`mocapseg methods` lists them).
            #[arg(long, default_value = "sssm")]
            method: String,
            /// A parameter as NAME=VALUE (JSON value), e.g. `--param radius=17`; repeatable.
            #[arg(long = "param", value_name = "NAME=VALUE")]
            params: Vec<String>,
            /// Folder for the segmentations (`<take>.json`); needed for more than one take.
            #[arg(long)]
            out: Option<PathBuf>,
            /// Takes segmented at once (default: one per core).
            #[arg(long)]
            jobs: Option<usize>,
            /// LMA: assess every candidate segment, not only those between slow-hand frames
            /// (the same as `--param exhaustive=true`).
            #[arg(long)]
            exhaustive: bool,
            /// DT-FCN / k-NN: a shipped model (exercises, cmu-actions, locomotion) or a model file
            /// (the same as `--param model=…`).
            #[arg(long)]
            model: Option<String>,
            /// LMA: the classifier family to use instead of the shipped one (a JSON file made by
            /// `mocapseg train-lma`, or saved from the page's LMA panel).
            #[arg(long, value_name = "FILE")]
            lma_model: Option<PathBuf>,
        },
        /// Cluster the segments of many takes together: every take segmented (on all cores; a bad file is
        /// reported and skipped), then its units (primitives and transitions, or actions) matched across the whole
        /// library on one self-similarity matrix (SSSM paper §VI across takes). Writes `<take>.json` per take, whose
        /// `cluster` ids (labels `C<id>`) mean the same motion in every take, and `clusters.json`: each cluster's
        /// occurrences (take, frames, seconds) and total duration, longest first.
        /// Exit code: 0 every take clustered; 1 nothing to cluster; 2 some takes failed (named, the rest clustered);
        /// 3 some take panicked (named, the rest clustered).
        Cluster {
            /// BVH files and/or folders.
            #[arg(required = true)]
            inputs: Vec<PathBuf>,
            /// Folder for the segmentations and clusters.json.
            #[arg(long)]
            out: PathBuf,
            #[command(flatten)]
            library: crate::library_cli::LibraryFlags,
        },
        /// Carry the labels of one take to every other take of a library (SSSM paper §VII-E): each segment of
        /// another take gets the label of the labelled segment its cheapest warping path joins it to, with a
        /// confidence (the JSON's `score`), and `unknown` where none fits. Writes `<take>.json` per take and
        /// `labels.csv` (the label CSV `train` reads; unknown stretches left out).
        /// Exit code: 0 every take labelled; 1 nothing done; 2 some takes failed (named, the rest labelled); 3 some
        /// take panicked (named, the rest labelled).
        Transfer {
            /// BVH files and/or folders (the labelled take is added if not among them).
            #[arg(required = true)]
            inputs: Vec<PathBuf>,
            /// The label CSV (`file,start_frame,end_frame,label`) with the labelled take's rows.
            #[arg(long)]
            labels: PathBuf,
            /// The labelled take.
            #[arg(long)]
            from: PathBuf,
            /// Folder for the labelled segmentations and labels.csv.
            #[arg(long)]
            out: PathBuf,
            /// nearest: the cheapest warping path to a labelled segment; clusters: the majority label of the labelled
            /// take's frames in the segment's shared cluster.
            #[arg(long, default_value = "nearest")]
            route: String,
            #[command(flatten)]
            library: crate::library_cli::LibraryFlags,
        },
        /// Label the gait phases of takes by rule (standing, begin/end left/right step, left/right
        /// step, turn — the DT-FCN paper's locomotion labels; heuristic, from foot contacts and the
        /// facing's turn rate) and write them as a label CSV `file,start_frame,end_frame,label`
        /// (0-based inclusive file frames).
        Gait {
            /// BVH files and/or folders.
            #[arg(required = true)]
            inputs: Vec<PathBuf>,
            /// The label CSV (default: stdout).
            #[arg(long, short)]
            out: Option<PathBuf>,
            /// Keep only the parts inside the segments of this label CSV labelled --label (the walking
            /// parts of takes whose actions are labelled); takes it does not name are kept whole.
            #[arg(long, requires = "label")]
            within: Option<PathBuf>,
            /// The label of --within's segments to keep (e.g. `walk`).
            #[arg(long, requires = "within")]
            label: Option<String>,
        },
        /// Convert ground truth in the shared data's format (`trial,label,start_frame,end_frame,…`,
        /// 1-based AMC frames) into the label CSV the supervised methods read
        /// (`file,start_frame,end_frame,label`, 0-based BVH rows).
        Labels {
            /// Ground-truth CSVs.
            #[arg(required = true)]
            truth: Vec<PathBuf>,
            /// The number the CSVs give the first frame (1 for CMU AMC frame numbers).
            #[arg(long, default_value_t = 1)]
            first_frame: usize,
            /// BVH rows before the CSV's first frame (1 when the BVH prepends a T-pose row).
            #[arg(long, default_value_t = 0)]
            row_offset: usize,
            /// The label CSV (default: stdout).
            #[arg(long, short)]
            out: Option<PathBuf>,
        },
        /// Train a model of any method with models (`mocapseg methods` lists them with their label CSV
        /// and training options) on labelled takes, exactly as the page's training panel does, and
        /// write its model file (`segment --method M --model FILE` reads it).
        Train {
            /// The method (dtfcn, knn, lma).
            #[arg(long)]
            method: String,
            /// The takes (BVH files and/or folders); takes the labels do not name are left out, and said.
            #[arg(required = true)]
            inputs: Vec<PathBuf>,
            /// The label CSV, with the header the method declares (`mocapseg methods`); a method that declares what it
            /// learns from without labels (LMA: its stand-in descriptors) trains on that when it is left out.
            #[arg(long)]
            labels: Option<PathBuf>,
            /// One of the takes kept out of the training, whose validation loss chooses the epoch (DT-FCN) and whose
            /// labels choose the model's decoding (DT-FCN, k-NN).
            #[arg(long, value_name = "TAKE")]
            validation: Option<String>,
            /// A training option of the method's table: NAME=VALUE (JSON, or a word), repeatable.
            #[arg(long = "option", value_name = "NAME=VALUE")]
            options: Vec<String>,
            /// The model's name (default: the output file's stem).
            #[arg(long)]
            name: Option<String>,
            #[arg(long, short)]
            out: PathBuf,
        },
        /// Give every segment of a segmentation JSON (any method's, or labels made into one) its Laban Effort from the
        /// LMA classifier family (Bouchard & Badler §6: LMA as a semantic layer over segments): the family's mean
        /// output over its 121 shifted classifiers, on the arm whose hand travels further in the segment. Segments
        /// that already carry one (LMA's own) keep it. Writes the segmentation JSON with `effort` filled.
        Effort {
            /// The segmentation JSON (`segment` writes it).
            segmentation: PathBuf,
            /// The take it segments (BVH, or AMC beside its ASF).
            take: PathBuf,
            /// The classifier family: a JSON file from `train-lma` or the page (default: the shipped one).
            #[arg(long)]
            lma_model: Option<PathBuf>,
            /// Where to write (default: stdout).
            #[arg(long, short)]
            out: Option<PathBuf>,
        },
        /// Print a model's header: kind, classes, colours, joint set, rate, how it was trained. FILE is
        /// a model file of any method with models, or a shipped model's name (`exercises`: every
        /// method's of that name, or one with --method; `dtfcn-exercises` / `dtfcn-exercises.model`,
        /// `lma-shipped`: that one).
        ModelInfo {
            #[arg(value_name = "FILE|NAME")]
            file: PathBuf,
            /// Only this method's model (a method with models: dtfcn, knn, lma).
            #[arg(long)]
            method: Option<String>,
        },
        /// Write the shipped models' cards (training takes, classes, command, held-out accuracy from
        /// the scoreboard where it measured one, else "not measured") as JSON: what the page shows
        /// beside each model choice. `make accuracy` writes them too.
        ModelCards {
            /// The scoreboard's JSON.
            #[arg(long, default_value = "docs/accuracy.json")]
            accuracy: PathBuf,
            /// Where to write them.
            #[arg(long, default_value = "models/cards.json")]
            out: PathBuf,
        },
        /// Score segmentation JSON against ground truth (boundary P/R/F1 at 0.5 s and 1 s, covering,
        /// Hungarian frame accuracy, strict/tolerant accuracy, edit, F1@k, segment score). One file: JSON;
        /// several files or a folder of predictions: one markdown table with the mean (--json for JSON).
        /// The truth is read as the page's ground-truth import reads it (the same core function).
        Eval {
            /// Segmentation JSON files and/or folders of them (the schema every method prints).
            #[arg(required = true)]
            predictions: Vec<PathBuf>,
            /// Ground truth: a CSV `start_frame,end_frame,label`, the shared data's CSV
            /// trial,label,start_frame,end_frame[,trial_frames,end_window_lo,end_window_hi], or a segmentation JSON.
            #[arg(long)]
            truth: PathBuf,
            /// Trial id in a shared-data CSV (default: each segmentation's file name without
            /// extension, else the file's only trial).
            #[arg(long)]
            trial: Option<String>,
            /// The number the CSV gives the first frame: 1 (CMU AMC frame numbers) or 0.
            #[arg(long, default_value_t = 1)]
            first_frame: usize,
            /// The rate the CSV's frame numbers count at (default: the take's, from the
            /// segmentation); other rates are converted by time to the take's frames.
            #[arg(long)]
            label_fps: Option<f64>,
            /// BVH rows before the CSV's first frame (1 when the BVH prepends a T-pose row).
            #[arg(long, default_value_t = 0)]
            row_offset: usize,
            /// JSON (a list of scores) instead of the table.
            #[arg(long)]
            json: bool,
        },
        /// Build a take with known boundaries from labelled takes (pieces of 0.8–3 s, each from another
        /// action than the one before, joined continuously); writes OUT.bvh and its ground truth OUT.csv.
        Splice {
            /// Source takes (same hierarchy and frame rate, Y up), files or folders.
            #[arg(long = "bvh", required = true, num_args = 1..)]
            bvh: Vec<PathBuf>,
            /// Ground-truth CSVs giving each take's labelled segments (trial = the take's file name
            /// without extension; 1-based frames as in the shared data).
            #[arg(long = "labels", required = true, num_args = 1..)]
            labels: Vec<PathBuf>,
            #[arg(long, default_value_t = 20)]
            pieces: usize,
            #[arg(long, default_value_t = 1)]
            seed: u64,
            /// Shortest and longest piece, seconds.
            #[arg(long, default_value_t = 0.8)]
            min_s: f64,
            #[arg(long, default_value_t = 3.0)]
            max_s: f64,
            /// Transition between two pieces, seconds.
            #[arg(long, default_value_t = 0.25)]
            blend_s: f64,
            /// The spliced take (`.bvh`); its ground truth goes next to it as `.csv`.
            #[arg(long, short)]
            out: PathBuf,
        },
        /// Cut each segment of a segmentation out of its take as a BVH clip of its own (the take's
        /// hierarchy, channel order and frame time; the segment's frames unchanged).
        Clips {
            /// The segmentation JSON (`mocapseg segment`, or the page's export).
            segmentation: PathBuf,
            /// The take it was made from (`.bvh`, or `.amc` with its `.asf` beside it).
            take: PathBuf,
            /// Folder for the clips (`<take>_<nn>_<label>.bvh`), created if needed.
            #[arg(long, short)]
            out: PathBuf,
            /// Which segments: action (transitions left out), primitive, or all.
            #[arg(long, default_value = "action", value_parser = ["action", "primitive", "all"])]
            level: String,
            /// Start each clip at the origin facing +Z (the root moved and turned; heights kept).
            #[arg(long)]
            origin: bool,
            /// One zip `<take>_clips.zip` in the folder instead of one file per clip.
            #[arg(long)]
            zip: bool,
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

    /// What `run` ends with: success, some takes of a batch failed (exit code 2), or some take of a
    /// batch panicked (exit code 3; failures without a panic are 2). Errors before any work are 1.
    enum Outcome {
        Ok,
        Partial,
        Panicked,
    }

    pub fn main() -> ExitCode {
        use clap::{CommandFactory, FromArgMatches};
        // a usage error is exit code 1 like every other error (clap's own is 2, which a batch
        // gives when some takes failed): a script can tell "nothing ran" from "some failed"
        let usage = |e: clap::Error| {
            let _ = e.print();
            if e.use_stderr() {
                ExitCode::FAILURE
            } else {
                ExitCode::SUCCESS // --help, --version
            }
        };
        let matches = match Cli::command().subcommands(training_commands()).try_get_matches() {
            Ok(m) => m,
            Err(e) => return usage(e),
        };
        let result = match matches.subcommand() {
            Some((sub, m)) if sub.starts_with("train-") => {
                train_from_flags(&sub["train-".len()..], m).map(|()| Outcome::Ok)
            }
            _ => match Cli::from_arg_matches(&matches) {
                Ok(cli) => run(cli.command),
                Err(e) => return usage(e),
            },
        };
        match result {
            Ok(Outcome::Ok) => ExitCode::SUCCESS,
            Ok(Outcome::Partial) => ExitCode::from(2),
            Ok(Outcome::Panicked) => ExitCode::from(3),
            Err(message) => {
                eprintln!("error: {message}");
                ExitCode::FAILURE
            }
        }
    }

    fn run(command: Command) -> Result<Outcome, String> {
        match command {
            Command::Segment { inputs, method, mut params, out, jobs, exhaustive, model, lma_model } => {
                if exhaustive {
                    params.push("exhaustive=true".into());
                }
                if let Some(path) = lma_model {
                    if method != "lma" {
                        return Err(format!("--lma-model is for --method lma, not {method}"));
                    }
                    params.push(format!("model={}", path.display()));
                }
                if let Some(m) = model {
                    params.push(format!("model={m}"));
                }
                let mut models = method::ModelStore::new();
                store_model_files(&method, &mut params, &mut models)?;
                return segment(&inputs, &method, &params, &models, out, jobs);
            }
            Command::Train { method, inputs, labels, validation, options, name, out } => {
                train(&method, &inputs, labels.as_deref(), validation, &options, name, &out)
            }
            Command::Cluster { inputs, out, library } => {
                return crate::library_cli::cluster_command(&inputs, &library, &out).map(library_outcome);
            }
            Command::Transfer { inputs, labels, from, out, route, library } => {
                let route = match route.as_str() {
                    "nearest" => mocapseg::library::TransferRoute::Nearest,
                    "clusters" => mocapseg::library::TransferRoute::Clusters,
                    other => return Err(format!("--route {other}: expected nearest or clusters")),
                };
                return crate::library_cli::transfer_command(&inputs, &library, &labels, &from, route, &out)
                    .map(library_outcome);
            }
            Command::Gait { inputs, out, within, label } => gait(&inputs, out, within.zip(label)),
            Command::Effort { segmentation, take, lma_model, out } => {
                effort(&segmentation, &take, lma_model.as_deref(), out.as_deref())
            }
            Command::ModelInfo { file, method } => crate::model_info::model_info(&file, method.as_deref()),
            Command::ModelCards { accuracy, out } => model_cards(&accuracy, &out),
            Command::Labels { truth, first_frame, row_offset, out } => {
                labels(&truth, TruthOptions { first_frame, bvh_row_offset: row_offset }, out)
            }
            Command::Info { file } => info(&file),
            Command::Image { file, output } => image(&file, &output),
            Command::Positions { file, fps, end_sites, output } => positions(&file, fps, end_sites, &output),
            Command::Features { file, fps, no_body_scale, output } => features(&file, fps, !no_body_scale, &output),
            Command::Methods { json } => methods(json),
            Command::Splice { bvh, labels, pieces, seed, min_s, max_s, blend_s, out } => {
                splice(&bvh, &labels, SpliceOptions { pieces, seed, min_s, max_s, blend_s }, &out)
            }
            Command::Bench { file, reps } => bench(file, reps),
            Command::Clips { segmentation, take, out, level, origin, zip } => {
                clips(&segmentation, &take, &out, &level, origin, zip)
            }
            Command::Eval { predictions, truth, trial, first_frame, label_fps, row_offset, json } => {
                let options = ImportOptions { first_frame, label_fps, bvh_row_offset: row_offset, trial };
                eval(&predictions, &truth, &options, json)
            }
        }
        .map(|()| Outcome::Ok)
    }

    /// A library command's exit: 2 when some takes failed (each reported), else 0.
    fn library_outcome(e: crate::library_cli::Ended) -> Outcome {
        if e.panicked > 0 {
            Outcome::Panicked
        } else if e.failed > 0 {
            Outcome::Partial
        } else {
            Outcome::Ok
        }
    }

    fn clips(segmentation: &Path, take: &Path, out: &Path, level: &str, origin: bool, zip: bool) -> Result<(), String> {
        use mocapseg::clips::{ClipOptions, Which};
        let seg = Segmentation::from_json(&read_text(segmentation)?)
            .map_err(|e| format!("{}: {e}", segmentation.display()))?;
        let loaded = load(take)?;
        let which = match level {
            "primitive" => Which::Primitives,
            "all" => Which::All,
            _ => Which::Actions,
        };
        let stem = take.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "take".into());
        let options = ClipOptions { which, to_origin: origin };
        let cut = mocapseg::clips::clips(&loaded.bvh, &loaded.motion, &seg, &stem, &options)
            .map_err(|e| format!("{} with {}: {e}", segmentation.display(), take.display()))?;
        std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
        if zip {
            let path = out.join(format!("{stem}_clips.zip"));
            let bytes = mocapseg::clips::zip(&cut).map_err(|e| e.to_string())?;
            std::fs::write(&path, &bytes).map_err(|e| format!("{}: {e}", path.display()))?;
            eprintln!("wrote {} ({} clips, {} bytes)", path.display(), cut.len(), bytes.len());
            return Ok(());
        }
        for clip in &cut {
            let path = out.join(&clip.file);
            std::fs::write(&path, mocapseg::bvh::write(&clip.bvh)).map_err(|e| format!("{}: {e}", path.display()))?;
            let s = &clip.segment;
            println!("{}\t{}–{}\t{}", path.display(), s.start, s.end, s.label);
        }
        eprintln!("wrote {} clips to {}", cut.len(), out.display());
        Ok(())
    }

    /// `segment --model FILE` (`--param model=FILE`) of a supervised method: a model file given by
    /// path is read by the method itself into `models`, and the parameter names the model it is
    /// stored under.
    fn store_model_files(
        method_name: &str,
        params: &mut [String],
        models: &mut method::ModelStore,
    ) -> Result<(), String> {
        let m = mocapseg::methods::find(method_name).map_err(|e| e.to_string())?;
        let (Some(supervised), Some(declared)) = (m.supervised(), m.supervision()) else { return Ok(()) };
        for p in params.iter_mut() {
            let Some(value) = p.strip_prefix("model=") else { continue };
            let value = value.trim().to_string();
            if declared.shipped.contains(&value) || !Path::new(&value).is_file() {
                continue;
            }
            let bytes = std::fs::read(&value).map_err(|e| format!("{value}: {e}"))?;
            let loaded = supervised.read_model(&value, &bytes).map_err(|e| e.to_string())?;
            *p = format!("model={}", loaded.info.name);
            models.install(loaded);
        }
        Ok(())
    }

    fn load(file: &Path) -> Result<Loaded, String> {
        load_path(file).map_err(|e| e.to_string())
    }

    /// `mocapseg model-cards`: the shipped models' cards, held-out figures from the scoreboard.
    fn model_cards(accuracy: &Path, out: &Path) -> Result<(), String> {
        let text = std::fs::read_to_string(accuracy).map_err(|e| format!("{}: {e}", accuracy.display()))?;
        let generated_by = format!("mocapseg model-cards --accuracy {} --out {}", accuracy.display(), out.display());
        let json =
            method::cards::cards_json(&text, &generated_by).map_err(|e| format!("{}: {e}", accuracy.display()))?;
        std::fs::write(out, json).map_err(|e| format!("{}: {e}", out.display()))?;
        eprintln!("wrote {}", out.display());
        Ok(())
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
        let png = img.try_to_png().map_err(|e| format!("{}: {e}", output.display()))?;
        std::fs::write(output, &png).map_err(|e| format!("{}: {e}", output.display()))?;
        eprintln!("wrote {} ({}×{} px, {} bytes)", output.display(), img.width, img.height, png.len());
        Ok(())
    }

    fn positions(file: &Path, fps: Option<f64>, end_sites: bool, output: &Path) -> Result<(), String> {
        let loaded = load(file)?;
        let motion: Motion = match fps {
            Some(f) => loaded.motion.resample(f).map_err(|e| format!("{}: {e}", file.display()))?,
            None => loaded.motion,
        };
        let out = std::fs::File::create(output).map_err(|e| format!("{}: {e}", output.display()))?;
        write_positions_csv(&motion, end_sites, std::io::BufWriter::new(out))
            .map_err(|e| format!("{}: {e}", output.display()))?;
        let cols = (0..motion.joints()).filter(|&j| end_sites || !motion.skeleton.is_end_site[j]).count();
        eprintln!("wrote {} ({} frames at {} fps, {} joints)", output.display(), motion.frames(), motion.fps, cols);
        Ok(())
    }

    /// Column names of `mocapseg features`, in the order of `src/features/end_effectors.rs`.
    const FEATURE_COLUMNS: [&str; 15] = [
        "lhand_x", "lhand_y", "lhand_z", "rhand_x", "rhand_y", "rhand_z", "lfoot_x", "lfoot_y", "lfoot_z", "rfoot_x",
        "rfoot_y", "rfoot_z", "head_x", "head_y", "head_z",
    ];

    fn features(file: &Path, fps: f64, body_scale: bool, output: &Path) -> Result<(), String> {
        let loaded = load(file)?;
        let e = mocapseg::features::end_effectors::end_effectors(&loaded.motion, fps, body_scale)
            .map_err(|e| format!("{}: {e}", file.display()))?;
        if e.base.dim() != FEATURE_COLUMNS.len() {
            return Err(format!("{}: {} features per frame, expected 15", file.display(), e.base.dim()));
        }
        let out = std::fs::File::create(output).map_err(|e| format!("{}: {e}", output.display()))?;
        let mut w = csv::Writer::from_writer(std::io::BufWriter::new(out));
        let fail = |e: csv::Error| format!("{}: {e}", output.display());
        let mut header = vec!["frame", "source_frame"];
        header.extend(FEATURE_COLUMNS);
        w.write_record(&header).map_err(fail)?;
        for i in 0..e.base.frames() {
            let mut row = vec![i.to_string(), e.source_frames[i].to_string()];
            row.extend(e.base.row(i).iter().map(|v| v.to_string()));
            w.write_record(&row).map_err(fail)?;
        }
        w.flush().map_err(|e| format!("{}: {e}", output.display()))?;
        eprintln!(
            "wrote {} ({} frames at {fps} fps from {} at {} fps, 15 features)",
            output.display(),
            e.base.frames(),
            loaded.motion.frames(),
            loaded.motion.fps
        );
        Ok(())
    }

    fn kind_text(kind: &ParamKind) -> String {
        match kind {
            ParamKind::Number { min, max } => format!("number in [{min}, {max}]"),
            ParamKind::Integer { min, max } => format!("whole number in [{min}, {max}]"),
            ParamKind::Bool => "true or false".into(),
            ParamKind::Choice { options } => format!("one of {}", options.join(", ")),
            ParamKind::IntegerList { min, max, max_len } => {
                format!("list of at most {max_len} whole numbers in [{min}, {max}], e.g. [-5,0,5]")
            }
            ParamKind::Flags { options } => format!("list of any of {}, e.g. [\"{}\"]", options.join(", "), options[0]),
        }
    }

    /// What a flag of a training table takes (lists written as the page's form writes them: comma-separated).
    fn flag_kind_text(kind: &ParamKind) -> String {
        match kind {
            ParamKind::IntegerList { min, max, max_len } => {
                format!("at most {max_len} whole numbers in [{min}, {max}], comma-separated")
            }
            ParamKind::Flags { options } => format!("any of {}, comma-separated; none: empty", options.join(", ")),
            other => kind_text(other),
        }
    }

    fn methods(json: bool) -> Result<(), String> {
        if json {
            let list: Vec<_> = mocapseg::methods::registry()
                .iter()
                .map(|m| serde_json::json!({"info": m.info(), "params": m.param_specs()}))
                .collect();
            println!("{}", serde_json::to_string_pretty(&list).map_err(|e| e.to_string())?);
            return Ok(());
        }
        for m in mocapseg::methods::registry() {
            let info = m.info();
            println!(
                "{} — {} ({})\n  {}\n  parameters (--param NAME=VALUE):",
                info.name, info.short, info.paper, info.summary
            );
            let show = |specs: Vec<method::ParamSpec>| {
                for p in specs {
                    let unit = p.unit.as_deref().map(|u| format!(" {u}")).unwrap_or_default();
                    // a `null` default: the method decides (a labeller's threshold is its model's own)
                    let default = if p.default.is_null() { "unset".to_string() } else { p.default.to_string() };
                    println!("    {:<28} default {default}{unit}; {}", p.name, kind_text(&p.kind));
                    println!("    {:<28} {}", "", p.help);
                }
            };
            show(m.param_specs());
            if let Some(decl) = m.supervision() {
                println!(
                    "  trains on a label CSV `{}` (mocapseg train --method {} …), models `.{}`, shipped: {}",
                    decl.labels_header,
                    info.name,
                    decl.model_extension,
                    decl.shipped.join(", ")
                );
                if !decl.training.is_empty() {
                    println!("  training options (--option NAME=VALUE):");
                    show(decl.training);
                }
            }
            println!();
        }
        Ok(())
    }

    /// `mocapseg train`: the method's own training, as the page's worker runs it (step by step,
    /// here without pause), on the takes and labels given; writes the model file.
    fn train(
        method_name: &str,
        inputs: &[PathBuf],
        labels: Option<&Path>,
        validation: Option<String>,
        options: &[String],
        name: Option<String>,
        out: &Path,
    ) -> Result<(), String> {
        let m = mocapseg::methods::find(method_name).map_err(|e| e.to_string())?;
        let Some(decl) = m.supervision() else {
            return Err(format!("{} has no models to train", m.info().short));
        };
        // the options as the method's table reads them (names checked against it)
        let mut given = Vec::new();
        for o in options {
            let (key, raw) = o.split_once('=').ok_or_else(|| format!("--option {o}: expected NAME=VALUE"))?;
            let key = key.trim().replace('-', "_");
            let Some(spec) = decl.training.iter().find(|s| s.name == key) else {
                let known: Vec<&str> = decl.training.iter().map(|s| s.name.as_str()).collect();
                return Err(format!(
                    "--option {key}: not a {} training option; known: {}",
                    m.info().short,
                    known.join(", ")
                ));
            };
            given.push((spec, raw.trim().to_string()));
        }
        let flag = |name: &str| format!("--option {name}");
        let json = options_json(m, given.into_iter(), flag)?;
        train_with(m, inputs, labels, validation, json, name, out, &flag)
    }

    /// A training through the method's [`method::Supervised`] interface, as the page trains — the one path
    /// for `train` and every `train-M`: on every take given (the page sends the take on screen, and the takes
    /// added where the method declares `more_takes`), with the labels, or without them where the method
    /// declares what it learns from instead, and a validation take where it declares one.
    #[allow(clippy::too_many_arguments)]
    fn train_with(
        m: &dyn DynMethod,
        inputs: &[PathBuf],
        labels: Option<&Path>,
        validation: Option<String>,
        options: serde_json::Value,
        name: Option<String>,
        out: &Path,
        flag: &dyn Fn(&str) -> String,
    ) -> Result<(), String> {
        let (Some(supervised), Some(decl)) = (m.supervised(), m.supervision()) else {
            return Err(format!("{} has no models to train", m.info().short));
        };
        if validation.is_some() && !decl.validation_take {
            return Err(format!("--validation: {} has no epochs for a validation take to choose", m.info().short));
        }
        let (labels_name, labels) = match (labels, &decl.without_labels) {
            (Some(path), _) => (
                path.file_name().map_or_else(|| path.display().to_string(), |n| n.to_string_lossy().into_owned()),
                read_text(path)?,
            ),
            (None, Some(instead)) => {
                eprintln!("no --labels: {} learns from {instead}", m.info().short);
                (String::new(), String::new())
            }
            (None, None) => return Err(format!("--labels FILE is needed (`{}`)", decl.labels_header)),
        };
        let files = collect_files(inputs, "bvh")?;
        let mut takes = Vec::new();
        for f in &files {
            let file_name = f.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
            takes.push((file_name, std::fs::read(f).map_err(|e| format!("{}: {e}", f.display()))?));
        }
        let stem = out.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "model".into());
        let ask = mocapseg::method::supervised::TrainingAsk {
            name: name.unwrap_or(stem),
            labels_name,
            labels,
            takes,
            options,
            command: Some(command_line()),
            start_from: None,
            validation,
            to_file: true,
            limits: Default::default(),
        };
        let started = Instant::now();
        let bar = ProgressBar::new(1000);
        bar.set_style(
            ProgressStyle::with_template("{bar:40} {msg}  {elapsed_precise}")
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        let mut progress = |stage: &str, fraction: f64| {
            bar.set_message(stage.to_string());
            bar.set_position((fraction.clamp(0.0, 1.0) * 1000.0) as u64);
        };
        // a refusal names the option as it was given here (`--filters`, `--option filters`), or what else it names
        let named = |e: method::MethodError| match e.param_name() {
            Some(p) if decl.training.iter().any(|s| s.name == p) => format!("{}: {e}", flag(p)),
            Some(p) => format!("{p}: {e}"),
            None => e.to_string(),
        };
        let mut training = supervised.start_training(ask, &mut progress).map_err(named)?;
        while !training.done() {
            let step = training.step(&mut progress).map_err(named)?;
            bar.suspend(|| eprintln!("{}", step.line));
            if step.steps > 1 {
                bar.set_position((step.step as f64 / step.steps as f64 * 1000.0) as u64);
            }
        }
        bar.finish_and_clear();
        let trained = training.finish().map_err(named)?;
        std::fs::write(out, &trained.bytes).map_err(|e| format!("{}: {e}", out.display()))?;
        eprintln!("{}", trained.report.summary);
        if !trained.report.rows.is_empty() {
            eprintln!("{}", trained.report.columns.join(" | "));
            for row in &trained.report.rows {
                eprintln!("{}", row.join(" | "));
            }
        }
        eprintln!(
            "wrote {} ({} `{}`, {} bytes) in {:.1} s",
            out.display(),
            m.info().short,
            trained.model.info.name,
            trained.bytes.len(),
            started.elapsed().as_secs_f64()
        );
        Ok(())
    }

    /// The `train-M` commands, one per method with models: the takes, the labels, the model file, and a
    /// flag per row of the method's training table (`--NAME VALUE`; help, bounds and default from the row,
    /// as the page's training form shows them), and `--validation` where the method declares a validation take.
    fn training_commands() -> Vec<clap::Command> {
        use clap::{value_parser, Arg};
        mocapseg::methods::registry()
            .iter()
            .filter_map(|m| {
                let decl = m.supervision()?;
                let info = m.info();
                let mut command = clap::Command::new(format!("train-{}", info.name))
                    .about(format!(
                        "Train {} on labelled takes and write its model file (`segment --method {} --model FILE` reads it). Every training option is a flag made from the method's table (`mocapseg methods` lists it; the page's training form has the same rows); `train --method {} --option NAME=VALUE` is the same training.",
                        info.short, info.name, info.name
                    ))
                    .arg(
                        Arg::new("bvh")
                            .long("bvh")
                            .required(true)
                            .num_args(1..)
                            .value_name("FILE|DIR")
                            .value_parser(value_parser!(PathBuf))
                            .help("BVH files and/or folders (takes the labels do not name are skipped, and said)"),
                    )
                    .arg(
                        Arg::new("labels")
                            .long("labels")
                            .value_name("CSV")
                            .value_parser(value_parser!(PathBuf))
                            .required(decl.without_labels.is_none())
                            .help(match &decl.without_labels {
                                None => format!("The label CSV `{}`", decl.labels_header),
                                Some(instead) => format!(
                                    "The label CSV `{}`; without it, {} learns from {instead}",
                                    decl.labels_header, info.short
                                ),
                            }),
                    )
                    .args(decl.validation_take.then(|| {
                        Arg::new("validation").long("validation").value_name("TAKE").help(
                            "One of the takes given, kept out of the training: its validation loss chooses a network's \
                             epoch (early stopping, --patience), and with --choose-decoding (the default) its labels \
                             choose the model's decoding and unknown threshold; default none",
                        )
                    }))
                    .arg(
                        Arg::new("out")
                            .long("out")
                            .short('o')
                            .required(true)
                            .value_name("FILE")
                            .value_parser(value_parser!(PathBuf))
                            .help("The model file to write"),
                    )
                    .arg(Arg::new("name").long("name").value_name("NAME").help("The model's name (default: the model file's stem)"));
                for spec in &decl.training {
                    let unit = spec.unit.as_deref().map(|u| format!(" {u}")).unwrap_or_default();
                    command = command.arg(
                        Arg::new(spec.name.clone())
                            .long(spec.name.replace('_', "-"))
                            .value_name("VALUE")
                            .allow_negative_numbers(true)
                            .help(format!(
                                "{} [{}; default {}{unit}]",
                                spec.help,
                                flag_kind_text(&spec.kind),
                                method::form::field_text(&spec.default)
                            )),
                    );
                }
                Some(command)
            })
            .collect()
    }

    /// The training options of `specs` given as NAME / text pairs, read as the page's form reads its fields
    /// (`flag`: how a refusal names the option on this command line).
    fn options_json<'a>(
        m: &dyn DynMethod,
        given: impl Iterator<Item = (&'a method::ParamSpec, String)>,
        flag: impl Fn(&str) -> String,
    ) -> Result<serde_json::Value, String> {
        let mut json = serde_json::Map::new();
        for (spec, text) in given {
            let value = method::form::params_from_form(&m.info().short, std::slice::from_ref(spec), &[text])
                .map_err(|e| format!("{}: {e}", flag(&spec.name)))?;
            json.insert(spec.name.clone(), value[&spec.name].clone());
        }
        Ok(serde_json::Value::Object(json))
    }

    /// `mocapseg train-M …`: the table's flags read into the options JSON, then the method's training.
    fn train_from_flags(method_name: &str, args: &clap::ArgMatches) -> Result<(), String> {
        let m = mocapseg::methods::find(method_name).map_err(|e| e.to_string())?;
        let decl = m.supervision().ok_or_else(|| format!("{method_name} has no models to train"))?;
        let given =
            decl.training.iter().filter_map(|spec| args.get_one::<String>(&spec.name).map(|text| (spec, text.clone())));
        let flag = |name: &str| format!("--{}", name.replace('_', "-"));
        let options = options_json(m, given, flag)?;
        let bvh: Vec<PathBuf> = args.get_many::<PathBuf>("bvh").into_iter().flatten().cloned().collect();
        let labels = args.get_one::<PathBuf>("labels").cloned();
        let validation = args.try_get_one::<String>("validation").ok().flatten().cloned();
        let out = args.get_one::<PathBuf>("out").cloned().ok_or("--out FILE is needed")?;
        let name = args.get_one::<String>("name").cloned();
        train_with(m, &bvh, labels.as_deref(), validation, options, name, &out, &flag)
    }

    /// The command line as typed (for a model's provenance), an argument with a space quoted.
    fn command_line() -> String {
        let mut shown = vec!["mocapseg".to_string()];
        shown.extend(std::env::args().skip(1).map(|a| if a.contains(' ') { format!("'{a}'") } else { a }));
        shown.join(" ")
    }

    /// `mocapseg effort SEG.json TAKE [--lma-model FILE] [-o OUT]`: through LMA's annotator, as the page's Effort
    /// bars are (the same checks of the take and of what the annotation will hold).
    fn effort(segmentation: &Path, take: &Path, family: Option<&Path>, out: Option<&Path>) -> Result<(), String> {
        let text = read_text(segmentation)?;
        let mut seg = Segmentation::from_json(&text).map_err(|e| format!("{}: {e}", segmentation.display()))?;
        let motion = load(take)?.motion;
        if seg.frames != motion.frames() {
            return Err(format!(
                "{} segments {} frames but {} has {}: give the take it was made from",
                segmentation.display(),
                seg.frames,
                take.display(),
                motion.frames()
            ));
        }
        let lma = mocapseg::methods::find("lma").map_err(|e| e.to_string())?;
        let mut models = mocapseg::method::ModelStore::new();
        let params = match family {
            Some(path) => {
                let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
                let file = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
                let loaded = lma
                    .supervised()
                    .ok_or("LMA reads no families")?
                    .read_model(&file, &bytes)
                    .map_err(|e| format!("{}: {e}", path.display()))?;
                let name = loaded.info.name.clone();
                models.install(loaded);
                serde_json::json!({ "model": name })
            }
            None => serde_json::json!({}),
        };
        let checked = lma.check_json_in(&params, &models).map_err(|e| e.to_string())?;
        let annotations = lma
            .annotate_checked(
                &motion,
                &checked,
                &seg.segments,
                &mocapseg::method::WorkLimits::default(),
                &mut NoProgress,
            )
            .map_err(|e| format!("{}: {e}", take.display()))?;
        let efforts = annotations.segments.into_iter().map(|a| a.effort);
        let mut given = 0;
        for (s, e) in seg.segments.iter_mut().zip(efforts) {
            if s.effort.is_none() {
                s.effort = e;
                given += usize::from(e.is_some());
            }
        }
        let json = seg.to_json();
        match out {
            Some(path) => std::fs::write(path, json + "\n").map_err(|e| format!("{}: {e}", path.display()))?,
            None => println!("{json}"),
        }
        eprintln!("{given} of {} segments given their Effort", seg.segments.len());
        Ok(())
    }

    fn read_text(path: &Path) -> Result<String, String> {
        std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))
    }

    pub(crate) use mocapseg::load::collect_files;

    fn labels(truth: &[PathBuf], options: TruthOptions, out: Option<PathBuf>) -> Result<(), String> {
        let mut rows = Vec::new();
        for path in truth {
            let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
            let (converted, skipped) =
                mocapseg::labels::from_truth_csv(&text, options).map_err(|e| format!("{}: {e}", path.display()))?;
            for why in skipped {
                eprintln!("skipped {}: {why}", path.display());
            }
            eprintln!("{}: {} labelled segments", path.display(), converted.len());
            rows.extend(converted);
        }
        let text = mocapseg::labels::to_csv(&rows);
        match out {
            Some(path) => std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display())),
            None => {
                print!("{text}");
                Ok(())
            }
        }
    }

    fn gait(inputs: &[PathBuf], out: Option<PathBuf>, within: Option<(PathBuf, String)>) -> Result<(), String> {
        use mocapseg::labels::gait::{gait_of, runs, GaitParams};
        use mocapseg::labels::{to_csv, LabelRow};
        let mut rows = Vec::new();
        let mut failed = 0;
        for f in collect_files(inputs, "bvh")? {
            let labelled = load(&f).and_then(|l| gait_of(&l.motion, &GaitParams::default()).map(|g| (l.motion, g)));
            match labelled {
                Ok((motion, labels)) => {
                    let spans = runs(&labels);
                    let mut seconds: Vec<(&str, f64)> = Vec::new();
                    for &(s, e, g) in &spans {
                        match seconds.iter_mut().find(|x| x.0 == g.name()) {
                            Some(x) => x.1 += (e + 1 - s) as f64 / motion.fps,
                            None => seconds.push((g.name(), (e + 1 - s) as f64 / motion.fps)),
                        }
                        rows.push(LabelRow {
                            file: motion.name.clone(),
                            start_frame: s,
                            end_frame: e,
                            label: g.name().into(),
                        });
                    }
                    let summary: Vec<String> = seconds.iter().map(|(n, s)| format!("{n} {s:.1} s")).collect();
                    eprintln!("ok    {}  {} segments: {}", f.display(), spans.len(), summary.join(", "));
                }
                Err(e) => {
                    failed += 1;
                    eprintln!("FAIL  {}: {e}", f.display());
                }
            }
        }
        if let Some((path, label)) = within {
            let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
            let spans = mocapseg::labels::read_csv(&text, &path.display().to_string())?;
            rows = mocapseg::labels::within(&rows, &spans, &label);
            eprintln!("kept {} rows inside the `{label}` segments of {}", rows.len(), path.display());
        }
        let text = to_csv(&rows);
        match out {
            Some(path) => std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))?,
            None => print!("{text}"),
        }
        if failed > 0 && rows.is_empty() {
            return Err("no take could be labelled".into());
        }
        Ok(())
    }

    fn stem(path: &Path) -> String {
        path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "take".into())
    }

    /// The indices of `names` that share their name with another, ignoring case, group by group.
    fn alike(names: &[String]) -> Vec<Vec<usize>> {
        let mut groups: Vec<(String, Vec<usize>)> = Vec::new();
        let mut at: HashMap<String, usize> = HashMap::new();
        for (i, name) in names.iter().enumerate() {
            let key = name.to_lowercase();
            let g = *at.entry(key.clone()).or_insert_with(|| {
                groups.push((key, Vec::new()));
                groups.len() - 1
            });
            groups[g].1.push(i);
        }
        groups.into_iter().map(|(_, g)| g).filter(|g| g.len() > 1).collect()
    }

    /// Output names `<stem>.json`, one per take and no two alike even where case is ignored (as
    /// macOS and Windows folders ignore it): takes of one stem are told apart by their folders below
    /// the folder they share (`a/x.bvh`, `b/x.bvh` → `a_x.json`, `b_x.json`), then by their
    /// extension (`x.bvh`, `x.amc` → `x_bvh.json`, `x_amc.json`), then by a number (`walk.bvh`,
    /// `walk.BVH` → `walk.json`, `walk_2.json`) that no other take's name has.
    /// `reserved`: names besides (a summary's, `clusters.json`) that no take's may take, compared as the names are.
    pub(crate) fn output_names(files: &[PathBuf], reserved: &[&str]) -> Vec<String> {
        use std::collections::HashSet;
        use std::path::Component;
        let mut names: Vec<String> = files.iter().map(|f| stem(f)).collect();
        let folders: Vec<Vec<String>> = files
            .iter()
            .map(|f| {
                let parent = f.parent().map(|p| p.components()).into_iter().flatten();
                parent
                    .filter_map(|c| match c {
                        Component::Normal(s) => Some(s.to_string_lossy().into_owned()),
                        _ => None,
                    })
                    .collect()
            })
            .collect();
        for group in alike(&names) {
            let first = &folders[group[0]];
            let shared = group
                .iter()
                .map(|&i| first.iter().zip(&folders[i]).take_while(|(a, b)| a == b).count())
                .min()
                .unwrap_or(0);
            for &i in &group {
                let below = &folders[i][shared..];
                if !below.is_empty() {
                    names[i] = format!("{}_{}", below.join("_"), names[i]);
                }
            }
        }
        let extension = |f: &Path| f.extension().map(|e| e.to_string_lossy().into_owned()).unwrap_or_default();
        for group in alike(&names) {
            let kinds: HashSet<String> = group.iter().map(|&i| extension(&files[i]).to_lowercase()).collect();
            if kinds.len() > 1 {
                for &i in &group {
                    names[i] = format!("{}_{}", names[i], extension(&files[i]));
                }
            }
        }
        let reserved: Vec<String> =
            reserved.iter().map(|r| r.strip_suffix(".json").unwrap_or(r).to_lowercase()).collect();
        let all: HashSet<String> = names.iter().map(|n| n.to_lowercase()).chain(reserved.iter().cloned()).collect();
        let mut used: HashSet<String> = reserved.into_iter().collect();
        for name in &mut names {
            if used.insert(name.to_lowercase()) {
                continue;
            }
            let numbered = (2..)
                .map(|n| format!("{name}_{n}"))
                .find(|c| !all.contains(&c.to_lowercase()) && used.insert(c.to_lowercase()))
                .unwrap_or_default();
            *name = numbered;
        }
        names.into_iter().map(|n| format!("{n}.json")).collect()
    }

    /// A method's message about `take` (its motion's name) after `file`, the path the user gave:
    /// the messages that start with the take's name (k-NN, DT-FCN) do not name it twice.
    fn run_error(file: &Path, take: &str, message: &str) -> String {
        let own = message.strip_prefix(take).and_then(|m| m.strip_prefix(": ")).unwrap_or(message);
        format!("{}: {own}", file.display())
    }

    fn segment(
        inputs: &[PathBuf],
        method_name: &str,
        overrides: &[String],
        models: &method::ModelStore,
        out: Option<PathBuf>,
        jobs: Option<usize>,
    ) -> Result<Outcome, String> {
        let method = mocapseg::methods::find(method_name).map_err(|e| e.to_string())?;
        let params = method::params_from_overrides(method, overrides).map_err(|e| e.to_string())?;
        let checked = method.check_json_in(&params, models).map_err(|e| e.to_string())?;
        let files = collect_files(inputs, "bvh")?;
        let single = inputs.len() == 1 && !inputs[0].is_dir();
        match out {
            None if single => {
                let loaded = load(&files[0])?;
                let name = Path::new(&loaded.motion.name);
                let output = method
                    .run_checked(&loaded.motion, &checked, &RunOptions::default(), &mut NoProgress)
                    .map_err(|e| run_error(name, &loaded.motion.name, &e.to_string()))?;
                println!("{}", output.segmentation.to_json());
                if let Some(note) = fit_note(&output.details) {
                    eprintln!("{}: {note}", name.display());
                }
                Ok(Outcome::Ok)
            }
            None => Err("several takes: give a folder for their segmentations with --out DIR".into()),
            Some(dir) => batch(method, &checked, &files, &dir, jobs),
        }
    }

    /// What a labelling run says about a take its model does not fit (the segmentation JSON has
    /// every frame `unknown` then): the reason and the method's models that fit the take instead.
    fn fit_note(details: &method::Details) -> Option<String> {
        let fit = details.take_fit.as_ref().filter(|f| !f.fits)?;
        Some(format!(
            "model `{}` does not fit this take ({}), every frame is labelled unknown; {}",
            fit.model,
            fit.reason,
            fit.advice().unwrap_or_default()
        ))
    }

    /// Writes `text` to `path` whole or not at all: into a temporary file in the same folder (a
    /// rename within one file system is atomic), flushed to disk, then renamed over `path`. A reader
    /// sees the earlier file or the new one, never a part of one; a write that fails (a full disk, a
    /// file-size limit) leaves no temporary file behind (`tempfile` removes it when dropped).
    pub(crate) fn write_atomically(path: &Path, text: &str) -> Result<(), String> {
        use std::io::Write;
        let dir = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
        let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        let prefix = format!(".{name}.");
        let mut builder = tempfile::Builder::new();
        builder.prefix(&prefix).suffix(".tmp");
        // the mode a plain write gives (0666 less the umask), not tempfile's private 0600
        #[cfg(unix)]
        builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o666));
        let mut file = builder.tempfile_in(dir).map_err(|e| format!("{}: cannot write there: {e}", dir.display()))?;
        file.write_all(text.as_bytes())
            .and_then(|()| file.as_file().sync_all())
            .map_err(|e| format!("{}: {e}", path.display()))?;
        file.persist(path).map_err(|e| format!("{}: {}", path.display(), e.error))?;
        Ok(())
    }

    /// One take of a batch: load, segment, write; the summary line and the take's frames.
    /// A take of a batch or library, loaded: its errors name the path, not only the file name (the loader's), so
    /// that takes of one name in several folders are told apart.
    pub(crate) fn load_at(file: &Path) -> Result<Loaded, String> {
        load(file).map_err(|e| {
            let name = file.file_name().map(|n| format!("{}: ", n.to_string_lossy())).unwrap_or_default();
            match e.strip_prefix(&name) {
                Some(rest) if !name.is_empty() => format!("{}: {rest}", file.display()),
                _ => e,
            }
        })
    }

    fn segment_one(
        method: &dyn DynMethod,
        checked: &CheckedParams,
        file: &Path,
        out: &Path,
    ) -> Result<(String, usize), String> {
        let started = Instant::now();
        let loaded = load_at(file)?;
        let output = method
            .run_checked(&loaded.motion, checked, &RunOptions::default(), &mut NoProgress)
            .map_err(|e| run_error(file, &loaded.motion.name, &e.to_string()))?;
        let seg = &output.segmentation;
        write_atomically(out, &seg.to_json())?;
        let counts: Vec<String> = [Level::Action, Level::Transition, Level::Primitive]
            .iter()
            .map(|&l| (l, seg.level(l).count()))
            .filter(|(_, n)| *n > 0)
            .map(|(l, n)| format!("{}s {n}", serde_json::to_value(l).unwrap_or_default().as_str().unwrap_or("?")))
            .collect();
        let mut line = format!(
            "ok    {}  {} frames at {} fps  {}  {:.2} s → {}",
            file.display(),
            seg.frames,
            seg.fps,
            counts.join(", "),
            started.elapsed().as_secs_f64(),
            out.display()
        );
        if let Some(note) = fit_note(&output.details) {
            line.push_str(&format!("  — {note}"));
        }
        Ok((line, seg.frames))
    }

    /// How one take of a batch ended.
    enum Ended {
        /// Written: its line and frames.
        Written(String, usize),
        /// Refused or failed with this message.
        Failed(String),
        /// Panicked with this message (a bug in mocapseg).
        Panicked(String),
    }

    thread_local! {
        /// Set while a thread runs a take of a batch: its panics are caught and reported there.
        static IN_TAKE: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
        /// Where the last panic of a take on this thread happened (the hook sees it, the payload not).
        static PANIC_AT: std::cell::RefCell<Option<String>> = const { std::cell::RefCell::new(None) };
    }

    /// The message a panic was raised with.
    pub(crate) fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
        payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "a panic without a message".into())
    }

    /// Test hook, for the test of the batch's guarantee that a panicking take is reported and
    /// skipped while the rest are written (`tests/cli.rs`), since no input is known to make a method
    /// panic: in a debug build only (`cfg(debug_assertions)`; a release build has no such hook), a
    /// batch panics on the take whose file name is `MOCAPSEG_TEST_PANIC_ON`, before loading it.
    #[cfg(debug_assertions)]
    fn test_panic_hook(file: &Path) {
        let name = file.file_name().map(|n| n.to_string_lossy().into_owned());
        if name.is_some() && std::env::var("MOCAPSEG_TEST_PANIC_ON").ok() == name {
            panic!("MOCAPSEG_TEST_PANIC_ON: a panic on {} asked for by the test", file.display());
        }
    }

    /// `work` on the take `file` with its panics caught: its result, or (`Err`) the panic's message and where it
    /// happened — a panic ends that take, not the batch. Inside [`with_batch_hook`], the default hook stays quiet.
    pub(crate) fn caught<T>(
        file: &Path,
        work: impl FnOnce() -> Result<T, String>,
    ) -> Result<Result<T, String>, String> {
        IN_TAKE.with(|t| t.set(true));
        let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            #[cfg(debug_assertions)]
            test_panic_hook(file);
            work()
        }));
        IN_TAKE.with(|t| t.set(false));
        outcome.map_err(|payload| {
            let at = PANIC_AT.with(|p| p.borrow_mut().take()).map(|at| format!(" (at {at})")).unwrap_or_default();
            format!("{}: panicked: {}{at}", file.display(), panic_message(payload.as_ref()))
        })
    }

    /// One take, its panics caught.
    fn run_take(method: &dyn DynMethod, checked: &CheckedParams, file: &Path, out: &Path) -> Ended {
        match caught(file, || segment_one(method, checked, file, out)) {
            Ok(Ok((line, frames))) => Ended::Written(line, frames),
            Ok(Err(message)) => Ended::Failed(message),
            Err(message) => Ended::Panicked(message),
        }
    }

    /// Runs `work` (a batch) with a panic hook that reports a take's panic on the take's line and in the summary,
    /// with where it happened, instead of the default hook's lines through the progress bar; other threads' panics
    /// (none expected) still go to the default hook, which is back once `work` returns.
    pub(crate) fn with_batch_hook<R>(work: impl FnOnce() -> R) -> R {
        let default_hook = std::sync::Arc::new(std::panic::take_hook());
        let other = default_hook.clone();
        std::panic::set_hook(Box::new(move |info| {
            if IN_TAKE.with(|t| t.get()) {
                let at = info.location().map(|l| format!("{}:{}:{}", l.file(), l.line(), l.column()));
                PANIC_AT.with(|p| *p.borrow_mut() = at);
            } else {
                other(info)
            }
        }));
        let out = work();
        let _ = std::panic::take_hook();
        if let Ok(hook) = std::sync::Arc::try_unwrap(default_hook) {
            std::panic::set_hook(hook);
        }
        out
    }

    /// Removes `out`, an earlier run's output for a take that has none now (it would read as this run's); what was
    /// done, for the take's message (`None`: there was none).
    pub(crate) fn remove_stale(out: &Path) -> Option<String> {
        match std::fs::remove_file(out) {
            Ok(()) => Some(format!("{} of an earlier run removed", out.display())),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
            Err(e) => Some(format!("{} of an earlier run NOT removed: {e}", out.display())),
        }
    }

    fn batch(
        method: &dyn DynMethod,
        checked: &CheckedParams,
        files: &[PathBuf],
        dir: &Path,
        jobs: Option<usize>,
    ) -> Result<Outcome, String> {
        if files.is_empty() {
            return Err("no .bvh files found in the inputs".into());
        }
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        let names = output_names(files, &[]);
        let threads = jobs.unwrap_or_else(rayon::current_num_threads).max(1);
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().map_err(|e| e.to_string())?;
        let bar = ProgressBar::new(files.len() as u64);
        bar.set_style(
            ProgressStyle::with_template("{bar:40} {pos}/{len} takes  {elapsed_precise}  eta {eta}")
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        let frames = AtomicUsize::new(0);
        let started = Instant::now();
        let ended: Vec<(Ended, Option<String>)> = with_batch_hook(|| {
            pool.install(|| {
                files
                    .par_iter()
                    .zip(&names)
                    .map(|(file, name)| {
                        let out = dir.join(name);
                        let ended = run_take(method, checked, file, &out);
                        // a take without a segmentation now leaves none: an earlier run's would read as this one's
                        let stale = match &ended {
                            Ended::Written(..) => None,
                            Ended::Failed(_) | Ended::Panicked(_) => remove_stale(&out),
                        };
                        let note = stale.as_ref().map(|s| format!(" ({s})")).unwrap_or_default();
                        match &ended {
                            Ended::Written(line, n) => {
                                frames.fetch_add(*n, Ordering::Relaxed);
                                bar.suspend(|| println!("{line}"));
                            }
                            Ended::Failed(message) => bar.suspend(|| println!("FAIL  {message}{note}")),
                            Ended::Panicked(message) => bar.suspend(|| println!("PANIC {message}{note}")),
                        }
                        bar.inc(1);
                        (ended, stale)
                    })
                    .collect()
            })
        });
        bar.finish_and_clear();
        let seconds = started.elapsed().as_secs_f64();
        let listed = |panics: bool| -> Vec<String> {
            ended
                .iter()
                .filter_map(|(e, stale)| {
                    let message = match (e, panics) {
                        (Ended::Failed(m), false) | (Ended::Panicked(m), true) => m,
                        _ => return None,
                    };
                    Some(format!("  {message}{}", stale.as_ref().map(|s| format!(" ({s})")).unwrap_or_default()))
                })
                .collect()
        };
        let (failed, panicked) = (listed(false), listed(true));
        let done = files.len() - failed.len() - panicked.len();
        let mut problems = Vec::new();
        if !failed.is_empty() {
            problems.push(format!("{} failed", failed.len()));
        }
        if !panicked.is_empty() {
            problems.push(format!("{} panicked", panicked.len()));
        }
        eprintln!(
            "{} {}: {done} of {} takes segmented{} in {seconds:.1} s on {threads} threads: {:.2} takes/s, {:.0} frames/s",
            method.info().name,
            dir.display(),
            files.len(),
            problems.iter().map(|p| format!(", {p}")).collect::<String>(),
            done as f64 / seconds,
            frames.into_inner() as f64 / seconds
        );
        if !failed.is_empty() {
            eprintln!("failed (not written):\n{}", failed.join("\n"));
        }
        if !panicked.is_empty() {
            eprintln!("panicked (not written; a bug in mocapseg, please report it):\n{}", panicked.join("\n"));
        }
        let outcome = if !panicked.is_empty() {
            Outcome::Panicked
        } else if !failed.is_empty() {
            Outcome::Partial
        } else {
            Outcome::Ok
        };
        eprintln!(
            "exit code {}",
            match outcome {
                Outcome::Ok => "0: every take written",
                Outcome::Partial => "2: some takes failed, the rest written",
                Outcome::Panicked => "3: some take panicked, the rest written",
            }
        );
        Ok(outcome)
    }

    fn eval(predictions: &[PathBuf], truth_path: &Path, options: &ImportOptions, json: bool) -> Result<(), String> {
        let files = collect_files(predictions, "json")?;
        if files.is_empty() {
            return Err("no segmentation .json files in the inputs".into());
        }
        let truth_text = read_text(truth_path)?;
        let mut rows = Vec::new();
        for path in &files {
            let seg = Segmentation::from_json(&read_text(path)?).map_err(|e| format!("{}: {e}", path.display()))?;
            let take = Take { name: seg.file.clone(), frames: seg.frames, fps: seg.fps };
            let imported =
                import_truth(&truth_text, &take, options).map_err(|e| format!("{}: {e}", truth_path.display()))?;
            if imported.applied.converted
                || imported.applied.trial.as_ref().is_some_and(|t| t.1 == TrialChoice::OnlyOne)
            {
                let segments = imported.truth.segments.len();
                eprintln!("note: {}: {}", truth_path.display(), imported.applied.describe(segments));
            }
            let truth = imported.truth;
            let scores = evaluate(&seg, &truth, &mocapseg::methods::scoring(&seg.method))
                .map_err(|e| format!("{}: {e}", path.display()))?;
            rows.push(Row { scores, found_actions: report::scored_segments(&seg), seconds: None });
        }
        let single = predictions.len() == 1 && !predictions[0].is_dir();
        if single && !json {
            println!("{}", serde_json::to_string_pretty(&rows[0].scores).map_err(|e| e.to_string())?);
        } else if json {
            let list: Vec<_> = rows.iter().map(|r| &r.scores).collect();
            println!("{}", serde_json::to_string_pretty(&list).map_err(|e| e.to_string())?);
        } else {
            print!("{}", report::markdown(&rows, &[]));
        }
        Ok(())
    }

    fn splice(bvh: &[PathBuf], labels: &[PathBuf], options: SpliceOptions, out: &Path) -> Result<(), String> {
        let files = collect_files(bvh, "bvh")?;
        let label_texts: Vec<(PathBuf, String)> =
            labels.iter().map(|p| read_text(p).map(|t| (p.clone(), t))).collect::<Result<_, _>>()?;
        let mut takes = Vec::new();
        for f in &files {
            let text = read_text(f)?;
            let parsed = bvh::parse(&text).map_err(|e| format!("{}: {e}", f.display()))?;
            let trial = stem(f);
            let truth = label_texts
                .iter()
                .find_map(|(_, t)| load_csv(t, &trial, TruthOptions::default()).ok())
                .ok_or_else(|| format!("{}: no labels for trial `{trial}` in the --labels files", f.display()))?;
            takes.push((trial, parsed, truth));
        }
        let sources: Vec<Source> = takes.iter().map(|(n, b, t)| Source { name: n, bvh: b, truth: t }).collect();
        let spliced = mocapseg::splice::splice(&sources, &options).map_err(|e| e.to_string())?;
        let csv_path = out.with_extension("csv");
        std::fs::write(out, bvh::write(&spliced.bvh)).map_err(|e| format!("{}: {e}", out.display()))?;
        std::fs::write(&csv_path, spliced.truth_csv(&stem(out))).map_err(|e| format!("{}: {e}", csv_path.display()))?;
        eprintln!(
            "wrote {} ({} pieces, {} frames) and its ground truth {}",
            out.display(),
            spliced.pieces.len(),
            spliced.bvh.frames(),
            csv_path.display()
        );
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
        stats::median(&mut v).unwrap_or(f64::NAN)
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
