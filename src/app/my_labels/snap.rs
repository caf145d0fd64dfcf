//! Where a dragged boundary of my labels lands, natively tested: the other rows' cuts ([`cuts_of`]), the
//! nearest of them within [`SNAP_PX`] pixels and never more than [`SNAP_MAX_FRAMES`] frames ([`snap_reach`] in
//! frames at the zoom), else the frame under the pointer ([`snap`]). Snapping is on by default; the row's toggle
//! (`#my-labels-snap`) or a held Alt (or Shift) turns it off.

/// A dragged boundary snaps to another row's boundary this near, in CSS pixels…
pub const SNAP_PX: f64 = 8.0;
/// …and never farther than this many frames, whatever the zoom (8 px are 50 frames of a 10 000-frame take seen
/// whole: a boundary dropped on the frame it was meant for must stay there).
pub const SNAP_MAX_FRAMES: f64 = 3.0;

/// How far (frames) a dragged boundary reaches for another row's boundary, for a window `span` frames wide drawn over
/// `width_px` pixels: [`SNAP_PX`] pixels, at most [`SNAP_MAX_FRAMES`].
pub fn snap_reach(span: f64, width_px: f64) -> f64 {
    snap_tolerance(SNAP_PX, span, width_px).min(SNAP_MAX_FRAMES)
}

/// The cuts of other rows' segments (`(start, end)` inclusive): each start and each end + 1,
/// sorted, once each — what a dragged boundary snaps to.
pub fn cuts_of<'a>(rows: impl IntoIterator<Item = &'a [(usize, usize)]>) -> Vec<usize> {
    let mut cuts: Vec<usize> = rows.into_iter().flatten().flat_map(|&(s, e)| [s, e + 1]).collect();
    cuts.sort_unstable();
    cuts.dedup();
    cuts
}

/// [`SNAP_PX`]-like `pixels` in frames, for a window `span` frames wide drawn over `width_px` pixels.
pub fn snap_tolerance(pixels: f64, span: f64, width_px: f64) -> f64 {
    if !(pixels > 0.0 && span > 0.0 && width_px > 0.0) || !span.is_finite() || !width_px.is_finite() {
        return 0.0;
    }
    pixels * span / width_px
}

/// The cut a boundary dragged to frame position `at` (fractional) lands on: the nearest of
/// `targets` (sorted) within `tolerance` frames — of two equally near, the earlier — else `at`
/// rounded to the nearest cut. Never negative.
pub fn snap(at: f64, targets: &[usize], tolerance: f64) -> usize {
    let at = if at.is_finite() { at.max(0.0) } else { 0.0 };
    let mut best: Option<(f64, usize)> = None;
    // the targets either side of `at` are the only candidates
    let i = targets.partition_point(|&t| (t as f64) < at);
    for &t in targets[i.saturating_sub(1)..(i + 1).min(targets.len())].iter() {
        let d = (t as f64 - at).abs();
        if d <= tolerance && best.is_none_or(|(bd, _)| d < bd) {
            best = Some((d, t));
        }
    }
    best.map_or(at.round() as usize, |(_, t)| t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_dragged_boundary_snaps_to_the_nearest_cut_within_the_tolerance() {
        let targets = cuts_of([&[(0, 9), (10, 29)][..], &[(5, 14), (40, 99)][..]]);
        assert_eq!(targets, vec![0, 5, 10, 15, 30, 40, 100]);
        assert_eq!(snap(12.2, &targets, 3.0), 10);
        assert_eq!(snap(13.6, &targets, 3.0), 15);
        assert_eq!(snap(12.5, &targets, 3.0), 10, "a tie: the earlier");
        assert_eq!(snap(22.4, &targets, 3.0), 22, "none near: rounded");
        assert_eq!(snap(22.6, &targets, 3.0), 23);
        assert_eq!(snap(27.0, &targets, 3.0), 30, "exactly at the tolerance snaps");
        assert_eq!(snap(-4.0, &targets, 1.0), 0);
        assert_eq!(snap(f64::NAN, &targets, 1.0), 0);
        assert_eq!(snap(103.0, &targets, 2.0), 103, "past the take: the model clamps it");
        assert_eq!(snap(7.0, &[], 10.0), 7);
        // 8 px on a 1000-px lane showing 2000 frames: 16 frames; zoomed to 100 frames: 0.8
        assert_eq!(snap_tolerance(SNAP_PX, 2000.0, 1000.0), 16.0);
        assert!((snap_tolerance(SNAP_PX, 100.0, 1000.0) - 0.8).abs() < 1e-12);
        assert_eq!(snap_tolerance(SNAP_PX, 100.0, 0.0), 0.0);
        // the reach: a few frames at any zoom — at full view of a long take, 3 frames, not 16 or 50
        assert_eq!(snap_reach(2000.0, 1000.0), SNAP_MAX_FRAMES);
        assert_eq!(snap_reach(10_000.0, 1600.0), SNAP_MAX_FRAMES);
        assert!((snap_reach(100.0, 1000.0) - 0.8).abs() < 1e-12, "zoomed in: 8 px");
        // the true walk → look_around change at 1020 of 86_01, the boundary dropped 3 px away at full view (6.5
        // frames a pixel) on a row whose next cut is 1047: it stays where it was dropped
        assert_eq!(snap(1040.0, &[1020, 1047], snap_reach(10_458.0, 1600.0)), 1040);
        assert_eq!(snap(1021.0, &[1020, 1047], snap_reach(10_458.0, 1600.0)), 1020);
        assert_eq!(
            snap(12.0, &targets, snap_tolerance(SNAP_PX, 100.0, 1000.0)),
            12,
            "zoomed in: no snap 2 frames away"
        );
    }
}
