//! The studio's "my labels" row as a pure edit model, tested natively: the user's own labelled
//! segments of the take on screen, the segment selected, and an undo/redo history. The page
//! (`src/app/my_labels/row.rs`) draws it, turns pointer and key events into the operations below and
//! keeps it in the browser's storage.
//!
//! * **Segments** are `(start, end, label)` with inclusive 0-based frames, sorted, never
//!   overlapping and never empty; there may be **gaps** (frames no segment covers). An empty
//!   label means *unlabelled* (drawn hatched, left out of the label CSV).
//! * **Start**: [`MyLabels::copy_from`] copies any row (its segments normalised: sorted, clipped to
//!   the take, overlaps cut); [`MyLabels::start_empty`] makes one unlabelled segment over the whole
//!   take, so that *split at the playhead* works at once (a row with no segment has nothing to
//!   split).
//! * **Boundaries** are *cuts*: cut `c` lies between frames `c - 1` and `c` (`0..=frames`). A cut
//!   between two touching segments moves both ([`MyLabels::move_boundary`]); a cut next to a gap
//!   moves only its segment's edge, into the gap. Either way it is clamped so that no segment
//!   becomes empty and none overlaps another. While dragging, [`snap`](super::snap::snap) pulls the cut to the
//!   nearest cut of the other rows within [`snap_reach`](super::snap::snap_reach) (8 px, 3 frames at most)
//!   ([`snap_tolerance`](super::snap::snap_tolerance) converts them to frames at the zoom); of two equally
//!   near, the earlier.
//! * **Delete** removes the selected segment and **leaves a gap** (as ELAN and Label Studio do:
//!   deleting a label does not relabel the neighbours' frames); the next segment is selected.
//!   [`MyLabels::fill_gap`] puts an unlabelled segment back over the gap under the playhead.
//! * **Split** at a frame keeps the label on both parts (the right one is selected); **merge**
//!   joins the selected segment with the next one (a gap between them included) under the
//!   selected segment's label (the next one's when it is unlabelled).
//! * **Add a boundary** ([`MyLabels::add_boundary`]: a consensus boundary accepted on the page) splits the segment
//!   it falls in, or, with no segment yet, starts the row as *start empty* does and cuts it there (one edit); a
//!   boundary already there, in a gap or at the take's edge is refused.
//! * **Undo / redo**: every edit (copy, start empty, move, split, merge, relabel, delete, fill,
//!   clear) is undoable; a new edit clears the redo list; the history keeps the last
//!   [`HISTORY_LIMIT`] edits. An edit that changes nothing (a boundary dropped where it was, the
//!   same label) is not recorded. Selecting is not an edit.
//! * **Storage**: [`MyLabels::to_json`] / [`MyLabels::from_json`] (format [`FORMAT`](super::stored::FORMAT), version
//!   [`VERSION`](super::stored::VERSION); the segments only, not the history), with a clear error when stored
//!   data is corrupt or for another take; the key is [`storage_key`](super::stored::storage_key) (file name,
//!   frames, frame rate, joints, a [`fingerprint`](super::stored::fingerprint) of the motion).
//!
//! Beside the model, in their own files: one segment and the maths over sorted segments ([`super::spans`]), the
//! label words — the reserved ones, the vocabulary, the colour class ([`super::vocabulary`]) —, snapping
//! ([`super::snap`]) and the stored form ([`super::stored`]).

use crate::app::my_labels::spans::{normalised, roll_right, LabelSpan};
use crate::app::my_labels::vocabulary::{is_labelled, suggestions};
use crate::labels::LabelRow;
use crate::segment::{Level, Segment, Segmentation};
use std::collections::VecDeque;

/// Edits the history keeps (older ones are forgotten).
pub const HISTORY_LIMIT: usize = 200;
/// The longest label, in characters.
pub const MAX_LABEL_CHARS: usize = 120;

