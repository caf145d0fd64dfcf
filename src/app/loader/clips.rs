//! The clip exports' jobs: a row asks for BVH clips of the take on screen, the worker cuts them,
//! the page saves the file; a worker that lost the take gets it again once.

use crate::app::dom::js_message;
use crate::app::loader::{next_id, post, replace_worker, restore, ExportStatus, Inner, Loader};
use crate::app::player::motion_image::download;
use crate::protocol::{FailureKind, Request, Response, RunId};
use leptos::prelude::*;
use std::rc::Rc;

/// A clip export on its way: the request (sent again once if the worker lost the take), where
/// to say how it went, whether it was sent again, and the row's id for the file's name
/// ([`crate::app::timeline::export_names::with_row`]).
pub(super) struct ClipJob {
    request: Request,
    status: ExportStatus,
    retried: bool,
    row: String,
    /// What the row calls the level cut ("labels", "gestures"), for a zip's name.
    word: Option<&'static str>,
}

impl Loader {
    /// Cuts the take on screen at the segments `which` chooses of method `index`'s last run and
    /// saves the clips (a zip, or with `only` that segment's BVH); the panel's export status says
    /// how it went.
    pub fn export_clips(
        &self,
        index: usize,
        which: crate::clips::Which,
        to_origin: bool,
        only: Option<(usize, usize)>,
    ) {
        let slot = &self.0.state.methods[index];
        match slot.view.get_untracked() {
            Some(view) => {
                let word = crate::app::timeline::rows::which_word(Some(&view), which);
                let status = slot.export_status;
                self.cut_clips(&view.segmentation, &slot.info.name, Some(word), which, to_origin, only, status)
            }
            None => slot.export_status.set(Some((true, "run the method on a take first".into()))),
        }
    }

    /// Cuts the take on screen at the segments `which` chooses of `segmentation` (any row's: `row`,
    /// its id, goes in the file's name) and saves the clips; `status` says how it went.
    #[allow(clippy::too_many_arguments)]
    pub fn export_clips_of(
        &self,
        segmentation: &crate::segment::Segmentation,
        row: &str,
        which: crate::clips::Which,
        to_origin: bool,
        only: Option<(usize, usize)>,
        status: ExportStatus,
    ) {
        self.cut_clips(segmentation, row, None, which, to_origin, only, status)
    }

    /// [`Loader::export_clips_of`] with what the row calls the level cut (`word`, for a zip's name).
    #[allow(clippy::too_many_arguments)]
    fn cut_clips(
        &self,
        segmentation: &crate::segment::Segmentation,
        row: &str,
        word: Option<&'static str>,
        which: crate::clips::Which,
        to_origin: bool,
        only: Option<(usize, usize)>,
        status: ExportStatus,
    ) {
        let inner = &self.0;
        let Some(take) = inner.shown.borrow().as_ref().map(|t| t.id) else {
            return status.set(Some((true, "no take is loaded".into())));
        };
        let run = next_id(inner);
        let segmentation = Box::new(segmentation.clone());
        let request = Request::Clips { take, run, segmentation, which, to_origin, only };
        status.set(Some((false, "cutting the clips…".into())));
        match post(inner, &request, None) {
            Ok(()) => inner.clip_jobs.borrow_mut().push(ClipJob {
                request,
                status,
                retried: false,
                row: row.to_string(),
                word,
            }),
            Err(message) => status.set(Some((true, message))),
        }
    }
}

/// Handles `response` when it answers a clip export; gives it back otherwise.
pub(super) fn handle(inner: &Rc<Inner>, response: Response) -> Option<Response> {
    match response {
        Response::Clips { run, file, clips, bytes, .. } => {
            if let Some(ClipJob { request, status, row, word, .. }) = take_clip_job(inner, run) {
                let stem = match &request {
                    Request::Clips { segmentation, .. } => crate::clips::stem_of(&segmentation.file),
                    _ => String::new(),
                };
                let file = crate::app::timeline::export_names::with_row_word(&file, &stem, &row, word);
                let said = match download(&bytes, clip_mime(&file), &file) {
                    Ok(()) => (false, format!("saved {file} ({})", crate::method::counted(clips, "clip"))),
                    Err(e) => (true, format!("could not save {file}: {}", js_message(&e))),
                };
                status.set(Some(said));
            }
        }
        Response::Failed { run: Some(run), message, kind, .. }
            if inner.clip_jobs.borrow().iter().any(|j| j.request.run_id() == Some(run)) =>
        {
            let Some(ClipJob { request, status, retried, row, word }) = take_clip_job(inner, run) else { return None };
            match kind {
                FailureKind::NotLoaded if !retried => {
                    let inner = inner.clone();
                    wasm_bindgen_futures::spawn_local(async move {
                        let sent = restore(&inner).await.and_then(|()| post(&inner, &request, None));
                        match sent {
                            Ok(()) => {
                                inner.clip_jobs.borrow_mut().push(ClipJob { request, status, retried: true, row, word })
                            }
                            Err(e) => status.set(Some((true, e))),
                        }
                    });
                }
                _ => {
                    status.set(Some((true, message)));
                    if kind == FailureKind::Internal {
                        replace_worker(inner);
                    }
                }
            }
        }
        other => return Some(other),
    }
    None
}

/// Removes and returns the clip export `run`.
fn take_clip_job(inner: &Inner, run: RunId) -> Option<ClipJob> {
    let mut jobs = inner.clip_jobs.borrow_mut();
    let i = jobs.iter().position(|j| j.request.run_id() == Some(run))?;
    Some(jobs.remove(i))
}

/// The type of a clip export's file.
fn clip_mime(file: &str) -> &'static str {
    if file.ends_with(".zip") {
        "application/zip"
    } else {
        "application/octet-stream"
    }
}
