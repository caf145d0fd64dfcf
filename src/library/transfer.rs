//! Label transfer from a labelled take to every other take of a library (SSSM paper §VII-E; see the
//! [module design](super)).
//!
//! * [`TransferRoute::Nearest`] — the paper's: the labelled take's units are the knowledge base, its frames indexed
//!   in a kd-tree of their own; every frame of the library gets its nearest labelled frames within the radius, and
//!   the warping paths through them (a subsequence DTW: the path must cover `coverage` of the *unlabelled* unit, any
//!   part of the labelled one; slope within `[1/ν, ν]`, long enough) join units to labelled units. A unit takes the
//!   label of the labelled unit whose path has the lowest mean distance. Confidence:
//!   `(1 − mean distance / radius) × the labelled unit's majority share`. No such path: unknown.
//! * [`TransferRoute::Clusters`] — through the shared clusters ([`super::cluster`]): a cluster's label is the
//!   majority label of the labelled take's frames in it, its confidence that majority's share; a unit of a cluster
//!   with no labelled frames is unknown.
//!
//! A labelled unit's label is the majority label of its frames; one whose frames are mostly unlabelled teaches
//! nothing.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use super::clusters::{cluster_placed, place, Placed};
use super::{LibraryError, LibraryParams, LibraryTake};
use crate::features::FeatureMatrix;
use crate::method::Cancelled;
use crate::segment::{Level, Segment, Segmentation, UNKNOWN};
use crate::similarity::neighbours::NeighbourSearch;
use crate::similarity::paths::{Blocks, NeighbourhoodGraph};
use crate::similarity::{frame_lookup, NONE};

/// How labels travel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TransferRoute {
    /// The cheapest valid warping path to a labelled unit (§VII-E).
    Nearest,
    /// The majority label of the labelled take's frames in the unit's shared cluster.
    Clusters,
}

/// The labelled take of a library: its index and a label (or none) for each of its file frames.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct KnowledgeBase {
    pub take: usize,
    pub frame_labels: Vec<Option<String>>,
}

/// One take's transferred labels.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Transferred {
    /// Consecutive units of one label joined into one action segment each (`unknown` where nothing fit), `score` the
    /// frame-weighted mean confidence.
    pub segmentation: Segmentation,
    /// Every file frame's label (`None`: unknown or in no unit).
    pub frame_labels: Vec<Option<String>>,
}

/// The labels of every take of a library (the labelled take keeps its own).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Transfer {
    pub route: TransferRoute,
    pub takes: Vec<Transferred>,
}

/// Carries the labels of `kb` to every take of `takes` by `route`.
pub fn transfer(
    takes: &[LibraryTake],
    kb: &KnowledgeBase,
    route: TransferRoute,
    params: &LibraryParams,
    progress: &mut dyn FnMut(f64) -> Result<(), Cancelled>,
) -> Result<Transfer, LibraryError> {
    let labelled = takes.get(kb.take).ok_or_else(|| LibraryError::Labels {
        take: kb.take.to_string(),
        message: format!("there is no take {} in a library of {}", kb.take, takes.len()),
    })?;
    if kb.frame_labels.len() != labelled.features.file_frames {
        return Err(LibraryError::Labels {
            take: labelled.name.clone(),
            message: format!(
                "the labels cover {} frames, the take has {}",
                kb.frame_labels.len(),
                labelled.features.file_frames
            ),
        });
    }
    if kb.frame_labels.iter().all(Option::is_none) {
        return Err(LibraryError::Labels { take: labelled.name.clone(), message: "no frame of it is labelled".into() });
    }
    // per take, per unit: (label, confidence)
    let placed = place(takes, params)?;
    let assigned: Vec<Vec<Option<(String, f64)>>> = match route {
        TransferRoute::Nearest => nearest(&placed, takes, kb, params, progress)?,
        TransferRoute::Clusters => through_clusters(&placed, takes, kb, params, progress)?,
    };
    let out = takes
        .iter()
        .enumerate()
        .map(|(t, take)| {
            if t == kb.take {
                return own_labels(take, &kb.frame_labels);
            }
            let stretches: Vec<(usize, usize, Option<(String, f64)>)> = placed.units[t]
                .iter()
                .zip(&assigned[t])
                .map(|(u, a)| {
                    let s = &take.segmentation.segments[u.segment];
                    (s.start, s.end, a.clone())
                })
                .collect();
            labelled_take(take, &stretches)
        })
        .collect();
    Ok(Transfer { route, takes: out })
}

