//! The registered `knn` method: the common labelling method ([`crate::labeller::method::Labelling`]) over the
//! k-NN's models — its words, its model files' own field and payload ([`super::model`]), what a run of it holds and
//! its fit ([`super::supervised`]).

use crate::labeller::input::canonical_names;
use crate::labeller::method::Kind;
use crate::labeller::model::{Labeller, ModelHeader};
use crate::method::supervised::{Training, TrainingAsk};
use crate::method::{MethodError, MethodInfo, ParamSpec, Progress};

/// The k-NN as a labelling method.
pub struct KnnMethod;

/// The k-NN method (`knn`), as the registry's labelling method takes it.
pub const KNN: KnnMethod = KnnMethod;

impl Kind for KnnMethod {
    fn name(&self) -> &'static str {
        "knn"
    }

    fn short(&self) -> &'static str {
        "k-NN"
    }

    fn info(&self) -> MethodInfo {
        MethodInfo {
            name: "knn".into(),
            short: "k-NN".into(),
            paper: "baseline for Cheema et al. 2019".into(),
            summary: "Per-frame labels by a 5-nearest-neighbour vote on ±1 s windows of the motion image.".into(),
            auto_run: true,
        }
    }

    fn joint_names(&self) -> Vec<String> {
        canonical_names()
    }

    /// A model reading DT-FCN's input ([`super::KnnInput::Network`]) lists the network's rows.
    fn header_joints(&self, header: &ModelHeader) -> Vec<String> {
        let params = header.knn.as_ref().and_then(|k| k.read::<super::KnnParams>().ok());
        params.map_or_else(canonical_names, |p| p.input.row_names())
    }

    fn check_header(&self, header: &ModelHeader) -> Result<(), String> {
        super::model::check_header(header)
    }

    fn read(&self, header: &mut ModelHeader, payload: &[u8]) -> Result<Box<dyn Labeller>, String> {
        super::model::read(header, payload)
    }

    fn has_windows(&self) -> bool {
        true
    }

    /// Measured in tests/limits.rs: the motion image and the k-NN's windows (2.9 kB a frame).
    fn frame_bytes(&self, _windows: bool) -> usize {
        4_000
    }

    fn step_name(&self) -> &'static str {
        "fit"
    }

    fn trains_on_my_labels(&self) -> bool {
        // one click from my labels, as DT-FCN (issue 48): fitting a k-NN is quick
        true
    }

    fn has_epochs(&self) -> bool {
        false
    }

    fn training_specs(&self) -> Vec<ParamSpec> {
        super::supervised::training_specs()
    }

    fn start_training(
        &self,
        _kinds: &[&'static dyn Kind],
        ask: TrainingAsk,
        progress: &mut dyn Progress,
    ) -> Result<Box<dyn Training>, MethodError> {
        super::supervised::start_training(ask, progress)
    }

    fn training_work(&self, options: &serde_json::Value) -> Result<crate::method::Work, MethodError> {
        let options = super::supervised::options_from_json(options)?;
        Ok(super::supervised::training_work(&options.train))
    }
}
