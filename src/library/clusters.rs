//! Clusters shared across the takes of a library: §VI of the SSSM paper on one SSSM of every take
//! (see the [module design](super)).

use serde::{Deserialize, Serialize};

use super::{units, LibraryError, LibraryParams, LibraryTake, Unit, MAX_ENTRIES};
use crate::features::{stack, FeatureMatrix};
use crate::method::Cancelled;
use crate::segment::Segmentation;
use crate::similarity::clusters::ClusterSearch;
use crate::similarity::neighbours::NeighbourSearch;
use crate::similarity::paths::NeighbourhoodGraph;
use crate::similarity::Span;

/// One occurrence of a shared cluster: segment `segment` of take `take`, file frames `start..=end`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Occurrence {
    pub take: usize,
    pub segment: usize,
    pub start: usize,
    pub end: usize,
}

/// A cluster of units of one or more takes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SharedCluster {
    pub id: usize,
    /// Its occurrences, by take and then frame.
    pub occurrences: Vec<Occurrence>,
    /// Total duration of its occurrences (seconds, each take at its own frame rate).
    pub seconds: f64,
    /// Number of distinct takes it occurs in.
    pub takes: usize,
}

/// The library's shared clusters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SharedClusters {
    /// Every take's segmentation with shared cluster ids: each unit (see [`units`]) carries its cluster as
    /// `cluster` and `C<id>` as its label; every other segment (an action made of primitives) the cluster that
    /// covers most of its frames.
    pub takes: Vec<Segmentation>,
    /// The clusters, numbered in order of their first occurrence (take by take).
    pub clusters: Vec<SharedCluster>,
    /// Links of the cluster graph that join units of different takes (how much the takes were matched).
    pub cross_links: usize,
}

impl SharedClusters {
    /// The clusters found in more than one take.
    pub fn shared(&self) -> impl Iterator<Item = &SharedCluster> + '_ {
        self.clusters.iter().filter(|c| c.takes > 1)
    }
}

/// Every take's units placed one after another in the library's frame index.
pub(crate) struct Placed {
    /// Per take, its units.
    pub units: Vec<Vec<Unit>>,
    /// Every unit's span in library frames, in order (take by take), with its take and unit index.
    pub spans: Vec<Span>,
    pub owner: Vec<(usize, usize)>,
    /// The stacked features of every take, one after another.
    pub stacked: FeatureMatrix,
    /// Per take, its first library frame and its number of working frames.
    pub frames: Vec<(usize, usize)>,
}

impl Placed {
    /// Take `t`'s first library frame and number of working frames.
    pub fn range(&self, t: usize) -> (usize, usize) {
        self.frames[t]
    }
}

/// Checks the takes and places them (see [`Placed`]).
pub(crate) fn place(takes: &[LibraryTake], params: &LibraryParams) -> Result<Placed, LibraryError> {
    params.check()?;
    if takes.is_empty() {
        return Err(LibraryError::Empty);
    }
    let mut all_units = Vec::with_capacity(takes.len());
    let (mut spans, mut owner) = (Vec::new(), Vec::new());
    let mut data: Vec<f32> = Vec::new();
    let mut dim = None;
    let mut frames = 0usize;
    let mut ranges = Vec::with_capacity(takes.len());
    for (t, take) in takes.iter().enumerate() {
        take.check()?;
        let base = take.features.matrix().map_err(|message| LibraryError::Take { take: take.name.clone(), message })?;
        if *dim.get_or_insert(base.dim()) != base.dim() {
            return Err(LibraryError::Take {
                take: take.name.clone(),
                message: format!(
                    "its features have {} values per frame, the first take's {}",
                    base.dim(),
                    dim.unwrap_or(0)
                ),
            });
        }
        frames += base.frames();
        if frames.saturating_mul(params.max_neighbours) > MAX_ENTRIES {
            return Err(LibraryError::TooLarge { frames, max_neighbours: params.max_neighbours, limit: MAX_ENTRIES });
        }
        let offset = frames - base.frames();
        ranges.push((offset, base.frames()));
        let u = units(&take.segmentation, &take.features);
        for (k, unit) in u.iter().enumerate() {
            spans.push(Span { start: unit.span.start + offset, end: unit.span.end + offset });
            owner.push((t, k));
        }
        all_units.push(u);
        data.extend_from_slice(stack(&base, &params.offsets).as_slice());
    }
    let stacked_dim = dim.unwrap_or(1) * params.offsets.len();
    let stacked = FeatureMatrix::new(frames, stacked_dim, data)
        .map_err(|e| LibraryError::Take { take: takes[0].name.clone(), message: e.to_string() })?;
    Ok(Placed { units: all_units, spans, owner, stacked, frames: ranges })
}

/// Clusters the units of every take of `takes` together (see the [module design](super)); `progress` gets the
/// fraction done and may cancel.
pub fn cluster(
    takes: &[LibraryTake],
    params: &LibraryParams,
    progress: &mut dyn FnMut(f64) -> Result<(), Cancelled>,
) -> Result<SharedClusters, LibraryError> {
    let placed = place(takes, params)?;
    cluster_placed(takes, &placed, params, progress)
}

