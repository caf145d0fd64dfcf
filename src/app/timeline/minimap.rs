//! The timeline's minimap: the whole take's motion image, the window shown on it and the playhead.

use crate::app::player::motion_image::Chunks;
use crate::app::state::AppState;
use crate::app::timeline::lanes::lane_box;
use crate::app::timeline::window::Window;
use leptos::ev::PointerEvent;
use leptos::html::{Canvas, Div};
use leptos::prelude::*;
use wasm_bindgen::JsCast;
use web_sys::Element;

/// The minimap: the whole take's image, the window on it and the playhead; pressing centres the window there
/// (unless on the window itself), dragging moves it.
#[component]
pub fn Minimap(state: AppState, chunks: Chunks, resized: RwSignal<u32>) -> impl IntoView {
    let minimap_ref = NodeRef::<Div>::new();
    let minimap_canvas = NodeRef::<Canvas>::new();
    let frames = move || state.frames();
    let window = move || state.window.get();
    {
        let chunks = chunks.clone();
        Effect::new(move |_| {
            resized.track();
            let frames = state.frames();
            let Some(canvas) = minimap_canvas.get() else { return };
            if let Err(e) = chunks.draw(&canvas, &Window::full(frames)) {
                web_sys::console::error_2(&"minimap: could not draw".into(), &e);
            }
        });
    }
    let minimap_drag = StoredValue::new(None::<(f64, Window)>);
    let on_minimap_down = move |ev: PointerEvent| {
        let Some((left, width)) = lane_box(&minimap_ref) else { return };
        let total = frames().max(1) as f64;
        let at = (ev.client_x() as f64 - left) / width * total;
        let w = state.window.get_untracked();
        let w = if at >= w.start && at <= w.end { w } else { w.centred_on(at, frames()) };
        state.window.set(w);
        minimap_drag.set_value(Some((ev.client_x() as f64, w)));
        if let Some(el) = ev.current_target().and_then(|t| t.dyn_into::<Element>().ok()) {
            let _ = el.set_pointer_capture(ev.pointer_id());
        }
    };
    let on_minimap_move = move |ev: PointerEvent| {
        if let (Some((x0, w0)), Some((_, width))) = (minimap_drag.get_value(), lane_box(&minimap_ref)) {
            let delta = (ev.client_x() as f64 - x0) / width * frames().max(1) as f64;
            state.window.set(w0.panned(delta, frames()));
        }
    };
    let on_minimap_up = move |_: PointerEvent| minimap_drag.set_value(None);
    let minimap_left = move || format!("{:.4}%", window().start / frames().max(1) as f64 * 100.0);
    let minimap_width = move || format!("{:.4}%", window().span() / frames().max(1) as f64 * 100.0);
    view! {
        <div class="ms-tl-line ms-tl-line--minimap">
            <div class="ms-tl-label">"Whole take"</div>
            <div
                id="timeline-minimap"
                class="ms-tl-lane ms-minimap"
                node_ref=minimap_ref
                aria-label="Minimap of the whole take: drag the window to pan"
                on:pointerdown=on_minimap_down
                on:pointermove=on_minimap_move
                on:pointerup=on_minimap_up
                on:pointercancel=on_minimap_up
            >
                <canvas id="minimap-canvas" class="ms-minimap-canvas" node_ref=minimap_canvas aria-hidden="true"></canvas>
                <div id="minimap-window" class="ms-minimap-window" style:left=minimap_left style:width=minimap_width></div>
                <div
                    class="ms-minimap-playhead"
                    style:left=move || format!("{:.4}%", (state.frame.get() as f64 + 0.5) / frames().max(1) as f64 * 100.0)
                ></div>
            </div>
        </div>
    }
}
