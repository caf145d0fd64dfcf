//! The methods' rows on the timeline (and the ground truth's and the library's, drawn alike): one row per level of
//! each method's run, its segments in the window, coloured by class or cluster, with their tooltips.

use crate::app::effort::bars::EffortLane;
use crate::app::models::row_model::RowModel;
use crate::app::state::AppState;
use crate::app::state::MethodSlot;
use crate::app::state::RunState;
use crate::app::state::Selection;
use crate::app::timeline::rows::{is_labelling, row_kind, ACTION_LEVELS};
use crate::app::timeline::window::visible_segments;
use crate::protocol::MethodView;
use crate::segment::palette::{action_colour, cluster_colour};
use crate::segment::{Level, Segment};
use leptos::ev::{KeyboardEvent, MouseEvent, PointerEvent};
use leptos::prelude::*;
use std::sync::Arc;

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

const PRIMITIVE_LEVELS: &[Level] = &[Level::Primitive];

/// At most about twice this many segments of a row are in the DOM at once (see
/// [`visible_segments`]); the sample's rows have a few dozen.
const MAX_SEGMENTS_PER_ROW: usize = 120;

/// The segments of `levels` in `v`, sorted by start.
fn row_segments(v: &MethodView, levels: &[Level]) -> Vec<Segment> {
    let mut segments: Vec<Segment> =
        v.segmentation.segments.iter().filter(|s| levels.contains(&s.level)).cloned().collect();
    segments.sort_by_key(|s| s.start);
    segments
}

/// The label of a method's row: "SSSM · actions", "DT-FCN · labels", "LMA · gestures" (one name
/// per row, the same in the metrics menu: [`crate::app::timeline::rows`]).
fn row_label(slot: &MethodSlot, v: Option<&MethodView>, primitive: bool) -> String {
    crate::app::timeline::rows::row_name(&slot.info.short, row_kind(v, primitive))
}

/// Every row with segments, in the page's order: its id (`truth`, `<method>-actions` /
/// `<method>-primitives`) and its segments' frames, sorted by start.
pub fn row_spans(state: AppState) -> Vec<(String, Vec<(usize, usize)>)> {
    let mut rows = state.truth.row_spans();
    for slot in state.methods {
        slot.view.with_untracked(|v| {
            if let Some(v) = v {
                for (level, levels) in [("actions", ACTION_LEVELS), ("primitives", PRIMITIVE_LEVELS)] {
                    let spans: Vec<(usize, usize)> = row_segments(v, levels).iter().map(|s| (s.start, s.end)).collect();
                    if !spans.is_empty() {
                        rows.push((format!("{}-{level}", slot.info.name), spans));
                    }
                }
            }
        });
    }
    rows
}

/// One row's segments, sorted, with the run they come from (made again when the run changes).
#[derive(Clone)]
struct RowData {
    view: Option<Arc<MethodView>>,
    segments: Arc<Vec<Segment>>,
    spans: Arc<Vec<(usize, usize)>>,
    /// Counts the runs, so that a new run's segments never reuse the old run's elements.
    generation: u64,
}

/// The timeline rows of every method with a result: a label at the left, the segments of the
/// timeline's window in the lane (only those, see [`visible_segments`]).
#[component]
pub fn MethodRows(state: AppState) -> impl IntoView {
    state
        .methods
        .iter()
        .enumerate()
        .flat_map(|(index, slot)| [(index, slot, false), (index, slot, true)])
        .map(|(index, slot, primitive)| {
            let levels = if primitive { PRIMITIVE_LEVELS } else { ACTION_LEVELS };
            let row_id = format!("{}-{}", slot.info.name, if primitive { "primitives" } else { "actions" });
            let label = Signal::derive(move || slot.view.with(|v| row_label(slot, v.as_deref(), primitive)));
            let tip = Signal::derive(move || {
                let kind = slot.view.with(|v| row_kind(v.as_deref(), primitive));
                crate::app::timeline::rows::row_tooltip(&slot.info.short, kind)
            });
            let stale = Signal::derive(move || stale_reason(slot));
            // a supervised method's labelling row shows its model and lets the user change it there
            let model = (slot.supervised.is_some() && !primitive).then_some(index);
            view! { <SegmentRow state=state row_id=row_id source=slot.view.into() levels=levels label=label tip=tip stale=stale model=model/> }
        })
        .collect_view()
}

