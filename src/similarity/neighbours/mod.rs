//! Local neighbours and the sparse self-similarity matrix (Krüger et al. 2017, §IV-A).
//!
//! For every frame `i` a kd-tree radius search gives the set `S_i` of pairs `(j, d_ij)` with
//! `d_ij ≤ r`; together they are the sparse self-similarity matrix (SSSM), stored in
//! compressed rows ([`Sssm`]) and never as a dense `n × n` matrix.
//!
//! The stacked features have 75 dimensions, too many for a kd-tree to prune on directly (a tree
//! over a few thousand points only ever splits on its first few axes). So the features are
//! first rotated onto their principal axes (a rotation keeps every Euclidean distance), the
//! kiddo tree is built over the leading [`TREE_DIMS`] coordinates, and each candidate it
//! returns — the distance over those coordinates is a lower bound of the full distance — is
//! checked over the remaining coordinates with an early exit. The result is exact.

use kiddo::immutable::float::kdtree::ImmutableKdTree;
use kiddo::SquaredEuclidean;
use serde::{Deserialize, Serialize};

use super::SimilarityError;
use crate::features::pca::{principal_axes, rotate};
use crate::features::FeatureMatrix;
use crate::method::Cancelled;

pub mod far;
pub mod stacked;
pub use far::FarSearch;
pub use stacked::StackedSearch;

/// Frames between two progress reports of a search.
const PROGRESS_ROWS: usize = 64;

/// The neighbour entries a run's searches may still make: the memory a run is allowed beyond
/// its per-frame arrays, counted as the entries are found rather than assumed for the worst case
/// (every frame with `max_neighbours` neighbours, which a real take seldom comes near). The near
/// search draws an entry for each pair of its upper triangle, the far search two for each far
/// pair (both directions); the plain and the mirror search draw from the same budget (at once,
/// natively: the count is atomic). A search that would pass it stops as a cancelled one does, and
/// [`EntryBudget::spent`] tells the caller why.
#[derive(Debug)]
pub struct EntryBudget {
    limit: usize,
    used: std::sync::atomic::AtomicUsize,
}

impl EntryBudget {
    /// At most `limit` entries.
    pub fn new(limit: usize) -> Self {
        EntryBudget { limit, used: std::sync::atomic::AtomicUsize::new(0) }
    }

    /// No limit (the searches' own callers: tests, the library, which bounds itself).
    pub fn unlimited() -> Self {
        EntryBudget::new(usize::MAX)
    }

    /// Draws `entries`; `Err(Cancelled)` once the budget is passed (the search stops there).
    pub fn take(&self, entries: usize) -> Result<(), Cancelled> {
        let used = self.used.fetch_add(entries, std::sync::atomic::Ordering::Relaxed).saturating_add(entries);
        if used > self.limit {
            Err(Cancelled)
        } else {
            Ok(())
        }
    }

    /// Whether a search passed the budget (and stopped for it).
    pub fn spent(&self) -> bool {
        self.used() > self.limit
    }

    /// Entries drawn so far.
    pub fn used(&self) -> usize {
        self.used.load(std::sync::atomic::Ordering::Relaxed)
    }

    /// The limit.
    pub fn limit(&self) -> usize {
        self.limit
    }
}

/// Number of leading principal coordinates the kd-tree indexes.
pub const TREE_DIMS: usize = 4;

/// A sparse self-similarity matrix: for each frame `i`, its neighbours `j` (ascending) and the
/// distances `d_ij`, in compressed-row form.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Sssm {
    n: usize,
    starts: Vec<u32>,
    cols: Vec<u32>,
    dists: Vec<f32>,
}

