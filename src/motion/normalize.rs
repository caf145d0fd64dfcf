//! The pose normalisations the segmentation papers use: root-relative, facing-aligned (rotated
//! about the vertical so the root faces +Z), scaled by body size.
//!
//! * **Y-up frame.** Everything here first brings positions into a right-handed Y-up frame:
//!   Z-up files are rotated −90° about X, `(x, y, z) → (x, z, −y)` ([`to_y_up`]).
//! * **Root-relative.** Positions minus the root's (or the canonical Hips') position of the
//!   same frame.
//! * **Facing-aligned.** Per frame, the body's facing is `up × across`, where `across` is the
//!   sum of the unit horizontal left→right hip vector and the unit horizontal left→right
//!   shoulder vector (a body facing +Z, up +Y, has its left side at +X, so `across` = −X and
//!   `up × across` = +Z). The frame is rotated about the vertical by minus the facing yaw
//!   so the body faces +Z. When hips and shoulders are both (nearly) vertical the previous
//!   frame's yaw is kept (0 for the first frame).
//! * **Body size.** Mean leg length (hip → knee → ankle bone lengths) plus the trunk length
//!   (Hips → … → Head bone lengths), i.e. roughly standing height minus foot height; dividing
//!   by it makes subjects of different sizes comparable. Methods that need real lengths (SSSM
//!   radii in inches) use [`to_inches`] instead.
//! * **End-effector features** (the SSSM paper's pose features): left hand, right hand, left
//!   foot, right foot, head, each root-relative (canonical Hips) and facing-aligned, in file
//!   units, Y-up frame: 15 numbers per frame.

use super::joints::{Canonical, JointMap};
use super::units::{leg_length, Units, UpAxis};
use super::{Motion, Skeleton};
use glam::{Quat, Vec3};

/// Horizontal vectors shorter than this (relative to their 3D length) carry no facing.
const MIN_HORIZONTAL: f32 = 1e-3;

/// The end effectors of [`end_effector_features`], in feature order.
pub const END_EFFECTORS: [Canonical; 5] =
    [Canonical::LeftHand, Canonical::RightHand, Canonical::LeftFoot, Canonical::RightFoot, Canonical::Head];

/// A file-frame point in the right-handed Y-up frame.
pub fn to_y_up(p: Vec3, up: UpAxis) -> Vec3 {
    match up {
        UpAxis::Y => p,
        UpAxis::Z => Vec3::new(p.x, p.z, -p.y),
    }
}

/// Inches per file unit.
pub fn to_inches(units: Units) -> f64 {
    units.metres_per_unit() / 0.0254
}

/// Positions minus the position of node `root` in the same frame (file axes), frame-major.
pub fn root_relative(motion: &Motion, root: usize) -> Vec<Vec3> {
    let mut out = Vec::with_capacity(motion.positions.len());
    for f in 0..motion.frames() {
        let frame = motion.frame(f);
        let r = frame[root];
        out.extend(frame.iter().map(|p| *p - r));
    }
    out
}

/// Unit horizontal (XZ) part of a Y-up vector, if it has one.
fn horizontal_unit(v: Vec3) -> Option<Vec3> {
    let h = Vec3::new(v.x, 0.0, v.z);
    let len = h.length();
    (len > MIN_HORIZONTAL * v.length().max(f32::MIN_POSITIVE)).then(|| h / len)
}

/// Facing yaw of one frame of Y-up positions: the angle about +Y from +Z to the facing
/// direction (`atan2(forward.x, forward.z)`), or `None` when hips and shoulders are vertical.
pub fn facing_yaw(frame_y_up: &[Vec3], map: &JointMap) -> Option<f32> {
    let line = |l: usize, r: usize| horizontal_unit(frame_y_up[r] - frame_y_up[l]);
    let hips = line(map.left_hip, map.right_hip);
    let shoulders = line(map.left_shoulder, map.right_shoulder);
    let across = hips.unwrap_or(Vec3::ZERO) + shoulders.unwrap_or(Vec3::ZERO);
    if across.length() < MIN_HORIZONTAL {
        return None;
    }
    let forward = Vec3::Y.cross(across);
    Some(forward.x.atan2(forward.z))
}

/// One frame in the Y-up frame.
fn frame_y_up(motion: &Motion, f: usize) -> Vec<Vec3> {
    motion.frame(f).iter().map(|p| to_y_up(*p, motion.up_axis)).collect()
}

/// Facing yaw of every frame (see [`facing_yaw`]; frames without a facing keep the last one).
pub fn facing_yaws(motion: &Motion, map: &JointMap) -> Vec<f32> {
    let mut last = 0.0;
    (0..motion.frames())
        .map(|f| {
            last = facing_yaw(&frame_y_up(motion, f), map).unwrap_or(last);
            last
        })
        .collect()
}

/// Every node, Y-up, relative to the canonical Hips and rotated about the vertical so the body
/// faces +Z, frame-major.
pub fn facing_aligned(motion: &Motion, map: &JointMap) -> Vec<Vec3> {
    let mut out = Vec::with_capacity(motion.positions.len());
    let mut last = 0.0;
    for f in 0..motion.frames() {
        let frame = frame_y_up(motion, f);
        last = facing_yaw(&frame, map).unwrap_or(last);
        let turn = Quat::from_rotation_y(-last);
        let root = frame[map.hips];
        out.extend(frame.iter().map(|p| turn * (*p - root)));
    }
    out
}

/// Body size in file units: mean leg length plus trunk length (Hips → Head bone lengths).
pub fn body_size(skeleton: &Skeleton, map: &JointMap) -> f64 {
    leg_length(skeleton, map) + skeleton.chain_length(map.hips, map.head)
}

/// [`facing_aligned`] divided by [`body_size`] (unitless; left unscaled if the size is 0).
pub fn body_scaled(motion: &Motion, map: &JointMap) -> Vec<Vec3> {
    let size = body_size(&motion.skeleton, map) as f32;
    let scale = if size > 0.0 && size.is_finite() { 1.0 / size } else { 1.0 };
    facing_aligned(motion, map).into_iter().map(|p| p * scale).collect()
}

/// Per frame: left hand, right hand, left foot, right foot, head (x, y, z each), relative to
/// the canonical Hips, facing-aligned, Y-up, file units (multiply by [`to_inches`] for inches).
pub fn end_effector_features(motion: &Motion, map: &JointMap) -> Vec<[f32; 15]> {
    let aligned = facing_aligned(motion, map);
    let j = motion.joints();
    let idx = END_EFFECTORS.map(|c| map.get(c));
    aligned
        .chunks_exact(j)
        .map(|frame| {
            let mut v = [0.0f32; 15];
            for (k, &i) in idx.iter().enumerate() {
                v[3 * k..3 * k + 3].copy_from_slice(&frame[i].to_array());
            }
            v
        })
        .collect()
}
