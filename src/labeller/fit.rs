//! Take fit: whether a labelling model's classes can describe a take at all (not in the paper).
//!
//! A model labels every frame with one of the classes it was taught, and its confidence says
//! which of *those* a frame is most like, not whether it is like any of them: the `exercises`
//! models paint a walk as Jog or Squat at a mean confidence of 0.99. Two measures of the take
//! against the model's training data say when it is outside what the model knows:
//!
//! * **Travel** — how fast the body moves across the floor (the hips' horizontal speed over 1 s,
//!   in inches of the reference body per second). The models' inputs are hip-relative, so a walk
//!   and jogging on the spot look alike to them; the training takes' travel (the largest of their 99th percentiles,
//!   [`TravelProfile`], stored in the model's header when it is made) says how fast any frame the
//!   model was taught moved.
//! * **Pose** — how far the take's ±1 s windows lie from the nearest training window (the k-NN's
//!   own distance, [`Windows::nearest_distances`]) compared with how far training windows lie from the
//!   *other* training windows 2 s or more away ([`Windows::familiar_distances`]): a new take of the
//!   taught movements lies about as far as another repetition does. A DT-FCN model is measured
//!   with the k-NN model made from the same data (the same data hash), when there is one.
//!
//! A run with the fit check labels every frame of a take that does not fit `unknown` and says why
//! ([`TakeFit::describe`]). A frame is *unfamiliar* when it travels faster than every training take's 99th percentile or its
//! window lies farther than the familiar distances' 95th percentile. The take does not fit when
//! more than [`TRAVEL_SHARE_LIMIT`] of its frames travel too fast, or its median distance is more
//! than [`POSE_RATIO_LIMIT`] times the familiar median. Both limits were set by hand on the table in
//! docs/methods/dtfcn.md ("Take fit", `cargo run --release --example take_fit`): four exercise
//! takes are too few for a nested choice, and the table shows the margins either side.

use serde::{Deserialize, Serialize};

use crate::features::end_effectors::REFERENCE_BODY_INCHES;
use crate::method::{FittingModel, TakeFitReport};
use crate::motion::normalize::{body_size, to_inches, to_y_up};
use crate::motion::Motion;

/// Windows of training motion a take's windows are measured against: how far each of a take's windows lies from
/// its nearest training window, and how far training windows lie from the other training windows `gap` working
/// frames or more away (`samples` of them). The k-NN labeller's windows are these (its model file holds them).
pub trait Windows {
    /// Per file frame of `motion`, its window's distance to the nearest training window; `None` once `go` (asked
    /// with the share done) answers false.
    fn nearest_distances(&self, motion: &Motion, go: crate::method::Go) -> Result<Option<Vec<f32>>, String>;
    fn familiar_distances(&self, gap: usize, samples: usize) -> Vec<f32>;
    /// Per file frame of `motion` given class `labels[f]`: the open-set unknown's score
    /// ([`crate::labeller::openset`]; the k-NN's `Knn::voted_ratios_going`); `None` once `go` answers false.
    fn voted_ratios(
        &self,
        motion: &Motion,
        labels: &[Option<usize>],
        go: crate::method::Go,
    ) -> Result<Option<Vec<f32>>, String>;
    /// Multiply-adds of [`TakeFit::assess`]'s search, at most: per working frame of a take, and besides (the familiar
    /// distances, [`FAMILIAR_SAMPLES`] windows each against every training window).
    fn search_ops(&self) -> (f64, f64);
}

/// The training frames' percentile a frame must travel faster than to be unfamiliar.
pub const TRAVEL_PERCENTILE: f64 = 0.99;
/// The familiar distances' percentile a window must lie beyond to be unfamiliar.
pub const POSE_PERCENTILE: f64 = 0.95;
/// A take whose frames travel faster than the training frames in more than this share does not fit.
pub const TRAVEL_SHARE_LIMIT: f64 = 0.25;
/// A take whose median nearest distance is more than this many familiar medians does not fit.
pub const POSE_RATIO_LIMIT: f64 = 2.0;
/// Working frames (30 Hz) a familiar window lies at least from the one it is measured for.
pub const FAMILIAR_GAP: usize = 60;
/// At most this many training windows are measured for the familiar distances (each against every
/// training window: 400 × 3,700 distances for the `exercises` models).
pub const FAMILIAR_SAMPLES: usize = 400;

