//! How well clusters match per-frame labels across the takes of a library: purity (each cluster counted as its
//! majority label), inverse purity (each label counted as the cluster holding most of it: one motion kept in one
//! cluster across takes), normalised mutual information (`2·I(C; L) / (H(C) + H(L))`), and the chance level of
//! clusters of the same sizes: the cluster ids shuffled among the units.

use std::collections::HashMap;

use serde::{Deserialize, Serialize};

use crate::segment::Segmentation;
use crate::stats::Rng;

/// Scores of clusters against labels, over the labelled frames of every take.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ClusterScores {
    pub purity: f64,
    pub inverse_purity: f64,
    pub nmi: f64,
    /// Distinct clusters among the labelled frames (frames in no cluster count as one more, "none").
    pub clusters: usize,
    /// Fraction of the labelled frames inside some cluster.
    pub coverage: f64,
    /// Labelled frames scored.
    pub frames: usize,
}

/// Every file frame's cluster in `segmentation`: the cluster of the shortest segment containing it that has one.
pub fn frame_clusters(segmentation: &Segmentation) -> Vec<Option<usize>> {
    let mut order: Vec<&crate::segment::Segment> =
        segmentation.segments.iter().filter(|s| s.cluster.is_some()).collect();
    order.sort_by_key(|s| std::cmp::Reverse(s.end + 1 - s.start));
    let mut of = vec![None; segmentation.frames];
    for s in order {
        let end = s.end.min(segmentation.frames.saturating_sub(1));
        of[s.start.min(end)..=end].iter_mut().for_each(|c| *c = s.cluster);
    }
    of
}

/// Scores of `clusters` against `labels` (per take, per frame; frames whose label is `None` are left out). Cluster
/// ids are compared across takes (pass ids made distinct per take to score per-take clusters). Frames in no cluster
/// form one cluster of their own.
pub fn cluster_scores(clusters: &[Vec<Option<usize>>], labels: &[Vec<Option<usize>>]) -> ClusterScores {
    let mut joint: HashMap<(Option<usize>, usize), usize> = HashMap::new();
    let mut n = 0usize;
    let mut inside = 0usize;
    for (c, l) in clusters.iter().zip(labels) {
        for (&c, &l) in c.iter().zip(l) {
            if let Some(l) = l {
                *joint.entry((c, l)).or_default() += 1;
                n += 1;
                inside += c.is_some() as usize;
            }
        }
    }
    let mut by_c: HashMap<Option<usize>, usize> = HashMap::new();
    let mut by_l: HashMap<usize, usize> = HashMap::new();
    let mut best_c: HashMap<Option<usize>, usize> = HashMap::new();
    let mut best_l: HashMap<usize, usize> = HashMap::new();
    for (&(c, l), &k) in &joint {
        *by_c.entry(c).or_default() += k;
        *by_l.entry(l).or_default() += k;
        let b = best_c.entry(c).or_default();
        *b = (*b).max(k);
        let b = best_l.entry(l).or_default();
        *b = (*b).max(k);
    }
    if n == 0 {
        return ClusterScores { purity: 0.0, inverse_purity: 0.0, nmi: 0.0, clusters: 0, coverage: 0.0, frames: 0 };
    }
    let nf = n as f64;
    let entropy = |counts: &mut dyn Iterator<Item = usize>| -> f64 {
        counts.map(|k| k as f64 / nf).filter(|&p| p > 0.0).map(|p| -p * p.ln()).sum()
    };
    let (hc, hl) = (entropy(&mut by_c.values().copied()), entropy(&mut by_l.values().copied()));
    let mi: f64 = joint
        .iter()
        .map(|(&(c, l), &k)| {
            let p = k as f64 / nf;
            p * (p * nf * nf / (by_c[&c] as f64 * by_l[&l] as f64)).ln()
        })
        .sum();
    let nmi = if hc + hl > 0.0 { (2.0 * mi / (hc + hl)).clamp(0.0, 1.0) } else { 1.0 };
    ClusterScores {
        purity: best_c.values().sum::<usize>() as f64 / nf,
        inverse_purity: best_l.values().sum::<usize>() as f64 / nf,
        nmi,
        clusters: by_c.len(),
        coverage: inside as f64 / nf,
        frames: n,
    }
}

/// The mean scores of clusters of the same sizes placed at random: the cluster ids of the segments that carry one
/// (the finest, see [`frame_clusters`]) shuffled among them, `seeds` times.
pub fn chance_scores(segmentations: &[Segmentation], labels: &[Vec<Option<usize>>], seeds: u64) -> ClusterScores {
    let mut sum = ClusterScores { purity: 0.0, inverse_purity: 0.0, nmi: 0.0, clusters: 0, coverage: 0.0, frames: 0 };
    let seeds = seeds.max(1);
    for seed in 0..seeds {
        let mut rng = Rng::new(seed);
        let mut ids: Vec<usize> =
            segmentations.iter().flat_map(|s| finest(s).into_iter().filter_map(|k| s.segments[k].cluster)).collect();
        for i in (1..ids.len()).rev() {
            ids.swap(i, rng.below(i + 1));
        }
        let mut next = ids.into_iter();
        let shuffled: Vec<Segmentation> = segmentations
            .iter()
            .map(|s| {
                let mut s = s.clone();
                for k in finest(&s) {
                    s.segments[k].cluster = next.next();
                }
                s
            })
            .collect();
        let clusters: Vec<Vec<Option<usize>>> = shuffled.iter().map(frame_clusters).collect();
        let s = cluster_scores(&clusters, labels);
        sum.purity += s.purity;
        sum.inverse_purity += s.inverse_purity;
        sum.nmi += s.nmi;
        sum.clusters += s.clusters;
        sum.coverage += s.coverage;
        sum.frames = s.frames;
    }
    let k = seeds as f64;
    ClusterScores {
        purity: sum.purity / k,
        inverse_purity: sum.inverse_purity / k,
        nmi: sum.nmi / k,
        clusters: (sum.clusters as f64 / k).round() as usize,
        coverage: sum.coverage / k,
        frames: sum.frames,
    }
}

