//! The methods' runs on the take on screen: each method of the registry has at most one run under way (a new one
//! replaces it), placed in the pool of workers ([`Loader::place`]: any worker may run it) and posted to the worker
//! the pool gives it. Its progress, result, refusal or failure go to the method's slot of the page's state. A worker
//! that does not hold the take (`not_loaded`: a new worker after a crash or a cancel) is given it and asked once
//! more; a run whose worker died is asked again once; a run that needs a shipped model file waits for it (the loader
//! fetches it). Cancelling replaces the worker that runs it (a wasm worker cannot be interrupted). After each load,
//! the methods whose `auto_run` is set (or those the URL names) run.

use crate::app::loader::{AfterDeath, Jobs, Loader};
use crate::app::state::{AppState, MethodSlot, RunState};
use crate::protocol::{FailureKind, Request, Response, RunId};
use crate::worker::pool::{Placed, Slot, Stop};
use leptos::prelude::*;
use std::cell::RefCell;
use std::rc::Rc;
use std::sync::Arc;

/// A run asked of a worker: its request, whether it was already repeated after a
/// `not_loaded` answer, and whether a worker died under it already (it is asked again once).
struct Run {
    id: RunId,
    method: String,
    params: serde_json::Value,
    retried: bool,
    crashed: bool,
}

/// The methods' runs; cheap to clone (one per page, in the page's context).
#[derive(Clone)]
pub struct MethodRuns(Rc<Inner>);

struct Inner {
    state: AppState,
    loader: Loader,
    /// The current run of each method (by registry index).
    runs: RefCell<Vec<Option<Run>>>,
    /// The methods that run after each load (URL parameter `methods`); `None`: those whose
    /// `auto_run` is set.
    auto_run: RefCell<Option<Vec<String>>>,
}

impl MethodRuns {
    /// The methods' runs, registered with `loader`.
    pub fn new(state: AppState, loader: Loader) -> MethodRuns {
        let runs = RefCell::new(state.methods.iter().map(|_| None).collect());
        let this = MethodRuns(Rc::new(Inner { state, loader: loader.clone(), runs, auto_run: RefCell::new(None) }));
        loader.register(Rc::new(this.clone()));
        this
    }

    /// Runs only the methods named (registry names) after each load, instead of those whose
    /// `auto_run` is set (the URL parameter `methods`).
    pub fn set_auto_run(&self, methods: Vec<String>) {
        *self.0.auto_run.borrow_mut() = Some(methods);
    }

    /// Runs method `index` of the registry on the take on screen with the parameters of its form.
    pub fn run(&self, index: usize) {
        self.start(index);
    }

    /// Runs method `index` again because its model choice changed (on its row or in its panel),
    /// unless no take is on screen or the run under way already uses that model.
    pub fn rerun_with_model(&self, index: usize) {
        if self.0.loader.shown_take().is_none() {
            return;
        }
        let Some((value, _)) = self.0.state.methods[index].param("model") else { return };
        let model = value.get_untracked();
        let underway = self.0.runs.borrow()[index]
            .as_ref()
            .is_some_and(|r| r.params.get("model").and_then(|m| m.as_str()) == Some(model.as_str()));
        if !underway {
            self.start(index);
        }
    }

    /// Stops method `index`'s run: the worker running it is replaced (a wasm worker cannot be interrupted; the
    /// main worker's other work starts again on the new one), or it stops waiting.
    pub fn cancel(&self, index: usize) {
        let Some(run) = self.0.runs.borrow_mut()[index].take() else { return };
        self.0.loader.forget(run.id);
        self.0.state.methods[index].run.set(RunState::Cancelled);
        if let Stop::Replace(slot) = self.0.loader.stop(run.id) {
            self.0.loader.replace_slot(slot);
        }
    }

