//! Duration-aware decoding of per-frame class probabilities: the labels of a take as one path
//! through the classes, not each frame's own most probable class — so that a labeller's
//! probabilities that waver between two classes for a few frames do not cut a 10 s exercise into
//! confetti.
//!
//! Not in Cheema et al. 2019 (the paper reports per-frame accuracy only); the segmental scores it
//! is judged by here (edit, F1@k — Lea et al. 2017, as MS-TCN reports them) punish exactly the
//! flicker that per-frame argmax leaves. The decoding is a hidden semi-Markov Viterbi in its
//! simplest form: the path maximises Σₜ log p(cₜ | frame t) − `switch_cost` · (number of
//! changes of class), over paths whose every run except the last is at least `min_frames` long.
//! It is solved exactly on an expanded state space (class × frames into its run, capped at
//! `min_frames`), O(frames · classes · min_frames) time and O(frames · classes) memory.
//!
//! With `min_frames ≤ 1` and `switch_cost = 0` the path is each frame's most probable class (the
//! raw labels), and the labelling method keeps its per-frame `unknown` then; a decoded path's
//! runs are called `unknown` as a whole when their mean probability is below the threshold.

use super::probabilities::Probabilities;
use crate::method::Go;
use crate::segment::frames::WorkingFrames;
use crate::segment::labelling::{score, LabellingScores};

/// How per-frame probabilities become labels.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Decoding {
    /// Shortest run of one class, in seconds (0: any).
    pub min_duration_s: f64,
    /// Cost of a change of class, in nats of summed log-probability (0: free).
    pub switch_cost: f64,
}

/// `v` as a message shows it: a huge or tiny number in exponent form (`1e300`, not 301 digits).
fn shown(v: f64) -> String {
    if v != 0.0 && !(1e-3..1e6).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        v.to_string()
    }
}

/// The decoder asks [`Go`] every this many frames.
const GO_EVERY: usize = 256;

/// The longest minimum run a decoding may ask for, in seconds (a run's parameter or a model file's
/// header): the decoder's time and memory grow with it (module docs).
pub const MAX_MIN_DURATION_S: f64 = 30.0;
/// The largest cost of a change of class, in nats.
pub const MAX_SWITCH_COST: f64 = 1000.0;

impl Decoding {
    /// Each frame's most probable class: the raw labels.
    pub const RAW: Decoding = Decoding { min_duration_s: 0.0, switch_cost: 0.0 };

    /// Refuses a decoding outside the stated ranges (not a number included), naming the field: what
    /// a model file's header says is checked here before the decoder sizes its tables by it.
    pub fn check(&self) -> Result<(), String> {
        if !(0.0..=MAX_MIN_DURATION_S).contains(&self.min_duration_s) {
            return Err(format!(
                "decoding min_duration_s = {}: expected seconds from 0 to {MAX_MIN_DURATION_S}",
                shown(self.min_duration_s)
            ));
        }
        if !(0.0..=MAX_SWITCH_COST).contains(&self.switch_cost) {
            return Err(format!(
                "decoding switch_cost = {}: expected a cost from 0 to {MAX_SWITCH_COST}",
                shown(self.switch_cost)
            ));
        }
        Ok(())
    }

    /// True when this is the raw per-frame labelling.
    pub fn is_raw(&self, fps: f64) -> bool {
        self.min_frames(fps) <= 1 && self.switch_cost <= 0.0
    }

    /// Multiply-adds (a comparison and an addition counted as one) of [`viterbi`] per frame of `classes` classes at
    /// `fps`: every class's every slot of its run; none for the raw labels (one pass over each frame's classes).
    pub fn ops_per_frame(&self, classes: usize, fps: f64) -> f64 {
        if self.is_raw(fps) {
            classes as f64
        } else {
            2.0 * classes as f64 * (self.min_frames(fps) as f64 + 2.0)
        }
    }

    /// The minimum duration in frames at `fps` (at least 1).
    pub fn min_frames(&self, fps: f64) -> usize {
        ((self.min_duration_s * fps).round() as usize).max(1)
    }
}

/// The most probable class path of `p` under `min_frames` and `switch_cost` (module docs): one
/// class per frame.
pub fn viterbi(p: &Probabilities, min_frames: usize, switch_cost: f32) -> Vec<usize> {
    viterbi_going(p, min_frames, switch_cost, &mut |_| true).unwrap_or_default()
}

