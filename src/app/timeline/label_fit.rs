//! A segment's text on a timeline row that fits its width: the full label when it fits, else a
//! clean abbreviation — never a word chopped at whatever letter the box ends on ("unkn", "Kne"),
//! which reads as another word. The full label stays in the segment's tooltip and `aria-label`.
//!
//! The candidates, best first: the whole label; its leading whole words and "…" ("left arm…");
//! the first syllable of its first word and "…" ("Jum…"); nothing (the segment shows its colour
//! alone — one colour per label on every row, so the colour still says which). The first that fits
//! is drawn. Initials are not offered: "BA", "RA", "LA" for LMA's arms read as nothing (issue 48).
//!
//! The browser measures text only once it is laid out, and a row of a long take has hundreds of
//! segments, so widths are *estimated* from the font size: each character class has a width in
//! ems a little over what common sans-serif faces give it (so an estimate that fits does fit; the
//! page's e2e test checks every segment's text against its box in a real browser).

/// Width of `c` in ems, slightly over the common sans-serif faces' (Helvetica, Arial, DejaVu
/// Sans, Segoe UI at the sizes the timeline uses).
fn char_em(c: char) -> f64 {
    match c {
        'i' | 'j' | 'l' | '.' | ',' | ':' | ';' | '\'' | '|' | '!' | 'I' | ' ' => 0.34,
        'f' | 't' | 'r' | '(' | ')' | '[' | ']' | '-' => 0.42,
        'm' | 'w' => 0.92,
        'M' | 'W' => 1.0,
        '…' => 1.0,
        '0'..='9' => 0.64,
        c if c.is_ascii_uppercase() => 0.76,
        c if c.is_ascii_lowercase() => 0.62,
        // anything else (accents, other scripts, symbols): as wide as a wide capital
        _ => 1.0,
    }
}

/// The estimated width of `text` in CSS pixels at `font_px`.
pub fn text_px(text: &str, font_px: f64) -> f64 {
    text.chars().map(char_em).sum::<f64>() * font_px
}

/// The first syllable of `word`: its letters up to the first consonant after its first vowel
/// ("Jumping" → "Jum", "unknown" → "un"); `None` when that is a single letter, the whole word or all of it but
/// its last letter.
fn first_syllable(word: &str) -> Option<String> {
    let vowel = |c: char| "aeiouyAEIOUY".contains(c);
    let chars: Vec<char> = word.chars().collect();
    let first_vowel = chars.iter().position(|&c| vowel(c))?;
    let end = chars[first_vowel..].iter().position(|&c| !vowel(c)).map(|k| first_vowel + k + 1)?;
    // a syllable one letter short of its word reads as the word misspelt ("bot…" for "both"): not offered
    (end > 1 && end + 1 < chars.len() && chars[..end].iter().all(|c| c.is_alphanumeric()))
        .then(|| chars[..end].iter().collect())
}

/// The text to draw for `label` in `width_px` CSS pixels of text at `font_px` (the box's padding
/// already taken off), or `None` when nothing readable fits.
pub fn fit_label(label: &str, width_px: f64, font_px: f64) -> Option<String> {
    let label = label.trim();
    if label.is_empty() || !(width_px > 0.0) || !(font_px > 0.0) {
        return None;
    }
    let fits = |t: &str| text_px(t, font_px) <= width_px;
    if fits(label) {
        return Some(label.to_string());
    }
    let words: Vec<&str> = label.split_whitespace().collect();
    // leading whole words, as many as fit
    for n in (1..words.len()).rev() {
        let text = format!("{}…", words[..n].join(" "));
        if fits(&text) {
            return Some(text);
        }
    }
    words.first().and_then(|w| first_syllable(w)).map(|syllable| format!("{syllable}…")).filter(|t| fits(t))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_label_that_fits_is_whole() {
        assert_eq!(fit_label("Squat", 200.0, 11.0).as_deref(), Some("Squat"));
        assert_eq!(fit_label("  walk ", 200.0, 11.0).as_deref(), Some("walk"));
        // exactly its estimated width fits
        let w = text_px("Knee lift", 11.0);
        assert_eq!(fit_label("Knee lift", w, 11.0).as_deref(), Some("Knee lift"));
        assert_ne!(fit_label("Knee lift", w - 0.01, 11.0).as_deref(), Some("Knee lift"));
    }

    #[test]
    fn a_long_label_keeps_whole_words_then_a_syllable_never_initials() {
        let font = 11.0;
        let label = "left arm raise";
        assert_eq!(fit_label(label, text_px("left arm…", font), font).as_deref(), Some("left arm…"));
        assert_eq!(fit_label(label, text_px("left…", font) + 1.0, font).as_deref(), Some("left…"));
        // LMA's arms: "both…" or colour alone, never "BA"
        assert_eq!(fit_label("both arms", text_px("both…", font), font).as_deref(), Some("both…"));
        assert_eq!(fit_label("both arms", text_px("BA", font), font), None);
        assert_eq!(
            fit_label("both arms", text_px("bot…", font), font),
            None,
            "no syllable one letter short of the word"
        );
        assert_eq!(fit_label(label, text_px("LAR", font), font), None);
        assert_eq!(fit_label("P1 mirrors P2", text_px("P1…", font), font).as_deref(), Some("P1…"));
        // one word: its first syllable, never the letters that happen to fit
        assert_eq!(fit_label("unknown", text_px("unkn", font), font).as_deref(), Some("un…"));
        assert_eq!(fit_label("Jumping", text_px("Jumpin", font), font).as_deref(), Some("Jum…"));
        assert_eq!(fit_label("Kneel", text_px("Kne", font), font), None, "no syllable shorter than the word fits");
    }

    #[test]
    fn nothing_is_drawn_when_nothing_readable_fits() {
        assert_eq!(fit_label("Jumping", 5.0, 11.0), None);
        assert_eq!(fit_label("Jumping", 0.0, 11.0), None);
        assert_eq!(fit_label("Jumping", f64::NAN, 11.0), None);
        assert_eq!(fit_label("", 100.0, 11.0), None);
        assert_eq!(fit_label("Jog", 100.0, 0.0), None);
        // a single-letter label is whole or nothing
        assert_eq!(fit_label("A", 100.0, 11.0).as_deref(), Some("A"));
        assert_eq!(fit_label("A", 2.0, 11.0), None);
    }

    #[test]
    fn every_text_drawn_fits_and_is_a_word_prefix_or_a_syllable() {
        let labels = ["unknown", "Knee lift", "Jog", "Squat", "P1 mirrors P2", "transition", "A0", "left arm", "Twist"];
        for label in labels {
            for width in (0..200).map(|w| w as f64 * 0.7) {
                let Some(text) = fit_label(label, width, 11.0) else { continue };
                assert!(text_px(&text, 11.0) <= width, "{label} at {width}: {text}");
                let clean = text == label
                    || text.strip_suffix('…').is_some_and(|p| {
                        label.starts_with(p)
                            && (label[p.len()..].starts_with(' ')
                                || first_syllable(label.split(' ').next().unwrap()).as_deref() == Some(p))
                    });
                assert!(clean, "{label} at {width}: {text}");
            }
        }
    }
}
