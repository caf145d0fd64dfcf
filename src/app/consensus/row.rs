//! The timeline's "Consensus" row (issue 26): the boundaries where the methods on screen agree, under the methods'
//! rows and above "my labels". The consensus is [`crate::segment::consensus`] (each method's boundaries as the
//! scores read them, grouped within a tolerance, one per method per group, at their median); the words and the
//! kept settings are [`crate::app::consensus::settings`]; this file draws them.
//!
//! * `#row-consensus` shows once at least two methods have a result: one marker `.ms-consensus-mark` per agreed
//!   boundary (`data-frame`: the cut, the first frame after it; `data-count`, `data-of`; `data-mine="true"` when my
//!   labels have that boundary already), its text "3/5" and its tooltip naming the methods. It is made again when
//!   any method's row changes. Only the window's markers are drawn, at most about [`MAX_MARKERS`] (past them, one per
//!   `1 / MAX_MARKERS` of the window, as the methods' rows thin their segments).
//! * Markers are buttons (Tab reaches them): clicking one (or Enter / Space) selects it (`aria-pressed`) and moves
//!   the playhead to it; `#consensus-accept` (or the key A) **accepts** it: the boundary goes into my labels
//!   ([`crate::app::my_labels::row::MyRow::accept_boundary`], splitting my segment there, or starting my labels with it).
//! * `#consensus-tools` (under the timeline): `#consensus-tolerance` (seconds) and `#consensus-min` (methods that
//!   must agree), kept in the browser's local storage ([`STORAGE_KEY`]); `#consensus-status` says how many
//!   boundaries agree, why a setting was refused, or what the last accept did. `data-consensus` on the body: the
//!   number of markers.

use crate::app::consensus::settings::{
    effective_options, from_stored, mark_text, mark_tiers, mark_tooltip, parse_min_methods, parse_tolerance, summary,
    to_stored, MARK_GAP_PX, MARK_TIERS, STORAGE_KEY,
};
use crate::app::my_labels::row::MyRow;
use crate::app::state::AppState;
use crate::app::timeline::keys::is_for_the_field;
use crate::app::timeline::window::visible_segments;
use crate::app::workspace::{storage_get, storage_set};
use crate::segment::consensus::{consensus, Consensus, ConsensusOptions};
use crate::segment::Segmentation;
use leptos::ev::{KeyboardEvent, MouseEvent, PointerEvent};
use leptos::prelude::*;
use std::sync::Arc;

/// At most about this many markers are on screen at once, as a method's row holds its segments
/// ([`visible_segments`]: past it, one per `1 / MAX_MARKERS` of the window); zooming in shows the others.
const MAX_MARKERS: usize = 60;

/// The key that accepts the selected consensus boundary (and its line in the help overlay).
pub const SHORTCUTS: [(&str, &str); 1] =
    [("A", "consensus row: accept the selected boundary into my labels (Tab to a marker, Enter selects it)")];

/// The row's state, shared by the row on the timeline and its tools under it.
#[derive(Clone, Copy)]
pub struct ConsensusRow {
    state: AppState,
    mine: MyRow,
    options: RwSignal<ConsensusOptions>,
    /// The consensus of the methods on screen (`None`: fewer than two have a result), or why there is none.
    result: Memo<Option<Result<Arc<Consensus>, String>>>,
    /// The selected marker's cut.
    selected: RwSignal<Option<usize>>,
    /// What the last accept (or a refused setting) said: (error, text).
    note: RwSignal<Option<(bool, String)>>,
}

impl ConsensusRow {
    pub fn new(state: AppState, mine: MyRow) -> ConsensusRow {
        let options = RwSignal::new(storage_get(STORAGE_KEY).as_deref().and_then(from_stored).unwrap_or_default());
        // embedded, the settings cannot be changed: the minimum never asks for more methods than ran
        let embedded = crate::app::dom::embedded();
        let result = Memo::new(move |_| {
            let runs: Vec<Arc<crate::protocol::MethodView>> =
                state.methods.iter().filter_map(|slot| slot.view.get()).collect();
            if runs.len() < 2 {
                return None;
            }
            let segs: Vec<&Segmentation> = runs.iter().map(|v| &v.segmentation).collect();
            let o = effective_options(options.get(), segs.len(), embedded);
            Some(consensus(&segs, o).map(Arc::new).map_err(|e| e.to_string()))
        });
        let row =
            ConsensusRow { state, mine, options, result, selected: RwSignal::new(None), note: RwSignal::new(None) };
        // a selection that is no longer a boundary (the rows or the settings changed) is dropped
        Effect::new(move |_| {
            let cuts = row.cuts();
            if row.selected.get_untracked().is_some_and(|c| !cuts.contains(&c)) {
                row.selected.set(None);
            }
        });
        // new rows (a run, another take): the status says the new consensus, not the last accept
        Effect::new(move |_| {
            row.result.track();
            row.note.set(None);
        });
        Effect::new(move |_| {
            let n = row.cuts().len();
            if let Some(body) = web_sys::window().and_then(|w| w.document()).and_then(|d| d.body()) {
                let _ = body.set_attribute("data-consensus", &n.to_string());
            }
        });
        row.listen();
        row
    }

