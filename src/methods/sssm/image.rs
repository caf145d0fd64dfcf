//! The SSSM of Krüger et al. 2017 drawn as an image for the page, like the paper's Fig. 2–3:
//! frame `i` down, frame `j` across (working frame rate), each neighbour entry of the sparse
//! self-similarity matrix as a grey pixel — black at distance 0, fading to light grey at the
//! search radius, white where frames are not neighbours — with the activity step's result drawn
//! over it (each action as a coloured square on the diagonal, each transition as an orange one)
//! and the primitive cuts as blue lines across their action's square (cuts found only in the
//! mirrored features in red).
//!
//! Pure function of an [`SssmOutcome`]: the worker renders it, the page only blits the bytes.
//! Takes longer than [`MAX_SIZE`] working frames are shrunk by square blocks (the darkest entry
//! of a block wins), so the image never exceeds `MAX_SIZE × MAX_SIZE` pixels.

use crate::methods::sssm::SssmOutcome;

/// Largest side of the image in pixels; longer takes are drawn in blocks of frames.
pub const MAX_SIZE: usize = 1500;

/// An RGBA image of the SSSM, row-major, `size × size` pixels.
#[derive(Debug, Clone, PartialEq)]
pub struct SssmImage {
    pub size: usize,
    /// Working frames per pixel along each axis (1 unless the take is longer than the maximum).
    pub block: usize,
    pub rgba: Vec<u8>,
}

const WHITE: [u8; 3] = [255, 255, 255];
/// Grey of an entry at the search radius (entries closer are darker, down to black).
const FAR_GREY: f32 = 215.0;
const TRANSITION: [u8; 3] = [230, 140, 20];
const CUT: [u8; 3] = [30, 90, 235];
const MIRROR_CUT: [u8; 3] = [215, 30, 40];
pub use crate::segment::palette::action_colour;

impl SssmImage {
    fn blank(size: usize, block: usize) -> Self {
        let mut rgba = vec![255; size * size * 4];
        for px in rgba.chunks_exact_mut(4) {
            px[..3].copy_from_slice(&WHITE);
        }
        SssmImage { size, block, rgba }
    }

    /// The pixel row/column of working frame `frame`.
    fn pixel(&self, frame: usize) -> usize {
        (frame / self.block).min(self.size - 1)
    }

    fn set(&mut self, x: usize, y: usize, colour: [u8; 3]) {
        let k = (y * self.size + x) * 4;
        self.rgba[k..k + 3].copy_from_slice(&colour);
    }

    /// Keeps the darker of the pixel's grey and `grey`.
    fn darken(&mut self, x: usize, y: usize, grey: u8) {
        let k = (y * self.size + x) * 4;
        for c in &mut self.rgba[k..k + 3] {
            *c = (*c).min(grey);
        }
    }

    /// Width in pixels of the lines drawn over the SSSM: thicker on large images, so they
    /// survive the page scaling the image down.
    fn line_width(&self) -> usize {
        1 + self.size / 400
    }

    /// The outline of the square spanning working frames `start..=end` on the diagonal (the
    /// lines lie inside it).
    fn square(&mut self, start: usize, end: usize, colour: [u8; 3]) {
        let (lo, hi) = (self.pixel(start), self.pixel(end));
        for d in 0..self.line_width().min((hi - lo) / 2 + 1) {
            let (a, b) = (lo + d, hi - d);
            for t in lo..=hi {
                for (x, y) in [(t, a), (t, b), (a, t), (b, t)] {
                    self.set(x, y, colour);
                }
            }
        }
    }

    /// A cut at working frame `cut` inside the square `start..=end`: a line across it at row
    /// `cut` and one at column `cut`.
    fn cut(&mut self, cut: usize, start: usize, end: usize, colour: [u8; 3]) {
        let (c, lo, hi) = (self.pixel(cut), self.pixel(start), self.pixel(end));
        for c in c..(c + self.line_width()).min(hi + 1) {
            for t in lo..=hi {
                self.set(t, c, colour);
                self.set(c, t, colour);
            }
        }
    }
}

/// Renders `outcome` (see the module documentation).
pub fn render(outcome: &SssmOutcome) -> SssmImage {
    render_max(outcome, MAX_SIZE)
}

