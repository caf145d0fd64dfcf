//! Training labels for the supervised methods (DT-FCN, k-NN): the label CSV every such method
//! reads and writes, and labels made by rule where no public labelled set exists.
//!
//! The label CSV: a header `file,start_frame,end_frame,label`, then one row per labelled segment;
//! `file` the take's file name, frames **0-based, inclusive, at the file's own frame rate** (BVH
//! data rows), `label` any text (quoted if it holds commas).
//!
//! * [`gait`]: heuristic gait-phase labels (Cheema et al. 2019's locomotion label kind);
//! * [`from_truth_csv`]: the shared data's ground truth (1-based AMC frames) as label rows —
//!   `mocapseg labels ../shared/data/labels/mocap6_gt.csv -o mocap6.csv`.

pub mod gait;

use crate::clips::Which;
use crate::segment::truth::{load_all_csv, TruthOptions};
use crate::segment::Segmentation;

/// One labelled segment of a take.
#[derive(Debug, Clone, PartialEq)]
pub struct LabelRow {
    pub file: String,
    pub start_frame: usize,
    pub end_frame: usize,
    pub label: String,
}

/// The label CSV of `rows` (header included).
pub fn to_csv(rows: &[LabelRow]) -> String {
    let mut w = csv::Writer::from_writer(Vec::new());
    let _ = w.write_record(["file", "start_frame", "end_frame", "label"]);
    for r in rows {
        let _ = w.write_record([r.file.as_str(), &r.start_frame.to_string(), &r.end_frame.to_string(), &r.label]);
    }
    String::from_utf8(w.into_inner().unwrap_or_default()).unwrap_or_default()
}

/// The segments of `segmentation` that `which` chooses as label rows of its file, in frame
/// order (what the page's "CSV" export saves: the same rows `train-dtfcn` and the page's training read).
pub fn from_segmentation(segmentation: &Segmentation, which: Which) -> Vec<LabelRow> {
    let mut rows: Vec<LabelRow> = segmentation
        .segments
        .iter()
        .filter(|s| which.takes(s.level))
        .map(|s| LabelRow {
            file: segmentation.file.clone(),
            start_frame: s.start,
            end_frame: s.end,
            label: if s.label.is_empty() { "unlabelled".to_string() } else { s.label.clone() },
        })
        .collect();
    rows.sort_by_key(|r| (r.start_frame, r.end_frame));
    rows
}

/// `a` and `b` name the same file (case-insensitive, with or without folders and `.bvh`): how a
/// label row's `file` finds its take, and a model's provenance its training takes.
pub fn same_file(a: &str, b: &str) -> bool {
    let stem = |s: &str| {
        let base = s.rsplit(['/', '\\']).next().unwrap_or(s).to_ascii_lowercase();
        base.strip_suffix(".bvh").map(str::to_string).unwrap_or(base)
    };
    stem(a) == stem(b)
}

/// One row of a label file of any kind: the take it names, its frames (0-based, inclusive, at the file's rate),
/// the columns after them, and its line in the file (1-based).
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    pub file: String,
    pub start_frame: usize,
    pub end_frame: usize,
    pub values: Vec<String>,
    pub line: usize,
}

/// How a row's two frames must stand.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Span {
    /// `end_frame >= start_frame` (a segment of one frame is a segment: the label CSV).
    Inclusive,
    /// `end_frame > start_frame` (a gesture has a duration: the Effort label CSV).
    Open,
}

/// Reads a label file whose header is `file,start_frame,end_frame` followed by `values` (the header is required,
/// case-insensitive; fields trimmed, quoted when they hold commas): every kind of label CSV goes through here. Errors
/// name `source` and the line.
pub fn read_rows(text: &str, source: &str, values: &[&str], span: Span) -> Result<Vec<Row>, String> {
    let header: Vec<&str> = ["file", "start_frame", "end_frame"].iter().chain(values).copied().collect();
    let mut reader = csv::ReaderBuilder::new().trim(csv::Trim::All).flexible(true).from_reader(text.as_bytes());
    let found: Vec<String> =
        reader.headers().map_err(|e| format!("{source}: {e}"))?.iter().map(|h| h.to_ascii_lowercase()).collect();
    if found != header {
        return Err(format!(
            "{source} line 1: expected the header `{}`, found `{}`",
            header.join(","),
            found.join(",")
        ));
    }
    let mut rows = Vec::new();
    for record in reader.records() {
        let r = record.map_err(|e| match e.position() {
            Some(p) => format!("{source} line {}: {e}", p.line()),
            None => format!("{source}: {e}"),
        })?;
        let line = r.position().map_or(0, |p| p.line()) as usize;
        if r.len() != header.len() {
            return Err(format!(
                "{source} line {line}: {} fields, expected {} ({})",
                r.len(),
                header.len(),
                header.join(",")
            ));
        }
        let frame = |i: usize| {
            r[i].parse::<usize>()
                .map_err(|_| format!("{source} line {line}: {} `{}` is not a frame number (0-based)", header[i], &r[i]))
        };
        let (start_frame, end_frame) = (frame(1)?, frame(2)?);
        match span {
            Span::Inclusive if end_frame < start_frame => {
                return Err(format!("{source} line {line}: end_frame {end_frame} is before start_frame {start_frame}"))
            }
            Span::Open if end_frame <= start_frame => {
                return Err(format!(
                    "{source} line {line}: end_frame {end_frame} is not after start_frame {start_frame}"
                ))
            }
            _ => {}
        }
        let values = (3..header.len()).map(|i| r[i].to_string()).collect();
        rows.push(Row { file: r[0].to_string(), start_frame, end_frame, values, line });
    }
    Ok(rows)
}

