//! What a run needs, declared by every method and checked before it allocates anything.
//!
//! The loader's budget ([`crate::load::MemoryBudget`]) bounds the *file*: its frames and
//! joints. A method then resamples the take to its own working rate (30 Hz for most), and the
//! work it does grows with the *working* frames — the take's duration times that rate. A
//! 200-frame file with `Frame Time: 100` passes the loader (200 frames) and is 5.5 hours long:
//! 597,000 working frames, gigabytes of arrays and minutes of a frozen worker. So every method
//! declares its [`Work`] — its rate and the bytes its own arrays hold per working frame (an upper
//! bound that `tests/limits.rs` measures with a counting allocator) — and
//! [`crate::method::DynMethod::run_checked`] checks it against [`WorkLimits`] before `run`:
//!
//! * a file rate below [`WorkLimits::min_file_fps`] is refused (motion capture is recorded at
//!   24–240 Hz; 1 Hz is already a slide show, and below it the working take is interpolated
//!   out of almost nothing);
//! * a take longer than [`WorkLimits::max_seconds`] is refused (the page's worker is one thread;
//!   a method must answer within minutes, with progress and cancel, not hours);
//! * a take whose working arrays — the resampled positions and the method's own — pass
//!   [`WorkLimits::max_bytes`] is refused, with the longest duration that would fit.

use super::MethodError;
use crate::motion::{resample, Motion};

/// What one run of a method needs per working frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Work {
    /// The rate the method resamples the take to (frames per second).
    pub fps: f64,
    /// Bytes the method's own arrays hold per working frame at their peak (the resampled
    /// positions not included: [`Work::bytes`] adds them). An upper bound, measured.
    pub bytes_per_frame: usize,
    /// Bytes besides, whatever the take's length (scratch of a fixed size, pictures).
    pub fixed_bytes: usize,
    /// What else than cutting the take makes it fit (`or lower max_neighbours`; empty: nothing).
    pub advice: &'static str,
}

/// The limits every run is checked against.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WorkLimits {
    /// The slowest file rate a method resamples from.
    pub min_file_fps: f64,
    /// The longest take, in seconds.
    pub max_seconds: f64,
    /// What a run may hold: the loader's budget (a browser tab's 1 GiB).
    pub max_bytes: usize,
}

impl Default for WorkLimits {
    /// 1 Hz, two hours, the loader's 1 GiB.
    fn default() -> Self {
        WorkLimits {
            min_file_fps: 1.0,
            max_seconds: 2.0 * 3600.0,
            max_bytes: crate::load::MemoryBudget::default().max_bytes,
        }
    }
}

/// Bytes of one resampled position (`f32` × 3).
const POSITION_BYTES: usize = 12;

impl Work {
    /// Working frames of `motion` at this rate (as [`resample`] makes them, without making them).
    pub fn frames(&self, motion: &Motion) -> usize {
        if motion.frames() == 0 || !(motion.fps > 0.0) || !(self.fps > 0.0) {
            return 0;
        }
        let (num, den) = resample::step(motion.fps, self.fps);
        let count = ((motion.frames() - 1) as f64 * den / num + 1e-9).floor() + 1.0;
        count.min(usize::MAX as f64) as usize
    }

    /// Bytes of `frames` working frames of a `joints`-joint take: the resampled positions and
    /// the method's arrays (saturating).
    pub fn bytes(&self, frames: usize, joints: usize) -> usize {
        let per_frame = joints.saturating_mul(POSITION_BYTES).saturating_add(self.bytes_per_frame);
        frames.saturating_mul(per_frame).saturating_add(self.fixed_bytes)
    }

    /// Ok if `method` (its short name, for the message) may run on `motion` within `limits`;
    /// otherwise why not, naming the take's duration and the limit passed (the command line and
    /// the page put the file's name before a method's message).
    pub fn check(&self, method: &str, motion: &Motion, limits: &WorkLimits) -> Result<(), MethodError> {
        if !(motion.fps >= limits.min_file_fps) {
            return Err(MethodError::Failed(format!(
                "Frame Time {} s is {} frames per second; {method} works at {} Hz and would make {} of \
                 its frames out of every one of the file's. Motion capture is recorded at {} Hz or more: check \
                 the file's Frame Time",
                round(1.0 / motion.fps),
                round(motion.fps),
                round(self.fps),
                round(self.fps / motion.fps),
                round(limits.min_file_fps),
            )));
        }
        let seconds = (motion.frames().saturating_sub(1)) as f64 / motion.fps;
        let frames = self.frames(motion);
        if seconds > limits.max_seconds {
            return Err(MethodError::Failed(format!(
                "the take is {} long ({} frames at {} Hz); {method} segments at most {} at a time: cut \
                 the take",
                duration(seconds),
                motion.frames(),
                round(motion.fps),
                duration(limits.max_seconds),
            )));
        }
        let needed = self.bytes(frames, motion.joints());
        if needed > limits.max_bytes {
            let per_second = self.bytes(self.fps.ceil() as usize, motion.joints()).max(1);
            let fits = limits.max_bytes.saturating_sub(self.fixed_bytes) as f64 / per_second as f64;
            return Err(MethodError::Failed(format!(
                "the take is {} long, {frames} frames at {method}'s {} Hz, which need about {} MiB, \
                 more than the budget of {} MiB: cut the take to at most {}{}",
                duration(seconds),
                round(self.fps),
                needed.div_ceil(1 << 20),
                limits.max_bytes / (1 << 20),
                duration(fits.floor()),
                if self.advice.is_empty() { String::new() } else { format!(" {}", self.advice) },
            )));
        }
        Ok(())
    }
}

