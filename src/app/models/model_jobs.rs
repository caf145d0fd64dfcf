//! The supervised methods' models in the workers (every method that declares [`crate::method::Supervision`], by its
//! slot, never by name): a model file the user loads (`use_model`: on success it becomes the method's model and the
//! method runs again), the user's models given to every new worker (those still being restored from this browser
//! too), a model a worker refuses, forgetting one, keeping one in this browser. The trainings are
//! [`crate::app::models::training_jobs`]; the replies and the worker's events, [`crate::app::models::jobs`].

use crate::app::loader::{Jobs, Loader};
use crate::app::method_panel::runs::MethodRuns;
use crate::app::models::browser_models;
use crate::app::models::kept_models::SwitchAsk;
use crate::app::models::kept_models::{forgotten_message, model_after_forget};
use crate::app::models::supervised::{describe, LoadStatus, Supervised, TrainAsk, Unloadable, UserModel};
use crate::app::state::{AppState, MethodSlot};
use crate::method::supervised::ModelInfo;
use crate::protocol::{Request, RunId, TakeId};
use crate::worker::pool::Slot;
use leptos::prelude::*;
use std::cell::RefCell;
use std::rc::Rc;
use std::sync::Arc;

/// A model file the worker is asked to store.
pub(super) struct ModelJob {
    pub id: RunId,
    /// The method's slot.
    pub index: usize,
    pub file: String,
    pub bytes: Arc<Vec<u8>>,
}

/// The training under way.
pub(super) struct TrainJob {
    pub id: RunId,
    /// The method's slot.
    pub index: usize,
    pub ask: TrainAsk,
    /// `performance.now()` when it was (last) sent.
    pub started: f64,
    /// The take on screen it was sent with: a model that finishes after another take was opened
    /// is not applied to that one unasked.
    pub take_name: String,
    pub take_id: TakeId,
    /// That take's file: a new worker is sent this take again, whatever take is on screen then.
    pub take_file: Option<web_sys::Blob>,
    /// A step was reported (Stop is then read between two steps; before, it replaces the worker).
    pub stepped: bool,
    /// Stop was pressed.
    pub stopping: bool,
}

/// Told when a training ends: the method's slot and the model's name (stored in the worker), or why not.
pub(crate) type TrainedListener = Rc<dyn Fn(usize, Result<String, String>)>;

/// The supervised methods' models and trainings in the workers; cheap to clone (one per page, in its context).
#[derive(Clone)]
pub struct ModelJobs(pub(super) Rc<Inner>);

pub(super) struct Inner {
    pub state: AppState,
    pub loader: Loader,
    pub runs: MethodRuns,
    /// Model files being stored (one per method at a time).
    pub model_jobs: RefCell<Vec<ModelJob>>,
    /// The requests that gave the newest main worker the user's models: run, method slot and name.
    pub model_sync: RefCell<Vec<(RunId, usize, String)>>,
    /// The training under way (one at a time).
    pub train_job: RefCell<Option<TrainJob>>,
    /// Models kept in this browser being given to the worker after a reload: run, file, bytes.
    pub restoring: RefCell<Vec<(RunId, String, Arc<Vec<u8>>)>>,
    /// The take the user opened during a training, waiting for their answer to `switch`.
    pub asked_open: RefCell<Option<crate::app::loader::Open>>,
    pub switch: RwSignal<Option<SwitchAsk>>,
    /// Told when a training ends (the library's supervised routes wait for it).
    pub trained: RefCell<Vec<TrainedListener>>,
}

