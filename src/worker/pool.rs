//! The page's pool of workers, as decisions: which worker a method's run goes to, what waits, what a
//! crashed or cancelled worker's replacement must run again, and which answers are stale. Pure Rust
//! (tested natively); the page's loader (`crate::app::loader`) only carries out what it says —
//! starts and terminates the `Worker`s and posts the requests.
//!
//! A worker runs one method at a time (a wasm worker cannot be interrupted, so a run is cancelled by
//! replacing the worker that runs it: nothing else may be under way there). Worker 0 is the page's
//! main worker, which also loads takes, trains, annotates and cuts clips; the others only run
//! methods. A run goes to a free run worker first and to the main worker last, so that the main
//! worker stays free for what only it does; with every worker busy it waits, in the order asked.

use std::collections::VecDeque;

use crate::protocol::RunId;

/// The index of a worker in the pool (0: the main worker).
pub type Slot = usize;

/// How many workers a page of `cores` logical processors (`navigator.hardwareConcurrency`; 0 when the
/// browser does not say) starts: one per core, at least two (a method's run beside another's, or
/// beside the main worker's loading), at most [`MAX_WORKERS`] (each holds the take and the models).
pub fn workers_for(cores: usize) -> usize {
    cores.clamp(2, MAX_WORKERS)
}

/// The most workers a page starts.
pub const MAX_WORKERS: usize = 4;

/// Where a run asked of the pool went.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Placed {
    /// Post it to this worker now.
    Now(Slot),
    /// Every worker is busy: it waits for one ([`Pool::finished`] hands it over).
    Queued,
}

/// What stopping a run asks of the page.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stop {
    /// It was waiting: dropped, nothing to terminate.
    Dequeued,
    /// It runs in this worker: replace the worker ([`Pool::replaced`]).
    Replace(Slot),
    /// The pool did not know it (finished already).
    Unknown,
}

/// The runs of a pool of workers (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Pool {
    /// The run each worker is busy with.
    busy: Vec<Option<RunId>>,
    /// Run workers that could not be started or died twice: no run goes to them.
    down: Vec<bool>,
    /// Runs waiting for a free worker, oldest first.
    queue: VecDeque<RunId>,
}

impl Pool {
    /// A pool of `workers` workers (at least one: the main worker), all free.
    pub fn new(workers: usize) -> Pool {
        Pool { busy: vec![None; workers.max(1)], down: vec![false; workers.max(1)], queue: VecDeque::new() }
    }

    /// The number of workers.
    pub fn workers(&self) -> usize {
        self.busy.len()
    }

    /// The run worker `slot` is busy with.
    pub fn running(&self, slot: Slot) -> Option<RunId> {
        self.busy.get(slot).copied().flatten()
    }

    /// The worker running `run`.
    pub fn slot_of(&self, run: RunId) -> Option<Slot> {
        self.busy.iter().position(|b| *b == Some(run))
    }

    /// Whether `run` waits for a worker.
    pub fn is_queued(&self, run: RunId) -> bool {
        self.queue.contains(&run)
    }

    /// Asks for `run` to be run: on a free run worker (1, 2, …) first, the main worker last, else it
    /// waits. A run asked again (a retry) while it is known keeps its place.
    pub fn place(&mut self, run: RunId) -> Placed {
        if let Some(slot) = self.slot_of(run) {
            return Placed::Now(slot);
        }
        if self.is_queued(run) {
            return Placed::Queued;
        }
        let free = (1..self.busy.len()).chain(std::iter::once(0)).find(|&s| self.busy[s].is_none() && !self.down[s]);
        match free {
            Some(slot) => {
                self.busy[slot] = Some(run);
                Placed::Now(slot)
            }
            None => {
                self.queue.push_back(run);
                Placed::Queued
            }
        }
    }

    /// Worker `slot` answered `run` for the last time (a result, a refusal, a failure, or a wait for
    /// a model file, after which the run is asked again): the worker is free, and the oldest waiting
    /// run, if any, goes to it — returned, to be posted there. An answer about a run the worker is
    /// not busy with (a stale one) changes nothing.
    pub fn finished(&mut self, slot: Slot, run: RunId) -> Option<RunId> {
        if self.running(slot) != Some(run) {
            return None;
        }
        self.busy[slot] = None;
        self.next_for(slot)
    }

    /// The oldest waiting run given to `slot` if it is free.
    fn next_for(&mut self, slot: Slot) -> Option<RunId> {
        if self.busy.get(slot)?.is_some() {
            return None;
        }
        let run = self.queue.pop_front()?;
        self.busy[slot] = Some(run);
        Some(run)
    }

