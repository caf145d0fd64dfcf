//! Scores of a [`Segmentation`] against a [`Truth`].
//!
//! - **Boundary precision / recall / F1** at a tolerance in seconds, with one-to-one matching (a maximum matching
//!   between predicted and true boundaries closer than the tolerance).
//! - **Covering** as in the ClaSP / TSSB papers: Σ over true segments of |g|·max Jaccard(g, p), divided by the length.
//! - **Hungarian frame accuracy**: the action clusters are matched one-to-one to the true labels so that the most
//!   frames agree (Kuhn–Munkres), then the fraction of agreeing frames.
//! - **Strict / tolerant accuracy** of Krüger et al. 2017 §VII-A (after Vögele et al. 2014): every primitive cluster is
//!   assigned the true class it overlaps most (many clusters may map to one class — left and right steps both map to
//!   `walk`); a frame is *strictly* correct when its primitive's class is its true class (frames in transitions or
//!   outside every primitive are wrong); *tolerantly* correct also when it lies in an uncertainty window of the truth
//!   (the annotators' `end_window_lo..hi`, or ± [`Tolerances::uncertain_s`] around a boundary where none is given).
//!
//! **What is scored** ([`ScoredView`]): a segmentation with actions is scored as a *tiling* of the take — its action and
//! transition segments with every transition split at its middle between its neighbours (a leading transition goes to
//! the first action, a trailing one to the last); that is how action labels are annotated. A segmentation without
//! actions (the gesture methods: velocity, KCS, LMA) is scored *as given*: its primitives as they are, gaps staying
//! gaps and overlapping segments (LMA's two arms) overlapping; its boundaries are every segment's start and the frame
//! after its end. The truth is read in the same view: as a tiling its boundaries are where its segments start; as given
//! every start and every frame after an end, so a gapped truth (spliced gestures) keeps its gaps.

use std::collections::BTreeMap;

use pathfinding::prelude::{kuhn_munkres, Matrix};
use serde::Serialize;

use super::labelling::{self, LabellingScores};
use super::truth::{Truth, MAX_FRAMES};
use super::{Level, SchemaError, Segment, Segmentation};

/// Tolerances of the scores, in seconds, and how labels are matched to the truth's.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Tolerances {
    /// Boundary tolerances for the F1 scores.
    pub boundary_s: [f64; 2],
    /// Half-width of the uncertainty window around a true boundary when the truth gives none.
    pub uncertain_s: f64,
    /// How the labelling scores match the segmentation's labels to the truth's.
    pub naming: Naming,
}

impl Default for Tolerances {
    fn default() -> Self {
        Tolerances { boundary_s: [0.5, 1.0], uncertain_s: 0.5, naming: Naming::Detect }
    }
}

impl Tolerances {
    /// The default tolerances, scoring labels by name (a labelling method's run: `crate::methods::scoring`).
    pub fn by_name() -> Tolerances {
        Tolerances { naming: Naming::ByName, ..Tolerances::default() }
    }
}

/// How the labelling scores (frame accuracy, edit, F1@k) read a segmentation's labels (issue 50: a labeller scored
/// right with the wrong names).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Naming {
    /// By name when any of its labels is one of the truth's or `unknown` (a labeller's, my labels, a carried
    /// truth), else by the one-to-one matching of its cluster ids to the true labels (clusters name nothing).
    Detect,
    /// By name, whatever the names (a labelling method's run: a class the take does not have is wrong, not matched
    /// to a label it does have).
    ByName,
}

/// Precision, recall and F1 of boundaries at one tolerance.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BoundaryScore {
    pub tolerance_s: f64,
    pub precision: f64,
    pub recall: f64,
    pub f1: f64,
    pub matched: usize,
}

/// Segment-level agreement as Bouchard & Badler measure it (their §5.1, eq. 3): two segments
/// match when both their starts and their ends lie within `tolerance_s` of each other, each
/// segment matching at most one (the closest); similarity `s = TP − (FP + FN) / 2`, a count.
/// (The paper's text as extracted reads like a ratio, but its Table 3 is the difference:
/// LMA 136 − (92 + 75)/2 = 52.5, velocity 119 − (109 + 92)/2 = 18.5, KCS 10.5, PCA 2.0.)
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SegmentScore {
    pub tolerance_s: f64,
    /// Matched segments.
    pub matched: usize,
    /// Found segments that match none.
    pub unmatched_found: usize,
    /// True segments that match none.
    pub unmatched_true: usize,
    /// `matched − (unmatched_found + unmatched_true) / 2`.
    pub similarity: f64,
}

/// How the scored segments were read from the segmentation (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ScoredView {
    /// Actions as a tiling of the take: transitions split at their middle, gaps stretched, the first action starting
    /// at frame 0 and the last ending at the take's end.
    Tiling,
    /// The primitives exactly as given: gaps stay gaps, overlaps stay overlaps.
    AsGiven,
}

impl ScoredView {
    /// One line saying what was scored, for the page and the command line.
    pub fn describe(self) -> &'static str {
        match self {
            ScoredView::Tiling => {
                "actions as a tiling of the take (transitions split at their middle, gaps stretched to the neighbours)"
            }
            ScoredView::AsGiven => "primitives as given (gaps stay gaps, overlapping segments overlap)",
        }
    }
}

