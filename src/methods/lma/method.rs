//! LMA Effort segmentation behind the common [`Method`] interface, with the shipped (or a user's)
//! classifier family and one of two searches: `effort` (the default) — one chain of boundaries
//! where the family's Effort changes most ([`super::change`]), or `deviance` — the paper's: per
//! arm the deviance map, its troughs paired, the two arms merged ([`super::search`]). Every segment
//! carries its Effort; the Effort change or the deviance maps, and the Effort bars, are drawn for
//! the page.

use serde::{Deserialize, Serialize};

use super::body::{upper_body, Side};
use super::classifier::{effort, Assessor, EffortModel, Outputs};
use super::deviance::{exhaustive, pruned, slow_frames};
use super::features::{Kinematics, Pool};
use super::search::{merge_arms, pair, smooth, troughs, Arms, DevianceMap};
use super::supervised::resolve;
use crate::method::bounds::{self, NumberParam, Valid};
use crate::method::supervised::{Loaded, Training, TrainingAsk};
use crate::method::{
    Details, Method, MethodError, MethodInfo, MethodOutput, ModelStore, ParamKind, ParamSpec, Picture, Progress,
    RunOptions, Supervised, Supervision, Work,
};
use crate::motion::Motion;
use crate::segment::frames::WorkingFrames;
use crate::segment::{Effort, Level, Segment, Segmentation};

/// Parameters of the LMA segmentation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LmaParams {
    /// Assess every candidate segment instead of those between slow-hand frames only.
    pub exhaustive: bool,
    /// Shortest and longest segment (seconds).
    pub min_s: f64,
    pub max_s: f64,
    /// Pruned search: candidate boundaries are the local minima of either hand's speed below this
    /// (arm bones per second); the default is above any hand's speed, so every minimum of both
    /// hands is a candidate — the paper's density (63 boundaries in its 25 s take).
    pub prune_speed: f64,
    /// Standard deviation (seconds) of the Gaussian that smooths the row and column profiles.
    pub smooth_s: f64,
    /// A trough is kept when the profile then rises by more than this share of its spread.
    pub min_rise: f64,
    /// The two arms' segments whose both ends lie within this many seconds are merged.
    pub merge_s: f64,
    /// How segments are found: `effort` — where the family's Effort changes ([`super::change`]), `deviance` — the
    /// paper's troughs of the classifiers' disagreement ([`super::search`]).
    pub search: String,
    /// Effort search: a boundary is kept where its Effort change beats this quantile of the take's.
    pub quantile: f64,
    /// The classifier family: `shipped`, or the name a user's family was stored under.
    pub model: String,
}

impl Default for LmaParams {
    /// The paper's lengths (0.67–3.33 s) and pruning density (every hand-speed minimum of both
    /// hands: `prune_speed` above any hand's speed); `min_rise` and `merge_s` chosen, as the
    /// paper chose its granularity, by a grid search on `s` — on takes spliced from the five
    /// labelled takes (`cargo run --release --example tune_lma`, which also reports the
    /// leave-one-take-out figure: docs/methods/lma.md).
    fn default() -> Self {
        LmaParams {
            exhaustive: false,
            min_s: 0.67,
            max_s: 3.33,
            prune_speed: 100.0,
            smooth_s: 0.1,
            min_rise: 0.4,
            merge_s: 0.67,
            search: SEARCHES[0].into(),
            quantile: 0.6,
            model: SHIPPED_NAME.into(),
        }
    }
}

/// The `search` parameter's choices, the default first.
pub const SEARCHES: [&str; 2] = ["effort", "deviance"];

/// The `model` parameter's name for the shipped family.
pub const SHIPPED_NAME: &str = "shipped";

/// [`LmaParams`] that passed the check.
pub type ValidParams = Valid<LmaParams>;

