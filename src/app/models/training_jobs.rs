//! The supervised methods' trainings in the main worker (`train`, one step per message, Stop), what a training
//! gives back (its model kept and chosen, or — another take opened meanwhile — offered, [`ModelJobs::settle_trained`]),
//! and the question before another take is opened during a training (the loader's gate: stop it, or keep it running
//! bound to its own take, whose file a new worker is sent again). A training's end is told to those who wait for it
//! ([`ModelJobs::when_trained`]: the library's supervised routes).

use crate::app::dom::now_ms;
use crate::app::loader::Open;
use crate::app::models::kept_models::{switch_question, SwitchAsk};
use crate::app::models::model_jobs::{ModelJobs, TrainJob};
use crate::app::models::supervised::{PendingChoice, PendingModel, TrainAsk, TrainState, TrainedFile, UserModel};
use crate::app::state::LoadState;
use crate::app::take::fetch::blob_bytes;
use crate::method::supervised::{ModelInfo, StepReport, TrainingReport};
use crate::protocol::{Request, RunId};
use leptos::prelude::*;
use std::rc::Rc;
use std::sync::Arc;

impl ModelJobs {
    /// Trains a model of the supervised method `index` in the worker on the take on screen (and
    /// the takes the ask adds).
    pub fn train(&self, index: usize, ask: TrainAsk) {
        let Some(s) = self.supervised(index) else { return };
        let other = self.0.train_job.borrow().as_ref().filter(|j| j.index != index).map(|j| j.index);
        if let Some(other) = other.and_then(|i| self.supervised(i)) {
            // one training at a time: the worker replaces the one under way
            other.status.set("Not trained: another method's training replaced this one.".into());
            other.state.set(TrainState::Failed);
        }
        s.errors.set(Vec::new());
        s.steps.set(Vec::new());
        s.report.set(None);
        s.pending.set(None);
        s.state.set(TrainState::Training { stage: "starting".into(), step: 0, steps: 1, fraction: 0.0 });
        s.status.set(format!("Training `{}` on the rows of {}…", ask.name, ask.labels_name));
        let id = self.0.loader.new_run();
        let old = self.0.train_job.borrow_mut().replace(TrainJob {
            id,
            index,
            ask,
            started: now_ms(),
            take_name: String::new(),
            take_id: 0,
            take_file: None,
            stepped: false,
            stopping: false,
        });
        if let Some(old) = old {
            self.0.loader.forget(old.id);
        }
        if let Err(message) = self.send_train_job() {
            self.fail_train_job(message, None);
        }
    }

    /// Whether a training is under way.
    pub fn training(&self) -> bool {
        self.0.train_job.borrow().is_some()
    }

    /// Calls `listener` with the method's slot and the model's name (or why there is none) each time a training ends.
    pub(crate) fn when_trained(&self, listener: impl Fn(usize, Result<String, String>) + 'static) {
        self.0.trained.borrow_mut().push(Rc::new(listener));
    }

    /// Tells those waiting that the training of method `index` ended.
    fn tell_trained(&self, index: usize, outcome: Result<String, String>) {
        let listeners = self.0.trained.borrow().clone();
        for listener in listeners {
            listener(index, outcome.clone());
        }
    }

    /// Stops the training of method `index`: after the step under way (the best model so far is
    /// kept and sent), or — before its first step — at once, replacing the worker.
    pub fn stop_training(&self, index: usize) {
        let (id, stepped) = {
            let mut job = self.0.train_job.borrow_mut();
            let Some(job) = job.as_mut().filter(|j| j.index == index && !j.stopping) else { return };
            job.stopping = true;
            (job.id, job.stepped)
        };
        let Some(s) = self.supervised(index) else { return };
        if !stepped {
            self.0.train_job.borrow_mut().take();
            self.0.loader.forget(id);
            let short = &self.0.state.methods[index].info.short;
            s.status.set(format!("Training cancelled; {short} runs with the model chosen in its panel."));
            s.state.set(TrainState::Cancelled);
            return self.0.loader.replace_worker();
        }
        s.state.set(TrainState::Stopping);
        let take = self.0.loader.shown_take().unwrap_or(0);
        if let Err(message) = self.0.loader.send(self.jobs(), &Request::StopTraining { take, run: id }) {
            self.fail_train_job(message, None);
        }
    }

