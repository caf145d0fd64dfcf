//! Model files: one file holds everything a trained labeller needs and everything a reader needs
//! to trust it — the class names and colours, the joint set and frame rate of its input, the
//! input's standardisation, how it was trained (the command, a hash of the data, the options) and
//! the weights (a burn record in burnpack form for the network; the training frames for k-NN).
//!
//! Layout: the magic line `mocapseg-model\n`, a format byte, the header's length (u32 LE), the
//! header (JSON, [`ModelHeader`]), the payload's length (u64 LE) and the payload. The header
//! carries the payload's SHA-256, so a truncated or damaged file is refused before its weights
//! are read; every other refusal names what is wrong (another format, another version, another
//! joint set, a class count that does not match the weights).

use burn::module::Module;
use burn::store::ModuleRecord;
use burn::tensor::Bytes;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use super::network::{DtFcn, DtFcnConfig};
use super::training::TrainOptions;
use crate::labeller::input::{canonical_names, joint_names, Standardise, CHANNELS, NETWORK_FPS};
use crate::method::supervised::MAX_MODEL_NAME;
use crate::methods::knn::{Knn, KnnParams};

/// The first bytes of every model file.
pub const MAGIC: &[u8] = b"mocapseg-model\n";
/// The format this build writes and reads.
pub const FORMAT: u8 = 1;
/// Largest header accepted (the header is JSON of names and a few hundred numbers).
const MAX_HEADER: usize = 1 << 20;
/// Largest payload accepted.
const MAX_PAYLOAD: u64 = 256 << 20;

/// What kind of labeller a model file holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ModelKind {
    /// The DT-FCN network ([`super::network`]).
    Dtfcn,
    /// The k-nearest-neighbour labeller ([`crate::methods::knn`]).
    Knn,
}

impl ModelKind {
    pub fn name(self) -> &'static str {
        match self {
            ModelKind::Dtfcn => "dtfcn",
            ModelKind::Knn => "knn",
        }
    }
}

/// How a model was made, so that it can be made again.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Provenance {
    /// The command that trained it.
    pub command: String,
    /// SHA-256 over the training data (file names, motion and labels), see [`data_hash`].
    pub data_hash: String,
    /// The training takes' file names.
    pub takes: Vec<String>,
    /// The SHA-256 of each training take's file, in the order of `takes` (models trained since
    /// issue 27; empty in older files): a take on screen is matched to them by content, not only
    /// by name, when the page warns that it was in the model's training set.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub take_sha256: Vec<String>,
    /// Labelled working frames trained on: for a model trained on from an earlier one
    /// ([`Provenance::continued_from`]), every run's added up (the frames its weights learnt from,
    /// run by run; a take labelled again in a later run counts again).
    pub frames: usize,
    pub options: TrainOptions,
    /// Epochs run and the epoch whose weights were kept (the first network's, in an ensemble).
    pub epochs_run: usize,
    pub best_epoch: usize,
    /// An ensemble's networks, each with its seed, epochs run and kept epoch (empty: one network).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub members: Vec<MemberRun>,
}

/// How one network of an ensemble was trained.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MemberRun {
    pub seed: u64,
    pub epochs_run: usize,
    pub best_epoch: usize,
}

impl Provenance {
    /// This run's provenance made the history of a model trained on from `before` (the model
    /// `from`): its command says so, its epochs count on after the earlier ones, its frames add the
    /// earlier model's, and every take the earlier model was trained on that this run's lack is
    /// added (with its SHA-256 when either side records them; an unknown one left empty).
    pub fn continued_from(&mut self, from: &str, before: &Provenance) {
        self.command = format!("{} (continued from `{from}` after its {} epochs)", self.command, before.epochs_run);
        self.best_epoch += before.epochs_run;
        self.epochs_run += before.epochs_run;
        for (now, earlier) in self.members.iter_mut().zip(&before.members) {
            now.best_epoch += earlier.epochs_run;
            now.epochs_run += earlier.epochs_run;
        }
        self.frames += before.frames;
        let hashed = !self.take_sha256.is_empty() || !before.take_sha256.is_empty();
        if hashed {
            self.take_sha256.resize(self.takes.len(), String::new());
        }
        for (i, take) in before.takes.iter().enumerate() {
            if !self.takes.iter().any(|t| crate::labels::same_file(t, take)) {
                self.takes.push(take.clone());
                if hashed {
                    self.take_sha256.push(before.take_sha256.get(i).cloned().unwrap_or_default());
                }
            }
        }
    }
}

