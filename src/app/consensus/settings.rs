//! The page's "Consensus" row, its pure part (tested natively): the settings as the user types them and as the
//! browser keeps them, and the words a marker and the status line say. The consensus itself is
//! [`crate::segment::consensus`]; the row is `src/app/consensus/row.rs`.

use crate::segment::consensus::{Agreed, Consensus, ConsensusOptions};

/// The widest tolerance the page offers, in seconds.
pub const MAX_TOLERANCE_S: f64 = 5.0;
/// The highest minimum agreement the page offers.
pub const MAX_MIN_METHODS: usize = 20;
/// Where the settings are kept in the browser's local storage.
pub const STORAGE_KEY: &str = "mocapseg.consensus";

/// The tolerance typed in its field, in seconds, or why it is not one.
pub fn parse_tolerance(text: &str) -> Result<f64, String> {
    let t = text.trim();
    match t.parse::<f64>() {
        Ok(v) if v.is_finite() && (0.0..=MAX_TOLERANCE_S).contains(&v) => Ok(v),
        Ok(_) => Err(format!("the tolerance is a number of seconds from 0 to {MAX_TOLERANCE_S} (got {t})")),
        Err(_) => Err(format!("the tolerance is a number of seconds, like 0.5 (got \"{t}\")")),
    }
}

/// The minimum agreement typed in its field, or why it is not one.
pub fn parse_min_methods(text: &str) -> Result<usize, String> {
    let t = text.trim();
    match t.parse::<usize>() {
        Ok(n) if (1..=MAX_MIN_METHODS).contains(&n) => Ok(n),
        _ => {
            Err(format!("the minimum agreement is a whole number of methods from 1 to {MAX_MIN_METHODS} (got \"{t}\")"))
        }
    }
}

/// The settings as the browser keeps them: `{"tolerance_s": …, "min_methods": …}`.
pub fn to_stored(o: &ConsensusOptions) -> String {
    serde_json::json!({"tolerance_s": o.tolerance_s, "min_methods": o.min_methods}).to_string()
}

/// Settings kept by [`to_stored`]; `None` (the defaults) when the text is not that, or out of the page's limits.
pub fn from_stored(text: &str) -> Option<ConsensusOptions> {
    let v: serde_json::Value = serde_json::from_str(text).ok()?;
    let tolerance_s =
        v.get("tolerance_s")?.as_f64().filter(|t| t.is_finite() && (0.0..=MAX_TOLERANCE_S).contains(t))?;
    let min_methods = v.get("min_methods")?.as_u64().filter(|n| (1..=MAX_MIN_METHODS as u64).contains(n))? as usize;
    Some(ConsensusOptions { tolerance_s, min_methods })
}

/// A marker's text: how many of the methods agree, "3/5".
pub fn mark_text(b: &Agreed, of: usize) -> String {
    format!("{}/{of}", b.count())
}

/// A marker's tooltip: where the boundary is, how many agree and which, each with its own frame (1-based, as the
/// readout); `name` gives a method's name on the page ("sssm" → "SSSM").
pub fn mark_tooltip(b: &Agreed, of: usize, fps: f64, name: impl Fn(&str) -> String) -> String {
    let seconds = if fps > 0.0 { b.frame as f64 / fps } else { 0.0 };
    let who: Vec<String> =
        b.methods.iter().zip(&b.frames).map(|(m, f)| format!("{} (frame {})", name(m), f + 1)).collect();
    format!(
        "{} of {of} methods agree on a boundary at frame {} ({seconds:.2} s): {}",
        b.count(),
        b.frame + 1,
        who.join(", ")
    )
}

/// The status line under the row: how many boundaries agree, under which settings.
pub fn summary(c: &Consensus) -> String {
    let n = c.boundaries.len();
    let of = c.methods.len();
    let o = &c.options;
    if o.min_methods > of {
        return format!(
            "No boundary: at least {} methods must agree and {of} ran — lower the minimum or run more methods",
            o.min_methods
        );
    }
    format!(
        "{n} boundar{} where at least {} of {of} methods agree within {} s",
        if n == 1 { "y" } else { "ies" },
        o.min_methods,
        o.tolerance_s
    )
}

/// The settings a consensus of `ran` methods is computed with: `options`, except that an embedded page (where the
/// settings cannot be changed) never asks more methods to agree than ran — two methods and a minimum of 3 would
/// always be empty.
pub fn effective_options(options: ConsensusOptions, ran: usize, embedded: bool) -> ConsensusOptions {
    let mut o = options;
    if embedded {
        o.min_methods = o.min_methods.min(ran.max(1));
    }
    o
}

