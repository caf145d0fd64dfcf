//! The timeline's "my labels" row: the user's own segmentation of the take on screen, edited in
//! place. The edit model (segments, selection, undo/redo, snapping, storage format) is
//! [`crate::app::my_labels::edits`]; this file holds the row's state ([`MyRow`], shared by the row on the
//! timeline and its tools) and the edits it applies. What the row draws is [`super::lane`]; the pointer and the
//! keys, [`super::input`]; the browser's storage, [`super::browser_storage`]; the rows it copies from,
//! [`super::others`]; its tools, [`super::tools`].
//!
//! * `#row-my-labels` (under the methods' rows): each segment `.ms-seg--mine` with `data-start`,
//!   `data-end`, `data-label`, its label drawn in the colour the other rows give the same label
//!   (else a class colour of its own, the same on every take; unlabelled segments hatched), the
//!   selected one outlined (`ms-seg--selected`). Each boundary is a handle `.ms-my-handle`
//!   (`data-cut`: the first frame after it) with a resize cursor: dragging it moves it (a shared
//!   boundary moves both segments), snapping to the other rows' boundaries within
//!   [`snap_reach`](super::snap::snap_reach) (8 px, 3 frames at most; off with `#my-labels-snap` or a held Alt/Shift); the pose and the frame readout follow it, and a neighbour in its way is
//!   rolled, never left a one-frame sliver ([`Model::drag_boundary`]). A handle takes the focus
//!   (Tab): ← / → move it one frame, with Shift one second (a focusable `separator` with
//!   `aria-valuenow`, as the ARIA window-splitter pattern has it), each step an undoable edit that
//!   rolls as a drag does ([`Model::nudge_boundary`]: a neighbour down to two frames is crossed by
//!   the next press, never left one frame). Clicking a segment selects it and moves the playhead to
//!   the frame clicked.
//! * `#my-labels-tools` (under the timeline): `#my-labels-source` + `#my-labels-copy` (copy a row),
//!   `#my-labels-empty`, `#my-labels-split` (at the playhead), `#my-labels-merge` (with the next),
//!   `#my-labels-fill` (the gap under the playhead), `#my-labels-label` (offering the label
//!   vocabulary, `#my-labels-suggestions`) + `#my-labels-apply`, `#my-labels-vocabulary` (the
//!   vocabulary as numbered buttons: the truth's classes, the labelling methods' model classes, the
//!   labels I typed — never a cluster name, a transition or unknown; keys 1–9 give the first
//!   nine), `#my-labels-delete` (leaves a gap), `#my-labels-undo`, `#my-labels-redo`, `#my-labels-train` (DT-FCN on these labels, with
//!   the DT-FCN panel's options), `#my-labels-train-stop`, `#my-labels-clear`, and
//!   `#my-labels-status` (what the last edit did, or why it was refused).
//! * Keys ([`SHORTCUTS`](super::input::SHORTCUTS), in the help overlay): Ctrl/⌘+Z undo, Ctrl/⌘+Shift+Z or Ctrl+Y
//!   redo, S split, M merge, Delete/Backspace delete, 1–9 the vocabulary's entries, and `[` / `]` select my
//!   segment at the previous / next boundary from the playhead when one of my segments is selected (the row's
//!   listener comes before the timeline's) — never while typing in a field.
//! * Every edit is saved in the browser's local storage under
//!   [`storage_key`](super::stored::storage_key) (file name, frames, frame rate, joints, a fingerprint of the first
//!   and last frames' positions); opening the same file again restores
//!   the segments (not the history). Clear removes them (undoable until the page is left). Stored
//!   data that cannot be read is reported in the status line and left alone until the next edit,
//!   which first keeps it under [`backup_key`](super::stored::backup_key) (and says so) — it is never lost. A write the
//!   browser refuses because its storage is full says so and offers the exports (CSV, JSON; the
//!   CSV button takes the focus): the labels stay on screen. Another tab on the same take
//!   (`storage` events): its edits replace this tab's row at once (the status says so), so the
//!   two tabs never overwrite each other's work unseen; the history then starts again.
//!   `document.body.dataset.myLabels` (`data-my-labels`): the number of segments.

use crate::app::library::carry::TRANSFERRED;
use crate::app::models::supervised::TrainRequest;
use crate::app::my_labels::edits::EditError;
use crate::app::my_labels::edits::MyLabels as Model;
use crate::app::my_labels::others::{other_rows, vocabulary_of, OtherRow};
use crate::app::my_labels::vocabulary::{is_reserved, suggestions};
use crate::app::player::motion_image::stem;
use crate::app::state::AppState;
use crate::app::state::Selection;
use crate::labels::to_csv;
use leptos::html::Div;
use leptos::prelude::*;
use std::sync::Arc;

