//! Clips: each segment of a segmentation as a BVH file of its own, cut from the take's parsed
//! file — the same hierarchy (joints, offsets, channels in their order) and the same frame time,
//! the segment's frame rows unchanged (the writer round-trips every value bit-exactly) — or,
//! on request, moved so that the clip starts at the origin facing +Z (the root's first-frame
//! floor position subtracted and the whole clip turned about the up axis; heights kept).

use crate::bvh::{Bvh, Channel, JointKind};
use crate::motion::fk::local_rotation;
use crate::motion::joints::map_joints;
use crate::motion::normalize::{facing_yaw, to_y_up};
use crate::motion::{Motion, UpAxis};
use crate::segment::{Level, Segment, Segmentation};
use glam::{DQuat, DVec3, EulerRot};

/// Why clips could not be cut.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ClipError {
    #[error("the segmentation is of a take of {segmentation} frames, this take has {take}: is it the take it was made from?")]
    OtherTake { segmentation: usize, take: usize },
    #[error("segment frames {start}–{end} are not inside the take (0–{last})")]
    Outside { start: usize, end: usize, last: usize },
    #[error("the segmentation has no {0} segments")]
    Nothing(String),
    #[error("the segmentation has no {which} segment at frames {start}–{end}")]
    NoSegment { which: String, start: usize, end: usize },
    #[error("cannot move the clip to the origin: {0}")]
    Origin(String),
    #[error("cannot write the zip: {0}")]
    Zip(String),
}

/// Which segments become clips (and rows of a label CSV: [`crate::labels::from_segmentation`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Which {
    /// Actions (transitions between them are left out).
    Actions,
    Primitives,
    /// Every segment, transitions included.
    All,
}

impl Which {
    /// Whether a segment of `level` is chosen.
    pub fn takes(self, level: Level) -> bool {
        match self {
            Which::Actions => level == Level::Action,
            Which::Primitives => level == Level::Primitive,
            Which::All => true,
        }
    }

    fn name(self) -> &'static str {
        match self {
            Which::Actions => "action",
            Which::Primitives => "primitive",
            Which::All => "",
        }
    }
}

/// How to cut.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ClipOptions {
    pub which: Which,
    /// Start each clip at the origin facing +Z (Y-up files; in a Z-up file the same heading is −Y).
    pub to_origin: bool,
}

impl Default for ClipOptions {
    fn default() -> Self {
        ClipOptions { which: Which::Actions, to_origin: false }
    }
}

/// One clip: its file name and its BVH.
#[derive(Debug, Clone, PartialEq)]
pub struct Clip {
    pub file: String,
    pub segment: Segment,
    pub bvh: Bvh,
}

/// Frames `start..=end` of `bvh` as a BVH of their own (same hierarchy and frame time).
pub fn cut(bvh: &Bvh, start: usize, end: usize) -> Result<Bvh, ClipError> {
    let frames = bvh.frames();
    if start > end || end >= frames {
        return Err(ClipError::Outside { start, end, last: frames.saturating_sub(1) });
    }
    let c = bvh.channels_per_frame;
    Ok(Bvh {
        joints: bvh.joints.clone(),
        frame_time: bvh.frame_time,
        declared_frames: end - start + 1,
        channels_per_frame: c,
        values: if c == 0 { Vec::new() } else { bvh.values[start * c..(end + 1) * c].to_vec() },
        warnings: Vec::new(),
    })
}

/// The Euler order of three distinct rotation channels, as BVH reads them (R = R1 · R2 · R3).
fn euler_order(axes: [usize; 3]) -> Option<EulerRot> {
    Some(match axes {
        [0, 1, 2] => EulerRot::XYZ,
        [0, 2, 1] => EulerRot::XZY,
        [1, 0, 2] => EulerRot::YXZ,
        [1, 2, 0] => EulerRot::YZX,
        [2, 0, 1] => EulerRot::ZXY,
        [2, 1, 0] => EulerRot::ZYX,
        _ => return None,
    })
}

/// Angles in degrees, in channel order, of `q` for rotation channels about `axes`.
pub fn euler_degrees(q: DQuat, axes: [usize; 3]) -> Option<[f64; 3]> {
    let (a, b, c) = q.to_euler(euler_order(axes)?);
    Some([a.to_degrees(), b.to_degrees(), c.to_degrees()])
}

