//! Spliced takes with known boundaries, for scoring segmentations at the gesture level where no
//! public gesture labels exist: pieces of 0.8–3 s cut from labelled takes, each from a different
//! action than the one before, joined so that the motion stays continuous.
//!
//! * **Pieces.** A seeded generator ([`crate::stats::Rng`]) picks a labelled segment of some take
//!   whose label differs from the previous piece's and that is at least `min_s` long, a length in
//!   `[min_s, max_s]` (at most the segment's) and a start inside the segment, leaving the transitions'
//!   `blend_s` of source motion before and after it.
//! * **Continuity, in motion.** Between two pieces go `blend_s` seconds of transition in which
//!   *both keep moving*: the last piece's source rows after its end and the next piece's source
//!   rows before its start play side by side and are cross-faded (every joint's rotation slerped
//!   with glam, position channels interpolated, the weight eased by a smoothstep). The next piece
//!   is turned about the vertical and moved so that its row at the transition's middle stands
//!   where, and faces how, the last piece's would (its own height kept). A seam therefore has no
//!   frozen pose and no built-in stop — a detector of slow frames gets no free boundary (the
//!   earlier splicer eased from the last frame of one piece to the first of the next, so every
//!   seam was a speed minimum).
//! * **Boundaries.** The true boundary between two pieces is the middle of their transition; the
//!   ground truth ([`Spliced::truth_csv`]) gives every piece's frames (its half of each
//!   transition included) with its source label, as 1-based frame numbers like the shared data's
//!   label files, so `mocapseg eval` reads it as it is.
//!
//! All takes must share one hierarchy (same joints and channels), frame time and up axis (Y, as
//! CMU's); each joint's rotation channels may come in any order. The first take's bone lengths
//! carry every piece (CMU takes of different subjects differ only in those).

use glam::{DQuat, DVec3};

use crate::bvh::{Bvh, Channel};
use crate::motion::fk::local_rotation;
use crate::segment::truth::Truth;
use crate::stats::Rng;

/// How pieces are cut and joined.
#[derive(Debug, Clone, PartialEq)]
pub struct SpliceOptions {
    pub pieces: usize,
    pub seed: u64,
    /// Shortest and longest piece, seconds.
    pub min_s: f64,
    pub max_s: f64,
    /// Transition between two pieces, seconds.
    pub blend_s: f64,
}

impl Default for SpliceOptions {
    fn default() -> Self {
        SpliceOptions { pieces: 20, seed: 1, min_s: 0.8, max_s: 3.0, blend_s: 0.25 }
    }
}

/// A source take: its BVH and its ground truth (0-based rows).
pub struct Source<'a> {
    pub name: &'a str,
    pub bvh: &'a Bvh,
    pub truth: &'a Truth,
}

/// One piece of the spliced take.
#[derive(Debug, Clone, PartialEq)]
pub struct Piece {
    pub source: String,
    pub label: String,
    /// Source rows `start..=end`.
    pub source_start: usize,
    pub source_end: usize,
    /// Output rows of the piece, its halves of the transitions included.
    pub start: usize,
    pub end: usize,
}

/// A spliced take and what it is made of.
#[derive(Debug, Clone)]
pub struct Spliced {
    pub bvh: Bvh,
    pub pieces: Vec<Piece>,
}

/// Why takes cannot be spliced.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SpliceError {
    #[error("no source takes")]
    NoSources,
    #[error("{0}: its joints, channels or frame time differ from the first take's")]
    Mismatch(String),
    #[error("{0}: joint `{1}` has {2} rotation channels; splicing needs 0 or 3 on different axes")]
    Rotations(String, String, usize),
    #[error("no labelled segment is at least {0} s long, or none differs from the others' labels")]
    NoPieces(f64),
    #[error("invalid splice option: {0}")]
    Options(String),
    #[error("{0}: its joints differ from those of `{1}`, whose bone lengths it was to be played on")]
    Skeleton(String, String),
}