/// Every score of one segmentation against one truth.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Scores {
    pub trial: String,
    /// How the scored segments were read: a tiling of actions, or primitives as given.
    pub scored_as: ScoredView,
    /// Segments of the truth.
    pub true_segments: usize,
    pub true_boundaries: usize,
    pub predicted_boundaries: usize,
    pub boundaries: Vec<BoundaryScore>,
    /// Bouchard & Badler's segment matching at 0.5 s.
    pub segments: SegmentScore,
    pub covering: f64,
    pub hungarian_accuracy: f64,
    pub strict_accuracy: f64,
    pub tolerant_accuracy: f64,
    /// Per-frame labelling scores (frame accuracy, edit, F1@{10,25,50}): the method's labels read by name (a name
    /// the truth lacks, and `unknown`, wrong), or its clusters mapped one-to-one onto the true labels ([`Naming`]).
    pub labelling: LabellingScores,
}

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MetricsError {
    #[error(
        "the segmentation has {seg} frames but the truth has {truth}: is it the same take at the same frame rate?"
    )]
    LengthMismatch { seg: usize, truth: usize },
    #[error("segmentation: {0}")]
    Schema(#[from] SchemaError),
    #[error("ground truth segment {index} (`{label}`): {problem}")]
    BadTruth { index: usize, label: String, problem: String },
    #[error("the take has {frames} frames, more than the {limit} this tool scores")]
    TooLong { frames: usize, limit: usize },
}

/// Checks what the scores rely on, so that no frame number can overflow or index past the take:
/// the segmentation's own schema, at most [`MAX_FRAMES`] frames, and every true segment (and its
/// uncertainty window) ordered and inside the take.
fn check_inputs(seg: &Segmentation, truth: &Truth) -> Result<(), MetricsError> {
    if truth.frames > MAX_FRAMES {
        return Err(MetricsError::TooLong { frames: truth.frames, limit: MAX_FRAMES });
    }
    seg.validate()?;
    let bad = |index: usize, problem: String| MetricsError::BadTruth {
        index,
        label: truth.segments[index].label.clone(),
        problem,
    };
    for (index, s) in truth.segments.iter().enumerate() {
        if s.start > s.end {
            return Err(bad(index, format!("start {} is after end {}", s.start, s.end)));
        }
        if s.end >= truth.frames {
            return Err(bad(index, format!("end {} is past the last frame {}", s.end, truth.frames.saturating_sub(1))));
        }
        if let Some((lo, hi)) = s.end_window.filter(|&(lo, hi)| lo > hi || hi >= truth.frames) {
            return Err(bad(index, format!("uncertainty window {lo}..={hi} is reversed or past the last frame")));
        }
    }
    Ok(())
}

/// A labelled interval `start..=end` used internally.
#[derive(Debug, Clone, PartialEq)]
struct Span {
    start: usize,
    end: usize,
    key: String,
    /// The segment's label (what a labelling method names the class).
    label: String,
}

impl Span {
    fn of(s: &Segment) -> Span {
        Span { start: s.start, end: s.end, key: cluster_key(s), label: s.label.clone() }
    }
}

fn cluster_key(s: &Segment) -> String {
    match s.cluster {
        Some(c) => format!("#{c}"),
        None => s.label.clone(),
    }
}

/// The level a segmentation is scored at: its actions, or its primitives when it has no actions.
pub fn scored_level(seg: &Segmentation) -> Level {
    if seg.segments.iter().any(|s| s.level == Level::Action) {
        Level::Action
    } else {
        Level::Primitive
    }
}

/// Action-level spans covering the take: actions in order, each transition split at its middle.
/// A method that finds no actions, only finer segments (the kinematic baselines' gestures), is
/// scored on those: its primitives stand for its actions.
fn action_spans(seg: &Segmentation) -> Vec<Span> {
    let unit = scored_level(seg);
    let has_actions = unit == Level::Action;
    let mut parts: Vec<&Segment> =
        seg.segments.iter().filter(|s| s.level == unit || (has_actions && s.level == Level::Transition)).collect();
    parts.sort_by_key(|s| (s.start, s.end));
    let actions: Vec<usize> = (0..parts.len()).filter(|&i| parts[i].level == unit).collect();
    if actions.is_empty() {
        return Vec::new();
    }
    let mut spans: Vec<Span> = actions.iter().map(|&i| Span::of(parts[i])).collect();
    // Stretch neighbouring actions over the gaps between them (transitions or unlabelled frames), meeting in the middle.
    for k in 0..spans.len().saturating_sub(1) {
        let (a_end, b_start) = (spans[k].end, spans[k + 1].start);
        if b_start > a_end + 1 {
            let gap = b_start - a_end - 1;
            let split = a_end + 1 + gap / 2; // first frame of the next action
            spans[k].end = split - 1;
            spans[k + 1].start = split;
        }
    }
    spans[0].start = 0;
    let last = spans.len() - 1;
    spans[last].end = seg.frames.saturating_sub(1);
    spans
}

/// A segmentation without actions: its primitives exactly as given, in time order.
fn primitive_spans(seg: &Segmentation) -> Vec<Span> {
    let mut spans: Vec<Span> = seg.level(Level::Primitive).map(Span::of).collect();
    spans.sort_by_key(|s| (s.start, s.end));
    spans
}

/// The boundaries of intervals `(start, end)` as given: every start and every frame after an end, except the take's
/// own first frame and the frame past its end. For a tiling these are the starts after the first; a gap between two
/// segments gives two boundaries, one where it begins and one where it ends.
fn boundaries(intervals: &[(usize, usize)], frames: usize) -> Vec<usize> {
    let mut b: Vec<usize> = intervals
        .iter()
        .flat_map(|&(start, end)| [start, end.saturating_add(1)])
        .filter(|&f| f > 0 && f < frames)
        .collect();
    b.sort_unstable();
    b.dedup();
    b
}

/// How a segmentation is scored and the spans scored ([`ScoredView`]): its actions as a tiling, or its primitives as
/// given when it has no actions.
fn scored_spans(seg: &Segmentation) -> (ScoredView, Vec<Span>) {
    match scored_level(seg) {
        Level::Action => (ScoredView::Tiling, action_spans(seg)),
        _ => (ScoredView::AsGiven, primitive_spans(seg)),
    }
}

