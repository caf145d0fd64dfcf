//! One generic panel per registered method, built from the registry
//! ([`crate::methods::registry`]): nothing here knows any method.
//!
//! * [`MethodPanel`] — `#<name>-panel`: heading with the paper, the result's one-line summary
//!   `#<name>-counts`, `#<name>-export` (saves the segmentation JSON as `<take>_<name>.json`),
//!   the parameter form `#<name>-params` generated from the method's [`ParamSpec`]s (one field
//!   `#<name>-<param>` each; the basic ones shown, the others under "Advanced"; every field two grid
//!   cells, name | control and unit), `#<name>-couplings` (a coupled parameter the form breaks —
//!   [`ParamSpec::at_most`], the SSSM's primitive radius above its radius — said with a one-click
//!   `#<name>-adjust-<param>`; Run lowers it and says so in `#<name>-adjusted`), `#<name>-run`,
//!   `#<name>-cancel` and `#<name>-progress` while it runs, and every picture the method draws as
//!   a canvas `#<name>-<picture>` with its caption.
//! * [`MethodRows`] — under the motion image, on the timeline's time axis, for every method with
//!   a result, each row labelled at its left with the method and level ("SSSM · actions"):
//!   `#row-<name>-actions` (actions coloured by kind, transitions hatched grey) and
//!   `#row-<name>-primitives` (coloured by cluster, mirror-pair clusters in one hue at two
//!   lightnesses). Only the segments in the timeline's window are in the DOM (at most about
//!   2 × [`MAX_SEGMENTS_PER_ROW`] per row), placed on the window. Every segment carries
//!   `data-start`/`data-end` (file frames) and its tooltip text as `aria-label`; clicking one
//!   selects it (`ms-seg--selected`) and plays it, looped while Loop is on, else once to its end.
//!   A labelling method (one DT-FCN, k-NN) colours each segment by its label (the one colour the page gives that
//!   label on every row, `AppState::label_css`; `data-colour`), lighter the lower its mean confidence (`score`,
//!   `data-score`), and hatches `unknown` segments grey (`ms-seg--unknown`); its row is labelled
//!   "<method> · labels". Labels are always text, never markup: the label when it fits the
//!   segment, else a clean abbreviation or nothing ([`crate::app::timeline::label_fit`]), the whole label in
//!   `data-label` and the tooltip.

use crate::app::method_panel::fields::checked_field;
use crate::app::method_panel::runs::MethodRuns;
use crate::app::player::motion_image::{download, stem};
use crate::app::state::AppState;
use crate::app::state::MethodSlot;
use crate::app::state::RunState;
use crate::app::timeline::clip_jobs::ClipJobs;
use crate::app::timeline::rows::{which_of, which_word};
use crate::clips::Which;
use crate::method::{form, Picture};
use crate::protocol::MethodView;
use crate::segment::Level;
use leptos::ev::MouseEvent;
use leptos::html::Canvas;
use leptos::prelude::*;
use std::sync::Arc;
use wasm_bindgen::{Clamped, JsCast, JsValue};
use web_sys::{CanvasRenderingContext2d, HtmlCanvasElement};

/// What Run lowered of the coupled parameters `pending` (each to its limit), as the note under the form says it.
fn lowered_message(slot: &'static MethodSlot, pending: &[form::Conflict]) -> String {
    let said: Vec<String> = pending
        .iter()
        .map(|c| {
            format!(
                "{} lowered from {} to {}: it may not exceed {}",
                spec_words(slot, &c.param),
                c.value,
                c.adjusted_text(),
                spec_words(slot, &c.limit_param)
            )
        })
        .collect();
    format!("{} (Advanced).", said.join("; "))
}

/// Parameter `name` of `slot` in words (its own name when the method has no such parameter).
fn spec_words(slot: &'static MethodSlot, name: &str) -> String {
    slot.specs.iter().find(|s| s.name == name).map(crate::method::ParamSpec::words).unwrap_or_else(|| name.to_string())
}

/// A coupled parameter the form breaks (`c`), with the button that sets it to its limit (`adjust`).
fn coupling_note(
    slot: &'static MethodSlot,
    c: form::Conflict,
    adjust: impl Fn(&form::Conflict) + Copy + 'static,
) -> impl IntoView {
    let (param, limit) = (spec_words(slot, &c.param), spec_words(slot, &c.limit_param));
    let text = format!("{param} ({}) may not exceed {limit} ({}).", c.value, c.limit);
    let button = format!("Set {param} to {}", c.adjusted_text());
    let id = format!("{}-adjust-{}", slot.info.name, c.param);
    let (param_name, limit_name) = (c.param.clone(), c.limit_param.clone());
    view! {
        <p class="ms-coupling" data-param=param_name data-limit=limit_name>
            {text}
            " "
            <button id=id class="ms-button ms-button--small" type="button" on:click=move |_| adjust(&c)>
                {button}
            </button>
            " or Run lowers it."
        </p>
    }
}

