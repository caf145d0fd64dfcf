//! The timeline's "my labels" row: the user's own segmentation of the take on screen, edited in
//! place. The edit model (segments, selection, undo/redo, snapping, storage format) is
//! [`crate::app::my_labels::edits`]; this file draws it and turns pointer and key events into its
//! operations.
//!
//! * `#row-my-labels` (under the methods' rows): each segment `.ms-seg--mine` with `data-start`,
//!   `data-end`, `data-label`, its label drawn in the colour the other rows give the same label
//!   (else a class colour of its own, the same on every take; unlabelled segments hatched), the
//!   selected one outlined (`ms-seg--selected`). Each boundary is a handle `.ms-my-handle`
//!   (`data-cut`: the first frame after it) with a resize cursor: dragging it moves it (a shared
//!   boundary moves both segments), snapping to the other rows' boundaries within
//!   [`SNAP_PX`] pixels; the pose and the frame readout follow it, and a neighbour in its way is
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
//! * Keys ([`SHORTCUTS`], in the help overlay): Ctrl/⌘+Z undo, Ctrl/⌘+Shift+Z or Ctrl+Y redo, S
//!   split, M merge, Delete/Backspace delete, 1–9 the vocabulary's entries, and `[` / `]` select my segment at the previous /
//!   next boundary from the playhead when one of my segments is selected (the row's listener
//!   comes before the timeline's) — never
//!   while typing in a field.
//! * Every edit is saved in the browser's local storage under
//!   [`storage_key`] (file name, frames, frame rate, joints, a fingerprint of the first and last
//!   frames' positions); opening the same file again restores
//!   the segments (not the history). Clear removes them (undoable until the page is left). Stored
//!   data that cannot be read is reported in the status line and left alone until the next edit,
//!   which first keeps it under [`backup_key`] (and says so) — it is never lost. A write the
//!   browser refuses because its storage is full says so and offers the exports (CSV, JSON; the
//!   CSV button takes the focus): the labels stay on screen. Another tab on the same take
//!   (`storage` events): its edits replace this tab's row at once (the status says so), so the
//!   two tabs never overwrite each other's work unseen; the history then starts again.
//!   `document.body.dataset.myLabels` (`data-my-labels`): the number of segments.

use crate::app::effort::bars::EffortLane;
use crate::app::library::carry::TRANSFERRED;
use crate::app::models::supervised::TrainRequest;
use crate::app::my_labels::edits::EditError;
use crate::app::my_labels::edits::MyLabels as Model;
use crate::app::my_labels::snap::{cuts_of, snap, snap_tolerance, SNAP_PX};
use crate::app::my_labels::spans::LabelSpan;
use crate::app::my_labels::stored::{backup_key, fingerprint, storage_key};
use crate::app::my_labels::vocabulary::{hotkey_label, is_reserved, label_class, suggestions, vocabulary};
use crate::app::player::motion_image::stem;
use crate::app::state::AppState;
use crate::app::state::Selection;
use crate::app::timeline::keys::is_for_the_field;
use crate::app::timeline::rows::is_labelling;
use crate::app::timeline::rows::labels_classes;
use crate::app::timeline::window::{visible_segments, Window};
use crate::labels::to_csv;
use crate::protocol::MethodView;
use crate::segment::palette::{action_colour, class_colour, cluster_colour};
use crate::segment::Level;
use gloo::events::EventListener;
use leptos::ev::{KeyboardEvent, MouseEvent, PointerEvent};
use leptos::html::Div;
use leptos::prelude::*;
use std::collections::HashMap;
use std::sync::Arc;
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;

/// The row's id in `state.selected` and its element's (`#row-my-labels`).
pub const ROW: &str = "my-labels";

/// At most about twice this many of my segments are in the DOM at once.
const MAX_SEGMENTS: usize = 120;