/// The boundaries a segmentation is scored on, sorted, each once: for a segmentation with actions the cuts between
/// consecutive segments of its tiling, else every start of its primitives and every frame after an end (gaps and
/// overlaps as given) — what [`evaluate`] matches against the truth's, and what each method contributes to a
/// consensus ([`super::consensus`]). Frame 0 and the frame past the end are never boundaries.
pub fn scored_boundaries(seg: &Segmentation) -> Vec<usize> {
    let (_, spans) = scored_spans(seg);
    let intervals: Vec<(usize, usize)> = spans.iter().map(|s| (s.start, s.end)).collect();
    boundaries(&intervals, seg.frames)
}

/// Maximum one-to-one matching of sorted boundaries closer than `tol` frames (greedy is optimal on a line).
fn matched_boundaries(pred: &[usize], truth: &[usize], tol: f64) -> usize {
    let (mut i, mut j, mut matched) = (0, 0, 0);
    while i < pred.len() && j < truth.len() {
        let (p, t) = (pred[i] as f64, truth[j] as f64);
        if (p - t).abs() <= tol {
            matched += 1;
            i += 1;
            j += 1;
        } else if p < t {
            i += 1;
        } else {
            j += 1;
        }
    }
    matched
}

fn boundary_score(pred: &[usize], truth: &[usize], tolerance_s: f64, fps: f64) -> BoundaryScore {
    let matched = matched_boundaries(pred, truth, tolerance_s * fps);
    // share of `n` boundaries matched; with none, perfect only if the other side has none either
    let rate = |n: usize, other: usize| match (n, other) {
        (0, 0) => 1.0,
        (0, _) => 0.0,
        _ => matched as f64 / n as f64,
    };
    let precision = rate(pred.len(), truth.len());
    let recall = rate(truth.len(), pred.len());
    let f1 = if precision + recall > 0.0 { 2.0 * precision * recall / (precision + recall) } else { 0.0 };
    BoundaryScore { tolerance_s, precision, recall, f1, matched }
}

fn jaccard(a: (usize, usize), b: (usize, usize)) -> f64 {
    let inter = (a.1.min(b.1) + 1).saturating_sub(a.0.max(b.0));
    let union = (a.1.max(b.1) + 1) - a.0.min(b.0);
    inter as f64 / union as f64
}

/// Covering of the truth by the prediction (ClaSP / TSSB definition): Σ over true segments of |g|·max Jaccard(g, p),
/// divided by the frames the truth labels (the take's length when the truth tiles it, as in those papers).
fn covering(truth: &[(usize, usize)], pred: &[(usize, usize)]) -> f64 {
    let length = |g: (usize, usize)| (g.1 - g.0 + 1) as f64;
    let total: f64 = truth
        .iter()
        .map(|&g| {
            let best = pred.iter().map(|&p| jaccard(g, p)).fold(0.0, f64::max);
            length(g) * best
        })
        .sum();
    let labelled: f64 = truth.iter().map(|&g| length(g)).sum();
    if labelled > 0.0 {
        total / labelled
    } else {
        0.0
    }
}

/// Per-frame keys of spans (None where no span covers the frame).
fn per_frame(spans: &[Span], frames: usize) -> Vec<Option<usize>> {
    let mut keys: BTreeMap<&str, usize> = BTreeMap::new();
    for s in spans {
        let n = keys.len();
        keys.entry(s.key.as_str()).or_insert(n);
    }
    let mut out = vec![None; frames];
    for s in spans {
        let k = keys[s.key.as_str()];
        for slot in out.iter_mut().take(s.end.min(frames.saturating_sub(1)) + 1).skip(s.start) {
            *slot = Some(k);
        }
    }
    out
}

fn truth_frames(truth: &Truth) -> (Vec<Option<usize>>, Vec<String>) {
    let mut labels: Vec<String> = Vec::new();
    let spans: Vec<Span> = truth
        .segments
        .iter()
        .map(|s| {
            if !labels.contains(&s.label) {
                labels.push(s.label.clone());
            }
            Span { start: s.start, end: s.end, key: s.label.clone(), label: s.label.clone() }
        })
        .collect();
    // Index keys by first appearance so that `labels[k]` names key k.
    let mut out = vec![None; truth.frames];
    for s in &spans {
        let k = labels.iter().position(|l| *l == s.key).unwrap_or(0);
        for slot in out.iter_mut().take(s.end.min(truth.frames.saturating_sub(1)) + 1).skip(s.start) {
            *slot = Some(k);
        }
    }
    (out, labels)
}

/// Contingency table rows = predicted keys, columns = true labels.
fn contingency(pred: &[Option<usize>], truth: &[Option<usize>], n_pred: usize, n_true: usize) -> Vec<Vec<i64>> {
    let mut table = vec![vec![0i64; n_true]; n_pred];
    for (p, t) in pred.iter().zip(truth) {
        if let (Some(p), Some(t)) = (p, t) {
            table[*p][*t] += 1;
        }
    }
    table
}

