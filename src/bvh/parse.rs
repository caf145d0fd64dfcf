//! The BVH (Biovision Hierarchy) parser.
//!
//! Implements the format as exporters actually write it:
//!
//! * `HIERARCHY`, then one or more `ROOT` trees of `JOINT`s and `End Site`s, each with an
//!   `OFFSET` (3 numbers) and, except End Sites, a `CHANNELS n c1 … cn` line with any of the six
//!   channels in any order (rotation-before-position roots, position channels on non-root
//!   joints). `OFFSET` and `CHANNELS` may come in either order but before the children.
//! * `MOTION`, `Frames: n`, `Frame Time: t`, then one row of values per line. The frame time is
//!   kept at full `f64` precision (`0.0417083750417`, 23.976 fps, stays exactly that).
//! * Tabs or runs of spaces between tokens; LF, CRLF, lone CR or mixed line endings; a UTF-8 BOM;
//!   scientific notation; names with colons or spaces (`mixamorig:Hips`, `Left Arm`; a name runs
//!   to the end of its line or to a `{`); `Frames:<TAB>455`, `Frames:455`, `.0083333`; keywords
//!   and channel names in any letter case; `{` / `}` glued to other text; trailing blank lines.
//! * End Sites become nodes of kind [`JointKind::EndSite`] named `<parent>_End` (`<parent>_End2`,
//!   … if a joint has several), with no channels.
//!
//! Frame rows:
//! * A `Frames:` count that disagrees with the complete rows present gives a [`Warning`] naming
//!   both numbers; the rows present are used.
//! * A row with too many values, a non-numeric, NaN or infinite value is an error naming the
//!   line and column of the token. A row with too few values is an error, except when it is the
//!   last non-blank line of the file: that is how a truncated download ends, so the incomplete
//!   row is dropped with a warning and all complete rows are kept. A file that declares frames
//!   but has no complete row at all is an error.
//! * A hierarchy with no channels has no data rows: it describes one pose (the rest pose), so it
//!   gives at most 1 frame whatever `Frames:` says, with a [`Warning`] naming the `Frames:` line
//!   if that says more.
//!
//! Every error is a [`BvhError`] naming the 1-based line and column (in characters) and what was
//! expected there. The parser never panics, is linear in the input, and allocates no more than a
//! constant times the input size, bounded further by [`ParseLimits`]. Numbers are read with a
//! correctly rounded fast path for plain decimals (Clinger's: an integer below 2^53 divided by an
//! exact power of ten) and `str::parse::<f64>` for everything else, so every value is the exact
//! nearest `f64`, and no `String` is allocated per token.

use super::{Bvh, BvhError, BvhJoint, Channel, JointKind, Warning};

/// Upper bounds that keep any input from allocating without bound, and what a take must have.
/// The loader (`crate::load`) derives its limits from its memory budget; docs/development.md "Limits" lists
/// them all.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ParseLimits {
    /// Maximum number of hierarchy nodes (joints and End Sites together).
    pub max_joints: usize,
    /// Maximum nesting depth of the hierarchy (a root is depth 1, its End Sites count too).
    pub max_depth: usize,
    /// Maximum number of channel values in the MOTION section (frames × channels).
    pub max_values: usize,
    /// Bytes the parsed take may occupy, the text included, or `usize::MAX` for no such bound.
    /// With [`ParseLimits::bytes_per_node_frame`] it bounds the frames: each frame costs its
    /// values (8 bytes each) plus that many bytes per node, and reading stops with an error at
    /// the first row past the budget, before anything is allocated for it.
    pub max_bytes: usize,
    /// What each frame will cost per node after parsing (world positions, pictures: the
    /// loader's estimate), counted against [`ParseLimits::max_bytes`].
    pub bytes_per_node_frame: usize,
    /// Takes with fewer frames are refused (the loader needs 1: a skeleton with no motion
    /// has nothing to play or segment). 0 accepts a file that ends after its hierarchy as a
    /// skeleton with no motion.
    pub min_frames: usize,
}

impl Default for ParseLimits {
    /// 10 000 nodes, depth 256, 2^27 ≈ 134 million values (1 GiB of `f64`: e.g. 300 channels
    /// for 5 hours at 120 fps), no byte budget, 0 frames accepted.
    fn default() -> Self {
        ParseLimits {
            max_joints: 10_000,
            max_depth: 256,
            max_values: 1 << 27,
            max_bytes: usize::MAX,
            bytes_per_node_frame: 0,
            min_frames: 0,
        }
    }
}

/// The frame time given to a skeleton with no `MOTION` section (it has no frame rate).
pub const NO_MOTION_FRAME_TIME: f64 = 1.0 / 30.0;

/// Parses BVH text with the default [`ParseLimits`].
pub fn parse(text: &str) -> Result<Bvh, BvhError> {
    parse_with_progress(text, &ParseLimits::default(), &mut |_| {})
}

