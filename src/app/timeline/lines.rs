//! `#timeline`: the studio's one time axis under the player. Every line has its label at the left
//! and its lane on the same x range: the time ruler (`#timeline-ruler`, seconds with a step chosen
//! for the zoom), the motion image, one row per method and level (`#row-<method>-actions`,
//! `#row-<method>-primitives`, from [`MethodRows`]), the consensus row (`#row-consensus`, [`crate::app::consensus::row`]),
//! my labels' row and, under them, the minimap of the whole take
//! (`#timeline-minimap`, its window `#minimap-window`). `#playhead` marks the current frame across
//! the lanes; `#time-readout` says `mm:ss.fff · frame N / total`.
//!
//! All lanes show the frames of `state.window` (`data-window-start`/`-end` on `#timeline`):
//! Ctrl/⌘+wheel zooms around the pointer, Shift+wheel or a sideways wheel pans, dragging the ruler
//! or the minimap's window pans, +/− zoom around the playhead, and a frame that leaves the window
//! (playback, keys) brings the window along. Clicking or dragging an empty lane seeks (and drops the
//! selection); clicking a segment selects it and plays it, looped while `#loop-toggle` is on.
//! Hovering shows `#timeline-tooltip` (a segment's label, frames and seconds, its Effort bars'
//! text, or the frame under the pointer). `#effort-toggle` shows the Effort bars under every row
//! ([`crate::app::effort::bars`]). The keyboard ([`crate::app::timeline::window::key_action`]) works anywhere on the page except
//! in text fields; `?` opens `#help-overlay`. The maths is in [`crate::app::timeline::window`].

use crate::app::consensus::row::{ConsensusLane, ConsensusRow, ConsensusTools};
use crate::app::effort::bars::EffortLegend;
use crate::app::my_labels::lane::MyLabelsRow;
use crate::app::my_labels::row::MyRow;
use crate::app::my_labels::tools::MyLabelsTools;
use crate::app::player::motion_image::{Chunks, MotionImageCanvas};
use crate::app::state::AppState;
use crate::app::state::Selection;
use crate::app::timeline::keys::is_for_the_field;
use crate::app::timeline::lanes::{lane_box, lane_px, KEY_ZOOM};
use crate::app::timeline::method_rows::{row_spans, MethodRows};
use crate::app::timeline::minimap::Minimap;
use crate::app::timeline::segment_menu::SegmentMenu;
use crate::app::timeline::tools::TimelineTools;
use crate::app::timeline::window::{key_action, readout, shuttle, stepped, ticks, KeyAction, Modifiers, Window};
use crate::app::truth::ground_truth::TruthRow;
use gloo::events::{EventListener, EventListenerOptions};
use leptos::ev::{KeyboardEvent, PointerEvent};
use leptos::html::Div;
use leptos::prelude::*;
use wasm_bindgen::JsCast;
use web_sys::{Element, WheelEvent};

/// Width of the lines' label column, in CSS pixels (also in `www/style.css`, `.ms-tl-line`).
pub const LABEL_PX: f64 = 132.0;

/// Ruler ticks at least this far apart, in CSS pixels.
const TICK_MIN_PX: f64 = 70.0;

/// Shortcuts shown in the help overlay (keys, what they do).
pub const SHORTCUTS: [(&str, &str); 15] = [
    ("Space", "play / pause"),
    ("← / →", "one frame back / forward"),
    ("Shift + ← / →", "one second back / forward"),
    ("J / K / L", "play backwards / pause / play forwards — press J or L again for 2×, 4×, 8×"),
    ("Home / End", "first / last frame"),
    ("+ / −", "zoom in / out around the playhead"),
    ("[ / ]", "previous / next boundary from the playhead on the selected row (else the first row), brought into view"),
    ("Ctrl or ⌘ + wheel", "zoom around the pointer"),
    ("Shift + wheel, sideways wheel", "pan"),
    ("Drag the ruler or the minimap", "pan"),
    (
        "Tab to a row's segment, Enter or Space",
        "select it and play it (Tab reaches one segment per row: the selected one, else the first in view)",
    ),
    (
        "Shift + F10, the context-menu key",
        "the selected segment's menu: play it, export its clip, copy it to my labels, show its panel",
    ),
    ("Loop (the button above the rows)", "on: a selected segment's playback repeats; off: it plays once"),
    ("?", "show / hide this help"),
    ("Esc", "close this help, else drop the selected segment"),
];

