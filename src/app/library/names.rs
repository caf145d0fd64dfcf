//! The names the user gives the library's shared clusters, kept by what each cluster holds — its occurrences, as
//! take names and frames — rather than by its number: a new matching (a take added, the library restored after a
//! reload, a project file opened) numbers the clusters afresh, and each name follows the cluster that now holds most
//! of the motion it was given to ([`ClusterNames::follow`]). A cluster without a name keeps the core's `C<id>`
//! ([`crate::library::SharedClusters`]).

use crate::segment::Segmentation;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// How much of a named cluster's motion a new cluster must hold (overlap over union of their frames, within the takes
/// the name was given in) for the name to follow it.
pub const FOLLOW_MIN_OVERLAP: f64 = 0.5;

/// One occurrence of a cluster by its take's name: frames `start..=end` of take `take`.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
pub struct NamedSpot {
    pub take: String,
    pub start: usize,
    pub end: usize,
}

/// A name and the occurrences of the cluster it names (when named, or when last followed).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Named {
    pub name: String,
    pub spots: Vec<NamedSpot>,
}

/// The names the user gave the shared clusters.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ClusterNames {
    /// Every name given, with what its cluster holds.
    named: Vec<Named>,
    /// The clusters of the matching shown that have a name: cluster id → index into `named`.
    ids: BTreeMap<usize, usize>,
    /// Names from the labels the clusters' takes carry ([`crate::app::library::takes::Shared::label_names`]), for
    /// the clusters the user has not named.
    suggested: BTreeMap<usize, String>,
}

/// Frames shared by two spans (inclusive ends).
fn overlap(a: &NamedSpot, b: &NamedSpot) -> usize {
    if a.take != b.take {
        return 0;
    }
    (a.end.min(b.end) + 1).saturating_sub(a.start.max(b.start))
}

/// Frames of `spots` (each counted once where spans overlap).
fn frames(spots: &[NamedSpot]) -> usize {
    let mut sorted: Vec<&NamedSpot> = spots.iter().collect();
    sorted.sort();
    let mut total = 0;
    let mut last: Option<(&str, usize)> = None;
    for s in sorted {
        let from = match last {
            Some((take, end)) if take == s.take => s.start.max(end + 1),
            _ => s.start,
        };
        total += (s.end + 1).saturating_sub(from);
        let end = match last {
            Some((take, end)) if take == s.take => end.max(s.end),
            _ => s.end,
        };
        last = Some((&s.take, end));
    }
    total
}

/// How much of `named`'s motion `cluster` holds: overlap over union of their frames, `cluster` counted only in the
/// takes `named` has spots in (a take added since holds nothing the name was given to).
pub fn likeness(named: &[NamedSpot], cluster: &[NamedSpot]) -> f64 {
    let within: Vec<NamedSpot> = cluster.iter().filter(|c| named.iter().any(|n| n.take == c.take)).cloned().collect();
    let shared: usize = named.iter().flat_map(|n| within.iter().map(move |c| overlap(n, c))).sum();
    let union = frames(named) + frames(&within);
    if union == 0 {
        return 0.0;
    }
    shared as f64 / union.saturating_sub(shared).max(1) as f64
}

impl ClusterNames {
    /// Names kept (from this browser or a project file), not yet following any cluster: [`ClusterNames::follow`]
    /// gives them their clusters.
    pub fn from_kept(named: Vec<Named>) -> ClusterNames {
        ClusterNames { named, ids: BTreeMap::new(), suggested: BTreeMap::new() }
    }

    /// Every name given, with what its cluster holds (what is kept).
    pub fn kept(&self) -> &[Named] {
        &self.named
    }

    /// The name of cluster `id`: the user's, else one from the labels its takes carry, else `C<id>`.
    pub fn name(&self, id: usize) -> String {
        match self.ids.get(&id) {
            Some(&i) => self.named[i].name.clone(),
            None => self.suggested.get(&id).cloned().unwrap_or_else(|| format!("C{id}")),
        }
    }

