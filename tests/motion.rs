//! Tests of `mocapseg::motion`: forward kinematics on hand-built hierarchies with known answers,
//! unit / up-axis detection, canonical joint mapping for many naming conventions, resampling,
//! the normalisations, and the same checks on the real fixtures in `tests/fixtures/`.

use glam::Vec3;
use mocapseg::bvh::{self, Bvh, BvhJoint, Channel, JointKind};
use mocapseg::motion::normalize::{
    body_size, end_effector_features, facing_aligned, facing_yaws, root_relative, to_inches, to_y_up,
};
use mocapseg::motion::resample::source_positions;
use mocapseg::motion::{map_joints, Canonical, Motion, MotionError, Units, UpAxis};

use Channel::{Xposition as XP, Xrotation as XR, Yposition as YP, Yrotation as YR, Zposition as ZP, Zrotation as ZR};

// ---------------------------------------------------------------------------------------------
// Building BVH values by hand

struct Node {
    name: String,
    parent: Option<usize>,
    offset: [f64; 3],
    channels: Vec<Channel>,
    end_site: bool,
}

fn node(name: &str, parent: Option<usize>, offset: [f64; 3], channels: &[Channel]) -> Node {
    Node { name: name.into(), parent, offset, channels: channels.to_vec(), end_site: false }
}

fn end_site(parent: usize, offset: [f64; 3], parent_name: &str) -> Node {
    Node { name: format!("{parent_name}_End"), parent: Some(parent), offset, channels: vec![], end_site: true }
}

fn build(nodes: &[Node], frame_time: f64, frames: &[Vec<f64>]) -> Bvh {
    let mut start = 0;
    let joints: Vec<BvhJoint> = nodes
        .iter()
        .map(|n| {
            let j = BvhJoint {
                name: n.name.clone(),
                kind: if n.end_site {
                    JointKind::EndSite
                } else if n.parent.is_none() {
                    JointKind::Root
                } else {
                    JointKind::Joint
                },
                parent: n.parent,
                offset: n.offset,
                channels: n.channels.clone(),
                channel_start: start,
            };
            start += n.channels.len();
            j
        })
        .collect();
    for f in frames {
        assert_eq!(f.len(), start, "test frame has the wrong number of values");
    }
    Bvh {
        joints,
        frame_time,
        declared_frames: frames.len(),
        channels_per_frame: start,
        values: frames.concat(),
        warnings: vec![],
    }
}

fn motion(nodes: &[Node], frame_time: f64, frames: &[Vec<f64>]) -> Motion {
    Motion::from_bvh("test", &build(nodes, frame_time, frames)).expect("motion")
}

fn close(a: Vec3, b: Vec3, tol: f32) -> bool {
    (a - b).abs().max_element() <= tol
}

#[track_caller]
fn assert_close(a: Vec3, b: Vec3, tol: f32) {
    assert!(close(a, b, tol), "{a:?} != {b:?} (tol {tol})");
}

// Independent rotation matrices (row-major), written out from the textbook formulas.
type M3 = [[f64; 3]; 3];

fn rot(axis: usize, deg: f64) -> M3 {
    let (s, c) = deg.to_radians().sin_cos();
    match axis {
        0 => [[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]],
        1 => [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]],
        _ => [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]],
    }
}

fn mul(a: M3, b: M3) -> M3 {
    let mut m = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            m[i][j] = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    m
}

fn apply(m: M3, v: [f64; 3]) -> Vec3 {
    let r: Vec<f64> = (0..3).map(|i| (0..3).map(|k| m[i][k] * v[k]).sum()).collect();
    Vec3::new(r[0] as f32, r[1] as f32, r[2] as f32)
}

fn rot_channel(axis: usize) -> Channel {
    [XR, YR, ZR][axis]
}

// ---------------------------------------------------------------------------------------------
// Forward kinematics

#[test]
fn fk_90_about_z_then_x() {
    // R = Rz(90)·Rx(90); Rx(90) takes +Z to −Y, Rz(90) takes −Y to +X.
    let nodes = [node("Root", None, [0.0; 3], &[ZR, XR]), node("Child", Some(0), [0.0, 0.0, 1.0], &[])];
    let m = motion(&nodes, 0.1, &[vec![90.0, 90.0]]);
    assert_close(m.frame(0)[1], Vec3::new(1.0, 0.0, 0.0), 1e-6);
    // Written the other way round, R = Rx(90)·Rz(90): Rz leaves +Z alone, Rx takes it to −Y.
    let nodes = [node("Root", None, [0.0; 3], &[XR, ZR]), node("Child", Some(0), [0.0, 0.0, 1.0], &[])];
    let m = motion(&nodes, 0.1, &[vec![90.0, 90.0]]);
    assert_close(m.frame(0)[1], Vec3::new(0.0, -1.0, 0.0), 1e-6);
}

#[test]
fn fk_every_rotation_order_matches_textbook_matrices() {
    let angles = [30.0, -45.0, 70.0];
    let offset = [0.3, 1.2, -0.7];
    let orders = [[0, 1, 2], [0, 2, 1], [1, 0, 2], [1, 2, 0], [2, 0, 1], [2, 1, 0]];
    let mut seen = Vec::new();
    for order in orders {
        let channels: Vec<Channel> = order.iter().map(|&a| rot_channel(a)).collect();
        let nodes = [node("Root", None, [0.0; 3], &channels), node("Child", Some(0), offset, &[])];
        let values: Vec<f64> = order.iter().map(|&a| angles[a]).collect();
        let m = motion(&nodes, 0.1, &[values]);
        let expect = apply(
            mul(mul(rot(order[0], angles[order[0]]), rot(order[1], angles[order[1]])), rot(order[2], angles[order[2]])),
            offset,
        );
        assert_close(m.frame(0)[1], expect, 1e-5);
        seen.push(m.frame(0)[1]);
    }
    // The six orders really give six different answers (the order is not ignored).
    for i in 0..seen.len() {
        for j in i + 1..seen.len() {
            assert!(!close(seen[i], seen[j], 1e-3), "orders {i} and {j} agree");
        }
    }
}

#[test]
fn fk_three_joint_chain_composes_parent_rotations() {
    // Root Ry(90) takes +X to −Z; the child adds Rz(90), so the grandchild's bone (+X) points
    // along Ry(90)·Rz(90)·X = Ry(90)·Y = +Y.
    let nodes = [
        node("Root", None, [0.0; 3], &[XP, YP, ZP, YR]),
        node("Child", Some(0), [1.0, 0.0, 0.0], &[ZR]),
        node("Grand", Some(1), [1.0, 0.0, 0.0], &[]),
    ];
    let m = motion(&nodes, 0.1, &[vec![2.0, 3.0, 4.0, 90.0, 90.0]]);
    assert_close(m.frame(0)[0], Vec3::new(2.0, 3.0, 4.0), 1e-6);
    assert_close(m.frame(0)[1], Vec3::new(2.0, 3.0, 3.0), 1e-6);
    assert_close(m.frame(0)[2], Vec3::new(2.0, 4.0, 3.0), 1e-6);
}