/// Moves `clip` (frames of `motion` from `first`) so that its first frame's root stands at the
/// origin of the floor and the body faces +Z: every root's channels are rewritten.
fn to_origin(clip: &mut Bvh, motion: &Motion, first: usize) -> Result<(), ClipError> {
    let map = map_joints(&motion.skeleton)
        .map_err(|e| ClipError::Origin(format!("no facing without hips and shoulders: {e}")))?;
    let frame: Vec<_> = motion.frame(first).iter().map(|p| to_y_up(*p, motion.up_axis)).collect();
    let yaw = facing_yaw(&frame, &map)
        .ok_or_else(|| ClipError::Origin("hips and shoulders give no facing in the first frame".into()))?;
    let up = match motion.up_axis {
        UpAxis::Y => DVec3::Y,
        UpAxis::Z => DVec3::Z,
    };
    let turn = DQuat::from_axis_angle(up, -(yaw as f64));
    let c = clip.channels_per_frame;
    let frames = clip.frames();
    let roots: Vec<usize> = (0..clip.joints.len()).filter(|&j| clip.joints[j].kind == JointKind::Root).collect();
    for r in roots {
        let joint = clip.joints[r].clone();
        let slots: Vec<(Channel, usize)> =
            joint.channels.iter().enumerate().map(|(i, &ch)| (ch, joint.channel_start + i)).collect();
        let rotations: Vec<(Channel, usize)> = slots.iter().copied().filter(|(ch, _)| ch.is_rotation()).collect();
        let positions: Vec<(Channel, usize)> = slots.iter().copied().filter(|(ch, _)| !ch.is_rotation()).collect();
        let axes: Option<[usize; 3]> = match rotations.as_slice() {
            [a, b, c] => Some([a.0.axis(), b.0.axis(), c.0.axis()]),
            _ => None,
        };
        let Some(axes) = axes.filter(|a| euler_order(*a).is_some()) else {
            return Err(ClipError::Origin(format!(
                "root `{}` does not have three rotation channels to turn",
                joint.name
            )));
        };
        if !(positions.is_empty() || positions.len() == 3) {
            return Err(ClipError::Origin(format!("root `{}` has only some position channels", joint.name)));
        }
        let position = |row: &[f64]| {
            let mut p = DVec3::from(joint.offset);
            for &(ch, slot) in &positions {
                p[ch.axis()] = row[slot];
            }
            p
        };
        // the first frame's root on the floor: its horizontal position
        let start = position(&clip.values[..c]);
        let floor = start - up * start.dot(up);
        let channels: Vec<Channel> = rotations.iter().map(|r| r.0).collect();
        for f in 0..frames {
            let row = &mut clip.values[f * c..(f + 1) * c];
            let values: Vec<f64> = rotations.iter().map(|r| row[r.1]).collect();
            let rotation = turn * local_rotation(&channels, &values);
            let angles = euler_degrees(rotation, axes).expect("three distinct axes");
            for (&(_, slot), v) in rotations.iter().zip(angles) {
                row[slot] = v;
            }
            let moved = turn * (position(row) - floor);
            if positions.is_empty() {
                clip.joints[r].offset = moved.to_array();
            } else {
                for &(ch, slot) in &positions {
                    row[slot] = moved[ch.axis()];
                }
            }
        }
    }
    Ok(())
}

/// The stem clips of the file `name` are named after: its name without folders and extension
/// (`take` when nothing is left).
pub fn stem_of(name: &str) -> String {
    let base = name.rsplit(['/', '\\']).next().unwrap_or(name);
    let stem = match base.rsplit_once('.') {
        Some((stem, _)) if !stem.is_empty() => stem,
        _ => base,
    };
    if stem.is_empty() {
        "take".to_string()
    } else {
        stem.to_string()
    }
}

/// A file name for a clip: `<stem>_<nn>_<label>.bvh`, the label reduced to letters, digits, `-`
/// and `_` (so any label is a safe file name).
pub fn clip_file_name(stem: &str, index: usize, count: usize, label: &str) -> String {
    let safe: String =
        label.chars().map(|c| if c.is_alphanumeric() || c == '-' || c == '_' { c } else { '_' }).take(60).collect();
    let width = count.to_string().len().max(2);
    let label = if safe.trim_matches('_').is_empty() { "segment".to_string() } else { safe };
    format!("{stem}_{:0width$}_{label}.bvh", index + 1)
}

/// The segments `which` chooses, in order of their frames (the clips' numbering).
fn chosen(segmentation: &Segmentation, which: Which) -> Result<Vec<&Segment>, ClipError> {
    let mut chosen: Vec<&Segment> = segmentation.segments.iter().filter(|s| which.takes(s.level)).collect();
    chosen.sort_by_key(|s| (s.start, s.end));
    if chosen.is_empty() {
        return Err(ClipError::Nothing(which.name().to_string()));
    }
    Ok(chosen)
}

