//! What the page keeps of the workspace across a reload (issue 48, "a reload loses the work"): the take on screen
//! (the bundled sample, or a file whose bytes the browser keeps beside this record, within [`MAX_KEPT_TAKE_BYTES`]),
//! its ground truth (the file's name and text and the choices it is read with), and each row's form (every field's
//! text, the model chosen among them). One JSON record, versioned; a record of another version, or one that does not
//! read, is dropped with a message and the page starts afresh.

use serde_json::{json, Map, Value};
use std::collections::BTreeMap;

/// The record's format (a record of another version is not read).
pub const RECORD_VERSION: u32 = 1;

/// The largest take file kept in this browser: a larger one is not kept (the page says so), so that keeping the
/// workspace never fills the browser's storage with one take.
pub const MAX_KEPT_TAKE_BYTES: f64 = 256.0 * 1024.0 * 1024.0;

/// The take that was on screen.
#[derive(Debug, Clone, PartialEq)]
pub struct KeptTake {
    /// Its file's name (the motion's, for an ASF skeleton with its AMC motion).
    pub name: String,
    /// The bundled sample (nothing kept but this mark).
    pub sample: bool,
    /// Whether its file's bytes are kept beside the record (false: too large, or the browser refused them).
    pub kept: bool,
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
}

impl Record {
    /// An empty record of this version.
    pub fn new() -> Record {
        Record { version: RECORD_VERSION, ..Record::default() }
    }

    /// The record as JSON (written through `serde_json::Value`, as the worker's parameters are: the page's wasm gets no
    /// code of its own for it).
    pub fn to_json(&self) -> String {
        let take = self.take.as_ref().map(|t| json!({ "name": t.name, "sample": t.sample, "kept": t.kept }));
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
        json!({ "version": self.version, "take": take, "truth": truth, "rows": rows }).to_string()
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
        Ok(Record { version: RECORD_VERSION, take, truth, rows })
    }

    /// The fields of `method`'s form to set again: (index among `names`, text), for the parameters it still has (a
    /// parameter kept from an older page that the method no longer declares is skipped).
    pub fn fields_of(&self, method: &str, names: &[&str]) -> Vec<(usize, String)> {
        let Some(kept) = self.rows.get(method) else { return Vec::new() };
        names.iter().enumerate().filter_map(|(i, name)| kept.get(*name).map(|text| (i, text.clone()))).collect()
    }
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
            take: Some(KeptTake { name: "02_01.bvh".into(), sample: false, kept: true }),
            truth: Some(KeptTruth {
                name: "02_01.csv".into(),
                text: "start_frame,end_frame,label\n1,10,walk\n".into(),
                base: "1".into(),
                fps: String::new(),
                trial: String::new(),
            }),
            rows,
        }
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
