//! The sparse self-similarity matrix and what is read from it, shared by SSSM — one take (Krüger et al. 2017,
//! §IV–VI) — and the library of takes, which builds one matrix over many takes ([`crate::library`]):
//!
//! * [`neighbours`]: every frame's neighbours within a radius (a kiddo kd-tree over principal axes, and the searches
//!   along the diagonals SSSM runs by default), stored as the sparse matrix [`neighbours::Sssm`];
//! * [`paths`]: the neighbourhood graph of the matrix's entries and its warping paths (§IV-C);
//! * [`clusters`]: the cluster graph of segments joined by valid warping paths, and its strongly connected
//!   components (§VI).
//!
//! No method owns it: `src/methods/sssm/` segments one take with it (activities, primitives, bundling, refinement),
//! `src/library/` matches the segments of any method across takes with it.

pub mod clusters;
pub mod neighbours;
pub mod paths;

use serde::{Deserialize, Serialize};

/// What can go wrong reading a self-similarity matrix (SSSM and the library report it in their own errors, with the
/// same words).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SimilarityError {
    #[error("the take has no frames")]
    NoFrames,
    #[error("invalid features: {0}")]
    BadFeatures(String),
    #[error("invalid neighbour lists: {0}")]
    BadNeighbours(String),
    #[error("cancelled")]
    Cancelled,
}

impl From<crate::features::FeatureError> for SimilarityError {
    fn from(e: crate::features::FeatureError) -> Self {
        match e {
            crate::features::FeatureError::NoFrames => SimilarityError::NoFrames,
            crate::features::FeatureError::Bad(message) => SimilarityError::BadFeatures(message),
        }
    }
}

impl From<crate::method::Cancelled> for SimilarityError {
    fn from(_: crate::method::Cancelled) -> Self {
        SimilarityError::Cancelled
    }
}

/// An absent index (a frame in no span).
pub const NONE: u32 = u32::MAX;

/// For each frame, the index of the span containing it ([`NONE`] outside all spans).
pub fn frame_lookup(n: usize, spans: &[Span]) -> Vec<u32> {
    let mut of = vec![NONE; n];
    for (k, s) in spans.iter().enumerate() {
        of[s.start..=s.end.min(n.saturating_sub(1))].iter_mut().for_each(|a| *a = k as u32);
    }
    of
}

/// Frames `start..=end` (0-based, inclusive) at the working rate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Span {
    pub start: usize,
    pub end: usize,
}

impl Span {
    /// Number of frames.
    pub fn len(&self) -> usize {
        self.end + 1 - self.start
    }

    /// Always false (a span holds at least one frame); for clippy's `len_without_is_empty`.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// True if `frame` lies in the span.
    pub fn contains(&self, frame: usize) -> bool {
        self.start <= frame && frame <= self.end
    }
}
