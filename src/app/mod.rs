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

mod browser_models;
mod consensus;
mod drop_zone;
mod effort;
mod embed;
mod error_banner;
mod fetch;
mod first_visit;
mod ground_truth;
mod keys;
mod library;
mod loader;
mod method_panel;
mod metrics_panel;
mod model_files;
mod motion_image;
mod my_labels;
mod playback;
mod player;
mod progress;
mod row_exports;
mod row_model;
mod segment_menu;
mod stopped;
mod summary;
mod supervised;
mod timeline;
mod training;
mod workspace;

use crate::method::{form, MethodInfo, ParamSpec};
use crate::protocol::{LoadedMotion, MethodView};
use crate::view::timeline::Window;
use leptos::prelude::*;
use std::sync::Arc;
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;

use drop_zone::DropZone;
use embed::{EmbedBar, Launch, UrlNotice};
use error_banner::ErrorBanner;
use ground_truth::{GroundTruth, GroundTruthPanel};
use loader::{Loader, Urls};
use method_panel::MethodPanel;
use metrics_panel::MetricsPanel;
use player::Player;
use progress::Progress;
use summary::Summary;
use supervised::Supervised;
use timeline::Timeline;
use training::{ModelFile, TakeSwitch, TrainingPanel};
use workspace::{SidePanel, Studio};

/// Where loading stands.
#[derive(Debug, Clone, PartialEq)]
pub enum LoadState {
    /// A file is being read or worked on; `fraction` is `None` when the stage cannot say.
    Loading { name: String, stage: String, fraction: Option<f64> },
    /// The last load succeeded.
    Ready,
    /// The last load failed (the error banner says why).
    Failed,
}

impl LoadState {
    /// The value of `document.body.dataset.state`.
    pub fn body_state(&self) -> &'static str {
        match self {
            LoadState::Loading { .. } => "loading",
            LoadState::Ready => "ready",
            LoadState::Failed => "error",
        }
    }
}

/// Where a method's run on the take on screen stands.
#[derive(Debug, Clone, PartialEq)]
pub enum RunState {
    /// Nothing asked yet.
    Idle,
    /// The worker is at `stage`, `fraction` (0..1) done.
    Running { stage: String, fraction: f64 },
    /// The last run finished (the slot's `view` holds it).
    Done,
    /// The last run failed (the error banner says why).
    Failed,
    /// The user stopped the last run.
    Cancelled,
}

impl RunState {
    /// The value of `document.body.dataset.<method>`.
    pub fn body_state(&self) -> &'static str {
        match self {
            RunState::Idle => "idle",
            RunState::Running { .. } => "running",
            RunState::Done => "done",
            RunState::Failed => "error",
            RunState::Cancelled => "cancelled",
        }
    }
}

/// One registered method on the page: who it is, its form, where its run stands, its result.
#[derive(Debug)]
pub struct MethodSlot {
    pub info: MethodInfo,
    pub specs: Vec<ParamSpec>,
    /// The form's text, one field per parameter (booleans as `true` / `false`).
    pub fields: Vec<RwSignal<String>>,
    /// The options of each choice parameter (empty for the others): the method's own, then the
    /// user's models the page added (a supervised method's `model`).
    pub choices: Vec<RwSignal<Vec<String>>>,
    /// A supervised method's training and models.
    pub supervised: Option<Supervised>,
    /// What the method declares about annotating any row's segments (the Effort bars: [`effort`]).
    pub annotator: Option<crate::method::Annotator>,
    pub run: RwSignal<RunState>,
    /// The last finished run on the take on screen.
    pub view: RwSignal<Option<Arc<MethodView>>>,
    /// What the last export of the panel did: (failed, message), shown beside its controls.
    pub export_status: RwSignal<Option<(bool, String)>>,
    /// The last run's refusal when it names a parameter: (parameter, message), shown at its field.
    pub field_error: RwSignal<Option<(String, String)>>,
    /// The last run's failure when it is about the take (not a field): shown in the panel too.
    pub failure: RwSignal<Option<String>>,
}

impl MethodSlot {
    fn new(method: &dyn crate::method::DynMethod) -> MethodSlot {
        let specs = method.param_specs();
        let fields = specs.iter().map(|s| RwSignal::new(form::default_text(&s.default))).collect();
        let choices = specs
            .iter()
            .map(|s| match &s.kind {
                crate::method::ParamKind::Choice { options } => RwSignal::new(options.clone()),
                _ => RwSignal::new(Vec::new()),
            })
            .collect();
        let info = method.info();
        MethodSlot {
            supervised: method.supervision().map(|decl| Supervised::new(decl, &info.name)),
            annotator: method.annotator(),
            info,
            specs,
            fields,
            choices,
            run: RwSignal::new(RunState::Idle),
            view: RwSignal::new(None),
            export_status: RwSignal::new(None),
            field_error: RwSignal::new(None),
            failure: RwSignal::new(None),
        }
    }

    /// The parameters the form holds now, as the worker reads them ([`form::params_from_fields`]: an empty
    /// number field is the method's default, or `null` when that default is `null` — the method decides).
    pub fn params(&self) -> Result<serde_json::Value, crate::method::MethodError> {
        let texts: Vec<String> = self.fields.iter().map(|f| f.get_untracked()).collect();
        form::params_from_fields(&self.info.short, &self.specs, &texts)
    }

    /// The field of parameter `name`, with its choices.
    pub fn param(&self, name: &str) -> Option<(RwSignal<String>, RwSignal<Vec<String>>)> {
        let i = self.specs.iter().position(|s| s.name == name)?;
        Some((self.fields[i], self.choices[i]))
    }
}

