//! `mocapseg cluster` and `mocapseg transfer`: a library of takes on the command line (`mocapseg::library`). Every
//! take is loaded and segmented on all cores (a bad file is reported and skipped), its features kept; then the
//! library is matched at once.

use std::path::{Path, PathBuf};
use std::time::Instant;

use indicatif::{ProgressBar, ProgressStyle};
use mocapseg::labels::same_file;
use mocapseg::labels::{read_csv, to_csv, LabelRow};
use mocapseg::library::{cluster, transfer, KnowledgeBase, LibraryParams, LibraryTake, TakeFeatures, TransferRoute};
use mocapseg::load::collect_files;
use mocapseg::method::{self, Cancelled, CheckedParams, DynMethod, NoProgress, RunOptions};
use rayon::prelude::*;
use serde_json::json;

/// How a library command ended: how many takes failed and how many panicked (each reported).
pub struct Ended {
    pub failed: usize,
    pub panicked: usize,
}

/// What the library commands share: the method whose segments are matched and the library's settings.
#[derive(clap::Args)]
pub struct LibraryFlags {
    /// The method whose segments are matched (`mocapseg methods`).
    #[arg(long, default_value = "sssm")]
    pub method: String,
    /// A parameter of the method as NAME=VALUE (JSON value); repeatable.
    #[arg(long = "param", value_name = "NAME=VALUE")]
    pub params: Vec<String>,
    /// The library's search radius R, inches of the reference body (cluster: 13, the SSSM's primitive radius;
    /// transfer: 30 by nearest, 20 through clusters — chosen by nested validation, docs/library.md).
    #[arg(long)]
    pub radius: Option<f64>,
    /// Fraction a warping path must cover to join two segments (cluster: 0.4 of both; transfer: 0.4 of the
    /// unlabelled one by nearest, of both through clusters).
    #[arg(long)]
    pub coverage: Option<f64>,
    /// Takes segmented at once (default: one per core).
    #[arg(long)]
    pub jobs: Option<usize>,
}

impl LibraryFlags {
    fn params(&self, base: LibraryParams) -> Result<LibraryParams, String> {
        let mut p = base;
        if let Some(r) = self.radius {
            p.radius = r;
        }
        if let Some(c) = self.coverage {
            p.coverage = c;
        }
        p.check().map_err(|e| e.to_string())?;
        Ok(p)
    }
}

/// One take of the library: loaded, segmented, its features made.
fn take_of(
    file: &Path,
    method: &dyn DynMethod,
    checked: &CheckedParams,
    params: &LibraryParams,
) -> Result<LibraryTake, String> {
    let loaded = crate::cli::load_at(file)?;
    let output = method
        .run_checked(&loaded.motion, checked, &RunOptions::default(), &mut NoProgress)
        .map_err(|e| format!("{}: {e}", file.display()))?;
    let features = TakeFeatures::of(&loaded.motion, params).map_err(|e| format!("{}: {e}", file.display()))?;
    Ok(LibraryTake { name: loaded.motion.name.clone(), features, segmentation: output.segmentation })
}

/// A take of the library, segmented: its file, its output's name in the output folder (`<stem>.json`) and itself.
struct Member {
    file: PathBuf,
    out_name: String,
    take: LibraryTake,
}

/// The takes left out of the library: each message (with what became of an earlier run's output of the take), and
/// which panicked.
#[derive(Default)]
struct LeftOut {
    failed: Vec<String>,
    panicked: Vec<String>,
}

impl LeftOut {
    /// Says which takes were left out and why, as `segment` does; the command's tally.
    fn report(&self) -> Ended {
        let list = |m: &[String]| m.iter().map(|m| format!("  {m}")).collect::<Vec<_>>().join("\n");
        if !self.failed.is_empty() {
            eprintln!("failed (left out of the library):\n{}", list(&self.failed));
        }
        if !self.panicked.is_empty() {
            eprintln!(
                "panicked (left out of the library; a bug in mocapseg, please report it):\n{}",
                list(&self.panicked)
            );
        }
        Ended { failed: self.failed.len(), panicked: self.panicked.len() }
    }

    /// Every message, failed and panicked (the summary file's `failed`).
    fn all(&self) -> Vec<String> {
        self.failed.iter().chain(&self.panicked).cloned().collect()
    }
}

