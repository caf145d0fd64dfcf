//! Acclaim ASF (skeleton) + AMC (motion) files, the format of the CMU motion capture database
//! originals, read into the same [`Bvh`](crate::bvh::Bvh) the BVH parser gives, so everything
//! downstream (`Motion`, the methods, clip export) treats both alike.
//!
//! * [`asf`] reads the skeleton: `:units` (length multiplier, `deg`/`rad`), `:root` (the order of
//!   the root's AMC values, its axis, position and orientation), `:bonedata` (each bone's
//!   direction and length in the global rest frame, its `axis` — a local frame given by Euler
//!   angles in a named order —, its `dof`s and `limits`) and `:hierarchy`.
//! * [`amc`] reads the motion: `:FULLY-SPECIFIED`, `:DEGREES`/`:RADIANS`, then per frame its
//!   number and one line per bone with that bone's dof values in the ASF's order.
//! * [`convert`] makes the BVH: one node per bone at the bone's start (the root at the origin),
//!   its OFFSET the parent bone's vector (direction × length, as the CMU BVH conversions do, in
//!   ASF units); each leaf bone's vector an End Site. A bone's rotation in its parent's frame is
//!   C·M·C⁻¹ (C from its `axis`, M = the AMC rotations about the axes of C's frame, X then Y
//!   then Z), written as `Zrotation Yrotation Xrotation`; the root adds its translation.
//!   AMC files carry no frame rate: 120 fps (the CMU rate) unless the caller says otherwise.
//!
//! Every error names the line and column of the file it is in (the ASF or the AMC).

pub mod amc;
pub mod asf;
pub mod convert;

pub use amc::{parse_amc, Amc};
pub use asf::{parse_asf, Asf};
pub use convert::{to_bvh, CMU_FPS};

/// The tokens of one line with their 1-based columns (in characters), comments (`#`) removed.
pub(crate) fn tokens(line: &str) -> Vec<(usize, &str)> {
    let line = line.split('#').next().unwrap_or("");
    let mut out = Vec::new();
    let mut start: Option<(usize, usize)> = None;
    for (column, (byte, c)) in (1..).zip(line.char_indices()) {
        if c.is_whitespace() {
            if let Some((b, col)) = start.take() {
                out.push((col, &line[b..byte]));
            }
        } else if start.is_none() {
            start = Some((byte, column));
        }
    }
    if let Some((b, col)) = start {
        out.push((col, &line[b..]));
    }
    out
}

/// A finite number, or `None`.
pub(crate) fn number(text: &str) -> Option<f64> {
    text.parse::<f64>().ok().filter(|v| v.is_finite())
}

/// The lines of a text with their 1-based numbers: LF, CRLF or lone CR breaks, like the BVH parser.
pub(crate) fn lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    text.split('\n').flat_map(|l| l.strip_suffix('\r').unwrap_or(l).split('\r')).enumerate().map(|(i, l)| (i + 1, l))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tokens_have_character_columns_and_comments_end_them() {
        assert_eq!(tokens("  dof rx  ry # rz"), vec![(3, "dof"), (7, "rx"), (11, "ry")]);
        assert_eq!(tokens("äb c"), vec![(1, "äb"), (4, "c")]);
        assert!(tokens("# only a comment").is_empty());
    }

    #[test]
    fn lines_count_every_kind_of_break() {
        let numbered: Vec<_> = lines("a\r\nb\rc\nd").collect();
        assert_eq!(numbered, vec![(1, "a"), (2, "b"), (3, "c"), (4, "d")]);
    }
}
