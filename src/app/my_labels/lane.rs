//! `#row-my-labels` on the timeline ([`MyLabelsRow`]): my segments in the window, coloured as the other rows
//! colour their labels, each a button that selects it, and the handles of their boundaries, with the Effort
//! bars of my segments under the row.

use crate::app::effort::bars::EffortLane;
use crate::app::my_labels::row::{MyRow, ROW};
use crate::app::my_labels::spans::LabelSpan;
use crate::app::state::AppState;
use crate::app::timeline::window::{visible_segments, Window};
use leptos::ev::{KeyboardEvent, MouseEvent, PointerEvent};
use leptos::prelude::*;
use std::collections::HashMap;
use std::sync::Arc;

/// At most about twice this many of my segments are in the DOM at once.
const MAX_SEGMENTS: usize = 120;

/// The colour of my label `label`: the one another row draws it in (the first that has it;
/// `None`: hatched there too), else a class colour of its own.
fn colour_of(state: AppState, label: &str, known: &HashMap<String, Option<String>>) -> Option<String> {
    match known.get(label) {
        Some(colour) => colour.clone(),
        None => Some(state.label_css(label)),
    }
}

/// My segment `i`, `s` (`selected`: the one selected), in the window `w`, coloured as the other rows colour its label
/// (`known`), its tip in seconds at `fps`: click to select it, the playhead where clicked.
fn my_segment(
    mine: MyRow,
    i: usize,
    s: LabelSpan,
    selected: bool,
    w: &Window,
    known: &HashMap<String, Option<String>>,
    fps: f64,
) -> impl IntoView {
    let colour = (!s.label.is_empty()).then(|| colour_of(mine.state, &s.label, known)).flatten();
    let class = match (s.label.is_empty(), &colour) {
        (true, _) => "ms-seg ms-seg--mine ms-seg--unlabelled",
        (false, None) => "ms-seg ms-seg--mine ms-seg--transition",
        (false, Some(_)) => "ms-seg ms-seg--mine ms-seg--coloured",
    };
    let left = w.fraction(s.start as f64).max(0.0);
    let right = w.fraction((s.end + 1) as f64).min(1.0);
    let text = if s.label.is_empty() { "unlabelled".to_string() } else { s.label.clone() };
    // the label, or a clean abbreviation when it does not fit (in full in the tip)
    let shown = crate::app::timeline::lanes::segment_text(&text, right - left);
    let tip = format!(
        "{text} · frames {}–{} · {:.2}–{:.2} s",
        s.start + 1,
        s.end + 1,
        s.start as f64 / fps,
        (s.end + 1) as f64 / fps
    );
    let (start, end) = (s.start, s.end);
    let on_click = move |ev: MouseEvent| {
        ev.stop_propagation();
        mine.model.update(|m| m.select(Some(i)));
        mine.state.play_until.set(None);
        if let Some((at, _)) = mine.position_at(ev.client_x() as f64) {
            mine.state.frame.set((at.floor().max(0.0) as usize).clamp(start, end));
        }
    };
    view! {
        <div
            class=class
            class:ms-seg--selected=selected
            style:left=format!("{:.4}%", left * 100.0)
            style:width=format!("{:.4}%", (right - left).max(0.0) * 100.0)
            style:color=colour.as_deref().map(crate::app::timeline::contrast::ink_on)
            style:background-color=colour
            data-start=s.start.to_string()
            data-end=s.end.to_string()
            data-label=s.label.clone()
            aria-label=tip
            aria-pressed=selected.to_string()
            role="button"
            on:pointerdown=move |ev: PointerEvent| ev.stop_propagation()
            on:click=on_click
        >
            {shown}
        </div>
    }
}

