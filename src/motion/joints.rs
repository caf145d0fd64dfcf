//! Canonical joints: maps the naming conventions of common BVH exporters onto the one set of
//! joints the segmentation methods use.
//!
//! Canonical set: Hips (root), Spine, Chest, Neck, Head, Left/Right Shoulder (the upper-arm
//! joint, not the clavicle), Elbow, Hand (the wrist), Hip (the thigh joint), Knee, Foot (the
//! ankle), plus optional Left/Right Toe.
//!
//! **Names.** A node name is reduced to a *core*: the part after the last `:` or `|`
//! (namespaces such as `mixamorig:`), lower-cased, with everything but letters and digits
//! removed (so case and separators `_ . - space` do not matter), and with a `mixamorig` or
//! 3ds Max Biped `bip01`/`bip001` prefix removed. A side is read from a leading or trailing
//! `left`/`right` or `l`/`r` (`LeftArm`, `lhumerus`, `Bip01 L Thigh`, `hand_l`, `Hand.R`,
//! `L_Hip`); a side reading only counts if what is left is a known word, so `lowerback` is not
//! "left owerback". Known words per limb joint, in priority order (first that exists wins):
//!
//! | canonical | words | conventions covered |
//! |---|---|---|
//! | Shoulder | upperarm uparm arm humerus shldr shldrbend shoulder | Biped, MotionBuilder/Mixamo (`LeftArm`; their `LeftShoulder` is the clavicle), ASF, Daz, 3ds Max (`LeftShoulder` after `LeftCollar`) |
//! | Elbow | forearm lowerarm lowarm elbow radius forearmbend ulna | |
//! | Hand | wrist hand | 3ds Max `LeftWrist` (its `lhand` is past the wrist), MotionBuilder `LeftHand`, ASF `lhand` |
//! | Hip | upleg upperleg thigh thighbend femur hip | `LeftUpLeg`, `Bip01 L Thigh`, `lThigh`, `lfemur`, `LeftHip` (CMU `LHipJoint` is not a hip) |
//! | Knee | leg lowerleg lowleg knee shin calf tibia | `LeftLeg`, `LeftKnee`, `lShin`, `Bip01 L Calf`, `ltibia` |
//! | Foot | ankle foot | |
//! | Toe | toebase toe toes toe0 ball forefoot | optional |
//!
//! Each limb joint must lie below the previous one of its chain (Knee below Hip, …).
//!
//! **Trunk.** Head = the node whose core is `head`. Hips = the node named `hips`, `hip`,
//! `pelvis`, `root` or a bare Biped `Bip01` (in that priority) that is an ancestor of Head,
//! else the root. The trunk path runs from Hips to Head. Neck = the lowest node on that path
//! whose core contains `neck` (`Neck`, `lowerneck`, `neck_01`), else Head's parent. Chest =
//! the trunk node below Neck closest (in the rest pose) to where the two arm chains leave the
//! trunk — that is the branch point of the arms, whatever it is called (`Spine1`, `Spine2`,
//! `Chest2`, `thorax`, `chest`). Spine = the trunk node between Hips and Chest named like a
//! spine (`spine`, `lowerback`, `abdomen`, `ab`, `torso`, `waist`, digits ignored), else the
//! one nearest the Hips–Chest midpoint, else Chest itself (noted in [`JointMap::notes`]).
//!
//! End Sites are never mapped. A skeleton with a canonical joint missing gets a
//! [`MissingJoints`] error naming every missing canonical joint.

use super::fk::rest_pose;
use super::Skeleton;
use glam::Vec3;
use serde::{Deserialize, Serialize};

/// One canonical joint.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Canonical {
    Hips,
    Spine,
    Chest,
    Neck,
    Head,
    LeftShoulder,
    LeftElbow,
    LeftHand,
    RightShoulder,
    RightElbow,
    RightHand,
    LeftHip,
    LeftKnee,
    LeftFoot,
    RightHip,
    RightKnee,
    RightFoot,
}