/// Saves the method's last segmentation as JSON (with the Effort the bars under the rows computed, where the run
/// has none of its own).
fn export_json(state: AppState, slot: &'static MethodSlot) {
    slot.view.with_untracked(|v| {
        if let Some(v) = v {
            let s = &v.segmentation;
            let file = format!("{}_{}.json", stem(&s.file), slot.info.name);
            let s = state.effort.fill(state, s);
            if let Err(e) = download(s.to_json().as_bytes(), "application/json", &file) {
                state.show_error(format!("could not save {file}: {e:?}"));
            }
        }
    })
}

/// A refused parameter's field: scrolled into view and focused.
fn focus_refused_field(slot: &'static MethodSlot) {
    let Some((param, _)) = slot.field_error.get() else { return };
    let id = format!("{}-{param}", slot.info.name);
    if let Some(el) = web_sys::window()
        .and_then(|w| w.document())
        .and_then(|d| d.get_element_by_id(&id))
        .and_then(|e| e.dyn_into::<web_sys::HtmlElement>().ok())
    {
        el.scroll_into_view_with_bool(false);
        let _ = el.focus();
    }
}

/// Run, Cancel (`on_cancel`) and the run's progress.
fn run_actions(
    state: AppState,
    slot: &'static MethodSlot,
    on_cancel: impl FnMut(MouseEvent) + 'static,
) -> impl IntoView {
    let name = slot.info.name.clone();
    let short = slot.info.short.clone();
    let running = move || slot.run.with(|s| matches!(s, RunState::Running { .. }));
    let progress = move || {
        slot.run.with(|s| match s {
            RunState::Running { stage, fraction } => (stage.clone(), *fraction),
            _ => (String::new(), 0.0),
        })
    };
    view! {
    <div class="ms-method-actions">
        <button
            id=format!("{name}-run")
            class="ms-button"
            type="submit"
            disabled=move || running() || state.motion.with(Option::is_none)
        >
            "Run"
        </button>
        <button
            id=format!("{name}-cancel")
            class="ms-button ms-button--quiet"
            type="button"
            hidden=move || !running()
            on:click=on_cancel
        >
            "Cancel"
        </button>
        <div id=format!("{name}-progress") class="ms-progress" role="status" aria-live="polite" hidden=move || !running()>
            <progress max="1" value=move || progress().1.clamp(0.0, 1.0).to_string()></progress>
            <span class="ms-progress-label">{move || format!("{short}: {}…", progress().0)}</span>
        </div>
    </div>
    }
}

