//! The project file (issue 48, "can be handed on"): the workspace as one JSON file a colleague opens on their machine —
//! the record kept in this browser ([`Record`]: the take on screen, its ground truth, each row's form, the side
//! panel's tab, the library with its method and cluster names), the takes named with their SHA-256 and size (their
//! files are not in it: they are opened with it, and found by what they hold, whatever they are called), my labels of
//! those takes as this browser keeps them, and the user's models the rows have chosen (their files, base64).
//! Everything read is checked, and a file that is not a project says what is wrong with it.

use crate::app::session::record::Record;
use base64::Engine;
use serde_json::{json, Value};
use sha2::{Digest, Sha256};

/// The `format` field of a project file.
pub const FORMAT: &str = "mocapseg-project";
/// The project files this code writes and reads.
pub const VERSION: u64 = 1;
/// The largest project file read (its models' files make most of it).
pub const MAX_PROJECT_BYTES: f64 = 64.0 * 1024.0 * 1024.0;
/// The prefix of the keys my labels are kept under in this browser (those a project carries).
pub const LABELS_PREFIX: &str = "mocapseg.my-labels.";

/// A file's SHA-256, in lower-case hex.
pub fn sha256_hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes).iter().map(|b| format!("{b:02x}")).collect()
}

/// A take's file as the project names it (and, for an AMC motion, its ASF skeleton's).
#[derive(Debug, Clone, PartialEq)]
pub struct TakeRef {
    pub name: String,
    pub sha256: String,
    pub bytes: u64,
    pub skeleton: Option<Box<TakeRef>>,
}

/// My labels of a take, as this browser keeps them (its key names the take, its text is the stored JSON).
#[derive(Debug, Clone, PartialEq)]
pub struct KeptLabels {
    pub key: String,
    pub json: String,
}

/// A model the rows chose, with its file.
#[derive(Debug, Clone, PartialEq)]
pub struct ProjectModel {
    pub method: String,
    pub name: String,
    pub file: String,
    pub data: Vec<u8>,
}

/// A project.
#[derive(Debug, Clone, PartialEq)]
pub struct Project {
    /// The workspace (the library's takes' `kept` flags mean nothing here).
    pub record: Record,
    /// The take on screen (`None`: the sample, or none).
    pub take: Option<TakeRef>,
    /// The library's takes, in the record's order.
    pub library: Vec<TakeRef>,
    pub labels: Vec<KeptLabels>,
    pub models: Vec<ProjectModel>,
}

/// Where each take of a project is among the files opened with it.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Found {
    /// The take on screen's file and skeleton (indices into the files).
    pub take: Option<(usize, Option<usize>)>,
    /// Each library take's, in the project's order.
    pub library: Vec<Option<(usize, Option<usize>)>>,
    /// The takes not among the files ("name (SHA-256 abcdef12…)"), and those whose file of the same name holds
    /// something else.
    pub missing: Vec<String>,
    pub differ: Vec<String>,
}

fn take_json(t: &TakeRef) -> Value {
    json!({ "name": t.name, "sha256": t.sha256, "bytes": t.bytes, "skeleton": t.skeleton.as_deref().map(take_json) })
}

fn take_of(v: &Value, what: &str) -> Result<TakeRef, String> {
    let text =
        |k: &str| v.get(k).and_then(Value::as_str).map(str::to_string).ok_or_else(|| format!("{what} has no \"{k}\""));
    let sha256 = text("sha256")?;
    if sha256.len() != 64 || !sha256.bytes().all(|b| b.is_ascii_hexdigit()) {
        return Err(format!("{what}'s \"sha256\" is not a SHA-256 (64 hex digits): {sha256:.80}"));
    }
    let bytes = v.get("bytes").and_then(Value::as_u64).ok_or_else(|| format!("{what} has no \"bytes\" (a size)"))?;
    let skeleton = match v.get("skeleton").filter(|s| !s.is_null()) {
        None => None,
        Some(s) => Some(Box::new(take_of(s, &format!("{what}'s skeleton"))?)),
    };
    Ok(TakeRef { name: text("name")?, sha256: sha256.to_ascii_lowercase(), bytes, skeleton })
}

impl Project {
    /// The project file's text.
    pub fn to_json(&self) -> String {
        let record: Value = serde_json::from_str(&self.record.to_json()).unwrap_or(Value::Null);
        let b64 = base64::engine::general_purpose::STANDARD;
        json!({
            "format": FORMAT,
            "version": VERSION,
            "workspace": record,
            "take": self.take.as_ref().map(take_json),
            "library": self.library.iter().map(take_json).collect::<Vec<_>>(),
            "labels": self.labels.iter().map(|l| json!({ "key": l.key, "json": l.json })).collect::<Vec<_>>(),
            "models": self.models.iter().map(|m| json!({
                "method": m.method, "name": m.name, "file": m.file, "data": b64.encode(&m.data),
            })).collect::<Vec<_>>(),
        })
        .to_string()
    }

