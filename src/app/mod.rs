//! The page: a leptos 0.8 client-side app (drop a BVH, see it play, its motion image and its segmentations).
//!
//! A user drops a BVH file (or the bundled sample loads by itself); the file goes to a web
//! worker ([`crate::worker`]) that parses it, runs forward kinematics and builds the motion
//! image, reporting progress; the page shows a summary, a skeleton player and the motion image
//! under a shared timeline. A bad file shows the parser's message in a banner and the previous
//! take stays on screen.
//!
//! The page is one folder per feature (docs/architecture.md draws the tree): each holds its pure
//! part — the view maths, compiled and tested natively — beside its leptos components (feature
//! `web`). The page's signals live in `state.rs` (`AppState`), made once by the root (`root.rs`) and
//! passed down; the components render them and compute little — the worker does the work. The
//! loader (`loader/`) carries requests to the workers and routes each reply by its run id; each
//! feature's jobs in the workers (the methods' runs, the models', the library's, the Effort bars', the clip
//! exports') are the feature's. [`session`] keeps the workspace across a reload. `document.body.dataset.state` says
//! where loading stands: `loading`, `ready` or `error` (the outcome of the last load).
//! After each successful load the worker runs every method whose `auto_run` is set with the
//! parameters in its form ([`method_panel`]: one generic panel per registered method, built from
//! the registry); `document.body.dataset.<method>` (e.g. `data-sssm`) says where each stands:
//! `idle`, `running`, `done`, `error` or `cancelled`. The panel of every supervised method (one
//! that declares [`crate::method::Supervision`]: DT-FCN, the k-NN, LMA) takes the user's model
//! files and trains a model in the worker one step at a time on the user's labels
//! ([`models`], `data-<method>-model`, `data-<method>-training`) — built from what the method
//! declares, never from its name. Under the
//! timeline, [`truth`] imports labels (`data-truth`, row `#row-truth`) and
//! scores any row against them as `mocapseg eval` does (`data-metrics`).
//! The URL parameters (`src`, `methods`, `t`, `autoplay`, `embed`) are read once ([`embed`]);
//! `embed=1` shows the player and the timeline only.
//! The timeline's "my labels" row ([`my_labels`], `data-my-labels`) holds the user's own
//! corrections. [`effort`] draws the Effort bars under every row (a toggle of the timeline).
//! Several files dropped at once (or a folder) make a [`library`] of takes, segmented one after
//! another in the worker, each opened on screen when clicked.

#[cfg(feature = "web")]
mod dom;
#[cfg(feature = "web")]
mod idb;
#[cfg(feature = "web")]
mod loader;
#[cfg(feature = "web")]
mod root;
#[cfg(feature = "web")]
mod state;
#[cfg(feature = "web")]
mod workspace;

pub mod consensus;
pub mod effort;
pub mod embed;
pub mod library;
pub mod method_panel;
pub mod models;
pub mod my_labels;
pub mod player;
pub mod session;
pub mod take;
pub mod timeline;
pub mod truth;
