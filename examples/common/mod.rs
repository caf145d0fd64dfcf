//! What the lab's examples share (not an example itself: cargo only builds `main.rs` in an
//! examples subfolder): the labelled takes of the shared data and the exit of a `main`.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use mocapseg::segment::truth::{load_csv, Truth, TruthOptions};

/// A labelled take of the shared data: its BVH and its ground truth.
pub struct LabelledTake {
    pub trial: &'static str,
    pub bvh: PathBuf,
    pub truth: Truth,
}

/// CMU 86_01 (Barbič/Zhou labels) and the four mocap6 takes (Fox/Hughes labels) that are present
/// under `data`; an error saying so when the folder is not the shared data or holds none of them.
pub fn labelled_takes(data: &Path) -> Result<Vec<LabelledTake>, String> {
    if !data.join("labels").is_dir() {
        return Err(format!(
            "{}: no shared data here (expected labels/ and cmu/ as in ../shared/data); pass --data DIR",
            data.display()
        ));
    }
    let mut list = vec![("86_01", data.join("cmu/86/86_01.bvh"), data.join("labels/cmu86_zhou_gt.csv"))];
    for t in ["13_29", "13_30", "13_31", "14_14"] {
        list.push((t, data.join(format!("cmu/mocap6/{t}.bvh")), data.join("labels/mocap6_gt.csv")));
    }
    let mut takes = Vec::new();
    for (trial, bvh, labels) in list {
        if !bvh.exists() {
            eprintln!("skipping {trial}: {} is absent", bvh.display());
            continue;
        }
        let text = std::fs::read_to_string(&labels).map_err(|e| format!("{}: {e}", labels.display()))?;
        let truth =
            load_csv(&text, trial, TruthOptions::default()).map_err(|e| format!("{}: {e}", labels.display()))?;
        takes.push(LabelledTake { trial, bvh, truth });
    }
    if takes.is_empty() {
        return Err(format!("{}: none of the labelled takes is present", data.display()));
    }
    Ok(takes)
}

/// The exit of an example's `main`: success, or the message on stderr and code 1.
pub fn exit(result: Result<(), String>) -> ExitCode {
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}

/// The by-class table of a leave-one-class-out experiment: per class left out, the number of folds and, for each
/// unknown in `columns`, the mean share of unseen and of seen frames it called unknown. `sums[c]` holds the sums of
/// those shares, unknown by unknown (unseen, seen), then the fold count last.
pub fn print_rates_by_class<const N: usize>(columns: &[&str], classes: &[String], sums: &[[f64; N]]) {
    println!("| class left out | folds | {} |", columns.join(" | "));
    println!("|---|---|{}", "---|".repeat(columns.len()));
    for (c, s) in sums.iter().enumerate().filter(|(_, s)| s[N - 1] > 0.0) {
        let folds = s[N - 1];
        let cells: Vec<String> = (0..columns.len())
            .map(|k| format!("{:.0} % / {:.0} %", 100.0 * s[2 * k] / folds, 100.0 * s[2 * k + 1] / folds))
            .collect();
        println!("| {} | {folds} | {} |", classes[c], cells.join(" | "));
    }
}

/// The threshold that calls the share `share` of `scores` unknown: the scores below it when `low` (a confidence),
/// above it otherwise (a distance); none called unknown when there are no scores.
pub fn threshold_for_share(mut scores: Vec<f32>, share: f64, low: bool) -> f32 {
    scores.sort_by(f32::total_cmp);
    let k = ((scores.len() as f64 * share) as usize).min(scores.len().saturating_sub(1));
    let at = if low { k } else { scores.len().saturating_sub(1 + k) };
    scores.get(at).copied().unwrap_or(if low { 0.0 } else { f32::INFINITY })
}

/// `values` over their (upper) median, the median taken as 1 when it is not positive.
pub fn over_median(values: &[f32]) -> Vec<f32> {
    let m = mocapseg::stats::median(&mut values.to_vec()).filter(|m| *m > 0.0).unwrap_or(1.0);
    values.iter().map(|v| v / m).collect()
}
