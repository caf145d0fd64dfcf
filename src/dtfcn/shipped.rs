//! The models shipped with the app, built into the binary and the page (`include_bytes!`), each
//! reproducible with the command in its header (`mocapseg model-info FILE` prints it) and in the
//! `models/README.md`:
//! * `exercises` — the four mocap6 exercise takes of the shared data (seven of mocap6's twelve
//!   exercises);
//! * `cmu-actions` — CMU 86_01's action labels (a small set: one take);
//! * `locomotion` — gait phases (standing, begin/end left/right step, left/right step, turn) from
//!   the heuristic gait labeller ([`crate::labels::gait`]) on the CMU walking clips.

use std::sync::{Arc, OnceLock};

use super::model::{Model, ModelKind};

/// Names of the shipped models, the default first.
pub const NAMES: [&str; 3] = ["exercises", "cmu-actions", "locomotion"];

const DTFCN: [&[u8]; 3] = [
    include_bytes!("../../models/dtfcn-exercises.model"),
    include_bytes!("../../models/dtfcn-cmu-actions.model"),
    include_bytes!("../../models/dtfcn-locomotion.model"),
];

const KNN: [&[u8]; 3] = [
    include_bytes!("../../models/knn-exercises.model"),
    include_bytes!("../../models/knn-cmu-actions.model"),
    include_bytes!("../../models/knn-locomotion.model"),
];

type Slot = OnceLock<Result<Arc<Model>, String>>;

/// The shipped model of `kind` called `name`, read once.
pub fn model(kind: ModelKind, name: &str) -> Result<Arc<Model>, String> {
    static LOADED: [[Slot; 3]; 2] =
        [[OnceLock::new(), OnceLock::new(), OnceLock::new()], [OnceLock::new(), OnceLock::new(), OnceLock::new()]];
    let i = NAMES.iter().position(|n| *n == name).ok_or_else(|| {
        format!("no {} model called `{name}`; shipped: {} (or load your own)", kind.name(), NAMES.join(", "))
    })?;
    let (slot, bytes) = match kind {
        ModelKind::Dtfcn => (&LOADED[0][i], DTFCN[i]),
        ModelKind::Knn => (&LOADED[1][i], KNN[i]),
    };
    slot.get_or_init(|| Model::from_bytes(bytes, &format!("shipped model {}-{name}", kind.name())).map(Arc::new))
        .clone()
}
