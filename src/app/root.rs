//! The page's root: mounts the page, makes its state, the loader and the features' jobs (shared through
//! leptos context), and lays out the header, the input, the studio and the side panel.

use leptos::prelude::*;
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;

use crate::app::effort::jobs::EffortJobs;
use crate::app::embed::launch::{EmbedBar, Launch, UrlNotice};
use crate::app::library::library_jobs::LibraryJobs;
use crate::app::library::panel::LibraryPanel;
use crate::app::loader::{Loader, Urls};
use crate::app::method_panel::panel::MethodPanel;
use crate::app::method_panel::runs::MethodRuns;
use crate::app::models::model_jobs::ModelJobs;
use crate::app::models::training::{ModelFile, TakeSwitch, TrainingPanel};
use crate::app::player::canvas::Player;
use crate::app::session::keeper::{Keeper, WorkspaceStatus};
use crate::app::session::project_file::ProjectFile;
use crate::app::state::{AppState, LoadState, RunState};
use crate::app::take::first_visit::WhatNext;
use crate::app::take::{drop_zone::DropZone, error_banner::ErrorBanner, progress::Progress, summary::Summary};
use crate::app::timeline::clip_jobs::ClipJobs;
use crate::app::timeline::lines::Timeline;
use crate::app::truth::{ground_truth::GroundTruthPanel, metrics_panel::MetricsPanel};
use crate::app::workspace::{SidePanel, Studio};

/// Id of the element the page mounts into (falls back to `<body>`).
const ROOT_ID: &str = "mocapseg-app";

/// Mounts the page. Called by `index.html` after `init()`; the worker loads the same module
/// and never calls it. The root element may override the asset locations with
/// `data-worker-url`, `data-sample-url` and `data-models-url` (default `./www/worker.js`,
/// `./www/sample.bvh.pack` — the sample packed, unpacked by the page —, `./models/`), and the
/// number of workers with `data-workers` (default one per core, two to four; the URL's `workers`
/// comes first).
#[wasm_bindgen]
pub fn mount_app() -> Result<(), JsValue> {
    // a panic logs and shows `#mocapseg-stopped` ("reload the page"), never a page that just stops
    crate::app::take::stopped::install();
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

#[component]
fn App(urls: Urls, launch: Launch) -> impl IntoView {
    let state = AppState::new();
    // the URL's `workers` before the root's `data-workers`
    let urls = Urls { workers: launch.params.workers.or(urls.workers), ..urls };
    let loader = Loader::new(state, urls.clone());
    // the rows that export clips without a method panel (my labels) find the worker here, and the
    // features' own jobs in the worker (registered with the loader, which routes their replies)
    // (registered in this order: the methods' runs, the models, the Effort bars, the clips, the library)
    let runs = MethodRuns::new(state, loader.clone());
    let models = ModelJobs::new(state, loader.clone(), runs.clone());
    provide_context(StoredValue::new_local(loader.clone()));
    provide_context(StoredValue::new_local(runs.clone()));
    provide_context(StoredValue::new_local(models.clone()));
    provide_context(StoredValue::new_local(EffortJobs::new(state.effort, loader.clone())));
    provide_context(StoredValue::new_local(ClipJobs::new(state, loader.clone())));
    let library_jobs = LibraryJobs::new(state, loader.clone(), models.clone());
    // the workspace kept in this browser: set again below when the URL names nothing to show, kept from then on
    let keeper = Keeper::new(state, loader.clone(), library_jobs.clone());
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
    crate::app::embed::launch::start(state, &loader, &runs, &keeper, &urls, &launch, notice);
    // the loader (and the worker it owns) lives as long as the page, even when no component holds
    // it (embed mode has no drop zone or method panels); the app is mounted once, never unmounted
    std::mem::forget(loader.clone());

    // the player and the timeline pinned at the left; the side panel's tabs at the right
    // (embed mode: the stage alone)
    let player = view! { <Player state=state/> }.into_any();
    let timeline = view! { <Timeline state=state/> }.into_any();
    let side = full.then(|| {
        let truth = view! {
            <WhatNext state=state/>
            <GroundTruthPanel state=state/>
            <MetricsPanel state=state/>
        }
        .into_any();
        let methods = state.methods.iter().enumerate().map(|(index, slot)| {
            // a supervised method's panel takes the user's model files and trains in the browser
            let extra = slot.supervised.is_some().then(|| {
                view! {
                    <ModelFile state=state jobs=models.clone() index=index/>
                    <TrainingPanel state=state jobs=models.clone() index=index/>
                }
                .into_any()
            });
            view! { <MethodPanel state=state method=slot runs=runs.clone() extra=extra/> }.into_any()
        });
        let panels = std::iter::once(truth).chain(methods).collect();
        let library = view! { <LibraryPanel state=state jobs=library_jobs.clone()/> }.into_any();
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
            {full.then(|| view! { <DropZone state=state loader=loader.clone() library=library_jobs.clone()/> })}
            <Progress state=state/>
            {full.then(|| view! { <WorkspaceStatus keeper=keeper.clone()/> })}
            {full.then(|| view! {
                <ProjectFile state=state loader=loader.clone() keeper=keeper.clone() models=models.clone()/>
            })}
            {full.then(|| view! { <TakeSwitch state=state jobs=models.clone()/> })}
        </section>
        {full.then(|| view! { <Summary state=state/> })}
        {studio}
    }
}
