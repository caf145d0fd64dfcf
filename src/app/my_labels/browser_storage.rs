//! My labels in the browser's local storage: restored for each take loaded, saved after every edit (a record
//! that cannot be read kept under its backup key first; a full storage offers the exports), and replaced when
//! another tab of the same take writes them. The stored form and its keys are [`super::stored`].

use crate::app::my_labels::edits::MyLabels as Model;
use crate::app::my_labels::row::{MyRow, Note};
use crate::app::my_labels::stored::{backup_key, fingerprint, storage_key};
use leptos::prelude::*;
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;

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
    #[wasm_bindgen(method, getter)]
    fn length(this: &WebStorage) -> u32;
    #[wasm_bindgen(method, catch)]
    fn key(this: &WebStorage, index: u32) -> Result<Option<String>, JsValue>;
}

/// My labels kept in this browser for the takes named `takes` (every take of one of those names, whatever its length
/// or motion: the keys tell them apart): (key, stored JSON), for a project file.
pub fn kept_labels(takes: &[String]) -> Vec<(String, String)> {
    let Ok(storage) = local_storage() else { return Vec::new() };
    let prefixes: Vec<String> =
        takes.iter().map(|t| format!("mocapseg.my-labels.v{}:{t}:", super::stored::VERSION)).collect();
    let keys: Vec<String> = (0..storage.length()).filter_map(|i| storage.key(i).ok().flatten()).collect();
    keys.into_iter()
        .filter(|k| prefixes.iter().any(|p| k.starts_with(p.as_str())))
        .filter_map(|k| storage.get_item(&k).ok().flatten().map(|v| (k, v)))
        .collect()
}

/// Keeps my labels `json` under `key` (from a project file; read back when their take is opened); why not.
pub fn keep_labels(key: &str, json: &str) -> Result<(), String> {
    local_storage()?.set_item(key, json).map_err(|e| describe(&e))
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

impl MyRow {
    /// Restores the stored labels of each take loaded (an effect; none loaded: no labels).
    pub(super) fn restore_each_take(self) {
        let (row, state) = (self, self.state);
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
            row.unsaved.set_value(false);
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
            Err(e) => {
                self.unsaved.set_value(true);
                return self.say(true, format!("My labels could not be saved in this browser: {e}"));
            }
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
        self.unsaved.set_value(saved.is_err());
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
        self.unsaved.set_value(true);
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
    /// (an edit here would otherwise overwrite them unseen) — unless this tab's labels are not stored (the browser
    /// refused their write): those are the user's only copy, and stay, with why and what to do.
    pub(super) fn from_other_tab(self) {
        let Some(key) = self.key.get_untracked() else { return };
        if self.unsaved.get_value() {
            return self.say(
                true,
                "Another tab changed my labels of this take, but these on screen were never saved (this browser's \
                 storage refused them): they are kept here, not replaced — export them (CSV or JSON) before you reload"
                    .into(),
            );
        }
        let frames = self.state.frames();
        self.drag.set_value(None);
        self.dragging.set(None);
        let (model, note, corrupt) = restore(&key, frames, true);
        self.corrupt.set_value(corrupt);
        self.model.set(model);
        self.note.set(note);
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