    /// Whether an answer from worker `slot` about `run` is the one the pool waits for: an answer
    /// from a worker that no longer runs it (replaced, or handed it back) is stale and dropped.
    pub fn accepts(&self, slot: Slot, run: RunId) -> bool {
        self.running(slot) == Some(run)
    }

    /// Stops `run` ([`Stop`]).
    pub fn stop(&mut self, run: RunId) -> Stop {
        if let Some(i) = self.queue.iter().position(|r| *r == run) {
            self.queue.remove(i);
            return Stop::Dequeued;
        }
        match self.slot_of(run) {
            Some(slot) => Stop::Replace(slot),
            None => Stop::Unknown,
        }
    }

    /// Worker `slot` was replaced by a new one (after a crash, a cancel or a superseded take): the
    /// run it was busy with is returned unless `dropped` (a cancelled or superseded run) — the new
    /// worker runs it again from the start —, else the new worker takes the oldest waiting run.
    /// Either way, the run returned is to be posted to `slot`.
    pub fn replaced(&mut self, slot: Slot, dropped: bool) -> Option<RunId> {
        let run = self.busy.get_mut(slot)?.take();
        match run {
            Some(run) if !dropped => {
                self.busy[slot] = Some(run);
                Some(run)
            }
            _ => self.next_for(slot),
        }
    }

    /// The runs that are still wanted are the ones `live` keeps (a new take drops every run of the
    /// old one): waiting ones that are not are forgotten, and the workers busy with one are returned
    /// — to be replaced ([`Pool::replaced`] with `dropped`), so that no worker spends its time on a
    /// result nobody will read. Only run workers are returned: the main worker (slot 0) holds more
    /// than runs (the take, a training), so its stale run is left to finish, its answer dropped.
    pub fn supersede(&mut self, live: impl Fn(RunId) -> bool) -> Vec<Slot> {
        self.queue.retain(|r| live(*r));
        let mut stale = Vec::new();
        for slot in 0..self.busy.len() {
            if self.busy[slot].is_some_and(|r| !live(r)) {
                if slot == 0 {
                    // its answer is dropped (the page no longer knows the run); the worker is free
                    // for the pool's purposes only when it answers, so it stays marked busy
                    continue;
                }
                stale.push(slot);
            }
        }
        stale
    }

    /// Run worker `slot` is out of the pool (it could not be started, or died twice): no run goes to
    /// it until [`Pool::up`]. The run it was busy with is returned, to be asked again elsewhere
    /// ([`Pool::place`]) or failed. The main worker (slot 0) is never out: the page starts it again.
    pub fn down(&mut self, slot: Slot) -> Option<RunId> {
        if slot == 0 || slot >= self.busy.len() {
            return None;
        }
        self.down[slot] = true;
        self.busy[slot].take()
    }

    /// Run worker `slot` is back (started again): it takes the oldest waiting run, returned, to be
    /// posted to it.
    pub fn up(&mut self, slot: Slot) -> Option<RunId> {
        *self.down.get_mut(slot)? = false;
        self.next_for(slot)
    }

    /// Every run of the pool, running or waiting (a worker that failed to start fails them all).
    pub fn all(&self) -> Vec<RunId> {
        self.busy.iter().flatten().copied().chain(self.queue.iter().copied()).collect()
    }

