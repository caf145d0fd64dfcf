//! What the page keeps of the workspace across a reload (issue 48, "a reload loses the work"): the take on screen
//! (the bundled sample, or a file whose bytes the browser keeps beside this record, within [`MAX_KEPT_TAKE_BYTES`]),
//! its ground truth (the file's name and text and the choices it is read with), and each row's form (every field's
//! text, the model chosen among them). One JSON record, versioned; a record of another version, or one that does not
//! read, is dropped with a message and the page starts afresh.

use crate::app::library::names::Named;
use serde_json::{json, Map, Value};
use std::collections::BTreeMap;

/// The record's format (a record of another version is not read).
pub const RECORD_VERSION: u32 = 1;

/// The largest take file kept in this browser: a larger one is not kept (the page says so), so that keeping the
/// workspace never fills the browser's storage with one take.
pub const MAX_KEPT_TAKE_BYTES: f64 = 256.0 * 1024.0 * 1024.0;

/// The most the library's take files kept in this browser may hold in all: a take past it is not kept (the page says
/// so; the takes before it are).
pub const MAX_KEPT_LIBRARY_BYTES: f64 = 1024.0 * 1024.0 * 1024.0;

/// The take that was on screen.
#[derive(Debug, Clone, PartialEq)]
pub struct KeptTake {
    /// Its file's name (the motion's, for an ASF skeleton with its AMC motion).
    pub name: String,
    /// The bundled sample (nothing kept but this mark).
    pub sample: bool,
    /// Whether its file's bytes are kept beside the record (false: too large, or the browser refused them).
    pub kept: bool,
    /// The library's take it is (its file is kept with the library's, not again).
    pub library: Option<usize>,
}

/// A take of the library as kept: its file's name (and its skeleton's) and whether its files are kept.
#[derive(Debug, Clone, PartialEq)]
pub struct KeptLibraryTake {
    pub name: String,
    pub kept: bool,
}

/// The library as kept: its takes (segmented again when the page opens, as they were: the methods are
/// deterministic), the method they are segmented with, and the names given to its clusters, kept by what each cluster
/// holds ([`crate::app::library::names`]).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct KeptLibrary {
    pub method: String,
    pub takes: Vec<KeptLibraryTake>,
    pub names: Vec<Named>,
}

/// The ground truth that was imported: its file and the choices it is read with.
#[derive(Debug, Clone, PartialEq)]
pub struct KeptTruth {
    pub name: String,
    pub text: String,
    /// The number CSV frames start at.
    pub base: String,
    /// The labels' frame rate as typed (empty: the take's).
    pub fps: String,
    /// The trial of a shared-data CSV (empty: found from the take's name).
    pub trial: String,
}

/// The workspace as kept.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Record {
    pub version: u32,
    pub take: Option<KeptTake>,
    pub truth: Option<KeptTruth>,
    /// Each row's form: method (registry name) → parameter name → the text of its field.
    pub rows: BTreeMap<String, BTreeMap<String, String>>,
    /// The library (`None`: it has no take).
    pub library: Option<KeptLibrary>,
    /// The side panel's tab shown (empty: the page's first).
    pub panel: String,
}

impl Record {
    /// An empty record of this version.
    pub fn new() -> Record {
        Record { version: RECORD_VERSION, ..Record::default() }
    }

    /// The record as JSON (written through `serde_json::Value`, as the worker's parameters are: the page's wasm gets no
    /// code of its own for it).
    pub fn to_json(&self) -> String {
        let take = self
            .take
            .as_ref()
            .map(|t| json!({ "name": t.name, "sample": t.sample, "kept": t.kept, "library": t.library }));
        let truth = self
            .truth
            .as_ref()
            .map(|t| json!({ "name": t.name, "text": t.text, "base": t.base, "fps": t.fps, "trial": t.trial }));
        let rows: Map<String, Value> = self
            .rows
            .iter()
            .map(|(method, fields)| {
                let fields: Map<String, Value> =
                    fields.iter().map(|(k, v)| (k.clone(), Value::from(v.as_str()))).collect();
                (method.clone(), Value::Object(fields))
            })
            .collect();
        let library = self.library.as_ref().map(|l| {
            let takes: Vec<Value> = l.takes.iter().map(|t| json!({ "name": t.name, "kept": t.kept })).collect();
            json!({ "method": l.method, "takes": takes, "names": serde_json::to_value(&l.names).unwrap_or_default() })
        });
        json!({ "version": self.version, "take": take, "truth": truth, "rows": rows, "library": library, "panel": self.panel })
            .to_string()
    }

