//! Heuristic gait-phase labels, the label kind of Cheema et al. 2019 (DT-FCN, Table 1: standing,
//! begin left/right step, left/right step, end left/right step, turn), made automatically because
//! no public set labelled that way exists. **Heuristic labels, not an expert's**: the DT-FCN paper's
//! point is robustness to noisy labels, and these are noisy.
//!
//! 1. A foot is in **contact** when it is near its own floor (its 5th-percentile height over the
//!    take, + `contact_height`) and its horizontal speed is low (`contact_speed`); a **step** is a run
//!    of its foot off the ground lasting at least `min_step_s` (shorter lifts are shuffles).
//! 2. A step during which the hips barely move (`turn_travel`) but the body turns (`turn_degrees`)
//!    is part of a **turn**; one during which they barely move and the body does not turn is dropped.
//! 3. Steps closer than `min_stand_s` form one walk; a walk's first step is a **begin** step, its
//!    last an **end** step (a one-step walk: begin), the others plain steps; each step also takes
//!    the double support before it inside the walk, so a walk is tiled.
//! 4. Every other frame is **standing**, or **turn** where the facing turns faster than `turn_rate`.
//!
//! Positions are in body sizes (leg + trunk length), so thresholds hold for any skeleton and unit.

use glam::DVec3;

use crate::motion::joints::Canonical;
use crate::motion::normalize::{body_size, facing_yaws, to_inches, to_y_up};
use crate::motion::Motion;
use crate::stats::gaussian_smooth;

/// The gait phases (Cheema et al. 2019, Table 1, without its arm primitives).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Gait {
    Standing,
    BeginLeftStep,
    BeginRightStep,
    LeftStep,
    RightStep,
    EndLeftStep,
    EndRightStep,
    Turn,
}

impl Gait {
    pub fn name(self) -> &'static str {
        match self {
            Gait::Standing => "standing",
            Gait::BeginLeftStep => "begin left step",
            Gait::BeginRightStep => "begin right step",
            Gait::LeftStep => "left step",
            Gait::RightStep => "right step",
            Gait::EndLeftStep => "end left step",
            Gait::EndRightStep => "end right step",
            Gait::Turn => "turn",
        }
    }
}

/// Thresholds of the labeller (lengths in body sizes, speeds in body sizes per second).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GaitParams {
    pub contact_height: f64,
    pub contact_speed: f64,
    pub min_step_s: f64,
    pub min_stand_s: f64,
    pub turn_travel: f64,
    pub turn_degrees: f64,
    /// Degrees per second.
    pub turn_rate: f64,
}

impl Default for GaitParams {
    /// From what walking bodies do: a planted foot stays within ~5 cm of the floor and slides
    /// slower than ~0.4 m/s; a step lasts ≥ 0.15 s; a standing pause ≥ 0.3 s; a turn in place moves
    /// the hips < 15 cm while turning ≥ 15°; turning on the spot faster than 30°/s.
    fn default() -> Self {
        GaitParams {
            contact_height: 0.035,
            contact_speed: 0.3,
            min_step_s: 0.15,
            min_stand_s: 0.3,
            turn_travel: 0.1,
            turn_degrees: 15.0,
            turn_rate: 30.0,
        }
    }
}

/// Runs of `true` in `mask`, as `(start, end)` inclusive.
fn runs_of(mask: &[bool]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut start = None;
    for (t, &m) in mask.iter().chain([false].iter()).enumerate() {
        match (m, start) {
            (true, None) => start = Some(t),
            (false, Some(s)) => {
                out.push((s, t - 1));
                start = None;
            }
            _ => {}
        }
    }
    out
}

