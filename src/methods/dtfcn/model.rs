//! DT-FCN's model files: the networks as a model file's payload (one burn record in burnpack form per network of an
//! ensemble, their lengths in the header's `member_bytes`) and the header fields only DT-FCN writes — the network's
//! shape (`network`) and the input's standardisation (`standardise`) — read and checked here; the framing, the
//! header and its common checks are [`crate::labeller::model`]'s.

use std::any::Any;

use burn::module::Module;
use burn::store::ModuleRecord;
use burn::tensor::Bytes;

use super::infer::{block_bytes, predict_members, BLOCK_FRAMES};
use super::network::{DtFcn, DtFcnConfig};
use super::training::TrainOptions;
use crate::labeller::input::{network_input, CHANNELS, NETWORK_FPS};
use crate::labeller::model::{Labeller, Model, ModelHeader};
use crate::labeller::probabilities::Probabilities;
use crate::method::{MethodError, Progress};
use crate::motion::Motion;

/// One network, or an ensemble of networks of the same shape whose probabilities are averaged
/// ([`super::infer::predict_members`]); never empty.
pub struct Networks {
    /// Their shape (the header's `network`).
    pub config: DtFcnConfig,
    pub nets: Vec<DtFcn>,
}

impl Labeller for Networks {
    fn label(
        &self,
        header: &ModelHeader,
        motion: &Motion,
        progress: &mut dyn Progress,
    ) -> Result<(Probabilities, Vec<f64>, f64), MethodError> {
        let input = network_input(motion).map_err(MethodError::Failed)?;
        let standardise = header
            .standardise
            .as_ref()
            .ok_or_else(|| MethodError::Failed("the model has no input standardisation".into()))?;
        progress.step("network", 0.05)?;
        let p = predict_members(&self.nets, standardise, &input, header.classes.len(), BLOCK_FRAMES, &mut |f| {
            progress.step("network", 0.05 + 0.9 * f).is_ok()
        })
        .ok_or(MethodError::Cancelled)?;
        Ok((p, input.source_frames, NETWORK_FPS))
    }

    fn payload(&self) -> Result<(Vec<u8>, Vec<u64>), String> {
        let mut payload = Vec::new();
        let mut member_bytes = Vec::new();
        for net in &self.nets {
            let bytes = net.clone().into_record().into_bytes().map_err(|e| format!("writing the weights: {e}"))?;
            member_bytes.push(bytes.len() as u64);
            payload.extend_from_slice(&bytes);
        }
        Ok((payload, member_bytes))
    }

    fn ops_per_frame(&self, _classes: usize) -> f64 {
        // every weight once per output frame (a convolution's multiply-adds), each block's frames computed with the
        // receptive field's context on either side, for every network of the ensemble; the image resized besides
        let context = self.nets.first().map_or(0, super::infer::receptive_half);
        let blocks = (BLOCK_FRAMES + 2 * context) as f64 / BLOCK_FRAMES as f64;
        let resize = (self.config.first_layer_inputs() * 2) as f64;
        self.nets.len() as f64 * (self.config.parameter_count() as f64 * blocks + resize)
    }

    fn members(&self) -> usize {
        self.nets.len()
    }

