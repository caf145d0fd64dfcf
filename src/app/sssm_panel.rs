//! The SSSM segmentation (Krüger et al. 2017, issue 3) on the page.
//!
//! * [`SssmPanel`] — `#sssm-panel`: the parameter form `#sssm-params` (radius, offsets,
//!   search horizon, bundling, mirror; `#sssm-run` re-runs in the worker), `#sssm-progress` while it runs, the
//!   SSSM image `#sssm-image` (rendered by the worker, see [`crate::sssm::image`]) and
//!   `#sssm-export`, which saves the segmentation JSON as `<name>_sssm.json`.
//! * [`SssmRows`] — `#row-actions` and `#row-primitives` under the motion image, on the
//!   timeline's time axis: actions coloured by cluster as in the SSSM image (transitions
//!   hatched grey), primitives
//!   coloured by cluster with mirror-pair clusters in the same hue at another lightness. Every
//!   segment carries `data-start`/`data-end` (file frames) and a tooltip; clicking a primitive
//!   plays it once (from its start, stopping at its end).

use super::loader::Loader;
use super::motion_image::{download, stem};
use super::{AppState, SssmState};
use crate::segment::{Level, Segment};
use crate::sssm::image as sssm_image;
use crate::sssm::SssmParams;
use crate::worker::SssmView;
use leptos::ev::{MouseEvent, PointerEvent};
use leptos::html::Canvas;
use leptos::prelude::*;
use std::sync::Arc;
use wasm_bindgen::{Clamped, JsCast, JsValue};
use web_sys::{CanvasRenderingContext2d, HtmlCanvasElement};

/// The parameters the form edits, as the JSON the worker reads (the other fields keep their
/// defaults, except the primitive graph's radius, which keeps its default ratio to the radius
/// so that any radius the user picks is consistent). Fails with a message naming the field the
/// text cannot be read from; the values themselves are checked by the core.
pub fn params_json(radius: &str, offsets: &str, horizon: &str, bundling: bool, mirror: bool) -> Result<String, String> {
    let number = |name: &str, text: &str, unit: &str| -> Result<f64, String> {
        text.trim()
            .parse()
            .ok()
            .filter(|r: &f64| r.is_finite())
            .ok_or_else(|| format!("invalid SSSM parameter {name} = {text:?}: expected a number of {unit}"))
    };
    let radius = number("radius", radius, "inches")?;
    let horizon = number("horizon_s", horizon, "seconds (0 = every pair)")?;
    let offsets = parse_offsets(offsets)?;
    let defaults = SssmParams::default();
    let primitive_radius = radius * defaults.primitive_radius / defaults.radius;
    Ok(serde_json::json!({
        "radius": radius, "primitive_radius": primitive_radius, "offsets": offsets,
        "horizon_s": horizon, "bundling": bundling, "mirror": mirror,
    })
    .to_string())
}

/// "-10,-5,0,5,10" → [-10, -5, 0, 5, 10] (commas and/or spaces between).
fn parse_offsets(text: &str) -> Result<Vec<i32>, String> {
    text.split(|c: char| c == ',' || c.is_whitespace())
        .filter(|t| !t.is_empty())
        .map(|t| {
            t.parse::<i32>().map_err(|_| {
                format!(
                    "invalid SSSM parameter offsets = {text:?}: expected whole numbers of frames separated by commas"
                )
            })
        })
        .collect()
}

/// The colour of primitive cluster `cluster`: a hue per cluster, shared by a mirror pair
/// (taken from the pair's lower id), the pair's higher id lighter.
pub fn cluster_colour(cluster: usize, mirror_of: &[Option<usize>]) -> String {
    let pair = mirror_of.get(cluster).copied().flatten();
    let base = pair.map_or(cluster, |m| m.min(cluster));
    let hue = (base as f64 * 137.508) % 360.0;
    let lightness = if pair.is_some_and(|m| m < cluster) { 72 } else { 48 };
    format!("hsl({hue:.0}, 62%, {lightness}%)")
}