/// The predicted per-frame keys as true label indices: by name ([`Naming`]: always for a labeller, else when any key
/// names a true label or is `unknown`) — a name the truth lacks, `unknown` and a key without a label count as wrong
/// (indices past the true ones) —, else by the one-to-one Hungarian matching of the contingency `table` (cluster
/// ids name nothing), keys left unmatched wrong.
fn mapped_labels(
    spans: &[Span],
    pred: &[Option<usize>],
    labels: &[String],
    table: &[Vec<i64>],
    naming: Naming,
) -> Vec<Option<usize>> {
    // the keys in the order `per_frame` numbers them
    let mut names: Vec<&str> = Vec::new();
    for s in spans {
        if !names.contains(&s.key.as_str()) {
            names.push(&s.key);
        }
    }
    // by name (a labeller's `#3` named `Jog`): a true label's index, else past the true ones (wrong) — `unknown`, a
    // class the take does not have (before issue 50 one such name sent the whole take to the matching below, where
    // a `Squat` called `KneeRaise` could count as right)
    let label_of = |key: &str| spans.iter().find(|s| s.key == key).map(|s| s.label.as_str());
    let named = match naming {
        Naming::ByName => true,
        Naming::Detect => {
            names.iter().any(|n| label_of(n).is_some_and(|l| l == super::UNKNOWN || labels.iter().any(|t| t == l)))
        }
    };
    let map: Vec<usize> = if named {
        names
            .iter()
            .enumerate()
            .map(|(k, n)| label_of(n).and_then(|l| labels.iter().position(|t| t == l)).unwrap_or(labels.len() + k))
            .collect()
    } else {
        let (rows, cols) = (table.len(), table.first().map_or(0, Vec::len));
        let mut map: Vec<usize> = (0..rows).map(|k| cols + k).collect();
        if rows > 0 && cols > 0 {
            if rows <= cols {
                let (_, assigned) = kuhn_munkres(&Matrix::from_fn(rows, cols, |(i, j)| table[i][j]));
                for (k, &label) in assigned.iter().enumerate() {
                    map[k] = label;
                }
            } else {
                let (_, assigned) = kuhn_munkres(&Matrix::from_fn(cols, rows, |(i, j)| table[j][i]));
                for (label, &k) in assigned.iter().enumerate() {
                    map[k] = label;
                }
            }
        }
        map
    };
    pred.iter().map(|k| k.and_then(|k| map.get(k).copied())).collect()
}

/// One-to-one matching of predicted clusters to labels maximising agreeing frames; returns the agreeing frames.
fn hungarian_agreement(table: &[Vec<i64>]) -> i64 {
    let (rows, cols) = (table.len(), table.first().map_or(0, Vec::len));
    if rows == 0 || cols == 0 {
        return 0;
    }
    // kuhn_munkres needs rows <= columns: transpose when there are more clusters than labels.
    let weights = if rows <= cols {
        Matrix::from_fn(rows, cols, |(i, j)| table[i][j])
    } else {
        Matrix::from_fn(cols, rows, |(i, j)| table[j][i])
    };
    kuhn_munkres(&weights).0
}

/// Whether each frame lies in an uncertainty window of the truth.
fn uncertain_frames(truth: &Truth, fps: f64, half_width_s: f64) -> Vec<bool> {
    let mut out = vec![false; truth.frames];
    let last = truth.frames.saturating_sub(1);
    let half = (half_width_s * fps).round() as usize;
    for (i, s) in truth.segments.iter().enumerate() {
        if i + 1 == truth.segments.len() {
            break; // the last segment's end is the end of the take, not a boundary
        }
        let (lo, hi) = s.end_window.unwrap_or((s.end.saturating_sub(half), s.end.saturating_add(half)));
        for slot in out.iter_mut().take(hi.min(last) + 1).skip(lo) {
            *slot = true;
        }
    }
    out
}

/// Strict and tolerant accuracy (see the module documentation).
fn strict_tolerant(
    seg: &Segmentation,
    truth: &Truth,
    truth_keys: &[Option<usize>],
    n_labels: usize,
    tol: &Tolerances,
) -> (f64, f64) {
    let mut prims: Vec<Span> = seg.level(Level::Primitive).map(Span::of).collect();
    if prims.is_empty() {
        prims = seg.level(Level::Action).map(Span::of).collect();
    }
    let frames = truth.frames;
    let pred = per_frame(&prims, frames);
    let n_pred = pred.iter().flatten().max().map_or(0, |m| m + 1);
    let table = contingency(&pred, truth_keys, n_pred, n_labels);
    // Many-to-one: each cluster takes the class it overlaps most.
    let class_of: Vec<Option<usize>> = table
        .iter()
        .map(|row| row.iter().enumerate().max_by_key(|(_, &v)| v).filter(|(_, &v)| v > 0).map(|(j, _)| j))
        .collect();
    let uncertain = uncertain_frames(truth, seg.fps, tol.uncertain_s);
    let (mut strict, mut tolerant) = (0usize, 0usize);
    for f in 0..frames {
        let ok = match (pred[f], truth_keys[f]) {
            (Some(p), Some(t)) => class_of[p] == Some(t),
            _ => false,
        };
        strict += ok as usize;
        tolerant += (ok || uncertain[f]) as usize;
    }
    (strict as f64 / frames.max(1) as f64, tolerant as f64 / frames.max(1) as f64)
}

/// Bouchard & Badler's segment score of the spans `found` against `truth` (see [`SegmentScore`]):
/// candidate pairs within the tolerance at both ends, taken closest first (sum of the two
/// boundary differences), each segment used once.
pub fn segment_score(found: &[(usize, usize)], truth: &[(usize, usize)], tolerance_s: f64, fps: f64) -> SegmentScore {
    let tol = tolerance_s * fps;
    let mut pairs: Vec<(usize, usize, usize)> = Vec::new();
    for (i, &(fs, fe)) in found.iter().enumerate() {
        for (j, &(ts, te)) in truth.iter().enumerate() {
            let (ds, de) = (fs.abs_diff(ts), fe.abs_diff(te));
            if ds as f64 <= tol && de as f64 <= tol {
                pairs.push((ds.saturating_add(de), i, j));
            }
        }
    }
    pairs.sort_unstable();
    let (mut used_f, mut used_t) = (vec![false; found.len()], vec![false; truth.len()]);
    let mut matched = 0;
    for (_, i, j) in pairs {
        if !used_f[i] && !used_t[j] {
            (used_f[i], used_t[j]) = (true, true);
            matched += 1;
        }
    }
    let (unmatched_found, unmatched_true) = (found.len() - matched, truth.len() - matched);
    let similarity = matched as f64 - (unmatched_found + unmatched_true) as f64 / 2.0;
    SegmentScore { tolerance_s, matched, unmatched_found, unmatched_true, similarity }
}

