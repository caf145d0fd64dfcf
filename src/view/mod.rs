//! The little maths the page's player needs, kept out of the web layer so it is tested natively:
//! the orbiting perspective camera and the playback clock.

pub mod camera;
pub mod clock;