/// Everything about a model but its weights.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModelHeader {
    pub kind: ModelKind,
    /// Short name (`exercises`).
    pub name: String,
    pub classes: Vec<String>,
    /// CSS colour of each class (`#rrggbb`).
    pub colours: Vec<String>,
    /// The image rows the model reads, by canonical joint name.
    pub joints: Vec<String>,
    /// Working frame rate of its input.
    pub fps: f64,
    /// Frames below this confidence are labelled `unknown` unless a run asks for another threshold.
    pub unknown_threshold: f32,
    /// How its per-frame probabilities are decoded into labels when a run asks for the model's decoding
    /// ([`super::decode`]; chosen by validation when it was made; none: the raw per-frame labels).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub decoding: Option<crate::labeller::decode::Decoding>,
    /// The network's shape (DT-FCN).
    #[serde(default)]
    pub network: Option<DtFcnConfig>,
    /// The input's standardisation (DT-FCN).
    #[serde(default)]
    pub standardise: Option<Standardise>,
    /// The k-NN's window and vote (k-NN).
    #[serde(default)]
    pub knn: Option<KnnParams>,
    /// How fast its training takes travelled ([`super::fit`]; none in models made before it was measured).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub travel: Option<crate::labeller::fit::TravelProfile>,
    pub provenance: Provenance,
    /// An ensemble's payload: the byte length of each network's weights, in order (empty: one network, the
    /// whole payload).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub member_bytes: Vec<u64>,
    /// SHA-256 of the payload, hex.
    pub payload_sha256: String,
    /// The mocapseg version that wrote it.
    pub written_by: String,
}

/// A loaded model: its header and its labeller.
pub struct Model {
    pub header: ModelHeader,
    pub labeller: Labeller,
}

/// The labeller inside a model.
pub enum Labeller {
    /// One network, or an ensemble of networks of the same shape whose probabilities are averaged
    /// ([`super::infer::predict_members`]); never empty.
    Network(Vec<DtFcn>),
    Knn(Box<Knn>),
}

impl std::fmt::Debug for Model {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Model({} {}, {} classes)", self.header.kind.name(), self.header.name, self.header.classes.len())
    }
}

/// Hex SHA-256 of `bytes`.
pub fn sha256_hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes).iter().map(|b| format!("{b:02x}")).collect()
}

/// The SHA-256 of the file of each of `takes` (names as in a provenance), found by name among
/// `files` (file name, bytes); a take without its file gets an empty string, so the list stays in
/// the order of `takes`.
pub fn take_hashes(takes: &[String], files: &[(String, Vec<u8>)]) -> Vec<String> {
    takes
        .iter()
        .map(|t| {
            files
                .iter()
                .find(|(f, _)| crate::labels::same_file(f, t))
                .map_or_else(String::new, |(_, bytes)| sha256_hex(bytes))
        })
        .collect()
}

/// SHA-256 over training data given as `(file name, file bytes)` pairs (sorted by name first)
/// and the label file's bytes.
pub fn data_hash(files: &[(String, Vec<u8>)], labels: &[u8]) -> String {
    let mut sorted: Vec<&(String, Vec<u8>)> = files.iter().collect();
    sorted.sort_by(|a, b| a.0.cmp(&b.0));
    let mut h = Sha256::new();
    for (name, bytes) in sorted {
        h.update((name.len() as u64).to_le_bytes());
        h.update(name.as_bytes());
        h.update((bytes.len() as u64).to_le_bytes());
        h.update(bytes);
    }
    h.update(labels);
    h.finalize().iter().map(|b| format!("{b:02x}")).collect()
}

