//! What the page's URL asks for (`src`, `methods`, `t`, `autoplay`, `embed`) and the embedded page's bar.
//!
//! Its pure part (natively tested) beside its components (built with the `web` feature).

pub mod url_params;

#[cfg(feature = "web")]
pub mod launch;