/// Why an edit was refused (the model is left as it was).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EditError {
    #[error("the take has no frames")]
    NoFrames,
    #[error("the row has no segment on this take to copy")]
    NothingToCopy,
    #[error("select one of my segments first")]
    NoSelection,
    #[error("frame {} is in none of my segments", .0 + 1)]
    NotInSegment(usize),
    #[error("frame {} is the first frame of its segment: move the playhead inside it to split", .0 + 1)]
    SplitAtStart(usize),
    #[error("the selected segment is the last one: there is no next segment to merge with")]
    NoNext,
    #[error("no segment starts or ends at this boundary (frame {})", .0 + 1)]
    NoBoundary(usize),
    #[error("frame {} is inside one of my segments, not in a gap", .0 + 1)]
    NotAGap(usize),
    #[error("my labels already have a boundary at frame {}", .0 + 1)]
    AlreadyBoundary(usize),
    #[error("frame {} is in a gap of my labels: fill the gap first to put a boundary in it", .0 + 1)]
    BoundaryInGap(usize),
    #[error("frame {} is the take's edge, not a boundary between two frames", .0 + 1)]
    AtTheEdge(usize),
    #[error("a label is at most {MAX_LABEL_CHARS} characters ({0} given)")]
    LabelTooLong(usize),
    #[error("a label cannot hold line breaks, tabs or other control characters")]
    LabelControl,
    #[error("nothing to undo")]
    NothingToUndo,
    #[error("nothing to redo")]
    NothingToRedo,
}

/// The segments and the selection as they were before an edit.
#[derive(Debug, Clone, PartialEq)]
struct Snapshot {
    spans: Vec<LabelSpan>,
    selected: Option<usize>,
}

/// My labels of one take: the segments, the selection and the history.
#[derive(Debug, Clone, PartialEq)]
pub struct MyLabels {
    frames: usize,
    spans: Vec<LabelSpan>,
    selected: Option<usize>,
    undo: VecDeque<Snapshot>,
    redo: Vec<Snapshot>,
}

/// A label as the user typed it, trimmed, or why it cannot be one.
pub fn clean_label(text: &str) -> Result<String, EditError> {
    let label = text.trim();
    if label.chars().any(char::is_control) {
        return Err(EditError::LabelControl);
    }
    let n = label.chars().count();
    if n > MAX_LABEL_CHARS {
        return Err(EditError::LabelTooLong(n));
    }
    Ok(label.to_string())
}

impl MyLabels {
    /// No segment yet, for a take of `frames` frames.
    pub fn new(frames: usize) -> MyLabels {
        MyLabels { frames, spans: Vec::new(), selected: None, undo: VecDeque::new(), redo: Vec::new() }
    }

    pub fn frames(&self) -> usize {
        self.frames
    }

    pub fn spans(&self) -> &[LabelSpan] {
        &self.spans
    }

    pub fn selected(&self) -> Option<usize> {
        self.selected
    }

    /// The selected segment.
    pub fn selected_span(&self) -> Option<&LabelSpan> {
        self.selected.and_then(|i| self.spans.get(i))
    }

    pub fn can_undo(&self) -> bool {
        !self.undo.is_empty()
    }

    pub fn can_redo(&self) -> bool {
        !self.redo.is_empty()
    }

    /// Edits that can be undone.
    pub fn undo_depth(&self) -> usize {
        self.undo.len()
    }

    /// Selects segment `index` (`None`, or an index past the end, drops the selection). Not an edit.
    pub fn select(&mut self, index: Option<usize>) {
        self.selected = index.filter(|i| *i < self.spans.len());
    }

    /// The segment covering `frame`.
    pub fn index_at(&self, frame: usize) -> Option<usize> {
        let i = self.spans.partition_point(|s| s.end < frame);
        (i < self.spans.len() && self.spans[i].contains(frame)).then_some(i)
    }

