//! `#summary`: one line about the take on screen — "02_01.bvh · 31 joints · 343 frames ·
//! 120 fps · 2.86 s · CMU units (Y up)" — and, under it, the parser's and the unit
//! detection's warnings.

use crate::app::state::AppState;
use crate::motion::{Units, UpAxis};
use crate::protocol::Summary as Facts;
use leptos::prelude::*;

/// The bundled sample's file name and frame count (CMU 13_30, www/SOURCES.md).
const SAMPLE_FILE: &str = "sample.bvh";
const SAMPLE_FRAMES: usize = 2465;

/// Whether a take is the bundled sample.
pub fn is_bundled_sample(name: &str, frames: usize) -> bool {
    name == SAMPLE_FILE && frames == SAMPLE_FRAMES
}

/// The shipped models the bundled sample trained (CMU 13_30 is a mocap6 take).
pub const SAMPLE_TRAINED: &str = "exercises";

#[component]
pub fn Summary(state: AppState) -> impl IntoView {
    let facts = move || state.motion.with(|m| m.as_ref().map(|m| m.summary.clone()));
    let text = move |f: fn(&Facts) -> String| move || facts().map(|s| f(&s)).unwrap_or_default();
    let warnings = move || facts().map(|s| s.warnings).unwrap_or_default();
    // the bundled sample is named `sample.bvh` (www/SOURCES.md says what it is)
    let is_sample = move || facts().is_some_and(|s| is_bundled_sample(&s.name, s.frames));

    view! {
        <section class="ms-summary" hidden=move || facts().is_none()>
            <p id="summary">
                <span id="summary-name">{text(|s| s.name.clone())}</span>
                " · "
                <span id="summary-joints" title=text(|s| format!("{} end sites", s.end_sites))>
                    {text(|s| plural(s.joints, "joint"))}
                </span>
                " · "
                <span id="summary-frames">{text(|s| plural(s.frames, "frame"))}</span>
                " · "
                <span id="summary-fps" title=text(|s| format!("frame time {} s", 1.0 / s.fps))>
                    {text(|s| format!("{} fps", format_fps(s.fps)))}
                </span>
                " · "
                <span id="summary-duration">{text(|s| format!("{:.2} s", s.duration_s))}</span>
                " · "
                <span id="summary-units" title=text(|s| s.units.label().to_string())>
                    {text(|s| format!("{} ({})", units_short(s.units), up_label(s.up_axis)))}
                </span>
            </p>
            <p id="summary-sample" class="ms-sample-credit" hidden=move || !is_sample()>
                "The bundled sample: CMU 13_30, an exercise sequence (jumping jacks, twists, squats…) from the CMU
                Graphics Lab Motion Capture Database (mocap.cs.cmu.edu), free for research and commercial use; labels
                from the mocap6 set (Hughes; Fox et al. 2014). It is one of the takes the shipped "
                <code>"exercises"</code>
                " models (DT-FCN, k-NN) were trained on: their labels here are in-sample, not what they do on a new take
                (held-out scores: docs/accuracy.md). "
                <a href="./www/SOURCES.md" target="_blank" rel="noopener">"Source and licence"</a>
            </p>
            <ul id="summary-warnings" class="ms-warnings" hidden=move || warnings().is_empty()>
                {move || warnings().into_iter().map(|w| view! { <li>{w}</li> }).collect_view()}
            </ul>
        </section>
    }
}

fn plural(n: usize, word: &str) -> String {
    if n == 1 {
        format!("1 {word}")
    } else {
        format!("{n} {word}s")
    }
}

/// A frame rate as people write it: "120" for 1 / 0.0083333 s, "23.976" for NTSC film.
///
/// A rate within 1e-4 (relative) of a whole number is one written with a rounded frame time
/// (0.0083333 s → 120.0005 fps); NTSC rates are 1e-3 away (23.976 vs 24) and keep 3 decimals.
pub fn format_fps(fps: f64) -> String {
    let whole = fps.round();
    if whole > 0.0 && ((fps - whole) / whole).abs() < 1e-4 {
        format!("{whole:.0}")
    } else {
        format!("{fps:.3}")
    }
}

/// Short unit names for the summary line (the full label is the tooltip).
fn units_short(units: Units) -> &'static str {
    match units {
        Units::CmuAsf => "CMU units",
        Units::Millimetres => "mm",
        Units::Centimetres => "cm",
        Units::Metres => "m",
        Units::Inches => "inches",
    }
}

fn up_label(up: UpAxis) -> String {
    format!("{} up", up.name())
}
