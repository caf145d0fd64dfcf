//! Playback at the file's real frame rate: a [`Clock`] turns animation-frame timestamps into
//! whole frames to advance, keeping the fraction left over, so 120 fps on a 60 Hz screen
//! advances exactly 2 frames per tick and 23.976 fps never drifts. The page's player drives it
//! with `requestAnimationFrame`.

/// A pause longer than this (a hidden tab, a debugger) is not played through on return.
const MAX_STEP_S: f64 = 0.25;

/// Turns wall-clock time into frames.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Clock {
    last_ms: Option<f64>,
    /// Fraction of a frame carried over to the next tick.
    carry: f64,
}

impl Clock {
    /// The frame to show at `now_ms`, having shown `frame` of `frames` at the previous tick;
    /// playback wraps around at the end.
    pub fn tick(&mut self, now_ms: f64, frame: usize, frames: usize, fps: f64, speed: f64) -> usize {
        let steps = self.steps(now_ms, fps, speed);
        if frames == 0 {
            return 0;
        }
        (frame + steps) % frames
    }

    /// How many whole frames to move at `now_ms` (in either direction: the caller decides which).
    pub fn steps(&mut self, now_ms: f64, fps: f64, speed: f64) -> usize {
        let elapsed_s = self.last_ms.map_or(0.0, |last| ((now_ms - last) / 1000.0).clamp(0.0, MAX_STEP_S));
        self.last_ms = Some(now_ms);
        if fps.is_nan() || fps <= 0.0 || speed.is_nan() || speed <= 0.0 {
            return 0;
        }
        let advance = elapsed_s * fps * speed + self.carry;
        let whole = advance.floor();
        self.carry = advance - whole;
        whole as usize
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_tick_only_starts_the_clock() {
        let mut clock = Clock::default();
        assert_eq!(clock.tick(1000.0, 5, 100, 120.0, 1.0), 5);
    }

    #[test]
    fn plays_at_the_file_rate_and_speed() {
        let mut clock = Clock::default();
        let mut frame = clock.tick(0.0, 0, 10_000, 120.0, 1.0);
        for i in 1..=16 {
            frame = clock.tick(i as f64 * 62.5, frame, 10_000, 120.0, 1.0);
        }
        assert_eq!(frame, 120, "one second at 120 fps");
        let mut clock = Clock::default();
        let mut frame = clock.tick(0.0, 0, 10_000, 30.0, 0.5);
        for i in 1..=16 {
            frame = clock.tick(i as f64 * 62.5, frame, 10_000, 30.0, 0.5);
        }
        assert_eq!(frame, 15, "one second at half speed of 30 fps");
    }

    #[test]
    fn wraps_and_survives_long_pauses() {
        let mut clock = Clock::default();
        clock.tick(0.0, 0, 10, 100.0, 1.0);
        assert_eq!(clock.tick(50.0, 8, 10, 100.0, 1.0), 3); // 8 + 5, wrapped
        assert_eq!(clock.tick(60_050.0, 3, 10, 100.0, 1.0), (3 + 25) % 10); // capped at 0.25 s
    }

    #[test]
    fn steps_count_frames_at_eight_times_speed() {
        // J/K/L at 8×: 120 fps for 62.5 ms is 60 frames
        let mut clock = Clock::default();
        assert_eq!(clock.steps(0.0, 120.0, 8.0), 0);
        assert_eq!(clock.steps(62.5, 120.0, 8.0), 60);
        assert_eq!(clock.steps(100.0, 120.0, 0.0), 0);
    }
}
