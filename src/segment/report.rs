//! Scores of several takes as one markdown table with their mean (what `mocapseg eval` prints for
//! a folder of predictions and the lab's `eval_data` example prints for the shared takes).

use super::metrics::{ScoredView, Scores};
use super::Segmentation;

/// The segments a segmentation is scored on: its actions, or its primitives when it finds no
/// actions (as the metrics do).
pub fn scored_segments(seg: &Segmentation) -> usize {
    seg.level(super::metrics::scored_level(seg)).count()
}

/// One take's row: its scores, how many actions (or, without actions, primitives) the method
/// found, and (if measured) how long it took.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    pub scores: Scores,
    pub found_actions: usize,
    pub seconds: Option<f64>,
}

/// The score columns; `s@0.5s` is Bouchard & Badler's segment similarity (matched − unmatched / 2, a count).
/// `edit` and `F1@10/25/50` are the per-frame labelling scores (percent; see `labelling.rs`).
const COLUMNS: [&str; 11] = [
    "F1@0.5s",
    "F1@1s",
    "covering",
    "Hungarian acc.",
    "strict",
    "tolerant",
    "s@0.5s",
    "edit",
    "F1@10",
    "F1@25",
    "F1@50",
];

fn values(s: &Scores) -> [f64; 11] {
    let f1 = |k: usize| s.boundaries.get(k).map_or(f64::NAN, |b| b.f1);
    let similarity = s.segments.similarity;
    let l = &s.labelling;
    [
        f1(0),
        f1(1),
        s.covering,
        s.hungarian_accuracy,
        s.strict_accuracy,
        s.tolerant_accuracy,
        similarity,
        l.edit,
        l.f1[0],
        l.f1[1],
        l.f1[2],
    ]
}

/// The mean of every score column over `rows` (`None` when there are none).
pub fn mean(rows: &[Row]) -> Option<[f64; 11]> {
    if rows.is_empty() {
        return None;
    }
    let mut mean = [0.0; 11];
    for r in rows {
        for (m, v) in mean.iter_mut().zip(values(&r.scores)) {
            *m += v / rows.len() as f64;
        }
    }
    Some(mean)
}

/// A markdown table: one line per row of `rows`, then their mean in bold, then `extra` (rows
/// shown but not in the mean, such as several takes joined into one).
pub fn markdown(rows: &[Row], extra: &[Row]) -> String {
    let timed = rows.iter().chain(extra).any(|r| r.seconds.is_some());
    let mut out = format!("| take | true actions / found | {} |", COLUMNS.join(" | "));
    out += if timed { " time |\n" } else { "\n" };
    out += &"|---".repeat(2 + COLUMNS.len() + usize::from(timed));
    out += "|\n";
    let line = |r: &Row| {
        let cells: Vec<String> = values(&r.scores).iter().map(|v| format!("{v:.2}")).collect();
        let time = match (timed, r.seconds) {
            (true, Some(s)) => format!(" {:.0} ms |", s * 1e3),
            (true, None) => " |".into(),
            _ => String::new(),
        };
        format!(
            "| {} | {} / {} | {} |{time}\n",
            r.scores.trial,
            r.scores.true_segments,
            r.found_actions,
            cells.join(" | ")
        )
    };
    for r in rows {
        out += &line(r);
    }
    if let Some(m) = mean(rows) {
        let cells: Vec<String> = m.iter().map(|v| format!("**{v:.2}**")).collect();
        out += &format!("| **mean** | | {} |{}\n", cells.join(" | "), if timed { " |" } else { "" });
    }
    for r in extra {
        out += &line(r);
    }
    // say how the rows were read (a tiling of actions, or primitives as given)
    let mut views: Vec<ScoredView> = rows.iter().chain(extra).map(|r| r.scores.scored_as).collect();
    views.dedup();
    views.sort_by_key(|v| *v as u8);
    views.dedup();
    for v in views {
        out += &format!("\nScored as {}.\n", v.describe());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::segment::metrics::BoundaryScore;

    fn row(trial: &str, f1: f64, covering: f64) -> Row {
        let b = BoundaryScore { tolerance_s: 1.0, precision: f1, recall: f1, f1, matched: 3 };
        Row {
            scores: Scores {
                trial: trial.into(),
                scored_as: ScoredView::Tiling,
                true_segments: 5,
                true_boundaries: 4,
                predicted_boundaries: 5,
                boundaries: vec![b, b],
                segments: crate::segment::metrics::segment_score(&[(0, 9)], &[(0, 10), (20, 29)], 0.5, 10.0),
                covering,
                hungarian_accuracy: 0.5,
                strict_accuracy: 0.25,
                tolerant_accuracy: 1.0,
                labelling: crate::segment::labelling::LabellingScores {
                    frame_accuracy: 0.5,
                    edit: 80.0,
                    f1: [90.0, 70.0, 50.0],
                },
            },
            found_actions: 6,
            seconds: None,
        }
    }

    #[test]
    fn table_has_a_line_per_take_and_their_mean() {
        let table = markdown(&[row("a", 1.0, 0.5), row("b", 0.5, 0.25)], &[row("a+b", 0.1, 0.1)]);
        let lines: Vec<&str> = table.lines().collect();
        assert_eq!(lines.len(), 8, "{table}");
        assert_eq!(lines[7], format!("Scored as {}.", ScoredView::Tiling.describe()));
        assert_eq!(
            lines[2],
            "| a | 5 / 6 | 1.00 | 1.00 | 0.50 | 0.50 | 0.25 | 1.00 | 0.50 | 80.00 | 90.00 | 70.00 | 50.00 |"
        );
        assert_eq!(
            lines[4],
            "| **mean** | | **0.75** | **0.75** | **0.38** | **0.50** | **0.25** | **1.00** | **0.50** | **80.00** | **90.00** | **70.00** | **50.00** |"
        );
        assert!(lines[5].starts_with("| a+b |"));
        assert!(!table.contains("time"));
    }
}
