//! Colours of segments, shared by the methods' pictures and the page's timeline rows so that a
//! segment has the same colour everywhere.

/// Colours of actions, by the action's cluster (kind of action).
const ACTION_COLOURS: [[u8; 3]; 6] =
    [[0, 160, 70], [150, 60, 200], [0, 150, 170], [200, 40, 140], [120, 150, 0], [90, 90, 220]];

/// The colour of the actions of cluster `cluster`.
pub fn action_colour(cluster: usize) -> [u8; 3] {
    ACTION_COLOURS[cluster % ACTION_COLOURS.len()]
}

/// The CSS colour of primitive cluster `cluster`: a hue per cluster, shared by a mirror pair
/// (taken from the pair's lower id), the pair's higher id lighter.
pub fn cluster_colour(cluster: usize, mirror_of: Option<usize>) -> String {
    let base = mirror_of.map_or(cluster, |m| m.min(cluster));
    let hue = (base as f64 * 137.508) % 360.0;
    let lightness = if mirror_of.is_some_and(|m| m < cluster) { 72 } else { 48 };
    format!("hsl({hue:.0}, 62%, {lightness}%)")
}

/// The CSS colour (`#rrggbb`) of class `i` of a labelling model (DT-FCN, k-NN): hues spread by
/// the golden angle, alternating lightness; a class index has the same colour in every row,
/// take and model file.
pub fn class_colour(i: usize) -> String {
    let h = (i as f64 * 137.508 + 20.0) % 360.0;
    let (s, l) = (0.65, if i % 2 == 0 { 0.45 } else { 0.55 });
    let c = (1.0 - (2.0 * l - 1.0f64).abs()) * s;
    let x = c * (1.0 - ((h / 60.0) % 2.0 - 1.0).abs());
    let m = l - c / 2.0;
    let (r, g, b) = match (h / 60.0) as u32 {
        0 => (c, x, 0.0),
        1 => (x, c, 0.0),
        2 => (0.0, c, x),
        3 => (0.0, x, c),
        4 => (x, 0.0, c),
        _ => (c, 0.0, x),
    };
    let byte = |v: f64| ((v + m) * 255.0).round().clamp(0.0, 255.0) as u8;
    format!("#{:02x}{:02x}{:02x}", byte(r), byte(g), byte(b))
}

/// The colour of an Effort factor's value `v` (−1 fully indulging … +1 fully condensing): blue
/// through grey to red, as LMA's "Effort of each segment" picture and the page's Effort bars under
/// every row draw it (a value out of range is clamped; not a number is neutral).
pub fn effort_colour(v: f64) -> [u8; 3] {
    let v = if v.is_nan() { 0.0 } else { v };
    let t = ((v + 1.0) / 2.0).clamp(0.0, 1.0);
    [(40.0 + 180.0 * t) as u8, (90.0 + 60.0 * (1.0 - (2.0 * t - 1.0).abs())) as u8, (220.0 - 180.0 * t) as u8]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn effort_runs_from_blue_through_grey_to_red() {
        assert_eq!(effort_colour(-1.0), [40, 90, 220], "indulging: blue");
        assert_eq!(effort_colour(0.0), [130, 150, 130], "neutral: grey-green middle");
        assert_eq!(effort_colour(1.0), [220, 90, 40], "condensing: red");
        assert_eq!(effort_colour(-7.0), effort_colour(-1.0), "clamped");
        assert_eq!(effort_colour(f64::NAN), effort_colour(0.0));
        // redder (and less blue) as the value grows
        let (a, b) = (effort_colour(-0.2), effort_colour(0.4));
        assert!(b[0] > a[0] && b[2] < a[2], "{a:?} {b:?}");
    }

    #[test]
    fn mirror_pairs_share_a_hue() {
        let (a, b, c) = (cluster_colour(0, Some(2)), cluster_colour(1, None), cluster_colour(2, Some(0)));
        let hue = |s: &str| s.split(',').next().unwrap().to_string();
        assert_eq!(hue(&a), hue(&c));
        assert_ne!(a, c);
        assert_ne!(hue(&a), hue(&b));
        assert_eq!(action_colour(0), action_colour(6));
    }
}
