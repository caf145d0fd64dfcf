//! Far blocks: the SSSM beyond a search horizon (not in the paper; parameter `horizon_s`).
//!
//! The exact search measures every pair of frames, so its cost grows with the square of the
//! take's length, and so does the SSSM itself until the neighbour cap binds (on the CMU takes
//! about a tenth of all frame pairs are within `r`). With a horizon `H`, the stacked search
//! ([`StackedSearch::with_horizon`]) only pairs frames at most `H` frames apart, which makes it
//! and every later step linear in the length. Most of the method never looks further:
//!
//! * region growing (§IV-B) only counts neighbours between the growing region's seed and the
//!   current frame, i.e. inside the action it grows — an action shorter than `H` sees all of them,
//!   a longer one its repetitions of the last `H` frames;
//! * primitive cuts (§IV-C) come from warping paths inside one action — but from every diagonal
//!   of it, and a diagonal `L` frames off the main one gives the cut of the repetition `L` frames
//!   after the action's start. So an action longer than the horizon gets its own block beyond the
//!   horizon searched too (this part stays quadratic in the length of one action, as in the
//!   paper, but not in the length of the take).
//!
//! What needs entries far from the diagonal are the *kinds* of actions (a walk at minute 1 and
//! one at minute 20 are the same kind) and the primitive *clusters* across them (§VI). For those,
//! this module links actions that reach beyond the horizon through exactly searched SSSM blocks:
//!
//! 1. every action that repeats itself gets a *summary*: [`SUMMARY_POSES`] poses from its middle,
//!    [`SUMMARY_STEP_S`] apart; two actions are *candidates* if the median distance from each
//!    one's poses to the nearest pose of the other (plain or mirrored) is within the other's
//!    repeat limit (the distance the kinds' test allows, per pose: `/√|offsets|`);
//! 2. candidates are taken nearest first (Kruskal's order). A pair whose actions are already
//!    linked, directly or through others, is skipped; otherwise its block (rows in the later
//!    action, columns in the earlier, plain and mirrored) is searched exactly and its entries
//!    beyond the horizon are added to the SSSM. If at least half of each action's frames repeat
//!    a frame of the other there (the test of two actions of one kind, with the relative gate),
//!    the two count as linked. Two groups of linked actions whose block failed to link are not
//!    tried again, and an action whose blocks failed [`FAR_TRIES`] times gets no more.
//!
//! Kinds and clusters are then found on the SSSM with the added blocks, as without a horizon.
//! Both are transitive (a union of kinds, strongly connected components of clusters), so a chain
//! of linked blocks joins every repetition of an activity. At most `(FAR_TRIES + 1) · actions`
//! blocks between actions are searched, each costing the product of its two actions' lengths, so
//! this stays linear in the take's length for actions of bounded length; the summaries cost
//! `actions² · SUMMARY_POSES²` pose distances, small beside the search for realistic takes (docs/benchmarks.md,
//! "SSSM in detail"). Of a far block only what the later steps use is kept: the entries within the
//! primitive graph's radius and every frame's nearest repeat.

use super::{cap_row, Sssm, SssmBuilder, StackedSearch};
use crate::method::Cancelled;
use crate::similarity::Span;
use std::sync::atomic::{AtomicBool, Ordering};

/// Blocks of an action that may fail to link before it gets no more.
pub const FAR_TRIES: usize = 2;
/// Poses of an action's summary.
pub const SUMMARY_POSES: usize = 32;
/// Seconds between two poses of a summary (so a summary spans about 4 s of the action).
pub const SUMMARY_STEP_S: f64 = 2.0 / 15.0;
/// A block links its two actions if at least this fraction of each one's frames repeats a frame
/// of the other (as for two actions of one kind).
pub const LINK_COVER: f64 = 0.5;

/// An action's summary poses, `dim` values each (frame-major), their mirror images, and the
/// poses again dimension-major (so distances to all of them vectorise).
struct Summary {
    plain: Vec<f32>,
    mirrored: Option<Vec<f32>>,
    columns: Vec<f32>,
}

impl Summary {
    fn new(plain: Vec<f32>, mirrored: Option<Vec<f32>>, d: usize) -> Self {
        let count = plain.len() / d;
        let mut columns = vec![0f32; plain.len()];
        for (k, pose) in plain.chunks_exact(d).enumerate() {
            for (t, &x) in pose.iter().enumerate() {
                columns[t * count + k] = x;
            }
        }
        Summary { plain, mirrored, columns }
    }