/// The handle of my boundary before frame `cut` (`left`: where it is, a fraction of the lanes; `active`: being
/// dragged): drag it, or ← / → (Shift: a second) when it has the focus.
fn boundary_handle(mine: MyRow, cut: usize, frames: usize, active: bool, left: f64) -> impl IntoView {
    let label = if cut >= frames {
        format!("End of my last segment, after frame {cut}: drag, or ← / → (Shift: 1 s), to move")
    } else {
        format!("Boundary before frame {}: drag, or ← / → (Shift: 1 s), to move", cut + 1)
    };
    let on_key = move |ev: KeyboardEvent| {
        let step = if ev.shift_key() { mine.state.fps().round().max(1.0) as isize } else { 1 };
        let by = match ev.key().as_str() {
            "ArrowLeft" => -step,
            "ArrowRight" => step,
            _ => return,
        };
        if ev.ctrl_key() || ev.meta_key() || ev.alt_key() {
            return;
        }
        // the timeline's own ← / → (a frame, a second) must not act as well
        ev.prevent_default();
        ev.stop_propagation();
        mine.nudge(cut, by);
    };
    view! {
        <div
            class="ms-my-handle"
            class:ms-my-handle--active=active
            style:left=format!("{:.4}%", left * 100.0)
            data-cut=cut.to_string()
            role="separator"
            aria-orientation="vertical"
            tabindex="0"
            aria-valuemin="1"
            aria-valuemax=(frames + 1).to_string()
            aria-valuenow=(cut + 1).to_string()
            aria-label=label.clone()
            title=label
            on:pointerdown=move |ev: PointerEvent| mine.grab(cut, &ev)
            on:keydown=on_key
        ></div>
    }
}

/// `#row-my-labels` on the timeline.
#[component]
pub fn MyLabelsRow(mine: MyRow) -> impl IntoView {
    let state = mine.state;
    let known = Memo::new(move |_| {
        let mut map = HashMap::new();
        mine.others.with(|rows| {
            for r in rows {
                for s in &r.segments {
                    map.entry(s.2.clone()).or_insert_with(|| s.3.clone());
                }
            }
        });
        map
    });
    let fps = move || state.fps().max(f64::MIN_POSITIVE);
    let segments = move || {
        let w = state.window.get();
        let known = known.get();
        let fps = fps();
        mine.model.with(|m| {
            let spans: Vec<(usize, usize)> = m.spans().iter().map(|s| (s.start, s.end)).collect();
            visible_segments(&spans, &w, MAX_SEGMENTS)
                .into_iter()
                .map(|i| my_segment(mine, i, m.spans()[i].clone(), m.selected() == Some(i), &w, &known, fps))
                .collect_view()
        })
    };
    let handles = move || {
        let w = state.window.get();
        let active = mine.dragging.get();
        let frames = state.frames();
        mine.model.with(|m| {
            // the boundaries of the segments on screen only (a long take's row stays light)
            let spans: Vec<(usize, usize)> = m.spans().iter().map(|s| (s.start, s.end)).collect();
            let mut cuts: Vec<usize> = visible_segments(&spans, &w, MAX_SEGMENTS)
                .into_iter()
                .flat_map(|i| [spans[i].0, spans[i].1 + 1])
                .filter(|c| (*c as f64) >= w.start && (*c as f64) <= w.end)
                .collect();
            cuts.dedup();
            cuts.into_iter()
                .map(|cut| boundary_handle(mine, cut, frames, active == Some(cut), w.fraction(cut as f64)))
                .collect_view()
        })
    };
    let empty = move || mine.model.with(|m| m.spans().is_empty());
    let count = move || mine.model.with(|m| m.spans().len());
    // my segments' frames, for the Effort bars under the row (a new list only when they change)
    let my_spans =
        Memo::new(move |_| mine.model.with(|m| m.spans().iter().map(|s| (s.start, s.end)).collect::<Vec<_>>()));
    let effort_spans = Signal::derive(move || Arc::new(my_spans.get()));
    view! {
        <div class="ms-tl-line ms-tl-line--row ms-tl-line--mine" hidden=move || state.motion.with(Option::is_none)>
            <div class="ms-tl-label" title="My labels: your own segments, edited here">"My labels"</div>
            <div
                id="row-my-labels"
                class="ms-row ms-row--mine ms-tl-lane"
                node_ref=mine.lane
                data-segments=move || count().to_string()
                data-dragging=move || mine.dragging.get().is_some().to_string()
                role="group"
                aria-label="My labels"
                title="Click one of my segments to select it (the playhead goes where you click, nothing plays); drag a boundary to move it"
            >
                <span class="ms-my-empty" hidden=move || !empty()>
                    "No labels of mine yet: copy a row or start empty with the tools below the timeline"
                </span>
                {segments}
                {handles}
            </div>
        </div>
        <EffortLane state=state row_id=ROW.to_string() spans=effort_spans label=Signal::derive(|| "my labels".to_string())/>
    }
}