#[wasm_bindgen::prelude::wasm_bindgen]
extern "C" {
    /// The browser's `ResizeObserver`, bound here rather than through a web-sys feature the crate
    /// does not turn on.
    type ResizeObserver;
    #[wasm_bindgen::prelude::wasm_bindgen(constructor)]
    fn new(callback: &js_sys::Function) -> ResizeObserver;
    #[wasm_bindgen::prelude::wasm_bindgen(method)]
    fn observe(this: &ResizeObserver, target: &Element);
}

/// The CSS `left` of frame position `x` across the lanes (which start after the label column).
fn lane_left(fraction: f64) -> String {
    format!("calc({LABEL_PX}px + (100% - {LABEL_PX}px) * {fraction:.6})")
}

#[component]
pub fn Timeline(state: AppState) -> impl IntoView {
    let ruler_ref = NodeRef::<Div>::new();
    let body_ref = NodeRef::<Div>::new();
    let chunks = Chunks::default();
    // bumped on window resize and when a take's image is cut into chunks: lanes redraw
    let resized = RwSignal::new(0u32);
    let hover = RwSignal::new(None::<(f64, f64, String)>);
    // the tooltip follows the pointer, not the content: any scroll (the timeline's, the page's) hides it
    EventListener::new_with_options(
        &gloo::utils::window(),
        "scroll",
        EventListenerOptions::run_in_capture_phase(),
        move |_| hover.set(None),
    )
    .forget();

    new_take(state, &chunks, resized);

    let frames = move || state.frames();
    let window = move || state.window.get();

    listen_wheel(state, body_ref, ruler_ref, resized);

    let rows_ref = NodeRef::<Div>::new();
    let mine = MyRow::new(state); // first: its keys ([ ] on my row) before the timeline's
    let agreed = ConsensusRow::new(state, mine);
    keyboard(state);

    measure_lanes(ruler_ref);

    let playhead_fraction = move || {
        let w = window();
        w.fraction(state.frame.get() as f64 + 0.5)
    };
    let playhead_hidden = move || frames() == 0 || !(0.0..=1.0).contains(&playhead_fraction());
    let rate = move || match state.shuttle.get() {
        0 => String::new(),
        r if r < 0 => format!("◀ {}×", -r),
        r => format!("▶ {r}×"),
    };

    // The rows and the tools below them are type-erased (`into_any`): as one static view type the timeline's
    // drop glue got a symbol name over 100,000 bytes, which rustc's LTO cannot read back from the library's wasm
    // object ("failed to get bitcode from object file for LTO (Invalid Wasm linking symbol)"), so the wasm test
    // binary did not link. `scripts/wasm-symbols.py` (run by `make web`) watches that length.
    // embedded: no editing of my labels (nothing made there is kept)
    let full = !crate::app::dom::embedded();
    let rows = view! {
        <div id="timeline-rows" class="ms-timeline-rows" node_ref=rows_ref>
            <TruthRow state=state/>
            <MethodRows state=state/>
            <ConsensusLane row=agreed/>
            // the user's own rows, pinned at the bottom of the timeline while the methods' rows scroll (issue 48)
            <div id="timeline-mine" class="ms-tl-mine">
                {full.then(|| view! { <MyLabelsRow mine=mine/> })}
                <crate::app::library::panel::LibraryRow state=state/>
                <crate::app::library::panel::TransferredRow state=state/>
            </div>
        </div>
    }
    .into_any();
    let row_tools = view! {
        {full.then(|| view! { <ConsensusTools row=agreed/> })}
        {full.then(|| view! { <MyLabelsTools mine=mine/> })}
    }
    .into_any();
    let overlays = view! {
        <HelpOverlay state=state/>
        <SegmentMenu state=state mine=mine rows=rows_ref/>
    }
    .into_any();
    view! {
        <section
            id="timeline"
            class="ms-timeline"
            aria-label="Timeline"
            data-window-start=move || format!("{:.3}", window().start)
            data-window-end=move || format!("{:.3}", window().end)
        >
            <div class="ms-timeline-head">
                <h2>"Timeline"</h2>
                <output id="time-readout" class="ms-readout" aria-live="off" aria-label="Current time and frame">
                    {move || readout(state.frame.get(), frames(), state.fps())}
                </output>
                <span id="shuttle-rate" class="ms-readout-rate">{rate}</span>
                <span class="ms-timeline-legend ms-timeline-legend--image">"motion image: rows = joints · columns = frames · colour = XYZ relative to the root"</span>
                <TimelineTools state=state/>
            </div>
            <EffortLegend state=state/>
            <div
                class="ms-tl"
                node_ref=body_ref
                on:pointerleave=move |_| hover.set(None)
            >
                <Ruler state=state ruler_ref=ruler_ref hover=hover resized=resized/>
                <TimelineBody state=state ruler_ref=ruler_ref hover=hover chunks=chunks.clone() resized=resized>
                    {rows}
                </TimelineBody>
                <div id="playhead" class="ms-playhead" style:left=move || lane_left(playhead_fraction()) hidden=playhead_hidden></div>
            </div>
            {row_tools}
            <Minimap state=state chunks=chunks.clone() resized=resized/>
            <p id="timeline-hint" class="ms-timeline-hint">
                "Click a segment to select it and play it (looped while Loop is on), right-click it for more · click elsewhere on the timeline to seek · "
                "Ctrl/⌘ + wheel zooms, Shift + wheel or dragging the ruler or the minimap pans · press ? for all shortcuts"
            </p>
            <div
                id="timeline-tooltip"
                class="ms-tooltip"
                role="tooltip"
                hidden=move || hover.with(Option::is_none)
                style:left=move || hover.with(|h| h.as_ref().map(|h| format!("{}px", h.0 + 12.0)))
                style:top=move || hover.with(|h| h.as_ref().map(|h| format!("{}px", h.1 + 16.0)))
            >
                {move || hover.with(|h| h.as_ref().map(|h| h.2.clone()).unwrap_or_default())}
            </div>
            {overlays}
        </section>
    }
}