/// Every take of `files` (on all cores, a progress bar), in the files' order, each with its output's name in `out`
/// (no two alike, none of `reserved`: the command's own files); a take that failed or panicked is left out, said
/// why, and its output of an earlier run in `out` removed (it would read as this run's).
fn library(
    args: &LibraryFlags,
    files: &[PathBuf],
    params: &LibraryParams,
    out: &Path,
    reserved: &[&str],
) -> Result<(Vec<Member>, LeftOut), String> {
    let method = mocapseg::methods::find(&args.method).map_err(|e| e.to_string())?;
    let json = method::params_from_overrides(method, &args.params).map_err(|e| e.to_string())?;
    let checked = method.check_json(&json).map_err(|e| e.to_string())?;
    if files.is_empty() {
        return Err("no .bvh files found in the inputs".into());
    }
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let names = crate::cli::output_names(files, reserved);
    let threads = args.jobs.unwrap_or_else(rayon::current_num_threads).max(1);
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().map_err(|e| e.to_string())?;
    let bar = ProgressBar::new(files.len() as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} takes segmented  {elapsed_precise}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let results: Vec<Result<Result<LibraryTake, String>, String>> = crate::cli::with_batch_hook(|| {
        pool.install(|| {
            files
                .par_iter()
                .zip(&names)
                .map(|(file, name)| {
                    let r = crate::cli::caught(file, || take_of(file, method, &checked, params));
                    let stale = match &r {
                        Ok(Ok(_)) => None,
                        _ => crate::cli::remove_stale(&out.join(name)),
                    };
                    let note = stale.map(|s| format!(" ({s})")).unwrap_or_default();
                    let r = match r {
                        Ok(Ok(t)) => {
                            bar.suspend(|| {
                                println!("ok    {}  {} segments", file.display(), t.segmentation.segments.len())
                            });
                            Ok(Ok(t))
                        }
                        Ok(Err(m)) => {
                            bar.suspend(|| println!("FAIL  {m}{note}"));
                            Ok(Err(format!("{m}{note}")))
                        }
                        Err(m) => {
                            bar.suspend(|| println!("PANIC {m}{note}"));
                            Err(format!("{m}{note}"))
                        }
                    };
                    bar.inc(1);
                    r
                })
                .collect()
        })
    });
    bar.finish_and_clear();
    let mut members = Vec::new();
    let mut left = LeftOut::default();
    for ((file, out_name), r) in files.iter().zip(names).zip(results) {
        match r {
            Ok(Ok(take)) => members.push(Member { file: file.clone(), out_name, take }),
            Ok(Err(m)) => left.failed.push(m),
            Err(m) => left.panicked.push(m),
        }
    }
    Ok((members, left))
}

/// Runs the matching step `work` (clustering or transfer) with a bar of its fraction done, its error as text.
fn matching<T, E: std::fmt::Display>(
    work: impl FnOnce(&mut dyn FnMut(f64) -> Result<(), Cancelled>) -> Result<T, E>,
) -> Result<T, String> {
    let bar = ProgressBar::new(100);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} matching the library {percent} %")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let done = work(&mut |f| {
        bar.set_position((100.0 * f) as u64);
        Ok(())
    })
    .map_err(|e| e.to_string());
    bar.finish_and_clear();
    done
}

/// The summary `cluster` writes beside the takes' segmentations (no take's output takes its name).
const CLUSTERS_FILE: &str = "clusters.json";

/// A take's output name without `.json` (the summary's name of the take).
fn stem(out_name: &str) -> &str {
    out_name.strip_suffix(".json").unwrap_or(out_name)
}

/// `mocapseg cluster`: one segmentation JSON per take whose cluster ids are shared, and `clusters.json`. Every file
/// written whole or not at all; a take left out leaves no output of an earlier run behind.
pub fn cluster_command(inputs: &[PathBuf], args: &LibraryFlags, out: &Path) -> Result<Ended, String> {
    let started = Instant::now();
    let params = args.params(LibraryParams::default())?;
    let files = collect_files(inputs, "bvh")?;
    let (members, left) = library(args, &files, &params, out, &[CLUSTERS_FILE])?;
    let ended = left.report();
    if members.is_empty() {
        return Err("no take could be segmented: nothing to cluster".into());
    }
    let library: Vec<LibraryTake> = members.iter().map(|m| m.take.clone()).collect();
    let shared = matching(|progress| cluster(&library, &params, progress))?;
    for (m, seg) in members.iter().zip(&shared.takes) {
        crate::cli::write_atomically(&out.join(&m.out_name), &seg.to_json())?;
    }
    let names: Vec<&str> = members.iter().map(|m| stem(&m.out_name)).collect();
    let mut order: Vec<&mocapseg::library::SharedCluster> = shared.clusters.iter().collect();
    order.sort_by(|a, b| b.seconds.total_cmp(&a.seconds).then(a.id.cmp(&b.id)));
    let summary = json!({
        "method": &args.method,
        "params": params,
        "takes": names,
        "failed": left.all(),
        "cross_links": shared.cross_links,
        "clusters": order.iter().map(|c| json!({
            "id": c.id,
            "label": format!("C{}", c.id),
            "takes": c.takes,
            "seconds": c.seconds,
            "occurrences": c.occurrences.iter().map(|o| json!({
                "take": names[o.take], "segment": o.segment, "start": o.start, "end": o.end,
                "seconds": (o.end + 1 - o.start) as f64 / shared.takes[o.take].fps,
            })).collect::<Vec<_>>(),
        })).collect::<Vec<_>>(),
    });
    let text = serde_json::to_string_pretty(&summary).map_err(|e| e.to_string())?;
    crate::cli::write_atomically(&out.join(CLUSTERS_FILE), &text)?;
    println!("cluster  takes  occurrences  seconds");
    for c in order.iter().filter(|c| c.takes > 1).take(20) {
        println!("C{:<7} {:>5}  {:>11}  {:>7.1}", c.id, c.takes, c.occurrences.len(), c.seconds);
    }
    eprintln!(
        "{} of {} takes clustered into {} clusters ({} in more than one take) in {:.1} s → {}",
        members.len(),
        files.len(),
        shared.clusters.len(),
        shared.shared().count(),
        started.elapsed().as_secs_f64(),
        out.display()
    );
    Ok(ended)
}