/// [`render`] with at most `max_size` pixels per side.
pub fn render_max(outcome: &SssmOutcome, max_size: usize) -> SssmImage {
    let n = outcome.frames.max(1);
    let block = n.div_ceil(max_size.max(1));
    let mut image = SssmImage::blank(n.div_ceil(block), block);
    let radius = (outcome.search_radius as f32).max(f32::MIN_POSITIVE);
    let sssm = &outcome.sssm;
    for i in 0..sssm.frames().min(n) {
        let (cols, dists) = sssm.row(i);
        let y = image.pixel(i);
        for (&j, &d) in cols.iter().zip(dists) {
            let closeness = (d / radius).clamp(0.0, 1.0);
            image.darken(image.pixel(j as usize), y, (FAR_GREY * closeness) as u8);
        }
    }
    for t in &outcome.activities.transitions {
        image.square(t.start, t.end, TRANSITION);
    }
    for a in &outcome.actions {
        image.square(a.span.start, a.span.end, action_colour(a.cluster));
        let inside = |c: &&usize| a.span.start < **c && **c <= a.span.end;
        for &c in outcome.mirror_cuts.iter().filter(inside) {
            if outcome.cuts.binary_search(&c).is_err() {
                image.cut(c, a.span.start, a.span.end, MIRROR_CUT);
            }
        }
        for &c in outcome.cuts.iter().filter(inside) {
            image.cut(c, a.span.start, a.span.end, CUT);
        }
    }
    image
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::methods::sssm::{Action, Activities, Span, Sssm, SymmetryKind};

    /// 8 working frames: frames 0–3 and 4–7 repeat each other (an action with one cut at 4 and
    /// a mirror-only cut at 6); frame 0 is also a neighbour of frame 4 at half the radius.
    fn outcome(frames: usize) -> SssmOutcome {
        let lists: Vec<Vec<(u32, f32)>> = (0..frames as u32)
            .map(|i| match i {
                0 => vec![(0, 0.0), (4, 1.0)],
                4 => vec![(4, 0.0), (0, 1.0)],
                _ => vec![(i, 0.0)],
            })
            .collect();
        let sssm = Sssm::from_lists(&lists).unwrap();
        let span = Span { start: 0, end: 7 };
        SssmOutcome {
            fps: 30.0,
            frames,
            search_radius: 2.0,
            sssm,
            mirror_sssm: None,
            activities: Activities {
                actions: vec![span],
                transitions: vec![Span { start: 8, end: frames - 1 }],
                forward: vec![],
                backward_starts: vec![],
            },
            actions: vec![Action { span, cluster: 0, symmetry: SymmetryKind::Asymmetric }],
            cuts: vec![4],
            mirror_cuts: vec![4, 6],
            primitives: vec![],
            clusters: vec![],
            far_pairs: vec![],
        }
    }

    fn rgb(image: &SssmImage, x: usize, y: usize) -> [u8; 3] {
        let k = (y * image.size + x) * 4;
        [image.rgba[k], image.rgba[k + 1], image.rgba[k + 2]]
    }

    #[test]
    fn distances_regions_and_cuts_are_drawn() {
        let image = render(&outcome(12));
        assert_eq!((image.size, image.block, image.rgba.len()), (12, 1, 12 * 12 * 4));
        assert!(image.rgba.chunks_exact(4).all(|px| px[3] == 255), "opaque");
        // an entry on the diagonal inside the square is black; off-diagonal empty is white
        assert_eq!(rgb(&image, 2, 2), [0, 0, 0]);
        assert_eq!(rgb(&image, 2, 1), WHITE);
        // (0, 4) is on the cut line at column 4; (5, 1) lies off every line: white
        assert_eq!(rgb(&image, 4, 0), CUT, "lines are drawn over the entries");
        assert_eq!(rgb(&image, 2, 0), action_colour(0));
        assert_eq!(rgb(&image, 5, 1), WHITE);
        assert_eq!(rgb(&image, 4, 2), CUT);
        assert_eq!(rgb(&image, 6, 2), MIRROR_CUT);
        // the action's border and the transition's
        assert_eq!(rgb(&image, 7, 3), action_colour(0));
        assert_eq!(rgb(&image, 8, 10), TRANSITION);
        // the transition's diagonal entries inside it stay grey-black
        assert_eq!(rgb(&image, 9, 9), [0, 0, 0]);
    }

    #[test]
    fn an_entry_at_half_the_radius_is_mid_grey() {
        let mut o = outcome(12);
        o.actions.clear();
        o.activities.transitions.clear();
        let image = render(&o);
        let grey = (FAR_GREY * 0.5) as u8;
        assert_eq!(rgb(&image, 4, 0), [grey; 3]);
        assert_eq!(rgb(&image, 0, 4), [grey; 3]);
    }

    #[test]
    fn long_takes_are_drawn_in_blocks() {
        let image = render_max(&outcome(3000), 1500);
        assert_eq!((image.size, image.block), (1500, 2));
        assert_eq!(image.rgba.len(), 1500 * 1500 * 4);
        assert_eq!(render_max(&outcome(3001), 1500).size, 1001);
        // frames 0 and 4 → pixels 0 and 2; the darkest entry of each block wins
        let o = outcome(3000);
        let mut bare = o.clone();
        bare.actions.clear();
        bare.activities.transitions.clear();
        let image = render_max(&bare, 1500);
        assert_eq!(rgb(&image, 2, 0), [(FAR_GREY * 0.5) as u8; 3]);
        assert_eq!(rgb(&image, 1, 1), [0, 0, 0]);
        assert!(render(&o).size <= MAX_SIZE);
        // on a large image the lines are several pixels wide: the action's border (pixels
        // 0..=3) and the transition's (from pixel 4)
        let image = render_max(&o, 1500);
        assert_eq!(image.size / 400 + 1, 4);
        assert_eq!(rgb(&image, 100, 4), TRANSITION, "the transition starts at frame 8 = pixel 4");
        assert_eq!(rgb(&image, 100, 7), TRANSITION, "its border is 4 pixels wide");
        assert_eq!(rgb(&image, 100, 8), WHITE);
        assert_eq!(rgb(&image, 1, 0), action_colour(0));
        assert_eq!(rgb(&image, 3, 1), CUT, "the cut at frame 4 = pixel 2 is 2 pixels wide inside the action");
    }
}