/// Everything the page shows, as signals (created once, passed to every component).
#[derive(Debug, Clone, Copy)]
pub struct AppState {
    /// The take on screen (kept when a later load fails).
    pub motion: RwSignal<Option<Arc<LoadedMotion>>>,
    pub load: RwSignal<LoadState>,
    /// The error banner's message, `None` when hidden.
    pub error: RwSignal<Option<String>>,
    /// Current frame, 0-based.
    pub frame: RwSignal<usize>,
    pub playing: RwSignal<bool>,
    /// Playback speed (1 = the file's own frame rate).
    pub speed: RwSignal<f64>,
    /// Playback stops at this frame (set when a primitive is played).
    pub play_until: RwSignal<Option<usize>>,
    /// True when the banner's error is a method's (not a load's).
    pub error_is_run: RwSignal<bool>,
    /// Every registered method, in the registry's order (made once per page).
    pub methods: &'static [MethodSlot],
    /// The frames the timeline shows (ruler, motion image and rows alike).
    pub window: RwSignal<Window>,
    /// The segment the user selected on the timeline.
    pub selected: RwSignal<Option<Selection>>,
    /// Playback loops inside the selected segment.
    pub looping: RwSignal<bool>,
    /// J/K/L: the shuttle's rate (0: ordinary playback; negative: backwards; × the speed menu's).
    pub shuttle: RwSignal<i32>,
    /// The keyboard help overlay is open.
    pub help: RwSignal<bool>,
    /// The imported ground truth ([`ground_truth`]; scored in [`metrics_panel`]).
    pub truth: GroundTruth,
    /// The "my labels" row as a segmentation (`None` while it is empty): scored and exported.
    pub mine: RwSignal<Option<Arc<crate::segment::Segmentation>>>,
    /// The side panel's tab shown ([`workspace`]): `truth` or a method's name.
    pub panel: RwSignal<String>,
    /// The Effort bars under every row ([`effort`]).
    pub effort: effort::EffortBars,
    /// The library of takes ([`library`]).
    pub library: library::LibraryState,
}

/// A segment selected on the timeline: its row (`<method>-actions` or `<method>-primitives`)
/// and its frames (inclusive).
#[derive(Debug, Clone, PartialEq)]
pub struct Selection {
    pub row: String,
    pub start: usize,
    pub end: usize,
}

impl AppState {
    fn new() -> AppState {
        AppState {
            motion: RwSignal::new(None),
            load: RwSignal::new(LoadState::Loading { name: String::new(), stage: "starting".into(), fraction: None }),
            error: RwSignal::new(None),
            frame: RwSignal::new(0),
            playing: RwSignal::new(false),
            speed: RwSignal::new(1.0),
            play_until: RwSignal::new(None),
            error_is_run: RwSignal::new(false),
            methods: Box::leak(crate::methods::registry().iter().map(|m| MethodSlot::new(*m)).collect()),
            window: RwSignal::new(Window::full(1)),
            selected: RwSignal::new(None),
            looping: RwSignal::new(true),
            shuttle: RwSignal::new(0),
            help: RwSignal::new(false),
            truth: GroundTruth::new(),
            mine: RwSignal::new(None),
            panel: RwSignal::new(workspace::TRUTH_TAB.to_string()),
            effort: effort::EffortBars::new(),
            library: library::LibraryState::new(),
        }
    }

    /// Shows `message` in the error banner (a load's error).
    pub fn show_error(&self, message: String) {
        self.error_is_run.set(false);
        self.error.set(Some(message));
    }

    /// Shows `message` in the error banner (a method's error).
    pub fn show_run_error(&self, message: String) {
        self.error_is_run.set(true);
        self.error.set(Some(message));
    }

    /// Frames per second of the take on screen (0 when none).
    pub fn fps(&self) -> f64 {
        self.motion.with(|m| m.as_ref().map_or(0.0, |m| m.summary.fps))
    }

    /// Number of frames of the take on screen (0 when none).
    pub fn frames(&self) -> usize {
        self.motion.with(|m| m.as_ref().map_or(0, |m| m.summary.frames))
    }
}

/// The message of a JS error (or the value itself, as text).
/// Sets `<body>`'s data attributes: where the page stands, as the end-to-end tests read it.
pub(crate) fn set_body_data(attributes: &[(&str, &str)]) {
    if let Some(body) = web_sys::window().and_then(|w| w.document()).and_then(|d| d.body()) {
        for (name, value) in attributes {
            let _ = body.set_attribute(name, value);
        }
    }
}

/// Milliseconds since the page started.
pub(crate) fn now_ms() -> f64 {
    web_sys::window().and_then(|w| w.performance()).map_or(0.0, |p| p.now())
}

pub(crate) fn js_message(value: &JsValue) -> String {
    value
        .dyn_ref::<js_sys::Error>()
        .map(|e| String::from(e.message()))
        .or_else(|| value.as_string())
        .unwrap_or_else(|| format!("{value:?}"))
}

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
    stopped::install();
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
    embed::start(state, &loader, &urls, &launch, notice);
    // the loader (and the worker it owns) lives as long as the page, even when no component holds
    // it (embed mode has no drop zone or method panels); the app is mounted once, never unmounted
    std::mem::forget(loader.clone());

    // the player and the timeline pinned at the left; the side panel's tabs at the right
    // (embed mode: the stage alone)
    let player = view! { <Player state=state/> }.into_any();
    let timeline = view! { <Timeline state=state/> }.into_any();
    let side = full.then(|| {
        let truth = view! {
            <first_visit::WhatNext state=state/>
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
        let library = view! { <library::LibraryPanel state=state loader=loader.clone()/> }.into_any();
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