/// Tooltip of a segment: label, frames (1-based as on the frame counter) and seconds.
fn tooltip(s: &Segment, fps: f64) -> String {
    format!(
        "{} · frames {}–{} · {:.2}–{:.2} s",
        s.label,
        s.start + 1,
        s.end + 1,
        s.start as f64 / fps,
        (s.end + 1) as f64 / fps
    )
}

#[component]
pub fn SssmPanel(state: AppState, loader: Loader) -> impl IntoView {
    let radius = RwSignal::new("19".to_string());
    let offsets = RwSignal::new("-10,-5,0,5,10".to_string());
    let horizon = RwSignal::new(SssmParams::default().horizon_s.to_string());
    let bundling = RwSignal::new(false);
    let mirror = RwSignal::new(true);
    let on_run = move |ev: leptos::ev::SubmitEvent| {
        ev.prevent_default();
        match params_json(
            &radius.get_untracked(),
            &offsets.get_untracked(),
            &horizon.get_untracked(),
            bundling.get_untracked(),
            mirror.get_untracked(),
        ) {
            Ok(json) => loader.run_sssm(&json),
            Err(message) => {
                state.error.set(Some(message));
                state.sssm.set(SssmState::Failed);
            }
        }
    };
    let running = move || state.sssm.with(|s| matches!(s, SssmState::Running { .. }));
    let progress = move || {
        state.sssm.with(|s| match s {
            SssmState::Running { stage, fraction } => (stage.clone(), *fraction),
            _ => (String::new(), 0.0),
        })
    };
    let on_export = move |_| {
        state.sssm_view.with_untracked(|v| {
            if let Some(v) = v {
                let s = &v.report.segmentation;
                let name = format!("{}_sssm.json", stem(&s.file));
                if let Err(e) = download(s.to_json().as_bytes(), "application/json", &name) {
                    state.error.set(Some(format!("could not save {name}: {e:?}")));
                }
            }
        })
    };
    let counts = move || {
        state.sssm_view.with(|v| match v {
            Some(v) => {
                let s = &v.report.segmentation;
                format!(
                    "{} actions · {} transitions · {} primitives in {} clusters · SSSM of {} frames at {} Hz",
                    s.level(Level::Action).count(),
                    s.level(Level::Transition).count(),
                    s.level(Level::Primitive).count(),
                    v.report.mirror_of.len(),
                    v.report.working_frames,
                    v.report.working_fps
                )
            }
            None => String::new(),
        })
    };

    view! {
        <section id="sssm-panel" class="ms-sssm" aria-label="SSSM segmentation">
            <div class="ms-timeline-head">
                <h2>"SSSM (Krüger et al. 2017)"</h2>
                <span id="sssm-counts" class="ms-timeline-legend">{counts}</span>
                <button
                    id="sssm-export"
                    class="ms-button ms-button--quiet"
                    type="button"
                    disabled=move || state.sssm_view.with(Option::is_none)
                    on:click=on_export
                >
                    "Export JSON"
                </button>
            </div>
            <form id="sssm-params" class="ms-sssm-params" on:submit=on_run>
                <label>
                    "Radius R (inches) "
                    <input
                        id="sssm-radius"
                        type="number"
                        step="any"
                        size="5"
                        title="Generalized radius R at the reference body size; the primitive graph's radius follows it (13/19 of R)"
                        bind:value=radius
                    />
                </label>
                <label>
                    "Offsets (frames at 30 Hz) "
                    <input id="sssm-offsets" type="text" size="16" bind:value=offsets/>
                </label>
                <label>
                    "Horizon (s) "
                    <input
                        id="sssm-horizon"
                        type="number"
                        step="any"
                        min="0"
                        size="4"
                        title="Neighbours are searched up to this far apart; actions farther apart are compared through far blocks (0 = every pair, the paper's SSSM)"
                        bind:value=horizon
                    />
                </label>
                <label>
                    <input id="sssm-bundling" type="checkbox" bind:checked=bundling/>
                    " Feature bundling"
                </label>
                <label>
                    <input id="sssm-mirror" type="checkbox" bind:checked=mirror/>
                    " Mirror (symmetry)"
                </label>
                <button
                    id="sssm-run"
                    class="ms-button"
                    type="submit"
                    disabled=move || running() || state.motion.with(Option::is_none)
                >
                    "Run"
                </button>
                <div id="sssm-progress" class="ms-progress" role="status" aria-live="polite" hidden=move || !running()>
                    <progress max="1" value=move || progress().1.clamp(0.0, 1.0).to_string()></progress>
                    <span class="ms-progress-label">{move || format!("SSSM: {}…", progress().0)}</span>
                </div>
            </form>
            <div class="ms-sssm-body">
                <SssmImageCanvas state=state/>
                <p class="ms-sssm-legend">
                    "Frame i down, frame j across (30 Hz). Grey: neighbours within the search radius, darker = closer. "
                    "Coloured squares: actions (colour = kind of action); orange squares: transitions; "
                    "blue lines: primitive cuts; red lines: cuts found only in the mirrored features. "
                    "Farther apart than the search horizon, only the blocks of actions that may repeat each other are searched."
                </p>
            </div>
        </section>
    }
}