    /// The segment starting at `start` and ending at `end`.
    pub fn index_of(&self, start: usize, end: usize) -> Option<usize> {
        self.spans.iter().position(|s| s.start == start && s.end == end)
    }

    /// Every cut a segment starts or ends at, sorted (a shared boundary once).
    pub fn boundaries(&self) -> Vec<usize> {
        let mut cuts: Vec<usize> = self.spans.iter().flat_map(|s| [s.start, s.end + 1]).collect();
        cuts.dedup();
        cuts
    }

    /// Every label in use (not the empty one), sorted, once each.
    pub fn labels_used(&self) -> Vec<String> {
        suggestions(self.spans.iter().map(|s| s.label.as_str()))
    }

    /// The labelled segments as label CSV rows of `file` (unlabelled segments and
    /// [`RESERVED`](super::vocabulary::RESERVED) labels left out: their frames are unlabelled for a training, never a
    /// class).
    pub fn label_rows(&self, file: &str) -> Vec<LabelRow> {
        self.spans
            .iter()
            .filter(|s| is_labelled(&s.label))
            .map(|s| LabelRow {
                file: file.to_string(),
                start_frame: s.start,
                end_frame: s.end,
                label: s.label.clone(),
            })
            .collect()
    }

    /// The row as a segmentation of `file` at `fps` (method `my-labels`): labelled segments are actions, unlabelled
    /// ones (and [`RESERVED`](super::vocabulary::RESERVED) labels) transitions — what the metrics panel scores and the
    /// exports save.
    pub fn to_segmentation(&self, file: &str, fps: f64) -> Segmentation {
        Segmentation {
            file: file.to_string(),
            fps,
            frames: self.frames,
            method: "my-labels".into(),
            params: serde_json::json!({}),
            segments: self
                .spans
                .iter()
                .map(|s| Segment {
                    start: s.start,
                    end: s.end,
                    label: if s.label.is_empty() { "unlabelled".into() } else { s.label.clone() },
                    level: if is_labelled(&s.label) { Level::Action } else { Level::Transition },
                    cluster: None,
                    score: None,
                    mirror_of: None,
                    effort: None,
                })
                .collect(),
        }
    }

    /// Records the state before an edit (forgetting the oldest past [`HISTORY_LIMIT`]) and clears redo.
    fn record(&mut self) {
        self.undo.push_back(Snapshot { spans: self.spans.clone(), selected: self.selected });
        while self.undo.len() > HISTORY_LIMIT {
            self.undo.pop_front();
        }
        self.redo.clear();
    }

    /// Replaces every segment with a copy of `spans` (another row's `(start, end, label)`), normalised to the take. Its
    /// unlabelled and [`RESERVED`](super::vocabulary::RESERVED) spans (the SSSM's transitions, a labeller's unknowns, a
    /// truth's unlabelled parts) are left out: they become gaps, so that the copy scores as the row itself and none of
    /// them becomes a class. Nothing is selected.
    pub fn copy_from(&mut self, spans: &[(usize, usize, String)]) -> Result<(), EditError> {
        if self.frames == 0 {
            return Err(EditError::NoFrames);
        }
        let copied = normalised(
            spans
                .iter()
                .filter(|(_, _, l)| is_labelled(l))
                .map(|(s, e, l)| LabelSpan { start: *s, end: *e, label: l.trim().to_string() })
                .collect(),
            self.frames,
        );
        if copied.is_empty() {
            return Err(EditError::NothingToCopy);
        }
        self.record();
        self.spans = copied;
        self.selected = None;
        Ok(())
    }

    /// Replaces every segment with one unlabelled segment over the whole take, selected.
    pub fn start_empty(&mut self) -> Result<(), EditError> {
        if self.frames == 0 {
            return Err(EditError::NoFrames);
        }
        self.record();
        self.spans = vec![LabelSpan::new(0, self.frames - 1, "")];
        self.selected = Some(0);
        Ok(())
    }