    /// Reads a project file (`file`: its name, for the messages); what is wrong with it when it is not one.
    pub fn from_json(file: &str, text: &str) -> Result<Project, String> {
        let bad = |why: String| format!("{file} is not a mocapseg project: {why}");
        let value: Value = serde_json::from_str(text).map_err(|e| bad(format!("not JSON ({e})")))?;
        match value.get("format").and_then(Value::as_str) {
            Some(FORMAT) => {}
            other => return Err(bad(format!("its \"format\" is {other:?}, expected \"{FORMAT}\""))),
        }
        match value.get("version").and_then(Value::as_u64) {
            Some(VERSION) => {}
            other => return Err(bad(format!("its \"version\" is {other:?}; this page reads version {VERSION}"))),
        }
        let workspace =
            value.get("workspace").filter(|w| w.is_object()).ok_or_else(|| bad("no \"workspace\"".into()))?;
        let record =
            Record::from_json(&workspace.to_string()).map_err(|e| bad(e.replace("kept in this browser ", "")))?;
        let take = match value.get("take").filter(|t| !t.is_null()) {
            None => None,
            Some(t) => Some(take_of(t, "the take").map_err(bad)?),
        };
        let list = |k: &str| value.get(k).and_then(Value::as_array).cloned().unwrap_or_default();
        let library: Vec<TakeRef> = list("library")
            .iter()
            .enumerate()
            .map(|(i, t)| take_of(t, &format!("library take {}", i + 1)))
            .collect::<Result<_, _>>()
            .map_err(bad)?;
        let kept = record.library.as_ref().map_or(0, |l| l.takes.len());
        if library.len() != kept {
            return Err(bad(format!("it names {} library takes, its workspace {kept}", library.len())));
        }
        let mut labels = Vec::new();
        for (i, l) in list("labels").iter().enumerate() {
            let field = |k: &str| l.get(k).and_then(Value::as_str).map(str::to_string);
            let (Some(key), Some(json)) = (field("key"), field("json")) else {
                return Err(bad(format!("labels {} have no \"key\" or \"json\"", i + 1)));
            };
            if !key.starts_with(LABELS_PREFIX) {
                return Err(bad(format!("labels {} are kept under {key:?}, not under {LABELS_PREFIX}…", i + 1)));
            }
            labels.push(KeptLabels { key, json });
        }
        let b64 = base64::engine::general_purpose::STANDARD;
        let mut models = Vec::new();
        for (i, m) in list("models").iter().enumerate() {
            let field = |k: &str| {
                m.get(k)
                    .and_then(Value::as_str)
                    .map(str::to_string)
                    .ok_or_else(|| bad(format!("model {} has no \"{k}\"", i + 1)))
            };
            let data = b64
                .decode(field("data")?)
                .map_err(|e| bad(format!("model {}'s \"data\" is not base64: {e}", i + 1)))?;
            models.push(ProjectModel { method: field("method")?, name: field("name")?, file: field("file")?, data });
        }
        Ok(Project { record, take, library, labels, models })
    }

    /// Finds the project's takes among `files` (name, SHA-256): each by what it holds (a file of another name
    /// holding the same bytes is the take), and says which are missing and which files hold something else.
    pub fn find(&self, files: &[(String, String)]) -> Found {
        let mut found = Found::default();
        let mut locate = |t: &TakeRef| -> Option<(usize, Option<usize>)> {
            let at = |r: &TakeRef| {
                files
                    .iter()
                    .position(|(n, h)| *h == r.sha256 && *n == r.name)
                    .or_else(|| files.iter().position(|(_, h)| *h == r.sha256))
            };
            let short = |r: &TakeRef| format!("{} (SHA-256 {}…)", r.name, &r.sha256[..12.min(r.sha256.len())]);
            let mut whole = Some(());
            let motion = at(t);
            if motion.is_none() {
                whole = None;
                if files.iter().any(|(n, _)| *n == t.name) {
                    found.differ.push(short(t));
                } else {
                    found.missing.push(short(t));
                }
            }
            let skeleton = match t.skeleton.as_deref() {
                None => None,
                Some(s) => {
                    let at = at(s);
                    if at.is_none() {
                        whole = None;
                        found.missing.push(short(s));
                    }
                    at
                }
            };
            whole.and(motion).map(|m| (m, skeleton))
        };
        let take = self.take.as_ref().map(&mut locate);
        let library: Vec<_> = self.library.iter().map(&mut locate).collect();
        found.take = take.flatten();
        found.library = library;
        found.missing.dedup();
        found
    }
}