/// The lanes' body: the motion image and the rows (`children`); pressing on their empty space seeks (dragging
/// scrubs), hovering says the segment or the frame under the pointer.
#[component]
fn TimelineBody(
    state: AppState,
    ruler_ref: NodeRef<Div>,
    hover: RwSignal<Option<(f64, f64, String)>>,
    chunks: Chunks,
    resized: RwSignal<u32>,
    children: Children,
) -> impl IntoView {
    let frames = move || state.frames();
    // seeking on the motion image and the rows' empty space
    let seeking = StoredValue::new(false);
    let seek = move |ev: &PointerEvent| {
        if let Some(frame) = frame_at(state, ruler_ref, ev.client_x() as f64).filter(|_| frames() > 0) {
            state.frame.set(frame);
        }
    };
    let on_body_down = move |ev: PointerEvent| {
        if frame_at(state, ruler_ref, ev.client_x() as f64).is_none() || ev.button() != 0 {
            return; // a label, or not the main button
        }
        seeking.set_value(true);
        state.selected.set(None);
        state.play_until.set(None);
        if let Some(el) = ev.current_target().and_then(|t| t.dyn_into::<Element>().ok()) {
            let _ = el.set_pointer_capture(ev.pointer_id());
        }
        seek(&ev);
    };
    let on_body_move = move |ev: PointerEvent| {
        if seeking.get_value() {
            seek(&ev);
        }
        // the tooltip: a segment's own text, else the frame under the pointer
        let over_segment = ev
            .target()
            .and_then(|t| t.dyn_into::<Element>().ok())
            .and_then(|e| e.closest(".ms-seg, .ms-effort-seg, .ms-consensus-mark").ok().flatten())
            .and_then(|e| e.get_attribute("aria-label"));
        let text = over_segment.or_else(|| {
            let frame = frame_at(state, ruler_ref, ev.client_x() as f64)?;
            Some(hover_text(frame, state.fps()))
        });
        hover.set(text.map(|t| (ev.client_x() as f64, ev.client_y() as f64, t)));
    };
    let on_up = move |_: PointerEvent| seeking.set_value(false);
    view! {
        <div
            class="ms-tl-body"
            on:pointerdown=on_body_down
            on:pointermove=on_body_move
            on:pointerup=on_up
            on:pointercancel=on_up
        >
            <div class="ms-tl-line">
                <div class="ms-tl-label">"Motion image"</div>
                <div class="ms-tl-lane">
                    <MotionImageCanvas state=state chunks=chunks.clone() resized=resized/>
                </div>
            </div>
            // Segmentation rows, one per level of each method.
            {children()}
        </div>
    }
}