    /// Reads a kept record; why not, when it is of another version or does not read.
    pub fn from_json(text: &str) -> Result<Record, String> {
        let unreadable = |why: &str| format!("the workspace kept in this browser does not read: {why}");
        let value: Value = serde_json::from_str(text).map_err(|e| unreadable(&e.to_string()))?;
        let version = value.get("version").and_then(Value::as_u64).ok_or_else(|| unreadable("no version"))?;
        if version != u64::from(RECORD_VERSION) {
            return Err(format!(
                "the workspace kept in this browser is of another version ({version}, this page reads {RECORD_VERSION}): it starts afresh"
            ));
        }
        let text_of = |v: &Value, k: &str| v.get(k).and_then(Value::as_str).map(str::to_string);
        let flag = |v: &Value, k: &str| v.get(k).and_then(Value::as_bool);
        let take = match value.get("take").filter(|t| !t.is_null()) {
            None => None,
            Some(t) => Some(KeptTake {
                name: text_of(t, "name").ok_or_else(|| unreadable("a take without a name"))?,
                sample: flag(t, "sample").unwrap_or(false),
                kept: flag(t, "kept").unwrap_or(false),
                library: t.get("library").and_then(Value::as_u64).map(|i| i as usize),
            }),
        };
        let truth = match value.get("truth").filter(|t| !t.is_null()) {
            None => None,
            Some(t) => {
                let field =
                    |k: &str| text_of(t, k).ok_or_else(|| unreadable(&format!("a ground truth without its {k}")));
                Some(KeptTruth {
                    name: field("name")?,
                    text: field("text")?,
                    base: field("base")?,
                    fps: field("fps")?,
                    trial: field("trial")?,
                })
            }
        };
        let mut rows = BTreeMap::new();
        for (method, fields) in value.get("rows").and_then(Value::as_object).into_iter().flatten() {
            let fields =
                fields.as_object().ok_or_else(|| unreadable(&format!("the form of {method} is not an object")))?;
            let texts = fields.iter().filter_map(|(k, v)| v.as_str().map(|v| (k.clone(), v.to_string()))).collect();
            rows.insert(method.clone(), texts);
        }
        let library = match value.get("library").filter(|l| !l.is_null()) {
            None => None,
            Some(l) => Some(library_of(l).map_err(|why| unreadable(&why))?),
        };
        let panel = text_of(&value, "panel").unwrap_or_default();
        Ok(Record { version: RECORD_VERSION, take, truth, rows, library, panel })
    }

    /// The fields of `method`'s form to set again: (index among `names`, text), for the parameters it still has (a
    /// parameter kept from an older page that the method no longer declares is skipped).
    pub fn fields_of(&self, method: &str, names: &[&str]) -> Vec<(usize, String)> {
        let Some(kept) = self.rows.get(method) else { return Vec::new() };
        names.iter().enumerate().filter_map(|(i, name)| kept.get(*name).map(|text| (i, text.clone()))).collect()
    }
}

/// The library as kept, from its JSON; why it does not read.
fn library_of(l: &Value) -> Result<KeptLibrary, String> {
    let method = l.get("method").and_then(Value::as_str).ok_or("a library without its method")?.to_string();
    let mut takes = Vec::new();
    for t in l.get("takes").and_then(Value::as_array).ok_or("a library without its takes")? {
        let name = t.get("name").and_then(Value::as_str).ok_or("a library take without a name")?.to_string();
        takes.push(KeptLibraryTake { name, kept: t.get("kept").and_then(Value::as_bool).unwrap_or(false) });
    }
    let names = match l.get("names") {
        None | Some(Value::Null) => Vec::new(),
        Some(n) => serde_json::from_value(n.clone()).map_err(|e| format!("the library's cluster names: {e}"))?,
    };
    Ok(KeptLibrary { method, takes, names })
}

