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
//!   becomes empty and none overlaps another. While dragging, [`snap`] pulls the cut to the
//!   nearest cut of the other rows within [`SNAP_PX`] pixels ([`snap_tolerance`] converts them to
//!   frames at the zoom); of two equally near, the earlier.
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
//! * **Storage**: [`MyLabels::to_json`] / [`MyLabels::from_json`] (format [`FORMAT`], version
//!   [`VERSION`]; the segments only, not the history), with a clear error when stored data is
//!   corrupt or for another take; the key is [`storage_key`] (file name, frames, frame rate,
//!   joints, a [`fingerprint`] of the motion).

use crate::labels::LabelRow;
use crate::segment::{Level, Segment, Segmentation};
use std::collections::VecDeque;

/// Edits the history keeps (older ones are forgotten).
pub const HISTORY_LIMIT: usize = 200;
/// A dragged boundary snaps to another row's boundary this near, in CSS pixels.
pub const SNAP_PX: f64 = 8.0;
/// The longest label, in characters.
pub const MAX_LABEL_CHARS: usize = 120;
/// The `format` field of the stored JSON.
pub const FORMAT: &str = "mocapseg-my-labels";
/// The `version` field of the stored JSON this code writes and reads.
pub const VERSION: u64 = 1;
/// Labels that say a span has *no* action label — the SSSM's transitions, a labeller's
/// unknowns, the page's own word for an unlabelled segment — compared ignoring case and spaces.
/// They are never my labels' classes: a copy leaves them as gaps, training and the scores read
/// them as unlabelled frames, the label vocabulary never offers them.
pub const RESERVED: [&str; 3] = ["transition", "unknown", "unlabelled"];

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

/// Why stored labels could not be read back.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StoreError {
    #[error("the stored labels are not JSON: {0}")]
    Json(String),
    #[error("the stored labels are not my labels (format `{0}`, expected `{FORMAT}`)")]
    Format(String),
    #[error("the stored labels are version {0}; this page reads version {VERSION}")]
    Version(String),
    #[error("the stored labels do not have the expected fields: {0}")]
    Shape(String),
    #[error("the stored labels are for a take of {stored} frames; this one has {frames}")]
    Frames { stored: usize, frames: usize },
    #[error("stored segment {index}: {why}")]
    Segment { index: usize, why: String },
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

/// Segments made fit for the row: sorted by start, clipped to `frames`, overlaps cut (a segment
/// starting inside the previous one starts after it; one left empty is dropped).
fn normalised(mut spans: Vec<LabelSpan>, frames: usize) -> Vec<LabelSpan> {
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

    /// The labelled segments as label CSV rows of `file` (unlabelled segments and [`RESERVED`]
    /// labels left out: their frames are unlabelled for a training, never a class).
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

    /// The row as a segmentation of `file` at `fps` (method `my-labels`): labelled segments are
    /// actions, unlabelled ones (and [`RESERVED`] labels) transitions — what the metrics panel
    /// scores and the exports save.
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

    /// Replaces every segment with a copy of `spans` (another row's `(start, end, label)`),
    /// normalised to the take. Its unlabelled and [`RESERVED`] spans (the SSSM's transitions, a
    /// labeller's unknowns, a truth's unlabelled parts) are left out: they become gaps, so that
    /// the copy scores as the row itself and none of them becomes a class. Nothing is selected.
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

    /// Drags boundary `cut` to `to` (a pointer drag): the frames it passes over go to the segment
    /// it grows (or to the gap it grows), and the segments in its way are *rolled* — shrunk, and
    /// removed only once the boundary has crossed them entirely. It never leaves a sliver: a
    /// segment it shrinks keeps at least [`MIN_SPAN`] frames until it is crossed (the boundary
    /// stops short of it), and a gap it narrows to under [`MIN_SPAN`] frames closes (the boundary
    /// goes on to the next segment). Returns where the boundary landed; the selection follows its
    /// segment (none when that was removed). Dropped where it was, nothing is recorded.
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

    /// Moves boundary `cut` by `by` frames from the keyboard (← / →): a drag by that much
    /// ([`MyLabels::drag_boundary`], so it rolls and never leaves a sliver), and where a drag by
    /// `by` would stop short (a neighbour down to [`MIN_SPAN`] frames, a gap about to close), the
    /// shortest drag further in that direction that moves it — so that holding a key walks the
    /// boundary across its neighbour instead of sticking. Returns where it landed (`cut`: it
    /// cannot go that way).
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

    /// The stored form: `{"format", "version", "file", "frames", "segments": [{start, end, label}]}`.
    pub fn to_json(&self, file: &str) -> String {
        serde_json::json!({
            "format": FORMAT,
            "version": VERSION,
            "file": file,
            "frames": self.frames,
            "segments": self.spans,
        })
        .to_string()
    }

    /// Reads back what [`to_json`](Self::to_json) wrote for a take of `frames` frames (no
    /// history, nothing selected), or says what is wrong with it.
    pub fn from_json(text: &str, frames: usize) -> Result<MyLabels, StoreError> {
        #[derive(serde::Deserialize)]
        struct Stored {
            frames: usize,
            segments: Vec<LabelSpan>,
        }
        let value: serde_json::Value = serde_json::from_str(text).map_err(|e| StoreError::Json(e.to_string()))?;
        let field = |name: &str| value.get(name).map_or_else(|| "missing".to_string(), |v| v.to_string());
        if value.get("format").and_then(|f| f.as_str()) != Some(FORMAT) {
            return Err(StoreError::Format(field("format")));
        }
        if value.get("version").and_then(|v| v.as_u64()) != Some(VERSION) {
            return Err(StoreError::Version(field("version")));
        }
        let stored: Stored = serde_json::from_value(value).map_err(|e| StoreError::Shape(e.to_string()))?;
        if stored.frames != frames {
            return Err(StoreError::Frames { stored: stored.frames, frames });
        }
        for (index, s) in stored.segments.iter().enumerate() {
            let bad = |why: String| Err(StoreError::Segment { index, why });
            if s.start > s.end {
                return bad(format!("start {} is after end {}", s.start, s.end));
            }
            if s.end >= frames {
                return bad(format!("end {} is past the last frame {}", s.end, frames.saturating_sub(1)));
            }
            if index > 0 && s.start <= stored.segments[index - 1].end {
                return bad(format!("starts at {}, inside the segment before it", s.start));
            }
            match clean_label(&s.label) {
                Ok(l) if l == s.label => {}
                Ok(_) => return bad("its label has spaces around it".into()),
                Err(e) => return bad(e.to_string()),
            }
        }
        Ok(MyLabels { spans: stored.segments, ..MyLabels::new(frames) })
    }
}

