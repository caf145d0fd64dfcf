//! "Which method is best?" (issue 48): the comparison ranks the rows on one headline metric per table — finding
//! actions (the segmenters: boundary F1 within 1 s by default) and labelling frames (the labellers and my labels:
//! frame accuracy by default) — every other metric on demand. Natively tested: the ranks ([`ranks`]), which table a
//! row belongs to ([`Table`]), and when my labels are left out of the ranks ([`copy_of_the_truth`]).

use crate::app::truth::compare::as_shown;

/// One metric of a row scored against the truth, as the tables show it.
#[derive(Debug, Clone, PartialEq)]
pub struct Line {
    pub key: &'static str,
    pub name: &'static str,
    pub value: f64,
    pub digits: usize,
    pub hint: String,
}

/// One row scored against the truth: its id and label, its metrics (or why it could not be scored), the ranked table
/// it belongs to and why it is not ranked (if it is not).
#[derive(Debug, Clone, PartialEq)]
pub struct Compared {
    pub id: String,
    pub label: String,
    pub scored: Result<Vec<Line>, String>,
    pub table: Table,
    pub unranked: Option<String>,
}

/// The two ranked tables.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Table {
    /// Rows that cut a take into actions (their boundaries are what they are for).
    Actions,
    /// Rows that give frames labels (DT-FCN, k-NN, my labels).
    Labels,
}

impl Table {
    /// The table's heading and the headline metric it ranks by unless another is chosen.
    pub fn heading(self) -> &'static str {
        match self {
            Table::Actions => "Finding actions",
            Table::Labels => "Labelling frames",
        }
    }

    /// The metric (its key in the comparison) the table ranks by unless another is chosen.
    pub fn default_metric(self) -> &'static str {
        match self {
            Table::Actions => "boundary_f1_1s",
            Table::Labels => "frame_accuracy",
        }
    }

    /// The metrics offered as the headline: those that mean something for the table's rows (a segmenter's clusters
    /// carry no label names, so label metrics are not offered for it).
    pub fn metrics(self) -> &'static [&'static str] {
        match self {
            Table::Actions => &["boundary_f1_1s", "boundary_f1_0.5s", "covering", "segment_score"],
            Table::Labels => &["frame_accuracy", "f1_50", "f1_25", "f1_10", "edit", "boundary_f1_1s"],
        }
    }
}

/// The ranks (1 = best; equal values as shown with `digits` decimals share a rank) of rows whose headline values are
/// `values` (higher is better); `None` for a row that is not ranked (no value, or not a number).
pub fn ranks(values: &[Option<f64>], digits: usize) -> Vec<Option<usize>> {
    let shown: Vec<Option<f64>> =
        values.iter().map(|v| v.map(|v| as_shown(v, digits)).filter(|v| v.is_finite())).collect();
    shown.iter().map(|v| v.map(|v| 1 + shown.iter().flatten().filter(|&&o| o > v).count())).collect()
}

/// Whether my labels are the ground truth itself (copied from it: every frame's label and every boundary the
/// same): they are then left out of the ranks, since they would top every table.
pub fn copy_of_the_truth(frame_accuracy: f64, boundary_f1: f64) -> bool {
    frame_accuracy >= 0.9995 && boundary_f1 >= 0.9995
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_rank_by_the_headline_ties_share_a_rank_and_rows_without_a_value_are_not_ranked() {
        let values = [Some(0.61), Some(0.8234), None, Some(0.8231), Some(f64::NAN), Some(0.2)];
        assert_eq!(ranks(&values, 3), vec![Some(3), Some(1), None, Some(1), None, Some(4)], "0.823 twice: both first");
        assert_eq!(ranks(&values, 4), vec![Some(3), Some(1), None, Some(2), None, Some(4)]);
        assert!(ranks(&[], 3).is_empty());
    }

    #[test]
    fn each_table_has_its_headline_and_my_labels_copied_from_the_truth_are_left_out() {
        assert_eq!(Table::Actions.default_metric(), "boundary_f1_1s");
        assert_eq!(Table::Labels.default_metric(), "frame_accuracy");
        assert!(!Table::Actions.metrics().contains(&"frame_accuracy"), "a segmenter's clusters have no label names");
        for t in [Table::Actions, Table::Labels] {
            assert_eq!(t.metrics()[0], t.default_metric());
        }
        assert!(copy_of_the_truth(1.0, 1.0));
        assert!(!copy_of_the_truth(0.98, 1.0), "an annotator's own labels are ranked");
    }
}