/// Per-frame gait labels from the feet (left, right) and hips, world positions Y-up in body sizes,
/// and the facing yaw (radians) of every frame, at `fps`.
pub fn label_gait(feet: [&[DVec3]; 2], hips: &[DVec3], yaw: &[f64], fps: f64, p: &GaitParams) -> Vec<Gait> {
    let n = hips.len();
    let mut labels = vec![Gait::Standing; n];
    if n < 3 {
        return labels;
    }
    let sigma = 0.05 * fps;
    let horizontal_speed = |x: &[DVec3]| {
        let raw: Vec<f64> = (0..n)
            .map(|t| {
                let (a, b) = (t.saturating_sub(1), (t + 1).min(n - 1));
                let d = x[b] - x[a];
                DVec3::new(d.x, 0.0, d.z).length() * fps / (b - a) as f64
            })
            .collect();
        gaussian_smooth(&raw, sigma)
    };
    // 1. contacts and steps
    let mut steps: Vec<(usize, usize, usize)> = Vec::new(); // (start, end, side 0 = left)
    for (side, foot) in feet.iter().enumerate() {
        let mut heights: Vec<f64> = foot.iter().map(|q| q.y).collect();
        heights.sort_by(f64::total_cmp);
        let floor = heights[(heights.len() - 1) / 20];
        let speed = horizontal_speed(foot);
        let lifted: Vec<bool> =
            (0..n).map(|t| foot[t].y > floor + p.contact_height || speed[t] > p.contact_speed).collect();
        for (s, e) in runs_of(&lifted) {
            if (e + 1 - s) as f64 >= p.min_step_s * fps {
                steps.push((s, e, side));
            }
        }
    }
    steps.sort_unstable();
    // unwrapped yaw, for turns
    let mut unwrapped = Vec::with_capacity(n);
    let mut acc = yaw[0];
    unwrapped.push(acc);
    for t in 1..n {
        let mut d = yaw[t] - yaw[t - 1];
        while d > std::f64::consts::PI {
            d -= std::f64::consts::TAU;
        }
        while d < -std::f64::consts::PI {
            d += std::f64::consts::TAU;
        }
        acc += d;
        unwrapped.push(acc);
    }
    let turned = |s: usize, e: usize| (unwrapped[e] - unwrapped[s]).abs().to_degrees();
    let travel = |s: usize, e: usize| {
        let d = hips[e] - hips[s];
        DVec3::new(d.x, 0.0, d.z).length()
    };
    // 4. turning on the spot (before steps overwrite their frames)
    let rate: Vec<f64> = gaussian_smooth(
        &(0..n)
            .map(|t| {
                let (a, b) = (t.saturating_sub(1), (t + 1).min(n - 1));
                (unwrapped[b] - unwrapped[a]).abs().to_degrees() * fps / (b - a) as f64
            })
            .collect::<Vec<_>>(),
        2.0 * sigma,
    );
    for t in 0..n {
        if rate[t] > p.turn_rate {
            labels[t] = Gait::Turn;
        }
    }
    // 2. steps in place: turns or shuffles
    let mut walking = Vec::new();
    for &(s, e, side) in &steps {
        if travel(s, e) < p.turn_travel {
            if turned(s, e) >= p.turn_degrees {
                labels[s..=e].iter_mut().for_each(|l| *l = Gait::Turn);
            }
        } else {
            walking.push((s, e, side));
        }
    }
    // 3. walks: steps closer than min_stand_s; each step takes the double support before it
    let pause = (p.min_stand_s * fps).round() as usize;
    let mut k = 0;
    while k < walking.len() {
        let mut last = k;
        while last + 1 < walking.len() && walking[last + 1].0 <= walking[last].1 + pause {
            last += 1;
        }
        for i in k..=last {
            let (s, e, side) = walking[i];
            let from = if i > k { walking[i - 1].1 + 1 } else { s };
            let label = match (i == k, i == last, side) {
                (true, _, 0) => Gait::BeginLeftStep,
                (true, _, _) => Gait::BeginRightStep,
                (false, true, 0) => Gait::EndLeftStep,
                (false, true, _) => Gait::EndRightStep,
                (false, false, 0) => Gait::LeftStep,
                (false, false, _) => Gait::RightStep,
            };
            labels[from.min(s)..=e].iter_mut().for_each(|l| *l = label);
        }
        k = last + 1;
    }
    labels
}

/// The gait labels of every frame of `motion` (at its own rate).
pub fn gait_of(motion: &Motion, p: &GaitParams) -> Result<Vec<Gait>, String> {
    let map = motion.joint_map().map_err(|e| e.to_string())?;
    let body = body_size(&motion.skeleton, &map) * to_inches(motion.units);
    if !(body.is_finite() && body > 0.0) {
        return Err(format!("the skeleton's body size is {body} inches; cannot label its gait"));
    }
    let scale = to_inches(motion.units) / body;
    let track = |c: Canonical| -> Vec<DVec3> {
        let j = map.get(c);
        (0..motion.frames()).map(|f| to_y_up(motion.frame(f)[j], motion.up_axis).as_dvec3() * scale).collect()
    };
    let (left, right, hips) = (track(Canonical::LeftFoot), track(Canonical::RightFoot), track(Canonical::Hips));
    let yaw: Vec<f64> = facing_yaws(motion, &map).into_iter().map(f64::from).collect();
    Ok(label_gait([&left, &right], &hips, &yaw, motion.fps, p))
}