/// [`viterbi`], asking `go` (the share of the frames done) every [`GO_EVERY`] frames: `None` once it answers false
/// (a run's cancel; the decoder is `frames × classes × min_frames`, minutes for a long take with a long minimum run).
pub fn viterbi_going(p: &Probabilities, min_frames: usize, switch_cost: f32, go: Go) -> Option<Vec<usize>> {
    let (n, c) = (p.frames, p.classes);
    if n == 0 || c == 0 {
        return Some(Vec::new());
    }
    let d = min_frames.max(1);
    let emit = |t: usize, k: usize| (p.prob(t, k).max(0.0) + 1e-6).ln();
    // score[k * d + j]: best score of a path ending at the current frame in class k, j + 1 frames into
    // its run (the last slot: d or more)
    let mut score = vec![f32::NEG_INFINITY; c * d];
    for k in 0..c {
        score[k * d] = emit(0, k);
    }
    // back-pointers per frame and class: the class a run entered from (slot 0; itself when d = 1 and
    // the run goes on), and whether the last slot was reached from itself (the run went on) or the slot before
    let mut from = vec![0u16; n * c];
    let mut stayed = vec![false; n * c];
    let mut next = vec![f32::NEG_INFINITY; c * d];
    for t in 1..n {
        if t % GO_EVERY == 0 && !go(t as f64 / n as f64) {
            return None;
        }
        // the two best classes in their last slot: a new run enters from the best other than itself
        let (mut b1, mut b2) = ((f32::NEG_INFINITY, usize::MAX), (f32::NEG_INFINITY, usize::MAX));
        for k in 0..c {
            let s = score[k * d + d - 1];
            if s > b1.0 {
                b2 = b1;
                b1 = (s, k);
            } else if s > b2.0 {
                b2 = (s, k);
            }
        }
        for k in 0..c {
            let e = emit(t, k);
            let (other, o) = if b1.1 != k { b1 } else { b2 };
            let mut enter = (other - switch_cost, o);
            if d == 1 && score[k] >= enter.0 {
                enter = (score[k], k);
            }
            next[k * d] = enter.0 + e;
            from[t * c + k] = enter.1.min(u16::MAX as usize) as u16;
            for j in 1..d {
                let mut s = score[k * d + j - 1];
                if j == d - 1 {
                    let stay = score[k * d + j];
                    stayed[t * c + k] = stay > s;
                    s = s.max(stay);
                }
                next[k * d + j] = s + e;
            }
        }
        std::mem::swap(&mut score, &mut next);
    }
    // the best end state (any slot: the last run may be short), then back
    let (mut k, mut j) = (0, 0);
    let mut best = f32::NEG_INFINITY;
    for kk in 0..c {
        for jj in 0..d {
            if score[kk * d + jj] > best {
                best = score[kk * d + jj];
                (k, j) = (kk, jj);
            }
        }
    }
    let mut path = vec![0; n];
    for t in (0..n).rev() {
        path[t] = k;
        if t == 0 {
            break;
        }
        if j == 0 {
            let prev = from[t * c + k] as usize;
            if prev != k {
                j = d - 1;
            }
            k = prev;
        } else if j == d - 1 && stayed[t * c + k] {
            // the run went on in its last slot
        } else {
            j -= 1;
        }
    }
    Some(path)
}

/// Per file frame: the label (`None` = unknown) and the probability of the frame's decoded class.
/// `source` holds the file position of each of `p`'s frames (at `fps`); raw decoding calls each
/// frame below `threshold` unknown, a decoded path each of its runs whose mean is below it.
pub fn file_labels(
    p: &Probabilities,
    source: &[f64],
    fps: f64,
    file_frames: usize,
    decoding: &Decoding,
    threshold: f64,
) -> Vec<(Option<usize>, f32)> {
    file_labels_going(p, source, fps, file_frames, decoding, threshold, &mut |_| true).unwrap_or_default()
}

