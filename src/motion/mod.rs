//! Motion: a skeleton plus the world position of every joint in every frame.
//!
//! This is the representation every segmentation method works on:
//! [`Motion::from_bvh`] runs forward kinematics over a parsed [`Bvh`] ([`fk`]), detects the
//! file's length units and up axis ([`units`]), and keeps the frame rate. [`Motion::resample`]
//! brings a take to the rate a method works at (30 Hz for the methods in the papers;
//! [`resample`]). [`joints`] maps the many skeleton naming conventions onto one canonical
//! set of joints, and [`normalize`] provides the normalisations the papers use
//! (root-relative, facing-aligned, body-size scaled, end-effector features).
//!
//! Positions are stored frame-major (`frames × joints`, End Sites included, in the order of
//! [`Bvh::joints`]) as `f32` in the file's own units and axes; FK itself runs in `f64`.

pub mod export;
pub mod fk;
pub mod joints;
pub mod normalize;
pub mod resample;
pub mod units;

pub use export::write_positions_csv;
pub use joints::{map_joints, Canonical, JointMap, MissingJoints};
pub use units::{UnitDetection, Units, UpAxis};

use crate::bvh::{Bvh, JointKind};
use glam::Vec3;
use serde::{Deserialize, Serialize};

/// The largest number of joint positions (frames × joints) a [`Motion`] may hold: 2^25 positions
/// = 384 MiB of `f32` triples. A 40-node skeleton at 120 fps fits about two hours.
pub const MAX_POSITIONS: usize = 1 << 25;

/// Why a [`Motion`] could not be built or transformed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MotionError {
    #[error("file has no joints")]
    NoJoints,
    #[error("file has no frames")]
    NoFrames,
    #[error("frame time must be positive (got {0})")]
    BadFrameTime(f64),
    #[error("target fps must be > 0 (got {0})")]
    BadTargetFps(f64),
    #[error("frame {frame} (0-based): channel {channel} of joint '{joint}' is not a finite number")]
    NonFinite { frame: usize, joint: String, channel: String },
    #[error("frame data has {values} values, which is not a whole number of frames of {per_frame} channels")]
    RaggedFrames { values: usize, per_frame: usize },
    #[error("invalid hierarchy: {0}")]
    InvalidHierarchy(String),
    #[error(
        "motion too large: {frames} frames × {joints} joints = {total} joint positions exceeds the limit of {limit}"
    )]
    TooLarge { frames: usize, joints: usize, total: usize, limit: usize },
    #[error("cannot join takes: {0}")]
    Incompatible(String),
}

/// The skeleton of a take: one entry per BVH node (End Sites included) in file order; a parent
/// always comes before its children.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Skeleton {
    pub names: Vec<String>,
    pub parents: Vec<Option<usize>>,
    /// OFFSET of each node from its parent, in file units.
    pub offsets: Vec<[f64; 3]>,
    pub is_end_site: Vec<bool>,
}

impl Skeleton {
    /// The skeleton of a parsed BVH file.
    pub fn from_bvh(bvh: &Bvh) -> Skeleton {
        Skeleton {
            names: bvh.joints.iter().map(|j| j.name.clone()).collect(),
            parents: bvh.joints.iter().map(|j| j.parent).collect(),
            offsets: bvh.joints.iter().map(|j| j.offset).collect(),
            is_end_site: bvh.joints.iter().map(|j| j.kind == JointKind::EndSite).collect(),
        }
    }

    /// Number of nodes (End Sites included).
    pub fn len(&self) -> usize {
        self.names.len()
    }

    pub fn is_empty(&self) -> bool {
        self.names.is_empty()
    }

    /// Length of the bone from a node's parent to the node (the norm of its OFFSET).
    pub fn bone_length(&self, i: usize) -> f64 {
        let [x, y, z] = self.offsets[i];
        (x * x + y * y + z * z).sqrt()
    }

