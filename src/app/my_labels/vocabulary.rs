//! The words of my labels, natively tested: the [`RESERVED`] labels that say "no label" (never a class), the
//! labels worth offering while typing ([`suggestions`]), the fixed vocabulary whose first [`HOTKEYS`] entries
//! the number keys give ([`vocabulary`], [`hotkey_label`]), and a label's own colour class ([`label_class`]).

/// Labels that say a span has *no* action label — the SSSM's transitions, a labeller's
/// unknowns, the page's own word for an unlabelled segment — compared ignoring case and spaces.
/// They are never my labels' classes: a copy leaves them as gaps, training and the scores read
/// them as unlabelled frames, the label vocabulary never offers them.
pub const RESERVED: [&str; 3] = ["transition", "unknown", "unlabelled"];

/// Whether `label` says "no label" ([`RESERVED`]).
pub fn is_reserved(label: &str) -> bool {
    let label = label.trim();
    RESERVED.iter().any(|r| r.eq_ignore_ascii_case(label))
}

/// Whether a segment labelled `label` is one of my labelled segments (not empty, not
/// [`RESERVED`]).
pub fn is_labelled(label: &str) -> bool {
    !label.trim().is_empty() && !is_reserved(label)
}

/// The labels of `labels` worth offering while typing: not empty, sorted, once each.
pub fn suggestions<'a>(labels: impl IntoIterator<Item = &'a str>) -> Vec<String> {
    let mut out: Vec<String> = labels.into_iter().filter(|l| !l.trim().is_empty()).map(str::to_string).collect();
    out.sort();
    out.dedup();
    out
}

/// The most entries of the vocabulary with a number key (1–9).
pub const HOTKEYS: usize = 9;

/// My labels' fixed vocabulary, in the order its number keys follow: the ground truth's classes
/// (`truth`, when one is imported), then the classes of the labelling methods' models
/// (`models`), then the labels the user gave my segments (`mine`) — each once, in the order
/// first met, and never a [`RESERVED`] label or one of `excluded` (the names unsupervised
/// methods give their clusters: "A0", "P1 mirrors P2" are no one's vocabulary) unless the truth
/// or a model has it too. Entry `n` (0-based, below [`HOTKEYS`]) has the key `n + 1`.
pub fn vocabulary<'a>(
    truth: impl IntoIterator<Item = &'a str>,
    models: impl IntoIterator<Item = &'a str>,
    mine: impl IntoIterator<Item = &'a str>,
    excluded: &[&str],
) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    let mut add = |label: &str, check: bool| {
        let label = label.trim();
        if is_labelled(label) && !(check && excluded.contains(&label)) && !out.iter().any(|l| l == label) {
            out.push(label.to_string());
        }
    };
    truth.into_iter().for_each(|l| add(l, false));
    models.into_iter().for_each(|l| add(l, false));
    mine.into_iter().for_each(|l| add(l, true));
    out
}

/// The vocabulary entry a number key `key` ("1"…"9") gives, if any.
pub fn hotkey_label<'a>(vocabulary: &'a [String], key: &str) -> Option<&'a str> {
    let n: usize = key.parse().ok().filter(|n| (1..=HOTKEYS).contains(n))?;
    vocabulary.get(n - 1).map(String::as_str)
}

/// A stable class index for a label no other row shows (FNV-1a of its text): the same label has
/// the same colour on every take.
pub fn label_class(label: &str) -> usize {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in label.as_bytes() {
        h ^= *b as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    (h % 64) as usize
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_vocabulary_is_the_truths_and_the_models_classes_and_my_own_labels() {
        let sssm = ["A0", "B1", "P1 mirrors P2", "transition"];
        let v = vocabulary(
            ["walk", "jump", "walk", "", "transition"],
            ["Jog", "walk", "Squat", "unknown"],
            ["kick", "A0", "jump", "  spin "],
            &sssm,
        );
        assert_eq!(v, ["walk", "jump", "Jog", "Squat", "kick", "spin"]);
        // a cluster name the truth has too stays (it is a class there)
        assert_eq!(vocabulary(["A0"], [], ["A0", "B1"], &sssm), ["A0"]);
        assert!(vocabulary([], [], sssm, &[]).iter().all(|l| l != "transition"));
        assert_eq!(hotkey_label(&v, "1"), Some("walk"));
        assert_eq!(hotkey_label(&v, "6"), Some("spin"));
        assert_eq!(hotkey_label(&v, "7"), None);
        assert_eq!(hotkey_label(&v, "0"), None);
        assert_eq!(hotkey_label(&v, "a"), None);
        let many: Vec<String> = (0..12).map(|k| format!("c{k}")).collect();
        assert_eq!(hotkey_label(&many, "9"), Some("c8"));
        assert_eq!(hotkey_label(&many, "10"), None, "nine keys");
    }
}
