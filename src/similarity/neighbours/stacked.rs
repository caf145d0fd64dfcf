//! The exact radius search of stacked features (§IV-A), using how they are stacked.
//!
//! A stacked feature is `F_i = [f_{i+o₁}, …, f_{i+o_k}]` (per-frame features `f`, frame offsets
//! `o`, indices clamped to the take), so its squared distance is a sum of per-frame squared
//! distances taken along a diagonal:
//!
//! ```text
//! |F_i − F_j|² = Σ_o D(c(i+o), c(j+o)),   D(a, b) = |f_a − f_b|²,   c = clamp to the take
//! ```
//!
//! Row `a` of `D` (for `b ≥ a`) is computed once, when the first stacked row needs it, and
//! kept while later rows still do (a ring of `max o − min o + 1` rows). Every `D(a, b)` costs
//! one per-frame distance (15 values for the end effectors), so the whole upper triangle costs
//! what a single 15-value distance per pair costs instead of a 75-value one, with every loop
//! running over contiguous memory (it vectorises). For the mirror SSSM (§V) the same holds with
//! `D_M(a, b) = |M f_a − f_b|²`, `M` the mirror map.
//!
//! Why not the kd-tree of [`super::NeighbourSearch`]: at the method's radius (`r = 19·√5`
//! inches) about a sixth of all frame pairs of a repetitive take are neighbours, and a tree
//! cannot prune a search whose ball covers much of the data: on 3000 frames of CMU 86_01
//! repeated, the kd-tree searches took 301 ms and these 90 ms on one thread (docs/methods/sssm.md,
//! "Neighbour search"). The kd-tree stays for features that
//! are not a plain stack (after feature bundling, §III) and for cross searches.

use super::{cap_tail, EntryBudget, Sssm, UpperTriangle, PROGRESS_ROWS};
use crate::features::{FeatureMatrix, MirrorMap};
use crate::method::Cancelled;
use crate::similarity::SimilarityError;

/// Per-frame features prepared for the stacked search.
pub struct StackedSearch {
    pub(super) n: usize,
    pub(super) dim: usize,
    pub(super) offsets: Vec<i32>,
    /// The features, centred, dimension-major (`dim × n`): the candidates `b`.
    columns: Vec<f32>,
    /// The features, centred, frame-major: the queries `a`.
    pub(super) queries: Vec<f32>,
    /// The mirrored features `M f_a`, centred, frame-major (if a mirror map was given).
    pub(super) mirrored: Option<Vec<f32>>,
    /// Only pairs at most this many frames apart are searched (`None`: all pairs).
    horizon: Option<usize>,
    /// What the searches (near and far) may find.
    pub(super) budget: EntryBudget,
}

impl StackedSearch {
    /// Prepares per-frame features `base` stacked at `offsets` (as in
    /// [`stack`](crate::features::stack)), with their mirror map if the mirror SSSM is
    /// wanted.
    pub fn new(base: &FeatureMatrix, offsets: &[i32], mirror: Option<&MirrorMap>) -> Result<Self, SimilarityError> {
        let (n, dim) = (base.frames(), base.dim());
        if offsets.is_empty() {
            return Err(SimilarityError::BadFeatures("no frame offsets to stack".into()));
        }
        let mirrored = match mirror {
            Some(m) if m.dim() != dim => {
                return Err(SimilarityError::BadFeatures(format!(
                    "the mirror map is for {} values per frame, the features have {dim}",
                    m.dim()
                )))
            }
            Some(m) => Some(m.apply(base)?),
            None => None,
        };
        // Centring keeps the sums small (better f32 rounding). The centre must be its own
        // mirror image, so that |M(f−μ) − (g−μ)| = |Mf − g|: the mean of f and M f.
        let mut centre = vec![0f64; dim];
        for i in 0..n {
            for (c, &x) in centre.iter_mut().zip(base.row(i)) {
                *c += x as f64;
            }
            if let Some(m) = &mirrored {
                for (c, &x) in centre.iter_mut().zip(m.row(i)) {
                    *c += x as f64;
                }
            }
        }
        let count = if mirrored.is_some() { 2 * n } else { n } as f64;
        let centre: Vec<f32> = centre.iter().map(|&c| (c / count) as f32).collect();
        let centred = |f: &FeatureMatrix| -> Vec<f32> {
            f.as_slice().chunks_exact(dim).flat_map(|row| row.iter().zip(&centre).map(|(&x, &c)| x - c)).collect()
        };
        let queries = centred(base);
        let mut columns = vec![0f32; n * dim];
        for (i, row) in queries.chunks_exact(dim).enumerate() {
            for (k, &x) in row.iter().enumerate() {
                columns[k * n + i] = x;
            }
        }
        let mirrored = mirrored.as_ref().map(centred);
        Ok(StackedSearch {
            n,
            dim,
            offsets: offsets.to_vec(),
            columns,
            queries,
            mirrored,
            horizon: None,
            budget: EntryBudget::unlimited(),
        })
    }

