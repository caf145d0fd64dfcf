//! The web worker that loads takes and runs every method off the page's thread: its state and
//! request handling ([`state`], pure Rust, tested natively) and, with the `web` feature, the
//! `postMessage` glue `www/worker.js` calls (`glue`). The messages themselves are
//! [`crate::protocol`]'s.

pub mod pool;
mod state;
pub use state::WorkerState;

#[cfg(feature = "web")]
mod glue;
#[cfg(feature = "web")]
pub use glue::{
    packet_from_js, packet_to_js, request_message, request_with_buffers, response_from_js, worker_handle, worker_next,
};
