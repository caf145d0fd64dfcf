//! The consensus of several methods' segmentations of one take: the boundaries where the methods agree, each with
//! how many (distinct) methods agree and which (issue 26, "a consensus row").
//!
//! * **What a method contributes**: the boundaries it is scored on ([`scored_boundaries`]) — for a method with
//!   actions the cuts between consecutive segments of its tiling (transitions split at their middle, as
//!   [`super::metrics::evaluate`] reads it), for a gesture method (velocity, KCS, LMA) every start of its segments
//!   and every frame after an end. Segmentations of the same method (the same `method` name) count as one method:
//!   their boundaries are pooled.
//! * **Grouping**: the boundaries of every method, in time order, are grouped from the earliest on: a group starts
//!   at the earliest boundary not yet grouped and takes, of every other method, its earliest ungrouped boundary at
//!   most `tolerance_s` seconds after the group's first (so every two boundaries of a group are within the
//!   tolerance, the edge included), **one boundary per method**: a method's second boundary inside the window stays
//!   for a later group, so a method with two boundaries close together is counted once.
//! * **The group's frame** is the median of its boundaries' frames (of an even count, the mean of the middle two,
//!   rounded down); its **agreement** is its number of methods. Groups agreed by fewer than `min_methods` methods
//!   are left out.
//! * **Bad input** is an error, never a panic: no segmentation, a segmentation that breaks the schema, takes of
//!   different lengths or frame rates, a tolerance that is not a finite non-negative number, a minimum of 0.
//!   A minimum above the number of methods is no error: nothing agrees that much.
//!
//! [`Consensus::to_segmentation`] writes the boundaries as a tiling of the take (method `consensus`, each part its own
//! segment), so that the scoreboard (`make accuracy`) scores it as it scores the methods; the page's "Consensus" row
//! (`src/app/consensus/row.rs`) draws the boundaries and moves an accepted one into "my labels".

use serde::Serialize;

use super::metrics::scored_boundaries;
use super::{Level, SchemaError, Segment, Segmentation};

/// The consensus's settings.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ConsensusOptions {
    /// Boundaries of different methods at most this far apart (seconds) may agree.
    pub tolerance_s: f64,
    /// A boundary is kept when at least this many methods agree on it.
    pub min_methods: usize,
}

/// The default tolerance, with [`DEFAULT_MIN_METHODS`]: the setting of the scoreboard's grid (tolerance 0.25, 0.5, 1
/// or 2 s × 2, 3 or 4 methods) best on the five unsupervised methods' defaults over the five labelled takes (`make
/// accuracy` prints every setting: 0.5 s and 3 methods, F1@1s 0.64 and covering 0.67, where 1 s and 2 methods, the
/// first guess, had 0.31 and 0.43 with three times as many boundaries).
pub const DEFAULT_TOLERANCE_S: f64 = 0.5;
/// The default minimum agreement (see [`DEFAULT_TOLERANCE_S`]).
pub const DEFAULT_MIN_METHODS: usize = 3;

impl Default for ConsensusOptions {
    fn default() -> Self {
        ConsensusOptions { tolerance_s: DEFAULT_TOLERANCE_S, min_methods: DEFAULT_MIN_METHODS }
    }
}

/// One boundary the methods agree on: cut `frame` (between frames `frame - 1` and `frame`), the methods that put a
/// boundary near it (in the order the segmentations were given) and where each put it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Agreed {
    pub frame: usize,
    pub methods: Vec<String>,
    /// Each method's own boundary, in the order of `methods`.
    pub frames: Vec<usize>,
}

impl Agreed {
    /// How many methods agree.
    pub fn count(&self) -> usize {
        self.methods.len()
    }
}

/// The boundaries the methods agree on, in time order.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Consensus {
    pub frames: usize,
    pub fps: f64,
    /// Every method that contributed (distinct, in the order given): the "of" of "3 of 5".
    pub methods: Vec<String>,
    pub options: ConsensusOptions,
    pub boundaries: Vec<Agreed>,
}