    /// The agreed boundaries' cuts (none without a consensus).
    fn cuts(self) -> Vec<usize> {
        self.result.with(|r| match r {
            Some(Ok(c)) => c.boundaries.iter().map(|b| b.frame).collect(),
            _ => Vec::new(),
        })
    }

    fn set_options(self, o: ConsensusOptions) {
        self.options.set(o);
        storage_set(STORAGE_KEY, &to_stored(&o));
        self.note.set(None);
    }

    fn select(self, cut: usize) {
        self.selected.set(Some(cut));
        let frames = self.state.frames();
        if frames > 0 {
            self.state.playing.set(false);
            self.state.frame.set(cut.min(frames - 1));
        }
    }

    /// Puts the selected boundary into my labels.
    fn accept(self) {
        let Some(cut) = self.selected.get_untracked() else {
            self.note
                .set(Some((true, "Select a consensus boundary first (click it, or Tab to it and press Enter)".into())));
            return;
        };
        let agreed = self.result.with_untracked(|r| match r {
            Some(Ok(c)) => c.boundaries.iter().find(|b| b.frame == cut).map(|b| (b.count(), c.methods.len())),
            _ => None,
        });
        let Some((count, of)) = agreed else { return };
        self.note.set(Some(match self.mine.accept_boundary(cut, &format!("{count} of {of} methods")) {
            Ok(()) => (false, format!("Accepted the boundary at frame {} into my labels", cut + 1)),
            Err(why) => (true, format!("Not accepted: {why}")),
        }));
    }

    /// The key A accepts the selected boundary (never while typing in a field).
    fn listen(self) {
        let keys = window_event_listener(leptos::ev::keydown, move |ev: KeyboardEvent| {
            let key = ev.key();
            if ev.default_prevented()
                || is_for_the_field(ev.target(), &key)
                || ev.ctrl_key()
                || ev.meta_key()
                || ev.alt_key()
                || !matches!(key.as_str(), "a" | "A")
                || self.selected.get_untracked().is_none()
            {
                return;
            }
            ev.prevent_default();
            self.accept();
        });
        std::mem::forget(keys); // the row lives as long as the page
    }
}

/// The method's name on the page ("sssm" → "SSSM"), else its registry name.
fn short_name(state: AppState, method: &str) -> String {
    state.methods.iter().find(|s| s.info.name == method).map_or_else(|| method.to_string(), |s| s.info.short.clone())
}

