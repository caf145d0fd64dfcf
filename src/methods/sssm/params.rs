//! Parameters of the SSSM method (Krüger et al. 2017, §III–§VI) with the defaults of the paper
//! and of the authors' published code, checked once into [`ValidParams`].
//!
//! Where the paper and the authors' code disagree, the difference and which one the default
//! follows are noted here, by the paper's section:
//!
//! * **Radius.** The paper (§IV-A) defines a *generalized* radius `R` for one stacked pose and
//!   rescales it as `r = R·√(|w|·N)`. The authors' code uses `r = R·√|w|` (`|w|` = number of
//!   stacked frame offsets) with `R = 19` in inches: `R` is the radius for one whole
//!   end-effector pose (15 values), so the pose dimension `N` is already inside `R` and only the
//!   number of stacked poses enters. If every stacked pose is off by the same distance `d`, the
//!   stacked distance is `d·√|w|`, so `r = R·√|w|` accepts exactly the frames whose poses are on
//!   average within `R` of each other. [`ValidParams::search_radius`] is that `r`. The inches
//!   are those of a body of the reference size (`body_scale`, see `features`).
//! * **Stop window.** The paper says `w = 8`; the code uses `fps/6` = 5 frames at 30 Hz.
//! * **Minimum primitive length / cut distance.** The paper says 5 frames for both; the code
//!   uses `fps/2` and `fps/4`. The paper's values are the defaults.
//! * **Minimum action size.** Not in the paper; the code only accepts an activity region holding
//!   more than `4·fps` = 120 neighbour entries (`nn_min_blob_size`), which keeps a handful of
//!   chance similarities from making an action.
//!
//! Not in the paper, each measured on the five shared CMU takes (see `activities`):
//! `mirror_activities` (region growing counts mirror neighbours), `relative_gate` (a scan line
//! must repeat the region about as closely as the region repeats itself) and
//! `primitive_radius` (the primitive and cluster graphs use the nearer neighbours, `R_p = 13`,
//! so the diagonals of one action stay apart). Setting `mirror_activities: false`,
//! `relative_gate: 0`, `primitive_radius: 19`, `pose_merge: 0` gives the paper's method (bundling,
//! §III, is a switch of its own and off by default: it did not help on the shared takes).
//!
//! Chosen by leave-one-take-out on the five shared takes (for each take, the value with the best
//! mean F1@1s on the other four; the default is the value best on all five), see `refine`:
//! `pose_merge = 2` (merging by poses; chosen in 4 of 5 folds over {0, 1.5, 1.75, 2, 2.25, 2.5},
//! held-out F1@1s 0.88 / covering 0.81, against 0.87 / 0.84 in-sample for the old defaults);
//! `boundary_window_s = 0` (the refinement to the least body speed is off: 0 was chosen in every
//! fold over {0, 0.25, 0.5} s).

use serde::{Deserialize, Serialize};

use super::SssmError;
use crate::method::{ParamKind, ParamSpec};

/// How the action boundaries are placed from the two region-growing passes (§IV-B).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BoundaryRule {
    /// As in the paper and the authors' code: the backward pass restarts at every forward cut,
    /// so an action start is only found when at least `w` empty scan lines separate it from the
    /// previous action's end (the default: it measured best).
    Paper,
    /// The backward pass for each action may run past the previous action's end (it only
    /// counts neighbours inside its own action), and where the start of one action precedes
    /// the end of the previous one the boundary is put at the middle of that overlap. The
    /// stacked window and transition poses smear every end late and every start early by the
    /// same amount, so the middle should cancel that bias (see `activities`). It measured
    /// worse than `Paper` on the shared takes (F1@1s 0.82 against 0.87): where a transition
    /// resembles the action after it, that action's start runs far back.
    Midpoint,
}

/// How the SSSM's radius search runs (§IV-A); both give the same neighbour lists.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum NeighbourSearchKind {
    /// Exact search using how the features are stacked: per-frame distances summed along the
    /// diagonals (see `neighbours::stacked`). The default; needs unbundled features, so with
    /// `bundling` on the kd-tree runs instead.
    Stacked,
    /// kiddo kd-tree over the leading principal coordinates of the stacked features, every
    /// candidate checked in full (see `neighbours`).
    KdTree,
}

/// Which optimum the feature bundling moves a point to (§III, eq. 4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BundlingOptimum {
    /// The mode of the Gaussian kernel density with Scott's-rule bandwidth (the paper).
    Density,
    /// The geometric median of the neighbours (Weiszfeld iterations): what the authors' code
    /// converges to, because its kernel width `1/mean(d)` makes the Gaussian term vanish and
    /// leaves `k·mean(d)/√(2π)` as the objective.
    GeometricMedian,
}