/// The row's id in `state.selected` and its element's (`#row-my-labels`).
pub const ROW: &str = "my-labels";

/// A boundary being dragged: which, the labels before the drag, where it may snap.
#[derive(Debug, Clone)]
pub(super) struct Drag {
    pub(super) cut: usize,
    pub(super) base: Model,
    pub(super) targets: Vec<usize>,
    pub(super) tolerance: f64,
}

/// A line of the status: what happened, or why not (`error`).
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Note {
    pub(super) error: bool,
    pub(super) text: String,
}

/// The row's state, shared by the row on the timeline and its tools under it.
#[derive(Clone, Copy)]
pub struct MyRow {
    pub(super) state: AppState,
    pub(super) model: RwSignal<Model>,
    /// The storage key of the take on screen.
    pub(super) key: RwSignal<Option<String>>,
    /// The stored record of that take when it could not be read: kept under [`backup_key`](super::stored::backup_key)
    /// before the next write replaces it.
    pub(super) corrupt: StoredValue<Option<String>>,
    pub(super) note: RwSignal<Option<Note>>,
    /// The label field's text.
    pub(super) label: RwSignal<String>,
    /// The row chosen to copy (`<method>-actions`…).
    pub(super) source: RwSignal<String>,
    /// The cut being dragged, where it is now.
    pub(super) dragging: RwSignal<Option<usize>>,
    pub(super) drag: StoredValue<Option<Drag>>,
    /// The labels on screen are not stored: the browser refused their last write (a full storage). Another tab's
    /// write then does not replace them (issue 49: nothing the user made is lost to another tab's older state).
    pub(super) unsaved: StoredValue<bool>,
    /// The last training of the chosen trainer was asked from this row.
    pub(super) training: RwSignal<bool>,
    /// The method my labels train in one click (index into [`AppState::my_labels_trainers`]; DT-FCN unless chosen).
    pub(super) trainer: RwSignal<usize>,
    /// A dragged boundary snaps to the other rows' (`#my-labels-snap`; on by default).
    pub(super) snapping: RwSignal<bool>,
    pub(super) others: Memo<Vec<OtherRow>>,
    /// My labels' fixed vocabulary (number keys 1–9 give its first nine).
    pub(super) vocabulary: Memo<Vec<String>>,
    pub(super) lane: NodeRef<Div>,
}

impl MyRow {
    /// The row's state for the page's take; restores the stored labels of each take loaded.
    pub fn new(state: AppState) -> MyRow {
        let model = RwSignal::new(Model::new(0));
        let others = Memo::new(move |_| other_rows(state));
        let row = MyRow {
            state,
            model,
            key: RwSignal::new(None),
            corrupt: StoredValue::new(None),
            note: RwSignal::new(None),
            label: RwSignal::new(String::new()),
            source: RwSignal::new(String::new()),
            dragging: RwSignal::new(None),
            drag: StoredValue::new(None),
            unsaved: StoredValue::new(false),
            training: RwSignal::new(false),
            trainer: RwSignal::new(
                state.my_labels_trainers().iter().position(|(short, _)| *short == "DT-FCN").unwrap_or_default(),
            ),
            snapping: RwSignal::new(true),
            others,
            vocabulary: Memo::new(move |_| vocabulary_of(state, others, model)),
            lane: NodeRef::new(),
        };
        // a take loaded: its stored labels, if any
        row.restore_each_take();
        // the library's "Copy carried labels into my labels": the take's carried labels copied (an undoable edit)
        Effect::new(move |asked: Option<u32>| {
            let now = state.library.copy_asked.get();
            if asked.is_some_and(|a| a != now) {
                row.source.set(TRANSFERRED.into());
                row.copy();
            }
            now
        });
        // my selection is the page's selection (Loop plays it; Esc and clicks elsewhere drop it)
        Effect::new(move |_| {
            let mine = row.model.with(|m| m.selected_span().map(|s| (s.start, s.end)));
            let current = state.selected.get_untracked();
            match mine {
                Some((start, end)) => {
                    let want = Selection { row: ROW.to_string(), start, end };
                    if current.as_ref() != Some(&want) {
                        state.selected.set(Some(want));
                    }
                }
                None if current.as_ref().is_some_and(|s| s.row == ROW) => state.selected.set(None),
                None => {}
            }
        });
        Effect::new(move |_| {
            let other = state.selected.with(|s| s.as_ref().is_none_or(|s| s.row != ROW));
            if other && row.model.with_untracked(|m| m.selected().is_some()) {
                row.model.update(|m| m.select(None));
            }
        });
        // the label field follows the selection
        let selected_label = Memo::new(move |_| row.model.with(|m| m.selected_span().map(|s| s.label.clone())));
        Effect::new(move |_| {
            if let Some(label) = selected_label.get() {
                row.label.set(label);
            }
        });
        // the copy source: the first row until the user picks one
        Effect::new(move |_| {
            let ids: Vec<String> = row.others.with(|o| o.iter().map(|r| r.id.clone()).collect());
            if !ids.contains(&row.source.get_untracked()) {
                row.source.set(ids.first().cloned().unwrap_or_default());
            }
        });
        Effect::new(move |_| {
            let n = row.model.with(|m| m.spans().len());
            if let Some(body) = web_sys::window().and_then(|w| w.document()).and_then(|d| d.body()) {
                let _ = body.set_attribute("data-my-labels", &n.to_string());
            }
        });
        // the row as a segmentation, for the metrics panel and the exports
        Effect::new(move |_| {
            let take = state.motion.with(|m| m.as_ref().map(|m| (m.summary.name.clone(), m.summary.fps)));
            let mine = row.model.with(|m| match take {
                Some((name, fps)) if !m.spans().is_empty() => Some(Arc::new(m.to_segmentation(&name, fps))),
                _ => None,
            });
            state.mine.set(mine);
        });
        row.listen();
        row
    }

