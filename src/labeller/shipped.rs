//! The labelling models shipped with the app, one of each labeller's kind per name (`models/{dtfcn,knn}-NAME.model`:
//! the fit check measures a shipped DT-FCN model with the k-NN file of its name), listed by
//! [`crate::method::shipped`]: built into the command line, fetched by the page when first
//! used), each reproducible with the command in its header (`mocapseg model-info NAME` prints
//! it) and in `models/README.md`:
//! * `exercises` — the four mocap6 exercise takes of the shared data (seven of mocap6's twelve
//!   exercises);
//! * `cmu-actions` — CMU 86_01's action labels (a small set: one take);
//! * `locomotion` — gait phases (standing, begin/end left/right step, left/right step, turn) from
//!   the heuristic gait labeller ([`crate::labels::gait`]) on the CMU walking clips.

use std::sync::Arc;

use super::method::Kind;
use super::model::Model;
use crate::method::{MethodError, ModelStore};

/// Names of the shipped models, the default first.
pub const NAMES: [&str; 3] = ["exercises", "cmu-actions", "locomotion"];

/// The file of the shipped model of `kind` called `name` (`dtfcn-exercises.model`).
pub fn file_name(kind: &dyn Kind, name: &str) -> String {
    format!("{}-{name}.model", kind.name())
}

/// The shipped model of `kind` called `name`, read once by `models` (the runner's store; `kinds`: the kinds a model
/// file may be of); [`MethodError::NeedsModel`] on the page until its file was handed over.
pub fn model(kind: &dyn Kind, name: &str, models: &ModelStore, kinds: &[&dyn Kind]) -> Result<Arc<Model>, MethodError> {
    if !NAMES.contains(&name) {
        return Err(MethodError::param(
            "model",
            format!(
                "model: no {} model called `{name}`; shipped: {} (or load your own)",
                kind.name(),
                NAMES.join(", ")
            ),
        ));
    }
    models.read_shipped(&file_name(kind, name), |bytes| {
        Model::from_bytes(bytes, &format!("shipped model {}-{name}", kind.name()), kinds).map_err(MethodError::Failed)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shipped model of the labelling method `method` called `name`, as the registry's method reads it.
    fn shipped(method: &str, name: &str) -> Result<Arc<Model>, MethodError> {
        let supervised = crate::methods::find(method).unwrap().supervised().unwrap();
        let loaded = supervised.shipped_model(name, &ModelStore::default())?;
        Ok(loaded.model.downcast::<Model>().unwrap())
    }

    #[test]
    fn every_shipped_name_has_a_file_of_both_kinds() {
        for kind in ["dtfcn", "knn"] {
            for name in NAMES {
                let m = shipped(kind, name).unwrap();
                assert_eq!(m.header.kind, kind);
                assert!(crate::method::shipped::find(&format!("{kind}-{name}.model")).is_ok());
            }
        }
        let err = shipped("knn", "nope").unwrap_err().to_string();
        assert!(err.contains("no knn model called `nope`") && err.contains("exercises"), "{err}");
    }

    /// What a shipped file's header says is what `models/README.md` tells a reader to type: the
    /// unknown threshold (which runs use unless they ask for another) is its command's
    /// `--unknown-threshold` or the option's default, the command is the README's line, and every
    /// training take's file is hashed (so the page tells the bundled sample, another version of
    /// 13_30, by content).
    #[test]
    fn every_shipped_header_is_what_runs_use_and_the_readme_reproduces() {
        let readme =
            std::fs::read_to_string(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("models/README.md")).unwrap();
        for kind in ["dtfcn", "knn"] {
            for name in NAMES {
                let h = &shipped(kind, name).unwrap().header;
                let file = format!("{kind}-{name}.model");
                let command = &h.provenance.command;
                let asked = command.split_once("--unknown-threshold ").map(|(_, rest)| {
                    rest.split_whitespace().next().and_then(|t| t.parse::<f32>().ok()).expect("a number")
                });
                let threshold = asked.unwrap_or(super::super::method::DEFAULT_THRESHOLD as f32);
                assert_eq!(h.unknown_threshold, threshold, "{file}");
                assert!(command.ends_with(&format!("--out models/{file}")), "{file}: {command}");
                assert!(readme.lines().any(|l| l == command), "{file}: `{command}` is not a line of models/README.md");
                let p = &h.provenance;
                assert_eq!(p.take_sha256.len(), p.takes.len(), "{file}");
                assert!(p.take_sha256.iter().all(|x| x.len() == 64), "{file}");
            }
        }
    }
}
