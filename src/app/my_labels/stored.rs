//! My labels as the browser's storage keeps them, natively tested: the stored JSON ([`MyLabels::to_json`],
//! [`MyLabels::from_json`]: format [`FORMAT`], version [`VERSION`], the segments only), why a stored record
//! cannot be read back ([`StoreError`]), and the keys a take's labels and a record that cannot be read are kept
//! under ([`storage_key`], [`backup_key`], with a [`fingerprint`] of the take's motion).

use crate::app::my_labels::edits::{clean_label, MyLabels};
use crate::app::my_labels::spans::LabelSpan;

/// The `format` field of the stored JSON.
pub const FORMAT: &str = "mocapseg-my-labels";
/// The `version` field of the stored JSON this code writes and reads.
pub const VERSION: u64 = 1;

/// Why stored labels could not be read back.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StoreError {
    #[error("the stored labels are not JSON: {0}")]
    Json(String),
    #[error("the stored labels are not my labels (format `{0}`, expected `{FORMAT}`)")]
    Format(String),
    #[error("the stored labels are version {0}; this page reads version {VERSION}")]
    Version(String),
    #[error("the stored labels do not have the expected fields: {0}")]
    Shape(String),
    #[error("the stored labels are for a take of {stored} frames; this one has {frames}")]
    Frames { stored: usize, frames: usize },
    #[error("stored segment {index}: {why}")]
    Segment { index: usize, why: String },
}

impl MyLabels {
    /// The stored form: `{"format", "version", "file", "frames", "segments": [{start, end, label}]}`.
    pub fn to_json(&self, file: &str) -> String {
        serde_json::json!({
            "format": FORMAT,
            "version": VERSION,
            "file": file,
            "frames": self.frames(),
            "segments": self.spans(),
        })
        .to_string()
    }

    /// Reads back what [`to_json`](Self::to_json) wrote for a take of `frames` frames (no
    /// history, nothing selected), or says what is wrong with it.
    pub fn from_json(text: &str, frames: usize) -> Result<MyLabels, StoreError> {
        #[derive(serde::Deserialize)]
        struct Stored {
            frames: usize,
            segments: Vec<LabelSpan>,
        }
        let value: serde_json::Value = serde_json::from_str(text).map_err(|e| StoreError::Json(e.to_string()))?;
        let field = |name: &str| value.get(name).map_or_else(|| "missing".to_string(), |v| v.to_string());
        if value.get("format").and_then(|f| f.as_str()) != Some(FORMAT) {
            return Err(StoreError::Format(field("format")));
        }
        if value.get("version").and_then(|v| v.as_u64()) != Some(VERSION) {
            return Err(StoreError::Version(field("version")));
        }
        let stored: Stored = serde_json::from_value(value).map_err(|e| StoreError::Shape(e.to_string()))?;
        if stored.frames != frames {
            return Err(StoreError::Frames { stored: stored.frames, frames });
        }
        for (index, s) in stored.segments.iter().enumerate() {
            let bad = |why: String| Err(StoreError::Segment { index, why });
            if s.start > s.end {
                return bad(format!("start {} is after end {}", s.start, s.end));
            }
            if s.end >= frames {
                return bad(format!("end {} is past the last frame {}", s.end, frames.saturating_sub(1)));
            }
            if index > 0 && s.start <= stored.segments[index - 1].end {
                return bad(format!("starts at {}, inside the segment before it", s.start));
            }
            match clean_label(&s.label) {
                Ok(l) if l == s.label => {}
                Ok(_) => return bad("its label has spaces around it".into()),
                Err(e) => return bad(e.to_string()),
            }
        }
        Ok(MyLabels::restored(frames, stored.segments))
    }
}

/// The browser-storage key of my labels for a take: its file name, frames, frame rate (to the
/// thousandth), joints and a [`fingerprint`] of its motion, so that the same file opened again
/// finds them and another one — even of the same name and length — does not.
pub fn storage_key(name: &str, frames: usize, fps: f64, joints: usize, print: u32) -> String {
    format!("mocapseg.my-labels.v{VERSION}:{name}:{frames}f:{fps:.3}fps:{joints}j:{print:08x}")
}

/// Where a stored record of my labels that cannot be read is kept before the next edit replaces
/// it: the take's key (from [`storage_key`]) under another prefix, so that the record is never
/// lost and is never read as labels.
pub fn backup_key(key: &str) -> String {
    let take = key.strip_prefix("mocapseg.my-labels.").unwrap_or(key);
    format!("mocapseg.my-labels-backup.{take}")
}