/// Every chosen segment of `segmentation` as a clip of the take (`bvh`, its `motion`), named
/// after `stem`.
pub fn clips(
    bvh: &Bvh,
    motion: &Motion,
    segmentation: &Segmentation,
    stem: &str,
    options: &ClipOptions,
) -> Result<Vec<Clip>, ClipError> {
    if segmentation.frames != bvh.frames() {
        return Err(ClipError::OtherTake { segmentation: segmentation.frames, take: bvh.frames() });
    }
    let chosen = chosen(segmentation, options.which)?;
    chosen
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let mut clip = cut(bvh, s.start, s.end)?;
            if options.to_origin {
                to_origin(&mut clip, motion, s.start)?;
            }
            Ok(Clip { file: clip_file_name(stem, i, chosen.len(), &s.label), segment: (*s).clone(), bvh: clip })
        })
        .collect()
}

/// Every clip as BVH text in one zip (deflated), named by [`Clip::file`].
pub fn zip(clips: &[Clip]) -> Result<Vec<u8>, ClipError> {
    use std::io::Write;
    let zip_error = |e: &dyn std::fmt::Display| ClipError::Zip(e.to_string());
    let mut writer = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let options = zip::write::SimpleFileOptions::default().compression_method(zip::CompressionMethod::Deflated);
    for clip in clips {
        writer.start_file(clip.file.as_str(), options).map_err(|e| zip_error(&e))?;
        writer.write_all(crate::bvh::write(&clip.bvh).as_bytes()).map_err(|e| zip_error(&e))?;
    }
    Ok(writer.finish().map_err(|e| zip_error(&e))?.into_inner())
}

/// What [`export`] makes: one file to save.
#[derive(Debug, Clone, PartialEq)]
pub struct Export {
    /// The file's name: `<stem>_<which>_clips.zip`, or the one clip's own name.
    pub file: String,
    pub bytes: Vec<u8>,
    /// How many clips it holds.
    pub clips: usize,
}

/// The chosen segments of `segmentation` as one file: every clip in a zip, or — `only` naming a
/// segment's frames `(start, end)` — that segment's clip alone as a BVH (named as in the zip).
/// What the page's clip exports save; the command line writes the same clips (`mocapseg clips`).
pub fn export(
    bvh: &Bvh,
    motion: &Motion,
    segmentation: &Segmentation,
    stem: &str,
    options: &ClipOptions,
    only: Option<(usize, usize)>,
) -> Result<Export, ClipError> {
    match only {
        None => {
            let all = clips(bvh, motion, segmentation, stem, options)?;
            let name = match options.which.name() {
                "" => "all".to_string(),
                level => format!("{level}s"),
            };
            Ok(Export { file: format!("{stem}_{name}_clips.zip"), bytes: zip(&all)?, clips: all.len() })
        }
        Some((start, end)) => {
            if segmentation.frames != bvh.frames() {
                return Err(ClipError::OtherTake { segmentation: segmentation.frames, take: bvh.frames() });
            }
            let chosen = chosen(segmentation, options.which)?;
            let (index, segment) = chosen
                .iter()
                .enumerate()
                .find(|(_, s)| s.start == start && s.end == end)
                .ok_or_else(|| ClipError::NoSegment { which: options.which.name().to_string(), start, end })?;
            let mut clip = cut(bvh, start, end)?;
            if options.to_origin {
                to_origin(&mut clip, motion, start)?;
            }
            let file = clip_file_name(stem, index, chosen.len(), &segment.label);
            Ok(Export { file, bytes: crate::bvh::write(&clip).into_bytes(), clips: 1 })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn euler_angles_rebuild_the_rotation_in_every_channel_order() {
        let q = DQuat::from_axis_angle(DVec3::new(0.3, -1.0, 0.6).normalize(), 2.1);
        for axes in [[0, 1, 2], [0, 2, 1], [1, 0, 2], [1, 2, 0], [2, 0, 1], [2, 1, 0]] {
            let channels: Vec<Channel> =
                axes.iter().map(|&a| [Channel::Xrotation, Channel::Yrotation, Channel::Zrotation][a]).collect();
            let back = local_rotation(&channels, &euler_degrees(q, axes).unwrap());
            assert!(back.dot(q).abs() > 1.0 - 1e-12, "{axes:?}");
        }
        assert!(euler_degrees(q, [0, 0, 1]).is_none());
    }

    #[test]
    fn a_stem_leaves_out_folders_and_the_extension() {
        assert_eq!(stem_of("86_01.bvh"), "86_01");
        assert_eq!(stem_of("a/b\\c.d.amc"), "c.d");
        assert_eq!(stem_of(".bvh"), ".bvh");
        assert_eq!(stem_of("dir/"), "take");
    }

    #[test]
    fn clip_names_are_safe_numbered_and_sortable() {
        assert_eq!(clip_file_name("86_01", 0, 7, "walk"), "86_01_01_walk.bvh");
        assert_eq!(clip_file_name("t", 9, 120, "<img src=x>/../a b"), "t_010__img_src_x_____a_b.bvh");
        assert_eq!(clip_file_name("t", 0, 3, "///"), "t_01_segment.bvh");
    }
}
