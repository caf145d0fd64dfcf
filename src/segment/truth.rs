//! Ground-truth segmentations read from CSV, as shipped with the CMU 86 and mocap6 labels.
//!
//! The CSV needs the columns `trial`, `label`, `start_frame`, `end_frame`; it may have `trial_frames`,
//! `end_window_lo` and `end_window_hi` (the annotator's uncertainty window around a segment's end).
//! Frames in those files are **1-based inclusive AMC frame numbers**; the converted BVHs have no T-pose row, so
//! BVH row = frame − 1. [`TruthOptions::first_frame`] says which number the file's first frame has, and
//! [`TruthOptions::bvh_row_offset`] covers BVHs that prepend a T-pose row (cgspeed MotionBuilder files: +1).

use serde::Serialize;

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
    pub fn concatenate(trial: &str, parts: &[Truth]) -> Truth {
        let mut segments = Vec::new();
        let mut shift = 0;
        for part in parts {
            segments.extend(part.segments.iter().map(|s| TruthSegment {
                start: s.start + shift,
                end: s.end + shift,
                label: s.label.clone(),
                end_window: s.end_window.map(|(lo, hi)| (lo + shift, hi + shift)),
            }));
            shift += part.frames;
        }
        Truth { trial: trial.to_string(), frames: shift, segments }
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

fn column(header: &[&str], name: &'static str) -> Result<usize, TruthError> {
    header.iter().position(|h| h.trim() == name).ok_or(TruthError::MissingColumn(name))
}

fn optional_column(header: &[&str], name: &str) -> Option<usize> {
    header.iter().position(|h| h.trim() == name)
}

/// Reads the segments of `trial` from a ground-truth CSV (simple CSV: no quoted commas).
pub fn load_csv(text: &str, trial: &str, options: TruthOptions) -> Result<Truth, TruthError> {
    let mut lines = text.lines().enumerate().filter(|(_, l)| !l.trim().is_empty());
    let (_, header_line) = lines.next().ok_or(TruthError::MissingColumn("trial"))?;
    let header: Vec<&str> = header_line.split(',').collect();
    let (c_trial, c_label) = (column(&header, "trial")?, column(&header, "label")?);
    let (c_start, c_end) = (column(&header, "start_frame")?, column(&header, "end_frame")?);
    let c_frames = optional_column(&header, "trial_frames");
    let c_lo = optional_column(&header, "end_window_lo");
    let c_hi = optional_column(&header, "end_window_hi");

    let mut trials_seen: Vec<String> = Vec::new();
    let mut segments = Vec::new();
    let mut frames: Option<usize> = None;
    for (index, line) in lines {
        let line_no = index + 1;
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        let field = |c: usize| -> Result<&str, TruthError> {
            fields.get(c).copied().ok_or_else(|| TruthError::Line {
                line: line_no,
                message: format!("expected at least {} fields, found {}", c + 1, fields.len()),
            })
        };
        let this_trial = field(c_trial)?;
        if !trials_seen.iter().any(|t| t == this_trial) {
            trials_seen.push(this_trial.to_string());
        }
        if this_trial != trial {
            continue;
        }
        let number = |c: usize, what: &str| -> Result<usize, TruthError> {
            let raw = field(c)?;
            let value: f64 = raw.parse().map_err(|_| TruthError::Line {
                line: line_no,
                message: format!("expected a frame number in `{what}`, found `{raw}`"),
            })?;
            if !(value.is_finite() && value >= options.first_frame as f64) {
                return Err(TruthError::Line {
                    line: line_no,
                    message: format!("`{what}` = {raw} is before the first frame {}", options.first_frame),
                });
            }
            Ok(value.floor() as usize - options.first_frame + options.bvh_row_offset)
        };
        let (start, end) = (number(c_start, "start_frame")?, number(c_end, "end_frame")?);
        if end < start {
            return Err(TruthError::Line { line: line_no, message: "end_frame is before start_frame".to_string() });
        }
        let end_window = match (c_lo, c_hi) {
            (Some(lo), Some(hi)) if !field(lo)?.is_empty() && !field(hi)?.is_empty() => {
                let (a, b) = (number(lo, "end_window_lo")?, number(hi, "end_window_hi")?);
                Some((a.min(b), a.max(b)))
            }
            _ => None,
        };
        if let Some(c) = c_frames {
            let raw = field(c)?;
            if !raw.is_empty() {
                frames = Some(raw.parse().map_err(|_| TruthError::Line {
                    line: line_no,
                    message: format!("expected a frame count in `trial_frames`, found `{raw}`"),
                })?);
            }
        }
        segments.push(TruthSegment { start, end, label: field(c_label)?.to_string(), end_window });
    }
    if segments.is_empty() {
        return Err(TruthError::NoTrial { trial: trial.to_string(), present: trials_seen.join(", ") });
    }
    segments.sort_by_key(|s| s.start);
    let last_end = segments.iter().map(|s| s.end).max().unwrap_or(0);
    let frames = frames.map(|f| f + options.bvh_row_offset).unwrap_or(last_end + 1).max(last_end + 1);
    Ok(Truth { trial: trial.to_string(), frames, segments })
}

#[cfg(test)]
mod tests {
    use super::*;

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
    }
}