/// The fewest frames a drag leaves of a segment it shrinks or of a gap it narrows: one frame
/// is too thin to see or to grab, and reads as a boundary of its own.
pub const MIN_SPAN: usize = 2;

/// [`MyLabels::drag_boundary`] to the right (`to > cut`) on sorted, non-overlapping `spans` of a
/// take of `frames`: the new segments and where the boundary landed.
fn roll_right(spans: &[LabelSpan], cut: usize, to: usize, frames: usize) -> (Vec<LabelSpan>, usize) {
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

/// Whether `label` says "no label" ([`RESERVED`]).
pub fn is_reserved(label: &str) -> bool {
    let label = label.trim();
    RESERVED.iter().any(|r| r.eq_ignore_ascii_case(label))
}

/// Whether a segment labelled `label` is one of my labelled segments (not empty, not
/// [`RESERVED`]).
pub fn is_labelled(label: &str) -> bool {
    !label.trim().is_empty() && !is_reserved(label)
}

/// The labels of `labels` worth offering while typing: not empty, sorted, once each.
pub fn suggestions<'a>(labels: impl IntoIterator<Item = &'a str>) -> Vec<String> {
    let mut out: Vec<String> = labels.into_iter().filter(|l| !l.trim().is_empty()).map(str::to_string).collect();
    out.sort();
    out.dedup();
    out
}

/// The most entries of the vocabulary with a number key (1–9).
pub const HOTKEYS: usize = 9;

/// My labels' fixed vocabulary, in the order its number keys follow: the ground truth's classes
/// (`truth`, when one is imported), then the classes of the labelling methods' models
/// (`models`), then the labels the user gave my segments (`mine`) — each once, in the order
/// first met, and never a [`RESERVED`] label or one of `excluded` (the names unsupervised
/// methods give their clusters: "A0", "P1 mirrors P2" are no one's vocabulary) unless the truth
/// or a model has it too. Entry `n` (0-based, below [`HOTKEYS`]) has the key `n + 1`.
pub fn vocabulary<'a>(
    truth: impl IntoIterator<Item = &'a str>,
    models: impl IntoIterator<Item = &'a str>,
    mine: impl IntoIterator<Item = &'a str>,
    excluded: &[&str],
) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    let mut add = |label: &str, check: bool| {
        let label = label.trim();
        if is_labelled(label) && !(check && excluded.contains(&label)) && !out.iter().any(|l| l == label) {
            out.push(label.to_string());
        }
    };
    truth.into_iter().for_each(|l| add(l, false));
    models.into_iter().for_each(|l| add(l, false));
    mine.into_iter().for_each(|l| add(l, true));
    out
}

/// The vocabulary entry a number key `key` ("1"…"9") gives, if any.
pub fn hotkey_label<'a>(vocabulary: &'a [String], key: &str) -> Option<&'a str> {
    let n: usize = key.parse().ok().filter(|n| (1..=HOTKEYS).contains(n))?;
    vocabulary.get(n - 1).map(String::as_str)
}

/// The cuts of other rows' segments (`(start, end)` inclusive): each start and each end + 1,
/// sorted, once each — what a dragged boundary snaps to.
pub fn cuts_of<'a>(rows: impl IntoIterator<Item = &'a [(usize, usize)]>) -> Vec<usize> {
    let mut cuts: Vec<usize> = rows.into_iter().flatten().flat_map(|&(s, e)| [s, e + 1]).collect();
    cuts.sort_unstable();
    cuts.dedup();
    cuts
}

/// [`SNAP_PX`]-like `pixels` in frames, for a window `span` frames wide drawn over `width_px` pixels.
pub fn snap_tolerance(pixels: f64, span: f64, width_px: f64) -> f64 {
    if !(pixels > 0.0 && span > 0.0 && width_px > 0.0) || !span.is_finite() || !width_px.is_finite() {
        return 0.0;
    }
    pixels * span / width_px
}

/// The cut a boundary dragged to frame position `at` (fractional) lands on: the nearest of
/// `targets` (sorted) within `tolerance` frames — of two equally near, the earlier — else `at`
/// rounded to the nearest cut. Never negative.
pub fn snap(at: f64, targets: &[usize], tolerance: f64) -> usize {
    let at = if at.is_finite() { at.max(0.0) } else { 0.0 };
    let mut best: Option<(f64, usize)> = None;
    // the targets either side of `at` are the only candidates
    let i = targets.partition_point(|&t| (t as f64) < at);
    for &t in targets[i.saturating_sub(1)..(i + 1).min(targets.len())].iter() {
        let d = (t as f64 - at).abs();
        if d <= tolerance && best.is_none_or(|(bd, _)| d < bd) {
            best = Some((d, t));
        }
    }
    best.map_or(at.round() as usize, |(_, t)| t)
}

/// The browser-storage key of my labels for a take: its file name, frames, frame rate (to the
/// thousandth), joints and a [`fingerprint`] of its motion, so that the same file opened again
/// finds them and another one — even of the same name and length — does not.
pub fn storage_key(name: &str, frames: usize, fps: f64, joints: usize, print: u32) -> String {
    format!("mocapseg.my-labels.v{VERSION}:{name}:{frames}f:{fps:.3}fps:{joints}j:{print:08x}")
}

/// Where a stored record of my labels that cannot be read is kept before the next edit replaces
/// it: the take's key (from [`storage_key`]) under another prefix, so that the record is never
/// lost and is never read as labels.
pub fn backup_key(key: &str) -> String {
    let take = key.strip_prefix("mocapseg.my-labels.").unwrap_or(key);
    format!("mocapseg.my-labels-backup.{take}")
}

