//! The neighbourhood graph of a sparse self-similarity matrix and its warping paths (Krüger et al. 2017, §IV-C):
//! entry `(i, j)` (frame `j` a neighbour of frame `i`) is reached from `(i−1, j−1)`, `(i−1, j)` and `(i, j−1)` —
//! the dynamic-time-warping steps — so a warping path between two stretches of motion is a shortest path through
//! the entries of their block. SSSM cuts actions into primitives at the starts of these paths and clusters
//! primitives by them; the library matches segments across takes by them.

use petgraph::unionfind::UnionFind;
use serde::{Deserialize, Serialize};

use super::neighbours::Sssm;

/// An absent entry (a frame in no span, no predecessor).
pub(crate) const NONE: u32 = super::NONE;

/// The neighbourhood graph `G` of an SSSM: the predecessors of every entry under the steps
/// (1,1), (1,0), (0,1).
pub struct NeighbourhoodGraph<'a> {
    sssm: &'a Sssm,
    /// Row (frame `i`) of each entry.
    rows: Vec<u32>,
    /// Predecessor entries `[(i−1, j−1), (i−1, j), (i, j−1)]`, `NONE` where absent.
    preds: Vec<[u32; 3]>,
    scratch: std::cell::RefCell<Scratch>,
}

impl<'a> NeighbourhoodGraph<'a> {
    /// Links every entry of `sssm` to its predecessors (rows are sorted, so a merge per row).
    pub fn new(sssm: &'a Sssm) -> Self {
        let m = sssm.entries();
        let mut rows = vec![0u32; m];
        let mut preds = vec![[NONE; 3]; m];
        let cols = sssm.cols();
        for i in 0..sssm.frames() {
            let here = sssm.row_range(i);
            rows[here.clone()].iter_mut().for_each(|r| *r = i as u32);
            let above = if i > 0 { sssm.row_range(i - 1) } else { 0..0 };
            let mut p = above.start;
            for e in here.clone() {
                let j = cols[e];
                while p < above.end && cols[p].saturating_add(1) < j {
                    p += 1;
                }
                let mut q = p;
                if j > 0 && q < above.end && cols[q] + 1 == j {
                    preds[e][0] = q as u32;
                    q += 1;
                }
                if q < above.end && cols[q] == j {
                    preds[e][1] = q as u32;
                }
                if e > here.start && cols[e - 1] + 1 == j {
                    preds[e][2] = (e - 1) as u32;
                }
            }
        }
        NeighbourhoodGraph { sssm, rows, preds, scratch: Default::default() }
    }

    /// The SSSM this graph is built on.
    pub fn sssm(&self) -> &Sssm {
        self.sssm
    }

    /// Frame `i` of entry `e`.
    pub fn row_of(&self, e: usize) -> usize {
        self.rows[e] as usize
    }

