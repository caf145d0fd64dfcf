//! `#segment-menu`: a segment's context menu on the timeline (issue 27). Right-clicking a segment
//! of any row (a long press on a touch screen, where the browser sends the same `contextmenu`
//! event), or the context-menu key / Shift+F10 while a segment is selected, selects it and opens
//! a menu of four actions, each the one the page already has elsewhere:
//!
//! * `#segment-menu-play` — plays it as a click on it does ([`play_segment`]);
//! * `#segment-menu-export` — saves it alone as a BVH clip, as its row's "Selected segment as BVH"
//!   does (the worker cuts it: [`ClipJobs::export_clips_of`]; named after its row);
//! * `#segment-menu-copy` — copies it into "my labels" ([`MyRow::place`]: the parts of my segments
//!   it covers give way; a transition or an unknown stretch comes in unlabelled);
//! * `#segment-menu-show` — switches the side panel to its row's tab (the method's, or "Truth &
//!   scores" for the ground truth; "my labels" has its tools under the timeline: their label field
//!   takes the focus).
//!
//! The menu is a `role="menu"` of `menuitem` buttons: the first takes the focus, ↑ / ↓ move it,
//! Home / End, Enter or Space acts, Esc or Tab closes it (the focus goes back where it was), as
//! does a press outside it. `#segment-menu-status` says what the last action did (`role="status"`).

use crate::app::my_labels::row::MyRow;
use crate::app::player::playback::play_segment;
use crate::app::state::AppState;
use crate::app::state::Selection;
use crate::app::state::TRUTH_TAB;
use crate::app::timeline::clip_jobs::ClipJobs;
use crate::app::timeline::rows::which_of;
use crate::clips::Which;
use leptos::ev::KeyboardEvent;
use leptos::html::Div;
use leptos::prelude::*;
use wasm_bindgen::JsCast;
use web_sys::Element;

/// The row id of "my labels" on the timeline.
const MINE: &str = "my-labels";

/// The menu's items, in order.
const ITEMS: [&str; 4] = ["segment-menu-play", "segment-menu-export", "segment-menu-copy", "segment-menu-show"];

/// The segment a menu is open on, and where (client pixels).
#[derive(Debug, Clone, PartialEq)]
struct Open {
    row: String,
    start: usize,
    end: usize,
    /// Its label ("" for a transition, an unknown or an unlabelled stretch).
    label: String,
    x: f64,
    y: f64,
}

/// The segment element `el` is in, as `(row id, start, end, label)`.
fn segment_of(el: &Element) -> Option<(Element, String, usize, usize, String)> {
    let seg = el.closest(".ms-seg").ok()??;
    let row = seg.closest(".ms-row").ok()??.id().strip_prefix("row-")?.to_string();
    let start = seg.get_attribute("data-start")?.parse().ok()?;
    let end = seg.get_attribute("data-end")?.parse().ok()?;
    let blank =
        ["ms-seg--transition", "ms-seg--unknown", "ms-seg--unlabelled"].iter().any(|c| seg.class_list().contains(c));
    let label = if blank {
        String::new()
    } else {
        seg.get_attribute("data-label").unwrap_or_else(|| seg.text_content().unwrap_or_default()).trim().to_string()
    };
    Some((seg, row, start, end, label))
}

/// The method a row belongs to (`<method>-actions` / `-primitives`), as its index.
fn method_of(state: AppState, row: &str) -> Option<usize> {
    state.methods.iter().position(|s| {
        row.strip_prefix(s.info.name.as_str()).is_some_and(|rest| rest == "-actions" || rest == "-primitives")
    })
}

/// The name a row goes by in messages (the one its label at the left shows).
fn row_title(row: &str) -> String {
    gloo::utils::document()
        .get_element_by_id(&format!("row-{row}"))
        .and_then(|r| r.get_attribute("data-label"))
        .unwrap_or_else(|| row.to_string())
}

fn focus_element(el: Option<Element>) {
    if let Some(el) = el.and_then(|e| e.dyn_into::<web_sys::HtmlElement>().ok()) {
        let _ = el.focus();
    }
}

