//! The page: a leptos 0.8 client-side app (drop a BVH, see it play, its motion image and its segmentations).
//!
//! A user drops a BVH file (or the bundled sample loads by itself); the file goes to a web
//! worker ([`crate::worker`]) that parses it, runs forward kinematics and builds the motion
//! image, reporting progress; the page shows a summary, a skeleton player and the motion image
//! under a shared timeline. A bad file shows the parser's message in a banner and the previous
//! take stays on screen.
//!
//! State lives in [`AppState`], created once in [`App`] and passed down; each component (one
//! per file) renders it and computes nothing — the worker does the work, [`camera`] and
//! [`playback`] hold the little math the player needs. `document.body.dataset.state` says
//! where loading stands: `loading`, `ready` or `error` (the outcome of the last load).
//! After each successful load the worker runs every method whose `auto_run` is set with the
//! parameters in its form ([`method_panel`]: one generic panel per registered method, built from
//! the registry); `document.body.dataset.<method>` (e.g. `data-sssm`) says where each stands:
//! `idle`, `running`, `done`, `error` or `cancelled`. The panel of every supervised method (one
//! that declares [`crate::method::Supervision`]: DT-FCN, the k-NN, LMA) takes the user's model
//! files and trains a model in the worker one step at a time on the user's labels
//! ([`training`], `data-<method>-model`, `data-<method>-training`) — built from what the method
//! declares, never from its name. Under the
//! timeline, [`ground_truth`] imports labels (`data-truth`, row `#row-truth`) and
//! [`metrics_panel`] scores any row against them as `mocapseg eval` does (`data-metrics`).
//! The URL parameters (`src`, `methods`, `t`, `autoplay`, `embed`) are read once ([`embed`]);
//! `embed=1` shows the player and the timeline only.
//! The timeline's "my labels" row ([`my_labels`], `data-my-labels`) holds the user's own
//! corrections. [`effort`] draws the Effort bars under every row (a toggle of the timeline).
//! Several files dropped at once (or a folder) make a [`library`] of takes, segmented one after
//! another in the worker, each opened on screen when clicked.

#[cfg(feature = "web")]
mod dom;
#[cfg(feature = "web")]
mod loader;
#[cfg(feature = "web")]
mod state;
#[cfg(feature = "web")]
mod workspace;

pub mod consensus;
pub mod effort;
pub mod embed;
pub mod library;
pub mod method_panel;
pub mod models;
pub mod my_labels;
pub mod player;
pub mod take;
pub mod timeline;
pub mod truth;

#[cfg(feature = "web")]
use leptos::prelude::*;
#[cfg(feature = "web")]
use wasm_bindgen::prelude::*;
#[cfg(feature = "web")]
use wasm_bindgen::JsCast;

#[cfg(feature = "web")]
use embed::launch::{EmbedBar, Launch, UrlNotice};
#[cfg(feature = "web")]
use loader::{Loader, Urls};
#[cfg(feature = "web")]
use method_panel::panel::MethodPanel;
#[cfg(feature = "web")]
use models::training::{ModelFile, TakeSwitch, TrainingPanel};
#[cfg(feature = "web")]
use player::canvas::Player;
#[cfg(feature = "web")]
use state::{AppState, LoadState, RunState};
#[cfg(feature = "web")]
use take::{drop_zone::DropZone, error_banner::ErrorBanner, progress::Progress, summary::Summary};
#[cfg(feature = "web")]
use timeline::lines::Timeline;
#[cfg(feature = "web")]
use truth::{ground_truth::GroundTruthPanel, metrics_panel::MetricsPanel};
#[cfg(feature = "web")]
use workspace::{SidePanel, Studio};

/// Id of the element the page mounts into (falls back to `<body>`).
#[cfg(feature = "web")]
const ROOT_ID: &str = "mocapseg-app";

