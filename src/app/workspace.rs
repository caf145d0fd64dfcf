//! The studio's workspace (issue 27): the player and the timeline pinned at the left, one side
//! panel at the right with a tab per place the user tweaks and reads — "Truth & scores" (the
//! ground truth, its metrics and the comparison table) and one tab per method (its form, Run,
//! exports, pictures) — so that tweak → Run → look never scrolls the page.
//!
//! * `#studio` fills the window under the header (`www/style.css`, `.ms-studio`): `#stage` holds
//!   the player, `#stage-splitter` and the timeline; `#side-splitter` sits between the stage and
//!   `#side-panel`. Both splitters are ARIA window splitters (`role="separator"`, focusable,
//!   `aria-valuenow` in per cent): dragging moves them, ← / → (the side panel's width) or ↑ / ↓ (the
//!   player's height) move them by [`STEP`] per cent, Home / End to their limits. Where they stand is
//!   kept in the browser's local storage ([`PLAYER_KEY`], [`SIDE_KEY`]) and restored on the next visit.
//! * `#side-panel` has a `role="tablist"` of buttons `#tab-<id>` (`role="tab"`, `aria-selected`,
//!   `aria-controls`, roving `tabindex`: ← / → / ↑ / ↓ select the previous / next tab, Home / End the
//!   first / last), and one `#tabpanel-<id>` (`role="tabpanel"`) each, only the selected one shown.
//!   `data-panel` on `#side-panel` names the tab shown (`state.panel`). The ids are [`TRUTH_TAB`]
//!   and each method's name, and `library` (the library of takes, [`crate::app::library::panel`]) last, there
//!   only once the library has a take.
//! * Selecting a method's tab, pressing its Run, and each of its runs finishing while its tab is
//!   shown, scroll the timeline (never the page) so that the method's row is in view.
//!
//! Narrower than 860 px the side panel goes under the stage, which stays pinned at the top
//! (`position: sticky`), so that the timeline is still on screen beside a panel's controls.

use crate::app::state::{AppState, TRUTH_TAB};
use leptos::ev::{KeyboardEvent, PointerEvent};
use leptos::prelude::*;
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;

/// Where the player's height (per cent of the stage) is kept in local storage.
pub const PLAYER_KEY: &str = "mocapseg.layout.player";
/// Where the side panel's width (per cent of the studio) is kept in local storage.
pub const SIDE_KEY: &str = "mocapseg.layout.side";

/// One arrow key moves a splitter by this many per cent.
const STEP: f64 = 2.0;

/// The player's share of the stage's height, per cent: default and limits.
const PLAYER: (f64, f64, f64) = (40.0, 15.0, 75.0);
/// The side panel's share of the studio's width, per cent: default and limits.
const SIDE: (f64, f64, f64) = (36.0, 22.0, 60.0);

#[wasm_bindgen]
extern "C" {
    /// The Web Storage interface (`localStorage`), bound here rather than through a web-sys
    /// feature the crate does not turn on (as `my_labels` does).
    type LayoutStorage;
    #[wasm_bindgen(method, catch, js_name = getItem)]
    fn get_item(this: &LayoutStorage, key: &str) -> Result<Option<String>, JsValue>;
    #[wasm_bindgen(method, catch, js_name = setItem)]
    fn set_item(this: &LayoutStorage, key: &str, value: &str) -> Result<(), JsValue>;
}

fn storage() -> Option<LayoutStorage> {
    let window = web_sys::window()?;
    let value = js_sys::Reflect::get(&window, &JsValue::from_str("localStorage")).ok()?;
    (!value.is_null() && !value.is_undefined()).then(|| value.unchecked_into())
}

/// The stored split under `key`, if it is a number within `(min, max)`; else `None` (the default).
fn stored(key: &str, (_, min, max): (f64, f64, f64)) -> Option<f64> {
    let text = storage()?.get_item(key).ok()??;
    text.trim().parse::<f64>().ok().filter(|v| v.is_finite() && (min..=max).contains(v))
}

/// Keeps a split; a browser that refuses (private mode, full storage) keeps it for this visit only.
fn store(key: &str, value: f64) {
    if let Some(s) = storage() {
        let _ = s.set_item(key, &format!("{value:.1}"));
    }
}