/// A new take: its image cut into chunks, shown whole, the selection forgotten; a frame off screen (playback,
/// keys, the scrub bar) brings the window along.
fn new_take(state: AppState, chunks: &Chunks, resized: RwSignal<u32>) {
    {
        let chunks = chunks.clone();
        Effect::new(move |_| {
            state.motion.with(|m| {
                if let Some(m) = m {
                    if let Err(e) = chunks.load(&m.image) {
                        web_sys::console::error_2(&"motion image: could not cut into chunks".into(), &e);
                    }
                }
            });
            state.window.set(Window::full(state.frames()));
            state.selected.set(None);
            state.play_until.set(None);
            resized.update(|n| *n += 1);
        });
    }
    // a frame off screen (playback, keys, the scrub bar) brings the window along
    Effect::new(move |_| {
        let frame = state.frame.get();
        let frames = state.frames();
        let w = state.window.get_untracked();
        if frames > 0 && !w.shows(frame) {
            state.window.set(w.paged_to(frame, frames));
        }
    });
}

/// The frame at a pointer's x, if it is over the lanes (the ruler is as wide as every lane).
fn frame_at(state: AppState, ruler_ref: NodeRef<Div>, client_x: f64) -> Option<usize> {
    let (left, width) = lane_box(&ruler_ref)?;
    let fraction = (client_x - left) / width;
    (0.0..=1.0)
        .contains(&fraction)
        .then(|| state.window.get_untracked().frame_at(fraction.min(0.999_999), state.frames()))
}

/// The wheel over the timeline: Ctrl/⌘ zooms around the pointer, Shift or sideways pans, plain scrolls the page;
/// a window resize redraws the lanes.
fn listen_wheel(state: AppState, body_ref: NodeRef<Div>, ruler_ref: NodeRef<Div>, resized: RwSignal<u32>) {
    let frames = move || state.frames();
    body_ref.on_load(move |body| {
        EventListener::new(&gloo::utils::window(), "resize", move |_| resized.update(|n| *n += 1)).forget();
        let options = EventListenerOptions::enable_prevent_default();
        let target: &web_sys::EventTarget = body.as_ref();
        EventListener::new_with_options(target, "wheel", options, move |ev| {
            let ev: &WheelEvent = ev.unchecked_ref();
            let (Some((left, width)), n) = (lane_box(&ruler_ref), frames()) else { return };
            if n == 0 {
                return;
            }
            let w = state.window.get_untracked();
            let scale = match ev.delta_mode() {
                1 => 16.0,  // lines
                2 => 400.0, // pages
                _ => 1.0,
            };
            let (dx, dy) = (ev.delta_x() * scale, ev.delta_y() * scale);
            if ev.ctrl_key() || ev.meta_key() {
                ev.prevent_default();
                let fraction = ((ev.client_x() as f64 - left) / width).clamp(0.0, 1.0);
                let anchor = w.start + fraction * w.span();
                state.window.set(w.zoomed((-dy * 0.002).exp(), anchor, n));
            } else if ev.shift_key() || dx.abs() > dy.abs() {
                ev.prevent_default();
                let delta = if dx.abs() > dy.abs() { dx } else { dy };
                state.window.set(w.panned(delta / width * w.span(), n));
            }
        })
        .forget();
    });
}

/// The lanes' width, for the rows' labels (the ruler is as wide as every lane), kept as the ruler is resized.
fn measure_lanes(ruler_ref: NodeRef<Div>) {
    Effect::new(move |_| {
        let Some(ruler) = ruler_ref.get() else { return };
        let lane = lane_px();
        lane.set(ruler.client_width() as f64);
        let measured = ruler.clone();
        let on_resize = wasm_bindgen::closure::Closure::<dyn FnMut()>::new(move || {
            let width = measured.client_width() as f64;
            if lane.get_untracked() != width {
                lane.set(width);
            }
        });
        ResizeObserver::new(on_resize.as_ref().unchecked_ref()).observe(&ruler);
        on_resize.forget(); // observes the ruler as long as the page lives
    });
}

