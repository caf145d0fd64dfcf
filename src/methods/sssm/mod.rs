//! SSSM segmentation: Krüger, Vögele, Willig, Yao, Klein, Weber, "Efficient Unsupervised
//! Temporal Segmentation of Motion Data", IEEE Trans. Multimedia 19(4), 2017.
//!
//! A take is cut into actions (repetitive activities) and the transitions between them, each
//! action into motion primitives (its repetitions), and the primitives are clustered — without
//! being told how many of anything there are. One module per section of the paper:
//!
//! | step | paper | module |
//! |---|---|---|
//! | end-effector features, stacked over frame offsets | §IV-A | [`features`] |
//! | feature bundling (optional) | §III | [`bundling`] |
//! | radius search → sparse self-similarity matrix | §IV-A | [`neighbours`] |
//! | forward/backward region growing → actions, transitions | §IV-B | [`activities`] |
//! | merging actions by poses, boundaries at low motion (not in the paper) | after §IV-B | [`refine`] |
//! | neighbourhood graph, warping paths → primitives | §IV-C | [`primitives`] |
//! | mirrored features → phase-shifted primitives | §V | [`symmetry`] |
//! | cluster graph, strongly connected components | §VI | [`clustering`] |
//!
//! [`segment`] runs everything on a [`Motion`]; [`segment_features`] on a plain feature matrix
//! at the working frame rate. Parameters: [`SssmParams`].

pub mod activities;
pub mod bundling;
pub mod features;
pub mod image;
pub mod method;
pub mod params;
pub mod primitives;
pub mod refine;
pub mod symmetry;

use serde::{Deserialize, Serialize};

use crate::features::FeatureError;
use crate::method::Cancelled;
use crate::motion::{Motion, MotionError};
use crate::parallel;
use crate::segment::Segmentation;

pub use crate::similarity::clusters::Cluster;
pub use crate::similarity::neighbours::Sssm;
pub use crate::similarity::Span;
pub use activities::Activities;
pub use features::{FeatureMatrix, MirrorMap, MotionFeatures};
pub use params::{param_specs, BoundaryRule, BundlingOptimum, NeighbourSearchKind, SssmParams, ValidParams};
pub use symmetry::SymmetryKind;

use crate::similarity::clusters::ClusterSearch;
use crate::similarity::neighbours::{EntryBudget, FarSearch, NeighbourSearch, StackedSearch};
use crate::similarity::paths::NeighbourhoodGraph;
use activities::RegionGrowing;
use bundling::Bundling;
use method::to_segmentation;
use primitives::PrimitiveSearch;

/// Everything that can go wrong in the SSSM method.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SssmError {
    #[error("invalid SSSM parameter {name} = {value}: expected {expected}")]
    InvalidParam { name: &'static str, value: String, expected: &'static str },
    #[error("the take has no frames")]
    NoFrames,
    #[error("invalid features: {0}")]
    BadFeatures(String),
    #[error("invalid neighbour lists: {0}")]
    BadNeighbours(String),
    #[error("the SSSM features need hands, feet, head and hips: {0}")]
    MissingJoints(String),
    #[error("cannot prepare the take: {0}")]
    Motion(#[from] MotionError),
    /// The searches found more neighbour entries than the run's memory allows ([`EntryBudget`]).
    #[error(
        "the take's SSSM needs more memory than the budget leaves for it: its frames have more close neighbours \
         than the {limit} entries (about {mib} MiB) that fit — a take that repeats one motion for long or holds \
         still has the most; cut the take or lower max_neighbours (now {max_neighbours})"
    )]
    TooLarge { limit: usize, mib: usize, max_neighbours: usize },
    /// The progress callback returned `Err(Cancelled)`: the run stopped where it was.
    #[error("cancelled")]
    Cancelled,
}

/// The self-similarity matrix's error as the SSSM reports it (same messages).
impl From<crate::similarity::SimilarityError> for SssmError {
    fn from(e: crate::similarity::SimilarityError) -> Self {
        use crate::similarity::SimilarityError as E;
        match e {
            E::NoFrames => SssmError::NoFrames,
            E::BadFeatures(m) => SssmError::BadFeatures(m),
            E::BadNeighbours(m) => SssmError::BadNeighbours(m),
            E::Cancelled => SssmError::Cancelled,
        }
    }
}

/// A feature matrix's or mirror map's error as the SSSM reports it (same messages).
impl From<FeatureError> for SssmError {
    fn from(e: FeatureError) -> Self {
        match e {
            FeatureError::NoFrames => SssmError::NoFrames,
            FeatureError::Bad(message) => SssmError::BadFeatures(message),
        }
    }
}

