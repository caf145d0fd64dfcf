//! The labelling models shipped with the app (`models/{dtfcn,knn}-NAME.model`, listed by
//! [`crate::method::shipped`]: built into the command line, fetched by the page when first
//! used), each reproducible with the command in its header (`mocapseg model-info NAME` prints
//! it) and in `models/README.md`:
//! * `exercises` — the four mocap6 exercise takes of the shared data (seven of mocap6's twelve
//!   exercises);
//! * `cmu-actions` — CMU 86_01's action labels (a small set: one take);
//! * `locomotion` — gait phases (standing, begin/end left/right step, left/right step, turn) from
//!   the heuristic gait labeller ([`crate::labels::gait`]) on the CMU walking clips.

use std::sync::Arc;

use super::model::{ModelKind, KINDS};
use crate::labeller::model::Model;
use crate::method::{MethodError, ModelStore};

/// Names of the shipped models, the default first.
pub const NAMES: [&str; 3] = ["exercises", "cmu-actions", "locomotion"];

/// The file of the shipped model of `kind` called `name` (`dtfcn-exercises.model`).
pub fn file_name(kind: ModelKind, name: &str) -> String {
    format!("{}-{name}.model", kind.name())
}

/// The shipped model of `kind` called `name`, read once by `models` (the runner's store); [`MethodError::NeedsModel`]
/// on the page until its file was handed over.
pub fn model(kind: ModelKind, name: &str, models: &ModelStore) -> Result<Arc<Model>, MethodError> {
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
        Model::from_bytes(bytes, &format!("shipped model {}-{name}", kind.name()), &KINDS).map_err(MethodError::Failed)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_shipped_name_has_a_file_of_both_kinds() {
        for kind in [ModelKind::Dtfcn, ModelKind::Knn] {
            for name in NAMES {
                let m = model(kind, name, &ModelStore::default()).unwrap();
                assert_eq!(m.header.kind, kind.name());
                assert!(crate::method::shipped::find(&file_name(kind, name)).is_ok());
            }
        }
        let err = model(ModelKind::Knn, "nope", &ModelStore::default()).unwrap_err().to_string();
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
        for kind in [ModelKind::Dtfcn, ModelKind::Knn] {
            for name in NAMES {
                let h = &model(kind, name, &ModelStore::default()).unwrap().header;
                let file = file_name(kind, name);
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
