//! The library's jobs as the loader sees them ([`Jobs`]): the workers' answers about its takes, its matching, its
//! carrying of labels and its clips; a take whose worker died; what a new main worker is sent again; what fails when
//! the main worker fails. The library waits for the trainings its supervised routes ask for
//! ([`crate::app::models::model_jobs::ModelJobs::when_trained`]).

use crate::app::library::library_jobs::{Inner, LibraryJobs};
use crate::app::loader::{AfterDeath, Jobs, Loader};
use crate::app::models::model_jobs::ModelJobs;
use crate::app::state::AppState;
use crate::protocol::{Response, RunId};
use crate::worker::pool::Slot;
use leptos::prelude::*;
use std::rc::Rc;

impl LibraryJobs {
    /// The library's jobs, registered with `loader`, told when `models` ends a training.
    pub fn new(state: AppState, loader: Loader, models: ModelJobs) -> LibraryJobs {
        let this = LibraryJobs(Rc::new(Inner { state, loader: loader.clone(), models: models.clone() }));
        loader.register(Rc::new(this.clone()));
        let listener = this.clone();
        models.when_trained(move |index, model| listener.model_trained(index, model));
        this
    }

    /// The clips `run` of several takes answered: saved, or why not.
    /// One take's clips of the export under way, zipped (or why not): joined to the archive, the next take sent.
    fn clips_done(&self, run: RunId, outcome: Result<(usize, Vec<u8>), String>) {
        let library = self.0.state.library;
        self.0.loader.forget(run);
        library.clip_run.set_value(None);
        match outcome {
            Ok((clips, bytes)) => self.clip_part(clips, &bytes),
            Err(message) => {
                library.clip_export.set_value(None);
                library.status.set(Some((true, message)));
            }
        }
    }

    /// The take-labelling run `run` of a supervised route made progress.
    fn labelling_progress(&self, fraction: Option<f64>) {
        let library = self.0.state.library;
        let (at, count, route) = library
            .by_model
            .with_value(|k| k.as_ref().map_or((0, 0, None), |k| (k.count - k.todo.len(), k.count, Some(k.route))));
        let title = route
            .and_then(|r| self.model_slot(r))
            .map_or_else(String::new, |i| self.0.state.methods[i].info.short.clone());
        let percent = fraction.unwrap_or(0.0) * 100.0;
        library.carrying.set(Some((false, format!("labelling take {at} of {count} with the {title}… {percent:.0} %"))));
    }
}

impl Jobs for LibraryJobs {
    fn reply(&self, _slot: Slot, response: Response) {
        let library = self.0.state.library;
        let Some(run) = response.run_id() else { return };
        let percent = |fraction: Option<f64>| fraction.unwrap_or(0.0) * 100.0;
        let cluster_run = library.cluster_run.with_value(|r| r.as_ref().map(|(run, _)| *run));
        let clip_run = library.clip_run.get_value();
        // (a failure of kind `internal` also replaces the worker: the loader does)
        if self.model_run() == Some(run) {
            return match response {
                Response::Progress { fraction, .. } => self.labelling_progress(fraction),
                Response::LibraryTake { segmentation, misfit, .. } => self.model_took(run, Ok((*segmentation, misfit))),
                Response::Refused { message, .. } | Response::Failed { message, .. } => {
                    self.model_took(run, Err(message))
                }
                _ => {}
            };
        }
        if self.transfer_run() == Some(run) {
            return match response {
                Response::Progress { fraction, .. } => {
                    let text = format!("carrying the labels… {:.0} %", percent(fraction));
                    library.carrying.set(Some((false, text)));
                }
                Response::LibraryTransferred { transfer, .. } => self.transferred(run, Ok(*transfer)),
                Response::Failed { message, .. } => self.transferred(run, Err(message)),
                _ => {}
            };
        }
        if cluster_run == Some(run) {
            return match response {
                Response::Progress { fraction, .. } => {
                    let text = format!("matching the takes… {:.0} %", percent(fraction));
                    library.matching.set(Some((false, text)));
                }
                Response::LibraryClusters { clusters, .. } => self.matched(run, *clusters),
                Response::Failed { message, .. } => {
                    self.0.loader.forget(run);
                    library.cluster_run.set_value(None);
                    library.matching.set(Some((true, message)));
                }
                _ => {}
            };
        }
        if clip_run == Some(run) {
            return match response {
                Response::Clips { clips, bytes, .. } => self.clips_done(run, Ok((clips, bytes))),
                Response::Failed { message, .. } => self.clips_done(run, Err(message)),
                _ => {}
            };
        }
        let Some(i) = self.take_of(run) else { return };
        match response {
            Response::Progress { stage, fraction, .. } => {
                library.queue.update(|q| q.progress(i, &stage, fraction.unwrap_or(0.0)))
            }
            Response::LibraryTake { frames, duration_s, segmentation, features, .. } => {
                self.finish(run, Ok((frames, duration_s, *segmentation, features)))
            }
            Response::Refused { message, .. } | Response::Failed { message, .. } => self.finish(run, Err(message)),
            _ => {}
        }
    }

    fn post_pooled(&self, run: RunId, slot: Slot) {
        self.post_take(run, slot);
    }

    fn died(&self, _run: RunId) -> AfterDeath {
        // the take fails, naming why; its worker is replaced for the next
        AfterDeath::Replace
    }

    fn needs_model(&self, run: RunId, file: &str) -> bool {
        // the library segments with the unsupervised methods only, which need no model file
        let why = format!("the library's method asked for a model file ({file}), which it does not fetch");
        if self.model_run() == Some(run) {
            self.model_took(run, Err(why));
        } else {
            self.finish(run, Err(why));
        }
        false
    }

    fn fail(&self, run: RunId, message: String) {
        self.finish(run, Err(message));
    }

    fn stage(&self, run: RunId, stage: &str, fraction: f64) {
        if let Some(i) = self.take_of(run) {
            self.0.state.library.queue.update(|q| q.progress(i, stage, fraction));
        }
    }

    fn resend(&self) {
        self.resend_matching();
        self.resend_carrying();
    }

    fn worker_failed(&self, message: &str) {
        self.fail_takes(message);
    }
}
