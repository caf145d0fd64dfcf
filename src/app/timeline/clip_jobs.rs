//! The clip exports' jobs: a row asks for BVH clips of the take on screen, the worker cuts them,
//! the page saves the file; a worker that lost the take gets it again once; a new main worker (a cancel, a crash)
//! is sent the exports under way, with the take; a main worker that fails fails them, saying why.
//!
//! The jobs are the timeline's (every row exports its clips): the loader only carries their requests
//! and routes the replies back by run id ([`crate::app::loader::Jobs`]).

use crate::app::dom::js_message;
use crate::app::loader::{Jobs, Loader};
use crate::app::player::motion_image::download;
use crate::app::state::AppState;
use crate::protocol::{FailureKind, Request, Response, RunId};
use crate::worker::pool::Slot;
use leptos::prelude::*;
use std::cell::RefCell;
use std::rc::Rc;

/// A row's export status line: (failed, message).
type ExportStatus = RwSignal<Option<(bool, String)>>;

/// A clip export on its way: the request (sent again once if the worker lost the take), where
/// to say how it went, whether it was sent again, and the row's id for the file's name
/// ([`crate::app::timeline::export_names::with_row`]).
struct ClipJob {
    request: Request,
    status: ExportStatus,
    retried: bool,
    row: String,
    /// What the row calls the level cut ("labels", "gestures"), for a zip's name.
    word: Option<&'static str>,
}

/// The clip exports under way; cheap to clone (one per page, in the page's context).
#[derive(Clone)]
pub struct ClipJobs(Rc<Inner>);

struct Inner {
    state: AppState,
    loader: Loader,
    jobs: RefCell<Vec<ClipJob>>,
}

/// The clip exports as the components find them (`None` only outside the page).
pub type ClipJobsHandle = Option<StoredValue<ClipJobs, LocalStorage>>;

impl ClipJobs {
    /// The clip exports' jobs, registered with `loader`.
    pub fn new(state: AppState, loader: Loader) -> ClipJobs {
        let jobs = ClipJobs(Rc::new(Inner { state, loader: loader.clone(), jobs: RefCell::new(Vec::new()) }));
        loader.register(Rc::new(jobs.clone()));
        jobs
    }

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

    /// [`ClipJobs::export_clips_of`] with what the row calls the level cut (`word`, for a zip's name).
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
        let Some(take) = self.0.loader.shown_take() else {
            return status.set(Some((true, "no take is loaded".into())));
        };
        let run = self.0.loader.new_run();
        let segmentation = Box::new(segmentation.clone());
        let request = Request::Clips { take, run, segmentation, which, to_origin, only };
        status.set(Some((false, "cutting the clips…".into())));
        match self.post(&request) {
            Ok(()) => {
                self.0.jobs.borrow_mut().push(ClipJob { request, status, retried: false, row: row.to_string(), word })
            }
            Err(message) => status.set(Some((true, message))),
        }
    }

    /// Posts `request` to the worker, its replies routed here.
    fn post(&self, request: &Request) -> Result<(), String> {
        self.0.loader.send(Rc::new(self.clone()), request)
    }

    /// Removes and returns the clip export `run` (its replies are no longer routed here).
    fn take_job(&self, run: RunId) -> Option<ClipJob> {
        self.0.loader.forget(run);
        let mut jobs = self.0.jobs.borrow_mut();
        let i = jobs.iter().position(|j| j.request.run_id() == Some(run))?;
        Some(jobs.remove(i))
    }
}

impl Jobs for ClipJobs {
    fn reply(&self, _slot: Slot, response: Response) {
        match response {
            Response::Clips { run, file, clips, bytes, .. } => {
                if let Some(ClipJob { request, status, row, word, .. }) = self.take_job(run) {
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
            Response::Failed { run: Some(run), message, kind, .. } => {
                let Some(ClipJob { request, status, retried, row, word }) = self.take_job(run) else { return };
                match kind {
                    FailureKind::NotLoaded if !retried => {
                        let this = self.clone();
                        wasm_bindgen_futures::spawn_local(async move {
                            let sent = this.0.loader.send_with_take(Rc::new(this.clone()), &request).await;
                            match sent {
                                Ok(()) => {
                                    this.0.jobs.borrow_mut().push(ClipJob { request, status, retried: true, row, word })
                                }
                                Err(e) => status.set(Some((true, e))),
                            }
                        });
                    }
                    _ => {
                        // (a failure of kind `internal` also replaces the worker: the loader does)
                        status.set(Some((true, message)));
                    }
                }
            }
            _ => {}
        }
    }

    fn resend(&self) {
        // a new main worker holds no take: each export is sent with the take on screen
        let jobs: Vec<ClipJob> = self.0.jobs.borrow_mut().drain(..).collect();
        for job in jobs {
            if let Some(run) = job.request.run_id() {
                self.0.loader.forget(run);
            }
            let this = self.clone();
            wasm_bindgen_futures::spawn_local(async move {
                match this.0.loader.send_with_take(Rc::new(this.clone()), &job.request).await {
                    Ok(()) => this.0.jobs.borrow_mut().push(job),
                    Err(e) => job.status.set(Some((true, e))),
                }
            });
        }
    }

    fn worker_failed(&self, message: &str) {
        let jobs: Vec<ClipJob> = self.0.jobs.borrow_mut().drain(..).collect();
        for job in jobs {
            if let Some(run) = job.request.run_id() {
                self.0.loader.forget(run);
            }
            job.status.set(Some((true, message.to_string())));
        }
    }
}

/// The type of a clip export's file.
fn clip_mime(file: &str) -> &'static str {
    if file.ends_with(".zip") {
        "application/zip"
    } else {
        "application/octet-stream"
    }
}