impl Sssm {
    /// Builds an SSSM from per-frame lists `(j, d_ij)` (any order). Indices must be `< n` and
    /// distinct within a list, distances finite and ≥ 0.
    pub fn from_lists(lists: &[Vec<(u32, f32)>]) -> Result<Sssm, SimilarityError> {
        let n = lists.len();
        let mut b = SssmBuilder::new(n);
        let mut row = Vec::new();
        for (i, list) in lists.iter().enumerate() {
            row.clear();
            row.extend_from_slice(list);
            if let Some(&(j, d)) = row.iter().find(|&&(j, d)| j as usize >= n || !(d.is_finite() && d >= 0.0)) {
                return Err(SimilarityError::BadNeighbours(format!(
                    "frame {i}: neighbour ({j}, {d}) is out of range or has an invalid distance"
                )));
            }
            row.sort_unstable_by_key(|&(j, _)| j);
            if let Some(w) = row.windows(2).find(|w| w[0].0 == w[1].0) {
                return Err(SimilarityError::BadNeighbours(format!("frame {i}: neighbour {} is listed twice", w[0].0)));
            }
            b.push_sorted_row(&row);
        }
        Ok(b.finish())
    }

    /// Number of frames (rows).
    pub fn frames(&self) -> usize {
        self.n
    }

    /// Total number of neighbour entries.
    pub fn entries(&self) -> usize {
        self.cols.len()
    }

    /// Entry indices of row `i`.
    pub fn row_range(&self, i: usize) -> std::ops::Range<usize> {
        self.starts[i] as usize..self.starts[i + 1] as usize
    }

    /// Neighbour frames (ascending) and distances of frame `i`.
    pub fn row(&self, i: usize) -> (&[u32], &[f32]) {
        let r = self.row_range(i);
        (&self.cols[r.clone()], &self.dists[r])
    }

    /// Neighbour frame of entry `e`.
    pub fn col(&self, e: usize) -> u32 {
        self.cols[e]
    }

    /// Distance of entry `e`.
    pub fn dist(&self, e: usize) -> f32 {
        self.dists[e]
    }

    /// All neighbour frames, entry by entry (row after row).
    pub fn cols(&self) -> &[u32] {
        &self.cols
    }

    /// All distances, entry by entry.
    pub fn dists(&self) -> &[f32] {
        &self.dists
    }

    /// Row starts: row `i` holds entries `starts[i]..starts[i+1]`.
    pub fn starts(&self) -> &[u32] {
        &self.starts
    }

    /// The distance `d_ij` if `j` is a neighbour of `i`.
    pub fn get(&self, i: usize, j: usize) -> Option<f32> {
        let (cols, dists) = self.row(i);
        cols.binary_search(&(j as u32)).ok().map(|k| dists[k])
    }

    /// The entries within `radius` (a sparser SSSM over the same frames).
    pub fn within(&self, radius: f32) -> Sssm {
        let mut b = SssmBuilder::new(self.n);
        b.cols.reserve(self.entries());
        for i in 0..self.n {
            for e in self.row_range(i) {
                if self.dists[e] <= radius {
                    b.cols.push(self.cols[e]);
                    b.dists.push(self.dists[e]);
                }
            }
            b.starts.push(b.cols.len() as u32);
        }
        b.finish()
    }

    /// Row by row union of two SSSMs over the same frames (the smaller distance where both
    /// hold an entry).
    pub fn union(&self, other: &Sssm) -> Sssm {
        assert_eq!(self.n, other.n, "SSSMs over different takes");
        let mut b = SssmBuilder::new(self.n);
        let mut row = Vec::new();
        for i in 0..self.n {
            row.clear();
            let (ca, da) = self.row(i);
            let (cb, db) = other.row(i);
            let (mut x, mut y) = (0, 0);
            while x < ca.len() || y < cb.len() {
                let take_a = y == cb.len() || (x < ca.len() && ca[x] <= cb[y]);
                let take_b = x == ca.len() || (y < cb.len() && cb[y] <= ca[x]);
                match (take_a, take_b) {
                    (true, true) => {
                        row.push((ca[x], da[x].min(db[y])));
                        x += 1;
                        y += 1;
                    }
                    (true, false) => {
                        row.push((ca[x], da[x]));
                        x += 1;
                    }
                    _ => {
                        row.push((cb[y], db[y]));
                        y += 1;
                    }
                }
            }
            b.push_sorted_row(&row);
        }
        b.finish()
    }