/// A cheap fingerprint of a take (FNV-1a over the bits of `values`: the page passes the positions
/// of its first and last frames).
pub fn fingerprint(values: impl IntoIterator<Item = f32>) -> u32 {
    let mut h: u32 = 0x811c_9dc5;
    for v in values {
        for b in v.to_bits().to_le_bytes() {
            h ^= b as u32;
            h = h.wrapping_mul(0x0100_0193);
        }
    }
    h
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::my_labels::edits::tests::sample;
    use crate::app::my_labels::vocabulary::{label_class, suggestions};
    use crate::labels::LabelRow;

    #[test]
    fn stored_labels_read_back_and_corrupt_ones_say_why() {
        let mut m = sample();
        m.select(Some(0));
        m.relabel("say \"hi\", ünïcode").unwrap();
        let json = m.to_json("take.bvh");
        let back = MyLabels::from_json(&json, 100).unwrap();
        assert_eq!(back.spans(), m.spans());
        assert!(!back.can_undo() && back.selected().is_none());
        let empty = MyLabels::from_json(&MyLabels::new(7).to_json("x"), 7).unwrap();
        assert!(empty.spans().is_empty());

        let err = |text: &str| MyLabels::from_json(text, 100).unwrap_err().to_string();
        assert!(err("").contains("not JSON"));
        assert!(err("{\"format\":\"mocapseg-my-labels\"").contains("not JSON"));
        assert!(err("[1,2]").contains("not my labels (format `missing`"));
        assert!(err(r#"{"format":"mocapseg-my-labels","version":2,"frames":100,"segments":[]}"#)
            .contains("version 2; this page reads version 1"));
        assert!(err(r#"{"format":"mocapseg-my-labels","version":1,"frames":100}"#).contains("expected fields"));
        assert!(err(
            r#"{"format":"mocapseg-my-labels","version":1,"frames":100,"segments":[{"start":-1,"end":3,"label":""}]}"#
        )
        .contains("expected fields"));
        assert_eq!(MyLabels::from_json(&json, 99).unwrap_err(), StoreError::Frames { stored: 100, frames: 99 });
        let seg = |list: &str| {
            err(&format!(r#"{{"format":"mocapseg-my-labels","version":1,"frames":100,"segments":[{list}]}}"#))
        };
        assert_eq!(seg(r#"{"start":5,"end":3,"label":""}"#), "stored segment 0: start 5 is after end 3");
        assert_eq!(seg(r#"{"start":5,"end":100,"label":""}"#), "stored segment 0: end 100 is past the last frame 99");
        assert_eq!(
            seg(r#"{"start":0,"end":10,"label":"a"},{"start":10,"end":20,"label":"b"}"#),
            "stored segment 1: starts at 10, inside the segment before it"
        );
        assert!(seg(r#"{"start":0,"end":1,"label":"a\u0000"}"#).starts_with("stored segment 0: a label cannot hold"));
        assert_eq!(seg(r#"{"start":0,"end":1,"label":" a"}"#), "stored segment 0: its label has spaces around it");
    }

    #[test]
    fn storage_keys_tell_takes_apart_and_labels_make_csv_rows() {
        let print = fingerprint([0.0, 1.5, -2.25]);
        let a = storage_key("13_30.bvh", 2465, 120.0, 31, print);
        assert_eq!(a, format!("mocapseg.my-labels.v1:13_30.bvh:2465f:120.000fps:31j:{print:08x}"));
        assert_ne!(a, storage_key("13_30.bvh", 2464, 120.0, 31, print));
        assert_ne!(a, storage_key("13_30.bvh", 2465, 60.0, 31, print));
        assert_ne!(a, storage_key("13_31.bvh", 2465, 120.0, 31, print));
        assert_ne!(a, storage_key("13_30.bvh", 2465, 120.0, 32, print));
        // a corrupt record's backup: the same take, another prefix (never read as labels)
        let backup = backup_key(&a);
        assert_eq!(backup, format!("mocapseg.my-labels-backup.v1:13_30.bvh:2465f:120.000fps:31j:{print:08x}"));
        assert!(!backup.starts_with("mocapseg.my-labels."));
        // the same numbers give the same print; any change (even -0.0 for 0.0) another
        assert_eq!(print, fingerprint([0.0, 1.5, -2.25]));
        assert_ne!(print, fingerprint([-0.0, 1.5, -2.25]));
        assert_ne!(print, fingerprint([0.0, 1.5]));
        assert_eq!(fingerprint([]), 0x811c_9dc5);
        let mut m = sample();
        m.select(Some(1));
        m.relabel("").unwrap();
        let rows = m.label_rows("take.bvh");
        assert_eq!(rows.len(), 2);
        assert_eq!(crate::labels::read_csv(&crate::labels::to_csv(&rows), "x").unwrap(), rows);
        assert_eq!(rows[1], LabelRow { file: "take.bvh".into(), start_frame: 40, end_frame: 99, label: "c".into() });
        assert_eq!(suggestions(["b", "", "a", "b", "  "]), vec!["a", "b"]);
        assert_eq!(label_class("walk"), label_class("walk"));
        assert!(label_class("walk") < 64);
        assert_ne!(label_class("walk"), label_class("kick"));
    }
}
