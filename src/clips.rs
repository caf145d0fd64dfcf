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

/// Zips made one at a time, joined into one archive (issue 49: a library's clips zipped one take at a time): each
/// part's local entries are kept byte for byte where they come (the page keeps them as a Blob's parts, never in one
/// buffer), its central directory's records moved by the bytes before it; [`ZipJoin::finish`] gives the central
/// directory and its end record. Parts are archives as [`zip`] writes them; the archive stays a plain zip (at most
/// 65 535 entries and 4 GiB: past them a part is refused, saying so).
#[derive(Debug, Default)]
pub struct ZipJoin {
    /// Bytes of the local entries so far (where the next part starts).
    offset: u64,
    central: Vec<u8>,
    entries: u64,
}

fn u16_at(b: &[u8], at: usize) -> Option<u64> {
    Some(u16::from_le_bytes(b.get(at..at + 2)?.try_into().ok()?) as u64)
}

fn u32_at(b: &[u8], at: usize) -> Option<u64> {
    Some(u32::from_le_bytes(b.get(at..at + 4)?.try_into().ok()?) as u64)
}

impl ZipJoin {
    pub fn new() -> ZipJoin {
        ZipJoin::default()
    }

    /// Adds the archive `part`: its local entries, to append after those before (the bytes returned, a slice of it).
    pub fn add<'a>(&mut self, part: &'a [u8]) -> Result<&'a [u8], ClipError> {
        let bad = |why: &str| ClipError::Zip(format!("joining the clips' zips: {why}"));
        const END: usize = 22;
        let end = (0..=part.len().saturating_sub(END))
            .rev()
            .find(|&i| part[i..].starts_with(&[0x50, 0x4b, 0x05, 0x06]))
            .ok_or_else(|| bad("a part has no end record"))?;
        let entries = u16_at(part, end + 10).ok_or_else(|| bad("a cut end record"))?;
        let (size, start) = (u32_at(part, end + 12), u32_at(part, end + 16));
        let (Some(size), Some(start)) = (size, start) else { return Err(bad("a cut end record")) };
        if entries == 0xffff || size == 0xffff_ffff || start == 0xffff_ffff {
            return Err(bad("a part too large for a plain zip"));
        }
        let (start, size) = (start as usize, size as usize);
        let central = part
            .get(start..start + size)
            .filter(|_| start + size <= end)
            .ok_or_else(|| bad("a cut central directory"))?;
        let mut at = 0;
        let mut moved = Vec::with_capacity(central.len());
        for _ in 0..entries {
            let record = central.get(at..at + 46).filter(|r| r.starts_with(&[0x50, 0x4b, 0x01, 0x02]));
            let record = record.ok_or_else(|| bad("a central record out of place"))?;
            let lengths = [28, 30, 32].map(|k| u16_at(record, k).unwrap_or(0) as usize);
            let len = 46 + lengths.iter().sum::<usize>();
            let local = u32_at(record, 42).unwrap_or(0) + self.offset;
            if local >= 0xffff_ffff {
                return Err(bad("the clips pass 4 GiB: export the clips of fewer clusters or takes"));
            }
            let whole = central.get(at..at + len).ok_or_else(|| bad("a cut central record"))?;
            moved.extend_from_slice(&whole[..42]);
            moved.extend_from_slice(&(local as u32).to_le_bytes());
            moved.extend_from_slice(&whole[46..]);
            at += len;
        }
        if self.entries + entries > 0xfffe {
            return Err(bad("more than 65 534 clips: export the clips of fewer clusters or takes"));
        }
        self.central.extend_from_slice(&moved);
        self.entries += entries;
        self.offset += start as u64;
        Ok(&part[..start])
    }

    /// The central directory of every part added and the archive's end record: the bytes that close the archive.
    pub fn finish(self) -> Result<Vec<u8>, ClipError> {
        if self.offset + self.central.len() as u64 >= 0xffff_ffff {
            return Err(ClipError::Zip("the clips pass 4 GiB: export the clips of fewer clusters or takes".into()));
        }
        let mut out = self.central;
        let size = out.len() as u32;
        out.extend_from_slice(&[0x50, 0x4b, 0x05, 0x06, 0, 0, 0, 0]);
        out.extend_from_slice(&(self.entries as u16).to_le_bytes());
        out.extend_from_slice(&(self.entries as u16).to_le_bytes());
        out.extend_from_slice(&size.to_le_bytes());
        out.extend_from_slice(&(self.offset as u32).to_le_bytes());
        out.extend_from_slice(&[0, 0]);
        Ok(out)
    }
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

    /// Zips written one take at a time and joined are the zip of every clip: the same files, the same bytes, read by
    /// the zip crate; a part that is no zip is refused.
    #[test]
    fn zips_joined_one_at_a_time_are_one_zip_of_every_clip() {
        use std::io::Read;
        let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/12_01.bvh")).unwrap();
        let bvh = crate::bvh::parse(&text).unwrap();
        let clip = |name: &str, start: usize, end: usize| Clip {
            file: name.into(),
            bvh: cut(&bvh, start, end).unwrap(),
            segment: crate::segment::Segment {
                start,
                end,
                label: "walk".into(),
                level: crate::segment::Level::Action,
                cluster: None,
                score: None,
                mirror_of: None,
                effort: None,
            },
        };
        let parts =
            [vec![clip("walk/a_1.bvh", 0, 40), clip("walk/a_2.bvh", 41, 90)], vec![clip("turn/b_1.bvh", 10, 60)]];
        let mut join = ZipJoin::new();
        let mut joined = Vec::new();
        for part in &parts {
            let z = zip(part).unwrap();
            joined.extend_from_slice(join.add(&z).unwrap());
        }
        joined.extend(join.finish().unwrap());
        let mut archive = zip::ZipArchive::new(std::io::Cursor::new(joined)).unwrap();
        assert_eq!(archive.len(), 3);
        for c in parts.iter().flatten() {
            let mut text = String::new();
            archive.by_name(&c.file).unwrap().read_to_string(&mut text).unwrap();
            assert_eq!(text, crate::bvh::write(&c.bvh), "{}", c.file);
        }
        let e = ZipJoin::new().add(b"not a zip at all, not even 22 bytes long").unwrap_err().to_string();
        assert!(e.contains("no end record"), "{e}");
        // nothing added: an empty archive
        let empty = ZipJoin::new().finish().unwrap();
        assert_eq!(zip::ZipArchive::new(std::io::Cursor::new(empty)).unwrap().len(), 0);
    }
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
