//! Clustering of motion primitives (Krüger et al. 2017, §VI).
//!
//! Every primitive is a node of the cluster graph. For each pair of primitives `(p, q)` the
//! neighbourhood graph is restricted to the rectangle of the SSSM they span (rows in `p`,
//! columns in `q`); if a warping path in it is long enough, has a valid slope and covers at
//! least `coverage` of both primitives (the authors' code: 0.66), the edge `p → q` is added.
//! The strongly connected components of that graph (petgraph's Tarjan) are the clusters — no
//! number of clusters is given. Every SSSM entry lies in exactly one rectangle, so all pairs
//! are handled by one sweep over the neighbourhood graph.
//!
//! The same test on the *mirror* SSSM (§V) links primitives that are mirror images of each
//! other; a cluster whose members are mirror-linked to another cluster's is marked as that
//! cluster's mirror partner (left step ↔ right step).

use petgraph::algo::tarjan_scc;
use petgraph::graph::{DiGraph, NodeIndex};
use serde::{Deserialize, Serialize};

use super::paths::{Blocks, NeighbourhoodGraph};
use super::{frame_lookup, Span};

/// Settings of the cluster graph (from the checked parameters).
#[derive(Debug, Clone, Copy)]
pub struct ClusterSearch {
    pub nu: f64,
    pub min_path_frames: usize,
    pub coverage: f64,
}

/// One cluster of primitives.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Cluster {
    pub id: usize,
    /// Indices of the member primitives, ascending.
    pub members: Vec<usize>,
    /// The cluster whose members are mirror images of this one's (§V), if any.
    pub mirror_of: Option<usize>,
    /// True if the mirror images of this cluster's members lie in this cluster itself.
    pub self_symmetric: bool,
}

impl ClusterSearch {
    /// The edges `p → q` (`p ≠ q`) of the cluster graph of `primitives` (sorted, disjoint) on
    /// the SSSM behind `graph`, sorted and without duplicates.
    pub fn links(&self, graph: &NeighbourhoodGraph, primitives: &[Span]) -> Vec<(usize, usize)> {
        let prim_of = frame_lookup(graph.sssm().frames(), primitives);
        let paths = graph.warping_paths(&Blocks::all_pairs(&prim_of));
        let mut links: Vec<(usize, usize)> = paths
            .iter()
            .filter(|path| path.is_valid(self.nu, self.min_path_frames))
            .filter_map(|path| {
                let (p, q) = path.block();
                let cover_p = (path.end.0 - path.start.0 + 1) as f64 / primitives[p].len() as f64;
                let cover_q = (path.end.1 - path.start.1 + 1) as f64 / primitives[q].len() as f64;
                (cover_p >= self.coverage && cover_q >= self.coverage).then_some((p, q))
            })
            .collect();
        links.sort_unstable();
        links.dedup();
        links
    }

    /// Cluster id of each of `count` primitives: the strongly connected components of the
    /// graph with edges `links` (self-links of the mirror test are ignored here), numbered in
    /// order of their first member.
    pub fn clusters(count: usize, links: &[(usize, usize)]) -> Vec<usize> {
        let mut g = DiGraph::<(), ()>::with_capacity(count, links.len());
        let nodes: Vec<NodeIndex> = (0..count).map(|_| g.add_node(())).collect();
        for &(p, q) in links.iter().filter(|(p, q)| p != q) {
            g.add_edge(nodes[p], nodes[q], ());
        }
        let mut comps: Vec<Vec<usize>> =
            tarjan_scc(&g).into_iter().map(|c| c.into_iter().map(|n| n.index()).collect()).collect();
        comps.iter_mut().for_each(|c| c.sort_unstable());
        comps.sort_by_key(|c| c[0]);
        let mut of = vec![0usize; count];
        for (id, comp) in comps.iter().enumerate() {
            for &p in comp {
                of[p] = id;
            }
        }
        of
    }

