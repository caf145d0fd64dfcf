//! Structure-aware BVH: an `arbitrary` take — a joint tree of any shape and depth, any channel
//! subset in any order, End Sites, any offsets, frame time and frame values, written with any
//! line endings, blanks, keyword case and number format — rendered to text and parsed.
//!
//! * A valid take must parse, to exactly the tree written and to exactly the numbers written
//!   (each as `str::parse::<f64>` reads its text: the parser is correctly rounded).
//! * A take with one planted fault (a NaN or infinite value, a word among the numbers, a row too
//!   long or too short, a channel listed twice, a bad frame time or frame count) must be refused
//!   with an error naming the line of the fault (and its column where the fault is one token).

use arbitrary::{Arbitrary, Unstructured};
use mocapseg::bvh::{self, Channel, JointKind};

#[derive(Arbitrary, Debug)]
struct Take {
    roots: Vec<Node>,
    frame_time: Number,
    rows: Vec<Vec<Number>>,
    declared: Declared,
    style: Style,
    fault: Option<Fault>,
    /// A last row with too few values (a truncated download): dropped with a warning.
    truncated_tail: bool,
}

#[derive(Arbitrary, Debug)]
struct Node {
    name: Vec<u8>,
    offset: [Number; 3],
    channels: Vec<u8>,
    children: Vec<Child>,
    /// CHANNELS before OFFSET.
    channels_first: bool,
}

#[derive(Arbitrary, Debug)]
enum Child {
    Joint(Node),
    EndSite([Number; 3]),
}

/// A number and how it is written.
#[derive(Arbitrary, Debug, Clone, Copy)]
struct Number {
    value: f64,
    format: u8,
}

#[derive(Arbitrary, Debug)]
enum Declared {
    Rows,
    Other(u32),
}

#[derive(Arbitrary, Debug)]
struct Style {
    /// Per line: `\n`, `\r\n` or `\r`.
    endings: Vec<u8>,
    /// Per token gap: a space, a tab, spaces, a space and a tab.
    gaps: Vec<u8>,
    /// Keywords upper, lower or capitalised.
    case: u8,
    indent_tabs: bool,
    brace_on_name_line: bool,
    bom: bool,
    glued_frames: bool,
    trailing_blank_lines: u8,
}

#[derive(Arbitrary, Debug, Clone, Copy)]
enum Fault {
    /// Value `at` (mod the values) is NaN, infinite, a word, or a row gets one value too many.
    Value { at: u16, kind: ValueFault },
    /// A row (not the last) loses its last value.
    ShortRow { row: u16 },
    /// A joint lists one of its channels twice.
    DuplicateChannel { joint: u16 },
    /// `Frame Time:` of 0, a negative number, NaN or infinity.
    FrameTime(u8),
    /// `Frames:` negative.
    NegativeFrames,
}

#[derive(Arbitrary, Debug, Clone, Copy)]
enum ValueFault {
    Nan,
    Infinite,
    Word,
    Extra,
}

const CHANNELS: [Channel; 6] = [
    Channel::Xposition,
    Channel::Yposition,
    Channel::Zposition,
    Channel::Xrotation,
    Channel::Yrotation,
    Channel::Zrotation,
];

/// What the parser must return for a node.
struct Expected {
    name: String,
    kind: JointKind,
    parent: Option<usize>,
    offset: [f64; 3],
    channels: Vec<Channel>,
}

/// Where a planted fault is, and what it is.
#[derive(Default)]
struct Planted {
    line: Option<usize>,
    column: Option<usize>,
}

struct Writer<'a> {
    out: String,
    line: usize,
    style: &'a Style,
    gap_i: usize,
    end_i: usize,
}

impl Writer<'_> {
    /// The column (1-based, in characters) where the next text on this line starts.
    fn column(&self) -> usize {
        let start = self.out.rfind(['\n', '\r']).map_or(0, |i| i + 1);
        self.out[start..].chars().count() + 1
    }

    fn gap(&mut self) {
        let g = self.style.gaps.get(self.gap_i % self.style.gaps.len().max(1)).copied().unwrap_or(0);
        self.gap_i += 1;
        self.out.push_str(["  ", "\t", " ", " \t", " "][g as usize % 5]);
    }

    fn end_line(&mut self) {
        let e = self.style.endings.get(self.end_i % self.style.endings.len().max(1)).copied().unwrap_or(0);
        self.end_i += 1;
        self.out.push_str(["\n", "\r\n", "\r", "\n"][e as usize % 4]);
        self.line += 1;
    }

    fn indent(&mut self, depth: usize) {
        for _ in 0..depth {
            self.out.push_str(if self.style.indent_tabs { "\t" } else { "  " });
        }
    }

    fn keyword(&self, k: &str) -> String {
        match self.style.case % 3 {
            0 => k.to_string(),
            1 => k.to_ascii_lowercase(),
            _ => k.split(' ').map(capitalise).collect::<Vec<_>>().join(" "),
        }
    }
}

