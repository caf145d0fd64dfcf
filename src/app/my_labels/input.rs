//! The pointer and the keys on my labels' row: a boundary grabbed and dragged (the drag follows the pointer
//! anywhere on the page, snapping to the other rows' cuts), a focused boundary nudged with ← / →, the row's keys
//! ([`SHORTCUTS`]), and the page-wide listener for another tab's writes.

use crate::app::my_labels::row::{Drag, MyRow};
use crate::app::my_labels::snap::{cuts_of, snap, snap_reach};
use crate::app::my_labels::vocabulary::hotkey_label;
use crate::app::timeline::keys::is_for_the_field;
use gloo::events::EventListener;
use leptos::ev::{KeyboardEvent, PointerEvent};
use leptos::prelude::*;
use wasm_bindgen::JsCast;

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
        "move it (the pose follows); it snaps to the other rows' boundaries within 8 px (3 frames at most) unless \
         Alt or Shift is held or Snap is off, and rolls over a neighbour, removing it once dragged across it",
    ),
    ("Tab to a boundary of my labels, ← / →", "move it one frame (with Shift: one second)"),
];

impl MyRow {
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
        let tolerance = snap_reach(self.state.window.get_untracked().span(), width);
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
            // snapping off: the row's toggle, or Alt (or Shift) held while dragging
            let snapping = self.snapping.get_untracked() && !ev.alt_key() && !ev.shift_key();
            let to = snap(at, &drag.targets, if snapping { drag.tolerance } else { 0.0 });
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
