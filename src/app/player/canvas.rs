//! The skeleton player: `#player-canvas` draws the current frame as a perspective stick figure
//! over a floor grid (drag to orbit, wheel to zoom, double-click to re-fit), with play/pause
//! (`#play-pause`), a scrub bar (`#scrub`), a speed menu (`#speed`), `#frame-counter` and the
//! follow camera (`#follow`: the view slides along the floor with the root, so a walking subject
//! stays in a zoomed view; the canvas' `data-root-x` is where the root was drawn, in CSS pixels, `none` when it was not).
//! Camera math is in [`crate::app::camera`]; playback timing in [`crate::app::player::playback`].

use crate::app::player::playback;

use crate::app::player::camera::{Basis, FloorGrid, Orbit, Projector};
use crate::app::state::AppState;
use crate::motion::UpAxis;
use crate::protocol::LoadedMotion;
use glam::{Vec2, Vec3};
use gloo::events::{EventListener, EventListenerOptions};
use leptos::ev::{Event, PointerEvent};
use leptos::html::Canvas;
use leptos::prelude::*;
use wasm_bindgen::JsCast;
use web_sys::{CanvasRenderingContext2d, HtmlCanvasElement, WheelEvent};

/// Playback speeds offered by `#speed`.
const SPEEDS: [(f64, &str); 5] = [(0.25, "0.25×"), (0.5, "0.5×"), (1.0, "1×"), (2.0, "2×"), (4.0, "4×")];

/// Radians of orbit per pixel of drag.
const ORBIT_PER_PIXEL: f32 = 0.008;

/// The player's colours: background, floor grid, shadow, bones, joints, root.
struct Colours {
    background: &'static str,
    grid: &'static str,
    shadow: &'static str,
    bone: &'static str,
    joint: &'static str,
    root: &'static str,
}

const LIGHT: Colours = Colours {
    background: "#f7f8fa",
    grid: "#d5dae1",
    shadow: "rgba(30, 40, 60, 0.13)",
    bone: "#1f4e79",
    joint: "#0d2a45",
    root: "#c2410c",
};

const DARK: Colours = Colours {
    background: "#161b24",
    grid: "#2e3746",
    shadow: "rgba(0, 0, 0, 0.35)",
    bone: "#8ab4f8",
    joint: "#dbe7ff",
    root: "#fb923c",
};

/// The colours of the system's theme (`prefers-color-scheme`, as www/style.css follows it).
fn colours() -> &'static Colours {
    // window.matchMedia(query).matches, through js_sys (no extra web-sys feature for one call)
    let dark = (|| {
        let window: wasm_bindgen::JsValue = web_sys::window()?.into();
        let match_media = js_sys::Reflect::get(&window, &"matchMedia".into()).ok()?;
        let list =
            match_media.dyn_ref::<js_sys::Function>()?.call1(&window, &"(prefers-color-scheme: dark)".into()).ok()?;
        js_sys::Reflect::get(&list, &"matches".into()).ok()?.as_bool()
    })()
    .unwrap_or(false);
    if dark {
        &DARK
    } else {
        &LIGHT
    }
}

