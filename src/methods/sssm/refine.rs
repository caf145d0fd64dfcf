//! Action boundaries after region growing (§IV-B), not in the paper: actions that are one
//! activity cut apart are merged by their *poses*, and each boundary is moved to the moment the
//! body moves least nearby.
//!
//! Both steps only compare a take with itself (no fixed distance or speed), so they carry over to
//! takes the method was not tuned on:
//!
//! * **Merging by poses** ([`merge_same_poses`]): region growing works on stacked features
//!   (§IV-A: the poses at −10 … +10 frames), which encode the *direction* of a movement. An
//!   activity whose direction changes halfway — arm circles forward, then backward — is two
//!   blocks in the SSSM and so two actions, although the annotators (and the poses) call it one.
//!   Two neighbouring actions are merged when the frames of each come, in plain pose space, about
//!   as close to the other action as the action's own frames come back to themselves: the median
//!   nearest-pose distance from one into the other is at most `factor ×` the other's median
//!   nearest-repeat distance (repeats at least `band` frames apart). The factor is relative to
//!   the take's own repeat distances; no distance in inches enters.
//! * **Boundaries at low motion** ([`refine_boundaries`]): an annotator puts a boundary
//!   mid-transition, where the body is nearly still between two movements; region growing puts it
//!   where the repetitions stop, which the ±10-frame stacking smears by a fraction of a second. Each
//!   boundary (the first frame of the next action, or the middle of the transition between them,
//!   as the action level is read) moves to the frame of least body speed (the speed of the
//!   per-frame features, smoothed over ±0.1 s) within `window` frames of it; the transition, if
//!   any, moves with it and keeps its length.

use super::features::FeatureMatrix;
use crate::similarity::Span;

/// Per-frame body speed of `base` (feature units per frame): central differences of the per-frame
/// feature vectors, averaged over `±smooth` frames.
pub fn body_speed(base: &FeatureMatrix, smooth: usize) -> Vec<f32> {
    let n = base.frames();
    if n < 2 {
        return vec![0.0; n];
    }
    let raw: Vec<f32> = (0..n)
        .map(|i| {
            let (a, b) = (i.saturating_sub(1), (i + 1).min(n - 1));
            let d: f32 = base.row(a).iter().zip(base.row(b)).map(|(x, y)| (y - x) * (y - x)).sum();
            d.sqrt() / (b - a) as f32
        })
        .collect();
    // moving average through a prefix sum
    let mut prefix = vec![0.0f64; n + 1];
    for (i, &s) in raw.iter().enumerate() {
        prefix[i + 1] = prefix[i] + s as f64;
    }
    (0..n)
        .map(|i| {
            let (lo, hi) = (i.saturating_sub(smooth), (i + smooth).min(n - 1));
            ((prefix[hi + 1] - prefix[lo]) / (hi + 1 - lo) as f64) as f32
        })
        .collect()
}

/// Moves every boundary between consecutive `actions` (sorted, disjoint) to the frame of least
/// `speed` within `window` frames of it (ties: the one nearest the old boundary). The boundary is
/// the next action's first frame when the two touch, else the middle of the transition between
/// them (how the action level is scored); the transition keeps its length. Every action keeps at
/// least one frame and the order is kept. `window = 0` returns the actions unchanged.
pub fn refine_boundaries(actions: &[Span], speed: &[f32], window: usize) -> Vec<Span> {
    let mut out = actions.to_vec();
    if window == 0 {
        return out;
    }
    for k in 1..out.len() {
        let (a, b) = (out[k - 1], out[k]);
        let gap = b.start - a.end - 1;
        // the boundary as scored: first frame of b, or of b's half of the transition
        let c = a.end + 1 + gap / 2;
        // the shift δ keeps a.end + δ ≥ a.start and b.start + δ ≤ b.end
        let lo = c.saturating_sub(window).max(c - (a.end - a.start));
        let hi = (c + window).min(c + (b.end - b.start)).min(speed.len().saturating_sub(1));
        if lo > hi {
            continue;
        }
        let best = (lo..=hi)
            .min_by(|&x, &y| speed[x].total_cmp(&speed[y]).then(x.abs_diff(c).cmp(&y.abs_diff(c))))
            .unwrap_or(c);
        let shift = best as isize - c as isize;
        out[k - 1].end = (a.end as isize + shift) as usize;
        out[k].start = (b.start as isize + shift) as usize;
    }
    out
}

