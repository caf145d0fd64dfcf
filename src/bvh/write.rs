//! The BVH writer: standard BVH text that [`super::parse`] reads back to the same values.
//!
//! Layout: `HIERARCHY`, each root tree with one tab of indentation per level, `End Site`s
//! written without a name (the parser names them `<parent>_End` again), then `MOTION`,
//! `Frames: n` (the rows present, see [`Bvh::frames`]), `Frame Time: t` and one line per frame.
//! Lines end with `\n`.
//!
//! Every number (offsets, frame time, channel values) is printed in Rust's shortest form that
//! reads back to the identical `f64` (`{}` for ordinary magnitudes, `{:e}` for very large or
//! very small ones so no value prints as hundreds of digits). So parse → write → parse gives
//! bit-identical values, the frame time included (`0.0417083750417` stays exactly that).
//!
//! The tree is rebuilt from the `parent` indices and frame values are taken through each
//! joint's `channel_start`, so a [`Bvh`] whose nodes are not in depth-first order still writes a
//! consistent file. Precondition: the `Bvh` is consistent (as the parser makes it): parents
//! point at existing nodes without cycles and every joint's channels lie inside a frame row.
//! Nodes unreachable from a root and values outside the rows are skipped (written as 0) rather
//! than panicking.

use std::fmt::Write as _;

use super::{Bvh, BvhJoint, JointKind};

/// Writes a [`Bvh`] as BVH text.
pub fn write(bvh: &Bvh) -> String {
    let children = children_of(&bvh.joints);
    let order = depth_first(&bvh.joints, &children);
    let mut out = String::with_capacity(estimate_len(bvh));
    out.push_str("HIERARCHY\n");
    write_hierarchy(&mut out, bvh, &children);
    write_motion(&mut out, bvh, &order);
    out
}

/// Children of every node, in node order.
fn children_of(joints: &[BvhJoint]) -> Vec<Vec<usize>> {
    let mut children = vec![Vec::new(); joints.len()];
    for (i, j) in joints.iter().enumerate() {
        if let Some(p) = j.parent.filter(|&p| p < joints.len() && p != i) {
            children[p].push(i);
        }
    }
    children
}

fn roots(joints: &[BvhJoint]) -> impl Iterator<Item = usize> + '_ {
    joints.iter().enumerate().filter(|(_, j)| j.parent.is_none_or(|p| p >= joints.len())).map(|(i, _)| i)
}

/// Nodes in the order they are written (depth first, roots in node order). Each node is
/// visited once even if the parent links were cyclic.
fn depth_first(joints: &[BvhJoint], children: &[Vec<usize>]) -> Vec<usize> {
    let mut seen = vec![false; joints.len()];
    let mut order = Vec::with_capacity(joints.len());
    for root in roots(joints) {
        let mut stack = vec![root];
        while let Some(i) = stack.pop() {
            if std::mem::replace(&mut seen[i], true) {
                continue;
            }
            order.push(i);
            stack.extend(children[i].iter().rev());
        }
    }
    order
}

/// One event of the iterative hierarchy walk.
enum Step {
    Open(usize, usize),
    Close(usize),
}

fn write_hierarchy(out: &mut String, bvh: &Bvh, children: &[Vec<usize>]) {
    let mut seen = vec![false; bvh.joints.len()];
    for root in roots(&bvh.joints) {
        let mut stack = vec![Step::Open(root, 0)];
        while let Some(step) = stack.pop() {
            match step {
                Step::Close(depth) => {
                    indent(out, depth);
                    out.push_str("}\n");
                }
                Step::Open(i, depth) => {
                    if std::mem::replace(&mut seen[i], true) {
                        continue;
                    }
                    write_node_head(out, &bvh.joints[i], depth);
                    stack.push(Step::Close(depth));
                    stack.extend(children[i].iter().rev().map(|&c| Step::Open(c, depth + 1)));
                }
            }
        }
    }
}

/// Writes the keyword line, `{`, OFFSET and CHANNELS of one node.
fn write_node_head(out: &mut String, joint: &BvhJoint, depth: usize) {
    indent(out, depth);
    // A node is written as what its place in the tree makes it: top level = ROOT.
    match (joint.kind, depth) {
        (_, 0) => push_line(out, &format!("ROOT {}", joint.name)),
        (JointKind::EndSite, _) => push_line(out, "End Site"),
        _ => push_line(out, &format!("JOINT {}", joint.name)),
    }
    indent(out, depth);
    out.push_str("{\n");
    indent(out, depth + 1);
    out.push_str("OFFSET");
    for v in joint.offset {
        out.push(' ');
        push_number(out, v);
    }
    out.push('\n');
    if joint.kind != JointKind::EndSite {
        indent(out, depth + 1);
        let _ = write!(out, "CHANNELS {}", joint.channels.len());
        for c in &joint.channels {
            out.push(' ');
            out.push_str(c.name());
        }
        out.push('\n');
    }
}

fn write_motion(out: &mut String, bvh: &Bvh, order: &[usize]) {
    out.push_str("MOTION\n");
    let _ = writeln!(out, "Frames: {}", bvh.frames());
    out.push_str("Frame Time: ");
    push_number(out, bvh.frame_time);
    out.push('\n');
    let cpf = bvh.channels_per_frame;
    if cpf == 0 {
        return;
    }
    for row in bvh.values.chunks_exact(cpf) {
        let mut first = true;
        for &i in order {
            let j = &bvh.joints[i];
            if j.kind == JointKind::EndSite {
                continue;
            }
            for k in 0..j.channels.len() {
                if !first {
                    out.push(' ');
                }
                first = false;
                push_number(out, row.get(j.channel_start + k).copied().unwrap_or(0.0));
            }
        }
        out.push('\n');
    }
}