/// Shortcuts of the row, listed in the help overlay after the timeline's.
pub const SHORTCUTS: [(&str, &str); 8] = [
    ("Ctrl or ⌘ + Z", "undo the last edit of my labels"),
    ("1 – 9", "my labels: give the selected segment that entry of the label vocabulary (numbered under the timeline)"),
    ("Ctrl or ⌘ + Shift + Z, Ctrl + Y", "redo it"),
    ("S", "my labels: split the segment under the playhead at the playhead"),
    ("M", "my labels: merge the selected segment with the next one"),
    ("Delete / Backspace", "my labels: delete the selected segment (its frames become a gap)"),
    (
        "Drag a boundary of my labels",
        "move it (the pose follows); it snaps to the other rows' boundaries within 8 px and rolls over a neighbour, \
         removing it once dragged across it",
    ),
    ("Tab to a boundary of my labels, ← / →", "move it one frame (with Shift: one second)"),
];

#[wasm_bindgen]
extern "C" {
    /// The Web Storage interface (`localStorage`), bound here rather than through a web-sys
    /// feature the crate does not turn on.
    type WebStorage;
    #[wasm_bindgen(method, catch, js_name = getItem)]
    fn get_item(this: &WebStorage, key: &str) -> Result<Option<String>, JsValue>;
    #[wasm_bindgen(method, catch, js_name = setItem)]
    fn set_item(this: &WebStorage, key: &str, value: &str) -> Result<(), JsValue>;
    #[wasm_bindgen(method, catch, js_name = removeItem)]
    fn remove_item(this: &WebStorage, key: &str) -> Result<(), JsValue>;
}

/// What a JavaScript exception says.
fn describe(e: &JsValue) -> String {
    e.dyn_ref::<js_sys::Error>()
        .map(|e| String::from(e.message()))
        .or_else(|| e.as_string())
        .unwrap_or_else(|| format!("{e:?}"))
}

/// The page's local storage (absent or refused in some private modes).
fn local_storage() -> Result<WebStorage, String> {
    let window = web_sys::window().ok_or("no window")?;
    let value = js_sys::Reflect::get(&window, &JsValue::from_str("localStorage")).map_err(|e| describe(&e))?;
    if value.is_null() || value.is_undefined() {
        return Err("this browser gives the page no local storage".into());
    }
    Ok(value.unchecked_into())
}

/// A row of the timeline besides mine: its id, its label and its segments (frames, label, the
/// CSS colour it is drawn in, `None` when hatched).
#[derive(Debug, Clone, PartialEq)]
pub(super) struct OtherRow {
    pub(super) id: String,
    pub(super) name: String,
    pub(super) segments: Vec<(usize, usize, String, Option<String>)>,
    /// Its labels are classes (the ground truth, a labelling method's): my labels' vocabulary.
    pub(super) classes: bool,
}

/// The colour a segment has in its method's row (as `method_panel` draws it; `None`: hatched).
fn segment_colour(v: &MethodView, s: &crate::segment::Segment) -> Option<String> {
    if is_labelling(v) {
        return s.cluster.map(|c| {
            v.segmentation
                .params
                .get("colours")
                .and_then(|c2| c2.get(c))
                .and_then(|c2| c2.as_str())
                .map_or_else(|| class_colour(c), str::to_string)
        });
    }
    match (s.level, s.cluster) {
        (Level::Transition, _) => None,
        (Level::Primitive, Some(c)) => Some(cluster_colour(c, s.mirror_of)),
        (_, Some(c)) => {
            let [r, g, b] = action_colour(c);
            Some(format!("rgb({r}, {g}, {b})"))
        }
        (_, None) => Some("#888".to_string()),
    }
}