/// [`file_labels`], asking `go` as its decoding goes ([`viterbi_going`]): `None` once it answers false.
pub fn file_labels_going(
    p: &Probabilities,
    source: &[f64],
    fps: f64,
    file_frames: usize,
    decoding: &Decoding,
    threshold: f64,
    go: Go,
) -> Option<Vec<(Option<usize>, f32)>> {
    if p.frames == 0 || file_frames == 0 {
        return Some(Vec::new());
    }
    let frames = WorkingFrames { source, file_frames };
    let at = |f: usize| frames.working_frame(f).min(p.frames - 1);
    if decoding.is_raw(fps) {
        return Some(
            (0..file_frames)
                .map(|f| {
                    let (c, q) = p.best(at(f));
                    ((q as f64 >= threshold).then_some(c), q)
                })
                .collect(),
        );
    }
    let path = viterbi_going(p, decoding.min_frames(fps), decoding.switch_cost as f32, go)?;
    let mut out: Vec<(Option<usize>, f32)> = (0..file_frames)
        .map(|f| {
            let w = at(f);
            (Some(path[w]), p.prob(w, path[w]))
        })
        .collect();
    // a run whose mean probability is below the threshold is unknown as a whole
    let mut start = 0;
    for f in 1..=out.len() {
        if f == out.len() || out[f].0 != out[start].0 {
            let mean = out[start..f].iter().map(|x| x.1 as f64).sum::<f64>() / (f - start) as f64;
            if mean < threshold {
                for x in &mut out[start..f] {
                    x.0 = None;
                }
            }
            start = f;
        }
    }
    Some(out)
}

/// The decodings a labelled take chooses between (the first: the raw per-frame labels): minimum runs of 0–8 s,
/// switch costs of 0–150 nats, alone and together.
pub const CANDIDATES: [Decoding; 10] = [
    Decoding::RAW,
    Decoding { min_duration_s: 1.0, switch_cost: 0.0 },
    Decoding { min_duration_s: 2.0, switch_cost: 0.0 },
    Decoding { min_duration_s: 4.0, switch_cost: 0.0 },
    Decoding { min_duration_s: 8.0, switch_cost: 0.0 },
    Decoding { min_duration_s: 0.0, switch_cost: 10.0 },
    Decoding { min_duration_s: 2.0, switch_cost: 10.0 },
    Decoding { min_duration_s: 2.0, switch_cost: 40.0 },
    Decoding { min_duration_s: 4.0, switch_cost: 40.0 },
    Decoding { min_duration_s: 2.0, switch_cost: 150.0 },
];

/// The unknown thresholds chosen with a decoding (the first wins ties).
pub const THRESHOLDS: [f64; 3] = [0.8, 0.5, 0.0];

/// What chooses a decoding: the mean of frame accuracy (%), edit and F1@50 — the labelling targets.
pub fn criterion(s: &LabellingScores) -> f64 {
    (100.0 * s.frame_accuracy + s.edit + s.f1[2]) / 3.0
}

/// A take a decoding is chosen on: its class probabilities per working frame by a labeller that was not trained
/// on it, their file positions and rate, and the take's true label of every file frame (`None`: not labelled).
pub struct Judged<'a> {
    pub probabilities: &'a Probabilities,
    pub source: &'a [f64],
    pub fps: f64,
    pub truth: &'a [Option<usize>],
}

impl Judged<'_> {
    /// Per file frame: the label under `decoding` and `threshold`.
    pub fn labels(&self, decoding: &Decoding, threshold: f64) -> Vec<Option<usize>> {
        file_labels(self.probabilities, self.source, self.fps, self.truth.len(), decoding, threshold)
            .into_iter()
            .map(|x| x.0)
            .collect()
    }
}

/// The decoding and unknown threshold chosen on labelled takes, with their scores there.
#[derive(Debug, Clone, PartialEq)]
pub struct Choice {
    pub decoding: Decoding,
    pub threshold: f64,
    /// The mean [`criterion`] over the takes.
    pub criterion: f64,
    /// The scores of the first take under the choice.
    pub scores: LabellingScores,
}

