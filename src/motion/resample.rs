//! Resampling a take to another frame rate (the methods work at 30 Hz).
//!
//! Output frame `k` lies at time `k / fps_target`, i.e. at fractional source frame
//! `s_k = k · r` with `r = fps_source / fps_target`; positions are interpolated linearly
//! between source frames `⌊s_k⌋` and `⌊s_k⌋ + 1`. Output frames run while `s_k ≤ N − 1`
//! (no extrapolation past the last source frame), so there are `⌊(N − 1) / r⌋ + 1` of them.
//!
//! BVH frame times are printed with 5–7 significant digits (`0.0083333` is 120.0005 fps), so
//! a ratio within [`INTEGER_RATIO_TOLERANCE`] (relative) of a whole number `m` is taken to be
//! exactly `m`: 120 → 30 Hz gives output frame `k` = source frame `4k`, bit for bit.
//! Likewise a ratio whose inverse is close to a whole number (upsampling 30 → 120) steps
//! exactly `1/m` per frame. The result's `fps` is the requested rate.

use super::{Motion, MotionError, MAX_POSITIONS};
use glam::Vec3;

/// Relative distance from a whole number below which a rate ratio counts as whole.
pub const INTEGER_RATIO_TOLERANCE: f64 = 1e-3;

/// The ratio `fps_source / fps_target`, snapped as described in the module documentation,
/// as `(numerator, denominator)`: source frame of output frame `k` is `k · num / den`.
pub fn step(fps_source: f64, fps_target: f64) -> (f64, f64) {
    let r = fps_source / fps_target;
    let near_whole = |x: f64| {
        let m = x.round();
        (m >= 1.0 && (x - m).abs() <= INTEGER_RATIO_TOLERANCE * x).then_some(m)
    };
    if let Some(m) = near_whole(r) {
        (m, 1.0)
    } else if let Some(m) = near_whole(1.0 / r) {
        (1.0, m)
    } else {
        (r, 1.0)
    }
}

/// Fractional source frame index of every output frame when resampling `frames` source
/// frames from `fps_source` to `fps_target` (also useful to map results back to file frames).
pub fn source_positions(frames: usize, fps_source: f64, fps_target: f64) -> Result<Vec<f64>, MotionError> {
    if !(fps_target.is_finite() && fps_target > 0.0) {
        return Err(MotionError::BadTargetFps(fps_target));
    }
    if !(fps_source.is_finite() && fps_source > 0.0) {
        return Err(MotionError::BadFrameTime(1.0 / fps_source));
    }
    if frames == 0 {
        return Err(MotionError::NoFrames);
    }
    let (num, den) = step(fps_source, fps_target);
    let last = (frames - 1) as f64;
    let count = (last * den / num + 1e-9).floor() + 1.0;
    if count > MAX_POSITIONS as f64 {
        return Err(MotionError::TooLarge {
            frames: count.min(usize::MAX as f64) as usize,
            joints: 1,
            total: count.min(usize::MAX as f64) as usize,
            limit: MAX_POSITIONS,
        });
    }
    Ok((0..count as usize).map(|k| (k as f64 * num / den).min(last)).collect())
}

/// Linear interpolation of the frame at fractional index `s` into `out`.
fn interpolate(positions: &[Vec3], joints: usize, s: f64, out: &mut Vec<Vec3>) {
    let i = s.floor() as usize;
    let frac = (s - i as f64) as f32;
    let a = &positions[i * joints..(i + 1) * joints];
    if frac == 0.0 || (i + 1) * joints >= positions.len() {
        out.extend_from_slice(a);
        return;
    }
    let b = &positions[(i + 1) * joints..(i + 2) * joints];
    out.extend(a.iter().zip(b).map(|(p, q)| p.lerp(*q, frac)));
}

/// `motion` resampled to `fps` frames per second.
pub fn resample(motion: &Motion, fps: f64) -> Result<Motion, MotionError> {
    let joints = motion.joints();
    let src = source_positions(motion.frames(), motion.fps, fps)?;
    let total = src.len().saturating_mul(joints);
    if total > MAX_POSITIONS {
        return Err(MotionError::TooLarge { frames: src.len(), joints, total, limit: MAX_POSITIONS });
    }
    let mut positions = Vec::with_capacity(total);
    for &s in &src {
        interpolate(&motion.positions, joints, s, &mut positions);
    }
    Ok(Motion {
        name: motion.name.clone(),
        skeleton: motion.skeleton.clone(),
        fps,
        positions,
        units: motion.units,
        up_axis: motion.up_axis,
        warnings: motion.warnings.clone(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ratios_close_to_whole_numbers_snap() {
        assert_eq!(step(1.0 / 0.0083333, 30.0), (4.0, 1.0));
        assert_eq!(step(1.0 / 0.008333, 30.0), (4.0, 1.0));
        assert_eq!(step(30.0, 120.0), (1.0, 4.0));
        assert_eq!(step(60.0, 30.0), (2.0, 1.0));
        let (num, den) = step(100.0, 30.0);
        assert_eq!(den, 1.0);
        assert!((num - 10.0 / 3.0).abs() < 1e-12);
        // 23.976 → 30 is not a whole ratio and must not snap.
        let (num, _) = step(1.0 / 0.0417083750417, 30.0);
        assert!((num - 0.7992).abs() < 1e-4, "{num}");
    }

    #[test]
    fn source_positions_stop_at_the_last_frame() {
        assert_eq!(source_positions(9, 120.0, 30.0).unwrap(), vec![0.0, 4.0, 8.0]);
        assert_eq!(source_positions(8, 120.0, 30.0).unwrap(), vec![0.0, 4.0]);
        assert_eq!(source_positions(1, 120.0, 30.0).unwrap(), vec![0.0]);
        assert_eq!(source_positions(0, 120.0, 30.0), Err(MotionError::NoFrames));
        assert_eq!(source_positions(5, 120.0, 0.0), Err(MotionError::BadTargetFps(0.0)));
    }
}