    /// The medians over the poses of `self` and over those of `other` of the distance to the
    /// nearest pose of the other summary, plain or mirrored (`|M p − q| = |p − M q|`: the mirror
    /// map is an isometry and its own inverse, so one matrix serves both directions).
    fn median_distances(&self, other: &Summary, d: usize) -> (f32, f32) {
        let (rows, cols) = (self.plain.len() / d, other.plain.len() / d);
        if rows == 0 || cols == 0 {
            return (f32::INFINITY, f32::INFINITY);
        }
        let (mut row_min, mut col_min) = (vec![f32::INFINITY; rows], vec![f32::INFINITY; cols]);
        let mut acc = vec![0f32; cols];
        for poses in std::iter::once(&self.plain).chain(&self.mirrored) {
            for (k, p) in poses.chunks_exact(d).enumerate() {
                acc.fill(0.0);
                for (t, &x) in p.iter().enumerate() {
                    for (a, &y) in acc.iter_mut().zip(&other.columns[t * cols..(t + 1) * cols]) {
                        *a += (x - y) * (x - y);
                    }
                }
                for (c, &a) in col_min.iter_mut().zip(&acc) {
                    *c = c.min(a);
                }
                row_min[k] = acc.iter().copied().fold(row_min[k], f32::min);
            }
        }
        // (no summary poses: no distance)
        let median = |v: &mut [f32]| crate::stats::median(v).unwrap_or(f32::INFINITY);
        (median(&mut row_min).sqrt(), median(&mut col_min).sqrt())
    }
}

/// Rows of a far block measured at once (bounds the memory of a block of two long actions).
const BLOCK_ROWS: usize = 256;

/// The far-block search over a [`StackedSearch`]'s features.
pub struct FarSearch<'a> {
    search: &'a StackedSearch,
    /// Pairs up to this many frames apart are already in the SSSM.
    horizon: usize,
    /// Search radius `r` of the stacked features.
    radius: f32,
    /// Far entries farther than this are only kept as a frame's nearest repeat.
    keep_radius: f32,
    /// Each row of a block keeps at most this many entries, the nearest.
    max_neighbours: usize,
    /// Frames between two summary poses.
    step: usize,
}

/// What a far search found.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FarEntries {
    /// Entries `(i, j, d)` of the plain and of the mirror SSSM, `i` in the later action (both
    /// directions are added when merged).
    pub plain: Vec<(u32, u32, f32)>,
    pub mirror: Vec<(u32, u32, f32)>,
    /// The action pairs `(earlier, later)` whose blocks were searched, in search order, and
    /// whether each linked its actions.
    pub pairs: Vec<(usize, usize, bool)>,
}

impl<'a> FarSearch<'a> {
    /// Far blocks for an SSSM searched with `horizon` frames at radius `radius` with at most
    /// `max_neighbours` per row, keeping the far entries within `keep_radius` (the primitive
    /// graph's) and each frame's nearest, at `fps` working frames per second.
    pub fn new(
        search: &'a StackedSearch,
        horizon: usize,
        radius: f32,
        max_neighbours: usize,
        keep_radius: f32,
        fps: f64,
    ) -> Self {
        let step = (SUMMARY_STEP_S * fps).round().max(1.0) as usize;
        FarSearch { search, horizon, radius, keep_radius, max_neighbours, step }
    }

    /// An action's summary frames: up to [`SUMMARY_POSES`], `step` apart, centred on the
    /// action's middle.
    fn summary(&self, span: Span) -> Vec<usize> {
        let count = span.len().div_ceil(self.step).min(SUMMARY_POSES);
        let first = span.start + (span.len() - ((count - 1) * self.step + 1).min(span.len())) / 2;
        (0..count).map(|k| first + k * self.step).filter(|&f| f <= span.end).collect()
    }