/// Scores `seg` against `truth` (both at the file's frame rate, 0-based rows). Inputs that break
/// the schema (reversed or out-of-range segments, more than [`MAX_FRAMES`] frames) are errors.
pub fn evaluate(seg: &Segmentation, truth: &Truth, tol: &Tolerances) -> Result<Scores, MetricsError> {
    if seg.frames != truth.frames {
        return Err(MetricsError::LengthMismatch { seg: seg.frames, truth: truth.frames });
    }
    check_inputs(seg, truth)?;
    let (scored_as, spans) = scored_spans(seg);
    // A method that found nothing is scored as finding nothing (every true segment and boundary missed), not refused.
    let true_iv: Vec<(usize, usize)> = truth.segments.iter().map(|s| (s.start, s.end)).collect();
    let pred_iv: Vec<(usize, usize)> = spans.iter().map(|s| (s.start, s.end)).collect();
    let pred_b = boundaries(&pred_iv, truth.frames);
    // the truth in the same view: as a tiling its boundaries are where segments start (an unlabelled tail or gap is
    // not a cut of its own), as given every start and every frame after an end
    let true_b = match scored_as {
        ScoredView::Tiling => {
            let mut starts: Vec<usize> = true_iv.iter().map(|g| g.0).filter(|&f| f > 0 && f < truth.frames).collect();
            starts.sort_unstable();
            starts.dedup();
            starts
        }
        ScoredView::AsGiven => boundaries(&true_iv, truth.frames),
    };
    let boundaries = tol.boundary_s.iter().map(|&t| boundary_score(&pred_b, &true_b, t, seg.fps)).collect();

    let covering = covering(&true_iv, &pred_iv);
    let segments = segment_score(&pred_iv, &true_iv, tol.boundary_s[0], seg.fps);

    let (truth_keys, labels) = truth_frames(truth);
    let labelled = truth_keys.iter().flatten().count();
    let pred_keys = per_frame(&spans, truth.frames);
    let n_pred = pred_keys.iter().flatten().max().map_or(0, |m| m + 1);
    let table = contingency(&pred_keys, &truth_keys, n_pred, labels.len());
    let hungarian_accuracy = hungarian_agreement(&table) as f64 / labelled.max(1) as f64;
    let (strict_accuracy, tolerant_accuracy) = strict_tolerant(seg, truth, &truth_keys, labels.len(), tol);
    let labelling = labelling::score(&mapped_labels(&spans, &pred_keys, &labels, &table, tol.naming), &truth_keys);

    Ok(Scores {
        trial: truth.trial.clone(),
        scored_as,
        true_segments: truth.segments.len(),
        true_boundaries: true_b.len(),
        predicted_boundaries: pred_b.len(),
        boundaries,
        segments,
        covering,
        hungarian_accuracy,
        strict_accuracy,
        tolerant_accuracy,
        labelling,
    })
}

#[cfg(test)]
mod tests {
    use super::super::truth::TruthSegment;
    use super::*;

    fn seg(frames: usize, parts: &[(usize, usize, Level, Option<usize>)]) -> Segmentation {
        Segmentation {
            file: "t.bvh".into(),
            fps: 10.0,
            frames,
            method: "test".into(),
            params: serde_json::Value::Null,
            segments: parts
                .iter()
                .map(|&(start, end, level, cluster)| Segment {
                    start,
                    end,
                    label: String::new(),
                    level,
                    cluster,
                    score: None,
                    mirror_of: None,
                    effort: None,
                })
                .collect(),
        }
    }

    fn truth(frames: usize, parts: &[(usize, usize, &str)]) -> Truth {
        Truth {
            trial: "t".into(),
            frames,
            segments: parts
                .iter()
                .map(|&(start, end, l)| TruthSegment { start, end, label: l.into(), end_window: None })
                .collect(),
        }
    }

    #[test]
    fn perfect_segmentation_scores_one_everywhere() {
        let t = truth(100, &[(0, 39, "walk"), (40, 69, "jump"), (70, 99, "walk")]);
        let s = seg(
            100,
            &[(0, 39, Level::Action, Some(0)), (40, 69, Level::Action, Some(1)), (70, 99, Level::Action, Some(0))],
        );
        let sc = evaluate(&s, &t, &Tolerances::default()).unwrap();
        assert_eq!((sc.true_boundaries, sc.predicted_boundaries), (2, 2));
        for b in &sc.boundaries {
            assert_eq!((b.precision, b.recall, b.f1), (1.0, 1.0, 1.0));
        }
        assert_eq!(sc.covering, 1.0);
        assert_eq!(sc.hungarian_accuracy, 1.0);
        assert_eq!(sc.strict_accuracy, 1.0);
        assert_eq!(sc.tolerant_accuracy, 1.0);
        // clusters #0/#1 mapped onto walk/jump by the Hungarian matching
        assert_eq!(sc.labelling, LabellingScores { frame_accuracy: 1.0, edit: 100.0, f1: [100.0; 3] });
    }

    #[test]
    fn labels_that_name_the_truths_are_scored_by_name() {
        let t = truth(100, &[(0, 39, "walk"), (40, 69, "jump"), (70, 99, "walk")]);
        let mut s = seg(100, &[(0, 39, Level::Action, None), (40, 99, Level::Action, None)]);
        // a labelling method calls the second half `walk`: wrong on 40..=69, by name (a Hungarian
        // matching of clusters would have called it `jump` and scored it 70 % instead)
        s.segments[0].label = "walk".into();
        s.segments[1].label = "walk".into();
        let sc = evaluate(&s, &t, &Tolerances::default()).unwrap();
        assert!((sc.labelling.frame_accuracy - 0.7).abs() < 1e-12, "{:?}", sc.labelling);
        // one `walk` run against walk, jump, walk: distance 2 over 3
        assert!((sc.labelling.edit - 100.0 / 3.0).abs() < 1e-9, "{:?}", sc.labelling);
    }

