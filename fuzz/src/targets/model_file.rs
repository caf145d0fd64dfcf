//! Model files: the DT-FCN / k-NN labelling model (`labeller::model::Model::from_bytes`, what
//! `segment --model FILE` and the page's model inputs read) and the LMA classifier family
//! (`lma::classifier::EffortModel::from_json`, `--lma-model FILE`). The first byte picks:
//!
//! * `0`: the rest is a labelling model file, as given;
//! * `1`: the rest is an LMA family (JSON text);
//! * `2`: the rest is `[header length u32 LE][header JSON][payload]`, assembled into a model
//!   file whose checksum is made to match, so the header's checks and the payload's readers (the
//!   k-NN's, burn's record) are reached past the checksum a random payload would fail.
//!
//! A model that loads must write back and load to the same header, and label a short take (or,
//! for an LMA family, segment it) without panicking.

use std::sync::OnceLock;

use mocapseg::labeller::input::{joint_names, Standardise, CHANNELS, NETWORK_FPS};
use mocapseg::labeller::method::Kind;
use mocapseg::labeller::model::{sha256_hex, Json, Model, ModelHeader, Provenance, FORMAT, MAGIC};
use mocapseg::method::{NoProgress, RunOptions};
use mocapseg::methods::dtfcn::model::Networks;
use mocapseg::methods::dtfcn::network::DtFcnConfig;
use mocapseg::methods::dtfcn::training::TrainOptions;
use mocapseg::methods::knn::{Knn, KnnParams, Labelled};
use mocapseg::methods::lma::classifier::EffortModel;
use mocapseg::methods::LABELLERS as KINDS;
use mocapseg::motion::Motion;

/// 3 s of a walk, the take every loaded model labels.
fn take() -> &'static Motion {
    static TAKE: OnceLock<Motion> = OnceLock::new();
    TAKE.get_or_init(|| {
        Motion::from_bvh("12_01.bvh", &crate::small_take("12_01.bvh", 360)).expect("the fixture's motion")
    })
}

fn header(kind: &dyn Kind, classes: usize) -> ModelHeader {
    let names: Vec<String> = (0..classes).map(|i| format!("class{i}")).collect();
    ModelHeader {
        kind: kind.name().into(),
        name: "tiny".into(),
        colours: (0..classes).map(|i| format!("#{:02x}8040", i * 40)).collect(),
        classes: names,
        joints: joint_names(),
        fps: NETWORK_FPS,
        unknown_threshold: 0.5,
        decoding: None,
        network: None,
        standardise: None,
        knn: None,
        travel: None,
        open_set: Some(mocapseg::labeller::openset::OpenSetUnknown { ratio: 2.0, folds: 1, accuracy: 0.8, never: 0.7 }),
        provenance: Provenance {
            command: "fuzz seed".into(),
            data_hash: String::new(),
            takes: vec!["12_01.bvh".into()],
            frames: 0,
            options: Json::of(&TrainOptions::default()).expect("the options serialise"),
            epochs_run: 0,
            best_epoch: 0,
            take_sha256: vec![],
            members: vec![],
        },
        member_bytes: vec![],
        payload_sha256: String::new(),
        written_by: "mocapseg-fuzz".into(),
    }
}

/// `header` and `payload` as a model file, the checksum made to match.
fn framed(mut header: ModelHeader, payload: &[u8]) -> Vec<u8> {
    header.payload_sha256 = sha256_hex(payload);
    let json = serde_json::to_vec(&header).expect("a header serialises");
    let mut out = MAGIC.to_vec();
    out.push(FORMAT);
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(&json);
    out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    out.extend_from_slice(payload);
    out
}

/// A mode-2 input: header JSON and payload, unframed.
fn split(header: &ModelHeader, payload: &[u8]) -> Vec<u8> {
    let json = serde_json::to_vec(header).expect("a header serialises");
    let mut out = vec![2u8];
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(&json);
    out.extend_from_slice(payload);
    out
}

