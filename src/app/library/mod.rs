//! The library of takes: several files segmented one after another, their clusters, and labels carried between them.
//!
//! Its pure part (natively tested) beside its components (built with the `web` feature).

pub mod carry;
pub mod names;
pub mod queue;
pub mod takes;

#[cfg(feature = "web")]
pub mod carry_jobs;
#[cfg(feature = "web")]
pub mod jobs;
#[cfg(feature = "web")]
pub mod library_jobs;
#[cfg(feature = "web")]
pub mod on_screen;
#[cfg(feature = "web")]
pub mod panel;
#[cfg(feature = "web")]
pub mod queue_jobs;
#[cfg(feature = "web")]
pub mod state;