impl Canonical {
    pub const ALL: [Canonical; 17] = [
        Canonical::Hips,
        Canonical::Spine,
        Canonical::Chest,
        Canonical::Neck,
        Canonical::Head,
        Canonical::LeftShoulder,
        Canonical::LeftElbow,
        Canonical::LeftHand,
        Canonical::RightShoulder,
        Canonical::RightElbow,
        Canonical::RightHand,
        Canonical::LeftHip,
        Canonical::LeftKnee,
        Canonical::LeftFoot,
        Canonical::RightHip,
        Canonical::RightKnee,
        Canonical::RightFoot,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Canonical::Hips => "Hips",
            Canonical::Spine => "Spine",
            Canonical::Chest => "Chest",
            Canonical::Neck => "Neck",
            Canonical::Head => "Head",
            Canonical::LeftShoulder => "LeftShoulder",
            Canonical::LeftElbow => "LeftElbow",
            Canonical::LeftHand => "LeftHand",
            Canonical::RightShoulder => "RightShoulder",
            Canonical::RightElbow => "RightElbow",
            Canonical::RightHand => "RightHand",
            Canonical::LeftHip => "LeftHip",
            Canonical::LeftKnee => "LeftKnee",
            Canonical::LeftFoot => "LeftFoot",
            Canonical::RightHip => "RightHip",
            Canonical::RightKnee => "RightKnee",
            Canonical::RightFoot => "RightFoot",
        }
    }

    /// The same joint on the other side of the body (itself for the trunk and head).
    pub fn mirror(self) -> Canonical {
        use Canonical::*;
        match self {
            LeftShoulder => RightShoulder,
            LeftElbow => RightElbow,
            LeftHand => RightHand,
            RightShoulder => LeftShoulder,
            RightElbow => LeftElbow,
            RightHand => LeftHand,
            LeftHip => RightHip,
            LeftKnee => RightKnee,
            LeftFoot => RightFoot,
            RightHip => LeftHip,
            RightKnee => LeftKnee,
            RightFoot => LeftFoot,
            other => other,
        }
    }
}

impl std::fmt::Display for Canonical {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Index (into [`Skeleton`] / a frame of positions) of each canonical joint.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JointMap {
    pub hips: usize,
    pub spine: usize,
    pub chest: usize,
    pub neck: usize,
    pub head: usize,
    pub left_shoulder: usize,
    pub left_elbow: usize,
    pub left_hand: usize,
    pub right_shoulder: usize,
    pub right_elbow: usize,
    pub right_hand: usize,
    pub left_hip: usize,
    pub left_knee: usize,
    pub left_foot: usize,
    pub right_hip: usize,
    pub right_knee: usize,
    pub right_foot: usize,
    pub left_toe: Option<usize>,
    pub right_toe: Option<usize>,
    /// Fallbacks taken while mapping (e.g. "Spine: … using Chest"), for the curious user.
    pub notes: Vec<String>,
}

impl JointMap {
    /// Index of one canonical joint.
    pub fn get(&self, c: Canonical) -> usize {
        match c {
            Canonical::Hips => self.hips,
            Canonical::Spine => self.spine,
            Canonical::Chest => self.chest,
            Canonical::Neck => self.neck,
            Canonical::Head => self.head,
            Canonical::LeftShoulder => self.left_shoulder,
            Canonical::LeftElbow => self.left_elbow,
            Canonical::LeftHand => self.left_hand,
            Canonical::RightShoulder => self.right_shoulder,
            Canonical::RightElbow => self.right_elbow,
            Canonical::RightHand => self.right_hand,
            Canonical::LeftHip => self.left_hip,
            Canonical::LeftKnee => self.left_knee,
            Canonical::LeftFoot => self.left_foot,
            Canonical::RightHip => self.right_hip,
            Canonical::RightKnee => self.right_knee,
            Canonical::RightFoot => self.right_foot,
        }
    }

    /// Indices of all canonical joints, in [`Canonical::ALL`] order.
    pub fn indices(&self) -> [usize; 17] {
        Canonical::ALL.map(|c| self.get(c))
    }
}

/// The skeleton lacks some canonical joints. The message says which were found (and as which of
/// the file's joints), which were not, and that joints are matched along their chains, so a file
/// joint named like a missing one (a `LeftHand` not below the left elbow) reads as what it is.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error(
    "cannot map the skeleton to the {} canonical joints: {} found{}, {} missing ({}). Joints are matched by \
     name, each below the one before it in its chain when that one is found (hips, spine, chest, neck, head; \
     shoulder, elbow, hand; hip, knee, foot), so a joint named like a missing one may sit elsewhere. Joints in \
     the file: {}",
    Canonical::ALL.len(),
    .found.len(),
    list_found(.found),
    .missing.len(),
    list_canonical(.missing),
    list_names(.joint_names)
)]
pub struct MissingJoints {
    /// The canonical joints that were found, with the file joint each is, in [`Canonical::ALL`] order.
    pub found: Vec<(Canonical, String)>,
    /// Every canonical joint that could not be found, in [`Canonical::ALL`] order.
    pub missing: Vec<Canonical>,
    /// The names of the file's joints (End Sites excluded), to help the user.
    pub joint_names: Vec<String>,
}