fn capitalise(w: &str) -> String {
    let lower = w.to_ascii_lowercase();
    let mut c = lower.chars();
    c.next().map(|f| f.to_ascii_uppercase().to_string() + c.as_str()).unwrap_or_default()
}

/// The text of a finite number in one of several formats, and the value that text denotes.
fn number_text(n: Number) -> (String, f64) {
    let v = if n.value.is_finite() { n.value } else { 0.0 };
    let text = match n.format % 6 {
        0 => format!("{v}"),
        1 => format!("{v:e}"),
        2 => format!("{v:.6}"),
        3 => format!("{v:E}"),
        4 => {
            let r = (v * 1000.0).round() / 1000.0;
            format!("{:.3}", if r.is_finite() { r } else { v })
        }
        _ => {
            // `.5` / `-.5`: no digit before the point, if there is none to drop
            let t = format!("{v}");
            match t.strip_prefix("0.") {
                Some(rest) => format!(".{rest}"),
                None => match t.strip_prefix("-0.") {
                    Some(rest) => format!("-.{rest}"),
                    None => t,
                },
            }
        }
    };
    let value = text.parse::<f64>().expect("a Rust-formatted finite number parses");
    (text, value)
}

/// A joint name: letters, digits and `_:.-`, single inner spaces, starting with a letter.
fn name(raw: &[u8], fallback: usize) -> String {
    const CHARS: &[u8] = b"abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_:.- ";
    let mut s = String::from("J");
    for &b in raw.iter().take(16) {
        let c = CHARS[b as usize % CHARS.len()] as char;
        if c == ' ' && s.ends_with(' ') {
            continue;
        }
        s.push(c);
    }
    let s = s.trim_end().to_string();
    if s == "J" {
        format!("J{fallback}")
    } else {
        s
    }
}

fn channel_list(raw: &[u8]) -> Vec<Channel> {
    let mut out = Vec::new();
    for &b in raw.iter().take(6) {
        let c = CHANNELS[b as usize % 6];
        if !out.contains(&c) {
            out.push(c);
        }
    }
    out
}

struct Render<'a> {
    w: Writer<'a>,
    expected: Vec<Expected>,
    fault: Option<Fault>,
    planted: Planted,
    max_depth: usize,
    /// End Sites seen per parent (for `<parent>_End`, `<parent>_End2`, …).
    end_sites: Vec<usize>,
}

impl Render<'_> {
    fn node(&mut self, n: &Node, parent: Option<usize>, depth: usize) {
        self.max_depth = self.max_depth.max(depth + 1);
        let index = self.expected.len();
        let name = name(&n.name, index);
        let kind = if parent.is_none() { JointKind::Root } else { JointKind::Joint };
        let channels = channel_list(&n.channels);
        let offset = n.offset.map(|o| number_text(o).1);
        self.expected.push(Expected { name: name.clone(), kind, parent, offset, channels: channels.clone() });
        self.end_sites.push(0);
        self.w.indent(depth);
        let kw = self.w.keyword(if parent.is_none() { "ROOT" } else { "JOINT" });
        self.w.out.push_str(&kw);
        self.w.gap();
        self.w.out.push_str(&name);
        self.open(depth);
        let duplicate = matches!(self.fault, Some(Fault::DuplicateChannel { joint }) if joint as usize % 64 == index)
            && !channels.is_empty()
            && channels.len() < 6
            && self.planted.line.is_none();
        let write_channels = |r: &mut Self| {
            r.w.indent(depth + 1);
            let kw = r.w.keyword("CHANNELS");
            r.w.out.push_str(&kw);
            r.w.gap();
            r.w.out.push_str(&(channels.len() + usize::from(duplicate)).to_string());
            for c in &channels {
                r.w.gap();
                r.w.out.push_str(c.name());
            }
            if duplicate {
                r.w.gap();
                r.planted = Planted { line: Some(r.w.line), column: Some(r.w.column()) };
                r.w.out.push_str(channels[0].name());
            }
            r.w.end_line();
        };
        if n.channels_first {
            write_channels(self);
            self.offset_line(&n.offset, depth + 1);
        } else {
            self.offset_line(&n.offset, depth + 1);
            write_channels(self);
        }
        for child in &n.children {
            match child {
                Child::Joint(j) => self.node(j, Some(index), depth + 1),
                Child::EndSite(o) => {
                    self.end_sites[index] += 1;
                    let k = self.end_sites[index];
                    let end_name = if k == 1 { format!("{name}_End") } else { format!("{name}_End{k}") };
                    self.max_depth = self.max_depth.max(depth + 2);
                    self.expected.push(Expected {
                        name: end_name,
                        kind: JointKind::EndSite,
                        parent: Some(index),
                        offset: o.map(|x| number_text(x).1),
                        channels: Vec::new(),
                    });
                    self.end_sites.push(0);
                    self.w.indent(depth + 1);
                    let kw = self.w.keyword("End Site");
                    self.w.out.push_str(&kw);
                    self.open(depth + 1);
                    self.offset_line(o, depth + 2);
                    self.w.indent(depth + 1);
                    self.w.out.push('}');
                    self.w.end_line();
                }
            }
        }
        self.w.indent(depth);
        self.w.out.push('}');
        self.w.end_line();
    }

    fn open(&mut self, depth: usize) {
        if self.w.style.brace_on_name_line {
            self.w.gap();
            self.w.out.push('{');
            self.w.end_line();
        } else {
            self.w.end_line();
            self.w.indent(depth);
            self.w.out.push('{');
            self.w.end_line();
        }
    }

    fn offset_line(&mut self, o: &[Number; 3], depth: usize) {
        self.w.indent(depth);
        let kw = self.w.keyword("OFFSET");
        self.w.out.push_str(&kw);
        for &x in o {
            self.w.gap();
            self.w.out.push_str(&number_text(x).0);
        }
        self.w.end_line();
    }
}

