//! Subdividing actions into motion primitives (Krüger et al. 2017, §IV-C).
//!
//! The entries of the SSSM are the nodes of a *neighbourhood graph*: entry `(i, j)` (frame `j`
//! is a neighbour of frame `i`) can be reached from `(i−1, j−1)`, `(i−1, j)` and `(i, j−1)` —
//! the dynamic-time-warping steps (1,1), (1,0), (0,1). Inside an action each diagonal of the
//! SSSM is one connected component of that graph (found with a union-find). A
//! start node joined to the component's first column and an end node joined to its last column
//! turn the best warping path along the diagonal into a shortest path; the graph is a DAG whose
//! topological order is the row order of the SSSM, so one sweep finds the shortest paths of all
//! components at once (the cost of a path is the sum of its entries' distances).
//!
//! A diagonal of a repeated action starts where a repetition starts: the start `(i₀, j₀)` of
//! every valid path gives a candidate cut at `j₀`. Paths covering fewer than
//! `min_path_frames` frames or with a slope outside `[1/ν, ν]` are discarded; of candidate cuts
//! closer than `min_cut_distance` the one whose path is cheaper (lower mean distance per entry)
//! is kept; cuts that close to the action's border are dropped. An action without repetitions
//! stays one primitive.

use serde::{Deserialize, Serialize};

use crate::similarity::paths::{Blocks, NeighbourhoodGraph, WarpingPath};
use crate::similarity::{frame_lookup, Span};

/// Settings of the primitive search (from the checked parameters).
#[derive(Debug, Clone, Copy)]
pub struct PrimitiveSearch {
    pub nu: f64,
    pub min_path_frames: usize,
    pub min_cut_distance: usize,
}

/// A candidate cut and the path it comes from.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Cut {
    /// First frame of a new primitive.
    pub frame: usize,
    pub path: WarpingPath,
}

impl PrimitiveSearch {
    /// The cuts inside each of `actions` (sorted, disjoint spans) found from the diagonals of
    /// `graph`; one list per action, ascending.
    pub fn cuts(&self, graph: &NeighbourhoodGraph, actions: &[Span]) -> Vec<Vec<Cut>> {
        let action_of = frame_lookup(graph.sssm().frames(), actions);
        let paths = graph.warping_paths(&Blocks::diagonal(&action_of));
        let mut per_action: Vec<Vec<Cut>> = vec![Vec::new(); actions.len()];
        for path in paths {
            if !path.is_valid(self.nu, self.min_path_frames) {
                continue;
            }
            let action = path.block().0;
            let a = &actions[action];
            let frame = path.start.1;
            if frame >= a.start + self.min_cut_distance && frame + self.min_cut_distance <= a.end {
                per_action[action].push(Cut { frame, path });
            }
        }
        per_action.into_iter().map(|c| self.thin(c)).collect()
    }

    /// Of candidate cuts closer than `min_cut_distance`, keeps the one with the cheaper path.
    pub fn thin(&self, mut candidates: Vec<Cut>) -> Vec<Cut> {
        candidates.sort_by(|a, b| a.path.mean_cost().total_cmp(&b.path.mean_cost()).then(a.frame.cmp(&b.frame)));
        let mut taken = std::collections::BTreeSet::new();
        let mut kept: Vec<Cut> = Vec::with_capacity(candidates.len());
        for c in candidates {
            let lo = c.frame.saturating_sub(self.min_cut_distance.saturating_sub(1));
            let hi = c.frame.saturating_add(self.min_cut_distance.saturating_sub(1));
            if self.min_cut_distance == 0 || taken.range(lo..=hi).next().is_none() {
                taken.insert(c.frame);
                kept.push(c);
            }
        }
        kept.sort_by_key(|c| c.frame);
        kept
    }
}

/// Splits `action` at `cuts` (frames that start a new primitive, ascending, inside the action).
pub fn split(action: Span, cuts: &[usize]) -> Vec<Span> {
    let mut out = Vec::with_capacity(cuts.len() + 1);
    let mut start = action.start;
    for &c in cuts {
        if c > start && c <= action.end {
            out.push(Span { start, end: c - 1 });
            start = c;
        }
    }
    out.push(Span { start, end: action.end });
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn close_cuts_keep_the_cheaper_path() {
        let search = PrimitiveSearch { nu: 2.0, min_path_frames: 5, min_cut_distance: 5 };
        let cut = |frame: usize, cost: f32| Cut {
            frame,
            path: WarpingPath { start: (0, frame), end: (10, frame + 10), cost, nodes: 11, region: 0 },
        };
        let kept = search.thin(vec![cut(40, 22.0), cut(43, 11.0), cut(60, 30.0), cut(64, 33.0), cut(80, 1.0)]);
        assert_eq!(kept.iter().map(|c| c.frame).collect::<Vec<_>>(), vec![43, 60, 80]);
    }

    #[test]
    fn splitting_an_action() {
        let a = Span { start: 10, end: 50 };
        assert_eq!(split(a, &[]), vec![a]);
        assert_eq!(
            split(a, &[20, 35]),
            vec![Span { start: 10, end: 19 }, Span { start: 20, end: 34 }, Span { start: 35, end: 50 }]
        );
    }
}