/// The majority label of `labels[start..=end]` and its share of those frames (`None` if most are unlabelled).
fn majority(labels: &[Option<String>], start: usize, end: usize) -> Option<(String, f64)> {
    let frames = labels.get(start..=end.min(labels.len().saturating_sub(1)))?;
    let mut votes: BTreeMap<&str, usize> = BTreeMap::new();
    for l in frames.iter().flatten() {
        *votes.entry(l).or_default() += 1;
    }
    let (label, n) = votes.into_iter().max_by_key(|&(l, n)| (n, std::cmp::Reverse(l)))?;
    let share = n as f64 / frames.len() as f64;
    (share >= 0.5).then(|| (label.to_string(), share))
}

/// The labels of the labelled take's units (`None` where a unit teaches nothing).
fn taught(placed: &Placed, takes: &[LibraryTake], kb: &KnowledgeBase) -> Vec<Option<(String, f64)>> {
    let take = &takes[kb.take];
    placed.units[kb.take]
        .iter()
        .map(|u| {
            let s = &take.segmentation.segments[u.segment];
            majority(&kb.frame_labels, s.start, s.end)
        })
        .collect()
}

fn nearest(
    placed: &Placed,
    takes: &[LibraryTake],
    kb: &KnowledgeBase,
    params: &LibraryParams,
    progress: &mut dyn FnMut(f64) -> Result<(), Cancelled>,
) -> Result<Vec<Vec<Option<(String, f64)>>>, LibraryError> {
    let teach = taught(placed, takes, kb);
    progress(0.0)?;
    // the knowledge base: a neighbour search over the labelled take's frames alone, so that every frame of the
    // library gets its `max_neighbours` nearest frames *of the labelled take* (not crowded out by its own take's)
    let (first, frames) = placed.range(kb.take);
    let dim = placed.stacked.dim();
    let known =
        FeatureMatrix::new(frames, dim, placed.stacked.as_slice()[first * dim..(first + frames) * dim].to_vec())
            .map_err(|e| LibraryError::Take { take: takes[kb.take].name.clone(), message: e.to_string() })?;
    let search = NeighbourSearch::new(&known);
    progress(0.1)?;
    let cross = search
        .cross_similarity(&placed.stacked, params.stacked_radius(), params.max_neighbours)
        .map_err(|e| LibraryError::Take { take: takes[kb.take].name.clone(), message: e.to_string() })?;
    progress(0.8)?;
    let graph = NeighbourhoodGraph::new(&cross);
    // rows: every unit of the library; columns: the labelled take's units, in its own frame index
    let rows = frame_lookup(cross.frames(), &placed.spans);
    let mut cols = vec![NONE; cross.frames()];
    for (u, span) in placed.spans.iter().enumerate().filter(|(u, _)| placed.owner[*u].0 == kb.take) {
        cols[span.start - first..=span.end - first].iter_mut().for_each(|c| *c = u as u32);
    }
    let paths = graph.warping_paths(&Blocks::rows_cols(&rows, &cols));
    progress(0.95)?;
    let radius = params.stacked_radius() as f64;
    // best (mean cost, labelled unit) per unit
    let mut best: Vec<Option<(f32, usize)>> = vec![None; placed.spans.len()];
    for path in paths.iter().filter(|p| p.is_valid(params.nu, params.min_path_frames)) {
        let (p, q) = path.block();
        let (tp, tq) = (placed.owner[p].0, placed.owner[q].0);
        if tq != kb.take || tp == kb.take || teach[placed.owner[q].1].is_none() {
            continue;
        }
        let cover_p = (path.end.0 - path.start.0 + 1) as f64 / placed.spans[p].len() as f64;
        if cover_p < params.coverage {
            continue;
        }
        let cost = path.mean_cost();
        if best[p].is_none_or(|(c, _)| cost < c) {
            best[p] = Some((cost, q));
        }
    }
    let mut out: Vec<Vec<Option<(String, f64)>>> = placed.units.iter().map(|u| vec![None; u.len()]).collect();
    for (p, b) in best.iter().enumerate() {
        if let Some((cost, q)) = *b {
            let (label, share) = teach[placed.owner[q].1].clone().expect("only teaching units are kept");
            let (t, k) = placed.owner[p];
            out[t][k] = Some((label, (1.0 - cost as f64 / radius).clamp(0.0, 1.0) * share));
        }
    }
    Ok(out)
}