/// The clustered segments of `s` that hold no other clustered segment (those whose ids [`frame_clusters`] shows).
fn finest(s: &Segmentation) -> Vec<usize> {
    let clustered: Vec<usize> = (0..s.segments.len()).filter(|&k| s.segments[k].cluster.is_some()).collect();
    clustered
        .iter()
        .copied()
        .filter(|&k| {
            let a = &s.segments[k];
            !clustered.iter().any(|&j| {
                let b = &s.segments[j];
                j != k && b.start >= a.start && b.end <= a.end && (b.end - b.start) < (a.end - a.start)
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::segment::{Level, Segment};

    #[test]
    fn scores_match_hand_computed_values() {
        // take 1: clusters 0 0 0 1 | labels a a b b ; take 2: clusters 1 1 none | labels b b a
        let clusters = vec![vec![Some(0), Some(0), Some(0), Some(1)], vec![Some(1), Some(1), None]];
        let labels = vec![vec![Some(0), Some(0), Some(1), Some(1)], vec![Some(1), Some(1), Some(0)]];
        let s = cluster_scores(&clusters, &labels);
        // clusters: 0 = {a,a,b}, 1 = {b,b,b}, none = {a}: purity (2 + 3 + 1) / 7
        assert!((s.purity - 6.0 / 7.0).abs() < 1e-12);
        // labels: a = {0,0,none} → 2, b = {0,1,1,1} → 3: inverse purity 5/7
        assert!((s.inverse_purity - 5.0 / 7.0).abs() < 1e-12);
        assert_eq!((s.clusters, s.frames), (3, 7));
        assert!((s.coverage - 6.0 / 7.0).abs() < 1e-12);
        // NMI by hand: p(c) = 3/7, 3/7, 1/7; p(l) = 3/7, 4/7; joint (0,a) 2, (0,b) 1, (1,b) 3, (none,a) 1
        let p = |k: f64| k / 7.0;
        let hc = -(2.0 * p(3.0) * p(3.0).ln() + p(1.0) * p(1.0).ln());
        let hl = -(p(3.0) * p(3.0).ln() + p(4.0) * p(4.0).ln());
        let term = |k: f64, c: f64, l: f64| p(k) * (p(k) / (p(c) * p(l))).ln();
        let mi = term(2.0, 3.0, 3.0) + term(1.0, 3.0, 4.0) + term(3.0, 3.0, 4.0) + term(1.0, 1.0, 3.0);
        assert!((s.nmi - 2.0 * mi / (hc + hl)).abs() < 1e-12, "{} vs {}", s.nmi, 2.0 * mi / (hc + hl));
        // unlabelled frames are left out; a perfect clustering scores 1
        let labels = vec![vec![Some(0), Some(0), Some(0), Some(1)], vec![Some(1), Some(1), None]];
        let s = cluster_scores(&clusters, &labels);
        assert_eq!((s.purity, s.inverse_purity, s.nmi, s.frames), (1.0, 1.0, 1.0, 6));
    }

    fn seg(start: usize, end: usize, level: Level, cluster: Option<usize>) -> Segment {
        Segment { start, end, label: String::new(), level, cluster, score: None, mirror_of: None, effort: None }
    }

    #[test]
    fn frames_take_the_finest_cluster_and_chance_is_below_a_perfect_clustering() {
        let s = Segmentation {
            file: "t".into(),
            fps: 30.0,
            frames: 40,
            method: "m".into(),
            params: serde_json::json!({}),
            segments: vec![
                seg(0, 19, Level::Action, Some(7)),
                seg(0, 9, Level::Primitive, Some(0)),
                seg(10, 19, Level::Primitive, Some(0)),
                seg(20, 29, Level::Primitive, Some(1)),
                seg(30, 39, Level::Primitive, Some(1)),
            ],
        };
        let f = frame_clusters(&s);
        assert_eq!((f[0], f[15], f[25], f[39]), (Some(0), Some(0), Some(1), Some(1)));
        let labels = vec![(0..40).map(|i| Some(i / 20)).collect::<Vec<_>>()];
        let perfect = cluster_scores(&[f], &labels);
        assert_eq!(perfect.nmi, 1.0);
        let chance = chance_scores(&[s], &labels, 50);
        assert!(chance.nmi < 0.5 && chance.purity < 0.9, "{chance:?}");
        assert_eq!(chance.frames, 40);
    }
}
