//! The ground truth on the page: `#truth-panel` imports a file and `#row-truth` shows it on the
//! timeline (drawn as the methods' rows are, [`SegmentRow`]).
//!
//! The file (`#truth-file`) is a CSV `start_frame,end_frame,label`, the shared data's CSV
//! (`trial,…,label,start_frame,end_frame,…`, the trial named like the take, else the file's only
//! one, else picked in `#truth-trial`) or a segmentation JSON; the core's
//! [`import_truth`] reads it — the function `mocapseg eval --truth` reads it with, with the same
//! choices: where CSV frames start (`#truth-base`, 1 or 0) and the labels' frame rate
//! (`#truth-fps`, empty = the take's own). The file's text is kept, so changing a choice (or
//! loading another take) reads it again without picking it again; `#truth-applied` says what was
//! applied, `#truth-error` (at the control) why it could not be read, with the file, the line and
//! what was expected. `#truth-export-json`, `-csv` and `-clips` save the truth as read against the
//! take (its frames, at the take's rate) as segmentation JSON, label CSV or BVH clips
//! ([`RowExports`]). `document.body.dataset.truth` is `none`, `loaded` or `error`.

use crate::app::state::AppState;
use crate::app::timeline::method_rows::SegmentRow;
use crate::app::timeline::row_exports::RowExports;
use crate::app::timeline::rows::ACTION_LEVELS;
use crate::app::truth::state::{GroundTruth, TruthState};
use crate::method::Details;
use crate::protocol::MethodView;
use crate::segment::truth::Truth;
use crate::segment::truth_import::{csv_trials, import_truth, ImportOptions, Take};
use crate::segment::{Level, Segment, Segmentation};
use leptos::prelude::*;
use std::sync::Arc;
use wasm_bindgen::JsCast;
use wasm_bindgen_futures::JsFuture;
use web_sys::{File, HtmlInputElement};

/// The largest ground-truth file the page reads.
const MAX_BYTES: f64 = 32.0 * 1024.0 * 1024.0;

/// Frame rates offered in `#truth-fps` (any other may be typed).
const COMMON_RATES: [&str; 9] = ["10", "24", "25", "30", "50", "60", "100", "120", "240"];

/// The choices as the core takes them, or what is wrong with the rate typed.
fn options(truth: &GroundTruth) -> Result<ImportOptions, String> {
    let first_frame = if truth.base.get() == "0" { 0 } else { 1 };
    let typed = truth.fps.get();
    let label_fps = match typed.trim() {
        "" => None,
        t => Some(t.parse::<f64>().ok().filter(|f| f.is_finite() && *f > 0.0).ok_or_else(|| {
            format!("the labels' frame rate: expected a positive number of frames per second, found `{t}`")
        })?),
    };
    let trial = Some(truth.trial.get()).filter(|t| !t.is_empty());
    Ok(ImportOptions { first_frame, label_fps, bvh_row_offset: 0, trial })
}

/// The truth as the segmentation of a timeline row: one action per labelled segment, its
/// cluster the label's index in order of first appearance, drawn as a labelling row in its
/// label's colour (`params.colours`, [`label_colours`]).
fn as_view(truth: &Truth, take: &Take, state: AppState) -> MethodView {
    let mut labels: Vec<&str> = Vec::new();
    let segments = truth
        .segments
        .iter()
        .map(|s| {
            let cluster = labels.iter().position(|l| *l == s.label).unwrap_or_else(|| {
                labels.push(&s.label);
                labels.len() - 1
            });
            Segment {
                start: s.start,
                end: s.end,
                label: s.label.clone(),
                level: Level::Action,
                cluster: Some(cluster),
                score: None,
                mirror_of: None,
                effort: None,
            }
        })
        .collect();
    let colours = label_colours(state, &labels);
    let segmentation = Segmentation {
        file: take.name.clone(),
        fps: take.fps,
        frames: take.frames,
        method: "truth".into(),
        params: serde_json::json!({ "colours": colours }),
        segments,
    };
    MethodView { method: "truth".into(), segmentation, details: Details::default() }
}

/// The colour of each label: the one it has on every row ([`AppState::label_css`]).
fn label_colours(state: AppState, labels: &[&str]) -> Vec<String> {
    labels.iter().map(|label| state.label_css(label)).collect()
}