    /// `node`, its parent, its grandparent, … up to the root. Stops after `len()` steps, so a
    /// hand-built skeleton with a parent cycle cannot loop forever.
    pub fn ancestors(&self, node: usize) -> impl Iterator<Item = usize> + '_ {
        std::iter::successors(Some(node), |&c| self.parents.get(c).copied().flatten()).take(self.len())
    }

    /// True if `ancestor` is `node` or one of its ancestors.
    pub fn is_ancestor_or_self(&self, ancestor: usize, node: usize) -> bool {
        self.ancestors(node).any(|c| c == ancestor)
    }

    /// The nodes from `ancestor` down to `node`, both included.
    /// `None` if `ancestor` is not an ancestor of `node` (or `node` itself).
    pub fn path_from(&self, ancestor: usize, node: usize) -> Option<Vec<usize>> {
        let mut path = Vec::new();
        for c in self.ancestors(node) {
            path.push(c);
            if c == ancestor {
                path.reverse();
                return Some(path);
            }
        }
        None
    }

    /// Sum of the bone lengths along the path from `ancestor` down to `node` (0 if not a path).
    pub fn chain_length(&self, ancestor: usize, node: usize) -> f64 {
        match self.path_from(ancestor, node) {
            Some(path) => path.iter().skip(1).map(|&i| self.bone_length(i)).sum(),
            None => 0.0,
        }
    }

    /// Indices of the nodes that are not End Sites, in file order.
    pub fn joint_indices(&self) -> Vec<usize> {
        (0..self.len()).filter(|&i| !self.is_end_site[i]).collect()
    }
}

/// A take: skeleton, frame rate and the world position of every node in every frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Motion {
    pub name: String,
    pub skeleton: Skeleton,
    /// Frames per second.
    pub fps: f64,
    /// Frame-major, `frames × joints` (End Sites included), world coordinates, file units.
    pub positions: Vec<Vec3>,
    pub units: Units,
    pub up_axis: UpAxis,
    /// The parser's warnings plus notes from unit / up-axis detection, as sentences.
    pub warnings: Vec<String>,
}

impl Motion {
    /// Forward kinematics over every frame of `bvh`, plus unit and up-axis detection.
    pub fn from_bvh(name: &str, bvh: &Bvh) -> Result<Motion, MotionError> {
        if bvh.joints.is_empty() {
            return Err(MotionError::NoJoints);
        }
        if !(bvh.frame_time.is_finite() && bvh.frame_time > 0.0) {
            return Err(MotionError::BadFrameTime(bvh.frame_time));
        }
        let positions = fk::forward_kinematics(bvh)?;
        let skeleton = Skeleton::from_bvh(bvh);
        let mut warnings: Vec<String> = bvh.warnings.iter().map(|w| w.to_string()).collect();
        let detection = units::detect(&skeleton, &positions);
        warnings.extend(detection.notes.iter().cloned());
        Ok(Motion {
            name: name.to_string(),
            skeleton,
            fps: bvh.fps(),
            positions,
            units: detection.units,
            up_axis: detection.up_axis,
            warnings,
        })
    }

    /// Frames `start..end` as a take of their own (same skeleton, rate, units; clamped to the take).
    pub fn slice(&self, start: usize, end: usize) -> Motion {
        let j = self.joints();
        let end = end.min(self.frames());
        let start = start.min(end);
        Motion { positions: self.positions[start * j..end * j].to_vec(), ..self.clone_without_positions() }
    }

    fn clone_without_positions(&self) -> Motion {
        Motion {
            name: self.name.clone(),
            skeleton: self.skeleton.clone(),
            fps: self.fps,
            positions: Vec::new(),
            units: self.units,
            up_axis: self.up_axis,
            warnings: self.warnings.clone(),
        }
    }

    /// Number of frames.
    pub fn frames(&self) -> usize {
        self.positions.len().checked_div(self.joints()).unwrap_or(0)
    }

    /// Number of nodes per frame (End Sites included).
    pub fn joints(&self) -> usize {
        self.skeleton.len()
    }

    /// The positions of all nodes in frame `i` (panics if `i >= frames()`, like slice indexing).
    pub fn frame(&self, i: usize) -> &[Vec3] {
        let j = self.joints();
        &self.positions[i * j..(i + 1) * j]
    }

    /// Position of node `joint` in frame `frame`.
    pub fn position(&self, frame: usize, joint: usize) -> Vec3 {
        self.positions[frame * self.joints() + joint]
    }

    /// Seconds per frame.
    pub fn frame_time(&self) -> f64 {
        1.0 / self.fps
    }

