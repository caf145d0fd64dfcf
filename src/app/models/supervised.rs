//! A supervised method's training and models on the page, as state (part of its
//! [`crate::app::state::MethodSlot`]): where a training stands, the user's models, the options' form text —
//! what the panels ([`crate::app::models::training`]) show and the loader's jobs (`crate::app::loader`) update.

use crate::method::supervised::{model_file_name, ModelInfo, StepReport, TrainingReport};
use crate::method::{form, Supervision};
use leptos::prelude::*;
use std::sync::Arc;

/// Where a training stands.
#[derive(Debug, Clone, PartialEq)]
pub enum TrainState {
    /// Nothing trained yet.
    Idle,
    /// The worker prepares (`stage`, `step` 0) or trains (`step` of `steps` done).
    Training { stage: String, step: usize, steps: usize, fraction: f64 },
    /// Stop was pressed: the worker ends after the step under way.
    Stopping,
    /// The last training ended with a model.
    Done,
    /// The last training was cancelled before its first step (the worker was replaced).
    Cancelled,
    /// The last training was refused or failed.
    Failed,
}

impl TrainState {
    /// The value of `document.body.dataset.<method>Training`.
    pub fn body_state(&self) -> &'static str {
        match self {
            TrainState::Idle => "idle",
            TrainState::Training { .. } => "training",
            TrainState::Stopping => "stopping",
            TrainState::Done => "done",
            TrainState::Cancelled => "cancelled",
            TrainState::Failed => "error",
        }
    }

    pub fn busy(&self) -> bool {
        matches!(self, TrainState::Training { .. } | TrainState::Stopping)
    }
}

/// Where the last model file load of one method stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LoadStatus {
    Idle,
    Loading,
    Done,
    Failed,
}

impl LoadStatus {
    pub fn body_state(self) -> &'static str {
        match self {
            LoadStatus::Idle => "idle",
            LoadStatus::Loading => "loading",
            LoadStatus::Done => "done",
            LoadStatus::Failed => "error",
        }
    }
}

/// A model the user gave the page or trained in it: what the worker said of it and its file.
#[derive(Debug, Clone, PartialEq)]
pub struct UserModel {
    pub info: ModelInfo,
    /// The file's name (a worker stores the model under the same name from it again).
    pub file: String,
    pub bytes: Arc<Vec<u8>>,
}

/// One of the user's models kept in this browser that this page's worker would not take (a model file of an
/// older format, of another skeleton or rate, or damaged): never deleted by the page — listed with why, exportable,
/// and forgotten only when the user asks.
#[derive(Debug, Clone, PartialEq)]
pub struct Unloadable {
    pub name: String,
    pub file: String,
    pub bytes: Arc<Vec<u8>>,
    /// What the worker said.
    pub why: String,
}

/// A model whose training finished after another take was opened: held until the user says
/// what to do with it ([`PendingChoice`]); nothing is applied to the take on screen unasked.
#[derive(Debug, Clone, PartialEq)]
pub struct PendingModel {
    pub info: ModelInfo,
    pub bytes: Arc<Vec<u8>>,
    /// The take it was trained on, and the one on screen when it finished.
    pub trained_on: String,
    pub now_on: String,
}

/// What the user does with a [`PendingModel`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PendingChoice {
    /// List it in the model choice (and keep it in this browser) without running it.
    Keep,
    /// As Keep, and run the method on the take on screen with it.
    Apply,
    /// Forget it.
    Discard,
}

/// A trained model the page offers for download.
#[derive(Debug, Clone, PartialEq)]
pub struct TrainedFile {
    pub name: String,
    pub bytes: Arc<Vec<u8>>,
}

/// A training asked from elsewhere on the page (the "my labels" row).
#[derive(Debug, Clone, PartialEq)]
pub enum TrainRequest {
    /// Train on `csv` (a label CSV named `labels_name`) with the form's options; `model_name`
    /// unless the user typed a name.
    Labels { labels_name: String, csv: String, model_name: String },
    /// Stop the training under way (as the Stop button).
    Stop,
}

/// What the user asked to train (the loader keeps it to send it again to a new worker).
#[derive(Debug, Clone)]
pub struct TrainAsk {
    pub name: String,
    pub labels_name: String,
    pub labels: String,
    /// Takes besides the one on screen: file names and bytes.
    pub extra: Vec<(String, Arc<Vec<u8>>)>,
    /// The options as the method's table reads them.
    pub options: serde_json::Value,
    /// Continue the training of this model of the user's instead of starting afresh.
    pub continue_from: Option<String>,
    /// The take kept out as the validation take (one of the takes trained on; a method that
    /// declares one).
    pub validation: Option<String>,
}