/// The text of `file`, or why it cannot be read.
async fn read_text(file: &File) -> Result<String, String> {
    let name = file.name();
    if file.size() > MAX_BYTES {
        return Err(format!(
            "{name}: {:.0} MiB is more than the page reads as ground truth (32 MiB)",
            file.size() / 1048576.0
        ));
    }
    let text = JsFuture::from(file.text()).await.map_err(|e| format!("{name}: could not read the file: {e:?}"))?;
    text.as_string().ok_or_else(|| format!("{name}: the file is not text"))
}

/// Reads the kept truth file again against the take on screen with the panel's choices (or clears the truth).
fn reread(state: AppState, truth: GroundTruth) {
    let file = truth.file.get();
    let take = state.motion.with(|m| {
        m.as_ref().map(|m| Take { name: m.summary.name.clone(), frames: m.summary.frames, fps: m.summary.fps })
    });
    let options = options(&truth);
    let Some((name, text)) = file else {
        truth.state.set(TruthState::None);
        truth.view.set(None);
        truth.trials.set(Vec::new());
        return;
    };
    truth.trials.set(csv_trials(&text));
    let result = match (take, options) {
        (None, _) => Err(format!("{name}: load a take first: the ground truth is read against its frames")),
        (_, Err(e)) => Err(format!("{name}: {e}")),
        (Some(take), Ok(options)) => import_truth(&text, &take, &options)
            .map(|i| (Arc::new(as_view(&i.truth, &take, state)), Arc::new(i)))
            .map_err(|e| format!("{name}: {e}")),
    };
    match result {
        Ok((view, imported)) => {
            truth.view.set(Some(view));
            truth.state.set(TruthState::Loaded(imported));
        }
        Err(message) => {
            truth.view.set(None);
            truth.state.set(TruthState::Failed(message));
        }
    }
}

/// `<body data-truth>`: where the truth stands (`none`, `loaded`, `error`), as the end-to-end tests read it.
fn mark_body(truth: GroundTruth) {
    let value = truth.state.with(|s| match s {
        TruthState::None => "none",
        TruthState::Loaded(_) => "loaded",
        TruthState::Failed(_) => "error",
    });
    crate::app::dom::set_body_data(&[("data-truth", value)]);
}

/// A truth file picked: its text kept (the panel reads it again), or why it could not be read.
fn pick(truth: GroundTruth, ev: leptos::ev::Event) {
    let Some(input) = ev.target().and_then(|t| t.dyn_into::<HtmlInputElement>().ok()) else { return };
    let file = input.files().and_then(|f| f.get(0));
    input.set_value(""); // picking the same file again reads it again
    let Some(file) = file else { return };
    wasm_bindgen_futures::spawn_local(async move {
        match read_text(&file).await {
            Ok(text) => {
                truth.trial.set(String::new());
                truth.file.set(Some((file.name(), Arc::new(text))));
            }
            Err(message) => {
                truth.file.set(None);
                truth.view.set(None);
                truth.state.set(TruthState::Failed(message));
            }
        }
    });
}