    /// Keeps the `max` nearest entries of every row (as [`cap_row`]), in place.
    pub fn cap_rows(&mut self, max: usize) {
        let n = self.n;
        if (0..n).all(|i| self.row_range(i).len() <= max) {
            return;
        }
        // each row moves down over what earlier rows dropped
        let mut row = Vec::new();
        let mut at = 0usize;
        for i in 0..n {
            let r = self.row_range(i);
            self.starts[i] = at as u32;
            if r.len() <= max {
                self.cols.copy_within(r.clone(), at);
                self.dists.copy_within(r.clone(), at);
                at += r.len();
                continue;
            }
            row.clear();
            row.extend(r.map(|e| (self.cols[e], self.dists[e])));
            cap_row(&mut row, max);
            for &(j, d) in &row {
                self.cols[at] = j;
                self.dists[at] = d;
                at += 1;
            }
        }
        self.starts[n] = at as u32;
        self.cols.truncate(at);
        self.dists.truncate(at);
    }

    /// The lists as `(j, d_ij)` pairs (for export; the method itself works on the rows).
    pub fn to_lists(&self) -> Vec<Vec<(u32, f32)>> {
        (0..self.n).map(|i| self.row_range(i).map(|e| (self.cols[e], self.dists[e])).collect()).collect()
    }
}

/// Appends sorted rows into an [`Sssm`].
struct SssmBuilder {
    n: usize,
    starts: Vec<u32>,
    cols: Vec<u32>,
    dists: Vec<f32>,
}

impl SssmBuilder {
    fn new(n: usize) -> Self {
        let mut starts = Vec::with_capacity(n + 1);
        starts.push(0);
        SssmBuilder { n, starts, cols: Vec::new(), dists: Vec::new() }
    }

    fn push_sorted_row(&mut self, row: &[(u32, f32)]) {
        for &(j, d) in row {
            self.cols.push(j);
            self.dists.push(d);
        }
        self.starts.push(self.cols.len() as u32);
    }

    fn finish(self) -> Sssm {
        debug_assert_eq!(self.starts.len(), self.n + 1);
        Sssm { n: self.n, starts: self.starts, cols: self.cols, dists: self.dists }
    }
}

/// The searchable form of a feature matrix: its frames rotated onto their principal axes and
/// a kd-tree over the leading coordinates.
pub struct NeighbourSearch {
    dim: usize,
    mean: Vec<f32>,
    /// `dim × dim` rotation, row `k` = principal axis `k` (by decreasing variance).
    axes: Vec<f32>,
    /// The rotated frames, frame-major.
    rotated: Vec<f32>,
    tree: ImmutableKdTree<f32, u32, TREE_DIMS, 32>,
    /// What the symmetric searches may find.
    budget: EntryBudget,
}

impl NeighbourSearch {
    /// Indexes the frames of `features`.
    pub fn new(features: &FeatureMatrix) -> Self {
        let dim = features.dim();
        let (mean, axes) = principal_axes(features);
        let rotated = rotate(features, &mean, &axes);
        let leading: Vec<[f32; TREE_DIMS]> = rotated.chunks_exact(dim).map(leading_coords).collect();
        let tree = ImmutableKdTree::new_from_slice(&leading);
        NeighbourSearch { dim, mean, axes, rotated, tree, budget: EntryBudget::unlimited() }
    }

    /// The symmetric searches draw their entries from a budget of `limit` ([`EntryBudget`]).
    pub fn with_entry_limit(mut self, limit: usize) -> Self {
        self.budget = EntryBudget::new(limit);
        self
    }

    /// The entries the searches drew, and whether they passed the limit.
    pub fn budget(&self) -> &EntryBudget {
        &self.budget
    }

    /// The SSSM of the indexed frames: for every frame its neighbours within `radius` (the
    /// frame itself included, at distance 0), at most `max_neighbours` of them (the nearest).
    pub fn self_similarity(&self, radius: f32, max_neighbours: usize) -> Sssm {
        match self.self_similarity_with_progress(radius, max_neighbours, &mut |_| Ok(())) {
            Ok(sssm) => sssm,
            Err(Cancelled) => unreachable!("a callback that never cancels"),
        }
    }

