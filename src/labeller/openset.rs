//! The open-set objective an unknown threshold is chosen on (issue 50; not in the papers).
//!
//! A labeller's unknown is for frames of a class it was never taught. Chosen on takes that hold no such class, any
//! rule that scores labels rewards never saying unknown. Chosen here on folds that leave a class out of the training
//! (each frame of that class is *unseen*: its right answer is `unknown`), the objective is the **open-set frame
//! accuracy**: the share of frames labelled right, where an unseen frame is right when called unknown and a taught
//! frame when given its own class. Every frame weighs the same, so a score that cannot tell unseen frames from taught
//! ones is best left unused (calling a taught frame unknown costs what calling an unseen one gains, and taught frames
//! are the more), and the objective never asks for more unknowns than the frames pay for. Beside it, the two rates the
//! issue's target is stated in: the share of unseen frames called unknown, and of taught ones.

use serde::{Deserialize, Serialize};

/// The open-set unknown a model holds and how it was chosen: frames whose score (the k-NN's windows' voted-class
/// ratio, `Knn::voted_ratios_going`) is above `ratio` are unknown.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OpenSetUnknown {
    pub ratio: f32,
    /// The leave-a-class-out folds it was chosen on (a class left out, a take holding it scored).
    pub folds: usize,
    /// Open-set frame accuracy on those folds at `ratio`, and without any unknown.
    pub accuracy: f32,
    pub never: f32,
}

/// The largest open-set ratio a model file or a run may hold: far beyond any frame of a take (a take's median is 1).
pub const MAX_RATIO: f32 = 1000.0;

impl OpenSetUnknown {
    /// Refuses what a file could hold but no choice makes: a ratio outside (0, [`MAX_RATIO`]], accuracies outside
    /// [0, 1].
    pub fn check(&self) -> Result<(), String> {
        if !(self.ratio > 0.0 && self.ratio <= MAX_RATIO) {
            return Err(format!("open-set unknown ratio {}: expected above 0, at most {MAX_RATIO}", self.ratio));
        }
        if ![self.accuracy, self.never].iter().all(|a| (0.0..=1.0).contains(a)) {
            return Err(format!(
                "open-set accuracies {} and {}: expected shares from 0 to 1",
                self.accuracy, self.never
            ));
        }
        Ok(())
    }
}

/// What [`choose_confirmed`] chose on a model's leave-a-class-out folds: the ratio (`f32::INFINITY`: never unknown),
/// the folds, the open-set frame accuracy there at the ratio and without any unknown, the ratio the objective picked
/// before it was confirmed, and that ratio's gain over never saying unknown — the mean over the scored takes with its
/// bootstrap 95 % interval.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OpenSetChoice {
    pub ratio: f32,
    pub folds: usize,
    pub accuracy: f64,
    pub never: f64,
    pub candidate: f32,
    pub gain: Option<(f64, f64, f64)>,
}

impl OpenSetChoice {
    /// What a model's header holds of it (`None`: never unknown).
    pub fn unknown(&self) -> Option<OpenSetUnknown> {
        self.ratio.is_finite().then_some(OpenSetUnknown {
            ratio: self.ratio,
            folds: self.folds,
            accuracy: self.accuracy as f32,
            never: self.never as f32,
        })
    }

    /// One sentence for a training's summary.
    pub fn describe(&self) -> String {
        let gain =
            self.gain.map_or(String::new(), |(m, lo, hi)| format!(", {m:+.3} [{lo:+.3}, {hi:+.3}] over its takes"));
        let how = if self.ratio.is_finite() {
            format!("frames farther than {:.2} from their class's training windows are unknown{gain}", self.ratio)
        } else if self.candidate.is_finite() {
            format!("no open-set unknown (the best ratio, {:.2}, gained not surely{gain})", self.candidate)
        } else {
            "no open-set unknown (never calling unknown did best)".to_string()
        };
        format!(
            " Open-set unknown chosen on {} folds leaving a class out: {how} (open-set frame accuracy {:.0} % there, \
             {:.0} % without).",
            self.folds,
            100.0 * self.accuracy,
            100.0 * self.never
        )
    }
}