    /// The candidate pairs `(distance, a, b)`, `a < b`: actions reaching more than `horizon`
    /// frames apart whose summaries are within the pose radius of each other (the larger of the
    /// two median distances), nearest first; of equal distance the pair nearer in time.
    pub fn candidates(&self, actions: &[Span], limits: &[Option<f32>]) -> Vec<(f32, usize, usize)> {
        // a stacked distance d means the stacked poses are on average d/√|offsets| apart
        let scale = (self.search.offsets.len() as f32).sqrt();
        let pose_limit = |a: usize| limits[a].map_or(f32::NEG_INFINITY, |l| l.min(self.radius) / scale);
        let d = self.search.dim;
        let gather = |rows: &[f32], frames: &[usize]| -> Vec<f32> {
            frames.iter().flat_map(|&f| rows[f * d..(f + 1) * d].iter().copied()).collect()
        };
        let summaries: Vec<Summary> = actions
            .iter()
            .map(|&s| {
                let frames = self.summary(s);
                let plain = gather(&self.search.queries, &frames);
                Summary::new(plain, self.search.mirrored.as_ref().map(|m| gather(m, &frames)), d)
            })
            .collect();
        // the later actions of each pair, odd and even on two threads (natively)
        let pairs_of = |parity: usize| {
            let mut scored: Vec<(f32, usize, usize)> = Vec::new();
            for b in (parity..actions.len()).step_by(2).filter(|&b| limits[b].is_some()) {
                for a in (0..b).filter(|&a| limits[a].is_some() && actions[b].end - actions[a].start > self.horizon) {
                    let (there, back) = summaries[b].median_distances(&summaries[a], d);
                    if there <= pose_limit(a) && back <= pose_limit(b) {
                        scored.push((there.max(back), a, b));
                    }
                }
            }
            scored
        };
        let (mut scored, odd) = crate::parallel::join(|| pairs_of(0), || pairs_of(1));
        scored.extend(odd);
        scored.sort_by(|x, y| x.0.total_cmp(&y.0).then((x.2 - x.1).cmp(&(y.2 - y.1))).then(x.1.cmp(&y.1)));
        scored
    }

    /// Searches the blocks of the candidate pairs in order (see the module documentation).
    /// `limits[a]` is how near a frame must come to action `a` to repeat it (the kinds' test,
    /// [`RegionGrowing::kinds`](crate::methods::sssm::activities::RegionGrowing::kinds); `None`: `a`
    /// does not repeat itself and links to nothing). Reports the fraction done before the
    /// first block, every 256 rows of a block and after each block, and stops as
    /// soon as `progress` returns `Err(Cancelled)`.
    pub fn search(
        &self,
        actions: &[Span],
        limits: &[Option<f32>],
        progress: &mut dyn FnMut(f64) -> Result<(), Cancelled>,
    ) -> Result<FarEntries, Cancelled> {
        assert_eq!(actions.len(), limits.len(), "one limit per action");
        let mut out = FarEntries::default();
        // the work: each long action's own block, then the candidates' blocks (at most), by the
        // frame pairs they hold
        let long: Vec<Span> = actions.iter().copied().filter(|a| a.len() > self.horizon.saturating_add(1)).collect();
        let candidates = self.candidates(actions, limits);
        let size = |a: Span, b: Span| (a.len() * b.len()) as f64;
        let total = long.iter().map(|&a| size(a, a)).sum::<f64>()
            + candidates.iter().map(|&(_, a, b)| size(actions[a], actions[b])).sum::<f64>();
        let total = total.max(1.0);
        // the fraction done: `done` pairs, plus `part` of a block of `work` pairs
        let fraction = |done: f64, part: f64, work: f64| ((done + part * work) / total).min(1.0);
        let mut done = 0.0;
        progress(0.0)?;
        // an action longer than the horizon: its own block beyond the horizon, whose diagonals
        // give the cuts of its later repetitions (§IV-C)
        for &a in &long {
            let work = size(a, a);
            let (plain, mirror, _, _) = self.searched_block(a, a, &mut |f| progress(fraction(done, f, work)))?;
            out.plain.extend(plain);
            out.mirror.extend(mirror);
            done += work;
            progress(fraction(done, 0.0, 0.0))?;
        }
        let mut linked = petgraph::unionfind::UnionFind::<usize>::new(actions.len());
        let mut failures = vec![0usize; actions.len()];
        let mut failed = std::collections::HashSet::new();
        for (_, a, b) in candidates {
            let work = size(actions[a], actions[b]);
            if failures[a] >= FAR_TRIES || failures[b] >= FAR_TRIES || linked.equiv(a, b) {
                done += work;
                progress(fraction(done, 0.0, 0.0))?;
                continue;
            }
            // a block between two groups of linked actions that failed is not tried again
            let groups = (linked.find_mut(a).min(linked.find_mut(b)), linked.find_mut(a).max(linked.find_mut(b)));
            if failed.contains(&groups) {
                done += work;
                progress(fraction(done, 0.0, 0.0))?;
                continue;
            }
            let (plain, mirror, rows, cols) =
                self.searched_block(actions[b], actions[a], &mut |f| progress(fraction(done, f, work)))?;
            done += work;
            progress(fraction(done, 0.0, 0.0))?;
            let cover = |nearest: &[f32], limit: Option<f32>| {
                limit.map_or(0.0, |l| nearest.iter().filter(|&&d| d <= l).count() as f64 / nearest.len() as f64)
            };
            let links = cover(&rows, limits[a]) >= LINK_COVER && cover(&cols, limits[b]) >= LINK_COVER;
            out.plain.extend(plain);
            out.mirror.extend(mirror);
            if links {
                linked.union(a, b);
            } else {
                failures[a] += 1;
                failures[b] += 1;
                failed.insert(groups);
            }
            out.pairs.push((a, b, links));
        }
        progress(1.0)?;
        Ok(out)
    }