    /// Restricts the search to pairs `(i, j)` with `|i − j| ≤ horizon` frames (`None`: every
    /// pair, the paper's SSSM). The cost then grows with `n · horizon` instead of `n²`; see
    /// [`super::far`] for how actions farther apart are still compared.
    pub fn with_horizon(mut self, horizon: Option<usize>) -> Self {
        self.horizon = horizon;
        self
    }

    /// The searches, near and far ([`super::far`]), draw their entries from a budget of `limit`
    /// ([`EntryBudget`]).
    pub fn with_entry_limit(mut self, limit: usize) -> Self {
        self.budget = EntryBudget::new(limit);
        self
    }

    /// The entries the searches drew, and whether they passed the limit.
    pub fn budget(&self) -> &EntryBudget {
        &self.budget
    }

    /// Last candidate column (exclusive) of row `i`.
    fn row_end(&self, i: usize) -> usize {
        match self.horizon {
            Some(h) => i.saturating_add(h).saturating_add(1).min(self.n),
            None => self.n,
        }
    }

    /// The SSSM (every frame with its neighbours within `radius`, itself included at distance
    /// 0, at most `max_neighbours` of them, the nearest) and, if a mirror map was given, the
    /// mirror SSSM (`|M·F_i − F_j| ≤ radius`, symmetric because `M` is an isometry and its own
    /// inverse). Exactly the lists a brute-force search over the stacked features gives.
    pub fn similarities(&self, radius: f32, max_neighbours: usize) -> (Sssm, Option<Sssm>) {
        match self.similarities_with_progress(radius, max_neighbours, &mut |_| Ok(())) {
            Ok(found) => found,
            Err(Cancelled) => unreachable!("a callback that never cancels"),
        }
    }

    /// [`Self::similarities`], reporting the fraction done (0 to 1) as it goes (every 64 rows);
    /// stops as soon as `progress` returns `Err(Cancelled)`.
    pub fn similarities_with_progress(
        &self,
        radius: f32,
        max_neighbours: usize,
        progress: &mut dyn FnMut(f64) -> Result<(), Cancelled>,
    ) -> Result<(Sssm, Option<Sssm>), Cancelled> {
        #[cfg(not(target_arch = "wasm32"))]
        {
            use std::sync::atomic::{AtomicBool, Ordering};
            // set when the caller cancels, so that the half without the callback stops too
            let stop = AtomicBool::new(false);
            // both halves at once; the plain one (on this thread) reports for both
            let plain = || {
                self.similarity(&self.queries, radius, max_neighbours, &mut |f| {
                    progress(f).inspect_err(|_| stop.store(true, Ordering::Relaxed))
                })
            };
            let mirror = || {
                self.mirrored.as_ref().map(|q| {
                    self.similarity(q, radius, max_neighbours, &mut |_| {
                        if stop.load(Ordering::Relaxed) {
                            Err(Cancelled)
                        } else {
                            Ok(())
                        }
                    })
                })
            };
            let (plain, mirror) = crate::parallel::join(plain, mirror);
            Ok((plain?, mirror.transpose()?))
        }
        #[cfg(target_arch = "wasm32")]
        {
            // one after the other, each half of the progress
            let share = if self.mirrored.is_some() { 0.5 } else { 1.0 };
            let plain = self.similarity(&self.queries, radius, max_neighbours, &mut |f| progress(share * f))?;
            let mirror = self
                .mirrored
                .as_ref()
                .map(|q| self.similarity(q, radius, max_neighbours, &mut |f| progress(share + share * f)))
                .transpose()?;
            Ok((plain, mirror))
        }
    }

