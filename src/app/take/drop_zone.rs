//! Where files come in: drag-and-drop on `#drop-zone`, the file picker `#file-input`, and the
//! `#load-sample` button (the bundled sample, also loaded on start). A BVH comes alone; a CMU
//! original comes as its ASF skeleton and AMC motion, dropped or picked together
//! ([`crate::load::opening`]). Several takes dropped or picked at once, or a folder picked with
//! `#folder-input`, make the library of takes ([`crate::app::library::panel`]).

use crate::app::library::library_jobs::LibraryJobs;
use crate::app::loader::Loader;
use crate::app::state::AppState;
use leptos::ev::{DragEvent, Event};
use leptos::prelude::*;
use wasm_bindgen::JsCast;
use web_sys::{File, FileList, HtmlInputElement};

#[component]
pub fn DropZone(state: AppState, loader: Loader, library: LibraryJobs) -> impl IntoView {
    // dragenter/dragleave also fire for the zone's children: count them to know when the
    // pointer really left.
    let depth = RwSignal::new(0i32);
    let loading = move || matches!(state.load.get(), crate::app::state::LoadState::Loading { .. });

    let on_drop = {
        let library = library.clone();
        move |ev: DragEvent| {
            ev.prevent_default();
            depth.set(0);
            let files = all_files(ev.data_transfer().and_then(|d| d.files()));
            if !files.is_empty() {
                library.open_dropped(files);
            }
        }
    };
    let on_pick = {
        let library = library.clone();
        move |ev: Event| {
            let Some(input) = ev.target().and_then(|t| t.dyn_into::<HtmlInputElement>().ok()) else {
                return;
            };
            let files = all_files(input.files());
            if !files.is_empty() {
                library.open_dropped(files);
            }
            // Picking the same file again must load it again.
            input.set_value("");
        }
    };
    let on_sample = move |_| loader.load_sample();
    // a picker of folders (every browser the page supports has `webkitdirectory`; leptos has no
    // attribute of that name)
    let folder = NodeRef::<leptos::html::Input>::new();
    Effect::new(move |_| {
        if let Some(input) = folder.get() {
            let _ = input.set_attribute("webkitdirectory", "");
        }
    });

    view! {
        <div
            id="drop-zone"
            class="ms-drop-zone"
            class:ms-drop-zone--over={move || depth.get() > 0}
            aria-busy=move || loading().to_string()
            on:dragenter=move |ev: DragEvent| {
                ev.prevent_default();
                depth.update(|d| *d += 1);
            }
            on:dragover=move |ev: DragEvent| {
                ev.prevent_default();
                if let Some(transfer) = ev.data_transfer() {
                    transfer.set_drop_effect("copy");
                }
            }
            on:dragleave=move |_| depth.update(|d| *d = (*d - 1).max(0))
            on:drop=on_drop
        >
            <p class="ms-drop-hint">
                "Drop a " <code>".bvh"</code> " motion-capture file here — or a CMU " <code>".asf"</code>
                " skeleton with its " <code>".amc"</code> " motion, both at once — or"
            </p>
            <div class="ms-drop-actions">
                <label class="ms-button" for="file-input">"Choose a file…"</label>
                <input
                    id="file-input"
                    class="ms-visually-hidden"
                    type="file"
                    accept=".bvh,.BVH,.asf,.ASF,.amc,.AMC"
                    multiple=true
                    aria-label="Choose a BVH file, or an ASF and its AMC file"
                    on:change=on_pick.clone()
                />
                <label class="ms-button ms-button--quiet" for="folder-input">"Choose a folder…"</label>
                <input
                    id="folder-input"
                    class="ms-visually-hidden"
                    type="file"
                    multiple=true
                    node_ref=folder
                    aria-label="Choose a folder of takes (a library)"
                    on:change=on_pick
                />
                <button id="load-sample" class="ms-button ms-button--quiet" type="button" on:click=on_sample>
                    "Load sample"
                </button>
            </div>
        </div>
    }
}

fn all_files(files: Option<FileList>) -> Vec<File> {
    files.map(|f| (0..f.length()).filter_map(|i| f.get(i)).collect()).unwrap_or_default()
}