/// The take a key of my labels names, with what comes before and after it (`mocapseg.my-labels.v1`, `02_01.bvh`,
/// `10f:120.000fps:31j:0badf00d`): the name may hold ':', the four fields after it do not.
fn labels_key_parts(key: &str) -> Option<(&str, &str, &str)> {
    let (head, rest) = key.split_once(':')?;
    let mut fields = rest.rsplitn(5, ':');
    let tail_len = (0..4).map(|_| fields.next().map(str::len)).sum::<Option<usize>>()? + 4;
    let name = fields.next()?;
    Some((head, name, &rest[rest.len() - tail_len + 1..]))
}

impl Project {
    /// The project as the files opened with it name its takes (`names[i]`: file i's name; `found`: [`Project::find`]'s
    /// answer): a take found under another name than the one it was saved under is that take, so its place in the
    /// workspace, its cluster names' occurrences and my labels of it (kept by take name) follow it to its new name.
    pub fn renamed(mut self, found: &Found, names: &[String]) -> Project {
        let mut renames: Vec<(String, String)> = Vec::new();
        let mut rename = |t: &mut TakeRef, at: Option<(usize, Option<usize>)>| {
            let Some(new) = at.and_then(|(m, _)| names.get(m)) else { return };
            if *new != t.name {
                renames.push((std::mem::replace(&mut t.name, new.clone()), new.clone()));
            }
        };
        if let Some(t) = self.take.as_mut() {
            rename(t, found.take);
        }
        for (t, at) in self.library.iter_mut().zip(&found.library) {
            rename(t, *at);
        }
        let new_name = |old: &str| renames.iter().find(|(o, _)| o == old).map(|(_, n)| n.clone());
        if let Some(t) = self.record.take.as_mut() {
            if let Some(n) = new_name(&t.name) {
                t.name = n;
            }
        }
        if let Some(library) = self.record.library.as_mut() {
            for t in &mut library.takes {
                if let Some(n) = new_name(&t.name) {
                    t.name = n;
                }
            }
            for spot in library.names.iter_mut().flat_map(|named| named.spots.iter_mut()) {
                if let Some(n) = new_name(&spot.take) {
                    spot.take = n;
                }
            }
        }
        for l in &mut self.labels {
            let Some((head, name, tail)) = labels_key_parts(&l.key) else { continue };
            if let Some(n) = new_name(name) {
                l.key = format!("{head}:{n}:{tail}");
            }
        }
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::session::record::{KeptLibrary, KeptLibraryTake, KeptTake};

    fn take(name: &str, bytes: &[u8]) -> TakeRef {
        TakeRef { name: name.into(), sha256: sha256_hex(bytes), bytes: bytes.len() as u64, skeleton: None }
    }

    /// The files opened with [`project`]'s: `first` (name, bytes), then its AMC take and skeleton as saved.
    fn opened(first: &[(&str, &[u8])]) -> Vec<(String, String)> {
        let saved: [(&str, &[u8]); 2] = [("b.amc", b"motion b"), ("02.asf", b"skeleton")];
        first.iter().chain(&saved).map(|(name, bytes)| (name.to_string(), sha256_hex(bytes))).collect()
    }

    fn project() -> Project {
        let mut record = Record::new();
        record.take = Some(KeptTake { name: "02_01.bvh".into(), sample: false, kept: true, library: None });
        record.library = Some(KeptLibrary {
            method: "sssm".into(),
            takes: vec![
                KeptLibraryTake { name: "a.bvh".into(), kept: true },
                KeptLibraryTake { name: "b.amc".into(), kept: true },
            ],
            names: Vec::new(),
        });
        let mut b = take("b.amc", b"motion b");
        b.skeleton = Some(Box::new(take("02.asf", b"skeleton")));
        Project {
            record,
            take: Some(take("02_01.bvh", b"take")),
            library: vec![take("a.bvh", b"motion a"), b],
            labels: vec![KeptLabels { key: "mocapseg.my-labels.v1:02_01.bvh:10f".into(), json: "{}".into() }],
            models: vec![ProjectModel {
                method: "knn".into(),
                name: "mine".into(),
                file: "mine.knn".into(),
                data: vec![0, 1, 255],
            }],
        }
    }

    #[test]
    fn a_project_reads_back_as_it_was_written() {
        let p = project();
        assert_eq!(Project::from_json("p.json", &p.to_json()).unwrap(), p);
        assert_eq!(sha256_hex(b"abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    }

    #[test]
    fn a_file_that_is_not_a_project_says_what_is_wrong_with_it() {
        let err = |text: &str| Project::from_json("p.json", text).unwrap_err();
        assert!(err("nope").contains("p.json is not a mocapseg project: not JSON"));
        assert!(err(r#"{"format":"x"}"#).contains(r#"its "format" is Some("x")"#));
        assert!(err(r#"{"format":"mocapseg-project","version":9}"#).contains("reads version 1"));
        assert!(err(r#"{"format":"mocapseg-project","version":1}"#).contains("no \"workspace\""));
        let good = project().to_json();
        let with = |from: &str, to: &str| {
            assert!(good.contains(from), "{from}");
            err(&good.replacen(from, to, 1))
        };
        assert!(with(&sha256_hex(b"take"), "123").contains("the take's \"sha256\" is not a SHA-256"));
        assert!(with("\"data\":\"AAH/\"", "\"data\":\"!!\"").contains("model 1's \"data\" is not base64"));
        assert!(with("mocapseg.my-labels.v1", "other").contains("labels 1 are kept under \"other:02_01.bvh:10f\""));
        assert!(with("\"name\":\"a.bvh\",\"sha256\"", "\"nom\":\"a.bvh\",\"sha256\"")
            .contains("library take 1 has no \"name\""));
        let mut fewer = project();
        fewer.library.pop();
        assert!(err(&fewer.to_json()).contains("names 1 library takes, its workspace 2"));
    }

    #[test]
    fn a_take_opened_under_another_name_keeps_its_labels_place_and_cluster_names() {
        let mut p = project();
        let key = |name: &str| format!("mocapseg.my-labels.v1:{name}:2465f:120.000fps:31j:0badf00d");
        p.labels = vec![
            KeptLabels { key: key("02_01.bvh"), json: "{\"mine\":1}".into() },
            KeptLabels { key: key("a.bvh"), json: "{}".into() },
        ];
        p.record.library.as_mut().unwrap().names = vec![crate::app::library::names::Named {
            name: "jog".into(),
            spots: vec![crate::app::library::names::NamedSpot { take: "a.bvh".into(), start: 3, end: 40 }],
        }];
        let files = opened(&[("renamed: 02_01 copy.bvh", b"take"), ("walk.bvh", b"motion a")]);
        let found = p.find(&files);
        let names: Vec<String> = files.iter().map(|(n, _)| n.clone()).collect();
        let r = p.clone().renamed(&found, &names);
        assert_eq!(r.take.as_ref().unwrap().name, "renamed: 02_01 copy.bvh");
        assert_eq!(
            r.record.take.as_ref().unwrap().name,
            "renamed: 02_01 copy.bvh",
            "the take on screen is the renamed one"
        );
        let library = r.record.library.as_ref().unwrap();
        assert_eq!(library.takes.iter().map(|t| t.name.as_str()).collect::<Vec<_>>(), ["walk.bvh", "b.amc"]);
        assert_eq!(library.names[0].spots[0].take, "walk.bvh", "the cluster name follows its take");
        assert_eq!(
            r.labels.iter().map(|l| l.key.as_str()).collect::<Vec<_>>(),
            [key("renamed: 02_01 copy.bvh"), key("walk.bvh")],
            "my labels are kept under the name the take is opened with"
        );
        assert_eq!(r.labels[0].json, "{\"mine\":1}");
        // the same names: nothing changes
        let same: Vec<String> = ["02_01.bvh", "a.bvh", "b.amc", "02.asf"].map(String::from).to_vec();
        let files_same: Vec<(String, String)> =
            same.iter().zip(&files).map(|(n, (_, h))| (n.clone(), h.clone())).collect();
        assert_eq!(p.clone().renamed(&p.find(&files_same), &same), p);
        assert_eq!(
            labels_key_parts(&key("a:b.bvh")),
            Some(("mocapseg.my-labels.v1", "a:b.bvh", "2465f:120.000fps:31j:0badf00d"))
        );
        assert_eq!(labels_key_parts("mocapseg.my-labels.v1:short"), None);
    }

    #[test]
    fn takes_are_found_by_what_they_hold_whatever_their_names() {
        let p = project();
        let files = opened(&[("renamed.bvh", b"take"), ("a.bvh", b"changed")]);
        let found = p.find(&files);
        assert_eq!(found.take, Some((0, None)), "a renamed file holding the take's bytes is the take");
        assert_eq!(found.library, vec![None, Some((2, Some(3)))]);
        assert_eq!(found.differ.len(), 1);
        assert!(found.differ[0].starts_with("a.bvh (SHA-256 "), "{:?}", found.differ);
        assert!(found.missing.is_empty());
        // without the skeleton the AMC take is missing its ASF
        let found = p.find(&files[..3]);
        assert_eq!(found.library[1], None);
        assert!(found.missing[0].starts_with("02.asf (SHA-256 "), "{:?}", found.missing);
    }
}
