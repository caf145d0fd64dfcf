//! The skeleton player, its clock and the motion image.
//!
//! Its pure part (natively tested) beside its components (built with the `web` feature).

pub mod camera;
pub mod clock;

#[cfg(feature = "web")]
pub mod canvas;
#[cfg(feature = "web")]
pub mod motion_image;
#[cfg(feature = "web")]
pub mod playback;
