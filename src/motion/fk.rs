//! Forward kinematics for BVH hierarchies: the world position of every node in every frame.
//!
//! Conventions, applied to every node of the file:
//! * local translation = the node's OFFSET, except that a position channel (`Xposition`,
//!   `Yposition`, `Zposition`, on any node, root or not) *replaces* that axis of the offset;
//! * local rotation = the product of the node's rotation channels in the order they are written,
//!   intrinsic, left to right: `CHANNELS 3 Zrotation Xrotation Yrotation` gives
//!   `R = Rz · Rx · Ry` (angles in degrees, right-handed);
//! * where position channels sit relative to rotation channels in the list does not matter
//!   (a root written `Zrotation Xrotation Yrotation Xposition Yposition Zposition` is the same
//!   transform as one written positions first): the translation is in the parent's frame;
//! * world: `R_w = R_w(parent) · R`, `p_w = p_w(parent) + R_w(parent) · t`.
//!
//! The maths runs in `f64` ([`glam::DQuat`], [`glam::DVec3`]); positions are stored as `f32`.

use super::{MotionError, Skeleton, MAX_POSITIONS};
use crate::bvh::{Bvh, Channel, JointKind};
use glam::{DQuat, DVec3, Vec3};

/// The elementary rotation of `degrees` about channel axis `axis` (0 = X, 1 = Y, 2 = Z).
pub fn axis_rotation(axis: usize, degrees: f64) -> DQuat {
    let r = degrees.to_radians();
    match axis {
        0 => DQuat::from_rotation_x(r),
        1 => DQuat::from_rotation_y(r),
        _ => DQuat::from_rotation_z(r),
    }
}

/// The local rotation of a node: rotation channels multiplied in written order,
/// `R = R1 · R2 · R3`. `channels` and `values` run in parallel; position channels are skipped.
pub fn local_rotation(channels: &[Channel], values: &[f64]) -> DQuat {
    channels
        .iter()
        .zip(values)
        .filter(|(c, _)| c.is_rotation())
        .fold(DQuat::IDENTITY, |q, (c, &v)| q * axis_rotation(c.axis(), v))
}

/// What one node needs from a frame row.
#[derive(Debug, Clone)]
struct NodePlan {
    parent: Option<usize>,
    offset: DVec3,
    /// Value index (within a frame row) of the X, Y and Z position channels, if present.
    position: [Option<usize>; 3],
    /// (axis, value index) of each rotation channel, in written order.
    rotations: Vec<(usize, usize)>,
}

/// A BVH hierarchy compiled for evaluating frames: validated once, then cheap per frame.
#[derive(Debug, Clone)]
pub struct FkPlan {
    nodes: Vec<NodePlan>,
    channels_per_frame: usize,
}

impl FkPlan {
    /// Check the hierarchy (parents before children, channel slots inside the frame row, no
    /// channels on End Sites) and compile it.
    pub fn new(bvh: &Bvh) -> Result<FkPlan, MotionError> {
        if bvh.joints.is_empty() {
            return Err(MotionError::NoJoints);
        }
        let cpf = bvh.channels_per_frame;
        let mut nodes = Vec::with_capacity(bvh.joints.len());
        for (i, j) in bvh.joints.iter().enumerate() {
            if let Some(p) = j.parent {
                if p >= i {
                    return Err(MotionError::InvalidHierarchy(format!(
                        "joint '{}' (#{i}) has parent #{p}, which does not come before it",
                        j.name
                    )));
                }
                if bvh.joints[p].kind == JointKind::EndSite {
                    return Err(MotionError::InvalidHierarchy(format!(
                        "joint '{}' has an End Site as its parent",
                        j.name
                    )));
                }
            }
            if j.kind == JointKind::EndSite && !j.channels.is_empty() {
                return Err(MotionError::InvalidHierarchy(format!("End Site '{}' has channels", j.name)));
            }
            if j.channel_start + j.channels.len() > cpf {
                return Err(MotionError::InvalidHierarchy(format!(
                    "channels of joint '{}' (from value {} on, {} of them) lie outside a frame row of {cpf} values",
                    j.name,
                    j.channel_start,
                    j.channels.len()
                )));
            }
            if j.offset.iter().any(|v| !v.is_finite()) {
                return Err(MotionError::InvalidHierarchy(format!("OFFSET of joint '{}' is not finite", j.name)));
            }
            let mut position = [None; 3];
            let mut rotations = Vec::new();
            for (k, c) in j.channels.iter().enumerate() {
                let slot = j.channel_start + k;
                if c.is_rotation() {
                    rotations.push((c.axis(), slot));
                } else {
                    position[c.axis()] = Some(slot);
                }
            }
            nodes.push(NodePlan { parent: j.parent, offset: DVec3::from_array(j.offset), position, rotations });
        }
        Ok(FkPlan { nodes, channels_per_frame: cpf })
    }

