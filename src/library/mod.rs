//! A library of takes: motions matched across takes and labels carried from one take to the others.
//!
//! The SSSM paper (Krüger et al. 2017) clusters the motion primitives *of one take* (§VI) and sketches, as an
//! application, carrying labels from a labelled knowledge base to unlabelled primitives (§VII-E: a feature-space
//! nearest-neighbour search, then the warping path of lowest cost between a labelled and an unlabelled primitive
//! decides the label). This module applies both across a library:
//!
//! * **Design — one SSSM over the whole library.** Every take's end-effector features (the SSSM's own, §IV-A:
//!   hands, feet, head relative to the hips, facing-aligned, scaled to the reference body, at the working rate)
//!   are stacked over the same frame offsets and put *one after another* into one neighbour search (kiddo's
//!   kd-tree, [`crate::similarity::neighbours::NeighbourSearch`]). Its sparse self-similarity matrix then holds
//!   neighbours within and across takes, and the cluster graph of §VI — an edge `p → q` where a valid warping
//!   path (slope within `[1/ν, ν]`, long enough) in the block `p × q` covers enough of both segments — is built on
//!   it for the segments of *every* take at once. Its strongly connected components are clusters whose ids mean
//!   the same motion in every take. Segments of different takes never share a block with frames of a third, so
//!   the paths are exactly those of pairs of segments. Any method's segments can be clustered: the *units* are the
//!   finest tiling a segmentation gives ([`units`]: primitives and transitions where there are primitives, else
//!   actions and transitions; overlaps — two arms' gestures — trimmed).
//! * **Label transfer** ([`transfer`]): the units of a labelled take are the knowledge base; every other unit
//!   takes the label of the labelled unit it is joined to by the *cheapest* valid warping path (§VII-E: a
//!   nearest-neighbour search among the labelled frames, then subsequence warping paths), with a confidence from
//!   that path's mean distance relative to the search radius, and `unknown` where no labelled unit is joined to it.
//!   Through the shared clusters instead: a cluster's label is the majority label of the labelled take's frames in
//!   it. [`LibraryParams::for_transfer`] are its settings, chosen by nested validation.
//! * [`score`]: purity, inverse purity and NMI of clusters against per-frame labels across takes, and the chance
//!   level (cluster ids shuffled among units of equal count).
//!
//! Memory: a take in the library is its [`TakeFeatures`] (15 numbers per working frame — 1.8 kB per second at
//! 30 Hz) and its segmentation, never its frames. The neighbour lists of the whole library are bounded like one
//! take's ([`LibraryError::TooLarge`]).

pub mod clusters;
pub mod score;
pub mod transfer;

use serde::{Deserialize, Serialize};

use crate::features::end_effectors::{end_effectors, EndEffectorError};
use crate::features::FeatureMatrix;
use crate::motion::Motion;
use crate::segment::frames::WorkingFrames;
use crate::segment::{Level, Segment, Segmentation};
use crate::similarity::Span;

pub use clusters::{cluster, Occurrence, SharedCluster, SharedClusters};
pub use transfer::{transfer, KnowledgeBase, Transfer, TransferRoute, Transferred};

/// How a library is matched. The defaults are the SSSM's own (its primitive radius, offsets, ν, path length) except
/// two: the neighbours kept per frame ([`DEFAULT_MAX_NEIGHBOURS`]) and the coverage, 0.4 of both segments instead
/// of the SSSM's 0.66 — what every fold chose in the nested leave-one-take-out of `cargo run --release --example
/// library` (by NMI on the library of the other takes; docs/library.md): another take repeats a motion less
/// exactly than a take repeats itself, and 0.66 left most clusters in one take.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct LibraryParams {
    /// Working frame rate (Hz).
    pub fps: f64,
    /// Frame offsets the features are stacked over.
    pub offsets: Vec<i32>,
    /// Scale every take's body to the reference body (takes of different actors then compare).
    pub body_scale: bool,
    /// Generalised search radius `R` (inches of the reference body); the stacked radius is `R·√|offsets|`.
    pub radius: f64,
    /// At most this many neighbours per working frame (the nearest).
    pub max_neighbours: usize,
    /// Slope limit ν of a valid warping path.
    pub nu: f64,
    /// Minimum frames a valid warping path covers.
    pub min_path_frames: usize,
    /// Fraction of both segments a path must cover to join them.
    pub coverage: f64,
}