/// Why the result on a method's row is stale: its last run failed (a refused parameter or a
/// failure on the take) and the row still shows the run before; `None` when the row is current.
fn stale_reason(slot: &'static MethodSlot) -> Option<String> {
    if !slot.run.with(|r| matches!(r, RunState::Failed)) || slot.view.with(Option::is_none) {
        return None;
    }
    let reason = slot.field_error.get().map(|(_, m)| m).or_else(|| slot.failure.get()).unwrap_or_default();
    Some(reason)
}

/// One timeline row `#row-<row_id>`: `label` at the left, the segments of `levels` of `source`
/// in the window (hidden while it has none). Method rows and the ground truth's draw alike. A
/// method's row whose last run failed (`stale`: why) keeps the run before, marked
/// `ms-row--stale` with `#row-<row_id>-stale` saying "stale: last run failed — <why>" until a
/// run succeeds.
#[component]
pub fn SegmentRow(
    state: AppState,
    row_id: String,
    source: Signal<Option<Arc<MethodView>>>,
    levels: &'static [Level],
    label: Signal<String>,
    /// What the row is, as its label's tooltip (else the label itself).
    #[prop(optional)]
    tip: Option<Signal<String>>,
    #[prop(optional)] stale: Option<Signal<Option<String>>>,
    /// The method (registry index) whose model choice the row's label shows ([`RowModel`]).
    #[prop(default = None)]
    model: Option<usize>,
) -> impl IntoView {
    let tip = move || tip.map_or_else(|| label.get(), |t| t.get());
    let stale = move || stale.and_then(|s| s.get());
    let stale_text = move || stale().map(|why| format!("stale: last run failed — {why}"));
    let data = RwSignal::new(RowData { view: None, segments: Arc::default(), spans: Arc::default(), generation: 0 });
    Effect::new(move |_| {
        let view = source.get();
        let segments = view.as_ref().map(|v| row_segments(v, levels)).unwrap_or_default();
        let spans = segments.iter().map(|s| (s.start, s.end)).collect();
        let generation = data.with_untracked(|d| d.generation) + 1;
        data.set(RowData { view, segments: Arc::new(segments), spans: Arc::new(spans), generation });
    });
    // a row shows only when its source has segments of its levels
    let hidden = move || data.with(|d| d.segments.is_empty());
    let visible = move || {
        let window = state.window.get();
        data.with(|d| {
            visible_segments(&d.spans, &window, MAX_SEGMENTS_PER_ROW)
                .into_iter()
                .map(|i| (d.generation, i))
                .collect::<Vec<_>>()
        })
    };
    // the row's one stop in the Tab order (a roving tabindex): its selected segment, else its first one in view
    let stop_row = row_id.clone();
    let tab_stop = Memo::new(move |_| {
        let selected = state.selected.with(|x| x.as_ref().filter(|x| x.row == stop_row).map(|x| (x.start, x.end)));
        let window = state.window.get();
        data.with(|d| {
            selected.filter(|span| d.spans.contains(span)).or_else(|| {
                visible_segments(&d.spans, &window, MAX_SEGMENTS_PER_ROW).into_iter().min().map(|i| d.spans[i])
            })
        })
    });
    let row = row_id.clone();
    let segment = move |(_, i): (u64, usize)| {
        let (v, s) = data.with_untracked(|d| (d.view.clone(), d.segments[i].clone()));
        v.map(|v| segment_view(state, &v, s, row.clone(), tab_stop))
    };
    let effort_spans = Signal::derive(move || data.with(|d| d.spans.clone()));
    let effort_row = row_id.clone();
    view! {
        <div class="ms-tl-line ms-tl-line--row" hidden=hidden>
            <div class="ms-tl-label" class:ms-tl-label--model=model.is_some() title=tip>
                <span class="ms-tl-label-name">{label}</span>
                {model.map(|index| view! { <RowModel state=state index=index/> })}
            </div>
            <div
                id=format!("row-{row_id}")
                class="ms-row ms-tl-lane"
                class:ms-row--stale=move || stale().is_some()
                data-label=label
                role="group"
                aria-label=label
            >
                <For each=visible key=|k| *k children=segment/>
                <span
                    id=format!("row-{row_id}-stale")
                    class="ms-row-stale"
                    title=stale_text
                    hidden=move || stale().is_none()
                >
                    {stale_text}
                </span>
            </div>
        </div>
        <EffortLane state=state row_id=effort_row spans=effort_spans label=label/>
    }
}

