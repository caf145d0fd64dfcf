//! Ground truth for one take from whichever file a user has — the one path the page's import
//! control and `mocapseg eval --truth` share:
//!
//! - **a simple CSV** `start_frame,end_frame,label` (a header naming those columns, in any order
//!   and with other columns ignored, or no header and the three fields in that order);
//! - **the shared data's CSV** `trial,…,label,start_frame,end_frame,…` ([`super::truth`]): the
//!   trial named by [`ImportOptions::trial`], else the one named like the take, else the file's
//!   only trial;
//! - **the segmentation JSON** every method exports ([`Segmentation`]): its actions (or, with
//!   none, its primitives) become the truth, transitions left unlabelled.
//!
//! CSV frame numbers count from [`ImportOptions::first_frame`] (0 or 1) at
//! [`ImportOptions::label_fps`] (the take's own rate when `None`); the JSON's are 0-based at its
//! `fps`. Labels at another rate than the take's are converted by time: label frame `f` starts
//! at `f / rate` seconds, so segment `s..=e` becomes take frames
//! `round(s·k) ..= round((e+1)·k) − 1` with `k = take fps / label fps` — neighbouring segments stay
//! neighbours. Rates within 0.1 % of each other are the same rate (a BVH's `Frame Time` is
//! printed rounded: 0.0083333 s is 120.0048 fps). A segment whose last label frame starts inside
//! the take but which reaches past its end by the conversion is cut at the take's last frame; a
//! segment that ends past the take otherwise is an error naming its line (JSON: its index).
//! [`ImportOptions::bvh_row_offset`] then shifts every segment (a BVH that prepends a T-pose row).

use super::metrics::scored_level;
use super::truth::{frame_number, load_csv_lines, Truth, TruthError, TruthOptions, TruthSegment, MAX_FRAMES};
use super::{SchemaError, Segmentation};
use serde::Serialize;

/// The take the ground truth is for.
#[derive(Debug, Clone, PartialEq)]
pub struct Take {
    /// The take's file name (`13_30.bvh`); its stem names the trial in a shared-data CSV.
    pub name: String,
    pub frames: usize,
    pub fps: f64,
}

impl Take {
    /// The file name without folders and extension (`13_30`).
    pub fn stem(&self) -> String {
        stem(&self.name)
    }
}

/// `dir/13_30.bvh` → `13_30`.
pub fn stem(name: &str) -> String {
    let base = name.rsplit(['/', '\\']).next().unwrap_or(name);
    match base.rfind('.') {
        Some(dot) if dot > 0 => base[..dot].to_string(),
        _ => base.to_string(),
    }
}

/// How to read a ground-truth file's frame numbers (the page's choices, `mocapseg eval`'s flags).
#[derive(Debug, Clone, PartialEq)]
pub struct ImportOptions {
    /// The number a CSV gives the first frame: 1 (AMC frame numbers, spreadsheets) or 0.
    pub first_frame: usize,
    /// The rate a CSV's frame numbers count at; `None`: the take's own.
    pub label_fps: Option<f64>,
    /// Take rows before the labels' first frame (1 for a BVH that prepends a T-pose row).
    pub bvh_row_offset: usize,
    /// The trial of a shared-data CSV; `None`: the take's name, else the file's only trial.
    pub trial: Option<String>,
}

impl Default for ImportOptions {
    fn default() -> Self {
        ImportOptions { first_frame: 1, label_fps: None, bvh_row_offset: 0, trial: None }
    }
}

/// What kind of file the ground truth came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum TruthFormat {
    /// `start_frame,end_frame,label`.
    Spans,
    /// The shared data's `trial,…,label,start_frame,end_frame,…`.
    Trials,
    /// The segmentation JSON.
    Segmentation,
}

/// How a shared-data CSV's trial was chosen.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum TrialChoice {
    /// Named in the options.
    Named,
    /// Named like the take.
    TakeName,
    /// The take's name is not in the file, which has this one trial only.
    OnlyOne,
}

/// What an import did (the page shows it next to the control).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Applied {
    pub format: TruthFormat,
    /// The number the file's first frame has (0 for the JSON).
    pub first_frame: usize,
    /// The rate the labels were read at, and the take's.
    pub label_fps: f64,
    pub take_fps: f64,
    /// Whether the frames were converted from `label_fps` to `take_fps`.
    pub converted: bool,
    pub bvh_row_offset: usize,
    /// The trial read, and how it was chosen (shared-data CSV only).
    pub trial: Option<(String, TrialChoice)>,
    /// Every trial in the file (shared-data CSV only).
    pub trials: Vec<String>,
    /// Segments the conversion left shorter than one take frame (dropped).
    pub dropped: usize,
    /// Whether the last segment was cut at the take's last frame.
    pub clamped: bool,
    /// The JSON's method and the level taken from it.
    pub source: Option<String>,
}

