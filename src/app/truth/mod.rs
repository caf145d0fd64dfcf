//! The ground truth: imported, shown as a row, and every row scored against it.
//!
//! Its pure part (natively tested) beside its components (built with the `web` feature).

pub mod compare;
pub mod ranking;

#[cfg(feature = "web")]
pub mod ground_truth;
#[cfg(feature = "web")]
pub mod metrics_panel;
#[cfg(feature = "web")]
pub mod ranked;
#[cfg(feature = "web")]
pub mod state;
