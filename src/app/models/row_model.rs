//! Models on the row: the labelling row of every supervised method (DT-FCN, the k-NN, LMA) shows
//! the model in use and lets the user change it right there; a change (there or in the panel)
//! runs the method again at once. Beside the choice, the model's card ([`ModelCardView`]: the takes
//! it was trained on, its classes, the command, its held-out accuracy — measured by the scoreboard
//! or "not measured"), and a warning when the take on screen was one of its training takes.
//!
//! * `#<method>-row-model` — the model choice (the same field as the panel's `#<method>-model`);
//! * `#<method>-row-card-toggle` opens `#<method>-row-card`, the card;
//! * `#<method>-row-in-sample` — shown when the take on screen is one of the model's training
//!   takes: by the SHA-256 of its file when the model recorded its takes' hashes, else by name
//!   (the bundled sample is CMU 13_30): "This take was in the model's training set (…) — its labels
//!   here are not a measure of accuracy.";
//! * `#<method>-row-shipped` — one click back to the shipped model last used (shown while a
//!   model of the user's is chosen);
//! * `#<method>-row-fit` — "does not fit", shown while the row's result says its model's classes do
//!   not fit the take (its run's take fit, [`crate::app::models::take_fit`]), the reason its tooltip and
//!   accessible description (`#<method>-row-fit-reason`); beside it one button per model that fits
//!   the take, best first (`.ms-row-fit-use`, `data-model`: "use cmu-actions" — chooses it, which
//!   runs the method again), or `#<method>-row-fit-none` when no model of the method fits. Those
//!   are measured only when asked: until then `#<method>-row-fit-find`, "find a model that fits",
//!   turns the panel's `fit_others` on and runs the method again (measuring every other model
//!   against the take is a search of each one's training windows, not paid on every run). Gone
//!   once a fitting model's result is on the row; never shown when the run's `fit_check` was off.
//!
//! The shipped models' cards are `models/cards.json` (`mocapseg model-cards`, fetched once, when a
//! supervised method first has a result or a card is opened: a page that runs only SSSM fetches
//! nothing beside itself); a
//! model the user trained or loaded carries its own ([`crate::method::supervised::ModelInfo::card`]).

use std::cell::RefCell;

use leptos::prelude::*;
use sha2::{Digest, Sha256};

use crate::app::loader::Loader;
use crate::app::method_panel::runs::MethodRuns;
use crate::app::models::model_card::{card_lines, card_summary};
use crate::app::models::model_files;
use crate::app::models::take_fit::{fit_badge, FitBadge, BADGE};
use crate::app::state::AppState;
use crate::app::state::MethodSlot;
use crate::app::take::fetch::blob_bytes;
use crate::app::take::summary::is_bundled_sample;
use crate::method::cards::{training_match, Cards, ModelCard, TrainingMatch};

/// The take the bundled sample is (www/SOURCES.md): a model trained on it knows it by this name.
const SAMPLE_TAKE: &str = "13_30.bvh";

/// Where the shipped models' cards stand.
#[derive(Debug, Clone, PartialEq)]
enum ShippedCards {
    /// Not asked yet: a page whose supervised methods never run fetches nothing.
    Unasked,
    Loading,
    Ready(Vec<ModelCard>),
    Failed(String),
}

thread_local! {
    /// The shipped cards (fetched once per page) and the SHA-256 of the take on screen's file
    /// (name, frames, hash), shared by every row and panel.
    static SHARED: RefCell<Option<(RwSignal<ShippedCards>, RwSignal<Option<(String, usize, String)>>)>> =
        const { RefCell::new(None) };
}

/// Fetches the shipped cards unless asked before (when a supervised method has a result to
/// describe, or a card is opened).
fn want_cards(cards: RwSignal<ShippedCards>, loader: &Loader) {
    if cards.get_untracked() != ShippedCards::Unasked {
        return;
    }
    cards.set(ShippedCards::Loading);
    let url = loader.model_url("cards.json");
    wasm_bindgen_futures::spawn_local(async move {
        let read = model_files::fetch(&url, 0, |_| {}).await.and_then(|bytes| {
            serde_json::from_slice::<Cards>(&bytes).map_err(|e| format!("{url}: not the models' cards: {e}"))
        });
        cards.set(match read {
            Ok(c) => ShippedCards::Ready(c.cards),
            Err(message) => ShippedCards::Failed(message),
        });
    });
}

