//! Model cards: what a model says about where it fits — the takes it was trained on (by name and,
//! for models trained since issue 27, by the SHA-256 of each file), its classes, the command that
//! made it, and its held-out accuracy when one was measured.
//!
//! A held-out figure is never made up or copied from an in-sample score: [`with_held_out`] takes
//! it from the scoreboard (`docs/accuracy.json`, written by `make accuracy`), and only for a model
//! the scoreboard actually held takes out of — a method's row whose folds' held-out takes are
//! exactly the model's training takes (each fold trained on the others with the model's recipe:
//! the knn and dtfcn rows on the mocap6 takes, which are the `exercises` models' takes). Every
//! other model's card says "not measured". `mocapseg model-cards` and the scoreboard
//! (`examples/accuracy.rs`) write the shipped models' cards to `models/cards.json`, which the page
//! fetches beside the model files; a model the user trains or loads carries its card in its
//! [`super::supervised::ModelInfo`].

use serde::{Deserialize, Serialize};

/// Where the held-out figures come from.
pub const SCOREBOARD: &str = "docs/accuracy.json";

/// A model's card.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct ModelCard {
    /// The method (registry name) and the model's name.
    pub method: String,
    pub name: String,
    /// The training takes' file names (empty when the model does not say).
    pub takes: Vec<String>,
    /// The SHA-256 of each training take's file, in the order of `takes` (empty for older models).
    pub take_sha256: Vec<String>,
    pub classes: Vec<String>,
    /// Labelled frames (or segments) trained on, if the model says.
    pub frames: Option<usize>,
    /// Epochs run and the epoch kept (a network's training).
    pub epochs_run: Option<usize>,
    pub best_epoch: Option<usize>,
    /// The command that made it.
    pub command: String,
    /// Where it came from, in a line, when it has no structured provenance (LMA's effort model).
    pub origin: String,
    /// Its held-out accuracy, when measured; `None`: not measured.
    pub held_out: Option<HeldOut>,
}

/// A measured held-out figure.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct HeldOut {
    /// Mean frame accuracy over the held-out takes (Hungarian-matched as `mocapseg eval`).
    pub frame_accuracy: f64,
    /// Each held-out take and its frame accuracy.
    pub folds: Vec<(String, f64)>,
    /// How it was measured, as the scoreboard says.
    pub how: String,
    /// The file it was read from.
    pub source: String,
}

/// The shipped models' cards as the page fetches them (`models/cards.json`).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Cards {
    /// How the file was made.
    pub generated_by: String,
    pub cards: Vec<ModelCard>,
}

impl ModelCard {
    /// The held-out figure in a sentence, or "not measured".
    pub fn held_out_text(&self) -> String {
        match &self.held_out {
            Some(h) => format!(
                "held-out frame accuracy {:.2} ({}; {} takes, from {})",
                h.frame_accuracy,
                h.how,
                h.folds.len(),
                h.source
            ),
            None => "held-out accuracy: not measured".to_string(),
        }
    }
}

/// The stem of a take's file name, lowercased (`13_30.bvh` → `13_30`).
fn stem(name: &str) -> String {
    let base = name.rsplit(['/', '\\']).next().unwrap_or(name).to_ascii_lowercase();
    base.strip_suffix(".bvh").map(str::to_string).unwrap_or(base)
}

/// `cards` with the held-out figure of every model the scoreboard `accuracy` (the JSON of
/// `docs/accuracy.json`) measured held out: a row of its `actions` for the model's method whose
/// folds held out exactly the model's training takes. The others are left "not measured".
pub fn with_held_out(mut cards: Vec<ModelCard>, accuracy: &serde_json::Value) -> Result<Vec<ModelCard>, String> {
    let rows = accuracy
        .get("actions")
        .and_then(|a| a.as_array())
        .ok_or_else(|| format!("{SCOREBOARD}: no `actions` list (expected the scoreboard's JSON)"))?;
    for card in &mut cards {
        card.held_out = None;
        if card.takes.is_empty() {
            continue;
        }
        let mut trained: Vec<String> = card.takes.iter().map(|t| stem(t)).collect();
        trained.sort();
        for row in rows.iter().filter(|r| r.get("method").and_then(|m| m.as_str()) == Some(card.method.as_str())) {
            let Some(mean) = row.get("held_out").and_then(|h| h.get("frame_accuracy")).and_then(|v| v.as_f64()) else {
                continue;
            };
            let folds: Vec<(String, f64)> = row
                .get("folds")
                .and_then(|f| f.as_array())
                .map(|folds| {
                    folds
                        .iter()
                        .filter_map(|f| {
                            let take = f.get("take")?.as_str()?.to_string();
                            let accuracy = f.get("scores")?.get("frame_accuracy")?.as_f64()?;
                            Some((take, accuracy))
                        })
                        .collect()
                })
                .unwrap_or_default();
            let mut held: Vec<String> = folds.iter().map(|(t, _)| stem(t)).collect();
            held.sort();
            if held != trained {
                continue;
            }
            let how = row.get("note").and_then(|n| n.as_str()).unwrap_or("").to_string();
            let how = match how.split_once("held out:") {
                Some((_, rest)) => format!("held out: {}", rest.trim()),
                None => "each take held out, trained on the others".to_string(),
            };
            card.held_out = Some(HeldOut { frame_accuracy: mean, folds, how, source: SCOREBOARD.into() });
            break;
        }
    }
    Ok(cards)
}