#[component]
fn SssmImageCanvas(state: AppState) -> impl IntoView {
    let canvas_ref = NodeRef::<Canvas>::new();
    Effect::new(move |_| {
        let Some(canvas) = canvas_ref.get() else { return };
        state.sssm_view.with(|v| {
            let drawn = match v {
                Some(v) => draw_sssm(&canvas, v),
                None => {
                    canvas.set_width(0);
                    canvas.set_height(0);
                    Ok(())
                }
            };
            if let Err(e) = drawn {
                web_sys::console::error_2(&"SSSM image: could not draw".into(), &e);
            }
        });
    });
    view! {
        <canvas
            id="sssm-image"
            class="ms-sssm-image"
            node_ref=canvas_ref
            aria-label="Sparse self-similarity matrix with actions and primitive cuts"
        ></canvas>
    }
}

/// Puts the worker's pixels on the canvas, one canvas pixel per image pixel (CSS scales it).
fn draw_sssm(canvas: &HtmlCanvasElement, view: &SssmView) -> Result<(), JsValue> {
    let size = view.image.size as u32;
    canvas.set_width(size);
    canvas.set_height(size);
    if size == 0 {
        return Ok(());
    }
    let ctx: CanvasRenderingContext2d = canvas.get_context("2d")?.ok_or("no 2d context")?.dyn_into()?;
    let pixels = web_sys::ImageData::new_with_u8_clamped_array_and_sh(Clamped(&view.image.rgba), size, size)?;
    ctx.put_image_data(&pixels, 0.0, 0.0)
}

#[component]
pub fn SssmRows(state: AppState) -> impl IntoView {
    let segments = move |level: Level| {
        state.sssm_view.with(|v| {
            v.as_ref().map_or_else(Vec::new, |v| v.report.segmentation.level(level).cloned().collect::<Vec<_>>())
        })
    };
    let view_of = move || state.sssm_view.get();
    let actions = move || {
        let Some(v) = view_of() else { return Vec::new() };
        let mut rows: Vec<Segment> = segments(Level::Action);
        rows.extend(segments(Level::Transition));
        rows.sort_by_key(|s| s.start);
        rows.into_iter().map(|s| segment_view(state, &v, s, false)).collect::<Vec<_>>()
    };
    let primitives = move || {
        let Some(v) = view_of() else { return Vec::new() };
        segments(Level::Primitive).into_iter().map(|s| segment_view(state, &v, s, true)).collect::<Vec<_>>()
    };
    let hidden = move || state.sssm_view.with(Option::is_none);
    view! {
        <div id="row-actions" class="ms-row" hidden=hidden title="SSSM actions and transitions">
            {actions}
        </div>
        <div id="row-primitives" class="ms-row" hidden=hidden title="SSSM primitives">
            {primitives}
        </div>
    }
}