/// Parses BVH text, calling `progress` with the fraction 0..1 of the file read (every 2 % of the
/// MOTION section, and 1.0 at the end).
pub fn parse_with_progress(text: &str, limits: &ParseLimits, progress: &mut dyn FnMut(f64)) -> Result<Bvh, BvhError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut lx = Lexer::new(text);
    let mut warnings = Vec::new();
    let (joints, motion_section) = parse_hierarchy(&mut lx, limits, &mut warnings)?;
    let channels_per_frame = joints.iter().map(|j| j.channels.len()).sum();
    if !motion_section {
        return skeleton_only(&lx, joints, channels_per_frame, limits, warnings);
    }
    let header = parse_motion_header(&mut lx)?;
    let total = text.len().max(1) as f64;
    let mut report = |done: usize| progress(done as f64 / total);
    report(lx.pos);
    let budget = FrameBudget::new(text.len(), channels_per_frame, joints.len(), header.frame_time, limits);
    let rows = RowReader::new(text, lx.pos, lx.line, channels_per_frame, header.frames, limits, budget);
    let (values, row_warning) = rows.read(&mut report)?;
    progress(1.0);
    // A file that declares frames but has none is refused below as truncated; this is the one
    // that declares none.
    let present = values.len().checked_div(channels_per_frame).unwrap_or(header.frames.min(1));
    if header.frames == 0 && present < limits.min_frames {
        return Err(BvhError::new(
            header.frames_line,
            header.frames_column,
            "the take has no frames (`Frames: 0`): a skeleton with no motion, so there is nothing to play or segment",
        ));
    }
    if channels_per_frame == 0 {
        // No channels, no data rows: every frame would be the rest pose, so a `Frames:` count
        // has nothing behind it and must not become that many frames (33 M frames from a
        // 100-byte file). One frame is all such a file describes.
        if header.frames > 1 {
            warnings.push(Warning {
                line: header.frames_line,
                message: format!(
                    "`Frames:` says {} but the hierarchy declares no channels, so the file has no data rows; \
                     using 1 frame (the rest pose)",
                    header.frames
                ),
            });
        }
        return Ok(Bvh {
            joints,
            frame_time: header.frame_time,
            declared_frames: header.frames,
            channels_per_frame,
            values,
            warnings,
        });
    }
    let present = values.len() / channels_per_frame;
    if header.frames > 0 && present == 0 {
        return Err(lx.error_at_end(format!(
            "`Frames:` declares {} frames but the file has no complete frame row (truncated file?)",
            header.frames
        )));
    }
    warnings.extend(row_warning);
    if present != header.frames {
        warnings.push(Warning {
            line: header.frames_line,
            message: format!(
                "`Frames:` says {} but the file has {} complete data rows; using the {} rows present",
                header.frames, present, present
            ),
        });
    }
    Ok(Bvh {
        joints,
        frame_time: header.frame_time,
        declared_frames: header.frames,
        channels_per_frame,
        values,
        warnings,
    })
}

/// A file that ends after a complete hierarchy: a skeleton with no motion (0 frames, frame
/// time [`NO_MOTION_FRAME_TIME`], a warning saying so), or an error where frames are required.
fn skeleton_only(
    lx: &Lexer<'_>,
    joints: Vec<BvhJoint>,
    channels_per_frame: usize,
    limits: &ParseLimits,
    mut warnings: Vec<Warning>,
) -> Result<Bvh, BvhError> {
    if limits.min_frames > 0 {
        return Err(lx.error_at_end(
            "the file ends after its hierarchy (no `MOTION` section): a skeleton with no motion, \
             so there is nothing to play or segment",
        ));
    }
    warnings.push(Warning {
        line: lx.line,
        message: "the file ends after its hierarchy (no `MOTION` section): a skeleton with no motion (0 frames)"
            .to_string(),
    });
    Ok(Bvh {
        joints,
        frame_time: NO_MOTION_FRAME_TIME,
        declared_frames: 0,
        channels_per_frame,
        values: Vec::new(),
        warnings,
    })
}

/// How many frames fit in [`ParseLimits::max_bytes`], and the words to say so when a file has more.
#[derive(Debug, Clone, Copy)]
pub(crate) struct FrameBudget {
    pub(crate) max_frames: usize,
    frame_bytes: usize,
    max_bytes: usize,
    nodes: usize,
    frame_time: f64,
}

impl FrameBudget {
    pub(crate) fn new(text_bytes: usize, channels: usize, nodes: usize, frame_time: f64, limits: &ParseLimits) -> Self {
        let frame_bytes = channels.saturating_mul(8).saturating_add(nodes.saturating_mul(limits.bytes_per_node_frame));
        let room = limits.max_bytes.saturating_sub(text_bytes);
        let max_frames = if limits.max_bytes == usize::MAX { usize::MAX } else { room / frame_bytes.max(1) };
        FrameBudget { max_frames, frame_bytes, max_bytes: limits.max_bytes, nodes, frame_time }
    }

    pub(crate) fn message(&self) -> String {
        let minutes = self.max_frames as f64 * self.frame_time / 60.0;
        format!(
            "the take is too large for the memory budget of {} MiB: a frame of this {}-node skeleton needs about {} bytes \
             once loaded, so at most {} frames ({minutes:.1} minutes at this frame rate) fit beside the file itself; \
             this row would be frame {} — cut the take",
            self.max_bytes.div_ceil(1 << 20),
            self.nodes,
            self.frame_bytes,
            self.max_frames,
            self.max_frames.saturating_add(1)
        )
    }
}

// ---------------------------------------------------------------------------------------------
// Lexer
// ---------------------------------------------------------------------------------------------

/// A token of the header: a run of non-whitespace bytes, or a single `{` / `}`.
#[derive(Debug, Clone, Copy)]
struct Tok<'a> {
    text: &'a str,
    /// Byte offset of the token in the text.
    start: usize,
    line: usize,
    /// Byte offset of the start of the token's line.
    line_start: usize,
}

impl Tok<'_> {
    fn is(&self, keyword: &str) -> bool {
        self.text.eq_ignore_ascii_case(keyword)
    }
}

