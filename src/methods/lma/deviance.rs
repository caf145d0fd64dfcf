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

use super::classifier::{deviance, EffortModel, Outputs, Projector};
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
/// computed once ([`Projector`]) — boundaries a few frames apart (the two hands slowing together)
/// share most of their shifted segments — and each of the (2s + 1)² classifiers run on all
/// candidates of a start in one batch per factor. Only the segments a later start can still use
/// are kept.
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
    let mut projector = Projector::new(model);
    let mut window = Window::new(2 * model.max_shift + 1, max_len + 2 * model.max_shift + 1, width);
    let shifts = model.shifts();
    let mut outputs: Vec<Outputs> = Vec::new();
    let (mut inputs, mut batch, mut scratch): (Vec<Vec<f32>>, Vec<f32>, Vec<f32>) =
        (vec![Vec::new(); model.factors.len()], Vec::new(), Vec::new());
    let mut ends: Vec<usize> = Vec::new();
    for (k, &start) in starts.iter().enumerate() {
        progress(k as f64 / starts.len().max(1) as f64)?;
        ends.clear();
        ends.extend(starts.iter().copied().filter(|&e| e >= start + min_len && e <= start + max_len));
        if ends.is_empty() {
            continue;
        }
        // every shifted segment of this start's candidates, projected once
        let segment = |end: usize, i: isize, j: isize| super::classifier::shifted(start, end, i, j, pool.frames());
        for i in -s..=s {
            for &end in &ends {
                for j in -s..=s {
                    let (a, b) = segment(end, i, j);
                    if let Some(z) = window.claim(a, b) {
                        projector.project(pool, a, b, z);
                    }
                }
            }
        }
        // then each classifier reads all of this start's candidates in one batch per factor
        outputs.resize(ends.len() * shifts, [0.0; 12]);
        for i in -s..=s {
            for j in -s..=s {
                let shift = model.shift_index(i, j);
                for input in inputs.iter_mut() {
                    input.clear();
                }
                for &end in &ends {
                    let (a, b) = segment(end, i, j);
                    let z = window.get(a, b);
                    let mut at = 0;
                    for (input, f) in inputs.iter_mut().zip(&model.factors) {
                        input.extend_from_slice(&z[at..at + f.components]);
                        at += f.components;
                    }
                }
                for (f, (factor, input)) in model.factors.iter().zip(&inputs).enumerate() {
                    batch.resize(ends.len() * 3, 0.0);
                    factor.nets[shift].forward_batch_with(input, &mut batch, &mut scratch);
                    for (e, out) in batch.chunks_exact(3).enumerate() {
                        outputs[e * shifts + shift][3 * f..3 * f + 3].copy_from_slice(out);
                    }
                }
            }
        }
        for (e, &end) in ends.iter().enumerate() {
            map.set(start, end, deviance(&outputs[e * shifts..(e + 1) * shifts]).0);
        }
    }
    Ok(map)
}

/// The projected inputs of the segments `a..=b` a start's candidates read, kept while a later
/// start may read them again: every start `a` they hold lies within the current start ± s, so
/// `rows` = 2s + 1 rows suffice, row `a mod rows` and column `b − a` — no hashing, no allocation.
/// A row is emptied when a later `a` takes it over; the `a` it held is then below every later
/// start − s, never read again.
struct Window {
    rows: usize,
    lengths: usize,
    width: usize,
    /// The `a` each row holds (`usize::MAX`: none yet).
    held: Vec<usize>,
    filled: Vec<bool>,
    z: Vec<f32>,
}

impl Window {
    fn new(rows: usize, lengths: usize, width: usize) -> Window {
        Window {
            rows,
            lengths,
            width,
            held: vec![usize::MAX; rows],
            filled: vec![false; rows * lengths],
            z: vec![0.0; rows * lengths * width],
        }
    }

    fn index(&self, a: usize, b: usize) -> usize {
        debug_assert!(b > a && b - a < self.lengths);
        (a % self.rows) * self.lengths + (b - a)
    }

