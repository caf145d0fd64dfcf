//! Cuts → segments, shared by the methods that find boundaries (first frames of new segments)
//! rather than labelled spans: merging the cuts of several signals (left and right hand, arms and
//! legs) and turning them into segments that cover the take, at the file's frame rate.

use super::frames::WorkingFrames;
use super::{Level, Segment};

/// `cuts` sorted, a run of cuts each within `merge` frames of the previous one replaced by one cut
/// at the run's (rounded) mean.
pub fn merge(mut cuts: Vec<usize>, merge: usize) -> Vec<usize> {
    cuts.sort_unstable();
    let mut out = Vec::new();
    let mut run: Vec<usize> = Vec::new();
    let mean = |run: &[usize]| (run.iter().sum::<usize>() as f64 / run.len() as f64).round() as usize;
    for c in cuts {
        if run.last().is_some_and(|&last| c - last > merge) {
            out.push(mean(&run));
            run.clear();
        }
        run.push(c);
    }
    if !run.is_empty() {
        out.push(mean(&run));
    }
    out.dedup();
    out
}

/// One segment per stretch between `cuts` (working frames, ascending, inside `1..working frames`)
/// over the whole take, mapped to file frames: the `k`-th (from 0) gets `label(k)`, `level`, and
/// `score(k, start, end)` (working frames, inclusive).
pub fn segments(
    frames: &WorkingFrames,
    cuts: &[usize],
    label: impl Fn(usize) -> String,
    level: Level,
    mut score: impl FnMut(usize, usize, usize) -> Option<f64>,
) -> Vec<Segment> {
    let n = frames.source.len();
    let starts: Vec<usize> = std::iter::once(0).chain(cuts.iter().copied().filter(|&c| c > 0 && c < n)).collect();
    let mut out = Vec::new();
    for (k, &start) in starts.iter().enumerate() {
        let end = starts.get(k + 1).map_or(n.saturating_sub(1), |&next| next - 1);
        if n == 0 || end < start {
            continue;
        }
        let (label, score) = (label(k), score(k, start, end));
        let working = Segment { start, end, label, level, cluster: None, score, mirror_of: None, effort: None };
        out.extend(frames.to_file(working));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn close_cuts_merge() {
        assert_eq!(merge(vec![60, 30, 32, 90], 3), vec![31, 60, 90]);
        assert_eq!(merge(vec![10, 12, 14, 16], 2), vec![13]);
        assert_eq!(merge(vec![10, 10], 0), vec![10]);
        assert!(merge(vec![], 5).is_empty());
    }

    #[test]
    fn segments_cover_the_take_at_the_file_rate() {
        // 40 working frames at 30 Hz of a 120 Hz file of 157 frames
        let source: Vec<f64> = (0..40).map(|k| 4.0 * k as f64).collect();
        let w = WorkingFrames { source: &source, file_frames: 157 };
        let s = segments(&w, &[10, 25], |k| format!("g{k}"), Level::Primitive, |_, a, b| Some((b - a) as f64));
        let spans: Vec<(usize, usize)> = s.iter().map(|s| (s.start, s.end)).collect();
        assert_eq!(spans, vec![(0, 37), (38, 97), (98, 156)]);
        assert_eq!((s[1].score, s[1].label.as_str()), (Some(14.0), "g1"));
        assert_eq!(segments(&w, &[], |_| "g".into(), Level::Action, |_, _, _| None).len(), 1);
    }
}