pub const PARAMS: [NumberParam; 7] = [
    NumberParam {
        name: "min_s",
        min: 0.4,
        max: 5.0,
        unit: "s",
        help: "Shortest segment (the family's boundary shifts need at least 0.4 s).",
        basic: false,
    },
    NumberParam { name: "max_s", min: 0.5, max: 6.0, unit: "s", help: "Longest segment.", basic: false },
    NumberParam {
        name: "prune_speed",
        min: 0.01,
        max: 100.0,
        unit: "bones/s",
        help: "Pruned search: boundaries only where either hand's speed has a local minimum below this (the default, above any hand's speed: every minimum of both hands, the paper's density).",
        basic: true,
    },
    NumberParam {
        name: "smooth_s",
        min: 0.0,
        max: 1.0,
        unit: "s",
        help: "Standard deviation of the Gaussian that smooths the deviance profiles.",
        basic: false,
    },
    NumberParam {
        name: "min_rise",
        min: 0.0,
        max: 1.0,
        unit: "",
        help: "A trough of the deviance profile is kept when the profile then rises by more than this share of its spread.",
        basic: true,
    },
    NumberParam {
        name: "merge_s",
        min: 0.0,
        max: 2.0,
        unit: "s",
        help: "Deviance search: left- and right-arm segments with both ends this close become one.",
        basic: true,
    },
    NumberParam {
        name: "quantile",
        min: 0.0,
        max: 1.0,
        unit: "",
        help: "Effort search: a boundary is kept where the Effort changes more than at this share of the take's candidate boundaries (higher: fewer, surer boundaries).",
        basic: true,
    },
];

impl LmaParams {
    fn value(&self, name: &str) -> f64 {
        match name {
            "min_s" => self.min_s,
            "max_s" => self.max_s,
            "prune_speed" => self.prune_speed,
            "smooth_s" => self.smooth_s,
            "min_rise" => self.min_rise,
            "quantile" => self.quantile,
            _ => self.merge_s,
        }
    }

    pub fn check(self) -> Result<ValidParams, MethodError> {
        bounds::check("LMA", &PARAMS, |n| self.value(n))?;
        if self.max_s <= self.min_s {
            return Err(bounds::refuse("LMA", "max_s", self.max_s, &format!("more than min_s ({})", self.min_s)));
        }
        if !SEARCHES.contains(&self.search.trim()) {
            return Err(MethodError::param(
                "search",
                format!("LMA: search = `{}`: expected one of {}", self.search, SEARCHES.join(", ")),
            ));
        }
        Ok(Valid::checked(self))
    }
}

/// LMA Effort segmentation (Bouchard & Badler).
#[derive(Debug, Clone, Copy, Default)]
pub struct Lma;

impl Method for Lma {
    type Params = LmaParams;
    type Checked = Checked;

    fn info(&self) -> MethodInfo {
        MethodInfo {
            name: "lma".into(),
            short: "LMA".into(),
            paper: "Bouchard & Badler".into(),
            summary: "Gestures cut where the Laban Effort of 121 classifiers, each trained on shifted boundaries, \
                      changes (or, as the paper, where they agree); every segment with its Space, Time, Weight and Flow."
                .into(),
            auto_run: true,
        }
    }

    fn param_specs(&self) -> Vec<ParamSpec> {
        let d = LmaParams::default();
        let mut specs = bounds::specs(&PARAMS, |n| d.value(n));
        let help = "Assess every candidate segment (slower) instead of only those between slow-hand frames.";
        specs.insert(0, bounds::switch("exhaustive", help, d.exhaustive, true));
        specs.insert(
            0,
            ParamSpec {
                name: "search".into(),
                help:
                    "How segments are found: `effort` — boundaries where the classifiers' Effort changes most, chosen \
                       as one chain (the default: chosen by held-out scores, docs/methods/lma.md); `deviance` — the \
                       paper's troughs where the 121 shifted classifiers agree."
                        .into(),
                kind: ParamKind::Choice { options: SEARCHES.iter().map(|s| s.to_string()).collect() },
                default: serde_json::json!(SEARCHES[0]),
                unit: None,
                basic: true,
                at_most: None,
            },
        );
        specs.insert(
            0,
            ParamSpec {
                name: "model".into(),
                help: "The Effort classifier family: the one shipped with the app, or one you trained or loaded."
                    .into(),
                // the shipped family; a page adds the ones it stored
                kind: ParamKind::Choice { options: vec![SHIPPED_NAME.into()] },
                default: serde_json::json!(SHIPPED_NAME),
                unit: None,
                basic: true,
                at_most: None,
            },
        );
        specs
    }

    fn check(&self, params: LmaParams) -> Result<Checked, MethodError> {
        self.check_in(params, &ModelStore::default())
    }

    fn check_in(&self, params: LmaParams, models: &ModelStore) -> Result<Checked, MethodError> {
        let (model, shipped) = resolve(params.model.trim(), models)?;
        Ok(Checked { params: params.check()?, model, shipped })
    }

