//! The Effort bars under every timeline row (the paper's conclusion, §6: LMA as a semantic layer
//! over segments): what each segment's four bars show and say, which segments lie outside the
//! lengths the classifiers learnt, and the key a row's annotation is kept under so that drawing
//! the row again never asks the worker twice. The page (`app::effort`) only draws this.

use std::hash::{Hash, Hasher};

use crate::method::{Annotated, Annotations};
use crate::segment::palette::effort_colour;
use crate::segment::Effort;

/// The four factors in the order the bars are drawn (top to bottom): name, indulging element,
/// condensing element.
pub const FACTORS: [(&str, &str, &str); 4] = [
    ("Space", "indirect", "direct"),
    ("Time", "sustained", "sudden"),
    ("Weight", "light", "strong"),
    ("Flow", "free", "bound"),
];

/// A value this far from 0 (either way) reads as its element; nearer, as neutral (the family's
/// three classes split [−1, 1] in thirds).
pub const ELEMENT_AT: f64 = 1.0 / 3.0;

/// The values of `e` in the order of [`FACTORS`].
pub fn values(e: &Effort) -> [f64; 4] {
    [e.space, e.time, e.weight, e.flow]
}

/// The element word of factor `k` ([`FACTORS`]) at value `v`: its indulging or condensing element,
/// or `neutral` between them.
pub fn element(k: usize, v: f64) -> &'static str {
    let (_, indulging, condensing) = FACTORS[k.min(3)];
    if v <= -ELEMENT_AT {
        indulging
    } else if v >= ELEMENT_AT {
        condensing
    } else {
        "neutral"
    }
}

/// The CSS colour of an Effort value: LMA's picture's ([`effort_colour`]).
pub fn css_colour(v: f64) -> String {
    let [r, g, b] = effort_colour(v);
    format!("rgb({r}, {g}, {b})")
}

/// How a segment's length stands to the lengths the classifiers learnt.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Fit {
    /// Within the learnt lengths.
    Learnt,
    /// Shorter or longer than them: its Effort is an extrapolation.
    Shorter {
        min_s: f64,
    },
    Longer {
        max_s: f64,
    },
}

impl Fit {
    /// Where a segment of `seconds` stands to `learnt` ([shortest, longest] seconds; `None`: the
    /// annotator gave none, so every length counts as learnt). A thousandth of a second of slack
    /// either way: frame counts rounded to seconds.
    pub fn of(seconds: f64, learnt: Option<[f64; 2]>) -> Fit {
        match learnt {
            Some([lo, _]) if seconds < lo - 1e-3 => Fit::Shorter { min_s: lo },
            Some([_, hi]) if seconds > hi + 1e-3 => Fit::Longer { max_s: hi },
            _ => Fit::Learnt,
        }
    }

    pub fn extrapolated(self) -> bool {
        self != Fit::Learnt
    }
}

/// The length in seconds of frames `start..=end` at `fps`.
pub fn seconds(start: usize, end: usize, fps: f64) -> f64 {
    (end + 1).saturating_sub(start) as f64 / fps.max(f64::MIN_POSITIVE)
}

/// A value as the bars' text writes it: two decimals, a true minus sign.
fn number(v: f64) -> String {
    let text = format!("{:.2}", v.abs());
    if v < 0.0 && text != "0.00" {
        format!("−{text}")
    } else {
        text
    }
}

/// What a segment's bars say (tooltip and accessible name): "Space direct 0.42 · Time sudden 0.70 ·
/// Weight neutral −0.12 · Flow free −0.51", then its length when it is outside the learnt lengths
/// ("· 4.20 s, longer than the 3.33 s the classifiers learnt: extrapolated").
pub fn text(e: &Effort, seconds: f64, fit: Fit) -> String {
    let mut out: Vec<String> = values(e)
        .iter()
        .enumerate()
        .map(|(k, &v)| format!("{} {} {}", FACTORS[k].0, element(k, v), number(v)))
        .collect();
    match fit {
        Fit::Learnt => {}
        Fit::Shorter { min_s } => {
            out.push(format!("{seconds:.2} s, shorter than the {min_s:.2} s the classifiers learnt: extrapolated"))
        }
        Fit::Longer { max_s } => {
            out.push(format!("{seconds:.2} s, longer than the {max_s:.2} s the classifiers learnt: extrapolated"))
        }
    }
    out.join(" · ")
}

