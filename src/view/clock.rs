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
        let elapsed_s = self.last_ms.map_or(0.0, |last| ((now_ms - last) / 1000.0).clamp(0.0, MAX_STEP_S));
        self.last_ms = Some(now_ms);
        if frames == 0 || fps.is_nan() || fps <= 0.0 || speed.is_nan() || speed <= 0.0 {
            return 0;
        }
        let advance = elapsed_s * fps * speed + self.carry;
        let whole = advance.floor();
        self.carry = advance - whole;
        (frame + whole as usize) % frames
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
}
