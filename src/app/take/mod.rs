//! Opening a take: files dropped, picked or fetched, the progress of their load, the take's summary, and what the
//! page says when a load or every method fails (or when the page's own wasm stops).
//!
//! Its pure part (natively tested) beside its components (built with the `web` feature).

pub mod run_failures;

#[cfg(feature = "web")]
pub mod drop_zone;
#[cfg(feature = "web")]
pub mod error_banner;
#[cfg(feature = "web")]
pub mod fetch;
#[cfg(feature = "web")]
pub mod first_visit;
#[cfg(feature = "web")]
pub mod progress;
#[cfg(feature = "web")]
pub mod stopped;
#[cfg(feature = "web")]
pub mod summary;