impl SpliceOptions {
    fn check(&self) -> Result<(), SpliceError> {
        let bad = |m: &str| Err(SpliceError::Options(m.into()));
        if !(1..=10_000).contains(&self.pieces) {
            return bad("pieces must be 1 to 10000");
        }
        if !(self.min_s.is_finite() && self.max_s.is_finite() && 0.1 <= self.min_s && self.min_s <= self.max_s)
            || self.max_s > 60.0
        {
            return bad("piece lengths must satisfy 0.1 ≤ min ≤ max ≤ 60 seconds");
        }
        if !(self.blend_s.is_finite() && (0.0..=2.0).contains(&self.blend_s)) {
            return bad("the transition must be 0 to 2 seconds");
        }
        Ok(())
    }
}

/// Where a row's channels are, read once from the hierarchy.
struct Layout {
    /// Per joint: its rotation channels in file order and their slots in a row (empty: none).
    rotations: Vec<(Vec<Channel>, Vec<usize>)>,
    /// The slots of every position channel (any joint's).
    positions: Vec<usize>,
    /// The root's x, y, z position slots (`None` where it has no such channel).
    root: [Option<usize>; 3],
}

impl Layout {
    fn of(bvh: &Bvh) -> Layout {
        let rotations = bvh
            .joints
            .iter()
            .map(|j| {
                j.channels
                    .iter()
                    .enumerate()
                    .filter(|(_, c)| c.is_rotation())
                    .map(|(k, &c)| (c, j.channel_start + k))
                    .unzip()
            })
            .collect();
        let mut positions = Vec::new();
        let mut root = [None; 3];
        for (n, j) in bvh.joints.iter().enumerate() {
            for (k, c) in j.channels.iter().enumerate().filter(|(_, c)| !c.is_rotation()) {
                positions.push(j.channel_start + k);
                if n == 0 {
                    root[c.axis()] = Some(j.channel_start + k);
                }
            }
        }
        Layout { rotations, positions, root }
    }

    /// The rotation of joint `j` in `row`.
    fn rotation(&self, j: usize, row: &[f64]) -> DQuat {
        let (channels, slots) = &self.rotations[j];
        let values: Vec<f64> = slots.iter().map(|&s| row[s]).collect();
        local_rotation(channels, &values)
    }

    fn set_rotation(&self, j: usize, row: &mut [f64], q: DQuat) {
        let (channels, slots) = &self.rotations[j];
        if channels.len() == 3 {
            for (s, v) in slots.iter().zip(euler_of(channels, q)) {
                row[*s] = v;
            }
        }
    }

    fn root_position(&self, row: &[f64]) -> DVec3 {
        let s = self.root;
        DVec3::new(s[0].map_or(0.0, |k| row[k]), s[1].map_or(0.0, |k| row[k]), s[2].map_or(0.0, |k| row[k]))
    }

    fn set_root_position(&self, row: &mut [f64], p: DVec3) {
        for (slot, v) in self.root.iter().zip(p.to_array()) {
            if let Some(k) = slot {
                row[*k] = v;
            }
        }
    }

    /// The direction (about +Y) the root faces in `row`.
    fn facing_yaw(&self, row: &[f64]) -> f64 {
        let forward = self.rotation(0, row) * DVec3::Z;
        forward.x.atan2(forward.z)
    }
}

/// Row `f` of `bvh`, the first or last row where `f` lies outside it.
fn row_of(bvh: &Bvh, f: isize) -> &[f64] {
    bvh.frame(f.clamp(0, bvh.frames() as isize - 1) as usize)
}

/// How a piece is set into the spliced take: turned about the vertical by `turn` and moved so that its
/// root at `from` (horizontally) lands on `to`; heights are kept.
#[derive(Debug, Clone, Copy)]
struct Placement {
    turn: DQuat,
    from: DVec3,
    to: DVec3,
}