/// How fast the training takes travelled (stored in a model's header).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TravelProfile {
    /// The training frames' median horizontal hip speed, reference-body inches per second.
    pub median: f32,
    /// Their [`TRAVEL_PERCENTILE`] speed: faster frames are unfamiliar.
    pub limit: f32,
}

/// Per file frame of `motion`: the hips' horizontal speed over the second around it, in inches of
/// the reference body per second (the body's size scaled out, as every threshold in inches here).
pub fn travel_speeds(motion: &Motion) -> Result<Vec<f32>, String> {
    let n = motion.frames();
    if n == 0 {
        return Err(format!("{}: the take has no frames", motion.name));
    }
    let map = motion.joint_map().map_err(|e| format!("{}: {e}", motion.name))?;
    let inches = to_inches(motion.units);
    let body = body_size(&motion.skeleton, &map) * inches;
    if !(body.is_finite() && body > 0.0) {
        return Err(format!("{}: the skeleton's body size is {body} inches", motion.name));
    }
    let scale = inches * REFERENCE_BODY_INCHES / body;
    let floor: Vec<(f64, f64)> = (0..n)
        .map(|f| {
            let p = to_y_up(motion.position(f, map.hips), motion.up_axis);
            (p.x as f64, p.z as f64)
        })
        .collect();
    // at most the take (a frame time of 1e-300 s makes half a second 5e299 frames: `f + half` overflowed)
    let half = ((0.5 * motion.fps).round() as usize).clamp(1, n);
    Ok((0..n)
        .map(|f| {
            let (a, b) = (f.saturating_sub(half), (f + half).min(n - 1));
            if b == a {
                return 0.0;
            }
            let (dx, dz) = (floor[b].0 - floor[a].0, floor[b].1 - floor[a].1);
            (dx.hypot(dz) * scale * motion.fps / (b - a) as f64) as f32
        })
        .collect())
}

/// The value at `q` (0..1) of sorted `values` (0 for none).
fn quantile(sorted: &[f32], q: f64) -> f32 {
    if sorted.is_empty() {
        return 0.0;
    }
    sorted[((sorted.len() - 1) as f64 * q).round() as usize]
}

fn sorted(mut v: Vec<f32>) -> Vec<f32> {
    v.retain(|x| x.is_finite());
    v.sort_by(f32::total_cmp);
    v
}

impl TravelProfile {
    /// The travel of the frames of `takes` the model is taught (`taught[i]`: those of take `i`;
    /// all of a take when `None`). The limit is the largest of the takes' own
    /// [`TRAVEL_PERCENTILE`] speeds, not the pooled frames': one fast walk among slow ones is
    /// taught too (pooled, a short fast take's frames fall past the percentile of the long ones).
    pub fn fit(takes: &[(&Motion, Option<&[bool]>)]) -> Result<TravelProfile, String> {
        let mut all = Vec::new();
        let mut limit = f32::NEG_INFINITY;
        for (motion, taught) in takes {
            let speeds = travel_speeds(motion)?;
            let own = sorted(match taught {
                Some(t) => speeds.iter().zip(t.iter()).filter(|(_, &t)| t).map(|(s, _)| *s).collect(),
                None => speeds,
            });
            if !own.is_empty() {
                limit = limit.max(quantile(&own, TRAVEL_PERCENTILE));
            }
            all.extend(own);
        }
        let all = sorted(all);
        if all.is_empty() {
            return Err("no training frames to measure travel on".into());
        }
        Ok(TravelProfile { median: quantile(&all, 0.5), limit })
    }
}

/// How a take lies against a model's training data (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct TakeFit {
    /// Share of the take's frames travelling faster than the model's training frames (`None`: the
    /// model's header has no travel profile).
    pub travel_share: Option<f64>,
    /// The training travel limit used, reference-body inches per second.
    pub travel_limit: Option<f32>,
    /// The take's median nearest-window distance over the familiar median (`None`: no k-NN
    /// windows of the model's data).
    pub pose_ratio: Option<f64>,
    /// Per file frame: unlike anything the model was taught (by either measure).
    pub unfamiliar: Vec<bool>,
}

impl TakeFit {
    /// Measures `motion` against a model's travel profile and (when given) the k-NN windows of its data.
    pub fn assess(
        motion: &Motion,
        travel: Option<&TravelProfile>,
        windows: Option<&dyn Windows>,
    ) -> Result<TakeFit, String> {
        Self::assess_going(motion, travel, windows, &mut |_| true)?.ok_or_else(|| "stopped".to_string())
    }

