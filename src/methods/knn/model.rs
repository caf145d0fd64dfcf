//! The k-NN's model files: the fitted labeller as a model file's payload ([`Knn::to_bytes`]) and the header field
//! only the k-NN writes — its window and vote (`knn`, [`KnnParams`]) — read and checked here; the framing, the header
//! and its common checks are [`crate::labeller::model`]'s.

use std::any::Any;

use serde::{Deserialize, Serialize};

use super::{Knn, KnnParams};
use crate::labeller::fit::Windows;
use crate::labeller::model::{Json, Labeller, Model, ModelHeader};
use crate::labeller::probabilities::Probabilities;
use crate::method::{MethodError, Progress};
use crate::motion::Motion;

impl Labeller for Knn {
    fn label(
        &self,
        header: &ModelHeader,
        motion: &Motion,
        progress: &mut dyn Progress,
    ) -> Result<(Probabilities, Vec<f64>, f64), MethodError> {
        progress.step("neighbours", 0.1)?;
        let (p, source) = self
            .probabilities_going(motion, header.classes.len(), &mut |f| {
                progress.step("neighbours", 0.1 + 0.8 * f).is_ok()
            })
            .map_err(MethodError::Failed)?
            .ok_or(MethodError::Cancelled)?;
        Ok((p, source, self.params().fps))
    }

    fn payload(&self) -> Result<(Vec<u8>, Vec<u64>), String> {
        Ok((self.to_bytes(), Vec::new()))
    }

    fn ops_per_frame(&self, classes: usize) -> f64 {
        // the query, then its k votes and the classes' shares
        self.search_ops_per_frame() + (self.params().k + classes) as f64
    }

    fn windows(&self) -> Option<&dyn Windows> {
        Some(self)
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}

/// The k-NN of `model`, when it holds one.
pub fn knn_of(model: &Model) -> Option<&Knn> {
    model.labeller.as_any().downcast_ref::<Knn>()
}

/// The training options a k-NN file's provenance records: the network trainer's table, at its defaults — k-NN files
/// carried them while both labellers were trained from one table, and the k-NN reads none of them. Read and written
/// in that shape (a field this build does not know dropped, one missing at its default) so that k-NN files, and
/// what `model-info` shows of them, stay byte for byte what they were.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct RecordedOptions {
    pub epochs: usize,
    pub learning_rate: f64,
    pub weight_decay: f64,
    pub seed: u64,
    pub label_noise: f64,
    pub mask_s: f64,
    pub augment: RecordedAugment,
    pub crop_frames: usize,
    pub batch: usize,
    pub patience: usize,
    pub width: usize,
    pub filters: Vec<usize>,
    pub padding: String,
    pub image_rows: Option<usize>,
    #[serde(skip_serializing_if = "is_zero")]
    pub average_last: usize,
    #[serde(skip_serializing_if = "is_one")]
    pub members: usize,
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub centre_on_take: bool,
}

/// The augmentations of [`RecordedOptions`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct RecordedAugment {
    pub mirror: bool,
    pub yaw: bool,
    pub time_warp: bool,
    pub scale: bool,
    pub jitter: bool,
}

