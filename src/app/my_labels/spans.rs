//! One of my labelled segments ([`LabelSpan`]) and the maths on a sorted, non-overlapping list of them that the
//! edit model ([`super::edits`]) uses: a copied row normalised to the take, and a dragged boundary rolling over
//! its neighbours, never leaving one thinner than [`MIN_SPAN`] frames.

/// One of my labelled segments: frames `start..=end` (0-based), `label` (empty: unlabelled).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LabelSpan {
    pub start: usize,
    pub end: usize,
    pub label: String,
}

impl LabelSpan {
    pub fn new(start: usize, end: usize, label: &str) -> LabelSpan {
        LabelSpan { start, end, label: label.to_string() }
    }

    /// Frames it covers.
    pub fn len(&self) -> usize {
        self.end + 1 - self.start
    }

    pub fn contains(&self, frame: usize) -> bool {
        self.start <= frame && frame <= self.end
    }
}

/// Segments made fit for the row: sorted by start, clipped to `frames`, overlaps cut (a segment
/// starting inside the previous one starts after it; one left empty is dropped).
pub(super) fn normalised(mut spans: Vec<LabelSpan>, frames: usize) -> Vec<LabelSpan> {
    spans.retain(|s| s.start <= s.end && s.start < frames);
    spans.sort_by_key(|s| (s.start, s.end));
    let mut out: Vec<LabelSpan> = Vec::with_capacity(spans.len());
    for mut s in spans {
        s.end = s.end.min(frames - 1);
        if let Some(prev) = out.last() {
            if s.start <= prev.end {
                s.start = prev.end + 1;
            }
        }
        if s.start <= s.end {
            out.push(s);
        }
    }
    out
}

/// The fewest frames a drag leaves of a segment it shrinks or of a gap it narrows: one frame
/// is too thin to see or to grab, and reads as a boundary of its own.
pub const MIN_SPAN: usize = 2;

/// [`MyLabels::drag_boundary`](crate::app::my_labels::edits::MyLabels::drag_boundary) to the right
/// (`to > cut`) on sorted, non-overlapping `spans` of a take of `frames`: the new segments and where the
/// boundary landed.
pub(super) fn roll_right(spans: &[LabelSpan], cut: usize, to: usize, frames: usize) -> (Vec<LabelSpan>, usize) {
    // the segment the boundary grows: the one ending at it (none: a gap, or the take's start, grows)
    let grower = spans.iter().position(|s| s.end + 1 == cut);
    let mut to = to.min(frames);
    // a gap grows: over the segment its boundary starts, at most (it never rolls on over others)
    if grower.is_none() {
        if let Some(own) = spans.iter().find(|s| s.start == cut) {
            to = to.min(own.end + 1);
        }
    }
    // the segment `to` falls inside (not at its start): shrunk to at least MIN_SPAN frames, or
    // left whole when it is shorter — it is removed only once the boundary passes its end
    if let Some(s) = spans.iter().find(|s| s.start < to && to <= s.end && s.start >= cut) {
        let left = s.end + 1 - to;
        if left < MIN_SPAN {
            to = if s.len() > MIN_SPAN { s.end + 1 - MIN_SPAN } else { s.start };
        }
    }
    let covered = |f: usize| spans.iter().any(|s| s.contains(f));
    match grower {
        // a segment grows: a gap it narrows to a sliver closes up to the next segment
        Some(_) if to < frames && !covered(to) && to > cut => {
            let gap_end = spans.iter().find(|s| s.start > to).map_or(frames, |s| s.start);
            if gap_end - to < MIN_SPAN {
                to = gap_end;
            }
        }
        // a gap grows from the take's start: none thinner than MIN_SPAN frames
        None if cut == 0 && to < MIN_SPAN => to = 0,
        _ => {}
    }
    if to <= cut {
        return (spans.to_vec(), cut);
    }
    let mut out = Vec::with_capacity(spans.len());
    for (i, s) in spans.iter().enumerate() {
        if Some(i) == grower {
            out.push(LabelSpan { end: to - 1, ..s.clone() });
        } else if s.start < cut || s.start >= to {
            out.push(s.clone());
        } else if s.end >= to {
            out.push(LabelSpan { start: to, ..s.clone() });
        }
        // else: crossed entirely, removed
    }
    (out, to)
}
