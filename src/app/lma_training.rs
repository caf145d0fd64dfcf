//! `#lma-training`, right under the LMA panel: the user's own Effort labels train the LMA
//! classifier family in the worker (`train_lma`), or a family they saved is loaded
//! (`use_lma_model`); LMA then runs again on the take on screen with it.
//!
//! * `#lma-labels` picks the labels CSV (`file,start_frame,end_frame,space,time,weight,flow`),
//!   `#lma-train` trains on its rows for the take on screen, `#lma-train-cancel` stops it (the
//!   worker is replaced) and `#lma-train-progress` shows the trainer's stage;
//! * `#lma-train-status` says which family LMA uses, how the last training or load went, or what
//!   was wrong (the CSV's line, no row for this take, too few segments, a bad family file);
//! * `#lma-train-report`: per Effort factor, the segments per class and the networks' errors;
//! * `#lma-model-download` saves the trained family (`lma-effort-<take>.json`, a Blob URL),
//!   `#lma-model-file` loads a saved one, `#lma-model-shipped` goes back to the shipped family.
//!
//! `document.body.dataset.lmaTraining` (`data-lma-training`) says where it stands: `idle` (the
//! shipped family), `training`, `switching` (a family is being loaded or dropped), `done` (the
//! user's family is in use) or `error` (the last training or load failed; the family in use
//! before it stays). The page holds the user's family ([`UserFamily`]) and the loader gives it
//! to every worker it starts, so a cancel or a crash never silently returns to the shipped one.

use super::loader::Loader;
use super::motion_image::stem;
use super::AppState;
use crate::lma::corpus::CorpusConfig;
use crate::lma::training::TrainConfig;
use crate::protocol::FactorSummary;
use js_sys::Array;
use leptos::prelude::*;
use std::sync::Arc;
use wasm_bindgen::JsCast;
use wasm_bindgen_futures::JsFuture;
use web_sys::{Blob, BlobPropertyBag, File, HtmlInputElement, Url};

/// The registry name of the method whose classifiers this trains.
pub const METHOD: &str = "lma";

/// The largest labels file and family file the page reads.
const MAX_LABELS_BYTES: f64 = 16.0 * 1024.0 * 1024.0;
const MAX_FAMILY_BYTES: f64 = 64.0 * 1024.0 * 1024.0;

/// Where training stands.
#[derive(Debug, Clone, PartialEq)]
pub enum TrainingState {
    /// LMA uses the shipped family.
    Idle,
    /// The worker trains, at `stage`, `fraction` (0..1) done.
    Training { stage: String, fraction: f64 },
    /// The worker is loading a family or going back to the shipped one.
    Switching,
    /// LMA uses the user's family (trained or loaded).
    Done,
    /// The last training or load failed (the status line says why).
    Failed,
}

impl TrainingState {
    /// The value of `document.body.dataset.lmaTraining`.
    pub fn body_state(&self) -> &'static str {
        match self {
            TrainingState::Idle => "idle",
            TrainingState::Training { .. } => "training",
            TrainingState::Switching => "switching",
            TrainingState::Done => "done",
            TrainingState::Failed => "error",
        }
    }

    fn busy(&self) -> bool {
        matches!(self, TrainingState::Training { .. } | TrainingState::Switching)
    }
}

/// A family of the user's that the page holds: LMA runs with it, and every new worker gets it.
#[derive(Debug, Clone, PartialEq)]
pub struct UserFamily {
    /// The family as JSON (`EffortModel::to_json`).
    pub json: String,
    /// Where its labels came from, in words.
    pub origin: String,
    /// The take it was trained on (its download is `lma-effort-<take>.json`); `None` for a
    /// family loaded from a file.
    pub trained_on: Option<String>,
}

/// The training's state, as signals (part of [`AppState`]).
#[derive(Debug, Clone, Copy)]
pub struct LmaTraining {
    pub state: RwSignal<TrainingState>,
    /// The status line.
    pub status: RwSignal<String>,
    /// The last training's report (empty before one, and after a family is loaded or dropped).
    pub report: RwSignal<Vec<FactorSummary>>,
    /// The user's family in use, `None`: the shipped one.
    pub family: RwSignal<Option<Arc<UserFamily>>>,
}

/// The status line before anything is asked.
const SHIPPED_STATUS: &str = "LMA uses the shipped classifiers (trained on stand-in labels). Choose an Effort \
                                  labels CSV to train your own on the take on screen.";

impl LmaTraining {
    pub fn new() -> LmaTraining {
        LmaTraining {
            state: RwSignal::new(TrainingState::Idle),
            status: RwSignal::new(SHIPPED_STATUS.into()),
            report: RwSignal::new(Vec::new()),
            family: RwSignal::new(None),
        }
    }
}