    /// The shortest warping path of every connected component of the subgraph inside the
    /// blocks of the SSSM that `blocks` marks (an entry `(i, j)` lies in block
    /// `(rows[i], cols[j])`; edges only join entries of one block). Components that span a
    /// single frame, or whose last column cannot be reached from their first, have no path.
    ///
    /// Two sweeps in row order. The first joins each entry with its predecessors in a
    /// union-find (petgraph's), keeping for each component its earliest entry, whose row is the
    /// component's first column, and its last row. The second is the
    /// shortest-path recursion of the DAG, started at the first column. A predecessor lies in
    /// the same block exactly when no span boundary lies between the two frames, so that test
    /// is two lookups; rows outside every span are skipped whole, and with `diagonal_only`
    /// each row only visits the columns of its own span (a binary search).
    pub fn warping_paths(&self, blocks: &Blocks) -> Vec<WarpingPath> {
        let n = self.sssm.frames();
        let m = self.sssm.entries();
        let cols = self.sssm.cols();
        assert!(blocks.rows.len() == n && blocks.cols.len() == n, "block lookups must cover the take");
        let cont = |spans: &[u32]| -> Vec<bool> { (0..n).map(|i| i > 0 && spans[i - 1] == spans[i]).collect() };
        let (row_cont, col_cont) = (cont(blocks.rows), cont(blocks.cols));
        // the entries of row i inside the blocks, as an entry range plus a per-entry test
        let live_range = |i: usize| -> std::ops::Range<usize> {
            let r = self.sssm.row_range(i);
            if blocks.rows[i] == NONE {
                return r.start..r.start;
            }
            if !blocks.diagonal_only {
                return r;
            }
            let (s, e) = blocks.row_span_bounds(i);
            let row_cols = &cols[r.clone()];
            let a = row_cols.partition_point(|&j| (j as usize) < s);
            let b = row_cols.partition_point(|&j| (j as usize) <= e);
            r.start + a..r.start + b
        };
        let live = |e: usize| blocks.cols[cols[e] as usize] != NONE;
        // which predecessors lie in the same block as entry e (row i, column j)
        let same = |k: usize, i: usize, j: usize| match k {
            0 => row_cont[i] && col_cont[j],
            1 => row_cont[i],
            _ => col_cont[j],
        };

        let mut scratch = self.scratch.borrow_mut();
        let Scratch { first, last, cost, start, nodes, best_end } = &mut *scratch;
        for v in [&mut *first, &mut *last, &mut *start, &mut *nodes, &mut *best_end] {
            v.resize(m, NONE);
        }
        cost.resize(m, f32::INFINITY);
        let mut components = UnionFind::<u32>::new(m);

        // sweep 1: components, with the earliest entry and the last row of each (indexed by the
        // component's representative)
        for i in 0..n {
            for e in live_range(i) {
                if !live(e) {
                    continue;
                }
                let j = cols[e] as usize;
                first[e] = e as u32;
                best_end[e] = NONE;
                for (k, &p) in self.preds[e].iter().enumerate() {
                    if p != NONE && same(k, i, j) {
                        let (a, b) = (components.find_mut(e as u32), components.find_mut(p));
                        if components.union(a, b) {
                            let earliest = first[a as usize].min(first[b as usize]);
                            first[components.find_mut(a) as usize] = earliest;
                        }
                    }
                }
                // the rows come in order: the last one to reach a component is its last row
                let r = components.find_mut(e as u32) as usize;
                last[r] = i as u32;
            }
        }

        // sweep 2: shortest paths from each component's first column
        let mut ends = Vec::new();
        for i in 0..n {
            for e in live_range(i) {
                if !live(e) {
                    continue;
                }
                let j = cols[e] as usize;
                let c = components.find_mut(e as u32) as usize;
                let (first_row, last_row) = (self.rows[first[c] as usize], last[c]);
                cost[e] = f32::INFINITY;
                if first_row == last_row {
                    continue;
                }
                let d = self.sssm.dist(e);
                if i as u32 == first_row {
                    (cost[e], start[e], nodes[e]) = (d, e as u32, 1);
                } else {
                    let mut best = NONE;
                    let mut best_cost = f32::INFINITY;
                    for (k, &p) in self.preds[e].iter().enumerate() {
                        if p != NONE && same(k, i, j) && cost[p as usize] < best_cost {
                            best = p;
                            best_cost = cost[p as usize];
                        }
                    }
                    if best != NONE {
                        let b = best as usize;
                        (cost[e], start[e], nodes[e]) = (best_cost + d, start[b], nodes[b] + 1);
                    }
                }
                if i as u32 == last_row && cost[e].is_finite() {
                    let be = best_end[c];
                    if be == NONE {
                        ends.push(c);
                    }
                    if be == NONE || cost[e] < cost[be as usize] {
                        best_end[c] = e as u32;
                    }
                }
            }
        }

        self.collect_paths(&ends, &scratch, blocks)
    }

    /// The warping path of each component of `ends`, from its start to its cheapest entry in its last row (what the
    /// sweeps of [`Self::warping_paths`] left in `s`), sorted by block, start and end.
    fn collect_paths(&self, ends: &[usize], sc: &Scratch, blocks: &Blocks) -> Vec<WarpingPath> {
        let cols = self.sssm.cols();
        let mut paths: Vec<WarpingPath> = ends
            .iter()
            .map(|&c| {
                let end = sc.best_end[c] as usize;
                let s = sc.start[end] as usize;
                let (i, j) = (self.row_of(end), cols[end] as usize);
                WarpingPath {
                    start: (self.row_of(s), cols[s] as usize),
                    end: (i, j),
                    cost: sc.cost[end],
                    nodes: sc.nodes[end] as usize,
                    region: ((blocks.rows[i] as u64) << 32) | blocks.cols[j] as u64,
                }
            })
            .collect();
        paths.sort_by_key(|p| (p.region, p.start, p.end));
        paths
    }
}

