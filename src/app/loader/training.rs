//! The supervised methods' jobs: model files the user loads (`use_model`), trainings (`train`,
//! one step per message, Stop), the question before another take is opened during a training
//! ([`ask_before_opening`]), the user's models given to every new worker (those still being
//! restored from the browser too), forgetting one (`forget_model`), and the answers to each — for
//! every method that declares [`crate::method::Supervision`], by its slot, never by name. A training's
//! end is also told to the library's supervised routes (k-NN, DT-FCN) (`crate::app::loader::library::model_trained`), which waits for it.

use crate::app::dom::now_ms;
use crate::app::loader::{next_id, post, post_buffers, replace_worker, start_run, Inner, Loader};
use crate::app::models::browser_models;
use crate::app::models::kept_models::{forgotten_message, model_after_forget, switch_question, SwitchQuestion};
use crate::app::models::supervised::{
    describe, LoadStatus, PendingChoice, PendingModel, Supervised, TrainAsk, TrainState, TrainedFile, Unloadable,
    UserModel,
};
use crate::app::state::MethodSlot;
use crate::app::take::fetch::blob_bytes;
use crate::method::supervised::{ModelInfo, StepReport, TrainingReport};
use crate::protocol::{FailureKind, Request, Response, RunId, TakeId};
use leptos::prelude::*;
use std::rc::Rc;
use std::sync::Arc;

/// A model file the worker is asked to store.
pub(super) struct ModelJob {
    id: RunId,
    /// The method's slot.
    index: usize,
    file: String,
    bytes: Arc<Vec<u8>>,
}

/// The training under way.
pub(super) struct TrainJob {
    id: RunId,
    /// The method's slot.
    index: usize,
    ask: TrainAsk,
    /// `performance.now()` when it was (last) sent.
    started: f64,
    /// The take on screen it was sent with: a model that finishes after another take was opened
    /// is not applied to that one unasked ([`on_trained`]).
    take_name: String,
    take_id: TakeId,
    /// That take's file: a new worker is sent this take again, whatever take is on screen then.
    take_file: Option<web_sys::Blob>,
    /// A step was reported (Stop is then read between two steps; before, it replaces the worker).
    stepped: bool,
    /// Stop was pressed.
    stopping: bool,
}

impl TrainJob {
    /// The method's slot.
    pub(super) fn index(&self) -> usize {
        self.index
    }
}

/// A take the user asked to open.
pub(super) enum Open {
    /// Files dropped or picked ([`Loader::load_files`]).
    Files(Vec<web_sys::File>),
    /// The bundled sample.
    Sample,
}

/// The question asked when a take is opened while a training runs: the method training (its
/// slot) and what the page says.
#[derive(Debug, Clone, PartialEq)]
pub struct SwitchAsk {
    pub index: usize,
    pub question: SwitchQuestion,
}

/// `open` when it may be opened at once; else — a training is under way (and not stopping) — it
/// waits for the user's answer to the question it puts up ([`Loader::answer_switch`]), replacing
/// a take that waited before it.
pub(super) fn ask_before_opening(inner: &Rc<Inner>, open: Open) -> Option<Open> {
    let under_way = inner
        .train_job
        .borrow()
        .as_ref()
        .filter(|j| !j.stopping)
        .map(|j| (j.index, j.ask.name.clone(), j.take_name.clone()));
    let Some((index, model, training_on)) = under_way else { return Some(open) };
    let next = match &open {
        Open::Sample => inner.urls.sample_name(),
        Open::Files(files) => {
            let names: Vec<String> = files.iter().map(web_sys::File::name).collect();
            let refs: Vec<&str> = names.iter().map(String::as_str).collect();
            match crate::load::opening(&refs) {
                Ok(crate::load::Opening::One(i)) | Ok(crate::load::Opening::AsfAmc { amc: i, .. }) => names[i].clone(),
                // refused when it is opened: the question names what was dropped
                Err(_) => names.join(", "),
            }
        }
    };
    let short = &inner.state.methods[index].info.short;
    let question = switch_question(short, &model, &training_on, &next);
    *inner.asked_open.borrow_mut() = Some(open);
    inner.switch.set(Some(SwitchAsk { index, question }));
    None
}