    /// Number of nodes (End Sites included).
    pub fn nodes(&self) -> usize {
        self.nodes.len()
    }

    /// World positions of every node for one frame row. `world` is scratch space (resized here).
    pub fn solve_frame(&self, row: &[f64], world: &mut Vec<(DQuat, DVec3)>, out: &mut [Vec3]) {
        world.clear();
        for (i, n) in self.nodes.iter().enumerate() {
            let mut t = n.offset;
            for (axis, slot) in n.position.iter().enumerate() {
                if let Some(s) = slot {
                    t[axis] = row[*s];
                }
            }
            let local = n.rotations.iter().fold(DQuat::IDENTITY, |q, &(axis, s)| q * axis_rotation(axis, row[s]));
            let (rot, pos) = match n.parent {
                Some(p) => {
                    let (prot, ppos) = world[p];
                    (prot * local, ppos + prot * t)
                }
                None => (local, t),
            };
            world.push((rot, pos));
            out[i] = pos.as_vec3();
        }
    }
}

/// Name of the value at `slot` of a frame row, for error messages.
fn channel_owner(bvh: &Bvh, slot: usize) -> (String, String) {
    for j in &bvh.joints {
        if slot >= j.channel_start && slot < j.channel_start + j.channels.len() {
            return (j.name.clone(), j.channels[slot - j.channel_start].name().to_string());
        }
    }
    (String::from("?"), format!("#{slot}"))
}

/// World positions of every node in every frame, frame-major.
pub fn forward_kinematics(bvh: &Bvh) -> Result<Vec<Vec3>, MotionError> {
    let plan = FkPlan::new(bvh)?;
    let cpf = plan.channels_per_frame;
    if cpf > 0 && bvh.values.len() % cpf != 0 {
        return Err(MotionError::RaggedFrames { values: bvh.values.len(), per_frame: cpf });
    }
    let frames = bvh.frames();
    if frames == 0 {
        return Err(MotionError::NoFrames);
    }
    let joints = plan.nodes();
    let total = frames.saturating_mul(joints);
    if total > MAX_POSITIONS {
        return Err(MotionError::TooLarge { frames, joints, total, limit: MAX_POSITIONS });
    }
    if let Some(bad) = bvh.values.iter().position(|v| !v.is_finite()) {
        let (joint, channel) = channel_owner(bvh, bad % cpf);
        return Err(MotionError::NonFinite { frame: bad / cpf, joint, channel });
    }
    let mut out = vec![Vec3::ZERO; total];
    let mut world = Vec::with_capacity(joints);
    let empty: [f64; 0] = [];
    for (f, chunk) in out.chunks_exact_mut(joints).enumerate() {
        let row = if cpf == 0 { &empty[..] } else { &bvh.values[f * cpf..(f + 1) * cpf] };
        plan.solve_frame(row, &mut world, chunk);
    }
    Ok(out)
}

/// The rest pose: every node at its OFFSETs with no rotation (the pose the hierarchy describes
/// before any frame is applied), root at the origin.
pub fn rest_pose(skeleton: &Skeleton) -> Vec<Vec3> {
    let mut world: Vec<DVec3> = Vec::with_capacity(skeleton.len());
    for i in 0..skeleton.len() {
        let off = DVec3::from_array(skeleton.offsets[i]);
        let p = match skeleton.parents[i] {
            Some(p) if p < i => world[p] + off,
            _ => DVec3::ZERO,
        };
        world.push(p);
    }
    world.iter().map(|p| p.as_vec3()).collect()
}