/// A supervised method's training and models on the page, as signals (part of its
/// [`crate::app::state::MethodSlot`]).
#[derive(Debug)]
pub struct Supervised {
    pub decl: Supervision,
    /// The training options' form text, one per row of `decl.training`.
    pub fields: Vec<RwSignal<String>>,
    /// The model's name, and whether the user typed it.
    pub name: RwSignal<String>,
    pub named: RwSignal<bool>,
    /// The chosen label CSV: its name and text.
    pub labels: RwSignal<Option<(String, String)>>,
    /// Takes besides the one on screen.
    pub extra: RwSignal<Vec<(String, Arc<Vec<u8>>)>>,
    /// The validation take chosen in the form (empty: none).
    pub validation: RwSignal<String>,
    pub state: RwSignal<TrainState>,
    /// The status line.
    pub status: RwSignal<String>,
    /// The steps of the training under way or the last one.
    pub steps: RwSignal<Vec<StepReport>>,
    /// The last training's report.
    pub report: RwSignal<Option<TrainingReport>>,
    /// What is wrong with which input (shown next to it).
    pub errors: RwSignal<Vec<(String, String)>>,
    /// The last trained model.
    pub trained: RwSignal<Option<TrainedFile>>,
    /// A model trained on another take than the one on screen now, waiting for the user's choice.
    pub pending: RwSignal<Option<PendingModel>>,
    /// What another part of the page asks (taken by the panel).
    pub request: RwSignal<Option<TrainRequest>>,
    /// Every model the user gave the page or trained in it, in the order given (one per name).
    pub models: RwSignal<Vec<Arc<UserModel>>>,
    /// The user's models kept in this browser that do not load here, with why ([`Unloadable`]).
    pub unloadable: RwSignal<Vec<Arc<Unloadable>>>,
    /// The model file input: where its last load stands and its status line.
    pub file_state: RwSignal<LoadStatus>,
    pub file_status: RwSignal<String>,
}

impl Supervised {
    pub fn new(decl: Supervision, method: &str) -> Supervised {
        let fields = decl.training.iter().map(|s| RwSignal::new(form::field_text(&s.default))).collect();
        Supervised {
            decl,
            fields,
            name: RwSignal::new(format!("my-{method}")),
            named: RwSignal::new(false),
            labels: RwSignal::new(None),
            extra: RwSignal::new(Vec::new()),
            validation: RwSignal::new(String::new()),
            state: RwSignal::new(TrainState::Idle),
            status: RwSignal::new(String::new()),
            steps: RwSignal::new(Vec::new()),
            report: RwSignal::new(None),
            errors: RwSignal::new(Vec::new()),
            trained: RwSignal::new(None),
            pending: RwSignal::new(None),
            request: RwSignal::new(None),
            models: RwSignal::new(Vec::new()),
            unloadable: RwSignal::new(Vec::new()),
            file_state: RwSignal::new(LoadStatus::Idle),
            file_status: RwSignal::new(String::new()),
        }
    }

    /// Shows `message` at the input `input`.
    pub fn refuse(&self, input: &str, message: String) {
        self.errors.update(|e| {
            e.retain(|(i, _)| i != input);
            e.push((input.to_string(), message));
        });
    }

    /// Whether `input` is one the form shows a message at.
    pub fn has_input(&self, input: &str) -> bool {
        matches!(input, "labels" | "name")
            || (input == "takes" && self.decl.more_takes)
            || (input == "validation" && self.decl.validation_take && self.decl.more_takes)
            || self.decl.training.iter().any(|s| s.name == input)
    }

    /// Adds `model` (replacing one of its name).
    pub fn add(&self, model: UserModel) {
        self.models.update(|list| {
            list.retain(|m| m.info.name != model.info.name);
            list.push(Arc::new(model));
        });
    }

    /// Drops the model called `name` (a usable one, or one that does not load here).
    pub fn remove(&self, name: &str) {
        self.models.update(|list| list.retain(|m| m.info.name != name));
        self.unloadable.update(|list| list.retain(|m| m.name != name));
    }

    /// Lists `model` among the models that do not load here (replacing one of its name), out of the model choice.
    pub fn set_unloadable(&self, model: Unloadable) {
        self.models.update(|list| list.retain(|m| m.info.name != model.name));
        self.unloadable.update(|list| {
            list.retain(|m| m.name != model.name);
            list.push(Arc::new(model));
        });
    }

    /// The model file name of the model `name`.
    pub fn file_name(&self, name: &str) -> String {
        model_file_name(name, &self.decl.model_extension)
    }
}

/// How a model was made, in a few words.
pub fn describe(info: &ModelInfo) -> String {
    info.origin.clone()
}
