//! The library of takes (issue 26): several files dropped or picked at once (or a folder, `#folder-input`)
//! become a list of takes in the side panel's "Library" tab (`#tab-library`, shown once the library
//! has a take). Each take (`#library-list li`, `data-status` = queued / running / done / failed /
//! cancelled) shows its name, duration and status; the worker segments them one after another with
//! the method chosen (`#library-method`) and its panel's parameters, `#library-cancel` drops the
//! rest, `#library-rerun` queues the failed and cancelled again. Clicking a take's name opens it
//! on screen as a dropped file opens (its `File` read again: takes not on screen keep their
//! segmentations, never their frames). `#library-export-csv` saves every take's labels as one label
//! CSV ([`crate::view::library::library_csv`]). The take on screen, when it is one of the
//! library's, shows its library segmentation as the timeline's row `#row-library` ("Library"),
//! its segments labelled by their clusters' names. The state is [`LibraryState`]; the worker's
//! side is `loader::library`; the decisions are [`crate::view::library`]'s.

use super::loader::Loader;
use super::method_panel::{SegmentRow, ACTION_LEVELS};
use super::motion_image::download;
use super::AppState;
use crate::protocol::{MethodView, RunId};
use crate::segment::Level;
use crate::view::library::{library_csv, ClusterNames, Playlist, Queue};
use leptos::prelude::*;
use std::sync::Arc;
use web_sys::File;

/// The library tab's id.
pub const TAB: &str = "library";

/// A take of the library as the page keeps it: its file (a handle, not its bytes) and, for an AMC
/// motion, its ASF skeleton's.
#[derive(Clone)]
pub struct Source {
    pub motion: File,
    pub skeleton: Option<File>,
}

/// The library's state (signals; cheap to copy).
#[derive(Clone, Copy)]
pub struct LibraryState {
    /// The takes and the worker's queue over them.
    pub queue: RwSignal<Queue>,
    /// Each take's files, in the queue's order.
    files: StoredValue<Vec<Source>, LocalStorage>,
    /// The method (registry name) the library's takes are segmented with.
    pub method: RwSignal<String>,
    /// The library's run in the worker: its run id and take.
    pub running: StoredValue<Option<(RunId, usize)>>,
    /// The library's clip export in the worker.
    pub clip_run: StoredValue<Option<RunId>>,
    /// The take of the library on screen (`None`: the take on screen is not one of the library's).
    pub open: RwSignal<Option<usize>>,
    /// The names the user gave the shared clusters.
    pub names: RwSignal<ClusterNames>,
    /// The cluster whose occurrences are playing.
    pub playlist: RwSignal<Option<Playlist>>,
    /// What the last export (or a refused file) did: (failed, message).
    pub status: RwSignal<Option<(bool, String)>>,
}

impl std::fmt::Debug for LibraryState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "LibraryState({} takes)", self.queue.with_untracked(|q| q.entries.len()))
    }
}

impl LibraryState {
    pub fn new() -> LibraryState {
        LibraryState {
            queue: RwSignal::new(Queue::default()),
            files: StoredValue::new_local(Vec::new()),
            method: RwSignal::new("sssm".into()),
            running: StoredValue::new(None),
            clip_run: StoredValue::new(None),
            open: RwSignal::new(None),
            names: RwSignal::new(ClusterNames::default()),
            playlist: RwSignal::new(None),
            status: RwSignal::new(None),
        }
    }

    /// Adds takes (their files), queued; returns their indices.
    pub fn add(&self, sources: Vec<Source>) -> std::ops::Range<usize> {
        let names: Vec<String> = sources.iter().map(|s| s.motion.name()).collect();
        self.files.update_value(|f| f.extend(sources));
        let mut added = 0..0;
        self.queue.update(|q| added = q.add(names));
        added
    }

    /// Take `i`'s files.
    pub fn source(&self, i: usize) -> Option<Source> {
        self.files.with_value(|f| f.get(i).cloned())
    }

    /// Whether the library has a take (its tab is shown).
    pub fn shown(&self) -> bool {
        self.queue.with(|q| !q.entries.is_empty())
    }

    /// Take `i`'s segmentation, its clusters' segments labelled by their names.
    fn labelled(&self, i: usize) -> Option<crate::segment::Segmentation> {
        let names = self.names.get();
        self.queue.with(|q| q.entries.get(i).and_then(|e| e.segmentation.as_ref()).map(|s| names.label(s)))
    }
}

impl Default for LibraryState {
    fn default() -> Self {
        LibraryState::new()
    }
}

/// The methods a library may segment with: those that need no model.
fn methods(state: AppState) -> Vec<(String, String)> {
    state
        .methods
        .iter()
        .filter(|s| s.supervised.is_none())
        .map(|s| (s.info.name.clone(), s.info.short.clone()))
        .collect()
}