/// The defaults SSSM's primitives use (Krüger et al. 2017: 30 Hz, offsets ±10 frames by 5, the reference body,
/// primitive radius 13 in, ν = 2, paths of 5 frames): the library matches as SSSM does within a take
/// (`tests/library.rs` keeps them equal to SSSM's defaults).
impl Default for LibraryParams {
    fn default() -> Self {
        LibraryParams {
            fps: 30.0,
            offsets: vec![-10, -5, 0, 5, 10],
            body_scale: true,
            radius: 13.0,
            max_neighbours: DEFAULT_MAX_NEIGHBOURS,
            nu: 2.0,
            min_path_frames: 5,
            coverage: 0.4,
        }
    }
}

impl LibraryParams {
    /// The settings label transfer uses by default: the library's defaults with a wider radius (30 in) and a looser
    /// coverage (0.4 of the unlabelled unit) — in the nested leave-one-source-out of `cargo run --release --example
    /// library` (docs/library.md) every fold chose coverage 0.4 and two of four radius 30 (the others 20 and 40):
    /// another take, often another actor, repeats a motion less exactly than a take repeats itself.
    pub fn for_transfer() -> LibraryParams {
        LibraryParams { radius: 30.0, coverage: 0.4, ..LibraryParams::default() }
    }

    /// The settings a transfer by `route` uses by default: [`Self::for_transfer`] for the nearest labelled unit;
    /// through the shared clusters radius 20 and coverage 0.4 (of both units) — what the nested leave-one-source-out
    /// chose (coverage 0.4 every fold, radius 20 two of four, 13 and 30 the others): wider radii merge the clusters
    /// into a few large ones that carry one label each.
    pub fn for_route(route: TransferRoute) -> LibraryParams {
        match route {
            TransferRoute::Nearest => Self::for_transfer(),
            TransferRoute::Clusters => LibraryParams { radius: 20.0, coverage: 0.4, ..Self::default() },
        }
    }

    /// Checks every value, naming the one that is wrong.
    pub fn check(&self) -> Result<(), LibraryError> {
        let bad = |name: &'static str, value: String, expected: &'static str| {
            Err(LibraryError::InvalidParam { name, value, expected })
        };
        if !(self.fps.is_finite() && self.fps >= 1.0 && self.fps <= 240.0) {
            return bad("fps", self.fps.to_string(), "a frame rate from 1 to 240 Hz");
        }
        if self.offsets.is_empty() || self.offsets.len() > 16 || self.offsets.iter().any(|o| o.unsigned_abs() > 1000) {
            return bad("offsets", format!("{:?}", self.offsets), "1 to 16 frame offsets within ±1000");
        }
        if !(self.radius.is_finite() && self.radius > 0.0) {
            return bad("radius", self.radius.to_string(), "a positive number of inches");
        }
        if !(1..=5000).contains(&self.max_neighbours) {
            return bad("max_neighbours", self.max_neighbours.to_string(), "1 to 5000");
        }
        if !(self.nu.is_finite() && self.nu >= 1.0) {
            return bad("nu", self.nu.to_string(), "a slope limit of at least 1");
        }
        if self.min_path_frames < 2 {
            return bad("min_path_frames", self.min_path_frames.to_string(), "at least 2 frames");
        }
        if !(self.coverage > 0.0 && self.coverage <= 1.0) {
            return bad("coverage", self.coverage.to_string(), "a fraction in (0, 1]");
        }
        Ok(())
    }

    /// The search radius in the stacked feature space, `R·√|offsets|`.
    pub fn stacked_radius(&self) -> f32 {
        (self.radius * (self.offsets.len() as f64).sqrt()) as f32
    }
}

/// What can go wrong with a library.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LibraryError {
    #[error("invalid library parameter {name} = {value}: expected {expected}")]
    InvalidParam { name: &'static str, value: String, expected: &'static str },
    #[error("{take}: {message}")]
    Take { take: String, message: String },
    #[error("the library has no takes")]
    Empty,
    #[error(
        "the library is too large to match at once: {frames} working frames × {max_neighbours} neighbours exceeds \
         {limit} entries; match fewer takes at a time or lower max_neighbours"
    )]
    TooLarge { frames: usize, max_neighbours: usize, limit: usize },
    #[error("take {take}: {message}")]
    Labels { take: String, message: String },
    #[error("cancelled")]
    Cancelled,
}