/// Which of the library's take files (`sizes`, bytes, in order; `None`: a take whose size is not known) are kept in
/// this browser, each within [`MAX_KEPT_TAKE_BYTES`] and all within [`MAX_KEPT_LIBRARY_BYTES`]; and, for those that
/// are not, why, in the words the page shows.
pub fn library_kept(names: &[String], sizes: &[f64]) -> (Vec<bool>, Vec<String>) {
    let mut total = 0.0;
    let mut why = Vec::new();
    let kept = names
        .iter()
        .zip(sizes)
        .map(|(name, &bytes)| {
            if let Err(e) = take_kept(name, bytes) {
                why.push(e);
                return false;
            }
            if total + bytes > MAX_KEPT_LIBRARY_BYTES {
                why.push(format!(
                    "{name} is not kept in this browser: the library's files kept would pass {:.0} MiB",
                    MAX_KEPT_LIBRARY_BYTES / 1024.0 / 1024.0
                ));
                return false;
            }
            total += bytes;
            true
        })
        .collect();
    (kept, why)
}

/// What `#workspace-status` says once a workspace is set again from `from` ("this browser", a project file): the
/// take `shown` (with its ground truth), the rows' settings, the library's `library` takes, and the takes `missing`
/// (a problem: they are named, with what to do). `None` when there is nothing to say (the sample, as it was).
pub fn restored_text(
    shown: Option<&str>,
    truth: bool,
    library: usize,
    from: &str,
    missing: &[String],
) -> Option<(bool, String)> {
    let mut what = Vec::new();
    if let Some(name) = shown {
        what.push(name.to_string());
        if truth {
            what.push("its ground truth".to_string());
        }
    }
    what.push("the rows' settings".to_string());
    if library > 0 {
        what.push(format!("the library's {}", crate::method::counted(library, "take")));
    }
    let said = match what.len() {
        1 => what[0].clone(),
        n => format!("{} and {}", what[..n - 1].join(", "), what[n - 1]),
    };
    let mut text = format!("Restored {said} from {from}.");
    if !missing.is_empty() {
        let mut names = missing.to_vec();
        names.dedup();
        let how =
            if from == "this browser" { "not kept in this browser: drop" } else { "not among the files opened: open" };
        text = format!(
            "{text} {} {how} {} again to go on with {}.",
            names.join(", "),
            if names.len() == 1 { "it" } else { "them" },
            if names.len() == 1 { "it" } else { "them" }
        );
    } else if shown.is_none() && library == 0 && from == "this browser" {
        return None;
    }
    Some((!missing.is_empty(), text))
}

/// Whether a take file of `bytes` bytes is kept in this browser; why not, in the words the page shows.
pub fn take_kept(name: &str, bytes: f64) -> Result<(), String> {
    if bytes > MAX_KEPT_TAKE_BYTES {
        let mib = |b: f64| b / 1024.0 / 1024.0;
        return Err(format!(
            "{name} ({:.0} MiB) is not kept in this browser (at most {:.0} MiB): after a reload, drop it again",
            mib(bytes),
            mib(MAX_KEPT_TAKE_BYTES)
        ));
    }
    Ok(())
}

