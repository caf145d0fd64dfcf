//! What the page's URL asks for (`src`, `methods`, `t`, `autoplay`, `embed`), what the page fetches from a URL and
//! says when it cannot, and the embedded page's bar.
//!
//! Its pure part (natively tested) beside its components (built with the `web` feature).

pub mod fetch_rules;
pub mod url_params;

#[cfg(feature = "web")]
pub mod launch;