fn list_found(found: &[(Canonical, String)]) -> String {
    if found.is_empty() {
        return String::new();
    }
    let pairs: Vec<String> = found
        .iter()
        .map(|(c, name)| if c.name() == name { name.clone() } else { format!("{} as {name}", c.name()) })
        .collect();
    format!(" ({})", pairs.join(", "))
}

fn list_canonical(c: &[Canonical]) -> String {
    c.iter().map(|c| c.name()).collect::<Vec<_>>().join(", ")
}

fn list_names(names: &[String]) -> String {
    const SHOWN: usize = 24;
    let mut s = names.iter().take(SHOWN).map(String::as_str).collect::<Vec<_>>().join(", ");
    if names.len() > SHOWN {
        s.push_str(&format!(", … and {} more", names.len() - SHOWN));
    }
    s
}

/// A side of the body.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    Left,
    Right,
}

const HIPS_WORDS: &[&str] = &["hips", "hip", "pelvis", "root", ""];
const SPINE_WORDS: &[&str] =
    &["spine", "lowerback", "abdomen", "abdomenlower", "ab", "lowerspine", "torso", "waist", "back"];
const CHEST_WORDS: &[&str] = &["chest", "thorax", "upperchest", "upperback"];
const SHOULDER_WORDS: &[&str] = &["upperarm", "uparm", "arm", "humerus", "shldr", "shldrbend", "shoulder"];
const ELBOW_WORDS: &[&str] = &["forearm", "lowerarm", "lowarm", "elbow", "radius", "forearmbend", "ulna"];
const HAND_WORDS: &[&str] = &["wrist", "hand"];
const HIP_WORDS: &[&str] = &["upleg", "upperleg", "thigh", "thighbend", "femur", "hip"];
const KNEE_WORDS: &[&str] = &["leg", "lowerleg", "lowleg", "knee", "shin", "calf", "tibia"];
const FOOT_WORDS: &[&str] = &["ankle", "foot"];
const TOE_WORDS: &[&str] = &["toebase", "toe", "toes", "toe0", "ball", "forefoot"];

/// The core of a node name: namespace dropped, lower-case letters and digits only, `mixamorig`
/// and Biped `bipNN` prefixes removed.
pub fn name_core(name: &str) -> String {
    let tail = name.rsplit([':', '|']).next().filter(|t| !t.is_empty()).unwrap_or(name);
    let squashed: String = tail.chars().filter(|c| c.is_ascii_alphanumeric()).map(|c| c.to_ascii_lowercase()).collect();
    let s = squashed.strip_prefix("mixamorig").map(|r| r.trim_start_matches(|c: char| c.is_ascii_digit()));
    let s = s.unwrap_or(&squashed);
    let s = match s.strip_prefix("bip") {
        Some(r) if r.starts_with(|c: char| c.is_ascii_digit()) => r.trim_start_matches(|c: char| c.is_ascii_digit()),
        _ => s,
    };
    s.to_string()
}

/// Every (side, rest) reading of a core: `leftarm` → (Left, `arm`), `lhumerus` → (Left,
/// `humerus`), `handl` → (Left, `hand`), and also spurious ones that callers filter by word.
pub fn side_readings(core: &str) -> Vec<(Side, &str)> {
    let mut out = Vec::new();
    for (side, long, short) in [(Side::Left, "left", "l"), (Side::Right, "right", "r")] {
        for affix in [long, short] {
            if let Some(r) = core.strip_prefix(affix) {
                out.push((side, r));
            }
            if let Some(r) = core.strip_suffix(affix) {
                out.push((side, r));
            }
        }
    }
    out.retain(|(_, r)| !r.is_empty());
    out
}

fn strip_digits(s: &str) -> &str {
    s.trim_end_matches(|c: char| c.is_ascii_digit())
}

struct Namer<'a> {
    skeleton: &'a Skeleton,
    cores: Vec<String>,
    /// Side readings of each core, computed once.
    sides: Vec<Vec<(Side, String)>>,
}