fn through_clusters(
    placed: &Placed,
    takes: &[LibraryTake],
    kb: &KnowledgeBase,
    params: &LibraryParams,
    progress: &mut dyn FnMut(f64) -> Result<(), Cancelled>,
) -> Result<Vec<Vec<Option<(String, f64)>>>, LibraryError> {
    let shared = cluster_placed(takes, placed, params, progress)?;
    // votes of the labelled take's frames per cluster
    let mut votes: Vec<BTreeMap<String, usize>> = vec![BTreeMap::new(); shared.clusters.len()];
    for c in &shared.clusters {
        for o in c.occurrences.iter().filter(|o| o.take == kb.take) {
            for l in kb.frame_labels[o.start..=o.end].iter().flatten() {
                *votes[c.id].entry(l.clone()).or_default() += 1;
            }
        }
    }
    let label_of: Vec<Option<(String, f64)>> = votes
        .iter()
        .map(|v| {
            let total: usize = v.values().sum();
            let (l, n) = v.iter().max_by_key(|&(l, &n)| (n, std::cmp::Reverse(l.clone())))?;
            Some((l.clone(), *n as f64 / total as f64))
        })
        .collect();
    Ok(placed
        .units
        .iter()
        .enumerate()
        .map(|(t, units)| {
            units
                .iter()
                .map(|u| shared.takes[t].segments[u.segment].cluster.and_then(|c| label_of[c].clone()))
                .collect()
        })
        .collect())
}

/// The labelled take as its own labels say (runs of one label).
fn own_labels(take: &LibraryTake, labels: &[Option<String>]) -> Transferred {
    let mut stretches = Vec::new();
    let mut start = 0;
    for f in 1..=labels.len() {
        if f == labels.len() || labels[f] != labels[start] {
            stretches.push((start, f - 1, labels[start].clone().map(|l| (l, 1.0))));
            start = f;
        }
    }
    labelled_take(take, &stretches)
}

/// A take's segmentation and frame labels from labelled stretches `(start, end, label and confidence)` (file
/// frames), consecutive stretches of one label joined.
fn labelled_take(take: &LibraryTake, stretches: &[(usize, usize, Option<(String, f64)>)]) -> Transferred {
    let frames = take.features.file_frames;
    let mut frame_labels = vec![None; frames];
    let mut segments: Vec<Segment> = Vec::new();
    let mut weight: Vec<f64> = Vec::new();
    for (start, end, a) in stretches {
        let end = (*end).min(frames.saturating_sub(1));
        let (label, conf) = match a {
            Some((l, c)) => (l.clone(), *c),
            None => (UNKNOWN.to_string(), 0.0),
        };
        if a.is_some() {
            frame_labels[*start..=end].iter_mut().for_each(|f| *f = Some(label.clone()));
        }
        let len = (end + 1 - start) as f64;
        match segments.last_mut() {
            Some(last) if last.label == label && last.end + 1 >= *start => {
                let w = weight.last_mut().expect("one weight per segment");
                let score = last.score.unwrap_or(0.0);
                last.score = Some((score * *w + conf * len) / (*w + len));
                *w += len;
                last.end = end;
            }
            _ => {
                segments.push(Segment {
                    start: *start,
                    end,
                    label,
                    level: Level::Action,
                    cluster: None,
                    score: Some(conf),
                    mirror_of: None,
                    effort: None,
                });
                weight.push(len);
            }
        }
    }
    Transferred {
        segmentation: Segmentation {
            file: take.segmentation.file.clone(),
            fps: take.segmentation.fps,
            frames,
            method: "transfer".into(),
            params: serde_json::json!({}),
            segments,
        },
        frame_labels,
    }
}

