//! The Effort bars under every timeline row (the paper's conclusion, §6: LMA as a semantic layer
//! over segments). `#effort-toggle` in the timeline's controls (a toggle button, `aria-pressed`;
//! kept in local storage under [`EFFORT_KEY`]) shows under each row with segments — every method's
//! rows, the ground truth and my labels — a lane `#effort-<row>` of four thin bars per segment
//! (`.ms-effort-seg`, top to bottom Space, Time, Weight, Flow), each coloured from indulging (blue)
//! through neutral to condensing (red) as LMA's own Effort picture is; a segment outside the
//! lengths the classifiers learnt is hatched (`ms-effort-seg--extrapolated`) and its text says so.
//! Each segment's text ([`crate::app::effort::layout::text`]) is its accessible name and the timeline's
//! tooltip over it. `#effort-legend` explains the colours, `#effort-status` says what is being
//! computed (or fetched) and what failed.
//!
//! Who computes is declared, never named: the first method whose [`crate::method::Annotator`] is
//! set (LMA), with the parameters it declares read from its form (its `model` choice: the shipped
//! family by default, or one of the user's). Each row's segments go to the worker as one `annotate`
//! request ([`crate::app::effort::jobs::EffortJobs::annotate`]) once they have settled ([`SETTLE_MS`]: my labels
//! being dragged ask once, when the drag stops), and the answer is kept under
//! [`crate::app::effort::layout::cache_key`] (take, method, parameters, segments) for the take's life: a
//! row drawn again, the window moved or another row with the same segments never asks twice. A
//! lane keeps its last bars while new ones are computed (`data-pending="true"` meanwhile). A row's
//! segmentation JSON export carries the Effort computed ([`EffortBars::fill`]).

use crate::app::effort::layout::{cache_key, legend, Bars};
use crate::app::effort::state::EffortBars;
use crate::app::state::AppState;
use crate::app::timeline::window::visible_segments;
use crate::app::workspace::{storage_get, storage_set};
use crate::method::Annotator;
use crate::segment::Segmentation;
use gloo::timers::callback::Timeout;
use leptos::prelude::*;
use std::collections::HashMap;
use std::sync::Arc;

/// Where the toggle is kept in local storage.
pub const EFFORT_KEY: &str = "mocapseg.view.effort";

/// A row's segments are sent this long after they last changed (milliseconds).
pub const SETTLE_MS: u32 = 300;

/// At most about twice this many segments of a lane are in the DOM at once.
const MAX_SEGMENTS: usize = 120;

impl EffortBars {
    /// `segmentation` with the Effort the bars computed for its segments (those without one of
    /// their own), for its JSON export.
    pub fn fill(&self, state: AppState, segmentation: &Segmentation) -> Segmentation {
        let mut out = segmentation.clone();
        if let Some((slot, annotator)) = annotator(state) {
            if let Ok(params) = annotator_params(slot, &annotator, false) {
                crate::app::effort::layout::fill(&mut out, &self.known(&params));
            }
        }
        out
    }
}

/// The method that annotates segments (the first that declares it), with its declaration.
pub fn annotator(state: AppState) -> Option<(&'static crate::app::state::MethodSlot, Annotator)> {
    state.methods.iter().find_map(|s| s.annotator.clone().map(|a| (s, a)))
}

/// The parameters `annotator` reads, from its method's form (`tracked`: re-read when they change).
fn annotator_params(
    slot: &'static crate::app::state::MethodSlot,
    annotator: &Annotator,
    tracked: bool,
) -> Result<serde_json::Value, String> {
    let mut specs = Vec::new();
    let mut texts = Vec::new();
    for name in &annotator.params {
        let Some(i) = slot.specs.iter().position(|s| s.name == *name) else { continue };
        specs.push(slot.specs[i].clone());
        texts.push(if tracked { slot.fields[i].get() } else { slot.fields[i].get_untracked() });
    }
    crate::method::form::params_from_form(&slot.info.short, &specs, &texts).map_err(|e| e.to_string())
}

use crate::app::effort::jobs::{EffortJobs, EffortJobsHandle as LoaderHandle};