    fn supervision(&self) -> Option<Supervision> {
        Some(super::supervised::supervision())
    }

    fn supervised(&self) -> Option<&dyn Supervised> {
        Some(self)
    }

    fn echo(&self, params: &Checked) -> serde_json::Value {
        serde_json::to_value(&*params.params).unwrap_or_default()
    }

    fn work(&self, params: &Checked) -> Work {
        // per arm: the feature pool's prefix sums (4 per series) and range-extremum tables (2 per
        // doubling up to the longest shifted segment) of its 45 series, in f64, and the deviance
        // map (f32 per candidate length); besides, both arms' joints and kinematics (2 kB).
        // 15.6 kB per frame at the defaults, measured 15.6 kB on 1800 frames (tests/limits.rs)
        let fps = params.model.fps;
        let min_len = (params.params.min_s * fps).round() as usize;
        let max_len = (params.params.max_s * fps).round() as usize;
        let longest = max_len + 2 * params.model.max_shift + 1;
        let pool = super::features::pool_bytes_per_frame(longest);
        let map = 4 * (max_len.saturating_sub(min_len) + 1);
        Work::memory(fps, 2 * (pool + map) + 2_000, 8 << 20, "or lower max_s")
    }

    /// The Effort layer ([`super::layer`]) resamples the whole take to the family's rate and pools both arms'
    /// features for the longest segment and its shifts: what it holds grows with that segment, not with `max_s`.
    fn annotation_work(&self, params: &Checked, motion: &Motion, segments: &[Segment]) -> Work {
        let fps = params.model.fps;
        let to_working = |f: usize| (f as f64 * fps / motion.fps.max(f64::MIN_POSITIVE)).round() as usize;
        let longest = segments.iter().map(|s| to_working(s.end).saturating_sub(to_working(s.start))).max().unwrap_or(0);
        // saturating: a file rate near 0 makes a segment's working length overflow (found by the long_takes fuzz
        // target once it annotated); the work check then refuses the take by its rate
        let pool = super::features::pool_bytes_per_frame(longest.saturating_add(2 * params.model.max_shift + 1));
        Work::memory(fps, 2 * pool + 2_000, 8 << 20, "or annotate shorter segments")
    }

    fn run(
        &self,
        motion: &Motion,
        params: &Checked,
        options: &RunOptions,
        progress: &mut dyn Progress,
    ) -> Result<MethodOutput, MethodError> {
        let mut out = segment_with(&params.model, motion, &params.params, options, progress)?;
        if !params.shipped {
            out.details.summary += &format!(" · your classifiers ({})", params.model.origin);
        }
        Ok(out)
    }

    fn annotator(&self) -> Option<crate::method::Annotator> {
        Some(crate::method::Annotator { quality: "Effort".into(), params: vec!["model".into()] })
    }

    fn annotate(
        &self,
        motion: &Motion,
        params: &Checked,
        segments: &[Segment],
        progress: &mut dyn Progress,
    ) -> Result<crate::method::Annotations, MethodError> {
        let by =
            if params.shipped { "LMA, shipped family".to_string() } else { format!("LMA, {}", params.params.model) };
        super::layer::annotate(&params.model, motion, segments, by, progress)
    }
}

impl Supervised for Lma {
    fn read_model(&self, file: &str, bytes: &[u8]) -> Result<Loaded, MethodError> {
        super::supervised::read_model(file, bytes)
    }

    fn training_work(&self, options: &serde_json::Value) -> Result<Work, MethodError> {
        super::supervised::config_from_json(options)?;
        Ok(super::supervised::training_work())
    }

    fn start_training(&self, ask: TrainingAsk, progress: &mut dyn Progress) -> Result<Box<dyn Training>, MethodError> {
        super::supervised::start_training(ask, progress)
    }

    fn shipped_model(&self, name: &str, models: &ModelStore) -> Result<Loaded, MethodError> {
        let (model, _) = resolve(name, models)?;
        Ok(Loaded { info: super::supervised::model_info(name, &model), model })
    }

    fn model_details(&self, model: &Loaded) -> serde_json::Value {
        let Some(m) = model.model.downcast_ref::<EffortModel>() else { return serde_json::Value::Null };
        serde_json::json!({
            "kind": "lma",
            "name": model.info.name,
            "origin": m.origin,
            "fps": m.fps,
            "samples": m.samples,
            "max_shift": m.max_shift,
            "classifiers_per_factor": m.shifts(),
            "segment_frames": [m.min_len, m.max_len],
            "factors": m.factors.len(),
        })
    }
}