    /// Posts the training under way: the take on screen first (read from its file), then the takes
    /// the user added (their bytes shared with the panel, copied once into the message, never cloned).
    pub(super) fn send_train_job(&self) -> Result<(), String> {
        let shown_id = self.0.loader.shown_take().ok_or("load a take before training")?;
        let (shown_name, shown_file) = self.0.loader.shown_file().ok_or("load a take before training")?;
        let (id, request, extra, file) = {
            let mut job = self.0.train_job.borrow_mut();
            let job = job.as_mut().ok_or("no training")?;
            // sent again (a new worker) after another take was opened: still bound to its own take,
            // and trained on that take's file
            if job.take_name.is_empty() {
                job.take_name = shown_name;
                job.take_id = shown_id;
                job.take_file = Some(shown_file.clone());
            }
            job.started = now_ms();
            job.stepped = false;
            let ask = &job.ask;
            let takes =
                std::iter::once(job.take_name.clone()).chain(ask.extra.iter().map(|(n, _)| n.clone())).collect();
            let extra: Vec<Arc<Vec<u8>>> = ask.extra.iter().map(|(_, b)| Arc::clone(b)).collect();
            let request = Request::Train {
                take: job.take_id,
                run: job.id,
                method: self.0.state.methods[job.index].info.name.clone(),
                name: ask.name.clone(),
                labels_name: ask.labels_name.clone(),
                labels: ask.labels.clone(),
                takes,
                options: ask.options.clone(),
                continue_from: ask.continue_from.clone(),
                validation: ask.validation.clone(),
                bytes: Vec::new(),
            };
            (job.id, request, extra, job.take_file.clone().unwrap_or(shown_file))
        };
        let this = self.clone();
        wasm_bindgen_futures::spawn_local(async move {
            let bytes = blob_bytes(&file).await;
            // stopped, or sent again (a new worker), while the file was read
            if this.0.train_job.borrow().as_ref().map(|j| j.id) != Some(id) {
                return;
            }
            let sent = bytes.and_then(|bytes| {
                let buffers = js_sys::Array::of1(&bytes);
                for b in &extra {
                    buffers.push(&js_sys::Uint8Array::from(&b[..]).buffer());
                }
                this.0.loader.send_buffers(this.jobs(), &request, buffers)
            });
            if let Err(message) = sent {
                this.fail_train_job(message, None);
            }
        });
        Ok(())
    }

    /// The method's slot of the training `run`, when it is the one under way.
    pub(super) fn train_index(&self, run: RunId) -> Option<usize> {
        self.0.train_job.borrow().as_ref().filter(|j| j.id == run).map(|j| j.index)
    }

    /// The training under way failed or was refused: the message shows at the input it names (or in
    /// the status line); the models stay.
    pub(super) fn fail_train_job(&self, message: String, param: Option<String>) {
        let Some(job) = self.0.train_job.borrow_mut().take() else { return };
        self.0.loader.forget(job.id);
        self.tell_trained(job.index, Err(message.clone()));
        let Some(s) = self.supervised(job.index) else { return };
        match param.filter(|p| s.has_input(p)) {
            Some(input) => {
                s.refuse(&input, message);
                s.status.set("Not trained: see the message at the input marked below.".into());
            }
            None => s.status.set(format!("Not trained: {message}")),
        }
        s.state.set(TrainState::Failed);
    }

    /// The training `run` is at `stage` (unless it is stopping).
    pub(super) fn on_training_progress(&self, run: RunId, stage: String, fraction: Option<f64>) {
        if let Some(s) = self.train_index(run).and_then(|i| self.supervised(i)) {
            s.state.update(|st| {
                if let TrainState::Training { stage: old, fraction: f, .. } = st {
                    *old = stage;
                    *f = fraction.unwrap_or(0.0);
                }
            });
        }
    }

