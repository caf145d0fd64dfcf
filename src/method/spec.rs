//! What a page needs to build a parameter form for a method: for every parameter its name, a
//! one-line help, its kind with exactly the bounds the method's check enforces, and its
//! default (as the method's parameters serialize it).

use serde::{Deserialize, Serialize};

/// One parameter of a method.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ParamSpec {
    /// The field name (as in the parameters' JSON).
    pub name: String,
    /// One sentence for a tooltip.
    pub help: String,
    pub kind: ParamKind,
    /// The default value, as it appears in the parameters' JSON.
    pub default: serde_json::Value,
    /// Unit of the value (`"s"`, `"frames"`, `"in"`, …), if it has one.
    pub unit: Option<String>,
    /// Shown in the basic form (others under "advanced").
    pub basic: bool,
    /// A coupling the method's check enforces: this (number) parameter may not exceed the
    /// parameter named here. A form uses it to offer lowering this one when the other is set
    /// below it, rather than leave a basic field refused because of a hidden one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub at_most: Option<String>,
}

impl ParamSpec {
    /// The parameter's name in words for a form's label, without its unit: the papers' symbols and the JSON's
    /// abbreviations spelt out (`k_sigma`: "cut threshold (k σ)"; `horizon_s`, in seconds: "search horizon"); any
    /// other name with its underscores as spaces. The JSON name stays the field's id and the command line's.
    pub fn words(&self) -> String {
        if let Some(words) = plain_words(&self.name) {
            return words.to_string();
        }
        let name = match self.unit.as_deref() {
            Some(unit) => self.name.strip_suffix(&format!("_{unit}")).unwrap_or(&self.name),
            None => &self.name,
        };
        name.replace('_', " ")
    }

    /// The spec, declared to be at most the parameter `other` (see [`ParamSpec::at_most`]).
    pub fn at_most(mut self, other: &str) -> ParamSpec {
        self.at_most = Some(other.to_string());
        self
    }
}

/// The words for the parameter names that do not read as words (a paper's symbol, an abbreviation, a name that
/// says too little alone); a name shared by several methods means the same there (`merge_s`: boundaries this close
/// become one). Units are the field's, not said here.
fn plain_words(name: &str) -> Option<&'static str> {
    Some(match name {
        // shared
        "fps" => "working frame rate",
        "smooth_s" => "smoothing (σ)",
        "merge_s" => "merge within",
        "min_s" | "min_segment_s" => "shortest segment",
        "max_s" => "longest segment",
        // PCA (Barbič et al.)
        "tau" => "variance kept (τ)",
        "window_s" => "first frames",
        "lag_s" => "derivative lag",
        "k_sigma" => "cut threshold (k σ)",
        // velocity, KCS
        "low_speed" => "low hand speed",
        "high_speed" => "peak hand speed",
        "drop" => "swing ends after",
        "legs" => "legs too",
        // SSSM (Krüger et al.)
        "offsets" => "stacked frame offsets",
        "radius" => "search radius (R)",
        "stop_window" => "stop after (w)",
        "max_neighbours" => "neighbours kept",
        "diagonal_band_s" => "diagonal band",
        "min_action_entries_per_fps" => "activity entries per second",
        "boundary_rule" => "boundary placement",
        "mirror_activities" => "mirror in activities",
        "relative_gate" => "relative gate",
        "primitive_radius" => "primitive radius",
        "nu" => "path slope limit (ν)",
        "min_path_frames" => "shortest warping path",
        "min_cut_distance" => "closest cuts",
        "bundling" => "feature bundling",
        "bundling_k" => "bundling neighbours (k)",
        "bundling_variance" => "bundling variance kept",
        "bundling_optimum" => "bundling optimum",
        "mirror" => "mirrored features",
        "neighbour_search" => "search structure",
        "cluster_coverage" => "path coverage of clusters",
        "horizon_s" => "search horizon",
        "pose_merge" => "merge repeated poses",
        "boundary_window_s" => "move boundaries within",
        // LMA (Bouchard & Badler)
        "model" => "model",
        "search" => "boundary search",
        "exhaustive" => "every candidate",
        "prune_speed" => "pruning hand speed",
        "min_rise" => "trough rise",
        "quantile" => "Effort change quantile",
        "told" => "leave out features correlated above",
        "validation" => "validation share",
        "test" => "test share",
        "saliency_rounds" => "saliency rounds",
        "max_epochs" => "most epochs",
        "shift_epochs" => "shifted networks' epochs",
        "shift_restarts" => "shifted networks' restarts",
        // the labellers (k-NN, DT-FCN) and their training
        "unknown_threshold" => "unknown below",
        "unknown_ratio" => "open-set unknown above",
        "half_window_s" => "half window",
        "k" => "votes (k)",
        "input" => "window rows",
        "fit_check" => "check the fit",
        "fit_others" => "measure other models",
        "min_duration_s" => "shortest run",
        "switch_cost" => "label change cost",
        "choose_decoding" => "choose the decoding",
        "label_noise" => "label noise",
        "mask_s" => "transition mask",
        "width" => "kernel width (w)",
        "filters" => "filters per layer",
        "image_rows" => "motion image rows",
        "crop_frames" => "crop length",
        "batch" => "crops per step",
        "rate" | "learning_rate" => "learning rate",
        "average_last" => "average the last",
        "members" => "ensemble of",
        "centre_on_take" => "centre on the take",
        _ => return None,
    })
}