impl Applied {
    /// One line saying what was read and how ("CSV start_frame,end_frame,label · frames counted
    /// from 1 · labels at 30 fps converted to the take's 120 fps").
    pub fn describe(&self, segments: usize) -> String {
        let mut parts = vec![match (&self.format, &self.source) {
            (TruthFormat::Spans, _) => "CSV start_frame,end_frame,label".to_string(),
            (TruthFormat::Trials, _) => "shared-data CSV".to_string(),
            (TruthFormat::Segmentation, Some(source)) => format!("segmentation JSON ({source})"),
            (TruthFormat::Segmentation, None) => "segmentation JSON".to_string(),
        }];
        if let Some((trial, choice)) = &self.trial {
            parts.push(match choice {
                TrialChoice::Named => format!("trial {trial}"),
                TrialChoice::TakeName => format!("trial {trial} (the take's name)"),
                TrialChoice::OnlyOne => format!("trial {trial} (the file's only trial; the take's name is not in it)"),
            });
        }
        parts.push(match self.format {
            TruthFormat::Segmentation => "frames counted from 0".to_string(),
            _ => format!("frames counted from {}", self.first_frame),
        });
        parts.push(if self.converted {
            format!("labels at {} fps converted to the take's {} fps", rate(self.label_fps), rate(self.take_fps))
        } else {
            format!("at the take's rate ({} fps)", rate(self.take_fps))
        });
        if self.bvh_row_offset > 0 {
            parts.push(format!("shifted by {} row(s)", self.bvh_row_offset));
        }
        parts.push(format!("{segments} segment{}", if segments == 1 { "" } else { "s" }));
        if self.dropped > 0 {
            parts.push(format!("{} shorter than one take frame dropped", self.dropped));
        }
        if self.clamped {
            parts.push("the last cut at the take's end".to_string());
        }
        parts.join(" · ")
    }
}

/// A rate as people write it: `120`, `29.97`.
fn rate(fps: f64) -> String {
    let rounded = (fps * 100.0).round() / 100.0;
    if rounded.fract() == 0.0 {
        format!("{rounded:.0}")
    } else {
        format!("{rounded}")
    }
}

/// The trials a shared-data CSV names, in the order it first names them (empty for any other
/// file, or one that cannot be read).
pub fn csv_trials(text: &str) -> Vec<String> {
    let body = text.trim_start_matches('\u{feff}');
    match header(body) {
        Ok(Header::Trials) => {
            load_csv_lines(body, "", TruthOptions::default()).map(|(_, names)| names).unwrap_or_default()
        }
        _ => Vec::new(),
    }
}

/// The ground truth read, and how.
#[derive(Debug, Clone, PartialEq)]
pub struct Imported {
    /// At the take's rate, 0-based rows; `frames` is the take's.
    pub truth: Truth,
    pub applied: Applied,
}