    /// The cuts boundary `cut` may move to, `(lowest, highest)`, and the segments ending and
    /// starting at it.
    fn boundary_limits(&self, cut: usize) -> Result<(usize, usize, Option<usize>, Option<usize>), EditError> {
        let left = self.spans.iter().position(|s| s.end + 1 == cut);
        let right = self.spans.iter().position(|s| s.start == cut);
        let low = match (left, right) {
            (Some(l), _) => self.spans[l].start + 1,
            (None, Some(r)) => r.checked_sub(1).map_or(0, |p| self.spans[p].end + 1),
            (None, None) => return Err(EditError::NoBoundary(cut)),
        };
        let high = match (right, left) {
            (Some(r), _) => self.spans[r].end,
            (None, Some(l)) => self.spans.get(l + 1).map_or(self.frames, |n| n.start),
            (None, None) => return Err(EditError::NoBoundary(cut)),
        };
        Ok((low, high, left, right))
    }

    /// Moves boundary `cut` to `to`, clamped so that no segment becomes empty or overlaps another;
    /// returns where it went. Dropped where it was, nothing is recorded.
    pub fn move_boundary(&mut self, cut: usize, to: usize) -> Result<usize, EditError> {
        let (low, high, left, right) = self.boundary_limits(cut)?;
        let to = to.clamp(low, high);
        if to == cut {
            return Ok(cut);
        }
        self.record();
        if let Some(l) = left {
            self.spans[l].end = to - 1;
        }
        if let Some(r) = right {
            self.spans[r].start = to;
        }
        Ok(to)
    }

    /// Drags boundary `cut` to `to` (a pointer drag): the frames it passes over go to the segment it grows (or to the
    /// gap it grows), and the segments in its way are *rolled* — shrunk, and removed only once the boundary has crossed
    /// them entirely. It never leaves a sliver: a segment it shrinks keeps at least
    /// [`MIN_SPAN`](super::spans::MIN_SPAN) frames until it is crossed (the boundary stops short of it), and a gap it
    /// narrows to under [`MIN_SPAN`](super::spans::MIN_SPAN) frames closes (the boundary goes on to the next segment).
    /// Returns where the boundary landed; the selection follows its segment (none when that was removed). Dropped where
    /// it was, nothing is recorded.
    pub fn drag_boundary(&mut self, cut: usize, to: usize) -> Result<usize, EditError> {
        self.boundary_limits(cut)?;
        let to = to.min(self.frames);
        if to == cut {
            return Ok(cut);
        }
        // a drag to the left is a drag to the right on the take read backwards
        let (spans, landed) = if to > cut {
            roll_right(&self.spans, cut, to, self.frames)
        } else {
            let mirror = |s: &LabelSpan| LabelSpan {
                start: self.frames - 1 - s.end,
                end: self.frames - 1 - s.start,
                ..s.clone()
            };
            let flipped: Vec<LabelSpan> = self.spans.iter().rev().map(mirror).collect();
            let (rolled, landed) = roll_right(&flipped, self.frames - cut, self.frames - to, self.frames);
            let back: Vec<LabelSpan> = rolled
                .iter()
                .rev()
                .map(|s| LabelSpan { start: self.frames - 1 - s.end, end: self.frames - 1 - s.start, ..s.clone() })
                .collect();
            (back, self.frames - landed)
        };
        if spans == self.spans {
            return Ok(cut);
        }
        let selected = self.selected_span().map(|s| (s.start, s.end));
        self.record();
        // the selected segment, where it is now: the one overlapping most of its old frames
        self.selected = selected.and_then(|(a, b)| {
            spans
                .iter()
                .enumerate()
                .map(|(i, s)| (i, (s.end.min(b) + 1).saturating_sub(s.start.max(a))))
                .filter(|(_, overlap)| *overlap > 0)
                .max_by_key(|(_, overlap)| *overlap)
                .map(|(i, _)| i)
        });
        self.spans = spans;
        Ok(landed)
    }

