//! Segmentation into distinct activities by region growing (Krüger et al. 2017, §IV-B).
//!
//! Repetitive actions show up in the SSSM as blocks of off-diagonal neighbours. A region is
//! seeded on the main diagonal and grown one scan line (frame) at a time; scan line `i` counts
//! the neighbours of frame `i` inside the triangle between the seed and `i`. After `w` scan
//! lines in a row without any, the region is complete: its lower-right corner (the last scan
//! line that found neighbours) is the end of an action, and the next region is seeded there.
//! The band `|i − j| < band` around the main diagonal is ignored, otherwise every frame would
//! count its own temporal neighbours. Each scan line is one neighbour list, searched by binary
//! search: O(k·n) for the whole pass. The same growing, run backward from the last frame, finds
//! the upper-left corners: the starts of actions. Frames between an end and the next start are
//! a transition.
//!
//! Additions, each measured on the five shared CMU takes (action boundaries, F1 at 1 s and
//! covering, transitions split at their middle):
//!
//! * **Mirror neighbours** ([`RegionGrowing::mirror`]): the entries of the mirror SSSM (§V)
//!   count too. Twisting, knee raises, kicks alternate sides; their frames repeat *mirrored*
//!   every half cycle but unmirrored only every full cycle, often too rarely for the region to
//!   survive its first cycle.
//! * **Relative gate** ([`RegionGrowing::relative`]): the paper grows a region as long as *any*
//!   neighbour lies within `r`. But different actions of one take are often within `r` of each
//!   other too — in CMU 86_01 walking frames repeat each other at distances of 17–22 (stacked
//!   inches) while punching frames are 30–35 from walking frames, both inside `r = 42.5` — so
//!   the region runs on through the next action. With the gate a scan line only continues the
//!   region if its nearest neighbour is within `relative ×` the median nearest-neighbour
//!   distance of the region's scan lines so far: a frame must repeat the region about as
//!   closely as the region repeats itself. Without the gate the results swing with `R` (F1@1s
//!   0.86 at R = 13, 0.65 at R = 19, 0.52 at R = 25); with a factor of 1.5 they stay at
//!   0.82–0.89 for R from 13 to 25 (0.87 at the default R = 19).
//! * **Merging and kinds**: neighbouring actions cut apart by a short gap are merged when at
//!   least half of each one's frames repeat frames of the other within the same gate
//!   ([`RegionGrowing::merge_repeating`]); the same test over all pairs groups actions into
//!   kinds ([`RegionGrowing::kinds`]).
//!
//! Two ways to combine the passes ([`BoundaryRule`]):
//!
//! * [`BoundaryRule::Paper`] — as the authors' code: the backward pass restarts at every
//!   forward cut. A start is then only found if `w` empty scan lines separate it from the
//!   previous end; otherwise the next action starts right after that end.
//! * [`BoundaryRule::Midpoint`] — every frame's feature spans ±10 frames, and the poses of a
//!   transition resemble the actions on both sides, so a forward end comes *late* (the first
//!   frames after an action still match it) and, by the same argument in reverse, a backward
//!   start comes *early*. Here the backward pass of each action only counts neighbours inside
//!   that action (after the previous forward end) and may run back past the previous end. When
//!   a start falls before the previous end the two estimates overlap, and the boundary goes to
//!   the middle of the overlap; otherwise the gap is a transition. On the shared takes this is
//!   worse (F1@1s 0.82 against 0.87): where the transition before an action resembles it, the
//!   start runs back far into the previous action.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use serde::{Deserialize, Serialize};

use super::params::BoundaryRule;
use crate::similarity::neighbours::Sssm;
use crate::similarity::{frame_lookup, Span};

/// One completed forward region: seeded at `seed`, its last scan line with neighbours at `end`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Region {
    pub seed: usize,
    pub end: usize,
    /// Number of neighbour entries the region collected.
    pub entries: usize,
}

/// The result of the activity step.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Activities {
    /// The actions, in order, disjoint.
    pub actions: Vec<Span>,
    /// The gaps between (and before/after) the actions.
    pub transitions: Vec<Span>,
    /// Forward regions (lower-right corners = `end`).
    pub forward: Vec<Region>,
    /// Upper-left corners found by the backward pass.
    pub backward_starts: Vec<usize>,
}

