//! Reference segmentations that every score is read beside (the scoreboard's *chance* and *oracle-K* rows):
//!
//! * [`chance`] — blind cuts every `period` frames from a random phase, each segment labelled with a class drawn from
//!   a prior (the training labels' frequencies). What a method scores without looking at the motion, knowing only how
//!   long segments are on average. Averaged over seeds by the caller ([`chance_scores`]).
//! * [`equal_parts`] — the take cut into `k` equal parts: what knowing the true number of segments alone gives.
//!
//! Both are ordinary [`Segmentation`]s, scored by [`super::metrics::evaluate`] like any method's.

use serde::Serialize;

use super::metrics::{evaluate, MetricsError, Scores, Tolerances};
use super::truth::Truth;
use super::{Level, Segment, Segmentation};
use crate::stats::Rng;

/// Classes with their share of labelled frames (need not sum to 1; only ratios count).
pub type Prior = Vec<(String, f64)>;

/// The label frequencies of `truths` (frames per label), in order of first appearance.
pub fn prior(truths: &[&Truth]) -> Prior {
    let mut out: Prior = Vec::new();
    for t in truths {
        for s in &t.segments {
            let frames = (s.end - s.start + 1) as f64;
            match out.iter_mut().find(|(l, _)| *l == s.label) {
                Some((_, n)) => *n += frames,
                None => out.push((s.label.clone(), frames)),
            }
        }
    }
    out
}

/// A class drawn from `prior` (empty label when the prior is empty or has no mass).
fn draw(prior: &Prior, rng: &mut Rng) -> String {
    let total: f64 = prior.iter().map(|(_, w)| w.max(0.0)).sum();
    if total <= 0.0 {
        return String::new();
    }
    let mut x = rng.next_f32() as f64 * total;
    for (label, w) in prior {
        x -= w.max(0.0);
        if x < 0.0 {
            return label.clone();
        }
    }
    prior.last().map(|(l, _)| l.clone()).unwrap_or_default()
}

fn segmentation(frames: usize, fps: f64, method: &str, segments: Vec<Segment>) -> Segmentation {
    Segmentation { file: String::new(), fps, frames, method: method.into(), params: serde_json::Value::Null, segments }
}

fn part(start: usize, end: usize, label: String, level: Level) -> Segment {
    Segment { start, end, label, level, cluster: None, score: None, mirror_of: None, effort: None }
}

/// Blind cuts every `period` frames (at least 1) from a phase drawn uniformly in `0..period`, tiling the take with
/// segments of `level`, each labelled with a class drawn from `prior` (labels name the truth's, so they are scored by
/// name). The same seed gives the same segmentation.
pub fn chance(frames: usize, fps: f64, period: f64, prior: &Prior, level: Level, seed: u64) -> Segmentation {
    let mut rng = Rng::new(seed);
    let period = period.max(1.0);
    let phase = rng.next_f32() as f64 * period;
    let mut cuts: Vec<usize> = Vec::new();
    let mut at = phase;
    while (at.round() as usize) < frames {
        let c = at.round() as usize;
        if c > 0 && cuts.last() != Some(&c) {
            cuts.push(c);
        }
        at += period;
    }
    let mut segments = Vec::new();
    let mut start = 0;
    for end in cuts.into_iter().chain(std::iter::once(frames)) {
        if end > start {
            segments.push(part(start, end - 1, draw(prior, &mut rng), level));
            start = end;
        }
    }
    segmentation(frames, fps, "chance", segments)
}

/// The take cut into `k` (at least 1, at most `frames`) parts of equal length, labelled `part 1`, `part 2`, ….
pub fn equal_parts(frames: usize, fps: f64, k: usize, level: Level) -> Segmentation {
    let k = k.clamp(1, frames.max(1));
    let segments = (0..k)
        .filter_map(|i| {
            let (start, end) = (i * frames / k, (i + 1) * frames / k);
            (end > start).then(|| part(start, end - 1, format!("part {}", i + 1), level))
        })
        .collect();
    segmentation(frames, fps, "oracle-k", segments)
}

/// The mean of the scores the scoreboard reports, over several seeds of [`chance`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MeanScores {
    pub f1_05: f64,
    pub f1_1: f64,
    pub covering: f64,
    pub similarity: f64,
    pub frame_accuracy: f64,
    pub edit: f64,
    pub f1_50: f64,
    /// Segments scored (a mean over seeds).
    pub segments: f64,
}

impl MeanScores {
    /// The numbers of one score.
    pub fn of(s: &Scores, segments: usize) -> MeanScores {
        MeanScores {
            f1_05: s.boundaries[0].f1,
            f1_1: s.boundaries.get(1).map_or(f64::NAN, |b| b.f1),
            covering: s.covering,
            similarity: s.segments.similarity,
            frame_accuracy: s.labelling.frame_accuracy,
            edit: s.labelling.edit,
            f1_50: s.labelling.f1[2],
            segments: segments as f64,
        }
    }