/// One segment's bars as the page draws them.
#[derive(Debug, Clone, PartialEq)]
pub struct Bars {
    pub start: usize,
    pub end: usize,
    /// The four values and their CSS colours ([`FACTORS`] order); `None`: no Effort (see `text`).
    pub values: Option<[(f64, String); 4]>,
    /// Outside the learnt lengths: drawn hatched.
    pub extrapolated: bool,
    /// The tooltip and accessible name.
    pub text: String,
}

/// The bars of a row whose segments are `spans` (file frames, inclusive, at `fps`) from their
/// annotations (one per span, in order); a span without one is said so.
pub fn bars(spans: &[(usize, usize)], annotations: &Annotations, fps: f64) -> Vec<Bars> {
    spans
        .iter()
        .enumerate()
        .map(|(i, &(start, end))| {
            let s = seconds(start, end, fps);
            let fit = Fit::of(s, annotations.learnt_s);
            match annotations.segments.get(i) {
                Some(Annotated { effort: Some(e), .. }) => Bars {
                    start,
                    end,
                    values: Some(std::array::from_fn(|k| (values(e)[k], css_colour(values(e)[k])))),
                    extrapolated: fit.extrapolated(),
                    text: text(e, s, fit),
                },
                Some(Annotated { effort: None, why }) => Bars {
                    start,
                    end,
                    values: None,
                    extrapolated: false,
                    text: format!("no Effort: {}", why.as_deref().unwrap_or("the classifiers could not read it")),
                },
                None => Bars { start, end, values: None, extrapolated: false, text: "no Effort".into() },
            }
        })
        .collect()
}

/// The key a row's annotation is kept under: the annotating method, the parameters it reads and
/// the row's segments — the same segments asked again (a row drawn again, the window moved, another
/// row with the same segments) find it; any change of a boundary, of the family, or of the take
/// (`take`) asks again.
pub fn cache_key(take: u32, method: &str, params: &serde_json::Value, spans: &[(usize, usize)]) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    take.hash(&mut h);
    method.hash(&mut h);
    params.to_string().hash(&mut h);
    spans.hash(&mut h);
    h.finish()
}

/// Fills the `effort` of each segment of `segmentation` that has none (a method's own, LMA's, are
/// kept) from `known` (a segment's first and last frame → its Effort, what the bars under the rows
/// computed); returns how many were filled. What a row's JSON export carries.
pub fn fill(
    segmentation: &mut crate::segment::Segmentation,
    known: &std::collections::HashMap<(usize, usize), Effort>,
) -> usize {
    let mut filled = 0;
    for s in segmentation.segments.iter_mut().filter(|s| s.effort.is_none()) {
        if let Some(e) = known.get(&(s.start, s.end)) {
            s.effort = Some(*e);
            filled += 1;
        }
    }
    filled
}

