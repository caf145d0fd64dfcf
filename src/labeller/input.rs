//! The motion image as the network reads it (Cheema et al. 2019, §2: "each column of the image
//! represents a frame … the rows represent the joints and the RGB values are the scaled XYZ
//! Euclidean coordinates of each corresponding joint").
//!
//! Here: the take resampled to [`NETWORK_FPS`] (30 Hz), one column per working frame, one row
//! per canonical joint ([`Canonical::ALL`], 17 joints found in any skeleton by the joint
//! mapping), the three channels the joint's X, Y, Z relative to the hips, facing +Z, in inches
//! of the reference body (the "local" coordinates of the paper's Fig. 2, made independent of
//! where the actor stands, which way they face, their size and the file's units).
//!
//! The hips row is zero in those coordinates, so it carries the root's own motion instead: its
//! velocity in the body frame (lateral, vertical, forward, inches per second). An 18th row,
//! [`TURN_ROW`], carries the turning rate (degrees per second, in its X channel). Without them
//! "turn", "begin step" (the paper's labels), a jump or a squat would have to be guessed from
//! the limbs alone.
//!
//! Before the network sees it every channel is standardised with the mean and spread of the
//! training frames ([`Standardise`], kept in the model file).

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::features::end_effectors::canonical_joints;
use crate::motion::joints::Canonical;
use crate::motion::normalize::{facing_yaws, to_y_up};
use crate::motion::Motion;

/// The rate the network works at (the paper's takes were 72 Hz; 30 Hz keeps its 243-frame
/// receptive field at 8 s).
pub const NETWORK_FPS: f64 = 30.0;

/// Rows of the image: the canonical joints and the turning row.
pub const JOINTS: usize = Canonical::ALL.len() + 1;

/// The image row of the hips (the root's velocity, see the module docs).
pub const HIP_ROW: usize = 0;

/// The image row of the turning rate (X channel; Y and Z are zero).
pub const TURN_ROW: usize = Canonical::ALL.len();

/// The name of [`TURN_ROW`] in model files.
pub const TURN_ROW_NAME: &str = "turning";

/// Channels per column: X, Y, Z of every row, channel-major (`channel · JOINTS + row`).
pub const CHANNELS: usize = 3 * JOINTS;

/// Names of the canonical joints (the k-NN's windows read these).
pub fn canonical_names() -> Vec<String> {
    Canonical::ALL.iter().map(|c| c.name().to_string()).collect()
}

/// Names of the image rows, as stored in model files (the joint set a model was trained on).
pub fn joint_names() -> Vec<String> {
    let mut names: Vec<String> = Canonical::ALL.iter().map(|c| c.name().to_string()).collect();
    names.push(TURN_ROW_NAME.into());
    names
}

/// A take's motion image at the network's rate.
#[derive(Debug, Clone, PartialEq)]
pub struct NetworkInput {
    /// `CHANNELS × frames`, channel-major (row `c` is one channel over time).
    pub values: Vec<f32>,
    /// Working frames (columns).
    pub frames: usize,
    /// Fractional file frame of each working frame.
    pub source_frames: Vec<f64>,
}

impl NetworkInput {
    /// The value of channel `c` at working frame `t`.
    pub fn at(&self, c: usize, t: usize) -> f32 {
        self.values[c * self.frames + t]
    }

    /// Channel `c` over time.
    pub fn channel(&self, c: usize) -> &[f32] {
        &self.values[c * self.frames..(c + 1) * self.frames]
    }
}

/// Index of the channel of `axis` (0 x lateral, 1 y up, 2 z forward) of image row `joint`.
pub fn channel_of(axis: usize, joint: usize) -> usize {
    axis * JOINTS + joint
}

