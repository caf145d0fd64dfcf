//! The Effort bars under every timeline row (LMA as a semantic layer over any segmentation).
//!
//! Its pure part (natively tested) beside its components (built with the `web` feature).

pub mod layout;

#[cfg(feature = "web")]
pub mod bars;
#[cfg(feature = "web")]
pub mod jobs;
#[cfg(feature = "web")]
pub mod state;
