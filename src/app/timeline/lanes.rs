//! The lanes' width on screen, which every row reads to fit its segments' labels; where the lanes are (a pointer's
//! frame); the zoom of one key press.

use leptos::html::Div;
use leptos::prelude::*;

thread_local! {
    /// The lanes' width in CSS pixels (0 until the timeline is laid out).
    static LANE_PX: RwSignal<f64> = RwSignal::new(0.0);
}

/// The lanes' width in CSS pixels, kept up to date as the timeline is resized (rows use it to fit
/// their segments' labels: [`crate::app::timeline::label_fit`]).
pub fn lane_px() -> RwSignal<f64> {
    LANE_PX.with(|s| *s)
}

/// The text a segment `fraction` of the lanes wide shows for `label` (`.ms-seg`: 11 px text,
/// 3 px of padding either side, www/style.css): the label, a clean abbreviation, or nothing.
pub fn segment_text(label: &str, fraction: f64) -> String {
    const FONT_PX: f64 = 11.0;
    const PADDING_PX: f64 = 6.0;
    let width = fraction * lane_px().get() - PADDING_PX;
    crate::app::timeline::label_fit::fit_label(label, width, FONT_PX).unwrap_or_default()
}

/// One +/− key press or zoom button zooms by this factor.
pub(crate) const KEY_ZOOM: f64 = 2.0;

/// The x range of the lanes on screen: (left, width) in client pixels.
pub(crate) fn lane_box(lane: &NodeRef<Div>) -> Option<(f64, f64)> {
    let rect = lane.get_untracked()?.get_bounding_client_rect();
    (rect.width() > 0.0).then(|| (rect.left(), rect.width()))
}
