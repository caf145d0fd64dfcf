//! Playback at the file's real frame rate: a [`Clock`] (in `crate::view`) turns animation-frame timestamps into
//! whole frames to advance (keeping the fraction left over, so 120 fps on a 60 Hz screen
//! advances exactly 2 frames per tick and 23.976 fps never drifts), and [`drive`] runs it with
//! `requestAnimationFrame` while `state.playing` is on.

use super::AppState;
use crate::view::clock::Clock;
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