/// Every method row with segments, in the page's order (tracks the methods' results).
fn other_rows(state: AppState) -> Vec<OtherRow> {
    let mut rows = Vec::new();
    // the imported ground truth first: copying it is where a correction usually starts
    state.truth.view.with(|v| {
        let Some(v) = v else { return };
        let mut segments: Vec<_> =
            v.segmentation.segments.iter().map(|s| (s.start, s.end, s.label.clone(), segment_colour(v, s))).collect();
        segments.sort_by_key(|s| s.0);
        if !segments.is_empty() {
            rows.push(OtherRow { id: "truth".into(), name: "Ground truth".into(), segments, classes: true });
        }
    });
    for slot in state.methods {
        slot.view.with(|v| {
            let Some(v) = v else { return };
            for primitive in [false, true] {
                let mut segments: Vec<_> = v
                    .segmentation
                    .segments
                    .iter()
                    .filter(|s| (s.level == Level::Primitive) == primitive)
                    .map(|s| (s.start, s.end, s.label.clone(), segment_colour(v, s)))
                    .collect();
                if segments.is_empty() {
                    continue;
                }
                segments.sort_by_key(|s| s.0);
                // the row's name as the timeline gives it (view::rows)
                let kind = crate::app::timeline::rows::row_kind(Some(&**v), primitive);
                rows.push(OtherRow {
                    id: format!("{}-{}", slot.info.name, if primitive { "primitives" } else { "actions" }),
                    name: crate::app::timeline::rows::row_name(&slot.info.short, kind),
                    segments,
                    classes: crate::app::timeline::rows::is_labelling(v) && !primitive,
                });
            }
        });
    }
    // the labels carried across the library to this take
    if let Some(v) = crate::app::library::panel::transferred_view(state) {
        let segments =
            v.segmentation.segments.iter().map(|s| (s.start, s.end, s.label.clone(), segment_colour(&v, s))).collect();
        rows.push(OtherRow { id: TRANSFERRED.into(), name: "Transferred".into(), segments, classes: true });
    }
    rows
}

/// My labels' vocabulary ([`vocabulary`]): the truth's classes, the labelling methods' model
/// classes (those their rows show, and every class of the models the user loaded or trained),
/// then the labels I gave — never an unsupervised method's cluster names.
fn vocabulary_of(state: AppState, others: Memo<Vec<OtherRow>>, model: RwSignal<Model>) -> Vec<String> {
    others.with(|others| {
        let truth: Vec<&str> =
            others.iter().filter(|r| r.id == "truth").flat_map(|r| r.segments.iter().map(|s| s.2.as_str())).collect();
        let mut models: Vec<String> = others
            .iter()
            .filter(|r| r.classes && r.id != "truth")
            .flat_map(|r| r.segments.iter().map(|s| s.2.clone()))
            .collect();
        for slot in state.methods.iter().filter(|m| labels_classes(&m.info.name)) {
            if let Some(sup) = &slot.supervised {
                sup.models.with(|list| models.extend(list.iter().flat_map(|m| m.info.classes.iter().cloned())));
            }
        }
        let excluded: Vec<&str> =
            others.iter().filter(|r| !r.classes).flat_map(|r| r.segments.iter().map(|s| s.2.as_str())).collect();
        let mine = model.with(|m| m.labels_used());
        vocabulary(truth, models.iter().map(String::as_str), mine.iter().map(String::as_str), &excluded)
    })
}