/// What the page says when the browser would not keep `what` (`error`: the browser's message, a full storage named
/// as such).
pub fn not_kept(what: &str, error: &str) -> String {
    if error.contains("QuotaExceeded") {
        format!("{what} is not kept: this browser's storage for this page is full (forget kept models, or free space)")
    } else {
        format!("{what} is not kept in this browser: {error}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record() -> Record {
        let mut rows = BTreeMap::new();
        rows.insert("sssm".to_string(), BTreeMap::from([("tau".to_string(), "0.4".to_string())]));
        rows.insert(
            "knn".to_string(),
            BTreeMap::from([("model".to_string(), "mine".to_string()), ("gone".to_string(), "1".to_string())]),
        );
        Record {
            version: RECORD_VERSION,
            take: Some(KeptTake { name: "02_01.bvh".into(), sample: false, kept: true, library: Some(1) }),
            truth: Some(KeptTruth {
                name: "02_01.csv".into(),
                text: "start_frame,end_frame,label\n1,10,walk\n".into(),
                base: "1".into(),
                fps: String::new(),
                trial: String::new(),
            }),
            rows,
            library: Some(KeptLibrary {
                method: "sssm".into(),
                takes: vec![
                    KeptLibraryTake { name: "01_01.bvh".into(), kept: true },
                    KeptLibraryTake { name: "02_01.bvh".into(), kept: false },
                ],
                names: vec![Named {
                    name: "jog".into(),
                    spots: vec![crate::app::library::names::NamedSpot { take: "01_01.bvh".into(), start: 3, end: 40 }],
                }],
            }),
            panel: "library".into(),
        }
    }

    #[test]
    fn what_came_back_is_said_with_what_did_not() {
        let said = |shown, truth, library, from, missing: &[&str]| {
            let missing: Vec<String> = missing.iter().map(|m| m.to_string()).collect();
            restored_text(shown, truth, library, from, &missing)
        };
        assert_eq!(
            said(Some("02_01.bvh"), true, 0, "this browser", &[]),
            Some((false, "Restored 02_01.bvh, its ground truth and the rows' settings from this browser.".into()))
        );
        assert_eq!(
            said(Some("b.bvh"), false, 2, "p.json", &["c.bvh"]),
            Some((
                true,
                "Restored b.bvh, the rows' settings and the library's 2 takes from p.json. c.bvh not among the files \
                 opened: open it again to go on with it."
                    .into()
            ))
        );
        assert_eq!(said(None, true, 0, "this browser", &[]), None, "the sample as it was: nothing to say");
        let (problem, text) = said(None, false, 0, "this browser", &["big.bvh"]).unwrap();
        assert!(
            problem && text.ends_with("big.bvh not kept in this browser: drop it again to go on with it."),
            "{text}"
        );
    }

    #[test]
    fn library_files_are_kept_each_within_a_take_s_limit_and_all_within_the_library_s() {
        let mib = 1024.0 * 1024.0;
        let names: Vec<String> = (0..7).map(|i| format!("t{i}.bvh")).collect();
        let sizes = [300.0 * mib, 250.0 * mib, 250.0 * mib, 250.0 * mib, 250.0 * mib, 30.0 * mib, 20.0 * mib];
        let (kept, why) = library_kept(&names, &sizes);
        assert_eq!(
            kept,
            [false, true, true, true, true, false, true],
            "a smaller take after one past the limit is kept"
        );
        assert!(why[0].contains("t0.bvh (300 MiB) is not kept") && why[0].contains("256 MiB"), "{why:?}");
        assert!(why[1].contains("t5.bvh is not kept") && why[1].contains("1024 MiB"), "{why:?}");
    }

    #[test]
    fn a_record_reads_back_as_it_was_written() {
        let r = record();
        assert_eq!(Record::from_json(&r.to_json()).unwrap(), r);
    }

    #[test]
    fn a_record_of_another_version_or_that_does_not_read_is_refused_saying_why() {
        let mut r = record();
        r.version = RECORD_VERSION + 1;
        let why = Record::from_json(&r.to_json()).unwrap_err();
        assert!(why.contains("another version") && why.contains("afresh"), "{why}");
        let why = Record::from_json("{\"version\":").unwrap_err();
        assert!(why.contains("does not read"), "{why}");
        let why = Record::from_json(r#"{"version":1,"take":{"sample":true}}"#).unwrap_err();
        assert!(why.contains("a take without a name"), "{why}");
        let why =
            Record::from_json(r#"{"version":1,"library":{"method":"sssm","takes":[{"kept":true}]}}"#).unwrap_err();
        assert!(why.contains("a library take without a name"), "{why}");
        let why = Record::from_json(r#"{"version":1,"library":{"method":"sssm","takes":[],"names":[{"name":1}]}}"#)
            .unwrap_err();
        assert!(why.contains("cluster names"), "{why}");
    }

    #[test]
    fn only_the_parameters_a_method_still_declares_are_set_again() {
        let r = record();
        assert_eq!(r.fields_of("knn", &["k", "model"]), vec![(1, "mine".to_string())]);
        assert_eq!(r.fields_of("sssm", &["tau"]), vec![(0, "0.4".to_string())]);
        assert!(r.fields_of("pca", &["tau"]).is_empty(), "a method without a kept form keeps its defaults");
    }

    #[test]
    fn a_take_over_the_limit_is_not_kept_and_a_full_storage_is_named() {
        assert!(take_kept("a.bvh", MAX_KEPT_TAKE_BYTES).is_ok());
        let why = take_kept("big.bvh", MAX_KEPT_TAKE_BYTES + 1.0).unwrap_err();
        assert!(why.starts_with("big.bvh (256 MiB) is not kept") && why.contains("drop it again"), "{why}");
        let full = not_kept("big.bvh", "QuotaExceededError: the quota has been exceeded");
        assert!(full.contains("storage for this page is full"), "{full}");
        assert!(not_kept("a.bvh", "UnknownError: x").ends_with("UnknownError: x"));
    }
}