/// Reads a label CSV (the header is required; errors name `source` and the line).
pub fn read_csv(text: &str, source: &str) -> Result<Vec<LabelRow>, String> {
    read_rows(text, source, &["label"], Span::Inclusive)?
        .into_iter()
        .map(|r| {
            let [label]: [String; 1] = r.values.try_into().expect("one value column");
            if label.is_empty() {
                return Err(format!("{source} line {}: the label is empty", r.line));
            }
            Ok(LabelRow { file: r.file, start_frame: r.start_frame, end_frame: r.end_frame, label })
        })
        .collect()
}

/// Ground truth in the shared data's format (`trial,label,start_frame,end_frame,…`, read by
/// [`crate::segment::truth::load_csv`] with `options`) as label rows: every trial that reads,
/// file `<trial>.bvh`, frames made 0-based BVH rows; and why each other trial could not be read
/// (the shared data lists trials whose motion it lacks, some with incomplete rows).
pub fn from_truth_csv(text: &str, options: TruthOptions) -> Result<(Vec<LabelRow>, Vec<String>), String> {
    let (mut rows, mut skipped) = (Vec::new(), Vec::new());
    for (trial, truth) in load_all_csv(text, options).map_err(|e| e.to_string())? {
        match truth {
            Ok(truth) => rows.extend(truth.segments.iter().map(|s| LabelRow {
                file: format!("{trial}.bvh"),
                start_frame: s.start,
                end_frame: s.end,
                label: s.label.clone(),
            })),
            Err(e) => skipped.push(format!("trial {trial}: {e}")),
        }
    }
    Ok((rows, skipped))
}

