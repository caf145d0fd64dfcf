//! Playback at the file's real frame rate: a [`Clock`] turns animation-frame timestamps into
//! whole frames to advance (keeping the fraction left over, so 120 fps on a 60 Hz screen
//! advances exactly 2 frames per tick and 23.976 fps never drifts), and [`drive`] runs it with
//! `requestAnimationFrame` while `state.playing` is on.

use super::AppState;
use gloo::render::{request_animation_frame, AnimationFrame};
use leptos::prelude::*;
use std::cell::RefCell;
use std::rc::Rc;

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

/// Plays `state.motion` while `state.playing` is set.
pub fn drive(state: AppState) {
    let pending: Rc<RefCell<Option<AnimationFrame>>> = Rc::default();
    Effect::new(move |_| {
        if state.playing.get() {
            schedule(state, pending.clone(), Clock::default());
        } else {
            pending.borrow_mut().take(); // dropping the handle cancels the request
        }
    });
}

fn schedule(state: AppState, pending: Rc<RefCell<Option<AnimationFrame>>>, mut clock: Clock) {
    let next = pending.clone();
    let request = request_animation_frame(move |now_ms| {
        if !state.playing.get_untracked() {
            return;
        }
        let (frames, fps) =
            state.motion.with_untracked(|m| m.as_ref().map_or((0, 0.0), |m| (m.summary.frames, m.summary.fps)));
        let frame = clock.tick(now_ms, state.frame.get_untracked(), frames, fps, state.speed.get_untracked());
        let shown = state.frame.get_untracked();
        if let Some(end) = state.play_until.get_untracked() {
            // playing one segment: stop on its last frame (also if playback wrapped around)
            if frame >= end || frame < shown {
                state.frame.set(end.min(frames.saturating_sub(1)));
                state.play_until.set(None);
                state.playing.set(false);
                return;
            }
        }
        if frame != shown {
            state.frame.set(frame);
        }
        schedule(state, next, clock);
    });
    *pending.borrow_mut() = Some(request);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
    #[cfg_attr(not(target_arch = "wasm32"), test)]
    fn first_tick_only_starts_the_clock() {
        let mut clock = Clock::default();
        assert_eq!(clock.tick(1000.0, 5, 100, 120.0, 1.0), 5);
    }

    #[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
    #[cfg_attr(not(target_arch = "wasm32"), test)]
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

    #[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
    #[cfg_attr(not(target_arch = "wasm32"), test)]
    fn wraps_and_survives_long_pauses() {
        let mut clock = Clock::default();
        clock.tick(0.0, 0, 10, 100.0, 1.0);
        assert_eq!(clock.tick(50.0, 8, 10, 100.0, 1.0), 3); // 8 + 5, wrapped
        assert_eq!(clock.tick(60_050.0, 3, 10, 100.0, 1.0), (3 + 25) % 10); // capped at 0.25 s
    }
}