/// The ratio [`choose_open_set`] picks on the frames of every take of `by_take` (each take's frames from the
/// leave-a-class-out folds that scored it), kept only when it is surely better than never saying unknown there: the
/// bootstrap 95 % interval, over the takes, of its gain in open-set frame accuracy lies above 0 (a change counts as
/// better only when the interval says so — here inside the training takes, so the rule is part of the nesting). `folds`
/// is the caller's to fill.
pub fn choose_confirmed(by_take: &[Vec<OpenSetFrame>]) -> OpenSetChoice {
    let all: Vec<OpenSetFrame> = by_take.iter().flatten().copied().collect();
    let candidate = choose_open_set(&all);
    let gains: Vec<f64> = by_take
        .iter()
        .filter(|t| !t.is_empty())
        .map(|t| open_set_scores(t, candidate).accuracy - open_set_scores(t, f32::INFINITY).accuracy)
        .collect();
    let gain = candidate.is_finite().then(|| crate::stats::bootstrap_mean(&gains, 2000, 50)).flatten();
    let ratio = if gain.is_some_and(|(_, lo, _)| lo > 0.0) { candidate } else { f32::INFINITY };
    OpenSetChoice {
        ratio,
        folds: 0,
        accuracy: open_set_scores(&all, ratio).accuracy,
        never: open_set_scores(&all, f32::INFINITY).accuracy,
        candidate,
        gain,
    }
}

/// One frame of a leave-a-class-out fold: how unlike the training it scores (higher: more likely unknown;
/// `f32::INFINITY`: unknown whatever the threshold — a frame the labeller already called unknown; NaN: never), whether
/// its class was left out, and, for a taught frame, whether the labeller gave it its class.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OpenSetFrame {
    pub score: f32,
    pub unseen: bool,
    pub right: bool,
}

/// What a threshold does on a set of frames: frames scoring above it are called unknown.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OpenSetScores {
    /// Open-set frame accuracy: unseen frames called unknown and taught frames given their class, over all frames.
    pub accuracy: f64,
    /// Share of the unseen frames called unknown.
    pub unseen_unknown: f64,
    /// Share of the taught frames called unknown.
    pub taught_unknown: f64,
    /// Share of the taught frames given their class.
    pub taught_right: f64,
}

/// The open-set scores of `threshold` on `frames` (a frame is unknown when its score is above the threshold, or
/// infinite; a threshold of `f32::INFINITY`: only those). Shares of an empty group are 0.
pub fn open_set_scores(frames: &[OpenSetFrame], threshold: f32) -> OpenSetScores {
    let (mut unseen, mut unseen_unknown, mut taught, mut taught_unknown, mut taught_right) = (0, 0, 0, 0, 0);
    for f in frames {
        let unknown = f.score > threshold || f.score == f32::INFINITY;
        if f.unseen {
            unseen += 1;
            unseen_unknown += usize::from(unknown);
        } else {
            taught += 1;
            taught_unknown += usize::from(unknown);
            taught_right += usize::from(!unknown && f.right);
        }
    }
    let share = |a: usize, b: usize| if b == 0 { 0.0 } else { a as f64 / b as f64 };
    OpenSetScores {
        accuracy: share(unseen_unknown + taught_right, unseen + taught),
        unseen_unknown: share(unseen_unknown, unseen),
        taught_unknown: share(taught_unknown, taught),
        taught_right: share(taught_right, taught),
    }
}