/// A number with at most 3 significant decimals, without trailing zeros (`100`, `0.01`, `3000`).
fn round(x: f64) -> String {
    let s = format!("{x:.3}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "0" || s == "-0" {
        format!("{x:.1e}")
    } else {
        s.to_string()
    }
}

/// `5 h 33 min`, `12 min 5 s`, `40 s`.
fn duration(seconds: f64) -> String {
    let s = seconds.round().max(0.0) as u64;
    match (s / 3600, s / 60 % 60, s % 60) {
        (0, 0, sec) => format!("{sec} s"),
        (0, min, sec) => format!("{min} min {sec} s"),
        (h, min, _) => format!("{h} h {min} min"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn take(frames: usize, frame_time: f64) -> Motion {
        let text = format!(
            "HIERARCHY\nROOT Hips\n{{\nOFFSET 0 0 0\nCHANNELS 3 Xposition Yposition Zposition\nEnd Site\n{{\nOFFSET 0 1 0\n}}\n}}\n\
             MOTION\nFrames: {frames}\nFrame Time: {frame_time}\n{}",
            "0 0 0\n".repeat(frames)
        );
        crate::load::load_bytes("odd.bvh", text.as_bytes(), &mut |_| {}).unwrap().motion
    }

    const LIGHT: Work = Work { fps: 30.0, bytes_per_frame: 1000, fixed_bytes: 0, advice: "" };

    #[test]
    fn working_frames_are_those_resampling_makes() {
        for (frames, frame_time) in [(200, 1.0 / 120.0), (201, 1.0 / 24.0), (1, 0.01), (7, 1.0 / 30.0)] {
            let m = take(frames, frame_time);
            assert_eq!(LIGHT.frames(&m), m.resample(30.0).unwrap().frames(), "{frames} at {frame_time}");
        }
    }

    #[test]
    fn a_slow_frame_time_is_refused_before_any_work() {
        let m = take(200, 100.0);
        let err = LIGHT.check("SSSM", &m, &WorkLimits::default()).unwrap_err().to_string();
        assert_eq!(
            err,
            "Frame Time 100 s is 0.01 frames per second; SSSM works at 30 Hz and would make 3000 of its \
             frames out of every one of the file's. Motion capture is recorded at 1 Hz or more: check the file's \
             Frame Time"
        );
        // 1 Hz is a rate (a 200 s take)
        assert_eq!(LIGHT.check("SSSM", &take(200, 1.0), &WorkLimits::default()), Ok(()));
    }

    #[test]
    fn a_take_too_long_or_too_heavy_is_refused_with_what_would_fit() {
        let limits = WorkLimits { max_seconds: 600.0, max_bytes: 64 << 20, ..WorkLimits::default() };
        // 10 min 1 s at 1 Hz
        let err = LIGHT.check("LMA", &take(602, 1.0), &limits).unwrap_err().to_string();
        assert_eq!(
            err,
            "the take is 10 min 1 s long (602 frames at 1 Hz); LMA segments at most 10 min 0 s at a time: \
             cut the take"
        );
        assert_eq!(LIGHT.check("LMA", &take(601, 1.0), &limits), Ok(()));
        // 2 joints (root and End Site): 1024 B per working frame, 64 MiB hold 65,536 frames = 36 min 24 s at 30 Hz
        let heavy = Work { bytes_per_frame: 1000, advice: "or lower max_neighbours", ..LIGHT };
        let limits = WorkLimits { max_seconds: 3600.0, ..limits };
        let m = take(2400, 1.0);
        assert_eq!(heavy.bytes(heavy.frames(&m), 2), 71_971 * 1024);
        let err = heavy.check("PCA", &m, &limits).unwrap_err().to_string();
        assert_eq!(
            err,
            "the take is 39 min 59 s long, 71971 frames at PCA's 30 Hz, which need about 71 MiB, more than \
             the budget of 64 MiB: cut the take to at most 36 min 24 s or lower max_neighbours"
        );
    }
}