/// The take that waited for the question, the question taken down.
pub(super) fn answered(inner: &Inner) -> Option<Open> {
    inner.switch.set(None);
    inner.asked_open.borrow_mut().take()
}

impl Loader {
    /// Stores the model file `file` (its bytes) of the supervised method `index`; on success it
    /// becomes the method's model and the method runs again on the take on screen.
    pub fn use_model(&self, index: usize, file: String, bytes: Vec<u8>) {
        let inner = &self.0;
        let Some(s) = supervised(inner, index) else { return };
        s.file_state.set(LoadStatus::Loading);
        s.file_status.set(format!("Checking {file}…"));
        let id = next_id(inner);
        inner.model_jobs.borrow_mut().retain(|j| j.index != index);
        inner.model_jobs.borrow_mut().push(ModelJob { id, index, file, bytes: Arc::new(bytes) });
        if let Err(message) = send_model_job(inner, id) {
            fail_model_job(inner, id, message);
        }
    }

    /// Trains a model of the supervised method `index` in the worker on the take on screen (and
    /// the takes the ask adds).
    pub fn train(&self, index: usize, ask: TrainAsk) {
        let inner = &self.0;
        let Some(s) = supervised(inner, index) else { return };
        if let Some(old) = inner.train_job.borrow().as_ref().filter(|j| j.index != index) {
            // one training at a time: the worker replaces the one under way
            if let Some(other) = supervised(inner, old.index) {
                other.status.set("Not trained: another method's training replaced this one.".into());
                other.state.set(TrainState::Failed);
            }
        }
        s.errors.set(Vec::new());
        s.steps.set(Vec::new());
        s.report.set(None);
        s.pending.set(None);
        s.state.set(TrainState::Training { stage: "starting".into(), step: 0, steps: 1, fraction: 0.0 });
        s.status.set(format!("Training `{}` on the rows of {}…", ask.name, ask.labels_name));
        let id = next_id(inner);
        *inner.train_job.borrow_mut() = Some(TrainJob {
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
        if let Err(message) = send_train_job(inner) {
            fail_train_job(inner, message, None);
        }
    }

    /// Stops the training of method `index`: after the step under way (the best model so far is
    /// kept and sent), or — before its first step — at once, replacing the worker.
    pub fn stop_training(&self, index: usize) {
        let inner = &self.0;
        let (id, stepped) = {
            let mut job = inner.train_job.borrow_mut();
            let Some(job) = job.as_mut().filter(|j| j.index == index && !j.stopping) else { return };
            job.stopping = true;
            (job.id, job.stepped)
        };
        let Some(s) = supervised(inner, index) else { return };
        if !stepped {
            inner.train_job.borrow_mut().take();
            let short = &inner.state.methods[index].info.short;
            s.status.set(format!("Training cancelled; {short} runs with the model chosen in its panel."));
            s.state.set(TrainState::Cancelled);
            return replace_worker(inner);
        }
        s.state.set(TrainState::Stopping);
        let take = inner.shown.borrow().as_ref().map_or(0, |t| t.id);
        if let Err(message) = post(inner, &Request::StopTraining { take, run: id }, None) {
            fail_train_job(inner, message, None);
        }
    }
}

/// The training and models of method `index`, if it is supervised.
pub(super) fn supervised(inner: &Inner, index: usize) -> Option<&'static Supervised> {
    let methods: &'static [MethodSlot] = inner.state.methods;
    methods.get(index)?.supervised.as_ref()
}

/// Gives a worker just started every model of the supervised methods the page holds (a worker
/// knows only the shipped ones), before any other request — and the models kept in this browser
/// that an earlier worker had not answered for yet (a worker replaced while they were restored):
/// they are asked again under new ids, so that none is lost for the session.
pub(super) fn send_models(inner: &Rc<Inner>) {
    let sync_before: Vec<(RunId, usize, String)> = std::mem::take(&mut *inner.model_sync.borrow_mut());
    for (index, slot) in inner.state.methods.iter().enumerate() {
        let Some(s) = slot.supervised.as_ref() else { continue };
        for m in s.models.get_untracked() {
            sync_model(inner, index, &m.file, &m.bytes, &m.info.name, false);
        }
    }
    let restoring: Vec<(RunId, String, Arc<Vec<u8>>)> = std::mem::take(&mut *inner.restoring.borrow_mut());
    for (old, file, bytes) in restoring {
        let Some((_, index, name)) = sync_before.iter().find(|(id, _, _)| *id == old).cloned() else { continue };
        sync_model(inner, index, &file, &bytes, &name, true);
    }
}

/// Gives the worker the model `name` of method `index` (its file's name and bytes); its answer
/// is absorbed ([`handle`]) — or, for a model kept in this browser being `restored`, lists it
/// ([`on_model_restored`]) — and a refusal drops the model ([`drop_model`]).
fn sync_model(inner: &Rc<Inner>, index: usize, file: &str, bytes: &Arc<Vec<u8>>, name: &str, restored: bool) {
    let id = next_id(inner);
    inner.model_sync.borrow_mut().push((id, index, name.to_string()));
    if restored {
        inner.restoring.borrow_mut().push((id, file.to_string(), bytes.clone()));
    }
    let request = Request::UseModel {
        take: inner.shown.borrow().as_ref().map_or(0, |t| t.id),
        run: id,
        method: inner.state.methods[index].info.name.clone(),
        file: file.to_string(),
        bytes: (**bytes).clone(),
    };
    if let Err(message) = post(inner, &request, None) {
        drop_model(inner, id, message);
    }
}

/// The worker would not take one of the user's models: no worker is asked for it again, and it leaves the model
/// choice — but a model kept in this browser is not deleted (an update that changed the model format, the joints or
/// the rate would otherwise wipe every kept model): it is listed as one that does not load here, with why, to be
/// exported or forgotten by the user.
pub(super) fn drop_model(inner: &Inner, run: RunId, message: String) {
    let entry = {
        let mut sync = inner.model_sync.borrow_mut();
        let at = sync.iter().position(|(id, _, _)| *id == run);
        at.map(|at| sync.remove(at))
    };
    let Some((_, index, name)) = entry else { return };
    let restored = {
        let mut restoring = inner.restoring.borrow_mut();
        let at = restoring.iter().position(|(id, _, _)| *id == run);
        at.map(|at| restoring.remove(at))
    };
    let Some(s) = supervised(inner, index) else { return };
    let kept =
        s.models.with_untracked(|l| l.iter().find(|m| m.info.name == name).map(|m| (m.file.clone(), m.bytes.clone())));
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
pub(super) fn send_model_job(inner: &Rc<Inner>, id: RunId) -> Result<(), String> {
    let take = inner.shown.borrow().as_ref().map_or(0, |t| t.id);
    let request = {
        let jobs = inner.model_jobs.borrow();
        let job = jobs.iter().find(|j| j.id == id).ok_or("no model file request")?;
        Request::UseModel {
            take,
            run: id,
            method: inner.state.methods[job.index].info.name.clone(),
            file: job.file.clone(),
            bytes: (*job.bytes).clone(),
        }
    };
    post(inner, &request, None)
}

/// Removes and returns the model file request `id`.
pub(super) fn take_model_job(inner: &Inner, id: RunId) -> Option<ModelJob> {
    let mut jobs = inner.model_jobs.borrow_mut();
    let at = jobs.iter().position(|j| j.id == id)?;
    Some(jobs.remove(at))
}

/// The model file request `id` failed: its message shows next to the method's file input; the
/// models the method had stay.
pub(super) fn fail_model_job(inner: &Inner, id: RunId, message: String) {
    let Some(job) = take_model_job(inner, id) else { return };
    let Some(s) = supervised(inner, job.index) else { return };
    s.file_status.set(message);
    s.file_state.set(LoadStatus::Failed);
}

/// The model `name` becomes method `index`'s model (added to its `model` choice if new), and the
/// method runs again on the take on screen.
pub(super) fn select_model(inner: &Rc<Inner>, index: usize, name: &str) {
    let slot = &inner.state.methods[index];
    if let Some((value, choices)) = slot.param("model") {
        choices.update(|c| {
            if !c.iter().any(|o| o == name) {
                c.push(name.to_string());
            }
        });
        value.set(name.to_string());
    }
    // the model choice's watcher (`row_model`) re-runs too, and skips a run already using it
    if inner.shown.borrow().is_some() {
        start_run(inner, index);
    }
}

/// The worker stored a model file the user loaded.
pub(super) fn on_model_stored(inner: &Rc<Inner>, run: RunId, info: ModelInfo) {
    let Some(job) = take_model_job(inner, run) else { return };
    let Some(s) = supervised(inner, job.index) else { return };
    let short = &inner.state.methods[job.index].info.short;
    let name = info.name.clone();
    s.file_status.set(format!(
        "Loaded {}: {short} model `{name}`, {}. {short} runs with it now.",
        job.file,
        describe(&info),
    ));
    s.file_state.set(LoadStatus::Done);
    keep_model(inner, job.index, UserModel { info, file: job.file, bytes: job.bytes });
    select_model(inner, job.index, &name);
}

/// A model kept in this browser is in the worker again: it is listed in its method's model choice.
fn on_model_restored(inner: &Rc<Inner>, info: ModelInfo, file: String, bytes: Arc<Vec<u8>>) {
    let Some(index) = inner.state.methods.iter().position(|m| m.info.name == info.method) else { return };
    let Some(s) = supervised(inner, index) else { return };
    if let Some((_, choices)) = inner.state.methods[index].param("model") {
        choices.update(|c| {
            if !c.iter().any(|o| *o == info.name) {
                c.push(info.name.clone());
            }
        });
    }
    s.add(UserModel { info, file, bytes });
}

/// Posts the training under way: the take on screen first (read from its file), then the takes
/// the user added (their bytes shared with the panel, copied once into the message, never cloned).
pub(super) fn send_train_job(inner: &Rc<Inner>) -> Result<(), String> {
    let shown = inner.shown.borrow().clone().ok_or("load a take before training")?;
    let (id, request, extra, file) = {
        let mut job = inner.train_job.borrow_mut();
        let job = job.as_mut().ok_or("no training")?;
        // sent again (a new worker) after another take was opened: still bound to its own take,
        // and trained on that take's file
        if job.take_name.is_empty() {
            job.take_name = shown.name.clone();
            job.take_id = shown.id;
            job.take_file = Some(shown.file.clone());
        }
        job.started = now_ms();
        job.stepped = false;
        let ask = &job.ask;
        let takes = std::iter::once(job.take_name.clone()).chain(ask.extra.iter().map(|(n, _)| n.clone())).collect();
        let extra: Vec<Arc<Vec<u8>>> = ask.extra.iter().map(|(_, b)| Arc::clone(b)).collect();
        let request = Request::Train {
            take: job.take_id,
            run: job.id,
            method: inner.state.methods[job.index].info.name.clone(),
            name: ask.name.clone(),
            labels_name: ask.labels_name.clone(),
            labels: ask.labels.clone(),
            takes,
            options: ask.options.clone(),
            continue_from: ask.continue_from.clone(),
            validation: ask.validation.clone(),
            bytes: Vec::new(),
        };
        (job.id, request, extra, job.take_file.clone().unwrap_or(shown.file))
    };
    let inner = inner.clone();
    wasm_bindgen_futures::spawn_local(async move {
        let bytes = blob_bytes(&file).await;
        // stopped, or sent again (a new worker), while the file was read
        if inner.train_job.borrow().as_ref().map(|j| j.id) != Some(id) {
            return;
        }
        let sent = bytes.and_then(|bytes| {
            let buffers = js_sys::Array::of1(&bytes);
            for b in &extra {
                buffers.push(&js_sys::Uint8Array::from(&b[..]).buffer());
            }
            post_buffers(&inner, &request, buffers)
        });
        if let Err(message) = sent {
            fail_train_job(&inner, message, None);
        }
    });
    Ok(())
}

/// The supervised slot of the training `run`, when it is the one under way.
pub(super) fn train_slot(inner: &Inner, run: RunId) -> Option<&'static Supervised> {
    let index = inner.train_job.borrow().as_ref().filter(|j| j.id == run).map(|j| j.index)?;
    supervised(inner, index)
}

/// The training under way failed or was refused: the message shows at the input it names (or in
/// the status line); the models stay.
pub(super) fn fail_train_job(inner: &Rc<Inner>, message: String, param: Option<String>) {
    let Some(job) = inner.train_job.borrow_mut().take() else { return };
    crate::app::loader::library::model_trained(inner, job.index, Err(message.clone()));
    let Some(s) = supervised(inner, job.index) else { return };
    match param.filter(|p| s.has_input(p)) {
        Some(input) => {
            s.refuse(&input, message);
            s.status.set("Not trained: see the message at the input marked below.".into());
        }
        None => s.status.set(format!("Not trained: {message}")),
    }
    s.state.set(TrainState::Failed);
}

/// One more step of the training under way.
pub(super) fn on_training_step(inner: &Inner, report: StepReport) {
    let Some(s) = inner
        .train_job
        .borrow_mut()
        .as_mut()
        .and_then(|job| {
            job.stepped = true;
            (!job.stopping).then_some(job.index)
        })
        .and_then(|index| supervised(inner, index))
    else {
        return;
    };
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
pub(super) fn on_trained(inner: &Rc<Inner>, model: ModelInfo, report: TrainingReport, bytes: Vec<u8>) {
    let Some(job) = inner.train_job.borrow_mut().take() else { return };
    let Some(s) = supervised(inner, job.index) else { return };
    let seconds = (now_ms() - job.started) / 1000.0;
    let bytes = Arc::new(bytes);
    let name = model.name.clone();
    // the main worker trained and holds it; the pool's run workers are given it too
    crate::app::loader::pool::share_model(
        inner,
        &Request::UseModel {
            take: job.take_id,
            run: next_id(inner),
            method: inner.state.methods[job.index].info.name.clone(),
            file: s.file_name(&name),
            bytes: (*bytes).clone(),
        },
    );
    // the library's supervised routes (k-NN, DT-FCN) trained this model (stored in the worker): it labels the takes now
    crate::app::loader::library::model_trained(inner, job.index, Ok(name.clone()));
    s.trained.set(Some(TrainedFile { name: name.clone(), bytes: bytes.clone() }));
    let shown = inner.shown.borrow().as_ref().map(|t| (t.id, t.name.clone()));
    // a take being opened is the one the user turned to (the answer to the take switch's
    // question may stop a training just before the take it opens is on screen)
    let opening = inner.state.load.with_untracked(|l| match l {
        crate::app::state::LoadState::Loading { name, .. } if !name.is_empty() => Some(name.clone()),
        _ => None,
    });
    let now = match (opening, shown) {
        (Some(name), Some((id, _))) if inner.current.get() != id => Some((inner.current.get(), name)),
        (_, shown) => shown,
    };
    match now {
        Some((id, now_on)) if id != job.take_id => {
            // another take was opened meanwhile: nothing is applied to it unasked
            let short = &inner.state.methods[job.index].info.short;
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
            keep_model(inner, job.index, UserModel { file: s.file_name(&name), info: model, bytes });
            select_model(inner, job.index, &name);
        }
    }
}

/// Adds `model` to method `index`'s models and its model choice (not chosen), and keeps it in
/// this browser (IndexedDB) so that it is listed again after a reload.
pub(super) fn keep_model(inner: &Rc<Inner>, index: usize, model: UserModel) {
    let Some(s) = supervised(inner, index) else { return };
    let slot = &inner.state.methods[index];
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

impl Loader {
    /// Forgets the user's model `name` of method `index`: it leaves this browser (IndexedDB), the
    /// page's models (no new worker gets it) and the method's model choice; when it was the model
    /// in use, the method goes back to its shipped model ([`model_after_forget`]) and runs again.
    /// The file input's status line says what was forgotten (or why the browser kept it).
    pub fn forget_model(&self, index: usize, name: &str) {
        let inner = &self.0;
        let Some(s) = supervised(inner, index) else { return };
        let slot = &inner.state.methods[index];
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
                    self.rerun_with_model(index);
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

    /// What to do with a model whose training finished after another take was opened.
    pub fn settle_trained(&self, index: usize, choice: PendingChoice) {
        let inner = &self.0;
        let Some(s) = supervised(inner, index) else { return };
        let Some(p) = s.pending.get_untracked() else { return };
        s.pending.set(None);
        let name = p.info.name.clone();
        let short = &inner.state.methods[index].info.short;
        if choice != PendingChoice::Discard {
            // the worker that trained it stored it, but it may have been replaced since (a cancel
            // or a crash while the choice waited): the one now running gets it again
            sync_model(inner, index, &s.file_name(&name), &p.bytes, &name, false);
        }
        match choice {
            PendingChoice::Keep => {
                keep_model(inner, index, UserModel { file: s.file_name(&name), info: p.info, bytes: p.bytes });
                s.status.set(format!(
                    "Kept `{name}` (trained on {}) in the {short} model choice; {} still uses the model it had.",
                    p.trained_on, p.now_on
                ));
            }
            PendingChoice::Apply => {
                keep_model(inner, index, UserModel { file: s.file_name(&name), info: p.info, bytes: p.bytes });
                s.status.set(format!("{short} labels {} with `{name}` (trained on {}) now.", p.now_on, p.trained_on));
                select_model(inner, index, &name);
            }
            PendingChoice::Discard => {
                s.trained.set(None);
                s.status.set(format!("Discarded `{name}` (trained on {}).", p.trained_on));
            }
        }
    }

    /// The URL of `file` beside the shipped model files (`models/cards.json`).
    pub fn model_url(&self, file: &str) -> String {
        self.0.models.url(file)
    }

    /// The file of the take on screen (its bytes are read when asked).
    pub fn shown_file(&self) -> Option<(String, web_sys::Blob)> {
        self.0.shown.borrow().as_ref().map(|t| (t.name.clone(), t.file.clone()))
    }

    /// The models kept in this browser (IndexedDB), read once when the page starts: each is given
    /// to the worker and listed in its method's model choice (not chosen).
    pub fn restore_kept_models(&self) {
        let inner = self.0.clone();
        wasm_bindgen_futures::spawn_local(async move {
            let kept = match browser_models::load_all().await {
                Ok(kept) => kept,
                Err(message) => {
                    web_sys::console::warn_1(&format!("models kept in this browser: {message}").into());
                    return;
                }
            };
            for k in kept {
                let Some(index) = inner.state.methods.iter().position(|m| m.info.name == k.method) else { continue };
                let Some(s) = supervised(&inner, index) else { continue };
                if s.models.with_untracked(|l| l.iter().any(|m| m.info.name == k.name)) {
                    continue;
                }
                sync_model(&inner, index, &k.file, &Arc::new(k.bytes), &k.name, true);
            }
        });
    }
}

/// Sends a new worker what the old one had of the supervised methods' jobs: the model file
/// requests, and the training under way (from its first step).
pub(super) fn resend(inner: &Rc<Inner>) {
    let model_jobs: Vec<RunId> = inner.model_jobs.borrow().iter().map(|j| j.id).collect();
    for id in model_jobs {
        if let Err(message) = send_model_job(inner, id) {
            fail_model_job(inner, id, message);
        }
    }
    let training = inner.train_job.borrow().as_ref().map(|j| (j.stopping, j.index));
    match training {
        Some((true, _)) => {
            fail_train_job(inner, "the worker was replaced before it sent the stopped model; train again".into(), None)
        }
        Some((false, index)) => {
            if let Some(s) = supervised(inner, index) {
                let step_name = s.decl.step_name.clone();
                s.steps.set(Vec::new());
                s.state.set(TrainState::Training { stage: "starting again".into(), step: 0, steps: 1, fraction: 0.0 });
                s.status.set(format!(
                    "The worker was replaced (a cancel or a crash): the training starts again from {step_name} 1."
                ));
            }
            if let Err(message) = send_train_job(inner) {
                fail_train_job(inner, message, None);
            }
        }
        None => {}
    }
}

/// Every job fails with `message` (the worker could not run).
pub(super) fn fail_all(inner: &Rc<Inner>, message: &str) {
    let model_jobs: Vec<RunId> = inner.model_jobs.borrow().iter().map(|j| j.id).collect();
    for id in model_jobs {
        fail_model_job(inner, id, message.to_string());
    }
    fail_train_job(inner, message.to_string(), None);
}

/// The training `run` is at `stage` (unless it is stopping).
pub(super) fn progress(inner: &Inner, run: RunId, stage: String, fraction: Option<f64>) {
    if let Some(s) = train_slot(inner, run) {
        s.state.update(|st| {
            if let TrainState::Training { stage: old, fraction: f, .. } = st {
                *old = stage;
                *f = fraction.unwrap_or(0.0);
            }
        });
    }
}

/// Handles `response` when it answers a supervised method's job; gives it back otherwise.
pub(super) fn handle(inner: &Rc<Inner>, response: Response) -> Option<Response> {
    match response {
        Response::ModelStored { run, model, .. } => {
            let synced = {
                let mut sync = inner.model_sync.borrow_mut();
                let before = sync.len();
                sync.retain(|(id, _, _)| *id != run);
                sync.len() != before
            };
            let restored = {
                let mut restoring = inner.restoring.borrow_mut();
                let at = restoring.iter().position(|(id, _, _)| *id == run);
                at.map(|at| restoring.remove(at))
            };
            if let Some((_, file, bytes)) = restored {
                on_model_restored(inner, model, file, bytes);
            } else if !synced {
                on_model_stored(inner, run, model);
            }
        }
        Response::TrainingStep { run, report, .. } if train_slot(inner, run).is_some() => {
            on_training_step(inner, report)
        }
        Response::Trained { run, model, report, bytes, .. } if train_slot(inner, run).is_some() => {
            on_trained(inner, model, report, bytes);
        }
        Response::Failed { run: Some(run), message, kind, param, .. } if train_slot(inner, run).is_some() => {
            fail_train_job(inner, message, param);
            if kind == FailureKind::Internal {
                replace_worker(inner);
            }
        }
        Response::Failed { run: Some(run), message, kind, .. }
            if inner.model_jobs.borrow().iter().any(|j| j.id == run) =>
        {
            fail_model_job(inner, run, message);
            if kind == FailureKind::Internal {
                replace_worker(inner);
            }
        }
        Response::Failed { run: Some(run), message, kind, .. }
            if inner.model_sync.borrow().iter().any(|(id, _, _)| *id == run) =>
        {
            drop_model(inner, run, message);
            if kind == FailureKind::Internal {
                replace_worker(inner);
            }
        }
        other => return Some(other),
    }
    None
}