    /// [`Self::self_similarity`], reporting the fraction of the frames done (every 64 frames);
    /// stops as soon as `progress` returns `Err(Cancelled)`.
    pub fn self_similarity_with_progress(
        &self,
        radius: f32,
        max_neighbours: usize,
        progress: &mut dyn FnMut(f64) -> Result<(), Cancelled>,
    ) -> Result<Sssm, Cancelled> {
        self.search_symmetric(&self.rotated, radius, max_neighbours, progress)
    }

    /// The mirror SSSM (§V): for every frame `i`, the frames `j` with `|M·F_i − F_j| ≤ radius`,
    /// `M` the mirror map. `M` is an isometry and its own inverse, so
    /// `|M·F_i − F_j| = |M·F_j − F_i|` and, like the SSSM, the matrix is symmetric.
    pub fn mirror_similarity(
        &self,
        mirrored: &FeatureMatrix,
        radius: f32,
        max_neighbours: usize,
    ) -> Result<Sssm, SimilarityError> {
        self.mirror_similarity_with_progress(mirrored, radius, max_neighbours, &mut |_| Ok(()))
    }

    /// [`Self::mirror_similarity`], reporting and stopping as
    /// [`Self::self_similarity_with_progress`] does ([`SimilarityError::Cancelled`]).
    pub fn mirror_similarity_with_progress(
        &self,
        mirrored: &FeatureMatrix,
        radius: f32,
        max_neighbours: usize,
        progress: &mut dyn FnMut(f64) -> Result<(), Cancelled>,
    ) -> Result<Sssm, SimilarityError> {
        self.check_dim(mirrored)?;
        Ok(self.search_symmetric(&rotate(mirrored, &self.mean, &self.axes), radius, max_neighbours, progress)?)
    }

    /// For every row of `queries`, its neighbours among the indexed frames (no symmetry
    /// assumed).
    pub fn cross_similarity(
        &self,
        queries: &FeatureMatrix,
        radius: f32,
        max_neighbours: usize,
    ) -> Result<Sssm, SimilarityError> {
        self.check_dim(queries)?;
        Ok(self.search(&rotate(queries, &self.mean, &self.axes), radius, max_neighbours))
    }

    fn check_dim(&self, queries: &FeatureMatrix) -> Result<(), SimilarityError> {
        if queries.dim() != self.dim {
            return Err(SimilarityError::BadFeatures(format!(
                "query features have {} values per frame, the indexed ones {}",
                queries.dim(),
                self.dim
            )));
        }
        Ok(())
    }

    /// The (at most `max`) nearest neighbours `j` of query `q` within `limit` (squared) whose
    /// index is at least `from`, ascending, appended to `out` as `(j, distance)`.
    fn query(&self, q: &[f32], limit: f32, from: usize, max: usize, out: &mut Vec<(u32, f32)>) {
        let d = self.dim;
        let first = out.len();
        for c in self.tree.within_unsorted::<SquaredEuclidean>(&leading_coords(q), limit) {
            let j = c.item as usize;
            if j >= from {
                if let Some(d2) = finish_distance(q, &self.rotated[j * d..(j + 1) * d], c.distance, limit) {
                    out.push((c.item, d2.sqrt()));
                }
            }
        }
        out[first..].sort_unstable_by_key(|c| c.0);
        cap_tail(out, first, max);
    }

    fn search(&self, rotated_queries: &[f32], radius: f32, max_neighbours: usize) -> Sssm {
        let limit = radius * radius;
        let mut b = SssmBuilder::new(rotated_queries.len() / self.dim);
        let mut row = Vec::new();
        for q in rotated_queries.chunks_exact(self.dim) {
            row.clear();
            self.query(q, limit, 0, max_neighbours, &mut row);
            b.push_sorted_row(&row);
        }
        b.finish()
    }