/// The decoding of [`CANDIDATES`] and threshold of [`THRESHOLDS`] with the best mean [`criterion`] over `takes`
/// (the first of equals: raw labels before decodings, higher thresholds before lower). The threshold is chosen
/// with the decoding: a decoded run is unknown as a whole. `None` without takes.
pub fn choose(takes: &[Judged]) -> Option<Choice> {
    let first = takes.first()?;
    let mut best: Option<Choice> = None;
    for d in &CANDIDATES {
        for &t in &THRESHOLDS {
            let c = takes.iter().map(|j| criterion(&score(&j.labels(d, t), j.truth))).sum::<f64>() / takes.len() as f64;
            if best.as_ref().is_none_or(|b| c > b.criterion + 1e-9) {
                let scores = score(&first.labels(d, t), first.truth);
                best = Some(Choice { decoding: *d, threshold: t, criterion: c, scores });
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Probabilities from per-frame rows.
    fn probs(rows: &[&[f32]]) -> Probabilities {
        Probabilities {
            frames: rows.len(),
            classes: rows[0].len(),
            values: rows.iter().flat_map(|r| r.to_vec()).collect(),
        }
    }

    fn changes(path: &[usize]) -> usize {
        path.windows(2).filter(|w| w[0] != w[1]).count()
    }

    /// Exhaustive search over every path (small takes only): the best score under the same rules.
    fn brute(p: &Probabilities, d: usize, cost: f32) -> f32 {
        let (n, c) = (p.frames, p.classes);
        let mut best = f32::NEG_INFINITY;
        for code in 0..c.pow(n as u32) {
            let path: Vec<usize> = (0..n).map(|t| code / c.pow(t as u32) % c).collect();
            // every run but the last at least d long
            let mut runs = vec![1usize];
            for t in 1..n {
                if path[t] == path[t - 1] {
                    *runs.last_mut().unwrap() += 1;
                } else {
                    runs.push(1);
                }
            }
            if runs[..runs.len() - 1].iter().any(|&r| r < d) {
                continue;
            }
            let s: f32 = (0..n).map(|t| (p.prob(t, path[t]) + 1e-6).ln()).sum::<f32>() - cost * changes(&path) as f32;
            best = best.max(s);
        }
        best
    }

    fn score(p: &Probabilities, path: &[usize], cost: f32) -> f32 {
        path.iter().enumerate().map(|(t, &k)| (p.prob(t, k) + 1e-6).ln()).sum::<f32>() - cost * changes(path) as f32
    }

    #[test]
    fn raw_decoding_is_each_frames_most_probable_class() {
        let p = probs(&[&[0.9, 0.1], &[0.2, 0.8], &[0.6, 0.4], &[0.3, 0.7]]);
        assert_eq!(viterbi(&p, 1, 0.0), vec![0, 1, 0, 1]);
    }

    #[test]
    fn a_short_flicker_inside_a_long_run_is_absorbed_and_a_long_change_is_kept() {
        // 40 frames of class 0 with a 3-frame flicker to class 1 at 20, then 30 frames of class 1
        let mut rows: Vec<Vec<f32>> = Vec::new();
        for t in 0..70 {
            let one = if t < 40 { (20..23).contains(&t) } else { true };
            rows.push(if one { vec![0.3, 0.7] } else { vec![0.8, 0.2] });
        }
        let refs: Vec<&[f32]> = rows.iter().map(|r| r.as_slice()).collect();
        let p = probs(&refs);
        assert_eq!(changes(&viterbi(&p, 1, 0.0)), 3, "raw keeps the flicker");
        for (d, cost) in [(10, 0.0), (1, 5.0), (10, 5.0)] {
            let path = viterbi(&p, d, cost);
            assert_eq!(changes(&path), 1, "d={d} cost={cost}: {path:?}");
            assert_eq!(path.iter().position(|&k| k == 1), Some(40));
        }
    }

    #[test]
    fn the_path_is_the_best_one_allowed_as_an_exhaustive_search_finds_it() {
        // pseudo-random 3-class probabilities over 7 frames: every path checked by brute force
        let mut x = 12345u64;
        let mut rnd = || {
            x = x.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((x >> 33) as f32 / (1u64 << 31) as f32).max(0.01)
        };
        for _ in 0..20 {
            let rows: Vec<Vec<f32>> = (0..7)
                .map(|_| {
                    let r = [rnd(), rnd(), rnd()];
                    let s: f32 = r.iter().sum();
                    r.iter().map(|v| v / s).collect()
                })
                .collect();
            let refs: Vec<&[f32]> = rows.iter().map(|r| r.as_slice()).collect();
            let p = probs(&refs);
            for d in 1..=4 {
                for cost in [0.0, 0.7, 3.0] {
                    let path = viterbi(&p, d, cost);
                    assert_eq!(path.len(), 7);
                    let want = brute(&p, d, cost);
                    let got = score(&p, &path, cost);
                    assert!((got - want).abs() < 1e-4, "d={d} cost={cost}: {got} vs best {want}, {path:?}");
                    // and the path keeps the rule it was asked to
                    let mut run = 1;
                    for t in 1..7 {
                        if path[t] == path[t - 1] {
                            run += 1;
                        } else {
                            assert!(run >= d, "a run of {run} < {d}: {path:?}");
                            run = 1;
                        }
                    }
                }
            }
        }
    }

    /// The choice on a labelled take: a take whose probabilities flicker to the wrong class for a frame every
    /// 10 frames chooses a decoding that absorbs the flicker (and scores better than the raw labels by the
    /// criterion); a take labelled cleanly keeps the raw labels (the first of equals); no take, no choice.
    #[test]
    fn the_choice_absorbs_flicker_and_keeps_the_raw_labels_when_they_are_right() {
        let truth: Vec<Option<usize>> = (0..300).map(|f| Some(usize::from(f >= 150))).collect();
        let rows = |flicker: bool| -> Vec<Vec<f32>> {
            truth
                .iter()
                .enumerate()
                .map(|(f, t)| {
                    let right = if flicker && f % 10 == 5 { 0.4 } else { 0.9 };
                    if t == &Some(0) {
                        vec![right, 1.0 - right]
                    } else {
                        vec![1.0 - right, right]
                    }
                })
                .collect()
        };
        let source: Vec<f64> = (0..300).map(|f| f as f64).collect();
        for flicker in [true, false] {
            let r = rows(flicker);
            let p = probs(&r.iter().map(|x| x.as_slice()).collect::<Vec<_>>());
            let judged = Judged { probabilities: &p, source: &source, fps: 30.0, truth: &truth };
            let c = choose(std::slice::from_ref(&judged)).unwrap();
            let raw = criterion(&crate::segment::labelling::score(&judged.labels(&Decoding::RAW, 0.5), &truth));
            if flicker {
                assert!(!c.decoding.is_raw(30.0), "{c:?}");
                assert!(c.criterion > raw + 10.0, "{c:?} against the raw labels' {raw}");
                assert_eq!((c.scores.edit, c.scores.frame_accuracy), (100.0, 1.0), "{c:?}");
            } else {
                assert_eq!((c.decoding, c.threshold, c.criterion), (Decoding::RAW, THRESHOLDS[0], 100.0), "{c:?}");
            }
        }
        assert!(choose(&[]).is_none());
    }

    #[test]
    fn file_labels_map_working_frames_and_call_weak_runs_unknown() {
        // 4 working frames at 30 Hz over 8 file frames at 60 Hz
        let p = probs(&[&[0.9, 0.1], &[0.9, 0.1], &[0.45, 0.55], &[0.4, 0.6]]);
        let source = [0.0, 2.0, 4.0, 6.0];
        let raw = file_labels(&p, &source, 30.0, 8, &Decoding::RAW, 0.5);
        assert_eq!(
            raw.iter().map(|x| x.0).collect::<Vec<_>>(),
            [Some(0), Some(0), Some(0), Some(0), Some(1), Some(1), Some(1), Some(1)]
        );
        // a raw frame below the threshold is unknown alone
        let raw = file_labels(&p, &source, 30.0, 8, &Decoding::RAW, 0.58);
        assert_eq!(raw[4].0, None);
        assert_eq!(raw[6].0, Some(1));
        // decoded: the run of class 1 (mean 0.575) is unknown as a whole below 0.58, kept at 0.5
        let runs2 = Decoding { min_duration_s: 2.0 / 30.0, switch_cost: 0.0 };
        let d = file_labels(&p, &source, 30.0, 8, &runs2, 0.58);
        assert_eq!(
            d.iter().map(|x| x.0).collect::<Vec<_>>(),
            [Some(0), Some(0), Some(0), Some(0), None, None, None, None]
        );
        let d = file_labels(&p, &source, 30.0, 8, &runs2, 0.5);
        assert_eq!(d[7], (Some(1), 0.6));
        assert!(file_labels(&probs(&[&[1.0]]), &[0.0], 30.0, 0, &runs2, 0.5).is_empty());
    }
}