#[component]
pub fn Player(state: AppState) -> impl IntoView {
    let canvas_ref = NodeRef::<Canvas>::new();
    let orbit = RwSignal::new(None::<Orbit>);
    // Bumped on window resize so the canvas redraws at its new size.
    let resized = RwSignal::new(0u32);
    let drag = StoredValue::new(None::<(i32, i32)>);
    let follow = RwSignal::new(false);

    let basis = Memo::new(move |_| state.motion.with(|m| m.as_ref().map(|m| basis_for(m.summary.up_axis))));
    let grid = Memo::new(move |_| {
        let bounds = state.motion.with(|m| m.as_ref().map(|m| m.bounds))?;
        Some(FloorGrid::under(bounds.min(), bounds.max(), &basis.get()?))
    });
    let fit = move || {
        let aspect = canvas_ref.get_untracked().map_or(1.5, |c| aspect_of(&c));
        let fitted =
            state.motion.with_untracked(|m| m.as_ref().map(|m| Orbit::fit(m.bounds.min(), m.bounds.max(), aspect)));
        orbit.set(fitted);
    };
    // A new take: frame the camera on it.
    Effect::new(move |_| {
        state.motion.track();
        fit();
    });
    // Redraw whenever the frame, the camera or the canvas size changes.
    Effect::new(move |_| {
        resized.track();
        let (Some(canvas), Some(orbit), Some(basis)) = (canvas_ref.get(), orbit.get(), basis.get()) else {
            return;
        };
        let frame = state.frame.get();
        let follow = follow.get();
        grid.with(|grid| {
            state.motion.with(|m| {
                if let (Some(m), Some(grid)) = (m, grid) {
                    let orbit = match root_at(m, frame) {
                        Some(root) if follow => orbit.following(root, &basis),
                        _ => orbit,
                    };
                    draw(&canvas, m, frame, &orbit, &basis, grid);
                }
            })
        });
    });
    canvas_ref.on_load(move |canvas| {
        EventListener::new(&gloo::utils::window(), "resize", move |_| resized.update(|n| *n += 1)).forget();
        // Wheel zoom must prevent page scrolling, which needs a non-passive listener.
        let options = EventListenerOptions::enable_prevent_default();
        EventListener::new_with_options(&canvas, "wheel", options, move |ev| {
            let ev: &WheelEvent = ev.unchecked_ref();
            ev.prevent_default();
            orbit.update(|o| *o = o.map(|o| o.zoomed((ev.delta_y() as f32 * 0.0015).exp())));
        })
        .forget();
        fit();
    });
    playback::drive(state);

    let on_pointer_down = move |ev: PointerEvent| {
        drag.set_value(Some((ev.client_x(), ev.client_y())));
        if let Some(canvas) = canvas_ref.get_untracked() {
            let _ = canvas.set_pointer_capture(ev.pointer_id());
        }
    };
    let on_pointer_move = move |ev: PointerEvent| {
        let Some((x, y)) = drag.get_value() else { return };
        let (dx, dy) = (ev.client_x() - x, ev.client_y() - y);
        drag.set_value(Some((ev.client_x(), ev.client_y())));
        orbit.update(|o| *o = o.map(|o| o.rotated(dx as f32 * ORBIT_PER_PIXEL, dy as f32 * ORBIT_PER_PIXEL)));
    };
    let on_pointer_up = move |_: PointerEvent| drag.set_value(None);

    view! {
        <section class="ms-player" aria-label="Skeleton player">
            <canvas
                id="player-canvas"
                node_ref=canvas_ref
                title="Drag to orbit, scroll to zoom, double-click to re-fit"
                on:pointerdown=on_pointer_down
                on:pointermove=on_pointer_move
                on:pointerup=on_pointer_up
                on:pointercancel=on_pointer_up
                on:dblclick=move |_| fit()
            ></canvas>
            <Controls state=state follow=follow />
        </section>
    }
}

/// The player's controls: play/pause, the frame slider and counter, follow, speed.
#[component]
fn Controls(state: AppState, follow: RwSignal<bool>) -> impl IntoView {
    let frames = move || state.frames();
    let has_motion = move || frames() > 0;
    let on_scrub = move |ev: Event| {
        if let Ok(frame) = event_target_value(&ev).parse::<usize>() {
            state.frame.set(frame.min(frames().saturating_sub(1)));
        }
    };
    let on_speed = move |ev: Event| {
        if let Ok(speed) = event_target_value(&ev).parse::<f64>() {
            state.speed.set(speed);
        }
    };

    view! {
        <div class="ms-controls">
            <button
                id="play-pause"
                class="ms-button"
                type="button"
                disabled=move || !has_motion()
                aria-pressed=move || state.playing.get().to_string()
                on:click=move |_| state.playing.update(|p| *p = !*p)
            >
                {move || if state.playing.get() { "Pause" } else { "Play" }}
            </button>
            <input
                id="scrub"
                type="range"
                min="0"
                step="1"
                aria-label="Frame"
                max=move || frames().saturating_sub(1).to_string()
                prop:value=move || state.frame.get().to_string()
                disabled=move || !has_motion()
                on:input=on_scrub
            />
            <span id="frame-counter" class="ms-frame-counter">
                {move || format!("frame {} / {}", if has_motion() { state.frame.get() + 1 } else { 0 }, frames())}
            </span>
            <button
                id="follow"
                class="ms-button"
                type="button"
                title="Follow the subject: the view slides along the floor with it"
                disabled=move || !has_motion()
                aria-pressed=move || follow.get().to_string()
                on:click=move |_| follow.update(|f| *f = !*f)
            >
                "Follow"
            </button>
            <label class="ms-speed">
                "Speed "
                <select id="speed" on:change=on_speed>
                    {SPEEDS
                        .iter()
                        .map(|(value, label)| {
                            view! {
                                <option value=value.to_string() selected=*value == 1.0>
                                    {*label}
                                </option>
                            }
                        })
                        .collect_view()}
                </select>
            </label>
        </div>
    }
}

