//! The registered `dtfcn` method: the common labelling method ([`crate::labeller::method::Labelling`]) over
//! DT-FCN's models — its words, its model files' own fields and payload ([`super::model`]), what a run of it holds
//! and its training ([`super::supervised`]).

use super::model::networks_of;
use crate::labeller::input::joint_names;
use crate::labeller::method::Kind;
use crate::labeller::model::{Labeller, Model, ModelHeader};
use crate::method::supervised::{Training, TrainingAsk};
use crate::method::{MethodError, MethodInfo, ParamSpec, Progress};

/// DT-FCN as a labelling method.
pub struct Dtfcn;

/// The DT-FCN method (`dtfcn`), as the registry's labelling method takes it.
pub const DTFCN: Dtfcn = Dtfcn;

impl Kind for Dtfcn {
    fn name(&self) -> &'static str {
        "dtfcn"
    }

    fn short(&self) -> &'static str {
        "DT-FCN"
    }

    fn info(&self) -> MethodInfo {
        MethodInfo {
            name: "dtfcn".into(),
            short: "DT-FCN".into(),
            paper: "Cheema et al. 2019".into(),
            summary: "Per-frame semantic labels from a dilated temporal fully-convolutional network trained on \
                      labelled takes."
                .into(),
            auto_run: true,
        }
    }

    fn joint_names(&self) -> Vec<String> {
        joint_names()
    }

    fn check_header(&self, header: &ModelHeader) -> Result<(), String> {
        super::model::check_header(header)
    }

    fn read(&self, header: &mut ModelHeader, payload: &[u8]) -> Result<Box<dyn Labeller>, String> {
        super::model::read(header, payload)
    }

    /// Measured in tests/limits.rs: the network's input, + 3 kB a frame when the fit check measures the take's poses
    /// with the k-NN's windows.
    fn frame_bytes(&self, windows: bool) -> usize {
        if windows {
            5_000
        } else {
            2_000
        }
    }

    fn step_name(&self) -> &'static str {
        "epoch"
    }

    fn trains_on_my_labels(&self) -> bool {
        true
    }

    fn has_epochs(&self) -> bool {
        true
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
        Ok(super::supervised::training_work(&super::supervised::options_from_json(options)?.train))
    }

    /// The network's parameter count (of every network, in an ensemble) and receptive field.
    fn details(&self, model: &Model, o: &mut serde_json::Map<String, serde_json::Value>) {
        let Some(nets) = networks_of(model) else { return };
        let (n, networks) = (&nets.config, nets.nets.len());
        o.insert("parameters".into(), (networks * n.parameter_count()).into());
        if networks > 1 {
            o.insert("networks".into(), networks.into());
            o.insert("parameters_per_network".into(), n.parameter_count().into());
        }
        o.insert("receptive_field_frames".into(), n.receptive_field().into());
    }
}