/// A cursor over the text that counts lines (LF, CRLF and lone CR each end one line).
#[derive(Debug, Clone, Copy)]
struct Lexer<'a> {
    text: &'a str,
    pos: usize,
    line: usize,
    line_start: usize,
}

impl<'a> Lexer<'a> {
    fn new(text: &'a str) -> Self {
        Lexer { text, pos: 0, line: 1, line_start: 0 }
    }

    fn bytes(&self) -> &'a [u8] {
        self.text.as_bytes()
    }

    /// Steps over one line break at `pos` (which must be `\r` or `\n`).
    fn newline(&mut self) {
        let b = self.bytes();
        self.pos += if b[self.pos] == b'\r' && b.get(self.pos + 1) == Some(&b'\n') { 2 } else { 1 };
        self.line += 1;
        self.line_start = self.pos;
    }

    fn skip_whitespace(&mut self) {
        while let Some(&c) = self.bytes().get(self.pos) {
            match c {
                b'\n' | b'\r' => self.newline(),
                c if c.is_ascii_whitespace() => self.pos += 1,
                _ => break,
            }
        }
    }

    /// Skips spaces and tabs but not line breaks.
    fn skip_blanks(&mut self) {
        while let Some(&c) = self.bytes().get(self.pos) {
            if c.is_ascii_whitespace() && c != b'\n' && c != b'\r' {
                self.pos += 1;
            } else {
                break;
            }
        }
    }

    fn tok(&self, start: usize, end: usize) -> Tok<'a> {
        Tok { text: &self.text[start..end], start, line: self.line, line_start: self.line_start }
    }

    fn next(&mut self) -> Option<Tok<'a>> {
        self.skip_whitespace();
        let b = self.bytes();
        let start = self.pos;
        let first = *b.get(start)?;
        if first == b'{' || first == b'}' {
            self.pos += 1;
        } else {
            while let Some(&c) = b.get(self.pos) {
                if c.is_ascii_whitespace() || c == b'{' || c == b'}' {
                    break;
                }
                self.pos += 1;
            }
        }
        Some(self.tok(start, self.pos))
    }

    fn peek(&self) -> Option<Tok<'a>> {
        let mut copy = *self;
        copy.next()
    }

    /// The rest of the current line up to a `{` or `}` (not consumed), trimmed: a joint name.
    /// Returns `None` if it is empty.
    fn name(&mut self) -> Option<Tok<'a>> {
        self.skip_blanks();
        let b = self.bytes();
        let start = self.pos;
        while let Some(&c) = b.get(self.pos) {
            if matches!(c, b'\n' | b'\r' | b'{' | b'}') {
                break;
            }
            self.pos += 1;
        }
        let end = start + self.text[start..self.pos].trim_end().len();
        (end > start).then(|| self.tok(start, end))
    }

    fn error_at(&self, tok: &Tok<'_>, message: impl Into<String>) -> BvhError {
        BvhError::new(tok.line, column(self.text, tok.line_start, tok.start), message)
    }

    /// An error at the current position (e.g. the end of a line that lacks something).
    fn error_here(&self, message: impl Into<String>) -> BvhError {
        BvhError::new(self.line, column(self.text, self.line_start, self.pos), message)
    }

    fn error_at_end(&self, message: impl Into<String>) -> BvhError {
        let mut end = *self;
        while end.pos < end.text.len() {
            match end.bytes()[end.pos] {
                b'\n' | b'\r' => end.newline(),
                _ => end.pos += 1,
            }
        }
        end.error_here(message)
    }
}

/// 1-based column, in characters, of byte offset `at` on the line starting at `line_start`.
fn column(text: &str, line_start: usize, at: usize) -> usize {
    text.get(line_start..at).map_or(1, |s| s.chars().count() + 1)
}

/// How a token is shown in an error message: in backticks, control characters escaped,
/// cut after 40 characters.
fn show(tok: Option<&Tok<'_>>) -> String {
    match tok {
        None => "end of file".to_string(),
        Some(t) => {
            let shown: String = t.text.chars().take(40).flat_map(char::escape_debug).collect();
            let cut = if t.text.chars().nth(40).is_some() { "…" } else { "" };
            format!("`{shown}{cut}`")
        }
    }
}

// ---------------------------------------------------------------------------------------------
// HIERARCHY
// ---------------------------------------------------------------------------------------------

/// A node whose `{` is open while its body is read.
struct Open {
    index: usize,
    seen_offset: bool,
    seen_channels: bool,
    children_started: bool,
    end_sites: usize,
}

impl Open {
    fn new(index: usize) -> Self {
        Open { index, seen_offset: false, seen_channels: false, children_started: false, end_sites: 0 }
    }
}

/// Reads `HIERARCHY` and all `ROOT` trees, up to and including `MOTION`. The flag is false when
/// the file ends after a complete hierarchy instead (a skeleton with no motion).
fn parse_hierarchy(
    lx: &mut Lexer<'_>,
    limits: &ParseLimits,
    warnings: &mut Vec<Warning>,
) -> Result<(Vec<BvhJoint>, bool), BvhError> {
    match lx.next() {
        Some(t) if t.is("HIERARCHY") => {}
        None => return Err(lx.error_here("expected `HIERARCHY`, found end of file (the file is empty)")),
        Some(t) => {
            return Err(
                lx.error_at(&t, format!("expected `HIERARCHY` at the start of a BVH file, found {}", show(Some(&t))))
            )
        }
    }
    let mut tree = Tree { joints: Vec::new(), lines: Vec::new(), channels: 0, limits };
    let motion_section = loop {
        let tok = lx.next();
        match tok {
            Some(t) if t.is("ROOT") => tree.parse_root(lx, &t)?,
            Some(t) if t.is("MOTION") => {
                if tree.joints.is_empty() {
                    return Err(lx.error_at(&t, "expected `ROOT` before `MOTION`: the hierarchy has no joints"));
                }
                break true;
            }
            Some(t) if t.text == "}" => {
                return Err(lx.error_at(&t, "unbalanced braces: this `}` closes nothing; expected `ROOT` or `MOTION`"))
            }
            None if tree.joints.is_empty() => {
                return Err(lx.error_here("expected `ROOT`, found end of file (truncated file?)"))
            }
            None => break false,
            Some(t) => {
                let what = if tree.joints.is_empty() { "`ROOT`" } else { "`ROOT` or `MOTION`" };
                return Err(lx.error_at(&t, format!("expected {what}, found {}", show(Some(&t)))));
            }
        }
    };
    warn_duplicate_names(&tree.joints, &tree.lines, warnings);
    Ok((tree.joints, motion_section))
}

