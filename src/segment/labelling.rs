//! The standard scores of per-frame labelling (temporal action segmentation: Lea et al. 2017,
//! "Temporal Convolutional Networks for Action Segmentation and Detection"; Farha & Gall 2019,
//! MS-TCN), on per-frame label indices (`None` = no label):
//!
//! * **frame accuracy**: the share of labelled frames whose predicted label is the true one;
//! * **segmental edit score**: `(1 − d / max(m, n)) × 100`, `d` the Levenshtein distance between the
//!   predicted and the true sequences of segment labels (runs of one label), `m`, `n` their lengths;
//! * **segmental F1@k** (k = 0.10, 0.25, 0.50): a predicted segment is a true positive when its
//!   intersection over union with a not yet matched true segment of the same label reaches k;
//!   `F1 = 2PR / (P + R) × 100`.
//!
//! Methods that name their own clusters (SSSM's `A3`, a baseline's `gesture`) are first mapped
//! onto the true labels one-to-one by the Hungarian matching of [`super::metrics`] (clusters left
//! without a label keep labels of their own and count as wrong).

use serde::Serialize;

/// The overlap thresholds of the segmental F1.
pub const OVERLAPS: [f64; 3] = [0.10, 0.25, 0.50];

/// Frame accuracy, edit score and F1 at [`OVERLAPS`] (percent, as the field reports them).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LabellingScores {
    pub frame_accuracy: f64,
    pub edit: f64,
    /// F1@10, F1@25, F1@50.
    pub f1: [f64; 3],
}

/// Runs of one label: `(label, start, end)` inclusive; frames without a label end a run and
/// belong to none.
fn runs(labels: &[Option<usize>]) -> Vec<(usize, usize, usize)> {
    let mut out: Vec<(usize, usize, usize)> = Vec::new();
    for (t, l) in labels.iter().enumerate() {
        match (l, out.last_mut()) {
            (Some(l), Some(last)) if last.0 == *l && last.2 + 1 == t => last.2 = t,
            (Some(l), _) => out.push((*l, t, t)),
            (None, _) => {}
        }
    }
    out
}

fn levenshtein(a: &[usize], b: &[usize]) -> usize {
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, x) in a.iter().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, y) in b.iter().enumerate() {
            let next = (row[j + 1] + 1).min(row[j] + 1).min(diagonal + usize::from(x != y));
            diagonal = row[j + 1];
            row[j + 1] = next;
        }
    }
    row[b.len()]
}

fn f1_at(pred: &[(usize, usize, usize)], truth: &[(usize, usize, usize)], overlap: f64) -> f64 {
    let mut used = vec![false; truth.len()];
    let mut tp = 0usize;
    for &(label, s, e) in pred {
        let iou = |&(l, ts, te): &(usize, usize, usize)| {
            if l != label {
                return 0.0;
            }
            let inter = (e.min(te) + 1).saturating_sub(s.max(ts)) as f64;
            inter / ((e.max(te) + 1 - s.min(ts)) as f64)
        };
        let best = (0..truth.len()).max_by(|&a, &b| iou(&truth[a]).total_cmp(&iou(&truth[b])));
        if let Some(k) = best.filter(|&k| iou(&truth[k]) >= overlap && !used[k]) {
            used[k] = true;
            tp += 1;
        }
    }
    let (fp, fn_) = (pred.len() - tp, truth.len() - tp);
    let precision = tp as f64 / (tp + fp).max(1) as f64;
    let recall = tp as f64 / (tp + fn_).max(1) as f64;
    if precision + recall > 0.0 {
        200.0 * precision * recall / (precision + recall)
    } else {
        0.0
    }
}

/// The scores of predicted against true per-frame labels (same length; the labels index one
/// vocabulary).
pub fn score(pred: &[Option<usize>], truth: &[Option<usize>]) -> LabellingScores {
    // the share of the labelled frames (a take labelled in part is scored where it is labelled)
    let frames = truth.iter().filter(|t| t.is_some()).count().max(1);
    let right = pred.iter().zip(truth).filter(|(p, t)| p.is_some() && p == t).count();
    let (p, t) = (runs(pred), runs(truth));
    let names = |r: &[(usize, usize, usize)]| r.iter().map(|x| x.0).collect::<Vec<_>>();
    let longest = p.len().max(t.len());
    let edit =
        if longest == 0 { 100.0 } else { (1.0 - levenshtein(&names(&p), &names(&t)) as f64 / longest as f64) * 100.0 };
    LabellingScores { frame_accuracy: right as f64 / frames as f64, edit, f1: OVERLAPS.map(|k| f1_at(&p, &t, k)) }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn labels(parts: &[(usize, usize)]) -> Vec<Option<usize>> {
        parts.iter().flat_map(|&(label, n)| std::iter::repeat_n(Some(label), n)).collect()
    }

    #[test]
    fn a_perfect_labelling_scores_full_marks() {
        let t = labels(&[(0, 10), (1, 20), (0, 5)]);
        let s = score(&t, &t);
        assert_eq!(s, LabellingScores { frame_accuracy: 1.0, edit: 100.0, f1: [100.0; 3] });
    }

    #[test]
    fn over_segmentation_costs_edit_and_f1_but_little_accuracy() {
        // truth: A×10 B×10; prediction: A×10 B×4 A×1 B×5 (one frame flickers)
        let t = labels(&[(0, 10), (1, 10)]);
        let p = labels(&[(0, 10), (1, 4), (0, 1), (1, 5)]);
        let s = score(&p, &t);
        assert!((s.frame_accuracy - 0.95).abs() < 1e-12);
        // label sequences ABAB vs AB: distance 2 over 4
        assert!((s.edit - 50.0).abs() < 1e-9, "{s:?}");
        // B×4 has IoU 0.4 with the true B, B×5 0.5, the stray A none with the true A: at 10 %
        // A×10 and B×4 match (B×5 then finds B taken), at 50 % A×10 and B×5 → P 2/4, R 2/2, F1 66.7
        assert!((s.f1[0] - 200.0 / 3.0).abs() < 1e-9, "{s:?}");
        assert!((s.f1[2] - 200.0 / 3.0).abs() < 1e-9, "{s:?}");
    }

    #[test]
    fn wrong_labels_score_nothing_and_unlabelled_frames_count_as_wrong() {
        let t = labels(&[(0, 10), (1, 10)]);
        let p = labels(&[(1, 10), (0, 10)]);
        let s = score(&p, &t);
        assert_eq!((s.frame_accuracy, s.f1), (0.0, [0.0; 3]));
        assert_eq!(s.edit, 0.0);
        let none = vec![None; 20];
        let s = score(&none, &t);
        assert_eq!((s.frame_accuracy, s.edit, s.f1), (0.0, 0.0, [0.0; 3]));
        assert_eq!(levenshtein(&[1, 2, 3], &[1, 3]), 1);
    }
}