fn check(take: &Take) {
    let style = &take.style;
    let mut r = Render {
        w: Writer { out: String::new(), line: 1, style, gap_i: 0, end_i: 0 },
        expected: Vec::new(),
        fault: take.fault,
        planted: Planted::default(),
        max_depth: 0,
        end_sites: Vec::new(),
    };
    if style.bom {
        r.w.out.push('\u{feff}');
    }
    r.w.out.push_str(&r.w.keyword("HIERARCHY"));
    r.w.end_line();
    let roots: Vec<&Node> = take.roots.iter().take(4).collect();
    if roots.is_empty() {
        return;
    }
    for n in &roots {
        r.node(n, None, 0);
    }
    let per_row: usize = r.expected.iter().map(|e| e.channels.len()).sum();
    let nodes = r.expected.len();
    let rows: Vec<Vec<(String, f64)>> = if per_row == 0 {
        Vec::new()
    } else {
        take.rows
            .iter()
            .take(64)
            .map(|row| {
                (0..per_row)
                    .map(|i| number_text(row.get(i).copied().unwrap_or(Number { value: 0.0, format: 0 })))
                    .collect()
            })
            .collect()
    };
    let value_count = rows.len() * per_row;
    let declared = match take.declared {
        Declared::Rows => rows.len(),
        Declared::Other(n) => n as usize,
    };

    r.w.out.push_str(&r.w.keyword("MOTION"));
    r.w.end_line();
    let frames_kw = r.w.keyword("Frames");
    r.w.out.push_str(&frames_kw);
    r.w.out.push(':');
    if !style.glued_frames {
        r.w.gap();
    }
    if matches!(take.fault, Some(Fault::NegativeFrames)) && r.planted.line.is_none() {
        r.planted = Planted { line: Some(r.w.line), column: Some(r.w.column()) };
        r.w.out.push('-');
    }
    r.w.out.push_str(&declared.to_string());
    r.w.end_line();
    let time_kw = r.w.keyword("Frame Time");
    r.w.out.push_str(&time_kw);
    r.w.out.push(':');
    r.w.gap();
    // any positive finite frame time as written (its sign dropped; 0 becomes 120 fps)
    let mut frame_time_text = number_text(take.frame_time).0.trim_start_matches('-').to_string();
    let mut frame_time: f64 = frame_time_text.parse().expect("a number");
    if !(frame_time > 0.0) {
        frame_time_text = "0.0083333".into();
        frame_time = 0.0083333;
    }
    if let (Some(Fault::FrameTime(k)), None) = (take.fault, r.planted.line) {
        frame_time_text = ["0", "-0.01", "NaN", "inf", "0.0", "-1e-300"][k as usize % 6].to_string();
        r.planted = Planted { line: Some(r.w.line), column: Some(r.w.column()) };
    }
    r.w.out.push_str(&frame_time_text);
    r.w.end_line();

    // the rows, and where a value fault lands
    let value_fault = match take.fault {
        Some(Fault::Value { at, kind }) if value_count > 0 && r.planted.line.is_none() => {
            let at = at as usize % value_count;
            // one value too many goes after the last value of its row
            let at = if matches!(kind, ValueFault::Extra) { at / per_row * per_row + per_row - 1 } else { at };
            Some((at, kind))
        }
        _ => None,
    };
    let short_row = match take.fault {
        // (a row of one value made short is a blank line, which is skipped: not a fault)
        Some(Fault::ShortRow { row }) if rows.len() >= 2 && per_row >= 2 && r.planted.line.is_none() => {
            Some(row as usize % (rows.len() - 1))
        }
        _ => None,
    };
    for (ri, row) in rows.iter().enumerate() {
        for (ci, (text, _)) in row.iter().enumerate() {
            if ci > 0 {
                r.w.gap();
            }
            if short_row == Some(ri) && ci + 1 == row.len() {
                r.planted = Planted { line: Some(r.w.line), column: None };
                break;
            }
            match value_fault {
                Some((at, kind)) if at == ri * per_row + ci => {
                    r.planted = Planted { line: Some(r.w.line), column: Some(r.w.column()) };
                    match kind {
                        ValueFault::Nan => r.w.out.push_str("NaN"),
                        ValueFault::Infinite => r.w.out.push_str("-inf"),
                        ValueFault::Word => r.w.out.push_str("x1"),
                        ValueFault::Extra => {
                            r.w.out.push_str(text);
                            r.w.gap();
                            r.planted.column = Some(r.w.column());
                            r.w.out.push_str("7");
                        }
                    }
                }
                _ => r.w.out.push_str(text),
            }
        }
        r.w.end_line();
    }
    let truncated = take.truncated_tail && per_row >= 2 && r.planted.line.is_none();
    if truncated {
        r.w.out.push_str(&rows.first().map(|row| row[0].0.clone()).unwrap_or_else(|| "0".into()));
        r.w.end_line();
    }
    for _ in 0..take.style.trailing_blank_lines % 3 {
        r.w.end_line();
    }

    let text = r.w.out;
    let result = bvh::parse(&text);
    let too_deep = r.max_depth > bvh::ParseLimits::default().max_depth;
    let planted = r.planted;
    if too_deep {
        assert!(result.is_err(), "a tree deeper than the limit parsed");
        return;
    }
    if let Some(line) = planted.line {
        let e = match result {
            Ok(_) => panic!("a planted fault on line {line} was accepted:\n{text}"),
            Err(e) => e,
        };
        assert_eq!(e.line, line, "{e}\n{text}");
        if let Some(column) = planted.column {
            assert_eq!(e.column, column, "{e}\n{text}");
        }
        return;
    }
    if per_row > 0 && rows.is_empty() && declared > 0 {
        // declares frames, has none (and no partial row either, or only one): refused
        let e = result.expect_err("frames declared, none present");
        assert!(e.message.contains("frame") || e.message.contains("row"), "{e}");
        return;
    }
    if per_row > 0 && rows.is_empty() && truncated {
        // only a partial row and `Frames: 0`: either reading is defensible; it must not panic
        return;
    }
    let b = result.unwrap_or_else(|e| panic!("a valid take was refused: {e}\n{text}"));
    assert_eq!(b.joints.len(), nodes);
    for (i, (j, e)) in b.joints.iter().zip(&r.expected).enumerate() {
        assert_eq!(j.name, e.name, "node {i}");
        assert_eq!((j.kind, j.parent), (e.kind, e.parent), "node {i}");
        assert_eq!(j.channels, e.channels, "node {i}");
        let bits = |o: &[f64; 3]| o.map(f64::to_bits);
        assert_eq!(bits(&j.offset), bits(&e.offset), "offset of node {i}: {:?} vs {:?}", j.offset, e.offset);
    }
    assert_eq!(b.frame_time.to_bits(), frame_time.to_bits(), "frame time {} vs {frame_time}", b.frame_time);
    assert_eq!(b.channels_per_frame, per_row);
    if per_row == 0 {
        assert_eq!(b.frames(), declared.min(1));
        return;
    }
    assert_eq!(b.frames(), rows.len(), "{text}");
    for (ri, row) in rows.iter().enumerate() {
        for (ci, (t, v)) in row.iter().enumerate() {
            let got = b.values[ri * per_row + ci];
            assert_eq!(got.to_bits(), v.to_bits(), "row {ri} value {ci}: `{t}` read as {got}, expected {v}");
        }
    }
    if truncated {
        assert!(!b.warnings.is_empty(), "a dropped partial row gave no warning");
    } else {
        let disagrees = declared != rows.len();
        let warned = b.warnings.iter().any(|w| w.message.contains("Frames:"));
        assert_eq!(disagrees, warned, "declared {declared}, rows {}: {:?}", rows.len(), b.warnings);
    }
}

/// One input of the target (what `fuzz_targets/bvh_grammar.rs` hands libFuzzer's bytes to).
pub fn run(data: &[u8]) {
    let mut u = Unstructured::new(data);
    if let Ok(take) = Take::arbitrary(&mut u) {
        check(&take);
    }
}

/// The target's seeds, `(name, bytes)`.
pub fn seeds() -> Vec<(String, Vec<u8>)> {
    Vec::new()
}