/// The motion image of `motion` (see the module docs); the message names the take and what is
/// missing.
pub fn network_input(motion: &Motion) -> Result<NetworkInput, String> {
    let f =
        canonical_joints(motion, NETWORK_FPS, true, &Canonical::ALL).map_err(|e| format!("{}: {e}", motion.name))?;
    let frames = f.base.frames();
    let mut values = vec![0f32; CHANNELS * frames];
    for t in 0..frames {
        let row = f.base.row(t);
        for j in 0..Canonical::ALL.len() {
            for axis in 0..3 {
                values[channel_of(axis, j) * frames + t] = row[3 * j + axis];
            }
        }
    }
    // the hips row: the root's motion in the body frame
    let working = motion.resample(NETWORK_FPS).map_err(|e| format!("{}: {e}", motion.name))?;
    let map = working.joint_map().map_err(|e| format!("{}: {e}", motion.name))?;
    let yaws = facing_yaws(&working, &map);
    let scale = f.scale as f32; // file units → inches of the reference body
    let hips: Vec<Vec3> =
        (0..frames).map(|t| to_y_up(working.position(t, map.hips), working.up_axis) * scale).collect();
    let hip = HIP_ROW;
    for t in 0..frames {
        let (a, b) = (t.saturating_sub(1), (t + 1).min(frames - 1));
        let dt = (b - a).max(1) as f32 / NETWORK_FPS as f32;
        let v = (hips[b] - hips[a]) / dt;
        let yaw = yaws[t];
        // into the body frame: rotate by −yaw about +Y (body faces +Z)
        let (s, c) = yaw.sin_cos();
        let lateral = c * v.x - s * v.z;
        let forward = s * v.x + c * v.z;
        let vertical = v.y;
        let mut turn = yaws[b] - yaws[a];
        while turn > std::f32::consts::PI {
            turn -= 2.0 * std::f32::consts::PI;
        }
        while turn < -std::f32::consts::PI {
            turn += 2.0 * std::f32::consts::PI;
        }
        // degrees per second: of the order of the limbs' inches per second
        let turn = turn.to_degrees() / dt;
        values[channel_of(0, hip) * frames + t] = lateral;
        values[channel_of(1, hip) * frames + t] = vertical;
        values[channel_of(2, hip) * frames + t] = forward;
        values[channel_of(0, TURN_ROW) * frames + t] = turn;
    }
    if let Some(k) = values.iter().position(|v| !v.is_finite()) {
        return Err(format!(
            "{}: the motion image has a non-finite value (channel {}, working frame {})",
            motion.name,
            k / frames,
            k % frames
        ));
    }
    Ok(NetworkInput { values, frames, source_frames: f.source_frames })
}

/// The image of the mirrored take (left and right swapped at the sagittal plane): rows of
/// sided joints swap, the lateral channel (and with it the turning rate) changes sign.
pub fn mirrored(input: &NetworkInput) -> NetworkInput {
    let mut partner: Vec<usize> = Canonical::ALL
        .iter()
        .map(|c| {
            let m = c.mirror();
            Canonical::ALL.iter().position(|&o| o == m).unwrap_or(0)
        })
        .collect();
    partner.push(TURN_ROW);
    let n = input.frames;
    let mut values = vec![0f32; input.values.len()];
    for (j, &other) in partner.iter().enumerate() {
        for axis in 0..3 {
            let sign = if axis == 0 { -1.0 } else { 1.0 };
            let from = channel_of(axis, other);
            let to = channel_of(axis, j);
            for t in 0..n {
                values[to * n + t] = sign * input.values[from * n + t];
            }
        }
    }
    NetworkInput { values, frames: n, source_frames: input.source_frames.clone() }
}

/// `input` with every joint channel less its own median over the take — the take's mean posture removed, the
/// movement kept (not in the paper; [`Standardise::centre_on_take`]). The hips' row (the root's velocities) and the
/// turning row, already rates, are left as they are. Centring a centred take changes nothing.
pub fn centred_on_take(input: &NetworkInput) -> NetworkInput {
    let n = input.frames;
    let mut values = input.values.clone();
    if n == 0 {
        return NetworkInput { values, frames: n, source_frames: input.source_frames.clone() };
    }
    let rates: Vec<usize> = (0..3).flat_map(|axis| [channel_of(axis, HIP_ROW), channel_of(axis, TURN_ROW)]).collect();
    for c in (0..CHANNELS).filter(|c| !rates.contains(c)) {
        let channel = &mut values[c * n..(c + 1) * n];
        let median = crate::stats::median(&mut channel.to_vec()).unwrap_or(0.0);
        channel.iter_mut().for_each(|v| *v -= median);
    }
    NetworkInput { values, frames: n, source_frames: input.source_frames.clone() }
}

/// Per value: the mean and the spread (standard deviation; 1 for a value that never varies, below 1e-3) from the
/// sums and the sums of squares of `n` samples of each (the k-NN's standardised windows share it).
pub fn mean_and_spread(sum: &[f64], squares: &[f64], n: f64) -> (Vec<f32>, Vec<f32>) {
    let n = n.max(1.0);
    let mean = sum.iter().map(|s| (s / n) as f32).collect();
    let spread = sum
        .iter()
        .zip(squares)
        .map(|(s, q)| {
            let sd = (q / n - (s / n) * (s / n)).max(0.0).sqrt() as f32;
            if sd > 1e-3 {
                sd
            } else {
                1.0
            }
        })
        .collect();
    (mean, spread)
}

/// Per-channel standardisation learnt from the training frames: `(x − mean) / spread`, after centring each whole
/// take on its own median posture when `centre_on_take`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Standardise {
    pub mean: Vec<f32>,
    pub spread: Vec<f32>,
    /// Each take is first centred on its own median posture ([`centred_on_take`]; not in the paper): a subject's
    /// stance and proportions, which shift every limb's position, no longer shift the input. Models without the field
    /// do not centre.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub centre_on_take: bool,
}