/// The label CSV `transfer` writes beside the takes' segmentations.
const LABELS_FILE: &str = "labels.csv";

/// `mocapseg transfer`: the labels of one take carried to every other; one JSON per take and one label CSV, each
/// written whole or not at all; a take left out leaves no output of an earlier run behind.
pub fn transfer_command(
    inputs: &[PathBuf],
    args: &LibraryFlags,
    labels: &Path,
    from: &Path,
    route: TransferRoute,
    out: &Path,
) -> Result<Ended, String> {
    let started = Instant::now();
    let params = args.params(LibraryParams::for_route(route))?;
    let mut files = collect_files(inputs, "bvh")?;
    if !files.iter().any(|f| f == from) {
        files.insert(0, from.to_path_buf());
    }
    let text = std::fs::read_to_string(labels).map_err(|e| format!("{}: {e}", labels.display()))?;
    let rows = read_csv(&text, &labels.display().to_string())?;
    let (members, left) = library(args, &files, &params, out, &[])?;
    let ended = left.report();
    let source = members
        .iter()
        .position(|m| m.file == from)
        .ok_or_else(|| format!("{}: the labelled take could not be segmented (see above)", from.display()))?;
    let labelled = &members[source].take;
    let mut frame_labels = vec![None; labelled.features.file_frames];
    let mut used = 0;
    for row in rows.iter().filter(|r| same_file(&r.file, &labelled.name)) {
        if row.end_frame >= frame_labels.len() || row.start_frame > row.end_frame {
            return Err(format!(
                "{}: the row {},{},{} is outside {} (frames 0–{})",
                labels.display(),
                row.file,
                row.start_frame,
                row.end_frame,
                labelled.name,
                frame_labels.len().saturating_sub(1)
            ));
        }
        frame_labels[row.start_frame..=row.end_frame].iter_mut().for_each(|l| *l = Some(row.label.clone()));
        used += 1;
    }
    if used == 0 {
        return Err(format!("{}: no row names the labelled take {}", labels.display(), labelled.name));
    }
    let library: Vec<LibraryTake> = members.iter().map(|m| m.take.clone()).collect();
    let kb = KnowledgeBase { take: source, frame_labels };
    let done = matching(|progress| transfer(&library, &kb, route, &params, progress))?;
    let mut csv_rows = Vec::new();
    for (m, t) in members.iter().zip(&done.takes) {
        crate::cli::write_atomically(&out.join(&m.out_name), &t.segmentation.to_json())?;
        let name = stem(&m.out_name);
        let file_name = m.file.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| name.into());
        let known: usize = t.frame_labels.iter().flatten().count();
        println!(
            "{:<24} {:>5.1} % labelled  {}",
            name,
            100.0 * known as f64 / t.frame_labels.len().max(1) as f64,
            if m.file == from { "(the labelled take)" } else { "" }
        );
        for s in t.segmentation.segments.iter().filter(|s| s.label != mocapseg::segment::UNKNOWN) {
            csv_rows.push(LabelRow {
                file: file_name.clone(),
                start_frame: s.start,
                end_frame: s.end,
                label: s.label.clone(),
            });
        }
    }
    crate::cli::write_atomically(&out.join(LABELS_FILE), &to_csv(&csv_rows))?;
    eprintln!(
        "labels of {} carried to {} takes ({:?}) in {:.1} s → {} (one JSON per take, {LABELS_FILE})",
        labelled.name,
        members.len() - 1,
        route,
        started.elapsed().as_secs_f64(),
        out.display()
    );
    Ok(ended)
}