/// Every parameter of the method; build with the setters, then [`SssmParams::check`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SssmParams {
    /// Frame rate the method works at; takes are resampled to it (the authors: 30 Hz).
    pub fps: f64,
    /// Frame offsets stacked into one feature vector (§IV-A), in frames at `fps`.
    pub offsets: Vec<i32>,
    /// Generalized radius `R` in inches (for a body of the reference size, see `body_scale`).
    pub radius: f64,
    /// Scale every take to the reference body size before searching (makes `R` work for
    /// children, giants and mislabelled units alike).
    pub body_scale: bool,
    /// Region growing stops after this many scan lines without new neighbours (§IV-B, `w`).
    pub stop_window: usize,
    /// At most this many neighbours per frame are kept (the nearest ones).
    pub max_neighbours: usize,
    /// Width in seconds of the band around the main diagonal removed before region growing.
    pub diagonal_band_s: f64,
    /// An activity region must hold more than this many neighbour entries per second of
    /// `fps` (the code's `nn_min_blob_size = 4·fps`).
    pub min_action_entries_per_fps: f64,
    /// How action boundaries are placed from the forward and backward passes.
    pub boundary_rule: BoundaryRule,
    /// Region growing also counts the neighbours from the mirrored features (§V), so an
    /// action that alternates sides (left kick, right kick) is repetitive from its first
    /// mirrored half-cycle on. Needs `mirror`.
    pub mirror_activities: bool,
    /// Relative gate of the region growing (not in the paper): after a few scan lines, a scan
    /// line only keeps a region growing if its nearest neighbour is within this factor of the
    /// region's median nearest-neighbour distance; the same factor decides when two actions
    /// repeat each other (merging neighbours, grouping kinds). 0 = off: every neighbour within
    /// `r` counts, as in the paper. See `activities` for why and how much it helps.
    pub relative_gate: f64,
    /// Generalized radius (inches) of the neighbourhoods the primitives and clusters are built
    /// from (§IV-C, §VI); the SSSM itself is searched at `radius`. At `radius` the diagonals of
    /// one action touch and merge into one component of the neighbourhood graph, so its cycles
    /// are not found (the authors' code gets thinner diagonals from its always-on feature
    /// bundling). Must not exceed `radius`.
    pub primitive_radius: f64,
    /// Warping paths must have a slope within `[1/ν, ν]` (§IV-C).
    pub nu: f64,
    /// Warping paths covering fewer frames than this are discarded (§IV-C).
    pub min_path_frames: usize,
    /// Candidate cuts closer than this many frames are merged, keeping the cheaper path; cuts
    /// this close to an action's border are dropped (§IV-C).
    pub min_cut_distance: usize,
    /// Feature bundling (§III) before the neighbour search.
    pub bundling: bool,
    /// Number of nearest neighbours used by the bundling (the authors' code: 32).
    pub bundling_k: usize,
    /// Fraction of the neighbours' variance the bundling's local PCA keeps (§III: 97.5 %).
    pub bundling_variance: f64,
    /// Optimum the bundling moves each point to.
    pub bundling_optimum: BundlingOptimum,
    /// Use the mirrored features to split phase-shifted primitives and pair clusters (§V).
    pub mirror: bool,
    /// How the radius search runs (same result either way; `stacked` is faster).
    pub neighbour_search: NeighbourSearchKind,
    /// A warping path links two primitives in the cluster graph only if it covers at least
    /// this fraction of both (§VI; the code's `coverage_clustering = 0.66`).
    pub cluster_coverage: f64,
    /// Search horizon in seconds (not in the paper; 0 = none, every pair is searched): the
    /// stacked radius search only pairs frames at most this far apart, and actions farther apart
    /// are compared through exactly searched far blocks (see `neighbours::far`), so the time grows
    /// with the take's length instead of its square. A take no longer than the horizon gets the
    /// paper's SSSM. The kd-tree search (`neighbour_search = "kd_tree"`, and with `bundling`)
    /// always searches every pair. 20 s: the segmentations of the five shared takes and of the
    /// four mocap6 takes joined into one (2 minutes) are the same as without a horizon.
    pub horizon_s: f64,
    /// Merging by poses (not in the paper; 0 = off): neighbouring actions at most
    /// `diagonal_band_s` apart are merged when the poses of each come as close to the other as
    /// within this factor of the other's own nearest-repeat distance (see `refine`): one
    /// activity whose direction changes (arm circles forward, then backward) is two SSSM blocks.
    pub pose_merge: f64,
    /// Boundary refinement (not in the paper; 0 = off): every action boundary moves to the frame
    /// of least body speed within this many seconds of it (see `refine`).
    pub boundary_window_s: f64,
}

impl Default for SssmParams {
    fn default() -> Self {
        SssmParams {
            fps: 30.0,
            offsets: vec![-10, -5, 0, 5, 10],
            radius: 19.0,
            body_scale: true,
            stop_window: 5,
            max_neighbours: 600,
            diagonal_band_s: 1.0,
            min_action_entries_per_fps: 4.0,
            boundary_rule: BoundaryRule::Paper,
            mirror_activities: true,
            relative_gate: 1.5,
            primitive_radius: 13.0,
            nu: 2.0,
            min_path_frames: 5,
            min_cut_distance: 5,
            bundling: false,
            bundling_k: 32,
            bundling_variance: 0.975,
            bundling_optimum: BundlingOptimum::Density,
            mirror: true,
            neighbour_search: NeighbourSearchKind::Stacked,
            cluster_coverage: 0.66,
            horizon_s: 20.0,
            pose_merge: 2.0,
            boundary_window_s: 0.0,
        }
    }
}