impl ModelJobs {
    /// The training and models of method `index`, if it is supervised.
    pub(super) fn supervised(&self, index: usize) -> Option<&'static Supervised> {
        let methods: &'static [MethodSlot] = self.0.state.methods;
        methods.get(index)?.supervised.as_ref()
    }

    /// This feature as the loader routes its replies.
    pub(super) fn jobs(&self) -> Rc<dyn Jobs> {
        Rc::new(self.clone())
    }

    /// Stores the model file `file` (its bytes) of the supervised method `index`; on success it
    /// becomes the method's model and the method runs again on the take on screen.
    pub fn use_model(&self, index: usize, file: String, bytes: Vec<u8>) {
        let Some(s) = self.supervised(index) else { return };
        s.file_state.set(LoadStatus::Loading);
        s.file_status.set(format!("Checking {file}…"));
        let id = self.0.loader.new_run();
        self.0.model_jobs.borrow_mut().retain(|j| j.index != index);
        self.0.model_jobs.borrow_mut().push(ModelJob { id, index, file, bytes: Arc::new(bytes) });
        if let Err(message) = self.send_model_job(id) {
            self.fail_model_job(id, message);
        }
    }

    /// Gives a main worker just started every model of the supervised methods the page holds (a worker
    /// knows only the shipped ones), before any other request — and the models kept in this browser
    /// that an earlier worker had not answered for yet (a worker replaced while they were restored):
    /// they are asked again under new ids, so that none is lost for the session.
    pub(super) fn send_models(&self) {
        let sync_before: Vec<(RunId, usize, String)> = std::mem::take(&mut *self.0.model_sync.borrow_mut());
        for run in sync_before.iter().map(|(id, _, _)| *id) {
            self.0.loader.forget(run);
        }
        for (index, slot) in self.0.state.methods.iter().enumerate() {
            let Some(s) = slot.supervised.as_ref() else { continue };
            for m in s.models.get_untracked() {
                self.sync_model(index, &m.file, &m.bytes, &m.info.name, false);
            }
        }
        let restoring: Vec<(RunId, String, Arc<Vec<u8>>)> = std::mem::take(&mut *self.0.restoring.borrow_mut());
        for (old, file, bytes) in restoring {
            let Some((_, index, name)) = sync_before.iter().find(|(id, _, _)| *id == old).cloned() else { continue };
            self.sync_model(index, &file, &bytes, &name, true);
        }
    }

    /// Gives run worker `slot`, just started, every model of the supervised methods the page holds (its answers are
    /// the main worker's to give).
    pub(super) fn give_models(&self, slot: Slot) {
        let take = self.0.loader.shown_take().unwrap_or(0);
        for slot_of in self.0.state.methods {
            let Some(s) = slot_of.supervised.as_ref() else { continue };
            for m in s.models.get_untracked() {
                let run = self.0.loader.new_run();
                let (method, file, bytes) = (slot_of.info.name.clone(), m.file.clone(), (*m.bytes).clone());
                let _ = self.0.loader.post_to(slot, Request::UseModel { take, run, method, file, bytes });
            }
        }
    }

    /// Gives the worker the model `name` of method `index` (its file's name and bytes); its answer
    /// is absorbed — or, for a model kept in this browser being `restored`, lists it
    /// ([`ModelJobs::on_model_restored`]) — and a refusal drops the model ([`ModelJobs::drop_model`]).
    pub(super) fn sync_model(&self, index: usize, file: &str, bytes: &Arc<Vec<u8>>, name: &str, restored: bool) {
        let id = self.0.loader.new_run();
        self.0.model_sync.borrow_mut().push((id, index, name.to_string()));
        if restored {
            self.0.restoring.borrow_mut().push((id, file.to_string(), bytes.clone()));
        }
        let request = Request::UseModel {
            take: self.0.loader.shown_take().unwrap_or(0),
            run: id,
            method: self.0.state.methods[index].info.name.clone(),
            file: file.to_string(),
            bytes: (**bytes).clone(),
        };
        if let Err(message) = self.0.loader.send(self.jobs(), &request) {
            self.drop_model(id, message);
        }
    }

    /// The worker would not take one of the user's models: no worker is asked for it again, and it leaves the model
    /// choice — but a model kept in this browser is not deleted (an update that changed the model format, the joints or
    /// the rate would otherwise wipe every kept model): it is listed as one that does not load here, with why, to be
    /// exported or forgotten by the user.
    pub(super) fn drop_model(&self, run: RunId, message: String) {
        self.0.loader.forget(run);
        let entry = {
            let mut sync = self.0.model_sync.borrow_mut();
            let at = sync.iter().position(|(id, _, _)| *id == run);
            at.map(|at| sync.remove(at))
        };
        let Some((_, index, name)) = entry else { return };
        let restored = {
            let mut restoring = self.0.restoring.borrow_mut();
            let at = restoring.iter().position(|(id, _, _)| *id == run);
            at.map(|at| restoring.remove(at))
        };
        let Some(s) = self.supervised(index) else { return };
        let kept = s
            .models
            .with_untracked(|l| l.iter().find(|m| m.info.name == name).map(|m| (m.file.clone(), m.bytes.clone())));
        match restored.map(|(_, file, bytes)| (file, bytes)).or(kept) {
            Some((file, bytes)) => {
                s.set_unloadable(Unloadable { name: name.clone(), file, bytes, why: message.clone() });
                s.file_status.set(format!(
                    "Your model `{name}` does not load here ({message}); it is kept in this browser: export it or forget it below."
                ));
            }
            None => {
                s.remove(&name);
                s.file_status.set(format!("The worker could not take your model `{name}` ({message})."));
            }
        }
        s.file_state.set(LoadStatus::Failed);
    }

    /// Posts the model file request `id`.
    pub(super) fn send_model_job(&self, id: RunId) -> Result<(), String> {
        let take = self.0.loader.shown_take().unwrap_or(0);
        let request = {
            let jobs = self.0.model_jobs.borrow();
            let job = jobs.iter().find(|j| j.id == id).ok_or("no model file request")?;
            Request::UseModel {
                take,
                run: id,
                method: self.0.state.methods[job.index].info.name.clone(),
                file: job.file.clone(),
                bytes: (*job.bytes).clone(),
            }
        };
        self.0.loader.send(self.jobs(), &request)
    }

    /// Removes and returns the model file request `id`.
    fn take_model_job(&self, id: RunId) -> Option<ModelJob> {
        self.0.loader.forget(id);
        let mut jobs = self.0.model_jobs.borrow_mut();
        let at = jobs.iter().position(|j| j.id == id)?;
        Some(jobs.remove(at))
    }

    /// Whether `run` is a model file request under way.
    pub(super) fn is_model_job(&self, run: RunId) -> bool {
        self.0.model_jobs.borrow().iter().any(|j| j.id == run)
    }

    /// The model file request `id` failed: its message shows next to the method's file input; the
    /// models the method had stay.
    pub(super) fn fail_model_job(&self, id: RunId, message: String) {
        let Some(job) = self.take_model_job(id) else { return };
        let Some(s) = self.supervised(job.index) else { return };
        s.file_status.set(message);
        s.file_state.set(LoadStatus::Failed);
    }

    /// The model `name` becomes method `index`'s model (added to its `model` choice if new), and the
    /// method runs again on the take on screen.
    pub(super) fn select_model(&self, index: usize, name: &str) {
        let slot = &self.0.state.methods[index];
        if let Some((value, choices)) = slot.param("model") {
            choices.update(|c| {
                if !c.iter().any(|o| o == name) {
                    c.push(name.to_string());
                }
            });
            value.set(name.to_string());
        }
        // the model choice's watcher (`row_model`) re-runs too, and skips a run already using it
        if self.0.loader.shown_take().is_some() {
            self.0.runs.run(index);
        }
    }

    /// The worker answered a model given to it (`ModelStored`): a model file the user loaded becomes the method's
    /// model; a model kept in this browser is listed; a model given to a new worker is absorbed.
    pub(super) fn on_model_stored(&self, run: RunId, model: ModelInfo) {
        self.0.loader.forget(run);
        let synced = {
            let mut sync = self.0.model_sync.borrow_mut();
            let before = sync.len();
            sync.retain(|(id, _, _)| *id != run);
            sync.len() != before
        };
        let restored = {
            let mut restoring = self.0.restoring.borrow_mut();
            let at = restoring.iter().position(|(id, _, _)| *id == run);
            at.map(|at| restoring.remove(at))
        };
        if let Some((_, file, bytes)) = restored {
            self.on_model_restored(model, file, bytes);
        } else if !synced {
            self.on_model_loaded(run, model);
        }
    }

    /// The worker stored a model file the user loaded.
    fn on_model_loaded(&self, run: RunId, info: ModelInfo) {
        let Some(job) = self.take_model_job(run) else { return };
        let Some(s) = self.supervised(job.index) else { return };
        let short = &self.0.state.methods[job.index].info.short;
        let name = info.name.clone();
        s.file_status.set(format!(
            "Loaded {}: {short} model `{name}`, {}. {short} runs with it now.",
            job.file,
            describe(&info),
        ));
        s.file_state.set(LoadStatus::Done);
        self.keep_model(job.index, UserModel { info, file: job.file, bytes: job.bytes });
        self.select_model(job.index, &name);
    }

    /// A model kept in this browser is in the worker again: it is listed in its method's model choice.
    fn on_model_restored(&self, info: ModelInfo, file: String, bytes: Arc<Vec<u8>>) {
        let Some(index) = self.0.state.methods.iter().position(|m| m.info.name == info.method) else { return };
        let Some(s) = self.supervised(index) else { return };
        if let Some((_, choices)) = self.0.state.methods[index].param("model") {
            choices.update(|c| {
                if !c.iter().any(|o| *o == info.name) {
                    c.push(info.name.clone());
                }
            });
        }
        s.add(UserModel { info, file, bytes });
    }

    /// Whether `run` gave a worker one of the user's models.
    pub(super) fn is_sync(&self, run: RunId) -> bool {
        self.0.model_sync.borrow().iter().any(|(id, _, _)| *id == run)
    }

    /// Adds `model` to method `index`'s models and its model choice (not chosen), and keeps it in
    /// this browser (IndexedDB) so that it is listed again after a reload.
    pub(super) fn keep_model(&self, index: usize, model: UserModel) {
        let Some(s) = self.supervised(index) else { return };
        let slot = &self.0.state.methods[index];
        if let Some((_, choices)) = slot.param("model") {
            choices.update(|c| {
                if !c.iter().any(|o| *o == model.info.name) {
                    c.push(model.info.name.clone());
                }
            });
        }
        let (method, name, file, bytes) =
            (slot.info.name.clone(), model.info.name.clone(), model.file.clone(), model.bytes.clone());
        s.add(model);
        wasm_bindgen_futures::spawn_local(async move {
            let kept = browser_models::save(&method, &name, &file, &bytes).await;
            if let Err(message) = kept {
                s.file_status
                    .set(format!("`{name}` could not be kept in this browser ({message}): download it to keep it."));
            }
        });
    }

    /// Forgets the user's model `name` of method `index`: it leaves this browser (IndexedDB), the
    /// page's models (no new worker gets it) and the method's model choice; when it was the model
    /// in use, the method goes back to its shipped model ([`model_after_forget`]) and runs again.
    /// The file input's status line says what was forgotten (or why the browser kept it).
    pub fn forget_model(&self, index: usize, name: &str) {
        let Some(s) = self.supervised(index) else { return };
        let slot = &self.0.state.methods[index];
        s.remove(name);
        let mut now = None;
        if let Some((value, choices)) = slot.param("model") {
            let chosen = value.get_untracked();
            let list = choices.get_untracked();
            let next = model_after_forget(&chosen, name, &s.decl.shipped, &list);
            choices.update(|c| c.retain(|m| m != name));
            if chosen == name {
                if let Some(next) = next {
                    // the model choice's watcher (`row_model`) runs the method again with it
                    value.set(next.clone());
                    self.0.runs.rerun_with_model(index);
                    now = Some(next);
                }
            }
        }
        s.file_state.set(LoadStatus::Done);
        s.file_status.set(forgotten_message(&slot.info.short, name, now.as_deref()));
        let (method, forgotten) = (slot.info.name.clone(), name.to_string());
        wasm_bindgen_futures::spawn_local(async move {
            if let Err(message) = browser_models::remove(&method, &forgotten).await {
                s.file_status.set(format!(
                    "`{forgotten}` left the model choice, but this browser could not forget it ({message}): it may be \
                     listed again after a reload."
                ));
                s.file_state.set(LoadStatus::Failed);
            }
        });
    }

    /// The models kept in this browser (IndexedDB), read once when the page starts: each is given
    /// to the worker and listed in its method's model choice (not chosen).
    pub(super) fn restore_kept_models(&self) {
        let this = self.clone();
        wasm_bindgen_futures::spawn_local(async move {
            let kept = match browser_models::load_all().await {
                Ok(kept) => kept,
                Err(message) => {
                    web_sys::console::warn_1(&format!("models kept in this browser: {message}").into());
                    return;
                }
            };
            for k in kept {
                let Some(index) = this.0.state.methods.iter().position(|m| m.info.name == k.method) else { continue };
                let Some(s) = this.supervised(index) else { continue };
                if s.models.with_untracked(|l| l.iter().any(|m| m.info.name == k.name)) {
                    continue;
                }
                this.sync_model(index, &k.file, &Arc::new(k.bytes), &k.name, true);
            }
        });
    }

    /// The model file requests sent again to a new main worker.
    pub(super) fn resend_model_jobs(&self) {
        let model_jobs: Vec<RunId> = self.0.model_jobs.borrow().iter().map(|j| j.id).collect();
        for id in model_jobs {
            if let Err(message) = self.send_model_job(id) {
                self.fail_model_job(id, message);
            }
        }
    }

    /// Every model file request fails with `message` (the worker could not run).
    pub(super) fn fail_model_jobs(&self, message: &str) {
        let model_jobs: Vec<RunId> = self.0.model_jobs.borrow().iter().map(|j| j.id).collect();
        for id in model_jobs {
            self.fail_model_job(id, message.to_string());
        }
    }
}
