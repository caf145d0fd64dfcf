//! The annotation jobs of the Effort bars ([`crate::app::effort::bars`]): a row's segments go to the
//! worker as one `annotate` request; its progress and its answer go to the bars' state under the
//! row's key. A worker that lost the take gets it again once; a job that needs the shipped family
//! waits for it like a method's run (the loader fetches it, then [`Jobs::send_again`]); a worker
//! replaced (a cancelled run, a crash) is sent the jobs still waiting ([`Jobs::resend`]); a main worker that fails
//! outside a request fails them, saying why ([`Jobs::worker_failed`]), rather than leaving them waiting. Turning the
//! bars off drops the jobs (their answers are then ignored).
//!
//! The jobs are the feature's: the loader only carries their requests and routes the replies back
//! by run id ([`crate::app::loader::Jobs`]).

use crate::app::effort::state::EffortBars;
use crate::app::loader::{Jobs, Loader};
use crate::protocol::{FailureKind, Request, Response, RunId};
use crate::worker::pool::Slot;
use leptos::prelude::*;
use std::cell::RefCell;
use std::rc::Rc;

/// An annotation asked of the worker: its request, the bars' key, whether it was sent again.
struct AnnotateJob {
    request: Request,
    key: u64,
    retried: bool,
}

/// The Effort bars' jobs in the worker; cheap to clone (one per page, in the page's context).
#[derive(Clone)]
pub struct EffortJobs(Rc<Inner>);

struct Inner {
    bars: EffortBars,
    loader: Loader,
    jobs: RefCell<Vec<AnnotateJob>>,
}

/// The bars' jobs as the components find them (`None` only outside the page).
pub type EffortJobsHandle = Option<StoredValue<EffortJobs, LocalStorage>>;

impl EffortJobs {
    /// The bars' jobs, registered with `loader`.
    pub fn new(bars: EffortBars, loader: Loader) -> EffortJobs {
        let jobs = EffortJobs(Rc::new(Inner { bars, loader: loader.clone(), jobs: RefCell::new(Vec::new()) }));
        loader.register(Rc::new(jobs.clone()));
        jobs
    }

    /// Asks the worker for `method`'s annotations (with `params`) of the segments `spans` of the
    /// take on screen; the answer goes to the bars under `key`.
    pub fn annotate(&self, key: u64, method: String, params: serde_json::Value, spans: Vec<(usize, usize)>) {
        let Some(take) = self.0.loader.shown_take() else {
            return self.0.bars.answered(key, Err("no take is loaded".into()));
        };
        let run = self.0.loader.new_run();
        let request = Request::Annotate { take, run, method, params, spans };
        match self.post(&request) {
            Ok(()) => self.0.jobs.borrow_mut().push(AnnotateJob { request, key, retried: false }),
            Err(message) => self.0.bars.answered(key, Err(message)),
        }
    }

    /// Forgets the annotations under way (the bars were turned off).
    pub fn drop_all(&self) {
        let dropped: Vec<AnnotateJob> = self.0.jobs.borrow_mut().drain(..).collect();
        for run in dropped.iter().filter_map(|j| j.request.run_id()) {
            self.0.loader.forget(run);
        }
    }

    /// Posts `request` to the worker, its replies routed here.
    fn post(&self, request: &Request) -> Result<(), String> {
        self.0.loader.send(Rc::new(self.clone()), request)
    }

    /// Whether `run` is an annotation job under way.
    fn is_job(&self, run: RunId) -> bool {
        self.0.jobs.borrow().iter().any(|j| j.request.run_id() == Some(run))
    }

    /// Removes and returns the job `run` (its replies are no longer routed here).
    fn take_job(&self, run: RunId) -> Option<AnnotateJob> {
        self.0.loader.forget(run);
        let mut jobs = self.0.jobs.borrow_mut();
        let i = jobs.iter().position(|j| j.request.run_id() == Some(run))?;
        Some(jobs.remove(i))
    }
}

impl Jobs for EffortJobs {
    fn reply(&self, _slot: Slot, response: Response) {
        let effort = self.0.bars;
        match response {
            Response::Annotated { run, annotations, .. } => {
                if let Some(job) = self.take_job(run) {
                    effort.answered(job.key, Ok(annotations));
                }
            }
            Response::Progress { run: Some(run), stage, fraction, .. } if self.is_job(run) => {
                effort.stage(&stage, fraction);
            }
            Response::Refused { run, message, .. } => self.fail(run, message),
            Response::Failed { run: Some(run), message, kind, .. } => {
                let Some(job) = self.take_job(run) else { return };
                match kind {
                    FailureKind::NotLoaded if !job.retried && effort.is_asked(job.key) => {
                        let this = self.clone();
                        wasm_bindgen_futures::spawn_local(async move {
                            let sent = this.0.loader.send_with_take(Rc::new(this.clone()), &job.request).await;
                            match sent {
                                Ok(()) => this.0.jobs.borrow_mut().push(AnnotateJob { retried: true, ..job }),
                                Err(e) => effort.answered(job.key, Err(e)),
                            }
                        });
                    }
                    _ => {
                        // (a failure of kind `internal` also replaces the worker: the loader does)
                        effort.answered(job.key, Err(message));
                    }
                }
            }
            _ => {}
        }
    }

    fn resend(&self) {
        let runs: Vec<RunId> = self.0.jobs.borrow().iter().filter_map(|j| j.request.run_id()).collect();
        for run in runs {
            self.send_again(run);
        }
    }

    fn worker_failed(&self, message: &str) {
        let jobs: Vec<AnnotateJob> = self.0.jobs.borrow_mut().drain(..).collect();
        for job in jobs {
            if let Some(run) = job.request.run_id() {
                self.0.loader.forget(run);
            }
            self.0.bars.lost(job.key, message.to_string());
        }
    }

    fn stage(&self, run: RunId, stage: &str, fraction: f64) {
        if self.is_job(run) {
            self.0.bars.stage(stage, Some(fraction));
        }
    }

    fn send_again(&self, run: RunId) {
        let request = self.0.jobs.borrow().iter().find(|j| j.request.run_id() == Some(run)).map(|j| j.request.clone());
        let Some(request) = request else { return };
        if let Err(message) = self.post(&request) {
            self.fail(run, message);
        }
    }

    fn fail(&self, run: RunId, message: String) {
        if let Some(job) = self.take_job(run) {
            self.0.bars.answered(job.key, Err(message));
        }
    }
}
