//! The timeline's maths, kept out of the web layer so it is tested natively: the visible window
//! of frames (zoom around a point, pan, follow the playhead), the time ruler's ticks, the time
//! readout, segment navigation, the rows' virtualisation and the keyboard's shortcuts.
//!
//! Frames are 0-based; a window `[start, end)` is in frames and may be fractional (zooming keeps
//! the point under the pointer fixed), always inside `[0, frames]` and at least [`MIN_SPAN`]
//! frames wide (or the whole take when it is shorter).

/// The narrowest window: this many frames across the timeline.
pub const MIN_SPAN: f64 = 20.0;

/// The frames shown across the timeline, `[start, end)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Window {
    pub start: f64,
    pub end: f64,
}

impl Window {
    /// The whole take of `frames` frames.
    pub fn full(frames: usize) -> Window {
        Window { start: 0.0, end: frames.max(1) as f64 }
    }

    pub fn span(&self) -> f64 {
        self.end - self.start
    }

    /// Whether this window shows the whole take.
    pub fn is_full(&self, frames: usize) -> bool {
        self.start <= 0.0 && self.end >= frames.max(1) as f64
    }

    /// The window of `span` frames starting at `start`, moved (not shrunk) to lie inside the
    /// take, and clamped to `[min(MIN_SPAN, frames), frames]` in width.
    pub fn clamped(start: f64, span: f64, frames: usize) -> Window {
        let total = frames.max(1) as f64;
        let span = if span.is_finite() { span.clamp(MIN_SPAN.min(total), total) } else { total };
        let start = if start.is_finite() { start.clamp(0.0, total - span) } else { 0.0 };
        Window { start, end: start + span }
    }

    /// Zoomed by `factor` (> 1 zooms in: the span divides by it) keeping frame position `anchor`
    /// where it is on screen.
    pub fn zoomed(&self, factor: f64, anchor: f64, frames: usize) -> Window {
        if !(factor.is_finite() && factor > 0.0) {
            return *self;
        }
        let span = (self.span() / factor).clamp(MIN_SPAN.min(frames.max(1) as f64), frames.max(1) as f64);
        let anchor = anchor.clamp(self.start, self.end);
        let at = if self.span() > 0.0 { (anchor - self.start) / self.span() } else { 0.5 };
        Window::clamped(anchor - at * span, span, frames)
    }

    /// Moved by `delta` frames (positive: later), kept inside the take.
    pub fn panned(&self, delta: f64, frames: usize) -> Window {
        Window::clamped(self.start + delta, self.span(), frames)
    }

    /// Centred on `frame` (as far as the take allows).
    pub fn centred_on(&self, frame: f64, frames: usize) -> Window {
        Window::clamped(frame - self.span() / 2.0, self.span(), frames)
    }

    /// Whether frame `frame` (its whole column) is on screen.
    pub fn shows(&self, frame: usize) -> bool {
        frame as f64 >= self.start && (frame + 1) as f64 <= self.end
    }

    /// The window scrolled just enough to show frames `first..=last` (as much of them as fits,
    /// their start first); unchanged when they are already on screen.
    pub fn showing(&self, first: usize, last: usize, frames: usize) -> Window {
        let (a, b) = (first as f64, (last + 1) as f64);
        if a >= self.start && b <= self.end {
            return *self;
        }
        if b - a >= self.span() || a < self.start {
            // too long, or before the window: its start at a tenth of the window
            return Window::clamped(a - self.span() * 0.1, self.span(), frames);
        }
        // after the window: its end at nine tenths
        Window::clamped(b - self.span() * 0.9, self.span(), frames)
    }

    /// The window that follows the playhead: unchanged while `frame` is on screen, else moved
    /// (not resized) to show it a tenth of the way in — playback pages through the take.
    pub fn paged_to(&self, frame: usize, frames: usize) -> Window {
        if self.shows(frame) {
            return *self;
        }
        Window::clamped(frame as f64 - self.span() * 0.1, self.span(), frames)
    }

    /// Where frame position `frame` falls across the window, 0 at its start and 1 at its end.
    pub fn fraction(&self, frame: f64) -> f64 {
        (frame - self.start) / self.span().max(f64::MIN_POSITIVE)
    }

