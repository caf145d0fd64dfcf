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

#[cfg(test)]
mod tests {
    use super::*;

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
