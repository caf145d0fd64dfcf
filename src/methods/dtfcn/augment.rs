//! Training-set augmentation — not in the paper (its 60 training takes were enough for it), but
//! what the tiny labelled sets here need: the changes a motion person knows leave a label as it is
//! (or, for mirroring, swap its side).
//!
//! Each is applied to a training crop of the motion image before standardisation, with its own
//! seeded draw, so the same seed gives the same training run:
//! * **mirror** — left and right swapped at the sagittal plane ([`mirrored`]), sided labels
//!   swapped (`left step` ↔ `right step`, any label whose name has `left`/`right`);
//! * **yaw** — the body frame turned by up to ±15° about the vertical (a whole-take rotation
//!   is a no-op on facing-aligned coordinates; this imitates an error in the facing estimate);
//! * **time warp** — played 0.8–1.2 times as fast (linear interpolation, root speeds scaled);
//! * **scale** — the body 0.9–1.1 times as large;
//! * **jitter** — Gaussian noise of 0.3 inch on every joint coordinate.
//!
//! Random crops are the training loop's own (see [`super::training`]).

use serde::{Deserialize, Serialize};

use crate::labeller::input::{channel_of, mirrored, NetworkInput, HIP_ROW, JOINTS, TURN_ROW};
use crate::stats::Rng;

/// Which augmentations training applies.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default)]
pub struct Augment {
    pub mirror: bool,
    pub yaw: bool,
    pub time_warp: bool,
    pub scale: bool,
    pub jitter: bool,
}

impl Default for Augment {
    fn default() -> Self {
        Augment::all()
    }
}

impl Augment {
    pub fn none() -> Augment {
        Augment { mirror: false, yaw: false, time_warp: false, scale: false, jitter: false }
    }

    pub fn all() -> Augment {
        Augment { mirror: true, yaw: true, time_warp: true, scale: true, jitter: true }
    }

    /// Reads `none`, `all`, or a comma-separated list of `mirror,yaw,warp,scale,jitter`.
    pub fn parse(text: &str) -> Result<Augment, String> {
        let text = text.trim();
        match text {
            "none" | "" => return Ok(Augment::none()),
            "all" => return Ok(Augment::all()),
            _ => {}
        }
        let mut a = Augment::none();
        for part in text.split(',') {
            match part.trim() {
                "mirror" => a.mirror = true,
                "yaw" => a.yaw = true,
                "warp" | "time_warp" => a.time_warp = true,
                "scale" => a.scale = true,
                "jitter" | "noise" => a.jitter = true,
                other => {
                    return Err(format!(
                    "unknown augmentation `{other}`; expected none, all, or a list of mirror, yaw, warp, scale, jitter"
                ))
                }
            }
        }
        Ok(a)
    }

    /// The names of the augmentations turned on (`none` when none is).
    pub fn describe(&self) -> String {
        let names: Vec<&str> = [
            (self.mirror, "mirror"),
            (self.yaw, "yaw"),
            (self.time_warp, "warp"),
            (self.scale, "scale"),
            (self.jitter, "jitter"),
        ]
        .iter()
        .filter(|(on, _)| *on)
        .map(|(_, n)| *n)
        .collect();
        if names.is_empty() {
            "none".into()
        } else {
            names.join(",")
        }
    }
}

/// For each class, the class of the mirrored motion: names with `left` and `right` swapped
/// when that name is also a class, else the class itself.
pub fn mirror_classes(classes: &[String]) -> Vec<usize> {
    classes
        .iter()
        .enumerate()
        .map(|(i, name)| {
            let swapped = swap_sides(name);
            classes.iter().position(|c| *c == swapped).unwrap_or(i)
        })
        .collect()
}

/// `name` with every `left`/`right` (any case) exchanged.
fn swap_sides(name: &str) -> String {
    let lower = name.to_ascii_lowercase();
    let mut out = String::with_capacity(name.len());
    let mut i = 0;
    while i < name.len() {
        let rest = &lower[i..];
        let (from, to) = if rest.starts_with("left") {
            (4, "right")
        } else if rest.starts_with("right") {
            (5, "left")
        } else {
            let c = name[i..].chars().next().unwrap_or(' ');
            out.push(c);
            i += c.len_utf8();
            continue;
        };
        // keep the case of the first letter
        let first_upper = name[i..].starts_with(|c: char| c.is_ascii_uppercase());
        if first_upper {
            out.push_str(&to[..1].to_ascii_uppercase());
            out.push_str(&to[1..]);
        } else {
            out.push_str(to);
        }
        i += from;
    }
    out
}