impl Placement {
    /// The first piece stays where it was recorded.
    const IDENTITY: Placement = Placement { turn: DQuat::IDENTITY, from: DVec3::ZERO, to: DVec3::ZERO };

    /// The placement that sets source row `row` where, and facing how, the output row `target` is.
    fn onto(layout: &Layout, row: &[f64], target: &[f64]) -> Placement {
        Placement {
            turn: DQuat::from_rotation_y(layout.facing_yaw(target) - layout.facing_yaw(row)),
            from: layout.root_position(row),
            to: layout.root_position(target),
        }
    }

    /// `row` placed (a new row).
    fn place(&self, layout: &Layout, row: &[f64]) -> Vec<f64> {
        let mut r = row.to_vec();
        if self.turn == DQuat::IDENTITY && self.from == self.to {
            return r;
        }
        let p = layout.root_position(row);
        let horizontal = self.turn * DVec3::new(p.x - self.from.x, 0.0, p.z - self.from.z);
        layout.set_root_position(&mut r, DVec3::new(self.to.x + horizontal.x, p.y, self.to.z + horizontal.z));
        layout.set_rotation(0, &mut r, self.turn * layout.rotation(0, row));
        r
    }
}

/// Euler angles (degrees) in the channel order `order` of the rotation `q` (the inverse of
/// [`local_rotation`] for three channels on different axes).
pub fn euler_of(order: &[Channel], q: DQuat) -> [f64; 3] {
    use glam::EulerRot as E;
    let axes: Vec<usize> = order.iter().map(|c| c.axis()).collect();
    let rot = match axes[..] {
        [0, 1, 2] => E::XYZ,
        [0, 2, 1] => E::XZY,
        [1, 0, 2] => E::YXZ,
        [1, 2, 0] => E::YZX,
        [2, 0, 1] => E::ZXY,
        _ => E::ZYX,
    };
    let (a, b, c) = q.to_euler(rot);
    [a.to_degrees(), b.to_degrees(), c.to_degrees()]
}

/// Checks that every take can be joined to the first; their common layout.
fn check_sources(sources: &[Source]) -> Result<Layout, SpliceError> {
    let first = sources.first().ok_or(SpliceError::NoSources)?.bvh;
    let layout = |b: &Bvh| b.joints.iter().map(|j| (j.name.clone(), j.channels.clone())).collect::<Vec<_>>();
    for s in sources {
        if layout(s.bvh) != layout(first) || s.bvh.frame_time != first.frame_time {
            return Err(SpliceError::Mismatch(s.name.into()));
        }
    }
    let layout = Layout::of(first);
    for (j, (channels, _)) in layout.rotations.iter().enumerate() {
        let mut axes: Vec<usize> = channels.iter().map(|c| c.axis()).collect();
        axes.sort_unstable();
        axes.dedup();
        if !(channels.is_empty() || (channels.len() == 3 && axes.len() == 3)) {
            return Err(SpliceError::Rotations(sources[0].name.into(), first.joints[j].name.clone(), channels.len()));
        }
    }
    Ok(layout)
}

/// `bvh`'s motion played on the bone lengths of `onto` (another subject's take with the same hierarchy: CMU's takes
/// differ only in their bones): every joint's offset is the joint of the same name in `onto`, the rotations and the
/// root's path are `bvh`'s own — a subject's movement on another subject's body, new training data from the takes we
/// have (issue 50). Refused when the joints (names, parents, channels) differ.
pub fn retarget(name: &str, bvh: &Bvh, onto_name: &str, onto: &Bvh) -> Result<Bvh, SpliceError> {
    fn shape(b: &Bvh) -> Vec<(&str, Option<usize>, &[Channel])> {
        b.joints.iter().map(|j| (j.name.as_str(), j.parent, j.channels.as_slice())).collect()
    }
    if shape(bvh) != shape(onto) {
        return Err(SpliceError::Skeleton(name.into(), onto_name.into()));
    }
    let mut out = bvh.clone();
    for (j, o) in out.joints.iter_mut().zip(&onto.joints) {
        j.offset = o.offset;
    }
    Ok(out)
}