    /// [`TakeFit::assess`], asking `go` (the share of the windows' search done) as it searches: `None` once it
    /// answers false (a run's cancel).
    pub fn assess_going(
        motion: &Motion,
        travel: Option<&TravelProfile>,
        windows: Option<&dyn Windows>,
        go: crate::method::Go,
    ) -> Result<Option<TakeFit>, String> {
        let mut unfamiliar = vec![false; motion.frames()];
        let mut travel_share = None;
        if let Some(profile) = travel {
            let speeds = travel_speeds(motion)?;
            for (u, s) in unfamiliar.iter_mut().zip(&speeds) {
                *u |= *s > profile.limit;
            }
            travel_share = Some(speeds.iter().filter(|&&s| s > profile.limit).count() as f64 / speeds.len() as f64);
        }
        let mut pose_ratio = None;
        if let Some(knn) = windows {
            let familiar = knn.familiar_distances(FAMILIAR_GAP, FAMILIAR_SAMPLES);
            let Some(distances) = knn.nearest_distances(motion, go)? else { return Ok(None) };
            let limit = quantile(&familiar, POSE_PERCENTILE);
            for (u, d) in unfamiliar.iter_mut().zip(&distances) {
                *u |= *d > limit;
            }
            let familiar_median = quantile(&familiar, 0.5) as f64;
            let median = quantile(&sorted(distances), 0.5) as f64;
            pose_ratio = Some(if familiar_median > 0.0 {
                median / familiar_median
            } else if median > 0.0 {
                f64::INFINITY
            } else {
                0.0
            });
        }
        Ok(Some(TakeFit { travel_share, travel_limit: travel.map(|t| t.limit), pose_ratio, unfamiliar }))
    }

    /// Whether the model's classes can describe the take (true when nothing was measured).
    pub fn fits(&self) -> bool {
        self.travel_share.is_none_or(|s| s <= TRAVEL_SHARE_LIMIT)
            && self.pose_ratio.is_none_or(|r| r <= POSE_RATIO_LIMIT)
    }

    /// Whether anything was measured.
    pub fn measured(&self) -> bool {
        self.travel_share.is_some() || self.pose_ratio.is_some()
    }

    /// Why the take does not fit, one phrase per measure past its limit (none when it fits).
    pub fn reasons(&self) -> Vec<String> {
        let mut why = Vec::new();
        if let (Some(s), Some(limit)) = (self.travel_share, self.travel_limit) {
            if s > TRAVEL_SHARE_LIMIT {
                why.push(format!(
                    "{:.0} % of its frames travel faster than any of the model's training takes did ({limit:.0} in/s)",
                    100.0 * s
                ));
            }
        }
        if let Some(r) = self.pose_ratio.filter(|&r| r > POSE_RATIO_LIMIT) {
            why.push(format!("its poses lie {r:.1} times as far from the training poses as a new repetition does"));
        }
        why
    }

    /// One sentence for a run's summary: why the take does not fit model `name`, or that it does.
    pub fn describe(&self, name: &str) -> String {
        let why = self.reasons();
        if why.is_empty() {
            let mut parts = Vec::new();
            if let Some(s) = self.travel_share {
                parts.push(format!("{:.0} % of frames travel beyond its training takes", 100.0 * s));
            }
            if let Some(r) = self.pose_ratio {
                parts.push(format!("poses {r:.1}× as far as a new repetition"));
            }
            format!("the take fits model `{name}` ({})", parts.join(", "))
        } else {
            format!(
                "model `{name}` does not fit this take: {}; its classes cannot describe it, so every frame is \
                 labelled unknown (fit_check = false shows its labels anyway)",
                why.join(" and ")
            )
        }
    }

    /// The verdict on model `name` as data, with the other models that fit the take (`fitting`,
    /// best first: [`rank_fitting`]; `None`: they were not measured).
    pub fn report(&self, name: &str, fitting: Option<Vec<FittingModel>>) -> TakeFitReport {
        let fits = self.fits();
        let searched = fitting.is_some();
        let fitting = fitting.unwrap_or_default();
        TakeFitReport {
            model: name.to_string(),
            fits,
            travel_share: self.travel_share,
            travel_limit: self.travel_limit,
            pose_ratio: self.pose_ratio,
            reason: self.reasons().join(" and "),
            fitting: if fits { Vec::new() } else { fitting },
            searched: searched && !fits,
        }
    }
}