/// Region growing over one SSSM (optionally together with the mirror SSSM).
#[derive(Debug, Clone, Copy)]
pub struct RegionGrowing<'a> {
    pub sssm: &'a Sssm,
    /// The mirror SSSM (§V): its entries count too, so an action whose sides alternate is
    /// repetitive from its first mirrored half-cycle on.
    pub mirror: Option<&'a Sssm>,
    /// Entries with `|i − j| < band` are ignored (at least 1: a frame never counts itself).
    pub band: usize,
    /// Stop window `w`.
    pub stop_window: usize,
    /// A region must collect more than this many entries to be an action.
    pub min_entries: usize,
    /// Relative gate: once a region has `GATE_LINES` scan lines with neighbours, a scan line
    /// only counts if its nearest neighbour is within `relative ×` the median nearest-neighbour
    /// distance of the region's scan lines so far (`None`: every neighbour counts, as in the
    /// paper).
    pub relative: Option<f32>,
}

/// Scan lines with neighbours a region needs before the relative gate applies.
pub const GATE_LINES: usize = 10;

/// The median of an action's nearest-repeat distances (`None` if fewer than [`GATE_LINES`]).
fn typical_of(d: &mut [f32]) -> Option<f32> {
    if d.len() < GATE_LINES {
        return None;
    }
    let k = d.len() / 2;
    Some(*d.select_nth_unstable_by(k, f32::total_cmp).1)
}

/// What one scan line found: the number of neighbours in range and the nearest one's distance.
#[derive(Debug, Clone, Copy)]
struct Line {
    count: usize,
    nearest: f32,
}

/// The relative gate of one region (see [`RegionGrowing::relative`]): a running median of
/// the nearest-neighbour distances of its scan lines, kept in two heaps (distances are ≥ 0, so
/// their bit patterns sort like the numbers).
struct Gate {
    factor: Option<f32>,
    /// The smaller half (max-heap) and the larger half (min-heap); `lower` holds the median.
    lower: BinaryHeap<u32>,
    upper: BinaryHeap<Reverse<u32>>,
}

impl Gate {
    fn new(factor: Option<f32>) -> Self {
        Gate { factor, lower: BinaryHeap::new(), upper: BinaryHeap::new() }
    }

    fn median(&self) -> Option<f32> {
        self.lower.peek().map(|&bits| f32::from_bits(bits))
    }

    fn admits(&self, line: Line) -> bool {
        if line.count == 0 {
            return false;
        }
        match (self.factor, self.median()) {
            (Some(f), Some(m)) if self.lower.len() + self.upper.len() >= GATE_LINES => line.nearest <= f * m,
            _ => true,
        }
    }

    fn record(&mut self, line: Line) {
        if self.factor.is_none() {
            return;
        }
        let bits = line.nearest.max(0.0).to_bits();
        if self.lower.peek().is_none_or(|&m| bits <= m) {
            self.lower.push(bits);
        } else {
            self.upper.push(Reverse(bits));
        }
        if self.lower.len() > self.upper.len() + 1 {
            let moved = self.lower.pop().expect("non-empty");
            self.upper.push(Reverse(moved));
        } else if self.upper.len() > self.lower.len() {
            let Reverse(moved) = self.upper.pop().expect("non-empty");
            self.lower.push(moved);
        }
    }

    fn reset(&mut self) {
        self.lower.clear();
        self.upper.clear();
    }
}