/// `#rrggbb` as RGB.
fn parse_hex(css: &str) -> Option<[u8; 3]> {
    let hex = css.strip_prefix('#').filter(|h| h.len() == 6 && h.is_ascii())?;
    let byte = |i: usize| u8::from_str_radix(&hex[i..i + 2], 16).ok();
    Some([byte(0)?, byte(2)?, byte(4)?])
}

/// A class colour shaded by confidence: the full colour at 1, towards white as it falls (a
/// third of the colour left at 0).
fn confidence_shade([r, g, b]: [u8; 3], score: f64) -> String {
    let strength = 0.3 + 0.7 * score.clamp(0.0, 1.0);
    let mix = |c: u8| (255.0 - strength * (255.0 - c as f64)).round().clamp(0.0, 255.0) as u8;
    format!("rgb({}, {}, {})", mix(r), mix(g), mix(b))
}

/// How segment `s` of `v` is filled: its class, its colour (a label's one colour shaded by confidence on a labelling
/// row; a cluster's or an action's colour; none where hatched) and the label colour it carries (`data-colour`).
fn segment_fill(state: AppState, v: &MethodView, s: &Segment) -> (&'static str, String, Option<String>) {
    let mut class_colour_of = None;
    let (class, colour) = match (is_labelling(v), s.level, s.cluster) {
        // a labelling method: its class's colour, by confidence; `unknown` hatched grey
        (true, _, cluster) => {
            // one colour per label on every row ([`AppState::label_css`]), not the model's class colour
            let css = cluster.and(Some(&s.label)).filter(|l| !l.is_empty()).map(|l| state.label_css(l));
            match css.and_then(|css| Some((parse_hex(&css)?, css))) {
                Some((rgb, css)) => {
                    class_colour_of = Some(css);
                    ("ms-seg ms-seg--label", confidence_shade(rgb, s.score.unwrap_or(1.0)))
                }
                None => ("ms-seg ms-seg--unknown", String::new()),
            }
        }
        (false, Level::Transition, _) => ("ms-seg ms-seg--transition", String::new()),
        (false, Level::Primitive, Some(c)) => ("ms-seg ms-seg--primitive", cluster_colour(c, s.mirror_of)),
        (false, _, Some(c)) => {
            let [r, g, b] = action_colour(c);
            ("ms-seg ms-seg--action", format!("rgb({r}, {g}, {b})"))
        }
        (false, _, None) => ("ms-seg", "#888".to_string()),
    };
    (class, colour, class_colour_of)
}