/// The hierarchy being built.
struct Tree<'l> {
    joints: Vec<BvhJoint>,
    /// Line of each node's keyword (for warnings).
    lines: Vec<usize>,
    /// Channels declared so far (the next joint's `channel_start`).
    channels: usize,
    limits: &'l ParseLimits,
}

impl Tree<'_> {
    fn add(&mut self, lx: &Lexer<'_>, at: &Tok<'_>, node: BvhJoint) -> Result<usize, BvhError> {
        if self.joints.len() >= self.limits.max_joints {
            return Err(lx.error_at(
                at,
                format!("too many joints: the limit is {} (joints and End Sites)", self.limits.max_joints),
            ));
        }
        self.joints.push(node);
        self.lines.push(at.line);
        Ok(self.joints.len() - 1)
    }

    /// Refuses a child (at `at`) of a node `open` levels deep when that passes the depth limit.
    fn check_depth(&self, lx: &Lexer<'_>, at: &Tok<'_>, open: usize) -> Result<(), BvhError> {
        if open < self.limits.max_depth {
            return Ok(());
        }
        Err(lx.error_at(
            at,
            format!(
                "the hierarchy nests too deep: the limit is {} levels (a root is level 1; real skeletons have fewer than 30)",
                self.limits.max_depth
            ),
        ))
    }

    fn name_of(&self, open: &Open) -> &str {
        &self.joints[open.index].name
    }

    /// Reads one `ROOT` tree (the `ROOT` keyword already read) without recursion.
    fn parse_root(&mut self, lx: &mut Lexer<'_>, keyword: &Tok<'_>) -> Result<(), BvhError> {
        let name = read_name(lx, "ROOT")?;
        let index = self.add(lx, keyword, node(name, JointKind::Root, None, self.channels))?;
        expect_open(lx, "ROOT name")?;
        let mut stack = vec![Open::new(index)];
        while let Some(top) = stack.last_mut() {
            let tok = lx.next();
            let kind = self.joints[top.index].kind;
            let Some(t) = tok else {
                let name = &self.joints[top.index].name;
                return Err(lx.error_here(format!(
                    "expected `}}` closing {} `{name}`, found end of file (truncated file or unbalanced braces)",
                    kind_word(kind)
                )));
            };
            if kind == JointKind::EndSite {
                if t.text == "}" {
                    let open = stack.pop().expect("stack is not empty");
                    self.require_offset(lx, &open, &t)?;
                } else if t.is("OFFSET") && !top.seen_offset {
                    top.seen_offset = true;
                    self.joints[top.index].offset = read_offset(lx)?;
                } else {
                    let parent = self.joints[top.index].parent.map_or("", |p| self.joints[p].name.as_str());
                    return Err(lx.error_at(
                        &t,
                        format!("expected `OFFSET` or `}}` in the End Site of `{parent}`, found {}", show(Some(&t))),
                    ));
                }
                continue;
            }
            if t.text == "}" {
                let open = stack.pop().expect("stack is not empty");
                self.require_offset(lx, &open, &t)?;
            } else if t.is("OFFSET") || t.is("CHANNELS") {
                let top = stack.last_mut().expect("stack is not empty");
                self.read_property(lx, top, &t)?;
            } else if t.is("JOINT") {
                let top = stack.last_mut().expect("stack is not empty");
                self.require_offset(lx, top, &t)?;
                top.children_started = true;
                let parent = top.index;
                self.check_depth(lx, &t, stack.len())?;
                let name = read_name(lx, "JOINT")?;
                let index = self.add(lx, &t, node(name, JointKind::Joint, Some(parent), self.channels))?;
                expect_open(lx, "JOINT name")?;
                stack.push(Open::new(index));
            } else if t.is("End") {
                let top = stack.last_mut().expect("stack is not empty");
                self.require_offset(lx, top, &t)?;
                top.children_started = true;
                top.end_sites += 1;
                let parent = top.index;
                let suffix = if top.end_sites == 1 { String::new() } else { top.end_sites.to_string() };
                self.check_depth(lx, &t, stack.len())?;
                match lx.next() {
                    Some(s) if s.is("Site") => {}
                    other => {
                        return Err(match other {
                            Some(s) => {
                                lx.error_at(&s, format!("expected `Site` after `End`, found {}", show(Some(&s))))
                            }
                            None => lx.error_here("expected `Site` after `End`, found end of file"),
                        })
                    }
                }
                let name = format!("{}_End{suffix}", self.joints[parent].name);
                let index = self.add(lx, &t, node(name, JointKind::EndSite, Some(parent), self.channels))?;
                expect_open(lx, "`End Site`")?;
                stack.push(Open::new(index));
            } else {
                let top = stack.last().expect("stack is not empty");
                return Err(self.unexpected_in_joint(lx, top, &t));
            }
        }
        Ok(())
    }

    /// Reads `OFFSET x y z` or `CHANNELS n …` in the body of a ROOT/JOINT.
    fn read_property(&mut self, lx: &mut Lexer<'_>, top: &mut Open, t: &Tok<'_>) -> Result<(), BvhError> {
        let keyword = if t.is("OFFSET") { "OFFSET" } else { "CHANNELS" };
        let seen = if keyword == "OFFSET" { &mut top.seen_offset } else { &mut top.seen_channels };
        let name = &self.joints[top.index].name;
        if *seen {
            return Err(lx.error_at(t, format!("second `{keyword}` in joint `{name}`: expected one")));
        }
        if top.children_started {
            return Err(
                lx.error_at(t, format!("`{keyword}` of joint `{name}` must come before its JOINT / End Site children"))
            );
        }
        *seen = true;
        if keyword == "OFFSET" {
            self.joints[top.index].offset = read_offset(lx)?;
        } else {
            let channels = read_channels(lx, name)?;
            let joint = &mut self.joints[top.index];
            joint.channel_start = self.channels;
            self.channels += channels.len();
            joint.channels = channels;
        }
        Ok(())
    }

    fn require_offset(&self, lx: &Lexer<'_>, open: &Open, at: &Tok<'_>) -> Result<(), BvhError> {
        if open.seen_offset {
            return Ok(());
        }
        let j = &self.joints[open.index];
        let what = match j.kind {
            JointKind::EndSite => {
                format!("the End Site of `{}`", j.parent.map_or("", |p| self.joints[p].name.as_str()))
            }
            kind => format!("{} `{}`", kind_word(kind), j.name),
        };
        Err(lx.error_at(at, format!("expected `OFFSET` in {what} before {}", show(Some(at)))))
    }

    fn unexpected_in_joint(&self, lx: &Lexer<'_>, open: &Open, t: &Tok<'_>) -> BvhError {
        let name = self.name_of(open);
        let expected = "expected `OFFSET`, `CHANNELS`, `JOINT`, `End Site` or `}`";
        let message = if t.is("ROOT") || t.is("MOTION") {
            format!("unbalanced braces: found {} but joint `{name}` is still open; expected `}}`", show(Some(t)))
        } else if number(t.text).is_some() {
            format!(
                "unexpected number {} in joint `{name}`: `OFFSET` takes 3 numbers and `CHANNELS` a count and that many channel names; {expected}",
                show(Some(t))
            )
        } else if parse_channel(t.text).is_some() {
            format!(
                "unexpected channel name {} in joint `{name}`: more channel names than the `CHANNELS` count says",
                show(Some(t))
            )
        } else {
            format!("unknown keyword {} in joint `{name}`: {expected}", show(Some(t)))
        };
        lx.error_at(t, message)
    }
}

