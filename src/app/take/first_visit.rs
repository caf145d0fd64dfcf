//! What a first visit needs to read the page (issue 27, finding 9):
//!
//! * [`Legend`] — `#legend-button` on the timeline's heading opens `#legend`, which says what
//!   every kind of row is and what its names mean (one entry `[data-kind]` per kind: the motion
//!   image, actions, labels, primitives, gestures, the ground truth, the consensus, my labels; the words come from
//!   [`crate::app::timeline::rows`], as the rows' tooltips do). Esc, its Close button or the button again
//!   closes it.
//! * [`WhatNext`] — `#what-next`, at the top of the side panel's first tab: three next steps (compare with a
//!   ground truth, correct in my labels, export), each with a button that goes there, and
//!   `#what-next-dismiss`; once dismissed it stays hidden on later visits ([`WHAT_NEXT_KEY`] in
//!   local storage).

use crate::app::state::AppState;
use crate::app::state::TRUTH_TAB;
use crate::app::timeline::rows::RowKind;
use crate::app::workspace::{storage_get, storage_set};
use leptos::prelude::*;
use wasm_bindgen::JsCast;

/// Local storage: "1" once the user dismissed "What next".
pub const WHAT_NEXT_KEY: &str = "mocapseg.whatnext.dismissed";

/// The legend's entries: kind (`data-kind`), name as on the timeline, what it means.
fn entries() -> Vec<(&'static str, String, String)> {
    let mut out = vec![(
        "motion-image",
        "Motion image".to_string(),
        "the whole body over time: rows = joints, columns = frames, colour = each joint's X, Y, Z relative to the \
         root; alike colours, alike poses"
            .to_string(),
    )];
    for (kind, example) in [
        (RowKind::Actions, "SSSM · actions, PCA · actions"),
        (RowKind::Labels, "DT-FCN · labels, k-NN · labels"),
        (RowKind::Primitives, "SSSM · primitives"),
        (RowKind::Gestures, "KCS · gestures, Velocity · gestures, LMA · gestures"),
    ] {
        out.push((kind.word(), format!("… · {} ({example})", kind.word()), kind.meaning().to_string()));
    }
    out.push((
        "truth",
        "Ground truth".to_string(),
        "labels you imported (Truth & scores tab): what the other rows are scored against".to_string(),
    ));
    out.push((
        "consensus",
        "Consensus".to_string(),
        "boundaries where the methods' rows agree: \"3/5\" — 3 of the 5 methods that ran cut there, within the \
         tolerance set under the timeline; select one and Accept puts it in my labels"
            .to_string(),
    ));
    out.push((
        "my-labels",
        "My labels".to_string(),
        "your own row: copy a row or a segment into it (right-click a segment), drag its boundaries, rename, export"
            .to_string(),
    ));
    out
}

/// `#legend-button` and `#legend`.
#[component]
pub fn Legend() -> impl IntoView {
    let open = RwSignal::new(false);
    // Esc closes it wherever the focus is, before the timeline's keys see it (which would drop
    // the selection): in the capture phase, marked as handled
    let options =
        gloo::events::EventListenerOptions { phase: gloo::events::EventListenerPhase::Capture, passive: false };
    gloo::events::EventListener::new_with_options(&gloo::utils::window(), "keydown", options, move |ev| {
        let ev: &web_sys::KeyboardEvent = ev.unchecked_ref();
        if open.get_untracked() && ev.key() == "Escape" {
            ev.prevent_default();
            open.set(false);
            focus("legend-button");
        }
    })
    .forget(); // the timeline lives as long as the page
    view! {
        <button
            id="legend-button"
            class="ms-button ms-button--quiet"
            type="button"
            aria-expanded=move || open.get().to_string()
            aria-controls="legend"
            title="What the rows and their names mean"
            on:click=move |_| {
                open.update(|o| *o = !*o);
                // the dialog takes the focus, so that Esc closes it
                if open.get_untracked() {
                    later(|| focus("legend-close"));
                }
            }
        >
            "Legend"
        </button>
        <div id="legend" class="ms-legend" role="dialog" aria-modal="false" aria-labelledby="legend-title"
            hidden=move || !open.get()>
            <h2 id="legend-title">"What the rows mean"</h2>
            <dl class="ms-legend-list">
                {entries()
                    .into_iter()
                    .map(|(kind, name, meaning)| view! { <dt data-kind=kind>{name}</dt> <dd data-kind=kind>{meaning}</dd> })
                    .collect_view()}
            </dl>
            <p class="ms-help-note">
                "A row's name at the left says which method found it and what it holds; hover a name for what it is, "
                "a segment for its frames. Right-click a segment (or select it and press the menu key) to play it, "
                "export it, copy it into my labels or open its method's panel."
            </p>
            <button id="legend-close" class="ms-button" type="button" on:click=move |_| { open.set(false); focus("legend-button"); }>
                "Close"
            </button>
        </div>
    }
}

/// Runs `f` once the page has drawn what the current event changed (a tab shown, a dialog open).
fn later(f: impl FnOnce() + 'static) {
    gloo::timers::callback::Timeout::new(0, f).forget();
}

fn focus(id: &str) {
    if let Some(el) =
        gloo::utils::document().get_element_by_id(id).and_then(|e| e.dyn_into::<web_sys::HtmlElement>().ok())
    {
        let _ = el.focus();
    }
}

/// `#what-next`: the first screen's three next steps, dismissible (remembered).
#[component]
pub fn WhatNext(state: AppState) -> impl IntoView {
    let hidden = RwSignal::new(storage_get(WHAT_NEXT_KEY).as_deref() == Some("1"));
    let dismiss = move |_| {
        hidden.set(true);
        storage_set(WHAT_NEXT_KEY, "1");
    };
    let to_truth = move |_| {
        state.panel.set(TRUTH_TAB.to_string());
        later(|| focus("truth-file"));
    };
    view! {
        <section id="what-next" class="ms-what-next" aria-label="What next" hidden=move || hidden.get()>
            <strong>"What next? "</strong>
            <ol>
                <li>
                    <button id="what-next-truth" class="ms-linklike" type="button" on:click=to_truth>"Compare with a ground truth"</button>
                    ": import its labels; every row is scored in one table."
                </li>
                <li>
                    <button id="what-next-correct" class="ms-linklike" type="button" on:click=move |_| focus("my-labels-source")>
                        "Correct in my labels"
                    </button>
                    ": copy a row (or right-click a segment), then drag, rename, split."
                </li>
                <li>
                    <button id="what-next-legend" class="ms-linklike" type="button" on:click=move |_| focus("legend-button")>
                        "Export"
                    </button>
                    ": right-click a segment for its clip, or a method's tab for all of them; the Legend says what rows mean."
                </li>
            </ol>
            <button id="what-next-dismiss" class="ms-error-dismiss" type="button" aria-label="Dismiss what next" on:click=dismiss>
                "×"
            </button>
        </section>
    }
}