    /// The mean of `all` (zeros when empty).
    pub fn mean(all: &[MeanScores]) -> MeanScores {
        let n = all.len().max(1) as f64;
        let sum = |f: fn(&MeanScores) -> f64| all.iter().map(f).sum::<f64>() / n;
        MeanScores {
            f1_05: sum(|m| m.f1_05),
            f1_1: sum(|m| m.f1_1),
            covering: sum(|m| m.covering),
            similarity: sum(|m| m.similarity),
            frame_accuracy: sum(|m| m.frame_accuracy),
            edit: sum(|m| m.edit),
            f1_50: sum(|m| m.f1_50),
            segments: sum(|m| m.segments),
        }
    }
}

/// [`chance`] against `truth` with the truth's own mean segment length as the period, averaged over `seeds`.
pub fn chance_scores(
    truth: &Truth,
    fps: f64,
    prior: &Prior,
    level: Level,
    seeds: u64,
) -> Result<MeanScores, MetricsError> {
    let labelled: usize = truth.segments.iter().map(|s| s.end - s.start + 1).sum();
    let period = labelled as f64 / truth.segments.len().max(1) as f64;
    let mut all = Vec::new();
    for seed in 1..=seeds.max(1) {
        let seg = chance(truth.frames, fps, period, prior, level, seed);
        let scores = evaluate(&seg, truth, &Tolerances::default())?;
        all.push(MeanScores::of(&scores, seg.segments.len()));
    }
    Ok(MeanScores::mean(&all))
}

#[cfg(test)]
mod tests {
    use super::super::truth::TruthSegment;
    use super::*;

    fn truth(frames: usize, parts: &[(usize, usize, &str)]) -> Truth {
        Truth {
            trial: "t".into(),
            frames,
            segments: parts
                .iter()
                .map(|&(start, end, l)| TruthSegment { start, end, label: l.into(), end_window: None })
                .collect(),
        }
    }

    #[test]
    fn chance_tiles_the_take_every_period_from_a_seeded_phase() {
        let p: Prior = vec![("a".into(), 3.0), ("b".into(), 1.0)];
        let s = chance(1000, 10.0, 100.0, &p, Level::Action, 7);
        s.validate().unwrap();
        assert_eq!(s.segments.first().unwrap().start, 0);
        assert_eq!(s.segments.last().unwrap().end, 999);
        for w in s.segments.windows(2) {
            assert_eq!(w[0].end + 1, w[1].start);
        }
        // every inner segment is one period long; the first is the phase, at most a period
        for seg in &s.segments[1..s.segments.len() - 1] {
            assert!((seg.end - seg.start + 1).abs_diff(100) <= 1, "{seg:?}");
        }
        assert!(s.segments[0].end < 100);
        assert_eq!(s, chance(1000, 10.0, 100.0, &p, Level::Action, 7), "seeded");
        assert_ne!(s, chance(1000, 10.0, 100.0, &p, Level::Action, 8));
        // labels are the prior's, about 3:1 over many draws
        let many = chance(100_000, 10.0, 10.0, &p, Level::Action, 1);
        let a = many.segments.iter().filter(|s| s.label == "a").count() as f64 / many.segments.len() as f64;
        assert!((a - 0.75).abs() < 0.03, "{a}");
    }

    #[test]
    fn equal_parts_cut_the_take_into_k() {
        let s = equal_parts(10, 1.0, 3, Level::Action);
        let spans: Vec<_> = s.segments.iter().map(|s| (s.start, s.end)).collect();
        assert_eq!(spans, vec![(0, 2), (3, 5), (6, 9)]);
        assert_eq!(equal_parts(2, 1.0, 5, Level::Action).segments.len(), 2);
        assert_eq!(equal_parts(5, 1.0, 0, Level::Action).segments.len(), 1);
    }

    #[test]
    fn the_prior_counts_frames_per_label_and_chance_scores_by_it() {
        let t = truth(100, &[(0, 59, "walk"), (60, 99, "jump")]);
        assert_eq!(prior(&[&t]), vec![("walk".to_string(), 60.0), ("jump".to_string(), 40.0)]);
        // a prior of one class labels every frame `walk`: frame accuracy 0.6 whatever the cuts
        let only_walk: Prior = vec![("walk".into(), 1.0)];
        let m = chance_scores(&t, 10.0, &only_walk, Level::Action, 5).unwrap();
        assert!((m.frame_accuracy - 0.6).abs() < 1e-12, "{m:?}");
        // cuts every 50 frames from a random phase: 2–3 segments
        assert!((2.0..=3.0).contains(&m.segments), "{m:?}");
        assert!(m.covering > 0.3 && m.covering < 1.0, "{m:?}");
    }
}