/// The shared signals, made (and the take hashed on each load) on first use.
fn shared(state: AppState, loader: &Loader) -> (RwSignal<ShippedCards>, RwSignal<Option<(String, usize, String)>>) {
    if let Some(s) = SHARED.with(|s| *s.borrow()) {
        return s;
    }
    let cards = RwSignal::new(ShippedCards::Unasked);
    let sha = RwSignal::new(None);
    SHARED.with(|s| *s.borrow_mut() = Some((cards, sha)));
    // the take on screen's file hashed once per load (a few milliseconds for a few MB)
    let loader = loader.clone();
    Effect::new(move |_| {
        let Some((name, frames)) =
            state.motion.with(|m| m.as_ref().map(|m| (m.summary.name.clone(), m.summary.frames)))
        else {
            return;
        };
        let Some((file_name, blob)) = loader.shown_file() else { return };
        if file_name != name {
            return;
        }
        wasm_bindgen_futures::spawn_local(async move {
            if let Ok(buffer) = blob_bytes(&blob).await {
                let bytes = js_sys::Uint8Array::new(&buffer).to_vec();
                let hex: String = Sha256::digest(&bytes).iter().map(|b| format!("{b:02x}")).collect();
                sha.set(Some((name, frames, hex)));
            }
        });
    });
    (cards, sha)
}

/// The methods' runs the page provides (`App`).
fn page_runs() -> Option<MethodRuns> {
    use_context::<StoredValue<MethodRuns, LocalStorage>>().map(|r| r.get_value())
}

/// The loader the page provides (`App`).
fn page_loader() -> Option<Loader> {
    use_context::<StoredValue<Loader, LocalStorage>>().map(|l| l.get_value())
}

/// The card of model `name` of `slot`: the user's model's own, else the shipped one's.
fn card_of(slot: &'static MethodSlot, name: &str, shipped: &ShippedCards) -> Result<ModelCard, String> {
    let s = slot.supervised.as_ref().ok_or("no models")?;
    if let Some(m) = s.models.with(|l| l.iter().find(|m| m.info.name == name).cloned()) {
        let mut card = m.info.card.clone();
        card.method = slot.info.name.clone();
        card.name = name.to_string();
        if card.classes.is_empty() {
            card.classes = m.info.classes.clone();
        }
        if card.takes.is_empty() && card.origin.is_empty() {
            card.origin = m.info.origin.clone();
        }
        return Ok(card);
    }
    match shipped {
        ShippedCards::Unasked | ShippedCards::Loading => Err("reading the models' cards…".into()),
        ShippedCards::Failed(message) => Err(format!("no card: {message}")),
        ShippedCards::Ready(cards) => cards
            .iter()
            .find(|c| c.method == slot.info.name && c.name == name)
            .cloned()
            .ok_or_else(|| format!("no card for model `{name}`")),
    }
}

/// The card of the model chosen for `slot` now, and whether the take on screen trained it.
fn chosen_card(
    state: AppState,
    slot: &'static MethodSlot,
    cards: RwSignal<ShippedCards>,
    sha: RwSignal<Option<(String, usize, String)>>,
) -> Option<(Result<ModelCard, String>, Option<TrainingMatch>)> {
    let (value, _) = slot.param("model")?;
    let name = value.get();
    let card = cards.with(|c| card_of(slot, &name, c));
    let found = card.as_ref().ok().and_then(|card| {
        state.motion.with(|m| {
            let m = m.as_ref()?;
            let (take, frames) = (&m.summary.name, m.summary.frames);
            let hash =
                sha.with(|h| h.as_ref().filter(|(n, f, _)| n == take && *f == frames).map(|(_, _, h)| h.clone()));
            let aliases: &[&str] = if is_bundled_sample(take, frames) { &[SAMPLE_TAKE] } else { &[] };
            training_match(card, take, hash.as_deref(), aliases)
        })
    });
    Some((card, found))
}

/// Re-runs method `index` whenever its model choice changes (on its row or in its panel).
fn rerun_on_change(slot: &'static MethodSlot, runs: MethodRuns, index: usize) {
    let Some((value, _)) = slot.param("model") else { return };
    Effect::new(move |previous: Option<String>| {
        let now = value.get();
        if previous.is_some_and(|p| p != now) {
            runs.rerun_with_model(index);
        }
        now
    });
}