/// The text kept under `key` in local storage, if the browser gives the page any.
pub(super) fn storage_get(key: &str) -> Option<String> {
    storage()?.get_item(key).ok()?
}

/// Keeps `value` under `key` in local storage (silently not, where the browser refuses).
pub(super) fn storage_set(key: &str, value: &str) {
    if let Some(s) = storage() {
        let _ = s.set_item(key, value);
    }
}

/// Tells the canvases (player, motion image, minimap) that their size changed: they redraw on
/// the window's `resize`.
fn announce_resize() {
    if let (Some(window), Ok(event)) = (web_sys::window(), web_sys::Event::new("resize")) {
        let _ = window.dispatch_event(&event);
    }
}

/// Which way a splitter moves.
#[derive(Clone, Copy, PartialEq)]
enum Axis {
    /// Up and down: the player's height in the stage.
    Rows,
    /// Left and right: the side panel's width in the studio (growing to the left).
    Columns,
}

/// A window splitter `#<id>` moving `value` (per cent of element `#<container>`'s height or
/// width) within `limits`, kept under `key`.
fn splitter(
    id: &'static str,
    label: &'static str,
    axis: Axis,
    value: RwSignal<f64>,
    limits: (f64, f64, f64),
    key: &'static str,
    container: &'static str,
) -> impl IntoView {
    let (_, min, max) = limits;
    let set = move |v: f64| {
        let v = v.clamp(min, max);
        value.set(v);
        store(key, v);
        announce_resize();
    };
    let dragging = StoredValue::new(false);
    let at_pointer = move |ev: &PointerEvent| {
        let Some(el) = gloo::utils::document().get_element_by_id(container) else { return };
        let rect = el.get_bounding_client_rect();
        let v = match axis {
            Axis::Rows if rect.height() > 0.0 => (ev.client_y() as f64 - rect.top()) / rect.height() * 100.0,
            Axis::Columns if rect.width() > 0.0 => (rect.right() - ev.client_x() as f64) / rect.width() * 100.0,
            _ => return,
        };
        set(v);
    };
    let on_down = move |ev: PointerEvent| {
        if ev.button() != 0 {
            return;
        }
        ev.prevent_default();
        dragging.set_value(true);
        if let Some(el) = ev.current_target().and_then(|t| t.dyn_into::<web_sys::Element>().ok()) {
            let _ = el.set_pointer_capture(ev.pointer_id());
        }
    };
    let on_move = move |ev: PointerEvent| {
        if dragging.get_value() {
            at_pointer(&ev);
        }
    };
    let on_up = move |_: PointerEvent| dragging.set_value(false);
    let on_key = move |ev: KeyboardEvent| {
        let v = value.get_untracked();
        // ↑ makes the player shorter; ← makes the side panel (at the right) wider
        let next = match (axis, ev.key().as_str()) {
            (Axis::Rows, "ArrowUp") | (Axis::Columns, "ArrowRight") => v - STEP,
            (Axis::Rows, "ArrowDown") | (Axis::Columns, "ArrowLeft") => v + STEP,
            (_, "Home") => min,
            (_, "End") => max,
            _ => return,
        };
        ev.prevent_default();
        ev.stop_propagation();
        set(next);
    };
    let orientation = if axis == Axis::Rows { "horizontal" } else { "vertical" };
    let class = if axis == Axis::Rows { "ms-splitter ms-splitter--rows" } else { "ms-splitter ms-splitter--columns" };
    view! {
        <div
            id=id
            class=class
            role="separator"
            tabindex="0"
            aria-label=label
            aria-orientation=orientation
            aria-valuemin=min.to_string()
            aria-valuemax=max.to_string()
            aria-valuenow=move || format!("{:.0}", value.get())
            on:pointerdown=on_down
            on:pointermove=on_move
            on:pointerup=on_up
            on:pointercancel=on_up
            on:keydown=on_key
        ></div>
    }
}