fn segment_view(state: AppState, v: &Arc<SssmView>, s: Segment, primitive: bool) -> impl IntoView {
    let s_frames = v.report.segmentation.frames.max(1) as f64;
    let fps = v.report.segmentation.fps;
    let left = format!("{:.4}%", s.start as f64 / s_frames * 100.0);
    let width = format!("{:.4}%", (s.end + 1 - s.start) as f64 / s_frames * 100.0);
    let (class, colour) = match (s.level, s.cluster) {
        (Level::Transition, _) => ("ms-seg ms-seg--transition", String::new()),
        (Level::Primitive, Some(c)) => ("ms-seg ms-seg--primitive", cluster_colour(c, &v.report.mirror_of)),
        (_, Some(c)) => {
            // the colour of the action's square in the SSSM image
            let [r, g, b] = sssm_image::action_colour(c);
            ("ms-seg ms-seg--action", format!("rgb({r}, {g}, {b})"))
        }
        (_, None) => ("ms-seg", "#888".to_string()),
    };
    let title = tooltip(&s, fps);
    let (start, end) = (s.start, s.end);
    // keep the timeline's own seek from capturing the pointer (the click must reach us)
    let on_down = move |ev: PointerEvent| ev.stop_propagation();
    let on_click = move |ev: MouseEvent| {
        ev.stop_propagation();
        if primitive {
            state.play_until.set(Some(end));
            state.frame.set(start);
            state.playing.set(true);
        } else {
            state.play_until.set(None);
            state.frame.set(start);
        }
    };
    view! {
        <div
            class=class
            style:left=left
            style:width=width
            style:background-color=(!colour.is_empty()).then_some(colour)
            data-start=start.to_string()
            data-end=end.to_string()
            data-cluster=s.cluster.map(|c| c.to_string()).unwrap_or_default()
            title=title
            on:pointerdown=on_down
            on:click=on_click
        >
            {s.label.clone()}
        </div>
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
    #[cfg_attr(not(target_arch = "wasm32"), test)]
    fn form_values_become_the_worker_params() {
        let json = params_json(" 15 ", "-10, -5,0 5,10", "0", true, false).unwrap();
        let v: serde_json::Value = serde_json::from_str(&json).unwrap();
        assert_eq!(v["radius"], 15.0);
        assert_eq!(v["horizon_s"], 0.0);
        let d = SssmParams::default();
        assert_eq!(v["primitive_radius"], 15.0 * d.primitive_radius / d.radius);
        // the form's initial values give the default parameters
        let initial = params_json("19", "-10,-5,0,5,10", &d.horizon_s.to_string(), false, true).unwrap();
        let back: SssmParams = serde_json::from_str(&initial).unwrap();
        assert_eq!(back, d);
        assert_eq!(v["offsets"], serde_json::json!([-10, -5, 0, 5, 10]));
        assert_eq!((v["bundling"].as_bool(), v["mirror"].as_bool()), (Some(true), Some(false)));
        // negative values are the core's to reject (it names the parameter)
        assert!(params_json("-1", "0", "-3", false, false).is_ok());
        assert!(params_json("abc", "0", "20", false, false).unwrap_err().contains("radius"));
        assert!(params_json("19", "-10,x", "20", false, false).unwrap_err().contains("offsets"));
        assert!(params_json("19", "0", "soon", false, false).unwrap_err().contains("horizon_s"));
    }

    #[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
    #[cfg_attr(not(target_arch = "wasm32"), test)]
    fn mirror_pairs_share_a_hue() {
        let mirror_of = [Some(2), None, Some(0)];
        let (a, b, c) = (cluster_colour(0, &mirror_of), cluster_colour(1, &mirror_of), cluster_colour(2, &mirror_of));
        let hue = |s: &str| s.split(',').next().unwrap().to_string();
        assert_eq!(hue(&a), hue(&c));
        assert_ne!(a, c);
        assert_ne!(hue(&a), hue(&b));
    }
}