impl Standardise {
    /// Mean and standard deviation of every channel over all frames of `inputs` (a channel
    /// that never varies gets spread 1).
    pub fn fit(inputs: &[&NetworkInput]) -> Standardise {
        let mut sum = vec![0f64; CHANNELS];
        let mut sq = vec![0f64; CHANNELS];
        let mut n = 0f64;
        for x in inputs {
            for (c, (s, q)) in sum.iter_mut().zip(sq.iter_mut()).enumerate() {
                for &v in x.channel(c) {
                    *s += v as f64;
                    *q += (v as f64) * (v as f64);
                }
            }
            n += x.frames as f64;
        }
        let (mean, spread) = mean_and_spread(&sum, &sq, n);
        Standardise { mean, spread, centre_on_take: false }
    }

    /// The same statistics, centring each take first or not (the statistics must have been fitted on takes prepared
    /// the same way).
    pub fn centring(self, centre_on_take: bool) -> Standardise {
        Standardise { centre_on_take, ..self }
    }

    /// `input` — a whole take — standardised, channel-major: centred on its own median first when
    /// [`Standardise::centre_on_take`], then scaled ([`Standardise::scale`]).
    pub fn apply(&self, input: &NetworkInput) -> Vec<f32> {
        if self.centre_on_take {
            self.scale(&centred_on_take(input))
        } else {
            self.scale(input)
        }
    }

    /// `input`'s values less the mean over the spread, channel-major, without centring: for a crop of a take that
    /// was centred whole (training), where the crop's own median is not the take's.
    pub fn scale(&self, input: &NetworkInput) -> Vec<f32> {
        let n = input.frames;
        let mut out = input.values.clone();
        for c in 0..CHANNELS {
            let (m, s) = (self.mean[c], self.spread[c]);
            for v in &mut out[c * n..(c + 1) * n] {
                *v = (*v - m) / s;
            }
        }
        out
    }