#[component]
pub fn MethodPanel(
    state: AppState,
    method: &'static MethodSlot,
    runs: MethodRuns,
    /// What the method adds under its form (a supervised method: model files and training).
    extra: Option<AnyView>,
) -> impl IntoView {
    let slot = method;
    let index = state.methods.iter().position(|s| std::ptr::eq(s, slot)).unwrap_or(0);
    let name = slot.info.name.clone();
    // coupled parameters the form breaks (the SSSM's primitive radius above its radius): offered
    // to adjust in one click, and lowered on Run with a note saying so
    let texts = move || slot.fields.iter().map(|f| f.get()).collect::<Vec<String>>();
    let conflicts = Memo::new(move |_| form::conflicts(&slot.specs, &texts()));
    let adjusted = RwSignal::new(None::<String>);
    let adjust = move |c: &form::Conflict| {
        if let Some(at) = slot.specs.iter().position(|s| s.name == c.param) {
            slot.fields[at].set(c.adjusted_text());
        }
    };
    let run_with = runs.clone();
    let on_run = move |ev: leptos::ev::SubmitEvent| {
        ev.prevent_default();
        let pending = conflicts.get_untracked();
        adjusted.set((!pending.is_empty()).then(|| {
            pending.iter().for_each(adjust);
            lowered_message(slot, &pending)
        }));
        run_with.run(index);
        // its row stays in view on the timeline (workspace.rs)
        crate::app::workspace::reveal_method(&slot.info.name);
    };
    let coupling_notes = move || conflicts.get().into_iter().map(|c| coupling_note(slot, c, adjust)).collect_view();
    let on_cancel = move |_| runs.cancel(index);
    let on_export = move |_| export_json(state, slot);
    let counts = move || slot.view.with(|v| v.as_ref().map(|v| v.details.summary.clone()).unwrap_or_default());
    let exports = view! { <Exports state=state method=slot index=index/> };
    let fields = || slot.specs.iter().zip(&slot.fields).zip(&slot.choices);
    let basic: Vec<AnyView> =
        fields().filter(|((s, _), _)| s.basic).map(|((s, v), c)| checked_field(slot, s, *v, *c)).collect();
    let advanced: Vec<AnyView> =
        fields().filter(|((s, _), _)| !s.basic).map(|((s, v), c)| checked_field(slot, s, *v, *c)).collect();
    // a refusal of an advanced parameter opens "Advanced"; the wrong field gets the focus
    let advanced_open = move || {
        slot.field_error.with(|e| e.as_ref().is_some_and(|(p, _)| slot.specs.iter().any(|s| !s.basic && &s.name == p)))
    };
    Effect::new(move |_| focus_refused_field(slot));
    let has_advanced = !advanced.is_empty();
    let extra = extra.map(|e| view! { <div class="ms-method-extra">{e}</div> });
    let pictures = move || {
        slot.view.with(|v| match v {
            Some(v) => {
                (0..v.details.pictures.len()).map(|k| picture_view(state, slot, v.clone(), k)).collect::<Vec<_>>()
            }
            None => Vec::new(),
        })
    };

    view! {
        <section id=format!("{name}-panel") class="ms-method" aria-label=format!("{} segmentation", slot.info.short)>
            <div class="ms-timeline-head">
                <h2 title=slot.info.summary.clone()>{format!("{} ({})", slot.info.short, slot.info.paper)}</h2>
                <span id=format!("{name}-counts") class="ms-timeline-legend">{counts}</span>
                <button
                    id=format!("{name}-export")
                    class="ms-button ms-button--quiet"
                    type="button"
                    disabled=move || slot.view.with(Option::is_none)
                    on:click=on_export
                >
                    "Export JSON"
                </button>
            </div>
            <form id=format!("{name}-params") class="ms-method-params" novalidate=true on:submit=on_run>
                {basic}
                <details class="ms-method-advanced" hidden=!has_advanced prop:open=advanced_open>
                    <summary>"Advanced"</summary>
                    {advanced}
                </details>
                <div id=format!("{name}-couplings") class="ms-couplings" role="status" aria-live="polite">
                    {coupling_notes}
                    <p id=format!("{name}-adjusted") class="ms-coupling ms-coupling--done" hidden=move || adjusted.with(Option::is_none)>
                        {move || adjusted.get().unwrap_or_default()}
                    </p>
                </div>
                {run_actions(state, slot, on_cancel)}
            </form>
            <p
                id=format!("{name}-failure")
                class="ms-method-failure"
                role="status"
                hidden=move || slot.failure.with(Option::is_none)
            >
                {move || slot.failure.get().unwrap_or_default()}
            </p>
            {exports}
            {extra}
            <div class="ms-method-body">{pictures}</div>
        </section>
    }
}