/// How far apart (CSS px) two markers must be to sit side by side on one line (a marker is at least 24 px wide).
pub const MARK_GAP_PX: f64 = 34.0;
/// The most lines the markers are laid out on (markers closer still share the last line).
pub const MARK_TIERS: usize = 3;

/// The line (0, 1, …) each marker at pixel `at` (sorted) sits on, so that markers closer than `gap` pixels are
/// laid out apart ("3/7" never drawn over "3/7"): each takes the first line whose last marker is `gap` away.
pub fn mark_tiers(at: &[f64], gap: f64, tiers: usize) -> Vec<usize> {
    let mut last: Vec<f64> = Vec::new();
    at.iter()
        .map(|&x| {
            let free = last.iter().position(|&l| x - l >= gap);
            let tier = match free {
                Some(t) => t,
                None if last.len() < tiers.max(1) => {
                    last.push(f64::NEG_INFINITY);
                    last.len() - 1
                }
                None => last.len() - 1,
            };
            last[tier] = x;
            tier
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn embedded_the_minimum_never_asks_more_methods_than_ran() {
        let o = ConsensusOptions { tolerance_s: 0.5, min_methods: 3 };
        assert_eq!(effective_options(o, 2, true).min_methods, 2);
        assert_eq!(effective_options(o, 2, false).min_methods, 3, "the full page says why and lets the user lower it");
        assert_eq!(effective_options(o, 5, true).min_methods, 3);
        assert_eq!(effective_options(o, 2, true).tolerance_s, 0.5);
    }

    #[test]
    fn markers_too_close_to_read_are_laid_out_on_lines_apart() {
        assert_eq!(mark_tiers(&[0.0, 100.0, 200.0], 34.0, 3), [0, 0, 0], "far apart: one line");
        assert_eq!(mark_tiers(&[0.0, 10.0, 40.0, 50.0], 34.0, 3), [0, 1, 0, 1]);
        assert_eq!(mark_tiers(&[0.0, 5.0, 10.0, 15.0], 34.0, 3), [0, 1, 2, 2], "at most three lines");
        assert!(mark_tiers(&[], 34.0, 3).is_empty());
    }

    fn agreed() -> Agreed {
        Agreed { frame: 120, methods: vec!["sssm".into(), "pca".into(), "kcs".into()], frames: vec![119, 120, 124] }
    }

    #[test]
    fn the_fields_take_numbers_within_the_pages_limits() {
        assert_eq!(parse_tolerance(" 0.5 "), Ok(0.5));
        assert_eq!(parse_tolerance("0"), Ok(0.0));
        assert!(parse_tolerance("-1").unwrap_err().contains("from 0 to 5"));
        assert!(parse_tolerance("soon").unwrap_err().contains("like 0.5"));
        assert!(parse_tolerance("NaN").is_err());
        assert_eq!(parse_min_methods("3"), Ok(3));
        for bad in ["0", "21", "2.5", ""] {
            assert!(parse_min_methods(bad).unwrap_err().contains("whole number"), "{bad}");
        }
    }

    #[test]
    fn stored_settings_come_back_and_bad_ones_are_the_defaults() {
        let o = ConsensusOptions { tolerance_s: 0.75, min_methods: 3 };
        assert_eq!(from_stored(&to_stored(&o)), Some(o));
        for bad in
            ["", "{", "{\"tolerance_s\": -1, \"min_methods\": 2}", "{\"tolerance_s\": 1, \"min_methods\": 0}", "[1, 2]"]
        {
            assert_eq!(from_stored(bad), None, "{bad}");
        }
    }

    #[test]
    fn a_marker_says_how_many_agree_and_which() {
        let b = agreed();
        assert_eq!(mark_text(&b, 5), "3/5");
        let tip = mark_tooltip(&b, 5, 120.0, |m| m.to_uppercase());
        assert_eq!(tip, "3 of 5 methods agree on a boundary at frame 121 (1.00 s): SSSM (frame 120), PCA (frame 121), KCS (frame 125)");
    }

    #[test]
    fn the_summary_counts_the_boundaries_and_says_when_the_minimum_is_too_high() {
        let c = |min_methods, boundaries: Vec<Agreed>| Consensus {
            frames: 500,
            fps: 120.0,
            methods: vec!["sssm".into(), "pca".into(), "kcs".into()],
            options: ConsensusOptions { tolerance_s: 0.5, min_methods },
            boundaries,
        };
        assert_eq!(summary(&c(2, vec![agreed()])), "1 boundary where at least 2 of 3 methods agree within 0.5 s");
        assert_eq!(
            summary(&c(2, vec![agreed(), agreed()])),
            "2 boundaries where at least 2 of 3 methods agree within 0.5 s"
        );
        assert!(summary(&c(4, vec![])).contains("at least 4 methods must agree and 3 ran"));
    }
}