    fn fixed_bytes(&self) -> usize {
        self.nets.first().map_or(0, block_bytes)
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}

/// The networks of `model`, when it holds them.
pub fn networks_of(model: &Model) -> Option<&Networks> {
    model.labeller.as_any().downcast_ref::<Networks>()
}

/// What DT-FCN's fields of a header must say: a network of the header's classes reading the motion image, and the
/// input's standardisation.
pub fn check_header(h: &ModelHeader) -> Result<(), String> {
    let n: DtFcnConfig = h.network.as_ref().ok_or("a DT-FCN model without its network shape")?.read()?;
    n.check()?;
    let k = h.classes.len();
    if n.classes != k {
        return Err(format!("the network has {} outputs but the header lists {k} classes", n.classes));
    }
    if n.channels != CHANNELS {
        return Err(format!("the network reads {} channels, expected {} (3 per joint)", n.channels, CHANNELS));
    }
    h.standardise.as_ref().ok_or("a DT-FCN model without its input standardisation")?.check()
}

/// The networks of a DT-FCN model file's payload, the header's network shape and the training's options put in the
/// one form DT-FCN writes them.
pub fn read(header: &mut ModelHeader, payload: &[u8]) -> Result<Box<dyn Labeller>, String> {
    let field = header.network.as_ref().ok_or("a DT-FCN model without its network shape")?;
    let (config, network) = field.normalised::<DtFcnConfig>()?;
    let (_, options) = header.provenance.options.normalised::<TrainOptions>()?;
    (header.network, header.provenance.options) = (Some(network), options);
    let parts = member_parts(payload, &header.member_bytes)?;
    let mut nets = Vec::with_capacity(parts.len());
    for (m, part) in parts.iter().enumerate() {
        let which = if parts.len() > 1 { format!(" (network {} of {})", m + 1, parts.len()) } else { String::new() };
        // the network is made (its weights allocated) before the payload is read into it:
        // a header that describes a larger network than its payload can hold (4 bytes per
        // f32 weight) is refused first — six layers of 2048 filters would be 700 MB
        let needed = (config.parameter_count() as u64).saturating_mul(4);
        if needed > part.len() as u64 {
            return Err(format!(
                "the header describes a network of {} parameters ({} bytes of weights), the file holds {} \
                     bytes{which}",
                config.parameter_count(),
                needed,
                part.len()
            ));
        }
        let record = ModuleRecord::from_bytes(Bytes::from_bytes_vec(part.to_vec()))
            .map_err(|e| format!("the weights{which} are not a burn record: {e}"))?;
        nets.push(
            config
                .init(&super::device())
                .try_load_record(record)
                .map_err(|e| format!("the weights{which} do not fit the network the header describes: {e}"))?,
        );
    }
    Ok(Box::new(Networks { config, nets }))
}

/// The payload of each network: `payload` cut at the header's `member_bytes` (the whole payload when
/// there are none), or what does not add up.
fn member_parts<'a>(payload: &'a [u8], member_bytes: &[u64]) -> Result<Vec<&'a [u8]>, String> {
    if member_bytes.is_empty() {
        return Ok(vec![payload]);
    }
    if member_bytes.len() > super::training::MAX_MEMBERS {
        return Err(format!("{} networks: at most {} are read", member_bytes.len(), super::training::MAX_MEMBERS));
    }
    let total = member_bytes.iter().fold(0u64, |a, &b| a.saturating_add(b));
    if total != payload.len() as u64 {
        return Err(format!(
            "the header's {} networks hold {total} bytes of weights, the file {}",
            member_bytes.len(),
            payload.len()
        ));
    }
    let mut at = 0usize;
    Ok(member_bytes
        .iter()
        .map(|&b| {
            let part = &payload[at..at + b as usize];
            at += b as usize;
            part
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::labeller::input::Standardise;
    use crate::labeller::model::{data_hash, frame, read_header, Json, Provenance, MAGIC};

    fn tiny() -> Model {
        let classes: Vec<String> = vec!["a".into(), "b".into(), "c".into()];
        let network = DtFcnConfig {
            channels: CHANNELS,
            classes: 3,
            width: 3,
            filters: vec![4, 8],
            ..DtFcnConfig::paper(CHANNELS, 3)
        };
        let device = crate::methods::dtfcn::device();
        device.seed(3);
        let net = network.init(&device);
        Model {
            header: ModelHeader {
                kind: "dtfcn".into(),
                name: "tiny".into(),
                colours: vec!["#ff0000".into(), "#00ff00".into(), "#0000ff".into()],
                classes,
                joints: crate::labeller::input::joint_names(),
                fps: NETWORK_FPS,
                unknown_threshold: 0.5,
                decoding: None,
                network: Some(Json::of(&network).unwrap()),
                standardise: Some(Standardise {
                    mean: vec![0.0; CHANNELS],
                    spread: vec![1.0; CHANNELS],
                    centre_on_take: false,
                }),
                knn: None,
                travel: None,
                open_set: None,
                provenance: Provenance {
                    command: "test".into(),
                    data_hash: data_hash(&[], b""),
                    takes: vec![],
                    frames: 0,
                    options: Json::of(&TrainOptions::default()).unwrap(),
                    epochs_run: 0,
                    best_epoch: 0,
                    take_sha256: vec![],
                    members: vec![],
                },
                member_bytes: vec![],
                payload_sha256: String::new(),
                written_by: "test".into(),
            },
            labeller: Box::new(Networks { config: network, nets: vec![net] }),
        }
    }

    #[test]
    fn a_model_reads_back_and_every_kind_of_damage_is_named() {
        let bytes = tiny().to_bytes().unwrap();
        let back = Model::from_bytes(&bytes, "m.model", &[&super::super::method::DTFCN]).unwrap();
        assert_eq!(back.header.classes, vec!["a", "b", "c"]);
        assert_eq!(back.to_bytes().unwrap(), bytes, "load → save is byte-identical");

        let err = |b: &[u8]| Model::from_bytes(b, "m.model", &[&super::super::method::DTFCN]).unwrap_err();
        assert!(err(b"{\"family\": 1}").contains("not a mocapseg model file"), "{}", err(b"{}"));
        assert!(err(&bytes[..bytes.len() - 10]).contains("truncated"), "{}", err(&bytes[..bytes.len() - 10]));
        assert!(err(&bytes[..30]).contains("truncated"));
        let mut other = bytes.clone();
        other[MAGIC.len()] = 9;
        assert!(err(&other).contains("format 9"), "{}", err(&other));
        let mut flipped = bytes.clone();
        let last = flipped.len() - 1;
        flipped[last] ^= 0xff;
        assert!(err(&flipped).contains("checksum"), "{}", err(&flipped));

        // a header that lies: another joint set, another class count
        let mut m = tiny();
        m.header.joints[3] = "Tail".into();
        let e = err(&m.to_bytes().unwrap());
        assert!(e.contains("image rows") && e.contains("Tail") && e.contains("train the model again"), "{e}");
        let mut m = tiny();
        m.header.classes.push("d".into());
        m.header.colours.push("#000000".into());
        let e = err(&m.to_bytes().unwrap());
        assert!(e.contains("3 outputs") && e.contains("4 classes"), "{e}");
        // weights of another shape than the header says
        let mut m = tiny();
        let mut n: DtFcnConfig = m.header.network.as_ref().unwrap().read().unwrap();
        n.filters = vec![4, 16];
        m.header.network = Some(Json::of(&n).unwrap());
        let e = err(&m.to_bytes().unwrap());
        assert!(e.contains("do not fit"), "{e}");
        // a header whose network is far larger than its payload: refused before the network is made
        let mut m = tiny();
        let mut n: DtFcnConfig = m.header.network.as_ref().unwrap().read().unwrap();
        (n.filters, n.width) = (vec![2048; 6], 7);
        m.header.network = Some(Json::of(&n).unwrap());
        let e = err(&m.to_bytes().unwrap());
        assert!(e.contains("parameters") && e.contains("bytes of weights"), "{e}");
    }

    /// A header field out of its range, as a file from anyone may carry it: refused on load with the
    /// field named, before anything is sized by it (issue 49: `min_duration_s = 1e300` panicked the
    /// decoder, 9e4 took 33 s on a 40 s take, 40,000 classes 7.9 s).
    #[test]
    fn hostile_headers_are_refused_naming_the_field() {
        use crate::labeller::decode::Decoding;
        let bytes = tiny().to_bytes().unwrap();
        // the header as a file carries it, framed around the untouched payload
        let refused = |edit: &dyn Fn(&mut ModelHeader), wanted: &[&str]| {
            let (mut header, payload) = read_header(&bytes, "tiny.model").unwrap();
            edit(&mut header);
            let e =
                Model::from_bytes(&frame(&header, payload).unwrap(), "hostile.model", &[&super::super::method::DTFCN])
                    .err()
                    .unwrap_or_else(|| panic!("a header meant to be refused for {wanted:?} loaded"));
            assert!(e.starts_with("hostile.model: "), "{e}");
            for w in wanted {
                assert!(e.contains(w), "`{w}` not in: {e}");
            }
        };
        let decoding = |d: f64, c: f64| {
            move |h: &mut ModelHeader| h.decoding = Some(Decoding { min_duration_s: d, switch_cost: c })
        };
        refused(&decoding(1e300, 0.0), &["min_duration_s = 1e300", "0 to 30"]);
        refused(&decoding(9e4, 0.0), &["min_duration_s = 90000"]);
        refused(&decoding(-1.0, 0.0), &["min_duration_s = -1"]);
        refused(&decoding(2.0, 1e6), &["switch_cost = 1e6", "0 to 1000"]);
        refused(&decoding(2.0, -5.0), &["switch_cost = -5"]);
        refused(
            &|h: &mut ModelHeader| {
                h.classes = (0..40_000).map(|i| format!("c{i}")).collect();
                h.colours = vec!["#000000".into(); 40_000];
            },
            &["40000 classes", "2 to 256"],
        );
        refused(&|h: &mut ModelHeader| h.classes[1] = "x".repeat(101), &["class name", "1 to 100 characters"]);
        refused(&|h: &mut ModelHeader| h.classes[1] = "a\u{7}b".into(), &["class name `a·b`", "control"]);
        refused(&|h: &mut ModelHeader| h.classes[1] = "  ".into(), &["class name", "not blank"]);
        refused(&|h: &mut ModelHeader| h.colours[0] = "red\"><script>".into(), &["class colour", "#rrggbb"]);
        refused(&|h: &mut ModelHeader| h.name = "n".repeat(65), &["model name", "at most 64"]);
        refused(
            &|h: &mut ModelHeader| h.travel = Some(crate::labeller::fit::TravelProfile { median: -1.0, limit: 3.0 }),
            &["travel median -1"],
        );
        refused(&|h: &mut ModelHeader| h.member_bytes = vec![1; 17], &["17 networks", "at most 16"]);
        refused(&|h: &mut ModelHeader| h.unknown_threshold = 2.0, &["unknown threshold 2"]);
        // what is in range still loads
        let mut m = tiny();
        m.header.decoding = Some(Decoding { min_duration_s: 30.0, switch_cost: 1000.0 });
        Model::from_bytes(&m.to_bytes().unwrap(), "edge.model", &[&super::super::method::DTFCN])
            .expect("the ranges' ends load");
    }
}