    /// The plain and the mirrored block of `rows × cols` beyond the horizon, with only the
    /// entries the later steps use: those within the keep radius (the warping paths of the
    /// primitives and clusters) and every row's and column's nearest (the kinds); also the
    /// nearest distance of every row and of every column (infinite if none). Reports the
    /// fraction of the rows done to `progress` and stops when it returns `Err(Cancelled)`.
    #[allow(clippy::type_complexity)]
    fn searched_block(
        &self,
        rows: Span,
        cols: Span,
        progress: &mut dyn FnMut(f64) -> Result<(), Cancelled>,
    ) -> Result<(Vec<(u32, u32, f32)>, Vec<(u32, u32, f32)>, Vec<f32>, Vec<f32>), Cancelled> {
        // the plain and the mirrored block at once (natively); the plain one reports, and the
        // mirrored one stops when the plain one was cancelled
        let stop = AtomicBool::new(false);
        let (plain, mirror) = crate::parallel::join(
            || {
                self.block(&self.search.queries, rows, cols, &mut |f| {
                    progress(f).inspect_err(|_| stop.store(true, Ordering::Relaxed))
                })
            },
            || {
                self.search.mirrored.as_ref().map_or(Ok(Vec::new()), |m| {
                    self.block(m, rows, cols, &mut |_| {
                        if stop.load(Ordering::Relaxed) {
                            Err(Cancelled)
                        } else {
                            Ok(())
                        }
                    })
                })
            },
        );
        let (plain, mirror) = (plain?, mirror?);
        let (mut row_min, mut col_min) = (vec![f32::INFINITY; rows.len()], vec![f32::INFINITY; cols.len()]);
        for &(i, j, d) in plain.iter().chain(&mirror) {
            let (r, c) = (&mut row_min[i as usize - rows.start], &mut col_min[j as usize - cols.start]);
            *r = r.min(d);
            *c = c.min(d);
        }
        let keep = |&(i, j, d): &(u32, u32, f32)| {
            d <= self.keep_radius || d == row_min[i as usize - rows.start] || d == col_min[j as usize - cols.start]
        };
        let (plain, mirror) = (plain.into_iter().filter(keep).collect(), mirror.into_iter().filter(keep).collect());
        Ok((plain, mirror, row_min, col_min))
    }