/// The text of `models/cards.json`: every shipped model's card, with the held-out figures of the
/// scoreboard whose JSON is `accuracy` (a refusal names the scoreboard file).
pub fn cards_json(accuracy: &str, generated_by: &str) -> Result<String, String> {
    let accuracy: serde_json::Value =
        serde_json::from_str(accuracy).map_err(|e| format!("{SCOREBOARD}: not the scoreboard's JSON: {e}"))?;
    let cards = with_held_out(crate::methods::shipped_cards(&super::ModelStore::default()), &accuracy)?;
    let file = Cards { generated_by: generated_by.to_string(), cards };
    serde_json::to_string_pretty(&file).map(|t| t + "\n").map_err(|e| e.to_string())
}

/// Which of a card's training takes the take on screen is, and how it was matched.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum TrainingMatch {
    /// Its file's SHA-256 is one the model recorded.
    Content(String),
    /// Its file name (or an alias) is one of the training takes': the model recorded no hashes
    /// (`hashed` false), or none matched and the name did (`hashed` true: another version of the
    /// take — the bundled sample is 13_30 rounded to 2 decimals). A renamed copy is matched by
    /// content only when hashes exist.
    Name { take: String, hashed: bool },
}

impl TrainingMatch {
    /// The warning the row and the card show.
    pub fn warning(&self) -> String {
        let how = match self {
            TrainingMatch::Content(t) => format!("same file as its training take {t}"),
            TrainingMatch::Name { take, hashed: false } => {
                format!("matched by name: {take}; this model recorded no file hashes")
            }
            TrainingMatch::Name { take, hashed: true } => {
                format!("matched by name: {take}, another version of the file it was trained on")
            }
        };
        format!("This take was in the model's training set ({how}) — its labels here are not a measure of accuracy.")
    }
}