/// Which blocks of the SSSM a warping-path search runs in: frame `i` belongs to span
/// `rows[i]` as a row and `cols[i]` as a column (`NONE` = outside every span).
pub struct Blocks<'a> {
    pub rows: &'a [u32],
    pub cols: &'a [u32],
    /// Only the blocks on the diagonal (row span = column span; `rows` and `cols` equal).
    pub diagonal_only: bool,
    /// First and last frame of each span of `cols` (for `diagonal_only`).
    pub bounds: Vec<(usize, usize)>,
}

impl<'a> Blocks<'a> {
    /// The blocks `span × span` of the same span (actions against themselves).
    pub fn diagonal(of: &'a [u32]) -> Self {
        let count = of.iter().filter(|&&s| s != NONE).map(|&s| s as usize + 1).max().unwrap_or(0);
        let mut bounds = vec![(usize::MAX, 0); count];
        for (i, &s) in of.iter().enumerate() {
            if s != NONE {
                let b = &mut bounds[s as usize];
                b.0 = b.0.min(i);
                b.1 = b.1.max(i);
            }
        }
        Blocks { rows: of, cols: of, diagonal_only: true, bounds }
    }

    /// Every block `span × span'` (all pairs of spans).
    pub fn all_pairs(of: &'a [u32]) -> Self {
        Blocks { rows: of, cols: of, diagonal_only: false, bounds: Vec::new() }
    }

    /// Blocks given by separate row and column lookups (all pairs).
    pub fn rows_cols(rows: &'a [u32], cols: &'a [u32]) -> Self {
        Blocks { rows, cols, diagonal_only: false, bounds: Vec::new() }
    }

    fn row_span_bounds(&self, i: usize) -> (usize, usize) {
        self.bounds[self.rows[i] as usize]
    }
}

/// Work arrays of [`NeighbourhoodGraph::warping_paths`], one value per entry, kept between
/// calls (the searches for cuts and for cluster links run on the same graph).
#[derive(Default)]
struct Scratch {
    /// The earliest entry of the component a representative stands for.
    first: Vec<u32>,
    last: Vec<u32>,
    cost: Vec<f32>,
    start: Vec<u32>,
    nodes: Vec<u32>,
    best_end: Vec<u32>,
}

/// A warping path through one component of the neighbourhood graph: from entry `start` =
/// `(i, j)` to entry `end`, through `nodes` entries with summed distance `cost`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WarpingPath {
    pub start: (usize, usize),
    pub end: (usize, usize),
    pub cost: f32,
    pub nodes: usize,
    /// The block the path lies in: row span `<< 32 |` column span (see [`Blocks`]).
    pub region: u64,
}

impl WarpingPath {
    /// The block `(row span, column span)` the path lies in.
    pub fn block(&self) -> (usize, usize) {
        ((self.region >> 32) as usize, (self.region & 0xffff_ffff) as usize)
    }

    /// Average gradient `Δj / Δi` (`None` if the path stays in one frame `i`).
    pub fn slope(&self) -> Option<f64> {
        let di = self.end.0 - self.start.0;
        (di > 0).then(|| (self.end.1 as f64 - self.start.1 as f64) / di as f64)
    }

    /// Number of frames the path covers on the shorter of its two axes.
    pub fn frames(&self) -> usize {
        (self.end.0 - self.start.0).min(self.end.1.saturating_sub(self.start.1)) + 1
    }

    /// Mean distance per entry.
    pub fn mean_cost(&self) -> f32 {
        self.cost / self.nodes.max(1) as f32
    }