/// The text of `file`, or why it cannot be read.
async fn read_text(file: &File, limit: f64) -> Result<String, String> {
    let name = file.name();
    if file.size() > limit {
        let mib = file.size() / 1024.0 / 1024.0;
        return Err(format!("{name}: {mib:.0} MiB is more than the page reads ({:.0} MiB)", limit / 1024.0 / 1024.0));
    }
    let text = JsFuture::from(file.text()).await.map_err(|e| format!("{name}: could not read the file: {e:?}"))?;
    text.as_string().ok_or_else(|| format!("{name}: the file is not text"))
}

/// The file an `<input type=file>` change picked (and the input emptied, so that picking the
/// same file again reads it again).
fn picked(ev: &leptos::ev::Event) -> Option<File> {
    let input = ev.target().and_then(|t| t.dyn_into::<HtmlInputElement>().ok())?;
    let file = input.files().and_then(|f| f.get(0));
    input.set_value("");
    file
}

/// A Blob URL of `json` (the caller revokes it).
fn json_url(json: &str) -> Option<String> {
    let options = BlobPropertyBag::new();
    options.set_type("application/json");
    let blob = Blob::new_with_str_sequence_and_options(&Array::of1(&json.into()), &options).ok()?;
    Url::create_object_url_with_blob(&blob).ok()
}

fn percent(error: f32) -> String {
    format!("{:.0} %", 100.0 * error)
}

