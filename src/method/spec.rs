//! What a page needs to build a parameter form for a method: for every parameter its name, a
//! one-line help, its kind with exactly the bounds the method's check enforces, and its
//! default (as the method's parameters serialize it).

use serde::{Deserialize, Serialize};

/// One parameter of a method.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ParamSpec {
    /// The field name (as in the parameters' JSON).
    pub name: String,
    /// One sentence for a tooltip.
    pub help: String,
    pub kind: ParamKind,
    /// The default value, as it appears in the parameters' JSON.
    pub default: serde_json::Value,
    /// Unit of the value (`"s"`, `"frames"`, `"in"`, …), if it has one.
    pub unit: Option<String>,
    /// Shown in the basic form (others under "advanced").
    pub basic: bool,
    /// A coupling the method's check enforces: this (number) parameter may not exceed the
    /// parameter named here. A form uses it to offer lowering this one when the other is set
    /// below it, rather than leave a basic field refused because of a hidden one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub at_most: Option<String>,
}

impl ParamSpec {
    /// The spec, declared to be at most the parameter `other` (see [`ParamSpec::at_most`]).
    pub fn at_most(mut self, other: &str) -> ParamSpec {
        self.at_most = Some(other.to_string());
        self
    }
}

/// The type of a parameter and the values it accepts (bounds included).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum ParamKind {
    Number {
        min: f64,
        max: f64,
    },
    Integer {
        min: i64,
        max: i64,
    },
    Bool,
    /// One of `options` (the serialized names).
    Choice {
        options: Vec<String>,
    },
    /// Any of `options` (a list of their names; the form's text joins them with commas).
    Flags {
        options: Vec<String>,
    },
    /// A list of at most `max_len` integers, each within `[min, max]`.
    IntegerList {
        min: i64,
        max: i64,
        max_len: usize,
    },
}