/// `#tabpanel-library`'s content: the list, the queue's controls and the exports.
#[component]
pub fn LibraryPanel(state: AppState, loader: Loader) -> impl IntoView {
    let library = state.library;
    let busy = move || library.queue.with(Queue::busy);
    let rerunnable =
        move || library.queue.with(|q| q.entries.iter().any(|e| matches!(e.status.word(), "failed" | "cancelled")));
    let segmented = move || library.queue.with(|q| !q.segmented().is_empty());
    let cancel = {
        let loader = loader.clone();
        move |_| loader.cancel_library()
    };
    let rerun = {
        let loader = loader.clone();
        move |_| loader.rerun_library()
    };
    let export_csv = move |_| {
        let names = library.names.get_untracked();
        let labelled: Vec<_> =
            library.queue.with_untracked(|q| q.segmented().into_iter().map(|(_, s)| names.label(s)).collect());
        let csv = library_csv(&labelled);
        let rows = csv.lines().count().saturating_sub(1);
        let file = "library_labels.csv";
        library.status.set(Some(match download(csv.as_bytes(), "text/csv", file) {
            Ok(()) => (false, format!("saved {file} ({rows} rows of {})", crate::method::counted(labelled.len(), "take"))),
            Err(e) => (true, format!("could not save {file}: {}", super::js_message(&e))),
        }));
    };
    let options = methods(state)
        .into_iter()
        .map(|(name, short)| view! { <option value=name.clone() selected=move || library.method.get() == name>{short}</option> })
        .collect_view();
    let loader = StoredValue::new_local(loader);
    let takes = move || {
        let open = library.open.get();
        library.queue.with(|q| {
            q.entries
                .iter()
                .enumerate()
                .map(|(i, e)| {
                    let duration = e.duration_s.map(|d| format!("{d:.1} s")).unwrap_or_default();
                    let failed = matches!(e.status.word(), "failed");
                    view! {
                        <li
                            class="ms-lib-take"
                            class:ms-lib-take--open=open == Some(i)
                            data-status=e.status.word()
                            data-index=i.to_string()
                            aria-current=(open == Some(i)).then_some("true")
                        >
                            <button
                                class="ms-lib-open"
                                type="button"
                                title="Open this take"
                                on:click=move |_| loader.with_value(|l| l.open_library_take(i))
                            >
                                {e.name.clone()}
                            </button>
                            <span class="ms-lib-duration">{duration}</span>
                            <span class="ms-lib-status" class:ms-lib-status--failed=failed role=failed.then_some("alert")>
                                {e.status.text()}
                            </span>
                        </li>
                    }
                })
                .collect_view()
        })
    };
    view! {
        <section class="ms-library" aria-label="Library of takes">
            <p id="library-summary" class="ms-lib-summary" aria-live="polite">{move || library.queue.with(Queue::summary)}</p>
            <div class="ms-lib-controls">
                <label>
                    "Segment with "
                    <select id="library-method" on:change=move |ev| library.method.set(event_target_value(&ev))>
                        {options}
                    </select>
                </label>
                <button id="library-cancel" class="ms-button ms-button--small" type="button" disabled=move || !busy() on:click=cancel>
                    "Cancel"
                </button>
                <button id="library-rerun" class="ms-button ms-button--small ms-button--quiet" type="button" disabled=move || busy() || !rerunnable() on:click=rerun>
                    "Run again"
                </button>
                <button id="library-export-csv" class="ms-button ms-button--small" type="button" disabled=move || !segmented() on:click=export_csv>
                    "Labels CSV (all takes)"
                </button>
            </div>
            <p
                id="library-status"
                class="ms-lib-note"
                class:ms-lib-note--failed=move || library.status.with(|s| s.as_ref().is_some_and(|(f, _)| *f))
                hidden=move || library.status.with(Option::is_none)
            >
                {move || library.status.with(|s| s.as_ref().map(|(_, m)| m.clone()))}
            </p>
            <ol id="library-list" class="ms-lib-list">{takes}</ol>
        </section>
    }
}

/// The timeline's `#row-library`: the library's segmentation of the take on screen, when it is one
/// of the library's, its segments labelled by their clusters' names.
#[component]
pub fn LibraryRow(state: AppState) -> impl IntoView {
    let library = state.library;
    let source = Signal::derive(move || {
        let i = library.open.get()?;
        let segmentation = library.labelled(i)?;
        // the take on screen must be that take (a load still under way shows nothing)
        let frames = state.motion.with(|m| m.as_ref().map(|m| m.summary.frames))?;
        (frames == segmentation.frames).then(|| {
            Arc::new(MethodView { method: segmentation.method.clone(), segmentation, details: Default::default() })
        })
    });
    let label = Signal::derive(|| "Library".to_string());
    let tip = Signal::derive(|| "The library's segmentation of this take, its clusters named".to_string());
    view! { <SegmentRow state=state row_id="library".to_string() source=source levels=LEVELS label=label tip=tip/> }
}

/// The levels the library's row shows.
const LEVELS: &[Level] = ACTION_LEVELS;
