//! One generic panel per registered method, built from the registry: its form, its run, its exports.
//! (Its row names and segment texts are the timeline's pure part: [`crate::app::timeline`].)

#[cfg(feature = "web")]
pub mod fields;
#[cfg(feature = "web")]
pub mod panel;
#[cfg(feature = "web")]
pub mod runs;