    /// Moves boundary `cut` by `by` frames from the keyboard (← / →): a drag by that much ([`MyLabels::drag_boundary`],
    /// so it rolls and never leaves a sliver), and where a drag by `by` would stop short (a neighbour down to
    /// [`MIN_SPAN`](super::spans::MIN_SPAN) frames, a gap about to close), the shortest drag further in that direction
    /// that moves it — so that holding a key walks the boundary across its neighbour instead of sticking. Returns where
    /// it landed (`cut`: it cannot go that way).
    pub fn nudge_boundary(&mut self, cut: usize, by: isize) -> Result<usize, EditError> {
        self.boundary_limits(cut)?;
        if by == 0 {
            return Ok(cut);
        }
        let mut step = by.unsigned_abs();
        loop {
            let to = if by > 0 { cut.saturating_add(step).min(self.frames) } else { cut.saturating_sub(step) };
            let landed = self.drag_boundary(cut, to)?;
            if landed != cut || to == 0 || to == self.frames {
                return Ok(landed);
            }
            step += 1;
        }
    }

    /// Splits the segment covering `frame` into `start..frame` and `frame..=end`, both with its
    /// label; the right part is selected.
    pub fn split_at(&mut self, frame: usize) -> Result<(), EditError> {
        let i = self.index_at(frame).ok_or(EditError::NotInSegment(frame))?;
        if self.spans[i].start == frame {
            return Err(EditError::SplitAtStart(frame));
        }
        self.record();
        let right = LabelSpan { start: frame, ..self.spans[i].clone() };
        self.spans[i].end = frame - 1;
        self.spans.insert(i + 1, right);
        self.selected = Some(i + 1);
        Ok(())
    }

    /// Puts a boundary at cut `cut` (between frames `cut - 1` and `cut`: an accepted consensus boundary): splits the
    /// segment it falls in ([`MyLabels::split_at`], the label kept on both parts, the right one selected); with no
    /// segment yet, first starts the row as [`MyLabels::start_empty`] does — one undoable edit either way. A boundary
    /// already there, one in a gap or at the take's edge (cut 0 or past the last frame) is refused.
    pub fn add_boundary(&mut self, cut: usize) -> Result<(), EditError> {
        if self.frames == 0 {
            return Err(EditError::NoFrames);
        }
        if cut == 0 || cut >= self.frames {
            return Err(EditError::AtTheEdge(cut.min(self.frames)));
        }
        if self.spans.is_empty() {
            self.record();
            self.spans = vec![LabelSpan::new(0, cut - 1, ""), LabelSpan::new(cut, self.frames - 1, "")];
            self.selected = Some(1);
            return Ok(());
        }
        if self.boundaries().contains(&cut) {
            return Err(EditError::AlreadyBoundary(cut));
        }
        if self.index_at(cut).is_none() {
            return Err(EditError::BoundaryInGap(cut));
        }
        self.split_at(cut)
    }

    /// Joins the selected segment with the next one (and the gap between them, if any).
    pub fn merge_with_next(&mut self) -> Result<(), EditError> {
        let i = self.selected.filter(|i| *i < self.spans.len()).ok_or(EditError::NoSelection)?;
        if i + 1 >= self.spans.len() {
            return Err(EditError::NoNext);
        }
        self.record();
        let next = self.spans.remove(i + 1);
        let s = &mut self.spans[i];
        s.end = next.end;
        if s.label.is_empty() {
            s.label = next.label;
        }
        Ok(())
    }

    /// Gives the selected segment label `text` (trimmed; empty: unlabelled).
    pub fn relabel(&mut self, text: &str) -> Result<(), EditError> {
        let label = clean_label(text)?;
        let i = self.selected.filter(|i| *i < self.spans.len()).ok_or(EditError::NoSelection)?;
        if self.spans[i].label == label {
            return Ok(());
        }
        self.record();
        self.spans[i].label = label;
        Ok(())
    }