/// Segment `s` of `v` on row `row`: drawn, its label fitted, selected by a click or by Enter / Space when it has the
/// focus (it is in the Tab order when it is the row's `tab_stop`; the focus follows the selection along the row).
fn segment_view(
    state: AppState,
    v: &Arc<MethodView>,
    s: Segment,
    row: String,
    tab_stop: Memo<Option<(usize, usize)>>,
) -> impl IntoView {
    let fps = v.segmentation.fps;
    let (class, colour, class_colour_of) = segment_fill(state, v, &s);
    // black or white, whichever reads on the fill (hatched segments: www/style.css)
    let text_colour = (!colour.is_empty()).then(|| crate::app::timeline::contrast::ink_on(&colour));
    let mut tip = tooltip(&s, fps);
    if v.method == crate::app::library::carry::TRANSFERRED && s.cluster.is_some() {
        tip = format!("{tip} · confidence {:.0} %", s.score.unwrap_or(0.0) * 100.0);
    }
    let (start, end) = (s.start, s.end);
    // placed on the timeline's window (a segment reaching past its edges is cut there)
    let left = move || {
        let w = state.window.get();
        format!("{:.4}%", w.fraction(start as f64).max(0.0) * 100.0)
    };
    let width = move || {
        let w = state.window.get();
        let (a, b) = (w.fraction(start as f64).max(0.0), w.fraction((end + 1) as f64).min(1.0));
        format!("{:.4}%", (b - a).max(0.0) * 100.0)
    };
    // the label, or a clean abbreviation when it does not fit (the full one is in the tooltip)
    let label = s.label.clone();
    let text = move || {
        let w = state.window.get();
        let (a, b) = (w.fraction(start as f64).max(0.0), w.fraction((end + 1) as f64).min(1.0));
        crate::app::timeline::lanes::segment_text(&label, (b - a).max(0.0))
    };
    let playing_row = row.clone();
    let playing = Memo::new(move |_| {
        state.occurrence.with(|x| x.as_ref().is_some_and(|x| x.row == playing_row && x.start == start && x.end == end))
    });
    let selected_row = row.clone();
    let selected = Memo::new(move |_| {
        state.selected.with(|x| x.as_ref().is_some_and(|x| x.row == selected_row && x.start == start && x.end == end))
    });
    // keep the timeline's own seek from capturing the pointer (the click must reach us)
    let on_down = move |ev: PointerEvent| ev.stop_propagation();
    let picked = Selection { row: row.clone(), start, end };
    let picked_by_key = picked.clone();
    let on_click = move |ev: MouseEvent| {
        ev.stop_propagation();
        crate::app::player::playback::play_segment(state, picked.clone());
    };
    let on_key = move |ev: KeyboardEvent| {
        if matches!(ev.key().as_str(), "Enter" | " ") {
            ev.prevent_default();
            ev.stop_propagation();
            crate::app::player::playback::play_segment(state, picked_by_key.clone());
        }
    };
    // the selection moved onto this segment ([ / ]) while the focus was on the row: the focus follows it
    let node = NodeRef::<leptos::html::Div>::new();
    let focus_row = row.clone();
    Effect::new(move |_| {
        if !selected.get() {
            return;
        }
        let Some(el) = node.get_untracked() else { return };
        let active = gloo::utils::document().active_element();
        let in_row =
            active.as_ref().and_then(|a| a.parent_element()).is_some_and(|p| p.id() == format!("row-{focus_row}"));
        if in_row && active.as_ref().is_some_and(|a| a.class_list().contains("ms-seg")) {
            let _ = el.focus();
        }
    });
    view! {
        <div
            class=class
            class:ms-seg--selected=selected
            class:ms-seg--playing=playing
            aria-current=move || playing.get().then_some("true")
            style:left=left
            style:width=width
            style:background-color=(!colour.is_empty()).then_some(colour)
            style:color=text_colour
            data-start=start.to_string()
            data-label=s.label.clone()
            data-end=end.to_string()
            data-cluster=s.cluster.map(|c| c.to_string()).unwrap_or_default()
            data-colour=class_colour_of
            data-score=s.score.map(|x| x.to_string())
            aria-label=tip
            aria-pressed=move || selected.get().to_string()
            role="button"
            tabindex=move || if tab_stop.get() == Some((start, end)) { "0" } else { "-1" }
            node_ref=node
            on:pointerdown=on_down
            on:click=on_click
            on:keydown=on_key
        >
            {text}
        </div>
    }
}
