//! ASF + AMC → [`Bvh`]: the same hierarchy and motion as the CMU BVH conversions (cgspeed's
//! layout: the root at the origin with 6 channels, one node per bone at the bone's start with
//! `Zrotation Yrotation Xrotation`, an End Site at each leaf bone's end), in ASF length units.

use super::amc::{layout, Amc};
use super::asf::{Asf, Axis, Dof};
use crate::bvh::{Bvh, BvhJoint, Channel, JointKind, Warning};
use glam::{DQuat, EulerRot};

/// The frame rate of the CMU database's AMC files (AMC files do not say theirs).
pub const CMU_FPS: f64 = 120.0;

const ROOT_CHANNELS: [Channel; 6] = [
    Channel::Xposition,
    Channel::Yposition,
    Channel::Zposition,
    Channel::Zrotation,
    Channel::Yrotation,
    Channel::Xrotation,
];
const BONE_CHANNELS: [Channel; 3] = [Channel::Zrotation, Channel::Yrotation, Channel::Xrotation];

fn elementary(axis: usize, radians: f64) -> DQuat {
    match axis {
        0 => DQuat::from_rotation_x(radians),
        1 => DQuat::from_rotation_y(radians),
        _ => DQuat::from_rotation_z(radians),
    }
}

/// C of an `axis` line: its rotations applied in its order (the first letter's first), as a
/// rotation of column vectors.
fn axis_frame(axis: &Axis, to_radians: f64) -> DQuat {
    axis.order.iter().fold(DQuat::IDENTITY, |q, &a| elementary(a, axis.angles[a] * to_radians) * q)
}

/// M of one bone's AMC values: the rotations in the order of its dofs (the first applied first).
fn motion_rotation(dofs: &[Dof], values: &[f64], to_radians: f64) -> DQuat {
    dofs.iter()
        .zip(values)
        .filter(|(d, _)| d.is_rotation())
        .fold(DQuat::IDENTITY, |q, (d, &v)| elementary(d.axis(), v * to_radians) * q)
}

/// `Zrotation Yrotation Xrotation` angles in degrees of `q` (q = Rz · Ry · Rx).
fn zyx_degrees(q: DQuat) -> [f64; 3] {
    let (z, y, x) = q.to_euler(EulerRot::ZYX);
    [z.to_degrees(), y.to_degrees(), x.to_degrees()]
}

/// The BVH nodes of `asf` in file order (depth first, `:hierarchy` order): `(bone, is End Site)`;
/// `bone` is `None` for the root.
fn node_order(asf: &Asf) -> Vec<(Option<usize>, bool)> {
    let mut order = vec![(None, false)];
    let mut stack: Vec<(usize, bool)> = asf.root_children.iter().rev().map(|&b| (b, false)).collect();
    while let Some((b, end)) = stack.pop() {
        order.push((Some(b), end));
        if end {
            continue;
        }
        if asf.children[b].is_empty() {
            stack.push((b, true));
        } else {
            stack.extend(asf.children[b].iter().rev().map(|&c| (c, false)));
        }
    }
    order
}

/// Nodes of the BVH `asf` becomes (root, bones, an End Site per leaf bone) and its channels per frame.
pub fn size(asf: &Asf) -> (usize, usize) {
    let leaves = asf.children.iter().filter(|c| c.is_empty()).count();
    let moving = asf.bones.iter().filter(|b| !b.dofs.is_empty()).count();
    (1 + asf.bones.len() + leaves, ROOT_CHANNELS.len() + BONE_CHANNELS.len() * moving)
}