/// Checked LMA parameters: the search's, and the family they name.
pub struct Checked {
    pub params: ValidParams,
    pub model: std::sync::Arc<EffortModel>,
    /// The family is the shipped one.
    pub shipped: bool,
}

/// What the classifiers say about a take: both arms' feature pools and either their deviance maps
/// or the Effort change at the candidate boundaries, at the family's rate. The boundary search
/// ([`Analysis::find`]) only reads it, so the search's own parameters (`quantile`; `smooth_s`,
/// `min_rise`, `merge_s`) can be tried without assessing a segment again.
pub struct Analysis {
    pub fps: f64,
    pub min_len: usize,
    pub max_len: usize,
    /// Fractional file frame of every working frame.
    pub source_frames: Vec<f64>,
    pub file_frames: usize,
    pools: Vec<Pool>,
    /// The deviance search's maps: left arm, right arm (none in the Effort search).
    pub maps: Vec<(Side, DevianceMap)>,
    /// The Effort search's candidate boundaries (working frames, sorted) and their Effort change `g`.
    pub changes: Vec<(usize, f64)>,
    /// Each arm's hand path length up to every working frame (`travel[arm][t]`), to say which arm a segment moves.
    travel: [Vec<f64>; 2],
}

/// A segment the search found (working frames), its arms, mean deviance and mean output.
#[derive(Debug, Clone, PartialEq)]
pub struct Found {
    pub start: usize,
    pub end: usize,
    pub arms: Arms,
    pub deviance: f32,
    pub outputs: Outputs,
}

/// Both arms' deviance maps of `motion` (pruned or exhaustive as `params` say).
pub fn analyse(
    model: &EffortModel,
    motion: &Motion,
    params: &LmaParams,
    progress: &mut dyn Progress,
) -> Result<Analysis, MethodError> {
    progress.step("arms", 0.0)?;
    let fps = model.fps;
    let body = upper_body(motion, fps).map_err(|e| MethodError::Failed(e.to_string()))?;
    let min_len = ((params.min_s * fps).round() as usize).max(2 * model.max_shift + 2);
    let max_len = ((params.max_s * fps).round() as usize).max(min_len);
    let longest = max_len + 2 * model.max_shift + 1;
    // each hand's path length up to every frame (read from the arms, not a copy of them)
    let travel: [Vec<f64>; 2] = std::array::from_fn(|k| {
        let hand = body.arms[k].hand();
        let mut sum = 0.0;
        std::iter::once(0.0)
            .chain(hand.windows(2).map(|w| {
                sum += w[1].distance(w[0]);
                sum
            }))
            .take(hand.len())
            .collect()
    });
    // the pruned search's boundaries: slow minima of either hand, for both arms' maps
    let mut slow: Vec<usize> = Vec::new();
    if !params.exhaustive {
        for arm in &body.arms {
            let speed = smooth(&Kinematics::speed(arm.hand(), fps), 0.1 * fps);
            slow.extend(slow_frames(&speed, params.prune_speed));
        }
        slow.sort_unstable();
        slow.dedup();
    }
    let (pools, maps, changes) = if params.search.trim() == "effort" {
        let window = min_len;
        let pools: Vec<Pool> = body.arms.iter().map(|arm| Pool::of(arm, fps, longest.max(window + 1))).collect();
        let frames = body.arms[0].frames();
        let boundaries: Vec<usize> = if params.exhaustive { (1..frames.saturating_sub(1)).collect() } else { slow };
        let mut report = |f: f64| progress.step("Effort change", 0.05 + 0.85 * f);
        let g = super::change::strengths(model, &pools, &boundaries, window, &mut report)?;
        (pools, Vec::new(), boundaries.into_iter().zip(g).collect())
    } else {
        let mut maps = Vec::new();
        let mut pools = Vec::new();
        for (k, arm) in body.arms.iter().enumerate() {
            let pool = Pool::of(arm, fps, longest);
            let base = 0.05 + 0.45 * k as f64;
            let stage = format!("{} arm", arm.side.name());
            let mut report = |f: f64| progress.step(&stage, base + 0.4 * f);
            let map = if params.exhaustive {
                exhaustive(model, &pool, (min_len, max_len), &mut report)?
            } else {
                pruned(model, &pool, &slow, (min_len, max_len), &mut report)?
            };
            maps.push((arm.side, map));
            pools.push(pool);
        }
        (pools, maps, Vec::new())
    };
    Ok(Analysis {
        fps,
        min_len,
        max_len,
        source_frames: body.source_frames,
        file_frames: motion.frames(),
        pools,
        maps,
        changes,
        travel,
    })
}