fn node(name: String, kind: JointKind, parent: Option<usize>, channel_start: usize) -> BvhJoint {
    BvhJoint { name, kind, parent, offset: [0.0; 3], channels: Vec::new(), channel_start }
}

fn kind_word(kind: JointKind) -> &'static str {
    match kind {
        JointKind::Root => "ROOT",
        JointKind::Joint => "JOINT",
        JointKind::EndSite => "End Site",
    }
}

fn read_name(lx: &mut Lexer<'_>, keyword: &str) -> Result<String, BvhError> {
    match lx.name() {
        Some(t) => Ok(t.text.to_string()),
        None => Err(lx.error_here(format!("expected a joint name after `{keyword}` on the same line"))),
    }
}

fn expect_open(lx: &mut Lexer<'_>, after: &str) -> Result<(), BvhError> {
    match lx.next() {
        Some(t) if t.text == "{" => Ok(()),
        Some(t) => Err(lx.error_at(&t, format!("expected `{{` after {after}, found {}", show(Some(&t))))),
        None => Err(lx.error_here(format!("expected `{{` after {after}, found end of file"))),
    }
}

fn read_offset(lx: &mut Lexer<'_>) -> Result<[f64; 3], BvhError> {
    let mut offset = [0.0; 3];
    for (i, slot) in offset.iter_mut().enumerate() {
        let tok = lx.next();
        *slot = match tok.as_ref().map(|t| (t, number(t.text))) {
            Some((_, Some(v))) if v.is_finite() => v,
            Some((t, Some(_))) => {
                return Err(lx.error_at(t, format!("`OFFSET` value {} is not a finite number", show(Some(t)))))
            }
            Some((t, None)) => {
                return Err(
                    lx.error_at(t, format!("expected 3 numbers after `OFFSET`, found {} after {i}", show(Some(t))))
                )
            }
            None => {
                return Err(lx.error_here(format!("expected 3 numbers after `OFFSET`, found end of file after {i}")))
            }
        };
    }
    Ok(offset)
}

fn parse_channel(s: &str) -> Option<Channel> {
    Channel::ALL.into_iter().find(|c| c.name().eq_ignore_ascii_case(s))
}

