//! The page's state: everything it shows, as leptos signals ([`AppState`], created once and passed
//! to every component), where the load and each method's run stand, and one slot per registered method.

use crate::app::effort::state::EffortBars;
use crate::app::library::state::LibraryState;
use crate::app::models::supervised::Supervised;
use crate::app::timeline::window::Window;
use crate::app::truth::state::GroundTruth;
use crate::method::{form, MethodInfo, ParamSpec};
use crate::protocol::{LoadedMotion, MethodView};
use leptos::prelude::*;
use std::sync::Arc;

/// The side panel's tab of the ground truth and the scores (the others are the methods' names).
pub const TRUTH_TAB: &str = "truth";

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
    /// The occurrence of a library cluster playing (its row and frames), highlighted on its row.
    pub occurrence: RwSignal<Option<Selection>>,
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
    pub effort: EffortBars,
    /// The library of takes ([`library`]).
    pub library: LibraryState,
    /// The colour each label is drawn in, on every row ([`AppState::label_css`]).
    pub label_colours: StoredValue<crate::segment::palette::LabelColours>,
}

/// Where this browser keeps the labels' colours (so that a label keeps its colour across takes and visits).
const LABEL_COLOURS_KEY: &str = "mocapseg.label-colours.v1";

/// The page's local storage, if the browser gives one.
fn local_storage() -> Option<web_sys::Storage> {
    web_sys::window()?.local_storage().ok().flatten()
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
    pub(crate) fn new() -> AppState {
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
            occurrence: RwSignal::new(None),
            shuttle: RwSignal::new(0),
            help: RwSignal::new(false),
            truth: GroundTruth::new(),
            mine: RwSignal::new(None),
            panel: RwSignal::new(TRUTH_TAB.to_string()),
            effort: EffortBars::new(),
            library: LibraryState::new(),
            label_colours: StoredValue::new(
                local_storage()
                    .and_then(|s| s.get_item(LABEL_COLOURS_KEY).ok().flatten())
                    .map(|t| crate::segment::palette::LabelColours::from_json(&t))
                    .unwrap_or_default(),
            ),
        }
    }

    /// The CSS colour of label `label` — the same on every row, take and visit in this browser, distinct from the
    /// other labels met (up to twelve: [`crate::segment::palette::LabelColours`]).
    pub fn label_css(&self, label: &str) -> String {
        let before = self.label_colours.with_value(|c| c.len());
        let mut css = String::new();
        self.label_colours.update_value(|c| css = c.css(label));
        if self.label_colours.with_value(|c| c.len()) != before {
            let kept = self.label_colours.with_value(|c| c.to_json());
            if let Some(storage) = local_storage() {
                let _ = storage.set_item(LABEL_COLOURS_KEY, &kept);
            }
        }
        css
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

    /// The supervised methods the "my labels" row trains in one click (those that declare `trains_on_my_labels`:
    /// the k-NN and DT-FCN), in the registry's order: their short names and their trainings.
    pub fn my_labels_trainers(&self) -> Vec<(&'static str, &'static Supervised)> {
        let methods: &'static [MethodSlot] = self.methods;
        methods
            .iter()
            .filter_map(|m| {
                m.supervised.as_ref().filter(|s| s.decl.trains_on_my_labels).map(|s| (m.info.short.as_str(), s))
            })
            .collect()
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