fn distance(a: &[f32], b: &[f32]) -> f32 {
    a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum::<f32>().sqrt()
}

/// At most this many frames of an action are compared (evenly spread), so merging stays linear
/// in the take's length.
const MAX_SAMPLES: usize = 150;

fn samples(span: Span) -> impl Iterator<Item = usize> {
    let step = span.len().div_ceil(MAX_SAMPLES).max(1);
    (span.start..=span.end).step_by(step)
}

fn median(mut v: Vec<f32>) -> Option<f32> {
    if v.is_empty() {
        return None;
    }
    let k = v.len() / 2;
    Some(*v.select_nth_unstable_by(k, f32::total_cmp).1)
}

/// Median over (sampled) frames of `from` of the distance to the nearest frame of `to` at least
/// `band` frames away in `base` (`None` if no frame has one).
fn nearest_median(base: &FeatureMatrix, from: Span, to: Span, band: usize) -> Option<f32> {
    let d: Vec<f32> = samples(from)
        .filter_map(|i| {
            (to.start..=to.end)
                .filter(|&j| j.abs_diff(i) >= band)
                .map(|j| distance(base.row(i), base.row(j)))
                .min_by(f32::total_cmp)
        })
        .collect();
    median(d)
}

/// Merges neighbouring `actions` (at most `max_gap` frames apart) whose poses repeat each other
/// about as closely as each repeats itself (see the module docs): with `t_x` the median distance
/// from a frame of `x` to its nearest pose in `x` at least `band` frames away and `c(x → y)` the
/// median distance from a frame of `x` to its nearest pose in `y`, `a` and `b` are merged when
/// `c(b → a) ≤ factor·t_a` and `c(a → b) ≤ factor·t_b` (an action too short to repeat itself
/// lends the other's `t`). `factor = 0` merges nothing.
pub fn merge_same_poses(base: &FeatureMatrix, actions: &[Span], band: usize, max_gap: usize, factor: f64) -> Vec<Span> {
    let mut out: Vec<Span> = Vec::with_capacity(actions.len());
    if factor <= 0.0 {
        return actions.to_vec();
    }
    let factor = factor as f32;
    let band = band.max(1);
    for &b in actions {
        if let Some(a) = out.last_mut() {
            if b.start <= a.end + 1 + max_gap {
                let (ta, tb) = (nearest_median(base, *a, *a, band), nearest_median(base, b, b, band));
                let (ta, tb) = match (ta, tb) {
                    (Some(x), Some(y)) => (x, y),
                    (Some(x), None) => (x, x),
                    (None, Some(y)) => (y, y),
                    (None, None) => {
                        out.push(b);
                        continue;
                    }
                };
                let into_a = nearest_median(base, b, *a, 0);
                let into_b = nearest_median(base, *a, b, 0);
                if into_a.is_some_and(|c| c <= factor * ta) && into_b.is_some_and(|c| c <= factor * tb) {
                    a.end = b.end;
                    continue;
                }
            }
        }
        out.push(b);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn span(start: usize, end: usize) -> Span {
        Span { start, end }
    }

    /// A circle of 20 frames per turn traversed forward on `0..n1`, backward on `n1..n1+n2`, then
    /// a circle shifted by `far` on the rest; every value with deterministic noise of ±0.05.
    fn circles(n1: usize, n2: usize, n3: usize, far: f32) -> FeatureMatrix {
        let mut rows = Vec::new();
        let mut state = 12345u64;
        let mut noise = move || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((state >> 40) as f32 / (1u64 << 24) as f32 - 0.5) * 0.1
        };
        for i in 0..n1 + n2 + n3 {
            let t = i as f32 * std::f32::consts::TAU / 20.0;
            let (dir, off) = if i < n1 {
                (1.0, 0.0)
            } else if i < n1 + n2 {
                (-1.0, 0.0)
            } else {
                (1.0, far)
            };
            rows.push([off + (dir * t).cos() + noise(), (dir * t).sin() + noise(), noise()]);
        }
        FeatureMatrix::from_rows(&rows).unwrap()
    }

    #[test]
    fn the_speed_is_the_smoothed_feature_speed() {
        // x moves 1 per frame for 10 frames, then stands still
        let rows: Vec<[f32; 1]> = (0..20).map(|i| [i.min(10) as f32]).collect();
        let m = FeatureMatrix::from_rows(&rows).unwrap();
        let s = body_speed(&m, 0);
        assert_eq!(s[5], 1.0);
        assert_eq!(s[15], 0.0);
        assert_eq!(s[10], 0.5, "central difference across the stop");
        let smooth = body_speed(&m, 2);
        assert!((smooth[10] - (1.0 + 1.0 + 0.5 + 0.0 + 0.0) / 5.0).abs() < 1e-6);
        assert!(body_speed(&FeatureMatrix::from_rows(&[[1.0f32]]).unwrap(), 3) == vec![0.0]);
    }

    #[test]
    fn boundaries_move_to_the_nearest_speed_minimum_within_the_window() {
        // speed minimum at frame 47; boundary at 50 (touching actions)
        let speed: Vec<f32> = (0..100).map(|i| (i as f32 - 47.0).abs()).collect();
        let actions = [span(0, 49), span(50, 99)];
        assert_eq!(refine_boundaries(&actions, &speed, 5), vec![span(0, 46), span(47, 99)]);
        // a window too small to reach the minimum goes as far as it can towards it
        assert_eq!(refine_boundaries(&actions, &speed, 2), vec![span(0, 47), span(48, 99)]);
        assert_eq!(refine_boundaries(&actions, &speed, 0), actions.to_vec());
        // with a transition 40..=59 (middle 50) the transition shifts and keeps its length
        let gapped = [span(0, 39), span(60, 99)];
        assert_eq!(refine_boundaries(&gapped, &speed, 5), vec![span(0, 36), span(57, 99)]);
    }

    #[test]
    fn refining_never_empties_an_action_nor_reorders() {
        // the minimum is far inside a short action: it may shrink to one frame, not vanish
        let speed: Vec<f32> = (0..30).map(|i| if i == 0 { 0.0 } else { 1.0 + i as f32 }).collect();
        let actions = [span(0, 4), span(5, 29)];
        assert_eq!(refine_boundaries(&actions, &speed, 20), vec![span(0, 0), span(1, 29)]);
        // flat speed: nothing moves (ties go to the old boundary)
        let flat = vec![1.0; 30];
        assert_eq!(refine_boundaries(&actions, &flat, 10), actions.to_vec());
    }

    #[test]
    fn an_activity_reversed_halfway_is_merged_but_a_different_one_is_not() {
        let m = circles(100, 100, 100, 5.0);
        let actions = [span(0, 99), span(100, 199), span(200, 299)];
        // forward and backward circles share their poses: merged; the far circle stays apart
        assert_eq!(merge_same_poses(&m, &actions, 10, 30, 2.0), vec![span(0, 199), span(200, 299)]);
        // off: unchanged
        assert_eq!(merge_same_poses(&m, &actions, 10, 30, 0.0), actions.to_vec());
        // too far apart in time: not neighbours
        let apart = [span(0, 59), span(140, 199)];
        assert_eq!(merge_same_poses(&m, &apart, 10, 30, 2.0), apart.to_vec());
        // a nearer circle (offset 0.5) merges only with a larger factor: the factor is relative
        // to how closely each action repeats itself
        let near = circles(100, 0, 100, 0.5);
        let two = [span(0, 99), span(100, 199)];
        assert_eq!(merge_same_poses(&near, &two, 10, 30, 1.5), two.to_vec());
        assert_eq!(merge_same_poses(&near, &two, 10, 30, 1e6), vec![span(0, 199)]);
    }
}