/// Turns the bars on or off (and keeps the choice); off forgets what was being asked.
fn set_on(state: AppState, loader: LoaderHandle, on: bool) {
    state.effort.on.set(on);
    storage_set(EFFORT_KEY, if on { "1" } else { "0" });
    if !on {
        state.effort.asked.update(HashMap::clear);
        state.effort.status.set(None);
        if let Some(loader) = loader {
            loader.with_value(EffortJobs::drop_all);
        }
    }
}

/// `#effort-toggle`, in the timeline's controls; also restores the stored choice and lets go of a
/// take's bars when the next one is shown.
#[component]
pub fn EffortToggle(state: AppState) -> impl IntoView {
    let bars = state.effort;
    let loader: LoaderHandle = use_context();
    bars.on.set(storage_get(EFFORT_KEY).as_deref() == Some("1"));
    Effect::new(move |_| {
        state.motion.track();
        bars.new_take();
    });
    let present = annotator(state).is_some();
    let title = annotator(state).map_or_else(String::new, |(slot, a)| {
        format!(
            "{} bars under every row: Space, Time, Weight and Flow of each segment, by {}",
            a.quality, slot.info.short
        )
    });
    present.then(|| {
        view! {
            <button
                id="effort-toggle"
                class="ms-button ms-button--quiet ms-toggle"
                type="button"
                aria-pressed=move || bars.on.get().to_string()
                title=title.clone()
                aria-label=title
                disabled=move || state.frames() == 0
                on:click=move |_| set_on(state, loader, !bars.on.get_untracked())
            >
                "Effort"
            </button>
        }
    })
}

/// `#effort-legend` and `#effort-status`, under the timeline's head while the bars are shown.
#[component]
pub fn EffortLegend(state: AppState) -> impl IntoView {
    let bars = state.effort;
    let by = move || {
        bars.entries.with(|e| e.values().find_map(|e| e.result.as_ref().ok().map(|a| (a.by.clone(), a.learnt_s))))
    };
    let learnt = move || {
        by().and_then(|(_, l)| l).map(|[lo, hi]| {
            format!("Hatched: a segment shorter than {lo:.2} s or longer than {hi:.2} s (the lengths the classifiers learnt): its Effort is extrapolated.")
        })
    };
    let swatch = |v: f64| crate::app::effort::layout::css_colour(v);
    view! {
        <div id="effort-legend" class="ms-effort-legend" hidden=move || !bars.on.get() role="note" aria-label="Effort bars: legend">
            <span class="ms-effort-legend-title">
                {move || format!("Effort{} — four bars per segment, top to bottom:", by().map(|(b, _)| format!(" ({b})")).unwrap_or_default())}
            </span>
            {legend().into_iter().map(|l| view! { <span class="ms-effort-legend-factor">{l}</span> }).collect_view()}
            <span class="ms-effort-legend-scale">
                <span class="ms-effort-swatch" style:background-color=swatch(-1.0)></span>" indulging "
                <span class="ms-effort-swatch" style:background-color=swatch(0.0)></span>" neutral "
                <span class="ms-effort-swatch" style:background-color=swatch(1.0)></span>" condensing"
            </span>
            <span class="ms-effort-legend-learnt" hidden=move || learnt().is_none()>{move || learnt().unwrap_or_default()}</span>
            <span
                id="effort-status"
                class="ms-effort-status"
                class:ms-effort-status--error=move || bars.status.with(|s| s.as_ref().is_some_and(|(e, _)| *e))
                role="status"
                aria-live="polite"
                data-busy=move || bars.asked.with(|a| !a.is_empty()).to_string()
            >
                {move || bars.status.with(|s| s.as_ref().map(|(_, t)| t.clone()).unwrap_or_default())}
            </span>
        </div>
    }
}