impl From<Cancelled> for SssmError {
    fn from(_: Cancelled) -> Self {
        SssmError::Cancelled
    }
}

/// Bytes a run holds at its peak per neighbour entry its searches draw ([`EntryBudget`]): the
/// upper triangle as it grows, the symmetric SSSM made from it, the far entries and their merge,
/// the nearer neighbours and the graphs built on them. Measured with a counting allocator on takes
/// whose frames have the most neighbours (tests/limits.rs).
pub const BYTES_PER_ENTRY: usize = 32;

/// The entries a run may draw when no budget is given: the page's and the command line's 1 GiB.
pub fn default_entry_limit() -> usize {
    crate::method::WorkLimits::default().max_bytes / BYTES_PER_ENTRY
}

/// A motion primitive: frames `span` of action `action`, in cluster `cluster`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Primitive {
    pub span: Span,
    pub action: usize,
    pub cluster: usize,
}

/// An action with the kind of action it is (actions whose frames repeat each other's, see
/// [`activities::RegionGrowing::kinds`]) and its symmetry (§V).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Action {
    pub span: Span,
    pub cluster: usize,
    pub symmetry: SymmetryKind,
}

/// The method's full output at the working frame rate: the segments and what the page needs
/// to draw the SSSM (the neighbour lists, the regions, the cuts).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SssmOutcome {
    /// Working frame rate and number of working frames.
    pub fps: f64,
    pub frames: usize,
    /// The search radius `r` in feature units (inches for motion features).
    pub search_radius: f64,
    /// The SSSM (neighbours of every frame, main diagonal included).
    pub sssm: Sssm,
    /// The SSSM of the mirrored features against the original ones (§V), if used.
    pub mirror_sssm: Option<Sssm>,
    /// Region growing: forward regions, backward starts, actions, transitions.
    pub activities: Activities,
    pub actions: Vec<Action>,
    /// Cuts from the original features (first frames of primitives), ascending.
    pub cuts: Vec<usize>,
    /// Cuts from the mirrored features, ascending (those added to `cuts` and those not).
    pub mirror_cuts: Vec<usize>,
    pub primitives: Vec<Primitive>,
    pub clusters: Vec<Cluster>,
    /// With a search horizon: the action pairs `(earlier, later)` whose far SSSM blocks were
    /// searched and whether each linked its actions (see [`neighbours::far`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub far_pairs: Vec<(usize, usize, bool)>,
}

/// [`segment`]'s result: the segmentation at the file's frame rate plus the working-rate
/// details.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SssmResult {
    pub segmentation: Segmentation,
    pub outcome: SssmOutcome,
    /// Fractional file frame of every working frame (to map working frames to the file).
    pub source_frames: Vec<f64>,
    /// Feature units per file unit: inches per file unit times the body-size scale.
    pub feature_scale: f64,
}

/// Segments `motion` with `params` (see the module documentation).
pub fn segment(motion: &Motion, params: &SssmParams) -> Result<SssmResult, SssmError> {
    segment_with_progress(motion, params, &mut |_, _| Ok(()))
}

/// [`segment`], reporting `(stage, fraction done)` as it goes: at every stage boundary and
/// inside the neighbour search and the far blocks. When `progress` returns `Err(Cancelled)`
/// the run stops at once with [`SssmError::Cancelled`].
pub fn segment_with_progress(
    motion: &Motion,
    params: &SssmParams,
    progress: &mut dyn FnMut(&str, f64) -> Result<(), Cancelled>,
) -> Result<SssmResult, SssmError> {
    segment_valid(motion, &params.clone().check()?, default_entry_limit(), progress)
}

/// [`segment_with_progress`] on parameters already checked (the registered method's: checked
/// once by the registry, not again here), its searches drawing at most `max_entries` neighbour
/// entries ([`EntryBudget`]).
pub fn segment_valid(
    motion: &Motion,
    valid: &ValidParams,
    max_entries: usize,
    progress: &mut dyn FnMut(&str, f64) -> Result<(), Cancelled>,
) -> Result<SssmResult, SssmError> {
    progress("features", 0.0)?;
    let features = features::from_motion(motion, valid)?;
    let outcome = segment_features_within(&features.base, Some(&features.mirror), valid, max_entries, progress)?;
    let segmentation = to_segmentation(motion, valid, &outcome, &features.source_frames);
    Ok(SssmResult { segmentation, outcome, source_frames: features.source_frames, feature_scale: features.scale })
}