/// Mounts the page. Called by `index.html` after `init()`; the worker loads the same module
/// and never calls it. The root element may override the asset locations with
/// `data-worker-url`, `data-sample-url` and `data-models-url` (default `./www/worker.js`,
/// `./www/sample.bvh.pack` — the sample packed, unpacked by the page —, `./models/`), and the
/// number of workers with `data-workers` (default one per core, two to four; the URL's `workers`
/// comes first).
#[cfg(feature = "web")]
#[wasm_bindgen]
pub fn mount_app() -> Result<(), JsValue> {
    // a panic logs and shows `#mocapseg-stopped` ("reload the page"), never a page that just stops
    take::stopped::install();
    let document = web_sys::window().and_then(|w| w.document()).ok_or("no document")?;
    let root = match document.get_element_by_id(ROOT_ID) {
        Some(el) => el.dyn_into::<web_sys::HtmlElement>()?,
        None => document.body().ok_or("no <body>")?,
    };
    let urls = Urls::from_root(&root);
    let launch = Launch::from_location();
    launch.mark(&root);
    leptos::mount::mount_to(root, move || view! { <App urls=urls launch=launch/> }).forget();
    Ok(())
}

#[cfg(feature = "web")]
#[component]
fn App(urls: Urls, launch: Launch) -> impl IntoView {
    let state = AppState::new();
    // the URL's `workers` before the root's `data-workers`
    let urls = Urls { workers: launch.params.workers.or(urls.workers), ..urls };
    let loader = Loader::new(state, urls.clone());
    // the rows that export clips without a method panel (my labels) find the worker here
    provide_context(StoredValue::new_local(loader.clone()));
    let notice = RwSignal::new(launch.messages.clone());
    let full = !launch.params.embed;

    Effect::new(move |_| {
        let value = state.load.with(LoadState::body_state);
        if let Some(body) = web_sys::window().and_then(|w| w.document()).and_then(|d| d.body()) {
            let _ = body.set_attribute("data-state", value);
        }
    });
    for slot in state.methods {
        let attribute = format!("data-{}", slot.info.name);
        Effect::new(move |_| {
            let value = slot.run.with(RunState::body_state);
            if let Some(body) = web_sys::window().and_then(|w| w.document()).and_then(|d| d.body()) {
                let _ = body.set_attribute(&attribute, value);
            }
        });
    }
    embed::launch::start(state, &loader, &urls, &launch, notice);
    // the loader (and the worker it owns) lives as long as the page, even when no component holds
    // it (embed mode has no drop zone or method panels); the app is mounted once, never unmounted
    std::mem::forget(loader.clone());

    // the player and the timeline pinned at the left; the side panel's tabs at the right
    // (embed mode: the stage alone)
    let player = view! { <Player state=state/> }.into_any();
    let timeline = view! { <Timeline state=state/> }.into_any();
    let side = full.then(|| {
        let truth = view! {
            <take::first_visit::WhatNext state=state/>
            <GroundTruthPanel state=state/>
            <MetricsPanel state=state/>
        }
        .into_any();
        let methods = state.methods.iter().enumerate().map(|(index, slot)| {
            // a supervised method's panel takes the user's model files and trains in the browser
            let extra = slot.supervised.is_some().then(|| {
                view! {
                    <ModelFile state=state loader=loader.clone() index=index/>
                    <TrainingPanel state=state loader=loader.clone() index=index/>
                }
                .into_any()
            });
            view! { <MethodPanel state=state method=slot loader=loader.clone() extra=extra/> }.into_any()
        });
        let panels = std::iter::once(truth).chain(methods).collect();
        let library = view! { <library::panel::LibraryPanel state=state loader=loader.clone()/> }.into_any();
        view! { <SidePanel state=state panels=panels library=library/> }.into_any()
    });
    let studio = view! {
        <Studio
            player=player
            timeline=timeline
            side=side
        />
    };
    // embed mode: no header, drop zone, summary or side panel (docs/page.md, "Embedding")
    view! {
        {full.then(|| view! {
            <header class="ms-header">
                <h1>"mocapseg"</h1>
                <p class="ms-tagline">"Motion-capture segmentation in the browser — BVH in, motion out."</p>
            </header>
        })}
        {(!full).then(|| view! { <EmbedBar state=state full_page=launch.full_page.clone()/> })}
        <ErrorBanner state=state/>
        <UrlNotice messages=notice/>
        <section class="ms-input">
            {full.then(|| view! { <DropZone state=state loader=loader.clone()/> })}
            <Progress state=state/>
            {full.then(|| view! { <TakeSwitch state=state loader=loader.clone()/> })}
        </section>
        {full.then(|| view! { <Summary state=state/> })}
        {studio}
    }
}