    /// The symmetric SSSM between the `queries` (plain or mirrored features) and the frames.
    fn similarity(
        &self,
        queries: &[f32],
        radius: f32,
        max_neighbours: usize,
        progress: &mut dyn FnMut(f64) -> Result<(), Cancelled>,
    ) -> Result<Sssm, Cancelled> {
        let n = self.n;
        let limit = radius * radius;
        let lo = *self.offsets.iter().min().expect("offsets checked in new");
        let hi = *self.offsets.iter().max().expect("offsets checked in new");
        let mut ring = RowRing::new(((hi - lo) as usize + 1).min(n), n);
        let mut upper = UpperTriangle::new(n);
        let mut sums = vec![0f32; n];
        // row i costs row_end(i) − i candidates
        let total: f64 = (0..n).map(|i| (self.row_end(i) - i) as f64).sum();
        let mut done = 0f64;
        for i in 0..n {
            if i % PROGRESS_ROWS == 0 {
                progress(done / total.max(1.0))?;
            }
            let sums = &mut sums[..self.row_end(i) - i];
            done += sums.len() as f64;
            self.stacked_row(i, queries, &mut ring, sums);
            let before = upper.entries.len();
            push_within(sums, i, limit, max_neighbours, &mut upper);
            self.budget.take(upper.entries.len() - before)?;
        }
        let sssm = upper.into_symmetric(max_neighbours);
        progress(1.0)?;
        Ok(sssm)
    }

    /// `sums[j − i] = Σ_o D(c(i+o), c(j+o))` for `i ≤ j < i + sums.len()`, with `D` measured
    /// from the query frames `queries` (the plain or the mirrored features) to the candidate
    /// frames.
    fn stacked_row(&self, i: usize, queries: &[f32], ring: &mut RowRing, sums: &mut [f32]) {
        let n = self.n;
        let end = i + sums.len();
        let clamp = |t: i64| t.clamp(0, n as i64 - 1) as usize;
        // c is monotone and moves no faster than its argument, so c(j+o) − c(i+o) ≤ j − i: row a
        // of D is needed up to column a + horizon
        let reach = self.horizon.map_or(n, |h| h.saturating_add(1));
        for &o in &self.offsets {
            let a = clamp(i as i64 + o as i64);
            let to = a.saturating_add(reach).min(n);
            ring.ensure(a, |out| self.distance_row(&queries[a * self.dim..(a + 1) * self.dim], a, to, out));
        }
        let rows = |k: usize| -> (&[f32], i64) {
            let o = self.offsets[k] as i64;
            (ring.get(clamp(i as i64 + o)), o)
        };
        // inside [j0, j1) every j + o lies in the take: one pass per two offsets, no clamping
        let lo = *self.offsets.iter().min().expect("offsets checked in new") as i64;
        let hi = *self.offsets.iter().max().expect("offsets checked in new") as i64;
        let j0 = (i as i64).max(-lo).min(end as i64) as usize;
        let j1 = (n as i64 - hi.max(0)).clamp(j0 as i64, end as i64) as usize;
        let at = |o: i64, from: usize, len: usize| -> std::ops::Range<usize> {
            let b = (from as i64 + o) as usize;
            b..b + len
        };
        if j1 > j0 {
            let len = j1 - j0;
            let inner = &mut sums[j0 - i..j1 - i];
            let (r0, o0) = rows(0);
            inner.copy_from_slice(&r0[at(o0, j0, len)]);
            let mut k = 1;
            while k + 1 < self.offsets.len() {
                let ((ra, oa), (rb, ob)) = (rows(k), rows(k + 1));
                for ((s, &x), &y) in inner.iter_mut().zip(&ra[at(oa, j0, len)]).zip(&rb[at(ob, j0, len)]) {
                    *s += x + y;
                }
                k += 2;
            }
            if k < self.offsets.len() {
                let (r, o) = rows(k);
                for (s, &x) in inner.iter_mut().zip(&r[at(o, j0, len)]) {
                    *s += x;
                }
            }
        }
        // the frames near the take's ends, where some j + o is clamped
        for j in (i..j0).chain(j1.max(i)..end) {
            sums[j - i] = (0..self.offsets.len())
                .map(|k| {
                    let (r, o) = rows(k);
                    r[clamp(j as i64 + o)]
                })
                .sum();
        }
    }