/// The menu, its status line and its listeners (the timeline's rows' `contextmenu`, the keys).
#[component]
pub fn SegmentMenu(state: AppState, mine: MyRow, rows: NodeRef<Div>) -> impl IntoView {
    let open = RwSignal::new(None::<Open>);
    let status = RwSignal::new(None::<(bool, String)>);
    let back_to = StoredValue::new_local(None::<Element>);

    let show = move |seg: &Element, row: String, start: usize, end: usize, label: String, at: Option<(f64, f64)>| {
        // the menu's segment is the selection (its exports and Loop act on it); nothing plays yet
        state.selected.set(Some(Selection { row: row.clone(), start, end }));
        let rect = seg.get_bounding_client_rect();
        let (x, y) = at.unwrap_or((rect.left() + rect.width().min(40.0) / 2.0, rect.bottom()));
        back_to.set_value(gloo::utils::document().active_element());
        open.set(Some(Open { row, start, end, label, x, y }));
        // the first item takes the focus once drawn
        gloo::timers::callback::Timeout::new(0, move || {
            focus_element(gloo::utils::document().get_element_by_id(ITEMS[0]));
        })
        .forget();
    };
    let close = move |refocus: bool| {
        if open.get_untracked().is_some() {
            open.set(None);
            if refocus {
                focus_element(back_to.get_value());
            }
        }
    };

    listen(state, rows, show, close);

    let loader = use_context::<StoredValue<ClipJobs, LocalStorage>>();
    let act = move |what: &str| {
        let Some(o) = open.get_untracked() else { return };
        close(what != "show");
        let title = row_title(&o.row);
        match what {
            "play" => play_segment(state, Selection { row: o.row.clone(), start: o.start, end: o.end }),
            "export" => export_segment(state, loader, &o, &title, status),
            "copy" => copy_segment(mine, &o, &title, status),
            _ => show_panel(state, &o, &title, status),
        }
    };
    let on_key = move |ev: KeyboardEvent| menu_key(&ev, close);
    let full = !crate::app::dom::embedded();
    let item = move |id: &'static str, what: &'static str, text: &'static str| {
        view! {
            <button id=id class="ms-menu-item" type="button" role="menuitem" tabindex="-1" on:click=move |_| act(what)>
                {text}
            </button>
        }
    };
    // at the pointer, kept inside the window (room: the menu's size, about)
    let place = move |vertical: bool| {
        open.with(|o| {
            o.as_ref().map(|o| {
                let (at, room) = if vertical { (o.y, 170.0) } else { (o.x, 230.0) };
                let limit = web_sys::window()
                    .and_then(|w| if vertical { w.inner_height() } else { w.inner_width() }.ok())
                    .and_then(|v| v.as_f64())
                    .unwrap_or(f64::MAX);
                format!("{}px", at.min(limit - room).max(0.0))
            })
        })
    };
    let heading = move || {
        open.with(|o| {
            o.as_ref()
                .map(|o| {
                    let label = if o.label.is_empty() { "unlabelled".to_string() } else { o.label.clone() };
                    format!("{label} · frames {}–{}", o.start + 1, o.end + 1)
                })
                .unwrap_or_default()
        })
    };
    view! {
        <div
            id="segment-menu"
            class="ms-menu"
            role="menu"
            aria-label=move || format!("Segment {}", heading())
            hidden=move || open.with(Option::is_none)
            data-row=move || open.with(|o| o.as_ref().map(|o| o.row.clone()))
            style:left=move || place(false)
            style:top=move || place(true)
            on:keydown=on_key
        >
            <div class="ms-menu-title" aria-hidden="true">{heading}</div>
            {item("segment-menu-play", "play", "Play")}
            {item("segment-menu-export", "export", "Export clip (BVH)")}
            // embedded: no my labels to copy to, no panels to show
            {full.then(|| item("segment-menu-copy", "copy", "Copy to my labels"))}
            {full.then(|| item("segment-menu-show", "show", "Show in its panel"))}
        </div>
        <p
            id="segment-menu-status"
            class="ms-menu-status"
            class:ms-exports-status--error=move || status.get().is_some_and(|(e, _)| e)
            role="status"
            aria-live="polite"
        >
            {move || status.get().map(|(_, m)| m).unwrap_or_default()}
        </p>
    }
}

/// The menu's keys: ↑ / ↓ / Home / End move among its items, Esc and Tab close it (the focus back where it was),
/// Enter and Space activate the item focused; the page's own keys stay out of the menu.
fn menu_key(ev: &KeyboardEvent, close: impl Fn(bool)) {
    let document = gloo::utils::document();
    let items: Vec<web_sys::HtmlElement> =
        ITEMS.iter().filter_map(|id| document.get_element_by_id(id)?.dyn_into().ok()).collect();
    let active = document.active_element().map(|a| a.id());
    let at = items.iter().position(|i| active.as_deref() == Some(i.id().as_str()));
    let n = items.len().max(1);
    let to = match ev.key().as_str() {
        "ArrowDown" => Some(at.map_or(0, |i| (i + 1) % n)),
        "ArrowUp" => Some(at.map_or(n - 1, |i| (i + n - 1) % n)),
        "Home" => Some(0),
        "End" => Some(n - 1),
        "Escape" | "Tab" => {
            ev.prevent_default();
            ev.stop_propagation();
            close(true);
            return;
        }
        // Enter and Space activate the focused button; the page's keys stay out of the menu
        _ => {
            ev.stop_propagation();
            return;
        }
    };
    ev.prevent_default();
    ev.stop_propagation();
    if let Some(item) = to.and_then(|i| items.get(i)) {
        let _ = item.focus();
    }
}