/// Why there is no consensus.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ConsensusError {
    #[error("no segmentation to agree on: run at least one method")]
    Empty,
    #[error("{method}: {source}")]
    Schema { method: String, source: SchemaError },
    #[error("{method} has {frames} frames but {first} has {expected}: are they segmentations of the same take?")]
    Frames { method: String, frames: usize, first: String, expected: usize },
    #[error(
        "{method} is at {fps} frames per second but {first} at {expected}: are they segmentations of the same take?"
    )]
    Fps { method: String, fps: f64, first: String, expected: f64 },
    #[error("the tolerance must be a finite number of seconds, 0 or more (got {0})")]
    Tolerance(f64),
    #[error("the minimum agreement must be at least 1 method")]
    NoMinimum,
}

/// The consensus of `segmentations` (one take, any methods) under `options`.
pub fn consensus(segmentations: &[&Segmentation], options: ConsensusOptions) -> Result<Consensus, ConsensusError> {
    if !(options.tolerance_s.is_finite() && options.tolerance_s >= 0.0) {
        return Err(ConsensusError::Tolerance(options.tolerance_s));
    }
    if options.min_methods == 0 {
        return Err(ConsensusError::NoMinimum);
    }
    let first = *segmentations.first().ok_or(ConsensusError::Empty)?;
    for s in segmentations {
        s.validate().map_err(|source| ConsensusError::Schema { method: s.method.clone(), source })?;
        if s.frames != first.frames {
            return Err(ConsensusError::Frames {
                method: s.method.clone(),
                frames: s.frames,
                first: first.method.clone(),
                expected: first.frames,
            });
        }
        if (s.fps - first.fps).abs() > 1e-9 * first.fps {
            return Err(ConsensusError::Fps {
                method: s.method.clone(),
                fps: s.fps,
                first: first.method.clone(),
                expected: first.fps,
            });
        }
    }
    // every method's boundaries, pooled per distinct method name
    let mut methods: Vec<String> = Vec::new();
    let mut marks: Vec<(usize, usize)> = Vec::new(); // (frame, method index)
    for s in segmentations {
        let m = methods.iter().position(|n| *n == s.method).unwrap_or_else(|| {
            methods.push(s.method.clone());
            methods.len() - 1
        });
        marks.extend(scored_boundaries(s).into_iter().map(|f| (f, m)));
    }
    marks.sort_unstable();
    marks.dedup();
    let tolerance = options.tolerance_s * first.fps;
    let mut taken = vec![false; marks.len()];
    let mut boundaries = Vec::new();
    for i in 0..marks.len() {
        if taken[i] {
            continue;
        }
        // the group of marks[i]: of every method, its earliest free boundary within the tolerance of this one
        let mut group: Vec<usize> = vec![i];
        taken[i] = true;
        for j in i + 1..marks.len() {
            if (marks[j].0 - marks[i].0) as f64 > tolerance {
                break;
            }
            if !taken[j] && !group.iter().any(|&g| marks[g].1 == marks[j].1) {
                taken[j] = true;
                group.push(j);
            }
        }
        if group.len() < options.min_methods {
            continue;
        }
        let mut at: Vec<usize> = group.iter().map(|&g| marks[g].0).collect();
        at.sort_unstable();
        let n = at.len();
        let frame = if n % 2 == 1 { at[n / 2] } else { (at[n / 2 - 1] + at[n / 2]) / 2 };
        // the methods in the order they were given
        let mut members: Vec<(usize, usize)> = group.iter().map(|&g| (marks[g].1, marks[g].0)).collect();
        members.sort_unstable();
        boundaries.push(Agreed {
            frame,
            methods: members.iter().map(|&(m, _)| methods[m].clone()).collect(),
            frames: members.iter().map(|&(_, f)| f).collect(),
        });
    }
    boundaries.sort_by_key(|b| b.frame);
    Ok(Consensus { frames: first.frames, fps: first.fps, methods, options, boundaries })
}

