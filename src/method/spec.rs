//! What a method's parameters look like, so a command line and a page can offer them without
//! knowing the method: name, help, kind with the bounds the method's check enforces, default.

use serde::{Deserialize, Serialize};

/// One parameter of a method.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ParamSpec {
    pub name: String,
    pub help: String,
    pub kind: ParamKind,
    pub default: serde_json::Value,
    pub unit: Option<String>,
    /// Shown in the basic form (the others under "advanced").
    pub basic: bool,
}

/// The kind of value a parameter takes, with the bounds the method's check enforces.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum ParamKind {
    Number { min: f64, max: f64 },
    Integer { min: i64, max: i64 },
    Bool,
    Choice { options: Vec<String> },
    IntegerList { min: i64, max: i64, max_len: usize },
}
