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
//!
//! The framing, the header and its checks are the same for every labeller; what one labeller adds is its own: its
//! header fields (DT-FCN's `network`, the k-NN's `knn`, the trainer's `options`), kept here as the JSON text it
//! writes ([`Json`]), and its payload, read by its method's [`Kind`] into its [`Labeller`].

use std::any::Any;

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use serde_json::value::RawValue;
use sha2::{Digest, Sha256};

use super::fit::{TravelProfile, Windows};
use super::input::{Standardise, NETWORK_FPS};
use super::method::Kind;
use super::probabilities::Probabilities;
use crate::method::supervised::MAX_MODEL_NAME;
use crate::method::{MethodError, Progress};
use crate::motion::Motion;

/// The first bytes of every model file.
pub const MAGIC: &[u8] = b"mocapseg-model\n";
/// The format this build writes and reads.
pub const FORMAT: u8 = 1;
/// Largest header accepted (the header is JSON of names and a few hundred numbers).
const MAX_HEADER: usize = 1 << 20;
/// Largest payload accepted.
const MAX_PAYLOAD: u64 = 256 << 20;

/// A field of the header that one kind of labeller writes and reads (DT-FCN's network shape, the k-NN's window and
/// vote, the trainer's options): kept as the JSON text it was read or written as, so that the file's bytes are what
/// that labeller wrote; the labeller reads it into its own type ([`Json::read`]).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(transparent)]
pub struct Json(Box<RawValue>);

impl Json {
    /// `value` as a header field.
    pub fn of<T: Serialize>(value: &T) -> Result<Json, String> {
        serde_json::value::to_raw_value(value).map(Json).map_err(|e| format!("writing the header: {e}"))
    }

    /// The field read as `T`.
    pub fn read<T: DeserializeOwned>(&self) -> Result<T, String> {
        serde_json::from_str(self.0.get()).map_err(|e| e.to_string())
    }

    /// The field as `T` written again: how a labeller keeps its fields in the one form it writes.
    pub fn normalised<T: Serialize + DeserializeOwned>(&self) -> Result<(T, Json), String> {
        let value: T = self.read()?;
        let json = Json::of(&value)?;
        Ok((value, json))
    }
}

impl PartialEq for Json {
    fn eq(&self, other: &Json) -> bool {
        self.0.get() == other.0.get()
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
    /// The training's options, as its labeller writes them ([`Kind::read`] reads them).
    pub options: Json,
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
    /// The labeller's kind: the name of its method ([`Kind::name`]).
    pub kind: String,
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
    pub decoding: Option<super::decode::Decoding>,
    /// The network's shape (DT-FCN's field, as it writes it).
    #[serde(default)]
    pub network: Option<Json>,
    /// The input's standardisation (DT-FCN's: [`super::input::Standardise`]).
    #[serde(default)]
    pub standardise: Option<Standardise>,
    /// The k-NN's window and vote (the k-NN's field, as it writes it).
    #[serde(default)]
    pub knn: Option<Json>,
    /// How fast its training takes travelled ([`super::fit`]; none in models made before it was measured).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub travel: Option<TravelProfile>,
    /// The open-set unknown ([`super::openset`]): a labelled frame whose window lies farther than this from its
    /// class's training windows is `unknown` unless a run asks for another; chosen on folds of its training takes
    /// that leave a class out (none: not chosen, or never calling unknown paid best there).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub open_set: Option<super::openset::OpenSetUnknown>,
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
    pub labeller: Box<dyn Labeller>,
}

/// The labeller inside a model file, as each method gives it: what it makes of a take, its payload's bytes, the
/// memory its work holds, and the training windows a take's fit is measured against when it has them.
pub trait Labeller: Send + Sync {
    /// The class probabilities of every working frame of `motion` (`header` is the model's), the file position of
    /// each working frame and their rate.
    fn label(
        &self,
        header: &ModelHeader,
        motion: &Motion,
        progress: &mut dyn Progress,
    ) -> Result<(Probabilities, Vec<f64>, f64), MethodError>;
    /// The payload's bytes, and the length of each of its parts when it holds several (an ensemble's networks;
    /// empty: one part, the whole payload).
    fn payload(&self) -> Result<(Vec<u8>, Vec<u64>), String>;
    /// Multiply-adds its labelling does per working frame, at most, for `classes` classes (as the model's file sets
    /// them: [`crate::method::Work::ops_per_frame`]).
    fn ops_per_frame(&self, classes: usize) -> f64;
    /// How many sets of probabilities a labelling holds before it averages them (an ensemble's networks).
    fn members(&self) -> usize {
        1
    }
    /// Bytes its labelling holds whatever the take's length (one block of a network's inference).
    fn fixed_bytes(&self) -> usize {
        0
    }
    /// The training windows a take's fit is measured against ([`super::fit`]), when the payload holds them.
    fn windows(&self) -> Option<&dyn Windows> {
        None
    }
    /// The labeller as its own type, for its method.
    fn as_any(&self) -> &dyn Any;
}

impl std::fmt::Debug for Model {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Model({} {}, {} classes)", self.header.kind, self.header.name, self.header.classes.len())
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
        let (payload, member_bytes) = self.labeller.payload()?;
        let mut header = self.header.clone();
        header.member_bytes = if member_bytes.len() < 2 { Vec::new() } else { member_bytes };
        header.payload_sha256 = sha256_hex(&payload);
        frame(&header, &payload)
    }

