//! The annotation jobs of the Effort bars ([`crate::app::effort::bars`]): a row's segments go to the
//! worker as one `annotate` request; its progress and its answer go to the bars' state under the
//! row's key. A worker that lost the take gets it again once; a job that needs the shipped family
//! waits for it like a method's run ([`crate::app::loader::shipped`]); a worker replaced (a cancelled run, a
//! crash) is sent the jobs still waiting. Turning the bars off drops the jobs (their answers are
//! then ignored).

use crate::app::loader::{next_id, post, replace_worker, restore, Inner, Loader};
use crate::protocol::{FailureKind, Request, Response, RunId};
use std::rc::Rc;

/// An annotation asked of the worker: its request, the bars' key, whether it was sent again.
pub(super) struct AnnotateJob {
    request: Request,
    key: u64,
    retried: bool,
}

impl Loader {
    /// Asks the worker for `method`'s annotations (with `params`) of the segments `spans` of the
    /// take on screen; the answer goes to the bars under `key`.
    pub fn annotate(&self, key: u64, method: String, params: serde_json::Value, spans: Vec<(usize, usize)>) {
        let inner = &self.0;
        let Some(take) = inner.shown.borrow().as_ref().map(|t| t.id) else {
            return inner.state.effort.answered(key, Err("no take is loaded".into()));
        };
        let run = next_id(inner);
        let request = Request::Annotate { take, run, method, params, spans };
        match post(inner, &request, None) {
            Ok(()) => inner.annotate_jobs.borrow_mut().push(AnnotateJob { request, key, retried: false }),
            Err(message) => inner.state.effort.answered(key, Err(message)),
        }
    }

    /// Forgets the annotations under way (the bars were turned off).
    pub fn drop_annotations(&self) {
        self.0.annotate_jobs.borrow_mut().clear();
    }
}

/// Whether `run` is an annotation job.
pub(super) fn is_job(inner: &Inner, run: RunId) -> bool {
    inner.annotate_jobs.borrow().iter().any(|j| j.request.run_id() == Some(run))
}

/// Removes and returns the job `run`.
fn take_job(inner: &Inner, run: RunId) -> Option<AnnotateJob> {
    let mut jobs = inner.annotate_jobs.borrow_mut();
    let i = jobs.iter().position(|j| j.request.run_id() == Some(run))?;
    Some(jobs.remove(i))
}

/// Sends the job `run` again (its model file arrived); false when `run` is not one.
pub(super) fn send_again(inner: &Rc<Inner>, run: RunId) -> bool {
    let request =
        inner.annotate_jobs.borrow().iter().find(|j| j.request.run_id() == Some(run)).map(|j| j.request.clone());
    let Some(request) = request else { return false };
    if let Err(message) = post(inner, &request, None) {
        fail(inner, run, message);
    }
    true
}

/// The job `run` failed with `message`; false when `run` is not one.
pub(super) fn fail(inner: &Inner, run: RunId, message: String) -> bool {
    match take_job(inner, run) {
        Some(job) => {
            inner.state.effort.answered(job.key, Err(message));
            true
        }
        None => false,
    }
}

/// Shows that the job `run` is at `stage` (a model file coming); false when `run` is not one.
pub(super) fn show_stage(inner: &Inner, run: RunId, stage: &str, fraction: f64) -> bool {
    let mine = is_job(inner, run);
    if mine {
        inner.state.effort.stage(stage, Some(fraction));
    }
    mine
}

/// Sends every job still waiting to a new worker.
pub(super) fn resend(inner: &Rc<Inner>) {
    let runs: Vec<RunId> = inner.annotate_jobs.borrow().iter().filter_map(|j| j.request.run_id()).collect();
    for run in runs {
        send_again(inner, run);
    }
}

/// Handles `response` when it is about an annotation job; gives it back otherwise.
pub(super) fn handle(inner: &Rc<Inner>, response: Response) -> Option<Response> {
    let effort = inner.state.effort;
    match response {
        Response::Annotated { run, annotations, .. } => {
            if let Some(job) = take_job(inner, run) {
                effort.answered(job.key, Ok(annotations));
            }
        }
        Response::Progress { run: Some(run), stage, fraction, .. } if is_job(inner, run) => {
            effort.stage(&stage, fraction);
        }
        Response::Refused { run, message, .. } if is_job(inner, run) => {
            fail(inner, run, message);
        }
        Response::Failed { run: Some(run), message, kind, .. } if is_job(inner, run) => {
            let Some(job) = take_job(inner, run) else { return None };
            match kind {
                FailureKind::NotLoaded if !job.retried && effort.is_asked(job.key) => {
                    let inner = inner.clone();
                    wasm_bindgen_futures::spawn_local(async move {
                        let sent = restore(&inner).await.and_then(|()| post(&inner, &job.request, None));
                        match sent {
                            Ok(()) => inner.annotate_jobs.borrow_mut().push(AnnotateJob { retried: true, ..job }),
                            Err(e) => inner.state.effort.answered(job.key, Err(e)),
                        }
                    });
                }
                _ => {
                    effort.answered(job.key, Err(message));
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