impl Model {
    /// The model's file bytes.
    pub fn to_bytes(&self) -> Result<Vec<u8>, String> {
        let mut member_bytes = Vec::new();
        let payload: Vec<u8> = match &self.labeller {
            Labeller::Network(nets) => {
                let mut payload = Vec::new();
                for net in nets {
                    let bytes =
                        net.clone().into_record().into_bytes().map_err(|e| format!("writing the weights: {e}"))?;
                    member_bytes.push(bytes.len() as u64);
                    payload.extend_from_slice(&bytes);
                }
                if nets.len() < 2 {
                    member_bytes.clear();
                }
                payload
            }
            Labeller::Knn(knn) => knn.to_bytes(),
        };
        let mut header = self.header.clone();
        header.member_bytes = member_bytes;
        header.payload_sha256 = sha256_hex(&payload);
        frame(&header, &payload)
    }

    /// The model file `bytes` with its header replaced by `header`, the payload kept byte for byte
    /// (for a header field measured after the model was made: the weights, their hash and the
    /// provenance stay as they were). Refuses a header of another kind, classes or payload.
    pub fn replace_header(bytes: &[u8], source: &str, header: &ModelHeader) -> Result<Vec<u8>, String> {
        let (old, payload) = read_header(bytes, source)?;
        if (old.kind, &old.classes, &old.payload_sha256) != (header.kind, &header.classes, &header.payload_sha256) {
            return Err(format!("{source}: the new header is of another kind, classes or payload"));
        }
        check_header(header).map_err(|e| format!("{source}: {e}"))?;
        frame(header, payload)
    }