impl<'a> Namer<'a> {
    fn new(skeleton: &'a Skeleton) -> Self {
        let cores: Vec<String> = skeleton.names.iter().map(|n| name_core(n)).collect();
        let sides =
            cores.iter().map(|c| side_readings(c).into_iter().map(|(s, r)| (s, r.to_string())).collect()).collect();
        Namer { skeleton, cores, sides }
    }

    fn joints(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.skeleton.len()).filter(|&i| !self.skeleton.is_end_site[i])
    }

    /// First joint (by word priority, then file order) without side whose core is a word and
    /// that satisfies `ok`.
    fn unsided(&self, words: &[&str], ok: impl Fn(usize) -> bool) -> Option<usize> {
        words.iter().find_map(|w| self.joints().find(|&j| self.cores[j] == *w && ok(j)))
    }

    /// First joint of `side` (by word priority, then file order) whose core is a word and that
    /// lies below `below` (if given).
    fn sided(&self, side: Side, words: &[&str], below: Option<usize>) -> Option<usize> {
        words.iter().find_map(|w| {
            self.joints().find(|&j| {
                self.sides[j].iter().any(|(s, r)| *s == side && r == w)
                    && below.is_none_or(|b| b != j && self.skeleton.is_ancestor_or_self(b, j))
            })
        })
    }
}

#[derive(Default)]
struct Limbs {
    shoulder: Option<usize>,
    elbow: Option<usize>,
    hand: Option<usize>,
    hip: Option<usize>,
    knee: Option<usize>,
    foot: Option<usize>,
    toe: Option<usize>,
}

fn find_limbs(n: &Namer, side: Side) -> Limbs {
    let chain = |words: &[&str], below: Option<usize>| n.sided(side, words, below);
    let shoulder = chain(SHOULDER_WORDS, None);
    let elbow = chain(ELBOW_WORDS, shoulder);
    let hand = chain(HAND_WORDS, elbow);
    let hip = chain(HIP_WORDS, None);
    let knee = chain(KNEE_WORDS, hip);
    let foot = chain(FOOT_WORDS, knee);
    let toe = foot.and_then(|f| chain(TOE_WORDS, Some(f)));
    Limbs { shoulder, elbow, hand, hip, knee, foot, toe }
}

struct Trunk {
    hips: usize,
    spine: Option<usize>,
    chest: Option<usize>,
    neck: Option<usize>,
    head: Option<usize>,
}

/// The first node of `path_to_shoulder` that is not on the trunk: where the arm leaves it.
fn arm_branch(trunk: &[usize], path_to_shoulder: &[usize]) -> Option<usize> {
    path_to_shoulder.iter().copied().find(|j| !trunk.contains(j))
}

fn nearest(candidates: &[usize], rest: &[Vec3], target: Vec3) -> Option<usize> {
    candidates.iter().copied().min_by(|&a, &b| rest[a].distance(target).total_cmp(&rest[b].distance(target)))
}

fn find_trunk(n: &Namer, shoulders: [Option<usize>; 2], notes: &mut Vec<String>) -> Trunk {
    let s = n.skeleton;
    let head = n.unsided(&["head"], |_| true);
    let hips = n
        .unsided(HIPS_WORDS, |j| head.is_none_or(|h| s.is_ancestor_or_self(j, h)))
        .or_else(|| (0..s.len()).find(|&i| s.parents[i].is_none()))
        .unwrap_or(0);
    let Some(path) = head.and_then(|h| s.path_from(hips, h)) else {
        return Trunk { hips, spine: None, chest: None, neck: None, head };
    };
    // the joints strictly between the hips and the head: none when the head is the hips (a root
    // named `Head`, found by fuzzing) or its child
    let interior = path.get(1..path.len().saturating_sub(1)).unwrap_or(&[]);
    let neck_pos = interior.iter().position(|&j| n.cores[j].contains("neck")).or_else(|| {
        let p = interior.len().checked_sub(1)?;
        notes.push(format!("Neck: no joint named like a neck; using '{}', the parent of Head", s.names[interior[p]]));
        Some(p)
    });
    let neck = neck_pos.map(|p| interior[p]);
    let below_neck = &interior[..neck_pos.unwrap_or(interior.len())];
    let rest = rest_pose(s);
    let branch_points: Vec<Vec3> = shoulders
        .iter()
        .flatten()
        .filter_map(|&sh| s.path_from(hips, sh))
        .filter_map(|p| arm_branch(&path, &p))
        .map(|b| rest[b])
        .collect();
    let chest = if branch_points.len() == 2 {
        nearest(below_neck, &rest, 0.5 * (branch_points[0] + branch_points[1]))
    } else {
        CHEST_WORDS
            .iter()
            .find_map(|w| below_neck.iter().copied().find(|&j| n.cores[j] == *w))
            .or_else(|| below_neck.last().copied())
    };
    let spine = chest.map(|c| {
        let between = &below_neck[..below_neck.iter().position(|&j| j == c).unwrap_or(0)];
        SPINE_WORDS
            .iter()
            .find_map(|w| between.iter().copied().find(|&j| strip_digits(&n.cores[j]) == *w))
            .or_else(|| nearest(between, &rest, 0.5 * (rest[hips] + rest[c])))
            .unwrap_or_else(|| {
                notes.push(format!("Spine: no joint between Hips and Chest; using Chest ('{}')", s.names[c]));
                c
            })
    });
    Trunk { hips, spine, chest, neck, head }
}

