//! Training labels for the supervised methods (DT-FCN, k-NN): the label CSV every such method
//! reads and writes, and labels made by rule where no public labelled set exists.
//!
//! The label CSV: a header `file,start_frame,end_frame,label`, then one row per labelled segment;
//! `file` the take's file name, frames **0-based, inclusive, at the file's own frame rate** (BVH
//! data rows), `label` any text (quoted if it holds commas).
//!
//! * [`gait`]: heuristic gait-phase labels (Cheema et al. 2019's locomotion label kind).

pub mod gait;

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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_are_written_with_their_header_and_quoted_when_needed() {
        let rows = [
            LabelRow { file: "a.bvh".into(), start_frame: 0, end_frame: 9, label: "left step".into() },
            LabelRow { file: "b, c.bvh".into(), start_frame: 10, end_frame: 20, label: "turn".into() },
        ];
        assert_eq!(to_csv(&rows), "file,start_frame,end_frame,label\na.bvh,0,9,left step\n\"b, c.bvh\",10,20,turn\n");
    }
}
