//! `#progress`: visible while a file is read and worked on — the stage, the file name and, when
//! the stage can measure it, how far it got (the parser reports the fraction of the file read).

use crate::app::state::AppState;

use crate::app::state::LoadState;
use leptos::prelude::*;

#[component]
pub fn Progress(state: AppState) -> impl IntoView {
    let loading = move || state.load.with(|l| matches!(l, LoadState::Loading { .. }));
    let fraction = move || {
        state.load.with(|l| match l {
            LoadState::Loading { fraction, .. } => *fraction,
            _ => None,
        })
    };
    let label = move || {
        state.load.with(|l| match l {
            LoadState::Loading { name, stage, fraction } => describe(name, stage, *fraction),
            _ => String::new(),
        })
    };

    view! {
        <div id="progress" class="ms-progress" role="status" aria-live="polite" hidden=move || !loading()>
            // No `value` while a stage cannot measure itself: the bar is then indeterminate.
            {move || match fraction() {
                Some(f) => view! { <progress max="1" value=f.clamp(0.0, 1.0).to_string()></progress> }.into_any(),
                None => view! { <progress max="1"></progress> }.into_any(),
            }}
            <span class="ms-progress-label">{label}</span>
        </div>
    }
}

/// "Parsing 02_01.bvh… 42 %", "Running forward kinematics on 02_01.bvh…", …
fn describe(name: &str, stage: &str, fraction: Option<f64>) -> String {
    let verb = match stage {
        "reading" => "Reading",
        "parsing" => "Parsing",
        "forward kinematics" => "Running forward kinematics on",
        "motion image" => "Building the motion image of",
        "starting" => "Starting",
        other => other,
    };
    let name = if name.is_empty() { String::new() } else { format!(" {name}") };
    match fraction {
        Some(f) => format!("{verb}{name}… {:.0} %", 100.0 * f.clamp(0.0, 1.0)),
        None => format!("{verb}{name}…"),
    }
}
