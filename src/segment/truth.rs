//! Ground-truth segmentations read from CSV, as shipped with the CMU 86 and mocap6 labels.
//!
//! The CSV needs the columns `trial`, `label`, `start_frame`, `end_frame`; it may have `trial_frames`,
//! `end_window_lo` and `end_window_hi` (the annotator's uncertainty window around a segment's end).
//! Frames in those files are **1-based inclusive AMC frame numbers**; the converted BVHs have no T-pose row, so
//! BVH row = frame − 1. [`TruthOptions::first_frame`] says which number the file's first frame has, and
//! [`TruthOptions::bvh_row_offset`] covers BVHs that prepend a T-pose row (cgspeed MotionBuilder files: +1).

use serde::{Deserialize, Serialize};

/// One labelled span, in 0-based inclusive BVH rows.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TruthSegment {
    pub start: usize,
    pub end: usize,
    pub label: String,
    /// Uncertainty window around this segment's end boundary (0-based rows, inclusive), if the file gives one.
    pub end_window: Option<(usize, usize)>,
}

/// The ground truth of one trial.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Truth {
    pub trial: String,
    /// Number of frames of the trial (from `trial_frames`, else the last segment's end + 1).
    pub frames: usize,
    pub segments: Vec<TruthSegment>,
}

impl Truth {
    /// The ground truth of `parts` played one after another (each part's frames shifted by the
    /// frames of the parts before it), as trial `trial`.
    /// Frame numbers saturate at `usize::MAX` rather than overflow (parts read by [`load_csv`]
    /// have at most [`MAX_FRAMES`] frames each, so that takes 2^39 of them).
    pub fn concatenate(trial: &str, parts: &[Truth]) -> Truth {
        let mut segments = Vec::new();
        let mut shift: usize = 0;
        for part in parts {
            segments.extend(part.segments.iter().map(|s| TruthSegment {
                start: s.start.saturating_add(shift),
                end: s.end.saturating_add(shift),
                label: s.label.clone(),
                end_window: s.end_window.map(|(lo, hi)| (lo.saturating_add(shift), hi.saturating_add(shift))),
            }));
            shift = shift.saturating_add(part.frames);
        }
        Truth { trial: trial.to_string(), frames: shift, segments }
    }

    /// Per frame: the index of its segment's label among `classes`, a label not yet there appended in order of first
    /// appearance (so several takes read in turn share one list); `None` for a frame no segment covers. What a
    /// labeller is trained on and scored against, from a take's truth.
    pub fn class_frames(&self, classes: &mut Vec<String>) -> Vec<Option<usize>> {
        let mut out = vec![None; self.frames];
        for s in &self.segments {
            let c = classes.iter().position(|c| *c == s.label).unwrap_or_else(|| {
                classes.push(s.label.clone());
                classes.len() - 1
            });
            if let Some(frames) = out.get_mut(s.start..=s.end.min(self.frames.saturating_sub(1))) {
                frames.iter_mut().for_each(|l| *l = Some(c));
            }
        }
        out
    }
}

/// How frame numbers in the CSV relate to BVH rows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TruthOptions {
    /// The number the CSV gives the first frame (1 for AMC frame numbers).
    pub first_frame: usize,
    /// Rows the BVH has before the CSV's first frame (1 for a prepended T-pose row).
    pub bvh_row_offset: usize,
}