    #[test]
    fn a_labellers_classes_are_scored_by_their_names_and_unknown_frames_are_wrong() {
        // DT-FCN / k-NN segments carry the class index as their cluster and its name as their label: scored by name,
        // not remapped by the Hungarian matching (which would turn a `jump` called `walk` into a right answer).
        let t = truth(100, &[(0, 39, "walk"), (40, 69, "jump"), (70, 99, "walk")]);
        let mut s = seg(
            100,
            &[(0, 39, Level::Action, Some(1)), (40, 59, Level::Action, Some(1)), (60, 69, Level::Action, None)],
        );
        s.segments.push(s.segments[0].clone());
        s.segments[3].start = 70;
        s.segments[3].end = 99;
        for (seg, label) in s.segments.iter_mut().zip(["walk", "walk", "unknown", "walk"]) {
            seg.label = label.into();
        }
        let sc = evaluate(&s, &t, &Tolerances::default()).unwrap();
        // walk on 0..=59 and 70..=99: right on 70 frames; 40..=59 (walk for jump) and 60..=69 (unknown) wrong
        assert!((sc.labelling.frame_accuracy - 0.7).abs() < 1e-12, "{:?}", sc.labelling);
    }

    /// Issue 50's case: a held-out take's labels, right, scored by name; the same labels with their names swapped
    /// (JumpJack↔Twist, KneeRaise→Squat, ArmCircle→Jog, a class the take does not have) score what they are — wrong
    /// — where one foreign name used to send the whole take to the one-to-one matching, which scored them as right.
    #[test]
    fn swapped_and_foreign_names_are_wrong_by_name() {
        let parts =
            [(0, 19, "JumpJack"), (20, 39, "Twist"), (40, 59, "KneeRaise"), (60, 79, "Squat"), (80, 99, "ArmCircle")];
        let t = truth(100, &parts);
        let named = |names: [&str; 5]| {
            let mut s = seg(100, &parts.map(|(a, b, _)| (a, b, Level::Action, None)));
            for (segment, name) in s.segments.iter_mut().zip(names) {
                segment.label = name.into();
            }
            s
        };
        let accuracy = |s: &Segmentation, tol: Tolerances| evaluate(s, &t, &tol).unwrap().labelling.frame_accuracy;
        let right = named(["JumpJack", "Twist", "KneeRaise", "Squat", "ArmCircle"]);
        assert_eq!(accuracy(&right, Tolerances::default()), 1.0);
        let swapped = named(["Twist", "JumpJack", "Squat", "Squat", "Jog"]);
        // only 60..=79 (Squat called Squat) is right
        assert!((accuracy(&swapped, Tolerances::default()) - 0.2).abs() < 1e-12);
        assert!((accuracy(&swapped, Tolerances::by_name()) - 0.2).abs() < 1e-12);
        // one foreign name: its frames wrong, the rest scored by name
        let foreign = named(["JumpJack", "Twist", "KneeRaise", "Squat", "Jog"]);
        assert!((accuracy(&foreign, Tolerances::default()) - 0.8).abs() < 1e-12);
        // every name foreign: a labeller's run is wrong everywhere; read as clusters (no naming asked, nothing named
        // as the truth names) the one-to-one matching scores the partition
        let strangers = named(["Jog", "Walk", "Run", "Skip", "Hop"]);
        assert_eq!(accuracy(&strangers, Tolerances::by_name()), 0.0);
        assert_eq!(accuracy(&strangers, Tolerances::default()), 1.0);
        // `unknown` is wrong, and a run naming only unknown is read by name
        let unknown = named(["unknown", "unknown", "unknown", "unknown", "unknown"]);
        assert_eq!(accuracy(&unknown, Tolerances::default()), 0.0);
    }

    #[test]
    fn transitions_split_at_their_middle() {
        // Transition 30..=49 between two actions: the boundary lands at 40.
        let s = seg(
            100,
            &[(0, 29, Level::Action, Some(0)), (30, 49, Level::Transition, None), (50, 99, Level::Action, Some(1))],
        );
        let spans = action_spans(&s);
        assert_eq!(spans.iter().map(|s| (s.start, s.end)).collect::<Vec<_>>(), vec![(0, 39), (40, 99)]);
        let t = truth(100, &[(0, 39, "a"), (40, 99, "b")]);
        let sc = evaluate(&s, &t, &Tolerances::default()).unwrap();
        assert_eq!(sc.boundaries[0].f1, 1.0);
        assert_eq!(sc.covering, 1.0);
        // Strict accuracy falls back to actions (no primitives); transition frames are unlabelled → wrong.
        assert!((sc.strict_accuracy - 0.8).abs() < 1e-12, "{}", sc.strict_accuracy);
    }

    #[test]
    fn boundary_matching_is_one_to_one_within_tolerance() {
        // fps 10: tolerance 0.5 s = 5 frames. Two predictions near one true boundary count once.
        assert_eq!(matched_boundaries(&[38, 42], &[40], 5.0), 1);
        assert_eq!(matched_boundaries(&[30], &[40], 5.0), 0);
        assert_eq!(matched_boundaries(&[10, 36, 44], &[12, 40], 5.0), 2);
        let b = boundary_score(&[38, 42, 90], &[40, 60], 0.5, 10.0);
        assert_eq!(b.matched, 1);
        assert!((b.precision - 1.0 / 3.0).abs() < 1e-12);
        assert!((b.recall - 0.5).abs() < 1e-12);
        assert!((b.f1 - 0.4).abs() < 1e-12);
    }