/// Why a file could not be read as the take's ground truth.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ImportError {
    #[error("{0}")]
    Csv(#[from] TruthError),
    #[error("segmentation JSON line {line}, column {column}: {message}")]
    Json { line: usize, column: usize, message: String },
    #[error("segmentation JSON: {0}")]
    Schema(SchemaError),
    #[error("segmentation JSON segment {index} (`{label}`): {message}")]
    Segment { index: usize, label: String, message: String },
    #[error("the labels' frame rate must be a positive number of frames per second, got {0}")]
    BadRate(f64),
    #[error("the frame base must be 0 or 1, got {0}")]
    BadBase(usize),
    #[error("the take has no frames")]
    EmptyTake,
    #[error("{what} has no labelled segments")]
    Empty { what: &'static str },
    #[error("{what} covers {frames} take frames but the take `{take}` has {take_frames}: {hint}")]
    Length { what: String, frames: usize, take: String, take_frames: usize, hint: &'static str },
}

/// Where a segment comes from, for its error.
#[derive(Debug, Clone, Copy)]
enum Origin {
    Line(usize),
    Segment(usize),
}

/// One segment as read, in the file's frames (0-based, at the labels' rate).
struct Raw {
    start: usize,
    end: usize,
    label: String,
    window: Option<(usize, usize)>,
    origin: Origin,
}

/// Label frames → take frames.
#[derive(Debug, Clone, Copy)]
struct Rates {
    k: f64,
    same: bool,
}

impl Rates {
    fn new(label_fps: f64, take_fps: f64) -> Rates {
        let k = take_fps / label_fps;
        Rates { k, same: (k - 1.0).abs() < 1e-3 }
    }

    /// The take frame where label frame `f` starts (saturating far past any take).
    fn at(self, f: usize) -> usize {
        if self.same {
            f
        } else {
            (f as f64 * self.k).round().min(MAX_FRAMES as f64 * 4.0) as usize
        }
    }

    /// The take frame whose period holds the start of label frame `f`.
    fn within(self, f: usize) -> usize {
        if self.same {
            f
        } else {
            (f as f64 * self.k).floor().min(MAX_FRAMES as f64 * 4.0) as usize
        }
    }

    /// How many take frames `n` label frames last.
    fn frames(self, n: usize) -> usize {
        self.at(n)
    }

    /// How far apart two lengths in take frames may be and still be the same take: less than
    /// one label frame, and less than one take frame when the labels are finer.
    fn slack(self) -> f64 {
        if self.same {
            1.0
        } else {
            self.k.max(1.0)
        }
    }
}

/// Reads `text` (a CSV or the segmentation JSON, told apart by its first character) as the
/// ground truth of `take`; see the module documentation.
pub fn import_truth(text: &str, take: &Take, options: &ImportOptions) -> Result<Imported, ImportError> {
    if take.frames == 0 {
        return Err(ImportError::EmptyTake);
    }
    if !(take.fps.is_finite() && take.fps > 0.0) {
        return Err(ImportError::Schema(SchemaError::BadFps(take.fps)));
    }
    let body = text.trim_start_matches('\u{feff}');
    if body.trim_start().starts_with('{') {
        return import_json(body, take, options);
    }
    if options.first_frame > 1 {
        return Err(ImportError::BadBase(options.first_frame));
    }
    let label_fps = options.label_fps.unwrap_or(take.fps);
    if !(label_fps.is_finite() && label_fps > 0.0) {
        return Err(ImportError::BadRate(label_fps));
    }
    let rates = Rates::new(label_fps, take.fps);
    let mut applied = Applied {
        format: TruthFormat::Spans,
        first_frame: options.first_frame,
        label_fps,
        take_fps: take.fps,
        converted: !rates.same,
        bvh_row_offset: options.bvh_row_offset,
        trial: None,
        trials: Vec::new(),
        dropped: 0,
        clamped: false,
        source: None,
    };
    let (raws, trial) = match header(body)? {
        Header::Trials => {
            applied.format = TruthFormat::Trials;
            let (raws, trial, frames_given) = read_trial(body, take, options, &mut applied)?;
            if let Some(frames) = frames_given {
                check_length(
                    format!("trial `{trial}` (its `trial_frames`)"),
                    rates.frames(frames),
                    take,
                    options,
                    rates,
                )?;
            }
            (raws, trial)
        }
        Header::Spans { columns, has_header } => {
            (read_spans(body, columns, has_header, options.first_frame)?, take.stem())
        }
    };
    if raws.is_empty() {
        return Err(ImportError::Empty { what: "the file" });
    }
    let segments = convert(raws, take, rates, options, &mut applied)?;
    if segments.is_empty() {
        return Err(ImportError::Empty { what: "the file at the take's rate" });
    }
    Ok(Imported { truth: Truth { trial, frames: take.frames, segments }, applied })
}

/// The take's length against the one the file gives (converted), within one label frame.
fn check_length(
    what: String,
    frames: usize,
    take: &Take,
    options: &ImportOptions,
    rates: Rates,
) -> Result<(), ImportError> {
    let frames = frames.saturating_add(options.bvh_row_offset);
    if (frames as f64 - take.frames as f64).abs() >= rates.slack() {
        return Err(ImportError::Length {
            what,
            frames,
            take: take.name.clone(),
            take_frames: take.frames,
            hint: "is it the same take? Check the labels' frame rate and, for a BVH that starts with a T-pose row, the row offset",
        });
    }
    Ok(())
}

enum Header {
    Trials,
    /// Column indices of start_frame, end_frame, label.
    Spans {
        columns: [usize; 3],
        has_header: bool,
    },
}

fn reader(text: &str) -> csv::Reader<&[u8]> {
    csv::ReaderBuilder::new().has_headers(false).trim(csv::Trim::All).flexible(true).from_reader(text.as_bytes())
}

fn csv_error(e: &csv::Error) -> TruthError {
    TruthError::Line { line: e.position().map_or(0, |p| p.line() as usize), message: e.to_string() }
}

/// What the first non-blank line says the file is.
fn header(text: &str) -> Result<Header, TruthError> {
    let mut reader = reader(text);
    let mut record = csv::StringRecord::new();
    loop {
        if !reader.read_record(&mut record).map_err(|e| csv_error(&e))? {
            return Err(TruthError::Line {
                line: 1,
                message: "the file is empty: expected `start_frame,end_frame,label` rows".into(),
            });
        }
        if !record.iter().all(str::is_empty) {
            break;
        }
    }
    let line = text.lines().position(|l| !l.trim().is_empty()).map_or(1, |i| i + 1);
    let names: Vec<String> = record.iter().map(|f| f.to_ascii_lowercase()).collect();
    let at = |n: &str| names.iter().position(|f| f == n);
    if at("trial").is_some() {
        return Ok(Header::Trials);
    }
    match (at("start_frame"), at("end_frame"), at("label")) {
        (Some(s), Some(e), Some(l)) => return Ok(Header::Spans { columns: [s, e, l], has_header: true }),
        (Some(_), Some(_), None) => return Err(TruthError::MissingColumn("label")),
        (Some(_), None, _) => return Err(TruthError::MissingColumn("end_frame")),
        (None, Some(_), _) => return Err(TruthError::MissingColumn("start_frame")),
        _ => {}
    }
    let number = |i: usize| record.get(i).is_some_and(|f| f.parse::<f64>().is_ok());
    if number(0) && number(1) {
        return Ok(Header::Spans { columns: [0, 1, 2], has_header: false });
    }
    let shown: String = record.iter().collect::<Vec<_>>().join(",").chars().take(60).collect();
    Err(TruthError::Line {
        line,
        message: format!(
            "expected a header `start_frame,end_frame,label` (or the shared data's `trial,label,start_frame,end_frame,…`) \
             or a row `start,end,label` of frame numbers, found `{shown}`"
        ),
    })
}

/// The rows of a `start_frame,end_frame,label` CSV.
fn read_spans(text: &str, columns: [usize; 3], has_header: bool, first: usize) -> Result<Vec<Raw>, TruthError> {
    let mut reader = reader(text);
    let mut record = csv::StringRecord::new();
    let width = columns.iter().max().map_or(3, |m| m + 1);
    let mut header_seen = !has_header;
    let mut raws = Vec::new();
    while reader.read_record(&mut record).map_err(|e| csv_error(&e))? {
        if record.iter().all(str::is_empty) {
            continue;
        }
        if !header_seen {
            header_seen = true;
            continue;
        }
        let line = record.position().map_or(0, |p| p.line() as usize);
        if record.len() < width {
            return Err(TruthError::Line {
                line,
                message: format!("expected {width} fields (start_frame,end_frame,label), found {}", record.len()),
            });
        }
        let [s, e, l] = columns.map(|c| &record[c]);
        let start = frame_number(s, "start_frame", first, line)?;
        let end = frame_number(e, "end_frame", first, line)?;
        if end < start {
            return Err(TruthError::Line { line, message: format!("end_frame {e} is before start_frame {s}") });
        }
        if l.is_empty() {
            return Err(TruthError::Line {
                line,
                message: "expected a label in the `label` field, found nothing".into(),
            });
        }
        raws.push(Raw { start, end, label: l.to_string(), window: None, origin: Origin::Line(line) });
    }
    raws.sort_by_key(|r| r.start);
    Ok(raws)
}

/// The chosen trial of a shared-data CSV, its name and its length if the file gives it.
fn read_trial(
    text: &str,
    take: &Take,
    options: &ImportOptions,
    applied: &mut Applied,
) -> Result<(Vec<Raw>, String, Option<usize>), ImportError> {
    let read_options = TruthOptions { first_frame: options.first_frame, bvh_row_offset: 0 };
    let (wanted, choice) = match &options.trial {
        Some(t) => (t.clone(), TrialChoice::Named),
        None => (take.stem(), TrialChoice::TakeName),
    };
    let (found, names) = load_csv_lines(text, &wanted, read_options)?;
    let (read, name, choice) = match found {
        Some(read) => (read, wanted, choice),
        None if options.trial.is_none() && names.len() == 1 => match load_csv_lines(text, &names[0], read_options)?.0 {
            Some(read) => (read, names[0].clone(), TrialChoice::OnlyOne),
            None => return Err(TruthError::NoTrial { trial: wanted, present: names.join(", ") }.into()),
        },
        None => return Err(TruthError::NoTrial { trial: wanted, present: names.join(", ") }.into()),
    };
    applied.trial = Some((name.clone(), choice));
    applied.trials = names;
    let frames = read.frames_given.then_some(read.truth.frames);
    let raws = read
        .truth
        .segments
        .into_iter()
        .zip(read.lines)
        .map(|(s, line)| Raw {
            start: s.start,
            end: s.end,
            label: s.label,
            window: s.end_window,
            origin: Origin::Line(line),
        })
        .collect();
    Ok((raws, name, frames))
}

/// The segmentation JSON's scored segments as the take's ground truth.
fn import_json(text: &str, take: &Take, options: &ImportOptions) -> Result<Imported, ImportError> {
    let seg: Segmentation = serde_json::from_str(text).map_err(|e| ImportError::Json {
        line: e.line(),
        column: e.column(),
        message: format!("expected the segmentation JSON (file, fps, frames, method, params, segments): {e}"),
    })?;
    seg.validate().map_err(ImportError::Schema)?;
    let rates = Rates::new(seg.fps, take.fps);
    check_length(
        format!("the segmentation ({} frames at {} fps)", seg.frames, rate(seg.fps)),
        rates.frames(seg.frames),
        take,
        options,
        rates,
    )?;
    let level = scored_level(&seg);
    let raws: Vec<Raw> = seg
        .segments
        .iter()
        .enumerate()
        .filter(|(_, s)| s.level == level)
        .map(|(index, s)| Raw {
            start: s.start,
            end: s.end,
            label: match (s.label.is_empty(), s.cluster) {
                (true, Some(c)) => format!("#{c}"),
                _ => s.label.clone(),
            },
            window: None,
            origin: Origin::Segment(index),
        })
        .collect();
    if raws.is_empty() {
        return Err(ImportError::Empty { what: "the segmentation" });
    }
    let level_name = match level {
        super::Level::Action => "actions",
        super::Level::Primitive => "primitives",
        super::Level::Transition => "transitions",
    };
    let mut applied = Applied {
        format: TruthFormat::Segmentation,
        first_frame: 0,
        label_fps: seg.fps,
        take_fps: take.fps,
        converted: !rates.same,
        bvh_row_offset: options.bvh_row_offset,
        trial: None,
        trials: Vec::new(),
        dropped: 0,
        clamped: false,
        source: Some(format!("{} {level_name}", seg.method)),
    };
    let mut raws = raws;
    raws.sort_by_key(|r| r.start);
    let segments = convert(raws, take, rates, options, &mut applied)?;
    if segments.is_empty() {
        return Err(ImportError::Empty { what: "the segmentation at the take's rate" });
    }
    Ok(Imported { truth: Truth { trial: take.stem(), frames: take.frames, segments }, applied })
}

/// The segments in take rows (converted, shifted, checked against the take's end).
fn convert(
    raws: Vec<Raw>,
    take: &Take,
    rates: Rates,
    options: &ImportOptions,
    applied: &mut Applied,
) -> Result<Vec<TruthSegment>, ImportError> {
    let last = take.frames - 1;
    let offset = options.bvh_row_offset;
    let shift = |f: usize| f.saturating_add(offset);
    let mut out = Vec::with_capacity(raws.len());
    for raw in raws {
        let start = shift(rates.at(raw.start));
        let first_of_last = shift(rates.within(raw.end));
        let past_end = |what: &str, number: usize, row: usize| {
            let (first, fps) =
                (if matches!(raw.origin, Origin::Line(_)) { options.first_frame } else { 0 }, applied.label_fps);
            let converted = if rates.same {
                String::new()
            } else {
                format!(" (at {} fps: take frame {row} counting from 0)", rate(fps))
            };
            let message = format!(
                "{what} {}{converted} is past the end of the take `{}` ({} frames at {} fps, the last numbered {})",
                number + first,
                take.name,
                take.frames,
                rate(take.fps),
                if rates.same { last + first } else { last },
            ) + if offset > 0 { " after the row offset" } else { "" };
            origin_error(raw.origin, &raw.label, message)
        };
        if start > last {
            return Err(past_end(
                if matches!(raw.origin, Origin::Line(_)) { "`start_frame` =" } else { "start" },
                raw.start,
                start,
            ));
        }
        if first_of_last > last {
            return Err(past_end(
                if matches!(raw.origin, Origin::Line(_)) { "`end_frame` =" } else { "end" },
                raw.end,
                first_of_last,
            ));
        }
        let end_exclusive = shift(rates.at(raw.end.saturating_add(1)));
        if end_exclusive <= start {
            applied.dropped += 1;
            continue;
        }
        let mut end = end_exclusive - 1;
        if end > last {
            end = last;
            applied.clamped = true;
        }
        let window = raw.window.map(|(lo, hi)| {
            let (lo, hi) = (shift(rates.at(lo)).min(last), shift(rates.at(hi)).min(last));
            (lo.min(hi), hi)
        });
        out.push(TruthSegment { start, end, label: raw.label, end_window: window });
    }
    Ok(out)
}

fn origin_error(origin: Origin, label: &str, message: String) -> ImportError {
    match origin {
        Origin::Line(line) => ImportError::Csv(TruthError::Line { line, message }),
        Origin::Segment(index) => ImportError::Segment { index, label: label.to_string(), message },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::segment::metrics::{evaluate, Tolerances};
    use crate::segment::truth::load_csv;

    fn take(name: &str, frames: usize, fps: f64) -> Take {
        Take { name: name.into(), frames, fps }
    }

    fn spans(t: &Truth) -> Vec<(usize, usize, &str)> {
        t.segments.iter().map(|s| (s.start, s.end, s.label.as_str())).collect()
    }

    fn opts(first_frame: usize, label_fps: Option<f64>) -> ImportOptions {
        ImportOptions { first_frame, label_fps, ..ImportOptions::default() }
    }

    #[test]
    fn simple_csv_with_or_without_header_and_either_base() {
        let t = take("walk.bvh", 100, 10.0);
        let with_header = "start_frame,end_frame,label\n1,40,walk\n41,100,jump\n";
        let a = import_truth(with_header, &t, &opts(1, None)).unwrap();
        assert_eq!(spans(&a.truth), [(0, 39, "walk"), (40, 99, "jump")]);
        assert_eq!((a.truth.frames, a.truth.trial.as_str()), (100, "walk"));
        assert_eq!(a.applied.format, TruthFormat::Spans);
        assert!(!a.applied.converted);
        // the same numbers 0-based are one frame later
        let b = import_truth("start_frame,end_frame,label\n0,40,walk\n41,99,jump\n", &t, &opts(0, None)).unwrap();
        assert_eq!(spans(&b.truth)[0], (0, 40, "walk"));
        // no header, columns reordered by a header, extra columns ignored, blank lines skipped
        let bare = import_truth("0,39,walk\n\n40,99,jump\n", &t, &opts(0, None)).unwrap();
        assert_eq!(spans(&bare.truth), spans(&a.truth));
        let reordered =
            import_truth("label,note,end_frame,start_frame\njump,x,100,41\nwalk,y,40,1\n", &t, &opts(1, None)).unwrap();
        assert_eq!(spans(&reordered.truth), spans(&a.truth));
        assert_eq!(
            a.applied.describe(2),
            "CSV start_frame,end_frame,label · frames counted from 1 · at the take's rate (10 fps) · 2 segments"
        );
    }

    #[test]
    fn labels_at_another_rate_are_converted_by_time_and_stay_contiguous() {
        // 30 fps labels on a 120 fps take: ×4
        let t = take("13_30.bvh", 2465, 1.0 / 0.0083333);
        let csv = "start_frame,end_frame,label\n0,99,a\n100,299,b\n300,616,c\n";
        let i = import_truth(csv, &t, &opts(0, Some(30.0))).unwrap();
        // label frame 616 starts at take frame 2464, the last: the segment is cut there
        assert_eq!(spans(&i.truth), [(0, 399, "a"), (400, 1199, "b"), (1200, 2464, "c")]);
        assert!(i.applied.converted && i.applied.clamped);
        assert!(
            i.applied.describe(3).contains("labels at 30 fps converted to the take's 120 fps"),
            "{}",
            i.applied.describe(3)
        );
        // label frame 617 starts past the take: an error naming the line and the conversion
        let e = import_truth(&csv.replace("616", "617"), &t, &opts(0, Some(30.0))).unwrap_err().to_string();
        assert_eq!(
            e,
            "ground truth CSV line 4: `end_frame` = 617 (at 30 fps: take frame 2468 counting from 0) is past the end of the take \
             `13_30.bvh` (2465 frames at 120 fps, the last numbered 2464)"
        );
        // 240 fps labels on a 120 fps take: halves; a one-label-frame segment may vanish
        let i = import_truth("0,10,a\n11,11,b\n12,19,c\n", &take("x.bvh", 10, 120.0), &opts(0, Some(240.0))).unwrap();
        assert_eq!(spans(&i.truth), [(0, 5, "a"), (6, 9, "c")]);
        assert_eq!(i.applied.dropped, 1);
    }

    #[test]
    fn labels_past_the_take_name_their_line() {
        let t = take("t.bvh", 100, 10.0);
        let e = import_truth("start_frame,end_frame,label\n1,50,a\n51,101,b\n", &t, &opts(1, None)).unwrap_err();
        assert_eq!(
            e.to_string(),
            "ground truth CSV line 3: `end_frame` = 101 is past the end of the take `t.bvh` (100 frames at 10 fps, the last numbered 100)"
        );
        // 0-based, the same file fits up to 100 only when 0-based numbers stop at 99
        let e = import_truth("0,100,a\n", &t, &opts(0, None)).unwrap_err();
        assert!(e.to_string().starts_with("ground truth CSV line 1: `end_frame` = 100 is past the end"), "{e}");
    }

    #[test]
    fn bad_lines_say_what_was_expected() {
        let t = take("t.bvh", 100, 10.0);
        let cases = [
            (
                "start_frame,end_frame,label\n1,10,a\n11,x,b\n",
                "ground truth CSV line 3: expected a frame number in `end_frame`, found `x`",
            ),
            (
                "start_frame,end_frame,label\n1,10,a\n20,11,b\n",
                "ground truth CSV line 3: end_frame 11 is before start_frame 20",
            ),
            (
                "start_frame,end_frame,label\n1,10\n",
                "ground truth CSV line 2: expected 3 fields (start_frame,end_frame,label), found 2",
            ),
            (
                "start_frame,end_frame,label\n1,10,\n",
                "ground truth CSV line 2: expected a label in the `label` field, found nothing",
            ),
            ("start_frame,end_frame\n1,10\n", "ground truth CSV: missing column `label` in the header line"),
            ("\n\nfrom,to,what\n", "ground truth CSV line 3: expected a header `start_frame,end_frame,label`"),
            ("", "ground truth CSV line 1: the file is empty"),
            (
                "start_frame,end_frame,label\n0,10,a\n",
                "ground truth CSV line 2: `start_frame` = 0 is before the first frame 1",
            ),
        ];
        for (text, want) in cases {
            let e = import_truth(text, &t, &opts(1, None)).unwrap_err().to_string();
            assert!(e.starts_with(want), "{e}\n  wanted {want}");
        }
        assert_eq!(import_truth("1,2,a\n", &t, &opts(2, None)).unwrap_err(), ImportError::BadBase(2));
        assert_eq!(import_truth("1,2,a\n", &t, &opts(1, Some(0.0))).unwrap_err(), ImportError::BadRate(0.0));
        assert_eq!(
            import_truth("start_frame,end_frame,label\n", &t, &opts(1, None)).unwrap_err(),
            ImportError::Empty { what: "the file" }
        );
    }

    const MOCAP6: &str =
        "trial,seg_index,label_id,label,start_block,end_block,start_frame,end_frame,trial_frames,fps,mocap_in_repo\n\
13_30,0,1,JumpJack,1,20,1,240,300,120,yes\n\
13_30,1,2,Jog,21,25,241,300,300,120,yes\n\
13_31,0,3,Squat,1,10,1,120,120,120,yes\n";

    #[test]
    fn shared_data_csv_picks_the_trial_named_like_the_take_as_load_csv_reads_it() {
        let t = take("data/13_30.bvh", 300, 120.0);
        let i = import_truth(MOCAP6, &t, &ImportOptions::default()).unwrap();
        assert_eq!(i.truth, load_csv(MOCAP6, "13_30", TruthOptions::default()).unwrap());
        assert_eq!(i.applied.trial, Some(("13_30".to_string(), TrialChoice::TakeName)));
        assert_eq!(i.applied.trials, ["13_30", "13_31"]);
        // a take named otherwise: the trial must be named when the file has several
        let e = import_truth(MOCAP6, &take("sample.bvh", 300, 120.0), &ImportOptions::default()).unwrap_err();
        assert_eq!(e.to_string(), "ground truth CSV: no rows for trial `sample` (trials present: 13_30, 13_31)");
        let named = ImportOptions { trial: Some("13_30".into()), ..ImportOptions::default() };
        let i = import_truth(MOCAP6, &take("sample.bvh", 300, 120.0), &named).unwrap();
        assert_eq!(i.applied.trial, Some(("13_30".to_string(), TrialChoice::Named)));
        // … and the only trial when there is one
        let one: String = MOCAP6.lines().take(3).map(|l| format!("{l}\n")).collect();
        let i = import_truth(&one, &take("sample.bvh", 300, 120.0), &ImportOptions::default()).unwrap();
        assert_eq!(i.applied.trial, Some(("13_30".to_string(), TrialChoice::OnlyOne)));
        assert!(i.applied.describe(2).contains("trial 13_30 (the file's only trial"), "{}", i.applied.describe(2));
    }

    #[test]
    fn the_trials_of_a_shared_data_csv_are_listed() {
        assert_eq!(csv_trials(MOCAP6), ["13_30", "13_31"]);
        assert!(csv_trials("start_frame,end_frame,label\n1,2,a\n").is_empty());
        assert!(csv_trials("{}").is_empty());
    }

    #[test]
    fn shared_data_csv_length_must_be_the_takes() {
        let e = import_truth(MOCAP6, &take("13_30.bvh", 301, 120.0), &ImportOptions::default()).unwrap_err();
        assert!(
            e.to_string().starts_with(
                "trial `13_30` (its `trial_frames`) covers 300 take frames but the take `13_30.bvh` has 301"
            ),
            "{e}"
        );
        // a T-pose row: the offset makes it fit and shifts every segment
        let o = ImportOptions { bvh_row_offset: 1, ..ImportOptions::default() };
        let i = import_truth(MOCAP6, &take("13_30.bvh", 301, 120.0), &o).unwrap();
        assert_eq!(spans(&i.truth), [(1, 240, "JumpJack"), (241, 300, "Jog")]);
        // at 30 fps the 300 frames are 1200 take frames
        let i = import_truth(MOCAP6, &take("13_30.bvh", 1200, 120.0), &opts(1, Some(30.0))).unwrap();
        assert_eq!(spans(&i.truth), [(0, 959, "JumpJack"), (960, 1199, "Jog")]);
    }

    #[test]
    fn segmentation_json_imports_its_actions() {
        let json = r#"{"file": "a.bvh", "fps": 10.0, "frames": 100, "method": "sssm", "params": {},
            "segments": [
              {"start": 0, "end": 39, "label": "walk", "level": "action", "cluster": 0, "score": null},
              {"start": 40, "end": 49, "label": "", "level": "transition", "cluster": null, "score": null},
              {"start": 50, "end": 99, "label": "", "level": "action", "cluster": 1, "score": null},
              {"start": 0, "end": 99, "label": "p", "level": "primitive", "cluster": 3, "score": null}]}"#;
        let t = take("a.bvh", 100, 10.0);
        let i = import_truth(json, &t, &ImportOptions::default()).unwrap();
        assert_eq!(spans(&i.truth), [(0, 39, "walk"), (50, 99, "#1")]);
        assert_eq!(i.applied.format, TruthFormat::Segmentation);
        assert_eq!(
            i.applied.describe(2),
            "segmentation JSON (sssm actions) · frames counted from 0 · at the take's rate (10 fps) · 2 segments"
        );
        // another take's length
        let e = import_truth(json, &take("b.bvh", 90, 10.0), &ImportOptions::default()).unwrap_err();
        assert!(
            e.to_string().starts_with(
                "the segmentation (100 frames at 10 fps) covers 100 take frames but the take `b.bvh` has 90"
            ),
            "{e}"
        );
        // broken JSON names line and column; a broken schema says which segment
        let e = import_truth("{\n  \"file\": \"a.bvh\",\n  \"fps\": x\n}", &t, &ImportOptions::default()).unwrap_err();
        assert!(
            e.to_string().starts_with("segmentation JSON line 3, column 10: expected the segmentation JSON"),
            "{e}"
        );
        let e = import_truth(&json.replace("\"end\": 39", "\"end\": 139"), &t, &ImportOptions::default()).unwrap_err();
        assert_eq!(e.to_string(), "segmentation JSON: segment 0: end 139 is past the last frame 99");
    }

    #[test]
    fn a_segmentation_scored_against_itself_as_truth_is_perfect() {
        let json = r#"{"file": "a.bvh", "fps": 10.0, "frames": 100, "method": "m", "params": {},
            "segments": [
              {"start": 0, "end": 39, "label": "walk", "level": "action", "cluster": 0, "score": null},
              {"start": 40, "end": 99, "label": "run", "level": "action", "cluster": 1, "score": null}]}"#;
        let i = import_truth(json, &take("a.bvh", 100, 10.0), &ImportOptions::default()).unwrap();
        let s = evaluate(&Segmentation::from_json(json).unwrap(), &i.truth, &Tolerances::default()).unwrap();
        assert_eq!((s.covering, s.hungarian_accuracy, s.boundaries[0].f1), (1.0, 1.0, 1.0));
        assert_eq!(s.segments.similarity, 2.0);
    }

    #[test]
    fn stems_drop_folders_and_extension() {
        assert_eq!(stem("dir/13_30.bvh"), "13_30");
        assert_eq!(stem("C:\\x\\86_01.bvh"), "86_01");
        assert_eq!(stem(".hidden"), ".hidden");
        assert_eq!(stem("take"), "take");
    }
}
