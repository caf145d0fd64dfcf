//! The library's jobs in the workers (issue 26), their handle: the takes of the library segmented as many at a time
//! as the pool has workers ([`crate::app::library::queue_jobs`]), matched into clusters shared across takes, the take
//! on screen's labels carried to the others ([`crate::app::library::carry_jobs`]), the clips of several takes cut into
//! one zip; the worker's answers, [`crate::app::library::jobs`]. The jobs' state is the library's
//! ([`crate::app::library::state::LibraryState`]); what the page shows is [`crate::app::library::panel`].

use crate::app::library::state::Source;
use crate::app::loader::{Jobs, Loader};
use crate::app::models::model_jobs::ModelJobs;
use crate::app::state::AppState;
use crate::app::take::fetch::blob_bytes;
use crate::protocol::{Request, RunId};
use leptos::prelude::*;
use std::rc::Rc;
use web_sys::{Blob, File};

/// The library's jobs; cheap to clone (one per page, in its context).
#[derive(Clone)]
pub struct LibraryJobs(pub(super) Rc<Inner>);

pub(super) struct Inner {
    pub state: AppState,
    pub loader: Loader,
    /// The trainings the supervised routes ask for.
    pub models: ModelJobs,
}

impl LibraryJobs {
    /// This feature as the loader routes its replies.
    pub(super) fn jobs(&self) -> Rc<dyn Jobs> {
        Rc::new(self.clone())
    }

    /// The take of the library that run `run` segments, if the library still wants it.
    pub(super) fn take_of(&self, run: RunId) -> Option<usize> {
        self.0.state.library.running.with_value(|r| r.iter().find(|(r, _)| *r == run).map(|&(_, i)| i))
    }

    /// The name of take `i` of the library.
    pub(super) fn take_name(&self, i: usize) -> String {
        self.0.state.library.take_name(i)
    }
}

/// Take `source`'s files read again (the motion, then its skeleton) as a request's buffers.
pub(super) async fn read_files(source: &Source) -> Result<js_sys::Array, String> {
    let buffers = js_sys::Array::new();
    for blob in std::iter::once(&source.motion).chain(source.skeleton.as_ref()) {
        let bytes = blob_bytes(&Blob::from(blob.clone()))
            .await
            .map_err(|e| format!("{}: could not read the file: {e}", blob.name()))?;
        buffers.push(&bytes);
    }
    Ok(buffers)
}

/// The `library_take` request segmenting take `source` with `method` and `params` as run `run`
/// (its files' bytes go as buffers).
pub(super) fn take_request(run: u32, source: &Source, method: String, params: serde_json::Value) -> Request {
    Request::LibraryTake {
        take: 0,
        run,
        name: source.motion.name(),
        bytes: Vec::new(),
        skeleton: source.skeleton.as_ref().map(File::name),
        skeleton_bytes: Vec::new(),
        method,
        params,
    }
}
