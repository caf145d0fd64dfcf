//! The label importers: the label CSV (`labels::read_csv`, what `train-dtfcn`, `gait --within`
//! and the page's training read), the ground-truth CSV (`truth::load_csv`, what `eval` and
//! `splice` read) and its conversion to label rows (`labels::from_truth_csv`).
//!
//! The first byte picks the ground truth's frame numbering (first frame 0 or 1, a T-pose row or
//! not); the rest is the file (decoded lossily, as the command line and the page read text).
//! Label rows that read must write back (`labels::to_csv`) and read again to the same rows.

use mocapseg::labels;
use mocapseg::segment::truth::{load_csv, TruthOptions, MAX_FRAMES};

pub fn seeds() -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    let dir = crate::repo().join("models/labels");
    for entry in std::fs::read_dir(&dir).expect("models/labels").flatten() {
        let path = entry.path();
        let text = std::fs::read(&path).expect("a label file");
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        out.push((format!("labels-{name}"), [&[0u8][..], &text].concat()));
        // the same segments in the ground truth's form (1-based, with windows and trial lengths)
        if let Ok(rows) = labels::read_csv(&String::from_utf8_lossy(&text), &name) {
            let mut truth =
                String::from("trial,seg_index,label,start_frame,end_frame,trial_frames,end_window_lo,end_window_hi\n");
            for (i, r) in rows.iter().enumerate() {
                let trial = r.file.trim_end_matches(".bvh");
                let last = rows.iter().filter(|x| x.file == r.file).map(|x| x.end_frame).max().unwrap_or(0);
                truth += &format!(
                    "{trial},{i},\"{}\",{},{},{},{},{}\n",
                    r.label.replace('"', "\"\""),
                    r.start_frame + 1,
                    r.end_frame + 1,
                    last + 1,
                    r.end_frame.saturating_sub(5) + 1,
                    r.end_frame + 6,
                );
            }
            out.push((format!("truth-{name}"), [&[1u8][..], truth.as_bytes()].concat()));
        }
    }
    out
}

/// One input of the target (what `fuzz_targets/labels_import.rs` hands libFuzzer's bytes to).
pub fn run(data: &[u8]) {
    let Some((&pick, rest)) = data.split_first() else { return };
    let text = String::from_utf8_lossy(rest);
    let options = TruthOptions { first_frame: usize::from(pick & 1), bvh_row_offset: usize::from(pick >> 1 & 1) };

    if let Ok(rows) = labels::read_csv(&text, "fuzz.csv") {
        for r in &rows {
            assert!(r.start_frame <= r.end_frame && !r.label.is_empty(), "{r:?}");
        }
        let again = labels::read_csv(&labels::to_csv(&rows), "again.csv")
            .unwrap_or_else(|e| panic!("written label rows do not read back: {e}"));
        assert_eq!(rows, again);
    }

    if let Ok((rows, _skipped)) = labels::from_truth_csv(&text, options) {
        for r in &rows {
            assert!(r.start_frame <= r.end_frame && r.end_frame < MAX_FRAMES, "{r:?}");
        }
    }

    // one trial directly: the first field of the second line, if any
    let trial = text.lines().nth(1).and_then(|l| l.split(',').next()).unwrap_or("13_29").trim();
    match load_csv(&text, trial, options) {
        Ok(truth) => {
            for s in &truth.segments {
                assert!(s.start <= s.end && s.end < MAX_FRAMES, "{s:?}");
                if let Some((lo, hi)) = s.end_window {
                    assert!(lo <= hi && hi < MAX_FRAMES, "{s:?}");
                }
            }
            assert!(truth.frames <= MAX_FRAMES);
        }
        Err(e) => assert!(!e.to_string().is_empty()),
    }
}