/// A boundary being dragged: which, the labels before the drag, where it may snap.
#[derive(Debug, Clone)]
struct Drag {
    cut: usize,
    base: Model,
    targets: Vec<usize>,
    tolerance: f64,
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
    /// The stored record of that take when it could not be read: kept under [`backup_key`]
    /// before the next write replaces it.
    pub(super) corrupt: StoredValue<Option<String>>,
    pub(super) note: RwSignal<Option<Note>>,
    /// The label field's text.
    pub(super) label: RwSignal<String>,
    /// The row chosen to copy (`<method>-actions`…).
    pub(super) source: RwSignal<String>,
    /// The cut being dragged, where it is now.
    pub(super) dragging: RwSignal<Option<usize>>,
    drag: StoredValue<Option<Drag>>,
    /// The last DT-FCN training was asked from this row.
    pub(super) training: RwSignal<bool>,
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
            training: RwSignal::new(false),
            others,
            vocabulary: Memo::new(move |_| vocabulary_of(state, others, model)),
            lane: NodeRef::new(),
        };
        // a take loaded: its stored labels, if any
        Effect::new(move |_| {
            let take = state.motion.with(|m| {
                m.as_ref().map(|m| {
                    let s = &m.summary;
                    let last = s.frames.saturating_sub(1);
                    let print = fingerprint(m.frame(0).chain(m.frame(last)).flat_map(|p| p.to_array()));
                    (storage_key(&s.name, s.frames, s.fps, s.joints, print), s.frames)
                })
            });
            row.drag.set_value(None);
            row.dragging.set(None);
            match take {
                None => {
                    row.key.set(None);
                    row.corrupt.set_value(None);
                    row.model.set(Model::new(0));
                }
                Some((key, frames)) => {
                    row.key.set(Some(key.clone()));
                    let (model, note, corrupt) = restore(&key, frames, false);
                    row.corrupt.set_value(corrupt);
                    row.model.set(model);
                    row.note.set(note);
                }
            }
        });
        // the library's "Copy into my labels": the take's transferred labels copied (an undoable edit)
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

    /// Writes the labels to storage (removes them when there are none). A stored record that
    /// could not be read is first kept under its backup key (and the user told where); a write
    /// the browser refuses is said, with the exports offered when its storage is full.
    pub(super) fn save(self) {
        let Some(key) = self.key.get_untracked() else { return };
        let name = self.take_name();
        let (empty, json) = self.model.with_untracked(|m| (m.spans().is_empty(), m.to_json(&name)));
        let storage = match local_storage() {
            Ok(storage) => storage,
            Err(e) => return self.say(true, format!("My labels could not be saved in this browser: {e}")),
        };
        let mut kept = None;
        if let Some(bad) = self.corrupt.get_value() {
            let backup = backup_key(&key);
            if let Err(e) = storage.set_item(&backup, &bad) {
                // the unreadable record stays where it is rather than be lost
                return self
                    .unsaved(&e, &format!(" (the unreadable record they replace could not be kept under {backup})"));
            }
            self.corrupt.set_value(None);
            kept = Some(backup);
        }
        let saved = if empty { storage.remove_item(&key) } else { storage.set_item(&key, &json) };
        match (saved, kept) {
            (Err(e), _) => self.unsaved(&e, ""),
            (Ok(()), Some(backup)) => self.say(
                true,
                format!(
                    "The labels saved before for this take could not be read: that record is kept in this browser's \
                     storage under {backup}, and these labels are saved in its place"
                ),
            ),
            (Ok(()), None) => {}
        }
    }

    /// Says why the labels could not be written (`e`, the browser's error; `also`, what else is
    /// left undone); when the browser's storage is full, offers the exports (the CSV button takes
    /// the focus) — the labels stay on screen until the page is left.
    pub(super) fn unsaved(self, e: &JsValue, also: &str) {
        let name = js_sys::Reflect::get(e, &"name".into()).ok().and_then(|n| n.as_string()).unwrap_or_default();
        let full = matches!(name.as_str(), "QuotaExceededError" | "NS_ERROR_DOM_QUOTA_REACHED");
        if !full {
            return self.say(true, format!("My labels could not be saved in this browser{also}: {}", describe(e)));
        }
        self.say(
            true,
            format!(
                "My labels could not be saved{also}: this browser's storage is full. Keep them with the CSV or JSON \
                 export below — they stay on screen until you leave the page"
            ),
        );
        // the export buttons are enabled once the row's segmentation is updated (an effect)
        gloo::timers::callback::Timeout::new(0, || {
            let button = gloo::utils::document().get_element_by_id("my-labels-export-csv");
            if let Some(b) = button.and_then(|b| b.dyn_into::<web_sys::HtmlElement>().ok()) {
                let _ = b.focus();
            }
        })
        .forget();
    }

    /// Another tab changed the stored labels of the take on screen: they replace this tab's row
    /// (an edit here would otherwise overwrite them unseen).
    pub(super) fn from_other_tab(self) {
        let Some(key) = self.key.get_untracked() else { return };
        let frames = self.state.frames();
        self.drag.set_value(None);
        self.dragging.set(None);
        let (model, note, corrupt) = restore(&key, frames, true);
        self.corrupt.set_value(corrupt);
        self.model.set(model);
        self.note.set(note);
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

    /// Starts a DT-FCN training on my labelled segments, with the DT-FCN panel's options.
    pub(super) fn train(self) {
        let name = self.take_name();
        let rows = self.model.with_untracked(|m| m.label_rows(&name));
        let classes = suggestions(rows.iter().map(|r| r.label.as_str()));
        let Some((short, trainer)) = self.state.my_labels_trainer() else { return };
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
        self.note.set(None);
        trainer.request.set(Some(TrainRequest::Labels {
            labels_name: format!("my labels of {name}"),
            csv: to_csv(&rows),
            model_name: format!("{}-my-labels", stem(&name)),
        }));
    }

    /// The frame position (fractional) at a pointer's x, over my lane.
    pub(super) fn position_at(self, client_x: f64) -> Option<(f64, f64)> {
        let rect = self.lane.get_untracked()?.get_bounding_client_rect();
        if rect.width() <= 0.0 {
            return None;
        }
        let w = self.state.window.get_untracked();
        Some((w.start + (client_x - rect.left()) / rect.width() * w.span(), rect.width()))
    }

    /// Moves boundary `cut` by `by` frames from the keyboard (one undoable edit; it rolls as a
    /// drag does: [`Model::nudge_boundary`]) and keeps the focus on its handle, drawn again at its
    /// new frame.
    pub(super) fn nudge(self, cut: usize, by: isize) {
        let mut landed = cut;
        let moved = self.edit(
            |m| {
                landed = m.nudge_boundary(cut, by)?;
                Ok(())
            },
            None,
        );
        if !moved {
            return;
        }
        let limit = if landed == cut { " (as far as it goes)" } else { "" };
        self.say(false, format!("Boundary before frame {}{limit}", landed + 1));
        // the handles are drawn again after this event: focus the new one then
        gloo::timers::callback::Timeout::new(0, move || {
            let selector = format!("#row-my-labels .ms-my-handle[data-cut=\"{landed}\"]");
            let handle = gloo::utils::document().query_selector(&selector).ok().flatten();
            if let Some(h) = handle.and_then(|h| h.dyn_into::<web_sys::HtmlElement>().ok()) {
                let _ = h.focus();
            }
        })
        .forget();
    }

    /// Starts dragging boundary `cut`.
    pub(super) fn grab(self, cut: usize, ev: &PointerEvent) {
        if ev.button() != 0 {
            return;
        }
        ev.stop_propagation();
        ev.prevent_default();
        let Some((_, width)) = self.position_at(ev.client_x() as f64) else { return };
        let rows: Vec<Vec<(usize, usize)>> =
            self.others.with_untracked(|o| o.iter().map(|r| r.segments.iter().map(|s| (s.0, s.1)).collect()).collect());
        let targets = cuts_of(rows.iter().map(Vec::as_slice));
        let tolerance = snap_tolerance(SNAP_PX, self.state.window.get_untracked().span(), width);
        self.drag.set_value(Some(Drag { cut, base: self.model.get_untracked(), targets, tolerance }));
        self.dragging.set(Some(cut));
        self.state.playing.set(false);
    }

    /// The page-wide listeners: the drag follows the pointer anywhere; the row's keys.
    pub(super) fn listen(self) {
        let window = gloo::utils::window();
        let on_move = move |ev: &web_sys::Event| {
            let Some(ev) = ev.dyn_ref::<web_sys::PointerEvent>() else { return };
            let Some(drag) = self.drag.get_value() else { return };
            let Some((at, _)) = self.position_at(ev.client_x() as f64) else { return };
            let to = snap(at, &drag.targets, drag.tolerance);
            let mut m = drag.base.clone();
            let landed = m.drag_boundary(drag.cut, to).unwrap_or(drag.cut);
            self.model.set(m);
            self.dragging.set(Some(landed));
            // the pose and the readout follow: the first frame after the boundary
            let frames = self.state.frames();
            if frames > 0 {
                self.state.frame.set(landed.min(frames - 1));
            }
            let snapped = landed == to && drag.targets.binary_search(&landed).is_ok() && (at - to as f64).abs() > 1e-9;
            let text = format!(
                "Boundary at frame {}{}",
                landed + 1,
                if snapped { " — snapped to another row's boundary" } else { "" }
            );
            self.say(false, text);
        };
        let on_up = move |ev: &web_sys::Event| {
            let Some(drag) = self.drag.get_value() else { return };
            self.drag.set_value(None);
            self.dragging.set(None);
            if ev.type_() == "pointercancel" {
                self.model.set(drag.base);
                self.note.set(None);
                return;
            }
            if self.model.with_untracked(|m| m.undo_depth() != drag.base.undo_depth() || m.spans() != drag.base.spans())
            {
                self.save();
            }
        };
        // another tab wrote my labels (`key` null: it cleared the whole storage)
        let on_storage = move |ev: &web_sys::Event| {
            let changed = js_sys::Reflect::get(ev, &"key".into()).ok().and_then(|k| k.as_string());
            if changed.is_none() || changed == self.key.get_untracked() {
                self.from_other_tab();
            }
        };
        EventListener::new(&window, "storage", on_storage).forget();
        EventListener::new(&window, "pointermove", on_move).forget();
        EventListener::new(&window, "pointerup", on_up).forget();
        EventListener::new(&window, "pointercancel", on_up).forget();

        let keys = window_event_listener(leptos::ev::keydown, move |ev: KeyboardEvent| {
            let key = ev.key();
            if ev.default_prevented() || is_for_the_field(ev.target(), &key) || self.state.frames() == 0 {
                return;
            }
            let command = ev.ctrl_key() || ev.meta_key();
            let started = self.model.with_untracked(|m| !m.spans().is_empty() || m.can_undo() || m.can_redo());
            let selected = self.model.with_untracked(|m| m.selected().is_some());
            let run: Option<fn(MyRow)> = match key.as_str() {
                "z" | "Z" if command && !ev.alt_key() && ev.shift_key() => Some(MyRow::redo),
                "z" | "Z" if command && !ev.alt_key() => Some(MyRow::undo),
                "y" | "Y" if ev.ctrl_key() && !ev.alt_key() && !ev.shift_key() => Some(MyRow::redo),
                _ if command || ev.alt_key() => None,
                "s" | "S" if started => Some(MyRow::split),
                "m" | "M" if selected => Some(MyRow::merge),
                "Delete" | "Backspace" if selected => Some(MyRow::delete),
                "]" if selected => Some(|row: MyRow| row.step(true)),
                "[" if selected => Some(|row: MyRow| row.step(false)),
                digit if selected && self.vocabulary.with_untracked(|v| hotkey_label(v, digit).is_some()) => {
                    let label = self.vocabulary.with_untracked(|v| hotkey_label(v, digit).map(str::to_string));
                    if let Some(label) = label {
                        ev.prevent_default();
                        self.label_with(label);
                    }
                    return;
                }
                _ => None,
            };
            if let Some(run) = run {
                ev.prevent_default();
                run(self);
            }
        });
        std::mem::forget(keys); // the row lives as long as the page
    }
}