    /// Entries `(i, j, d)`, `i` in `rows`, `j` in `cols`, `i − j > horizon`, with the stacked
    /// distance `d = √Σ_o |q_{c(i+o)} − f_{c(j+o)}|² ≤ r` (`c` clamps to the take). Calls
    /// `tick` with the fraction of the rows done before every [`BLOCK_ROWS`] rows and stops
    /// when it returns `Err(Cancelled)`.
    fn block(
        &self,
        queries: &[f32],
        rows: Span,
        cols: Span,
        tick: &mut dyn FnMut(f64) -> Result<(), Cancelled>,
    ) -> Result<Vec<(u32, u32, f32)>, Cancelled> {
        let mut out = Vec::new();
        let s = self.search;
        let (n, d) = (s.n as i64, s.dim);
        let clamp = |t: i64| t.clamp(0, n - 1) as usize;
        let lo = *s.offsets.iter().min().expect("offsets checked") as i64;
        let hi = *s.offsets.iter().max().expect("offsets checked") as i64;
        let limit = self.radius * self.radius;
        let y0 = clamp(cols.start as i64 + lo);
        let mut scratch = vec![0f32; s.n];
        let mut poses = Vec::new();
        let mut sums = vec![0f32; cols.len()];
        let mut row = Vec::new();
        for chunk in (rows.start..=rows.end).step_by(BLOCK_ROWS) {
            tick((chunk - rows.start) as f64 / rows.len() as f64)?;
            let last = (chunk + BLOCK_ROWS - 1).min(rows.end);
            // the columns these rows pair with beyond the horizon
            let Some(j_last) = last.checked_sub(self.horizon.saturating_add(1)).map(|j| j.min(cols.end)) else {
                continue;
            };
            if j_last < cols.start {
                continue;
            }
            // per-pose squared distances P[x − x0][y − y0] for the poses these rows and columns stack
            let y1 = clamp(j_last as i64 + hi);
            let width = y1 - y0 + 1;
            let (x0, x1) = (clamp(chunk as i64 + lo), clamp(last as i64 + hi));
            poses.clear();
            for x in x0..=x1 {
                s.distance_row(&queries[x * d..(x + 1) * d], y0, y1 + 1, &mut scratch);
                poses.extend_from_slice(&scratch[y0..=y1]);
            }
            for i in chunk..=last {
                // only pairs beyond the horizon (the nearer ones are in the SSSM already)
                let Some(j_max) = i.checked_sub(self.horizon.saturating_add(1)) else { continue };
                if j_max < cols.start {
                    continue;
                }
                let sums = &mut sums[..=cols.end.min(j_max) - cols.start];
                sums.fill(0.0);
                for &o in &s.offsets {
                    let row = &poses[(clamp(i as i64 + o as i64) - x0) * width..][..width];
                    let first = cols.start as i64 + o as i64;
                    if first >= 0 && first + sums.len() as i64 <= n {
                        // no clamping: a contiguous run of the row
                        let (from, len) = (first as usize - y0, sums.len());
                        for (sum, &x) in sums.iter_mut().zip(&row[from..from + len]) {
                            *sum += x;
                        }
                    } else {
                        for (k, sum) in sums.iter_mut().enumerate() {
                            *sum += row[clamp(first + k as i64) - y0];
                        }
                    }
                }
                // the row's nearest `max` (as the search caps its rows: a long action's own block
                // may hold far more repetitions than the SSSM keeps)
                row.clear();
                row.extend(
                    sums.iter()
                        .enumerate()
                        .filter(|&(_, &d2)| d2 <= limit)
                        .map(|(k, &d2)| ((cols.start + k) as u32, d2.max(0.0).sqrt())),
                );
                cap_row(&mut row, self.max_neighbours);
                // each far pair becomes two entries of the SSSM
                self.search.budget.take(2 * row.len())?;
                out.extend(row.iter().map(|&(j, d)| (i as u32, j, d)));
            }
        }
        Ok(out)
    }
}