    /// One more step of the training under way.
    pub(super) fn on_training_step(&self, report: StepReport) {
        let index = self.0.train_job.borrow_mut().as_mut().and_then(|job| {
            job.stepped = true;
            (!job.stopping).then_some(job.index)
        });
        let Some(s) = index.and_then(|i| self.supervised(i)) else { return };
        let (step, steps) = (report.step, report.steps);
        s.steps.update(|r| {
            // a training started again on a new worker begins with step 1
            r.retain(|old| old.step < step);
            r.push(report);
        });
        s.state.set(TrainState::Training { stage: "training".into(), step, steps, fraction: 0.0 });
    }

    /// The training ended with a model, stored in the worker: the page keeps it (for the download and
    /// for new workers), makes it the method's model and runs the method again.
    pub(super) fn on_trained(&self, model: ModelInfo, report: TrainingReport, bytes: Vec<u8>) {
        let Some(job) = self.0.train_job.borrow_mut().take() else { return };
        self.0.loader.forget(job.id);
        let Some(s) = self.supervised(job.index) else { return };
        let seconds = (now_ms() - job.started) / 1000.0;
        let bytes = Arc::new(bytes);
        let name = model.name.clone();
        // the main worker trained and holds it; the pool's run workers are given it too
        let take = job.take_id;
        let method = self.0.state.methods[job.index].info.name.clone();
        for slot in 1..self.0.loader.workers() {
            let run = self.0.loader.new_run();
            let (method, file, bytes) = (method.clone(), s.file_name(&name), (*bytes).clone());
            let _ = self.0.loader.post_to(slot, Request::UseModel { take, run, method, file, bytes });
        }
        // the library's supervised routes (k-NN, DT-FCN) trained this model (stored in the worker): it labels the takes now
        self.tell_trained(job.index, Ok(name.clone()));
        s.trained.set(Some(TrainedFile { name: name.clone(), bytes: bytes.clone() }));
        let shown = self.0.loader.shown_take().zip(self.0.loader.shown_file().map(|(name, _)| name));
        // a take being opened is the one the user turned to (the answer to the take switch's
        // question may stop a training just before the take it opens is on screen)
        let opening = self.0.state.load.with_untracked(|l| match l {
            LoadState::Loading { name, .. } if !name.is_empty() => Some(name.clone()),
            _ => None,
        });
        let current = self.0.loader.current_take();
        let now = match (opening, shown) {
            (Some(name), Some((id, _))) if current != id => Some((current, name)),
            (_, shown) => shown,
        };
        match now {
            Some((id, now_on)) if id != job.take_id => {
                // another take was opened meanwhile: nothing is applied to it unasked
                let short = &self.0.state.methods[job.index].info.short;
                s.status.set(format!(
                    "Trained `{name}` on {}; {now_on} is on screen now, so {short} was not re-run with it ({seconds:.1} s \
                     in this tab). Keep the model for later, apply it to {now_on} anyway, or discard it.",
                    job.take_name
                ));
                s.pending.set(Some(PendingModel { info: model, bytes, trained_on: job.take_name, now_on }));
                s.report.set(Some(report));
                s.state.set(TrainState::Done);
            }
            _ => {
                let summary = report
                    .summary
                    .replace(" labels the take with it now.", &format!(" labels {} with it now.", job.take_name));
                s.status.set(format!("{summary} ({seconds:.1} s in this tab, on {})", job.take_name));
                s.report.set(Some(report));
                s.state.set(TrainState::Done);
                self.keep_model(job.index, UserModel { file: s.file_name(&name), info: model, bytes });
                self.select_model(job.index, &name);
            }
        }
    }

    /// What to do with a model whose training finished after another take was opened.
    pub fn settle_trained(&self, index: usize, choice: PendingChoice) {
        let Some(s) = self.supervised(index) else { return };
        let Some(p) = s.pending.get_untracked() else { return };
        s.pending.set(None);
        let name = p.info.name.clone();
        let short = &self.0.state.methods[index].info.short;
        if choice != PendingChoice::Discard {
            // the worker that trained it stored it, but it may have been replaced since (a cancel
            // or a crash while the choice waited): the one now running gets it again
            self.sync_model(index, &s.file_name(&name), &p.bytes, &name, false);
        }
        match choice {
            PendingChoice::Keep => {
                self.keep_model(index, UserModel { file: s.file_name(&name), info: p.info, bytes: p.bytes });
                s.status.set(format!(
                    "Kept `{name}` (trained on {}) in the {short} model choice; {} still uses the model it had.",
                    p.trained_on, p.now_on
                ));
            }
            PendingChoice::Apply => {
                self.keep_model(index, UserModel { file: s.file_name(&name), info: p.info, bytes: p.bytes });
                s.status.set(format!("{short} labels {} with `{name}` (trained on {}) now.", p.now_on, p.trained_on));
                self.select_model(index, &name);
            }
            PendingChoice::Discard => {
                s.trained.set(None);
                s.status.set(format!("Discarded `{name}` (trained on {}).", p.trained_on));
            }
        }
    }