/// Tiny models made with the crate's API (the shipped ones are 0.2–1.5 MB, slow to mutate):
/// a DT-FCN of two small layers and a k-NN fitted on 3 s of a walk, each as a file (mode 0)
/// and split (mode 2); and the shipped LMA family cut to its unshifted classifiers (mode 1).
pub fn seeds() -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    let device = mocapseg::methods::dtfcn::device();
    device.seed(7);
    let config = DtFcnConfig {
        channels: CHANNELS,
        classes: 3,
        width: 3,
        filters: vec![4, 8],
        padding: Default::default(),
        image_rows: None,
    };
    let net = config.init(&device);
    let other = config.init(&device);
    let mut h = header(&mocapseg::methods::dtfcn::method::DTFCN, 3);
    h.network = Some(Json::of(&config).expect("the shape serialises"));
    h.standardise = Some(Standardise { mean: vec![0.0; CHANNELS], spread: vec![1.0; CHANNELS], centre_on_take: false });
    let dtfcn =
        Model { header: h.clone(), labeller: Box::new(Networks { config: config.clone(), nets: vec![net.clone()] }) };
    let bytes = dtfcn.to_bytes().expect("the tiny DT-FCN writes");
    let payload = &bytes[bytes.len() - dtfcn_payload_len(&bytes)..];
    out.push(("dtfcn-tiny.model".into(), [&[0u8][..], &bytes].concat()));
    out.push(("dtfcn-tiny.split".into(), split(&h, payload)));
    // an ensemble of two: the header's byte count of each network cuts the payload
    let pair = Model { header: h, labeller: Box::new(Networks { config, nets: vec![net, other] }) };
    out.push(("dtfcn-pair.model".into(), [&[0u8][..], &pair.to_bytes().expect("the pair writes")].concat()));

    let motion = take();
    let labels: Vec<usize> = (0..motion.frames()).map(|f| (f * 3 / motion.frames()).min(2)).collect();
    let params = KnnParams { half_window: 6, stride: 3, ..KnnParams::default() };
    let knn = Knn::fit(&[Labelled { motion, labels: &labels }], params).expect("the tiny k-NN fits");
    let payload = knn.to_bytes();
    let mut h = header(&mocapseg::methods::knn::method::KNN, 3);
    h.knn = Some(Json::of(&params).expect("the parameters serialise"));
    out.push(("knn-tiny.model".into(), [&[0u8][..], &framed(h.clone(), &payload)].concat()));
    out.push(("knn-tiny.split".into(), split(&h, &payload)));

    let mut lma = (*mocapseg::methods::lma::shipped_model().expect("the shipped LMA family")).clone();
    let centre = lma.shift_index(0, 0);
    for f in &mut lma.factors {
        f.nets = vec![f.nets[centre].clone()];
    }
    lma.max_shift = 0;
    out.push(("lma-unshifted.json".into(), [&[1u8][..], lma.to_json().as_bytes()].concat()));
    out
}

/// The payload's length, from the 8 bytes before it (the file ends with the payload).
fn dtfcn_payload_len(bytes: &[u8]) -> usize {
    let at = MAGIC.len() + 1;
    let hlen = u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
    let p = at + 4 + hlen;
    u64::from_le_bytes(bytes[p..p + 8].try_into().unwrap()) as usize
}

fn labelling_model(bytes: &[u8]) {
    let model = match Model::from_bytes(bytes, "fuzz.model", &KINDS) {
        Ok(m) => m,
        Err(e) => {
            assert!(e.starts_with("fuzz.model: "), "{e}");
            return;
        }
    };
    let written = model.to_bytes().expect("a loaded model writes");
    let back = Model::from_bytes(&written, "again.model", &KINDS)
        .unwrap_or_else(|e| panic!("a written model does not load: {e}"));
    assert_eq!(model.header.classes, back.header.classes);
    assert_eq!(model.header.kind, back.header.kind);
    if let Ok(l) = mocapseg::labeller::method::label(&model, take(), &mut NoProgress) {
        assert_eq!(l.per_file_frame.len(), take().frames());
        assert!(l.per_file_frame.iter().all(|&(c, _)| c < model.header.classes.len()));
    }
}

/// One input of the target (what `fuzz_targets/model_file.rs` hands libFuzzer's bytes to).
pub fn run(data: &[u8]) {
    let Some((&mode, rest)) = data.split_first() else { return };
    match mode {
        0 => labelling_model(rest),
        1 => {
            let Ok(model) = EffortModel::from_json(&String::from_utf8_lossy(rest)) else { return };
            let back = EffortModel::from_json(&model.to_json()).unwrap_or_else(|e| panic!("its own JSON: {e}"));
            assert_eq!(model, back);
            let params = mocapseg::methods::lma::method::LmaParams::default();
            let _ = mocapseg::methods::lma::method::segment_with(
                &model,
                take(),
                &params,
                &RunOptions::default(),
                &mut NoProgress,
            );
        }
        2 => {
            let Some((len, rest)) = rest.split_first_chunk::<4>() else { return };
            let len = (u32::from_le_bytes(*len) as usize).min(rest.len());
            let (json, payload) = rest.split_at(len);
            let Ok(header) = serde_json::from_slice::<ModelHeader>(json) else { return };
            labelling_model(&framed(header, payload));
        }
        _ => {}
    }
}