impl RegionGrowing<'_> {
    /// Neighbours `j` of frame `i` with `lo ≤ j ≤ hi` in both SSSMs.
    fn line(&self, i: usize, lo: usize, hi: usize) -> Line {
        let mut line = Line { count: 0, nearest: f32::INFINITY };
        if lo > hi {
            return line;
        }
        for s in std::iter::once(self.sssm).chain(self.mirror) {
            let (cols, dists) = s.row(i);
            let a = cols.partition_point(|&j| (j as usize) < lo);
            let b = cols.partition_point(|&j| (j as usize) <= hi);
            if b > a {
                line.count += b - a;
                line.nearest = dists[a..b].iter().copied().fold(line.nearest, f32::min);
            }
        }
        line
    }

    fn band(&self) -> usize {
        self.band.max(1)
    }

    /// Scan line `i` of a forward region seeded at `seed`: neighbours in `[seed, i − band]`.
    fn forward_line(&self, i: usize, seed: usize) -> Line {
        match i.checked_sub(self.band()) {
            Some(hi) => self.line(i, seed, hi),
            None => Line { count: 0, nearest: f32::INFINITY },
        }
    }

    /// Scan line `i` of a backward region bounded by `[lo, hi]`: neighbours in
    /// `[max(i + band, lo), hi]`.
    fn backward_line(&self, i: usize, lo: usize, hi: usize) -> Line {
        self.line(i, (i + self.band()).max(lo), hi)
    }

    /// The forward pass: regions seeded at frame 0 and then at each region's end.
    pub fn forward(&self) -> Vec<Region> {
        let n = self.sssm.frames();
        let mut regions = Vec::new();
        let mut gate = Gate::new(self.relative);
        let (mut seed, mut blob, mut zeros, mut last) = (0usize, 0usize, 0usize, None::<usize>);
        for i in 0..n {
            let line = self.forward_line(i, seed);
            if gate.admits(line) {
                gate.record(line);
                blob += line.count;
                zeros = 0;
                last = Some(i);
                continue;
            }
            zeros += 1;
            if zeros >= self.stop_window && blob > self.min_entries {
                let end = last.expect("a region with entries has a last scan line");
                regions.push(Region { seed, end, entries: blob });
                seed = end;
                blob = 0;
                zeros = 0;
                gate.reset();
            }
        }
        if blob > self.min_entries {
            if let Some(end) = last.filter(|&e| e >= seed) {
                regions.push(Region { seed, end, entries: blob });
            }
        }
        regions
    }

    /// The paper's backward pass: seeded at the last frame, restarted at every forward end;
    /// returns the upper-left corners (action starts) it finds, ascending.
    pub fn backward_restarting(&self, forward_ends: &[usize]) -> Vec<usize> {
        let n = self.sssm.frames();
        let mut starts = Vec::new();
        if n == 0 {
            return starts;
        }
        let mut gate = Gate::new(self.relative);
        let (mut hi, mut blob, mut zeros, mut last) = (n - 1, 0usize, 0usize, None::<usize>);
        for i in (0..n).rev() {
            let line = self.backward_line(i, 0, hi);
            let admitted = gate.admits(line);
            if admitted {
                gate.record(line);
                blob += line.count;
            }
            if forward_ends.binary_search(&i).is_ok() {
                hi = i;
                blob = 0;
                zeros = 0;
                last = None;
                gate.reset();
                continue;
            }
            if admitted {
                zeros = 0;
                last = Some(i);
                continue;
            }
            zeros += 1;
            if zeros >= self.stop_window && blob > self.min_entries {
                let start = last.expect("a region with entries has a last scan line");
                starts.push(start);
                hi = start;
                blob = 0;
                zeros = 0;
                last = None;
                gate.reset();
            }
        }
        starts.reverse();
        starts
    }

    /// The backward pass of one action ending at `end` whose neighbours lie in `[lo, end]`:
    /// scans down from `end` to `floor` and returns the last scan line with neighbours before
    /// `w` empty ones (`None` if no scan line finds any).
    pub fn backward_start(&self, end: usize, lo: usize, floor: usize) -> Option<usize> {
        let mut gate = Gate::new(self.relative);
        let (mut zeros, mut last) = (0usize, None::<usize>);
        for i in (floor..=end).rev() {
            let line = self.backward_line(i, lo, end);
            if gate.admits(line) {
                gate.record(line);
                zeros = 0;
                last = Some(i);
            } else if last.is_some() {
                zeros += 1;
                if zeros >= self.stop_window {
                    break;
                }
            }
        }
        last
    }

    /// Distance from frame `i` to its nearest neighbour in `span` at least `band` frames away
    /// (both SSSMs).
    fn nearest_in(&self, i: usize, span: Span) -> Option<f32> {
        let band = self.band();
        let mut best = None::<f32>;
        for s in std::iter::once(self.sssm).chain(self.mirror) {
            let (cols, dists) = s.row(i);
            let a = cols.partition_point(|&j| (j as usize) < span.start);
            let b = cols.partition_point(|&j| (j as usize) <= span.end);
            for (&j, &d) in cols[a..b].iter().zip(&dists[a..b]) {
                if (j as usize).abs_diff(i) >= band {
                    best = Some(best.map_or(d, |x| x.min(d)));
                }
            }
        }
        best
    }

    /// Median over the frames of `span` of their nearest-repeat distance inside `span`: how
    /// closely the action repeats itself (`None` if fewer than `GATE_LINES` frames repeat).
    pub fn typical_repeat(&self, span: Span) -> Option<f32> {
        let mut d: Vec<f32> = (span.start..=span.end).filter_map(|i| self.nearest_in(i, span)).collect();
        typical_of(&mut d)
    }

    /// How near a frame must come to a frame of `span` to repeat it in [`Self::kinds`]: the
    /// relative gate times the action's typical repeat distance (`None` if the action does not
    /// repeat itself; unbounded without a gate).
    pub fn repeat_limit(&self, span: Span) -> Option<f32> {
        match self.relative {
            Some(f) => self.typical_repeat(span).map(|t| f * t),
            None => Some(f32::INFINITY),
        }
    }

    /// Fraction of the frames of `from` whose nearest repeat in `to` is within `limit`.
    fn cover(&self, from: Span, to: Span, limit: f32) -> f64 {
        let hits = (from.start..=from.end).filter(|&i| self.nearest_in(i, to).is_some_and(|d| d <= limit)).count();
        hits as f64 / from.len() as f64
    }

    /// Merges neighbouring actions that are one activity cut in two: at most `max_gap` frames
    /// apart, and at least half of each one's frames repeat frames of the other within the
    /// relative gate (`factor ×` the other's typical repeat distance).
    pub fn merge_repeating(&self, actions: &[Span], factor: f32, max_gap: usize) -> Vec<Span> {
        let mut out: Vec<Span> = Vec::with_capacity(actions.len());
        for &b in actions {
            if let Some(a) = out.last_mut() {
                if b.start <= a.end + 1 + max_gap && self.same_activity(*a, b, factor) {
                    a.end = b.end;
                    continue;
                }
            }
            out.push(b);
        }
        out
    }

    fn same_activity(&self, a: Span, b: Span, factor: f32) -> bool {
        let (Some(ta), Some(tb)) = (self.typical_repeat(a), self.typical_repeat(b)) else {
            return false;
        };
        self.cover(b, a, factor * ta) >= 0.5 && self.cover(a, b, factor * tb) >= 0.5
    }

    /// Groups `actions` into kinds: two actions are of one kind if at least half of each one's
    /// frames repeat frames of the other within the relative gate (`factor`; without a gate,
    /// any neighbour counts). Kinds are numbered in order of first appearance.
    pub fn kinds(&self, actions: &[Span], factor: Option<f32>) -> Vec<usize> {
        // One pass over the neighbour lists: for every frame of an action, its nearest repeat
        // in each action (the same as `nearest_in` per pair, but O(entries) for all pairs).
        let count = actions.len();
        let action_of = frame_lookup(self.sssm.frames(), actions);
        let mut nearest = vec![f32::INFINITY; count];
        let mut touched: Vec<usize> = Vec::new();
        let mut own: Vec<Vec<f32>> = vec![Vec::new(); count];
        let mut near_lists: Vec<(u32, usize, f32)> = Vec::new(); // (frame's action, other action, distance)
        let band = self.band();
        for (i, &y) in action_of.iter().enumerate() {
            if y == u32::MAX {
                continue;
            }
            for s in std::iter::once(self.sssm).chain(self.mirror) {
                let (cols, dists) = s.row(i);
                for (&j, &d) in cols.iter().zip(dists) {
                    let x = action_of[j as usize];
                    if x != u32::MAX && (j as usize).abs_diff(i) >= band {
                        let slot = &mut nearest[x as usize];
                        if slot.is_infinite() {
                            touched.push(x as usize);
                        }
                        *slot = slot.min(d);
                    }
                }
            }
            for &x in &touched {
                if x == y as usize {
                    own[x].push(nearest[x]);
                }
                near_lists.push((y, x, nearest[x]));
                nearest[x] = f32::INFINITY;
            }
            touched.clear();
        }
        let limits: Vec<Option<f32>> = own
            .iter_mut()
            .map(|d| match factor {
                Some(f) => typical_of(d).map(|t| f * t),
                None => Some(f32::INFINITY),
            })
            .collect();
        // hits[y·count + x]: frames of y whose nearest repeat in x is within x's limit
        let mut hits = vec![0u32; count * count];
        for &(y, x, d) in &near_lists {
            if limits[x].is_some_and(|l| d <= l) {
                hits[y as usize * count + x] += 1;
            }
        }
        let cover = |from: usize, to: usize| hits[from * count + to] as f64 / actions[from].len() as f64;
        let mut uf = petgraph::unionfind::UnionFind::<usize>::new(count);
        for x in 0..count {
            for y in x + 1..count {
                if limits[x].is_some() && limits[y].is_some() && cover(y, x) >= 0.5 && cover(x, y) >= 0.5 {
                    uf.union(x, y);
                }
            }
        }
        let mut ids: Vec<(usize, usize)> = Vec::new();
        (0..actions.len())
            .map(|a| {
                let root = uf.find_mut(a);
                match ids.iter().find(|(r, _)| *r == root) {
                    Some(&(_, id)) => id,
                    None => {
                        ids.push((root, ids.len()));
                        ids.len() - 1
                    }
                }
            })
            .collect()
    }

    /// Both passes, combined by `rule`.
    pub fn activities(&self, rule: BoundaryRule) -> Activities {
        let forward = self.forward();
        let ends: Vec<usize> = forward.iter().map(|r| r.end).collect();
        let (actions, backward_starts) = match rule {
            BoundaryRule::Paper => {
                let starts = self.backward_restarting(&ends);
                (paper_actions(self.sssm.frames(), &ends, &starts), starts)
            }
            BoundaryRule::Midpoint => self.midpoint_actions(&forward),
        };
        let actions = match self.relative {
            Some(f) => self.merge_repeating(&actions, f, self.band()),
            None => actions,
        };
        let transitions = gaps(self.sssm.frames(), &actions);
        Activities { actions, transitions, forward, backward_starts }
    }

    fn midpoint_actions(&self, forward: &[Region]) -> (Vec<Span>, Vec<usize>) {
        let mut actions: Vec<Span> = Vec::with_capacity(forward.len());
        let mut starts = Vec::with_capacity(forward.len());
        for (k, region) in forward.iter().enumerate() {
            let lo = if k == 0 { 0 } else { region.seed + 1 };
            let floor = actions.last().map_or(0, |a| a.start + 1);
            let start = self.backward_start(region.end, lo, floor).unwrap_or(lo).min(region.end);
            starts.push(start);
            let mut span = Span { start, end: region.end };
            if let Some(prev) = actions.last_mut() {
                if span.start <= prev.end {
                    let middle = (span.start + prev.end) / 2;
                    prev.end = middle.max(prev.start);
                    span.start = prev.end + 1;
                }
            }
            if span.start <= span.end {
                actions.push(span);
            }
        }
        (actions, starts)
    }
}

