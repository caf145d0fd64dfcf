//! The timeline's controls: zoom, fit, loop, the keyboard help, the Effort bars, the PNG and the legend.

use crate::app::effort::bars::EffortToggle;
use crate::app::player::motion_image::DownloadPng;
use crate::app::state::AppState;
use crate::app::take::first_visit::Legend;
use crate::app::timeline::lanes::KEY_ZOOM;
use crate::app::timeline::window::Window;
use leptos::prelude::*;

/// The timeline's controls: zoom, fit, loop, the keyboard help, the Effort bars, the PNG and the legend.
#[component]
pub fn TimelineTools(state: AppState) -> impl IntoView {
    let frames = move || state.frames();
    let window = move || state.window.get();
    let zoom_by = move |factor: f64| {
        let anchor = state.frame.get_untracked() as f64 + 0.5;
        state.window.update(|w| *w = w.zoomed(factor, anchor, state.frames()));
    };
    view! {
        <div class="ms-timeline-tools" role="group" aria-label="Timeline controls">
            <button id="zoom-out" class="ms-button ms-button--quiet" type="button" aria-label="Zoom out (−)" title="Zoom out (−)"
                disabled=move || frames() == 0 on:click=move |_| zoom_by(1.0 / KEY_ZOOM)>"−"</button>
            <button id="zoom-in" class="ms-button ms-button--quiet" type="button" aria-label="Zoom in (+)" title="Zoom in (+)"
                disabled=move || frames() == 0 on:click=move |_| zoom_by(KEY_ZOOM)>"+"</button>
            <button id="zoom-fit" class="ms-button ms-button--quiet" type="button" aria-label="Show the whole take" title="Show the whole take"
                disabled=move || frames() == 0 || window().is_full(frames())
                on:click=move |_| state.window.set(Window::full(state.frames()))>"Fit"</button>
            <button
                id="loop-toggle"
                class="ms-button ms-button--quiet ms-toggle"
                type="button"
                aria-pressed=move || state.looping.get().to_string()
                title="Loop the selected segment's playback"
                disabled=move || state.selected.with(Option::is_none)
                on:click=move |_| {
                    state.looping.update(|l| *l = !*l);
                    state.play_until.set(None);
                }
            >
                "Loop"
            </button>
            <button id="help-button" class="ms-button ms-button--quiet" type="button" aria-label="Keyboard shortcuts (?)"
                aria-expanded=move || state.help.get().to_string() on:click=move |_| state.help.update(|h| *h = !*h)>"?"</button>
            <EffortToggle state=state/>
            <DownloadPng state=state/>
            <Legend/>
        </div>
    }
}