#[test]
fn fk_rotation_first_root_equals_position_first_root() {
    let child = [0.5, 1.0, -0.25];
    let rot_first = [node("Hips", None, [0.0; 3], &[ZR, XR, YR, XP, YP, ZP]), node("C", Some(0), child, &[])];
    let pos_first = [node("Hips", None, [0.0; 3], &[XP, YP, ZP, ZR, XR, YR]), node("C", Some(0), child, &[])];
    let a = motion(&rot_first, 0.1, &[vec![90.0, 0.0, 0.0, 10.0, 20.0, 30.0], vec![10.0, 20.0, 30.0, 1.0, 2.0, 3.0]]);
    let b = motion(&pos_first, 0.1, &[vec![10.0, 20.0, 30.0, 90.0, 0.0, 0.0], vec![1.0, 2.0, 3.0, 10.0, 20.0, 30.0]]);
    assert_eq!(a.positions, b.positions);
    // Rz(90) takes (0.5, 1, −0.25) to (−1, 0.5, −0.25).
    assert_close(a.frame(0)[0], Vec3::new(10.0, 20.0, 30.0), 1e-6);
    assert_close(a.frame(0)[1], Vec3::new(9.0, 20.5, 29.75), 1e-5);
}

#[test]
fn fk_position_channels_on_a_child_replace_offset_axes() {
    let nodes = [
        node("Root", None, [100.0, 100.0, 100.0], &[ZR]),
        node("Child", Some(0), [1.0, 2.0, 3.0], &[YP]),
        node("Grand", Some(1), [0.0, 0.0, 1.0], &[XP, YP, ZP, XR]),
    ];
    let m = motion(&nodes, 0.1, &[vec![90.0, 7.0, 4.0, 5.0, 6.0, 0.0]]);
    // Root without position channels sits at its OFFSET.
    assert_close(m.frame(0)[0], Vec3::new(100.0, 100.0, 100.0), 1e-5);
    // Child: local t = (1, 7, 3) (Y replaced), rotated by Rz(90) → (−7, 1, 3).
    assert_close(m.frame(0)[1], Vec3::new(93.0, 101.0, 103.0), 1e-4);
    // Grand: local t = (4, 5, 6) (all replaced), rotated by Rz(90) → (−5, 4, 6).
    assert_close(m.frame(0)[2], Vec3::new(88.0, 105.0, 109.0), 1e-4);
}

#[test]
fn fk_root_position_channels_replace_root_offset() {
    let nodes = [node("Root", None, [5.0, 5.0, 5.0], &[XP, YP, ZP])];
    let m = motion(&nodes, 0.1, &[vec![1.0, 2.0, 3.0]]);
    assert_eq!(m.frame(0)[0], Vec3::new(1.0, 2.0, 3.0));
}

#[test]
fn motion_basics() {
    let nodes = [node("Hips", None, [0.0; 3], &[XP, YP, ZP]), end_site(0, [0.0, 1.0, 0.0], "Hips")];
    let frames: Vec<Vec<f64>> = (0..5).map(|f| vec![f as f64, 0.0, 0.0]).collect();
    let m = motion(&nodes, 0.0083333, &frames);
    assert_eq!(m.frames(), 5);
    assert_eq!(m.joints(), 2);
    assert!((m.fps - 120.0).abs() < 1e-3);
    assert!((m.duration_s() - 5.0 * 0.0083333).abs() < 1e-12);
    assert_eq!(m.frame(3)[1], Vec3::new(3.0, 1.0, 0.0));
    assert_eq!(m.joint_index("Hips"), Some(0));
    assert_eq!(m.joint_index("hips"), Some(0));
    assert_eq!(m.joint_index("Hips_End"), Some(1));
    assert_eq!(m.joint_index("Nope"), None);
    assert!(m.skeleton.is_end_site[1]);
}

#[test]
fn motion_errors_are_clear() {
    let nodes = [node("Hips", None, [0.0; 3], &[XP, YP, ZP])];
    let err = Motion::from_bvh("x", &build(&nodes, 0.0, &[vec![0.0; 3]])).unwrap_err();
    assert_eq!(err, MotionError::BadFrameTime(0.0));
    assert!(err.to_string().contains("frame time must be positive"), "{err}");
    let err = Motion::from_bvh("x", &build(&nodes, -1.0, &[vec![0.0; 3]])).unwrap_err();
    assert!(err.to_string().contains("frame time must be positive"), "{err}");
    let err = Motion::from_bvh("x", &build(&nodes, 0.1, &[])).unwrap_err();
    assert_eq!(err.to_string(), "file has no frames");
    let err = Motion::from_bvh("x", &build(&nodes, 0.1, &[vec![0.0, f64::NAN, 0.0]])).unwrap_err();
    assert_eq!(err.to_string(), "frame 0 (0-based): channel Yposition of joint 'Hips' is not a finite number");
    let mut bad = build(&nodes, 0.1, &[vec![0.0; 3]]);
    bad.joints[0].channel_start = 2;
    let err = Motion::from_bvh("x", &bad).unwrap_err();
    assert!(matches!(err, MotionError::InvalidHierarchy(_)), "{err}");
    assert!(err.to_string().contains("'Hips'"), "{err}");
    let mut bad = build(&[node("A", None, [0.0; 3], &[]), node("B", Some(0), [0.0; 3], &[])], 0.1, &[vec![]]);
    bad.joints[0].parent = Some(1);
    assert!(matches!(Motion::from_bvh("x", &bad), Err(MotionError::InvalidHierarchy(_))));
    let empty = Bvh {
        joints: vec![],
        frame_time: 0.1,
        declared_frames: 1,
        channels_per_frame: 0,
        values: vec![],
        warnings: vec![],
    };
    assert_eq!(Motion::from_bvh("x", &empty).unwrap_err().to_string(), "file has no joints");
}

#[test]
fn huge_declared_frame_count_without_channels_is_one_frame_not_allocated() {
    // No channels, no data rows: the file describes one pose whatever `Frames:` says.
    let nodes = [node("Root", None, [0.0; 3], &[]), end_site(0, [0.0, 1.0, 0.0], "Root")];
    let mut b = build(&nodes, 0.1, &[vec![]]);
    b.declared_frames = usize::MAX / 2;
    let m = Motion::from_bvh("x", &b).expect("one frame");
    assert_eq!((m.frames(), m.positions.len()), (1, 2));
}

// ---------------------------------------------------------------------------------------------
// A parametric humanoid (metres, Y-up, facing +Z, left side at +X) for mapping / units / facing