    /// Reads a model file; `source` names it in messages.
    pub fn from_bytes(bytes: &[u8], source: &str) -> Result<Model, String> {
        let header = read_header(bytes, source)?;
        let (header, payload) = header;
        check_header(&header).map_err(|e| format!("{source}: {e}"))?;
        let labeller = match header.kind {
            ModelKind::Dtfcn => {
                let config = header
                    .network
                    .clone()
                    .ok_or_else(|| format!("{source}: a DT-FCN model without its network shape"))?;
                let parts = member_parts(payload, &header.member_bytes).map_err(|e| format!("{source}: {e}"))?;
                let mut nets = Vec::with_capacity(parts.len());
                for (m, part) in parts.iter().enumerate() {
                    let which = if parts.len() > 1 {
                        format!(" (network {} of {})", m + 1, parts.len())
                    } else {
                        String::new()
                    };
                    // the network is made (its weights allocated) before the payload is read into it:
                    // a header that describes a larger network than its payload can hold (4 bytes per
                    // f32 weight) is refused first — six layers of 2048 filters would be 700 MB
                    let needed = (config.parameter_count() as u64).saturating_mul(4);
                    if needed > part.len() as u64 {
                        return Err(format!(
                            "{source}: the header describes a network of {} parameters ({} bytes of weights), the \
                             file holds {} bytes{which}",
                            config.parameter_count(),
                            needed,
                            part.len()
                        ));
                    }
                    let record = ModuleRecord::from_bytes(Bytes::from_bytes_vec(part.to_vec()))
                        .map_err(|e| format!("{source}: the weights{which} are not a burn record: {e}"))?;
                    nets.push(config.init(&super::device()).try_load_record(record).map_err(|e| {
                        format!("{source}: the weights{which} do not fit the network the header describes: {e}")
                    })?);
                }
                Labeller::Network(nets)
            }
            ModelKind::Knn => {
                let params = header.knn.ok_or_else(|| format!("{source}: a k-NN model without its parameters"))?;
                Labeller::Knn(Box::new(
                    Knn::from_bytes(payload, params, header.classes.len()).map_err(|e| format!("{source}: {e}"))?,
                ))
            }
        };
        Ok(Model { header, labeller })
    }
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

/// A model file: the magic, the format, the header as JSON and the payload, each length-prefixed
/// (what [`read_header`] reads back).
fn frame(header: &ModelHeader, payload: &[u8]) -> Result<Vec<u8>, String> {
    let json = serde_json::to_vec(header).map_err(|e| format!("writing the header: {e}"))?;
    let mut out = Vec::with_capacity(MAGIC.len() + 13 + json.len() + payload.len());
    out.extend_from_slice(MAGIC);
    out.push(FORMAT);
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(&json);
    out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    out.extend_from_slice(payload);
    Ok(out)
}

/// The header and payload of a model file, or what is wrong with its framing.
fn read_header<'a>(bytes: &'a [u8], source: &str) -> Result<(ModelHeader, &'a [u8]), String> {
    if !bytes.starts_with(MAGIC) {
        let shown: String = String::from_utf8_lossy(&bytes[..bytes.len().min(16)])
            .chars()
            .map(|c| if c.is_control() { '·' } else { c })
            .collect();
        let hint = if bytes.starts_with(b"{") {
            " (a JSON file: an LMA family or a segmentation, not a labelling model?)"
        } else {
            ""
        };
        return Err(format!(
            "{source}: not a mocapseg model file: it starts with `{shown}`, expected `mocapseg-model`{hint}"
        ));
    }
    let mut at = MAGIC.len();
    let format = *bytes.get(at).ok_or_else(|| format!("{source}: truncated after the magic line"))?;
    if format != FORMAT {
        return Err(format!(
            "{source}: model file format {format}; this mocapseg ({}) reads format {FORMAT} — retrain the model or use the mocapseg that wrote it",
            env!("CARGO_PKG_VERSION")
        ));
    }
    at += 1;
    let len = u32::from_le_bytes(
        bytes
            .get(at..at + 4)
            .ok_or_else(|| format!("{source}: truncated before the header length"))?
            .try_into()
            .unwrap_or([0; 4]),
    ) as usize;
    at += 4;
    if len > MAX_HEADER {
        return Err(format!("{source}: header of {len} bytes (at most {MAX_HEADER}): not a model file or damaged"));
    }
    let json = bytes
        .get(at..at + len)
        .ok_or_else(|| format!("{source}: truncated: the header needs {len} bytes, {} are left", bytes.len() - at))?;
    let header: ModelHeader =
        serde_json::from_slice(json).map_err(|e| format!("{source}: the header is not a model header: {e}"))?;
    at += len;
    let plen = u64::from_le_bytes(
        bytes
            .get(at..at + 8)
            .ok_or_else(|| format!("{source}: truncated before the weights"))?
            .try_into()
            .unwrap_or([0; 8]),
    );
    at += 8;
    if plen > MAX_PAYLOAD {
        return Err(format!("{source}: weights of {plen} bytes (at most {MAX_PAYLOAD}): damaged file"));
    }
    let left = bytes.len() - at;
    if (left as u64) < plen {
        return Err(format!("{source}: truncated: the weights need {plen} bytes, {left} are left"));
    }
    if left as u64 > plen {
        return Err(format!("{source}: {} bytes after the weights: not one model file", left as u64 - plen));
    }
    let payload = &bytes[at..];
    let sum = sha256_hex(payload);
    if sum != header.payload_sha256 {
        return Err(format!("{source}: the weights do not match their checksum: the file is damaged"));
    }
    Ok((header, payload))
}

/// The most classes a labelling model may list: its votes and probabilities take `frames × classes`
/// numbers, its decoding `frames × classes` states.
pub const MAX_CLASSES: usize = 256;
/// The longest class name, in characters.
pub const MAX_NAME_CHARS: usize = 100;
/// The most networks an ensemble's payload may hold.
pub const MAX_MEMBERS: usize = 16;

/// True for a CSS colour written `#rrggbb`.
fn is_hex_colour(c: &str) -> bool {
    c.len() == 7 && c.starts_with('#') && c[1..].chars().all(|ch| ch.is_ascii_hexdigit())
}

/// The rows a model of `kind` reads: the network's image rows, or the k-NN's canonical joints.
pub fn joint_names_of(kind: ModelKind) -> Vec<String> {
    match kind {
        ModelKind::Dtfcn => joint_names(),
        ModelKind::Knn => canonical_names(),
    }
}