    #[test]
    fn one_segment_covering_matches_hand_computation() {
        // Truth 0..=39, 40..=99; prediction one segment 0..=99.
        // Covering = (40·0.4 + 60·0.6) / 100 = 0.52.
        let t = truth(100, &[(0, 39, "a"), (40, 99, "b")]);
        let s = seg(100, &[(0, 99, Level::Action, Some(0))]);
        let sc = evaluate(&s, &t, &Tolerances::default()).unwrap();
        assert!((sc.covering - 0.52).abs() < 1e-12);
        assert_eq!(sc.boundaries[1].f1, 0.0);
        assert!((sc.hungarian_accuracy - 0.6).abs() < 1e-12);
    }

    #[test]
    fn hungarian_is_one_to_one_but_strict_is_many_to_one() {
        // Three predicted clusters over two labels: Hungarian can use only two of them,
        // strict accuracy maps clusters 0 and 2 both to "walk".
        let t = truth(90, &[(0, 59, "walk"), (60, 89, "jump")]);
        let s = seg(
            90,
            &[
                (0, 29, Level::Action, Some(0)),
                (30, 59, Level::Action, Some(2)),
                (60, 89, Level::Action, Some(1)),
                (0, 29, Level::Primitive, Some(0)),
                (30, 59, Level::Primitive, Some(2)),
                (60, 89, Level::Primitive, Some(1)),
            ],
        );
        let sc = evaluate(&s, &t, &Tolerances::default()).unwrap();
        assert!((sc.hungarian_accuracy - 60.0 / 90.0).abs() < 1e-12);
        assert_eq!(sc.strict_accuracy, 1.0);
    }

    #[test]
    fn tolerant_accepts_uncertainty_windows() {
        let mut t = truth(100, &[(0, 49, "a"), (50, 99, "b")]);
        t.segments[0].end_window = Some((45, 54));
        // Prediction cuts 5 frames late: frames 50..=54 wrong strictly, inside the window tolerantly.
        let s = seg(100, &[(0, 54, Level::Primitive, Some(0)), (55, 99, Level::Primitive, Some(1))]);
        let sc = evaluate(&s, &t, &Tolerances::default()).unwrap();
        assert!((sc.strict_accuracy - 0.95).abs() < 1e-12);
        assert_eq!(sc.tolerant_accuracy, 1.0);
    }