    /// Duration in seconds, `frames / fps`: every frame is taken to last one frame time, so a
    /// take of N frames covers N frame times (the last frame *starts* at `(N − 1) / fps`).
    pub fn duration_s(&self) -> f64 {
        self.frames() as f64 / self.fps
    }

    /// The take resampled to `fps` frames per second (positions interpolated linearly at the
    /// exact sample times; see [`resample`]).
    pub fn resample(&self, fps: f64) -> Result<Motion, MotionError> {
        resample::resample(self, fps)
    }

    /// Index of the node called `name`: an exact match first, then a case-insensitive one.
    pub fn joint_index(&self, name: &str) -> Option<usize> {
        let names = &self.skeleton.names;
        names.iter().position(|n| n == name).or_else(|| names.iter().position(|n| n.eq_ignore_ascii_case(name)))
    }

    /// Index of the root node (the first node of the file).
    pub fn root(&self) -> usize {
        0
    }

    /// A take of exactly `frames` frames made of `takes` one after another, cycling through them
    /// again from the first when they run out (long synthetic sequences for benchmarks and
    /// tests). The takes must share skeleton names and frame rate; the first one's metadata is kept.
    pub fn concatenate(takes: &[Motion], frames: usize) -> Result<Motion, MotionError> {
        let first = takes.first().ok_or(MotionError::NoFrames)?;
        for t in takes {
            if t.skeleton.names != first.skeleton.names {
                return Err(MotionError::Incompatible(format!(
                    "`{}` and `{}` have different skeletons",
                    first.name, t.name
                )));
            }
            if (t.fps - first.fps).abs() > 1e-6 * first.fps {
                return Err(MotionError::Incompatible(format!(
                    "`{}` is at {} fps, `{}` at {} fps",
                    first.name, first.fps, t.name, t.fps
                )));
            }
            if t.frames() == 0 {
                return Err(MotionError::NoFrames);
            }
        }
        let joints = first.joints();
        let limit = 1usize << 25;
        if frames.saturating_mul(joints) > limit {
            return Err(MotionError::TooLarge { frames, joints, total: frames.saturating_mul(joints), limit });
        }
        let mut positions = Vec::with_capacity(frames * joints);
        for t in takes.iter().cycle() {
            let need = frames * joints - positions.len();
            if need == 0 {
                break;
            }
            positions.extend_from_slice(&t.positions[..need.min(t.positions.len())]);
        }
        let names: Vec<&str> = takes.iter().map(|t| t.name.as_str()).collect();
        Ok(Motion { name: names.join("+"), positions, warnings: Vec::new(), ..first.clone() })
    }

    /// Map the skeleton onto the canonical joints (see [`joints::map_joints`]).
    pub fn joint_map(&self) -> Result<JointMap, MissingJoints> {
        map_joints(&self.skeleton)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn take(name: &str, frames: usize, x0: f32) -> Motion {
        Motion {
            name: name.into(),
            skeleton: Skeleton {
                names: vec!["Hips".into()],
                parents: vec![None],
                offsets: vec![[0.0; 3]],
                is_end_site: vec![false],
            },
            fps: 30.0,
            positions: (0..frames).map(|i| Vec3::new(x0 + i as f32, 0.0, 0.0)).collect(),
            units: Units::CmuAsf,
            up_axis: UpAxis::Y,
            warnings: Vec::new(),
        }
    }

    #[test]
    fn concatenate_cycles_through_the_takes_to_the_requested_length() {
        let (a, b) = (take("a", 3, 0.0), take("b", 2, 100.0));
        let m = Motion::concatenate(&[a, b], 7).unwrap();
        let xs: Vec<f32> = m.positions.iter().map(|p| p.x).collect();
        assert_eq!(xs, vec![0.0, 1.0, 2.0, 100.0, 101.0, 0.0, 1.0]);
        assert_eq!(m.name, "a+b");
    }

    #[test]
    fn concatenate_refuses_different_frame_rates() {
        let mut b = take("b", 2, 0.0);
        b.fps = 120.0;
        let e = Motion::concatenate(&[take("a", 2, 0.0), b], 4).unwrap_err();
        assert!(e.to_string().contains("120 fps"), "{e}");
    }
}