impl Analysis {
    /// Candidate segments assessed, both arms (the deviance search), or candidate boundaries (the Effort search).
    pub fn assessed(&self) -> usize {
        self.maps.iter().map(|(_, m)| m.candidates().count()).sum::<usize>() + self.changes.len()
    }

    /// The Effort search's segments: the chain of boundaries whose Effort change beats the take's `quantile`.
    pub fn effort_segments(&self, params: &LmaParams) -> Vec<(usize, usize)> {
        let (b, g): (Vec<usize>, Vec<f64>) = self.changes.iter().copied().unzip();
        let frames = self.travel[0].len();
        let tau = super::change::relative_threshold(&g, params.quantile);
        super::change::chain(&b, &g, frames, (self.min_len, self.max_len), tau)
    }

    /// The Effort change at the candidate boundaries, drawn along the take (file frames; linear between candidates).
    pub fn change_curve(&self) -> crate::method::Curve {
        let mut values = vec![0.0f32; self.file_frames];
        let at = |b: usize| self.source_frames.get(b).copied().unwrap_or(0.0);
        for w in self.changes.windows(2) {
            let ((b0, g0), (b1, g1)) = (w[0], w[1]);
            let (f0, f1) = (at(b0).round() as usize, (at(b1).round() as usize).min(self.file_frames.saturating_sub(1)));
            for f in f0..=f1 {
                let u = if f1 > f0 { (f - f0) as f64 / (f1 - f0) as f64 } else { 0.0 };
                values[f] = (g0 + (g1 - g0) * u) as f32;
            }
        }
        crate::method::Curve {
            id: "effort-change".into(),
            title: "Effort change at candidate boundaries".into(),
            values,
        }
    }

    /// The Effort search drawn along the take: a stem per candidate boundary as high as its Effort change (grey), the
    /// take's threshold (blue line), the chosen boundaries (red stems).
    pub fn change_picture(&self, params: &LmaParams) -> Picture {
        let frames = self.travel[0].len().max(1);
        let (width, height) = (frames.clamp(1, 960), 90usize);
        let mut rgba = vec![250u8; width * height * 4];
        let (b, g): (Vec<usize>, Vec<f64>) = self.changes.iter().copied().unzip();
        let top = g.iter().copied().filter(|v| v.is_finite()).fold(0.0, f64::max).max(1e-9);
        let tau = super::change::relative_threshold(&g, params.quantile);
        let chosen: std::collections::BTreeSet<usize> =
            self.effort_segments(params).into_iter().flat_map(|(s, e)| [s, e]).collect();
        let x_of = |t: usize| (t * width / frames).min(width - 1);
        let y_of = |v: f64| height - 1 - ((v / top).clamp(0.0, 1.0) * (height - 4) as f64).round() as usize;
        let mut paint = |x: usize, y: usize, c: [u8; 3]| {
            let i = (y * width + x) * 4;
            rgba[i..i + 3].copy_from_slice(&c);
        };
        for (&t, &v) in b.iter().zip(&g) {
            let colour = if chosen.contains(&t) { [210, 35, 35] } else { [120, 124, 132] };
            for y in y_of(v)..height {
                paint(x_of(t), y, colour);
            }
        }
        for x in 0..width {
            paint(x, y_of(tau), [40, 90, 200]);
        }
        Picture {
            id: "effort-change".into(),
            title: "Effort change at candidate boundaries".into(),
            caption: format!(
                "Time across. At each candidate boundary a stem as high as the change of the classifiers' Effort from the \
                 {:.2} s before it to the {:.2} s after (grey); the blue line is the take's threshold (its {:.0} % \
                 quantile); red stems are the boundaries chosen, at least {:.2} s apart.",
                self.min_len as f64 / self.fps,
                self.min_len as f64 / self.fps,
                100.0 * params.quantile,
                self.min_len as f64 / self.fps
            ),
            width,
            height,
            rgba,
            frames_per_pixel: None,
        }
    }