/// Names of the humanoid's nodes by role, one table per naming convention.
struct Names {
    extra_root: Option<&'static str>,
    hips: &'static str,
    spine: &'static str,
    chest: &'static str,
    neck: &'static str,
    head: &'static str,
    /// clavicle, upper arm, forearm, hand; thigh, shin, foot, toe — each with `{}` for the side.
    left: [&'static str; 8],
    right: [&'static str; 8],
    clavicle_on_neck: bool,
}

const MOTIONBUILDER: Names = Names {
    extra_root: None,
    hips: "Hips",
    spine: "Spine",
    chest: "Spine1",
    neck: "Neck",
    head: "Head",
    left: ["LeftShoulder", "LeftArm", "LeftForeArm", "LeftHand", "LeftUpLeg", "LeftLeg", "LeftFoot", "LeftToeBase"],
    right: [
        "RightShoulder",
        "RightArm",
        "RightForeArm",
        "RightHand",
        "RightUpLeg",
        "RightLeg",
        "RightFoot",
        "RightToeBase",
    ],
    clavicle_on_neck: false,
};

const MIXAMO: Names = Names {
    extra_root: None,
    hips: "mixamorig:Hips",
    spine: "mixamorig:Spine",
    chest: "mixamorig:Spine2",
    neck: "mixamorig:Neck",
    head: "mixamorig:Head",
    left: [
        "mixamorig:LeftShoulder",
        "mixamorig:LeftArm",
        "mixamorig:LeftForeArm",
        "mixamorig:LeftHand",
        "mixamorig:LeftUpLeg",
        "mixamorig:LeftLeg",
        "mixamorig:LeftFoot",
        "mixamorig:LeftToeBase",
    ],
    right: [
        "mixamorig:RightShoulder",
        "mixamorig:RightArm",
        "mixamorig:RightForeArm",
        "mixamorig:RightHand",
        "mixamorig:RightUpLeg",
        "mixamorig:RightLeg",
        "mixamorig:RightFoot",
        "mixamorig:RightToeBase",
    ],
    clavicle_on_neck: false,
};

const MAX3DS: Names = Names {
    extra_root: None,
    hips: "Hips",
    spine: "Chest",
    chest: "Chest2",
    neck: "Neck",
    head: "Head",
    left: ["LeftCollar", "LeftShoulder", "LeftElbow", "LeftWrist", "LeftHip", "LeftKnee", "LeftAnkle", "LeftToe"],
    right: [
        "RightCollar",
        "RightShoulder",
        "RightElbow",
        "RightWrist",
        "RightHip",
        "RightKnee",
        "RightAnkle",
        "RightToe",
    ],
    clavicle_on_neck: false,
};

const DAZ: Names = Names {
    extra_root: None,
    hips: "hip",
    spine: "abdomen",
    chest: "chest",
    neck: "neck",
    head: "head",
    left: ["lCollar", "lShldr", "lForeArm", "lHand", "lThigh", "lShin", "lFoot", "lToe"],
    right: ["rCollar", "rShldr", "rForeArm", "rHand", "rThigh", "rShin", "rFoot", "rToe"],
    clavicle_on_neck: false,
};

const BIPED: Names = Names {
    extra_root: Some("Bip01"),
    hips: "Bip01 Pelvis",
    spine: "Bip01 Spine",
    chest: "Bip01 Spine1",
    neck: "Bip01 Neck",
    head: "Bip01 Head",
    left: [
        "Bip01 L Clavicle",
        "Bip01 L UpperArm",
        "Bip01 L Forearm",
        "Bip01 L Hand",
        "Bip01 L Thigh",
        "Bip01 L Calf",
        "Bip01 L Foot",
        "Bip01 L Toe0",
    ],
    right: [
        "Bip01 R Clavicle",
        "Bip01 R UpperArm",
        "Bip01 R Forearm",
        "Bip01 R Hand",
        "Bip01 R Thigh",
        "Bip01 R Calf",
        "Bip01 R Foot",
        "Bip01 R Toe0",
    ],
    clavicle_on_neck: true,
};

const ASF: Names = Names {
    extra_root: None,
    hips: "root",
    spine: "lowerback",
    chest: "thorax",
    neck: "lowerneck",
    head: "head",
    left: ["lclavicle", "lhumerus", "lradius", "lwrist", "lfemur", "ltibia", "lfoot", "ltoes"],
    right: ["rclavicle", "rhumerus", "rradius", "rwrist", "rfemur", "rtibia", "rfoot", "rtoes"],
    clavicle_on_neck: false,
};

const UNREAL: Names = Names {
    extra_root: None,
    hips: "pelvis",
    spine: "spine_01",
    chest: "spine_02",
    neck: "neck_01",
    head: "head",
    left: ["clavicle_l", "upperarm_l", "lowerarm_l", "hand_l", "thigh_l", "calf_l", "foot_l", "ball_l"],
    right: ["clavicle_r", "upperarm_r", "lowerarm_r", "hand_r", "thigh_r", "calf_r", "foot_r", "ball_r"],
    clavicle_on_neck: false,
};

const BLENDER: Names = Names {
    extra_root: None,
    hips: "Hips",
    spine: "spine.001",
    chest: "chest",
    neck: "neck",
    head: "head",
    left: ["shoulder.L", "upper_arm.L", "forearm.L", "hand.L", "thigh.L", "shin.L", "foot.L", "toe.L"],
    right: ["shoulder.R", "upper_arm.R", "forearm.R", "hand.R", "thigh.R", "shin.R", "foot.R", "toe.R"],
    clavicle_on_neck: false,
};

const GENERIC_LR: Names = Names {
    extra_root: None,
    hips: "Pelvis",
    spine: "Spine",
    chest: "Chest",
    neck: "Neck",
    head: "Head",
    left: ["L_Collar", "L_Shoulder", "L_Elbow", "L_Wrist", "L_Hip", "L_Knee", "L_Ankle", "L_Toe"],
    right: ["R_Collar", "R_Shoulder", "R_Elbow", "R_Wrist", "R_Hip", "R_Knee", "R_Ankle", "R_Toe"],
    clavicle_on_neck: false,
};

/// Node indices of the humanoid by role.
#[derive(Debug, Clone, Copy)]
struct Roles {
    hips: usize,
    spine: usize,
    chest: usize,
    neck: usize,
    head: usize,
    left: [usize; 8],
    right: [usize; 8],
}

/// Humanoid hierarchy in metres × `scale`; `z_up` rotates it into a Z-up file (Rx(+90°)).
fn humanoid(n: &Names, scale: f64, z_up: bool) -> (Vec<Node>, Roles) {
    let conv = |v: [f64; 3]| {
        let v = v.map(|x| x * scale);
        if z_up {
            [v[0], -v[2], v[1]]
        } else {
            v
        }
    };
    let mut nodes = Vec::new();
    let root_ch: &[Channel] = &[XP, YP, ZP, ZR, YR, XR];
    let rot: &[Channel] = &[ZR, YR, XR];
    let add = |name: &str, parent: Option<usize>, off: [f64; 3], ch: &[Channel], nodes: &mut Vec<Node>| {
        nodes.push(node(name, parent, conv(off), ch));
        nodes.len() - 1
    };
    let top = n.extra_root.map(|r| add(r, None, [0.0; 3], root_ch, &mut nodes));
    let hips = add(n.hips, top, [0.0; 3], if top.is_some() { rot } else { root_ch }, &mut nodes);
    let spine = add(n.spine, Some(hips), [0.0, 0.1, 0.0], rot, &mut nodes);
    let chest = add(n.chest, Some(spine), [0.0, 0.2, 0.0], rot, &mut nodes);
    let neck = add(n.neck, Some(chest), [0.0, 0.25, 0.0], rot, &mut nodes);
    let head = add(n.head, Some(neck), [0.0, 0.1, 0.0], rot, &mut nodes);
    nodes.push(end_site(head, conv([0.0, 0.15, 0.0]), n.head));
    let limbs = |names: &[&str; 8], sx: f64, nodes: &mut Vec<Node>| {
        let mut idx = [0; 8];
        let (clav_parent, clav_off) =
            if n.clavicle_on_neck { (neck, [0.05 * sx, -0.05, 0.0]) } else { (chest, [0.05 * sx, 0.2, 0.0]) };
        idx[0] = add(names[0], Some(clav_parent), clav_off, rot, nodes);
        idx[1] = add(names[1], Some(idx[0]), [0.12 * sx, 0.0, 0.0], rot, nodes);
        idx[2] = add(names[2], Some(idx[1]), [0.28 * sx, 0.0, 0.0], rot, nodes);
        idx[3] = add(names[3], Some(idx[2]), [0.25 * sx, 0.0, 0.0], rot, nodes);
        nodes.push(end_site(idx[3], conv([0.08 * sx, 0.0, 0.0]), names[3]));
        idx[4] = add(names[4], Some(hips), [0.1 * sx, -0.05, 0.0], rot, nodes);
        idx[5] = add(names[5], Some(idx[4]), [0.0, -0.42, 0.0], rot, nodes);
        idx[6] = add(names[6], Some(idx[5]), [0.0, -0.42, 0.0], rot, nodes);
        idx[7] = add(names[7], Some(idx[6]), [0.0, -0.06, 0.12], rot, nodes);
        nodes.push(end_site(idx[7], conv([0.0, 0.0, 0.05]), names[7]));
        idx
    };
    let left = limbs(&n.left, 1.0, &mut nodes);
    let right = limbs(&n.right, -1.0, &mut nodes);
    (nodes, Roles { hips, spine, chest, neck, head, left, right })
}

fn channel_count(nodes: &[Node]) -> usize {
    nodes.iter().map(|n| n.channels.len()).sum()
}

/// A frame: root at `root` (metres × scale, file axes), yaw `yaw` degrees about the up axis,
/// and a fixed non-trivial pose on the limbs (so facing is tested on more than a T-pose).
fn pose_frame(nodes: &[Node], roles: &Roles, root: [f64; 3], yaw: f64, z_up: bool) -> Vec<f64> {
    let mut v = vec![0.0; channel_count(nodes)];
    let mut starts = Vec::new();
    let mut s = 0;
    for n in nodes {
        starts.push(s);
        s += n.channels.len();
    }
    let top = 0;
    v[starts[top]..starts[top] + 3].copy_from_slice(&root);
    // Root channels are Zrot Yrot Xrot after the positions: yaw is about Y (Y-up) or Z (Z-up).
    if z_up {
        v[starts[top] + 3] = yaw;
    } else {
        v[starts[top] + 4] = yaw;
    }
    // Bend: left elbow 40° about Z, right upper arm −60° about Z, left knee 30° about X,
    // chest twist 10° about Y (ZYX order: slot 0 = Z, 1 = Y, 2 = X).
    // In a Z-up file the same pose needs C·R·C⁻¹ (C = Rx(90°)): about X stays about X, about
    // Y(up) becomes about Z, about Z becomes about −Y.
    let (z_slot, z_sign, y_slot) = if z_up { (1, -1.0, 0) } else { (0, 1.0, 1) };
    let set = |v: &mut Vec<f64>, joint: usize, slot: usize, deg: f64| v[starts[joint] + slot] = deg;
    set(&mut v, roles.left[2], z_slot, z_sign * 40.0);
    set(&mut v, roles.right[1], z_slot, z_sign * -60.0);
    set(&mut v, roles.left[5], 2, 30.0);
    set(&mut v, roles.chest, y_slot, 10.0);
    v
}

fn standing(n: &Names, scale: f64, z_up: bool, yaw: f64) -> (Motion, Roles) {
    let (nodes, roles) = humanoid(n, scale, z_up);
    let h = 0.95 * scale;
    let root = if z_up { [0.3 * scale, -0.2 * scale, h] } else { [0.3 * scale, h, 0.2 * scale] };
    let frames = vec![pose_frame(&nodes, &roles, root, yaw, z_up); 3];
    (motion(&nodes, 1.0 / 30.0, &frames), roles)
}

// ---------------------------------------------------------------------------------------------
// Canonical joints

fn check_mapping(n: &Names) {
    let (m, r) = standing(n, 1.0, false, 0.0);
    let map = map_joints(&m.skeleton).unwrap_or_else(|e| panic!("{}: {e}", n.hips));
    let expect = [
        (Canonical::Hips, r.hips),
        (Canonical::Spine, r.spine),
        (Canonical::Chest, r.chest),
        (Canonical::Neck, r.neck),
        (Canonical::Head, r.head),
        (Canonical::LeftShoulder, r.left[1]),
        (Canonical::LeftElbow, r.left[2]),
        (Canonical::LeftHand, r.left[3]),
        (Canonical::RightShoulder, r.right[1]),
        (Canonical::RightElbow, r.right[2]),
        (Canonical::RightHand, r.right[3]),
        (Canonical::LeftHip, r.left[4]),
        (Canonical::LeftKnee, r.left[5]),
        (Canonical::LeftFoot, r.left[6]),
        (Canonical::RightHip, r.right[4]),
        (Canonical::RightKnee, r.right[5]),
        (Canonical::RightFoot, r.right[6]),
    ];
    for (c, i) in expect {
        assert_eq!(m.skeleton.names[map.get(c)], m.skeleton.names[i], "convention of {}: canonical {c}", n.hips);
    }
    assert_eq!(map.left_toe, Some(r.left[7]), "{}", n.hips);
    assert_eq!(map.right_toe, Some(r.right[7]), "{}", n.hips);
}

#[test]
fn maps_motionbuilder_names() {
    check_mapping(&MOTIONBUILDER);
}

#[test]
fn maps_mixamo_names_with_namespace() {
    check_mapping(&MIXAMO);
}

#[test]
fn maps_3dsmax_friendly_names() {
    check_mapping(&MAX3DS);
}

#[test]
fn maps_daz_friendly_names() {
    check_mapping(&DAZ);
}

#[test]
fn maps_biped_names_with_extra_root_and_clavicles_on_neck() {
    check_mapping(&BIPED);
}

#[test]
fn maps_asf_like_lowercase_names() {
    check_mapping(&ASF);
}

#[test]
fn maps_unreal_style_suffix_names() {
    check_mapping(&UNREAL);
}

#[test]
fn maps_blender_dot_side_names() {
    check_mapping(&BLENDER);
}

#[test]
fn maps_generic_l_r_prefix_names() {
    check_mapping(&GENERIC_LR);
}

#[test]
fn unmappable_skeleton_names_the_missing_joints() {
    let nodes = [
        node("Hips", None, [0.0; 3], &[XP, YP, ZP]),
        node("Torso", Some(0), [0.0, 0.5, 0.0], &[ZR]),
        node("Head", Some(1), [0.0, 0.3, 0.0], &[ZR]),
        node("LeftUpLeg", Some(0), [0.1, 0.0, 0.0], &[ZR]),
        node("LeftLeg", Some(3), [0.0, -0.4, 0.0], &[ZR]),
        node("LeftFoot", Some(4), [0.0, -0.4, 0.0], &[ZR]),
    ];
    let m = motion(&nodes, 0.1, &[vec![0.0; 8]]);
    let err = map_joints(&m.skeleton).unwrap_err();
    assert_eq!(
        err.missing,
        vec![
            Canonical::Spine,
            Canonical::Chest,
            Canonical::LeftShoulder,
            Canonical::LeftElbow,
            Canonical::LeftHand,
            Canonical::RightShoulder,
            Canonical::RightElbow,
            Canonical::RightHand,
            Canonical::RightHip,
            Canonical::RightKnee,
            Canonical::RightFoot,
        ]
    );
    let msg = err.to_string();
    assert!(
        msg.starts_with("cannot map the skeleton to the 17 canonical joints: 6 found (Hips, Neck as Torso, Head, ")
            && msg.contains(", 11 missing (Spine, Chest, LeftShoulder,"),
        "{msg}"
    );
    assert!(msg.contains("RightFoot). Joints are matched by name"), "{msg}");
    assert!(msg.ends_with("Joints in the file: Hips, Torso, Head, LeftUpLeg, LeftLeg, LeftFoot"), "{msg}");
    assert_eq!(err.found.len() + err.missing.len(), 17);
}

#[test]
fn a_joint_named_like_a_missing_one_is_explained_not_contradicted() {
    // a left hand beside the arm, not below its elbow: LeftHand is missing though a joint of that
    // name is in the file, and the message says how joints are matched
    let nodes = [
        node("Hips", None, [0.0; 3], &[XP, YP, ZP]),
        node("LeftArm", Some(0), [0.2, 0.5, 0.0], &[ZR]),
        node("LeftForeArm", Some(1), [0.3, 0.0, 0.0], &[ZR]),
        node("LeftHand", Some(0), [0.3, 0.5, 0.0], &[ZR]),
        node("Head", Some(0), [0.0, 0.6, 0.0], &[ZR]),
    ];
    let m = motion(&nodes, 0.1, &[vec![0.0; 7]]);
    let err = map_joints(&m.skeleton).unwrap_err();
    assert!(err.missing.contains(&Canonical::LeftHand), "{err}");
    assert!(err.found.contains(&(Canonical::LeftElbow, "LeftForeArm".to_string())), "{err}");
    assert!(!err.found.iter().any(|(_, name)| name == "LeftHand"), "{:?}", err.found);
    let msg = err.to_string();
    assert!(msg.contains("LeftElbow as LeftForeArm"), "{msg}");
    assert!(msg.contains("each below the one before it in its chain when that one is found"), "{msg}");
    assert!(msg.ends_with("Joints in the file: Hips, LeftArm, LeftForeArm, LeftHand, Head"), "{msg}");
}

// ---------------------------------------------------------------------------------------------
// Units and up axis

#[test]
fn detects_units_from_body_size() {
    let cases = [
        (1.0, Units::Metres),
        (100.0, Units::Centimetres),
        (1000.0, Units::Millimetres),
        (1.0 / 0.0254, Units::Inches),
        (1.0 / 0.056444, Units::CmuAsf),
    ];
    for (scale, units) in cases {
        for z_up in [false, true] {
            let (m, _) = standing(&MOTIONBUILDER, scale, z_up, 0.0);
            assert_eq!(m.units, units, "scale {scale}, z_up {z_up}");
            assert_eq!(m.up_axis, if z_up { UpAxis::Z } else { UpAxis::Y }, "scale {scale}");
            assert!(m.warnings.is_empty(), "{:?}", m.warnings);
        }
    }
}

#[test]
fn detects_units_and_up_without_recognised_names() {
    for (scale, units) in [(100.0, Units::Centimetres), (1.0 / 0.056444, Units::CmuAsf), (1.0, Units::Metres)] {
        for z_up in [false, true] {
            let (mut nodes, _) = humanoid(&MOTIONBUILDER, scale, z_up);
            for (i, n) in nodes.iter_mut().enumerate() {
                n.name = format!("j{i}");
            }
            let root = if z_up { [0.0, 0.0, 0.95 * scale] } else { [0.0, 0.95 * scale, 0.0] };
            let mut frame = vec![0.0; channel_count(&nodes)];
            frame[..3].copy_from_slice(&root);
            let m = motion(&nodes, 0.1, &[frame]);
            assert_eq!(m.units, units, "scale {scale}");
            assert_eq!(m.up_axis, if z_up { UpAxis::Z } else { UpAxis::Y });
            assert!(m.warnings.iter().any(|w| w.contains("guessed")), "{:?}", m.warnings);
        }
    }
}

#[test]
fn unit_names_and_factors() {
    assert_eq!(Units::CmuAsf.metres_per_unit(), 0.056444);
    assert_eq!(Units::Inches.metres_per_unit(), 0.0254);
    assert_eq!(Units::CmuAsf.name(), "cmu_asf");
    assert_eq!(serde_json::to_string(&Units::Centimetres).unwrap(), "\"centimetres\"");
    assert_eq!(serde_json::from_str::<Units>("\"cmu_asf\"").unwrap(), Units::CmuAsf);
    for u in Units::ALL {
        assert_eq!(Units::from_name(u.name()), Some(u));
    }
    assert!((to_inches(Units::Metres) - 39.370_078_740_157_48).abs() < 1e-9);
    assert!((to_inches(Units::CmuAsf) - 2.222_204_724_409_449).abs() < 1e-9);
    assert_eq!(to_inches(Units::Inches), 1.0);
}

// ---------------------------------------------------------------------------------------------
// Normalisation

#[test]
fn end_effector_features_of_the_rest_pose() {
    let (nodes, _) = humanoid(&MOTIONBUILDER, 1.0, false);
    let mut frame = vec![0.0; channel_count(&nodes)];
    frame[..3].copy_from_slice(&[2.0, 0.95, -1.0]);
    let m = motion(&nodes, 0.1, &[frame]);
    let map = map_joints(&m.skeleton).unwrap();
    let f = end_effector_features(&m, &map);
    assert_eq!(f.len(), 1);
    let expect = [
        0.70, 0.5, 0.0, // left hand: clavicle (0.05, 0.2) + 0.12 + 0.28 + 0.25 along +X, above Spine1
        -0.70, 0.5, 0.0, // right hand
        0.1, -0.89, 0.0, // left ankle
        -0.1, -0.89, 0.0, // right ankle
        0.0, 0.65, 0.0, // head
    ];
    for (a, b) in f[0].iter().zip(expect) {
        assert!((a - b).abs() < 1e-5, "{:?}", f[0]);
    }
    assert!((body_size(&m.skeleton, &map) - (0.84 + 0.65)).abs() < 1e-9);
}

#[test]
fn facing_yaw_follows_root_yaw() {
    // The pose twists the chest 10° about the vertical: the shoulder line turns 10°, the hip
    // line does not, and the facing (their bisector) is 5° left of the root's yaw.
    for yaw in [0.0, 90.0, -137.0, 179.0] {
        let (m, _) = standing(&MOTIONBUILDER, 1.0, false, yaw);
        let map = map_joints(&m.skeleton).unwrap();
        let got = facing_yaws(&m, &map)[0].to_degrees() as f64;
        let diff = (got - yaw - 5.0 + 540.0).rem_euclid(360.0) - 180.0;
        assert!(diff.abs() < 0.01, "yaw {yaw}: got {got}");
    }
}

#[test]
fn facing_alignment_removes_rotation_about_up() {
    let (m0, _) = standing(&MOTIONBUILDER, 1.0, false, 0.0);
    let map = map_joints(&m0.skeleton).unwrap();
    let base = end_effector_features(&m0, &map);
    for (yaw, z_up) in [(90.0, false), (-137.0, false), (0.0, true), (90.0, true), (33.0, true)] {
        let (m, _) = standing(&MOTIONBUILDER, 1.0, z_up, yaw);
        let f = end_effector_features(&m, &map);
        for (a, b) in f[0].iter().zip(base[0].iter()) {
            assert!((a - b).abs() < 1e-5, "yaw {yaw} z_up {z_up}: {:?} vs {:?}", f[0], base[0]);
        }
    }
    // The features are not trivially zero: the pose bends the left elbow up and the left knee.
    assert!(base[0][1] > 0.6, "left hand raised by the elbow bend: {:?}", base[0]);
    let aligned = facing_aligned(&m0, &map);
    assert_eq!(aligned.len(), m0.positions.len());
    assert_eq!(aligned[map.hips], Vec3::ZERO);
}

#[test]
fn root_relative_and_y_up() {
    let (m, _) = standing(&MOTIONBUILDER, 1.0, false, 0.0);
    let rel = root_relative(&m, 0);
    for f in 0..m.frames() {
        assert_eq!(rel[f * m.joints()], Vec3::ZERO);
        assert_eq!(rel[f * m.joints() + 3], m.frame(f)[3] - m.frame(f)[0]);
    }
    assert_eq!(to_y_up(Vec3::new(1.0, 2.0, 3.0), UpAxis::Y), Vec3::new(1.0, 2.0, 3.0));
    assert_eq!(to_y_up(Vec3::new(1.0, 2.0, 3.0), UpAxis::Z), Vec3::new(1.0, 3.0, -2.0));
}

// ---------------------------------------------------------------------------------------------
// Resampling

/// One root with Xposition = g(frame index).
fn ramp(n: usize, frame_time: f64, g: impl Fn(f64) -> f64) -> Motion {
    let nodes = [node("Root", None, [0.0; 3], &[XP]), end_site(0, [0.0, 1.0, 0.0], "Root")];
    let frames: Vec<Vec<f64>> = (0..n).map(|f| vec![g(f as f64)]).collect();
    motion(&nodes, frame_time, &frames)
}

#[test]
fn resample_120_to_30_picks_every_fourth_frame_exactly() {
    let m = ramp(343, 0.0083333, |f| (f * 0.37).sin() * 10.0);
    let r = m.resample(30.0).unwrap();
    assert_eq!(r.fps, 30.0);
    assert_eq!(r.frames(), 86); // frames 0, 4, …, 340
    for k in 0..r.frames() {
        assert_eq!(r.frame(k), m.frame(4 * k), "frame {k}");
    }
}

#[test]
fn resample_100_to_30_interpolates_linearly() {
    let m = ramp(31, 0.01, |f| f * f);
    let r = m.resample(30.0).unwrap();
    // Source frame of output k is k·10/3; the last source frame is 30 → k ≤ 9.
    assert_eq!(r.frames(), 10);
    for k in 0..10 {
        let s = k as f64 * 10.0 / 3.0;
        let (i, t) = (s.floor(), s - s.floor());
        let expect = i * i + t * ((i + 1.0) * (i + 1.0) - i * i);
        assert!((r.frame(k)[0].x as f64 - expect).abs() < 1e-3, "k {k}: {} vs {expect}", r.frame(k)[0].x);
        assert_eq!(r.frame(k)[1].y, 1.0);
    }
    assert_eq!(r.frame(3)[0].x, 100.0); // k = 3 lands on source frame 10 exactly
}

#[test]
fn resample_upsamples_and_rejects_bad_rates() {
    let m = ramp(5, 1.0 / 30.0, |f| f);
    let r = m.resample(120.0).unwrap();
    assert_eq!(r.frames(), 17);
    assert_eq!(r.frame(1)[0].x, 0.25);
    assert_eq!(r.frame(16)[0].x, 4.0);
    for bad in [0.0, -30.0, f64::NAN, f64::INFINITY] {
        let err = m.resample(bad).unwrap_err();
        assert!(err.to_string().starts_with("target fps must be > 0"), "{err}");
    }
    assert!(matches!(m.resample(1e12), Err(MotionError::TooLarge { .. })));
    let same = m.resample(m.fps).unwrap();
    assert_eq!(same.positions, m.positions);
    assert_eq!(source_positions(343, 120.0005, 30.0).unwrap()[85], 340.0);
}

// ---------------------------------------------------------------------------------------------
// Real files

fn fixture(name: &str) -> Motion {
    let path = format!("{}/tests/fixtures/{name}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let bvh = bvh::parse(&text).unwrap_or_else(|e| panic!("{name}: {e}"));
    Motion::from_bvh(name, &bvh).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn sorted(mut v: Vec<f32>) -> Vec<f32> {
    v.sort_by(|a, b| a.total_cmp(b));
    v
}

#[test]
fn cmu_02_01_stands_on_the_floor_in_cmu_units() {
    let m = fixture("02_01.bvh");
    assert_eq!((m.frames(), m.joints()), (343, 38)); // 31 joints + 7 End Sites
    assert!((m.fps - 1.0 / 0.0083333).abs() < 1e-9);
    assert_eq!(m.units, Units::CmuAsf);
    assert_eq!(m.up_axis, UpAxis::Y);
    assert!(m.warnings.is_empty(), "{:?}", m.warnings);
    let lowest = sorted((0..m.frames()).map(|f| m.frame(f).iter().map(|p| p.y).fold(f32::MAX, f32::min)).collect());
    let root = sorted((0..m.frames()).map(|f| m.frame(f)[0].y).collect());
    let n = m.frames();
    // Some foot touches the floor (y = 0) and no joint sinks more than half a unit (3 cm) into it.
    assert!(lowest[0] > -0.5 && lowest[0] < 0.5, "lowest joint over the take: {}", lowest[0]);
    assert!(lowest[n / 2] > 0.0 && lowest[n / 2] < 1.5, "median lowest joint: {}", lowest[n / 2]);
    // Walking hip height of a CMU subject: 16–18 units ≈ 0.9–1.0 m.
    assert!(root[0] > 16.0 && root[n - 1] < 18.0, "root height {} … {}", root[0], root[n - 1]);
}

#[test]
fn cmu_locomotion_takes_are_cmu_units_y_up_and_walk_forward() {
    for (name, frames) in
        [("02_01.bvh", 343), ("35_01.bvh", 358), ("12_01.bvh", 524), ("131_01.bvh", 994), ("131_03.bvh", 1102)]
    {
        let m = fixture(name);
        assert_eq!(m.frames(), frames, "{name}");
        assert_eq!((m.units, m.up_axis), (Units::CmuAsf, UpAxis::Y), "{name}");
        let map = map_joints(&m.skeleton).unwrap_or_else(|e| panic!("{name}: {e}"));
        // Straight walks: the body faces the way the root travels (checks left/right and the
        // facing sign on real data). 131_03 hops and turns in place, so it is left out.
        if name == "131_03.bvh" {
            continue;
        }
        let yaws = facing_yaws(&m, &map);
        let end = m.frames() - 1;
        let d = m.frame(end)[0] - m.frame(0)[0];
        let travel = d.x.atan2(d.z);
        let facing = yaws[end / 2];
        let diff = (facing - travel).to_degrees();
        assert!(diff.abs() < 20.0, "{name}: facing {:.1}° vs travel {:.1}°", facing.to_degrees(), travel.to_degrees());
    }
}

#[test]
fn scaled_metres_file_is_131_01_times_0_056444() {
    let cmu = fixture("131_01.bvh");
    let metres = fixture("cmu_131_01_scaled_meters.bvh");
    assert_eq!(metres.units, Units::Metres);
    assert_eq!(metres.up_axis, UpAxis::Y);
    // 995 vs 994 frames: row k of the rescaled file is row k of the original; its extra last row
    // repeats row 993.
    assert_eq!((cmu.frames(), metres.frames()), (994, 995));
    assert_eq!(metres.frame(994), metres.frame(993));
    let mut worst = 0.0f32;
    for k in 0..994 {
        for (a, b) in cmu.frame(k).iter().zip(metres.frame(k)) {
            worst = worst.max((*a * 0.056444 - *b).abs().max_element());
        }
    }
    // Both files print 4–6 decimals; the rescaled positions agree to 0.02 mm.
    assert!(worst < 2e-5, "max difference {worst} m");
    // Shifted by one frame they would not agree (the take moves 1–8 cm per frame pair).
    let shifted = (cmu.frame(500)[0] * 0.056444 - metres.frame(501)[0]).length();
    assert!(shifted > 1e-3, "{shifted}");
}

#[track_caller]
fn assert_mapped(name: &str, expect: [&str; 17]) {
    let m = fixture(name);
    let map = map_joints(&m.skeleton).unwrap_or_else(|e| panic!("{name}: {e}"));
    let got: Vec<&str> = map.indices().iter().map(|&i| m.skeleton.names[i].as_str()).collect();
    assert_eq!(got, expect, "{name}");
}

#[test]
fn real_skeletons_map_to_the_canonical_joints() {
    // Order: Hips Spine Chest Neck Head, L shoulder/elbow/hand, R …, L hip/knee/foot, R …
    assert_mapped(
        "02_01.bvh",
        [
            "Hips",
            "Spine",
            "Spine1",
            "Neck",
            "Head",
            "LeftArm",
            "LeftForeArm",
            "LeftHand",
            "RightArm",
            "RightForeArm",
            "RightHand",
            "LeftUpLeg",
            "LeftLeg",
            "LeftFoot",
            "RightUpLeg",
            "RightLeg",
            "RightFoot",
        ],
    );
    assert_mapped(
        "131_01.bvh",
        [
            "Hips",
            "lowerback",
            "Chest2",
            "lowerneck",
            "Head",
            "LeftShoulder",
            "LeftElbow",
            "LeftWrist",
            "RightShoulder",
            "RightElbow",
            "RightWrist",
            "LeftHip",
            "LeftKnee",
            "LeftAnkle",
            "RightHip",
            "RightKnee",
            "RightAnkle",
        ],
    );
    assert_mapped(
        "mixamo_names_freebvh.bvh",
        [
            "mixamorig:Hips",
            "mixamorig:Spine",
            "mixamorig:Spine2",
            "mixamorig:Neck",
            "mixamorig:Head",
            "mixamorig:LeftArm",
            "mixamorig:LeftForeArm",
            "mixamorig:LeftHand",
            "mixamorig:RightArm",
            "mixamorig:RightForeArm",
            "mixamorig:RightHand",
            "mixamorig:LeftUpLeg",
            "mixamorig:LeftLeg",
            "mixamorig:LeftFoot",
            "mixamorig:RightUpLeg",
            "mixamorig:RightLeg",
            "mixamorig:RightFoot",
        ],
    );
    assert_mapped(
        "gpmat_Swagger2_1frame.bvh",
        [
            "root",
            "lowerback",
            "thorax",
            "neck",
            "head",
            "lhumerus",
            "lradius",
            "lhand",
            "rhumerus",
            "rradius",
            "rhand",
            "lfemur",
            "ltibia",
            "lfoot",
            "rfemur",
            "rtibia",
            "rfoot",
        ],
    );
    assert_mapped(
        "assimp_Boxing_Toes_100fps.bvh",
        [
            "Hips",
            "Ab",
            "Chest",
            "Neck",
            "Head",
            "LeftShoulder",
            "LeftElbow",
            "LeftWrist",
            "RightShoulder",
            "RightElbow",
            "RightWrist",
            "LeftHip",
            "LeftKnee",
            "LeftAnkle",
            "RightHip",
            "RightKnee",
            "RightAnkle",
        ],
    );
    for name in ["pybvh_bvh_test1.bvh", "pybvh_bvh_test3.bvh", "pybvh_standard_skeleton_1frame.bvh"] {
        assert_mapped(
            name,
            [
                "Hips",
                "Spine",
                "Spine3",
                "Neck",
                "Head",
                "LeftArm",
                "LeftForeArm",
                "LeftHand",
                "RightArm",
                "RightForeArm",
                "RightHand",
                "LeftUpLeg",
                "LeftLeg",
                "LeftFoot",
                "RightUpLeg",
                "RightLeg",
                "RightFoot",
            ],
        );
    }
    // Hips → Chest → Chest2 → Chest3 → Chest4 → Neck: the arms leave at Chest4; no joint is
    // called a spine, so Spine is the one nearest the Hips–Chest4 midpoint.
    assert_mapped(
        "pybvh_bvh_test2.bvh",
        [
            "Hips",
            "Chest2",
            "Chest4",
            "Neck",
            "Head",
            "LeftShoulder",
            "LeftElbow",
            "LeftWrist",
            "RightShoulder",
            "RightElbow",
            "RightWrist",
            "LeftHip",
            "LeftKnee",
            "LeftAnkle",
            "RightHip",
            "RightKnee",
            "RightAnkle",
        ],
    );
}

#[test]
fn real_skeletons_without_a_body_name_what_is_missing() {
    let m = fixture("pybvh_full_precision_frame_time.bvh"); // Hips → Head only
    let err = map_joints(&m.skeleton).unwrap_err();
    assert_eq!(err.missing.len(), 15);
    assert!(!err.missing.contains(&Canonical::Head) && !err.missing.contains(&Canonical::Hips));
    assert_eq!(
        err.to_string(),
        "cannot map the skeleton to the 17 canonical joints: 2 found (Hips, Head), 15 missing (Spine, Chest, Neck, \
         LeftShoulder, LeftElbow, LeftHand, RightShoulder, RightElbow, RightHand, LeftHip, LeftKnee, LeftFoot, \
         RightHip, RightKnee, RightFoot). Joints are matched by name, each below the one before it in its chain when \
         that one is found (hips, spine, chest, neck, head; shoulder, elbow, hand; hip, knee, foot), so a joint \
         named like a missing one may sit elsewhere. Joints in the file: Hips, Head"
    );
    let m = fixture("bvh_anim_test_simple.bvh"); // Base → End
    let err = map_joints(&m.skeleton).unwrap_err();
    assert_eq!(err.missing.len(), 16);
    assert!(err.to_string().contains("16 missing (Spine, Chest, Neck, Head, LeftShoulder"), "{err}");
    assert!(err.to_string().ends_with("Joints in the file: Base, End"), "{err}");
}

#[test]
fn real_files_units_and_up_axis() {
    // (file, units, up): Mixamo/assimp/gpmat are centimetre rigs (hip height 92–98 units); the
    // pybvh rigs are Z-up (spine offsets along +Z) and 60–66 units tall, i.e. inches (in cm
    // they would be 0.65 m adults).
    for (name, units, up) in [
        ("mixamo_names_freebvh.bvh", Units::Centimetres, UpAxis::Y),
        ("assimp_Boxing_Toes_100fps.bvh", Units::Centimetres, UpAxis::Y),
        ("gpmat_Swagger2_1frame.bvh", Units::Centimetres, UpAxis::Y),
        ("pybvh_bvh_test2.bvh", Units::Centimetres, UpAxis::Y),
        ("pybvh_bvh_test1.bvh", Units::Inches, UpAxis::Z),
        ("pybvh_bvh_test3.bvh", Units::Inches, UpAxis::Z),
        ("pybvh_standard_skeleton_1frame.bvh", Units::Inches, UpAxis::Z),
        ("12_01.bvh", Units::CmuAsf, UpAxis::Y),
    ] {
        let m = fixture(name);
        assert_eq!((m.units, m.up_axis), (units, up), "{name}");
    }
    // The assimp file's `Frames:` disagreement reaches the motion's warnings.
    let m = fixture("assimp_Boxing_Toes_100fps.bvh");
    assert_eq!(m.frames(), 3070);
    assert!(m.warnings.iter().any(|w| w.contains("3069") && w.contains("3070")), "{:?}", m.warnings);
    // Full-precision frame time survives into the motion.
    let m = fixture("pybvh_full_precision_frame_time.bvh");
    assert_eq!(m.fps, 1.0 / 0.0417083750417);
    assert!((m.duration_s() - 3.0 * 0.0417083750417).abs() < 1e-12);
}

#[test]
fn cmu_take_resampled_to_30_hz() {
    let m = fixture("02_01.bvh");
    let r = m.resample(30.0).unwrap();
    assert_eq!(r.frames(), 86);
    for k in 0..r.frames() {
        assert_eq!(r.frame(k), m.frame(4 * k));
    }
    let b = fixture("assimp_Boxing_Toes_100fps.bvh");
    let r = b.resample(30.0).unwrap();
    assert_eq!(r.frames(), 3069 * 3 / 10 + 1); // last source frame 3069 → k ≤ 920
    let (i, t) = (3usize, 1.0f32 / 3.0); // k = 1 → source frame 10/3
    let expect = b.frame(i)[5].lerp(b.frame(i + 1)[5], t);
    assert!((r.frame(1)[5] - expect).length() < 1e-4);
}

#[test]
fn end_effector_features_on_a_real_take() {
    let m = fixture("02_01.bvh");
    let map = map_joints(&m.skeleton).unwrap();
    let f = end_effector_features(&m, &map);
    assert_eq!(f.len(), m.frames());
    for (k, v) in f.iter().enumerate() {
        // Facing +Z, Y up: hands on their own side, feet below the hips, head above.
        assert!(v[0] > 0.0 && v[3] < 0.0, "frame {k}: hands x {} {}", v[0], v[3]);
        assert!(v[7] < -12.0 && v[10] < -12.0, "frame {k}: feet y {} {}", v[7], v[10]);
        assert!(v[13] > 8.0, "frame {k}: head y {}", v[13]);
    }
    // Walking: the feet alternate front/back along +Z.
    let zs: Vec<f32> = f.iter().map(|v| v[8] - v[11]).collect();
    assert!(zs.iter().cloned().fold(f32::MIN, f32::max) > 3.0);
    assert!(zs.iter().cloned().fold(f32::MAX, f32::min) < -3.0);
}

#[test]
fn skeleton_with_a_parent_cycle_does_not_hang_the_mapper() {
    let s = mocapseg::motion::Skeleton {
        names: vec!["Hips".into(), "Head".into()],
        parents: vec![Some(1), Some(0)],
        offsets: vec![[0.0; 3]; 2],
        is_end_site: vec![false; 2],
    };
    assert!(!s.is_ancestor_or_self(5, 0));
    let err = map_joints(&s).unwrap_err();
    assert!(err.missing.contains(&Canonical::LeftHand));
}

// ---------------------------------------------------------------------------------------------
// Positions as CSV

#[test]
fn positions_csv_reads_back_with_a_csv_reader_even_with_commas_in_names() {
    let nodes = [
        node("Hips", None, [0.0; 3], &[XP, YP, ZP]),
        node("Left, \"Arm\"", Some(0), [1.0, 0.0, 0.0], &[]),
        end_site(1, [0.0, 2.0, 0.0], "Left, \"Arm\""),
    ];
    let m = motion(&nodes, 0.5, &[vec![0.0, 0.0, 0.0], vec![0.25, -1.5, 3.0]]);
    for end_sites in [false, true] {
        let mut out = Vec::new();
        mocapseg::motion::write_positions_csv(&m, end_sites, &mut out).expect("writes");
        let mut r = csv::Reader::from_reader(out.as_slice());
        let header: Vec<String> = r.headers().expect("header").iter().map(String::from).collect();
        let mut expected = vec!["frame", "time_s", "Hips_x", "Hips_y", "Hips_z"];
        expected.extend(["Left, \"Arm\"_x", "Left, \"Arm\"_y", "Left, \"Arm\"_z"]);
        if end_sites {
            expected.extend(["Left, \"Arm\"_End_x", "Left, \"Arm\"_End_y", "Left, \"Arm\"_End_z"]);
        }
        assert_eq!(header, expected);
        let rows: Vec<Vec<f64>> = r
            .records()
            .map(|rec| rec.expect("record").iter().map(|v| v.parse().expect("a number")).collect())
            .collect();
        assert_eq!(rows.len(), 2);
        for (f, row) in rows.iter().enumerate() {
            assert_eq!(row.len(), header.len());
            assert_eq!((row[0], row[1]), (f as f64, f as f64 * 0.5));
            for j in 0..(header.len() - 2) / 3 {
                let p = m.position(f, j);
                let got: Vec<f32> = row[2 + 3 * j..5 + 3 * j].iter().map(|&v| v as f32).collect();
                assert_eq!(got, p.to_array(), "frame {f} joint {j}");
            }
        }
    }
}