    /// Starts (or starts again) method `index`'s run with the parameters of its form.
    fn start(&self, index: usize) {
        let slot: &MethodSlot = &self.0.state.methods[index];
        let params = match slot.params() {
            Ok(p) => p,
            Err(e) => return self.refuse_run(index, e.to_string(), e.param_name().map(str::to_string)),
        };
        slot.field_error.set(None);
        slot.failure.set(None);
        let id = self.0.loader.new_run();
        let run = Run { id, method: slot.info.name.clone(), params, retried: false, crashed: false };
        // a run asked again replaces the one under way: its run worker is replaced, or it stops waiting (the main
        // worker finishes it, its answer dropped: it holds more than the run)
        let previous = self.0.runs.borrow_mut()[index].replace(run);
        if let Some(previous) = previous {
            self.0.loader.forget(previous.id);
            if let Stop::Replace(worker) = self.0.loader.stop(previous.id) {
                if worker > 0 {
                    self.0.loader.replace_slot(worker);
                }
            }
        }
        slot.run.set(RunState::Running { stage: "starting".into(), fraction: 0.0 });
        if let Err(message) = self.send(index) {
            self.fail_run(index, format!("{}: {message}", slot.info.short));
        }
    }

    /// Places the current run of method `index` in the pool and posts it to the worker it gives (or leaves it
    /// waiting for one, "waiting for a worker" on its row).
    fn send(&self, index: usize) -> Result<(), String> {
        let run = self.0.runs.borrow()[index].as_ref().map(|r| r.id).ok_or("no run")?;
        match self.0.loader.place(Rc::new(self.clone()), run) {
            Placed::Now(slot) => self.post(index, slot),
            Placed::Queued => {
                let waiting = RunState::Running { stage: "waiting for a worker".into(), fraction: 0.0 };
                self.0.state.methods[index].run.set(waiting);
                Ok(())
            }
        }
    }

    /// Posts the current run of method `index`, for the take on screen, to worker `slot`.
    fn post(&self, index: usize, slot: Slot) -> Result<(), String> {
        let take = self.0.loader.shown_take().ok_or("no take is loaded")?;
        let request = {
            let runs = self.0.runs.borrow();
            let run = runs[index].as_ref().ok_or("no run")?;
            Request::Segment { take, run: run.id, method: run.method.clone(), params: run.params.clone() }
        };
        self.0.loader.post_to(slot, request)
    }

    /// A run failed: its message shows in the banner.
    fn fail_run(&self, index: usize, message: String) {
        self.refuse_run(index, message, None)
    }

    /// A run failed or was refused: a refusal of one of the method's parameters (`param`, as the
    /// method named it) shows at that field, any other message in the banner.
    fn refuse_run(&self, index: usize, message: String, param: Option<String>) {
        let run = self.0.runs.borrow_mut()[index].take();
        if let Some(run) = run {
            self.0.loader.forget(run.id);
            self.0.loader.release(run.id);
        }
        let state = self.0.state;
        let slot = &state.methods[index];
        slot.run.set(RunState::Failed);
        match param.filter(|p| slot.specs.iter().any(|s| s.name == *p)) {
            Some(param) => slot.field_error.set(Some((param, message))),
            None => {
                slot.failure.set(Some(message.clone()));
                state.show_run_error(no_method_can_read(&state).unwrap_or(message));
            }
        }
    }

    /// The method whose current run is `run`.
    fn index_of(&self, run: RunId) -> Option<usize> {
        self.0.runs.borrow().iter().position(|r| r.as_ref().is_some_and(|r| r.id == run))
    }

    /// Whether method `index`'s current run meets something for the first time (`flag`: it was asked again
    /// after `not_loaded`, or after its worker died), noting that it has: each is allowed once.
    fn first_time(&self, index: usize, flag: impl FnOnce(&mut Run) -> &mut bool) -> bool {
        self.0.runs.borrow_mut()[index].as_mut().is_some_and(|r| !std::mem::replace(flag(r), true))
    }

    /// Worker `slot` does not hold the take of method `index`'s run: it is given the take again and asked once
    /// more (the main worker reads the take's file again); failed the second time.
    fn not_loaded(&self, slot: Slot, index: usize, run: RunId, message: String) {
        if !self.first_time(index, |r| &mut r.retried) {
            return self.fail_run(index, message);
        }
        if slot > 0 {
            self.0.loader.hold(slot);
            if let Err(e) = self.send(index) {
                self.fail_run(index, format!("{message} ({e})"));
            }
            return;
        }
        let this = self.clone();
        wasm_bindgen_futures::spawn_local(async move {
            let restored = this.0.loader.restore().await;
            // the run may have been cancelled, or replaced, while the file was read
            if this.index_of(run) != Some(index) {
                return;
            }
            if let Err(e) = restored.and_then(|()| this.send(index)) {
                this.fail_run(index, format!("{message} ({e})"));
            }
        });
    }
}