/// A standard normal draw (Box–Muller).
fn normal(rng: &mut Rng) -> f32 {
    let u1 = rng.next_f32().max(1e-7);
    let u2 = rng.next_f32();
    (-2.0 * u1.ln()).sqrt() * (2.0 * std::f32::consts::PI * u2).cos()
}

/// Uniform in `[lo, hi)`.
fn uniform(rng: &mut Rng, lo: f32, hi: f32) -> f32 {
    lo + (hi - lo) * rng.next_f32()
}

/// An augmented crop: its motion image, the original frame each of its frames was made from,
/// and whether it was mirrored (sided labels must then swap, [`Augmented::labels`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Augmented {
    pub input: NetworkInput,
    pub frame_of: Vec<usize>,
    pub mirrored: bool,
}

impl Augmented {
    /// Per-frame `labels` of the original crop carried to the augmented one.
    pub fn labels(&self, labels: &[Option<usize>], mirror_of: &[usize]) -> Vec<Option<usize>> {
        self.frame_of
            .iter()
            .map(|&f| labels[f].map(|l| if self.mirrored { mirror_of.get(l).copied().unwrap_or(l) } else { l }))
            .collect()
    }

    /// Any per-frame values of the original crop carried to the augmented one.
    pub fn carry<T: Copy>(&self, values: &[T]) -> Vec<T> {
        self.frame_of.iter().map(|&f| values[f]).collect()
    }
}

/// `input` changed by the augmentations `a` turns on, with draws from `rng`.
pub fn augment(input: NetworkInput, a: &Augment, rng: &mut Rng) -> Augmented {
    // draw every augmentation's numbers whether it is on or not: turning one off leaves the
    // others' draws as they were
    let (flip, yaw, warp, scale) =
        (rng.next_f32() < 0.5, uniform(rng, -15.0, 15.0).to_radians(), uniform(rng, 0.8, 1.2), uniform(rng, 0.9, 1.1));
    let jitter_seed = rng.next_u64();
    let mut out = Augmented { frame_of: (0..input.frames).collect(), input, mirrored: false };
    if a.mirror && flip {
        out.input = mirrored(&out.input);
        out.mirrored = true;
    }
    if a.yaw {
        turn(&mut out.input, yaw);
    }
    if a.time_warp {
        let (input, frame_of) = time_warp(&out.input, warp);
        out.input = input;
        out.frame_of = frame_of;
    }
    let n = out.input.frames;
    if a.scale {
        for j in (0..JOINTS).filter(|&j| j != TURN_ROW) {
            for axis in 0..3 {
                let c = channel_of(axis, j);
                out.input.values[c * n..(c + 1) * n].iter_mut().for_each(|v| *v *= scale);
            }
        }
    }
    if a.jitter {
        let mut r = Rng::new(jitter_seed);
        for j in (0..JOINTS).filter(|&j| j != HIP_ROW && j != TURN_ROW) {
            for axis in 0..3 {
                let c = channel_of(axis, j);
                out.input.values[c * n..(c + 1) * n].iter_mut().for_each(|v| *v += 0.3 * normal(&mut r));
            }
        }
    }
    out
}

/// Turns the body frame by `angle` about the vertical: every joint's (x, z) and the root's
/// (lateral, forward) speed (not the turning rate).
fn turn(input: &mut NetworkInput, angle: f32) {
    let (sin, cos) = angle.sin_cos();
    let n = input.frames;
    for j in (0..JOINTS).filter(|&j| j != TURN_ROW) {
        let (cx, cz) = (channel_of(0, j), channel_of(2, j));
        for t in 0..n {
            let (x, z) = (input.values[cx * n + t], input.values[cz * n + t]);
            input.values[cx * n + t] = cos * x + sin * z;
            input.values[cz * n + t] = -sin * x + cos * z;
        }
    }
}

