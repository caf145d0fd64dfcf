//! A row's exports, for the rows that are not a method's run ("my labels", the ground truth): the
//! row as segmentation JSON (`#<id>-export-json`; each segment with the `effort` the Effort bars
//! computed for it, when they did: [`crate::app::effort::bars`]), as the label CSV `file,start_frame,end_frame,label`
//! (`#<id>-export-csv`), and each of its labelled segments (its actions: an unlabelled stretch of
//! "my labels" is a transition) as a BVH clip cut from the file on screen, in one
//! zip (`#<id>-export-clips`, cut by the worker: [`ClipJobs::export_clips_of`]), or the segment
//! selected on the row (its timeline row's id starts with `<id>`) alone as a BVH
//! (`#<id>-export-clip`); `#<id>-export-origin` starts each clip at the origin facing +Z.
//! `#<id>-export-status` says what was saved or why not. The buttons are disabled while the row
//! is empty. A method's panel has its own exports (choosing actions or primitives):
//! `method_panel::Exports`.

use crate::app::player::motion_image::{download, stem};
use crate::app::state::AppState;
use crate::app::timeline::clip_jobs::ClipJobs;
use crate::clips::Which;
use crate::labels::{from_segmentation, to_csv};
use crate::segment::Segmentation;
use leptos::prelude::*;
use std::sync::Arc;

/// The export buttons of a row whose segmentation `row` holds (`None`: nothing to save). `id` is
/// the prefix of the elements' ids and of the files' names (`<take>_<id>.json`); `what` names the
/// row in the buttons' labels ("my labels", "the ground truth").
#[component]
pub fn RowExports(
    state: AppState,
    id: &'static str,
    what: &'static str,
    row: Signal<Option<Arc<Segmentation>>>,
) -> impl IntoView {
    let status = RwSignal::new(None::<(bool, String)>);
    let origin = RwSignal::new(false);
    let empty = move || row.with(|r| r.as_ref().is_none_or(|s| s.segments.is_empty()));
    let save = move |bytes: &[u8], mime: &str, file: String, rows: Option<usize>| {
        status.set(Some(match download(bytes, mime, &file) {
            Ok(()) => (false, rows.map_or_else(|| format!("saved {file}"), |n| format!("saved {file} ({n} rows)"))),
            Err(e) => (true, format!("could not save {file}: {e:?}")),
        }));
    };
    let on_json = move |_| {
        if let Some(seg) = row.get_untracked() {
            // with the Effort the bars under the rows computed for its segments
            let seg = state.effort.fill(state, &seg);
            save(seg.to_json().as_bytes(), "application/json", format!("{}_{id}.json", stem(&seg.file)), None);
        }
    };
    let on_csv = move |_| {
        if let Some(seg) = row.get_untracked() {
            let rows = from_segmentation(&seg, Which::Actions);
            if rows.is_empty() {
                return status.set(Some((true, "no labelled segments to save".into())));
            }
            let file = format!("{}_{id}.csv", stem(&seg.file));
            if let Err(e) = download(to_csv(&rows).as_bytes(), "text/csv", &file) {
                return status.set(Some((true, format!("could not save {file}: {e:?}"))));
            }
            // the CSV counts frames from 0 (as mocapseg reads label CSVs), the page from 1: said at every export
            let said = format!(
                "saved {file} ({} rows; its frames count from 0 — frame 1 on the page is 0 in the file)",
                rows.len()
            );
            status.set(Some((false, said)));
        }
    };
    let loader = use_context::<StoredValue<ClipJobs, LocalStorage>>();
    let cut = move |which: Which, only: Option<(usize, usize)>| match (row.get_untracked(), loader) {
        (Some(seg), Some(loader)) => {
            loader.with_value(|l| l.export_clips_of(&seg, id, which, origin.get_untracked(), only, status))
        }
        _ => status.set(Some((true, "nothing to cut".into()))),
    };
    let on_clips = move |_| cut(Which::Actions, None);
    // the segment selected on this row, if it is one of the row's
    let selected = move || {
        let picked = state.selected.with(|s| s.as_ref().filter(|s| s.row.starts_with(id)).map(|s| (s.start, s.end)))?;
        row.with(|r| r.as_ref().is_some_and(|r| r.segments.iter().any(|s| (s.start, s.end) == picked)))
            .then_some(picked)
    };
    let on_clip = move |_| {
        if let Some(picked) = selected() {
            cut(Which::All, Some(picked));
        }
    };
    view! {
        <div class="ms-my-group ms-row-exports" role="group" aria-label=format!("Export {what}")>
            <button id=format!("{id}-export-json") class="ms-button ms-button--quiet" type="button"
                aria-label=format!("Save {what} as segmentation JSON") disabled=empty on:click=on_json>"JSON"</button>
            <button id=format!("{id}-export-csv") class="ms-button ms-button--quiet" type="button"
                aria-label=format!("Save {what} as a label CSV")
                title="A label CSV: file,start_frame,end_frame,label — its frames count from 0 (frame 1 on the page is 0 in the file)"
                disabled=empty on:click=on_csv>"CSV"</button>
            <button id=format!("{id}-export-clips") class="ms-button ms-button--quiet" type="button"
                aria-label=format!("Save each segment of {what} as its own BVH clip, in one zip")
                title="Each segment as its own BVH clip cut from the original file, in one zip"
                disabled=empty on:click=on_clips>"BVH clips (zip)"</button>
            <button id=format!("{id}-export-clip") class="ms-button ms-button--quiet" type="button"
                aria-label=format!("Save the segment selected on the row of {what} as a BVH clip")
                title="Select a segment of this row on the timeline to save it alone"
                disabled=move || selected().is_none() on:click=on_clip>"Selected segment as BVH"</button>
            <label class="ms-exports-field">
                <input id=format!("{id}-export-origin") type="checkbox"
                    aria-label=format!("Clips of {what} start at the origin facing +Z")
                    prop:checked=move || origin.get()
                    on:change=move |ev| origin.set(event_target_checked(&ev))/>
                " clips start at the origin facing +Z"
            </label>
            <span id=format!("{id}-export-status") class="ms-exports-status"
                class:ms-exports-status--error=move || status.get().is_some_and(|(e, _)| e)
                role="status" aria-live="polite">
                {move || status.get().map(|(_, m)| m).unwrap_or_default()}
            </span>
        </div>
    }
}