/// Reads `n c1 … cn` after `CHANNELS`.
fn read_channels(lx: &mut Lexer<'_>, joint: &str) -> Result<Vec<Channel>, BvhError> {
    let count = match lx.next() {
        None => return Err(lx.error_here("expected the channel count after `CHANNELS`, found end of file")),
        Some(t) => match t.text.parse::<usize>() {
            Ok(n) if n <= 6 => n,
            _ => {
                return Err(lx.error_at(
                    &t,
                    format!("expected a channel count from 0 to 6 after `CHANNELS`, found {}", show(Some(&t))),
                ))
            }
        },
    };
    let mut channels = Vec::with_capacity(count);
    for i in 0..count {
        let tok = lx.next();
        match tok.map(|t| (t, parse_channel(t.text))) {
            Some((t, Some(c))) if channels.contains(&c) => {
                return Err(lx.error_at(&t, format!("channel `{}` listed twice for joint `{joint}`", c.name())))
            }
            Some((_, Some(c))) => channels.push(c),
            _ => {
                let message = format!(
                    "`CHANNELS {count}` of joint `{joint}` needs {count} channel names (Xposition, Yposition, Zposition, Xrotation, Yrotation, Zrotation), found {} after {i}",
                    show(tok.as_ref())
                );
                return Err(match tok {
                    Some(t) => lx.error_at(&t, message),
                    None => lx.error_here(message),
                });
            }
        }
    }
    if let Some(t) = lx.peek().filter(|t| parse_channel(t.text).is_some()) {
        return Err(lx.error_at(
            &t,
            format!(
                "`CHANNELS {count}` of joint `{joint}` is followed by more channel names than {count}: {}",
                show(Some(&t))
            ),
        ));
    }
    Ok(channels)
}

fn warn_duplicate_names(joints: &[BvhJoint], lines: &[usize], warnings: &mut Vec<Warning>) {
    let mut first: std::collections::HashMap<&str, usize> = std::collections::HashMap::new();
    for (i, j) in joints.iter().enumerate() {
        if let Some(&k) = first.get(j.name.as_str()) {
            warnings.push(Warning {
                line: lines[i],
                message: format!("joint name `{}` is used again (first on line {})", j.name, lines[k]),
            });
        } else {
            first.insert(&j.name, i);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// MOTION header
// ---------------------------------------------------------------------------------------------

struct MotionHeader {
    frames: usize,
    frames_line: usize,
    /// Column of the frame count.
    frames_column: usize,
    frame_time: f64,
}

fn parse_motion_header(lx: &mut Lexer<'_>) -> Result<MotionHeader, BvhError> {
    let frames_tok = label_value(lx, &["Frames"], "`Frames:` after `MOTION`")?;
    let frames = parse_frame_count(lx, &frames_tok)?;
    let time_tok = label_value(lx, &["Frame", "Time"], "`Frame Time:` after `Frames:`")?;
    let frame_time = match number(time_tok.text) {
        Some(t) if t.is_finite() && t > 0.0 => t,
        Some(_) => {
            return Err(lx.error_at(
                &time_tok,
                format!("`Frame Time:` must be a positive finite number of seconds, found {}", show(Some(&time_tok))),
            ))
        }
        None => {
            return Err(lx.error_at(
                &time_tok,
                format!("expected seconds per frame after `Frame Time:`, found {}", show(Some(&time_tok))),
            ))
        }
    };
    let frames_column = column(lx.text, frames_tok.line_start, frames_tok.start);
    Ok(MotionHeader { frames, frames_line: frames_tok.line, frames_column, frame_time })
}

fn parse_frame_count(lx: &Lexer<'_>, tok: &Tok<'_>) -> Result<usize, BvhError> {
    let digits = tok.text.strip_prefix('+').unwrap_or(tok.text);
    if !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit()) {
        return digits
            .parse::<usize>()
            .map_err(|_| lx.error_at(tok, format!("frame count {} after `Frames:` is too large", show(Some(tok)))));
    }
    let why = if tok.text.starts_with('-') { " (it must not be negative)" } else { "" };
    Err(lx.error_at(tok, format!("expected a whole number of frames after `Frames:`{why}, found {}", show(Some(tok)))))
}

/// Reads a label such as `Frames:` or `Frame Time:` (words in any case, the colon may be
/// separated by blanks or glued to the value) and returns the value token.
fn label_value<'a>(lx: &mut Lexer<'a>, words: &[&str], expected: &str) -> Result<Tok<'a>, BvhError> {
    let mut rest: Option<Tok<'a>> = None;
    for (i, word) in words.iter().enumerate() {
        let tok = lx.next();
        let ok = tok.filter(|t| {
            let prefix = t.text.get(..word.len());
            let glued_ok = i + 1 == words.len() || t.text.len() == word.len();
            prefix.is_some_and(|p| p.eq_ignore_ascii_case(word)) && glued_ok
        });
        match ok {
            Some(t) => rest = Some(sub_tok(&t, word.len())),
            None => {
                let found = show(tok.as_ref());
                let message = format!("expected {expected}, found {found}");
                return Err(match tok {
                    Some(t) => lx.error_at(&t, message),
                    None => lx.error_here(message),
                });
            }
        }
    }
    let mut rest = rest.expect("words is not empty");
    if rest.text.is_empty() {
        if let Some(t) = lx.peek().filter(|t| t.text.starts_with(':')) {
            lx.next();
            rest = t;
        }
    }
    let Some(after_colon) = rest.text.strip_prefix(':') else {
        let found = if rest.text.is_empty() { lx.peek() } else { Some(rest) };
        let message = format!("expected `:` after `{}`, found {}", words.join(" "), show(found.as_ref()));
        return Err(match found {
            Some(t) => lx.error_at(&t, message),
            None => lx.error_at_end(message),
        });
    };
    if !after_colon.is_empty() {
        return Ok(sub_tok(&rest, 1));
    }
    match lx.next() {
        Some(t) => Ok(t),
        None => Err(lx.error_here(format!("expected a value after `{}:`, found end of file", words.join(" ")))),
    }
}