    /// Which arms move in `start..=end`: the one whose hand travels further, or both when the other travels at
    /// least three quarters as far.
    fn moving(&self, start: usize, end: usize) -> Arms {
        let [l, r] = [0, 1].map(|k| self.travel[k][end] - self.travel[k][start]);
        if l.min(r) >= 0.75 * l.max(r) {
            Arms::Both
        } else if l > r {
            Arms::First
        } else {
            Arms::Second
        }
    }

    /// Each arm's segments: troughs of the smoothed row and column profiles paired start to end.
    pub fn arm_segments(&self, params: &LmaParams) -> Vec<Vec<(usize, usize)>> {
        let sigma = params.smooth_s * self.fps;
        self.maps
            .iter()
            .map(|(_, map)| {
                let (rows, cols) = map.profiles();
                let starts = troughs(&smooth(&rows, sigma), params.min_rise);
                let ends = troughs(&smooth(&cols, sigma), params.min_rise);
                pair(&starts, &ends, self.min_len, self.max_len)
            })
            .collect()
    }

    /// The segments found (the Effort search's chain, or both arms' deviance segments merged), each
    /// assessed by the family for its Effort.
    pub fn find(&self, model: &EffortModel, params: &LmaParams) -> Vec<Found> {
        let merged = if self.maps.is_empty() {
            self.effort_segments(params).into_iter().map(|(s, e)| (s, e, self.moving(s, e))).collect()
        } else {
            let arms = self.arm_segments(params);
            let within = (params.merge_s * self.fps).round() as usize;
            merge_arms(&arms[0], &arms[1], within)
        };
        // each arm's segments assessed together, in order, as each would be alone
        let mut assessor = Assessor::new(model);
        let mut assessed = [0, 1].map(|arm| {
            let reads = |arms: Arms| matches!((arm, arms), (_, Arms::Both) | (0, Arms::First) | (1, Arms::Second));
            let segments: Vec<(usize, usize)> =
                merged.iter().filter(|m| reads(m.2)).map(|&(start, end, _)| (start, end)).collect();
            let mut out = Vec::new();
            assessor.assess(&self.pools[arm], &segments, &mut out);
            out.into_iter()
        });
        merged
            .into_iter()
            .map(|(start, end, arms)| {
                let mut next = |arm: usize| assessed[arm].next().expect("one assessment per segment of the arm");
                let (deviance, outputs) = match arms {
                    Arms::First => next(0),
                    Arms::Second => next(1),
                    Arms::Both => {
                        let (l, r) = (next(0), next(1));
                        ((l.0 + r.0) / 2.0, std::array::from_fn(|k| (l.1[k] + r.1[k]) / 2.0))
                    }
                };
                Found { start, end, arms, deviance, outputs }
            })
            .collect()
    }

    /// Found segments as schema segments at the file's frame rate (level `primitive`, labelled by
    /// arm, `score` = mean deviance, with their Effort).
    pub fn to_file(&self, found: &[Found]) -> Vec<Segment> {
        let frames = WorkingFrames { source: &self.source_frames, file_frames: self.file_frames };
        found
            .iter()
            .filter_map(|f| {
                let label = match f.arms {
                    Arms::First => "left arm",
                    Arms::Second => "right arm",
                    Arms::Both => "both arms",
                };
                frames.to_file(Segment {
                    start: f.start,
                    end: f.end,
                    label: label.into(),
                    level: Level::Primitive,
                    cluster: None,
                    score: Some((f.deviance as f64 * 1000.0).round() / 1000.0),
                    mirror_of: None,
                    effort: Some(rounded(effort(&f.outputs))),
                })
            })
            .collect()
    }
}