    pub(super) fn take_name(self) -> String {
        self.state.motion.with_untracked(|m| m.as_ref().map(|m| m.summary.name.clone()).unwrap_or_default())
    }

    pub(super) fn say(self, error: bool, text: String) {
        self.note.set(Some(Note { error, text }));
    }

    /// Applies an edit and saves; a refused edit says why. `done` describes a successful one.
    pub(super) fn edit(self, edit: impl FnOnce(&mut Model) -> Result<(), EditError>, done: Option<String>) -> bool {
        let mut result = Ok(());
        self.model.update(|m| result = edit(m));
        match result {
            Ok(()) => {
                self.note.set(done.map(|text| Note { error: false, text }));
                self.save();
                true
            }
            Err(e) => {
                self.say(true, capitalised(&e.to_string()));
                false
            }
        }
    }

    pub(super) fn frame(self) -> usize {
        self.state.frame.get_untracked()
    }

    pub(super) fn split(self) {
        let f = self.frame();
        self.edit(|m| m.split_at(f), Some(format!("Split at frame {}", f + 1)));
    }

    pub(super) fn merge(self) {
        self.edit(Model::merge_with_next, None);
    }

    pub(super) fn delete(self) {
        self.edit(
            Model::delete,
            Some("Deleted: its frames are a gap now (Fill gap or Undo brings a segment back)".into()),
        );
    }

    /// `[` / `]` with one of my segments selected: the previous / next boundary of my row from the
    /// playhead (not from the selected segment: the playhead may have moved since); selects my
    /// segment starting there (at a gap's start the selection stays) and brings it into view.
    pub(super) fn step(self, forward: bool) {
        let (frame, frames) = (self.state.frame.get_untracked(), self.state.frames());
        let Some((at, segment)) = self.model.with_untracked(|m| {
            let spans: Vec<(usize, usize)> = m.spans().iter().map(|s| (s.start, s.end)).collect();
            let at = if forward {
                crate::app::timeline::window::next_boundary(&spans, frame, frames)
            } else {
                crate::app::timeline::window::previous_boundary(&spans, frame, frames)
            }?;
            Some((at, spans.into_iter().find(|s| s.0 == at)))
        }) else {
            return;
        };
        let (start, end) = segment.unwrap_or((at, at));
        if segment.is_some() {
            self.model.update(|m| m.select(m.index_of(start, end)));
        }
        self.state.play_until.set(None);
        self.state.window.update(|w| *w = w.showing(start, end, frames));
        self.state.frame.set(at);
    }

    pub(super) fn undo(self) {
        self.edit(Model::undo, None);
    }

    pub(super) fn redo(self) {
        self.edit(Model::redo, None);
    }

    pub(super) fn relabel(self) {
        let text = self.label.get_untracked();
        self.edit(|m| m.relabel(&text), None);
    }

