//! The workspace kept across a reload (issue 48): what was on screen — the take, its ground truth, each row's form
//! and chosen model — kept in this browser as one record ([`record`]) beside the take's file ([`store`]: the page's
//! IndexedDB database), and set again when the page opens without a URL that names what to show ([`keeper`]); and
//! the project file that hands it on ([`project`], [`project_file`]).

pub mod project;
pub mod record;

#[cfg(feature = "web")]
pub mod keeper;
#[cfg(feature = "web")]
pub mod project_file;
#[cfg(feature = "web")]
pub mod store;
