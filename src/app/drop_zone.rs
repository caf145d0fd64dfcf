//! Where files come in: drag-and-drop on `#drop-zone`, the file picker `#file-input`, and the
//! `#load-sample` button (the bundled sample, also loaded on start).

use super::loader::Loader;
use super::AppState;
use leptos::ev::{DragEvent, Event};
use leptos::prelude::*;
use wasm_bindgen::JsCast;
use web_sys::{File, FileList, HtmlInputElement};

#[component]
pub fn DropZone(state: AppState, loader: Loader) -> impl IntoView {
    // dragenter/dragleave also fire for the zone's children: count them to know when the
    // pointer really left.
    let depth = RwSignal::new(0i32);
    let loading = move || matches!(state.load.get(), super::LoadState::Loading { .. });

    let on_drop = {
        let loader = loader.clone();
        move |ev: DragEvent| {
            ev.prevent_default();
            depth.set(0);
            if let Some(file) = first_file(ev.data_transfer().and_then(|d| d.files())) {
                loader.load_file(file);
            }
        }
    };
    let on_pick = {
        let loader = loader.clone();
        move |ev: Event| {
            let Some(input) = ev.target().and_then(|t| t.dyn_into::<HtmlInputElement>().ok()) else {
                return;
            };
            if let Some(file) = first_file(input.files()) {
                loader.load_file(file);
            }
            // Picking the same file again must load it again.
            input.set_value("");
        }
    };
    let on_sample = move |_| loader.load_sample();

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
            <p class="ms-drop-hint">"Drop a " <code>".bvh"</code> " motion-capture file here, or"</p>
            <div class="ms-drop-actions">
                <label class="ms-button" for="file-input">"Choose a file…"</label>
                <input
                    id="file-input"
                    class="ms-visually-hidden"
                    type="file"
                    accept=".bvh,.BVH"
                    on:change=on_pick
                />
                <button id="load-sample" class="ms-button ms-button--quiet" type="button" on:click=on_sample>
                    "Load sample"
                </button>
            </div>
        </div>
    }
}

fn first_file(files: Option<FileList>) -> Option<File> {
    files.and_then(|f| f.get(0))
}