/// The time ruler: its ticks for the window and the lane's width; dragging it pans (the window moves with the
/// pointer), hovering says the frame.
#[component]
fn Ruler(
    state: AppState,
    ruler_ref: NodeRef<Div>,
    hover: RwSignal<Option<(f64, f64, String)>>,
    resized: RwSignal<u32>,
) -> impl IntoView {
    let frames = move || state.frames();
    let window = move || state.window.get();
    let ruler_drag = StoredValue::new(None::<(f64, Window)>);
    let on_ruler_down = move |ev: PointerEvent| {
        ruler_drag.set_value(Some((ev.client_x() as f64, state.window.get_untracked())));
        if let Some(el) = ev.current_target().and_then(|t| t.dyn_into::<Element>().ok()) {
            let _ = el.set_pointer_capture(ev.pointer_id());
        }
    };
    let on_ruler_move = move |ev: PointerEvent| {
        if let (Some((x0, w0)), Some((_, width))) = (ruler_drag.get_value(), lane_box(&ruler_ref)) {
            let delta = -(ev.client_x() as f64 - x0) / width * w0.span();
            state.window.set(w0.panned(delta, frames()));
        }
        hover.set(
            frame_at(state, ruler_ref, ev.client_x() as f64)
                .map(|f| (ev.client_x() as f64, ev.client_y() as f64, hover_text(f, state.fps()))),
        );
    };
    let on_ruler_up = move |_: PointerEvent| ruler_drag.set_value(None);
    let tick_views = move || {
        resized.track();
        let width = ruler_ref.get().map_or(0.0, |r| r.client_width() as f64);
        let w = window();
        ticks(&w, state.fps(), width, TICK_MIN_PX)
            .into_iter()
            .map(|t| {
                view! {
                    <span class="ms-tick" style:left=format!("{:.4}%", w.fraction(t.frame) * 100.0) data-seconds=t.seconds.to_string()>
                        {t.label}
                    </span>
                }
            })
            .collect_view()
    };
    view! {
        <div class="ms-tl-line ms-tl-line--ruler">
            <div class="ms-tl-label">"Time"</div>
            <div
                id="timeline-ruler"
                class="ms-tl-lane ms-ruler"
                node_ref=ruler_ref
                aria-label="Time ruler: drag to pan"
                on:pointerdown=on_ruler_down
                on:pointermove=on_ruler_move
                on:pointerup=on_ruler_up
                on:pointercancel=on_ruler_up
            >
                {tick_views}
            </div>
        </div>
    }
}

/// The tooltip over an empty lane: the frame (1-based, as the readout) and its time.
fn hover_text(frame: usize, fps: f64) -> String {
    let seconds = if fps > 0.0 { frame as f64 / fps } else { 0.0 };
    format!("frame {} · {} · {:.3} s", frame + 1, crate::app::timeline::window::clock_time(seconds), seconds)
}

/// `#help-overlay`: every shortcut; `?` or its button toggles it, Esc or its Close button closes it.
#[component]
fn HelpOverlay(state: AppState) -> impl IntoView {
    // opened: the focus goes to it (its Close button), closed: back to where it was
    let before = StoredValue::new_local(None::<web_sys::HtmlElement>);
    Effect::new(move |was: Option<bool>| {
        let open = state.help.get();
        let document = gloo::utils::document();
        if open && was != Some(true) {
            let active = document.active_element().and_then(|a| a.dyn_into::<web_sys::HtmlElement>().ok());
            before.set_value(active);
            gloo::timers::callback::Timeout::new(0, || {
                let close = gloo::utils::document().get_element_by_id("help-close");
                if let Some(b) = close.and_then(|b| b.dyn_into::<web_sys::HtmlElement>().ok()) {
                    let _ = b.focus();
                }
            })
            .forget();
        } else if !open && was == Some(true) {
            if let Some(el) = before.get_value() {
                let _ = el.focus();
            }
        }
        open
    });
    view! {
        <div
            id="help-overlay"
            class="ms-help"
            role="dialog"
            aria-modal="false"
            aria-labelledby="help-title"
            hidden=move || !state.help.get()
        >
            <div class="ms-help-box">
                <h2 id="help-title">"Keyboard shortcuts"</h2>
                <dl class="ms-help-list">
                    {SHORTCUTS
                        .iter()
                        .chain(crate::app::my_labels::input::SHORTCUTS.iter())
                        .chain(crate::app::consensus::row::SHORTCUTS.iter())
                        .map(|(keys, what)| view! { <dt><kbd>{*keys}</kbd></dt> <dd>{*what}</dd> })
                        .collect_view()}
                </dl>
                <p class="ms-help-note">"Keys do nothing while you type in a field. Shortcuts the browser uses (Alt+←, Ctrl+L, Ctrl++ …) are left to it."</p>
                <button id="help-close" class="ms-button" type="button" on:click=move |_| state.help.set(false)>"Close"</button>
            </div>
        </div>
    }
}