/// [`cluster`] on takes already placed (label transfer places them once for both steps).
pub(crate) fn cluster_placed(
    takes: &[LibraryTake],
    placed: &Placed,
    params: &LibraryParams,
    progress: &mut dyn FnMut(f64) -> Result<(), Cancelled>,
) -> Result<SharedClusters, LibraryError> {
    progress(0.0)?;
    // one SSSM of the whole library: every working frame's neighbours within the stacked radius, in any take
    let search = NeighbourSearch::new(&placed.stacked);
    let sssm = search
        .self_similarity_with_progress(params.stacked_radius(), params.max_neighbours, &mut |f| progress(0.8 * f))?;
    progress(0.8)?;
    let graph = NeighbourhoodGraph::new(&sssm);
    let search = ClusterSearch { nu: params.nu, min_path_frames: params.min_path_frames, coverage: params.coverage };
    let links = search.links(&graph, &placed.spans);
    progress(0.95)?;
    let cross_links = links.iter().filter(|&&(p, q)| placed.owner[p].0 != placed.owner[q].0).count();
    let cluster_of = ClusterSearch::clusters(placed.spans.len(), &links);
    Ok(describe(takes, placed, &cluster_of, cross_links))
}

/// The shared clusters of `cluster_of` (one id per placed unit).
fn describe(takes: &[LibraryTake], placed: &Placed, cluster_of: &[usize], cross_links: usize) -> SharedClusters {
    let count = cluster_of.iter().map(|&c| c + 1).max().unwrap_or(0);
    let mut clusters: Vec<SharedCluster> =
        (0..count).map(|id| SharedCluster { id, occurrences: Vec::new(), seconds: 0.0, takes: 0 }).collect();
    let mut out: Vec<Segmentation> = takes.iter().map(|t| t.segmentation.clone()).collect();
    // per take, per segment: the cluster of the unit it is
    let mut unit_cluster: Vec<Vec<Option<usize>>> = out.iter().map(|s| vec![None; s.segments.len()]).collect();
    for (u, &(t, k)) in placed.owner.iter().enumerate() {
        let c = cluster_of[u];
        let segment = placed.units[t][k].segment;
        let s = &out[t].segments[segment];
        clusters[c].occurrences.push(Occurrence { take: t, segment, start: s.start, end: s.end });
        clusters[c].seconds += (s.end + 1 - s.start) as f64 / out[t].fps;
        unit_cluster[t][segment] = Some(c);
    }
    for c in &mut clusters {
        let mut seen: Vec<usize> = c.occurrences.iter().map(|o| o.take).collect();
        seen.dedup();
        c.takes = seen.len();
    }
    for (t, seg) in out.iter_mut().enumerate() {
        let units: Vec<(usize, usize, usize)> = seg
            .segments
            .iter()
            .enumerate()
            .filter_map(|(k, s)| unit_cluster[t][k].map(|c| (s.start, s.end, c)))
            .collect();
        for (k, s) in seg.segments.iter_mut().enumerate() {
            let c = unit_cluster[t][k].or_else(|| covering_cluster(&units, s.start, s.end));
            s.cluster = c;
            s.mirror_of = None;
            if let Some(c) = c {
                s.label = format!("C{c}");
            }
        }
    }
    SharedClusters { takes: out, clusters, cross_links }
}