/// Map a skeleton onto the canonical joints (see the module documentation for the rules).
pub fn map_joints(s: &Skeleton) -> Result<JointMap, MissingJoints> {
    let n = Namer::new(s);
    let left = find_limbs(&n, Side::Left);
    let right = find_limbs(&n, Side::Right);
    let mut notes = Vec::new();
    let t = find_trunk(&n, [left.shoulder, right.shoulder], &mut notes);
    let found: [Option<usize>; 17] = [
        Some(t.hips),
        t.spine,
        t.chest,
        t.neck,
        t.head,
        left.shoulder,
        left.elbow,
        left.hand,
        right.shoulder,
        right.elbow,
        right.hand,
        left.hip,
        left.knee,
        left.foot,
        right.hip,
        right.knee,
        right.foot,
    ];
    let missing: Vec<Canonical> =
        Canonical::ALL.iter().zip(found).filter(|(_, f)| f.is_none()).map(|(c, _)| *c).collect();
    if !missing.is_empty() {
        let joint_names = n.joints().map(|j| s.names[j].clone()).collect();
        let found = Canonical::ALL.iter().zip(found).filter_map(|(c, f)| f.map(|j| (*c, s.names[j].clone()))).collect();
        return Err(MissingJoints { found, missing, joint_names });
    }
    let f = found.map(|x| x.unwrap_or(0));
    Ok(JointMap {
        hips: f[0],
        spine: f[1],
        chest: f[2],
        neck: f[3],
        head: f[4],
        left_shoulder: f[5],
        left_elbow: f[6],
        left_hand: f[7],
        right_shoulder: f[8],
        right_elbow: f[9],
        right_hand: f[10],
        left_hip: f[11],
        left_knee: f[12],
        left_foot: f[13],
        right_hip: f[14],
        right_knee: f[15],
        right_foot: f[16],
        left_toe: left.toe,
        right_toe: right.toe,
        notes,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn name_cores() {
        assert_eq!(name_core("mixamorig:LeftUpLeg"), "leftupleg");
        assert_eq!(name_core("mixamorig1:Hips"), "hips");
        assert_eq!(name_core("mixamorig_LeftArm"), "leftarm");
        assert_eq!(name_core("Bip01 L Thigh"), "lthigh");
        assert_eq!(name_core("Bip001 Head"), "head");
        assert_eq!(name_core("Bip01"), "");
        assert_eq!(name_core("Character|upper_arm.L"), "upperarml");
        assert_eq!(name_core("spine_01"), "spine01");
        assert_eq!(name_core("bipod"), "bipod");
    }

    #[test]
    fn side_readings_need_a_known_word_to_count() {
        let has = |core: &str, side: Side, word: &str| side_readings(core).contains(&(side, word));
        assert!(has("leftarm", Side::Left, "arm"));
        assert!(has("rhumerus", Side::Right, "humerus"));
        assert!(has("handl", Side::Left, "hand"));
        assert!(has("thighright", Side::Right, "thigh"));
        assert!(has("lshldr", Side::Left, "shldr"));
        // Spurious readings exist but name no known word.
        assert!(has("lowerback", Side::Left, "owerback"));
        assert!(!SPINE_WORDS.contains(&"owerback"));
        assert!(side_readings("l").is_empty());
    }
}