    /// Forgets every run (every worker free, nothing waiting).
    pub fn clear(&mut self) {
        self.busy.iter_mut().for_each(|b| *b = None);
        self.queue.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_page_starts_a_worker_per_core_at_least_two_at_most_four() {
        assert_eq!(workers_for(0), 2, "a browser that does not say gets two");
        assert_eq!(workers_for(1), 2);
        assert_eq!(workers_for(2), 2);
        assert_eq!(workers_for(3), 3);
        assert_eq!(workers_for(16), MAX_WORKERS);
    }

    /// Seven rows on three workers: the run workers first, the main worker last, then the queue in
    /// the order asked, each row handed to the worker that finished.
    #[test]
    fn runs_go_to_free_workers_main_last_and_wait_in_order() {
        let mut pool = Pool::new(3);
        let placed: Vec<Placed> = (1..=5).map(|r| pool.place(r)).collect();
        assert_eq!(placed, [Placed::Now(1), Placed::Now(2), Placed::Now(0), Placed::Queued, Placed::Queued]);
        assert_eq!(pool.place(4), Placed::Queued, "asked again, it keeps its place");
        assert_eq!(pool.place(2), Placed::Now(2), "a retry of a running run goes to its worker");
        assert_eq!(pool.finished(2, 2), Some(4), "the worker that finished takes the oldest waiting run");
        assert_eq!(pool.finished(0, 3), Some(5));
        assert_eq!(pool.finished(1, 1), None, "nothing waits: the worker is free");
        assert_eq!(pool.place(6), Placed::Now(1));
        assert_eq!(pool.all().len(), 3);
    }

    /// A crashed worker's row runs again on its replacement; the other workers' rows are untouched.
    #[test]
    fn a_crashed_workers_run_runs_again_on_its_replacement() {
        let mut pool = Pool::new(2);
        pool.place(10);
        pool.place(11);
        pool.place(12);
        assert_eq!(pool.replaced(1, false), Some(10), "the crashed worker's run, again");
        assert_eq!(pool.running(1), Some(10));
        assert_eq!(pool.running(0), Some(11), "the other worker's run is untouched");
        assert!(pool.is_queued(12));
        // a worker replaced while free takes what waits
        assert_eq!(pool.finished(1, 10), Some(12));
        let mut idle = Pool::new(2);
        idle.place(1);
        idle.place(2);
        idle.place(3);
        idle.finished(0, 2);
        assert_eq!(idle.running(0), Some(3));
        assert_eq!(idle.replaced(0, true), None, "a cancelled run is not run again, nothing waits");
    }

    /// A run worker that is out takes no run; its run goes elsewhere; back, it takes what waits.
    #[test]
    fn a_worker_that_is_out_takes_no_run_until_it_is_back() {
        let mut pool = Pool::new(3);
        assert_eq!(pool.place(1), Placed::Now(1));
        assert_eq!(pool.down(1), Some(1), "its run is handed back");
        assert_eq!(pool.place(1), Placed::Now(2), "and goes to the next free worker");
        assert_eq!(pool.place(2), Placed::Now(0));
        assert_eq!(pool.place(3), Placed::Queued, "worker 1 is out");
        assert_eq!(pool.down(0), None, "the main worker is never out");
        assert_eq!(pool.up(1), Some(3), "back, it takes the waiting run");
        assert_eq!(pool.running(1), Some(3));
    }

    /// Cancelling reaches the run wherever it is: a waiting run is dropped, a running one replaces
    /// exactly its worker, which then takes the next waiting run; a stale answer of the old worker
    /// is not accepted.
    #[test]
    fn cancel_reaches_every_worker_and_drops_waiting_runs() {
        let mut pool = Pool::new(3);
        for r in 1..=5 {
            pool.place(r);
        }
        assert_eq!(pool.stop(5), Stop::Dequeued);
        assert!(!pool.is_queued(5));
        for (run, slot) in [(1, 1), (2, 2), (3, 0)] {
            let mut p = pool.clone();
            assert_eq!(p.stop(run), Stop::Replace(slot), "run {run} is stopped in worker {slot}");
            assert_eq!(p.replaced(slot, true), Some(4), "the new worker takes the waiting run");
            assert!(!p.accepts(slot, run), "the replaced worker's answers about run {run} are stale");
            assert!(p.accepts(slot, 4));
        }
        assert_eq!(pool.stop(99), Stop::Unknown);
    }

    /// A new take: the old take's waiting runs are forgotten and every run worker busy with one is
    /// to be replaced; the main worker's stale run finishes, its answer not accepted once done.
    #[test]
    fn a_new_take_supersedes_the_old_takes_runs_on_every_worker() {
        let mut pool = Pool::new(3);
        for r in 1..=4 {
            pool.place(r);
        }
        let live = |r: RunId| r >= 100;
        let stale = pool.supersede(live);
        assert_eq!(stale, vec![1, 2], "both run workers are busy with the old take");
        assert!(pool.all().iter().all(|r| *r != 4), "the waiting run of the old take is forgotten");
        for slot in stale {
            assert_eq!(pool.replaced(slot, true), None);
        }
        // the new take's rows: the run workers are free again, the main worker still finishes run 3
        assert_eq!(pool.place(100), Placed::Now(1));
        assert_eq!(pool.place(101), Placed::Now(2));
        assert_eq!(pool.place(102), Placed::Queued);
        assert!(!pool.accepts(1, 1), "an answer about the old run from the new worker is stale");
        assert_eq!(pool.finished(0, 3), Some(102), "when the main worker answers, it takes the next");
    }
}
