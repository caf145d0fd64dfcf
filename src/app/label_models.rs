//! The user's own labelling models for DT-FCN and k-NN: a model file loaded in the method's panel
//! (`use_label_model`) or a DT-FCN trained in the browser ([`super::dtfcn_training`]).
//!
//! * `#<method>-model-file` ("Load model file…", `<method>` = `dtfcn` or `knn`) reads a model
//!   file (`mocapseg train-dtfcn`'s, or a download of the page's training); the worker checks it
//!   (`Model::from_bytes`) and installs it; the page then adds it to the method's model choice
//!   (`#<method>-model`), selects it and runs the method again on the take on screen;
//! * `#<method>-model-status`, next to the file input, says which models the method has, what
//!   was loaded, or — for a bad file — the core's message (the model in use stays).
//!
//! The page holds every model it was given ([`UserModel`], its file's bytes) and the loader sends
//! them to each worker it starts, so a worker replaced after a cancel or a crash still knows them.
//! `document.body.dataset.<method>Model` (`data-dtfcn-model`, `data-knn-model`) says where the
//! last load stands: `idle`, `loading`, `done` or `error`.

use super::loader::Loader;
use super::AppState;
use crate::dtfcn::model::ModelKind;
use crate::protocol::{kind_short, LabelModelInfo};
use js_sys::Uint8Array;
use leptos::prelude::*;
use std::sync::Arc;
use wasm_bindgen::JsCast;
use wasm_bindgen_futures::JsFuture;
use web_sys::{File, HtmlInputElement};

/// The largest model file the page reads (the core refuses weights over 256 MiB).
const MAX_MODEL_BYTES: f64 = 300.0 * 1024.0 * 1024.0;

/// The model kind of a registered method, for the labelling methods.
pub fn kind_of(method: &str) -> Option<ModelKind> {
    match method {
        "dtfcn" => Some(ModelKind::Dtfcn),
        "knn" => Some(ModelKind::Knn),
        _ => None,
    }
}

/// A model the user gave the page: what the worker said of it and its file.
#[derive(Debug, Clone, PartialEq)]
pub struct UserModel {
    pub info: LabelModelInfo,
    /// The file's name (a worker installs the model under the same name from it again).
    pub file: String,
    pub bytes: Arc<Vec<u8>>,
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

/// One method's model file input: where it stands and what its status line says.
#[derive(Debug, Clone, Copy)]
pub struct ModelInput {
    pub state: RwSignal<LoadStatus>,
    pub status: RwSignal<String>,
}

/// The user's models, as signals (part of [`AppState`]).
#[derive(Debug, Clone, Copy)]
pub struct LabelModels {
    /// Every model the user gave the page, both kinds, in the order given (one per kind and name).
    pub models: RwSignal<Vec<Arc<UserModel>>>,
    pub dtfcn: ModelInput,
    pub knn: ModelInput,
}

impl LabelModels {
    pub fn new() -> LabelModels {
        let input = || ModelInput { state: RwSignal::new(LoadStatus::Idle), status: RwSignal::new(String::new()) };
        LabelModels { models: RwSignal::new(Vec::new()), dtfcn: input(), knn: input() }
    }

    /// The file input of the method of `kind`.
    pub fn input(&self, kind: ModelKind) -> ModelInput {
        match kind {
            ModelKind::Dtfcn => self.dtfcn,
            ModelKind::Knn => self.knn,
        }
    }

    /// Adds `model` (replacing one of its kind and name).
    pub fn add(&self, model: UserModel) {
        self.models.update(|list| {
            list.retain(|m| !(m.info.kind == model.info.kind && m.info.name == model.info.name));
            list.push(Arc::new(model));
        });
    }