    /// `out[b] = |q − f_b|²` for `from ≤ b < to` (the rest of `out` is left as it is). Blocks
    /// of [`LANES`] candidates are summed over all dimensions in a local accumulator, which the
    /// compiler keeps in vector registers.
    pub(super) fn distance_row(&self, q: &[f32], from: usize, to: usize, out: &mut [f32]) {
        let n = self.n;
        let out = &mut out[from..to];
        let mut blocks = out.chunks_exact_mut(LANES);
        let mut b = from;
        for block in &mut blocks {
            let mut acc = [0f32; LANES];
            for (k, &qk) in q.iter().enumerate() {
                let column: &[f32; LANES] =
                    self.columns[k * n + b..k * n + b + LANES].try_into().expect("a block of LANES values");
                for t in 0..LANES {
                    let d = column[t] - qk;
                    acc[t] += d * d;
                }
            }
            block.copy_from_slice(&acc);
            b += LANES;
        }
        let rest = blocks.into_remainder();
        rest.fill(0.0);
        for (k, &qk) in q.iter().enumerate() {
            for (o, &x) in rest.iter_mut().zip(&self.columns[k * n + b..k * n + to]) {
                let d = x - qk;
                *o += d * d;
            }
        }
    }
}

/// Candidates tested at once by `push_within`.
const SCAN_BLOCK: usize = 16;

/// Candidates summed at once by [`StackedSearch::distance_row`].
const LANES: usize = 32;

/// Appends the entries `(i + k, √sums[k])` with `sums[k] ≤ limit` as row `i` of `upper`,
/// capped to the `max` nearest.
fn push_within(sums: &[f32], i: usize, limit: f32, max: usize, upper: &mut UpperTriangle) {
    let first = upper.entries.len();
    let mut push = |k: usize, s: f32| {
        if s <= limit {
            upper.entries.push(((i + k) as u32, s.max(0.0).sqrt()));
        }
    };
    // most candidates are out of reach: test a block at once (branch-free, vectorised) and look
    // at its values one by one only if one of them is within the limit
    let mut blocks = sums.chunks_exact(SCAN_BLOCK);
    for (b, block) in (&mut blocks).enumerate() {
        let hit = block.iter().fold(0u32, |hit, &s| hit | u32::from(s <= limit));
        if hit != 0 {
            for (k, &s) in block.iter().enumerate() {
                push(b * SCAN_BLOCK + k, s);
            }
        }
    }
    let done = sums.len() - blocks.remainder().len();
    for (k, &s) in blocks.remainder().iter().enumerate() {
        push(done + k, s);
    }
    cap_tail(&mut upper.entries, first, max);
    upper.end_row();
}

/// The rows `D(a, ·)` still needed, in `slots` rows of `n` values (slot `a mod slots`).
struct RowRing {
    n: usize,
    owner: Vec<usize>,
    data: Vec<f32>,
}

impl RowRing {
    fn new(slots: usize, n: usize) -> Self {
        RowRing { n, owner: vec![usize::MAX; slots], data: vec![0f32; slots * n] }
    }

    /// Computes row `a` with `fill` unless it is still held.
    fn ensure(&mut self, a: usize, fill: impl FnOnce(&mut [f32])) {
        let slot = a % self.owner.len();
        if self.owner[slot] != a {
            fill(&mut self.data[slot * self.n..(slot + 1) * self.n]);
            self.owner[slot] = a;
        }
    }