    /// The place of segment `a..=b` to project it into, or `None` when it holds it already.
    fn claim(&mut self, a: usize, b: usize) -> Option<&mut [f32]> {
        let row = a % self.rows;
        if self.held[row] != a {
            self.held[row] = a;
            self.filled[row * self.lengths..(row + 1) * self.lengths].fill(false);
        }
        let k = self.index(a, b);
        if std::mem::replace(&mut self.filled[k], true) {
            return None;
        }
        Some(&mut self.z[k * self.width..(k + 1) * self.width])
    }

    /// The projected inputs of `a..=b`, claimed and projected before.
    fn get(&self, a: usize, b: usize) -> &[f32] {
        let k = self.index(a, b);
        debug_assert!(self.held[a % self.rows] == a && self.filled[k]);
        &self.z[k * self.width..(k + 1) * self.width]
    }
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
    let mut projector = Projector::new(model);
    let mut z = vec![0.0; model.width()];
    let mut project_row = |a: usize| {
        let mut factors: Vec<Vec<f32>> = model.factors.iter().map(|f| vec![0.0; lengths * f.components]).collect();
        for k in 0..lengths {
            let b = (a + lo + k).min(n - 1).max(a + 1);
            projector.project(pool, a, b, &mut z);
            let mut at = 0;
            for (row, f) in factors.iter_mut().zip(&model.factors) {
                row[k * f.components..(k + 1) * f.components].copy_from_slice(&z[at..at + f.components]);
                at += f.components;
            }
        }
        Row { a, factors }
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
            rows.push_back(project_row(a));
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::methods::lma::body::upper_body;
    use crate::methods::lma::classifier::shifted;
    use crate::methods::lma::features::Kinematics;

    /// The pruned search before the projector and the batches: every shifted segment projected one
    /// pool feature at a time, each classifier run on each candidate alone.
    fn reference(
        model: &EffortModel,
        pool: &Pool,
        boundaries: &[usize],
        (lo, hi): (usize, usize),
    ) -> Vec<(usize, usize, f32)> {
        let s = model.max_shift as isize;
        let mut z = vec![0.0; model.width()];
        let mut out = Vec::new();
        for &start in boundaries {
            for &end in boundaries.iter().filter(|&&e| e >= start + lo && e <= start + hi) {
                let mut outputs = Vec::new();
                for i in -s..=s {
                    for j in -s..=s {
                        let (a, b) = shifted(start, end, i, j, pool.frames());
                        model.project(pool, a, b, &mut z);
                        let mut o = [0.0; 12];
                        let mut at = 0;
                        for (k, f) in model.factors.iter().enumerate() {
                            let net = &f.nets[model.shift_index(i, j)];
                            net.forward(
                                &z[at..at + f.components],
                                &mut vec![0.0; net.hidden],
                                &mut o[3 * k..3 * k + 3],
                            );
                            at += f.components;
                        }
                        outputs.push(o);
                    }
                }
                out.push((start, end, deviance(&outputs).0));
            }
        }
        out
    }

    #[test]
    fn the_pruned_map_is_the_one_candidate_at_a_time_map() {
        let model = &crate::methods::lma::shipped_model().unwrap();
        let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/35_01.bvh")).unwrap();
        let motion = crate::motion::Motion::from_bvh("35_01.bvh", &crate::bvh::parse(&text).unwrap()).unwrap();
        let body = upper_body(&motion, model.fps).unwrap();
        let mut boundaries: Vec<usize> = body
            .arms
            .iter()
            .flat_map(|arm| slow_frames(&Kinematics::speed(arm.hand(), model.fps), f64::INFINITY))
            .collect();
        boundaries.sort_unstable();
        boundaries.dedup();
        let lengths = (20, 100);
        let mut compared = 0;
        for arm in &body.arms {
            let pool = Pool::of(arm, model.fps, 111);
            let map = pruned(model, &pool, &boundaries, lengths, &mut |_| Ok(())).unwrap();
            let expected = reference(model, &pool, &boundaries, lengths);
            assert_eq!(map.candidates().count(), expected.len());
            for (s, e, d) in expected {
                let fast = map.candidates().find(|c| (c.0, c.1) == (s, e)).expect("every candidate is in the map").2;
                assert!((fast - d).abs() <= 1e-5 * d.abs().max(1.0), "{s}..={e}: {fast} vs {d}");
                compared += 1;
            }
        }
        assert!(compared > 100, "{compared} candidates");
    }
}