/// `#<name>-exports`: the run's segments as the label CSV (`#<name>-export-csv`), as BVH clips
/// in one zip (`#<name>-export-clips`) or the selected segment's clip alone
/// (`#<name>-export-clip`), choosing the segments (`#<name>-export-which`: actions,
/// primitives, all) and whether clips start at the origin facing +Z (`#<name>-export-origin`);
/// `#<name>-export-status` says what was saved or why not.
#[component]
fn Exports(state: AppState, method: &'static MethodSlot, index: usize) -> impl IntoView {
    let clips = use_context::<StoredValue<ClipJobs, LocalStorage>>();
    let slot = method;
    let name = slot.info.name.clone();
    let which = RwSignal::new(Which::Actions);
    let origin = RwSignal::new(false);
    let has = move |level: Level| {
        slot.view.with(|v| v.as_ref().is_some_and(|v| v.segmentation.level(level).next().is_some()))
    };
    // a new run: the choice stays if the run has such segments, else actions, else all
    Effect::new(move |_| {
        if slot.view.with(Option::is_none) {
            return;
        }
        let (a, p) = (has(Level::Action), has(Level::Primitive));
        let w = which.get_untracked();
        if (w == Which::Actions && !a) || (w == Which::Primitives && !p) {
            which.set(if a { Which::Actions } else { Which::All });
        }
    });
    let on_csv = move |_| {
        slot.view.with_untracked(|v| {
            let Some(v) = v else { return };
            let rows = crate::labels::from_segmentation(&v.segmentation, which.get_untracked());
            let word = which_word(Some(v), which.get_untracked());
            let file = format!("{}_{}_{word}.csv", stem(&v.segmentation.file), slot.info.name);
            let status = if rows.is_empty() {
                (true, "no segments of that kind to save".to_string())
            } else {
                match download(crate::labels::to_csv(&rows).as_bytes(), "text/csv", &file) {
                    Ok(()) => (false, format!("saved {file} ({} rows)", rows.len())),
                    Err(e) => (true, format!("could not save {file}: {e:?}")),
                }
            };
            slot.export_status.set(Some(status));
        })
    };
    let on_clips = move |_| {
        if let Some(clips) = clips {
            clips.with_value(|c| c.export_clips(index, which.get_untracked(), origin.get_untracked(), None));
        }
    };
    let mine = {
        let prefix = format!("{name}-");
        move || state.selected.with(|s| s.as_ref().filter(|s| s.row.starts_with(&prefix)).map(|s| (s.start, s.end)))
    };
    let selected = mine.clone();
    let on_clip = move |_| {
        let Some((start, end)) = selected() else { return };
        let Some(w) = slot.view.with_untracked(|v| v.as_ref().and_then(|v| which_of(v, start, end))) else { return };
        if let Some(clips) = clips {
            clips.with_value(|c| c.export_clips(index, w, origin.get_untracked(), Some((start, end))));
        }
    };
    let none = move || slot.view.with(Option::is_none);
    let options = move || {
        [(Which::Actions, Level::Action), (Which::Primitives, Level::Primitive)]
            .into_iter()
            .filter(|(_, level)| has(*level))
            .map(|(w, _)| {
                let label = slot.view.with(|v| which_word(v.as_deref(), w));
                view! { <option value=which_name(w) selected=move || which.get() == w>{label}</option> }
            })
            .collect_view()
    };
    let on_which = move |ev: leptos::ev::Event| {
        which.set(match event_target_value(&ev).as_str() {
            "actions" => Which::Actions,
            "primitives" => Which::Primitives,
            _ => Which::All,
        })
    };
    let status = move || slot.export_status.get();
    view! {
        <div
            id=format!("{name}-exports")
            class="ms-exports"
            role="group"
            aria-label=format!("Export {}", slot.info.short)
            hidden=none
        >
            <label class="ms-exports-field">
                "Segments "
                <select id=format!("{name}-export-which") disabled=none on:change=on_which>
                    {options}
                    <option value="all" selected=move || which.get() == Which::All>"all"</option>
                </select>
            </label>
            <button id=format!("{name}-export-csv") class="ms-button ms-button--quiet" type="button" disabled=none on:click=on_csv>
                "CSV"
            </button>
            <button id=format!("{name}-export-clips") class="ms-button ms-button--quiet" type="button" disabled=none on:click=on_clips
                title="Every chosen segment as its own BVH file, cut from the original with its hierarchy, channel order and frame time, in one zip">
                "BVH clips (zip)"
            </button>
            <button id=format!("{name}-export-clip") class="ms-button ms-button--quiet" type="button"
                disabled=move || mine().is_none()
                on:click=on_clip
                title="Select a segment of this method on the timeline to save it alone">
                "Selected segment as BVH"
            </button>
            <label class="ms-exports-field">
                <input id=format!("{name}-export-origin") type="checkbox"
                    prop:checked=move || origin.get()
                    on:change=move |ev| origin.set(event_target_checked(&ev))/>
                " clips start at the origin facing +Z"
            </label>
            <span
                id=format!("{name}-export-status")
                class="ms-exports-status"
                class:ms-exports-status--error=move || status().is_some_and(|(e, _)| e)
                role="status"
                aria-live="polite"
            >
                {move || status().map(|(_, m)| m).unwrap_or_default()}
            </span>
        </div>
    }
}

fn which_name(w: Which) -> &'static str {
    match w {
        Which::Actions => "actions",
        Which::Primitives => "primitives",
        Which::All => "all",
    }
}