    /// Row `a` (which must have been ensured since its slot was last reused).
    fn get(&self, a: usize) -> &[f32] {
        let slot = a % self.owner.len();
        debug_assert_eq!(self.owner[slot], a);
        &self.data[slot * self.n..(slot + 1) * self.n]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::features::stack;
    use crate::similarity::neighbours::NeighbourSearch;

    fn walk(n: usize, d: usize, seed: u64) -> FeatureMatrix {
        crate::similarity::neighbours::tests::walk(n, d, seed, 0.9)
    }

    /// For every row of `a`, its rows of `b` within `r`.
    fn brute_force(a: &FeatureMatrix, b: &FeatureMatrix, r: f32) -> Vec<Vec<(u32, f32)>> {
        crate::similarity::neighbours::tests::brute_force(b, a, r)
    }

    /// Same neighbours and distances, allowing for pairs within rounding of the radius.
    fn same_lists(got: &Sssm, truth: &[Vec<(u32, f32)>], r: f32) {
        let got = got.to_lists();
        assert_eq!(got.len(), truth.len());
        for (i, (x, y)) in got.iter().zip(truth).enumerate() {
            let border = |&&(_, d): &&(u32, f32)| (d - r).abs() > 1e-3;
            let xs: Vec<_> = x.iter().filter(border).collect();
            let ys: Vec<_> = y.iter().filter(border).collect();
            assert_eq!(
                xs.iter().map(|p| p.0).collect::<Vec<_>>(),
                ys.iter().map(|p| p.0).collect::<Vec<_>>(),
                "row {i}"
            );
            for (p, q) in xs.iter().zip(&ys) {
                assert!((p.1 - q.1).abs() < 1e-3, "row {i}: {p:?} vs {q:?}");
            }
        }
    }

    /// A walk whose second half repeats the mirror image of its first half, slightly off.
    fn walk_and_mirror(half: usize, seed: u64) -> FeatureMatrix {
        let map = MirrorMap::end_effectors();
        let first = walk(half, 15, seed);
        let wobble = walk(half, 15, seed + 1);
        let mirrored = map.apply(&first).unwrap();
        let mut data = first.as_slice().to_vec();
        data.extend(mirrored.as_slice().iter().zip(wobble.as_slice()).map(|(m, w)| m + 0.2 * w));
        FeatureMatrix::new(2 * half, 15, data).unwrap()
    }

    #[test]
    fn matches_brute_force_on_the_stacked_features_with_the_take_ends_clamped() {
        let base = walk_and_mirror(150, 5);
        let map = MirrorMap::end_effectors();
        for offsets in [vec![-10, -5, 0, 5, 10], vec![0], vec![3, -7, 0], vec![-40, 40]] {
            let stacked = stack(&base, &offsets);
            let mirrored = map.apply(&stacked).unwrap();
            let r = 4.0 * (offsets.len() as f32).sqrt();
            let search = StackedSearch::new(&base, &offsets, Some(&map)).unwrap();
            let (sssm, mirror) = search.similarities(r, 10_000);
            let truth = brute_force(&stacked, &stacked, r);
            assert!(sssm.entries() > 3 * 300, "{offsets:?}: the test needs real neighbours, got {}", sssm.entries());
            same_lists(&sssm, &truth, r);
            let mirror = mirror.unwrap();
            let mirror_truth = brute_force(&mirrored, &stacked, r);
            assert!(mirror.entries() > 300, "{offsets:?}: the test needs mirror neighbours, got {}", mirror.entries());
            same_lists(&mirror, &mirror_truth, r);
            // the same lists as the kd-tree search
            let tree = NeighbourSearch::new(&stacked);
            same_lists(&tree.self_similarity(r, 10_000), &sssm.to_lists(), r);
        }
    }

    #[test]
    fn with_a_horizon_the_lists_are_the_brute_force_ones_up_to_that_far() {
        let base = walk_and_mirror(150, 7);
        let map = MirrorMap::end_effectors();
        for (offsets, horizon) in
            [(vec![-10, -5, 0, 5, 10], 40), (vec![0], 1), (vec![3, -7, 0], 120), (vec![-40, 40], 33)]
        {
            let stacked = stack(&base, &offsets);
            let mirrored = map.apply(&stacked).unwrap();
            let r = 4.0 * (offsets.len() as f32).sqrt();
            let search = StackedSearch::new(&base, &offsets, Some(&map)).unwrap().with_horizon(Some(horizon));
            let (sssm, mirror) = search.similarities(r, 10_000);
            let near = |lists: Vec<Vec<(u32, f32)>>| -> Vec<Vec<(u32, f32)>> {
                lists
                    .into_iter()
                    .enumerate()
                    .map(|(i, l)| l.into_iter().filter(|&(j, _)| (j as usize).abs_diff(i) <= horizon).collect())
                    .collect()
            };
            let truth = near(brute_force(&stacked, &stacked, r));
            assert!(truth.iter().map(Vec::len).sum::<usize>() > 2 * 300, "{offsets:?}: the test needs neighbours");
            // and some beyond the horizon, which must be left out
            assert!(
                brute_force(&stacked, &stacked, r).iter().map(Vec::len).sum::<usize>()
                    > truth.iter().map(Vec::len).sum::<usize>()
            );
            same_lists(&sssm, &truth, r);
            same_lists(&mirror.unwrap(), &near(brute_force(&mirrored, &stacked, r)), r);
        }
        // a horizon as long as the take is no horizon
        let search = StackedSearch::new(&base, &[-10, 0, 10], None).unwrap();
        let all = search.similarities(7.0, 600).0;
        let whole = StackedSearch::new(&base, &[-10, 0, 10], None).unwrap().with_horizon(Some(base.frames()));
        assert_eq!(whole.similarities(7.0, 600).0, all);
    }

    #[test]
    fn a_take_shorter_than_the_offsets_and_a_single_frame() {
        let base = walk(7, 15, 9);
        let offsets = [-10, -5, 0, 5, 10];
        let stacked = stack(&base, &offsets);
        let (sssm, mirror) = StackedSearch::new(&base, &offsets, None).unwrap().similarities(8.0, 100);
        assert!(mirror.is_none());
        same_lists(&sssm, &brute_force(&stacked, &stacked, 8.0), 8.0);
        let one = walk(1, 15, 1);
        let (sssm, _) =
            StackedSearch::new(&one, &offsets, Some(&MirrorMap::end_effectors())).unwrap().similarities(1.0, 5);
        assert_eq!(sssm.to_lists(), vec![vec![(0, 0.0)]]);
    }

    #[test]
    fn the_cap_keeps_the_nearest_neighbours() {
        let rows: Vec<[f32; 1]> = (0..50).map(|i| [i as f32]).collect();
        let base = FeatureMatrix::from_rows(&rows).unwrap();
        let (sssm, _) = StackedSearch::new(&base, &[0], None).unwrap().similarities(100.0, 5);
        let (cols, dists) = sssm.row(20);
        assert_eq!(cols, &[18, 19, 20, 21, 22]);
        assert_eq!(dists, &[2.0, 1.0, 0.0, 1.0, 2.0]);
    }

    #[test]
    fn progress_rises_to_one() {
        let base = walk_and_mirror(200, 3);
        let search = StackedSearch::new(&base, &[-10, -5, 0, 5, 10], Some(&MirrorMap::end_effectors())).unwrap();
        let mut seen = Vec::new();
        let (sssm, _) = search
            .similarities_with_progress(10.0, 600, &mut |f| {
                seen.push(f);
                Ok(())
            })
            .unwrap();
        assert_eq!(sssm.to_lists(), search.similarities(10.0, 600).0.to_lists());
        assert!(seen.len() >= 5, "{seen:?}");
        assert!(seen.windows(2).all(|w| w[0] <= w[1]), "{seen:?}");
        assert_eq!(seen.first(), Some(&0.0));
        assert_eq!(seen.last(), Some(&1.0));
    }

    #[test]
    fn bad_inputs_are_errors() {
        let base = walk(10, 6, 1);
        assert!(StackedSearch::new(&base, &[], None).is_err());
        assert!(StackedSearch::new(&base, &[0], Some(&MirrorMap::end_effectors())).is_err());
    }
}
