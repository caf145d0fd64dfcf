//! `mocapseg cluster` and `mocapseg transfer`: a library of takes on the command line (`mocapseg::library`). Every
//! take is loaded and segmented on all cores (a bad file is reported and skipped), its features kept; then the
//! library is matched at once.

use std::path::{Path, PathBuf};
use std::time::Instant;

use indicatif::{ProgressBar, ProgressStyle};
use mocapseg::labels::{read_csv, to_csv, LabelRow};
use mocapseg::library::{cluster, transfer, KnowledgeBase, LibraryParams, LibraryTake, TakeFeatures, TransferRoute};
use mocapseg::load::collect_files;
use mocapseg::method::{self, Cancelled, CheckedParams, DynMethod, NoProgress, RunOptions};
use mocapseg::methods::lma::corpus::same_file;
use rayon::prelude::*;
use serde_json::json;

/// How a library command ended: how many takes failed (each reported).
pub struct Ended {
    pub failed: usize,
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

/// Every take of `files` (on all cores, a progress bar), the failures as messages; the takes keep the files' order.
fn library(
    args: &LibraryFlags,
    files: &[PathBuf],
    params: &LibraryParams,
) -> Result<(Vec<(PathBuf, LibraryTake)>, Vec<String>), String> {
    let method = mocapseg::methods::find(&args.method).map_err(|e| e.to_string())?;
    let json = method::params_from_overrides(method, &args.params).map_err(|e| e.to_string())?;
    let checked = method.check_json(&json).map_err(|e| e.to_string())?;
    if files.is_empty() {
        return Err("no .bvh files found in the inputs".into());
    }
    let threads = args.jobs.unwrap_or_else(rayon::current_num_threads).max(1);
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().map_err(|e| e.to_string())?;
    let bar = ProgressBar::new(files.len() as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} takes segmented  {elapsed_precise}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let results: Vec<Result<LibraryTake, String>> = pool.install(|| {
        files
            .par_iter()
            .map(|file| {
                let r =
                    std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| take_of(file, method, &checked, params)))
                        .unwrap_or_else(|p| {
                            Err(format!("{}: panicked: {}", file.display(), crate::cli::panic_message(p.as_ref())))
                        });
                match &r {
                    Ok(t) => {
                        bar.suspend(|| println!("ok    {}  {} segments", file.display(), t.segmentation.segments.len()))
                    }
                    Err(m) => bar.suspend(|| println!("FAIL  {m}")),
                }
                bar.inc(1);
                r
            })
            .collect()
    });
    bar.finish_and_clear();
    let mut takes = Vec::new();
    let mut failed = Vec::new();
    for (file, r) in files.iter().zip(results) {
        match r {
            Ok(t) => takes.push((file.clone(), t)),
            Err(m) => failed.push(m),
        }
    }
    Ok((takes, failed))
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

/// The output file names of `takes` (their stems; repeated stems numbered).
fn names(takes: &[(PathBuf, LibraryTake)]) -> Vec<String> {
    let mut used: Vec<String> = Vec::new();
    takes
        .iter()
        .map(|(file, _)| {
            let stem = file.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "take".into());
            let mut name = stem.clone();
            let mut k = 2;
            while used.iter().any(|u| u.eq_ignore_ascii_case(&name)) {
                name = format!("{stem}-{k}");
                k += 1;
            }
            used.push(name.clone());
            name
        })
        .collect()
}

fn write(path: &Path, text: &str) -> Result<(), String> {
    std::fs::write(path, text).map_err(|e| format!("{}: {e}", path.display()))
}

fn report_failures(failed: &[String]) {
    if !failed.is_empty() {
        eprintln!(
            "failed (left out of the library):\n{}",
            failed.iter().map(|m| format!("  {m}")).collect::<Vec<_>>().join("\n")
        );
    }
}

/// `mocapseg cluster`: one segmentation JSON per take whose cluster ids are shared, and `clusters.json`.
pub fn cluster_command(inputs: &[PathBuf], args: &LibraryFlags, out: &Path) -> Result<Ended, String> {
    let started = Instant::now();
    let params = args.params(LibraryParams::default())?;
    let files = collect_files(inputs, "bvh")?;
    let (takes, failed) = library(args, &files, &params)?;
    report_failures(&failed);
    if takes.is_empty() {
        return Err("no take could be segmented: nothing to cluster".into());
    }
    let library: Vec<LibraryTake> = takes.iter().map(|(_, t)| t.clone()).collect();
    let shared = matching(|progress| cluster(&library, &params, progress))?;
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let names = names(&takes);
    for (name, seg) in names.iter().zip(&shared.takes) {
        write(&out.join(format!("{name}.json")), &seg.to_json())?;
    }
    let mut order: Vec<&mocapseg::library::SharedCluster> = shared.clusters.iter().collect();
    order.sort_by(|a, b| b.seconds.total_cmp(&a.seconds).then(a.id.cmp(&b.id)));
    let summary = json!({
        "method": &args.method,
        "params": params,
        "takes": names,
        "failed": failed,
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
    write(&out.join("clusters.json"), &serde_json::to_string_pretty(&summary).map_err(|e| e.to_string())?)?;
    println!("cluster  takes  occurrences  seconds");
    for c in order.iter().filter(|c| c.takes > 1).take(20) {
        println!("C{:<7} {:>5}  {:>11}  {:>7.1}", c.id, c.takes, c.occurrences.len(), c.seconds);
    }
    eprintln!(
        "{} of {} takes clustered into {} clusters ({} in more than one take) in {:.1} s → {}",
        takes.len(),
        files.len(),
        shared.clusters.len(),
        shared.shared().count(),
        started.elapsed().as_secs_f64(),
        out.display()
    );
    Ok(Ended { failed: failed.len() })
}

/// `mocapseg transfer`: the labels of one take carried to every other; one JSON per take and one label CSV.
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
    let (takes, failed) = library(args, &files, &params)?;
    report_failures(&failed);
    let source = takes
        .iter()
        .position(|(f, _)| f == from)
        .ok_or_else(|| format!("{}: the labelled take could not be segmented (see above)", from.display()))?;
    let labelled = &takes[source].1;
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
    let library: Vec<LibraryTake> = takes.iter().map(|(_, t)| t.clone()).collect();
    let kb = KnowledgeBase { take: source, frame_labels };
    let done = matching(|progress| transfer(&library, &kb, route, &params, progress))?;
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let names = names(&takes);
    let mut csv_rows = Vec::new();
    for ((name, (file, _)), t) in names.iter().zip(&takes).zip(&done.takes) {
        write(&out.join(format!("{name}.json")), &t.segmentation.to_json())?;
        let file_name = file.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| name.clone());
        let known: usize = t.frame_labels.iter().flatten().count();
        println!(
            "{:<24} {:>5.1} % labelled  {}",
            name,
            100.0 * known as f64 / t.frame_labels.len().max(1) as f64,
            if file == from { "(the labelled take)" } else { "" }
        );
        for s in t.segmentation.segments.iter().filter(|s| s.label != mocapseg::library::transfer::UNKNOWN) {
            csv_rows.push(LabelRow {
                file: file_name.clone(),
                start_frame: s.start,
                end_frame: s.end,
                label: s.label.clone(),
            });
        }
    }
    write(&out.join("labels.csv"), &to_csv(&csv_rows))?;
    eprintln!(
        "labels of {} carried to {} takes ({:?}) in {:.1} s → {} (one JSON per take, labels.csv)",
        labelled.name,
        takes.len() - 1,
        route,
        started.elapsed().as_secs_f64(),
        out.display()
    );
    Ok(Ended { failed: failed.len() })
}