/// Picture `k` of `view` on a canvas, one canvas pixel per picture pixel (CSS scales it).
fn picture_view(state: AppState, slot: &'static MethodSlot, view: Arc<MethodView>, k: usize) -> impl IntoView {
    let view_of_canvas = view.clone();
    // a picture of frame pairs (the SSSM): a click goes to the row's frame and offers the column's
    let pair = RwSignal::new(None::<(usize, usize)>);
    let pairs = p_pairs(&view, k);
    let view_of_click = view.clone();
    let on_pick = move |ev: MouseEvent| {
        let p = &view_of_click.details.pictures[k];
        let Some(canvas) = ev.target().and_then(|t| t.dyn_into::<HtmlCanvasElement>().ok()) else { return };
        let (w, h) = (canvas.client_width().max(1) as f64, canvas.client_height().max(1) as f64);
        let x = ((ev.offset_x() as f64 / w) * p.width as f64).floor().max(0.0) as usize;
        let y = ((ev.offset_y() as f64 / h) * p.height as f64).floor().max(0.0) as usize;
        let frames = view_of_click.segmentation.frames;
        if let (Some(i), Some(j)) = (p.frame_at(y, frames), p.frame_at(x, frames)) {
            state.playing.set(false);
            state.frame.set(i);
            pair.set(Some((i, j)));
        }
    };
    let fps = view.segmentation.fps;
    let pair_text = move || {
        pair.get().map(|(i, j)| {
            format!(
                "frame {} ↔ frame {} ({:.2} s ↔ {:.2} s): at frame {} now",
                i + 1,
                j + 1,
                i as f64 / fps,
                j as f64 / fps,
                i + 1
            )
        })
    };
    let p: &Picture = &view.details.pictures[k];
    let id = format!("{}-{}", slot.info.name, p.id);
    let (title, caption) = (p.title.clone(), p.caption.clone());
    let canvas_ref = NodeRef::<Canvas>::new();
    Effect::new(move |_| {
        if let Some(canvas) = canvas_ref.get() {
            if let Err(e) = draw_picture(&canvas, &view_of_canvas.details.pictures[k]) {
                web_sys::console::error_2(&"could not draw a picture".into(), &e);
            }
        }
    });
    let png_id = format!("{id}-png");
    let on_png = move |_| {
        let p = &view.details.pictures[k];
        let file = format!("{}_{}_{}.png", stem(&view.segmentation.file), slot.info.name, p.id);
        let saved = p
            .to_png()
            .map_err(|e| e.to_string())
            .and_then(|png| download(&png, "image/png", &file).map_err(|e| format!("{e:?}")));
        slot.export_status.set(Some(match saved {
            Ok(()) => (false, format!("saved {file}")),
            Err(e) => (true, format!("could not save {file}: {e}")),
        }));
    };
    let pair_id = format!("{id}-pair");
    let other_id = format!("{id}-pair-other");
    let go_other = move |_| {
        if let Some((i, j)) = pair.get_untracked() {
            state.playing.set(false);
            state.frame.set(j);
            pair.set(Some((j, i)));
        }
    };
    view! {
        <figure class="ms-method-figure">
            <canvas
                id=id
                class="ms-method-picture"
                class:ms-method-picture--pairs=pairs
                node_ref=canvas_ref
                aria-label=title.clone()
                title=pairs.then_some("Click a pixel to go to its pair of frames")
                on:click=move |ev| if pairs { on_pick(ev) }
            ></canvas>
            <p id=pair_id class="ms-picture-pair" role="status" aria-live="polite" hidden=move || pair.with(Option::is_none)>
                {pair_text}" "
                <button id=other_id class="ms-button ms-button--quiet ms-button--small" type="button" on:click=go_other>
                    "Go to the other frame"
                </button>
            </p>
            <figcaption class="ms-method-legend">
                <strong>{title.clone()}". "</strong>{caption}" "
                <button id=png_id class="ms-button ms-button--quiet ms-button--small" type="button"
                    aria-label=format!("Save {title} as PNG") on:click=on_png>"PNG"</button>
            </figcaption>
        </figure>
    }
}

/// Whether picture `k` of `view` is of frame pairs (clickable).
fn p_pairs(view: &MethodView, k: usize) -> bool {
    view.details.pictures[k].frames_per_pixel.is_some()
}

fn draw_picture(canvas: &HtmlCanvasElement, p: &Picture) -> Result<(), JsValue> {
    canvas.set_width(p.width as u32);
    canvas.set_height(p.height as u32);
    if p.width == 0 || p.height == 0 {
        return Ok(());
    }
    let ctx: CanvasRenderingContext2d = canvas.get_context("2d")?.ok_or("no 2d context")?.dyn_into()?;
    let pixels =
        web_sys::ImageData::new_with_u8_clamped_array_and_sh(Clamped(&p.rgba), p.width as u32, p.height as u32)?;
    ctx.put_image_data(&pixels, 0.0, 0.0)
}