    /// The model file `bytes` with its header replaced by `header`, the payload kept byte for byte
    /// (for a header field measured after the model was made: the weights, their hash and the
    /// provenance stay as they were). Refuses a header of another kind, classes or payload.
    pub fn replace_header(
        bytes: &[u8],
        source: &str,
        header: &ModelHeader,
        kinds: &[&dyn Kind],
    ) -> Result<Vec<u8>, String> {
        let (old, payload) = read_header(bytes, source)?;
        if (&old.kind, &old.classes, &old.payload_sha256) != (&header.kind, &header.classes, &header.payload_sha256) {
            return Err(format!("{source}: the new header is of another kind, classes or payload"));
        }
        check_header(header, kind_of(header, kinds)?).map_err(|e| format!("{source}: {e}"))?;
        frame(header, payload)
    }

    /// Reads a model file of any of `kinds` (the labellers this program knows); `source` names it in messages.
    pub fn from_bytes(bytes: &[u8], source: &str, kinds: &[&dyn Kind]) -> Result<Model, String> {
        let (mut header, payload) = read_header(bytes, source)?;
        let kind = kind_of(&header, kinds).map_err(|e| format!("{source}: the header is not a model header: {e}"))?;
        check_header(&header, kind).map_err(|e| format!("{source}: {e}"))?;
        let labeller = kind.read(&mut header, payload).map_err(|e| format!("{source}: {e}"))?;
        Ok(Model { header, labeller })
    }
}

/// The kind among `kinds` whose model `header` describes.
fn kind_of<'a>(header: &ModelHeader, kinds: &[&'a dyn Kind]) -> Result<&'a dyn Kind, String> {
    kinds.iter().copied().find(|k| k.name() == header.kind).ok_or_else(|| {
        let known: Vec<String> = kinds.iter().map(|k| format!("`{}`", k.name())).collect();
        format!("unknown variant `{}`, expected {}", header.kind, known.join(" or "))
    })
}

/// A model file: the magic, the format, the header as JSON and the payload, each length-prefixed
/// (what [`read_header`] reads back).
pub fn frame(header: &ModelHeader, payload: &[u8]) -> Result<Vec<u8>, String> {
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
pub fn read_header<'a>(bytes: &'a [u8], source: &str) -> Result<(ModelHeader, &'a [u8]), String> {
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

/// What a header must say for this build to use the model.
pub fn check_header(h: &ModelHeader, kind: &dyn Kind) -> Result<(), String> {
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
    let ours = kind.header_joints(h);
    if h.joints != ours {
        return Err(format!(
            "trained on the image rows [{}], but this mocapseg's {} reads [{}]: train the model again with this version",
            h.joints.join(", "),
            h.kind,
            ours.join(", ")
        ));
    }
    if (h.fps - NETWORK_FPS).abs() > 1e-9 {
        return Err(format!("input at {} Hz, but this mocapseg's motion image is at {NETWORK_FPS} Hz", h.fps));
    }
    if !(0.0..=1.0).contains(&h.unknown_threshold) {
        return Err(format!("unknown threshold {}: expected 0 to 1", h.unknown_threshold));
    }
    if let Some(o) = &h.open_set {
        o.check()?;
    }
    kind.check_header(h)
}

#[cfg(test)]
mod tests {
    use super::*;

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
            options: Json::of(&serde_json::json!({})).unwrap(),
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

    /// A header field a labeller writes keeps the text it was written as.
    #[test]
    fn a_labellers_field_keeps_its_text() {
        let field = Json::of(&serde_json::json!({"b": 1, "a": [1.5, null]})).unwrap();
        let back: Json = serde_json::from_str(&serde_json::to_string(&field).unwrap()).unwrap();
        assert_eq!(serde_json::to_string(&back).unwrap(), r#"{"a":[1.5,null],"b":1}"#);
        assert_eq!(back, field);
        let (value, again): (serde_json::Value, Json) = back.normalised().unwrap();
        assert_eq!((value["b"].as_i64(), again), (Some(1), field));
    }
}