/// A cheap fingerprint of a take (FNV-1a over the bits of `values`: the page passes the positions
/// of its first and last frames).
pub fn fingerprint(values: impl IntoIterator<Item = f32>) -> u32 {
    let mut h: u32 = 0x811c_9dc5;
    for v in values {
        for b in v.to_bits().to_le_bytes() {
            h ^= b as u32;
            h = h.wrapping_mul(0x0100_0193);
        }
    }
    h
}

/// A stable class index for a label no other row shows (FNV-1a of its text): the same label has
/// the same colour on every take.
pub fn label_class(label: &str) -> usize {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in label.as_bytes() {
        h ^= *b as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    (h % 64) as usize
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_row_as_a_segmentation_has_labelled_actions_and_unlabelled_transitions() {
        let mut m = MyLabels::new(100);
        m.copy_from(&[(0, 39, "walk".into()), (40, 59, "x".into()), (70, 99, "run".into())]).unwrap();
        m.select(Some(1));
        m.relabel("").unwrap();
        let seg = m.to_segmentation("a.bvh", 120.0);
        seg.validate().unwrap();
        assert_eq!((seg.file.as_str(), seg.frames, seg.method.as_str()), ("a.bvh", 100, "my-labels"));
        let levels: Vec<_> = seg.segments.iter().map(|s| (s.start, s.end, s.level)).collect();
        assert_eq!(levels, [(0, 39, Level::Action), (40, 59, Level::Transition), (70, 99, Level::Action)]);
        assert_eq!(Segmentation::from_json(&seg.to_json()).unwrap(), seg);
    }

    /// An SSSM-like row of `frames` at 30 Hz: actions `A0`/`B1` with a transition between each
    /// pair (as `sssm` labels them) and DT-FCN-like `unknown` actions.
    fn sssm_like(parts: &[(usize, usize, &str, Level)], frames: usize) -> Segmentation {
        Segmentation {
            file: "t.bvh".into(),
            fps: 30.0,
            frames,
            method: "sssm".into(),
            params: serde_json::json!({}),
            segments: parts
                .iter()
                .map(|&(start, end, label, level)| Segment {
                    start,
                    end,
                    label: label.into(),
                    level,
                    cluster: (level == Level::Action).then(|| usize::from(label == "B1")),
                    score: None,
                    mirror_of: None,
                    effort: None,
                })
                .collect(),
        }
    }

    #[test]
    fn a_copied_row_scores_as_the_row_itself_transitions_and_unknowns_are_gaps() {
        use crate::segment::metrics::{evaluate, Tolerances};
        use crate::segment::truth::{Truth, TruthSegment};
        use Level::{Action, Transition};
        let frames = 600;
        // the issue's case: SSSM's row, copied, scored 0.833 → 0.444 at F1@1s — its transitions
        // had become segments labelled "transition"
        let row = sssm_like(
            &[
                (0, 89, "A0", Action),
                (90, 129, "transition", Transition),
                (130, 259, "B1", Action),
                (260, 289, "transition", Transition),
                (290, 419, "A0", Action),
                (420, 459, "transition", Transition),
                (460, 599, "B1", Action),
            ],
            frames,
        );
        let cut =
            |start: usize, end: usize, label: &str| TruthSegment { start, end, label: label.into(), end_window: None };
        let truth = Truth {
            trial: "t".into(),
            frames,
            segments: vec![cut(0, 109, "walk"), cut(110, 274, "jump"), cut(275, 439, "walk"), cut(440, 599, "punch")],
        };
        let tol = Tolerances::default();
        let own = evaluate(&row, &truth, &tol).unwrap();
        let mut m = MyLabels::new(frames);
        let copied: Vec<(usize, usize, String)> =
            row.segments.iter().map(|s| (s.start, s.end, s.label.clone())).collect();
        m.copy_from(&copied).unwrap();
        assert_eq!(spans(&m), vec![(0, 89, "A0"), (130, 259, "B1"), (290, 419, "A0"), (460, 599, "B1")]);
        let mine = evaluate(&m.to_segmentation("t.bvh", 30.0), &truth, &tol).unwrap();
        assert_eq!(mine.boundaries[1].f1, own.boundaries[1].f1, "F1@1s");
        assert_eq!(mine.boundaries[0].f1, own.boundaries[0].f1, "F1@0.5s");
        assert_eq!(mine.covering, own.covering);
        assert_eq!(mine.labelling, own.labelling);
        assert_eq!(mine.hungarian_accuracy, own.hungarian_accuracy);
        assert!(own.boundaries[1].f1 > 0.99, "the fixture's row finds every cut: {:?}", own.boundaries[1]);

        // a labeller's unknowns and a truth's unlabelled parts are gaps as well; none is a class
        m.copy_from(&row_of(&[(0, 49, "walk"), (50, 99, "unknown"), (100, 199, ""), (200, 599, "Unknown ")])).unwrap();
        assert_eq!(spans(&m), vec![(0, 49, "walk")]);
        assert_eq!(MyLabels::new(10).copy_from(&row_of(&[(0, 9, "transition")])), Err(EditError::NothingToCopy));
    }

    #[test]
    fn transition_and_unknown_never_become_training_classes() {
        // labels stored before copies left gaps, or typed: unlabelled frames for training and scores
        let stored = r#"{"format":"mocapseg-my-labels","version":1,"frames":100,"segments":[
            {"start":0,"end":29,"label":"walk"},{"start":30,"end":39,"label":"transition"},
            {"start":40,"end":59,"label":"unknown"},{"start":60,"end":99,"label":"run"}]}"#;
        let m = MyLabels::from_json(stored, 100).unwrap();
        let rows = m.label_rows("t.bvh");
        let classes: Vec<&str> = rows.iter().map(|r| r.label.as_str()).collect();
        assert_eq!(classes, ["walk", "run"]);
        let seg = m.to_segmentation("t.bvh", 30.0);
        let levels: Vec<Level> = seg.segments.iter().map(|s| s.level).collect();
        assert_eq!(levels, [Level::Action, Level::Transition, Level::Transition, Level::Action]);
        assert!(
            is_reserved(" Transition") && is_reserved("UNKNOWN") && is_reserved("unlabelled") && !is_reserved("walk")
        );
    }

    fn row_of(list: &[(usize, usize, &str)]) -> Vec<(usize, usize, String)> {
        row(list)
    }

    fn spans(m: &MyLabels) -> Vec<(usize, usize, &str)> {
        m.spans().iter().map(|s| (s.start, s.end, s.label.as_str())).collect()
    }

    fn row(list: &[(usize, usize, &str)]) -> Vec<(usize, usize, String)> {
        list.iter().map(|(s, e, l)| (*s, *e, l.to_string())).collect()
    }

    /// `a 0..=9 | b 10..=29 | gap 30..=39 | c 40..=99` on a 100-frame take.
    fn sample() -> MyLabels {
        let mut m = MyLabels::new(100);
        m.copy_from(&row(&[(0, 9, "a"), (10, 29, "b"), (40, 99, "c")])).unwrap();
        m
    }

    #[test]
    fn copy_normalises_the_row_and_is_undoable() {
        let mut m = MyLabels::new(50);
        assert!(!m.can_undo() && m.spans().is_empty());
        // unsorted, overlapping, past the end, reversed: sorted, cut, clipped, dropped
        m.copy_from(&row(&[(20, 60, "c"), (0, 9, "a"), (5, 14, "b"), (70, 80, "x"), (9, 3, "bad"), (8, 8, "in")]))
            .unwrap();
        assert_eq!(spans(&m), vec![(0, 9, "a"), (10, 14, "b"), (20, 49, "c")]);
        assert_eq!(m.selected(), None);
        assert!(m.can_undo());
        assert_eq!(MyLabels::new(50).copy_from(&row(&[(60, 70, "x")])), Err(EditError::NothingToCopy));
        assert_eq!(MyLabels::new(0).copy_from(&row(&[(0, 0, "x")])), Err(EditError::NoFrames));
        m.undo().unwrap();
        assert!(m.spans().is_empty());
    }

    #[test]
    fn place_puts_one_segment_in_and_trims_what_it_covers() {
        let mut m = MyLabels::new(100);
        // on an empty row: the segment alone, gaps around it
        m.place(10, 19, "punch").unwrap();
        assert_eq!(spans(&m), vec![(10, 19, "punch")]);
        assert_eq!(m.selected(), Some(0));
        m.copy_from(&row(&[(0, 29, "walk"), (30, 59, "jump"), (60, 99, "walk")])).unwrap();
        // across a boundary: both neighbours trimmed, their labels kept outside it
        m.place(20, 39, "punch").unwrap();
        assert_eq!(spans(&m), vec![(0, 19, "walk"), (20, 39, "punch"), (40, 59, "jump"), (60, 99, "walk")]);
        assert_eq!(m.selected_span().map(|s| s.label.as_str()), Some("punch"));
        // inside one segment: it splits around it
        m.place(70, 79, "kick").unwrap();
        assert_eq!(
            spans(&m),
            vec![
                (0, 19, "walk"),
                (20, 39, "punch"),
                (40, 59, "jump"),
                (60, 69, "walk"),
                (70, 79, "kick"),
                (80, 99, "walk")
            ]
        );
        // one undoable edit each
        m.undo().unwrap();
        assert_eq!(spans(&m), vec![(0, 19, "walk"), (20, 39, "punch"), (40, 59, "jump"), (60, 99, "walk")]);
        // past the take's end: clipped; refused outside it or with a bad label
        m.place(90, 500, "rest").unwrap();
        assert_eq!(spans(&m).last(), Some(&(90, 99, "rest")));
        assert_eq!(m.place(100, 120, "x"), Err(EditError::NothingToCopy));
        assert_eq!(m.place(1, 2, "a\nb"), Err(EditError::LabelControl));
    }

    #[test]
    fn start_empty_is_one_unlabelled_segment_over_the_take() {
        let mut m = sample();
        m.start_empty().unwrap();
        assert_eq!(spans(&m), vec![(0, 99, "")]);
        assert_eq!(m.selected(), Some(0));
        assert!(m.label_rows("t.bvh").is_empty(), "unlabelled segments are not training rows");
        assert_eq!(MyLabels::new(0).start_empty(), Err(EditError::NoFrames));
        m.undo().unwrap();
        assert_eq!(spans(&m), spans(&sample()));
    }

    #[test]
    fn a_shared_boundary_moves_both_segments_and_is_clamped() {
        let mut m = sample();
        assert_eq!(m.boundaries(), vec![0, 10, 30, 40, 100]);
        assert_eq!(m.move_boundary(10, 14), Ok(14));
        assert_eq!(spans(&m)[..2], [(0, 13, "a"), (14, 29, "b")]);
        // never empties a segment: at most to the right one's last frame, at least past the left one's first
        assert_eq!(m.move_boundary(14, 95), Ok(29));
        assert_eq!(spans(&m)[..2], [(0, 28, "a"), (29, 29, "b")], "b keeps one frame");
        assert_eq!(m.move_boundary(29, 0), Ok(1));
        assert_eq!(spans(&m)[..2], [(0, 0, "a"), (1, 29, "b")], "a keeps one frame");
        assert_eq!(m.undo_depth(), 4);
        // dropped where it was: nothing recorded
        assert_eq!(m.move_boundary(1, 1), Ok(1));
        assert_eq!(m.undo_depth(), 4);
        assert_eq!(m.move_boundary(7, 8), Err(EditError::NoBoundary(7)));
    }

    #[test]
    fn an_edge_next_to_a_gap_moves_into_the_gap_up_to_the_next_segment() {
        let mut m = sample();
        // b's end (cut 30) into the gap, stopped at c's start
        assert_eq!(m.move_boundary(30, 80), Ok(40));
        assert_eq!(spans(&m)[1..], [(10, 39, "b"), (40, 99, "c")]);
        m.undo().unwrap();
        // c's start (cut 40) back into the gap, stopped at b's end
        assert_eq!(m.move_boundary(40, 3), Ok(30));
        assert_eq!(spans(&m)[1..], [(10, 29, "b"), (30, 99, "c")]);
        m.undo().unwrap();
        // the first and last frames: cut 0 and cut 100 (the take's edges) stay put when nothing is outside
        assert_eq!(m.move_boundary(0, 5), Ok(5));
        assert_eq!(spans(&m)[0], (5, 9, "a"));
        assert_eq!(m.move_boundary(5, 0), Ok(0), "back to the first frame, not before");
        assert_eq!(m.move_boundary(100, 500), Ok(100), "the last frame is the end");
        assert_eq!(m.move_boundary(100, 60), Ok(60));
        assert_eq!(spans(&m)[2], (40, 59, "c"));
    }

    #[test]
    fn a_nudged_boundary_rolls_like_a_drag_and_never_sticks_or_leaves_a_sliver() {
        // a 0..=9 | b 10..=29 | gap 30..=39 | c 40..=99
        let mut m = sample();
        // one frame at a time to the right: b shrinks to two frames, then the next press crosses it
        let mut cut = 10;
        for _ in 0..18 {
            cut = m.nudge_boundary(cut, 1).unwrap();
        }
        assert_eq!(cut, 28);
        assert_eq!(spans(&m)[..2], [(0, 27, "a"), (28, 29, "b")]);
        cut = m.nudge_boundary(cut, 1).unwrap();
        assert_eq!(cut, 30, "b crossed: removed, never a one-frame b");
        assert_eq!(spans(&m)[..2], [(0, 29, "a"), (40, 99, "c")]);
        // on through the gap: it never leaves a one-frame gap (39 → the segments touch at 40)
        for _ in 0..8 {
            cut = m.nudge_boundary(cut, 1).unwrap();
        }
        assert_eq!(cut, 38);
        assert_eq!(m.nudge_boundary(cut, 1).unwrap(), 40);
        // at the take's end it stops
        let mut end = sample();
        assert_eq!(end.nudge_boundary(100, 1).unwrap(), 100);
        // every walk, either way, by one frame or a second, leaves no one-frame segment or gap
        for start in [0, 10, 30, 40, 100] {
            for by in [-30, -1, 1, 30] {
                let mut m = sample();
                let mut cut = start;
                for _ in 0..120 {
                    let next = m.nudge_boundary(cut, by).unwrap_or_else(|e| {
                        panic!(
                            "{start} by {by} at {cut}: {e:?} in {:?}",
                            m.spans().iter().map(|s| (s.start, s.end)).collect::<Vec<_>>()
                        )
                    });
                    let covered: Vec<(usize, usize)> = m.spans().iter().map(|s| (s.start, s.end)).collect();
                    assert!(covered.iter().all(|(a, b)| b + 1 - a >= MIN_SPAN), "{start} by {by}: {covered:?}");
                    for w in covered.windows(2) {
                        let gap = w[1].0 - (w[0].1 + 1);
                        assert!(gap == 0 || gap >= MIN_SPAN, "{start} by {by}: a {gap}-frame gap in {covered:?}");
                    }
                    // stuck at the take's edge, or the segment it edged was crossed and the boundary is gone
                    if next == cut || m.boundary_limits(next).is_err() {
                        break;
                    }
                    cut = next;
                }
            }
        }
    }

    #[test]
    fn a_dragged_boundary_rolls_its_neighbour_and_never_leaves_a_sliver() {
        // a 0..=9 | b 10..=29 | gap 30..=39 | c 40..=99
        let dragged = |cut: usize, to: usize| {
            let mut m = sample();
            let landed = m.drag_boundary(cut, to).unwrap();
            (landed, spans(&m).into_iter().map(|(s, e, l)| (s, e, l.to_string())).collect::<Vec<_>>())
        };
        let own =
            |list: &[(usize, usize, &str)]| list.iter().map(|(s, e, l)| (*s, *e, l.to_string())).collect::<Vec<_>>();
        // within the neighbour: it shrinks, like a move
        assert_eq!(dragged(10, 20), (20, own(&[(0, 19, "a"), (20, 29, "b"), (40, 99, "c")])));
        // onto its last frame: it keeps MIN_SPAN frames until the boundary passes its end
        assert_eq!(dragged(10, 29), (28, own(&[(0, 27, "a"), (28, 29, "b"), (40, 99, "c")])));
        // fully across it: removed, the gap after it is taken up to where the pointer is
        assert_eq!(dragged(10, 30), (30, own(&[(0, 29, "a"), (40, 99, "c")])));
        assert_eq!(dragged(10, 35), (35, own(&[(0, 34, "a"), (40, 99, "c")])));
        // a gap narrowed to one frame closes: the segments touch
        assert_eq!(dragged(10, 39), (40, own(&[(0, 39, "a"), (40, 99, "c")])));
        assert_eq!(dragged(30, 39), (40, own(&[(0, 9, "a"), (10, 39, "b"), (40, 99, "c")])));
        // on over the next segment: rolled in turn
        assert_eq!(dragged(10, 60), (60, own(&[(0, 59, "a"), (60, 99, "c")])));
        assert_eq!(dragged(10, 99), (98, own(&[(0, 97, "a"), (98, 99, "c")])));
        assert_eq!(dragged(10, 100), (100, own(&[(0, 99, "a")])));
        // to the left: the segment on the right grows, the ones on the left roll
        assert_eq!(dragged(10, 1), (2, own(&[(0, 1, "a"), (2, 29, "b"), (40, 99, "c")])));
        assert_eq!(dragged(10, 0), (0, own(&[(0, 29, "b"), (40, 99, "c")])));
        assert_eq!(dragged(40, 31), (30, own(&[(0, 9, "a"), (10, 29, "b"), (30, 99, "c")])), "the gap closes");
        assert_eq!(dragged(40, 5), (5, own(&[(0, 4, "a"), (5, 99, "c")])));
        // an edge next to a gap moved away from it: the gap grows, never by a single frame at the take's edges
        assert_eq!(
            dragged(0, 1),
            (
                0,
                own(&[(0, 9, "a"), (10, 29, "b"), (30, 39, ""), (40, 99, "c")])
                    .into_iter()
                    .filter(|s| s.2 != "")
                    .collect()
            )
        );
        assert_eq!(dragged(0, 2).0, 2);
        assert_eq!(dragged(100, 99).0, 100, "no one-frame gap at the end");
        assert_eq!(dragged(100, 98), (98, own(&[(0, 9, "a"), (10, 29, "b"), (40, 97, "c")])));
        assert_eq!(dragged(30, 12), (12, own(&[(0, 9, "a"), (10, 11, "b"), (40, 99, "c")])));
        assert_eq!(dragged(30, 11), (12, own(&[(0, 9, "a"), (10, 11, "b"), (40, 99, "c")])), "b keeps two frames");
        assert_eq!(dragged(30, 10), (10, own(&[(0, 9, "a"), (40, 99, "c")])), "crossed: b removed");
        assert_eq!(
            dragged(0, 60),
            (10, own(&[(10, 29, "b"), (40, 99, "c")])),
            "a gap's edge crosses its own segment only"
        );
        assert_eq!(dragged(40, 35).1, own(&[(0, 9, "a"), (10, 29, "b"), (35, 99, "c")]));
        // no drag leaves a segment or a gap of one frame
        for cut in [0, 10, 30, 40, 100] {
            for to in 0..=100 {
                let (_, after) = dragged(cut, to);
                assert!(after.iter().all(|s| s.1 + 1 - s.0 >= MIN_SPAN), "{cut} → {to}: {after:?}");
                let edges = after.first().zip(after.last()).map(|(f, l)| [f.0, 99 - l.1]).unwrap_or_default();
                let gaps = after.windows(2).map(|w| w[1].0 - w[0].1 - 1).chain(edges);
                assert!(gaps.into_iter().all(|g| g == 0 || g >= MIN_SPAN), "{cut} → {to}: {after:?}");
            }
        }
        // one undoable edit, the selection follows its segment
        let mut m = sample();
        m.select(Some(2));
        assert_eq!(m.drag_boundary(10, 35), Ok(35));
        assert_eq!(m.selected_span().map(|s| s.label.as_str()), Some("c"));
        m.select(Some(0));
        assert_eq!(m.drag_boundary(35, 3), Ok(3), "a's end into its own frames: the gap grows");
        assert_eq!(m.selected_span().map(|s| s.label.as_str()), Some("a"));
        m.drag_boundary(3, 0).unwrap();
        assert_eq!(m.selected(), None, "a removed");
        assert_eq!(spans(&m), vec![(40, 99, "c")]);
        assert_eq!(m.undo_depth(), 4);
        m.undo().unwrap();
        assert_eq!(spans(&m), vec![(0, 2, "a"), (40, 99, "c")]);
        assert_eq!(m.drag_boundary(3, 3), Ok(3));
        assert_eq!(m.undo_depth(), 3, "dropped where it was: no edit");
        assert_eq!(m.drag_boundary(7, 8), Err(EditError::NoBoundary(7)));
    }

    #[test]
    fn split_at_a_frame_keeps_the_label_and_selects_the_right_part() {
        let mut m = sample();
        m.split_at(50).unwrap();
        assert_eq!(spans(&m)[2..], [(40, 49, "c"), (50, 99, "c")]);
        assert_eq!(m.selected(), Some(3));
        assert_eq!(m.split_at(50), Err(EditError::SplitAtStart(50)));
        assert_eq!(m.split_at(35), Err(EditError::NotInSegment(35)), "a gap");
        // the last frame of a segment: a one-frame right part; a one-frame segment cannot be split
        m.split_at(99).unwrap();
        assert_eq!(spans(&m).last(), Some(&(99, 99, "c")));
        assert_eq!(m.split_at(99), Err(EditError::SplitAtStart(99)));
        assert_eq!(m.split_at(0), Err(EditError::SplitAtStart(0)));
        assert_eq!(m.split_at(100), Err(EditError::NotInSegment(100)));
    }

    #[test]
    fn an_accepted_boundary_splits_my_segment_or_starts_the_row() {
        // no labels yet: the row starts, unlabelled, cut there — one edit, undone at once
        let mut m = MyLabels::new(100);
        m.add_boundary(30).unwrap();
        assert_eq!(spans(&m), [(0, 29, ""), (30, 99, "")]);
        assert_eq!(m.selected(), Some(1));
        assert_eq!(m.undo_depth(), 1);
        m.undo().unwrap();
        assert!(m.spans().is_empty());
        // in a segment: split, the label on both parts
        let mut m = sample();
        m.add_boundary(60).unwrap();
        assert_eq!(spans(&m)[2..], [(40, 59, "c"), (60, 99, "c")]);
        assert_eq!(m.selected(), Some(3));
        // already a boundary (between two segments, at a gap's edge, the one just added): refused, nothing recorded
        let depth = m.undo_depth();
        for cut in [10, 30, 40, 60] {
            assert_eq!(m.add_boundary(cut), Err(EditError::AlreadyBoundary(cut)), "cut {cut}");
        }
        assert_eq!(m.add_boundary(35), Err(EditError::BoundaryInGap(35)));
        assert_eq!(m.add_boundary(0), Err(EditError::AtTheEdge(0)));
        assert_eq!(m.add_boundary(100), Err(EditError::AtTheEdge(100)));
        assert_eq!(m.undo_depth(), depth);
        assert!(EditError::BoundaryInGap(35).to_string().contains("frame 36"));
        assert_eq!(MyLabels::new(0).add_boundary(1), Err(EditError::NoFrames));
    }

    #[test]
    fn merge_joins_the_next_segment_and_the_gap_between() {
        let mut m = sample();
        assert_eq!(m.merge_with_next(), Err(EditError::NoSelection));
        m.select(Some(1));
        m.merge_with_next().unwrap();
        assert_eq!(spans(&m), vec![(0, 9, "a"), (10, 99, "b")], "b takes the gap and c");
        assert_eq!(m.merge_with_next(), Err(EditError::NoNext));
        // an unlabelled segment takes the next one's label
        let mut m = MyLabels::new(20);
        m.copy_from(&row(&[(0, 4, "x"), (5, 19, "walk")])).unwrap();
        m.select(Some(0));
        m.relabel("").unwrap();
        m.merge_with_next().unwrap();
        assert_eq!(spans(&m), vec![(0, 19, "walk")]);
        assert_eq!(m.selected(), Some(0));
    }

    #[test]
    fn relabel_trims_refuses_bad_labels_and_skips_no_change() {
        let mut m = sample();
        assert_eq!(m.relabel("x"), Err(EditError::NoSelection));
        m.select(Some(0));
        m.relabel("  kick, left  ").unwrap();
        assert_eq!(spans(&m)[0], (0, 9, "kick, left"));
        let depth = m.undo_depth();
        m.relabel("kick, left").unwrap();
        assert_eq!(m.undo_depth(), depth, "the same label is no edit");
        assert_eq!(m.relabel("a\nb"), Err(EditError::LabelControl));
        assert_eq!(m.relabel(&"é".repeat(121)), Err(EditError::LabelTooLong(121)));
        m.relabel(&"é".repeat(120)).unwrap();
        m.relabel("").unwrap();
        assert_eq!(spans(&m)[0], (0, 9, ""), "empty: unlabelled");
        assert_eq!(m.labels_used(), vec!["b", "c"]);
    }

    #[test]
    fn delete_leaves_a_gap_and_selects_the_next_segment() {
        let mut m = sample();
        assert_eq!(m.delete(), Err(EditError::NoSelection));
        m.select(Some(1));
        m.delete().unwrap();
        assert_eq!(spans(&m), vec![(0, 9, "a"), (40, 99, "c")]);
        assert_eq!(m.selected(), Some(1), "c, now second");
        m.delete().unwrap();
        assert_eq!(m.selected(), Some(0), "the last one deleted: the one before");
        m.delete().unwrap();
        assert_eq!(m.selected(), None);
        assert!(m.spans().is_empty());
        // a gap filled again: up to the segments either side
        let mut m = sample();
        m.fill_gap(33).unwrap();
        assert_eq!(spans(&m)[2], (30, 39, ""));
        assert_eq!(m.selected(), Some(2));
        assert_eq!(m.fill_gap(33), Err(EditError::NotAGap(33)));
        let mut m = MyLabels::new(10);
        m.fill_gap(4).unwrap();
        assert_eq!(spans(&m), vec![(0, 9, "")], "an empty row: the whole take");
        assert_eq!(m.fill_gap(10), Err(EditError::NotInSegment(10)));
    }

    #[test]
    fn undo_and_redo_walk_every_edit_back_and_forth() {
        let mut m = MyLabels::new(100);
        let mut states = vec![m.clone()];
        m.copy_from(&row(&[(0, 49, "a"), (50, 99, "b")])).unwrap();
        states.push(m.clone());
        m.move_boundary(50, 60).unwrap();
        states.push(m.clone());
        m.split_at(30).unwrap();
        states.push(m.clone());
        m.relabel("c").unwrap();
        states.push(m.clone());
        m.merge_with_next().unwrap();
        states.push(m.clone());
        m.delete().unwrap();
        states.push(m.clone());
        m.fill_gap(50).unwrap();
        states.push(m.clone());
        m.clear();
        states.push(m.clone());
        let same = |a: &MyLabels, b: &MyLabels| a.spans() == b.spans() && a.selected() == b.selected();
        for want in states.iter().rev().skip(1) {
            m.undo().unwrap();
            assert!(same(&m, want), "undo: {:?} != {:?}", spans(&m), spans(want));
        }
        assert_eq!(m.undo(), Err(EditError::NothingToUndo));
        for want in states.iter().skip(1) {
            m.redo().unwrap();
            assert!(same(&m, want), "redo: {:?} != {:?}", spans(&m), spans(want));
        }
        assert_eq!(m.redo(), Err(EditError::NothingToRedo));
        // a new edit after an undo clears redo
        m.undo().unwrap();
        m.undo().unwrap();
        assert!(m.can_redo());
        m.select(Some(0));
        m.relabel("new").unwrap();
        assert!(!m.can_redo());
        // clearing an empty row is no edit
        let mut e = MyLabels::new(5);
        e.clear();
        assert!(!e.can_undo());
    }

    #[test]
    fn the_history_is_bounded() {
        let mut m = MyLabels::new(1000);
        m.start_empty().unwrap();
        for k in 0..HISTORY_LIMIT + 50 {
            m.relabel(&format!("l{k}")).unwrap();
        }
        assert_eq!(m.undo_depth(), HISTORY_LIMIT);
        for _ in 0..HISTORY_LIMIT {
            m.undo().unwrap();
        }
        assert_eq!(m.undo(), Err(EditError::NothingToUndo));
        assert_eq!(m.spans()[0].label, "l49", "the oldest edits are forgotten");
    }

    #[test]
    fn a_dragged_boundary_snaps_to_the_nearest_cut_within_the_tolerance() {
        let targets = cuts_of([&[(0, 9), (10, 29)][..], &[(5, 14), (40, 99)][..]]);
        assert_eq!(targets, vec![0, 5, 10, 15, 30, 40, 100]);
        assert_eq!(snap(12.2, &targets, 3.0), 10);
        assert_eq!(snap(13.6, &targets, 3.0), 15);
        assert_eq!(snap(12.5, &targets, 3.0), 10, "a tie: the earlier");
        assert_eq!(snap(22.4, &targets, 3.0), 22, "none near: rounded");
        assert_eq!(snap(22.6, &targets, 3.0), 23);
        assert_eq!(snap(27.0, &targets, 3.0), 30, "exactly at the tolerance snaps");
        assert_eq!(snap(-4.0, &targets, 1.0), 0);
        assert_eq!(snap(f64::NAN, &targets, 1.0), 0);
        assert_eq!(snap(103.0, &targets, 2.0), 103, "past the take: the model clamps it");
        assert_eq!(snap(7.0, &[], 10.0), 7);
        // 8 px on a 1000-px lane showing 2000 frames: 16 frames; zoomed to 100 frames: 0.8
        assert_eq!(snap_tolerance(SNAP_PX, 2000.0, 1000.0), 16.0);
        assert!((snap_tolerance(SNAP_PX, 100.0, 1000.0) - 0.8).abs() < 1e-12);
        assert_eq!(snap_tolerance(SNAP_PX, 100.0, 0.0), 0.0);
        assert_eq!(
            snap(12.0, &targets, snap_tolerance(SNAP_PX, 100.0, 1000.0)),
            12,
            "zoomed in: no snap 2 frames away"
        );
    }

    #[test]
    fn stored_labels_read_back_and_corrupt_ones_say_why() {
        let mut m = sample();
        m.select(Some(0));
        m.relabel("say \"hi\", ünïcode").unwrap();
        let json = m.to_json("take.bvh");
        let back = MyLabels::from_json(&json, 100).unwrap();
        assert_eq!(back.spans(), m.spans());
        assert!(!back.can_undo() && back.selected().is_none());
        let empty = MyLabels::from_json(&MyLabels::new(7).to_json("x"), 7).unwrap();
        assert!(empty.spans().is_empty());

        let err = |text: &str| MyLabels::from_json(text, 100).unwrap_err().to_string();
        assert!(err("").contains("not JSON"));
        assert!(err("{\"format\":\"mocapseg-my-labels\"").contains("not JSON"));
        assert!(err("[1,2]").contains("not my labels (format `missing`"));
        assert!(err(r#"{"format":"mocapseg-my-labels","version":2,"frames":100,"segments":[]}"#)
            .contains("version 2; this page reads version 1"));
        assert!(err(r#"{"format":"mocapseg-my-labels","version":1,"frames":100}"#).contains("expected fields"));
        assert!(err(
            r#"{"format":"mocapseg-my-labels","version":1,"frames":100,"segments":[{"start":-1,"end":3,"label":""}]}"#
        )
        .contains("expected fields"));
        assert_eq!(MyLabels::from_json(&json, 99).unwrap_err(), StoreError::Frames { stored: 100, frames: 99 });
        let seg = |list: &str| {
            err(&format!(r#"{{"format":"mocapseg-my-labels","version":1,"frames":100,"segments":[{list}]}}"#))
        };
        assert_eq!(seg(r#"{"start":5,"end":3,"label":""}"#), "stored segment 0: start 5 is after end 3");
        assert_eq!(seg(r#"{"start":5,"end":100,"label":""}"#), "stored segment 0: end 100 is past the last frame 99");
        assert_eq!(
            seg(r#"{"start":0,"end":10,"label":"a"},{"start":10,"end":20,"label":"b"}"#),
            "stored segment 1: starts at 10, inside the segment before it"
        );
        assert!(seg(r#"{"start":0,"end":1,"label":"a\u0000"}"#).starts_with("stored segment 0: a label cannot hold"));
        assert_eq!(seg(r#"{"start":0,"end":1,"label":" a"}"#), "stored segment 0: its label has spaces around it");
    }

    #[test]
    fn storage_keys_tell_takes_apart_and_labels_make_csv_rows() {
        let print = fingerprint([0.0, 1.5, -2.25]);
        let a = storage_key("13_30.bvh", 2465, 120.0, 31, print);
        assert_eq!(a, format!("mocapseg.my-labels.v1:13_30.bvh:2465f:120.000fps:31j:{print:08x}"));
        assert_ne!(a, storage_key("13_30.bvh", 2464, 120.0, 31, print));
        assert_ne!(a, storage_key("13_30.bvh", 2465, 60.0, 31, print));
        assert_ne!(a, storage_key("13_31.bvh", 2465, 120.0, 31, print));
        assert_ne!(a, storage_key("13_30.bvh", 2465, 120.0, 32, print));
        // a corrupt record's backup: the same take, another prefix (never read as labels)
        let backup = backup_key(&a);
        assert_eq!(backup, format!("mocapseg.my-labels-backup.v1:13_30.bvh:2465f:120.000fps:31j:{print:08x}"));
        assert!(!backup.starts_with("mocapseg.my-labels."));
        // the same numbers give the same print; any change (even -0.0 for 0.0) another
        assert_eq!(print, fingerprint([0.0, 1.5, -2.25]));
        assert_ne!(print, fingerprint([-0.0, 1.5, -2.25]));
        assert_ne!(print, fingerprint([0.0, 1.5]));
        assert_eq!(fingerprint([]), 0x811c_9dc5);
        let mut m = sample();
        m.select(Some(1));
        m.relabel("").unwrap();
        let rows = m.label_rows("take.bvh");
        assert_eq!(rows.len(), 2);
        assert_eq!(crate::labels::read_csv(&crate::labels::to_csv(&rows), "x").unwrap(), rows);
        assert_eq!(rows[1], LabelRow { file: "take.bvh".into(), start_frame: 40, end_frame: 99, label: "c".into() });
        assert_eq!(suggestions(["b", "", "a", "b", "  "]), vec!["a", "b"]);
        assert_eq!(label_class("walk"), label_class("walk"));
        assert!(label_class("walk") < 64);
        assert_ne!(label_class("walk"), label_class("kick"));
    }

    #[test]
    fn the_vocabulary_is_the_truths_and_the_models_classes_and_my_own_labels() {
        let sssm = ["A0", "B1", "P1 mirrors P2", "transition"];
        let v = vocabulary(
            ["walk", "jump", "walk", "", "transition"],
            ["Jog", "walk", "Squat", "unknown"],
            ["kick", "A0", "jump", "  spin "],
            &sssm,
        );
        assert_eq!(v, ["walk", "jump", "Jog", "Squat", "kick", "spin"]);
        // a cluster name the truth has too stays (it is a class there)
        assert_eq!(vocabulary(["A0"], [], ["A0", "B1"], &sssm), ["A0"]);
        assert!(vocabulary([], [], sssm, &[]).iter().all(|l| l != "transition"));
        assert_eq!(hotkey_label(&v, "1"), Some("walk"));
        assert_eq!(hotkey_label(&v, "6"), Some("spin"));
        assert_eq!(hotkey_label(&v, "7"), None);
        assert_eq!(hotkey_label(&v, "0"), None);
        assert_eq!(hotkey_label(&v, "a"), None);
        let many: Vec<String> = (0..12).map(|k| format!("c{k}")).collect();
        assert_eq!(hotkey_label(&many, "9"), Some("c8"));
        assert_eq!(hotkey_label(&many, "10"), None, "nine keys");
    }

    #[test]
    fn selection_and_lookup_stay_in_range() {
        let mut m = sample();
        m.select(Some(7));
        assert_eq!(m.selected(), None);
        m.select(Some(2));
        assert_eq!(m.selected_span().map(|s| s.len()), Some(60));
        assert_eq!(m.index_at(0), Some(0));
        assert_eq!(m.index_at(9), Some(0));
        assert_eq!(m.index_at(10), Some(1));
        assert_eq!(m.index_at(35), None);
        assert_eq!(m.index_at(99), Some(2));
        assert_eq!(m.index_at(100), None);
        assert_eq!(m.index_of(40, 99), Some(2));
        assert_eq!(m.index_of(40, 98), None);
    }
}
