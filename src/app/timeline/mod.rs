//! The studio's one time axis: its window, its rows and their names, a segment's text and colours, the segment menu,
//! the keyboard and a row's exports.
//!
//! Its pure part (natively tested) beside its components (built with the `web` feature).

pub mod contrast;
pub mod export_names;
pub mod label_fit;
pub mod rows;
pub mod window;

#[cfg(feature = "web")]
pub mod clip_jobs;
#[cfg(feature = "web")]
pub mod keys;
#[cfg(feature = "web")]
pub mod lanes;
#[cfg(feature = "web")]
pub mod lines;
#[cfg(feature = "web")]
pub mod method_rows;
#[cfg(feature = "web")]
pub mod minimap;
#[cfg(feature = "web")]
pub mod row_exports;
#[cfg(feature = "web")]
pub mod segment_menu;
#[cfg(feature = "web")]
pub mod tools;