/// The cluster of `units` (`(start, end, cluster)`) covering most frames of `start..=end`, if any does.
fn covering_cluster(units: &[(usize, usize, usize)], start: usize, end: usize) -> Option<usize> {
    let mut frames: std::collections::BTreeMap<usize, usize> = Default::default();
    for &(a, b, c) in units {
        let (lo, hi) = (a.max(start), b.min(end));
        if lo <= hi {
            *frames.entry(c).or_default() += hi + 1 - lo;
        }
    }
    frames.into_iter().max_by_key(|&(c, n)| (n, std::cmp::Reverse(c))).map(|(c, _)| c)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::super::TakeFeatures;
    use super::*;
    use crate::segment::{Level, Segment};

    /// A take of `reps` repetitions of `shape` (a closed loop of `period` working frames in 15-D), file = working
    /// frames (30 Hz), one primitive per repetition.
    pub(crate) fn take(name: &str, shapes: &[(usize, usize, f32)]) -> LibraryTake {
        let mut values = Vec::new();
        let mut segments = Vec::new();
        let mut n = 0;
        for &(reps, period, shape) in shapes {
            let start = n;
            for r in 0..reps {
                let s = n;
                for i in 0..period {
                    let phase = i as f32 / period as f32 * std::f32::consts::TAU;
                    for d in 0..15 {
                        let a = 20.0 * (phase + d as f32 * shape).sin() + 8.0 * shape * d as f32;
                        values.push(a);
                    }
                    n += 1;
                }
                let _ = r;
                segments.push(seg(s, n - 1, Level::Primitive));
            }
            segments.push(seg(start, n - 1, Level::Action));
        }
        segments.sort_by_key(|s| (s.start, s.level != Level::Primitive, s.end));
        LibraryTake {
            name: name.into(),
            features: TakeFeatures {
                dim: 15,
                values,
                source_frames: (0..n).map(|k| k as f64).collect(),
                file_frames: n,
                file_fps: 30.0,
            },
            segmentation: Segmentation {
                file: name.into(),
                fps: 30.0,
                frames: n,
                method: "test".into(),
                params: serde_json::json!({}),
                segments,
            },
        }
    }

    fn seg(start: usize, end: usize, level: Level) -> Segment {
        Segment { start, end, label: "x".into(), level, cluster: None, score: None, mirror_of: None, effort: None }
    }

    fn cluster_of_primitives(c: &SharedClusters, take: usize) -> Vec<usize> {
        c.takes[take].segments.iter().filter(|s| s.level == Level::Primitive).map(|s| s.cluster.unwrap()).collect()
    }

    #[test]
    fn the_same_motion_in_two_takes_shares_a_cluster() {
        // take a: 5 reps of motion 0.3 then 5 of motion 1.1; take b: 5 of 1.1 then 5 of 0.3 (other tempi). The
        // first and last repetition of a block see the other motion through the stacked offsets (±10 frames), so
        // the inner repetitions are the ones that must match.
        let a = take("a", &[(5, 30, 0.3), (5, 24, 1.1)]);
        let b = take("b", &[(5, 26, 1.1), (5, 33, 0.3)]);
        let c = cluster(&[a, b], &LibraryParams::default(), &mut |_| Ok(())).unwrap();
        let (pa, pb) = (cluster_of_primitives(&c, 0), cluster_of_primitives(&c, 1));
        let inner = |p: &[usize], block: usize| -> Vec<usize> { p[block * 5 + 1..block * 5 + 4].to_vec() };
        let (a0, a1, b0, b1) = (inner(&pa, 0), inner(&pa, 1), inner(&pb, 0), inner(&pb, 1));
        // within a motion one cluster, the two motions different, and the same ids across takes
        assert!(a0.iter().chain(&b1).all(|&x| x == a0[0]), "{pa:?} {pb:?}");
        assert!(a1.iter().chain(&b0).all(|&x| x == a1[0]), "{pa:?} {pb:?}");
        assert_ne!(a0[0], a1[0]);
        assert!(c.cross_links > 0);
        assert!(c.shared().count() >= 2);
        // the actions take the cluster covering most of their frames, and its label
        let actions: Vec<&Segment> = c.takes[1].segments.iter().filter(|s| s.level == Level::Action).collect();
        assert_eq!(actions[0].cluster, Some(a1[0]));
        assert_eq!(actions[0].label, format!("C{}", a1[0]));
        let shared = &c.clusters[a0[0]];
        assert!(shared.takes == 2 && shared.occurrences.len() >= 6, "{shared:?}");
        let seconds: f64 = shared.occurrences.iter().map(|o| (o.end + 1 - o.start) as f64 / 30.0).sum();
        assert!((shared.seconds - seconds).abs() < 1e-9);
        assert!(shared.occurrences.iter().all(|o| c.takes[o.take].segments[o.segment].cluster == Some(a0[0])));
    }

    #[test]
    fn different_motions_in_two_takes_stay_apart() {
        let a = take("a", &[(4, 30, 0.3)]);
        let b = take("b", &[(4, 30, 1.7)]);
        let c = cluster(&[a, b], &LibraryParams::default(), &mut |_| Ok(())).unwrap();
        let (pa, pb) = (cluster_of_primitives(&c, 0), cluster_of_primitives(&c, 1));
        assert!(pa.iter().all(|x| !pb.contains(x)), "{pa:?} {pb:?}");
        assert_eq!(c.cross_links, 0);
        assert_eq!(c.shared().count(), 0);
    }

    #[test]
    fn bad_libraries_are_refused_with_the_take_named() {
        assert_eq!(cluster(&[], &LibraryParams::default(), &mut |_| Ok(())).unwrap_err(), LibraryError::Empty);
        let mut a = take("a", &[(2, 30, 0.3)]);
        a.segmentation.frames += 1;
        let e = cluster(&[a], &LibraryParams::default(), &mut |_| Ok(())).unwrap_err();
        assert!(e.to_string().starts_with("a: the segmentation is of a take of 61 frames, the take has 60"), "{e}");
        let mut a = take("a", &[(2, 30, 0.3)]);
        a.features.values.pop();
        let e = cluster(&[a], &LibraryParams::default(), &mut |_| Ok(())).unwrap_err();
        assert!(e.to_string().starts_with("a: "), "{e}");
        let big = LibraryParams { max_neighbours: 5000, ..LibraryParams::default() };
        let long = take("long", &[(150, 30, 0.3)]);
        let e = cluster(&[long], &big, &mut |_| Ok(())).unwrap_err();
        assert!(matches!(e, LibraryError::TooLarge { frames: 4500, .. }), "{e}");
        let a = take("a", &[(2, 30, 0.3)]);
        let e = cluster(&[a], &LibraryParams::default(), &mut |_| Err(Cancelled)).unwrap_err();
        assert_eq!(e, LibraryError::Cancelled);
    }
}
