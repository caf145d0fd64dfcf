//! BVH (Biovision Hierarchy) files: the data model, a parser, a writer and a packed form.
//!
//! The parser accepts the whole format as exporters write it (see `parse.rs`); the writer
//! produces a file that parses back to the same values within print precision (`write.rs`);
//! `pack.rs` ships a file in about half its gzipped size and gives back the same bytes (the
//! page's bundled sample).

mod error;
mod pack;
mod parse;
mod write;

pub use error::{BvhError, Warning};
pub use pack::{pack, unpack, unpacked_name, PackError, MAX_UNPACKED_BYTES, PACK_EXTENSION};
pub(crate) use parse::FrameBudget;
pub use parse::{parse, parse_with_progress, ParseLimits, NO_MOTION_FRAME_TIME};
pub use write::write;

use serde::{Deserialize, Serialize};

/// One of the six BVH channels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Channel {
    Xposition,
    Yposition,
    Zposition,
    Xrotation,
    Yrotation,
    Zrotation,
}

impl Channel {
    /// The six channels, positions then rotations, X Y Z.
    pub const ALL: [Channel; 6] = [
        Channel::Xposition,
        Channel::Yposition,
        Channel::Zposition,
        Channel::Xrotation,
        Channel::Yrotation,
        Channel::Zrotation,
    ];

    /// The name as written in a BVH file.
    pub fn name(self) -> &'static str {
        match self {
            Channel::Xposition => "Xposition",
            Channel::Yposition => "Yposition",
            Channel::Zposition => "Zposition",
            Channel::Xrotation => "Xrotation",
            Channel::Yrotation => "Yrotation",
            Channel::Zrotation => "Zrotation",
        }
    }

    /// Axis index 0 = X, 1 = Y, 2 = Z.
    pub fn axis(self) -> usize {
        match self {
            Channel::Xposition | Channel::Xrotation => 0,
            Channel::Yposition | Channel::Yrotation => 1,
            Channel::Zposition | Channel::Zrotation => 2,
        }
    }

    pub fn is_rotation(self) -> bool {
        matches!(self, Channel::Xrotation | Channel::Yrotation | Channel::Zrotation)
    }
}

/// What a node of the hierarchy is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum JointKind {
    Root,
    Joint,
    /// An `End Site`: an offset only, no channels. Named `<parent>_End` in [`BvhJoint::name`].
    EndSite,
}

/// One node of the hierarchy, in file order (depth first; a parent always comes before its children).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BvhJoint {
    pub name: String,
    pub kind: JointKind,
    /// Index of the parent in [`Bvh::joints`]; `None` for a root.
    pub parent: Option<usize>,
    /// OFFSET from the parent, in file units.
    pub offset: [f64; 3],
    /// CHANNELS in the order they appear in the file (empty for End Sites).
    pub channels: Vec<Channel>,
    /// Index of this joint's first channel within a frame row.
    pub channel_start: usize,
}

/// A parsed BVH file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Bvh {
    /// All nodes in file order, End Sites included.
    pub joints: Vec<BvhJoint>,
    /// Seconds per frame exactly as written (`Frame Time:`), at full precision.
    pub frame_time: f64,
    /// The frame count the file declares in `Frames:` (may disagree with the data; see `warnings`).
    pub declared_frames: usize,
    /// Number of values in one frame row (the sum of all CHANNELS counts).
    pub channels_per_frame: usize,
    /// Channel values, `frames() * channels_per_frame` of them, row-major.
    pub values: Vec<f64>,
    /// Non-fatal problems found while parsing (e.g. a `Frames:` count that disagrees with the data).
    pub warnings: Vec<Warning>,
}

impl Bvh {
    /// Number of frame rows actually present. A file with no channels has no rows and describes
    /// one pose (the rest pose): 1 frame if it declares any, whatever `Frames:` says.
    pub fn frames(&self) -> usize {
        self.values.len().checked_div(self.channels_per_frame).unwrap_or(self.declared_frames.min(1))
    }

    /// The channel values of one frame.
    pub fn frame(&self, i: usize) -> &[f64] {
        let c = self.channels_per_frame;
        &self.values[i * c..(i + 1) * c]
    }

    /// Frames per second (1 / frame time).
    pub fn fps(&self) -> f64 {
        1.0 / self.frame_time
    }

    /// Indices of the nodes that are not End Sites.
    pub fn joint_indices(&self) -> impl Iterator<Item = usize> + '_ {
        self.joints.iter().enumerate().filter(|(_, j)| j.kind != JointKind::EndSite).map(|(i, _)| i)
    }
}
