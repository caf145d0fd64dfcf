//! What a training gives back on the page: its progress, its report, the trained model's file, and a model trained
//! on another take than the one on screen (keep, apply or discard it).

use crate::app::models::model_jobs::ModelJobs;
use crate::app::models::supervised::PendingChoice;
use crate::app::models::supervised::{Supervised, TrainState};
use crate::app::player::motion_image::download;
use crate::app::state::AppState;
use leptos::prelude::*;

/// A training's progress: its stage, or the last step's line, and a bar.
#[component]
pub(crate) fn TrainProgress(s: &'static Supervised, method: String) -> impl IntoView {
    let busy = move || s.state.with(TrainState::busy);
    let step_name = s.decl.step_name.clone();
    let progress = move || {
        s.state.with(|st| match st {
            TrainState::Training { stage, step, steps, fraction } => (stage.clone(), *step, *steps, *fraction),
            _ => (String::new(), 0, 1, 0.0),
        })
    };
    let progress_label = {
        let step_name = step_name.clone();
        move || {
            if s.state.with(|st| *st == TrainState::Stopping) {
                return format!("Stopping after this {step_name}…");
            }
            let (stage, step, _, _) = progress();
            match (step, s.steps.with(|r| r.last().map(|r| r.line.clone()))) {
                (0, _) | (_, None) => format!("Training: {stage}…"),
                (_, Some(line)) => line,
            }
        }
    };
    // the bar: steps done of steps while stepping, else the stage's own fraction
    let bar = move || {
        let (_, step, steps, fraction) = progress();
        if step > 0 && steps > 1 {
            (step as f64 / steps as f64).clamp(0.0, 1.0)
        } else {
            fraction.clamp(0.0, 1.0)
        }
    };
    view! {
    <div id=format!("{method}-train-progress") class="ms-progress" role="status" aria-live="polite" hidden=move || !busy()>
        <progress max="1" value=move || bar().to_string()></progress>
        <span class="ms-progress-label">{progress_label}</span>
    </div>
    }
}

/// The report of the last training (the held-out scores per class and more).
#[component]
pub(crate) fn TrainReport(s: &'static Supervised, method: String) -> impl IntoView {
    let report_rows = move || {
        s.report.with(|r| {
            r.as_ref()
                .map(|r| {
                    r.rows
                        .iter()
                        .map(|row| {
                            let mut cells = row.iter();
                            let head = cells.next().cloned().unwrap_or_default();
                            let rest = cells.map(|c| view! { <td>{c.clone()}</td> }).collect_view();
                            view! { <tr><th scope="row">{head}</th>{rest}</tr> }
                        })
                        .collect_view()
                })
                .unwrap_or_default()
        })
    };
    let report_head = move || {
        s.report.with(|r| {
            r.as_ref()
                .map(|r| r.columns.iter().map(|c| view! { <th scope="col">{c.clone()}</th> }).collect_view())
                .unwrap_or_default()
        })
    };
    let no_report = move || s.report.with(|r| r.as_ref().is_none_or(|r| r.rows.is_empty()));
    view! {
    <table id=format!("{method}-train-report") class="ms-lma-report" hidden=no_report>
        <thead><tr>{report_head}</tr></thead>
        <tbody>{report_rows}</tbody>
    </table>
    }
}

/// A model trained on another take than the one on screen: keep it for later, apply it to the take on screen, or
/// discard it.
#[component]
pub(crate) fn PendingTrained(
    state: AppState,
    jobs: ModelJobs,
    index: usize,
    s: &'static Supervised,
    method: String,
) -> impl IntoView {
    let settle = {
        let jobs = jobs.clone();
        move |choice: PendingChoice| jobs.settle_trained(index, choice)
    };
    let (keep, apply, discard) = (settle.clone(), settle.clone(), settle);
    let pending_now = move || s.pending.with(|p| p.as_ref().map(|p| p.now_on.clone())).unwrap_or_default();
    view! {
    <div id=format!("{method}-train-pending") class="ms-train-pending" role="group"
        aria-label="A model trained on another take" hidden=move || s.pending.with(Option::is_none)>
        <button id=format!("{method}-train-keep") class="ms-button" type="button"
            on:click=move |_| keep(PendingChoice::Keep)>"Keep it for later"</button>
        // applied only to a take on screen: while the next one loads it would run on the last
        <button id=format!("{method}-train-apply") class="ms-button ms-button--quiet" type="button"
            disabled=move || !state.load.with(|l| matches!(l, crate::app::state::LoadState::Ready))
            title=move || if state.load.with(|l| matches!(l, crate::app::state::LoadState::Ready)) { "" } else { "waits until the take is on screen" }
            on:click=move |_| apply(PendingChoice::Apply)>{move || format!("Apply it to {}", pending_now())}</button>
        <button id=format!("{method}-train-discard") class="ms-button ms-button--quiet" type="button"
            on:click=move |_| discard(PendingChoice::Discard)>"Discard it"</button>
    </div>
    }
}

/// The trained model's file, to download (`Download <file>`).
#[component]
pub(crate) fn DownloadTrained(state: AppState, s: &'static Supervised, method: String) -> impl IntoView {
    let on_download = move |_| {
        if let Some(file) = s.trained.get_untracked() {
            let file_name = s.file_name(&file.name);
            if let Err(e) = download(&file.bytes, "application/octet-stream", &file_name) {
                state.show_error(format!("could not save {file_name}: {e:?}"));
            }
        }
    };
    view! {
        <button
            id=format!("{method}-train-download")
            class="ms-button ms-button--quiet"
            type="button"
            hidden=move || s.trained.with(Option::is_none)
            on:click=on_download
        >
            {move || s.trained.with(|f| f.as_ref().map(|f| format!("Download {}", s.file_name(&f.name))).unwrap_or_default())}
        </button>
    }
}