/// The BVH of a skeleton and its motion at `fps` frames per second. Warnings of both files are
/// kept, each naming its file (`asf_name`, `amc_name`).
pub fn to_bvh(asf: &Asf, amc: &Amc, fps: f64, asf_name: &str, amc_name: &str) -> Bvh {
    let order = node_order(asf);
    let mut node_of_bone = vec![0; asf.bones.len()];
    let mut joints: Vec<BvhJoint> = Vec::with_capacity(order.len());
    let mut channel_start = 0;
    for &(bone, end) in &order {
        let joint = match (bone, end) {
            (None, _) => BvhJoint {
                name: "root".into(),
                kind: JointKind::Root,
                parent: None,
                offset: [0.0; 3],
                channels: ROOT_CHANNELS.to_vec(),
                channel_start,
            },
            (Some(b), true) => BvhJoint {
                name: format!("{}_End", asf.bones[b].name),
                kind: JointKind::EndSite,
                parent: Some(node_of_bone[b]),
                offset: asf.bones[b].vector(),
                channels: vec![],
                channel_start,
            },
            (Some(b), false) => {
                node_of_bone[b] = joints.len();
                let (parent, offset) = match asf.parents[b] {
                    None => (0, [0.0; 3]),
                    Some(p) => (node_of_bone[p], asf.bones[p].vector()),
                };
                let channels = if asf.bones[b].dofs.is_empty() { vec![] } else { BONE_CHANNELS.to_vec() };
                BvhJoint {
                    name: asf.bones[b].name.clone(),
                    kind: JointKind::Joint,
                    parent: Some(parent),
                    offset,
                    channels,
                    channel_start,
                }
            }
        };
        channel_start += joint.channels.len();
        joints.push(joint);
    }
    let channels_per_frame = channel_start;
    let degrees = amc.degrees.unwrap_or(asf.degrees);
    let amc_radians = if degrees { 1f64.to_radians() } else { 1.0 };
    let asf_radians = if asf.degrees { 1f64.to_radians() } else { 1.0 };
    // C and C⁻¹ of the root and of every bone, once
    let root_c = axis_frame(&asf.root.axis, asf_radians);
    let bone_c: Vec<DQuat> = asf.bones.iter().map(|b| axis_frame(&b.axis, asf_radians)).collect();
    let (starts, _) = layout(asf);
    let mut values = Vec::with_capacity(amc.frames() * channels_per_frame);
    for f in 0..amc.frames() {
        let row = amc.frame(f);
        let root_values = &row[..asf.root.order.len()];
        let mut translation = [0.0; 3];
        for (d, &v) in asf.root.order.iter().zip(root_values) {
            if !d.is_rotation() {
                translation[d.axis()] = v;
            }
        }
        let m = motion_rotation(&asf.root.order, root_values, amc_radians);
        values.extend_from_slice(&translation);
        values.extend_from_slice(&zyx_degrees(root_c * m * root_c.inverse()));
        for &(bone, end) in &order[1..] {
            let Some(b) = bone.filter(|_| !end) else { continue };
            let Some(start) = starts[b] else { continue };
            let dofs = &asf.bones[b].dofs;
            let m = motion_rotation(dofs, &row[start..start + dofs.len()], amc_radians);
            let c = bone_c[b];
            values.extend_from_slice(&zyx_degrees(c * m * c.inverse()));
        }
    }
    let mut warnings: Vec<Warning> = Vec::new();
    for (file, list) in [(asf_name, &asf.warnings), (amc_name, &amc.warnings)] {
        warnings.extend(list.iter().map(|w| Warning { line: 0, message: format!("{file}: {w}") }));
    }
    if amc.degrees.is_none() && !asf.degrees {
        warnings.push(Warning {
            line: 0,
            message: format!("{amc_name}: no `:DEGREES` or `:RADIANS`; read as radians, as the ASF's angles"),
        });
    }
    Bvh { joints, frame_time: 1.0 / fps, declared_frames: amc.frames(), channels_per_frame, values, warnings }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion::fk::local_rotation;

    #[test]
    fn zyx_angles_rebuild_the_rotation_as_bvh_channels_read_it() {
        for (i, q) in [
            DQuat::from_rotation_x(0.3) * DQuat::from_rotation_y(-1.1) * DQuat::from_rotation_z(2.0),
            DQuat::from_rotation_z(-0.4),
            DQuat::from_axis_angle(glam::DVec3::new(1.0, 2.0, 3.0).normalize(), 1.7),
        ]
        .into_iter()
        .enumerate()
        {
            let back = local_rotation(&BONE_CHANNELS, &zyx_degrees(q));
            assert!(back.dot(q).abs() > 1.0 - 1e-12, "case {i}: {q:?} → {back:?}");
        }
    }

    #[test]
    fn the_axis_frame_applies_its_first_letter_first() {
        let axis = Axis { angles: [90.0, 0.0, 90.0], order: [0, 1, 2] };
        let c = axis_frame(&axis, 1f64.to_radians());
        let expected =
            DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2) * DQuat::from_rotation_x(std::f64::consts::FRAC_PI_2);
        assert!(c.dot(expected).abs() > 1.0 - 1e-12);
    }
}