/// The part of a token after its first `skip` bytes (ASCII, so always a char boundary).
fn sub_tok<'a>(t: &Tok<'a>, skip: usize) -> Tok<'a> {
    let skip = skip.min(t.text.len());
    Tok { text: &t.text[skip..], start: t.start + skip, ..*t }
}

// ---------------------------------------------------------------------------------------------
// Frame rows
// ---------------------------------------------------------------------------------------------

/// Streams the frame rows, one per line, straight into the value buffer.
struct RowReader<'a> {
    text: &'a str,
    pos: usize,
    line: usize,
    channels: usize,
    max_values: usize,
    capacity: usize,
    budget: FrameBudget,
}

impl<'a> RowReader<'a> {
    fn new(
        text: &'a str,
        pos: usize,
        line: usize,
        channels: usize,
        declared: usize,
        limits: &ParseLimits,
        budget: FrameBudget,
    ) -> Self {
        // Never trust `Frames:` for the allocation: a value takes at least two bytes ("0 ").
        let by_size = (text.len() - pos) / 2 + 1;
        let capacity = declared.min(budget.max_frames).saturating_mul(channels).min(by_size).min(limits.max_values);
        RowReader { text, pos, line, channels, max_values: limits.max_values, capacity, budget }
    }

    /// Reads every row; returns the values and a warning if an incomplete last row was dropped.
    fn read(mut self, progress: &mut dyn FnMut(usize)) -> Result<(Vec<f64>, Option<Warning>), BvhError> {
        let bytes = self.text.as_bytes();
        let mut values = Vec::with_capacity(self.capacity);
        let step = (bytes.len() - self.pos) / 50 + 1;
        let mut next_report = self.pos + step;
        let mut warning = None;
        while self.pos < bytes.len() {
            let start = self.pos;
            let end = bytes[start..].iter().position(|&b| b == b'\n' || b == b'\r').map_or(bytes.len(), |n| start + n);
            let row = &self.text[start..end];
            let before = values.len();
            let n = self.read_row(row, start, &mut values)?;
            // step over the line break
            self.pos = end;
            if self.pos < bytes.len() {
                self.pos += if bytes[end] == b'\r' && bytes.get(end + 1) == Some(&b'\n') { 2 } else { 1 };
            }
            if n > 0 && n < self.channels {
                if !bytes[self.pos..].iter().all(u8::is_ascii_whitespace) {
                    return Err(BvhError::new(
                        self.line,
                        column(self.text, start, end),
                        format!("too few values in frame row: expected {}, found {n}", self.channels),
                    ));
                }
                values.truncate(before);
                warning = Some(Warning {
                    line: self.line,
                    message: format!(
                        "the last frame row has {n} of {} values (truncated file?); it was dropped",
                        self.channels
                    ),
                });
            }
            self.line += 1;
            if self.pos >= next_report {
                progress(self.pos);
                next_report = self.pos + step;
            }
        }
        Ok((values, warning))
    }

    /// Parses the values of one line into `values`; returns how many there were.
    fn read_row(&self, row: &str, line_start: usize, values: &mut Vec<f64>) -> Result<usize, BvhError> {
        let mut n = 0;
        for tok in row.split_ascii_whitespace() {
            if n == 0 && values.len() + self.channels > self.max_values {
                return Err(self.error(
                    tok,
                    line_start,
                    format!("too many frame values: the limit is {}", self.max_values),
                ));
            }
            if n == 0 && self.channels > 0 && values.len() / self.channels >= self.budget.max_frames {
                return Err(self.error(tok, line_start, self.budget.message()));
            }
            if n == self.channels {
                let message = if self.channels == 0 {
                    "the hierarchy declares no channels, so frame rows must be empty; found a value".to_string()
                } else {
                    format!("too many values in frame row: expected {}, found more", self.channels)
                };
                return Err(self.error(tok, line_start, message));
            }
            match number(tok) {
                Some(v) if v.is_finite() => values.push(v),
                Some(_) => {
                    return Err(self.error(
                        tok,
                        line_start,
                        format!("value `{}` is not a finite number", tok_text(tok)),
                    ))
                }
                None => {
                    return Err(self.error(
                        tok,
                        line_start,
                        format!(
                            "expected a number (value {} of {} in the frame row), found `{}`",
                            n + 1,
                            self.channels,
                            tok_text(tok)
                        ),
                    ))
                }
            }
            n += 1;
        }
        Ok(n)
    }

    fn error(&self, tok: &str, line_start: usize, message: String) -> BvhError {
        let at = tok.as_ptr() as usize - self.text.as_ptr() as usize;
        BvhError::new(self.line, column(self.text, line_start, at), message)
    }
}

fn tok_text(tok: &str) -> String {
    let shown: String = tok.chars().take(40).flat_map(char::escape_debug).collect();
    if tok.chars().nth(40).is_some() {
        shown + "…"
    } else {
        shown
    }
}

// ---------------------------------------------------------------------------------------------
// Numbers
// ---------------------------------------------------------------------------------------------

/// Exact powers of ten up to 10^15 (all representable in `f64`).
const POW10: [f64; 16] = [1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15];

/// Parses a number the way `str::parse::<f64>` does (correctly rounded; `inf`/`NaN` come back
/// non-finite for the caller to reject), with a fast path for plain decimals.
pub(crate) fn number(s: &str) -> Option<f64> {
    fast_decimal(s.as_bytes()).or_else(|| s.parse::<f64>().ok())
}