/// Cuts `options.pieces` pieces from `sources` and joins them (see the module documentation).
pub fn splice(sources: &[Source], options: &SpliceOptions) -> Result<Spliced, SpliceError> {
    options.check()?;
    let layout = check_sources(sources)?;
    let first = sources[0].bvh;
    let fps = 1.0 / first.frame_time;
    let (min_f, max_f) = ((options.min_s * fps).round() as usize, (options.max_s * fps).round() as usize);
    let blend = (options.blend_s * fps).round() as usize;
    let width = first.channels_per_frame;
    // every labelled segment long enough once the transitions' source rows are kept free around it (a piece's
    // source must go on `blend` rows after it and begin `blend` rows before it): (source, start, end, label)
    let candidates: Vec<(usize, usize, usize, &str)> = sources
        .iter()
        .enumerate()
        .flat_map(|(k, s)| {
            let frames = s.bvh.frames();
            s.truth.segments.iter().filter(move |t| t.end < frames).filter_map(move |t| {
                let (a, b) = (t.start.max(blend + 1), t.end.min(frames.saturating_sub(blend + 2)));
                (b + 1 >= a + min_f.max(1)).then_some((k, a, b, t.label.as_str()))
            })
        })
        .collect();
    let mut rng = Rng::new(options.seed);
    let mut values: Vec<f64> = Vec::new();
    let mut pieces: Vec<Piece> = Vec::new();
    let mut last_label: Option<&str> = None;
    // the last piece: its source, last source row and placement (its motion continues into the transition)
    let mut previous: Option<(usize, usize, Placement)> = None;
    for _ in 0..options.pieces {
        let allowed: Vec<&(usize, usize, usize, &str)> =
            candidates.iter().filter(|c| Some(c.3) != last_label).collect();
        if allowed.is_empty() {
            return Err(SpliceError::NoPieces(options.min_s));
        }
        let &&(k, seg_start, seg_end, label) = &allowed[rng.below(allowed.len())];
        let seg_len = seg_end + 1 - seg_start;
        let len = min_f.max(1) + rng.below(max_f.min(seg_len).saturating_sub(min_f.max(1)) + 1);
        let start = seg_start + rng.below(seg_len - len + 1);
        let src = sources[k].bvh;
        let mut piece_start = values.len() / width.max(1);
        let placement = match previous {
            None => Placement::IDENTITY,
            Some((ka, last, ref pa)) => {
                // both motions keep playing through the transition: the last piece's source rows after its
                // end and this piece's source rows before its start, cross-faded; this piece is placed so that
                // its row at the transition's middle stands where, and faces how, the last piece's would
                let a_src = sources[ka].bvh;
                let continued = |i: usize| pa.place(&layout, row_of(a_src, (last + i) as isize));
                let lead_in = |i: usize| row_of(src, start as isize - (blend + 1 - i) as isize);
                let middle = (blend + 1) / 2;
                let pb = if blend == 0 {
                    Placement::onto(&layout, row_of(src, start as isize), &values[values.len() - width..])
                } else {
                    Placement::onto(&layout, lead_in(middle), &continued(middle))
                };
                for i in 1..=blend {
                    let x = i as f64 / (blend + 1) as f64;
                    let t = x * x * (3.0 - 2.0 * x);
                    let (a, b) = (continued(i), pb.place(&layout, lead_in(i)));
                    let mut row = a.clone();
                    for j in 0..layout.rotations.len() {
                        if !layout.rotations[j].0.is_empty() {
                            let q = layout.rotation(j, &a).slerp(layout.rotation(j, &b), t);
                            layout.set_rotation(j, &mut row, q);
                        }
                    }
                    // position channels (the root's and any other joint's) interpolated
                    for &c in &layout.positions {
                        row[c] = a[c] + (b[c] - a[c]) * t;
                    }
                    values.extend(&row);
                }
                // the boundary is the middle of the transition: the earlier half goes to the last piece
                let middle = piece_start + blend / 2;
                if let Some(prev) = pieces.last_mut() {
                    prev.end = middle.saturating_sub(1).max(prev.start);
                }
                piece_start = middle;
                pb
            }
        };
        for f in start..start + len {
            values.extend(placement.place(&layout, src.frame(f)));
        }
        let end = values.len() / width.max(1) - 1;
        pieces.push(Piece {
            source: sources[k].name.into(),
            label: label.into(),
            source_start: start,
            source_end: start + len - 1,
            start: piece_start,
            end,
        });
        last_label = Some(label);
        previous = Some((k, start + len - 1, placement));
    }
    let frames = values.len() / width.max(1);
    let bvh = Bvh {
        joints: first.joints.clone(),
        frame_time: first.frame_time,
        declared_frames: frames,
        channels_per_frame: width,
        values,
        warnings: Vec::new(),
    };
    Ok(Spliced { bvh, pieces })
}

