//! Text that reads on the colour it is drawn on: the timeline's segments are filled with class
//! and cluster colours of every lightness, so their labels take black or white, whichever has the
//! higher WCAG 2 contrast with the fill (never below 4.5:1, WCAG AA for normal text; issue 27).

/// The colour of a CSS colour as the page writes them: `#rgb`, `#rrggbb`, `rgb(r, g, b)` or
/// `hsl(h, s%, l%)` (the palettes of [`crate::segment::palette`]); `None` for anything else.
pub fn rgb_of(css: &str) -> Option<[u8; 3]> {
    let css = css.trim();
    if let Some(hex) = css.strip_prefix('#') {
        let digits: Vec<u8> = hex.chars().map(|c| c.to_digit(16).map(|d| d as u8)).collect::<Option<_>>()?;
        return match digits[..] {
            [r, g, b] => Some([r * 17, g * 17, b * 17]),
            [r1, r2, g1, g2, b1, b2] => Some([r1 * 16 + r2, g1 * 16 + g2, b1 * 16 + b2]),
            _ => None,
        };
    }
    let (name, args) = css.strip_suffix(')')?.split_once('(')?;
    let parts: Vec<&str> = args.split(',').map(str::trim).collect();
    let [a, b, c] = parts[..] else { return None };
    match name.trim() {
        "rgb" => {
            let byte = |s: &str| s.parse::<f64>().ok().filter(|v| (0.0..=255.0).contains(v)).map(|v| v.round() as u8);
            Some([byte(a)?, byte(b)?, byte(c)?])
        }
        "hsl" => {
            let percent = |s: &str| s.strip_suffix('%')?.parse::<f64>().ok().map(|v| (v / 100.0).clamp(0.0, 1.0));
            Some(hsl([a.parse::<f64>().ok()?, percent(b)?, percent(c)?]))
        }
        _ => None,
    }
}

/// `hsl(h, s, l)` (h in degrees, s and l in 0..=1) as bytes, by the CSS Color 4 formula.
fn hsl([h, s, l]: [f64; 3]) -> [u8; 3] {
    let h = h.rem_euclid(360.0);
    let a = s * l.min(1.0 - l);
    let f = |n: f64| {
        let k = (n + h / 30.0) % 12.0;
        let v = l - a * (k - 3.0).min(9.0 - k).clamp(-1.0, 1.0);
        (v * 255.0).round().clamp(0.0, 255.0) as u8
    };
    [f(0.0), f(8.0), f(4.0)]
}

/// The WCAG 2 relative luminance of an sRGB colour.
pub fn luminance(rgb: [u8; 3]) -> f64 {
    let linear = |c: u8| {
        let s = c as f64 / 255.0;
        if s <= 0.039_28 {
            s / 12.92
        } else {
            ((s + 0.055) / 1.055).powf(2.4)
        }
    };
    0.2126 * linear(rgb[0]) + 0.7152 * linear(rgb[1]) + 0.0722 * linear(rgb[2])
}

/// The WCAG 2 contrast ratio of two colours (1 to 21).
pub fn contrast(a: [u8; 3], b: [u8; 3]) -> f64 {
    let (la, lb) = (luminance(a), luminance(b));
    (la.max(lb) + 0.05) / (la.min(lb) + 0.05)
}

/// The text colour for a fill of `css`: black or white, whichever contrasts more (at least
/// 4.58:1 for any fill); white when the colour cannot be read.
pub fn ink_on(css: &str) -> &'static str {
    const BLACK: [u8; 3] = [0, 0, 0];
    const WHITE: [u8; 3] = [255, 255, 255];
    match rgb_of(css) {
        Some(fill) if contrast(fill, BLACK) > contrast(fill, WHITE) => "#000000",
        _ => "#ffffff",
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::segment::palette::{action_colour, class_colour, cluster_colour};

    #[test]
    fn reads_the_colours_the_page_writes() {
        assert_eq!(rgb_of("#1a202b"), Some([0x1a, 0x20, 0x2b]));
        assert_eq!(rgb_of("#333"), Some([0x33, 0x33, 0x33]));
        assert_eq!(rgb_of("rgb(0, 160, 70)"), Some([0, 160, 70]));
        assert_eq!(rgb_of("hsl(0, 100%, 50%)"), Some([255, 0, 0]));
        assert_eq!(rgb_of("hsl(120, 100%, 25%)"), Some([0, 128, 0]));
        // what Chromium computes for the SSSM primitives' hsl(275, 62%, 48%)
        assert_eq!(rgb_of("hsl(275, 62%, 48%)"), Some([135, 47, 198]));
        for bad in ["", "#12", "#gggggg", "rgb(1, 2)", "rgb(300, 0, 0)", "red", "hsl(1, 2, 3)"] {
            assert_eq!(rgb_of(bad), None, "{bad}");
        }
    }

    #[test]
    fn contrast_matches_wcag() {
        assert!((contrast([0, 0, 0], [255, 255, 255]) - 21.0).abs() < 1e-9);
        // the dark theme's old row labels: #333 on #1a202b
        assert!((contrast([0x33; 3], [0x1a, 0x20, 0x2b]) - 1.29).abs() < 0.01);
    }

    #[test]
    fn every_segment_fill_gets_readable_ink() {
        let mut fills: Vec<String> = (0..64).map(class_colour).collect();
        fills.extend((0..64).map(|c| cluster_colour(c, None)));
        fills.extend((1..64).map(|c| cluster_colour(c, Some(c - 1))));
        fills.extend((0..6).map(|c| {
            let [r, g, b] = action_colour(c);
            format!("rgb({r}, {g}, {b})")
        }));
        fills.extend(["#888", "#ffffff", "#000000", "rgb(128, 128, 128)"].map(String::from));
        fills.extend(crate::segment::palette::LABEL_PALETTE.iter().map(|[r, g, b]| format!("#{r:02x}{g:02x}{b:02x}")));
        for fill in &fills {
            let ink = rgb_of(ink_on(fill)).unwrap();
            let ratio = contrast(rgb_of(fill).unwrap(), ink);
            assert!(ratio >= 4.5, "{fill}: {} at {ratio:.2}:1", ink_on(fill));
        }
        // the old white-on-green SSSM action (3.43:1) now takes black
        assert_eq!(ink_on("rgb(0, 160, 70)"), "#000000");
        assert_eq!(ink_on("#1a202b"), "#ffffff");
    }
}