/// The LMA segmentation of `motion` with the classifier family `model`.
pub fn segment_with(
    model: &EffortModel,
    motion: &Motion,
    params: &LmaParams,
    options: &RunOptions,
    progress: &mut dyn Progress,
) -> Result<MethodOutput, MethodError> {
    let analysis = analyse(model, motion, params, progress)?;
    progress.step("search", 0.9)?;
    let merged = analysis.find(model, params);
    let segments = analysis.to_file(&merged);
    let assessed = analysis.assessed();
    let mut pictures = Vec::new();
    if options.pictures {
        progress.step("pictures", 0.95)?;
        let arms = analysis.arm_segments(params);
        for ((side, map), segments) in analysis.maps.iter().zip(&arms) {
            pictures.push(deviance_picture(*side, map, segments));
        }
        if !analysis.changes.is_empty() {
            pictures.push(analysis.change_picture(params));
        }
        pictures.push(effort_picture(&segments, motion.frames()));
    }
    let count = |a: Arms| merged.iter().filter(|m| m.arms == a).count();
    let searched = if analysis.maps.is_empty() {
        format!(
            "Effort search ({}): {} where the {} classifiers' Effort may change",
            if params.exhaustive { "every frame" } else { "pruned" },
            crate::method::counted(assessed, "candidate boundary"),
            model.shifts()
        )
    } else {
        format!(
            "{} deviance search, {} assessed by {} classifiers",
            if params.exhaustive { "exhaustive" } else { "pruned" },
            crate::method::counted(assessed, "candidate segment"),
            model.shifts()
        )
    };
    let summary = format!(
        "{} ({} both arms, {} left, {} right) · {searched}",
        crate::method::counted(segments.len(), "gesture"),
        count(Arms::Both),
        count(Arms::First),
        count(Arms::Second),
    );
    let mut curves = Vec::new();
    if !analysis.changes.is_empty() {
        curves.push(analysis.change_curve());
    }
    let segmentation = Segmentation {
        file: motion.name.clone(),
        fps: motion.fps,
        frames: motion.frames(),
        method: "lma".into(),
        params: serde_json::to_value(params).unwrap_or_default(),
        segments,
    };
    Ok(MethodOutput { segmentation, details: Details { summary, pictures, curves, take_fit: None } })
}

pub(super) fn rounded(e: Effort) -> Effort {
    let r = |x: f64| (x * 1000.0).round() / 1000.0;
    Effort { space: r(e.space), time: r(e.time), weight: r(e.weight), flow: r(e.flow) }
}

/// Largest side of a drawn deviance map (pixels).
const MAP_PIXELS: usize = 480;

/// The start × end deviance map of one arm (the paper's Fig. 5): rows are start frames, columns
/// end frames, darker = the classifiers agree more; the chosen segments in red.
fn deviance_picture(arm: Side, map: &DevianceMap, segments: &[(usize, usize)]) -> Picture {
    let n = map.frames.max(1);
    let side = n.min(MAP_PIXELS);
    let px = |t: usize| (t * side / n).min(side - 1);
    let mut sums = vec![0.0f32; side * side];
    let mut counts = vec![0u32; side * side];
    for (s, e, d) in map.candidates() {
        let i = px(s) * side + px(e);
        sums[i] += d;
        counts[i] += 1;
    }
    // grey from the 2nd to the 98th percentile of the drawn values (a few extreme candidates,
    // e.g. at a T-pose, would otherwise leave everything else one shade)
    let mut drawn: Vec<f32> = (0..side * side).filter(|&i| counts[i] > 0).map(|i| sums[i] / counts[i] as f32).collect();
    drawn.sort_by(f32::total_cmp);
    let at = |q: f64| drawn.get(((drawn.len().max(1) - 1) as f64 * q).round() as usize).copied().unwrap_or(0.0);
    let (lo, hi) = (at(0.02), at(0.98));
    let span = (hi - lo).max(1e-6);
    let mut rgba = vec![255u8; side * side * 4];
    // the pruned search's few candidates are drawn as blocks, or they would be single pixels
    let filled = counts.iter().filter(|&&c| c > 0).count();
    let radius = if filled * 50 < side * side { 2isize } else { 0 };
    // a light backdrop marks where candidates could lie (the band), the rest stays white
    for y in 0..side {
        for x in 0..side {
            let (s, e) = (y * n / side, x * n / side);
            if e > s + map.min_len.saturating_sub(1) && e <= s + map.max_len + n / side {
                rgba[4 * (y * side + x)..4 * (y * side + x) + 3].copy_from_slice(&[236, 238, 242]);
            }
        }
    }
    for i in (0..side * side).filter(|&i| counts[i] > 0) {
        let v = ((sums[i] / counts[i] as f32 - lo) / span).clamp(0.0, 1.0);
        let grey = (30.0 + 200.0 * v) as u8;
        let (y, x) = ((i / side) as isize, (i % side) as isize);
        for dy in -radius..=radius {
            for dx in -radius..=radius {
                let (py, px) = (y + dy, x + dx);
                if (0..side as isize).contains(&py) && (0..side as isize).contains(&px) {
                    let k = (py as usize * side + px as usize) * 4;
                    rgba[k..k + 3].copy_from_slice(&[grey, grey, grey]);
                }
            }
        }
    }
    // each chosen segment: a red ring of radius 4 around its (start, end)
    for &(s, e) in segments {
        for dy in -4isize..=4 {
            for dx in -4isize..=4 {
                let r2 = dy * dy + dx * dx;
                if !(9..=20).contains(&r2) {
                    continue;
                }
                let (y, x) = (px(s) as isize + dy, px(e) as isize + dx);
                if (0..side as isize).contains(&y) && (0..side as isize).contains(&x) {
                    let i = (y as usize * side + x as usize) * 4;
                    rgba[i..i + 3].copy_from_slice(&[225, 25, 25]);
                }
            }
        }
    }
    let name = arm.name();
    Picture {
        id: format!("deviance-{name}"),
        title: format!("Deviance map, {name} arm"),
        caption: format!(
            "Mean deviance of the classifiers for every candidate segment of the {name} arm: start frame down, end \
             frame across (the band between the shortest and longest segment, shaded); darker = more agreement \
             (the pruned search assesses only segments between slow-hand frames: dots). Red: the segments chosen for \
             this arm (rings), before the arms are merged."
        ),
        width: side,
        height: side,
        rgba,
        frames_per_pixel: None,
    }
}