    /// Drops the model of `kind` called `name`.
    pub fn remove(&self, kind: ModelKind, name: &str) {
        self.models.update(|list| list.retain(|m| !(m.info.kind == kind && m.info.name == name)));
    }
}

/// How a model was made, in a few words.
pub fn describe(info: &LabelModelInfo) -> String {
    let classes = info.classes.join(", ");
    let mut text = format!("{} classes ({classes})", info.classes.len());
    if !info.takes.is_empty() {
        text += &format!(", trained on {} labelled frames of {}", info.frames, info.takes.join(", "));
    }
    if info.epochs_run > 0 {
        text += &format!(", epoch {} of {} kept", info.best_epoch, info.epochs_run);
    }
    text
}

/// The bytes of `file`, or why it cannot be read.
pub async fn read_bytes(file: &File, limit: f64) -> Result<Vec<u8>, String> {
    let name = file.name();
    if file.size() > limit {
        let mib = file.size() / 1024.0 / 1024.0;
        return Err(format!("{name}: {mib:.0} MiB is more than the page reads ({:.0} MiB)", limit / 1024.0 / 1024.0));
    }
    let buffer =
        JsFuture::from(file.array_buffer()).await.map_err(|e| format!("{name}: could not read the file: {e:?}"))?;
    Ok(Uint8Array::new(&buffer).to_vec())
}

/// The files an `<input type=file>` change picked (and the input emptied, so that picking the
/// same file again reads it again).
pub fn picked_files(ev: &leptos::ev::Event) -> Vec<File> {
    let Some(input) = ev.target().and_then(|t| t.dyn_into::<HtmlInputElement>().ok()) else { return Vec::new() };
    let files = input.files().map(|list| (0..list.length()).filter_map(|i| list.get(i)).collect()).unwrap_or_default();
    input.set_value("");
    files
}

/// `#<method>-model-file` and its status line, inside the method's panel.
#[component]
pub fn LabelModelFile(state: AppState, loader: Loader, kind: ModelKind) -> impl IntoView {
    let input = state.labels.input(kind);
    let method = kind.name();
    let short = kind_short(kind);

    let attribute = format!("data-{method}-model");
    Effect::new(move |_| {
        let value = input.state.get().body_state();
        if let Some(body) = web_sys::window().and_then(|w| w.document()).and_then(|d| d.body()) {
            let _ = body.set_attribute(&attribute, value);
        }
    });

    let on_file = move |ev: leptos::ev::Event| {
        let Some(file) = picked_files(&ev).into_iter().next() else { return };
        let loader = loader.clone();
        input.state.set(LoadStatus::Loading);
        input.status.set(format!("Reading {}…", file.name()));
        wasm_bindgen_futures::spawn_local(async move {
            match read_bytes(&file, MAX_MODEL_BYTES).await {
                Ok(bytes) => loader.use_label_model(kind, file.name(), bytes),
                Err(message) => {
                    input.status.set(message);
                    input.state.set(LoadStatus::Failed);
                }
            }
        });
    };
    // the status line: the last load's outcome, else the models the method has
    let status = move || {
        let text = input.status.get();
        if !text.is_empty() {
            return text;
        }
        let mine: Vec<String> = state
            .labels
            .models
            .with(|l| l.iter().filter(|m| m.info.kind == kind).map(|m| m.info.name.clone()).collect());
        let shipped = crate::dtfcn::shipped::NAMES.join(", ");
        if mine.is_empty() {
            format!("Shipped {short} models: {shipped}. Load a model file to add your own.")
        } else {
            format!("Shipped {short} models: {shipped}; yours: {}.", mine.join(", "))
        }
    };
    let id = format!("{method}-model-file");
    view! {
        <div class="ms-method-params ms-model-file">
            <label class="ms-button ms-button--quiet" for=id.clone()>"Load model file…"</label>
            <input
                id=id
                class="ms-visually-hidden"
                type="file"
                accept=".model,application/octet-stream"
                disabled=move || input.state.get() == LoadStatus::Loading
                on:change=on_file
            />
            <span
                id=format!("{method}-model-status")
                class="ms-model-status"
                class:ms-field-error=move || input.state.get() == LoadStatus::Failed
                role="status"
                aria-live="polite"
            >
                {status}
            </span>
        </div>
    }
}