/// The stored labels of `key` for a take of `frames`, what to tell the user, and the stored text
/// when it cannot be read (kept under its backup key before the next write). `other_tab`: they
/// were just written by another tab.
fn restore(key: &str, frames: usize, other_tab: bool) -> (Model, Option<Note>, Option<String>) {
    let stored = local_storage().and_then(|s| s.get_item(key).map_err(|e| describe(&e)));
    let plural = |n: usize| if n == 1 { "" } else { "s" };
    match stored {
        Ok(None) if other_tab => {
            let text = "My labels were cleared in another tab of this take".to_string();
            (Model::new(frames), Some(Note { error: false, text }), None)
        }
        Ok(None) => (Model::new(frames), None, None),
        Ok(Some(text)) => match Model::from_json(&text, frames) {
            Ok(model) => {
                let n = model.spans().len();
                let text = if other_tab {
                    format!("Updated from another tab of this take: {n} segment{}", plural(n))
                } else {
                    format!("Restored {n} segment{} saved in this browser for this take", plural(n))
                };
                (model, Some(Note { error: false, text }), None)
            }
            Err(e) => (
                Model::new(frames),
                Some(Note {
                    error: true,
                    text: format!(
                        "My labels saved for this take could not be read ({e}); they stay stored until you edit or \
                         Clear, and are then kept under {}",
                        backup_key(key)
                    ),
                }),
                Some(text),
            ),
        },
        Err(e) => {
            let text = format!("Browser storage is unavailable: {e}");
            (Model::new(frames), Some(Note { error: true, text }), None)
        }
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

/// The colour of my label `label`: the one another row draws it in (the first that has it;
/// `None`: hatched there too), else a class colour of its own.
fn colour_of(label: &str, known: &HashMap<String, Option<String>>) -> Option<String> {
    match known.get(label) {
        Some(colour) => colour.clone(),
        None => Some(class_colour(label_class(label))),
    }
}

/// My segment `i`, `s` (`selected`: the one selected), in the window `w`, coloured as the other rows colour its label
/// (`known`), its tip in seconds at `fps`: click to select it, the playhead where clicked.
fn my_segment(
    mine: MyRow,
    i: usize,
    s: LabelSpan,
    selected: bool,
    w: &Window,
    known: &HashMap<String, Option<String>>,
    fps: f64,
) -> impl IntoView {
    let colour = (!s.label.is_empty()).then(|| colour_of(&s.label, known)).flatten();
    let class = match (s.label.is_empty(), &colour) {
        (true, _) => "ms-seg ms-seg--mine ms-seg--unlabelled",
        (false, None) => "ms-seg ms-seg--mine ms-seg--transition",
        (false, Some(_)) => "ms-seg ms-seg--mine ms-seg--coloured",
    };
    let left = w.fraction(s.start as f64).max(0.0);
    let right = w.fraction((s.end + 1) as f64).min(1.0);
    let text = if s.label.is_empty() { "unlabelled".to_string() } else { s.label.clone() };
    // the label, or a clean abbreviation when it does not fit (in full in the tip)
    let shown = crate::app::timeline::lanes::segment_text(&text, right - left);
    let tip = format!(
        "{text} · frames {}–{} · {:.2}–{:.2} s",
        s.start + 1,
        s.end + 1,
        s.start as f64 / fps,
        (s.end + 1) as f64 / fps
    );
    let (start, end) = (s.start, s.end);
    let on_click = move |ev: MouseEvent| {
        ev.stop_propagation();
        mine.model.update(|m| m.select(Some(i)));
        mine.state.play_until.set(None);
        if let Some((at, _)) = mine.position_at(ev.client_x() as f64) {
            mine.state.frame.set((at.floor().max(0.0) as usize).clamp(start, end));
        }
    };
    view! {
        <div
            class=class
            class:ms-seg--selected=selected
            style:left=format!("{:.4}%", left * 100.0)
            style:width=format!("{:.4}%", (right - left).max(0.0) * 100.0)
            style:color=colour.as_deref().map(crate::app::timeline::contrast::ink_on)
            style:background-color=colour
            data-start=s.start.to_string()
            data-end=s.end.to_string()
            data-label=s.label.clone()
            aria-label=tip
            aria-pressed=selected.to_string()
            role="button"
            on:pointerdown=move |ev: PointerEvent| ev.stop_propagation()
            on:click=on_click
        >
            {shown}
        </div>
    }
}

/// The handle of my boundary before frame `cut` (`left`: where it is, a fraction of the lanes; `active`: being
/// dragged): drag it, or ← / → (Shift: a second) when it has the focus.
fn boundary_handle(mine: MyRow, cut: usize, frames: usize, active: bool, left: f64) -> impl IntoView {
    let label = if cut >= frames {
        format!("End of my last segment, after frame {cut}: drag, or ← / → (Shift: 1 s), to move")
    } else {
        format!("Boundary before frame {}: drag, or ← / → (Shift: 1 s), to move", cut + 1)
    };
    let on_key = move |ev: KeyboardEvent| {
        let step = if ev.shift_key() { mine.state.fps().round().max(1.0) as isize } else { 1 };
        let by = match ev.key().as_str() {
            "ArrowLeft" => -step,
            "ArrowRight" => step,
            _ => return,
        };
        if ev.ctrl_key() || ev.meta_key() || ev.alt_key() {
            return;
        }
        // the timeline's own ← / → (a frame, a second) must not act as well
        ev.prevent_default();
        ev.stop_propagation();
        mine.nudge(cut, by);
    };
    view! {
        <div
            class="ms-my-handle"
            class:ms-my-handle--active=active
            style:left=format!("{:.4}%", left * 100.0)
            data-cut=cut.to_string()
            role="separator"
            aria-orientation="vertical"
            tabindex="0"
            aria-valuemin="1"
            aria-valuemax=(frames + 1).to_string()
            aria-valuenow=(cut + 1).to_string()
            aria-label=label.clone()
            title=label
            on:pointerdown=move |ev: PointerEvent| mine.grab(cut, &ev)
            on:keydown=on_key
        ></div>
    }
}

/// `#row-my-labels` on the timeline.
#[component]
pub fn MyLabelsRow(mine: MyRow) -> impl IntoView {
    let state = mine.state;
    let known = Memo::new(move |_| {
        let mut map = HashMap::new();
        mine.others.with(|rows| {
            for r in rows {
                for s in &r.segments {
                    map.entry(s.2.clone()).or_insert_with(|| s.3.clone());
                }
            }
        });
        map
    });
    let fps = move || state.fps().max(f64::MIN_POSITIVE);
    let segments = move || {
        let w = state.window.get();
        let known = known.get();
        let fps = fps();
        mine.model.with(|m| {
            let spans: Vec<(usize, usize)> = m.spans().iter().map(|s| (s.start, s.end)).collect();
            visible_segments(&spans, &w, MAX_SEGMENTS)
                .into_iter()
                .map(|i| my_segment(mine, i, m.spans()[i].clone(), m.selected() == Some(i), &w, &known, fps))
                .collect_view()
        })
    };
    let handles = move || {
        let w = state.window.get();
        let active = mine.dragging.get();
        let frames = state.frames();
        mine.model.with(|m| {
            // the boundaries of the segments on screen only (a long take's row stays light)
            let spans: Vec<(usize, usize)> = m.spans().iter().map(|s| (s.start, s.end)).collect();
            let mut cuts: Vec<usize> = visible_segments(&spans, &w, MAX_SEGMENTS)
                .into_iter()
                .flat_map(|i| [spans[i].0, spans[i].1 + 1])
                .filter(|c| (*c as f64) >= w.start && (*c as f64) <= w.end)
                .collect();
            cuts.dedup();
            cuts.into_iter()
                .map(|cut| boundary_handle(mine, cut, frames, active == Some(cut), w.fraction(cut as f64)))
                .collect_view()
        })
    };
    let empty = move || mine.model.with(|m| m.spans().is_empty());
    let count = move || mine.model.with(|m| m.spans().len());
    // my segments' frames, for the Effort bars under the row (a new list only when they change)
    let my_spans =
        Memo::new(move |_| mine.model.with(|m| m.spans().iter().map(|s| (s.start, s.end)).collect::<Vec<_>>()));
    let effort_spans = Signal::derive(move || Arc::new(my_spans.get()));
    view! {
        <div class="ms-tl-line ms-tl-line--row ms-tl-line--mine" hidden=move || state.motion.with(Option::is_none)>
            <div class="ms-tl-label" title="My labels: your own segments, edited here">"My labels"</div>
            <div
                id="row-my-labels"
                class="ms-row ms-row--mine ms-tl-lane"
                node_ref=mine.lane
                data-segments=move || count().to_string()
                data-dragging=move || mine.dragging.get().is_some().to_string()
                role="group"
                aria-label="My labels"
                title="Click one of my segments to select it (the playhead goes where you click, nothing plays); drag a boundary to move it"
            >
                <span class="ms-my-empty" hidden=move || !empty()>
                    "No labels of mine yet: copy a row or start empty with the tools below the timeline"
                </span>
                {segments}
                {handles}
            </div>
        </div>
        <EffortLane state=state row_id=ROW.to_string() spans=effort_spans label=Signal::derive(|| "my labels".to_string())/>
    }
}