    /// Refuses statistics of the wrong size or with non-finite or non-positive spreads.
    pub fn check(&self) -> Result<(), String> {
        if self.mean.len() != CHANNELS || self.spread.len() != CHANNELS {
            return Err(format!(
                "standardisation has {} means and {} spreads, expected {CHANNELS} ({JOINTS} joints × 3)",
                self.mean.len(),
                self.spread.len()
            ));
        }
        if self.mean.iter().any(|m| !m.is_finite()) || self.spread.iter().any(|s| !(s.is_finite() && *s > 0.0)) {
            return Err("standardisation holds a non-finite mean or a spread that is not positive".into());
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh;

    fn walk() -> Motion {
        Motion::from_bvh("02_01.bvh", &bvh::parse(include_str!("../../tests/fixtures/02_01.bvh")).unwrap()).unwrap()
    }

    #[test]
    fn a_walk_becomes_an_18_row_image_at_30_hz_with_the_root_moving_forwards() {
        let m = walk();
        let x = network_input(&m).unwrap();
        assert_eq!(x.values.len(), CHANNELS * x.frames);
        let expected = (m.duration_s() * NETWORK_FPS).floor() as usize;
        assert!(x.frames.abs_diff(expected) <= 1, "{} vs {expected}", x.frames);
        assert_eq!(Canonical::ALL[HIP_ROW], Canonical::Hips);
        let hip = HIP_ROW;
        let forward: f32 = x.channel(channel_of(2, hip)).iter().sum::<f32>() / x.frames as f32;
        // a walk at about 1.2 m/s: tens of inches per second forwards, little sideways
        assert!(forward > 20.0 && forward < 120.0, "{forward}");
        let lateral: f32 = x.channel(channel_of(0, hip)).iter().sum::<f32>() / x.frames as f32;
        assert!(lateral.abs() < forward / 4.0, "{lateral}");
        // the root bobs up and down as it walks (vertical speed), but does not climb
        let vertical = x.channel(channel_of(1, hip));
        let mean_up = vertical.iter().sum::<f32>() / x.frames as f32;
        let bob = vertical.iter().map(|v| v.abs()).sum::<f32>() / x.frames as f32;
        assert!(mean_up.abs() < 2.0 && bob > 0.5 && bob < forward / 2.0, "mean {mean_up}, mean |v| {bob}");
        // a walk mostly straight ahead: little turning; the turning row's other channels are zero
        let turning: f32 = x.channel(channel_of(0, TURN_ROW)).iter().sum::<f32>() / x.frames as f32;
        assert!(turning.abs() < 30.0, "{turning} °/s");
        assert!(x.channel(channel_of(1, TURN_ROW)).iter().chain(x.channel(channel_of(2, TURN_ROW))).all(|&v| v == 0.0));
        assert_eq!(joint_names().len(), JOINTS);
        assert_eq!(joint_names()[TURN_ROW], TURN_ROW_NAME);
        // the head is above the hips
        let head = Canonical::ALL.iter().position(|&c| c == Canonical::Head).unwrap();
        assert!(x.at(channel_of(1, head), 10) > 10.0);
    }

    #[test]
    fn mirroring_twice_is_the_identity_and_swaps_the_hands() {
        let x = network_input(&walk()).unwrap();
        let m = mirrored(&x);
        assert_eq!(mirrored(&m), x);
        let lh = Canonical::ALL.iter().position(|&c| c == Canonical::LeftHand).unwrap();
        let rh = Canonical::ALL.iter().position(|&c| c == Canonical::RightHand).unwrap();
        assert_eq!(m.at(channel_of(0, lh), 5), -x.at(channel_of(0, rh), 5));
        assert_eq!(m.at(channel_of(1, lh), 5), x.at(channel_of(1, rh), 5));
        // turning left becomes turning right; the root's vertical speed stays
        assert_eq!(m.at(channel_of(0, TURN_ROW), 5), -x.at(channel_of(0, TURN_ROW), 5));
        assert_eq!(m.at(channel_of(1, HIP_ROW), 5), x.at(channel_of(1, HIP_ROW), 5));
    }

    #[test]
    fn standardised_channels_have_zero_mean_and_unit_spread() {
        let x = network_input(&walk()).unwrap();
        let s = Standardise::fit(&[&x]);
        s.check().unwrap();
        let z = s.apply(&x);
        let c = channel_of(1, 7);
        let col = &z[c * x.frames..(c + 1) * x.frames];
        let mean = col.iter().sum::<f32>() / x.frames as f32;
        let var = col.iter().map(|v| (v - mean) * (v - mean)).sum::<f32>() / x.frames as f32;
        assert!(mean.abs() < 1e-3 && (var - 1.0).abs() < 1e-2, "{mean} {var}");
        let mut bad = s.clone();
        bad.spread[3] = 0.0;
        assert!(bad.check().is_err());
    }

    #[test]
    fn centring_removes_the_takes_posture_and_keeps_the_rates() {
        let x = network_input(&walk()).unwrap();
        let n = x.frames;
        let c = centred_on_take(&x);
        let median = |v: &[f32]| crate::stats::median(&mut v.to_vec()).unwrap();
        for ch in 0..CHANNELS {
            let rate = (0..3).any(|a| ch == channel_of(a, HIP_ROW) || ch == channel_of(a, TURN_ROW));
            if rate {
                assert_eq!(c.channel(ch), x.channel(ch), "channel {ch}: the root's velocities and turning stay");
            } else {
                assert_eq!(median(c.channel(ch)), 0.0, "channel {ch}");
                // the movement kept: every frame moved by the same amount
                let shift = x.at(ch, 0) - c.at(ch, 0);
                assert!((0..n).all(|t| ((x.at(ch, t) - c.at(ch, t)) - shift).abs() < 1e-3), "channel {ch}");
            }
        }
        // a centred take is centred; a take held in another posture (every limb channel offset) centres alike
        assert_eq!(centred_on_take(&c), c);
        let mut other = x.clone();
        let head = Canonical::ALL.iter().position(|&j| j == Canonical::Head).unwrap();
        for ch in [channel_of(0, head), channel_of(1, head), channel_of(2, 7)] {
            other.values[ch * n..(ch + 1) * n].iter_mut().for_each(|v| *v += 4.0);
        }
        let o = centred_on_take(&other);
        assert!(o.values.iter().zip(&c.values).all(|(a, b)| (a - b).abs() < 1e-3));
        // the standardisation: centred whole, then scaled; without the flag, scaled only
        let s = Standardise::fit(&[&c]).centring(true);
        assert_eq!(s.apply(&x), s.scale(&c));
        assert_eq!(s.clone().centring(false).apply(&x), s.scale(&x));
        // in a model file: written only when on, read as off when absent (earlier models)
        let off = serde_json::to_value(s.clone().centring(false)).unwrap();
        assert!(off.get("centre_on_take").is_none(), "{off}");
        let on = serde_json::to_value(&s).unwrap();
        assert_eq!(on["centre_on_take"], true);
        let back: Standardise = serde_json::from_value(off).unwrap();
        assert!(!back.centre_on_take);
    }

    #[test]
    fn a_skeleton_without_the_canonical_joints_is_refused_by_name() {
        let stick = Motion::from_bvh(
            "stick.bvh",
            &bvh::parse(include_str!("../../tests/fixtures/bvh_anim_test_simple.bvh")).unwrap(),
        )
        .unwrap();
        assert!(network_input(&stick).unwrap_err().starts_with("stick.bvh:"));
    }
}