/// The paper's reading of the cuts: between a forward end and the next backward start lies a
/// transition, and so do the frames before the first start and after the last end; every
/// other stretch between consecutive cuts is an action (a forward region whose start the
/// backward pass did not find begins right after the previous end).
fn paper_actions(n: usize, ends: &[usize], starts: &[usize]) -> Vec<Span> {
    if n == 0 || ends.is_empty() {
        return Vec::new();
    }
    #[derive(Clone, Copy, PartialEq)]
    enum Cut {
        End,
        Start,
    }
    let mut cuts: Vec<(usize, Cut)> =
        ends.iter().map(|&e| (e, Cut::End)).chain(starts.iter().map(|&s| (s, Cut::Start))).collect();
    cuts.sort_by_key(|&(f, c)| (f, c == Cut::Start));
    let mut actions = Vec::new();
    let mut begin = 0usize;
    let mut previous: Option<Cut> = None;
    for &(f, kind) in &cuts {
        match kind {
            Cut::Start => {
                if previous == Some(Cut::Start) && f > begin {
                    actions.push(Span { start: begin, end: f - 1 });
                }
                begin = f;
            }
            Cut::End => {
                if f >= begin {
                    actions.push(Span { start: begin, end: f });
                }
                begin = f + 1;
            }
        }
        previous = Some(kind);
    }
    if previous == Some(Cut::Start) && begin < n {
        actions.push(Span { start: begin, end: n - 1 });
    }
    actions
}