/// The page's keyboard: [`key_action`] on every key press outside text fields.
fn keyboard(state: AppState) {
    let handle = window_event_listener(leptos::ev::keydown, move |ev: KeyboardEvent| {
        if ev.default_prevented() || is_for_the_field(ev.target(), &ev.key()) {
            return;
        }
        let modifiers =
            Modifiers { shift: ev.shift_key(), ctrl: ev.ctrl_key(), alt: ev.alt_key(), meta: ev.meta_key() };
        let Some(action) = key_action(&ev.key(), modifiers) else { return };
        let frames = state.frames();
        if frames == 0 && !matches!(action, KeyAction::ToggleHelp | KeyAction::Escape) {
            return;
        }
        if action == KeyAction::Escape && !state.help.get_untracked() && state.selected.with_untracked(Option::is_none)
        {
            return; // Esc is the browser's unless it closes the help or drops a selection
        }
        ev.prevent_default();
        let frame = state.frame.get_untracked();
        let step = |delta: i64| {
            state.playing.set(false);
            state.frame.set(stepped(frame, delta, frames));
        };
        match action {
            KeyAction::PlayPause => {
                state.shuttle.set(0);
                state.play_until.set(None);
                state.playing.update(|p| *p = !*p);
            }
            KeyAction::StepFrames(n) => step(n),
            KeyAction::StepSeconds(n) => step(n * state.fps().round().max(1.0) as i64),
            KeyAction::ShuttleBack | KeyAction::ShuttleForward => {
                let forward = action == KeyAction::ShuttleForward;
                let rate = if state.playing.get_untracked() { state.shuttle.get_untracked() } else { 0 };
                state.play_until.set(None);
                // ordinary playback forwards counts as 1× for L
                let rate = if rate == 0 && state.playing.get_untracked() && forward { 1 } else { rate };
                state.shuttle.set(shuttle(rate, forward));
                state.playing.set(true);
            }
            KeyAction::ShuttleStop => state.playing.set(false),
            KeyAction::First => step(-(frames as i64)),
            KeyAction::Last => step(frames as i64),
            KeyAction::ZoomIn | KeyAction::ZoomOut => {
                let factor = if action == KeyAction::ZoomIn { KEY_ZOOM } else { 1.0 / KEY_ZOOM };
                state.window.update(|w| *w = w.zoomed(factor, frame as f64 + 0.5, frames));
            }
            KeyAction::PreviousSegment | KeyAction::NextSegment => {
                go_to_segment(state, action == KeyAction::NextSegment);
            }
            KeyAction::ToggleHelp => state.help.update(|h| *h = !*h),
            KeyAction::Escape => {
                if state.help.get_untracked() {
                    state.help.set(false);
                } else {
                    state.selected.set(None);
                }
            }
        }
    });
    std::mem::forget(handle); // the timeline lives as long as the page
}

/// `[` / `]`: moves the playhead to the previous / next boundary of the selected row (else the
/// first row with segments) before / after the playhead — wherever the playhead was moved to since
/// a segment was selected — selects the segment starting there (none: a gap or the row's end) and
/// brings it into view.
fn go_to_segment(state: AppState, forward: bool) {
    let rows = row_spans(state);
    let chosen = state.selected.with_untracked(|s| s.as_ref().map(|s| s.row.clone()));
    let Some((row, spans)) =
        chosen.and_then(|id| rows.iter().find(|(r, _)| *r == id)).or_else(|| rows.first()).cloned()
    else {
        return;
    };
    let (frame, frames) = (state.frame.get_untracked(), state.frames());
    let found = if forward {
        crate::app::timeline::window::next_boundary(&spans, frame, frames)
    } else {
        crate::app::timeline::window::previous_boundary(&spans, frame, frames)
    };
    let Some(at) = found else { return };
    let segment = spans.iter().find(|s| s.0 == at).copied();
    state.play_until.set(None);
    match segment {
        Some((start, end)) => {
            state.window.update(|w| *w = w.showing(start, end, frames));
            state.selected.set(Some(Selection { row, start, end }));
        }
        // a gap's start: the selection (and so the row `[` / `]` walk) stays as it was
        None => state.window.update(|w| *w = w.showing(at, at, frames)),
    }
    state.frame.set(at);
}