impl Consensus {
    /// The agreed boundaries as a segmentation of `file`: the take cut at them into action segments `part 1`,
    /// `part 2`… (each its own class, as the scoreboard's oracle-K parts), method `consensus`, the settings and every
    /// boundary's methods in `params`.
    pub fn to_segmentation(&self, file: &str) -> Segmentation {
        let mut cuts: Vec<usize> =
            self.boundaries.iter().map(|b| b.frame).filter(|&f| f > 0 && f < self.frames).collect();
        cuts.dedup();
        let starts = std::iter::once(0).chain(cuts.iter().copied());
        let ends = cuts.iter().map(|&c| c - 1).chain(std::iter::once(self.frames.saturating_sub(1)));
        let segments = if self.frames == 0 {
            Vec::new()
        } else {
            starts
                .zip(ends)
                .enumerate()
                .map(|(i, (start, end))| Segment {
                    start,
                    end,
                    label: format!("part {}", i + 1),
                    level: Level::Action,
                    cluster: None,
                    score: None,
                    mirror_of: None,
                    effort: None,
                })
                .collect()
        };
        Segmentation {
            file: file.to_string(),
            fps: self.fps,
            frames: self.frames,
            method: "consensus".into(),
            params: serde_json::json!({
                "tolerance_s": self.options.tolerance_s,
                "min_methods": self.options.min_methods,
                "methods": self.methods,
                "boundaries": self.boundaries,
            }),
            segments,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn segment(start: usize, end: usize, level: Level) -> Segment {
        Segment {
            start,
            end,
            label: String::new(),
            level,
            cluster: Some(0),
            score: None,
            mirror_of: None,
            effort: None,
        }
    }

    /// A method's tiling of 100 frames at 10 fps with boundaries at `cuts` (actions).
    fn tiling(method: &str, cuts: &[usize]) -> Segmentation {
        let mut edges = vec![0];
        edges.extend_from_slice(cuts);
        edges.push(100);
        Segmentation {
            file: "t.bvh".into(),
            fps: 10.0,
            frames: 100,
            method: method.into(),
            params: serde_json::Value::Null,
            segments: edges.windows(2).map(|w| segment(w[0], w[1] - 1, Level::Action)).collect(),
        }
    }

    /// A gesture method's primitives as given.
    fn gestures(method: &str, spans: &[(usize, usize)]) -> Segmentation {
        Segmentation {
            segments: spans.iter().map(|&(a, b)| segment(a, b, Level::Primitive)).collect(),
            ..tiling(method, &[])
        }
    }

    fn options(tolerance_s: f64, min_methods: usize) -> ConsensusOptions {
        ConsensusOptions { tolerance_s, min_methods }
    }

    fn summary(c: &Consensus) -> Vec<(usize, Vec<&str>)> {
        c.boundaries.iter().map(|b| (b.frame, b.methods.iter().map(String::as_str).collect())).collect()
    }

    #[test]
    fn groups_boundaries_within_the_tolerance_at_their_median() {
        // tolerance 0.5 s at 10 fps: 5 frames
        let a = tiling("a", &[20, 60]);
        let b = tiling("b", &[22, 80]);
        let c = tiling("c", &[24, 61]);
        let got = consensus(&[&a, &b, &c], options(0.5, 2)).unwrap();
        assert_eq!(got.methods, ["a", "b", "c"]);
        // 20, 22, 24: median 22, all three; 60, 61: mean of the two, rounded down; 80 alone is left out
        assert_eq!(summary(&got), [(22, vec!["a", "b", "c"]), (60, vec!["a", "c"])]);
        assert_eq!(got.boundaries[0].frames, [20, 22, 24]);
        assert_eq!(got.boundaries[0].count(), 3);
        // with a minimum of 1, the lone boundary is kept too, agreed by one
        let all = consensus(&[&a, &b, &c], options(0.5, 1)).unwrap();
        assert_eq!(summary(&all), [(22, vec!["a", "b", "c"]), (60, vec!["a", "c"]), (80, vec!["b"])]);
    }

    #[test]
    fn the_tolerance_includes_its_edge_and_not_a_frame_more() {
        let a = tiling("a", &[30]);
        let at_edge = tiling("b", &[35]);
        let past = tiling("b", &[36]);
        assert_eq!(summary(&consensus(&[&a, &at_edge], options(0.5, 2)).unwrap()), [(32, vec!["a", "b"])]);
        assert!(consensus(&[&a, &past], options(0.5, 2)).unwrap().boundaries.is_empty());
        // a group spans at most the tolerance from its first boundary: 30, 34 agree, 38 starts the next group
        let c = tiling("c", &[38]);
        let b = tiling("b", &[34]);
        assert_eq!(
            summary(&consensus(&[&a, &b, &c], options(0.5, 1)).unwrap()),
            [(32, vec!["a", "b"]), (38, vec!["c"])]
        );
        // a tolerance of 0: only the same frame agrees
        let same = tiling("b", &[30]);
        assert_eq!(summary(&consensus(&[&a, &same, &b], options(0.0, 2)).unwrap()), [(30, vec!["a", "b"])]);
    }

    #[test]
    fn a_method_with_two_boundaries_close_together_is_counted_once() {
        // a gesture method: a stroke 40..=42 gives boundaries 40 and 43, both near the tiling's 41
        let a = gestures("lma", &[(40, 42)]);
        let b = tiling("sssm", &[41]);
        let got = consensus(&[&a, &b], options(0.5, 1)).unwrap();
        // 40 (lma) and 41 (sssm) agree; lma's 43 is a group of its own, never a second vote
        assert_eq!(summary(&got), [(40, vec!["lma", "sssm"]), (43, vec!["lma"])]);
        assert!(got.boundaries.iter().all(|b| b.count() <= 2));
        // two segmentations of one method (a rerun) are one method, their boundaries pooled: 2 of 2, not 3
        let again = tiling("sssm", &[41, 70]);
        let pooled = consensus(&[&a, &b, &again], options(0.5, 2)).unwrap();
        assert_eq!(pooled.methods, ["lma", "sssm"]);
        assert_eq!(summary(&pooled), [(40, vec!["lma", "sssm"])]);
    }

    #[test]
    fn the_minimum_agreement_filters_groups() {
        let a = tiling("a", &[10, 50, 90]);
        let b = tiling("b", &[11, 50]);
        let c = tiling("c", &[12]);
        let counts = |min| {
            consensus(&[&a, &b, &c], options(0.5, min))
                .unwrap()
                .boundaries
                .iter()
                .map(|x| (x.frame, x.count()))
                .collect::<Vec<_>>()
        };
        assert_eq!(counts(1), [(11, 3), (50, 2), (90, 1)]);
        assert_eq!(counts(2), [(11, 3), (50, 2)]);
        assert_eq!(counts(3), [(11, 3)]);
        // more than there are methods: nothing agrees that much, and that is no error
        assert_eq!(counts(4), []);
    }

    #[test]
    fn actions_are_read_as_a_tiling_with_transitions_split_in_the_middle() {
        // actions 0..=29 and 41..=99 with a transition 30..=40 between them: one boundary, at the transition's middle
        let mut a = tiling("sssm", &[]);
        a.segments =
            vec![segment(0, 29, Level::Action), segment(30, 40, Level::Transition), segment(41, 99, Level::Action)];
        let b = tiling("pca", &[35]);
        let got = consensus(&[&a, &b], options(0.0, 2)).unwrap();
        assert_eq!(summary(&got), [(35, vec!["sssm", "pca"])]);
    }

    #[test]
    fn bad_input_is_an_error_saying_what() {
        let a = tiling("a", &[20]);
        let mut short = tiling("b", &[20]);
        short.frames = 90;
        short.segments.last_mut().unwrap().end = 89;
        let e = consensus(&[&a, &short], ConsensusOptions::default()).unwrap_err();
        assert!(matches!(e, ConsensusError::Frames { frames: 90, expected: 100, .. }), "{e:?}");
        assert!(e.to_string().contains("same take"), "{e}");
        let mut slow = tiling("b", &[20]);
        slow.fps = 30.0;
        assert!(matches!(consensus(&[&a, &slow], ConsensusOptions::default()), Err(ConsensusError::Fps { .. })));
        let mut broken = tiling("b", &[20]);
        broken.segments[0].end = 100;
        assert!(matches!(consensus(&[&a, &broken], ConsensusOptions::default()), Err(ConsensusError::Schema { .. })));
        assert_eq!(consensus(&[], ConsensusOptions::default()), Err(ConsensusError::Empty));
        for bad in [f64::NAN, -0.5, f64::INFINITY] {
            assert!(matches!(consensus(&[&a], options(bad, 2)), Err(ConsensusError::Tolerance(_))));
        }
        assert_eq!(consensus(&[&a], options(0.5, 0)), Err(ConsensusError::NoMinimum));
    }

    /// A method's segmentation for the property below: a tiling cut at `cuts` (actions), or primitives at `spans`
    /// (gaps and overlaps as they come), of `frames` frames at `fps`.
    fn generated(method: &str, frames: usize, fps: f64, tiling: bool, marks: &[(usize, usize)]) -> Segmentation {
        let segments = if tiling {
            let mut cuts: Vec<usize> = marks.iter().map(|&(a, _)| a % frames).filter(|&c| c > 0).collect();
            cuts.sort_unstable();
            cuts.dedup();
            let starts = std::iter::once(0).chain(cuts.iter().copied());
            let ends = cuts.iter().map(|&c| c - 1).chain(std::iter::once(frames - 1));
            starts.zip(ends).map(|(a, b)| segment(a, b, Level::Action)).collect()
        } else {
            marks
                .iter()
                .map(|&(a, len)| {
                    let start = a % frames;
                    segment(start, (start + len).min(frames - 1), Level::Primitive)
                })
                .collect()
        };
        Segmentation {
            file: "t.bvh".into(),
            fps,
            frames,
            method: method.into(),
            params: serde_json::Value::Null,
            segments,
        }
    }

    proptest::proptest! {
        /// On any valid segmentations: no error, and every agreed boundary is what the module says — its methods
        /// distinct and at least the minimum, its own boundaries within the tolerance of each other and each a
        /// boundary of its method, its frame their median, and no method's boundary in two groups.
        #[test]
        fn every_agreed_boundary_keeps_the_rules(
            frames in 2usize..400,
            fps in proptest::sample::select(vec![10.0, 30.0, 120.0]),
            tolerance_s in 0.0f64..2.0,
            min_methods in 1usize..5,
            methods in proptest::collection::vec(
                (0usize..4, proptest::bool::ANY, proptest::collection::vec((0usize..1000, 0usize..60), 0..12)),
                1..6,
            ),
        ) {
            let names = ["a", "b", "c", "d"];
            let segs: Vec<Segmentation> = methods
                .iter()
                .map(|(n, tiling, marks)| generated(names[*n], frames, fps, *tiling, marks))
                .collect();
            let refs: Vec<&Segmentation> = segs.iter().collect();
            let options = ConsensusOptions { tolerance_s, min_methods };
            let c = consensus(&refs, options).unwrap();
            // every method's own boundaries, pooled by name
            let own = |m: &str| -> Vec<usize> {
                let mut all: Vec<usize> = segs.iter().filter(|s| s.method == m).flat_map(scored_boundaries).collect();
                all.sort_unstable();
                all
            };
            let mut used: Vec<(String, usize)> = Vec::new();
            let mut last = 0;
            for b in &c.boundaries {
                proptest::prop_assert!(b.frame >= last, "sorted");
                last = b.frame;
                proptest::prop_assert!(b.count() >= min_methods && b.count() <= c.methods.len());
                let mut distinct = b.methods.clone();
                distinct.sort();
                distinct.dedup();
                proptest::prop_assert_eq!(distinct.len(), b.count(), "one boundary per method");
                let (lo, hi) = (*b.frames.iter().min().unwrap(), *b.frames.iter().max().unwrap());
                proptest::prop_assert!((hi - lo) as f64 <= tolerance_s * fps + 1e-9, "within the tolerance");
                proptest::prop_assert!(lo <= b.frame && b.frame <= hi && b.frame > 0 && b.frame < frames);
                for (m, f) in b.methods.iter().zip(&b.frames) {
                    proptest::prop_assert!(own(m).binary_search(f).is_ok(), "{m}'s own boundary {f}");
                    proptest::prop_assert!(!used.contains(&(m.clone(), *f)), "{m}'s {f} in one group only");
                    used.push((m.clone(), *f));
                }
            }
        }
    }

    #[test]
    fn as_a_segmentation_it_tiles_the_take_at_the_agreed_boundaries() {
        let a = tiling("a", &[20, 60]);
        let b = tiling("b", &[22, 60]);
        let c = consensus(&[&a, &b], options(0.5, 2)).unwrap();
        let seg = c.to_segmentation("t.bvh");
        seg.validate().unwrap();
        let parts: Vec<(usize, usize)> = seg.segments.iter().map(|s| (s.start, s.end)).collect();
        assert_eq!(parts, [(0, 20), (21, 59), (60, 99)]);
        assert_eq!(scored_boundaries(&seg), [21, 60]);
        assert_eq!(seg.params["boundaries"][0]["methods"], serde_json::json!(["a", "b"]));
        // nothing agreed: one part, the whole take
        let none = consensus(&[&a, &b], options(0.5, 3)).unwrap().to_segmentation("t.bvh");
        assert_eq!(none.segments.len(), 1);
        assert_eq!((none.segments[0].start, none.segments[0].end), (0, 99));
    }
}