/// Runs the method on per-frame features `base` at the working rate `params.fps` (stacked
/// here over `params.offsets`). The mirror step (§V) runs if `params.mirror` is on and a
/// `mirror` map for `base` is given. Progress and cancelling as in [`segment_with_progress`].
pub fn segment_features(
    base: &FeatureMatrix,
    mirror: Option<&MirrorMap>,
    params: &ValidParams,
    progress: &mut dyn FnMut(&str, f64) -> Result<(), Cancelled>,
) -> Result<SssmOutcome, SssmError> {
    segment_features_within(base, mirror, params, default_entry_limit(), progress)
}

/// [`segment_features`] with its searches drawing at most `max_entries` neighbour entries: a take
/// whose frames have more neighbours than that is refused with [`SssmError::TooLarge`] as soon as
/// the searches pass it, having held no more than the budget.
pub fn segment_features_within(
    base: &FeatureMatrix,
    mirror: Option<&MirrorMap>,
    params: &ValidParams,
    max_entries: usize,
    progress: &mut dyn FnMut(&str, f64) -> Result<(), Cancelled>,
) -> Result<SssmOutcome, SssmError> {
    let mirror = checked_mirror(base, mirror, params)?;
    let too_large = || SssmError::TooLarge {
        limit: max_entries,
        mib: max_entries.saturating_mul(BYTES_PER_ENTRY) >> 20,
        max_neighbours: params.max_neighbours,
    };
    // why a search stopped: the budget, or the caller
    let stopped = |budget: &EntryBudget| if budget.spent() { too_large() } else { SssmError::Cancelled };
    // the bundling holds k neighbours of every frame besides the SSSM's
    let bundling_k = if params.bundling { params.bundling_k } else { 0 };
    if base.frames().saturating_mul(bundling_k) > max_entries {
        return Err(too_large());
    }
    let max_entries = max_entries - base.frames() * bundling_k;
    let radius = params.search_radius();
    let near_radius = params.primitive_search_radius() as f32;
    let (mut sssm, mut mirror_sssm, search) =
        neighbour_matrices(base, mirror, params, max_entries, &stopped, progress)?;

    // Region growing needs both SSSMs; the primitive and cluster graphs only the nearer
    // neighbours (see `primitive_radius`). Natively the kinds and the nearer neighbours are found
    // at once (`parallel::join`), as are the searches on the plain and on the mirror graph below.
    progress("activities", 0.5)?;
    let mut activities = region_growing(params, &sssm, mirror_sssm.as_ref()).activities(params.boundary_rule);
    if params.pose_merge > 0.0 || params.boundary_window_frames() > 0 {
        let band = params.band_frames();
        let merged = refine::merge_same_poses(base, &activities.actions, band, band, params.pose_merge);
        // body speed smoothed over ±0.1 s
        let speed = refine::body_speed(base, (params.fps * 0.1).round() as usize);
        activities.actions = refine::refine_boundaries(&merged, &speed, params.boundary_window_frames());
        activities.transitions = activities::gaps(base.frames(), &activities.actions);
    }
    let mut far_pairs = Vec::new();
    if let (Some(search), Some(horizon)) = (&search, params.horizon_frames()) {
        if horizon.saturating_add(1) < base.frames() {
            // with a horizon: the far blocks between actions that may repeat each other (and of
            // each long action), then kinds and clusters on the SSSM with them
            let grow = region_growing(params, &sssm, mirror_sssm.as_ref());
            let limits: Vec<Option<f32>> = activities.actions.iter().map(|&a| grow.repeat_limit(a)).collect();
            let far = FarSearch::new(search, horizon, radius as f32, params.max_neighbours, near_radius, params.fps);
            progress("far blocks", 0.5)?;
            let entries = far
                .search(&activities.actions, &limits, &mut |f| progress("far blocks", 0.5 + 0.08 * f))
                .map_err(|_| stopped(search.budget()))?;
            (sssm, mirror_sssm) = parallel::join(
                || sssm.with_far_entries(&entries.plain, params.max_neighbours),
                || mirror_sssm.as_ref().map(|m| m.with_far_entries(&entries.mirror, params.max_neighbours)),
            );
            far_pairs = entries.pairs;
        }
    }
    progress("kinds", 0.58)?;
    let grow = region_growing(params, &sssm, mirror_sssm.as_ref());
    let (kinds, (near, mirror_near)) = parallel::join(
        || grow.kinds(&activities.actions, grow.relative),
        || (sssm.within(near_radius), mirror_sssm.as_ref().map(|m| m.within(near_radius))),
    );
    let spans = activities.actions.clone();

    progress("primitives", 0.6)?;
    let (mut graph, mut mirror_graph) =
        parallel::join(|| NeighbourhoodGraph::new(&near), || mirror_near.as_ref().map(NeighbourhoodGraph::new));
    let prim_search = PrimitiveSearch {
        nu: params.nu,
        min_path_frames: params.min_path_frames,
        min_cut_distance: params.min_cut_distance,
    };
    let (main_cuts, mirror_cuts) = parallel::join(
        || cut_frames(&prim_search, Some(&mut graph), &spans),
        || cut_frames(&prim_search, mirror_graph.as_mut(), &spans),
    );
    let (primitive_spans, primitive_action, symmetry) =
        split_actions(&spans, &main_cuts, &mirror_cuts, mirror.is_some(), params.min_cut_distance);

    progress("clusters", 0.85)?;
    let cluster_search =
        ClusterSearch { nu: params.nu, min_path_frames: params.min_path_frames, coverage: params.cluster_coverage };
    // each graph moves to one thread (`&mut`: its work arrays are not shared)
    let (plain_graph, mirror_graph, spans_ref) = (&mut graph, mirror_graph.as_mut(), &primitive_spans);
    let (links, mirror_links) = parallel::join(
        move || cluster_search.links(plain_graph, spans_ref),
        move || mirror_graph.map_or(Vec::new(), |g| cluster_search.links(g, spans_ref)),
    );
    let cluster_of = ClusterSearch::clusters(primitive_spans.len(), &links);
    let clusters = ClusterSearch::describe(&cluster_of, &mirror_links);

    progress("done", 1.0)?;
    Ok(SssmOutcome {
        fps: params.fps,
        frames: base.frames(),
        search_radius: radius,
        actions: (0..spans.len())
            .map(|a| Action { span: spans[a], cluster: kinds[a], symmetry: symmetry[a] })
            .collect(),
        primitives: (0..primitive_spans.len())
            .map(|p| Primitive { span: primitive_spans[p], action: primitive_action[p], cluster: cluster_of[p] })
            .collect(),
        cuts: sorted_flat(main_cuts),
        mirror_cuts: sorted_flat(mirror_cuts),
        sssm,
        mirror_sssm,
        activities,
        clusters,
        far_pairs,
    })
}