/// What opens and closes the menu: a right click (a long press) on a segment of any row, the context-menu key or
/// Shift+F10 on the selected segment; a press outside closes it.
fn listen(
    state: AppState,
    rows: NodeRef<Div>,
    show: impl Fn(&Element, String, usize, usize, String, Option<(f64, f64)>) + Copy + 'static,
    close: impl Fn(bool) + Copy + 'static,
) {
    rows.on_load(move |el| {
        let target: &web_sys::EventTarget = el.as_ref();
        gloo::events::EventListener::new_with_options(
            target,
            "contextmenu",
            gloo::events::EventListenerOptions::enable_prevent_default(),
            move |ev| {
                let ev: &web_sys::MouseEvent = ev.unchecked_ref();
                let Some(el) = ev.target().and_then(|t| t.dyn_into::<Element>().ok()) else { return };
                let Some((seg, row, start, end, label)) = segment_of(&el) else { return };
                ev.prevent_default();
                show(&seg, row, start, end, label, Some((ev.client_x() as f64, ev.client_y() as f64)));
            },
        )
        .forget();
    });
    // the context-menu key or Shift+F10 on the selected segment; a press outside closes the menu
    let key = window_event_listener(leptos::ev::keydown, move |ev: KeyboardEvent| {
        let menu_key = ev.key() == "ContextMenu" || (ev.shift_key() && ev.key() == "F10");
        if !menu_key || ev.default_prevented() || crate::app::timeline::keys::is_for_the_field(ev.target(), &ev.key()) {
            return;
        }
        let Some(sel) = state.selected.get_untracked() else { return };
        let selector = format!("#row-{} .ms-seg[data-start=\"{}\"][data-end=\"{}\"]", sel.row, sel.start, sel.end);
        let Some(el) = gloo::utils::document().query_selector(&selector).ok().flatten() else { return };
        let Some((seg, row, start, end, label)) = segment_of(&el) else { return };
        ev.prevent_default();
        show(&seg, row, start, end, label, None);
    });
    std::mem::forget(key); // the timeline lives as long as the page
                           // in the capture phase: a segment's own press stops there
    gloo::events::EventListener::new_with_options(
        &gloo::utils::window(),
        "pointerdown",
        gloo::events::EventListenerOptions::run_in_capture_phase(),
        move |ev| {
            let inside = ev
                .target()
                .and_then(|t| t.dyn_into::<Element>().ok())
                .is_some_and(|e| e.closest("#segment-menu").ok().flatten().is_some());
            if !inside {
                close(false);
            }
        },
    )
    .forget();
}

/// A segment menu's status line: (failed, message).
type Status = RwSignal<Option<(bool, String)>>;

/// "Export clip (BVH)": the worker cuts the take at segment `o` of its row (`title`), saved as a BVH.
fn export_segment(
    state: AppState,
    loader: Option<StoredValue<ClipJobs, LocalStorage>>,
    o: &Open,
    title: &str,
    status: Status,
) {
    let only = Some((o.start, o.end));
    let Some(loader) = loader else { return };
    if let Some(index) = method_of(state, &o.row) {
        let slot = &state.methods[index];
        let Some(view) = slot.view.get_untracked() else {
            return status.set(Some((true, format!("{title}: run the method first"))));
        };
        let which = which_of(&view, o.start, o.end).unwrap_or(Which::All);
        loader.with_value(|l| l.export_clips_of(&view.segmentation, &slot.info.name, which, false, only, status));
    } else {
        let segmentation = if o.row == MINE {
            state.mine.get_untracked()
        } else {
            state.truth.view.with_untracked(|v| v.as_ref().map(|v| std::sync::Arc::new(v.segmentation.clone())))
        };
        match segmentation {
            Some(s) => loader.with_value(|l| l.export_clips_of(&s, &o.row, Which::All, false, only, status)),
            None => status.set(Some((true, format!("{title} has no segments to cut")))),
        }
    }
}

/// "Copy to my labels": segment `o` of row `title` copied into my labels.
fn copy_segment(mine: MyRow, o: &Open, title: &str, status: Status) {
    if o.row == MINE {
        return status.set(Some((true, "That segment is in my labels already".into())));
    }
    if mine.place(o.start, o.end, &o.label, &title) {
        status.set(Some((false, format!("Copied frames {}–{} of {title} to my labels", o.start + 1, o.end + 1))));
    } else {
        status.set(Some((true, "Could not copy it: my labels' status line says why".into())));
    }
}

/// "Show in its panel": the side panel's tab of segment `o`'s row (`title`), or my labels' tools.
fn show_panel(state: AppState, o: &Open, title: &str, status: Status) {
    let tab = if o.row == MINE {
        None
    } else if let Some(index) = method_of(state, &o.row) {
        Some(state.methods[index].info.name.clone())
    } else {
        Some(TRUTH_TAB.to_string())
    };
    match tab {
        Some(tab) => {
            state.panel.set(tab.clone());
            focus_element(gloo::utils::document().get_element_by_id(&format!("tab-{tab}")));
            status.set(Some((false, format!("{title}: its panel is the \"{}\" tab", tab_title(state, &tab)))));
        }
        None => {
            focus_element(gloo::utils::document().get_element_by_id("my-labels-label"));
            status.set(Some((false, "My labels: its tools are under the timeline".into())));
        }
    }
}

/// The title of side panel tab `id`.
fn tab_title(state: AppState, id: &str) -> String {
    crate::app::workspace::tabs(state).into_iter().find(|(t, _)| t == id).map(|(_, title)| title).unwrap_or_default()
}