#[cfg(test)]
mod tests {
    use super::super::clusters::tests::take;
    use super::*;

    fn labels_of(t: &LibraryTake, runs: &[(usize, &str)]) -> Vec<Option<String>> {
        let mut out = Vec::new();
        for &(n, l) in runs {
            out.extend(std::iter::repeat_n(Some(l.to_string()), n));
        }
        assert_eq!(out.len(), t.features.file_frames);
        out
    }

    #[test]
    fn labels_travel_to_the_same_motion_in_another_take_both_routes() {
        let a = take("a", &[(5, 30, 0.3), (5, 24, 1.1)]);
        let b = take("b", &[(5, 26, 1.1), (5, 33, 0.3), (5, 30, 2.3)]);
        let kb = KnowledgeBase { take: 0, frame_labels: labels_of(&a, &[(150, "squat"), (120, "jog")]) };
        let blocks = [(0, 130, "jog"), (130, 295, "squat")];
        for route in [TransferRoute::Nearest, TransferRoute::Clusters] {
            let t = transfer(&[a.clone(), b.clone()], &kb, route, &LibraryParams::default(), &mut |_| Ok(())).unwrap();
            assert_eq!(t.takes[0].frame_labels, kb.frame_labels, "{route:?}: the labelled take keeps its labels");
            let got = &t.takes[1].frame_labels;
            assert_eq!(got.len(), b.features.file_frames);
            for (start, end, label) in blocks {
                // never a wrong label; most of the block's frames (all but its edge repetitions) the right one
                let part = &got[start..end];
                assert!(part.iter().flatten().all(|l| l == label), "{route:?}: {part:?}");
                let right = part.iter().filter(|l| l.as_deref() == Some(label)).count();
                assert!(right * 5 >= part.len() * 3, "{route:?} {label}: {right} of {}", part.len());
            }
            // a motion the labelled take does not hold: its inner repetitions stay unknown
            assert!(got[325..385].iter().all(Option::is_none), "{route:?}: {:?}", &got[295..]);
            let segs = &t.takes[1].segmentation.segments;
            assert!(
                segs.windows(2).all(|w| w[0].label != w[1].label && w[0].end + 1 == w[1].start),
                "{route:?}: joined"
            );
            assert!(segs.iter().any(|s| s.label == "jog") && segs.iter().any(|s| s.label == UNKNOWN));
            for s in segs {
                let conf = s.score.unwrap();
                assert!((0.0..=1.0).contains(&conf) && (s.label == UNKNOWN) == (conf == 0.0), "{route:?}: {s:?}");
            }
        }
    }

    #[test]
    fn bad_knowledge_bases_are_refused() {
        let a = take("a", &[(2, 30, 0.3)]);
        let p = LibraryParams::default();
        let kb = KnowledgeBase { take: 3, frame_labels: vec![] };
        let e = transfer(&[a.clone()], &kb, TransferRoute::Nearest, &p, &mut |_| Ok(())).unwrap_err();
        assert!(e.to_string().contains("there is no take 3 in a library of 1"), "{e}");
        let kb = KnowledgeBase { take: 0, frame_labels: vec![None; 10] };
        let e = transfer(&[a.clone()], &kb, TransferRoute::Nearest, &p, &mut |_| Ok(())).unwrap_err();
        assert_eq!(e.to_string(), "take a: the labels cover 10 frames, the take has 60");
        let kb = KnowledgeBase { take: 0, frame_labels: vec![None; 60] };
        let e = transfer(&[a], &kb, TransferRoute::Clusters, &p, &mut |_| Ok(())).unwrap_err();
        assert_eq!(e.to_string(), "take a: no frame of it is labelled");
    }
}