impl Default for TruthOptions {
    fn default() -> Self {
        TruthOptions { first_frame: 1, bvh_row_offset: 0 }
    }
}

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TruthError {
    #[error("ground truth CSV: missing column `{0}` in the header line")]
    MissingColumn(&'static str),
    #[error("ground truth CSV line {line}: {message}")]
    Line { line: usize, message: String },
    #[error("ground truth CSV: no rows for trial `{trial}` (trials present: {present})")]
    NoTrial { trial: String, present: String },
}

/// The longest take, in frames, whose ground truth can be read: a take the tool loads has at most
/// [`MAX_POSITIONS`](crate::motion::MAX_POSITIONS) joint positions, so at most that many frames.
/// Bounding every frame number by it keeps all arithmetic on them far from overflow.
pub const MAX_FRAMES: usize = crate::motion::MAX_POSITIONS;

/// One CSV row: only the columns this module reads (every other column is ignored). Values stay
/// text so that a bad number gets an error naming its column and value.
#[derive(Debug, Deserialize)]
struct Row {
    trial: String,
    label: String,
    start_frame: String,
    end_frame: String,
    #[serde(default)]
    trial_frames: Option<String>,
    #[serde(default)]
    end_window_lo: Option<String>,
    #[serde(default)]
    end_window_hi: Option<String>,
}

const REQUIRED: [&str; 4] = ["trial", "label", "start_frame", "end_frame"];

fn line_error(line: usize, message: String) -> TruthError {
    TruthError::Line { line, message }
}

fn csv_error(e: &csv::Error) -> TruthError {
    let line = e.position().map_or(0, |p| p.line() as usize);
    let message = match e.kind() {
        csv::ErrorKind::Deserialize { err, .. } => err.to_string(),
        _ => e.to_string(),
    };
    line_error(line, message)
}

/// A whole frame number (`550`, or `550.0` as spreadsheets write it; a fraction is cut) that
/// is at least `first` and at most `first +` [`MAX_FRAMES`].
pub(super) fn frame_number(raw: &str, what: &str, first: usize, line: usize) -> Result<usize, TruthError> {
    let value = match raw.parse::<u64>() {
        Ok(v) => v as f64,
        Err(_) => match raw.parse::<f64>() {
            Ok(v) if v.is_finite() => v.floor(),
            _ => return Err(line_error(line, format!("expected a frame number in `{what}`, found `{raw}`"))),
        },
    };
    if value < first as f64 {
        return Err(line_error(line, format!("`{what}` = {raw} is before the first frame {first}")));
    }
    if value - first as f64 >= MAX_FRAMES as f64 {
        return Err(line_error(
            line,
            format!("`{what}` = {raw} is past the longest take this tool reads ({MAX_FRAMES} frames)"),
        ));
    }
    Ok(value as usize - first)
}

/// `row` + `offset`, or an error naming the column (so no frame number can overflow).
fn shifted(row: usize, offset: usize, what: &str, line: usize) -> Result<usize, TruthError> {
    row.checked_add(offset).filter(|&r| r < MAX_FRAMES).ok_or_else(|| {
        line_error(
            line,
            format!("`{what}` plus the BVH row offset {offset} is past the longest take ({MAX_FRAMES} frames)"),
        )
    })
}

/// Reads the segments of `trial` from a ground-truth CSV (RFC 4180: quoted fields may hold
/// commas, quotes and line breaks; blank lines are skipped; extra columns are ignored).
/// Errors name the file's line.
pub fn load_csv(text: &str, trial: &str, options: TruthOptions) -> Result<Truth, TruthError> {
    match load_csv_lines(text, trial, options)? {
        (Some(read), _) => Ok(read.truth),
        (None, present) => Err(TruthError::NoTrial { trial: trial.to_string(), present: present.join(", ") }),
    }
}

/// One trial as [`load_csv_lines`] reads it.
#[derive(Debug, Clone, PartialEq)]
pub struct TrialRead {
    pub truth: Truth,
    /// The file line of each segment, in the order of [`Truth::segments`].
    pub lines: Vec<usize>,
    /// Whether the file gives the trial's length (`trial_frames`); else `truth.frames` is the
    /// last segment's end + 1.
    pub frames_given: bool,
}

/// [`load_csv`] that also says where each segment comes from ([`TrialRead`]), or `None` when
/// the file has no rows for `trial`; and the names of every trial the file has, in the order
/// it first names them.
pub fn load_csv_lines(
    text: &str,
    trial: &str,
    options: TruthOptions,
) -> Result<(Option<TrialRead>, Vec<String>), TruthError> {
    let (mut trials, present) = read_trials_lines(text, options, Some(trial))?;
    match trials.pop() {
        Some((_, read)) => Ok((Some(read?), present)),
        None => Ok((None, present)),
    }
}

/// Every trial of a ground-truth CSV, in the order the file first names them, each read as
/// [`load_csv`] reads it (a trial with a bad row gets that row's error) — in one pass over the
/// file, however many trials it has. Errors that concern the whole file (its header, a row too
/// short or not CSV) are the `Err`.
pub fn load_all_csv(text: &str, options: TruthOptions) -> Result<TrialTruths, TruthError> {
    let (trials, _) = read_trials_lines(text, options, None)?;
    Ok(trials.into_iter().map(|(name, read)| (name, read.map(|r| r.truth))).collect())
}

/// Each trial's name and its ground truth, or why it could not be read.
pub type TrialTruths = Vec<(String, Result<Truth, TruthError>)>;

/// One trial being read.
struct Reading {
    segments: Vec<TruthSegment>,
    /// The file line of each segment.
    lines: Vec<usize>,
    frames: Option<usize>,
    /// Its first bad row's error; its later rows are not read.
    error: Option<TruthError>,
}

/// The trials of the file (only `only` when given, its first bad row failing the call) and the
/// names of all trials the file has.
type TrialLines = Vec<(String, Result<TrialRead, TruthError>)>;

fn read_trials_lines(
    text: &str,
    options: TruthOptions,
    only: Option<&str>,
) -> Result<(TrialLines, Vec<String>), TruthError> {
    let mut reader = csv::ReaderBuilder::new().trim(csv::Trim::All).flexible(true).from_reader(text.as_bytes());
    let headers = reader.headers().map_err(|e| csv_error(&e))?.clone();
    let position = |name: &str| headers.iter().position(|h| h == name);
    let mut width = 0;
    for name in REQUIRED {
        width = width.max(position(name).ok_or(TruthError::MissingColumn(name))? + 1);
    }

    let mut names: Vec<String> = Vec::new();
    let mut index: std::collections::HashMap<String, usize> = std::collections::HashMap::new();
    let mut reading: Vec<Reading> = Vec::new();
    let mut record = csv::StringRecord::new();
    loop {
        match reader.read_record(&mut record) {
            Ok(true) => {}
            Ok(false) => break,
            Err(e) => return Err(csv_error(&e)),
        }
        let line = record.position().map_or(0, |p| p.line() as usize);
        if record.iter().all(str::is_empty) {
            continue; // a line of blanks
        }
        if record.len() < width {
            return Err(line_error(line, format!("expected at least {width} fields, found {}", record.len())));
        }
        let row: Row = record.deserialize(Some(&headers)).map_err(|e| csv_error(&e))?;
        let at = match index.get(&row.trial) {
            Some(&at) => at,
            None => {
                index.insert(row.trial.clone(), names.len());
                names.push(row.trial.clone());
                reading.push(Reading { segments: Vec::new(), lines: Vec::new(), frames: None, error: None });
                names.len() - 1
            }
        };
        if only.is_some_and(|t| t != row.trial) || reading[at].error.is_some() {
            continue;
        }
        if let Err(e) = read_row(&row, line, options, &mut reading[at]) {
            if only.is_some() {
                return Err(e);
            }
            reading[at].error = Some(e);
        }
    }
    let trials = names
        .iter()
        .zip(reading)
        .filter(|(name, r)| only.is_none_or(|t| t == name.as_str()) && (r.error.is_some() || !r.segments.is_empty()))
        .map(|(name, r)| (name.clone(), finish(name, r)))
        .collect();
    Ok((trials, names))
}

/// Adds one row of a trial.
fn read_row(row: &Row, line: usize, options: TruthOptions, trial: &mut Reading) -> Result<(), TruthError> {
    let number = |raw: &str, what: &str| -> Result<usize, TruthError> {
        let n = frame_number(raw, what, options.first_frame, line)?;
        shifted(n, options.bvh_row_offset, what, line)
    };
    let (start, end) = (number(&row.start_frame, "start_frame")?, number(&row.end_frame, "end_frame")?);
    if end < start {
        return Err(line_error(line, "end_frame is before start_frame".to_string()));
    }
    let end_window = match (row.end_window_lo.as_deref(), row.end_window_hi.as_deref()) {
        (Some(lo), Some(hi)) if !lo.is_empty() && !hi.is_empty() => {
            let (a, b) = (number(lo, "end_window_lo")?, number(hi, "end_window_hi")?);
            Some((a.min(b), a.max(b)))
        }
        _ => None,
    };
    if let Some(raw) = row.trial_frames.as_deref().filter(|r| !r.is_empty()) {
        let n: usize = raw
            .parse()
            .map_err(|_| line_error(line, format!("expected a frame count in `trial_frames`, found `{raw}`")))?;
        trial.frames = Some(n.checked_add(options.bvh_row_offset).filter(|&f| f <= MAX_FRAMES).ok_or_else(|| {
            line_error(
                line,
                format!("`trial_frames` = {raw} is past the longest take this tool reads ({MAX_FRAMES} frames)"),
            )
        })?);
    }
    trial.segments.push(TruthSegment { start, end, label: row.label.clone(), end_window });
    trial.lines.push(line);
    Ok(())
}

/// A trial read: its segments in order with their lines, and its frames, or its first bad row's error.
fn finish(name: &str, r: Reading) -> Result<TrialRead, TruthError> {
    if let Some(e) = r.error {
        return Err(e);
    }
    let mut pairs: Vec<(TruthSegment, usize)> = r.segments.into_iter().zip(r.lines).collect();
    pairs.sort_by_key(|(s, _)| s.start);
    let (segments, lines): (Vec<TruthSegment>, Vec<usize>) = pairs.into_iter().unzip();
    // every end < MAX_FRAMES, so + 1 cannot overflow
    let last_end = segments.iter().map(|s| s.end).max().unwrap_or(0);
    let frames = r.frames.unwrap_or(last_end + 1).max(last_end + 1);
    Ok(TrialRead {
        truth: Truth { trial: name.to_string(), frames, segments },
        lines,
        frames_given: r.frames.is_some(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two takes read in turn share one class list (first appearance first); uncovered frames and a segment past
    /// the last frame are no panic.
    #[test]
    fn class_frames_index_the_labels_in_order_of_first_appearance() {
        let seg = |start, end, label: &str| TruthSegment { start, end, label: label.into(), end_window: None };
        let a = Truth { trial: "a".into(), frames: 6, segments: vec![seg(0, 1, "Jog"), seg(3, 5, "Squat")] };
        let b = Truth { trial: "b".into(), frames: 4, segments: vec![seg(0, 1, "Squat"), seg(2, 9, "Twist")] };
        let mut classes = Vec::new();
        assert_eq!(a.class_frames(&mut classes), [Some(0), Some(0), None, Some(1), Some(1), Some(1)]);
        assert_eq!(b.class_frames(&mut classes), [Some(1), Some(1), Some(2), Some(2)]);
        assert_eq!(classes, ["Jog", "Squat", "Twist"]);
        let empty = Truth { trial: "e".into(), frames: 0, segments: vec![seg(0, 0, "Jog")] };
        assert_eq!(empty.class_frames(&mut classes), Vec::<Option<usize>>::new());
    }

    const CMU: &str = "trial,seg_index,label,start_frame,end_frame,n_frames,end_window_lo,end_window_mid,end_window_hi,trial_frames,fps,mocap_in_repo,flag\n\
86_01,0,walk,1,550,550,500,550,600,4579,120,yes,\n\
86_01,1,jump,551,1150,600,1100,1150,1200,4579,120,yes,\n\
86_02,0,walk,1,1010,1010,980,1010,1100,10617,120,no,\n";

    #[test]
    fn concatenated_trials_shift_by_the_frames_before_them() {
        let a = load_csv(CMU, "86_01", TruthOptions::default()).unwrap();
        let b = load_csv(CMU, "86_02", TruthOptions::default()).unwrap();
        let both = Truth::concatenate("86_01+02", &[a.clone(), b]);
        assert_eq!(both.frames, 4579 + 10617);
        assert_eq!(both.segments.len(), 3);
        assert_eq!(both.segments[..2], a.segments[..]);
        let last = &both.segments[2];
        assert_eq!((last.start, last.end, last.label.as_str()), (4579, 4579 + 1009, "walk"));
        assert_eq!(last.end_window, Some((4579 + 979, 4579 + 1099)));
    }

    #[test]
    fn all_trials_in_one_pass_read_as_each_alone_and_a_bad_row_fails_only_its_trial() {
        let text = format!("{CMU}86_03,0,walk,0,10,11,,,,,120,no,\n86_04,0,run,5,9,5,,,,20,120,no,\n");
        let all = load_all_csv(&text, TruthOptions::default()).unwrap();
        let names: Vec<&str> = all.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, ["86_01", "86_02", "86_03", "86_04"]);
        for (name, truth) in &all {
            assert_eq!(truth, &load_csv(&text, name, TruthOptions::default()), "{name}");
        }
        let bad = all[2].1.as_ref().unwrap_err().to_string();
        assert!(bad.contains("line 5") && bad.contains("before the first frame 1"), "{bad}");
        assert_eq!(all[3].1.as_ref().unwrap().frames, 20);
    }

    #[test]
    fn one_based_amc_frames_become_zero_based_rows() {
        let t = load_csv(CMU, "86_01", TruthOptions::default()).unwrap();
        assert_eq!(t.frames, 4579);
        assert_eq!(t.segments.len(), 2);
        assert_eq!((t.segments[0].start, t.segments[0].end), (0, 549));
        assert_eq!((t.segments[1].start, t.segments[1].end), (550, 1149));
        assert_eq!(t.segments[0].end_window, Some((499, 599)));
        assert_eq!(t.segments[1].label, "jump");
    }

    #[test]
    fn t_pose_offset_shifts_rows() {
        let o = TruthOptions { first_frame: 1, bvh_row_offset: 1 };
        let t = load_csv(CMU, "86_01", o).unwrap();
        assert_eq!((t.segments[0].start, t.segments[0].end), (1, 550));
        assert_eq!(t.frames, 4580);
    }

    #[test]
    fn errors_name_the_problem() {
        let e = load_csv(CMU, "86_99", TruthOptions::default()).unwrap_err();
        assert_eq!(e.to_string(), "ground truth CSV: no rows for trial `86_99` (trials present: 86_01, 86_02)");
        let e = load_csv("trial,label,start_frame\n", "x", TruthOptions::default()).unwrap_err();
        assert_eq!(e, TruthError::MissingColumn("end_frame"));
        let bad = "trial,label,start_frame,end_frame\nA,walk,one,5\n";
        let e = load_csv(bad, "A", TruthOptions::default()).unwrap_err();
        assert_eq!(e.to_string(), "ground truth CSV line 2: expected a frame number in `start_frame`, found `one`");
        let short = "trial,label,start_frame,end_frame\nA,walk,1,5\nA,walk\n";
        let e = load_csv(short, "A", TruthOptions::default()).unwrap_err();
        assert_eq!(e.to_string(), "ground truth CSV line 3: expected at least 4 fields, found 2");
        let e = load_csv("", "A", TruthOptions::default()).unwrap_err();
        assert_eq!(e, TruthError::MissingColumn("trial"));
    }

    #[test]
    fn quoted_fields_may_hold_commas_quotes_and_line_breaks() {
        // What a CSV writer produces for such labels; the hand-written reader split them.
        let mut w = csv::Writer::from_writer(Vec::new());
        w.write_record(["trial", "label", "start_frame", "end_frame", "trial_frames"]).unwrap();
        w.write_record(["86,01", "walk, then \"run\"", "1", "10", "30"]).unwrap();
        w.write_record(["86,01", "two\nlines", "11", "30", "30"]).unwrap();
        let text = String::from_utf8(w.into_inner().unwrap()).unwrap();
        assert!(text.contains("\"walk, then \"\"run\"\"\""), "{text}");
        let t = load_csv(&text, "86,01", TruthOptions::default()).unwrap();
        assert_eq!(t.frames, 30);
        let labels: Vec<&str> = t.segments.iter().map(|s| s.label.as_str()).collect();
        assert_eq!(labels, ["walk, then \"run\"", "two\nlines"]);
        assert_eq!((t.segments[1].start, t.segments[1].end), (10, 29));
    }

    #[test]
    fn errors_give_the_file_line_past_quoted_line_breaks_and_blank_lines() {
        let text = "\n trial , label,start_frame,end_frame\n\nA,\"two\nlines\",1,5\n   \nA,walk,x,9\n";
        let e = load_csv(text, "A", TruthOptions::default()).unwrap_err();
        assert_eq!(e.to_string(), "ground truth CSV line 7: expected a frame number in `start_frame`, found `x`");
        let ok = load_csv(&text.replace(",x,", ",6,"), "A", TruthOptions::default()).unwrap();
        assert_eq!(ok.segments.len(), 2);
        let e = load_csv("trial,label,start_frame,end_frame\nA,\"open,1,5\n", "A", TruthOptions::default());
        assert!(e.is_err(), "{e:?}");
    }

    #[test]
    fn huge_frame_numbers_are_errors_not_overflows() {
        let head = "trial,label,start_frame,end_frame,trial_frames\n";
        for (row, what) in [
            ("A,walk,1,18446744073709551615,", "`end_frame` = 18446744073709551615 is past the longest take"),
            ("A,walk,1,99999999999999999999999,", "`end_frame` = 99999999999999999999999 is past the longest take"),
            ("A,walk,1,1e300,", "`end_frame` = 1e300 is past the longest take"),
            ("A,walk,1,5,18446744073709551615", "`trial_frames` = 18446744073709551615 is past the longest take"),
        ] {
            let e = load_csv(&format!("{head}{row}\n"), "A", TruthOptions::default()).unwrap_err();
            assert!(e.to_string().starts_with(&format!("ground truth CSV line 2: {what}")), "{e}");
        }
        // The offsets are checked too.
        let last = MAX_FRAMES.to_string();
        let o = TruthOptions { first_frame: 1, bvh_row_offset: usize::MAX };
        let e = load_csv(&format!("{head}A,walk,1,{last},\n"), "A", o).unwrap_err();
        assert!(e.to_string().contains("plus the BVH row offset"), "{e}");
        let o = TruthOptions { first_frame: 0, bvh_row_offset: 1 };
        let e = load_csv(&format!("{head}A,walk,0,5,{last}\n"), "A", o).unwrap_err();
        assert!(e.to_string().contains("`trial_frames`"), "{e}");
    }
}