impl Spliced {
    /// The ground truth as CSV (`trial,label,start_frame,end_frame,trial_frames`, 1-based frames
    /// like the shared data's label files), the trial named `trial`.
    pub fn truth_csv(&self, trial: &str) -> String {
        let mut w = csv::Writer::from_writer(Vec::new());
        let frames = self.bvh.frames().to_string();
        let _ = w.write_record(["trial", "label", "start_frame", "end_frame", "trial_frames"]);
        for p in &self.pieces {
            let (s, e) = ((p.start + 1).to_string(), (p.end + 1).to_string());
            let _ = w.write_record([trial, p.label.as_str(), s.as_str(), e.as_str(), frames.as_str()]);
        }
        String::from_utf8(w.into_inner().unwrap_or_default()).unwrap_or_default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh;
    use crate::motion::Motion;
    use crate::segment::truth::{load_csv, TruthOptions};

    /// A take played on another subject's bones: the carrier's bone lengths, the take's own root path and joint
    /// rotations (a knee bends as much, so the foot lies at the carrier's shin length from it); a hierarchy that
    /// differs is refused by name.
    #[test]
    fn a_retargeted_take_has_the_carriers_bones_and_its_own_movement() {
        let take = bvh::parse(include_str!("../tests/fixtures/02_01.bvh")).unwrap();
        let carrier = bvh::parse(include_str!("../tests/fixtures/35_01.bvh")).unwrap();
        let moved = retarget("02_01", &take, "35_01", &carrier).unwrap();
        assert_eq!(moved.values, take.values);
        let (a, b, c) = (
            Motion::from_bvh("a", &take).unwrap(),
            Motion::from_bvh("b", &moved).unwrap(),
            Motion::from_bvh("c", &carrier).unwrap(),
        );
        let knee = a.joint_index("LeftLeg").unwrap();
        let foot = a.joint_index("LeftFoot").unwrap();
        let length = |m: &Motion, f: usize| (m.position(f, foot) - m.position(f, knee)).length();
        assert!((length(&b, 100) - length(&c, 0)).abs() < 1e-3, "{} vs {}", length(&b, 100), length(&c, 0));
        assert!((length(&a, 100) - length(&c, 0)).abs() > 1e-3, "the subjects' shins differ");
        assert_eq!(b.position(100, b.root()), a.position(100, a.root()), "the root's path is the take's");
        let other = bvh::parse(include_str!("../tests/fixtures/131_01.bvh")).unwrap();
        let e = retarget("02_01", &take, "131_01", &other).unwrap_err().to_string();
        assert!(e.contains("02_01") && e.contains("131_01"), "{e}");
    }

    fn take(name: &str, text: &str, labels: &[(usize, usize, &str)]) -> (String, Bvh, Truth) {
        let b = bvh::parse(text).unwrap();
        let truth = Truth {
            trial: name.into(),
            frames: b.frames(),
            segments: labels
                .iter()
                .map(|&(start, end, l)| crate::segment::truth::TruthSegment {
                    start,
                    end,
                    label: l.into(),
                    end_window: None,
                })
                .collect(),
        };
        (name.into(), b, truth)
    }

    #[test]
    fn euler_angles_round_trip_in_every_channel_order() {
        use Channel::*;
        let mut rng = Rng::new(3);
        for order in [
            [Xrotation, Yrotation, Zrotation],
            [Xrotation, Zrotation, Yrotation],
            [Yrotation, Xrotation, Zrotation],
            [Yrotation, Zrotation, Xrotation],
            [Zrotation, Xrotation, Yrotation],
            [Zrotation, Yrotation, Xrotation],
        ] {
            for _ in 0..50 {
                let v: Vec<f64> = (0..3).map(|_| (rng.next_f32() as f64 - 0.5) * 300.0).collect();
                let q = local_rotation(&order, &v);
                let back = local_rotation(&order, &euler_of(&order, q));
                assert!(q.dot(back).abs() > 1.0 - 1e-9, "{order:?} {v:?}");
            }
        }
    }

    /// Largest distance any node moves between two consecutive frames.
    fn fastest(m: &Motion) -> f32 {
        (1..m.frames())
            .map(|f| m.frame(f).iter().zip(m.frame(f - 1)).map(|(a, b)| (*a - *b).length()).fold(0.0, f32::max))
            .fold(0.0, f32::max)
    }

    #[test]
    fn spliced_pieces_are_continuous_and_their_boundaries_known() {
        let walk = take("02_01", include_str!("../tests/fixtures/02_01.bvh"), &[(0, 170, "walk"), (171, 342, "walk2")]);
        let run = take("35_01", include_str!("../tests/fixtures/35_01.bvh"), &[(0, 357, "other")]);
        let sources: Vec<Source> = [&walk, &run].iter().map(|(n, b, t)| Source { name: n, bvh: b, truth: t }).collect();
        let opts = SpliceOptions { pieces: 8, seed: 7, ..Default::default() };
        let s = splice(&sources, &opts).unwrap();
        assert_eq!(s.pieces.len(), 8);
        // pieces cover the take in order, each 0.8–3 s of source, labels never repeat back to back
        assert_eq!(s.pieces[0].start, 0);
        assert_eq!(s.pieces.last().unwrap().end + 1, s.bvh.frames());
        for w in s.pieces.windows(2) {
            assert_eq!(w[0].end + 1, w[1].start);
            assert_ne!(w[0].label, w[1].label);
        }
        for p in &s.pieces {
            let seconds = (p.source_end + 1 - p.source_start) as f64 * walk.1.frame_time;
            assert!((0.79..=3.01).contains(&seconds), "{p:?}");
        }
        // the same seed gives the same take
        let again = splice(&sources, &opts).unwrap();
        assert_eq!((again.bvh.values.len(), &again.pieces), (s.bvh.values.len(), &s.pieces));
        // continuity: no node moves more between two frames than in the sources' own fastest frame
        let out = Motion::from_bvh("spliced", &s.bvh).unwrap();
        let limit =
            fastest(&Motion::from_bvh("a", &walk.1).unwrap()).max(fastest(&Motion::from_bvh("b", &run.1).unwrap()));
        assert!(fastest(&out) <= limit * 1.05, "spliced {} > sources {limit}", fastest(&out));
        // the ground truth reads back as written, 1-based
        let truth = load_csv(&s.truth_csv("mix"), "mix", TruthOptions::default()).unwrap();
        assert_eq!(truth.frames, s.bvh.frames());
        let spans: Vec<(usize, usize)> = truth.segments.iter().map(|t| (t.start, t.end)).collect();
        let want: Vec<(usize, usize)> = s.pieces.iter().map(|p| (p.start, p.end)).collect();
        assert_eq!(spans, want);
        // the spliced take writes and parses back
        let back = bvh::parse(&bvh::write(&s.bvh)).unwrap();
        assert_eq!(back.frames(), s.bvh.frames());
    }

    /// Mean distance the nodes move from frame `f − 1` to `f`.
    fn movement(m: &Motion, f: usize) -> f32 {
        m.frame(f).iter().zip(m.frame(f - 1)).map(|(a, b)| (*a - *b).length()).sum::<f32>() / m.frame(f).len() as f32
    }

    #[test]
    fn seams_keep_moving() {
        // a walk and a run move all the time: so must every transition between their pieces (the earlier
        // splicer eased from a frozen last frame, so each seam was a stop a speed-minimum detector found free)
        let walk = take("02_01", include_str!("../tests/fixtures/02_01.bvh"), &[(0, 170, "walk"), (171, 342, "walk2")]);
        let run = take("35_01", include_str!("../tests/fixtures/35_01.bvh"), &[(0, 357, "other")]);
        let sources: Vec<Source> = [&walk, &run].iter().map(|(n, b, t)| Source { name: n, bvh: b, truth: t }).collect();
        let s = splice(&sources, &SpliceOptions { pieces: 10, seed: 3, ..Default::default() }).unwrap();
        let out = Motion::from_bvh("spliced", &s.bvh).unwrap();
        let blend = (SpliceOptions::default().blend_s / walk.1.frame_time).round() as usize;
        let mut inside: Vec<f32> = (1..out.frames()).map(|f| movement(&out, f)).collect();
        inside.sort_by(f32::total_cmp);
        let typical = inside[inside.len() / 10];
        for p in &s.pieces[1..] {
            // the transition's frames: blend/2 before the boundary to the rest after it
            let (a, b) = (p.start - blend / 2, p.start + (blend + 1) / 2);
            let slowest = (a.max(1)..=b).map(|f| movement(&out, f)).fold(f32::MAX, f32::min);
            assert!(
                slowest > 0.5 * typical,
                "seam at {}: slowest frame moves {slowest}, a 10th-percentile frame {typical}",
                p.start
            );
        }
    }

    #[test]
    fn bad_sources_and_options_are_refused() {
        let walk = take("02_01", include_str!("../tests/fixtures/02_01.bvh"), &[(0, 342, "walk")]);
        let other = take("mixamo", include_str!("../tests/fixtures/mixamo_names_freebvh.bvh"), &[(0, 60, "x")]);
        let src = |v: &[&(String, Bvh, Truth)]| -> Vec<(String, Bvh, Truth)> {
            v.iter().map(|(n, b, t)| (n.clone(), b.clone(), t.clone())).collect()
        };
        let both = src(&[&walk, &other]);
        let sources: Vec<Source> = both.iter().map(|(n, b, t)| Source { name: n, bvh: b, truth: t }).collect();
        assert!(matches!(splice(&sources, &SpliceOptions::default()), Err(SpliceError::Mismatch(_))));
        let one = src(&[&walk]);
        let sources: Vec<Source> = one.iter().map(|(n, b, t)| Source { name: n, bvh: b, truth: t }).collect();
        // one label only: the second piece has nothing different to come from
        assert!(matches!(splice(&sources, &SpliceOptions::default()), Err(SpliceError::NoPieces(_))));
        let bad = SpliceOptions { min_s: 4.0, max_s: 3.0, ..Default::default() };
        assert!(matches!(splice(&sources, &bad), Err(SpliceError::Options(_))));
        assert!(matches!(splice(&[], &SpliceOptions::default()), Err(SpliceError::NoSources)));
    }
}