/// `#effort-<row_id>`: the bars of the row `row_id` (its segments `spans`, `label` its name),
/// under it while the bars are on and it has segments.
#[component]
pub fn EffortLane(
    state: AppState,
    row_id: String,
    spans: Signal<Arc<Vec<(usize, usize)>>>,
    label: Signal<String>,
) -> impl IntoView {
    let bars = state.effort;
    let loader: LoaderHandle = use_context();
    // the segments once they stopped changing for SETTLE_MS
    let settled = RwSignal::new(Arc::new(Vec::<(usize, usize)>::new()));
    let timer = StoredValue::new_local(None::<Timeout>);
    Effect::new(move |_| {
        let now = spans.get();
        if !bars.on.get() {
            return;
        }
        // a new timer replaces (and so cancels) the one before
        timer.set_value(Some(Timeout::new(SETTLE_MS, move || settled.set(now))));
    });
    // what the lane wants: its key, and what to ask for it
    let wanted = Memo::new(move |_| {
        if !bars.on.get() {
            return None;
        }
        let spans = settled.get();
        let (slot, annotator) = annotator(state)?;
        if spans.is_empty() {
            return None;
        }
        let take = bars.take.get();
        let params = annotator_params(slot, &annotator, true).ok()?;
        Some((cache_key(take, &slot.info.name, &params, &spans), slot.info.name.clone(), params, spans, take))
    });
    Effect::new(move |_| {
        let Some((key, method, params, spans, take)) = wanted.get() else { return };
        if bars.entries.with_untracked(|e| e.contains_key(&key)) || bars.is_asked(key) {
            return;
        }
        let Some(loader) = loader else { return };
        bars.asking(key, (take, params.clone(), spans.clone()));
        loader.with_value(|l| l.annotate(key, method, params, spans.to_vec()));
    });
    // the last bars answered for this lane, kept while new ones are computed
    let shown = RwSignal::new(None::<(u64, Arc<Vec<Bars>>)>);
    Effect::new(move |_| {
        let Some((key, _, _, spans, _)) = wanted.get() else { return };
        let fps = state.fps();
        let found = bars.entries.with(|e| e.get(&key).map(|e| e.result.clone()));
        match found {
            Some(Ok(a)) => shown.set(Some((key, Arc::new(crate::app::effort::layout::bars(&spans, &a, fps))))),
            Some(Err(_)) => shown.set(None),
            None => {}
        }
    });
    // pending: the segments have not settled yet, or their bars are not answered yet
    let pending = move || {
        let unsettled = bars.on.get() && spans.with(|s| settled.with(|t| s != t));
        let want = wanted.with(|w| w.as_ref().map(|w| w.0));
        unsettled || (want.is_some() && shown.with(|s| s.as_ref().map(|s| s.0)) != want)
    };
    let hidden = move || !bars.on.get() || spans.with(|s| s.is_empty());
    let segments = move || {
        let w = state.window.get();
        shown.with(|s| {
            let Some((_, drawn)) = s else { return Vec::new() };
            let spans: Vec<(usize, usize)> = drawn.iter().map(|b| (b.start, b.end)).collect();
            visible_segments(&spans, &w, MAX_SEGMENTS).into_iter().map(|i| drawn[i].clone()).collect()
        })
        .into_iter()
        .map(|b| {
            let left = w.fraction(b.start as f64).max(0.0);
            let right = w.fraction((b.end + 1) as f64).min(1.0);
            let factors = b.values.as_ref().map(|v| {
                v.iter()
                    .map(|(value, colour)| {
                        view! { <span class="ms-effort-bar" style:background-color=colour.clone() data-value=value.to_string()></span> }
                    })
                    .collect_view()
            });
            view! {
                <div
                    class="ms-effort-seg"
                    class:ms-effort-seg--extrapolated=b.extrapolated
                    class:ms-effort-seg--none=b.values.is_none()
                    style:left=format!("{:.4}%", left * 100.0)
                    style:width=format!("{:.4}%", (right - left).max(0.0) * 100.0)
                    data-start=b.start.to_string()
                    data-end=b.end.to_string()
                    role="img"
                    aria-label=b.text.clone()
                >
                    {factors}
                </div>
            }
        })
        .collect_view()
    };
    view! {
        <div class="ms-tl-line ms-tl-line--effort" hidden=hidden>
            <div class="ms-tl-label ms-tl-label--effort" title=move || format!("Effort of {}", label.get())>"Effort"</div>
            <div
                id=format!("effort-{row_id}")
                class="ms-effort ms-tl-lane"
                role="group"
                aria-label=move || format!("Effort of {}", label.get())
                data-pending=move || pending().to_string()
            >
                {segments}
            </div>
        </div>
    }
}
