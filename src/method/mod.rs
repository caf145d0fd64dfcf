//! One shape for every segmentation method (in the spirit of linfa's `Fit`/`Predict` with
//! checked hyper-parameters): parameters with the paper's defaults, a checked form, and one
//! function from a [`Motion`](crate::motion::Motion) to a segmentation, reporting progress and
//! stopping when asked to.

pub mod spec;
pub use spec::{ParamKind, ParamSpec};

/// The caller asked a running method to stop (the method returns as soon as it next reports).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Cancelled;

impl std::fmt::Display for Cancelled {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("cancelled")
    }
}

impl std::error::Error for Cancelled {}
