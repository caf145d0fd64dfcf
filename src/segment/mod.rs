//! The segmentation JSON schema shared by every method, the page's exports and the CLI.
//!
//! ```json
//! {"file": "86_01.bvh", "fps": 120.0, "frames": 4579, "method": "sssm", "params": {},
//!  "segments": [{"start": 0, "end": 549, "label": "walk", "level": "action",
//!                "cluster": 0, "score": null}]}
//! ```
//! Frame indices are 0-based and inclusive, at the file's own frame rate. A segment may also carry
//! `"mirror_of": K`: its cluster is the mirror image of cluster `K` (SSSM primitives), and
//! `"effort": {"space": x, "time": x, "weight": x, "flow": x}`: its Laban Effort, each factor in
//! [−1, 1] from fully indulging (−1) to fully condensing (+1) (LMA segments).

/// The label of frames a labeller will not name (below its model's confidence threshold, or a class the
/// transfer's knowledge base lacks): the same word on every row, counted wrong by every score.
pub const UNKNOWN: &str = "unknown";

pub mod consensus;
pub mod cuts;
pub mod frames;
pub mod labelling;
pub mod metrics;
pub mod palette;
pub mod reference;
pub mod report;
pub mod truth;
pub mod truth_import;

use serde::{Deserialize, Serialize};

/// The granularity a segment describes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Level {
    Action,
    Transition,
    Primitive,
}

/// One segment: frames `start..=end` (0-based, inclusive).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Segment {
    pub start: usize,
    pub end: usize,
    pub label: String,
    pub level: Level,
    pub cluster: Option<usize>,
    pub score: Option<f64>,
    /// The cluster whose segments are this one's mirror image (left step ↔ right step), for
    /// methods that find mirror pairs (SSSM §V); left out of the JSON when there is none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mirror_of: Option<usize>,
    /// The segment's Laban Effort (methods that classify it, LMA); left out of the JSON when none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub effort: Option<Effort>,
}

/// Laban Effort of a segment: each factor in [−1, 1], −1 fully indulging (indirect, sustained,
/// light, free), +1 fully condensing (direct, sudden, strong, bound).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Effort {
    pub space: f64,
    pub time: f64,
    pub weight: f64,
    pub flow: f64,
}

/// A method's output for one file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Segmentation {
    pub file: String,
    pub fps: f64,
    pub frames: usize,
    pub method: String,
    pub params: serde_json::Value,
    pub segments: Vec<Segment>,
}

/// Why a segmentation does not fit the schema's rules.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SchemaError {
    #[error("segment {index}: start {start} is after end {end}")]
    Reversed { index: usize, start: usize, end: usize },
    #[error("segment {index}: end {end} is past the last frame {last}")]
    PastEnd { index: usize, end: usize, last: usize },
    #[error("fps must be a positive finite number, got {0}")]
    BadFps(f64),
    #[error("invalid segmentation JSON: {0}")]
    Json(String),
}

impl Segmentation {
    /// Checks the invariants every producer must keep: positive fps, ordered in-range indices.
    pub fn validate(&self) -> Result<(), SchemaError> {
        if !(self.fps.is_finite() && self.fps > 0.0) {
            return Err(SchemaError::BadFps(self.fps));
        }
        for (index, s) in self.segments.iter().enumerate() {
            if s.start > s.end {
                return Err(SchemaError::Reversed { index, start: s.start, end: s.end });
            }
            if self.frames == 0 || s.end >= self.frames {
                return Err(SchemaError::PastEnd { index, end: s.end, last: self.frames.saturating_sub(1) });
            }
        }
        Ok(())
    }

    /// Pretty JSON text of this segmentation.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("a Segmentation always serialises")
    }

    /// Parses and validates segmentation JSON.
    pub fn from_json(text: &str) -> Result<Self, SchemaError> {
        let s: Segmentation = serde_json::from_str(text).map_err(|e| SchemaError::Json(e.to_string()))?;
        s.validate()?;
        Ok(s)
    }

    /// The segments of one level, in order of their start frame.
    pub fn level(&self, level: Level) -> impl Iterator<Item = &Segment> + '_ {
        self.segments.iter().filter(move |s| s.level == level)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Segmentation {
        Segmentation {
            file: "a.bvh".into(),
            fps: 120.0,
            frames: 100,
            method: "test".into(),
            params: serde_json::json!({"radius": 19.0}),
            segments: vec![
                Segment {
                    start: 0,
                    end: 49,
                    label: "walk".into(),
                    level: Level::Action,
                    cluster: Some(0),
                    score: None,
                    mirror_of: None,
                    effort: None,
                },
                Segment {
                    start: 50,
                    end: 99,
                    label: "t".into(),
                    level: Level::Transition,
                    cluster: None,
                    score: Some(0.5),
                    mirror_of: None,
                    effort: Some(Effort { space: -1.0, time: 0.5, weight: 0.0, flow: 1.0 }),
                },
            ],
        }
    }

    #[test]
    fn json_round_trip_uses_the_documented_field_names() {
        let s = sample();
        let text = s.to_json();
        let v: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(v["segments"][0]["level"], "action");
        assert_eq!(v["segments"][1]["level"], "transition");
        assert!(v["segments"][0]["score"].is_null());
        assert_eq!(v["params"]["radius"], 19.0);
        // the optional fields appear only where a method sets them
        assert!(v["segments"][0].get("effort").is_none() && v["segments"][0].get("mirror_of").is_none());
        assert_eq!(v["segments"][1]["effort"]["space"], -1.0);
        assert_eq!(v["segments"][1]["effort"]["time"], 0.5);
        assert_eq!(Segmentation::from_json(&text).unwrap(), s);
    }

    #[test]
    fn validation_rejects_bad_segments() {
        let mut s = sample();
        s.segments[1].end = 100;
        assert!(matches!(s.validate(), Err(SchemaError::PastEnd { index: 1, .. })));
        let mut s = sample();
        s.segments[0].start = 60;
        assert!(matches!(s.validate(), Err(SchemaError::Reversed { index: 0, .. })));
        let mut s = sample();
        s.fps = 0.0;
        assert!(matches!(s.validate(), Err(SchemaError::BadFps(_))));
        assert!(matches!(Segmentation::from_json("{"), Err(SchemaError::Json(_))));
    }
}