/// `#studio`: `stage` (the player and the timeline) with its splitter, the side splitter and
/// `side` (the side panel). `full` is false in embed mode: the stage alone, no splitters.
#[component]
pub fn Studio(player: AnyView, timeline: AnyView, side: Option<AnyView>) -> impl IntoView {
    let player_split = RwSignal::new(stored(PLAYER_KEY, PLAYER).unwrap_or(PLAYER.0));
    let side_split = RwSignal::new(stored(SIDE_KEY, SIDE).unwrap_or(SIDE.0));
    let full = side.is_some();
    let stage_splitter = full
        .then(|| splitter("stage-splitter", "Player height", Axis::Rows, player_split, PLAYER, PLAYER_KEY, "stage"));
    let side_splitter = full
        .then(|| splitter("side-splitter", "Side panel width", Axis::Columns, side_split, SIDE, SIDE_KEY, "studio"));
    view! {
        <main
            id="studio"
            class="ms-studio"
            class:ms-studio--full=full
            // the splits, set as the grid's tracks (inline: the page's CSP allows styles set
            // through the CSSOM); a narrow window stacks the panel under the stage (style.css)
            style:grid-template-columns=move || {
                full.then(|| format!("minmax(0, 1fr) 10px minmax(300px, {:.1}%)", side_split.get()))
            }
        >
            <div
                id="stage"
                class="ms-stage ms-workspace"
                style:grid-template-rows=move || {
                    full.then(|| format!("minmax(100px, {:.1}%) 10px minmax(0, 1fr)", player_split.get()))
                }
            >
                {player}
                {stage_splitter}
                {timeline}
            </div>
            {side_splitter}
            {side}
        </main>
    }
}

/// The ids and titles of the side panel's tabs: the truth's, then each method's.
pub fn tabs(state: AppState) -> Vec<(String, String)> {
    std::iter::once((TRUTH_TAB.to_string(), "Truth & scores".to_string()))
        .chain(state.methods.iter().map(|s| (s.info.name.clone(), s.info.short.clone())))
        .collect()
}

/// How many tabs are always there (the library's comes after them).
fn tabs_count(state: AppState) -> usize {
    1 + state.methods.len()
}

/// Focuses element `#id`, if there is one.
fn focus(id: &str) {
    if let Some(el) =
        gloo::utils::document().get_element_by_id(id).and_then(|e| e.dyn_into::<web_sys::HtmlElement>().ok())
    {
        let _ = el.focus();
    }
}

/// Scrolls the timeline (`#timeline`, which scrolls inside the stage; never the page) so that row
/// `#row-<row>` is in view under its pinned ruler; a row not shown (no result yet) leaves it alone.
pub fn reveal_row(row: &str) {
    let document = gloo::utils::document();
    let (Some(timeline), Some(el)) =
        (document.get_element_by_id("timeline"), document.get_element_by_id(&format!("row-{row}")))
    else {
        return;
    };
    let (outer, inner) = (timeline.get_bounding_client_rect(), el.get_bounding_client_rect());
    if inner.height() <= 0.0 {
        return;
    }
    // the ruler pinned at the top and the minimap at the bottom hide what is under them
    let height = |id: &str| document.get_element_by_id(id).map_or(0.0, |r| r.get_bounding_client_rect().height());
    let top = outer.top() + height("timeline-ruler") + 8.0;
    let bottom = outer.bottom() - height("timeline-minimap") - 8.0;
    if inner.top() < top {
        timeline.set_scroll_top(timeline.scroll_top() - (top - inner.top()).ceil() as i32);
    } else if inner.bottom() > bottom {
        timeline.set_scroll_top(timeline.scroll_top() + (inner.bottom() - bottom).ceil() as i32);
    }
}

/// The row a method's tab brings into view: its actions (or labels) row, else its primitives'.
pub(super) fn reveal_method(name: &str) {
    let document = gloo::utils::document();
    let shown = |row: &str| {
        document
            .get_element_by_id(&format!("row-{row}"))
            .and_then(|e| e.parent_element())
            .is_some_and(|line| !line.has_attribute("hidden"))
    };
    let actions = format!("{name}-actions");
    let row = if shown(&actions) { actions } else { format!("{name}-primitives") };
    reveal_row(&row);
}