/// The model choice, card and warnings on method `index`'s labelling row.
#[component]
pub fn RowModel(state: AppState, index: usize) -> impl IntoView {
    let slot: &'static MethodSlot = &state.methods[index];
    let (Some(s), Some((value, choices)), Some(loader), Some(runs)) =
        (slot.supervised.as_ref(), slot.param("model"), page_loader(), page_runs())
    else {
        return ().into_any();
    };
    let (cards, sha) = shared(state, &loader);
    rerun_on_change(slot, runs.clone(), index);
    let method = slot.info.name.clone();
    let short = slot.info.short.clone();
    // the shipped model to go back to: the last one used
    let last_shipped = RwSignal::new(s.decl.shipped.first().cloned().unwrap_or_default());
    Effect::new(move |_| {
        let v = value.get();
        if s.decl.shipped.contains(&v) {
            last_shipped.set(v);
        }
    });
    let is_shipped = move || value.with(|v| s.decl.shipped.contains(v));
    let open = RwSignal::new(false);
    // where the card opens: in the window, under its button (above it in the window's lower half), never clipped
    // by the timeline's scrolling box (it is `position: fixed`)
    let place = RwSignal::new(CardPlace::default());
    Effect::new(move |_| {
        if slot.view.with(Option::is_some) || open.get() {
            want_cards(cards, &loader);
        }
    });
    let found = move || chosen_card(state, slot, cards, sha).and_then(|(_, m)| m);
    let warning = move || found().map(|m| m.warning());
    let summary = move || match chosen_card(state, slot, cards, sha).map(|(c, _)| c) {
        Some(Ok(card)) => card_summary(&card),
        Some(Err(message)) => message,
        None => String::new(),
    };
    let options = move || crate::app::models::row_model::choice_options(choices, value);
    let card_id = format!("{method}-row-card");
    // the row's result's verdict on the take (none while it fits, or without a fit check)
    let short_fit = short.clone();
    let badge = Memo::new(move |_| {
        slot.view.with(|v| v.as_ref().and_then(|v| fit_badge(v.details.take_fit.as_ref(), &short_fit)))
    });
    // the other models measured only when asked: the panel's `fit_others` on, and the method again
    let find = move |_| {
        if let Some((field, _)) = slot.param("fit_others") {
            field.set("true".into());
        }
        runs.run(index);
    };
    view! {
        <span class="ms-row-model" on:pointerdown=|ev| ev.stop_propagation()>
            <select
                id=format!("{method}-row-model")
                class="ms-row-model-select"
                aria-label=format!("{short} model (runs {short} again when changed)")
                title=summary
                bind:value=value
            >
                {options}
            </select>
            <button
                id=format!("{method}-row-card-toggle")
                class="ms-row-model-button"
                type="button"
                aria-expanded=move || open.get().to_string()
                aria-controls=card_id.clone()
                title="The model's card: its training takes, classes, command and held-out accuracy"
                aria-label="The model's card"
                on:click=move |ev: leptos::ev::MouseEvent| {
                    if let Some(button) = ev.current_target().and_then(|t| wasm_bindgen::JsCast::dyn_into::<web_sys::Element>(t).ok()) {
                        place.set(CardPlace::under(&button.get_bounding_client_rect()));
                    }
                    open.update(|o| *o = !*o)
                }
            >
                "ⓘ"
            </button>
            <button
                id=format!("{method}-row-shipped")
                class="ms-row-model-button"
                type="button"
                hidden=is_shipped
                title=move || format!("Back to the shipped model `{}`", last_shipped.get())
                on:click=move |_| value.set(last_shipped.get_untracked())
            >
                {move || format!("↺ {}", last_shipped.get())}
            </button>
            <span
                id=format!("{method}-row-in-sample")
                class="ms-row-in-sample"
                role="note"
                hidden=move || warning().is_none()
                title=warning
                aria-label=warning
            >
                "in training"
            </span>
            <span class="ms-row-fit-bar">{fit_parts(&method, &short, badge, value, find)}</span>
            <div id=card_id class="ms-row-card" hidden=move || !open.get()
                style:left=move || format!("{:.0}px", place.get().left)
                style:top=move || place.get().top.map(|t| format!("{t:.0}px"))
                style:bottom=move || place.get().bottom.map(|b| format!("{b:.0}px"))>
                <ModelCardView state=state index=index id=format!("{method}-row-card-body")/>
            </div>
        </span>
    }
    .into_any()
}

/// Where a row's model card opens in the window (CSS pixels): `left`, and `top` (under its button) or `bottom` (above
/// it, when the button is in the window's lower half).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct CardPlace {
    left: f64,
    top: Option<f64>,
    bottom: Option<f64>,
}

impl CardPlace {
    /// Under (or above) the button whose box is `rect`, inside the window (a card is at most 420 px wide).
    fn under(rect: &web_sys::DomRect) -> CardPlace {
        let window = web_sys::window();
        let size = |f: fn(&web_sys::Window) -> Result<wasm_bindgen::JsValue, wasm_bindgen::JsValue>| {
            window.as_ref().and_then(|w| f(w).ok()).and_then(|v| v.as_f64()).unwrap_or(1024.0)
        };
        let (width, height) = (size(web_sys::Window::inner_width), size(web_sys::Window::inner_height));
        let left = rect.left().min(width - 428.0).max(4.0);
        if rect.bottom() > height / 2.0 {
            CardPlace { left, top: None, bottom: Some(height - rect.top() + 2.0) }
        } else {
            CardPlace { left, top: Some(rect.bottom() + 2.0), bottom: None }
        }
    }
}