/// Region growing (§IV-B) over `sssm` (and `mirror`, if `mirror_activities`) with `params`.
fn region_growing<'a>(params: &ValidParams, sssm: &'a Sssm, mirror: Option<&'a Sssm>) -> RegionGrowing<'a> {
    RegionGrowing {
        sssm,
        mirror: mirror.filter(|_| params.mirror_activities),
        band: params.band_frames(),
        stop_window: params.stop_window,
        min_entries: params.min_action_entries(),
        relative: (params.relative_gate > 0.0).then_some(params.relative_gate as f32),
    }
}

/// The SSSM of `base` and its mirror SSSM (§IV-A, §V) within `max_entries`, by the kd-tree (after the bundling,
/// when on) or the stacked search — which is returned too, for the far blocks; `stopped` says why a search stopped.
fn neighbour_matrices(
    base: &FeatureMatrix,
    mirror: Option<&MirrorMap>,
    params: &ValidParams,
    max_entries: usize,
    stopped: &dyn Fn(&EntryBudget) -> SssmError,
    progress: &mut dyn FnMut(&str, f64) -> Result<(), Cancelled>,
) -> Result<(Sssm, Option<Sssm>, Option<StackedSearch>), SssmError> {
    let radius = params.search_radius();
    if params.bundling || params.neighbour_search == NeighbourSearchKind::KdTree {
        let mut stacked = features::stack(base, &params.offsets);
        if params.bundling {
            progress("bundling", 0.05)?;
            let b =
                Bundling { k: params.bundling_k, variance: params.bundling_variance, optimum: params.bundling_optimum };
            stacked = b.bundle_with_progress(&stacked, &mut |f| progress("bundling", 0.05 + 0.25 * f))?;
        }
        progress("neighbours", 0.3)?;
        let search = NeighbourSearch::new(&stacked).with_entry_limit(max_entries);
        let share = if mirror.is_some() { 0.1 } else { 0.2 };
        let sssm = search
            .self_similarity_with_progress(radius as f32, params.max_neighbours, &mut |f| {
                progress("neighbours", 0.3 + share * f)
            })
            .map_err(|_| stopped(search.budget()))?;
        let mirror_sssm = match mirror {
            Some(m) => Some(
                search
                    .mirror_similarity_with_progress(
                        &m.apply(&stacked)?,
                        radius as f32,
                        params.max_neighbours,
                        &mut |f| progress("neighbours", 0.4 + 0.1 * f),
                    )
                    .map_err(|e| match SssmError::from(e) {
                        SssmError::Cancelled => stopped(search.budget()),
                        other => other,
                    })?,
            ),
            None => None,
        };
        Ok((sssm, mirror_sssm, None))
    } else {
        progress("neighbours", 0.3)?;
        let stacked = StackedSearch::new(base, &params.offsets, mirror)?
            .with_horizon(params.horizon_frames())
            .with_entry_limit(max_entries);
        let found = stacked
            .similarities_with_progress(radius as f32, params.max_neighbours, &mut |f| {
                progress("neighbours", 0.3 + 0.2 * f)
            })
            .map_err(|_| stopped(stacked.budget()))?;
        Ok((found.0, found.1, Some(stacked)))
    }
}

