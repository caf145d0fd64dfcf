//! The models feature's jobs as the loader sees them ([`Jobs`]): the worker's answers about model files and
//! trainings, the user's models given to every worker that starts, what a new main worker is sent again (model file
//! requests; the training under way, from its first step), and what fails when the main worker fails. The loader's
//! gate asks before a take opens during a training.

use crate::app::loader::{Jobs, Loader};
use crate::app::method_panel::runs::MethodRuns;
use crate::app::models::model_jobs::{Inner, ModelJobs};
use crate::app::state::AppState;
use crate::protocol::Response;
use crate::worker::pool::Slot;
use leptos::prelude::*;
use std::cell::RefCell;
use std::rc::Rc;

impl ModelJobs {
    /// The models' jobs, registered with `loader` (and its gate), the models kept in this browser restored.
    pub fn new(state: AppState, loader: Loader, runs: MethodRuns) -> ModelJobs {
        let this = ModelJobs(Rc::new(Inner {
            state,
            loader: loader.clone(),
            runs,
            model_jobs: RefCell::new(Vec::new()),
            model_sync: RefCell::new(Vec::new()),
            train_job: RefCell::new(None),
            restoring: RefCell::new(Vec::new()),
            asked_open: RefCell::new(None),
            switch: RwSignal::new(None),
            trained: RefCell::new(Vec::new()),
        }));
        loader.register(Rc::new(this.clone()));
        let gate = this.clone();
        loader.set_gate(move |open| gate.ask_before_opening(open));
        // the main worker started before this feature registered: it is given the user's models now
        this.send_models();
        this.restore_kept_models();
        this
    }
}

impl Jobs for ModelJobs {
    fn reply(&self, _slot: Slot, response: Response) {
        match response {
            Response::ModelStored { run, model, .. } => self.on_model_stored(run, model),
            Response::Progress { run: Some(run), stage, fraction, .. } => {
                self.on_training_progress(run, stage, fraction)
            }
            Response::TrainingStep { run, report, .. } if self.train_index(run).is_some() => {
                self.on_training_step(report)
            }
            Response::Trained { run, model, report, bytes, .. } if self.train_index(run).is_some() => {
                self.on_trained(model, report, bytes)
            }
            // a failure of kind `internal` also replaces the worker (the loader does)
            Response::Failed { run: Some(run), message, param, .. } if self.train_index(run).is_some() => {
                self.fail_train_job(message, param)
            }
            Response::Failed { run: Some(run), message, .. } if self.is_model_job(run) => {
                self.fail_model_job(run, message)
            }
            Response::Failed { run: Some(run), message, .. } if self.is_sync(run) => self.drop_model(run, message),
            _ => {}
        }
    }

    fn worker_started(&self, slot: Slot) {
        if slot == 0 {
            self.send_models();
        } else {
            self.give_models(slot);
        }
    }

    fn resend(&self) {
        self.resend_model_jobs();
        self.resend_training();
    }

    fn worker_failed(&self, message: &str) {
        self.fail_model_jobs(message);
        self.fail_train_job(message.to_string(), None);
    }
}