/// The models a take fits, best first: the lowest pose ratio (nearest to the training poses; a
/// model whose poses were not measured after those that were), then the smallest share of frames
/// travelling past the training takes, then by name.
pub fn rank_fitting(mut models: Vec<FittingModel>) -> Vec<FittingModel> {
    let key = |m: &FittingModel| (m.pose_ratio.unwrap_or(f64::INFINITY), m.travel_share.unwrap_or(0.0));
    models.sort_by(|a, b| {
        let (ka, kb) = (key(a), key(b));
        ka.0.total_cmp(&kb.0).then(ka.1.total_cmp(&kb.1)).then_with(|| a.name.cmp(&b.name))
    });
    models
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh;

    fn motion(name: &str, text: &str) -> Motion {
        Motion::from_bvh(name, &bvh::parse(text).unwrap()).unwrap()
    }

    /// A walk (CMU 02_01: about 48 reference-body inches, 1.2 m, per second — an ordinary walking
    /// pace) travels; the exercises on the spot of the sample (13_30) hardly do.
    #[test]
    fn a_walk_travels_and_exercises_on_the_spot_do_not() {
        let walk = motion("02_01.bvh", include_str!("../../tests/fixtures/02_01.bvh"));
        let speeds = travel_speeds(&walk).unwrap();
        assert_eq!(speeds.len(), walk.frames());
        let median = quantile(&sorted(speeds.clone()), 0.5);
        assert!((35.0..65.0).contains(&median), "{median}");
        let spot = motion("13_30.bvh", include_str!("../../www/sample.bvh"));
        let profile = TravelProfile::fit(&[(&spot, None)]).unwrap();
        assert!(profile.median < 5.0 && profile.limit < 15.0 && profile.limit > profile.median, "{profile:?}");
        // only the taught frames count
        let none = vec![false; spot.frames()];
        assert!(TravelProfile::fit(&[(&spot, Some(&none))]).is_err());
        // the walk under the sample's profile: nearly every frame too fast, so it does not fit
        let fit = TakeFit::assess(&walk, Some(&profile), None).unwrap();
        assert!(fit.travel_share.unwrap() > 0.9 && !fit.fits(), "{fit:?}");
        assert!(fit.unfamiliar.iter().filter(|&&u| u).count() as f64 > 0.9 * walk.frames() as f64);
        assert!(fit.describe("x").starts_with("model `x` does not fit this take"), "{}", fit.describe("x"));
        // the sample under its own profile fits; nothing measured fits too (and says so by `measured`)
        let own = TakeFit::assess(&spot, Some(&profile), None).unwrap();
        assert!(own.fits() && own.travel_share.unwrap() <= 0.02, "{own:?}");
        let nothing = TakeFit::assess(&walk, None, None).unwrap();
        assert!(nothing.fits() && !nothing.measured() && nothing.unfamiliar.iter().all(|u| !u));
    }

    /// A frame time of 1e-300 s (any f64 a file may hold; found by tests/fuzz_targets.rs's `long_takes`)
    /// made half a second 5e299 frames and the window's end overflow: the window is now at most the take.
    #[test]
    fn a_vanishing_frame_time_does_not_overflow_the_window() {
        let mut walk = motion("02_01.bvh", include_str!("../../tests/fixtures/02_01.bvh"));
        walk.fps = 1e300;
        let speeds = travel_speeds(&walk).unwrap();
        assert_eq!(speeds.len(), walk.frames());
    }

    /// The same walk written in metres travels the same reference-body speed (within the 2 % the
    /// two files' detected body sizes differ by).
    #[test]
    fn travel_does_not_depend_on_the_files_units() {
        let inches = motion("131_01.bvh", include_str!("../../tests/fixtures/131_01.bvh"));
        let metres = motion("m.bvh", include_str!("../../tests/fixtures/cmu_131_01_scaled_meters.bvh"));
        let (a, b) = (travel_speeds(&inches).unwrap(), travel_speeds(&metres).unwrap());
        let (ma, mb) = (quantile(&sorted(a), 0.5), quantile(&sorted(b), 0.5));
        assert!(ma > 1.0 && (ma - mb).abs() < 0.03 * ma, "{ma} vs {mb}");
    }
}