    /// Search for a symmetric matrix: each query `i` only looks for `j ≥ i` (half the distance
    /// computations) and entry `(i, j)` also gives `(j, i)`. The cap applies to each query's
    /// `j ≥ i` and again to the finished rows, so at most `2 · max_neighbours` entries per frame
    /// are ever held (a still take, where every frame is everyone's neighbour, stays small).
    fn search_symmetric(
        &self,
        rotated_queries: &[f32],
        radius: f32,
        max_neighbours: usize,
        progress: &mut dyn FnMut(f64) -> Result<(), Cancelled>,
    ) -> Result<Sssm, Cancelled> {
        let limit = radius * radius;
        let n = rotated_queries.len() / self.dim;
        let mut upper = UpperTriangle::new(n);
        for (i, q) in rotated_queries.chunks_exact(self.dim).enumerate() {
            if i % PROGRESS_ROWS == 0 {
                progress(i as f64 / n as f64)?;
            }
            let before = upper.entries.len();
            self.query(q, limit, i, max_neighbours, &mut upper.entries);
            self.budget.take(upper.entries.len() - before)?;
            upper.end_row();
        }
        let sssm = upper.into_symmetric(max_neighbours);
        progress(1.0)?;
        Ok(sssm)
    }
}

/// Rows transposed together by [`UpperTriangle::into_symmetric`].
const TRANSPOSE_BLOCK: usize = 64;

/// The upper triangle (`j ≥ i`) of a symmetric SSSM, row by row (each row sorted by `j`), as a
/// search produces it.
pub(crate) struct UpperTriangle {
    n: usize,
    /// `(j, d_ij)` of every row, ascending `j` within a row.
    pub(crate) entries: Vec<(u32, f32)>,
    starts: Vec<usize>,
}

impl UpperTriangle {
    pub(crate) fn new(n: usize) -> Self {
        let mut starts = Vec::with_capacity(n + 1);
        starts.push(0);
        UpperTriangle { n, entries: Vec::new(), starts }
    }

    /// Closes the current row (its entries are those pushed since the last call).
    pub(crate) fn end_row(&mut self) {
        self.starts.push(self.entries.len());
    }

    /// The full symmetric matrix: row `i` = its lower entries (from earlier rows, ascending)
    /// then its upper entries. The cap applies to each row of the triangle and again to the
    /// finished rows, so at most `2 · max_neighbours` entries per frame are ever held (a still
    /// take, where every frame is everyone's neighbour, stays small).
    pub(crate) fn into_symmetric(self, max_neighbours: usize) -> Sssm {
        let UpperTriangle { n, entries: upper, starts: upper_starts } = self;
        debug_assert_eq!(upper_starts.len(), n + 1);
        let mut lower = vec![0u32; n];
        for &(j, _) in &upper {
            lower[j as usize] += 1;
        }
        for i in 0..n {
            // the diagonal entry (i, i) was counted as "lower" of row i; it belongs to upper
            if upper[upper_starts[i]..upper_starts[i + 1]].first().is_some_and(|&(j, _)| j as usize == i) {
                lower[i] -= 1;
            }
        }
        let mut starts = Vec::with_capacity(n + 1);
        starts.push(0u32);
        for i in 0..n {
            let len = lower[i] as usize + upper_starts[i + 1] - upper_starts[i];
            starts.push(starts[i] + len as u32);
        }
        let total = starts[n] as usize;
        let mut cols = vec![0u32; total];
        let mut dists = vec![0f32; total];
        let mut fill: Vec<u32> = starts[..n].to_vec();
        // Entry (i, j) of the triangle is entry (j, i) of row j's lower part. Writing them row
        // by row would jump across the whole matrix for every entry; instead each block of
        // `TRANSPOSE_BLOCK` rows is first sorted by `j` in a small buffer (a counting sort), then
        // copied out with `j` ascending, so the writes move through memory in order.
        let mut count = vec![0u32; n + 1];
        let mut buffer: Vec<(u32, f32)> = Vec::new();
        for block in (0..n).step_by(TRANSPOSE_BLOCK) {
            let rows = block..(block + TRANSPOSE_BLOCK).min(n);
            // the columns these rows reach (rows are sorted: the last entry is the farthest), so
            // that a banded SSSM (search horizon) costs the band, not n, per block
            let end = rows
                .clone()
                .filter_map(|i| upper[upper_starts[i]..upper_starts[i + 1]].last().map(|e| e.0 as usize + 1))
                .max()
                .unwrap_or(block)
                .max(block);
            count[block..=end].iter_mut().for_each(|c| *c = 0);
            for i in rows.clone() {
                for &(j, _) in &upper[upper_starts[i]..upper_starts[i + 1]] {
                    count[j as usize + 1] += u32::from(j as usize != i);
                }
            }
            for j in block..end {
                count[j + 1] += count[j];
            }
            buffer.resize(count[end] as usize, (0, 0.0));
            for i in rows {
                for &(j, d) in &upper[upper_starts[i]..upper_starts[i + 1]] {
                    if j as usize != i {
                        let k = &mut count[j as usize];
                        buffer[*k as usize] = (i as u32, d);
                        *k += 1;
                    }
                }
            }
            // count[j] is now the end of row j's run in the buffer
            let mut from = 0usize;
            for j in block..end {
                let to = count[j] as usize;
                let at = fill[j] as usize;
                for (k, &(i, d)) in (at..).zip(&buffer[from..to]) {
                    cols[k] = i;
                    dists[k] = d;
                }
                fill[j] += (to - from) as u32;
                from = to;
            }
        }
        for i in 0..n {
            let (from, to) = (upper_starts[i], upper_starts[i + 1]);
            let at = fill[i] as usize;
            for (k, &(j, d)) in (at..).zip(&upper[from..to]) {
                cols[k] = j;
                dists[k] = d;
            }
        }
        let mut sssm = Sssm { n, starts, cols, dists };
        sssm.cap_rows(max_neighbours);
        sssm
    }
}