    /// The training under way sent again to a new main worker (from its first step); one that was stopping fails.
    pub(super) fn resend_training(&self) {
        let training = self.0.train_job.borrow().as_ref().map(|j| (j.stopping, j.index));
        match training {
            Some((true, _)) => self
                .fail_train_job("the worker was replaced before it sent the stopped model; train again".into(), None),
            Some((false, index)) => {
                if let Some(s) = self.supervised(index) {
                    let step_name = s.decl.step_name.clone();
                    s.steps.set(Vec::new());
                    s.state.set(TrainState::Training {
                        stage: "starting again".into(),
                        step: 0,
                        steps: 1,
                        fraction: 0.0,
                    });
                    s.status.set(format!(
                        "The worker was replaced (a cancel or a crash): the training starts again from {step_name} 1."
                    ));
                }
                if let Err(message) = self.send_train_job() {
                    self.fail_train_job(message, None);
                }
            }
            None => {}
        }
    }

    /// `open` when it may be opened at once; else — a training is under way (and not stopping) — it
    /// waits for the user's answer to the question it puts up ([`ModelJobs::answer_switch`]), replacing
    /// a take that waited before it. The loader's gate.
    pub(super) fn ask_before_opening(&self, open: Open) -> Option<Open> {
        let under_way = self
            .0
            .train_job
            .borrow()
            .as_ref()
            .filter(|j| !j.stopping)
            .map(|j| (j.index, j.ask.name.clone(), j.take_name.clone()));
        let Some((index, model, training_on)) = under_way else { return Some(open) };
        let next = match &open {
            Open::Sample => self.0.loader.sample_name(),
            Open::Files(files) => {
                let names: Vec<String> = files.iter().map(web_sys::File::name).collect();
                let refs: Vec<&str> = names.iter().map(String::as_str).collect();
                match crate::load::opening(&refs) {
                    Ok(crate::load::Opening::One(i)) | Ok(crate::load::Opening::AsfAmc { amc: i, .. }) => {
                        names[i].clone()
                    }
                    // refused when it is opened: the question names what was dropped
                    Err(_) => names.join(", "),
                }
            }
        };
        let short = &self.0.state.methods[index].info.short;
        let question = switch_question(short, &model, &training_on, &next);
        *self.0.asked_open.borrow_mut() = Some(open);
        self.0.switch.set(Some(SwitchAsk { index, question }));
        None
    }

    /// The question on screen while a take the user opened waits for their answer about the
    /// training under way (`None`: nothing asked).
    pub fn switch_question(&self) -> RwSignal<Option<SwitchAsk>> {
        self.0.switch
    }

    /// The take that waited for the question, the question taken down.
    fn answered(&self) -> Option<Open> {
        self.0.switch.set(None);
        self.0.asked_open.borrow_mut().take()
    }

    /// Opens the take that waits for the question's answer: `stop` stops the training first (its
    /// best model so far is then offered for its own take); else it keeps running, bound to its take.
    pub fn answer_switch(&self, stop: bool) {
        let Some(open) = self.answered() else { return };
        if stop {
            // (the borrow ends before Stop, which may replace the worker)
            let index = self.0.train_job.borrow().as_ref().map(|j| j.index);
            if let Some(index) = index {
                self.stop_training(index);
            }
        }
        self.0.loader.open_now(open);
    }

    /// Withdraws the take the question was about (Esc): nothing opens, the training goes on.
    pub fn cancel_switch(&self) {
        drop(self.answered());
    }
}