/// `#row-consensus`: a marker per agreed boundary in the timeline's window.
#[component]
pub fn ConsensusLane(row: ConsensusRow) -> impl IntoView {
    let state = row.state;
    let mine_cuts = row.mine.cuts();
    // how many lines the markers take (the row grows to hold them)
    let lines = RwSignal::new(1usize);
    let markers = move || {
        let w = state.window.get();
        let selected = row.selected.get();
        let mine = mine_cuts.get();
        let Some(Ok(c)) = row.result.get() else { return Vec::new() };
        let of = c.methods.len();
        let at: Vec<(usize, usize)> = c.boundaries.iter().map(|b| (b.frame, b.frame)).collect();
        let shown = visible_segments(&at, &w, MAX_MARKERS);
        // markers too close to read side by side go on lines apart
        let width = crate::app::timeline::lanes::lane_px().get();
        let px: Vec<f64> = shown.iter().map(|&i| w.fraction(c.boundaries[i].frame as f64) * width).collect();
        let tiers = mark_tiers(&px, MARK_GAP_PX, MARK_TIERS);
        lines.set(tiers.iter().max().map_or(1, |t| t + 1));
        shown
            .into_iter()
            .zip(tiers)
            .map(|(i, tier)| (&c.boundaries[i], tier))
            .map(|(b, tier)| {
                let cut = b.frame;
                let tip = mark_tooltip(b, of, c.fps, |m| short_name(state, m));
                let in_mine = mine.binary_search(&cut).is_ok();
                let label = if in_mine { format!("{tip} — in my labels") } else { tip };
                view! {
                    <button
                        type="button"
                        class="ms-consensus-mark"
                        class:ms-consensus-mark--selected=selected == Some(cut)
                        class:ms-consensus-mark--mine=in_mine
                        style:left=format!("{:.4}%", w.fraction(cut as f64) * 100.0)
                        style:top=format!("{}px", 2 + 18 * tier)
                        data-tier=tier.to_string()
                        data-frame=cut.to_string()
                        data-count=b.count().to_string()
                        data-of=of.to_string()
                        data-mine=in_mine.to_string()
                        aria-pressed=(selected == Some(cut)).to_string()
                        aria-label=label.clone()
                        title=label
                        on:pointerdown=move |ev: PointerEvent| ev.stop_propagation()
                        on:click=move |ev: MouseEvent| {
                            ev.stop_propagation();
                            row.select(cut);
                        }
                    >
                        {mark_text(b, of)}
                    </button>
                }
            })
            .collect::<Vec<_>>()
    };
    view! {
        <div class="ms-tl-line ms-tl-line--row" hidden=move || row.result.with(Option::is_none)>
            <div class="ms-tl-label" title="Boundaries where the methods above agree: how many of them, within the tolerance set under the timeline">
                <span class="ms-tl-label-name">"Consensus"</span>
            </div>
            <div id="row-consensus" class="ms-row ms-row--consensus ms-tl-lane" role="group" aria-label="Consensus: boundaries where the methods agree"
                style:height=move || format!("{}px", 4 + 18 * lines.get())>
                {markers}
            </div>
        </div>
    }
}

/// `#consensus-tools`: the tolerance, the minimum agreement, Accept and the status line.
#[component]
pub fn ConsensusTools(row: ConsensusRow) -> impl IntoView {
    let tolerance = RwSignal::new(row.options.get_untracked().tolerance_s.to_string());
    let minimum = RwSignal::new(row.options.get_untracked().min_methods.to_string());
    let apply = move || match (parse_tolerance(&tolerance.get_untracked()), parse_min_methods(&minimum.get_untracked()))
    {
        (Ok(tolerance_s), Ok(min_methods)) => row.set_options(ConsensusOptions { tolerance_s, min_methods }),
        (Err(e), _) | (_, Err(e)) => row.note.set(Some((true, format!("Not changed: {e}")))),
    };
    let status = move || match row.note.get() {
        Some((error, text)) => (error, text),
        None => match row.result.get() {
            Some(Ok(c)) => (false, summary(&c)),
            Some(Err(e)) => (true, format!("No consensus: {e}")),
            None => (false, String::new()),
        },
    };
    view! {
        <div id="consensus-tools" class="ms-my-tools ms-consensus-tools" role="toolbar" aria-label="Consensus of the methods"
            hidden=move || row.result.with(Option::is_none)>
            <span class="ms-my-tools-title">"Consensus"</span>
            <div class="ms-my-group" role="group" aria-label="Consensus settings">
                <span>"within"</span>
                <input id="consensus-tolerance" type="number" min="0" max="5" step="0.05" size="5"
                    aria-label="Tolerance in seconds"
                    title="Boundaries of different methods at most this far apart agree (seconds)"
                    bind:value=tolerance on:change=move |_| apply()/>
                <span>"s, at least"</span>
                <input id="consensus-min" type="number" min="1" max="20" step="1" size="3"
                    aria-label="Methods that must agree"
                    title="A boundary shows when at least this many methods agree on it"
                    bind:value=minimum on:change=move |_| apply()/>
                <span>"methods"</span>
            </div>
            <button id="consensus-accept" class="ms-button ms-button--quiet" type="button"
                aria-label="Accept the selected consensus boundary into my labels (A)"
                title="Accept the selected consensus boundary into my labels (A)"
                disabled=move || row.selected.with(Option::is_none)
                on:click=move |_| row.accept()>"Accept into my labels"</button>
            <span id="consensus-status" class="ms-my-status" class:ms-my-status--error=move || status().0 role="status">
                {move || status().1}
            </span>
        </div>
    }
}
