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
//!   [`WorkLimits::max_bytes`] is refused, with the longest duration that would fit;
//! * a take whose run would do more than [`WorkLimits::max_ops`] multiply-adds is refused the same way (issue 49:
//!   a model file from anyone sets a labeller's work — its window, its training frames, its classes, its network and
//!   its decoding — and a run the worker would spend many minutes on, without a way to stop it short of killing
//!   the worker, is refused before it starts, naming the model's share of it).

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
    /// Multiply-adds per working frame, at most, where a model file sets them (a labeller: its window's projection,
    /// its training frames' scan, its network, its decoding; [`crate::labeller::method::model_work`]). 0 for a method
    /// whose time its parameters' checked ranges bound (the unsupervised methods: their time on a 10-minute take is
    /// in docs/benchmarks.md).
    pub ops_per_frame: f64,
    /// Multiply-adds besides, whatever the take's length (a k-NN's familiar distances).
    pub fixed_ops: f64,
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
    /// The most multiply-adds a run may do ([`MAX_OPS`]).
    pub max_ops: f64,
}

/// The most multiply-adds a run may do: 2·10¹¹, so that a run a model file asks for ends within a minute or so or is
/// refused. Measured: a ±300-frame k-NN window's projection ran 6.3·10⁹ declared multiply-adds a second natively
/// (`tests/limits.rs`, the test profile), the decoder with a 30 s minimum run ~6·10⁹ (release CLI, 60 k frames at
/// 120 Hz); the k-NN runs 1.2–1.65× slower in wasm, DT-FCN's products at 10·10⁹ a second (docs/benchmarks.md) — so
/// 30–60 s of the page's worker. The shipped models declare 0.14–0.6·10⁶ a frame: a 2-hour take is within it.
pub const MAX_OPS: f64 = 2e11;

/// Multiply-adds as a message shows them (`3.1·10¹¹`).
pub fn ops(x: f64) -> String {
    if !(x >= 1e3) {
        return format!("{}", x.max(0.0).round());
    }
    let e = x.log10().floor();
    let digits: String = (e as i64)
        .to_string()
        .chars()
        .map(|c| match c {
            '-' => '⁻',
            d => ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'][d.to_digit(10).unwrap_or(0) as usize],
        })
        .collect();
    format!("{:.1}·10{digits}", x / 10f64.powf(e))
}

impl Default for WorkLimits {
    /// 1 Hz, two hours, the loader's 1 GiB, [`MAX_OPS`].
    fn default() -> Self {
        WorkLimits {
            min_file_fps: 1.0,
            max_seconds: 2.0 * 3600.0,
            max_bytes: crate::load::MemoryBudget::default().max_bytes,
            max_ops: MAX_OPS,
        }
    }
}

/// Bytes of one resampled position (`f32` × 3).
const POSITION_BYTES: usize = 12;

impl Work {
    /// Nothing held and nothing done, at `fps`: what counts a take's working frames at that rate.
    pub fn at(fps: f64) -> Work {
        Work::memory(fps, 0, 0, "")
    }

    /// What a method whose time its parameters' checked ranges bound declares: its rate, its bytes and its advice
    /// (no multiply-adds: [`Work::ops_per_frame`]).
    pub const fn memory(fps: f64, bytes_per_frame: usize, fixed_bytes: usize, advice: &'static str) -> Work {
        Work { fps, bytes_per_frame, fixed_bytes, advice, ops_per_frame: 0.0, fixed_ops: 0.0 }
    }

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

    /// Multiply-adds of a run over `frames` working frames.
    pub fn ops(&self, frames: usize) -> f64 {
        frames as f64 * self.ops_per_frame + self.fixed_ops
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
            // a second's working frames, without the fixed bytes (counted once, below: with them the 2-hour take DT-FCN
            // refused was told to cut itself to 34 s, not 1 h 47 min)
            let per_second = (self.bytes(self.fps.ceil() as usize, motion.joints()) - self.fixed_bytes).max(1);
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
        let needed = self.ops(frames);
        if needed > limits.max_ops {
            let fits =
                (limits.max_ops - self.fixed_ops).max(0.0) / (self.ops_per_frame * self.fps).max(f64::MIN_POSITIVE);
            return Err(MethodError::Failed(format!(
                "the take is {} long, {frames} frames at {method}'s {} Hz; with this model and decoding that is about \
                 {} multiply-adds ({} a frame), more than the budget of {} (minutes of the page's worker): cut the \
                 take to at most {}, or choose a model with a narrower window, fewer training frames or classes, a \
                 smaller network, or a shorter minimum run",
                duration(seconds),
                round(self.fps),
                ops(needed),
                ops(self.ops_per_frame),
                ops(limits.max_ops),
                duration(fits.floor()),
            )));
        }
        Ok(())
    }
}

/// What a training holds as it reads its takes (issue 49, "one budget gate that every door passes"): every take's file
/// and motion at once (a training learns from all of them together), and its method's arrays per working frame of
/// them all ([`Work`], declared by [`crate::method::supervised::Supervised::training_work`]). Each take is added as it
/// is read, and refused — before the next is read and before the method builds its arrays — once the total passes
/// the budget.
#[derive(Debug, Clone)]
pub struct TrainingHold {
    work: Work,
    limits: WorkLimits,
    method: String,
    /// Bytes held so far (the method's fixed bytes included), the takes and their seconds.
    bytes: usize,
    takes: usize,
    seconds: f64,
}

impl TrainingHold {
    /// Nothing held yet by a training of `method` (its short name) declaring `work`, checked against `limits`.
    pub fn new(method: &str, work: Work, limits: WorkLimits) -> TrainingHold {
        TrainingHold { work, limits, method: method.to_string(), bytes: work.fixed_bytes, takes: 0, seconds: 0.0 }
    }

