//! The timeline's "Consensus" row: where the methods on screen agree on a boundary.
//!
//! Its pure part (natively tested) beside its components (built with the `web` feature).

pub mod settings;

#[cfg(feature = "web")]
pub mod row;