macro_rules! setter {
    ($(#[$doc:meta] $name:ident: $ty:ty),* $(,)?) => {
        $(
            #[$doc]
            pub fn $name(mut self, value: $ty) -> Self {
                self.$name = value;
                self
            }
        )*
    };
}

impl SssmParams {
    /// The defaults (same as `SssmParams::default()`).
    pub fn new() -> Self {
        Self::default()
    }

    setter! {
        /// Sets the working frame rate.
        fps: f64,
        /// Sets the generalized radius `R` (inches).
        radius: f64,
        /// Turns body-size scaling on or off.
        body_scale: bool,
        /// Sets the region-growing stop window `w` (frames).
        stop_window: usize,
        /// Sets the neighbour cap per frame.
        max_neighbours: usize,
        /// Sets the width of the removed diagonal band (seconds).
        diagonal_band_s: f64,
        /// Sets the minimum activity size (neighbour entries per frame of `fps`).
        min_action_entries_per_fps: f64,
        /// Sets the boundary rule.
        boundary_rule: BoundaryRule,
        /// Lets region growing count mirror neighbours too.
        mirror_activities: bool,
        /// Sets the relative gate of the region growing (0 = off).
        relative_gate: f64,
        /// Sets the generalized radius of the primitive and cluster graphs (inches).
        primitive_radius: f64,
        /// Sets the slope limit ν.
        nu: f64,
        /// Sets the minimum warping-path length (frames).
        min_path_frames: usize,
        /// Sets the minimum distance between cuts (frames).
        min_cut_distance: usize,
        /// Turns feature bundling on or off.
        bundling: bool,
        /// Sets the bundling's number of neighbours.
        bundling_k: usize,
        /// Sets the variance fraction kept by the bundling's local PCA.
        bundling_variance: f64,
        /// Sets the bundling optimum.
        bundling_optimum: BundlingOptimum,
        /// Turns the mirrored features (§V) on or off.
        mirror: bool,
        /// Chooses how the radius search runs.
        neighbour_search: NeighbourSearchKind,
        /// Sets the coverage a linking path needs in the cluster graph.
        cluster_coverage: f64,
        /// Sets the search horizon in seconds (0 = none).
        horizon_s: f64,
        /// Sets the factor of the merging by poses (0 = off).
        pose_merge: f64,
        /// Sets the window of the boundary refinement in seconds (0 = off).
        boundary_window_s: f64,
    }

    /// Sets the stacked frame offsets.
    pub fn offsets(mut self, offsets: impl Into<Vec<i32>>) -> Self {
        self.offsets = offsets.into();
        self
    }

    /// Validates every parameter; the method only ever runs on the result.
    pub fn check(self) -> Result<ValidParams, SssmError> {
        let p = self;
        let bad = |name: &'static str, value: f64, expected: &'static str| {
            // huge values in exponent form (1e300, not 301 digits)
            let value = if value.abs() >= 1e16 { format!("{value:e}") } else { value.to_string() };
            Err(SssmError::InvalidParam { name, value, expected })
        };
        if !(FPS.0..=FPS.1).contains(&p.fps) {
            return bad("fps", p.fps, "a frame rate between 1 and 1000");
        }
        if p.offsets.is_empty() {
            return Err(SssmError::InvalidParam {
                name: "offsets",
                value: "[]".into(),
                expected: "at least one frame offset",
            });
        }
        if p.offsets.len() > MAX_OFFSETS {
            return Err(SssmError::InvalidParam {
                name: "offsets",
                value: format!("{} offsets", p.offsets.len()),
                expected: "at most 32 frame offsets",
            });
        }
        if let Some(&o) = p.offsets.iter().find(|o| o.unsigned_abs() > MAX_OFFSET) {
            return bad("offsets", o as f64, "offsets between -300 and 300 frames");
        }
        let mut sorted = p.offsets.clone();
        sorted.sort_unstable();
        if sorted.windows(2).any(|w| w[0] == w[1]) {
            return Err(SssmError::InvalidParam {
                name: "offsets",
                value: format!("{:?}", p.offsets),
                expected: "distinct frame offsets",
            });
        }
        if !(p.radius.is_finite() && p.radius > 0.0) {
            return bad("radius", p.radius, "a positive radius in inches");
        }
        if !(RADIUS.0..=RADIUS.1).contains(&p.radius) {
            return bad("radius", p.radius, "a radius between 0.1 and 1000 inches");
        }
        if p.stop_window == 0 {
            return bad("stop_window", 0.0, "a stop window of at least 1 frame");
        }
        if p.stop_window > MAX_STOP_WINDOW {
            return bad("stop_window", p.stop_window as f64, "a stop window of at most 300 frames");
        }
        if p.max_neighbours == 0 {
            return bad("max_neighbours", 0.0, "at least 1 neighbour per frame");
        }
        if p.max_neighbours > MAX_NEIGHBOURS {
            return bad("max_neighbours", p.max_neighbours as f64, "at most 5000 neighbours per frame");
        }
        if !(DIAGONAL_BAND_S.0..=DIAGONAL_BAND_S.1).contains(&p.diagonal_band_s) {
            return bad("diagonal_band_s", p.diagonal_band_s, "a band between 0 and 60 seconds");
        }
        if !(MIN_ACTION_ENTRIES_PER_FPS.0..=MIN_ACTION_ENTRIES_PER_FPS.1).contains(&p.min_action_entries_per_fps) {
            return bad("min_action_entries_per_fps", p.min_action_entries_per_fps, "a number between 0 and 1000");
        }
        if !(p.relative_gate == 0.0 || (RELATIVE_GATE.0..=RELATIVE_GATE.1).contains(&p.relative_gate)) {
            return bad("relative_gate", p.relative_gate, "0 (off) or a factor ≥ 1, at most 100");
        }
        if !(p.primitive_radius >= RADIUS.0 && p.primitive_radius <= p.radius) {
            return bad("primitive_radius", p.primitive_radius, "a radius of at least 0.1 inches, at most `radius`");
        }
        if !(NU.0..=NU.1).contains(&p.nu) {
            return bad("nu", p.nu, "a slope limit ν ≥ 1, at most 100");
        }
        if !(MIN_PATH_FRAMES.0..=MIN_PATH_FRAMES.1).contains(&p.min_path_frames) {
            return bad("min_path_frames", p.min_path_frames as f64, "a minimum path length between 2 and 3000 frames");
        }
        if !(MIN_CUT_DISTANCE.0..=MIN_CUT_DISTANCE.1).contains(&p.min_cut_distance) {
            return bad("min_cut_distance", p.min_cut_distance as f64, "a cut distance between 1 and 3000 frames");
        }
        if !(BUNDLING_K.0..=BUNDLING_K.1).contains(&p.bundling_k) {
            return bad("bundling_k", p.bundling_k as f64, "between 2 and 256 neighbours for the bundling");
        }
        if !(FRACTION.0..=FRACTION.1).contains(&p.bundling_variance) {
            return bad("bundling_variance", p.bundling_variance, "a fraction between 0.01 and 1");
        }
        if !(FRACTION.0..=FRACTION.1).contains(&p.cluster_coverage) {
            return bad("cluster_coverage", p.cluster_coverage, "a fraction between 0.01 and 1");
        }
        if !(p.horizon_s == 0.0 || (MIN_HORIZON_S..=MAX_HORIZON_S).contains(&p.horizon_s)) {
            return bad("horizon_s", p.horizon_s, "0 (no horizon) or at least 5 seconds, at most 3600");
        }
        if !(p.pose_merge == 0.0 || (POSE_MERGE.0..=POSE_MERGE.1).contains(&p.pose_merge)) {
            return bad("pose_merge", p.pose_merge, "0 (off) or a factor ≥ 1, at most 100");
        }
        if !(BOUNDARY_WINDOW_S.0..=BOUNDARY_WINDOW_S.1).contains(&p.boundary_window_s) {
            return bad("boundary_window_s", p.boundary_window_s, "a window between 0 (off) and 10 seconds");
        }
        Ok(ValidParams(p))
    }
}

/// Shortest accepted search horizon in seconds: region growing needs a few repetitions of an
/// activity inside the horizon.
pub const MIN_HORIZON_S: f64 = 5.0;
/// Longest accepted search horizon in seconds (an hour: longer takes exceed the entry budget,
/// [`EntryBudget`](crate::similarity::neighbours::EntryBudget), anyway).
pub const MAX_HORIZON_S: f64 = 3600.0;

// The accepted ranges `(min, max)`, both included, of the other numeric parameters; the
// messages of `check` and the ranges of `param_specs` are these.
const FPS: (f64, f64) = (1.0, 1000.0);
/// 0.1 inch: no two poses are ever that close; 1000 inches: every pose of any take is within.
const RADIUS: (f64, f64) = (0.1, 1000.0);
/// 10 s at 30 Hz.
const MAX_STOP_WINDOW: usize = 300;
/// Largest neighbour cap per frame (the default is 600; more only costs memory).
pub const MAX_NEIGHBOURS: usize = 5000;
const DIAGONAL_BAND_S: (f64, f64) = (0.0, 60.0);
const MIN_ACTION_ENTRIES_PER_FPS: (f64, f64) = (0.0, 1000.0);
/// Beside 0 (off).
const RELATIVE_GATE: (f64, f64) = (1.0, 100.0);
const NU: (f64, f64) = (1.0, 100.0);
/// Frames; 3000 is 100 s at 30 Hz (and 3 s at the highest `fps`).
const MIN_PATH_FRAMES: (usize, usize) = (2, 3000);
/// Frames; at least 1 so that no cut falls on an action's border (an empty primitive).
const MIN_CUT_DISTANCE: (usize, usize) = (1, 3000);
/// The bundling holds `k` neighbours of every frame (counted in the entry budget).
pub const BUNDLING_K: (usize, usize) = (2, 256);
/// Beside 0 (off): below 1 an action's frames would have to repeat the other action more
/// closely than they repeat their own.
const POSE_MERGE: (f64, f64) = (1.0, 100.0);
/// Seconds; 10 s is longer than any transition of the shared takes.
const BOUNDARY_WINDOW_S: (f64, f64) = (0.0, 10.0);
/// `bundling_variance` and `cluster_coverage`.
const FRACTION: (f64, f64) = (0.01, 1.0);

/// Largest accepted |offset| in frames.
pub const MAX_OFFSET: u32 = 300;
/// Largest accepted number of stacked offsets.
pub const MAX_OFFSETS: usize = 32;

/// One [`ParamSpec`] per field of [`SssmParams`], in the order of the fields, with exactly the
/// ranges [`SssmParams::check`] accepts (so a page can build its form from them).
pub fn param_specs() -> Vec<ParamSpec> {
    let d = serde_json::to_value(SssmParams::default()).unwrap_or(serde_json::Value::Null);
    let spec = |name: &str, help: &str, kind: ParamKind, unit: Option<&str>, basic: bool| ParamSpec {
        name: name.into(),
        help: help.into(),
        kind,
        default: d[name].clone(),
        unit: unit.map(Into::into),
        basic,
        at_most: None,
    };
    let mut specs = activity_specs(&spec);
    specs.extend(primitive_specs(&spec));
    specs
}

/// A row of the table: name, help, kind, unit, whether the basic form shows it (its default is the field's).
type Row<'a> = dyn Fn(&str, &str, ParamKind, Option<&str>, bool) -> ParamSpec + 'a;

fn number((min, max): (f64, f64)) -> ParamKind {
    ParamKind::Number { min, max }
}

fn integer((min, max): (usize, usize)) -> ParamKind {
    ParamKind::Integer { min: min as i64, max: max as i64 }
}

fn choice(options: &[&str]) -> ParamKind {
    ParamKind::Choice { options: options.iter().map(|&o| o.into()).collect() }
}

const FRAMES: Option<&str> = Some("frames");
const INCHES: Option<&str> = Some("in");

/// The rows of the features, the neighbour search and the activities (§III–IV-B).
fn activity_specs(spec: &Row) -> Vec<ParamSpec> {
    vec![
        spec("fps", "Frame rate the method works at; takes are resampled to it.", number(FPS), Some("Hz"), false),
        spec(
            "offsets",
            "Frame offsets stacked into one feature vector (§IV-A), distinct.",
            ParamKind::IntegerList { min: -(MAX_OFFSET as i64), max: MAX_OFFSET as i64, max_len: MAX_OFFSETS },
            FRAMES,
            true,
        ),
        spec("radius", "Generalized radius R of the neighbour search (§IV-A).", number(RADIUS), INCHES, true),
        spec("body_scale", "Scale every take to the reference body size first.", ParamKind::Bool, None, false),
        spec(
            "stop_window",
            "Region growing stops after this many scan lines without new neighbours (§IV-B, w).",
            integer((1, MAX_STOP_WINDOW)),
            FRAMES,
            false,
        ),
        spec(
            "max_neighbours",
            "At most this many neighbours per frame are kept (the nearest).",
            integer((1, MAX_NEIGHBOURS)),
            None,
            false,
        ),
        spec(
            "diagonal_band_s",
            "Width of the band around the main diagonal removed before region growing.",
            number(DIAGONAL_BAND_S),
            Some("s"),
            false,
        ),
        spec(
            "min_action_entries_per_fps",
            "An activity region must hold more than this many neighbour entries per second.",
            number(MIN_ACTION_ENTRIES_PER_FPS),
            None,
            false,
        ),
        spec(
            "boundary_rule",
            "How action boundaries are placed from the forward and backward passes (§IV-B).",
            choice(&["paper", "midpoint"]),
            None,
            false,
        ),
        spec(
            "mirror_activities",
            "Region growing also counts the mirror neighbours (§V); needs mirror.",
            ParamKind::Bool,
            None,
            false,
        ),
        spec(
            "relative_gate",
            "Relative gate of the region growing: 0 = off (the paper), else a factor from 1 to 100.",
            number((0.0, RELATIVE_GATE.1)),
            None,
            false,
        ),
    ]
}

/// The rows of the primitives, the clusters and what SSSM adds to the paper (§IV-C–VI).
fn primitive_specs(spec: &Row) -> Vec<ParamSpec> {
    vec![
        spec(
            "primitive_radius",
            "Generalized radius of the primitive and cluster graphs (§IV-C, §VI); at most radius.",
            number(RADIUS),
            INCHES,
            false,
        )
        .at_most("radius"),
        spec("nu", "Warping paths must have a slope within [1/ν, ν] (§IV-C).", number(NU), None, false),
        spec(
            "min_path_frames",
            "Warping paths covering fewer frames than this are discarded (§IV-C).",
            integer(MIN_PATH_FRAMES),
            FRAMES,
            false,
        ),
        spec(
            "min_cut_distance",
            "Cuts closer than this are merged, and cuts this close to an action's border dropped (§IV-C).",
            integer(MIN_CUT_DISTANCE),
            FRAMES,
            false,
        ),
        spec("bundling", "Feature bundling (§III) before the neighbour search.", ParamKind::Bool, None, true),
        spec("bundling_k", "Number of nearest neighbours used by the bundling.", integer(BUNDLING_K), None, false),
        spec(
            "bundling_variance",
            "Fraction of the neighbours' variance the bundling's local PCA keeps (§III).",
            number(FRACTION),
            None,
            false,
        ),
        spec(
            "bundling_optimum",
            "Optimum the bundling moves each point to.",
            choice(&["density", "geometric_median"]),
            None,
            false,
        ),
        spec(
            "mirror",
            "Use the mirrored features to split primitives and pair clusters (§V).",
            ParamKind::Bool,
            None,
            true,
        ),
        spec(
            "neighbour_search",
            "How the radius search runs (same result; stacked is faster).",
            choice(&["stacked", "kd_tree"]),
            None,
            false,
        ),
        spec(
            "cluster_coverage",
            "A path links two primitives only if it covers at least this fraction of both (§VI).",
            number(FRACTION),
            None,
            false,
        ),
        spec(
            "horizon_s",
            "Search horizon: 0 = none (every pair is searched), else 5 to 3600 seconds.",
            number((0.0, MAX_HORIZON_S)),
            Some("s"),
            true,
        ),
        spec(
            "pose_merge",
            "Merge neighbouring actions whose poses repeat each other: 0 = off, else a factor from 1 to 100.",
            number((0.0, POSE_MERGE.1)),
            None,
            false,
        ),
        spec(
            "boundary_window_s",
            "Move each action boundary to the least body speed within this window (0 = off).",
            number(BOUNDARY_WINDOW_S),
            Some("s"),
            false,
        ),
    ]
}

/// Parameters that passed [`SssmParams::check`], with the derived quantities in frames.
#[derive(Debug, Clone, PartialEq)]
pub struct ValidParams(SssmParams);

impl std::ops::Deref for ValidParams {
    type Target = SssmParams;
    fn deref(&self) -> &SssmParams {
        &self.0
    }
}

impl ValidParams {
    /// The checked parameters.
    pub fn params(&self) -> &SssmParams {
        &self.0
    }

    /// The search radius `r = R·√|w|` in the stacked feature space (see the module docs).
    pub fn search_radius(&self) -> f64 {
        self.0.radius * (self.0.offsets.len() as f64).sqrt()
    }

    /// The search radius of the primitive and cluster graphs, `R_p·√|w|`.
    pub fn primitive_search_radius(&self) -> f64 {
        self.0.primitive_radius * (self.0.offsets.len() as f64).sqrt()
    }

    /// Half-width of the removed main-diagonal band in frames: entries with `|i − j| < band`
    /// are ignored by the region growing (`floor(fps · diagonal_band_s)`, 30 at the defaults).
    pub fn band_frames(&self) -> usize {
        (self.0.fps * self.0.diagonal_band_s).floor() as usize
    }

    /// The search horizon in frames (`None`: no horizon, every pair is searched).
    pub fn horizon_frames(&self) -> Option<usize> {
        (self.0.horizon_s > 0.0).then(|| (self.0.fps * self.0.horizon_s).round() as usize)
    }

    /// Half-width of the boundary refinement's window in frames (0: off).
    pub fn boundary_window_frames(&self) -> usize {
        (self.0.fps * self.0.boundary_window_s).round() as usize
    }

    /// Minimum number of neighbour entries an activity region must exceed.
    pub fn min_action_entries(&self) -> usize {
        (self.0.fps * self.0.min_action_entries_per_fps).floor() as usize
    }

    /// The parameters as JSON, as echoed in a segmentation's `params`.
    pub fn to_json(&self) -> serde_json::Value {
        serde_json::to_value(&self.0).unwrap_or(serde_json::Value::Null)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err_of(p: SssmParams) -> String {
        p.check().expect_err("must be rejected").to_string()
    }

    #[test]
    fn defaults_are_the_papers_and_the_authors_code_values() {
        let v = SssmParams::default().check().unwrap();
        assert_eq!(v.offsets, vec![-10, -5, 0, 5, 10]);
        assert!((v.search_radius() - 19.0 * 5f64.sqrt()).abs() < 1e-12);
        assert_eq!(v.band_frames(), 30);
        assert_eq!(v.stop_window, 5);
        assert_eq!(v.max_neighbours, 600);
        assert_eq!(v.min_action_entries(), 120);
        assert_eq!(v.nu, 2.0);
        assert_eq!(v.min_path_frames, 5);
        assert_eq!(v.min_cut_distance, 5);
        assert_eq!(v.horizon_frames(), Some(600));
        assert_eq!(SssmParams::new().horizon_s(0.0).check().unwrap().horizon_frames(), None);
        assert_eq!(SssmParams::new().fps(60.0).check().unwrap().horizon_frames(), Some(1200));
    }

    #[test]
    fn each_bad_value_is_named_in_the_message() {
        assert!(err_of(SssmParams::new().radius(0.0)).contains("radius"));
        assert!(err_of(SssmParams::new().radius(f64::NAN)).contains("radius"));
        assert!(err_of(SssmParams::new().offsets(vec![])).contains("at least one frame offset"));
        assert!(err_of(SssmParams::new().offsets(vec![0, 5, 5])).contains("distinct"));
        assert!(err_of(SssmParams::new().offsets(vec![0, 1000])).contains("-300 and 300"));
        assert!(err_of(SssmParams::new().stop_window(0)).contains("stop_window"));
        assert!(err_of(SssmParams::new().max_neighbours(0)).contains("max_neighbours"));
        assert!(err_of(SssmParams::new().nu(0.5)).contains("ν ≥ 1"));
        assert!(err_of(SssmParams::new().fps(0.0)).contains("fps"));
        assert!(err_of(SssmParams::new().horizon_s(-1.0)).contains("horizon_s"));
        assert!(err_of(SssmParams::new().horizon_s(3.0)).contains("at least 5 seconds"));
        assert!(err_of(SssmParams::new().horizon_s(f64::INFINITY)).contains("horizon_s"));
        assert!(err_of(SssmParams::new().diagonal_band_s(-1.0)).contains("diagonal_band_s"));
        assert!(err_of(SssmParams::new().min_path_frames(1)).contains("min_path_frames"));
        assert!(err_of(SssmParams::new().bundling_k(1)).contains("bundling_k"));
        assert!(err_of(SssmParams::new().bundling_variance(1.5)).contains("bundling_variance"));
        assert!(err_of(SssmParams::new().cluster_coverage(0.0)).contains("cluster_coverage"));
        assert!(err_of(SssmParams::new().relative_gate(0.5)).contains("relative_gate"));
        assert!(err_of(SssmParams::new().pose_merge(0.5)).contains("pose_merge"));
        assert!(err_of(SssmParams::new().pose_merge(f64::NAN)).contains("pose_merge"));
        assert!(err_of(SssmParams::new().boundary_window_s(-0.1)).contains("boundary_window_s"));
        assert!(SssmParams::new().pose_merge(0.0).boundary_window_s(0.0).check().is_ok());
        assert!(err_of(SssmParams::new().primitive_radius(25.0)).contains("at most `radius`"));
        assert!(SssmParams::new().relative_gate(0.0).check().is_ok());
    }

    #[test]
    fn every_numeric_parameter_has_an_upper_bound() {
        // the bound itself passes, just beyond it is refused, with the field named
        let ok = |p: SssmParams| assert!(p.clone().check().is_ok(), "{p:?} refused");
        ok(SssmParams::new().radius(1000.0).primitive_radius(0.1));
        ok(SssmParams::new().stop_window(300).max_neighbours(5000).min_action_entries_per_fps(1000.0));
        ok(SssmParams::new().relative_gate(100.0).nu(100.0).min_path_frames(3000).min_cut_distance(3000));
        ok(SssmParams::new().bundling_k(256).bundling_variance(0.01).cluster_coverage(0.01).horizon_s(3600.0));
        ok(SssmParams::new().pose_merge(100.0).boundary_window_s(10.0));
        let refused = [
            (SssmParams::new().radius(1000.5), "radius"),
            (SssmParams::new().radius(0.09).primitive_radius(0.09), "radius"),
            (SssmParams::new().primitive_radius(0.05), "primitive_radius"),
            (SssmParams::new().stop_window(301), "stop_window"),
            (SssmParams::new().max_neighbours(5001), "max_neighbours"),
            (SssmParams::new().min_action_entries_per_fps(1000.5), "min_action_entries_per_fps"),
            (SssmParams::new().min_action_entries_per_fps(f64::INFINITY), "min_action_entries_per_fps"),
            (SssmParams::new().relative_gate(101.0), "relative_gate"),
            (SssmParams::new().nu(100.5), "nu"),
            (SssmParams::new().nu(f64::NAN), "nu"),
            (SssmParams::new().min_path_frames(3001), "min_path_frames"),
            (SssmParams::new().min_cut_distance(0), "min_cut_distance"),
            (SssmParams::new().min_cut_distance(usize::MAX), "min_cut_distance"),
            (SssmParams::new().bundling_k(257), "bundling_k"),
            (SssmParams::new().bundling_k(usize::MAX), "bundling_k"),
            (SssmParams::new().bundling_variance(0.005), "bundling_variance"),
            (SssmParams::new().cluster_coverage(0.005), "cluster_coverage"),
            (SssmParams::new().horizon_s(3600.5), "horizon_s"),
            (SssmParams::new().horizon_s(1e300), "horizon_s"),
            (SssmParams::new().pose_merge(100.5), "pose_merge"),
            (SssmParams::new().boundary_window_s(10.5), "boundary_window_s"),
            (SssmParams::new().boundary_window_s(f64::INFINITY), "boundary_window_s"),
        ];
        for (p, name) in refused {
            let e = err_of(p);
            assert!(e.starts_with(&format!("invalid SSSM parameter {name} = ")), "{e}");
            assert!(e.contains(": expected "), "{e}");
        }
    }

    /// `SssmParams::default()` with `name` set to `value` (through the JSON, as a form would).
    fn with(name: &str, value: serde_json::Value) -> Result<ValidParams, String> {
        let mut json = serde_json::to_value(SssmParams::default()).unwrap();
        json[name] = value;
        // primitive_radius may not exceed radius: try each with the other at its extreme
        match name {
            "primitive_radius" => json["radius"] = json!(RADIUS.1),
            "radius" => json["primitive_radius"] = json!(RADIUS.0),
            _ => {}
        }
        let p: SssmParams = serde_json::from_value(json).map_err(|e| e.to_string())?;
        p.check().map_err(|e| e.to_string())
    }

    use serde_json::json;

    #[test]
    fn the_specs_are_the_fields_with_the_bounds_check_enforces() {
        let specs = param_specs();
        let fields = serde_json::to_value(SssmParams::default()).unwrap();
        let names: Vec<&str> = specs.iter().map(|s| s.name.as_str()).collect();
        assert_eq!(names.len(), 25);
        assert_eq!(names.len(), fields.as_object().unwrap().len());
        let basic: Vec<&str> = specs.iter().filter(|s| s.basic).map(|s| s.name.as_str()).collect();
        assert_eq!(basic, ["offsets", "radius", "bundling", "mirror", "horizon_s"]);
        for s in &specs {
            assert_eq!(s.default, fields[&s.name], "{}", s.name);
            assert!(!s.help.is_empty() && s.help.len() <= 100, "{}: {}", s.name, s.help);
            let name = s.name.as_str();
            let pass = |v: serde_json::Value| assert!(with(name, v.clone()).is_ok(), "{name} = {v} refused");
            let fail = |v: serde_json::Value| {
                let e = with(name, v.clone()).expect_err(&format!("{name} = {v} accepted"));
                // refused by check with the field named, or already by the JSON's types
                assert!(
                    e.starts_with(&format!("invalid SSSM parameter {name} = ")) || !e.starts_with("invalid"),
                    "{e}"
                );
            };
            pass(s.default.clone());
            match &s.kind {
                ParamKind::Number { min, max } => {
                    pass(json!(min));
                    pass(json!(max));
                    fail(json!(max + 1e-6 * max.abs().max(1.0)));
                    fail(json!(min - 1e-6 * min.abs().max(1.0)));
                }
                ParamKind::Integer { min, max } => {
                    pass(json!(min));
                    pass(json!(max));
                    fail(json!(max + 1));
                    fail(json!(min - 1));
                }
                ParamKind::IntegerList { min, max, max_len } => {
                    pass(json!([min, 0, max]));
                    fail(json!([min - 1, 0]));
                    fail(json!([0, max + 1]));
                    pass(json!((0..*max_len as i64).collect::<Vec<_>>()));
                    fail(json!((0..*max_len as i64 + 1).collect::<Vec<_>>()));
                }
                ParamKind::Choice { options } => {
                    options.iter().for_each(|o| pass(json!(o)));
                    fail(json!("none of them"));
                }
                ParamKind::Flags { options } => {
                    pass(json!(options));
                    fail(json!(["none of them"]));
                }
                ParamKind::Bool => {
                    pass(json!(true));
                    pass(json!(false));
                }
            }
        }
        // specs serialize with their kind tagged
        let radius = serde_json::to_value(&specs[2]).unwrap();
        assert_eq!(radius["kind"], json!({"type": "number", "min": 0.1, "max": 1000.0}));
        assert_eq!(radius["unit"], "in");
    }

    #[test]
    fn params_round_trip_through_json_and_reject_unknown_fields() {
        let p = SssmParams::new().radius(15.0).mirror(false).offsets(vec![-5, 0, 5]);
        let v = p.clone().check().unwrap().to_json();
        assert_eq!(v["radius"], 15.0);
        assert_eq!(v["boundary_rule"], "paper");
        assert_eq!(v["relative_gate"], 1.5);
        assert_eq!(v["pose_merge"], 2.0);
        assert_eq!(v["boundary_window_s"], 0.0);
        let back: SssmParams = serde_json::from_value(v).unwrap();
        assert_eq!(back, p);
        let partial: SssmParams = serde_json::from_str(r#"{"radius": 11}"#).unwrap();
        assert_eq!(partial.radius, 11.0);
        assert_eq!(partial.offsets, vec![-10, -5, 0, 5, 10]);
        assert!(serde_json::from_str::<SssmParams>(r#"{"radius_": 11}"#).is_err());
    }

    #[test]
    fn band_scales_with_the_frame_rate() {
        let v = SssmParams::new().fps(60.0).check().unwrap();
        assert_eq!(v.band_frames(), 60);
        assert_eq!(v.min_action_entries(), 240);
    }
}