    /// The clusters with their members and mirror partners from the `mirror_links` (edges of
    /// the cluster graph built on the mirror SSSM).
    pub fn describe(cluster_of: &[usize], mirror_links: &[(usize, usize)]) -> Vec<Cluster> {
        let count = cluster_of.iter().map(|&c| c + 1).max().unwrap_or(0);
        let mut clusters: Vec<Cluster> =
            (0..count).map(|id| Cluster { id, members: Vec::new(), mirror_of: None, self_symmetric: false }).collect();
        for (p, &c) in cluster_of.iter().enumerate() {
            clusters[c].members.push(p);
        }
        // votes[a][b]: mirror links from members of a to members of b
        let mut votes = vec![std::collections::BTreeMap::<usize, usize>::new(); count];
        for &(p, q) in mirror_links {
            *votes[cluster_of[p]].entry(cluster_of[q]).or_default() += 1;
        }
        for (a, v) in votes.iter().enumerate() {
            clusters[a].self_symmetric = v.contains_key(&a);
            let best = v.iter().filter(|(&b, _)| b != a).max_by_key(|(&b, &n)| (n, std::cmp::Reverse(b)));
            clusters[a].mirror_of = best.map(|(&b, _)| b);
        }
        clusters
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::similarity::neighbours::Sssm;

    #[test]
    fn strongly_connected_components_are_the_clusters() {
        // 0 ↔ 2 ↔ 4, 1 ↔ 3, 5 alone, 6 → 0 only (not strongly connected)
        let links = [(0, 2), (2, 0), (2, 4), (4, 2), (1, 3), (3, 1), (6, 0)];
        let of = ClusterSearch::clusters(7, &links);
        assert_eq!(of, vec![0, 1, 0, 1, 0, 2, 3]);
    }

    #[test]
    fn mirror_partners_follow_the_majority_of_mirror_links() {
        let of = vec![0, 1, 0, 1, 2];
        let clusters = ClusterSearch::describe(&of, &[(0, 1), (2, 3), (1, 0), (3, 2), (4, 4), (2, 4)]);
        assert_eq!(clusters[0].members, vec![0, 2]);
        assert_eq!(clusters[0].mirror_of, Some(1));
        assert_eq!(clusters[1].mirror_of, Some(0));
        assert_eq!(clusters[2].mirror_of, None);
        assert!(clusters[2].self_symmetric);
        assert!(!clusters[0].self_symmetric);
    }

    #[test]
    fn a_diagonal_linking_two_primitives_makes_an_edge() {
        // primitives [0,19], [20,39], [40,59]; frames 0..20 match 20..40 (diagonal j = i + 20)
        // and vice versa; primitive 2 matches nothing.
        let n = 60;
        let mut lists = vec![Vec::new(); n];
        for i in 0..20 {
            lists[i].push(((i + 20) as u32, 1.0));
            lists[i + 20].push((i as u32, 1.0));
        }
        // a short stray match between primitive 0 and 2 (covers 4 of 20 frames)
        for (i, list) in lists.iter_mut().enumerate().take(4) {
            list.push(((i + 45) as u32, 0.5));
        }
        let s = Sssm::from_lists(&lists).unwrap();
        let g = NeighbourhoodGraph::new(&s);
        let prims = [Span { start: 0, end: 19 }, Span { start: 20, end: 39 }, Span { start: 40, end: 59 }];
        let search = ClusterSearch { nu: 2.0, min_path_frames: 3, coverage: 0.66 };
        let links = search.links(&g, &prims);
        assert_eq!(links, vec![(0, 1), (1, 0)]);
        // the same SSSM restricted below the diagonal's distance has no link
        let near = s.within(0.9);
        assert!(search.links(&NeighbourhoodGraph::new(&near), &prims).is_empty());
        assert_eq!(ClusterSearch::clusters(3, &links), vec![0, 0, 1]);
        let loose = ClusterSearch { coverage: 0.1, ..search };
        assert_eq!(loose.links(&g, &prims), vec![(0, 1), (0, 2), (1, 0)]);
    }
}
