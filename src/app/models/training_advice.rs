//! Advice before a training: how many labelled segments and seconds each class has in the takes
//! trained on, and which classes have too few to learn from.
//!
//! The thresholds come from what the labellers look at, not from taste:
//! * **2 segments** — a class labelled once is one performance of it (one direction, one speed,
//!   one person's style): the model learns that stretch, not the class, and nothing of the class is
//!   left to tell the two apart;
//! * **2.7 s** — the shipped DT-FCN network sees 81 working frames at 30 Hz (kernel width 3, four
//!   layers: 3⁴ frames, `network::DtFcnConfig::receptive_field`); a class with less labelled time
//!   than one receptive field never fills the network's view, so its frames are learnt mostly from
//!   their neighbours' motion. The k-NN's window is ±1 s, shorter: the same bound covers it.

use crate::labels::LabelRow;

/// The fewest labelled segments of a class advised.
pub const MIN_SEGMENTS: usize = 2;
/// The least labelled time of a class advised, in seconds (one receptive field of the network).
pub const MIN_SECONDS: f64 = 81.0 / 30.0;

/// One class's labelled examples in the takes trained on.
#[derive(Debug, Clone, PartialEq)]
pub struct ClassCount {
    pub label: String,
    pub segments: usize,
    pub seconds: f64,
}

/// The file name's stem, lowercased (`dir/13_30.BVH` → `13_30`), as label files name takes.
fn stem(name: &str) -> String {
    let base = name.rsplit(['/', '\\']).next().unwrap_or(name).to_ascii_lowercase();
    base.strip_suffix(".bvh").map(str::to_string).unwrap_or(base)
}

/// The classes of `rows` that label the takes `takes` (file name and frame rate), with their
/// segments and seconds, in the order they first appear.
pub fn class_counts(rows: &[LabelRow], takes: &[(String, f64)]) -> Vec<ClassCount> {
    let mut out: Vec<ClassCount> = Vec::new();
    for row in rows {
        let Some((_, fps)) = takes.iter().find(|(t, _)| stem(t) == stem(&row.file)) else { continue };
        let frames = row.end_frame.saturating_sub(row.start_frame) + 1;
        let seconds = if *fps > 0.0 { frames as f64 / fps } else { 0.0 };
        match out.iter_mut().find(|c| c.label == row.label) {
            Some(c) => {
                c.segments += 1;
                c.seconds += seconds;
            }
            None => out.push(ClassCount { label: row.label.clone(), segments: 1, seconds }),
        }
    }
    out
}

/// One line of advice per class below a threshold (empty: nothing to advise).
pub fn advice(counts: &[ClassCount]) -> Vec<String> {
    let mut lines = Vec::new();
    if counts.len() == 1 {
        lines.push(format!(
            "Only one class ({}) in the takes trained on: the model can tell nothing apart. Label at least two.",
            counts[0].label
        ));
    }
    for c in counts {
        let few_segments = c.segments < MIN_SEGMENTS;
        let short = c.seconds < MIN_SECONDS;
        if !(few_segments || short) {
            continue;
        }
        let segments = if c.segments == 1 { "1 segment".to_string() } else { format!("{} segments", c.segments) };
        let mut why = Vec::new();
        if few_segments {
            why.push(format!("fewer than {MIN_SEGMENTS} segments: the model learns that one stretch, not the class"));
        }
        if short {
            why.push(format!(
                "under {MIN_SECONDS:.1} s: less than the network sees at once, so it learns mostly the neighbours"
            ));
        }
        lines.push(format!("`{}`: {segments}, {:.1} s — {}. Label more of it.", c.label, c.seconds, why.join("; ")));
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(file: &str, start: usize, end: usize, label: &str) -> LabelRow {
        LabelRow { file: file.into(), start_frame: start, end_frame: end, label: label.into() }
    }

    #[test]
    fn classes_are_counted_in_the_takes_trained_on_only() {
        let rows = vec![
            row("13_30.bvh", 0, 119, "jog"),
            row("13_30", 120, 479, "squat"),
            row("13_30.bvh", 480, 719, "jog"),
            row("other.bvh", 0, 9999, "jog"),
        ];
        let counts = class_counts(&rows, &[("dir/13_30.BVH".into(), 120.0)]);
        assert_eq!(counts.len(), 2);
        assert_eq!(counts[0], ClassCount { label: "jog".into(), segments: 2, seconds: 3.0 });
        assert_eq!(counts[1], ClassCount { label: "squat".into(), segments: 1, seconds: 3.0 });
        let lines = advice(&counts);
        assert_eq!(lines.len(), 1, "{lines:?}");
        assert!(lines[0].starts_with("`squat`: 1 segment, 3.0 s — fewer than 2 segments"), "{}", lines[0]);
    }

    #[test]
    fn short_classes_and_a_single_class_are_advised_against() {
        let counts = vec![ClassCount { label: "wave".into(), segments: 3, seconds: 1.5 }];
        let lines = advice(&counts);
        assert_eq!(lines.len(), 2, "{lines:?}");
        assert!(lines[0].contains("Only one class (wave)"));
        assert!(lines[1].contains("under 2.7 s") && !lines[1].contains("fewer than"), "{}", lines[1]);
        let fine = vec![
            ClassCount { label: "a".into(), segments: 2, seconds: 2.7 },
            ClassCount { label: "b".into(), segments: 5, seconds: 30.0 },
        ];
        assert!(advice(&fine).is_empty());
    }
}
