//! Errors and warnings of the BVH parser. Every error names the line and column (1-based)
//! where the problem is and what was expected there.

use serde::{Deserialize, Serialize};

/// A fatal parse error.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("line {line}, column {column}: {message}")]
pub struct BvhError {
    /// 1-based line number.
    pub line: usize,
    /// 1-based column (in characters).
    pub column: usize,
    /// What was found and what was expected, in words.
    pub message: String,
}

impl BvhError {
    pub fn new(line: usize, column: usize, message: impl Into<String>) -> Self {
        BvhError { line, column, message: message.into() }
    }
}

/// A problem that does not stop parsing but that the user must hear about.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Warning {
    /// 1-based line number the warning refers to (0 if it concerns the whole file).
    pub line: usize,
    pub message: String,
}

impl std::fmt::Display for Warning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.line > 0 {
            write!(f, "line {}: {}", self.line, self.message)
        } else {
            f.write_str(&self.message)
        }
    }
}