#[component]
pub fn LmaTrainingPanel(state: AppState, loader: Loader) -> impl IntoView {
    let lma = state.lma;
    // the chosen labels file: its name and text
    let labels = RwSignal::new(None::<(String, String)>);
    let busy = move || lma.state.with(TrainingState::busy);

    Effect::new(move |_| {
        let value = lma.state.with(TrainingState::body_state);
        if let Some(body) = web_sys::window().and_then(|w| w.document()).and_then(|d| d.body()) {
            let _ = body.set_attribute("data-lma-training", value);
        }
    });

    // the download link of a trained family: a Blob URL, revoked when the family changes
    let download = RwSignal::new(None::<(String, String)>);
    Effect::new(move |_| {
        let next = lma.family.with(|f| {
            let f = f.as_ref()?;
            let take = f.trained_on.as_ref()?;
            Some((json_url(&f.json)?, format!("lma-effort-{}.json", stem(take))))
        });
        if let Some((old, _)) = download.get_untracked() {
            let _ = Url::revoke_object_url(&old);
        }
        download.set(next);
    });
    on_cleanup(move || {
        if let Some((old, _)) = download.get_untracked() {
            let _ = Url::revoke_object_url(&old);
        }
    });

    let on_labels = move |ev: leptos::ev::Event| {
        let Some(file) = picked(&ev) else { return };
        wasm_bindgen_futures::spawn_local(async move {
            match read_text(&file, MAX_LABELS_BYTES).await {
                Ok(text) => {
                    lma.status.set(format!("{}: ready to train on the take on screen.", file.name()));
                    labels.set(Some((file.name(), text)));
                }
                Err(message) => {
                    labels.set(None);
                    lma.status.set(message);
                    lma.state.set(TrainingState::Failed);
                }
            }
        });
    };
    let train_loader = loader.clone();
    let on_train = move |_| {
        if let Some((name, text)) = labels.get_untracked() {
            train_loader.train_lma(name, text);
        }
    };
    let cancel_loader = loader.clone();
    let on_cancel = move |_| cancel_loader.cancel_lma_training();
    let model_loader = loader.clone();
    let on_model = move |ev: leptos::ev::Event| {
        let Some(file) = picked(&ev) else { return };
        let loader = model_loader.clone();
        wasm_bindgen_futures::spawn_local(async move {
            match read_text(&file, MAX_FAMILY_BYTES).await {
                Ok(text) => loader.use_lma_model(Some((file.name(), text))),
                Err(message) => {
                    lma.status.set(message);
                    lma.state.set(TrainingState::Failed);
                }
            }
        });
    };
    let on_shipped = move |_| loader.use_lma_model(None);

    let progress = move || {
        lma.state.with(|s| match s {
            TrainingState::Training { stage, fraction } => (stage.clone(), *fraction),
            _ => (String::new(), 0.0),
        })
    };
    let training = move || lma.state.with(|s| matches!(s, TrainingState::Training { .. }));
    let rows = move || {
        lma.report.with(|report| {
            report
                .iter()
                .map(|r| {
                    let [indulging, neutral, condensing] = r.segments;
                    view! {
                        <tr data-factor=r.factor.clone()>
                            <th scope="row">{r.factor.clone()}</th>
                            <td>{format!("{indulging} / {neutral} / {condensing}")}</td>
                            <td>{r.hidden}</td>
                            <td>{percent(r.train_error)}</td>
                            <td class="ms-lma-validation">{percent(r.validation_error)}</td>
                            <td>{percent(r.shifted_validation_error)}</td>
                        </tr>
                    }
                })
                .collect_view()
        })
    };

    let shift = CorpusConfig::default().max_shift;
    let classifiers = (2 * shift + 1).pow(2);
    let caption = format!(
        "Error rates of each factor's unshifted network (the paper's rule: the right output beats the other two \
         together) on its training segments and on the {:.0} % held out for validation, and the boundary-shifted \
         networks' mean on their shifted validation segments.",
        100.0 * TrainConfig::default().validation
    );

    view! {
        <section id="lma-training" class="ms-lma-training" aria-label="LMA classifiers from your own Effort labels">
            <div class="ms-timeline-head">
                <h3>"LMA classifiers from your own Effort labels"</h3>
            </div>
            <p class="ms-lma-help">
                "A CSV with the header " <code>"file,start_frame,end_frame,space,time,weight,flow"</code>
                ": frames of the file (0-based, inclusive), each factor " <code>"indulging"</code> ", "
                <code>"neutral"</code> " or " <code>"condensing"</code>
                {format!(
                    ". Its rows for the take on screen (at least 8) train the {classifiers} classifiers of each factor \
                     in this tab; rows for other files are left out."
                )}
            </p>
            <div class="ms-method-params">
                <label class="ms-button ms-button--quiet" for="lma-labels">"Labels CSV…"</label>
                <input id="lma-labels" class="ms-visually-hidden" type="file" accept=".csv,text/csv" on:change=on_labels/>
                <span id="lma-labels-name" class="ms-lma-file">
                    {move || labels.with(|l| l.as_ref().map_or("no file chosen".to_string(), |(name, _)| name.clone()))}
                </span>
                <button
                    id="lma-train"
                    class="ms-button"
                    type="button"
                    disabled=move || busy() || labels.with(Option::is_none) || state.motion.with(Option::is_none)
                    on:click=on_train
                >
                    "Train"
                </button>
                <button id="lma-train-cancel" class="ms-button ms-button--quiet" type="button" hidden=move || !training() on:click=on_cancel>
                    "Cancel"
                </button>
                <div id="lma-train-progress" class="ms-progress" role="status" aria-live="polite" hidden=move || !training()>
                    <progress max="1" value=move || progress().1.clamp(0.0, 1.0).to_string()></progress>
                    <span class="ms-progress-label">{move || format!("Training: {}…", progress().0)}</span>
                </div>
            </div>
            <p id="lma-train-status" class="ms-lma-status" class:ms-lma-status--error=move || lma.state.with(|s| *s == TrainingState::Failed) role="status" aria-live="polite">
                {move || lma.status.get()}
            </p>
            <table id="lma-train-report" class="ms-lma-report" hidden=move || lma.report.with(Vec::is_empty)>
                <caption>{caption}</caption>
                <thead>
                    <tr>
                        <th scope="col">"factor"</th>
                        <th scope="col">"segments (indulging / neutral / condensing)"</th>
                        <th scope="col">"hidden units"</th>
                        <th scope="col">"training error"</th>
                        <th scope="col">"validation error"</th>
                        <th scope="col">"shifted validation error"</th>
                    </tr>
                </thead>
                <tbody>{rows}</tbody>
            </table>
            <div class="ms-method-params">
                <a
                    id="lma-model-download"
                    class="ms-button ms-button--quiet"
                    href=move || download.with(|d| d.as_ref().map(|(url, _)| url.clone()))
                    download=move || download.with(|d| d.as_ref().map(|(_, name)| name.clone()))
                    hidden=move || download.with(Option::is_none)
                >
                    "Download your classifiers"
                </a>
                <label class="ms-button ms-button--quiet" for="lma-model-file">"Load classifiers…"</label>
                <input
                    id="lma-model-file"
                    class="ms-visually-hidden"
                    type="file"
                    accept=".json,application/json"
                    disabled=busy
                    on:change=on_model
                />
                <button
                    id="lma-model-shipped"
                    class="ms-button ms-button--quiet"
                    type="button"
                    disabled=move || busy() || lma.family.with(Option::is_none)
                    on:click=on_shipped
                >
                    "Back to the shipped classifiers"
                </button>
            </div>
        </section>
    }
}