impl From<crate::method::Cancelled> for LibraryError {
    fn from(_: crate::method::Cancelled) -> Self {
        LibraryError::Cancelled
    }
}

/// Neighbours kept per working frame in a library (the SSSM keeps 600 within one take): 100 matched the four mocap6
/// takes as well as 600 did (docs/library.md measured both: the same shared clusters, label transfer 77 % held out
/// where 600 gave 75 %), and lets a library hold six times as much motion under [`MAX_ENTRIES`] — 200,000 working
/// frames, about 1.9 hours at 30 Hz.
pub const DEFAULT_MAX_NEIGHBOURS: usize = 100;

/// Upper bound on the library's `working frames × max_neighbours` (its neighbour lists are bounded as one take's
/// SSSM is).
pub const MAX_ENTRIES: usize = 20_000_000;

/// A take's features as the library keeps them: the SSSM's end-effector features at the working rate and where
/// each working frame lies in the file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TakeFeatures {
    /// Values per working frame (15: hands, feet, head relative to the hips, 3 each).
    pub dim: usize,
    /// Working frames × `dim` values, frame-major.
    pub values: Vec<f32>,
    /// Fractional file frame of every working frame.
    pub source_frames: Vec<f64>,
    /// Frames of the file.
    pub file_frames: usize,
    /// The file's frame rate.
    pub file_fps: f64,
}

impl TakeFeatures {
    /// The features of `motion` with `params` (its working rate and body scaling).
    pub fn of(motion: &Motion, params: &LibraryParams) -> Result<TakeFeatures, LibraryError> {
        params.check()?;
        let e = end_effectors(motion, params.fps, params.body_scale).map_err(|e| LibraryError::Take {
            take: motion.name.clone(),
            message: match e {
                EndEffectorError::MissingJoints(m) => {
                    format!("the library's features need hands, feet, head and hips: {m}")
                }
                other => other.to_string(),
            },
        })?;
        Ok(TakeFeatures {
            dim: e.base.dim(),
            values: e.base.as_slice().to_vec(),
            source_frames: e.source_frames,
            file_frames: motion.frames(),
            file_fps: motion.fps,
        })
    }

    /// Working frames.
    pub fn frames(&self) -> usize {
        self.values.len() / self.dim.max(1)
    }

    /// Bytes held (features and frame map).
    pub fn bytes(&self) -> usize {
        self.values.len() * 4 + self.source_frames.len() * 8
    }

    /// The features as a matrix (checked: a deserialised take may be damaged).
    pub fn matrix(&self) -> Result<FeatureMatrix, String> {
        if self.source_frames.len() != self.frames() {
            return Err(format!(
                "{} working frames of features but {} frame positions",
                self.frames(),
                self.source_frames.len()
            ));
        }
        FeatureMatrix::new(self.frames(), self.dim, self.values.clone()).map_err(|e| e.to_string())
    }

    fn working(&self) -> WorkingFrames<'_> {
        WorkingFrames { source: &self.source_frames, file_frames: self.file_frames }
    }
}

/// One take of a library: its name, its features and one method's segmentation of it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LibraryTake {
    pub name: String,
    pub features: TakeFeatures,
    pub segmentation: Segmentation,
}

impl LibraryTake {
    /// Checks that the segmentation is of this take (same number of file frames, valid).
    fn check(&self) -> Result<(), LibraryError> {
        let take = |message: String| LibraryError::Take { take: self.name.clone(), message };
        self.segmentation.validate().map_err(|e| take(format!("its segmentation: {e}")))?;
        if self.segmentation.frames != self.features.file_frames {
            return Err(take(format!(
                "the segmentation is of a take of {} frames, the take has {}",
                self.segmentation.frames, self.features.file_frames
            )));
        }
        if self.features.frames() == 0 {
            return Err(take("the take has no frames".into()));
        }
        Ok(())
    }
}

/// A unit of matching: the index of a segment of the take's segmentation and its frames at the working rate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Unit {
    pub segment: usize,
    pub span: Span,
}