    /// Removes the selected segment, leaving a gap; the segment after it (else before it) is selected.
    pub fn delete(&mut self) -> Result<(), EditError> {
        let i = self.selected.filter(|i| *i < self.spans.len()).ok_or(EditError::NoSelection)?;
        self.record();
        self.spans.remove(i);
        self.selected = if i < self.spans.len() { Some(i) } else { i.checked_sub(1) };
        Ok(())
    }

    /// Puts an unlabelled segment over the gap around `frame` (up to the segments either side),
    /// selected.
    pub fn fill_gap(&mut self, frame: usize) -> Result<(), EditError> {
        if frame >= self.frames {
            return Err(EditError::NotInSegment(frame));
        }
        if self.index_at(frame).is_some() {
            return Err(EditError::NotAGap(frame));
        }
        let i = self.spans.partition_point(|s| s.end < frame);
        let start = i.checked_sub(1).map_or(0, |p| self.spans[p].end + 1);
        let end = self.spans.get(i).map_or(self.frames - 1, |n| n.start - 1);
        self.record();
        self.spans.insert(i, LabelSpan::new(start, end, ""));
        self.selected = Some(i);
        Ok(())
    }

    /// Puts segment `start..=end` with `label` in the row (a segment copied from another row, one
    /// at a time: the timeline's context menu): the parts of my segments it covers give way (those
    /// reaching past it keep their label outside it), gaps stay gaps elsewhere. It is selected.
    pub fn place(&mut self, start: usize, end: usize, label: &str) -> Result<(), EditError> {
        if self.frames == 0 {
            return Err(EditError::NoFrames);
        }
        let label = clean_label(label)?;
        if start > end || start >= self.frames {
            return Err(EditError::NothingToCopy);
        }
        let end = end.min(self.frames - 1);
        self.record();
        let mut spans = Vec::with_capacity(self.spans.len() + 2);
        for s in self.spans.drain(..) {
            if s.end < start || s.start > end {
                spans.push(s);
                continue;
            }
            if s.start < start {
                spans.push(LabelSpan { start: s.start, end: start - 1, label: s.label.clone() });
            }
            if s.end > end {
                spans.push(LabelSpan { start: end + 1, end: s.end, label: s.label });
            }
        }
        spans.push(LabelSpan { start, end, label });
        spans.sort_by_key(|s| s.start);
        self.spans = spans;
        self.selected = self.index_of(start, end);
        Ok(())
    }

    /// Removes every segment (undoable).
    pub fn clear(&mut self) {
        if self.spans.is_empty() {
            return;
        }
        self.record();
        self.spans.clear();
        self.selected = None;
    }

    /// Goes back to the state before the last edit.
    pub fn undo(&mut self) -> Result<(), EditError> {
        let before = self.undo.pop_back().ok_or(EditError::NothingToUndo)?;
        self.redo.push(Snapshot { spans: std::mem::replace(&mut self.spans, before.spans), selected: self.selected });
        self.selected = before.selected;
        Ok(())
    }

    /// Does again the last edit undone.
    pub fn redo(&mut self) -> Result<(), EditError> {
        let after = self.redo.pop().ok_or(EditError::NothingToRedo)?;
        self.undo
            .push_back(Snapshot { spans: std::mem::replace(&mut self.spans, after.spans), selected: self.selected });
        self.selected = after.selected;
        Ok(())
    }

    /// A take of `frames` frames with `spans` and nothing else (no history, nothing selected): labels read back
    /// from storage ([`MyLabels::from_json`]).
    pub(super) fn restored(frames: usize, spans: Vec<LabelSpan>) -> MyLabels {
        MyLabels { spans, ..MyLabels::new(frames) }
    }
}

#[cfg(test)]
pub(crate) mod tests;