/// The type of a parameter and the values it accepts (bounds included).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum ParamKind {
    Number {
        min: f64,
        max: f64,
    },
    Integer {
        min: i64,
        max: i64,
    },
    Bool,
    /// One of `options` (the serialized names).
    Choice {
        options: Vec<String>,
    },
    /// Any of `options` (a list of their names; the form's text joins them with commas).
    Flags {
        options: Vec<String>,
    },
    /// A list of at most `max_len` integers, each within `[min, max]`.
    IntegerList {
        min: i64,
        max: i64,
        max_len: usize,
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(name: &str, unit: Option<&str>) -> ParamSpec {
        ParamSpec {
            name: name.into(),
            help: String::new(),
            kind: ParamKind::Bool,
            default: serde_json::Value::Null,
            unit: unit.map(Into::into),
            basic: true,
            at_most: None,
        }
    }

    #[test]
    fn symbols_and_abbreviations_are_spelt_out_and_units_left_to_the_field() {
        assert_eq!(spec("k_sigma", None).words(), "cut threshold (k σ)");
        assert_eq!(spec("tau", None).words(), "variance kept (τ)");
        assert_eq!(spec("offsets", Some("frames")).words(), "stacked frame offsets");
        assert_eq!(spec("horizon_s", Some("s")).words(), "search horizon");
        // a name that reads as words: its underscores as spaces, its unit suffix off
        assert_eq!(spec("low_threshold_s", Some("s")).words(), "low threshold");
        assert_eq!(spec("max_neighbours", None).words(), "neighbours kept");
    }

    /// Every parameter of every registered method and every training option reads as words: no underscore, no bare
    /// symbol of one or two letters, no unit suffix.
    #[test]
    fn every_form_field_of_the_app_is_named_in_words() {
        let mut specs: Vec<ParamSpec> = Vec::new();
        for m in crate::methods::registry() {
            specs.extend(m.param_specs());
            specs.extend(m.supervision().map(|s| s.training).unwrap_or_default());
        }
        assert!(specs.len() > 40, "{} parameters", specs.len());
        for s in &specs {
            let w = s.words();
            assert!(!w.contains('_'), "{}: {w:?}", s.name);
            assert!(w.chars().filter(|c| c.is_alphabetic()).count() >= 3, "{}: {w:?}", s.name);
            assert!(
                !["tau", "nu", "k sigma", "offsets", "drop", "told", "min rise"].contains(&w.as_str()),
                "{}: {w:?}",
                s.name
            );
            if let Some(unit) = &s.unit {
                assert!(!w.ends_with(&format!(" {unit}")), "{}: {w:?} repeats its unit", s.name);
            }
        }
    }
}