/// Effort bars: one row per factor along the take, each segment's span coloured from blue
/// (indulging) through grey (neutral) to red (condensing).
fn effort_picture(segments: &[Segment], frames: usize) -> Picture {
    let (width, row) = (frames.clamp(1, 960), 14usize);
    let height = 4 * row;
    let mut rgba = vec![245u8; width * height * 4];
    for s in segments {
        let Some(e) = s.effort else { continue };
        let (x0, x1) = (s.start * width / frames.max(1), (s.end * width / frames.max(1)).min(width - 1));
        for (k, v) in [e.space, e.time, e.weight, e.flow].into_iter().enumerate() {
            let colour = crate::segment::palette::effort_colour(v);
            for y in k * row + 1..(k + 1) * row - 1 {
                for x in x0..=x1 {
                    let i = (y * width + x) * 4;
                    rgba[i..i + 3].copy_from_slice(&colour);
                }
            }
        }
    }
    Picture {
        id: "effort".into(),
        title: "Effort of each segment".into(),
        caption: "Rows from top: Space (indirect … direct), Time (sustained … sudden), Weight (light … strong), Flow \
                  (free … bound); each segment's span from blue (indulging) through grey to red (condensing), time \
                  across."
            .into(),
        width,
        height,
        rgba,
        frames_per_pixel: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::method::NoProgress;

    /// The found segments' deviance and Effort, assessed together per arm, are those of each segment assessed
    /// alone on the arms it moves (both arms: the mean of the two), bit for bit, in both searches.
    #[test]
    fn found_segments_are_assessed_as_each_alone() {
        let model = &crate::methods::lma::shipped_model().unwrap();
        let text = std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/tests/fixtures/assimp_Boxing_Toes_100fps.bvh"
        ))
        .unwrap();
        let motion = Motion::from_bvh("boxing.bvh", &crate::bvh::parse(&text).unwrap()).unwrap();
        let mut arms = Vec::new();
        for search in ["effort", "deviance"] {
            let params = LmaParams { search: search.into(), ..LmaParams::default() };
            let analysis = analyse(model, &motion, &params, &mut NoProgress).unwrap();
            let found = analysis.find(model, &params);
            assert!(found.len() > 3, "{search}: {} segments", found.len());
            for f in &found {
                let [l, r] = [0, 1].map(|k| model.assess(&analysis.pools[k], f.start, f.end));
                let (d, m) = match f.arms {
                    Arms::First => l,
                    Arms::Second => r,
                    Arms::Both => ((l.0 + r.0) / 2.0, std::array::from_fn(|k| (l.1[k] + r.1[k]) / 2.0)),
                };
                assert_eq!((f.deviance.to_bits(), f.outputs.map(f32::to_bits)), (d.to_bits(), m.map(f32::to_bits)));
                arms.push(f.arms);
            }
        }
        for kind in [Arms::First, Arms::Second, Arms::Both] {
            assert!(arms.contains(&kind), "no segment of {kind:?} among {arms:?}");
        }
    }
}