/// What a header must say for this build to use the model.
pub fn check_header(h: &ModelHeader) -> Result<(), String> {
    if h.name.chars().count() > MAX_MODEL_NAME || h.name.chars().any(char::is_control) {
        return Err(format!("model name: expected at most {MAX_MODEL_NAME} characters and no control characters"));
    }
    let k = h.classes.len();
    if !(2..=MAX_CLASSES).contains(&k) {
        return Err(format!("{k} classes: a labelling model needs 2 to {MAX_CLASSES}"));
    }
    if h.colours.len() != k {
        return Err(format!("{k} classes but {} colours", h.colours.len()));
    }
    if let Some(c) = h
        .classes
        .iter()
        .find(|c| c.trim().is_empty() || c.chars().count() > MAX_NAME_CHARS || c.chars().any(char::is_control))
    {
        let shown: String = c.chars().take(40).map(|ch| if ch.is_control() { '·' } else { ch }).collect();
        return Err(format!(
            "class name `{shown}`: expected 1 to {MAX_NAME_CHARS} characters, not blank, no control characters"
        ));
    }
    if let Some(c) = h.colours.iter().find(|c| !is_hex_colour(c)) {
        let shown: String = c.chars().take(20).map(|ch| if ch.is_control() { '·' } else { ch }).collect();
        return Err(format!("class colour `{shown}`: expected #rrggbb"));
    }
    if let Some(dup) = h.classes.iter().enumerate().find(|(i, c)| h.classes[..*i].contains(c)) {
        return Err(format!("class `{}` is listed twice", dup.1));
    }
    if let Some(d) = &h.decoding {
        d.check()?;
    }
    if let Some(t) = &h.travel {
        if !(t.median.is_finite() && t.limit.is_finite() && t.median >= 0.0 && t.limit > 0.0 && t.limit <= 1e4) {
            return Err(format!(
                "travel median {} and limit {} (inches per second): expected finite, 0 ≤ median, 0 < limit ≤ 10000",
                t.median, t.limit
            ));
        }
    }
    if h.member_bytes.len() > MAX_MEMBERS {
        return Err(format!("{} networks: an ensemble holds at most {MAX_MEMBERS}", h.member_bytes.len()));
    }
    let ours = joint_names_of(h.kind);
    if h.joints != ours {
        return Err(format!(
            "trained on the image rows [{}], but this mocapseg's {} reads [{}]: train the model again with this version",
            h.joints.join(", "),
            h.kind.name(),
            ours.join(", ")
        ));
    }
    if (h.fps - NETWORK_FPS).abs() > 1e-9 {
        return Err(format!("input at {} Hz, but this mocapseg's motion image is at {NETWORK_FPS} Hz", h.fps));
    }
    if !(0.0..=1.0).contains(&h.unknown_threshold) {
        return Err(format!("unknown threshold {}: expected 0 to 1", h.unknown_threshold));
    }
    match h.kind {
        ModelKind::Dtfcn => {
            let n = h.network.as_ref().ok_or("a DT-FCN model without its network shape")?;
            n.check()?;
            if n.classes != k {
                return Err(format!("the network has {} outputs but the header lists {k} classes", n.classes));
            }
            if n.channels != CHANNELS {
                return Err(format!("the network reads {} channels, expected {} (3 per joint)", n.channels, CHANNELS));
            }
            h.standardise.as_ref().ok_or("a DT-FCN model without its input standardisation")?.check()?;
        }
        ModelKind::Knn => {
            h.knn.as_ref().ok_or("a k-NN model without its parameters")?.check()?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

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
                kind: ModelKind::Dtfcn,
                name: "tiny".into(),
                colours: vec!["#ff0000".into(), "#00ff00".into(), "#0000ff".into()],
                classes,
                joints: joint_names_of(ModelKind::Dtfcn),
                fps: NETWORK_FPS,
                unknown_threshold: 0.5,
                decoding: None,
                network: Some(network),
                standardise: Some(Standardise {
                    mean: vec![0.0; CHANNELS],
                    spread: vec![1.0; CHANNELS],
                    centre_on_take: false,
                }),
                knn: None,
                travel: None,
                provenance: Provenance {
                    command: "test".into(),
                    data_hash: data_hash(&[], b""),
                    takes: vec![],
                    frames: 0,
                    options: TrainOptions::default(),
                    epochs_run: 0,
                    best_epoch: 0,
                    take_sha256: vec![],
                    members: vec![],
                },
                member_bytes: vec![],
                payload_sha256: String::new(),
                written_by: "test".into(),
            },
            labeller: Labeller::Network(vec![net]),
        }
    }

    /// A model trained on from an earlier one records the earlier one's frames, epochs and takes
    /// (a take both trained on once, by file name), their hashes kept in the takes' order.
    #[test]
    fn a_continued_provenance_carries_the_earlier_models_frames_and_takes() {
        let run = |takes: &[&str], hashes: &[&str], frames, epochs| Provenance {
            command: "mocapseg dtfcn train".into(),
            data_hash: String::new(),
            takes: takes.iter().map(|t| t.to_string()).collect(),
            take_sha256: hashes.iter().map(|h| h.to_string()).collect(),
            frames,
            options: TrainOptions::default(),
            epochs_run: epochs,
            best_epoch: epochs - 1,
            members: vec![],
        };
        let before = run(&["13_29.bvh", "35_01.bvh"], &["aa", "bb"], 900, 3);
        let mut now = run(&["35_01.BVH", "86_01.bvh"], &["cc", "dd"], 400, 2);
        now.continued_from("mine", &before);
        assert_eq!(now.frames, 1300, "this run's frames and the earlier model's");
        assert_eq!((now.epochs_run, now.best_epoch), (5, 4));
        assert_eq!(now.takes, ["35_01.BVH", "86_01.bvh", "13_29.bvh"]);
        assert_eq!(now.take_sha256, ["cc", "dd", "aa"], "each hash stays with its take");
        assert!(now.command.ends_with("(continued from `mine` after its 3 epochs)"), "{}", now.command);
        // an earlier model without hashes: the takes it adds get an empty (unknown) one
        let mut hashed = run(&["86_01.bvh"], &["dd"], 10, 1);
        hashed.continued_from("old", &run(&["13_29.bvh"], &[], 5, 1));
        assert_eq!((hashed.takes.len(), hashed.take_sha256), (2, vec!["dd".to_string(), String::new()]));
        // neither side hashed: none recorded
        let mut plain = run(&["86_01.bvh"], &[], 10, 1);
        plain.continued_from("old", &run(&["13_29.bvh"], &[], 5, 1));
        assert!(plain.take_sha256.is_empty());
        assert_eq!(plain.frames, 15);
    }

    #[test]
    fn a_model_reads_back_and_every_kind_of_damage_is_named() {
        let bytes = tiny().to_bytes().unwrap();
        let back = Model::from_bytes(&bytes, "m.model").unwrap();
        assert_eq!(back.header.classes, vec!["a", "b", "c"]);
        assert_eq!(back.to_bytes().unwrap(), bytes, "load → save is byte-identical");

        let err = |b: &[u8]| Model::from_bytes(b, "m.model").unwrap_err();
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
        if let Some(n) = m.header.network.as_mut() {
            n.filters = vec![4, 16];
        }
        let e = err(&m.to_bytes().unwrap());
        assert!(e.contains("do not fit"), "{e}");
        // a header whose network is far larger than its payload: refused before the network is made
        let mut m = tiny();
        if let Some(n) = m.header.network.as_mut() {
            (n.filters, n.width) = (vec![2048; 6], 7);
        }
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
            let e = Model::from_bytes(&frame(&header, payload).unwrap(), "hostile.model")
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
        Model::from_bytes(&m.to_bytes().unwrap(), "edge.model").expect("the ranges' ends load");
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
        let e = Model::from_bytes(&hostile, "knn-hostile.model").err().expect("refused");
        assert!(e.contains("knn-hostile.model") && e.contains("min_duration_s = 1e300"), "{e}");
        // and `replace_header`, which writes a measured field into a kept model, refuses it too
        let e = Model::replace_header(bytes, "knn-exercises.model", &header).unwrap_err();
        assert!(e.contains("min_duration_s"), "{e}");
    }
}
