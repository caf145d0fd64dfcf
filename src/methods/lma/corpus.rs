//! The segments the Effort classifiers learn from, and their labels.
//!
//! Bouchard & Badler trained on 288 performances by LMA experts, "segmented using a hybrid
//! manual/kinematic technique where segment boundaries are manually selected from hand linear
//! velocity local minima". That corpus is not public, so here:
//!
//! * **segments**: per arm of every take, the spans between a local minimum of the hand's speed
//!   and the next or the one after (the kinematic half of their technique), between the shortest
//!   and longest segment length;
//! * **labels**, either
//!   - the computable Effort descriptors of [`super::effort`] (peak kinetic energy → Weight, peak
//!     acceleration → Time, directness → Space, mean jerk → Flow), each cut into three classes at
//!     its terciles over the whole corpus — *stand-in labels*, not an expert's judgement; or
//!   - a user's own file, `file,start_frame,end_frame,space,time,weight,flow` (frames of the
//!     file, 0-based, inclusive; values `indulging`, `neutral` or `condensing`), read by
//!     [`parse_labels`]; each row is learnt from the arm whose hand travels further in it.

use glam::DVec3;

use super::body::{upper_body, Side};
use super::effort::{element, terciles, EffortTables, Element, Factor};
use super::features::{Kinematics, Pool};
use super::search::smooth;
use crate::labels::same_file;
use crate::motion::Motion;

/// How the corpus is cut (frames at `fps`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CorpusConfig {
    pub fps: f64,
    pub min_len: usize,
    pub max_len: usize,
    /// The family's largest boundary shift: segments keep this many frames from the take's ends.
    pub max_shift: usize,
}

impl Default for CorpusConfig {
    /// The paper's: 30 Hz, 0.67–3.33 s, shifts of ±5 frames.
    fn default() -> Self {
        CorpusConfig { fps: 30.0, min_len: 20, max_len: 100, max_shift: 5 }
    }
}

/// One arm of one take.
pub struct Source {
    pub name: String,
    pub side: Side,
    pub pool: Pool,
}

/// A labelled segment `start..=end` (working frames) of a source; `classes` per factor index
/// into [`Element::ALL`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    pub source: usize,
    pub start: usize,
    pub end: usize,
    pub classes: [usize; 4],
}

/// Sources and labelled segments.
pub struct Corpus {
    pub config: CorpusConfig,
    pub sources: Vec<Source>,
    pub samples: Vec<Sample>,
    /// Where the labels came from, in words (kept in the model).
    pub origin: String,
    /// Stand-in labels: each sample's four descriptors (in [`Factor::ALL`] order), the quantities
    /// its classes are terciles of — so training can leave out the pool features that tell them.
    /// Empty for a user's labels.
    pub descriptors: Vec<[f64; 4]>,
}

/// The candidate segments of one hand: from each local minimum of its speed (Gaussian-smoothed,
/// σ = 0.1 s) to the next and the one after, when `min_len ≤ end − start ≤ max_len`, at least
/// `margin` frames from either end of the take.
pub fn candidate_segments(hand: &[DVec3], config: &CorpusConfig) -> Vec<(usize, usize)> {
    let speed = smooth(&Kinematics::speed(hand, config.fps), 0.1 * config.fps);
    let n = speed.len();
    let minima: Vec<usize> = (1..n.saturating_sub(1))
        .filter(|&t| speed[t] <= speed[t - 1] && speed[t] < speed[t + 1])
        .filter(|&t| t >= config.max_shift && t + config.max_shift < n)
        .collect();
    let mut out = Vec::new();
    for (k, &s) in minima.iter().enumerate() {
        for &e in minima.iter().skip(k + 1).take(2) {
            if (config.min_len..=config.max_len).contains(&(e - s)) {
                out.push((s, e));
            }
        }
    }
    out
}

fn sources_of(takes: &[&Motion], config: &CorpusConfig) -> Result<(Vec<Source>, Vec<Vec<DVec3>>), String> {
    let longest = config.max_len + 2 * config.max_shift + 1;
    let mut sources = Vec::new();
    let mut hands = Vec::new();
    for m in takes {
        let body = upper_body(m, config.fps).map_err(|e| format!("{}: {e}", m.name))?;
        for arm in &body.arms {
            sources.push(Source { name: m.name.clone(), side: arm.side, pool: Pool::of(arm, config.fps, longest) });
            hands.push(arm.hand().to_vec());
        }
    }
    Ok((sources, hands))
}

impl Corpus {
    /// Candidate segments of both arms of `takes`, labelled by descriptor terciles over them all.
    pub fn from_descriptors(takes: &[&Motion], config: CorpusConfig) -> Result<Corpus, String> {
        let (sources, hands) = sources_of(takes, &config)?;
        let mut spans = Vec::new();
        for (k, hand) in hands.iter().enumerate() {
            let tables = EffortTables::new(std::slice::from_ref(hand), config.fps);
            for (s, e) in candidate_segments(hand, &config) {
                spans.push((k, s, e, tables.descriptors(s, e).values()));
            }
        }
        let cuts: Vec<(f64, f64)> =
            (0..4).map(|f| terciles(&spans.iter().map(|x| x.3[f]).collect::<Vec<_>>()).unwrap_or((0.0, 0.0))).collect();
        let descriptors: Vec<[f64; 4]> = spans.iter().map(|x| x.3).collect();
        let samples = spans
            .iter()
            .map(|&(source, start, end, d)| Sample {
                source,
                start,
                end,
                classes: std::array::from_fn(|f| element(d[f], cuts[f]) as usize),
            })
            .collect::<Vec<_>>();
        if samples.is_empty() {
            return Err("no candidate segments: the takes are too short or too still to train on".into());
        }
        let names: Vec<&str> = takes.iter().map(|m| m.name.as_str()).collect();
        let origin = format!(
            "stand-in labels: terciles of computable Effort descriptors (peak kinetic energy, peak acceleration, \
             directness, mean jerk of the hand) over {} segments between hand-speed minima of {} takes ({}); \
             tercile cuts {}",
            samples.len(),
            names.len(),
            names.join(", "),
            Factor::ALL
                .iter()
                .zip(&cuts)
                .map(|(f, c)| format!("{} {:.3}/{:.3}", f.name(), c.0, c.1))
                .collect::<Vec<_>>()
                .join(", ")
        );
        Ok(Corpus { config, sources, samples, origin, descriptors })
    }

