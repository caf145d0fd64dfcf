//! Which take of the library is on screen, and the labels it gives the library (its my labels, else its ground
//! truth): what the library's panel shows and the loader's label carrying sends.

use crate::app::library::carry::frame_labels;
use crate::app::library::state::LibraryState;
use crate::app::state::AppState;
use leptos::prelude::*;

impl LibraryState {
    /// Whether the take on screen is take `i` of the library (tracked): it was opened from the
    /// library, has that take's name and frames, and is loaded.
    pub(crate) fn on_screen(&self, state: AppState, i: usize) -> bool {
        let shown = state.motion.with(|m| m.as_ref().map(|m| (m.summary.name.clone(), m.summary.frames)));
        let entry = self.queue.with(|q| q.entries.get(i).map(|e| (e.name.clone(), e.frames)));
        self.open.get() == Some(i)
            && state.load.with(|l| *l == crate::app::state::LoadState::Ready)
            && matches!((shown, entry), (Some((a, n)), Some((b, Some(m)))) if a == b && n == m)
    }

    /// The take of the library on screen (tracked), when it is one.
    pub(crate) fn open_on_screen(&self, state: AppState) -> Option<usize> {
        self.open.get().filter(|&i| self.on_screen(state, i))
    }
}

/// The labels the take on screen gives the library (tracked): its library index, each frame's
/// label from my labels — else from its imported ground truth — and which of the two; or why
/// there are none.
pub(crate) fn source_labels(state: AppState) -> Result<(usize, Vec<Option<String>>, &'static str), String> {
    let Some(i) = state.library.open_on_screen(state) else {
        return Err("open a take of the library (its name in the list) to carry its labels".into());
    };
    let frames = state.frames();
    let from = |seg: &crate::segment::Segmentation| {
        let labels = frame_labels(seg, frames);
        labels.iter().any(Option::is_some).then_some(labels)
    };
    if let Some(labels) = state.mine.with(|m| m.as_deref().and_then(from)) {
        return Ok((i, labels, "my labels"));
    }
    if let Some(labels) = state.truth.view.with(|v| v.as_ref().and_then(|v| from(&v.segmentation))) {
        return Ok((i, labels, "its ground truth"));
    }
    Err("this take has no labels yet: label it in my labels, or import its ground truth".into())
}