/// The threshold with the best open-set frame accuracy on `frames`: `f32::INFINITY` (never unknown) unless a finite
/// one does better; among equals the highest (the fewest unknowns). Candidates lie between consecutive distinct
/// scores, so the choice does not sit on a frame of the frames it was chosen on. Non-finite scores are never
/// thresholds (a frame scoring NaN is never unknown, one scoring infinity always).
pub fn choose_open_set(frames: &[OpenSetFrame]) -> f32 {
    let mut sorted: Vec<&OpenSetFrame> = frames.iter().filter(|f| f.score.is_finite()).collect();
    sorted.sort_by(|a, b| b.score.total_cmp(&a.score));
    // walking down from the highest score: each frame passed becomes unknown
    let always = |f: &&OpenSetFrame| f.score == f32::INFINITY;
    let mut right = frames.iter().filter(|f| if always(f) { f.unseen } else { !f.unseen && f.right }).count() as f64;
    let (mut best, mut best_right) = (f32::INFINITY, right);
    let mut i = 0;
    while i < sorted.len() {
        let s = sorted[i].score;
        while i < sorted.len() && sorted[i].score == s {
            let f = sorted[i];
            right += if f.unseen {
                1.0
            } else if f.right {
                -1.0
            } else {
                0.0
            };
            i += 1;
        }
        // every frame at s or above is unknown: the threshold lies below s, halfway to the next score
        if right > best_right + 1e-9 {
            best_right = right;
            best = match sorted.get(i) {
                Some(next) => next.score + 0.5 * (s - next.score),
                None => s - s.abs().max(1e-6) * 0.5,
            };
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(score: f32, unseen: bool, right: bool) -> OpenSetFrame {
        OpenSetFrame { score, unseen, right }
    }

    /// Unseen frames scoring above every taught one: the threshold falls between them, every unseen frame unknown and
    /// no taught one; the objective is then 1.
    #[test]
    fn a_score_that_separates_is_cut_between_the_unseen_and_the_taught() {
        let frames: Vec<_> = (0..10)
            .map(|i| frame(i as f32 / 10.0, false, true))
            .chain((0..4).map(|i| frame(2.0 + i as f32, true, false)))
            .collect();
        let t = choose_open_set(&frames);
        assert!(t > 0.9 && t < 2.0, "{t}");
        let s = open_set_scores(&frames, t);
        assert_eq!((s.accuracy, s.unseen_unknown, s.taught_unknown, s.taught_right), (1.0, 1.0, 0.0, 1.0));
        // never unknown: only the taught frames right
        let never = open_set_scores(&frames, f32::INFINITY);
        assert_eq!((never.accuracy, never.unseen_unknown), (10.0 / 14.0, 0.0));
    }

    /// A score that says nothing (unseen and taught frames interleaved alike): calling any frame unknown costs a taught
    /// frame for each unseen one gained, and taught frames are the more, so the threshold is never (a rule that fixes
    /// the taught frames' share, or the balanced accuracy, would call unknown here).
    #[test]
    fn a_score_that_cannot_tell_is_not_used() {
        let frames: Vec<_> = (0..40).map(|i| frame(i as f32, i % 4 == 0, true)).collect();
        assert_eq!(choose_open_set(&frames), f32::INFINITY);
    }

    /// Taught frames the labeller gets wrong cost nothing when called unknown: high-scoring wrong frames are cut along
    /// with the unseen ones, right ones are kept.
    #[test]
    fn wrong_taught_frames_are_free_to_call_unknown() {
        let frames = vec![
            frame(0.1, false, true),
            frame(0.2, false, true),
            frame(0.3, false, true),
            frame(0.8, true, false),
            frame(0.85, true, false),
            frame(0.9, false, false),
            frame(1.0, false, true),
            frame(1.1, true, false),
        ];
        // below 0.8: +3 unseen, −1 right taught (1.0), the wrong one (0.9) free → 3 + 3 = 6 of 8 right; never: 4 of 8
        let t = choose_open_set(&frames);
        assert!(t > 0.3 && t < 0.8, "{t}");
        let s = open_set_scores(&frames, t);
        assert!((s.accuracy - 6.0 / 8.0).abs() < 1e-12, "{s:?}");
        assert_eq!(s.unseen_unknown, 1.0);
        assert!((s.taught_unknown - 2.0 / 5.0).abs() < 1e-12);
        assert!((s.taught_right - 3.0 / 5.0).abs() < 1e-12);
        // equals: the highest threshold (fewest unknowns) — cutting below 1.0 and below 0.4 both make 2 of 3 right
        let tie = vec![frame(1.0, true, false), frame(0.5, false, true), frame(0.4, true, false)];
        let t = choose_open_set(&tie);
        assert!(t > 0.5 && t < 1.0, "{t}");
    }

    /// A model file's open-set unknown is refused when no choice makes it.
    #[test]
    fn a_files_open_set_unknown_is_checked() {
        let good = OpenSetUnknown { ratio: 1.7, folds: 3, accuracy: 0.8, never: 0.7 };
        assert!(good.check().is_ok());
        for ratio in [0.0, -1.0, f32::NAN, f32::INFINITY, MAX_RATIO * 2.0] {
            let e = OpenSetUnknown { ratio, ..good }.check().unwrap_err();
            assert!(e.contains("open-set unknown ratio"), "{e}");
        }
        assert!(OpenSetUnknown { accuracy: 1.5, ..good }.check().is_err());
        assert!(OpenSetUnknown { never: f32::NAN, ..good }.check().is_err());
        // what a training holds of its choice: never unknown is no field at all
        let never = OpenSetChoice {
            ratio: f32::INFINITY,
            folds: 4,
            accuracy: 0.7,
            never: 0.7,
            candidate: f32::INFINITY,
            gain: None,
        };
        assert_eq!(never.unknown(), None);
        assert!(never.describe().contains("no open-set unknown"), "{}", never.describe());
        let chosen = OpenSetChoice {
            candidate: 1.7,
            gain: Some((0.1, 0.05, 0.15)),
            ratio: 1.7,
            folds: 3,
            accuracy: 0.8,
            ..never
        };
        assert_eq!(chosen.unknown(), Some(good));
        assert!(chosen.describe().contains("1.70"), "{}", chosen.describe());
    }

    /// The objective's ratio is kept only when every way of resampling the takes says it gains: two takes gaining
    /// keep it; one take gaining and one losing as much leave no open-set unknown, the candidate and its gain said.
    #[test]
    fn a_ratio_is_kept_only_when_the_takes_say_it_gains() {
        // a take whose unseen frames score above its taught ones
        let separable = |shift: f32| -> Vec<OpenSetFrame> {
            (0..10)
                .map(|i| frame(shift + i as f32 / 10.0, false, true))
                .chain((0..4).map(|i| frame(shift + 2.0 + i as f32, true, false)))
                .collect()
        };
        let c = choose_confirmed(&[separable(0.0), separable(0.1)]);
        assert!(c.ratio.is_finite() && c.ratio == c.candidate, "{c:?}");
        assert!(c.gain.unwrap().1 > 0.0 && c.accuracy > c.never, "{c:?}");
        // the second take's taught frames score where the first take's unseen ones do: the pooled cut between them
        // gains on one take and loses on the other
        let mut against: Vec<OpenSetFrame> = (0..4).map(|i| frame(2.0 + i as f32, false, true)).collect();
        against.extend((0..10).map(|i| frame(i as f32 / 10.0, true, false)));
        let c = choose_confirmed(&[separable(0.0), separable(0.0), against]);
        assert!(c.candidate.is_finite() && c.ratio.is_infinite(), "{c:?}");
        assert!(c.gain.unwrap().1 <= 0.0);
        assert_eq!(c.accuracy, c.never);
        assert!(c.describe().contains("gained not surely"), "{}", c.describe());
    }

    /// NaN scores are never thresholds and never unknown; no frames: never; the lowest score as a cut stays finite.
    #[test]
    fn odd_scores_are_handled() {
        assert_eq!(choose_open_set(&[]), f32::INFINITY);
        let frames = vec![frame(f32::NAN, true, false), frame(0.0, true, false), frame(-1.0, true, false)];
        let t = choose_open_set(&frames);
        assert!(t.is_finite() && t < -1.0, "{t}");
        assert_eq!(open_set_scores(&frames, t).unseen_unknown, 2.0 / 3.0);
        // an infinite score is unknown at every threshold, never too: an unseen one right, a taught one wrong
        let frames =
            vec![frame(f32::INFINITY, true, false), frame(f32::INFINITY, false, false), frame(0.5, false, true)];
        assert_eq!(choose_open_set(&frames), f32::INFINITY);
        let never = open_set_scores(&frames, f32::INFINITY);
        assert_eq!((never.unseen_unknown, never.taught_unknown, never.accuracy), (1.0, 0.5, 2.0 / 3.0));
    }
}