/// `[+-]digits[.digits]` with at most 15 digits: the integer of its digits is exact in `f64`
/// and so is the power of ten, so one division gives the correctly rounded value.
fn fast_decimal(b: &[u8]) -> Option<f64> {
    let (negative, digits) = match b.first()? {
        b'-' => (true, &b[1..]),
        b'+' => (false, &b[1..]),
        _ => (false, b),
    };
    let mut mantissa: u64 = 0;
    let mut count = 0;
    let mut fraction = 0;
    let mut dot = false;
    for &c in digits {
        match c {
            b'0'..=b'9' => {
                count += 1;
                if count > 15 {
                    return None;
                }
                mantissa = mantissa * 10 + u64::from(c - b'0');
                fraction += usize::from(dot);
            }
            b'.' if !dot => dot = true,
            _ => return None,
        }
    }
    if count == 0 {
        return None;
    }
    let v = mantissa as f64 / POW10[fraction];
    Some(if negative { -v } else { v })
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::stats::Rng;

    #[test]
    fn fast_path_agrees_bit_for_bit_with_std_parse() {
        let mut rng = Rng::new(7);
        for _ in 0..200_000 {
            let int_digits = (rng.next_u64() % 8) as usize;
            let frac_digits = (rng.next_u64() % 9) as usize;
            let mut s = String::new();
            if rng.next_u64() % 2 == 0 {
                s.push('-');
            }
            for _ in 0..int_digits {
                s.push(char::from(b'0' + (rng.next_u64() % 10) as u8));
            }
            if frac_digits > 0 || rng.next_u64() % 4 == 0 {
                s.push('.');
            }
            for _ in 0..frac_digits {
                s.push(char::from(b'0' + (rng.next_u64() % 10) as u8));
            }
            let std = s.parse::<f64>().ok();
            let fast = fast_decimal(s.as_bytes());
            if let Some(f) = fast {
                assert_eq!(Some(f.to_bits()), std.map(f64::to_bits), "{s}");
            } else {
                assert!(std.is_none() || int_digits + frac_digits > 15, "{s}: fast path declined a plain decimal");
            }
            assert_eq!(number(&s).map(f64::to_bits), std.map(f64::to_bits), "{s}");
        }
    }

    #[test]
    fn numbers_in_every_notation() {
        assert_eq!(number("1.5e3"), Some(1500.0));
        assert_eq!(number("-2E-2"), Some(-0.02));
        assert_eq!(number(".0083333"), Some(0.0083333));
        assert_eq!(number("5."), Some(5.0));
        assert_eq!(number("+7"), Some(7.0));
        assert_eq!(number("-0.000000").map(f64::to_bits), Some((-0.0f64).to_bits()));
        assert_eq!(number("0.0417083750417"), Some(0.0417083750417));
        assert_eq!(number("12345678901234567890.5"), Some(12345678901234567890.5));
        assert!(number("nan").is_some_and(f64::is_nan));
        assert!(number("1e999").is_some_and(f64::is_infinite));
        for bad in ["", "-", ".", "1.2.3", "1,5", "abc", "1e", "--1", "1.#QNAN"] {
            assert_eq!(number(bad), None, "{bad}");
        }
    }

    #[test]
    fn lexer_counts_lf_crlf_and_lone_cr_as_one_line_each() {
        let mut lx = Lexer::new("a\nb\r\nc\rd\r\r\ne");
        let lines: Vec<(String, usize)> =
            std::iter::from_fn(|| lx.next()).map(|t| (t.text.to_string(), t.line)).collect();
        let expected = [("a", 1), ("b", 2), ("c", 3), ("d", 4), ("e", 6)];
        assert_eq!(lines, expected.map(|(s, l)| (s.to_string(), l)));
    }

    #[test]
    fn lexer_splits_braces_and_names_run_to_brace_or_line_end() {
        let mut lx = Lexer::new("ROOT  Left Arm \t{OFFSET}\nJOINT x");
        assert_eq!(lx.next().map(|t| t.text), Some("ROOT"));
        assert_eq!(lx.name().map(|t| t.text), Some("Left Arm"));
        let rest: Vec<&str> = std::iter::from_fn(|| lx.next()).map(|t| t.text).collect();
        assert_eq!(rest, ["{", "OFFSET", "}", "JOINT", "x"]);
    }

    #[test]
    fn columns_count_characters_not_bytes() {
        let text = "JOINT Hüfte x";
        let mut lx = Lexer::new(text);
        lx.next();
        lx.next();
        let t = lx.next().expect("token");
        assert_eq!(t.text, "x");
        assert_eq!(column(text, t.line_start, t.start), 13);
    }

    #[test]
    fn shown_tokens_are_escaped_and_cut() {
        let long = "y".repeat(100);
        let t = Tok { text: &long, start: 0, line: 1, line_start: 0 };
        assert_eq!(show(Some(&t)), format!("`{}…`", "y".repeat(40)));
        let t = Tok { text: "a\u{7}", start: 0, line: 1, line_start: 0 };
        assert_eq!(show(Some(&t)), "`a\\u{7}`");
        assert_eq!(show(None), "end of file");
    }

    #[test]
    fn allocation_follows_the_input_not_the_declared_frame_count() {
        let text = "0 0 0\n";
        let limits = ParseLimits::default();
        let budget = FrameBudget::new(text.len(), 3, 1, 0.1, &limits);
        let reader = RowReader::new(text, 0, 1, 3, usize::MAX, &limits, budget);
        assert!(reader.capacity <= text.len() / 2 + 1);
    }
}