/// `input` played `speed` times as fast: frame `t'` of the result is frame `t'·speed` of the
/// original (linear interpolation); root speeds and turning rate scaled by `speed`. Also gives
/// the nearest original frame of each new one.
pub fn time_warp(input: &NetworkInput, speed: f32) -> (NetworkInput, Vec<usize>) {
    let n = input.frames;
    if n < 2 {
        return (input.clone(), (0..n).collect());
    }
    let m = (((n - 1) as f32 / speed).floor() as usize + 1).max(1);
    let channels = input.values.len() / n;
    let mut values = vec![0f32; channels * m];
    let mut frame_of = Vec::with_capacity(m);
    let mut source_frames = Vec::with_capacity(m);
    for t in 0..m {
        let x = (t as f32 * speed).min((n - 1) as f32);
        let i = (x.floor() as usize).min(n - 2);
        let f = x - i as f32;
        for c in 0..channels {
            let a = input.values[c * n + i];
            let b = input.values[c * n + i + 1];
            values[c * m + t] = a + f * (b - a);
        }
        let nearest = (x.round() as usize).min(n - 1);
        frame_of.push(nearest);
        source_frames.push(input.source_frames.get(nearest).copied().unwrap_or(0.0));
    }
    for c in [0, 1, 2].map(|axis| channel_of(axis, HIP_ROW)).into_iter().chain([channel_of(0, TURN_ROW)]) {
        values[c * m..(c + 1) * m].iter_mut().for_each(|v| *v *= speed);
    }
    (NetworkInput { values, frames: m, source_frames }, frame_of)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::labeller::input::CHANNELS;

    fn input(frames: usize) -> NetworkInput {
        let values = (0..CHANNELS * frames).map(|i| (i % 97) as f32 * 0.1).collect();
        NetworkInput { values, frames, source_frames: (0..frames).map(|f| f as f64).collect() }
    }

    /// The turning row is a rate, not a position: turning the body frame or scaling the body leaves
    /// it, playing faster scales it; the root's speeds turn with the frame and scale with the body.
    #[test]
    fn the_turning_rate_is_not_turned_or_scaled_but_warped() {
        use crate::labeller::input::TURN_ROW;
        let x = input(50);
        let turning = channel_of(0, TURN_ROW);
        let mut turned = x.clone();
        turn(&mut turned, 0.3);
        assert_eq!(turned.channel(turning), x.channel(turning));
        assert_ne!(turned.channel(channel_of(0, HIP_ROW)), x.channel(channel_of(0, HIP_ROW)));
        let scaled = augment(x.clone(), &Augment { scale: true, ..Augment::none() }, &mut Rng::new(3));
        assert_eq!(scaled.input.channel(turning), x.channel(turning));
        assert_ne!(scaled.input.channel(channel_of(1, HIP_ROW)), x.channel(channel_of(1, HIP_ROW)));
        let (fast, _) = time_warp(&x, 2.0);
        assert!((fast.at(turning, 3) - 2.0 * x.at(turning, 6)).abs() < 1e-5);
    }

    #[test]
    fn sided_labels_swap_and_others_stay() {
        let classes: Vec<String> =
            ["standing", "begin left step", "begin right step", "Left step", "Right step", "turn", "left only"]
                .iter()
                .map(|s| s.to_string())
                .collect();
        assert_eq!(mirror_classes(&classes), vec![0, 2, 1, 4, 3, 5, 6]);
    }

    #[test]
    fn warping_changes_the_length_and_keeps_the_frames_in_order() {
        let x = input(100);
        let (fast, frame_of) = time_warp(&x, 1.25);
        assert_eq!(fast.frames, 80);
        assert_eq!(frame_of.len(), 80);
        assert_eq!((frame_of[0], frame_of[79]), (0, 99));
        assert!(frame_of.windows(2).all(|w| w[0] <= w[1]));
        let (slow, _) = time_warp(&x, 0.8);
        assert_eq!(slow.frames, 124);
        assert_eq!(time_warp(&x, 1.0).0, x);
    }

    #[test]
    fn augmenting_is_deterministic_mirrors_sided_labels_and_none_is_the_identity() {
        let x = input(60);
        let a = augment(x.clone(), &Augment::all(), &mut Rng::new(7));
        let b = augment(x.clone(), &Augment::all(), &mut Rng::new(7));
        assert_eq!(a, b);
        assert_ne!(a.input, x);
        let same = augment(x.clone(), &Augment::none(), &mut Rng::new(7));
        assert_eq!(same.input, x);
        assert!(!same.mirrored);
        // a mirrored crop swaps its sided labels
        let flipped = (0..40)
            .map(|s| augment(x.clone(), &Augment { mirror: true, ..Augment::none() }, &mut Rng::new(s)))
            .find(|a| a.mirrored)
            .unwrap();
        let labels: Vec<Option<usize>> = (0..60).map(|f| Some(usize::from(f >= 30))).collect();
        let swapped = flipped.labels(&labels, &[1, 0]);
        assert_eq!((swapped[0], swapped[59]), (Some(1), Some(0)));
        assert_eq!(Augment::parse("mirror,warp").unwrap().describe(), "mirror,warp");
        assert!(Augment::parse("mirror,spin").unwrap_err().contains("`spin`"));
    }
}