/// `#side-panel`: the tabs and their panels (`panels`, in the order of [`tabs`]), and the
/// library's tab last (`library`), there only while the library has a take.
#[component]
pub fn SidePanel(state: AppState, panels: Vec<AnyView>, library: AnyView) -> impl IntoView {
    let tabs = tabs(state);
    let fixed: Vec<String> = tabs.iter().map(|(id, _)| id.clone()).collect();
    let library_shown = move || state.library.shown();
    // the tabs the arrow keys go through: the library's too while it is shown
    let ids = move || {
        let mut ids = fixed.clone();
        if library_shown() {
            ids.push(crate::app::library::state::TAB.to_string());
        }
        ids
    };
    let on_tab_key = move |i: usize, ev: KeyboardEvent| {
        let ids = ids();
        let n = ids.len();
        let to = match ev.key().as_str() {
            "ArrowRight" | "ArrowDown" => (i + 1) % n,
            "ArrowLeft" | "ArrowUp" => (i + n - 1) % n,
            "Home" => 0,
            "End" => n - 1,
            _ => return,
        };
        ev.prevent_default();
        ev.stop_propagation();
        state.panel.set(ids[to].clone());
        focus(&format!("tab-{}", ids[to]));
    };
    // a method's tab chosen, or its run finishing while shown: its row comes into view (after
    // the row is drawn)
    Effect::new(move |_| {
        let id = state.panel.get();
        if let Some(slot) = state.methods.iter().find(|s| s.info.name == id) {
            slot.view.track();
            let name = slot.info.name.clone();
            gloo::timers::callback::Timeout::new(0, move || reveal_method(&name)).forget();
        }
    });
    let buttons = tabs
        .iter()
        .enumerate()
        .map(|(i, (id, title))| {
            let on_tab_key = on_tab_key.clone();
            let selected = {
                let id = id.clone();
                Memo::new(move |_| state.panel.with(|p| *p == id))
            };
            let on_key = move |ev: KeyboardEvent| on_tab_key(i, ev);
            tab_button(state, id.clone(), title.clone(), move || selected.get(), on_key)
        })
        .collect_view();
    let panels = tabs
        .into_iter()
        .zip(panels)
        .map(|((id, _), panel)| {
            let shown = {
                let id = id.clone();
                move || state.panel.with(|p| *p == id)
            };
            tab_panel(id, move || !shown(), panel)
        })
        .collect_view();
    let library_index = tabs_count(state);
    let library_selected = move || state.panel.with(|p| p == crate::app::library::state::TAB);
    let library_button = move || {
        let on_tab_key = on_tab_key.clone();
        library_shown().then(|| {
            let on_key = move |ev: KeyboardEvent| on_tab_key(library_index, ev);
            tab_button(
                state,
                crate::app::library::state::TAB.to_string(),
                "Library".to_string(),
                library_selected,
                on_key,
            )
        })
    };
    let library_panel = tab_panel(
        crate::app::library::state::TAB.to_string(),
        move || !(library_selected() && library_shown()),
        library,
    );
    view! {
        <aside id="side-panel" class="ms-side" aria-label="Methods, ground truth and scores" data-panel=move || state.panel.get()>
            <div class="ms-tabs" role="tablist" aria-label="Side panel">{buttons}{library_button}</div>
            {panels}
            {library_panel}
        </aside>
    }
}

/// One tab of the side panel's tab list: `selected` says whether it is the one shown, a click shows panel `id`, a
/// key moves along the tabs (`on_key`).
fn tab_button(
    state: AppState,
    id: String,
    title: String,
    selected: impl Fn() -> bool + Copy + Send + Sync + 'static,
    on_key: impl FnMut(KeyboardEvent) + 'static,
) -> impl IntoView {
    let choose = {
        let id = id.clone();
        move |_| state.panel.set(id.clone())
    };
    view! {
        <button
            id=format!("tab-{id}")
            class="ms-tab"
            type="button"
            role="tab"
            aria-selected=move || selected().to_string()
            aria-controls=format!("tabpanel-{id}")
            tabindex=move || if selected() { "0" } else { "-1" }
            on:click=choose
            on:keydown=on_key
        >
            {title}
        </button>
    }
}

/// The panel of tab `id`, holding `content`, hidden while `hidden` says so.
fn tab_panel(id: String, hidden: impl Fn() -> bool + Send + Sync + 'static, content: AnyView) -> impl IntoView {
    view! {
        <div
            id=format!("tabpanel-{id}")
            class="ms-tabpanel"
            role="tabpanel"
            aria-labelledby=format!("tab-{id}")
            tabindex="0"
            hidden=hidden
        >
            {content}
        </div>
    }
}