impl Default for RecordedAugment {
    fn default() -> Self {
        RecordedAugment { mirror: true, yaw: true, time_warp: true, scale: true, jitter: true }
    }
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

fn is_one(n: &usize) -> bool {
    *n == 1
}

impl Default for RecordedOptions {
    fn default() -> Self {
        RecordedOptions {
            epochs: 60,
            learning_rate: 1e-3,
            weight_decay: 1e-4,
            seed: 1,
            label_noise: 0.0,
            mask_s: 0.0,
            augment: RecordedAugment::default(),
            crop_frames: 128,
            batch: 2,
            patience: 12,
            width: 3,
            filters: vec![64, 128, 256, 512],
            padding: "zero".into(),
            image_rows: None,
            average_last: 0,
            members: 1,
            centre_on_take: false,
        }
    }
}

/// What the k-NN's field of a header must say: a window and a vote it can use.
pub fn check_header(h: &ModelHeader) -> Result<(), String> {
    h.knn.as_ref().ok_or("a k-NN model without its parameters")?.read::<KnnParams>()?.check()
}

/// The k-NN of a model file's payload, the header's window and vote and the training's options put in the one form
/// the k-NN writes them.
pub fn read(header: &mut ModelHeader, payload: &[u8]) -> Result<Box<dyn Labeller>, String> {
    let field = header.knn.as_ref().ok_or("a k-NN model without its parameters")?;
    let (params, knn) = field.normalised::<KnnParams>()?;
    let (_, options) = header.provenance.options.normalised::<RecordedOptions>()?;
    (header.knn, header.provenance.options) = (Some(knn), options);
    Ok(Box::new(Knn::from_bytes(payload, params, header.classes.len())?))
}

/// The options a new k-NN file records ([`RecordedOptions`]).
pub fn recorded_options() -> Result<Json, String> {
    Json::of(&RecordedOptions::default())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::labeller::model::{frame, read_header};

    /// What a new k-NN file records of its training's options is what the shipped k-NN files carry.
    #[test]
    fn the_recorded_options_are_the_shipped_files() {
        let bytes = crate::method::ModelStore::default().shipped_bytes("knn-exercises.model").unwrap().to_vec();
        let (header, _) = crate::labeller::model::read_header(&bytes, "knn-exercises.model").unwrap();
        assert_eq!(header.provenance.options, recorded_options().unwrap());
    }

    /// A k-NN reading DT-FCN's input is written with the network's rows in its header and read back voting the same;
    /// its header claiming the joints' rows (what a joints model lists) is refused, naming both.
    #[test]
    fn a_network_input_knn_file_lists_the_networks_rows() {
        use crate::labeller::corpus::ModelMeta;
        use crate::methods::knn::{training::fit_knn_model, KnnInput, KnnParams};
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/www/sample.bvh");
        let take = Motion::from_bvh("13_30", &crate::bvh::parse(&std::fs::read_to_string(path).unwrap()).unwrap())
            .unwrap()
            .slice(0, 800);
        let labels: Vec<Option<usize>> = (0..take.frames()).map(|f| Some(usize::from(f >= 216))).collect();
        let meta = ModelMeta {
            name: "n".into(),
            command: "test".into(),
            data_hash: String::new(),
            decoding: None,
            unknown_threshold: 0.0,
            travel: None,
        };
        let params = KnnParams { input: KnnInput::Network, ..KnnParams::default() };
        let classes = ["JumpJack".to_string(), "Twist".to_string()];
        let model = fit_knn_model(&[(&take, &labels[..])], &classes, &meta, params).unwrap();
        assert_eq!(model.header.joints, crate::labeller::input::joint_names());
        let kinds: [&dyn crate::labeller::method::Kind; 1] = [&super::super::method::KNN];
        let bytes = model.to_bytes().unwrap();
        let back = Model::from_bytes(&bytes, "n.model", &kinds).unwrap();
        assert_eq!(knn_of(&back).unwrap().params(), params);
        let votes = |m: &Model| knn_of(m).unwrap().predict(&take).unwrap();
        assert_eq!(votes(&back), votes(&model));
        let (mut header, payload) = read_header(&bytes, "n.model").unwrap();
        header.joints = crate::labeller::input::canonical_names();
        let e = Model::from_bytes(&frame(&header, payload).unwrap(), "n.model", &kinds).err().expect("refused");
        assert!(e.contains("turning") && e.contains("train the model again"), "{e}");
        // a joints model's file says nothing of its input: the shipped files stay byte for byte what they were
        let joints = fit_knn_model(&[(&take, &labels[..])], &classes, &meta, KnnParams::default()).unwrap();
        let field: serde_json::Value = joints.header.knn.as_ref().unwrap().read().unwrap();
        assert!(field.get("input").is_none(), "{field}");
    }

    /// The shipped k-NN file with its header's decoding made hostile, framed as a file would carry it:
    /// refused on load (its payload and checksum untouched, so only the header can be why).
    #[test]
    fn a_shipped_knn_file_with_a_hostile_decoding_is_refused() {
        use crate::labeller::decode::Decoding;
        let bytes = crate::method::ModelStore::default()
            .shipped_bytes("knn-exercises.model")
            .expect("the shipped k-NN model")
            .to_vec();
        let bytes = &bytes[..];
        let (mut header, payload) = read_header(bytes, "knn-exercises.model").unwrap();
        header.decoding = Some(Decoding { min_duration_s: 1e300, switch_cost: 0.0 });
        let hostile = frame(&header, payload).unwrap();
        let e = Model::from_bytes(&hostile, "knn-hostile.model", &[&super::super::method::KNN]).err().expect("refused");
        assert!(e.contains("knn-hostile.model") && e.contains("min_duration_s = 1e300"), "{e}");
        // and `replace_header`, which writes a measured field into a kept model, refuses it too
        let e =
            Model::replace_header(bytes, "knn-exercises.model", &header, &[&super::super::method::KNN]).unwrap_err();
        assert!(e.contains("min_duration_s"), "{e}");
    }
}