/// `#truth-panel`: the import control, its choices, what was applied and any error.
#[component]
pub fn GroundTruthPanel(state: AppState) -> impl IntoView {
    let truth = state.truth;
    // a new take: its trial is found again from its name
    Effect::new(move |_| {
        state.motion.track();
        truth.trial.set(String::new());
    });
    // read the kept file again whenever it, a choice or the take changes
    Effect::new(move |_| reread(state, truth));
    Effect::new(move |_| mark_body(truth));

    let on_pick = move |ev: leptos::ev::Event| pick(truth, ev);
    let on_clear = move |_| truth.file.set(None);

    let applied = move || {
        truth.state.with(|s| match s {
            TruthState::Loaded(i) => {
                let name = truth.file.with(|f| f.as_ref().map(|f| f.0.clone()).unwrap_or_default());
                format!("{name}: {}", i.applied.describe(i.truth.segments.len()))
            }
            TruthState::None => "No ground truth yet: pick a CSV or a segmentation JSON.".into(),
            TruthState::Failed(_) => String::new(),
        })
    };
    let error = move || truth.state.with(|s| if let TruthState::Failed(m) = s { m.clone() } else { String::new() });
    // the choices of a CSV do not apply to the JSON (0-based, its own fps)
    let is_json = move || {
        truth
            .file
            .with(|f| f.as_ref().is_some_and(|(_, t)| t.trim_start_matches('\u{feff}').trim_start().starts_with('{')))
    };
    let chosen_trial =
        move || truth.truth().and_then(|i| i.applied.trial.as_ref().map(|t| t.0.clone())).unwrap_or_default();
    let trial_options = move || truth.trials.get();
    let take_fps =
        move || state.motion.with(|m| m.as_ref().map(|m| format!("{:.2}", m.summary.fps)).unwrap_or_default());

    // the truth as it reads against the take on screen (its frames, the take's rate)
    let row = Signal::derive(move || truth.view.with(|v| v.as_ref().map(|v| Arc::new(v.segmentation.clone()))));

    view! {
        <section id="truth-panel" class="ms-panel-box ms-truth" aria-label="Ground truth">
            <div class="ms-timeline-head">
                <h2>"Ground truth"</h2>
                <span class="ms-timeline-legend">"labels to score the methods against — shown as the first timeline row"</span>
            </div>
            <div class="ms-method-params ms-truth-controls" role="group" aria-label="Ground-truth import">
                <label class="ms-button" for="truth-file">"Import labels…"</label>
                <input
                    id="truth-file"
                    class="ms-visually-hidden"
                    type="file"
                    accept=".csv,.txt,.json,text/csv,application/json"
                    aria-label="Ground-truth file: a CSV start_frame,end_frame,label, the shared data's CSV or a segmentation JSON"
                    aria-describedby="truth-error truth-applied"
                    on:change=on_pick
                />
                <label title="The number the CSV gives the take's first frame (CMU AMC frame numbers start at 1)">
                    "CSV frames start at "
                    <select id="truth-base" bind:value=truth.base disabled=is_json>
                        <option value="1" prop:selected=move || truth.base.get() == "1">"1"</option>
                        <option value="0" prop:selected=move || truth.base.get() == "0">"0"</option>
                    </select>
                </label>
                <label title="The frame rate the CSV's frame numbers count at; empty: the take's own. Other rates are converted by time.">
                    "Labels' frame rate (fps) "
                    <input
                        id="truth-fps"
                        type="number"
                        min="0"
                        step="any"
                        size="6"
                        list="truth-fps-rates"
                        placeholder=take_fps
                        disabled=is_json
                        bind:value=truth.fps
                    />
                    <datalist id="truth-fps-rates">
                        {COMMON_RATES.iter().map(|r| view! { <option value=*r></option> }).collect_view()}
                    </datalist>
                </label>
                <label hidden=move || trial_options().is_empty() title="The trial of the shared data's CSV that is this take">
                    "Trial "
                    <select
                        id="truth-trial"
                        on:change=move |ev| truth.trial.set(event_target_value(&ev))
                    >
                        <option value="" prop:selected=move || truth.trial.get().is_empty() && chosen_trial().is_empty()>"choose…"</option>
                        {move || {
                            trial_options()
                                .into_iter()
                                .map(|t| {
                                    let value = t.clone();
                                    view! { <option value=t.clone() prop:selected=move || chosen_trial() == value>{t.clone()}</option> }
                                })
                                .collect_view()
                        }}
                    </select>
                </label>
                <button
                    id="truth-clear"
                    class="ms-button ms-button--quiet"
                    type="button"
                    disabled=move || truth.file.with(Option::is_none)
                    on:click=on_clear
                >
                    "Clear"
                </button>
            </div>
            <p id="truth-error" class="ms-truth-error" role="alert" hidden=move || error().is_empty()>{error}</p>
            <p id="truth-applied" class="ms-truth-applied" aria-live="polite" hidden=move || applied().is_empty()>{applied}</p>
            <RowExports state=state id="truth" what="the ground truth" row=row/>
        </section>
    }
}

/// `#row-truth` on the timeline (hidden while there is no ground truth).
#[component]
pub fn TruthRow(state: AppState) -> impl IntoView {
    let label = Signal::derive(|| "Ground truth".to_string());
    view! { <SegmentRow state=state row_id="truth".to_string() source=state.truth.view.into() levels=ACTION_LEVELS label=label/> }
}
