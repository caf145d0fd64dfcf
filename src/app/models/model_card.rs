//! A model card as the page shows it, beside the model choice of a labelling row and of its
//! method's panel ([`crate::method::cards::ModelCard`]): its lines, and the card's one-line summary.

use crate::method::cards::ModelCard;

/// The card's lines: what they say, and the text.
pub fn card_lines(card: &ModelCard) -> Vec<(&'static str, String)> {
    let mut lines = Vec::new();
    let trained_on = if !card.takes.is_empty() {
        let hashed = if card.take_sha256.iter().any(|h| !h.is_empty()) { " (with their files' SHA-256)" } else { "" };
        format!("{} take{}: {}{hashed}", card.takes.len(), plural(card.takes.len()), card.takes.join(", "))
    } else if !card.origin.is_empty() {
        card.origin.clone()
    } else {
        "not recorded".to_string()
    };
    lines.push(("trained on", trained_on));
    if !card.classes.is_empty() {
        lines.push(("classes", format!("{}: {}", card.classes.len(), card.classes.join(", "))));
    }
    let mut training = Vec::new();
    if let Some(frames) = card.frames {
        training.push(format!("{frames} labelled frames"));
    }
    if let (Some(run), Some(best)) = (card.epochs_run, card.best_epoch) {
        if run > 0 {
            training.push(format!("{run} epoch{}, epoch {best} kept", plural(run)));
        }
    }
    if !training.is_empty() {
        lines.push(("training", training.join(", ")));
    }
    if !card.command.is_empty() {
        lines.push(("command", card.command.clone()));
    }
    let held_out = match &card.held_out {
        Some(_) => card.held_out_text().trim_start_matches("held-out ").to_string(),
        None => "not measured".to_string(),
    };
    lines.push(("held out", held_out));
    lines
}

/// The card in a line (the row's title): classes, takes and the held-out figure.
pub fn card_summary(card: &ModelCard) -> String {
    let mut parts = vec![format!("model `{}`", card.name)];
    if !card.classes.is_empty() {
        parts.push(format!("{} class{}", card.classes.len(), if card.classes.len() == 1 { "" } else { "es" }));
    }
    if !card.takes.is_empty() {
        parts.push(format!("trained on {} take{}", card.takes.len(), plural(card.takes.len())));
    }
    parts.push(match &card.held_out {
        Some(h) => format!("held-out frame accuracy {:.2}", h.frame_accuracy),
        None => "held-out accuracy not measured".to_string(),
    });
    parts.join(" · ")
}

fn plural(n: usize) -> &'static str {
    if n == 1 {
        ""
    } else {
        "s"
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::method::cards::HeldOut;

    #[test]
    fn a_card_says_its_takes_classes_command_and_held_out_figure_or_not_measured() {
        let mut card = ModelCard {
            method: "dtfcn".into(),
            name: "mine".into(),
            takes: vec!["13_30.bvh".into()],
            take_sha256: vec!["ab".into()],
            classes: vec!["jog".into(), "squat".into()],
            frames: Some(600),
            epochs_run: Some(20),
            best_epoch: Some(18),
            command: "mocapseg train-dtfcn …".into(),
            ..ModelCard::default()
        };
        let lines = card_lines(&card);
        let get = |k: &str| lines.iter().find(|(l, _)| *l == k).map(|(_, t)| t.clone()).unwrap_or_default();
        assert_eq!(get("trained on"), "1 take: 13_30.bvh (with their files' SHA-256)");
        assert_eq!(get("classes"), "2: jog, squat");
        assert_eq!(get("training"), "600 labelled frames, 20 epochs, epoch 18 kept");
        assert_eq!(get("held out"), "not measured");
        assert_eq!(
            card_summary(&card),
            "model `mine` · 2 classes · trained on 1 take · held-out accuracy not measured"
        );
        card.held_out = Some(HeldOut { frame_accuracy: 0.9352, folds: vec![], how: "h".into(), source: "s".into() });
        assert!(card_lines(&card).iter().any(|(l, t)| *l == "held out" && t.starts_with("frame accuracy 0.94 (h")));
        assert!(card_summary(&card).ends_with("held-out frame accuracy 0.94"));
        let lma =
            ModelCard { name: "shipped".into(), origin: "stand-in labels of 12 takes".into(), ..ModelCard::default() };
        assert_eq!(card_lines(&lma)[0], ("trained on", "stand-in labels of 12 takes".to_string()));
    }
}