    /// Names from labels for the clusters of the matching shown (replacing those before).
    pub fn suggest(&mut self, names: BTreeMap<usize, String>) {
        self.suggested = names;
    }

    /// Whether cluster `id` has a name the user gave.
    pub fn is_named(&self, id: usize) -> bool {
        self.ids.contains_key(&id)
    }

    /// Renames cluster `id`, which holds `spots` (blank text brings back its default name; the text is trimmed and
    /// kept to one line).
    pub fn rename(&mut self, id: usize, name: &str, spots: Vec<NamedSpot>) {
        let name: String = name.split_whitespace().collect::<Vec<_>>().join(" ");
        match (self.ids.get(&id).copied(), name.is_empty()) {
            (Some(i), true) => {
                self.named.remove(i);
                self.ids.remove(&id);
                for at in self.ids.values_mut() {
                    if *at > i {
                        *at -= 1;
                    }
                }
            }
            (Some(i), false) => self.named[i] = Named { name, spots },
            (None, true) => {}
            (None, false) => {
                self.named.push(Named { name, spots });
                self.ids.insert(id, self.named.len() - 1);
            }
        }
    }

    /// A new matching's clusters (id, occurrences): each name goes to the cluster holding most of its motion (at
    /// least [`FOLLOW_MIN_OVERLAP`]), the likeliest pairs first, one name per cluster; a name followed takes its new
    /// cluster's occurrences. A name no cluster holds now is kept (a later matching may hold it again).
    pub fn follow(&mut self, clusters: &[(usize, Vec<NamedSpot>)]) {
        let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
        for (n, named) in self.named.iter().enumerate() {
            for (c, (_, spots)) in clusters.iter().enumerate() {
                let l = likeness(&named.spots, spots);
                if l >= FOLLOW_MIN_OVERLAP {
                    pairs.push((l, n, c));
                }
            }
        }
        pairs.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
        let mut ids = BTreeMap::new();
        let (mut names_used, mut clusters_used) = (vec![false; self.named.len()], vec![false; clusters.len()]);
        for (_, n, c) in pairs {
            if names_used[n] || clusters_used[c] {
                continue;
            }
            names_used[n] = true;
            clusters_used[c] = true;
            ids.insert(clusters[c].0, n);
            self.named[n].spots = clusters[c].1.clone();
        }
        self.ids = ids;
        // the names from labels were of the clusters before
        self.suggested.clear();
    }