    /// The frame at `fraction` across the window, as a whole frame inside the take.
    pub fn frame_at(&self, fraction: f64, frames: usize) -> usize {
        let x = self.start + fraction * self.span();
        (x.floor().max(0.0) as usize).min(frames.saturating_sub(1))
    }
}

/// One labelled mark of the time ruler.
#[derive(Debug, Clone, PartialEq)]
pub struct Tick {
    /// Frame position of the mark (fractional when the tick's time falls between frames).
    pub frame: f64,
    pub seconds: f64,
    pub label: String,
}

/// Tick steps the ruler chooses from, in seconds.
const STEPS_S: [f64; 20] = [
    0.001, 0.002, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0, 15.0, 30.0, 60.0, 120.0, 300.0, 600.0,
    1800.0,
];

/// The ruler's step: the smallest of [`STEPS_S`] at least `min_px` pixels apart when the window
/// spans `width_px` pixels.
pub fn tick_step(window: &Window, fps: f64, width_px: f64, min_px: f64) -> f64 {
    if !(fps > 0.0 && width_px > 0.0) {
        return 1.0;
    }
    let seconds_per_px = window.span() / fps / width_px;
    STEPS_S.iter().copied().find(|s| s / seconds_per_px >= min_px).unwrap_or(3600.0)
}

/// The ruler's ticks for `window`: every multiple of the chosen step inside it, labelled in
/// seconds with as many decimals as the step needs (`1:05` past a minute).
pub fn ticks(window: &Window, fps: f64, width_px: f64, min_px: f64) -> Vec<Tick> {
    if !(fps > 0.0) {
        return Vec::new();
    }
    let step = tick_step(window, fps, width_px, min_px);
    let decimals = if step >= 1.0 {
        0
    } else if step >= 0.1 {
        1
    } else if step >= 0.01 {
        2
    } else {
        3
    };
    let (t0, t1) = (window.start / fps, window.end / fps);
    let first = (t0 / step - 1e-9).ceil() as i64;
    let last = (t1 / step + 1e-9).floor() as i64;
    (first.max(0)..=last)
        .take(1000)
        .map(|k| {
            let seconds = k as f64 * step;
            Tick { frame: seconds * fps, seconds, label: tick_label(seconds, decimals) }
        })
        .collect()
}

fn tick_label(seconds: f64, decimals: usize) -> String {
    if seconds >= 60.0 {
        let minutes = (seconds / 60.0 + 1e-9).floor();
        let rest = seconds - minutes * 60.0;
        let width = if decimals > 0 { decimals + 3 } else { 2 };
        format!("{minutes}:{:0width$.decimals$}", rest.max(0.0), width = width, decimals = decimals)
    } else {
        format!("{seconds:.decimals$} s")
    }
}

/// `mm:ss.fff` (minutes past 99 keep growing) of `seconds` ≥ 0, rounded to the millisecond.
pub fn clock_time(seconds: f64) -> String {
    let ms = if seconds.is_finite() { (seconds.max(0.0) * 1000.0).round() as u64 } else { 0 };
    format!("{:02}:{:02}.{:03}", ms / 60_000, ms / 1000 % 60, ms % 1000)
}

/// The timeline's readout: `mm:ss.fff · frame N / total`, the time of 0-based `frame` and its
/// 1-based number as the frame counter shows it.
pub fn readout(frame: usize, frames: usize, fps: f64) -> String {
    if frames == 0 {
        return "00:00.000 · frame 0 / 0".to_string();
    }
    let seconds = if fps > 0.0 { frame as f64 / fps } else { 0.0 };
    format!("{} · frame {} / {}", clock_time(seconds), frame + 1, frames)
}

/// The segment after `frame` in a row (`spans` sorted by start, inclusive `(start, end)`): the
/// first starting after it.
pub fn next_segment(spans: &[(usize, usize)], frame: usize) -> Option<usize> {
    let i = spans.partition_point(|s| s.0 <= frame);
    (i < spans.len()).then_some(i)
}

/// The segment before `frame` in a row: the last starting before it.
pub fn previous_segment(spans: &[(usize, usize)], frame: usize) -> Option<usize> {
    spans.partition_point(|s| s.0 < frame).checked_sub(1)
}