/// The frames of `0..n` not covered by `actions` (sorted, disjoint), as spans.
pub fn gaps(n: usize, actions: &[Span]) -> Vec<Span> {
    let mut out = Vec::new();
    let mut next = 0usize;
    for a in actions {
        if a.start > next {
            out.push(Span { start: next, end: a.start - 1 });
        }
        next = a.end + 1;
    }
    if next < n {
        out.push(Span { start: next, end: n - 1 });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Symmetric lists where every pair of frames inside one of `blocks` whose distance is a
    /// multiple of `period` (± 1) are neighbours, plus the main diagonal ±2.
    fn block_sssm(n: usize, blocks: &[(usize, usize, usize)]) -> Sssm {
        let mut lists = vec![Vec::new(); n];
        for (i, list) in lists.iter_mut().enumerate() {
            for j in 0..n {
                let near = i.abs_diff(j) <= 2;
                let repeat = blocks.iter().any(|&(s, e, p)| {
                    (s..=e).contains(&i) && (s..=e).contains(&j) && {
                        let d = i.abs_diff(j) % p;
                        i != j && (d <= 1 || d + 1 == p)
                    }
                });
                if near || repeat {
                    list.push((j as u32, 1.0));
                }
            }
        }
        Sssm::from_lists(&lists).unwrap()
    }

    fn grow(s: &Sssm) -> RegionGrowing<'_> {
        RegionGrowing { sssm: s, mirror: None, band: 10, stop_window: 5, min_entries: 20, relative: None }
    }

    #[test]
    fn two_blocks_give_two_actions_and_the_gap_is_a_transition() {
        let s = block_sssm(200, &[(10, 89, 15), (110, 189, 12)]);
        let g = grow(&s);
        let fwd = g.forward();
        assert_eq!(fwd.iter().map(|r| (r.seed, r.end)).collect::<Vec<_>>(), vec![(0, 89), (89, 189)]);
        for rule in [BoundaryRule::Paper, BoundaryRule::Midpoint] {
            let a = g.activities(rule);
            assert_eq!(a.actions, vec![Span { start: 10, end: 89 }, Span { start: 110, end: 189 }], "{rule:?}");
            assert_eq!(
                a.transitions,
                vec![Span { start: 0, end: 9 }, Span { start: 90, end: 109 }, Span { start: 190, end: 199 }]
            );
        }
        assert_eq!(g.backward_restarting(&[89, 189]), vec![10, 110]);
    }

    #[test]
    fn a_small_region_is_not_an_action() {
        // a block of 3 periods of 10 frames: 2·(entries) ≈ 60 > 20, but with a big minimum
        let s = block_sssm(100, &[(20, 49, 10)]);
        let mut g = grow(&s);
        assert_eq!(g.forward().len(), 1);
        g.min_entries = 10_000;
        assert!(g.forward().is_empty());
        let a = g.activities(BoundaryRule::Midpoint);
        assert!(a.actions.is_empty());
        assert_eq!(a.transitions, vec![Span { start: 0, end: 99 }]);
    }

    #[test]
    fn back_to_back_actions_with_a_smeared_boundary_split_in_the_middle() {
        // Action A = 0..=99 (period 12), action B = 100..=199 (period 20); frames 100..=105 still
        // match A (the late smear of A's end), frames 94..=99 already match B (the early smear
        // of B's start).
        let mut s = block_sssm(200, &[(0, 105, 12), (94, 199, 20)]).to_lists();
        // make the smear symmetric and clean: nothing else links the two
        for (i, row) in s.iter_mut().enumerate() {
            row.retain(|&(j, _)| {
                let (i, j) = (i, j as usize);
                let in_a = |f: usize| f <= 105;
                let in_b = |f: usize| f >= 94;
                (in_a(i) && in_a(j)) || (in_b(i) && in_b(j)) || i.abs_diff(j) <= 2
            });
        }
        let s = Sssm::from_lists(&s).unwrap();
        let g = grow(&s);
        let fwd = g.forward();
        assert_eq!(fwd[0].end, 105, "the forward end is late by the smear");
        let paper = g.activities(BoundaryRule::Paper);
        assert_eq!(paper.actions[0].end, 105, "the paper's rule keeps the late end");
        let mid = g.activities(BoundaryRule::Midpoint);
        assert_eq!(mid.backward_starts[1], 94, "the backward start is early by the smear");
        assert_eq!(mid.actions, vec![Span { start: 0, end: 99 }, Span { start: 100, end: 199 }]);
        assert!(mid.transitions.is_empty());
    }

    #[test]
    fn hand_made_lists_stop_after_the_window() {
        // Frames 0..=39: frame i ≥ 20 has neighbour i − 20 (and vice versa); nothing after.
        let n = 60;
        let mut lists = vec![Vec::new(); n];
        for i in 20..40 {
            lists[i].push(((i - 20) as u32, 0.5));
            lists[i - 20].push((i as u32, 0.5));
        }
        let s = Sssm::from_lists(&lists).unwrap();
        let g = RegionGrowing { sssm: &s, mirror: None, band: 10, stop_window: 3, min_entries: 5, relative: None };
        let fwd = g.forward();
        assert_eq!(fwd, vec![Region { seed: 0, end: 39, entries: 20 }]);
        assert_eq!(g.backward_start(39, 0, 0), Some(0));
        // with a stop window longer than the take nothing is cut, but the take's end closes it
        let g = RegionGrowing { stop_window: 100, ..g };
        assert_eq!(g.forward(), vec![Region { seed: 0, end: 39, entries: 20 }]);
        // a minimum larger than the region: no action
        let g = RegionGrowing { min_entries: 20, ..g };
        assert!(g.forward().is_empty());
    }

    #[test]
    fn the_diagonal_band_is_ignored() {
        // only near-diagonal neighbours (|i − j| < band): never an action
        let s = block_sssm(100, &[]);
        assert!(grow(&s).forward().is_empty());
    }

    #[test]
    fn the_gate_tracks_the_running_median() {
        let mut g = Gate::new(Some(1.5));
        let line = |nearest: f32| Line { count: 1, nearest };
        for (k, d) in [5.0f32, 1.0, 9.0, 3.0, 7.0, 2.0, 8.0, 4.0, 6.0, 10.0].into_iter().enumerate() {
            assert!(g.admits(line(1e6)), "not gating before {GATE_LINES} lines (line {k})");
            g.record(line(d));
        }
        // 1..=10: the lower median is 5
        assert_eq!(g.median(), Some(5.0));
        assert!(g.admits(line(7.5)));
        assert!(!g.admits(line(7.6)));
        assert!(!g.admits(Line { count: 0, nearest: 0.0 }));
        g.reset();
        assert_eq!(g.median(), None);
        assert!(Gate::new(None).admits(line(1e6)));
    }

    #[test]
    fn paper_reading_of_cuts() {
        let span = |start, end| Span { start, end };
        // start → end → start: a leading transition, an action, a transition, an open action
        assert_eq!(paper_actions(100, &[49], &[10, 60]), vec![span(10, 49), span(60, 99)]);
        // no start found: each action begins right after the previous end
        assert_eq!(paper_actions(100, &[49, 89], &[]), vec![span(0, 49), span(50, 89)]);
        // two starts inside one forward region: two actions
        assert_eq!(paper_actions(100, &[89], &[10, 40]), vec![span(10, 39), span(40, 89)]);
        assert_eq!(gaps(10, &[Span { start: 2, end: 3 }]), vec![Span { start: 0, end: 1 }, Span { start: 4, end: 9 }]);
    }
}
