//! What a page feature gives the loader for its work in the workers ([`Jobs`]), and what the loader tells it.

use crate::protocol::{Response, RunId};
use crate::worker::pool::Slot;

/// What the loader does with a worker that died under one of a feature's runs, as the feature says ([`Jobs::died`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum AfterDeath {
    /// The run is asked again, of a new worker in place of the dead one.
    RunAgain,
    /// The feature failed the run; a new worker takes the dead one's place for the next run.
    Replace,
    /// The feature failed the run; the slot stays empty (its worker died twice, or its script cannot load), and its
    /// runs go to the other workers.
    Retire,
}

/// A feature's work in the workers. The feature sends its requests through the loader
/// ([`crate::app::loader::Loader::send`], or [`crate::app::loader::Loader::place`] for a run of the pool), and the
/// loader hands it every reply about a run it sent, by run id. Before it does, the loader frees the worker of a
/// run's last answer for the pool's next run, and after it, it replaces a worker whose wasm trapped (a `failed` of
/// kind `internal`); a run that needs a shipped model file waits for it ([`Jobs::stage`]), then is sent again
/// ([`Jobs::send_again`]) or fails ([`Jobs::fail`]). Every method has a default that does nothing, so that a feature
/// writes only what it needs.
pub(crate) trait Jobs {
    /// A reply from worker `slot` (0: the main worker) about one of the runs this feature sent (never `needs_model`:
    /// the loader fetches the file).
    fn reply(&self, slot: Slot, response: Response);
    /// A worker was just started in `slot`: give it what it must hold before anything else (the user's models).
    fn worker_started(&self, _slot: Slot) {}
    /// A new main worker replaced the one that had this feature's requests: send again what still waits (a run of
    /// the pool is the pool's to send again, [`Jobs::post_pooled`]).
    fn resend(&self) {}
    /// The main worker failed outside any request (`message` says how): what it was doing cannot be asked again.
    fn worker_failed(&self, _message: &str) {}
    /// A new take is about to be handed to the workers: drop the old take's runs (and [`crate::app::loader::Loader::forget`]
    /// them, so that the pool stops them).
    fn take_changed(&self) {}
    /// The new take is on screen and every worker has it.
    fn take_ready(&self) {}
    /// The pool gave run `run` worker `slot` (it waited for one, or its worker was replaced): post it there.
    fn post_pooled(&self, _run: RunId, _slot: Slot) {}
    /// A worker died under run `run` without answering: what the loader does next ([`AfterDeath`]). A run not
    /// asked again is then failed ([`Jobs::fail`]).
    fn died(&self, _run: RunId) -> AfterDeath {
        AfterDeath::Retire
    }
    /// Run `run` needs the shipped model file `file`: whether the loader fetches it for the run (else the feature
    /// failed the run).
    fn needs_model(&self, _run: RunId, _file: &str) -> bool {
        true
    }
    /// Run `run` waits for a shipped model file (`stage` says which, `fraction` how far).
    fn stage(&self, _run: RunId, _stage: &str, _fraction: f64) {}
    /// Run `run` can be asked again (the model file it waited for is in the worker).
    fn send_again(&self, _run: RunId) {}
    /// Run `run` failed outside its worker (`message` says why): the model file it waited for could not be had, or
    /// the worker running it died.
    fn fail(&self, _run: RunId, _message: String) {}
}