/// One banner for all when every method that ran on the take (two or more) failed on it: what
/// each said, the shared reason once ([`crate::app::take::run_failures`]); `None` while one is still
/// running or has a result.
fn no_method_can_read(state: &AppState) -> Option<String> {
    let mut failures = Vec::new();
    for slot in state.methods {
        match slot.run.get_untracked() {
            RunState::Idle | RunState::Cancelled => {}
            RunState::Failed => failures.push((slot.info.short.clone(), slot.failure.get_untracked()?)),
            RunState::Running { .. } | RunState::Done => return None,
        }
    }
    let failures: Vec<(&str, &str)> = failures.iter().map(|(m, f)| (m.as_str(), f.as_str())).collect();
    (failures.len() >= 2).then(|| crate::app::take::run_failures::no_method_can_read(&failures))
}

impl Jobs for MethodRuns {
    fn reply(&self, slot: Slot, response: Response) {
        let state = self.0.state;
        let Some(index) = response.run_id().and_then(|run| self.index_of(run)) else { return };
        match response {
            Response::Progress { stage, fraction, .. } => {
                state.methods[index].run.set(RunState::Running { stage, fraction: fraction.unwrap_or(0.0) });
            }
            Response::Segmented { take, run, view } => {
                if self.0.loader.shown_take() != Some(take) {
                    return;
                }
                self.0.runs.borrow_mut()[index] = None;
                self.0.loader.forget(run);
                let method = &state.methods[index];
                method.view.set(Some(Arc::new(*view)));
                if state.error_is_run.get_untracked() {
                    state.error.set(None);
                }
                method.run.set(RunState::Done);
            }
            Response::Refused { message, param, .. } => self.refuse_run(index, message, param),
            Response::Failed { run: Some(run), message, kind, .. } => match kind {
                FailureKind::NotLoaded => self.not_loaded(slot, index, run, message),
                // the run trapped: it fails (it would trap again; the loader replaces its worker)
                FailureKind::Internal | FailureKind::Input => self.fail_run(index, message),
                FailureKind::Cancelled => {
                    self.0.runs.borrow_mut()[index] = None;
                    self.0.loader.forget(run);
                    state.methods[index].run.set(RunState::Cancelled);
                }
            },
            _ => {}
        }
    }

    fn take_changed(&self) {
        for slot in self.0.state.methods {
            slot.view.set(None);
            slot.run.set(RunState::Idle);
            slot.export_status.set(None);
            slot.failure.set(None);
            slot.field_error.set(None);
        }
        let old: Vec<Run> = self.0.runs.borrow_mut().iter_mut().filter_map(Option::take).collect();
        for run in old {
            self.0.loader.forget(run.id);
        }
    }

    fn take_ready(&self) {
        let auto_run = self.0.auto_run.borrow().clone();
        for (index, slot) in self.0.state.methods.iter().enumerate() {
            let wanted = auto_run.as_ref().map_or(slot.info.auto_run, |names| names.contains(&slot.info.name));
            if wanted {
                self.start(index);
            }
        }
    }

    fn post_pooled(&self, run: RunId, slot: Slot) {
        let Some(index) = self.index_of(run) else { return };
        if let Err(message) = self.post(index, slot) {
            self.fail_run(index, message);
        }
    }

    fn died(&self, run: RunId) -> AfterDeath {
        match self.index_of(run) {
            Some(index) if self.first_time(index, |r| &mut r.crashed) => AfterDeath::RunAgain,
            _ => AfterDeath::Retire,
        }
    }

    fn stage(&self, run: RunId, stage: &str, fraction: f64) {
        if let Some(index) = self.index_of(run) {
            self.0.state.methods[index].run.set(RunState::Running { stage: stage.to_string(), fraction });
        }
    }

    fn send_again(&self, run: RunId) {
        let Some(index) = self.index_of(run) else { return };
        if let Err(message) = self.send(index) {
            self.fail_run(index, message);
        }
    }

    fn fail(&self, run: RunId, message: String) {
        if let Some(index) = self.index_of(run) {
            self.fail_run(index, message);
        }
    }
}
