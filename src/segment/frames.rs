//! Working frames ↔ file frames. The methods work at their own rate (SSSM and DT-FCN at 30 Hz);
//! their segments are reported at the file's own frame rate. Each working frame `k` sits at a
//! fractional file frame `source[k]` (from [`crate::motion::resample`]); a working span maps to
//! the file frames closer to its frames than to their neighbours', so consecutive working spans
//! map to consecutive, non-overlapping file spans that cover the whole file.

use crate::segment::Segment;

/// The file positions of a method's working frames.
#[derive(Debug, Clone, PartialEq)]
pub struct WorkingFrames<'a> {
    /// Fractional file frame of every working frame, ascending.
    pub source: &'a [f64],
    /// Number of frames of the file.
    pub file_frames: usize,
}

impl WorkingFrames<'_> {
    /// The first file frame of working frame `k` (file frames are split half-way between the
    /// file positions of consecutive working frames).
    pub fn file_start(&self, k: usize) -> usize {
        if k == 0 {
            0
        } else {
            ((self.source[k - 1] + self.source[k]) / 2.0).ceil() as usize
        }
    }

    /// The working frames `start..=end` as file frames `(start, end)`, inclusive (`None` if they
    /// map to no file frame, e.g. an upsampled frame inside one file frame).
    pub fn file_span(&self, start: usize, end: usize) -> Option<(usize, usize)> {
        let first = self.file_start(start);
        let last = if end + 1 < self.source.len() {
            self.file_start(end + 1).checked_sub(1)?
        } else {
            self.file_frames.checked_sub(1)?
        };
        (first <= last && last < self.file_frames).then_some((first, last))
    }

    /// The working frame nearest to file frame `f`.
    pub fn working_frame(&self, f: usize) -> usize {
        let k = self.source.partition_point(|&s| s < f as f64);
        match k {
            0 => 0,
            k if k >= self.source.len() => self.source.len().saturating_sub(1),
            k if (self.source[k] - f as f64) < (f as f64 - self.source[k - 1]) => k,
            k => k - 1,
        }
    }

    /// `segment` with `start`/`end` given in working frames, moved to file frames (`None` if it
    /// maps to none).
    pub fn to_file(&self, mut segment: Segment) -> Option<Segment> {
        let (start, end) = self.file_span(segment.start, segment.end)?;
        segment.start = start;
        segment.end = end;
        Some(segment)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn working_spans_map_to_contiguous_file_frames() {
        // 120 Hz file of 41 frames → 30 Hz working frames at file frames 0, 4, …, 40
        let source: Vec<f64> = (0..11).map(|k| 4.0 * k as f64).collect();
        let w = WorkingFrames { source: &source, file_frames: 41 };
        assert_eq!(w.file_span(0, 2), Some((0, 9)));
        assert_eq!(w.file_span(3, 10), Some((10, 40)));
        // a file with a trailing partial frame: the last span runs to the end
        let w = WorkingFrames { source: &source, file_frames: 43 };
        assert_eq!(w.file_span(3, 10), Some((10, 42)));
        assert_eq!((w.working_frame(0), w.working_frame(5), w.working_frame(7), w.working_frame(99)), (0, 1, 2, 10));
        // upsampled 20 Hz → 30 Hz: a working frame may fall inside one file frame
        let source: Vec<f64> = (0..7).map(|k| k as f64 * 2.0 / 3.0).collect();
        let w = WorkingFrames { source: &source, file_frames: 5 };
        assert_eq!(w.file_span(0, 0), Some((0, 0)));
        assert_eq!(w.file_span(1, 1), None);
        assert_eq!(w.file_span(2, 6), Some((1, 4)));
    }
}