/// Keeps the `max` nearest entries of a row sorted by index (still sorted by index after; of
/// entries tied at the cut-off distance the lower indices stay). Linear in the row's length.
pub(crate) fn cap_row(row: &mut Vec<(u32, f32)>, max: usize) {
    cap_tail(row, 0, max);
}

/// [`cap_row`] for the entries `row[first..]` (the earlier entries are left alone).
pub(crate) fn cap_tail(row: &mut Vec<(u32, f32)>, first: usize, max: usize) {
    let tail = &mut row[first..];
    if tail.len() <= max {
        return;
    }
    if max == 0 {
        row.truncate(first);
        return;
    }
    let cutoff = CAP_SCRATCH.with(|scratch| {
        let mut dists = scratch.take();
        dists.clear();
        dists.extend(tail.iter().map(|e| e.1));
        let (_, &mut cutoff, _) = dists.select_nth_unstable_by(max - 1, f32::total_cmp);
        scratch.set(dists);
        cutoff
    });
    // entries nearer than the cut-off all stay; those at it fill the rest in index order
    let nearer = tail.iter().filter(|e| e.1 < cutoff).count();
    let mut ties = max - nearer;
    let mut kept = 0;
    for k in 0..tail.len() {
        let e = tail[k];
        let keep = e.1 < cutoff || (e.1 == cutoff && ties > 0);
        if keep {
            if e.1 == cutoff {
                ties -= 1;
            }
            tail[kept] = e;
            kept += 1;
        }
    }
    row.truncate(first + kept);
}

thread_local! {
    /// The distances [`cap_tail`] selects from (kept to avoid an allocation per row).
    static CAP_SCRATCH: std::cell::Cell<Vec<f32>> = const { std::cell::Cell::new(Vec::new()) };
}

/// The leading [`TREE_DIMS`] coordinates of a rotated frame (zero-padded).
fn leading_coords(x: &[f32]) -> [f32; TREE_DIMS] {
    let mut p = [0f32; TREE_DIMS];
    let k = x.len().min(TREE_DIMS);
    p[..k].copy_from_slice(&x[..k]);
    p
}