    /// Puts one segment of another row in my labels (the timeline's context menu): `label`
    /// empty for a transition or an unknown stretch, which stays unlabelled.
    pub fn place(self, start: usize, end: usize, label: &str, from: &str) -> bool {
        let done = format!("Copied frames {}–{} from {from}", start + 1, end + 1);
        self.edit(|m| m.place(start, end, label), Some(done))
    }

    /// Puts a boundary at cut `cut` in my labels (an accepted consensus boundary, `agreed`: by how many methods),
    /// splitting my segment there or starting my labels with it ([`Model::add_boundary`]); why not, when refused.
    pub fn accept_boundary(self, cut: usize, agreed: &str) -> Result<(), String> {
        let done = format!("Boundary at frame {} accepted from the consensus ({agreed})", cut + 1);
        let mut refused = String::new();
        let accepted =
            self.edit(|m| m.add_boundary(cut).inspect_err(|e| refused = capitalised(&e.to_string())), Some(done));
        if accepted {
            Ok(())
        } else {
            Err(refused)
        }
    }

    /// My boundaries' cuts, sorted (the consensus row marks the ones it agrees with).
    pub fn cuts(self) -> Signal<Vec<usize>> {
        let model = self.model;
        Signal::derive(move || model.with(Model::boundaries))
    }

    /// Gives the selected segment `label` (a vocabulary entry: its number key or its button).
    pub(super) fn label_with(self, label: String) {
        let done = format!("Labelled {label}");
        if self.edit(|m| m.relabel(&label), Some(done)) {
            self.label.set(label);
        }
    }

    pub(super) fn copy(self) {
        let id = self.source.get_untracked();
        let Some(from) = self.others.with_untracked(|o| o.iter().find(|r| r.id == id).cloned()) else {
            self.say(true, "No row to copy yet: run a method first, or start empty".into());
            return;
        };
        let spans: Vec<(usize, usize, String)> = from.segments.iter().map(|s| (s.0, s.1, s.2.clone())).collect();
        // transitions, unknowns and unlabelled parts stay gaps (never a label or a class)
        let gaps = spans.iter().filter(|s| s.2.trim().is_empty() || is_reserved(&s.2)).count();
        let n = spans.len() - gaps;
        let left = match gaps {
            0 => String::new(),
            g => format!(" ({g} transition{} or unknown part{} left as gaps)", plural(g), plural(g)),
        };
        self.edit(|m| m.copy_from(&spans), Some(format!("Copied {n} segment{} from {}{left}", plural(n), from.name)));
    }

    /// The method my labels train in one click, as chosen: its short name and its training.
    pub(super) fn chosen_trainer(self) -> Option<(&'static str, &'static crate::app::models::supervised::Supervised)> {
        let trainers = self.state.my_labels_trainers();
        trainers.get(self.trainer.get()).or(trainers.first()).copied()
    }

    /// Starts a training of the chosen method (k-NN or DT-FCN) on my labelled segments, with its panel's options, and
    /// says the same advice its panel gives (classes with too few segments or seconds).
    pub(super) fn train(self) {
        let name = self.take_name();
        let rows = self.model.with_untracked(|m| m.label_rows(&name));
        let classes = suggestions(rows.iter().map(|r| r.label.as_str()));
        let Some((short, trainer)) = self.chosen_trainer() else { return };
        if classes.len() < 2 {
            self.say(
                true,
                format!(
                    "{short} learns to tell labels apart: give my segments at least two different labels (now {})",
                    if classes.is_empty() { "none".to_string() } else { classes.join(", ") }
                ),
            );
            return;
        }
        self.training.set(true);
        let fps = self.state.fps();
        let counts = crate::app::models::training_advice::class_counts(&rows, &[(name.clone(), fps)]);
        let advice = crate::app::models::training_advice::advice(&counts);
        if advice.is_empty() {
            self.note.set(None);
        } else {
            self.say(true, format!("Training {short} anyway — advice: {}", advice.join(" ")));
        }
        trainer.request.set(Some(TrainRequest::Labels {
            labels_name: format!("my labels of {name}"),
            csv: to_csv(&rows),
            model_name: format!("{}-my-labels", stem(&name)),
        }));
    }
}

fn plural(n: usize) -> &'static str {
    if n == 1 {
        ""
    } else {
        "s"
    }
}

fn capitalised(text: &str) -> String {
    let mut c = text.chars();
    c.next().map(|f| f.to_uppercase().chain(c).collect()).unwrap_or_default()
}