/// The units of `segmentation` on the working frames of `features`: the finest tiling it gives — its primitives
/// and transitions if it has primitives, else its actions and transitions — in order, disjoint (a segment that
/// overlaps the one before starts after it; one left empty is dropped).
pub fn units(segmentation: &Segmentation, features: &TakeFeatures) -> Vec<Unit> {
    let has_primitives = segmentation.segments.iter().any(|s| s.level == Level::Primitive);
    let finest = |s: &Segment| match s.level {
        Level::Primitive => true,
        Level::Transition => true,
        Level::Action => !has_primitives,
    };
    let working = features.working();
    let mut chosen: Vec<(usize, Span)> = segmentation
        .segments
        .iter()
        .enumerate()
        .filter(|(_, s)| finest(s))
        .map(|(k, s)| (k, Span { start: working.working_frame(s.start), end: working.working_frame(s.end) }))
        .collect();
    chosen.sort_by_key(|(k, span)| (span.start, span.end, *k));
    let mut out: Vec<Unit> = Vec::with_capacity(chosen.len());
    for (segment, mut span) in chosen {
        if let Some(last) = out.last() {
            span.start = span.start.max(last.span.end + 1);
        }
        if span.start <= span.end {
            out.push(Unit { segment, span });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn seg(start: usize, end: usize, level: Level) -> Segment {
        Segment { start, end, label: String::new(), level, cluster: None, score: None, mirror_of: None, effort: None }
    }

    fn features(file_frames: usize, step: f64) -> TakeFeatures {
        let n = ((file_frames - 1) as f64 / step).floor() as usize + 1;
        TakeFeatures {
            dim: 1,
            values: vec![0.0; n],
            source_frames: (0..n).map(|k| k as f64 * step).collect(),
            file_frames,
            file_fps: 120.0,
        }
    }

    fn segmentation(frames: usize, segments: Vec<Segment>) -> Segmentation {
        Segmentation {
            file: "t.bvh".into(),
            fps: 120.0,
            frames,
            method: "test".into(),
            params: serde_json::json!({}),
            segments,
        }
    }

    #[test]
    fn units_are_the_finest_tiling_on_working_frames() {
        // 120 Hz file of 121 frames, working frames every 4 file frames (31 of them)
        let f = features(121, 4.0);
        let s = segmentation(
            121,
            vec![
                seg(0, 59, Level::Action),
                seg(0, 29, Level::Primitive),
                seg(30, 59, Level::Primitive),
                seg(60, 120, Level::Transition),
            ],
        );
        let u = units(&s, &f);
        assert_eq!(u.iter().map(|u| u.segment).collect::<Vec<_>>(), vec![1, 2, 3]);
        assert_eq!(u[0].span, Span { start: 0, end: 7 });
        assert_eq!(u[1].span, Span { start: 8, end: 15 });
        assert_eq!(u[2].span, Span { start: 16, end: 30 });
        // without primitives: the actions; overlapping gestures trimmed, one swallowed dropped
        let s =
            segmentation(121, vec![seg(0, 59, Level::Action), seg(40, 100, Level::Action), seg(44, 52, Level::Action)]);
        let u = units(&s, &f);
        assert_eq!(u.len(), 2);
        assert_eq!((u[0].segment, u[0].span), (0, Span { start: 0, end: 15 }));
        assert_eq!((u[1].segment, u[1].span), (1, Span { start: 16, end: 25 }));
    }

    #[test]
    fn parameters_are_checked_by_name() {
        assert!(LibraryParams::default().check().is_ok());
        let bad = LibraryParams { coverage: 0.0, ..LibraryParams::default() };
        assert!(matches!(bad.check(), Err(LibraryError::InvalidParam { name: "coverage", .. })));
        let bad = LibraryParams { offsets: vec![], ..LibraryParams::default() };
        assert!(matches!(bad.check(), Err(LibraryError::InvalidParam { name: "offsets", .. })));
        let bad = LibraryParams { fps: f64::NAN, ..LibraryParams::default() };
        assert_eq!(
            bad.check().unwrap_err().to_string(),
            "invalid library parameter fps = NaN: expected a frame rate from 1 to 240 Hz"
        );
    }
}