/// The row's verdict on the take (its badge and why), the models it could use instead, and the button that looks for
/// them (`find`).
fn fit_parts(
    method: &str,
    short: &str,
    badge: Memo<Option<FitBadge>>,
    value: RwSignal<String>,
    find: impl FnMut(leptos::ev::MouseEvent) + 'static,
) -> impl IntoView {
    let reason_id = format!("{method}-row-fit-reason");
    let suggestions = move || {
        badge
            .get()
            .map(|b| b.suggestions)
            .unwrap_or_default()
            .into_iter()
            .map(|s| {
                let model = s.model.clone();
                view! {
                    <button
                        class="ms-row-model-button ms-row-fit-use"
                        type="button"
                        data-model=s.model.clone()
                        title=s.title
                        on:click=move |_| value.set(model.clone())
                    >
                        {s.text}
                    </button>
                }
            })
            .collect_view()
    };
    view! {
        <span
            id=format!("{method}-row-fit")
            class="ms-row-fit"
            role="note"
            hidden=move || badge.with(Option::is_none)
            title=move || badge.with(|b| b.as_ref().map(|b| b.description.clone()).unwrap_or_default())
            aria-describedby=reason_id.clone()
        >
            {BADGE}
        </span>
        <span id=reason_id hidden>
            {move || badge.with(|b| b.as_ref().map(|b| b.description.clone()).unwrap_or_default())}
        </span>
        {suggestions}
        <button
            id=format!("{method}-row-fit-find")
            class="ms-row-model-button ms-row-fit-find"
            type="button"
            hidden=move || !badge.with(|b| b.as_ref().is_some_and(|b| b.find))
            title=format!(
                "Measure {short}'s other models against this take and offer those that fit (runs {short} again \
                 with fit_others on)"
            )
            on:click=find
        >
            "find a model that fits"
        </button>
        <span
            id=format!("{method}-row-fit-none")
            class="ms-row-fit-none"
            hidden=move || badge.with(|b| b.as_ref().and_then(|b| b.none.as_ref()).is_none())
        >
            {move || badge.with(|b| b.as_ref().and_then(|b| b.none.clone()).unwrap_or_default())}
        </span>
    }
}

/// Method `index`'s chosen model's card `#<id>`: its lines (`#<id>-<line>`), and
/// `#<id>-in-sample` when the take on screen was one of its training takes.
#[component]
pub fn ModelCardView(state: AppState, index: usize, id: String) -> impl IntoView {
    let slot: &'static MethodSlot = &state.methods[index];
    let Some(loader) = page_loader() else { return ().into_any() };
    let (cards, sha) = shared(state, &loader);
    Effect::new(move |_| {
        if slot.view.with(Option::is_some) {
            want_cards(cards, &loader);
        }
    });
    let chosen = move || chosen_card(state, slot, cards, sha);
    let prefix = id.clone();
    let lines = move || {
        let prefix = prefix.clone();
        match chosen().map(|(c, _)| c) {
            Some(Ok(card)) => card_lines(&card)
                .into_iter()
                .map(|(what, text)| {
                    let line_id = format!("{prefix}-{}", what.replace(' ', "-"));
                    view! { <dt>{what}</dt><dd id=line_id>{text}</dd> }
                })
                .collect_view()
                .into_any(),
            Some(Err(message)) => view! { <dt>"card"</dt><dd>{message}</dd> }.into_any(),
            None => ().into_any(),
        }
    };
    let name = move || slot.param("model").map(|(v, _)| v.get()).unwrap_or_default();
    let warning = move || chosen().and_then(|(_, m)| m).map(|m| m.warning());
    view! {
        <section id=id.clone() class="ms-model-card" aria-label=move || format!("Card of the {} model `{}`", slot.info.short, name())>
            <h4>{move || format!("{} model `{}`", slot.info.short, name())}</h4>
            <dl>{lines}</dl>
            <p id=format!("{id}-in-sample") class="ms-in-sample" role="note" hidden=move || warning().is_none()>
                {move || warning().unwrap_or_default()}
            </p>
        </section>
    }
    .into_any()
}

/// The name of a choice of segments in file names and the select's values.
/// The `<option>`s of a choice whose options are `choices` (they may grow: a model the user
/// loads or trains); each says whether it is `value`, so a value set before its option exists
/// still shows once it does.
pub(crate) fn choice_options(choices: RwSignal<Vec<String>>, value: RwSignal<String>) -> impl IntoView {
    choices
        .get()
        .into_iter()
        .map(|o| {
            let chosen = o.clone();
            view! { <option value=o.clone() prop:selected=move || value.get() == chosen>{o.clone()}</option> }
        })
        .collect_view()
}
