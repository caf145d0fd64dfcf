//! The page's other workers: the run workers of the pool ([`crate::worker::pool`] decides; this
//! carries it out). The main worker (slot 0) loads the take, trains, annotates and cuts clips; every worker, the
//! main one too, runs the pool's runs (a method's run, a take of the library). Each run worker is handed the take
//! on screen as the motion the main worker made of it (`hold`: parsed once, not once per worker), every model file
//! the page holds (shipped or the user's, as the main worker gets them), and then one run at a time, which the
//! feature that placed it posts ([`Jobs::post_pooled`]). Their answers about anything but the run they are busy with
//! (the models' and the take's acknowledgements, a stale run's result) are dropped: the main worker answers for
//! the models.
//!
//! A run worker that traps is replaced (the loader's top layer); one that dies without saying which run (its
//! script failed, it ran out of memory) is replaced or retired as the run's feature says ([`Jobs::died`]).
//! Stopping a run replaces the run worker that runs it, and a new take replaces every run worker still busy with a
//! run nobody wants any longer, so that none computes a result nobody reads. A run is wanted while its feature's
//! route stands ([`crate::app::loader::Loader::forget`] ends it).

use std::rc::Rc;

use leptos::prelude::*;

use crate::app::loader::jobs::{AfterDeath, Jobs};
use crate::app::loader::transport::{post_to, route, shown_id, spawn_helper, Inner};
use crate::protocol::{Request, RunId};
use crate::worker::pool::Slot;

/// How many workers this page starts: the root element's `data-workers` when it gives a number (an
/// embedding page may want one), else one per logical processor the browser reports
/// ([`crate::worker::pool::workers_for`]: at least two, at most four).
pub(super) fn workers(root_workers: Option<usize>) -> usize {
    if let Some(n) = root_workers {
        return n.clamp(1, crate::worker::pool::MAX_WORKERS);
    }
    let cores = js_sys::Reflect::get(&js_sys::global(), &"navigator".into())
        .and_then(|n| js_sys::Reflect::get(&n, &"hardwareConcurrency".into()))
        .ok()
        .and_then(|c| c.as_f64())
        .map_or(0, |c| c as usize);
    crate::worker::pool::workers_for(cores)
}

/// Starts run worker `slot` (1…), replacing the one there: given every model file the page holds (as it starts)
/// and the take on screen, then the oldest waiting run.
pub(super) fn spawn(inner: &Rc<Inner>, slot: Slot) {
    if !spawn_helper(inner, slot) {
        return out_of_pool(inner, slot);
    }
    hold(inner, slot);
    let waiting = inner.pool.borrow_mut().up(slot);
    if let Some(run) = waiting {
        post_run(inner, run);
    }
}

/// Run worker `slot` is out of the pool (terminated, not replaced): its run, if still wanted, is asked of another.
fn out_of_pool(inner: &Rc<Inner>, slot: Slot) {
    inner.helpers.borrow_mut()[slot - 1] = None; // terminates it
    let run = inner.pool.borrow_mut().down(slot);
    if let Some(run) = run.filter(|&run| route(inner, run).is_some()) {
        place_again(inner, run);
    }
}

/// Places `run` (its worker gone) again: on another worker now, or waiting for one.
fn place_again(inner: &Rc<Inner>, run: RunId) {
    let placed = inner.pool.borrow_mut().place(run);
    if let crate::worker::pool::Placed::Now(_) = placed {
        post_run(inner, run);
    }
}

/// Hands run worker `slot` the take on screen (the main worker's motion of it), if there is one.
pub(super) fn hold(inner: &Rc<Inner>, slot: Slot) {
    let take = shown_id(inner);
    if take == 0 || slot == 0 {
        return;
    }
    let Some(motion) = inner.state.motion.get_untracked() else { return };
    let _ = post_to(inner, slot, Request::Hold { take, motion: Box::new(motion.motion()) });
}

/// Hands every run worker the take now on screen, replacing those still busy with a run nobody wants (the old
/// take's, its features told first, [`Jobs::take_changed`]); the new take's runs are asked once every worker has it.
pub(super) fn new_take(inner: &Rc<Inner>) {
    // a run still routed is still wanted (the library's takes are not the take on screen's: they go on)
    let stale = inner.pool.borrow_mut().supersede(|run| route(inner, run).is_some());
    let workers = inner.pool.borrow().workers();
    for slot in 1..workers {
        if stale.contains(&slot) {
            replace(inner, slot);
        } else {
            hold(inner, slot);
        }
    }
}

/// Replaces run worker `slot` and posts it the run the pool gives it: its own run again if the page
/// still wants it (not stopped, failed or of an old take), else the oldest waiting run.
pub(super) fn replace(inner: &Rc<Inner>, slot: Slot) {
    spawn(inner, slot);
    let wanted = inner.pool.borrow().running(slot).is_some_and(|run| route(inner, run).is_some());
    let next = inner.pool.borrow_mut().replaced(slot, !wanted);
    if let Some(run) = next {
        post_run(inner, run);
    }
}

/// Has the feature of run `run` post it to the worker the pool gave it; a run the page no longer wants frees its
/// worker for the next.
pub(super) fn post_run(inner: &Rc<Inner>, run: RunId) {
    let Some(slot) = inner.pool.borrow().slot_of(run) else { return };
    match route(inner, run) {
        Some(jobs) => jobs.post_pooled(run, slot),
        None => release(inner, slot, run),
    }
}

/// Worker `slot` is done with `run` (its last answer came, or the run ended on the page): the next
/// waiting run goes to it.
pub(super) fn release(inner: &Rc<Inner>, slot: Slot, run: RunId) {
    let next = inner.pool.borrow_mut().finished(slot, run);
    if let Some(next) = next {
        post_run(inner, next);
    }
}

/// Frees whichever worker runs `run` (a run that ended on the page: failed, refused).
pub(super) fn release_run(inner: &Rc<Inner>, run: RunId) {
    let slot = inner.pool.borrow().slot_of(run);
    if let Some(slot) = slot {
        release(inner, slot, run);
    }
}

/// A run worker died without an answer (`onerror`: its script failed to load, or it ran out of memory): its run's
/// feature says what next ([`Jobs::died`]). Idle (a script that cannot load would fail again, and again), or busy
/// with a run nobody wants: the slot stays empty — its runs go to the other workers.
pub(super) fn died(inner: &Rc<Inner>, slot: Slot) {
    let run = inner.pool.borrow().running(slot);
    let jobs: Option<(RunId, Rc<dyn Jobs>)> = run.and_then(|run| route(inner, run).map(|jobs| (run, jobs)));
    let Some((run, jobs)) = jobs else { return out_of_pool(inner, slot) };
    let after = jobs.died(run);
    if after == AfterDeath::RunAgain {
        return replace(inner, slot);
    }
    // the run ends here: nobody waits for it any longer (its worker's place goes to the next run), then its feature
    // fails it
    inner.routes.borrow_mut().remove(&run);
    if after == AfterDeath::Replace {
        replace(inner, slot);
        jobs.fail(run, "the worker running it stopped (out of memory?)".into());
    } else {
        out_of_pool(inner, slot);
        jobs.fail(run, "the worker running it stopped twice (out of memory?)".into());
    }
}