/// The first boundary of a row after the playhead at `frame`: a segment's start or the frame after
/// its end (a row with gaps has both), before `frames`. What `]` goes to, whatever is selected.
pub fn next_boundary(spans: &[(usize, usize)], frame: usize, frames: usize) -> Option<usize> {
    boundaries(spans).filter(|&b| b > frame && b < frames).min()
}

/// The last boundary of a row before the playhead at `frame` (see [`next_boundary`]): what `[`
/// goes to.
pub fn previous_boundary(spans: &[(usize, usize)], frame: usize, frames: usize) -> Option<usize> {
    boundaries(spans).filter(|&b| b < frame && b < frames).max()
}

/// Every start and end + 1 of a row's segments (unordered, with repeats).
fn boundaries(spans: &[(usize, usize)]) -> impl Iterator<Item = usize> + '_ {
    spans.iter().flat_map(|&(start, end)| [start, end + 1])
}

/// The segments of a row (`spans` sorted by start, not overlapping) to put on screen for
/// `window` across `width_px` pixels: those overlapping it, and when more than `max` of them do,
/// only one per `span / max`-frame bucket (the first starting in it) besides those wider than a
/// bucket — so a row never holds more than about `2 max + 2` elements however long the take.
pub fn visible_segments(spans: &[(usize, usize)], window: &Window, max: usize) -> Vec<usize> {
    let first = spans.partition_point(|s| ((s.1 + 1) as f64) <= window.start);
    let last = spans.partition_point(|s| (s.0 as f64) < window.end);
    if last <= first {
        return Vec::new();
    }
    if last - first <= max.max(1) {
        return (first..last).collect();
    }
    let bucket = window.span() / max.max(1) as f64;
    let mut shown = Vec::new();
    let mut last_bucket = None;
    for i in first..last {
        let (s, e) = spans[i];
        let b = ((s as f64 - window.start) / bucket).floor() as i64;
        if Some(b) != last_bucket || (e + 1 - s) as f64 >= bucket {
            shown.push(i);
            last_bucket = Some(b);
        }
    }
    shown
}

/// What a key press does on the page.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum KeyAction {
    PlayPause,
    /// Move by this many frames (and pause).
    StepFrames(i64),
    /// Move by this many seconds (and pause).
    StepSeconds(i64),
    /// J: play backwards, faster each press.
    ShuttleBack,
    /// K: pause.
    ShuttleStop,
    /// L: play forwards, faster each press.
    ShuttleForward,
    First,
    Last,
    ZoomIn,
    ZoomOut,
    PreviousSegment,
    NextSegment,
    ToggleHelp,
    /// Esc: closes the help if it is open, else drops the selected segment.
    Escape,
}

/// Modifier keys held with a key.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Modifiers {
    pub shift: bool,
    pub ctrl: bool,
    pub alt: bool,
    pub meta: bool,
}

/// The page's action for `key` (`KeyboardEvent.key`) with `modifiers`; `None` for everything the
/// page leaves to the browser — any key with Ctrl, Alt or ⌘ (Alt+←, Ctrl+L, Ctrl++ …) among them.
pub fn key_action(key: &str, m: Modifiers) -> Option<KeyAction> {
    if m.ctrl || m.alt || m.meta {
        return None;
    }
    use KeyAction::*;
    Some(match key {
        " " | "Spacebar" => PlayPause,
        "ArrowLeft" if m.shift => StepSeconds(-1),
        "ArrowRight" if m.shift => StepSeconds(1),
        "ArrowLeft" => StepFrames(-1),
        "ArrowRight" => StepFrames(1),
        "j" | "J" => ShuttleBack,
        "k" | "K" => ShuttleStop,
        "l" | "L" => ShuttleForward,
        "Home" => First,
        "End" => Last,
        "+" | "=" => ZoomIn,
        "-" | "_" => ZoomOut,
        "[" => PreviousSegment,
        "]" => NextSegment,
        "?" => ToggleHelp,
        "Escape" => Escape,
        _ => return None,
    })
}

/// The fastest J/K/L shuttle rate (× the speed menu's).
pub const MAX_SHUTTLE: i32 = 8;

