//! The deviance map of one arm (Bouchard & Badler §4.2, Fig. 5): the family's mean deviance for
//! every candidate segment between the shortest and longest segment length.
//!
//! * [`pruned`]: candidates start and end only at frames where the hand's speed has a local
//!   minimum below a threshold ("computing the average deviation for frames where the end
//!   effector speed is below a threshold"), each assessed on its own;
//! * [`exhaustive`]: every candidate. Each segment the family reads (every start, every length
//!   from `min_len − 2s` to `max_len + 2s`) is projected once, a start row at a time, and every
//!   network of the family reads a whole row of candidates in one batched pass
//!   ([`crate::methods::lma::network::Net::forward_batch`]) — the paper's "more than 3 hours" for a 25-second
//!   take become seconds.

use std::collections::VecDeque;

use super::classifier::{deviance, EffortModel, Outputs};
use super::features::Pool;
use super::search::DevianceMap;
use crate::method::Cancelled;

/// Frames where `speed` has a local minimum below `threshold` (the pruned search's boundaries).
pub fn slow_frames(speed: &[f64], threshold: f64) -> Vec<usize> {
    (1..speed.len().saturating_sub(1))
        .filter(|&t| speed[t] < threshold && speed[t] <= speed[t - 1] && speed[t] < speed[t + 1])
        .collect()
}

/// The map over candidates whose both ends are in `boundaries`, lengths `min_len..=max_len`: each
/// candidate as [`EffortModel::assess`] scores it, every shifted segment's projected inputs
/// computed once — boundaries a few frames apart (the two hands slowing together) share most of
/// their shifted segments. Only the segments a later start can still use are kept.
pub fn pruned(
    model: &EffortModel,
    pool: &Pool,
    boundaries: &[usize],
    (min_len, max_len): (usize, usize),
    progress: &mut dyn FnMut(f64) -> Result<(), Cancelled>,
) -> Result<DevianceMap, Cancelled> {
    let mut map = DevianceMap::new(pool.frames(), min_len, max_len);
    let mut starts: Vec<usize> = boundaries.to_vec();
    starts.sort_unstable();
    starts.dedup();
    let s = model.max_shift as isize;
    let width = model.width();
    // projected inputs of segment (a, b), while a start ≤ a + 2s may still come
    let mut cache: std::collections::BTreeMap<(usize, usize), Vec<f32>> = std::collections::BTreeMap::new();
    let mut outputs: Vec<Outputs> = Vec::with_capacity(model.shifts());
    for (k, &start) in starts.iter().enumerate() {
        progress(k as f64 / starts.len().max(1) as f64)?;
        let oldest = start.saturating_sub(model.max_shift);
        cache = cache.split_off(&(oldest, 0));
        for &end in starts.iter().filter(|&&e| e >= start + min_len && e <= start + max_len) {
            outputs.clear();
            for i in -s..=s {
                for j in -s..=s {
                    let (a, b) = super::classifier::shifted(start, end, i, j, pool.frames());
                    let z = cache.entry((a, b)).or_insert_with(|| {
                        let mut z = vec![0.0; width];
                        model.project(pool, a, b, &mut z);
                        z
                    });
                    outputs.push(model.classify(model.shift_index(i, j), z));
                }
            }
            map.set(start, end, deviance(&outputs).0);
        }
    }
    Ok(map)
}

/// One start row of projected inputs: per factor, `lengths × components` values for the
/// segments `a ..= a + lo + k` (ends past the take clamped to its last frame).
struct Row {
    a: usize,
    factors: Vec<Vec<f32>>,
}

/// The map over every candidate of lengths `min_len..=max_len`.
pub fn exhaustive(
    model: &EffortModel,
    pool: &Pool,
    (min_len, max_len): (usize, usize),
    progress: &mut dyn FnMut(f64) -> Result<(), Cancelled>,
) -> Result<DevianceMap, Cancelled> {
    let n = pool.frames();
    let mut map = DevianceMap::new(n, min_len, max_len);
    let s = model.max_shift;
    if n < min_len + 2 || min_len < 2 * s + 2 {
        return Ok(map);
    }
    // lengths the family reads: min_len − 2s ..= max_len + 2s (at least 1)
    let lo = min_len.saturating_sub(2 * s).max(1);
    let hi = max_len + 2 * s;
    let lengths = hi - lo + 1;
    let widest = model.factors.iter().map(|f| f.selected.len()).max().unwrap_or(0);
    let mut x = vec![0.0; widest];
    let project_row = |a: usize, x: &mut [f32]| Row {
        a,
        factors: model
            .factors
            .iter()
            .map(|f| {
                let mut z = vec![0.0; lengths * f.components];
                for k in 0..lengths {
                    let b = (a + lo + k).min(n - 1).max(a + 1);
                    let z_k = &mut z[k * f.components..(k + 1) * f.components];
                    f.project(pool, a, b, &mut x[..f.selected.len()], z_k);
                }
                z
            })
            .collect(),
    };
    let shifts = model.shifts();
    let candidates = max_len - min_len + 1;
    let mut outputs: Vec<Outputs> = vec![[0.0; 12]; candidates * shifts];
    let mut batch = vec![0.0f32; candidates * 3];
    let mut rows: VecDeque<Row> = VecDeque::new();
    let last_start = n - 1 - min_len;
    for start in 0..=last_start {
        if start % 16 == 0 {
            progress(start as f64 / (last_start + 1) as f64)?;
        }
        // the rows start − s ..= start + s (clamped), projected once each
        let first = start.saturating_sub(s);
        while rows.front().is_some_and(|r| r.a < first) {
            rows.pop_front();
        }
        let need = (start + s).min(n - 2);
        let next = rows.back().map_or(first, |r| r.a + 1);
        for a in next..=need {
            rows.push_back(project_row(a, &mut x));
        }
        let ends = (n - 1 - start - min_len + 1).min(candidates);
        for i in -(s as isize)..=s as isize {
            let a = (start as isize + i).clamp(0, need as isize) as usize;
            let row = &rows[a - rows[0].a];
            for j in -(s as isize)..=s as isize {
                let shift = model.shift_index(i, j);
                // candidate (start, start + min_len + c) reads (a, start + min_len + c + j)
                let offset = start as isize + min_len as isize + j - a as isize - lo as isize;
                // min_len > 2s keeps every shifted length inside the row (see EffortModel::check_lengths)
                debug_assert!(offset >= 0 && offset as usize + ends <= lengths);
                let offset = offset as usize;
                for (f, factor) in model.factors.iter().enumerate() {
                    let k = factor.components;
                    let input = &row.factors[f][offset * k..(offset + ends) * k];
                    factor.nets[shift].forward_batch(input, &mut batch[..ends * 3]);
                    for c in 0..ends {
                        outputs[c * shifts + shift][3 * f..3 * f + 3].copy_from_slice(&batch[3 * c..3 * c + 3]);
                    }
                }
            }
        }
        for c in 0..ends {
            let (d, _) = deviance(&outputs[c * shifts..(c + 1) * shifts]);
            map.set(start, start + min_len + c, d);
        }
    }
    Ok(map)
}