fn indent(out: &mut String, depth: usize) {
    out.extend(std::iter::repeat_n('\t', depth));
}

fn push_line(out: &mut String, line: &str) {
    out.push_str(line);
    out.push('\n');
}

/// The shortest text that parses back to exactly `v`, without hundreds of digits for extreme
/// magnitudes. Non-finite values (which the parser never produces) are written as 0.
fn push_number(out: &mut String, v: f64) {
    let a = v.abs();
    let _ = if !v.is_finite() {
        write!(out, "0")
    } else if a == 0.0 || (1e-5..1e16).contains(&a) {
        write!(out, "{v}")
    } else {
        write!(out, "{v:e}")
    };
}

fn estimate_len(bvh: &Bvh) -> usize {
    bvh.joints.len() * 80 + bvh.values.len().saturating_mul(9) + 64
}

#[cfg(test)]
mod tests {
    use super::super::{parse, Channel};
    use super::*;

    fn joint(name: &str, kind: JointKind, parent: Option<usize>, channels: &[Channel], start: usize) -> BvhJoint {
        BvhJoint {
            name: name.into(),
            kind,
            parent,
            offset: [1.0, 2.5, -3.0],
            channels: channels.to_vec(),
            channel_start: start,
        }
    }

    #[test]
    fn numbers_are_shortest_round_trip_text() {
        for v in [0.0, -0.0, 1.0, 0.1, -12.3456, 0.0417083750417, 1e-7, 3.5e20, f64::MAX, f64::MIN_POSITIVE, 5e-324] {
            let mut s = String::new();
            push_number(&mut s, v);
            assert!(s.len() <= 24, "{s}");
            assert_eq!(s.parse::<f64>().map(f64::to_bits), Ok(v.to_bits()), "{s}");
        }
        let mut s = String::new();
        push_number(&mut s, 0.0417083750417);
        assert_eq!(s, "0.0417083750417");
    }

    #[test]
    fn writes_standard_layout_with_tabs() {
        use Channel::*;
        let bvh = Bvh {
            joints: vec![
                joint(
                    "Hips",
                    JointKind::Root,
                    None,
                    &[Xposition, Yposition, Zposition, Zrotation, Yrotation, Xrotation],
                    0,
                ),
                joint("Spine", JointKind::Joint, Some(0), &[Zrotation, Xrotation, Yrotation], 6),
                joint("Spine_End", JointKind::EndSite, Some(1), &[], 9),
            ],
            frame_time: 1.0 / 30.0,
            declared_frames: 1,
            channels_per_frame: 9,
            values: (0..9).map(f64::from).collect(),
            warnings: vec![],
        };
        let text = write(&bvh);
        let expected = "HIERARCHY\nROOT Hips\n{\n\tOFFSET 1 2.5 -3\n\tCHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation\n\tJOINT Spine\n\t{\n\t\tOFFSET 1 2.5 -3\n\t\tCHANNELS 3 Zrotation Xrotation Yrotation\n\t\tEnd Site\n\t\t{\n\t\t\tOFFSET 1 2.5 -3\n\t\t}\n\t}\n}\nMOTION\nFrames: 1\nFrame Time: 0.03333333333333333\n0 1 2 3 4 5 6 7 8\n";
        assert_eq!(text, expected);
        assert_eq!(parse(&text).expect("parses"), bvh);
    }

    #[test]
    fn nodes_out_of_order_are_written_as_a_tree_with_their_own_values() {
        use Channel::*;
        // Node 0 is a child of node 1, and its channels sit first in the row.
        let bvh = Bvh {
            joints: vec![
                joint("Arm", JointKind::Joint, Some(1), &[Xrotation], 0),
                joint("Root", JointKind::Root, None, &[Yposition, Zrotation], 1),
            ],
            frame_time: 0.01,
            declared_frames: 2,
            channels_per_frame: 3,
            values: vec![10.0, 20.0, 30.0, 11.0, 21.0, 31.0],
            warnings: vec![],
        };
        let back = parse(&write(&bvh)).expect("parses");
        assert_eq!(back.joints[0].name, "Root");
        assert_eq!(back.joints[1].name, "Arm");
        assert_eq!(back.joints[1].parent, Some(0));
        assert_eq!(back.values, vec![20.0, 30.0, 10.0, 21.0, 31.0, 11.0]);
    }

    #[test]
    fn inconsistent_input_does_not_panic() {
        let bvh = Bvh {
            joints: vec![
                joint("A", JointKind::Joint, Some(1), &[Channel::Xrotation], 5),
                joint("B", JointKind::Joint, Some(0), &[], 0),
                joint("C", JointKind::Root, Some(99), &[], 0),
            ],
            frame_time: f64::NAN,
            declared_frames: 0,
            channels_per_frame: 1,
            values: vec![1.0, 2.0],
            warnings: vec![],
        };
        let text = write(&bvh);
        assert!(text.starts_with("HIERARCHY\nROOT C\n"));
    }
}
