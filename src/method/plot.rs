//! A line plot of per-frame curves as a [`Picture`], for methods whose work is a signal over time
//! (hand speed, limb displacement, projection error): the curves, horizontal threshold lines
//! (dashed grey) and the cuts (black), time across at the working rate.

use super::Picture;

/// Height in pixels of a plot.
pub const HEIGHT: usize = 120;
/// Widest plot in pixels (longer series put several frames in a column, keeping the highest).
pub const MAX_WIDTH: usize = 1500;

/// One curve: its values (one per working frame) and its colour.
pub struct Series<'a> {
    pub values: &'a [f32],
    pub colour: [u8; 3],
}

/// Plots `series` (all as long as the first) with `thresholds` and `cuts` (working frames).
/// The vertical axis runs from 0 to the largest value or threshold (×1.2 for a threshold).
pub fn lines(id: &str, title: &str, caption: &str, series: &[Series], thresholds: &[f32], cuts: &[usize]) -> Picture {
    let n = series.first().map_or(0, |s| s.values.len()).max(1);
    let per_column = n.div_ceil(MAX_WIDTH).max(1);
    let width = n.div_ceil(per_column);
    let top = thresholds.iter().map(|t| t * 1.2).chain(series.iter().flat_map(|s| s.values.iter().copied()));
    let top = top.filter(|v| v.is_finite()).fold(f32::MIN_POSITIVE, f32::max);
    let y_of = |v: f32| HEIGHT - 1 - ((v / top).clamp(0.0, 1.0) * (HEIGHT - 1) as f32).round() as usize;
    let mut rgba = vec![255u8; width * HEIGHT * 4];
    let mut set = |x: usize, y: usize, c: [u8; 3]| {
        let k = (y * width + x) * 4;
        rgba[k..k + 3].copy_from_slice(&c);
    };
    for &t in thresholds {
        let y = y_of(t);
        (0..width).filter(|x| x % 4 < 2).for_each(|x| set(x, y, [185; 3]));
    }
    for &c in cuts.iter().filter(|&&c| c < n) {
        (0..HEIGHT).for_each(|y| set(c / per_column, y, [40, 40, 40]));
    }
    for s in series {
        let mut last: Option<usize> = None;
        for x in 0..width {
            let chunk = &s.values[(x * per_column).min(s.values.len())..((x + 1) * per_column).min(s.values.len())];
            let Some(v) = chunk.iter().copied().filter(|v| v.is_finite()).reduce(f32::max) else { continue };
            let y = y_of(v);
            // a connected line: every pixel between the previous column's height and this one
            let (a, b) = last.map_or((y, y), |l| (l.min(y), l.max(y)));
            (a..=b).for_each(|yy| set(x, yy, s.colour));
            last = Some(y);
        }
    }
    let scale = if per_column > 1 { format!(" ({per_column} frames per pixel)") } else { String::new() };
    Picture {
        id: id.into(),
        title: title.into(),
        caption: format!("{caption} Vertical axis 0 to {top:.0}{scale}."),
        width,
        height: HEIGHT,
        rgba,
        frames_per_pixel: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_plot_has_its_curve_thresholds_and_cuts() {
        let values: Vec<f32> = (0..100).map(|i| i as f32).collect();
        let p = lines("p", "t", "c.", &[Series { values: &values, colour: [255, 0, 0] }], &[50.0], &[30]);
        assert_eq!((p.width, p.height, p.rgba.len()), (100, HEIGHT, 100 * HEIGHT * 4));
        let at = |x: usize, y: usize| &p.rgba[(y * p.width + x) * 4..(y * p.width + x) * 4 + 3];
        assert_eq!(at(99, 0), [255, 0, 0], "the largest value is at the top");
        assert_eq!(at(0, HEIGHT - 1), [255, 0, 0], "zero at the bottom");
        assert_eq!(at(30, 5), [40, 40, 40], "the cut");
        let long: Vec<f32> = vec![1.0; 4000];
        let p = lines("p", "t", "c.", &[Series { values: &long, colour: [0, 0, 255] }], &[], &[]);
        assert_eq!(p.width, 1334);
        assert!(p.caption.contains("3 frames per pixel"));
        let empty = lines("p", "t", "c.", &[], &[], &[]);
        assert_eq!(empty.rgba.len(), empty.width * empty.height * 4);
    }
}