/// Runs of equal labels as `(start, end, label)`, inclusive.
pub fn runs(labels: &[Gait]) -> Vec<(usize, usize, Gait)> {
    let mut out: Vec<(usize, usize, Gait)> = Vec::new();
    for (t, &l) in labels.iter().enumerate() {
        match out.last_mut() {
            Some(last) if last.2 == l => last.1 = t,
            _ => out.push((t, t, l)),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const FPS: f64 = 60.0;

    /// A synthetic walk: standing 1 s, four steps (left, right, left, right; each foot swings
    /// 0.4 s, 0.1 s of double support between), standing 1 s. Returns feet, hips and the true
    /// per-frame labels.
    fn walk() -> ([Vec<DVec3>; 2], Vec<DVec3>, Vec<Gait>) {
        let second = FPS as usize;
        let (swing, support) = ((0.4 * FPS) as usize, (0.1 * FPS) as usize);
        let mut feet = [Vec::new(), Vec::new()];
        let mut hips = Vec::new();
        let mut truth = Vec::new();
        let mut at = [DVec3::new(0.1, 0.0, 0.0), DVec3::new(-0.1, 0.0, 0.0)];
        let push = |feet: &mut [Vec<DVec3>; 2], hips: &mut Vec<DVec3>, at: &[DVec3; 2]| {
            feet[0].push(at[0]);
            feet[1].push(at[1]);
            hips.push(DVec3::new(0.0, 0.5, (at[0].z + at[1].z) / 2.0));
        };
        for _ in 0..second {
            push(&mut feet, &mut hips, &at);
            truth.push(Gait::Standing);
        }
        let labels = [Gait::BeginLeftStep, Gait::RightStep, Gait::LeftStep, Gait::EndRightStep];
        for (k, &label) in labels.iter().enumerate() {
            let side = k % 2;
            for _ in 0..support {
                push(&mut feet, &mut hips, &at);
                truth.push(label);
            }
            let start = at[side];
            for i in 1..=swing {
                let u = i as f64 / swing as f64;
                // forward 0.4 body sizes, lifted 0.1 at mid-swing
                at[side] = start + DVec3::new(0.0, 0.1 * (std::f64::consts::PI * u).sin(), 0.4 * u);
                push(&mut feet, &mut hips, &at);
                truth.push(label);
            }
        }
        for _ in 0..second {
            push(&mut feet, &mut hips, &at);
            truth.push(Gait::Standing);
        }
        (feet, hips, truth)
    }

    #[test]
    fn a_synthetic_walk_gets_its_phases() {
        let (feet, hips, truth) = walk();
        let yaw = vec![0.0; hips.len()];
        let labels = label_gait([&feet[0], &feet[1]], &hips, &yaw, FPS, &GaitParams::default());
        let names: Vec<Gait> = runs(&labels).iter().map(|r| r.2).collect();
        assert_eq!(
            names,
            [Gait::Standing, Gait::BeginLeftStep, Gait::RightStep, Gait::LeftStep, Gait::EndRightStep, Gait::Standing]
        );
        let right = labels.iter().zip(&truth).filter(|(a, b)| a == b).count() as f64 / truth.len() as f64;
        // the first step starts at lift-off, not at the double support the truth gives it
        assert!(right > 0.95, "{right}");
    }

    #[test]
    fn turning_on_the_spot_is_a_turn() {
        let n = 120;
        let feet = [vec![DVec3::new(0.1, 0.0, 0.0); n], vec![DVec3::new(-0.1, 0.0, 0.0); n]];
        let hips = vec![DVec3::new(0.0, 0.5, 0.0); n];
        // still for 0.5 s, then 90° in 1 s, still for 0.5 s
        let yaw: Vec<f64> =
            (0..n).map(|t| ((t as f64 - 30.0) / 60.0).clamp(0.0, 1.0) * std::f64::consts::FRAC_PI_2).collect();
        let labels = label_gait([&feet[0], &feet[1]], &hips, &yaw, FPS, &GaitParams::default());
        assert_eq!(labels[60], Gait::Turn);
        assert_eq!(labels[0], Gait::Standing);
        assert_eq!(labels[n - 1], Gait::Standing);
        assert_eq!(runs(&labels).len(), 3, "{:?}", runs(&labels));
    }

    #[test]
    fn short_takes_are_standing() {
        let one = [DVec3::ZERO];
        assert_eq!(label_gait([&one, &one], &one, &[0.0], FPS, &GaitParams::default()), [Gait::Standing]);
    }
}
