//! `#timeline`: the shared time axis under the player. The motion image spans its width; rows
//! for segmentations (later issues) go under it in `#timeline-rows`; `#playhead` marks the
//! current frame across all of them and follows playback. Clicking or dragging seeks.

use super::method_panel::MethodRows;
use super::motion_image::{DownloadPng, MotionImageCanvas};
use super::AppState;
use leptos::ev::PointerEvent;
use leptos::prelude::*;
use wasm_bindgen::JsCast;
use web_sys::Element;

#[component]
pub fn Timeline(state: AppState) -> impl IntoView {
    let seeking = StoredValue::new(false);
    let seek = move |ev: &PointerEvent| {
        let Some(track) = ev.current_target().and_then(|t| t.dyn_into::<Element>().ok()) else {
            return;
        };
        let rect = track.get_bounding_client_rect();
        let frames = state.frames();
        if frames > 0 && rect.width() > 0.0 {
            let fraction = (ev.client_x() as f64 - rect.left()) / rect.width();
            state.frame.set(((fraction * frames as f64).floor().max(0.0) as usize).min(frames - 1));
        }
    };
    let on_down = move |ev: PointerEvent| {
        seeking.set_value(true);
        if let Some(track) = ev.current_target().and_then(|t| t.dyn_into::<Element>().ok()) {
            let _ = track.set_pointer_capture(ev.pointer_id());
        }
        seek(&ev);
    };
    let on_move = move |ev: PointerEvent| {
        if seeking.get_value() {
            seek(&ev);
        }
    };
    let on_up = move |_: PointerEvent| seeking.set_value(false);
    // Centre of the current frame's column, as a percentage of the track.
    let playhead_left = move || {
        let frames = state.frames().max(1) as f64;
        format!("{:.4}%", (state.frame.get() as f64 + 0.5) / frames * 100.0)
    };

    view! {
        <section id="timeline" class="ms-timeline" aria-label="Timeline">
            <div class="ms-timeline-head">
                <h2>"Motion image"</h2>
                <span class="ms-timeline-legend">"rows = joints · columns = frames · colour = XYZ relative to the root"</span>
                <DownloadPng state=state/>
            </div>
            <div
                class="ms-timeline-track"
                on:pointerdown=on_down
                on:pointermove=on_move
                on:pointerup=on_up
                on:pointercancel=on_up
            >
                <MotionImageCanvas state=state/>
                // Segmentation rows, one per level of each method.
                <div id="timeline-rows" class="ms-timeline-rows">
                    <MethodRows state=state/>
                </div>
                <div id="playhead" class="ms-playhead" style:left=playhead_left hidden=move || state.frames() == 0></div>
            </div>
        </section>
    }
}
