//! The timeline's "my labels" row: the user's own segmentation of the take on screen.
//!
//! Its pure part (natively tested) beside its components (built with the `web` feature).

pub mod edits;
pub mod snap;
pub mod spans;
pub mod stored;
pub mod vocabulary;

#[cfg(feature = "web")]
pub mod browser_storage;
#[cfg(feature = "web")]
pub mod input;
#[cfg(feature = "web")]
pub mod lane;
#[cfg(feature = "web")]
pub mod others;
#[cfg(feature = "web")]
pub mod row;
#[cfg(feature = "web")]
pub mod tools;