/// The parts of `rows` inside the segments of `spans` labelled `label` (same file by
/// [`same_file`]), each row clipped to them: the gait phases of the walking
/// parts of a take whose actions are labelled (`mocapseg gait --within actions.csv --label walk`).
/// Rows of files `spans` does not name at all are kept whole (walking clips are walks throughout).
pub fn within(rows: &[LabelRow], spans: &[LabelRow], label: &str) -> Vec<LabelRow> {
    let mut out = Vec::new();
    for r in rows {
        if !spans.iter().any(|s| same_file(&s.file, &r.file)) {
            out.push(r.clone());
            continue;
        }
        for s in spans.iter().filter(|s| s.label == label && same_file(&s.file, &r.file)) {
            let (a, b) = (r.start_frame.max(s.start_frame), r.end_frame.min(s.end_frame));
            if a <= b {
                out.push(LabelRow { start_frame: a, end_frame: b, ..r.clone() });
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn files_are_the_same_whatever_their_folder_case_or_extension() {
        assert!(same_file("dir/35_01.BVH", "35_01") && same_file("a\\b\\86_01.bvh", "86_01.BVH"));
        assert!(!same_file("35_01", "35_02") && !same_file("35_01.bvh.bak", "35_01"));
    }

    #[test]
    fn every_label_file_kind_is_read_by_one_reader_with_its_lines() {
        let text = "File,Start_Frame,End_Frame,a,b\nx.bvh, 3, 3,\"p, q\", r\ny.bvh,4,9,s,t\n";
        let rows = read_rows(text, "f.csv", &["a", "b"], Span::Inclusive).unwrap();
        assert_eq!(
            rows[0],
            Row {
                file: "x.bvh".into(),
                start_frame: 3,
                end_frame: 3,
                values: vec!["p, q".into(), "r".into()],
                line: 2
            }
        );
        assert_eq!((rows[1].file.as_str(), rows[1].line), ("y.bvh", 3));
        let open = read_rows(text, "f.csv", &["a", "b"], Span::Open).unwrap_err();
        assert!(open.contains("f.csv line 2: end_frame 3 is not after start_frame 3"), "{open}");
        let short = read_rows("file,start_frame,end_frame,a\nx,1,2\n", "f.csv", &["a"], Span::Inclusive).unwrap_err();
        assert!(short.contains("f.csv line 2: 3 fields, expected 4"), "{short}");
        let frame = read_rows("file,start_frame,end_frame\nx,-1,2\n", "f.csv", &[], Span::Inclusive).unwrap_err();
        assert!(frame.contains("line 2: start_frame `-1` is not a frame number"), "{frame}");
        assert!(read_csv("file,start_frame,end_frame,label\nx,1,2,\n", "l.csv")
            .unwrap_err()
            .contains("line 2: the label is empty"));
    }

    #[test]
    fn rows_are_clipped_to_the_spans_of_one_label_in_the_same_file() {
        let row = |f: &str, a, b, l: &str| LabelRow { file: f.into(), start_frame: a, end_frame: b, label: l.into() };
        let gait =
            [row("86_01.bvh", 0, 99, "left step"), row("86_01.bvh", 100, 299, "standing"), row("x.bvh", 0, 9, "turn")];
        let actions = [row("86_01", 50, 149, "walk"), row("86_01.bvh", 150, 400, "jump"), row("x.bvh", 0, 9, "walk")];
        assert_eq!(
            within(&gait, &actions, "walk"),
            vec![
                row("86_01.bvh", 50, 99, "left step"),
                row("86_01.bvh", 100, 149, "standing"),
                row("x.bvh", 0, 9, "turn")
            ]
        );
        assert!(within(&gait, &actions, "run").is_empty());
    }

    #[test]
    fn label_files_read_back_and_name_their_bad_lines() {
        let rows = vec![
            LabelRow { file: "a.bvh".into(), start_frame: 0, end_frame: 9, label: "left step".into() },
            LabelRow { file: "b, c.bvh".into(), start_frame: 10, end_frame: 20, label: "turn".into() },
        ];
        assert_eq!(read_csv(&to_csv(&rows), "x.csv").unwrap(), rows);
        let err =
            read_csv("file,start_frame,end_frame,label\na.bvh,0,9,walk\na.bvh,ten,20,run\n", "x.csv").unwrap_err();
        assert!(err.contains("x.csv line 3") && err.contains("`ten`"), "{err}");
        assert!(read_csv("trial,label\n", "x.csv").unwrap_err().contains("line 1: expected the header"));
        assert!(read_csv("file,start_frame,end_frame,label\na,5,2,x\n", "x.csv").unwrap_err().contains("before"));
    }

    #[test]
    fn the_shared_ground_truth_converts_to_zero_based_rows() {
        let gt = "trial,label,start_frame,end_frame,trial_frames\n86_01,walk,1,550,1000\n86_01,jump,551,1000,1000\n\
                  13_29,JumpJack,1,468,900\n13_29,Twist,469,900,900\n";
        let (rows, skipped) = from_truth_csv(gt, TruthOptions::default()).unwrap();
        assert!(skipped.is_empty());
        assert_eq!(rows.len(), 4);
        assert_eq!(
            rows[0],
            LabelRow { file: "86_01.bvh".into(), start_frame: 0, end_frame: 549, label: "walk".into() }
        );
        assert_eq!((rows[3].file.as_str(), rows[3].start_frame, rows[3].end_frame), ("13_29.bvh", 468, 899));
        // a trial with an incomplete row is skipped, and said
        let partial = format!("{gt}14_06,Box,901,,\n");
        let (rows, skipped) = from_truth_csv(&partial, TruthOptions::default()).unwrap();
        assert_eq!(rows.len(), 4);
        assert_eq!(skipped.len(), 1);
        assert!(skipped[0].starts_with("trial 14_06:"), "{skipped:?}");
    }

    #[test]
    fn rows_are_written_with_their_header_and_quoted_when_needed() {
        let rows = [
            LabelRow { file: "a.bvh".into(), start_frame: 0, end_frame: 9, label: "left step".into() },
            LabelRow { file: "b, c.bvh".into(), start_frame: 10, end_frame: 20, label: "turn".into() },
        ];
        assert_eq!(to_csv(&rows), "file,start_frame,end_frame,label\na.bvh,0,9,left step\n\"b, c.bvh\",10,20,turn\n");
    }
}