    /// The validity test of §IV-C: long enough and with a slope within `[1/ν, ν]`.
    pub fn is_valid(&self, nu: f64, min_frames: usize) -> bool {
        self.frames() >= min_frames && self.slope().is_some_and(|s| s >= 1.0 / nu && s <= nu)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sssm_from_pairs(n: usize, pairs: &[(usize, usize, f32)]) -> Sssm {
        let mut lists = vec![Vec::new(); n];
        for &(i, j, d) in pairs {
            lists[i].push((j as u32, d));
        }
        Sssm::from_lists(&lists).unwrap()
    }

    #[test]
    fn predecessors_follow_the_three_steps() {
        // entries (0,0) (0,1) (1,1) (1,2) (2,2)
        let s = sssm_from_pairs(3, &[(0, 0, 0.0), (0, 1, 1.0), (1, 1, 0.0), (1, 2, 1.0), (2, 2, 0.0)]);
        let g = NeighbourhoodGraph::new(&s);
        // (1,1): diagonal from (0,0), vertical from (0,1), none in its row
        assert_eq!(g.preds[2], [0, 1, NONE]);
        // (1,2): diagonal from (0,1), horizontal from (1,1)
        assert_eq!(g.preds[3], [1, NONE, 2]);
        // (2,2): diagonal from (1,1), vertical from (1,2)
        assert_eq!(g.preds[4], [2, 3, NONE]);
    }

    #[test]
    fn each_diagonal_is_one_component_with_its_cheapest_path() {
        // a diagonal j = i + 10 for i in 0..=20, doubled by a parallel cheaper lane j = i + 11
        let mut pairs = Vec::new();
        for i in 0..=20 {
            pairs.push((i, i + 10, 2.0));
            pairs.push((i, i + 11, 1.0));
        }
        // and a separate short diagonal j = i + 30 for i in 0..=3
        for i in 0..=3 {
            pairs.push((i, i + 30, 0.5));
        }
        let s = sssm_from_pairs(40, &pairs);
        let g = NeighbourhoodGraph::new(&s);
        let paths = g.warping_paths(&Blocks::all_pairs(&[0; 40]));
        assert_eq!(paths.len(), 2);
        let long = paths.iter().find(|p| p.nodes > 10).unwrap();
        assert_eq!(long.start, (0, 11));
        assert_eq!(long.end, (20, 31));
        assert_eq!(long.nodes, 21);
        assert!((long.cost - 21.0).abs() < 1e-5);
        assert_eq!(long.slope(), Some(1.0));
        let short = paths.iter().find(|p| p.nodes <= 10).unwrap();
        assert_eq!((short.start, short.end, short.frames()), ((0, 30), (3, 33), 4));
        // regions split the graph: only the part with i < 10 in region 0
        let rows: Vec<u32> = (0..40).map(|i| if i < 10 { 0 } else { NONE }).collect();
        let split_paths = g.warping_paths(&Blocks::rows_cols(&rows, &[0; 40]));
        let long = split_paths.iter().find(|p| p.start.1 == 11).unwrap();
        assert_eq!(long.end, (9, 20));
    }

    #[test]
    fn slope_filtering() {
        let path = |di: usize, dj: usize| WarpingPath {
            start: (0, 0),
            end: (di, dj),
            cost: 1.0,
            nodes: di.max(dj) + 1,
            region: 0,
        };
        assert!(path(20, 20).is_valid(2.0, 5));
        assert!(path(20, 40).is_valid(2.0, 5));
        assert!(path(20, 10).is_valid(2.0, 5));
        assert!(!path(20, 41).is_valid(2.0, 5), "slope 2.05 > ν");
        assert!(!path(20, 9).is_valid(2.0, 5), "slope 0.45 < 1/ν");
        assert!(!path(0, 9).is_valid(2.0, 5), "no extent in i");
        assert!(!path(3, 3).is_valid(2.0, 5), "4 frames < 5");
        assert!(path(3, 3).is_valid(2.0, 4));
        assert!(!path(20, 30).is_valid(1.2, 5));
    }

    #[test]
    fn a_steep_path_found_in_the_graph_is_rejected() {
        // a "standing" stretch: frames 30..=32 map onto 0..=29 (slope 10)
        let mut pairs = Vec::new();
        for j in 0..30 {
            pairs.push((30 + j / 10, j, 1.0));
        }
        let s = sssm_from_pairs(40, &pairs);
        let g = NeighbourhoodGraph::new(&s);
        let paths = g.warping_paths(&Blocks::all_pairs(&[0; 40]));
        assert_eq!(paths.len(), 1);
        // cheapest: enter at (30, 9), leave at (32, 20)
        assert_eq!((paths[0].start, paths[0].end), ((30, 9), (32, 20)));
        assert_eq!(paths[0].slope(), Some(5.5));
        assert!(!paths[0].is_valid(2.0, 2));
    }
}