    /// The rows of a user's label file on `takes` (matched by file name).
    pub fn from_labels(takes: &[&Motion], labels: &[EffortLabel], config: CorpusConfig) -> Result<Corpus, String> {
        let (sources, hands) = sources_of(takes, &config)?;
        let mut samples = Vec::new();
        for l in labels {
            let take = takes
                .iter()
                .position(|m| same_file(&m.name, &l.file))
                .ok_or_else(|| format!("labels line {}: no loaded take is called `{}`", l.line, l.file))?;
            let motion = takes[take];
            let to_working = |f: usize| (f as f64 * config.fps / motion.fps).round() as usize;
            let n = hands[2 * take].len();
            let (start, end) = (to_working(l.start_frame), to_working(l.end_frame).min(n.saturating_sub(1)));
            if l.end_frame >= motion.frames() || end <= start + 1 {
                return Err(format!(
                    "labels line {}: frames {}..{} do not fit `{}` ({} frames)",
                    l.line,
                    l.start_frame,
                    l.end_frame,
                    motion.name,
                    motion.frames()
                ));
            }
            let path = |h: &[DVec3]| h[start..=end].windows(2).map(|w| w[0].distance(w[1])).sum::<f64>();
            let arm = if path(&hands[2 * take]) > path(&hands[2 * take + 1]) { 0 } else { 1 };
            samples.push(Sample { source: 2 * take + arm, start, end, classes: l.classes.map(|e| e as usize) });
        }
        if samples.is_empty() {
            return Err("the label file has no rows".into());
        }
        let origin = format!("{} user-labelled segments of {} takes", samples.len(), takes.len());
        Ok(Corpus { config, sources, samples, origin, descriptors: Vec::new() })
    }
}

/// One row of a user's Effort label file.
#[derive(Debug, Clone, PartialEq)]
pub struct EffortLabel {
    pub file: String,
    pub start_frame: usize,
    pub end_frame: usize,
    /// Space, Time, Weight, Flow.
    pub classes: [Element; 4],
    /// Line in the file (1-based).
    pub line: usize,
}

/// Reads `file,start_frame,end_frame,space,time,weight,flow` rows (a header line naming the
/// columns is required; frames 0-based inclusive file frames; [`crate::labels::read_rows`]); errors name `source`
/// and the line.
pub fn parse_labels(text: &str, source: &str) -> Result<Vec<EffortLabel>, String> {
    const FACTORS: [&str; 4] = ["space", "time", "weight", "flow"];
    let mut labels = Vec::new();
    for row in crate::labels::read_rows(text, source, &FACTORS, crate::labels::Span::Open)? {
        let mut classes = [Element::Neutral; 4];
        for (f, c) in classes.iter_mut().enumerate() {
            *c = Element::parse(&row.values[f]).ok_or_else(|| {
                format!(
                    "{source} line {}: {} `{}`: expected indulging, neutral or condensing",
                    row.line, FACTORS[f], row.values[f]
                )
            })?;
        }
        labels.push(EffortLabel {
            file: row.file,
            start_frame: row.start_frame,
            end_frame: row.end_frame,
            classes,
            line: row.line,
        });
    }
    Ok(labels)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn label_files_are_read_with_their_line_numbers() {
        let text =
            "file,start_frame,end_frame,space,time,weight,flow\n35_01.bvh, 0, 90, direct_typo,neutral,neutral,free\n";
        let err = parse_labels(text, "mine.csv").unwrap_err();
        assert!(err.contains("mine.csv line 2") && err.contains("space `direct_typo`"), "{err}");
        let text =
            "file,start_frame,end_frame,space,time,weight,flow\n35_01.bvh,0,90,Condensing,neutral,indulging,neutral\n";
        let rows = parse_labels(text, "mine.csv").unwrap();
        assert_eq!(rows[0].classes, [Element::Condensing, Element::Neutral, Element::Indulging, Element::Neutral]);
        assert_eq!((rows[0].start_frame, rows[0].end_frame, rows[0].line), (0, 90, 2));
        assert!(parse_labels("a,b\n", "x.csv").unwrap_err().contains("x.csv line 1: expected the header"));
        let reversed = "file,start_frame,end_frame,space,time,weight,flow\na,9,3,neutral,neutral,neutral,neutral\n";
        assert!(parse_labels(reversed, "x.csv").unwrap_err().contains("line 2: end_frame 3 is not after"));
    }

    #[test]
    fn candidates_run_between_speed_minima() {
        // a hand that strokes back and forth once a second: minima every 15 frames at 30 Hz
        let hand: Vec<DVec3> =
            (0..300).map(|t| DVec3::new((std::f64::consts::TAU * t as f64 / 30.0).sin(), 0.0, 0.0)).collect();
        let config = CorpusConfig::default();
        let spans = candidate_segments(&hand, &config);
        assert!(!spans.is_empty());
        for (s, e) in spans {
            assert!((20..=100).contains(&(e - s)) && s >= 5 && e + 5 < 300, "{s}..{e}");
            assert!((29..=31).contains(&(e - s)), "two half-strokes: {s}..{e}");
        }
    }
}