/// Whether the take on screen (`name`, the SHA-256 of its file if known, and other names it is
/// known by — the bundled sample is CMU 13_30) was one of `card`'s training takes: by content when
/// the model recorded its takes' hashes, else by name.
pub fn training_match(card: &ModelCard, name: &str, sha256: Option<&str>, aliases: &[&str]) -> Option<TrainingMatch> {
    if let Some(sha) = sha256 {
        if let Some(i) = card.take_sha256.iter().position(|h| !h.is_empty() && h.eq_ignore_ascii_case(sha)) {
            let take = card.takes.get(i).cloned().unwrap_or_else(|| name.to_string());
            return Some(TrainingMatch::Content(take));
        }
    }
    let names: Vec<String> = std::iter::once(name).chain(aliases.iter().copied()).map(stem).collect();
    let hashed = card.take_sha256.iter().any(|h| !h.is_empty());
    card.takes.iter().find(|t| names.contains(&stem(t))).map(|t| TrainingMatch::Name { take: t.clone(), hashed })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn card(method: &str, name: &str, takes: &[&str]) -> ModelCard {
        ModelCard {
            method: method.into(),
            name: name.into(),
            takes: takes.iter().map(|t| t.to_string()).collect(),
            ..ModelCard::default()
        }
    }

    /// The scoreboard's held-out figure goes to the model whose training takes its folds held out,
    /// and to no other (the same method's models trained on other takes stay "not measured").
    #[test]
    fn held_out_figures_come_from_the_scoreboard_only_for_the_takes_it_held_out() {
        let accuracy = serde_json::json!({
            "actions": [
                {"method": "sssm", "held_out": {"frame_accuracy": 0.86},
                 "folds": [{"take": "13_29", "scores": {"frame_accuracy": 0.9}}]},
                {"method": "dtfcn", "note": "defaults: the shipped models (in-sample); held out: mocap6 takes only, trained on the other three",
                 "held_out": {"frame_accuracy": 0.935},
                 "folds": [{"take": "13_29", "scores": {"frame_accuracy": 0.947}},
                           {"take": "13_30", "scores": {"frame_accuracy": 0.95}},
                           {"take": "13_31", "scores": {"frame_accuracy": 0.9}},
                           {"take": "14_14", "scores": {"frame_accuracy": 0.94}}]}
            ]
        });
        let cards = vec![
            card("dtfcn", "exercises", &["13_29.bvh", "13_30.bvh", "13_31.bvh", "14_14.bvh"]),
            card("dtfcn", "cmu-actions", &["86_01.bvh"]),
            card("knn", "exercises", &["13_29.bvh", "13_30.bvh", "13_31.bvh", "14_14.bvh"]),
            card("lma", "shipped", &[]),
        ];
        let out = with_held_out(cards, &accuracy).unwrap();
        let h = out[0].held_out.as_ref().expect("exercises: its takes were held out");
        assert_eq!(h.frame_accuracy, 0.935);
        assert_eq!(h.folds.len(), 4);
        assert_eq!(h.folds[1], ("13_30".to_string(), 0.95));
        assert_eq!(h.how, "held out: mocap6 takes only, trained on the other three");
        assert_eq!(h.source, SCOREBOARD);
        assert!(out[0].held_out_text().starts_with("held-out frame accuracy 0.94 (held out: mocap6"));
        assert!(out[1].held_out.is_none(), "cmu-actions: not held out by the scoreboard");
        assert!(out[2].held_out.is_none(), "no knn row in this scoreboard");
        assert!(out[3].held_out.is_none());
        assert_eq!(out[1].held_out_text(), "held-out accuracy: not measured");
        assert!(with_held_out(vec![], &serde_json::json!({})).unwrap_err().contains("actions"));
    }

    /// The repository's own scoreboard: both shipped `exercises` models measured, nothing else.
    #[test]
    fn the_shipped_cards_from_the_saved_scoreboard() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(SCOREBOARD);
        let accuracy: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
        let cards =
            with_held_out(crate::methods::shipped_cards(&crate::method::ModelStore::default()), &accuracy).unwrap();
        let mut measured: Vec<String> =
            cards.iter().filter(|c| c.held_out.is_some()).map(|c| format!("{}-{}", c.method, c.name)).collect();
        measured.sort();
        assert_eq!(measured, ["dtfcn-exercises", "knn-exercises"]);
        assert!(cards.iter().any(|c| c.method == "lma"), "LMA's model has a card too");
        let e = cards.iter().find(|c| c.method == "dtfcn" && c.name == "exercises").unwrap();
        assert!(e.takes.contains(&"13_30.bvh".to_string()) && e.command.contains("train-dtfcn"));
        assert!(!e.classes.is_empty() && e.frames.is_some());
    }

    #[test]
    fn the_cards_file_reads_back_and_refuses_what_is_not_a_scoreboard() {
        let text = cards_json(r#"{"actions": []}"#, "test").unwrap();
        let back: Cards = serde_json::from_str(&text).unwrap();
        assert_eq!(back.generated_by, "test");
        assert!(back.cards.iter().all(|c| c.held_out.is_none()));
        assert!(cards_json("nope", "t").unwrap_err().starts_with(SCOREBOARD));
    }

    #[test]
    fn a_take_matches_by_content_first_then_by_name() {
        let mut c = card("dtfcn", "mine", &["walk.bvh", "13_30.bvh"]);
        let by_name = |hashed| Some(TrainingMatch::Name { take: "13_30.bvh".into(), hashed });
        assert_eq!(training_match(&c, "13_30.bvh", None, &[]), by_name(false));
        assert_eq!(training_match(&c, "sample.bvh", None, &["13_30.bvh"]), by_name(false));
        assert_eq!(training_match(&c, "86_01.bvh", Some("ab"), &[]), None);
        c.take_sha256 = vec!["AB12".into(), String::new()];
        // a renamed copy of walk.bvh: matched by its content
        assert_eq!(training_match(&c, "copy.bvh", Some("ab12"), &[]), Some(TrainingMatch::Content("walk.bvh".into())));
        let w = TrainingMatch::Content("walk.bvh".into()).warning();
        assert!(w.contains("in the model's training set") && w.contains("not a measure of accuracy"), "{w}");
        let w = TrainingMatch::Name { take: "x".into(), hashed: false }.warning();
        assert!(w.contains("matched by name") && w.contains("recorded no file hashes"), "{w}");
        // with hashes, none matching: the bundled sample (13_30 at 2 decimals) under a model trained on 13_30
        assert_eq!(training_match(&c, "sample.bvh", Some("ffff"), &["13_30.bvh"]), by_name(true));
        let w = by_name(true).unwrap().warning();
        assert!(w.contains("matched by name: 13_30.bvh, another version") && !w.contains("no file hashes"), "{w}");
    }
}