/// The root joint's position in `frame` (the node without a parent).
fn root_at(m: &LoadedMotion, frame: usize) -> Option<Vec3> {
    let root = m.skeleton.parents.iter().position(Option::is_none)?;
    m.frame(frame).nth(root)
}

fn basis_for(up: UpAxis) -> Basis {
    match up {
        UpAxis::Y => Basis::Y_UP,
        UpAxis::Z => Basis::Z_UP,
    }
}

fn aspect_of(canvas: &HtmlCanvasElement) -> f32 {
    canvas.client_width().max(1) as f32 / canvas.client_height().max(1) as f32
}

/// Sizes the canvas' backing store to its CSS size × device pixels; returns the size in pixels.
fn fit_backing_store(canvas: &HtmlCanvasElement) -> Vec2 {
    let dpr = gloo::utils::window().device_pixel_ratio().max(1.0);
    let (w, h) = ((canvas.client_width() as f64 * dpr) as u32, (canvas.client_height() as f64 * dpr) as u32);
    if canvas.width() != w.max(1) || canvas.height() != h.max(1) {
        canvas.set_width(w.max(1));
        canvas.set_height(h.max(1));
    }
    Vec2::new(canvas.width() as f32, canvas.height() as f32)
}

fn context(canvas: &HtmlCanvasElement) -> Option<CanvasRenderingContext2d> {
    canvas.get_context("2d").ok().flatten()?.dyn_into().ok()
}

/// Draws one frame: floor grid, the figure's shadow on the floor, bones, joints.
fn draw(canvas: &HtmlCanvasElement, m: &LoadedMotion, frame: usize, orbit: &Orbit, basis: &Basis, grid: &FloorGrid) {
    let size = fit_backing_store(canvas);
    let Some(ctx) = context(canvas) else { return };
    let scale = (size.y / 400.0).max(0.5) as f64;
    let c = colours();
    ctx.set_fill_style_str(c.background);
    ctx.fill_rect(0.0, 0.0, size.x as f64, size.y as f64);
    let projector = Projector::new(orbit, basis, size);
    let points: Vec<Vec3> = m.frame(frame).collect();
    let bones: Vec<(Vec3, Vec3)> =
        m.skeleton.parents.iter().enumerate().filter_map(|(i, p)| p.map(|p| (points[p], points[i]))).collect();

    stroke_segments(&ctx, &projector, grid.lines.iter().copied(), c.grid, scale);
    let shadows = bones.iter().map(|(a, b)| (basis.on_floor(*a, grid.height), basis.on_floor(*b, grid.height)));
    stroke_segments(&ctx, &projector, shadows, c.shadow, 3.0 * scale);
    ctx.set_line_cap("round");
    stroke_segments(&ctx, &projector, bones.iter().copied(), c.bone, 2.5 * scale);
    // "none" unless the root is drawn below (behind the camera it is not)
    let _ = canvas.set_attribute("data-root-x", "none");
    for (i, p) in points.iter().enumerate() {
        let (is_root, is_end) = (m.skeleton.parents[i].is_none(), m.skeleton.is_end_site[i]);
        if is_end {
            continue;
        }
        if let Some(q) = projector.point(*p) {
            if is_root {
                // where the root was drawn, in CSS pixels (the follow camera's e2e reads it)
                let dpr = gloo::utils::window().device_pixel_ratio().max(1.0);
                let _ = canvas.set_attribute("data-root-x", &format!("{:.1}", q.x as f64 / dpr));
            }
            ctx.set_fill_style_str(if is_root { c.root } else { c.joint });
            ctx.begin_path();
            let r = if is_root { 4.0 } else { 2.5 } * scale;
            let _ = ctx.arc(q.x as f64, q.y as f64, r, 0.0, std::f64::consts::TAU);
            ctx.fill();
        }
    }
}

fn stroke_segments(
    ctx: &CanvasRenderingContext2d,
    projector: &Projector,
    segments: impl Iterator<Item = (Vec3, Vec3)>,
    colour: &str,
    width: f64,
) {
    ctx.set_stroke_style_str(colour);
    ctx.set_line_width(width);
    ctx.begin_path();
    for (a, b) in segments {
        if let Some((p, q)) = projector.segment(a, b) {
            ctx.move_to(p.x as f64, p.y as f64);
            ctx.line_to(q.x as f64, q.y as f64);
        }
    }
    ctx.stroke();
}