    #[test]
    fn out_of_range_frame_numbers_are_errors_not_overflows() {
        let t = truth(100, &[(0, 99, "a")]);
        // From JSON: `end: usize::MAX` is past the last frame.
        let text = r#"{"file": "t.bvh", "fps": 10.0, "frames": 100, "method": "m", "params": null,
            "segments": [{"start": 0, "end": 18446744073709551615, "label": "", "level": "action",
                          "cluster": 0, "score": null}]}"#;
        let e = Segmentation::from_json(text).unwrap_err();
        assert!(e.to_string().contains("end 18446744073709551615 is past the last frame 99"), "{e}");
        // Built in code, never validated: evaluate checks it itself.
        let mut s = seg(100, &[(0, 49, Level::Action, Some(0)), (50, 99, Level::Action, Some(1))]);
        s.segments[0].end = usize::MAX;
        let e = evaluate(&s, &t, &Tolerances::default()).unwrap_err();
        assert_eq!(e.to_string(), "segmentation: segment 0: end 18446744073709551615 is past the last frame 99");
        // A take as long as usize allows, on both sides.
        let mut huge = truth(usize::MAX, &[(0, usize::MAX - 1, "a")]);
        let s = seg(usize::MAX, &[(0, usize::MAX - 1, Level::Action, Some(0))]);
        let e = evaluate(&s, &huge, &Tolerances::default()).unwrap_err();
        assert!(matches!(e, MetricsError::TooLong { .. }), "{e}");
        // A truth built in code with a segment past its end, or a window past it.
        huge.frames = 100;
        let s = seg(100, &[(0, 99, Level::Action, Some(0))]);
        let e = evaluate(&s, &huge, &Tolerances::default()).unwrap_err();
        assert!(e.to_string().starts_with("ground truth segment 0 (`a`): end"), "{e}");
        let mut t = truth(100, &[(0, 49, "a"), (50, 99, "b")]);
        t.segments[0].end_window = Some((40, usize::MAX));
        let e = evaluate(&s, &t, &Tolerances::default()).unwrap_err();
        assert!(e.to_string().contains("uncertainty window"), "{e}");
        // A huge tolerance saturates instead of overflowing.
        let t = truth(100, &[(0, 49, "a"), (50, 99, "b")]);
        let tol = Tolerances { uncertain_s: 1e300, ..Tolerances::default() };
        assert_eq!(evaluate(&s, &t, &tol).unwrap().tolerant_accuracy, 1.0);
    }

    #[test]
    fn length_mismatch_is_an_error_not_a_score() {
        let t = truth(100, &[(0, 99, "a")]);
        let s = seg(25, &[(0, 24, Level::Action, None)]);
        assert_eq!(evaluate(&s, &t, &Tolerances::default()), Err(MetricsError::LengthMismatch { seg: 25, truth: 100 }));
    }

    #[test]
    fn a_segmentation_of_primitives_only_is_scored_on_its_primitives() {
        let truth = truth(100, &[(0, 49, "a"), (50, 99, "b")]);
        let s = seg(100, &[(0, 51, Level::Primitive, None), (52, 99, Level::Primitive, None)]);
        let scores = evaluate(&s, &truth, &Tolerances::default()).unwrap();
        assert_eq!((scores.predicted_boundaries, scores.boundaries[0].matched), (1, 1));
        assert!(scores.covering > 0.9, "{}", scores.covering);
    }

    #[test]
    fn gestures_equal_to_the_truths_spans_with_gaps_score_as_given() {
        // The issue's case: three gestures equal to the truth's three spans, 2 s gaps (20 frames at
        // 10 fps) between them. As given, every segment matches: s = 3 (the number of segments),
        // boundary F1 1 at both tolerances, covering 1. (Stretched into a tiling, as `eval` used to
        // score every level, none matched and s was −3.)
        let t = truth(150, &[(10, 39, "reach"), (60, 89, "wave"), (110, 139, "reach")]);
        let s = seg(
            150,
            &[
                (10, 39, Level::Primitive, Some(0)),
                (60, 89, Level::Primitive, Some(1)),
                (110, 139, Level::Primitive, Some(0)),
            ],
        );
        let sc = evaluate(&s, &t, &Tolerances::default()).unwrap();
        assert_eq!(sc.scored_as, ScoredView::AsGiven);
        assert_eq!(
            (sc.segments.matched, sc.segments.unmatched_found, sc.segments.unmatched_true, sc.segments.similarity),
            (3, 0, 0, 3.0)
        );
        // boundaries where each gesture starts and after each one ends: 10, 40, 60, 90, 110, 140
        assert_eq!((sc.true_boundaries, sc.predicted_boundaries), (6, 6));
        assert!(sc.boundaries.iter().all(|b| b.f1 == 1.0), "{:?}", sc.boundaries);
        assert_eq!(sc.covering, 1.0);
        // gaps are unlabelled on both sides: every labelled frame agrees
        assert_eq!(sc.hungarian_accuracy, 1.0);
    }

    #[test]
    fn overlapping_arms_are_scored_as_given_and_actions_as_a_tiling() {
        // Two arms' gestures overlap (LMA): both are matched, neither is cut by the other.
        let t = truth(100, &[(0, 49, "a"), (50, 99, "b")]);
        let s = seg(100, &[(0, 49, Level::Primitive, None), (20, 79, Level::Primitive, None)]);
        let sc = evaluate(&s, &t, &Tolerances::default()).unwrap();
        // boundaries as given: 20, 50 and 80 (0 and 100 are the take's own ends), truth 50: P 1/3, R 1
        assert_eq!((sc.predicted_boundaries, sc.boundaries[0].matched), (3, 1));
        assert!((sc.boundaries[0].f1 - 0.5).abs() < 1e-12);
        // (0,49) matches (0,49); (20,79) ends 20 frames from 99: s = 1 − (1 + 1)/2 = 0
        assert_eq!(sc.segments.similarity, 0.0);
        // covering: a by (0,49) → 50·1; b by (20,79): Jaccard 30/80 → 50·0.375; over 100 frames
        assert!((sc.covering - (50.0 + 50.0 * 0.375) / 100.0).abs() < 1e-12, "{}", sc.covering);
        // Actions with a gap between them are a tiling: the gap is split, the first starts at 0.
        let s = seg(100, &[(5, 39, Level::Action, Some(0)), (60, 99, Level::Action, Some(1))]);
        let sc = evaluate(&s, &t, &Tolerances::default()).unwrap();
        assert_eq!(sc.scored_as, ScoredView::Tiling);
        assert_eq!(sc.predicted_boundaries, 1); // at 50, the gap 40..=59 split in its middle
        assert_eq!(sc.boundaries[0].f1, 1.0);
        assert_eq!(sc.covering, 1.0);
        // Against a truth that leaves the take's last frames unlabelled, the tiling's truth cuts only where its
        // segments start: the unlabelled tail is no boundary of its own.
        let t = truth(100, &[(0, 49, "a"), (50, 97, "b")]);
        let sc = evaluate(&s, &t, &Tolerances::default()).unwrap();
        assert_eq!((sc.true_boundaries, sc.boundaries[0].f1), (1, 1.0));
    }

    #[test]
    fn a_method_that_found_nothing_scores_nothing() {
        let t = truth(100, &[(0, 49, "a"), (50, 99, "b")]);
        let sc = evaluate(&seg(100, &[]), &t, &Tolerances::default()).unwrap();
        assert_eq!(sc.scored_as, ScoredView::AsGiven);
        assert_eq!((sc.predicted_boundaries, sc.boundaries[1].f1, sc.covering), (0, 0.0, 0.0));
        assert_eq!(sc.segments.similarity, -1.0); // two true segments missed: 0 − 2/2
        assert_eq!((sc.hungarian_accuracy, sc.labelling.frame_accuracy), (0.0, 0.0));
    }

    #[test]
    fn boundaries_as_given_are_starts_and_frames_after_ends() {
        assert_eq!(boundaries(&[(0, 9), (10, 19), (20, 29)], 30), vec![10, 20]);
        assert_eq!(boundaries(&[(5, 9), (20, 29)], 30), vec![5, 10, 20]);
        assert_eq!(boundaries(&[(0, usize::MAX - 1)], usize::MAX), Vec::<usize>::new());
    }

    #[test]
    fn segments_match_when_both_ends_are_close_and_only_once() {
        // at 10 fps, 0.5 s = 5 frames
        let truth = [(0, 49), (50, 99), (100, 149)];
        let found = [(0, 47), (48, 60), (61, 100), (101, 149)];
        let s = segment_score(&found, &truth, 0.5, 10.0);
        // (0,47)~(0,49); (101,149)~(100,149); (48,60) ends 39 from 99; (61,100) starts 11 from 50
        assert_eq!((s.matched, s.unmatched_found, s.unmatched_true), (2, 2, 1));
        assert_eq!(s.similarity, 2.0 - 3.0 / 2.0);
        // the closest pair wins when one segment could match two
        let s = segment_score(&[(0, 50), (2, 49)], &[(0, 49)], 0.5, 10.0);
        assert_eq!((s.matched, s.unmatched_found), (1, 1));
        assert_eq!(segment_score(&truth, &truth, 0.5, 10.0).similarity, 3.0);
        assert_eq!(segment_score(&[], &truth, 0.5, 10.0).similarity, -1.5);
    }
}