/// Adds the squared differences beyond the tree's coordinates to `partial`; `None` as soon as
/// the sum exceeds `limit` (checked every 16 values; 8 independent sums let the compiler
/// vectorise).
fn finish_distance(a: &[f32], b: &[f32], partial: f32, limit: f32) -> Option<f32> {
    if partial > limit {
        return None;
    }
    let (a, b) = (&a[TREE_DIMS.min(a.len())..], &b[TREE_DIMS.min(b.len())..]);
    let mut sum = partial;
    for (ca, cb) in a.chunks(16).zip(b.chunks(16)) {
        let mut acc = [0f32; 8];
        let (ea, eb) = (ca.chunks_exact(8), cb.chunks_exact(8));
        let (ra, rb) = (ea.remainder(), eb.remainder());
        for (x, y) in ea.zip(eb) {
            for k in 0..8 {
                let t = x[k] - y[k];
                acc[k] += t * t;
            }
        }
        for (x, y) in ra.iter().zip(rb) {
            acc[0] += (x - y) * (x - y);
        }
        sum += acc.iter().sum::<f32>();
        if sum > limit {
            return None;
        }
    }
    Some(sum)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic pseudo-random walk: neighbours are frames close in time.
    fn noisy(n: usize, d: usize, seed: u64) -> FeatureMatrix {
        walk(n, d, seed, 1.0)
    }

    /// A deterministic pseudo-random walk in `d` dimensions: each step keeps `decay` of the
    /// position (1 = a free walk, below 1 it stays near the origin) and adds uniform noise.
    pub(super) fn walk(n: usize, d: usize, seed: u64, decay: f32) -> FeatureMatrix {
        let mut rng = crate::stats::Rng::new(seed);
        let mut x = vec![0f32; d];
        let mut data = Vec::with_capacity(n * d);
        for _ in 0..n {
            for v in x.iter_mut() {
                *v = decay * *v + 2.0 * rng.next_f32() - 1.0;
            }
            data.extend_from_slice(&x);
        }
        FeatureMatrix::new(n, d, data).unwrap()
    }

    /// For every row of `q`, its rows of `f` within `r` (ascending), by measuring every pair.
    pub(super) fn brute_force(f: &FeatureMatrix, q: &FeatureMatrix, r: f32) -> Vec<Vec<(u32, f32)>> {
        (0..q.frames())
            .map(|i| {
                (0..f.frames())
                    .filter_map(|j| {
                        let d2: f32 = q.row(i).iter().zip(f.row(j)).map(|(a, b)| (a - b) * (a - b)).sum();
                        (d2 <= r * r).then(|| (j as u32, d2.sqrt()))
                    })
                    .collect()
            })
            .collect()
    }

    fn same_lists(a: &Sssm, b: &[Vec<(u32, f32)>]) {
        let la = a.to_lists();
        assert_eq!(la.len(), b.len());
        for (i, (x, y)) in la.iter().zip(b).enumerate() {
            let xi: Vec<u32> = x.iter().map(|p| p.0).collect();
            let yi: Vec<u32> = y.iter().map(|p| p.0).collect();
            assert_eq!(xi, yi, "row {i}");
            for (p, q) in x.iter().zip(y) {
                assert!((p.1 - q.1).abs() < 1e-3, "row {i}: {p:?} vs {q:?}");
            }
        }
    }

    #[test]
    fn radius_search_matches_brute_force_in_high_dimension() {
        let f = noisy(400, 30, 7);
        let s = NeighbourSearch::new(&f);
        let sssm = s.self_similarity(14.0, 10_000);
        let truth = brute_force(&f, &f, 14.0);
        assert!(sssm.entries() > 2000, "the test needs real neighbours, got {}", sssm.entries());
        same_lists(&sssm, &truth);
        // every frame is its own neighbour at distance 0
        assert_eq!(sssm.get(17, 17), Some(0.0));
    }

    #[test]
    fn radius_search_matches_brute_force_in_low_dimension() {
        let f = noisy(300, 3, 3);
        let s = NeighbourSearch::new(&f);
        same_lists(&s.self_similarity(2.0, 10_000), &brute_force(&f, &f, 2.0));
    }

    #[test]
    fn cross_search_finds_the_query_frames_among_the_indexed_ones() {
        let f = noisy(200, 12, 11);
        let q = noisy(50, 12, 12);
        let s = NeighbourSearch::new(&f);
        let cross = s.cross_similarity(&q, 12.0, 10_000).unwrap();
        assert_eq!(cross.frames(), 50);
        same_lists(&cross, &brute_force(&f, &q, 12.0));
        assert!(s.cross_similarity(&noisy(5, 3, 1), 1.0, 10).is_err());
    }

    #[test]
    fn mirror_search_matches_brute_force_and_is_symmetric() {
        let f = noisy(300, 15, 5);
        let map = crate::features::MirrorMap::end_effectors();
        let m = map.apply(&f).unwrap();
        let s = NeighbourSearch::new(&f);
        let mirror = s.mirror_similarity(&m, 14.0, 10_000).unwrap();
        let truth = brute_force(&f, &m, 14.0);
        assert!(mirror.entries() > 300, "the test needs real neighbours, got {}", mirror.entries());
        same_lists(&mirror, &truth);
        same_lists(&s.cross_similarity(&m, 14.0, 10_000).unwrap(), &truth);
        for i in 0..300 {
            for (&j, &d) in mirror.row(i).0.iter().zip(mirror.row(i).1) {
                assert_eq!(mirror.get(j as usize, i), Some(d), "({i}, {j})");
            }
        }
    }

    #[test]
    fn the_cap_keeps_the_nearest_neighbours() {
        let rows: Vec<[f32; 1]> = (0..50).map(|i| [i as f32]).collect();
        let f = FeatureMatrix::from_rows(&rows).unwrap();
        let sssm = NeighbourSearch::new(&f).self_similarity(100.0, 5);
        let (cols, dists) = sssm.row(20);
        assert_eq!(cols, &[18, 19, 20, 21, 22]);
        assert_eq!(dists, &[2.0, 1.0, 0.0, 1.0, 2.0]);
        let (cols, _) = sssm.row(0);
        assert_eq!(cols, &[0, 1, 2, 3, 4]);
    }

    #[test]
    fn identical_frames_do_not_break_the_tree() {
        let f = FeatureMatrix::new(500, 4, vec![1.5; 2000]).unwrap();
        let sssm = NeighbourSearch::new(&f).self_similarity(0.1, 600);
        assert_eq!(sssm.row(0).0.len(), 500);
        assert_eq!(sssm.entries(), 500 * 500);
        // a still take longer than the cap: every row keeps exactly the cap
        let f = FeatureMatrix::new(2000, 4, vec![1.5; 8000]).unwrap();
        let sssm = NeighbourSearch::new(&f).self_similarity(0.1, 50);
        assert!((0..2000).all(|i| sssm.row(i).0.len() == 50));
        // row 1000 gathers 1000..=1049 (its own query) and 951..=999 (rows whose queries
        // reached it); of these ties at distance 0 the lowest indices stay
        assert_eq!(sssm.row(1000).0, (951..=1000).collect::<Vec<u32>>().as_slice());
    }

    #[test]
    fn within_keeps_the_near_entries() {
        let a = Sssm::from_lists(&[vec![(0, 0.0), (2, 3.0)], vec![(0, 4.0)], vec![(1, 1.0)]]).unwrap();
        assert_eq!(a.within(3.0).to_lists(), vec![vec![(0, 0.0), (2, 3.0)], vec![], vec![(1, 1.0)]]);
    }

    #[test]
    fn union_merges_rows_keeping_the_smaller_distance() {
        let a = Sssm::from_lists(&[vec![(0, 0.0), (2, 3.0)], vec![], vec![(1, 1.0)]]).unwrap();
        let b = Sssm::from_lists(&[vec![(1, 0.5), (2, 2.0)], vec![(0, 4.0)], vec![]]).unwrap();
        assert_eq!(a.union(&b).to_lists(), vec![vec![(0, 0.0), (1, 0.5), (2, 2.0)], vec![(0, 4.0)], vec![(1, 1.0)]]);
    }

    #[test]
    fn lists_are_validated() {
        assert!(Sssm::from_lists(&[vec![(1, 0.5)], vec![(0, 0.5)]]).is_ok());
        assert!(Sssm::from_lists(&[vec![(2, 0.5)], vec![]]).is_err());
        assert!(Sssm::from_lists(&[vec![(1, -0.5)], vec![]]).is_err());
        assert!(Sssm::from_lists(&[vec![(1, 0.5), (1, 0.7)], vec![]]).is_err());
        let s = Sssm::from_lists(&[vec![(1, 0.5), (0, 0.0)], vec![]]).unwrap();
        assert_eq!(s.row(0).0, &[0, 1]);
        assert_eq!(s.get(0, 1), Some(0.5));
        assert_eq!(s.get(1, 0), None);
    }
}