    /// `segmentation` with every clustered segment labelled by its cluster's name (the labels every take shows and
    /// exports).
    pub fn label(&self, segmentation: &Segmentation) -> Segmentation {
        let mut labelled = segmentation.clone();
        for s in &mut labelled.segments {
            if let Some(id) = s.cluster {
                s.label = self.name(id);
            }
        }
        labelled
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spot(take: &str, start: usize, end: usize) -> NamedSpot {
        NamedSpot { take: take.into(), start, end }
    }

    #[test]
    fn renaming_gives_a_name_changes_it_and_blank_brings_the_default_back() {
        let mut names = ClusterNames::default();
        names.rename(1, "  walk \n cycle ", vec![spot("a.bvh", 0, 9)]);
        names.rename(2, "jog", vec![spot("a.bvh", 10, 19)]);
        assert_eq!(names.name(1), "walk cycle");
        assert_eq!(names.name(0), "C0");
        names.rename(1, "   ", Vec::new());
        assert_eq!(names.name(1), "C1", "a blank name brings the default back");
        assert_eq!(names.name(2), "jog", "the other names stay with their clusters");
        assert_eq!(names.kept().len(), 1);
        names.rename(2, "run", vec![spot("a.bvh", 10, 19)]);
        assert_eq!((names.name(2), names.kept().len()), ("run".to_string(), 1));
        // a name from labels names a cluster the user has not named, never one they have
        names.suggest(BTreeMap::from([(2, "walk · C2".to_string()), (5, "walk · C5".to_string())]));
        assert_eq!((names.name(2), names.name(5), names.name(6)), ("run".into(), "walk · C5".into(), "C6".into()));
        assert!(!names.is_named(5));
    }

    #[test]
    fn overlap_counts_frames_of_one_take_once() {
        assert_eq!(frames(&[spot("a", 0, 9), spot("a", 5, 14), spot("b", 0, 9)]), 25);
        assert_eq!(likeness(&[spot("a", 0, 9)], &[spot("a", 0, 9)]), 1.0);
        assert_eq!(likeness(&[spot("a", 0, 9)], &[spot("a", 5, 14)]), 5.0 / 15.0);
        assert_eq!(likeness(&[spot("a", 0, 9)], &[spot("b", 0, 9)]), 0.0);
        // a take added since counts for nothing either way
        assert_eq!(likeness(&[spot("a", 0, 9)], &[spot("a", 0, 9), spot("c", 0, 99)]), 1.0);
    }

    #[test]
    fn a_name_follows_its_motion_when_the_clusters_are_numbered_afresh() {
        let mut names = ClusterNames::default();
        names.rename(0, "jog", vec![spot("a.bvh", 0, 49), spot("b.bvh", 30, 89)]);
        names.rename(1, "wave", vec![spot("b.bvh", 0, 29)]);
        // a take added before them renumbers the clusters: jog is now 2, wave 0, and a new cluster 1
        let clusters = vec![
            (0, vec![spot("b.bvh", 0, 27), spot("c.bvh", 0, 40)]),
            (1, vec![spot("c.bvh", 41, 90)]),
            (2, vec![spot("a.bvh", 0, 49), spot("b.bvh", 30, 85), spot("c.bvh", 91, 120)]),
        ];
        names.follow(&clusters);
        assert_eq!((names.name(2), names.name(0), names.name(1)), ("jog".into(), "wave".into(), "C1".into()));
        let segment = crate::segment::Segment {
            start: 0,
            end: 49,
            label: "C2".into(),
            level: crate::segment::Level::Primitive,
            cluster: Some(2),
            score: None,
            mirror_of: None,
            effort: None,
        };
        let take = crate::segment::Segmentation {
            file: "a.bvh".into(),
            method: "sssm".into(),
            fps: 30.0,
            frames: 50,
            segments: vec![segment],
            params: serde_json::Value::Null,
        };
        let csv_label = names.label(&take);
        assert_eq!(csv_label.segments[0].label, "jog");
        // the followed name now holds its cluster's occurrences (the new take's too)
        assert!(names.kept().iter().any(|n| n.name == "jog" && n.spots.iter().any(|s| s.take == "c.bvh")));
    }

    #[test]
    fn a_name_whose_motion_no_cluster_holds_is_kept_but_names_nothing() {
        let mut names = ClusterNames::from_kept(vec![Named { name: "jog".into(), spots: vec![spot("a.bvh", 0, 49)] }]);
        assert_eq!(names.name(0), "C0", "kept names name nothing before a matching");
        names.follow(&[(0, vec![spot("a.bvh", 30, 99)])]);
        assert_eq!(names.name(0), "C0", "20 of 100 frames is not the same motion");
        assert_eq!(names.kept().len(), 1);
        names.follow(&[(4, vec![spot("a.bvh", 0, 52)])]);
        assert_eq!(names.name(4), "jog");
    }

    #[test]
    fn two_names_never_go_to_one_cluster() {
        let mut names = ClusterNames::from_kept(vec![
            Named { name: "a".into(), spots: vec![spot("t", 0, 9)] },
            Named { name: "b".into(), spots: vec![spot("t", 0, 11)] },
        ]);
        names.follow(&[(7, vec![spot("t", 0, 9)])]);
        assert_eq!(names.name(7), "a", "the likelier name wins");
        assert_eq!(names.kept().len(), 2);
    }
}
