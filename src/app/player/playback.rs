//! Playback at the file's real frame rate: a [`Clock`] (in `crate::view`) turns animation-frame timestamps into
//! whole frames to advance (keeping the fraction left over, so 120 fps on a 60 Hz screen
//! advances exactly 2 frames per tick and 23.976 fps never drifts), and [`drive`] runs it with
//! `requestAnimationFrame` while `state.playing` is on: forwards, or backwards and faster with the
//! J/K/L shuttle (`state.shuttle`), wrapping around the take or looping the selected segment
//! (`state.looping`), or once to `state.play_until`.

use crate::app::player::clock::Clock;
use crate::app::state::{AppState, Selection};
use crate::app::timeline::window::advanced;
use gloo::render::{request_animation_frame, AnimationFrame};
use leptos::prelude::*;
use std::cell::RefCell;
use std::rc::Rc;

/// Plays `state.motion` while `state.playing` is set.
pub fn drive(state: AppState) {
    let pending: Rc<RefCell<Option<AnimationFrame>>> = Rc::default();
    Effect::new(move |_| {
        if state.playing.get() {
            schedule(state, pending.clone(), Clock::default());
        } else {
            pending.borrow_mut().take(); // dropping the handle cancels the request
            state.shuttle.set(0);
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
        // J/K/L: the shuttle's rate multiplies the speed menu's, its sign is the direction
        let rate = state.shuttle.get_untracked();
        let speed = state.speed.get_untracked() * rate.unsigned_abs().max(1) as f64;
        let forward = rate >= 0;
        let steps = clock.steps(now_ms, fps, speed);
        let shown = state.frame.get_untracked();
        let looped = if state.looping.get_untracked() {
            state.selected.with_untracked(|s| s.as_ref().map(|s| (s.start, s.end)))
        } else {
            None
        };
        if let (None, Some(end)) = (looped, state.play_until.get_untracked()) {
            // playing one segment once: stop on its last frame (also if playback wrapped around)
            let frame = advanced(shown, steps, true, frames, None);
            if frame >= end || frame < shown {
                state.frame.set(end.min(frames.saturating_sub(1)));
                state.play_until.set(None);
                state.playing.set(false);
                return;
            }
        }
        let frame = advanced(shown, steps, forward, frames, looped);
        if frame != shown {
            state.frame.set(frame);
        }
        schedule(state, next, clock);
    });
    *pending.borrow_mut() = Some(request);
}

/// Selects segment `s` and plays it: looped while Loop is on, else once to its end (what a click
/// on a segment does).
pub fn play_segment(state: AppState, s: Selection) {
    let (start, end) = (s.start, s.end);
    state.selected.set(Some(s));
    state.play_until.set((!state.looping.get_untracked()).then_some(end));
    state.shuttle.set(0);
    state.frame.set(start);
    state.playing.set(true);
}
