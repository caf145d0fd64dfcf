//! What a labelling row's header says about its model's fit to the take on screen (issue 27,
//! "Models on the row": a model whose classes do not fit the take says so instead of painting
//! confident labels). From the run's [`TakeFitReport`]: a "does not fit" badge whose description
//! is the reason, and — when the run measured the method's other models (`fit_others`) — one
//! "use NAME" suggestion per model that fits the take (best first, as the report ranks them), or
//! a note that no model of the method fits it; when it did not, an offer to find the models that
//! fit (the run again with `fit_others`: asked for, not paid on every run). Nothing when the take fits,
//! or when the run made no fit check (`fit_check` off: the user asked to see the labels anyway —
//! the panel's `fit_check` box shows the check off, the row shows the labels as they are).

use crate::method::TakeFitReport;

/// The badge's text.
pub const BADGE: &str = "does not fit";

/// What the row header shows for a run that does not fit its take.
#[derive(Debug, Clone, PartialEq)]
pub struct FitBadge {
    /// The badge's accessible description and tooltip: the model, the reason, what the row shows.
    pub description: String,
    /// One per model that fits the take, best first: (model name, the button's text, its tooltip).
    pub suggestions: Vec<Suggestion>,
    /// When no other model fits: a sentence that says so (`None` when there are suggestions, or the
    /// other models were not measured).
    pub none: Option<String>,
    /// The other models were not measured: offer to (the row's "find a model that fits").
    pub find: bool,
}

/// A model to switch the row to.
#[derive(Debug, Clone, PartialEq)]
pub struct Suggestion {
    /// The model's name (the value the row's model choice takes).
    pub model: String,
    /// The button's text: "use cmu-actions".
    pub text: String,
    /// Its tooltip: what it does and how well the model fits.
    pub title: String,
}

/// The badge for a run whose report is `report` (`None`: no fit check) of method `short` (k-NN).
pub fn fit_badge(report: Option<&TakeFitReport>, short: &str) -> Option<FitBadge> {
    let report = report.filter(|r| !r.fits)?;
    let reason =
        if report.reason.is_empty() { "its classes cannot describe it".to_string() } else { report.reason.clone() };
    let description = format!(
        "Model `{}` does not fit this take: {reason}. Its classes cannot describe the take, so every frame is \
         labelled unknown instead of painting confident wrong labels.",
        report.model
    );
    let suggestions: Vec<Suggestion> = report
        .fitting
        .iter()
        .map(|m| {
            let how = match m.pose_ratio {
                Some(r) => format!(
                    "this take's poses are {r:.1} times as far from what it learnt as a new performance of a move it \
                     knows"
                ),
                None => "its training takes travel as this take does".to_string(),
            };
            Suggestion {
                model: m.name.clone(),
                text: format!("use {}", m.name),
                title: format!("Label with model `{}` and run {short} again: it fits this take ({how})", m.name),
            }
        })
        .collect();
    let none = (report.searched && suggestions.is_empty()).then(|| format!("no {short} model fits this take"));
    Some(FitBadge { description, suggestions, none, find: !report.searched })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::method::FittingModel;

    fn report(fitting: Vec<FittingModel>) -> TakeFitReport {
        TakeFitReport {
            model: "exercises".into(),
            fits: false,
            travel_share: Some(0.43),
            travel_limit: Some(10.9),
            pose_ratio: Some(1.3),
            reason: "43 % of its frames travel faster than any of the model's training takes did (11 in/s)".into(),
            fitting,
            searched: true,
        }
    }

    #[test]
    fn a_take_that_does_not_fit_gets_a_badge_with_its_reason_and_the_models_that_fit() {
        let fitting = vec![
            FittingModel { name: "cmu-actions".into(), travel_share: Some(0.01), pose_ratio: Some(0.0) },
            FittingModel { name: "locomotion".into(), travel_share: Some(0.0), pose_ratio: Some(1.63) },
        ];
        let badge = fit_badge(Some(&report(fitting)), "k-NN").unwrap();
        assert!(
            badge.description.starts_with("Model `exercises` does not fit this take: 43 % of its frames"),
            "{}",
            badge.description
        );
        assert!(badge.description.contains("every frame is labelled unknown"));
        let texts: Vec<&str> = badge.suggestions.iter().map(|s| s.text.as_str()).collect();
        assert_eq!(texts, ["use cmu-actions", "use locomotion"], "best first, as the report ranks them");
        assert_eq!(badge.suggestions[1].model, "locomotion");
        assert!(
            badge.suggestions[1].title.contains("run k-NN again")
                && badge.suggestions[1].title.contains("1.6 times as far from what it learnt")
        );
        assert!(badge.none.is_none() && !badge.find);
        // no model fits: said, no button
        let alone = fit_badge(Some(&report(Vec::new())), "DT-FCN").unwrap();
        assert!(alone.suggestions.is_empty());
        assert_eq!(alone.none.as_deref(), Some("no DT-FCN model fits this take"));
        assert!(!alone.find);
        // the other models not measured (the default): no suggestion, no "none fits", an offer to find them
        let unsearched = TakeFitReport { searched: false, ..report(Vec::new()) };
        let badge = fit_badge(Some(&unsearched), "k-NN").unwrap();
        assert!(badge.suggestions.is_empty() && badge.none.is_none() && badge.find, "{badge:?}");
        assert!(badge.description.contains("every frame is labelled unknown"));
    }

    #[test]
    fn no_badge_when_the_take_fits_or_nothing_was_checked() {
        let fits = TakeFitReport { fits: true, reason: String::new(), fitting: Vec::new(), ..report(Vec::new()) };
        assert_eq!(fit_badge(Some(&fits), "k-NN"), None);
        assert_eq!(fit_badge(None, "k-NN"), None);
        // a report without a reason still says why in general terms
        let bare = TakeFitReport { reason: String::new(), ..report(Vec::new()) };
        assert!(fit_badge(Some(&bare), "k-NN").unwrap().description.contains("its classes cannot describe it"));
    }
}