impl Sssm {
    /// The SSSM with the far `entries` `(i, j, d)` added in both directions (`(i, j)` and
    /// `(j, i)`), every row capped to the `max` nearest again. The far entries must lie outside
    /// the band the SSSM was searched in, `|i − j| > horizon ≥` its own entries' `|i − j|`, so
    /// each row is its far entries before `i`, its own entries, its far entries after `i`.
    pub fn with_far_entries(&self, entries: &[(u32, u32, f32)], max: usize) -> Sssm {
        if entries.is_empty() {
            return self.clone();
        }
        let n = self.frames();
        // the far entries in compressed rows (a counting sort by row), each row sorted by column
        let mut starts = vec![0usize; n + 1];
        for &(i, j, _) in entries {
            starts[i as usize + 1] += 1;
            starts[j as usize + 1] += 1;
        }
        for i in 0..n {
            starts[i + 1] += starts[i];
        }
        let mut fill = starts.clone();
        let mut far = vec![(0u32, 0f32); 2 * entries.len()];
        for &(i, j, d) in entries {
            for (row, col) in [(i, j), (j, i)] {
                far[fill[row as usize]] = (col, d);
                fill[row as usize] += 1;
            }
        }
        let mut b = SssmBuilder::new(n);
        b.cols.reserve(self.entries() + far.len());
        b.dists.reserve(self.entries() + far.len());
        let mut row = Vec::new();
        for i in 0..n {
            let theirs = &mut far[starts[i]..starts[i + 1]];
            if theirs.is_empty() {
                // most rows: copied as they are (already capped)
                let (cols, dists) = self.row(i);
                b.cols.extend_from_slice(cols);
                b.dists.extend_from_slice(dists);
                b.starts.push(b.cols.len() as u32);
                continue;
            }
            theirs.sort_unstable_by_key(|e| e.0);
            let split = theirs.partition_point(|e| (e.0 as usize) < i);
            let (cols, dists) = self.row(i);
            debug_assert!(theirs[..split].last().is_none_or(|e| cols.first().is_none_or(|&c| e.0 < c)));
            row.clear();
            row.extend_from_slice(&theirs[..split]);
            row.extend(cols.iter().copied().zip(dists.iter().copied()));
            row.extend_from_slice(&theirs[split..]);
            cap_row(&mut row, max);
            b.push_sorted_row(&row);
        }
        b.finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::features::{stack, FeatureMatrix, MirrorMap};

    /// 15 values per frame: a periodic motion of `period` frames and `shape` (different shapes
    /// are different activities), with a little deterministic wobble.
    fn periodic(frames: std::ops::Range<usize>, period: f32, shape: f32) -> Vec<[f32; 15]> {
        frames
            .map(|t| {
                let a = std::f32::consts::TAU * t as f32 / period;
                std::array::from_fn(|k| {
                    let k = k as f32;
                    (10.0 + shape * k) * (a + 0.4 * k).sin() + 0.3 * (0.37 * t as f32 + k).sin()
                })
            })
            .collect()
    }

    /// A take of activity A (0–299), B (300–899), A again (900–1199).
    fn a_b_a() -> FeatureMatrix {
        let mut rows = periodic(0..300, 30.0, 0.0);
        rows.extend(periodic(300..900, 41.0, 3.0));
        rows.extend(periodic(900..1200, 30.0, 0.0));
        FeatureMatrix::from_rows(&rows).unwrap()
    }

    const OFFSETS: [i32; 5] = [-10, -5, 0, 5, 10];

    fn spans() -> Vec<Span> {
        vec![Span { start: 0, end: 299 }, Span { start: 300, end: 899 }, Span { start: 900, end: 1199 }]
    }

    #[test]
    fn blocks_hold_the_brute_force_entries_beyond_the_horizon() {
        // A, B, A, then A mirrored (frames 1200–1499)
        let map = MirrorMap::end_effectors();
        let mut rows =
            a_b_a().as_slice().chunks_exact(15).map(|r| <[f32; 15]>::try_from(r).unwrap()).collect::<Vec<_>>();
        let again = FeatureMatrix::from_rows(&periodic(1200..1500, 30.0, 0.0)).unwrap();
        rows.extend(map.apply(&again).unwrap().as_slice().chunks_exact(15).map(|r| <[f32; 15]>::try_from(r).unwrap()));
        let base = FeatureMatrix::from_rows(&rows).unwrap();
        let stacked = stack(&base, &OFFSETS);
        let mirrored = map.apply(&stacked).unwrap();
        let search = StackedSearch::new(&base, &OFFSETS, Some(&map)).unwrap();
        let r = 30.0;
        let far = FarSearch::new(&search, 200, r, 100_000, 10.0, 30.0);
        let mut found = [0usize; 2]; // plain, mirror
                                     // the take's first and last frames: the stacked features are clamped there
        let blocks = [(900, 1199, 0, 299), (1200, 1499, 0, 299), (350, 420, 0, 180), (1300, 1499, 950, 1050)];
        for (r0, r1, c0, c1) in blocks {
            let (rows, cols) = (Span { start: r0, end: r1 }, Span { start: c0, end: c1 });
            let cases = [(&search.queries, &stacked), (search.mirrored.as_ref().unwrap(), &mirrored)];
            for (k, (queries, features)) in cases.into_iter().enumerate() {
                let got = far.block(queries, rows, cols, &mut |_| Ok(())).unwrap();
                let mut truth = Vec::new();
                for i in rows.start..=rows.end {
                    for j in cols.start..=cols.end.min(i.saturating_sub(201)) {
                        let d2: f32 = features.row(i).iter().zip(stacked.row(j)).map(|(x, y)| (x - y) * (x - y)).sum();
                        if d2.sqrt() <= r {
                            truth.push((i as u32, j as u32, d2.sqrt()));
                        }
                    }
                }
                found[k] += truth.len();
                let border = |e: &&(u32, u32, f32)| (e.2 - r).abs() > 1e-3;
                let (g, t): (Vec<_>, Vec<_>) =
                    (got.iter().filter(border).collect(), truth.iter().filter(border).collect());
                assert_eq!(g.len(), t.len(), "block {rows:?} × {cols:?}, mirror {}", k == 1);
                for (x, y) in g.iter().zip(&t) {
                    assert_eq!((x.0, x.1), (y.0, y.1));
                    assert!((x.2 - y.2).abs() < 1e-3, "{x:?} vs {y:?}");
                }
            }
        }
        assert!(found.iter().all(|&f| f > 1000), "the test needs plain and mirror neighbours: {found:?}");
    }

    #[test]
    fn repeated_activities_beyond_the_horizon_are_linked_and_others_not() {
        let base = a_b_a();
        let search = StackedSearch::new(&base, &OFFSETS, Some(&MirrorMap::end_effectors())).unwrap();
        let far = FarSearch::new(&search, 200, 19.0 * 5f32.sqrt(), 600, 13.0 * 5f32.sqrt(), 30.0);
        let limits = vec![Some(6.0); 3];
        // A and A again: a candidate; B is another activity, and near A's end within the horizon
        let candidates = far.candidates(&spans(), &limits);
        assert_eq!(candidates.iter().map(|c| (c.1, c.2)).collect::<Vec<_>>(), vec![(0, 2)], "{candidates:?}");
        let found = far.search(&spans(), &limits, &mut |_| Ok(())).unwrap();
        assert_eq!(found.pairs, vec![(0, 2, true)]);
        // entries of the far block, and of each action's own block (all are longer than the
        // horizon)
        let action = |f: u32| spans().iter().position(|s| s.contains(f as usize));
        let own = |&(i, j, _): &(u32, u32, f32)| action(i) == action(j);
        assert!(found.plain.iter().all(|e| e.0 - e.1 > 200 && (own(e) || (900..1200).contains(&e.0) && e.1 < 300)));
        for k in 0..3 {
            assert!(found.plain.iter().any(|e| own(e) && action(e.0) == Some(k)), "action {k}'s own block");
        }
        // every frame of the second A (its stacked window inside A) repeats a frame of the first
        let rows: std::collections::BTreeSet<u32> = found.plain.iter().filter(|e| !own(e)).map(|e| e.0).collect();
        assert!(rows.len() >= 280, "{} rows of the second A found a repeat", rows.len());
        // an action that does not repeat itself (no limit) is linked to nothing
        assert!(far.candidates(&spans(), &[Some(6.0), Some(6.0), None]).is_empty());
        // a tight limit: the summaries are no longer near enough
        assert!(far.candidates(&spans(), &[Some(1e-3); 3]).is_empty());
    }

    #[test]
    fn a_block_that_does_not_repeat_counts_as_a_failure() {
        // A, then A played backwards at four speeds: the same poses (the summaries match), in
        // other orders (the stacked features, ±10 frames around each pose, do not)
        let period = 30.0;
        let mut rows = periodic(0..300, period, 0.0);
        for speed in [1.0f32, 1.3, 0.8, 1.6] {
            let copy = periodic(0..300, period / speed, 0.0);
            rows.extend(copy.into_iter().rev());
        }
        let base = FeatureMatrix::from_rows(&rows).unwrap();
        let search = StackedSearch::new(&base, &OFFSETS, None).unwrap();
        let far = FarSearch::new(&search, 200, 19.0 * 5f32.sqrt(), 600, 13.0 * 5f32.sqrt(), 30.0);
        let spans: Vec<Span> = (0..5).map(|k| Span { start: 300 * k + 15, end: 300 * k + 284 }).collect();
        let limits = vec![Some(12.0); 5];
        let candidates = far.candidates(&spans, &limits);
        assert!(candidates.len() >= 8, "{candidates:?}");
        let found = far.search(&spans, &limits, &mut |_| Ok(())).unwrap();
        // every block fails to link; each action gives up after FAR_TRIES failed blocks, so
        // fewer blocks are searched than there are candidates
        assert!(!found.pairs.is_empty() && found.pairs.iter().all(|p| !p.2), "{:?}", found.pairs);
        let mut tries = [0usize; 5];
        for &(a, b, _) in &found.pairs {
            tries[a] += 1;
            tries[b] += 1;
        }
        assert!(tries.iter().all(|&t| t <= FAR_TRIES), "{tries:?}");
        assert!(tries.contains(&FAR_TRIES), "{tries:?}");
        assert!(found.pairs.len() < candidates.len(), "{:?} of {candidates:?}", found.pairs);
    }

    #[test]
    fn block_rows_keep_their_nearest_and_progress_rises_to_one() {
        let base = a_b_a();
        let search = StackedSearch::new(&base, &OFFSETS, Some(&MirrorMap::end_effectors())).unwrap();
        let (rows, cols) = (Span { start: 900, end: 1199 }, Span { start: 0, end: 299 });
        let all = FarSearch::new(&search, 200, 60.0, 100_000, 10.0, 30.0)
            .block(&search.queries, rows, cols, &mut |_| Ok(()))
            .unwrap();
        let capped = FarSearch::new(&search, 200, 60.0, 7, 10.0, 30.0)
            .block(&search.queries, rows, cols, &mut |_| Ok(()))
            .unwrap();
        let row_of = |v: &[(u32, u32, f32)], i: u32| -> Vec<(u32, f32)> {
            v.iter().filter(|e| e.0 == i).map(|e| (e.1, e.2)).collect()
        };
        // (the stacked windows of frames 900–909 reach into B)
        for i in 910..1200u32 {
            let mut nearest = row_of(&all, i);
            assert!(nearest.len() > 7, "row {i} needs more than 7 neighbours, has {}", nearest.len());
            crate::similarity::neighbours::cap_row(&mut nearest, 7);
            assert_eq!(row_of(&capped, i), nearest, "row {i}");
        }
        // progress: rising, ending at 1
        let far = FarSearch::new(&search, 200, 19.0 * 5f32.sqrt(), 600, 13.0 * 5f32.sqrt(), 30.0);
        let mut seen = Vec::new();
        far.search(&spans(), &[Some(6.0); 3], &mut |f| {
            seen.push(f);
            Ok(())
        })
        .unwrap();
        assert!(seen.len() >= 4, "{seen:?}");
        assert!(seen.windows(2).all(|w| w[0] <= w[1]) && seen.iter().all(|f| (0.0..=1.0).contains(f)), "{seen:?}");
        assert_eq!(seen.last(), Some(&1.0));
    }

    #[test]
    fn a_search_reports_inside_its_blocks_and_stops_there_when_cancelled() {
        let base = a_b_a();
        let search = StackedSearch::new(&base, &OFFSETS, Some(&MirrorMap::end_effectors())).unwrap();
        let far = FarSearch::new(&search, 200, 19.0 * 5f32.sqrt(), 600, 13.0 * 5f32.sqrt(), 30.0);
        let limits = [Some(6.0); 3];
        // three own blocks and one candidate block, each reporting every 256 rows
        let mut seen = Vec::new();
        let found = far.search(&spans(), &limits, &mut |f| {
            seen.push(f);
            Ok(())
        });
        assert_eq!(found.unwrap().pairs.len(), 1);
        assert!(seen.windows(2).all(|w| w[0] <= w[1]), "{seen:?}");
        // A's own block is 1/7 of the work (300² of 300² + 600² + 300² + 300²), B's the next 4/7:
        // the first report past 2/7 is from inside B's block
        let b_inside = seen.iter().position(|&f| f > 2.0 / 7.0).unwrap();
        assert!(seen[b_inside] < 5.0 / 7.0 - 1e-9, "{seen:?}");
        for stop_at in [1, b_inside, seen.len() - 1] {
            let mut calls = 0;
            let r = far.search(&spans(), &limits, &mut |_| {
                calls += 1;
                if calls > stop_at {
                    Err(Cancelled)
                } else {
                    Ok(())
                }
            });
            assert_eq!(r, Err(Cancelled), "cancelled at report {stop_at}");
            assert_eq!(calls, stop_at + 1, "no report after the cancelling one");
        }
    }

    #[test]
    fn far_entries_are_merged_into_their_rows_in_order_and_capped() {
        // frames 0..10, near entries up to 2 apart
        let lists: Vec<Vec<(u32, f32)>> = (0..10u32)
            .map(|i| (i.saturating_sub(2)..(i + 3).min(10)).map(|j| (j, i.abs_diff(j) as f32)).collect())
            .collect();
        let sssm = Sssm::from_lists(&lists).unwrap();
        let far = [(9u32, 0u32, 0.5f32), (8, 1, 7.0), (9, 3, 3.0)];
        let merged = sssm.with_far_entries(&far, 100);
        let mut expected = lists.clone();
        for &(i, j, d) in &far {
            expected[i as usize].push((j, d));
            expected[j as usize].push((i, d));
        }
        expected.iter_mut().for_each(|l| l.sort_by_key(|e| e.0));
        assert_eq!(merged.to_lists(), expected);
        // capped again to the nearest: row 9 keeps (9,0.0), (0,0.5), (8,1.0)
        let capped = sssm.with_far_entries(&far, 3);
        assert_eq!(capped.row(9).0, &[0, 8, 9]);
        assert!(capped.row(0).0.len() <= 3);
        assert_eq!(sssm.with_far_entries(&[], 3), sssm);
    }
}