/// The legend under the timeline's head: each factor from its indulging to its condensing element.
pub fn legend() -> Vec<String> {
    FACTORS.iter().map(|(name, i, c)| format!("{name}: {i} … {c}")).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn effort(space: f64, time: f64, weight: f64, flow: f64) -> Effort {
        Effort { space, time, weight, flow }
    }

    #[test]
    fn the_text_names_each_factor_s_element_and_value() {
        let e = effort(0.42, 0.7, -0.12, -0.51);
        assert_eq!(
            text(&e, 1.5, Fit::Learnt),
            "Space direct 0.42 · Time sudden 0.70 · Weight neutral −0.12 · Flow free −0.51"
        );
        assert_eq!(element(0, -ELEMENT_AT), "indirect");
        assert_eq!(element(2, 0.34), "strong");
        assert_eq!(element(3, 0.33), "neutral");
        assert_eq!(element(1, -0.9), "sustained");
        assert_eq!(number(-0.001), "0.00", "no minus before a zero");
    }

    #[test]
    fn segments_outside_the_learnt_lengths_are_marked_extrapolated_and_say_so() {
        let learnt = Some([0.667, 3.333]);
        assert_eq!(Fit::of(1.0, learnt), Fit::Learnt);
        assert_eq!(Fit::of(0.667, learnt), Fit::Learnt, "the ends count as learnt");
        assert_eq!(Fit::of(3.333, learnt), Fit::Learnt);
        assert_eq!(Fit::of(0.5, learnt), Fit::Shorter { min_s: 0.667 });
        assert_eq!(Fit::of(4.2, learnt), Fit::Longer { max_s: 3.333 });
        assert_eq!(Fit::of(100.0, None), Fit::Learnt, "no learnt lengths: nothing to mark");
        let e = effort(0.0, 0.0, 0.0, 0.0);
        let said = text(&e, 4.2, Fit::of(4.2, learnt));
        assert!(said.ends_with("· 4.20 s, longer than the 3.33 s the classifiers learnt: extrapolated"), "{said}");
        let said = text(&e, 0.4, Fit::of(0.4, learnt));
        assert!(said.ends_with("· 0.40 s, shorter than the 0.67 s the classifiers learnt: extrapolated"), "{said}");
        // frames to seconds: inclusive
        assert_eq!(seconds(0, 119, 120.0), 1.0);
    }

    #[test]
    fn a_row_s_bars_carry_colours_marks_and_why_none() {
        let annotations = Annotations {
            segments: vec![
                Annotated { effort: Some(effort(-1.0, 0.0, 1.0, 0.5)), why: None },
                Annotated { effort: None, why: Some("shorter than the 3 frames".into()) },
                Annotated { effort: Some(effort(0.2, 0.2, 0.2, 0.2)), why: None },
            ],
            learnt_s: Some([0.667, 3.333]),
            by: "LMA, shipped family".into(),
        };
        let spans = [(0, 119), (120, 121), (122, 122 + 600)];
        let b = bars(&spans, &annotations, 120.0);
        assert_eq!(b.len(), 3);
        let v = b[0].values.as_ref().unwrap();
        assert_eq!(v[0], (-1.0, "rgb(40, 90, 220)".to_string()), "indulging: LMA's picture's blue");
        assert_eq!(v[2].1, "rgb(220, 90, 40)", "condensing: its red");
        assert_eq!(v[1].1, css_colour(0.0));
        assert!(!b[0].extrapolated);
        assert_eq!((b[1].values.clone(), b[1].text.as_str()), (None, "no Effort: shorter than the 3 frames"));
        assert!(b[2].extrapolated && b[2].text.contains("5.01 s, longer than"), "{}", b[2].text);
        // a span the answer has no annotation for (it cannot happen with the worker's answers)
        let more = bars(&[(0, 10), (11, 20), (21, 30), (31, 40)], &annotations, 120.0);
        assert_eq!(more[3].text, "no Effort");
    }

    #[test]
    fn the_cache_key_changes_with_the_segments_the_family_and_the_take_only() {
        let params = serde_json::json!({"model": "shipped"});
        let spans = [(0, 100), (101, 300)];
        let key = cache_key(1, "lma", &params, &spans);
        assert_eq!(key, cache_key(1, "lma", &serde_json::json!({"model": "shipped"}), &[(0, 100), (101, 300)]));
        assert_ne!(key, cache_key(1, "lma", &params, &[(0, 100), (101, 301)]), "a boundary moved");
        assert_ne!(key, cache_key(1, "lma", &params, &[(0, 100)]), "a segment deleted");
        assert_ne!(key, cache_key(1, "lma", &serde_json::json!({"model": "mine"}), &spans), "another family");
        assert_ne!(key, cache_key(2, "lma", &params, &spans), "another take");
        assert_eq!(legend()[3], "Flow: free … bound");
    }

    #[test]
    fn an_export_carries_the_effort_computed_and_keeps_a_method_s_own() {
        let segment = |start, end, effort| crate::segment::Segment {
            start,
            end,
            label: "a".into(),
            level: crate::segment::Level::Action,
            cluster: None,
            score: None,
            mirror_of: None,
            effort,
        };
        let own = effort(0.9, 0.9, 0.9, 0.9);
        let mut seg = crate::segment::Segmentation {
            file: "x.bvh".into(),
            fps: 30.0,
            frames: 100,
            method: "my-labels".into(),
            params: serde_json::json!({}),
            segments: vec![segment(0, 9, None), segment(10, 49, Some(own)), segment(50, 99, None)],
        };
        let computed = effort(-0.5, 0.1, 0.2, 0.3);
        let known = std::collections::HashMap::from([((0, 9), computed), ((10, 49), computed)]);
        assert_eq!(fill(&mut seg, &known), 1);
        assert_eq!(seg.segments[0].effort, Some(computed));
        assert_eq!(seg.segments[1].effort, Some(own), "a method's own Effort is kept");
        assert_eq!(seg.segments[2].effort, None, "not computed: left out");
        let back = crate::segment::Segmentation::from_json(&seg.to_json()).unwrap();
        assert_eq!(back.segments[0].effort, Some(computed), "the JSON carries it");
    }
}