    /// Adds take `motion`, read from a file of `file_bytes`: refused, naming the take, when its file rate or length
    /// would refuse a run ([`Work::check`]), or when the takes so far with it pass the budget (the message says how
    /// much motion fits).
    pub fn add(&mut self, motion: &Motion, file_bytes: usize) -> Result<(), MethodError> {
        if self.work.fixed_bytes > self.limits.max_bytes {
            return Err(MethodError::params(format!(
                "{} training with these options needs about {} MiB before any take, more than the budget of {} MiB{}",
                self.method,
                self.work.fixed_bytes.div_ceil(1 << 20),
                self.limits.max_bytes / (1 << 20),
                if self.work.advice.is_empty() { String::new() } else { format!(": {}", self.work.advice) },
            )));
        }
        let unbounded = WorkLimits { max_bytes: usize::MAX, ..self.limits };
        self.work
            .check(&self.method, motion, &unbounded)
            .map_err(|e| MethodError::param("takes", format!("{}: {e}", motion.name)))?;
        let load = crate::load::MemoryBudget::estimate(motion.frames(), motion.joints());
        let arrays = self.work.bytes(self.work.frames(motion), motion.joints()).saturating_sub(self.work.fixed_bytes);
        let bytes = self.bytes.saturating_add(file_bytes).saturating_add(load).saturating_add(arrays);
        let seconds = self.seconds + motion.frames().saturating_sub(1) as f64 / motion.fps;
        if bytes > self.limits.max_bytes {
            let per_second = (bytes - self.work.fixed_bytes) as f64 / seconds.max(f64::MIN_POSITIVE);
            let fits = self.limits.max_bytes.saturating_sub(self.work.fixed_bytes) as f64 / per_second;
            return Err(MethodError::param(
                "takes",
                format!(
                    "{} training on {} ({} of motion with {}) needs about {} MiB, more than the budget of {} MiB: \
                     train on at most {} of motion in all (fewer or shorter takes)",
                    self.method,
                    crate::method::counted(self.takes + 1, "take"),
                    duration(seconds),
                    motion.name,
                    bytes.div_ceil(1 << 20),
                    self.limits.max_bytes / (1 << 20),
                    duration(fits.floor()),
                ),
            ));
        }
        (self.bytes, self.takes, self.seconds) = (bytes, self.takes + 1, seconds);
        Ok(())
    }

    /// Bytes held so far, as declared.
    pub fn bytes(&self) -> usize {
        self.bytes
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

    /// A training's takes are added as they are read: within the budget they are held, the take that passes it is
    /// refused naming the takes, their motion, what they need and how much motion fits; options whose fixed part
    /// alone passes the budget are refused before any take, with the work's advice.
    #[test]
    fn a_training_holds_its_takes_until_they_pass_the_budget() {
        let take = |name: &str, frames: usize| {
            let mut m = take(frames, 1.0 / 120.0);
            m.name = name.into();
            m
        };
        let work = Work::memory(30.0, 10_000, 1 << 20, "smaller");
        let limits = WorkLimits { max_bytes: 64 << 20, ..Default::default() };
        let mut hold = TrainingHold::new("k-NN", work, limits);
        // 1 minute at 120 Hz: 1801 working frames of 10 kB and its file and motion
        hold.add(&take("a.bvh", 7200), 3_000_000).unwrap();
        let after_one = hold.bytes();
        assert!(after_one > (1 << 20) + 1801 * 10_000, "{after_one}");
        let e = (0..10).find_map(|i| hold.add(&take(&format!("t{i}.bvh"), 7200), 3_000_000).err()).unwrap();
        assert_eq!(e.param_name(), Some("takes"));
        let text = e.to_string();
        assert!(text.starts_with("k-NN training on "), "{text}");
        assert!(text.contains("more than the budget of 64 MiB: train on at most"), "{text}");
        assert!(hold.bytes() <= 64 << 20, "what is held stays within the budget");
        // a working rate the run would refuse is refused for training, naming the take
        let mut slow = super::tests::take(10, 100.0);
        slow.name = "slow.bvh".into();
        let e = TrainingHold::new("k-NN", work, limits).add(&slow, 10).unwrap_err().to_string();
        assert!(e.starts_with("slow.bvh: Frame Time 100 s"), "{e}");
        // options that cannot fit whatever the takes
        let big = Work { fixed_bytes: 65 << 20, ..work };
        let e = TrainingHold::new("DT-FCN", big, limits).add(&take("a.bvh", 10), 10).unwrap_err().to_string();
        assert!(e.contains("needs about 65 MiB before any take, more than the budget of 64 MiB: smaller"), "{e}");
    }

    fn take(frames: usize, frame_time: f64) -> Motion {
        let text = format!(
            "HIERARCHY\nROOT Hips\n{{\nOFFSET 0 0 0\nCHANNELS 3 Xposition Yposition Zposition\nEnd Site\n{{\nOFFSET 0 1 0\n}}\n}}\n\
             MOTION\nFrames: {frames}\nFrame Time: {frame_time}\n{}",
            "0 0 0\n".repeat(frames)
        );
        crate::load::load_bytes("odd.bvh", text.as_bytes(), &mut |_| {}).unwrap().motion
    }

    const LIGHT: Work = Work::memory(30.0, 1000, 0, "");

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
        // fixed bytes are counted once, not once a second: half the budget fixed leaves half the duration
        let fixed = Work { fixed_bytes: 32 << 20, ..heavy };
        let err = fixed.check("PCA", &m, &limits).unwrap_err().to_string();
        assert!(err.ends_with("cut the take to at most 18 min 12 s or lower max_neighbours"), "{err}");
    }
}