/// The shuttle rate after J (`forward = false`) or L at rate `rate` (0 = stopped or ordinary
/// playback; negative = backwards): the same direction again doubles it up to [`MAX_SHUTTLE`],
/// the other direction starts at 1× that way.
pub fn shuttle(rate: i32, forward: bool) -> i32 {
    let sign = if forward { 1 } else { -1 };
    if rate != 0 && rate.signum() == sign {
        (rate * 2).clamp(-MAX_SHUTTLE, MAX_SHUTTLE)
    } else {
        sign
    }
}

/// The frame after stepping `delta` frames from `frame`, inside `0..frames`.
pub fn stepped(frame: usize, delta: i64, frames: usize) -> usize {
    if frames == 0 {
        return 0;
    }
    (frame as i64 + delta).clamp(0, frames as i64 - 1) as usize
}

/// The frame playback shows after advancing `steps` frames from `frame` in direction `forward`,
/// wrapping around the take, or inside `looped = (first, last)` when it loops a segment: leaving
/// it either way starts it again from its start (forwards) or its end (backwards).
pub fn advanced(frame: usize, steps: usize, forward: bool, frames: usize, looped: Option<(usize, usize)>) -> usize {
    if frames == 0 {
        return 0;
    }
    match looped {
        Some((first, last)) if first <= last && last < frames => {
            let len = last - first + 1;
            if frame < first || frame > last {
                return if forward { first } else { last };
            }
            let at = frame - first;
            let at = if forward { (at + steps) % len } else { (at + len - steps % len) % len };
            first + at
        }
        _ => {
            if forward {
                (frame + steps) % frames
            } else {
                (frame + frames - steps % frames) % frames
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zoom_keeps_the_anchor_in_place_and_stays_inside_the_take() {
        let w = Window::full(1000);
        let z = w.zoomed(4.0, 500.0, 1000);
        assert_eq!(z, Window { start: 375.0, end: 625.0 });
        assert!((z.fraction(500.0) - w.fraction(500.0)).abs() < 1e-12);
        // near the start: the anchor stays at its fraction, the window stays inside
        let z = w.zoomed(2.0, 100.0, 1000);
        assert!((z.fraction(100.0) - 0.1).abs() < 1e-12 && z.start == 50.0);
        // zooming out past the take is the whole take; in past MIN_SPAN stops there
        assert_eq!(z.zoomed(0.01, 100.0, 1000), Window::full(1000));
        assert_eq!(w.zoomed(1e6, 999.0, 1000).span(), MIN_SPAN);
        assert!(w.zoomed(1e6, 999.0, 1000).end <= 1000.0);
        // a take shorter than MIN_SPAN is always shown whole
        assert_eq!(Window::full(5).zoomed(8.0, 2.0, 5), Window::full(5));
        assert_eq!(w.zoomed(f64::NAN, 3.0, 1000), w);
    }

    #[test]
    fn pan_and_follow_stay_inside_the_take() {
        let w = Window { start: 100.0, end: 200.0 };
        assert_eq!(w.panned(50.0, 1000), Window { start: 150.0, end: 250.0 });
        assert_eq!(w.panned(-500.0, 1000), Window { start: 0.0, end: 100.0 });
        assert_eq!(w.panned(5000.0, 1000), Window { start: 900.0, end: 1000.0 });
        assert!(w.shows(100) && w.shows(199) && !w.shows(200) && !w.shows(99));
        assert_eq!(w.showing(120, 130, 1000), w, "already on screen");
        assert_eq!(w.showing(250, 260, 1000), Window { start: 171.0, end: 271.0 });
        assert_eq!(w.showing(10, 20, 1000), Window { start: 0.0, end: 100.0 });
        assert_eq!(w.showing(500, 900, 1000), Window { start: 490.0, end: 590.0 }, "a long one: its start");
        assert_eq!(w.centred_on(990.0, 1000), Window { start: 900.0, end: 1000.0 });
        assert_eq!(w.paged_to(150, 1000), w);
        assert_eq!(w.paged_to(200, 1000), Window { start: 190.0, end: 290.0 });
        assert_eq!(w.paged_to(5, 1000), Window { start: 0.0, end: 100.0 });
        assert_eq!(w.frame_at(0.0, 1000), 100);
        assert_eq!(w.frame_at(0.999, 1000), 199);
        assert_eq!(Window::full(1000).frame_at(1.0, 1000), 999);
    }

    #[test]
    fn ruler_ticks_are_round_seconds_spaced_for_the_zoom() {
        // 47 940 frames at 120 fps (400 s) over 1000 px, ticks ≥ 60 px apart: every 30 s
        let whole = Window::full(47_940);
        assert_eq!(tick_step(&whole, 120.0, 1000.0, 60.0), 30.0);
        let t = ticks(&whole, 120.0, 1000.0, 60.0);
        assert_eq!(t.first().map(|t| t.label.as_str()), Some("0 s"));
        assert_eq!(t[2].label, "1:00");
        assert_eq!(t[3].label, "1:30");
        assert_eq!(t[3].frame, 90.0 * 120.0);
        assert_eq!(t.len(), 14, "0, 30, …, 390 s");
        // zoomed to 1 s: tenths
        let near = Window { start: 1200.0, end: 1320.0 };
        assert_eq!(tick_step(&near, 120.0, 1000.0, 60.0), 0.1);
        let t = ticks(&near, 120.0, 1000.0, 60.0);
        assert_eq!(t.first().map(|t| t.label.as_str()), Some("10.0 s"));
        assert_eq!(t.last().map(|t| t.label.as_str()), Some("11.0 s"));
        assert!(t.windows(2).all(|p| (p[1].frame - p[0].frame - 12.0).abs() < 1e-9));
        // the narrowest window at 120 fps: 20 frames
        let t = ticks(&Window { start: 0.0, end: 20.0 }, 120.0, 900.0, 60.0); // 0.01 s = 54 px
        assert_eq!(t[1].label, "0.02 s");
        assert!(ticks(&whole, 0.0, 1000.0, 60.0).is_empty());
        // minutes with decimals
        assert_eq!(tick_label(61.5, 1), "1:01.5");
    }

    #[test]
    fn readout_is_minutes_seconds_milliseconds_and_the_frame() {
        assert_eq!(clock_time(0.0), "00:00.000");
        assert_eq!(clock_time(65.4321), "01:05.432");
        assert_eq!(clock_time(3600.0), "60:00.000");
        assert_eq!(readout(0, 343, 120.0), "00:00.000 · frame 1 / 343");
        assert_eq!(readout(120, 47_940, 120.0), "00:01.000 · frame 121 / 47940");
        assert_eq!(readout(0, 0, 120.0), "00:00.000 · frame 0 / 0");
    }

    #[test]
    fn segment_navigation_finds_the_neighbours_of_the_playhead() {
        let row = [(0, 9), (10, 29), (30, 49), (60, 99)];
        assert_eq!(next_segment(&row, 0), Some(1));
        assert_eq!(next_segment(&row, 10), Some(2));
        assert_eq!(next_segment(&row, 55), Some(3));
        assert_eq!(next_segment(&row, 60), None);
        assert_eq!(previous_segment(&row, 30), Some(1));
        assert_eq!(previous_segment(&row, 31), Some(2));
        assert_eq!(previous_segment(&row, 0), None);
        assert_eq!(next_segment(&[], 3), None);
    }

    #[test]
    fn boundary_navigation_starts_from_the_playhead() {
        // a row with a gap (50..=59): its end + 1 is a boundary too
        let row = [(0, 9), (10, 29), (30, 49), (60, 99)];
        // the playhead inside a segment: the next boundary is that segment's end, not the segment
        // after a selected one
        assert_eq!(next_boundary(&row, 15, 100), Some(30));
        assert_eq!(next_boundary(&row, 30, 100), Some(50));
        assert_eq!(next_boundary(&row, 50, 100), Some(60));
        assert_eq!(next_boundary(&row, 0, 100), Some(10));
        // the row's end is the take's end: nowhere further to go
        assert_eq!(next_boundary(&row, 60, 100), None);
        assert_eq!(next_boundary(&row, 99, 100), None);
        // a row ending before the take does: the frame after its end
        assert_eq!(next_boundary(&row[..3], 40, 100), Some(50));
        assert_eq!(previous_boundary(&row, 15, 100), Some(10));
        assert_eq!(previous_boundary(&row, 10, 100), Some(0));
        assert_eq!(previous_boundary(&row, 55, 100), Some(50));
        assert_eq!(previous_boundary(&row, 99, 100), Some(60));
        assert_eq!(previous_boundary(&row, 0, 100), None);
        assert_eq!(next_boundary(&[], 3, 100), None);
        assert_eq!(previous_boundary(&[], 3, 100), None);
    }

    #[test]
    fn rows_put_only_what_is_visible_on_screen() {
        let row: Vec<(usize, usize)> = (0..100_000).map(|i| (i, i)).collect();
        let w = Window { start: 100.0, end: 150.0 };
        assert_eq!(visible_segments(&row, &w, 400), (100..150).collect::<Vec<_>>());
        let whole = Window::full(100_000);
        let shown = visible_segments(&row, &whole, 400);
        assert!(shown.len() <= 400 && shown.len() >= 399, "{} one-frame segments", shown.len());
        // a wide segment among slivers is always kept
        let mut mixed: Vec<(usize, usize)> = (0..1000).map(|i| (i, i)).collect();
        mixed.push((1000, 49_999));
        mixed.extend((50_000..100_000).map(|i| (i, i)));
        assert!(visible_segments(&mixed, &whole, 100).contains(&1000));
        assert!(visible_segments(&row, &Window { start: 200_000.0, end: 300_000.0 }, 10).is_empty());
        // a segment reaching into the window from before it is shown
        assert_eq!(visible_segments(&[(0, 120), (121, 200)], &w, 10), vec![0, 1]);
    }

    #[test]
    fn keys_map_to_actions_and_never_take_the_browsers_own() {
        let none = Modifiers::default();
        let shift = Modifiers { shift: true, ..none };
        assert_eq!(key_action(" ", none), Some(KeyAction::PlayPause));
        assert_eq!(key_action("ArrowRight", none), Some(KeyAction::StepFrames(1)));
        assert_eq!(key_action("ArrowLeft", shift), Some(KeyAction::StepSeconds(-1)));
        assert_eq!(key_action("J", shift), Some(KeyAction::ShuttleBack));
        assert_eq!(key_action("k", none), Some(KeyAction::ShuttleStop));
        assert_eq!(key_action("+", shift), Some(KeyAction::ZoomIn));
        assert_eq!(key_action("-", none), Some(KeyAction::ZoomOut));
        assert_eq!(key_action("]", none), Some(KeyAction::NextSegment));
        assert_eq!(key_action("?", shift), Some(KeyAction::ToggleHelp));
        assert_eq!(key_action("Escape", none), Some(KeyAction::Escape));
        for m in [Modifiers { alt: true, ..none }, Modifiers { ctrl: true, ..none }, Modifiers { meta: true, ..none }] {
            for key in ["ArrowLeft", "ArrowRight", "l", "+", "-", " ", "z"] {
                assert_eq!(key_action(key, m), None, "{key} with {m:?} is the browser's");
            }
        }
        assert_eq!(key_action("a", none), None);
    }

    #[test]
    fn shuttle_doubles_in_its_direction_and_turns_at_one() {
        assert_eq!(shuttle(0, true), 1);
        assert_eq!(shuttle(1, true), 2);
        assert_eq!(shuttle(4, true), 8);
        assert_eq!(shuttle(8, true), 8);
        assert_eq!(shuttle(4, false), -1);
        assert_eq!(shuttle(-2, false), -4);
        assert_eq!(shuttle(-8, false), -8);
    }

    #[test]
    fn stepping_and_playing_stay_inside_the_take_or_the_loop() {
        assert_eq!(stepped(5, -10, 100), 0);
        assert_eq!(stepped(95, 120, 100), 99);
        assert_eq!(stepped(3, 1, 0), 0);
        assert_eq!(advanced(98, 3, true, 100, None), 1);
        assert_eq!(advanced(1, 3, false, 100, None), 98);
        // looping frames 10..=19
        assert_eq!(advanced(18, 3, true, 100, Some((10, 19))), 11);
        assert_eq!(advanced(11, 3, false, 100, Some((10, 19))), 18);
        assert_eq!(advanced(50, 1, true, 100, Some((10, 19))), 10, "outside: from its start");
        assert_eq!(advanced(50, 1, false, 100, Some((10, 19))), 19, "backwards: from its end");
        assert_eq!(advanced(12, 0, true, 100, Some((10, 19))), 12);
        for steps in 0..50 {
            let f = advanced(15, steps, steps % 2 == 0, 100, Some((10, 19)));
            assert!((10..=19).contains(&f));
        }
    }
}