/// The mirror map to use: `None` if mirroring is off or no map is given; an error if it does
/// not fit the features.
fn checked_mirror<'m>(
    base: &FeatureMatrix,
    mirror: Option<&'m MirrorMap>,
    params: &ValidParams,
) -> Result<Option<&'m MirrorMap>, SssmError> {
    match mirror {
        Some(m) if params.mirror && m.dim() != base.dim() => Err(SssmError::BadFeatures(format!(
            "the mirror map is for {} values per frame, the features have {}",
            m.dim(),
            base.dim()
        ))),
        Some(m) if params.mirror => Ok(Some(m)),
        _ => Ok(None),
    }
}

/// The cut frames of each action on `graph` (no cuts without a graph).
fn cut_frames(search: &PrimitiveSearch, graph: Option<&mut NeighbourhoodGraph>, spans: &[Span]) -> Vec<Vec<usize>> {
    match graph {
        Some(g) => search.cuts(g, spans).into_iter().map(|c| c.into_iter().map(|c| c.frame).collect()).collect(),
        None => vec![Vec::new(); spans.len()],
    }
}

/// Splits every action at its cuts (original and mirror, §V): the primitive spans, the action
/// of each, and the symmetry of each action.
fn split_actions(
    spans: &[Span],
    main_cuts: &[Vec<usize>],
    mirror_cuts: &[Vec<usize>],
    mirrored: bool,
    min_cut_distance: usize,
) -> (Vec<Span>, Vec<usize>, Vec<SymmetryKind>) {
    let mut primitive_spans = Vec::new();
    let mut primitive_action = Vec::new();
    let mut kinds = Vec::with_capacity(spans.len());
    for (a, span) in spans.iter().enumerate() {
        let (main, mirror) = (&main_cuts[a], &mirror_cuts[a]);
        kinds.push(if mirrored { symmetry::classify(main, mirror, min_cut_distance) } else { SymmetryKind::Unchecked });
        for p in primitives::split(*span, &symmetry::merge_cuts(main, mirror, min_cut_distance)) {
            primitive_spans.push(p);
            primitive_action.push(a);
        }
    }
    (primitive_spans, primitive_action, kinds)
}

fn sorted_flat(cuts: Vec<Vec<usize>>) -> Vec<usize> {
    let mut all: Vec<usize> = cuts.into_iter().flatten().collect();
    all.sort_unstable();
    all
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn feature_errors_read_as_before_the_move() {
        let e = SssmError::from(FeatureMatrix::new(2, 2, vec![0.0; 3]).unwrap_err());
        assert_eq!(e, SssmError::BadFeatures("3 values do not make 2 frames of 2 values".into()));
        assert_eq!(e.to_string(), "invalid features: 3 values do not make 2 frames of 2 values");
        assert_eq!(SssmError::from(FeatureMatrix::new(0, 2, vec![]).unwrap_err()), SssmError::NoFrames);
        let m = MirrorMap::new(vec![0, 1], vec![1.0, 1.0]).unwrap();
        let wide = FeatureMatrix::from_rows(&[[1.0f32, 2.0, 3.0]]).unwrap();
        assert!(matches!(m.apply(&wide).map_err(SssmError::from), Err(SssmError::BadFeatures(_))));
    }
}
