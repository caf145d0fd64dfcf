//! From the bytes of a file to a [`Motion`]: decoding, parsing, forward kinematics, with errors
//! that name the file. Shared by the CLI and the web worker so both report problems the same way.

use crate::bvh::{self, Bvh, BvhError, ParseLimits, Warning};
use crate::motion::{Motion, MotionError};

/// A loaded take: the parsed file and its motion (world positions).
#[derive(Debug, Clone)]
pub struct Loaded {
    pub bvh: Bvh,
    pub motion: Motion,
}

impl Loaded {
    /// Parser warnings followed by motion warnings, as text, each once ([`Motion::from_bvh`]
    /// already starts the motion's warnings with the parser's).
    pub fn warnings(&self) -> Vec<String> {
        self.motion.warnings.clone()
    }
}

/// Why a file could not be loaded; the message always starts with the file name.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    #[error("{file}: {source}")]
    Parse { file: String, source: BvhError },
    #[error("{file}: {source}")]
    Motion { file: String, source: MotionError },
    #[error("{file}: {message}")]
    Io { file: String, message: String },
    #[error(
        "{file}: {frames} frames × {nodes} joints need about {} MiB, more than the page's budget of {} MiB; cut the take",
        mib(*needed),
        mib(*budget)
    )]
    TooLarge { file: String, frames: usize, nodes: usize, needed: usize, budget: usize },
}

/// Whole MiB, rounded up (so a refused load never reads as "needs 1024 MiB of 1024").
fn mib(bytes: usize) -> usize {
    bytes.div_ceil(1 << 20)
}

/// How much memory one load may take, checked before the big allocations (the world positions
/// and the motion image), so a take too large for a browser tab is refused with a message
/// instead of killing the tab.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MemoryBudget {
    pub max_bytes: usize,
}

impl Default for MemoryBudget {
    /// 1 GiB: what a browser tab can hold besides the page itself (a 40-node skeleton at
    /// 120 fps fits about 80 minutes).
    fn default() -> Self {
        MemoryBudget { max_bytes: 1 << 30 }
    }
}

impl MemoryBudget {
    /// Bytes of one world position (`f32` × 3).
    const POSITION_BYTES: usize = 12;
    /// World positions are held three times: the motion, the flat copy sent to the page, and
    /// the page's own copy.
    const POSITION_COPIES: usize = 3;
    /// Motion image bytes per frame and node: 4 RGBA plus as much again for its PNG (deflate of
    /// smooth motion is smaller; this bounds it).
    const IMAGE_BYTES: usize = 4 + 4;

    /// About how many bytes loading `frames` frames of a `nodes`-node skeleton (End Sites
    /// included) takes: positions and motion image. Saturates instead of overflowing.
    pub fn estimate(frames: usize, nodes: usize) -> usize {
        let per_position = Self::POSITION_BYTES * Self::POSITION_COPIES + Self::IMAGE_BYTES;
        frames.saturating_mul(nodes).saturating_mul(per_position)
    }

    /// Ok if [`MemoryBudget::estimate`] fits in the budget; otherwise an error naming `file`,
    /// the size of the take, what it needs and the budget.
    pub fn check(&self, file: &str, frames: usize, nodes: usize) -> Result<(), LoadError> {
        let needed = Self::estimate(frames, nodes);
        if needed <= self.max_bytes {
            return Ok(());
        }
        Err(LoadError::TooLarge { file: file.to_string(), frames, nodes, needed, budget: self.max_bytes })
    }

    /// Parser limits that keep the whole take within the budget while it is read: the text, the
    /// frame values (`f64`) and what each frame will need once loaded ([`MemoryBudget::estimate`]
    /// per node), so the parser stops at the first row past the budget instead of allocating it.
    /// A take must have a frame.
    pub fn parse_limits(&self) -> ParseLimits {
        let default = ParseLimits::default();
        ParseLimits {
            max_values: default.max_values.min(self.max_bytes / 8),
            max_bytes: self.max_bytes,
            bytes_per_node_frame: Self::estimate(1, 1),
            min_frames: 1,
            ..default
        }
    }
}

/// Decodes BVH bytes: UTF-8, or (for files from old exporters) Latin-1 with a warning.
pub fn decode(bytes: &[u8]) -> (std::borrow::Cow<'_, str>, Option<Warning>) {
    match std::str::from_utf8(bytes) {
        Ok(text) => (std::borrow::Cow::Borrowed(text), None),
        Err(e) => {
            let line = line_breaks(&bytes[..e.valid_up_to()]) + 1;
            let text: String = bytes.iter().map(|&b| b as char).collect();
            let warning = Warning { line, message: "the file is not valid UTF-8; read it as Latin-1".to_string() };
            (std::borrow::Cow::Owned(text), Some(warning))
        }
    }
}

/// Line breaks in `bytes` counted as the BVH parser counts them: `\n`, `\r\n` and a lone `\r`
/// (old Mac exporters) are one break each.
fn line_breaks(bytes: &[u8]) -> usize {
    let lone_cr = bytes.windows(2).filter(|w| w[0] == b'\r' && w[1] != b'\n').count();
    let last_cr = usize::from(bytes.last() == Some(&b'\r'));
    bytes.iter().filter(|&&b| b == b'\n').count() + lone_cr + last_cr
}

/// Parses `bytes` (the content of `file`) and computes its motion, reporting parse progress 0..1,
/// within the default [`MemoryBudget`].
pub fn load_bytes(file: &str, bytes: &[u8], progress: &mut dyn FnMut(f64)) -> Result<Loaded, LoadError> {
    load_bytes_with_budget(file, bytes, &MemoryBudget::default(), progress)
}

/// Parses `bytes` (the content of `file`) and computes its motion, reporting parse progress 0..1.
/// The frame values may take at most `budget` (the parser stops at that many values), and the
/// frames present × nodes are checked against `budget` after parsing, before forward kinematics
/// allocates the positions.
pub fn load_bytes_with_budget(
    file: &str,
    bytes: &[u8],
    budget: &MemoryBudget,
    progress: &mut dyn FnMut(f64),
) -> Result<Loaded, LoadError> {
    let (text, decode_warning) = decode(bytes);
    let mut bvh = bvh::parse_with_progress(&text, &budget.parse_limits(), progress)
        .map_err(|source| LoadError::Parse { file: file.to_string(), source })?;
    if let Some(w) = decode_warning {
        bvh.warnings.insert(0, w);
    }
    budget.check(file, bvh.frames(), bvh.joints.len())?;
    let motion = Motion::from_bvh(file, &bvh).map_err(|source| LoadError::Motion { file: file.to_string(), source })?;
    Ok(Loaded { bvh, motion })
}

/// Reads and loads a file from disk (native only).
#[cfg(not(target_arch = "wasm32"))]
pub fn load_path(path: &std::path::Path) -> Result<Loaded, LoadError> {
    let extension = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
    match extension.as_deref() {
        Some("amc") => {
            let asf = asf_beside(path)?;
            let amc_bytes = read(path)?;
            let asf_bytes = read(&asf)?;
            load_asf_amc((&file_name(&asf), &asf_bytes), (&file_name(path), &amc_bytes), &MemoryBudget::default())
        }
        Some("asf") => Err(LoadError::Io {
            file: file_name(path),
            message: "an ASF file is a skeleton with no motion: give its AMC motion (the ASF beside it is found)"
                .into(),
        }),
        _ => load_bytes(&file_name(path), &read(path)?, &mut |_| {}),
    }
}

#[cfg(not(target_arch = "wasm32"))]
fn file_name(path: &std::path::Path) -> String {
    path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| path.display().to_string())
}

#[cfg(not(target_arch = "wasm32"))]
fn read(path: &std::path::Path) -> Result<Vec<u8>, LoadError> {
    std::fs::read(path).map_err(|e| LoadError::Io { file: path.display().to_string(), message: e.to_string() })
}

/// The ASF skeleton of an AMC motion: `<subject>.asf` beside `<subject>_<trial>.amc` (the CMU
/// naming), else the only `.asf` in its folder.
/// Every file under `inputs` with extension `ext` (folders searched recursively, sorted);
/// files named directly are kept whatever their extension. The command line's way of reading
/// folders of takes (`mocapseg segment DIR`, the examples).
#[cfg(not(target_arch = "wasm32"))]
pub fn collect_files(inputs: &[std::path::PathBuf], ext: &str) -> Result<Vec<std::path::PathBuf>, String> {
    fn walk(dir: &std::path::Path, ext: &str, out: &mut Vec<std::path::PathBuf>) -> Result<(), String> {
        let mut entries: Vec<std::path::PathBuf> = std::fs::read_dir(dir)
            .map_err(|e| format!("{}: {e}", dir.display()))?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .collect();
        entries.sort();
        for p in entries {
            if p.is_dir() {
                walk(&p, ext, out)?;
            } else if p.extension().is_some_and(|e| e.eq_ignore_ascii_case(ext)) {
                out.push(p);
            }
        }
        Ok(())
    }
    let mut files = Vec::new();
    for input in inputs {
        if input.is_dir() {
            walk(input, ext, &mut files)?;
        } else if input.exists() {
            files.push(input.clone());
        } else {
            return Err(format!("{}: no such file or folder", input.display()));
        }
    }
    files.dedup();
    Ok(files)
}

#[cfg(not(target_arch = "wasm32"))]
pub fn asf_beside(amc: &std::path::Path) -> Result<std::path::PathBuf, LoadError> {
    let folder = amc.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(std::path::Path::new("."));
    let stem = amc.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let subject = stem.split('_').next().unwrap_or(&stem);
    for candidate in [format!("{subject}.asf"), format!("{stem}.asf")] {
        let path = folder.join(&candidate);
        if path.is_file() {
            return Ok(path);
        }
    }
    let mut found: Vec<std::path::PathBuf> = std::fs::read_dir(folder)
        .map(|entries| {
            entries
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|e| e.eq_ignore_ascii_case("asf")))
                .collect()
        })
        .unwrap_or_default();
    if found.len() == 1 {
        return Ok(found.remove(0));
    }
    Err(LoadError::Io {
        file: file_name(amc),
        message: format!(
            "an AMC motion needs its ASF skeleton: expected {subject}.asf beside it{}",
            if found.is_empty() {
                String::new()
            } else {
                format!(" (found {} other .asf files; which one?)", found.len())
            }
        ),
    })
}

/// Reads an ASF skeleton and an AMC motion, each `(file name, bytes)`, into a take at the CMU
/// rate (120 fps; AMC files carry no frame rate), through the same [`Bvh`] and [`Motion`] as
/// a BVH file and within the same memory budget. Errors name the file they are in.
pub fn load_asf_amc(asf: (&str, &[u8]), amc: (&str, &[u8]), budget: &MemoryBudget) -> Result<Loaded, LoadError> {
    use crate::asfamc;
    let limits = budget.parse_limits();
    let (asf_text, asf_warning) = decode(asf.1);
    let skeleton =
        asfamc::parse_asf(&asf_text, &limits).map_err(|source| LoadError::Parse { file: asf.0.to_string(), source })?;
    let (nodes, channels) = asfamc::convert::size(&skeleton);
    let (amc_text, amc_warning) = decode(amc.1);
    let fps = asfamc::CMU_FPS;
    // the AMC's text and values, then the BVH values and the frame's cost once loaded
    let motion = asfamc::parse_amc(&amc_text, &skeleton, &limits, channels * 8, nodes, 1.0 / fps)
        .map_err(|source| LoadError::Parse { file: amc.0.to_string(), source })?;
    let mut bvh = asfamc::to_bvh(&skeleton, &motion, fps, asf.0, amc.0);
    for (name, w) in [(amc.0, amc_warning), (asf.0, asf_warning)] {
        if let Some(w) = w {
            bvh.warnings.insert(0, Warning { line: 0, message: format!("{name}: {w}") });
        }
    }
    bvh.warnings.push(Warning {
        line: 0,
        message: format!("{}: AMC files carry no frame rate; {fps} fps (the CMU rate) assumed", amc.0),
    });
    budget.check(amc.0, bvh.frames(), bvh.joints.len())?;
    let motion =
        Motion::from_bvh(amc.0, &bvh).map_err(|source| LoadError::Motion { file: amc.0.to_string(), source })?;
    Ok(Loaded { bvh, motion })
}

/// What a set of files dropped or picked together is: one take's file, or an ASF skeleton and
/// its AMC motion (indices into the names given).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Opening {
    One(usize),
    AsfAmc { asf: usize, amc: usize },
}

/// Reads the names of the files the user dropped or picked at once: a single file is a take (a
/// BVH, or anything the parser will judge), an `.asf` with an `.amc` is a CMU original; anything
/// else is refused with what to drop instead.
pub fn opening(names: &[&str]) -> Result<Opening, String> {
    let kind = |name: &str| name.rsplit_once('.').map(|(_, e)| e.to_ascii_lowercase()).unwrap_or_default();
    match names {
        [] => Err("no file was dropped".into()),
        [one] => match kind(one).as_str() {
            "asf" => Err(format!(
                "{one} is an ASF skeleton without motion: drop or pick it together with one of its AMC motions"
            )),
            "amc" => Err(format!(
                "{one} is an AMC motion without its skeleton: drop or pick it together with its ASF file \
                 (for CMU takes `<subject>.asf`, e.g. 02.asf for 02_01.amc)"
            )),
            _ => Ok(Opening::One(0)),
        },
        [a, b] => match (kind(a).as_str(), kind(b).as_str()) {
            ("asf", "amc") => Ok(Opening::AsfAmc { asf: 0, amc: 1 }),
            ("amc", "asf") => Ok(Opening::AsfAmc { asf: 1, amc: 0 }),
            _ => Err(format!(
                "{a} and {b}: two files are read together only as an ASF skeleton and its AMC motion; \
                 drop one BVH at a time"
            )),
        },
        _ => Err(format!(
            "{} files at once: drop one take at a time — a BVH file, or an ASF skeleton with its AMC motion",
            names.len()
        )),
    }
}

#[cfg(test)]
mod tests {

    #[test]
    fn files_dropped_together_are_one_take_or_an_asf_amc_pair() {
        assert_eq!(opening(&["a.bvh"]), Ok(Opening::One(0)));
        assert_eq!(opening(&["noext"]), Ok(Opening::One(0)));
        assert_eq!(opening(&["02.ASF", "02_01.amc"]), Ok(Opening::AsfAmc { asf: 0, amc: 1 }));
        assert_eq!(opening(&["02_01.amc", "02.asf"]), Ok(Opening::AsfAmc { asf: 1, amc: 0 }));
        let alone = opening(&["02_01.amc"]).unwrap_err();
        assert!(alone.starts_with("02_01.amc is an AMC motion without its skeleton") && alone.contains("02.asf"));
        assert!(opening(&["02.asf"]).unwrap_err().contains("ASF skeleton without motion"));
        assert!(opening(&["a.bvh", "b.bvh"]).unwrap_err().contains("drop one BVH at a time"));
        assert!(opening(&["a.asf", "b.asf"]).unwrap_err().starts_with("a.asf and b.asf"));
        assert!(opening(&["a", "b", "c"]).unwrap_err().starts_with("3 files at once"));
        assert!(opening(&[]).is_err());
    }
    use super::*;

    #[test]
    fn latin1_bytes_decode_with_a_warning_naming_the_line() {
        let bytes = b"HIERARCHY\nROOT H\xe4nd\n";
        let (text, warning) = decode(bytes);
        assert!(text.contains("Händ"));
        let w = warning.expect("a warning");
        assert_eq!(w.line, 2);
        assert!(w.message.contains("UTF-8"));
    }

    #[test]
    fn the_warning_counts_lines_like_the_parser_whatever_the_line_breaks() {
        for (bytes, line) in [
            (&b"A\r\nB\r\nROOT H\xe4nd"[..], 3),
            (&b"A\rB\rC\rROOT H\xe4nd"[..], 4),
            (&b"A\r\rB\nROOT H\xe4nd"[..], 4),
            (&b"A\r\xe4"[..], 2),
        ] {
            assert_eq!(decode(bytes).1.expect("a warning").line, line, "{bytes:?}");
        }
    }

    /// A chain of `nodes` joints with one rotation channel each, and `frames` rows of zeros.
    fn chain(nodes: usize, frames: usize) -> String {
        let mut s = String::from("HIERARCHY\n");
        for i in 0..nodes {
            s.push_str(&format!(
                "{} J{i}\n{{\nOFFSET 0 1 0\nCHANNELS 1 Xrotation\n",
                if i == 0 { "ROOT" } else { "JOINT" }
            ));
        }
        s.push_str(&"}\n".repeat(nodes));
        s.push_str(&format!("MOTION\nFrames: {frames}\nFrame Time: 0.01\n"));
        let row = format!("{}\n", vec!["0"; nodes].join(" "));
        s.push_str(&row.repeat(frames));
        s
    }

    #[test]
    fn estimate_counts_positions_three_times_and_the_image_and_saturates() {
        assert_eq!(MemoryBudget::estimate(1000, 10), 1000 * 10 * (12 * 3 + 8));
        assert_eq!(MemoryBudget::estimate(usize::MAX, 3), usize::MAX);
        assert_eq!(MemoryBudget::default().max_bytes, 1 << 30);
    }

    #[test]
    fn a_take_over_the_budget_is_refused_at_the_first_row_past_it() {
        // The budget covers the text, the values (8 bytes each) and each frame's estimate once
        // loaded: with room for exactly 100 frames the take loads, with a byte less the parser
        // stops at the row of frame 100 and says why, naming the budget and the frames that fit.
        let text = chain(4, 100);
        let per_frame = 4 * 8 + MemoryBudget::estimate(1, 4);
        let exact = MemoryBudget { max_bytes: text.len() + 100 * per_frame };
        let loaded = load_bytes_with_budget("walk.bvh", text.as_bytes(), &exact, &mut |_| {}).expect("fits exactly");
        assert_eq!(loaded.motion.frames(), 100);
        let tight = MemoryBudget { max_bytes: exact.max_bytes - 1 };
        let e = load_bytes_with_budget("walk.bvh", text.as_bytes(), &tight, &mut |_| {}).unwrap_err();
        let m = e.to_string();
        let last_row = text.lines().count();
        assert!(m.starts_with(&format!("walk.bvh: line {last_row}, column 1: the take is too large")), "{m}");
        assert!(m.contains("budget of 1 MiB") && m.contains("at most 99 frames") && m.contains("cut the take"), "{m}");
        assert!(m.contains(&format!("needs about {per_frame} bytes")), "{m}");
    }

    #[test]
    fn a_take_needing_more_than_the_budget_after_parsing_is_refused_naming_its_size() {
        // No channels: nothing to read, one frame of 10 001 nodes, too many for a tiny budget.
        let mut text = "HIERARCHY\nROOT A\n{\nOFFSET 0 0 0\nCHANNELS 0\n".to_string();
        for i in 0..50 {
            text += &format!("JOINT J{i}\n{{\nOFFSET 0 1 0\nCHANNELS 0\nEnd Site\n{{\nOFFSET 0 1 0\n}}\n}}\n");
        }
        text += "}\nMOTION\nFrames: 1\nFrame Time: 0.1\n";
        let budget = MemoryBudget { max_bytes: MemoryBudget::estimate(1, 101) - 1 };
        let e = load_bytes_with_budget("wide.bvh", text.as_bytes(), &budget, &mut |_| {}).unwrap_err();
        assert!(matches!(e, LoadError::TooLarge { frames: 1, nodes: 101, .. }), "{e}");
        assert!(e.to_string().starts_with("wide.bvh: 1 frames × 101 joints need about 1 MiB"), "{e}");
    }

    #[test]
    fn the_value_limit_stops_the_parser_where_it_is_passed() {
        // 8 values: the parser stops at the row that would pass them, and says where.
        let limits = ParseLimits { max_values: 8, ..ParseLimits::default() };
        let e = bvh::parse_with_progress(&chain(4, 3), &limits, &mut |_| {}).unwrap_err().to_string();
        assert!(e.starts_with("line 27, column 1: too many frame values: the limit is 8"), "{e}");
        // The budget's own value limit is never the tighter one: the frame budget counts the values too.
        let tight = MemoryBudget { max_bytes: 64 }.parse_limits();
        assert_eq!((tight.max_values, tight.max_bytes, tight.min_frames), (8, 64, 1));
    }

    #[test]
    fn a_take_without_frames_is_refused_where_it_says_so() {
        let text = chain(2, 0);
        let e = load_bytes("still.bvh", text.as_bytes(), &mut |_| {}).unwrap_err().to_string();
        let line = text.lines().position(|l| l.starts_with("Frames:")).unwrap() + 1;
        assert!(e.starts_with(&format!("still.bvh: line {line}, column 9: the take has no frames")), "{e}");
        assert!(e.contains("a skeleton with no motion"), "{e}");
        let skeleton = &text[..text.find("MOTION").unwrap()];
        let e = load_bytes("skeleton.bvh", skeleton.as_bytes(), &mut |_| {}).unwrap_err().to_string();
        assert!(e.starts_with("skeleton.bvh: line ") && e.contains("no `MOTION` section"), "{e}");
        let parsed = crate::bvh::parse(skeleton).expect("a skeleton with no motion");
        assert_eq!((parsed.joints.len(), parsed.frames()), (2, 0));
        assert!(parsed.warnings[0].message.contains("a skeleton with no motion"), "{:?}", parsed.warnings);
    }

    #[test]
    fn declared_frames_with_no_data_behind_them_load_as_one_frame() {
        let text = "HIERARCHY\nROOT Pelvis\n{\n\tOFFSET 0 0 0\n\tCHANNELS 0\n}\nMOTION\nFrames: 33554432\nFrame Time: 0.008333333\n";
        assert_eq!(text.len(), 100);
        let loaded = load_bytes("tiny.bvh", text.as_bytes(), &mut |_| {}).expect("loads");
        assert_eq!((loaded.motion.frames(), loaded.motion.positions.len()), (1, 1));
        assert_eq!(crate::image::MotionImage::from_motion(&loaded.motion).width, 1);
    }

    #[test]
    fn each_warning_is_reported_once() {
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/assimp_Boxing_Toes_100fps.bvh");
        let loaded = load_path(&path).expect("loads");
        let warnings = loaded.warnings();
        let frames = warnings.iter().filter(|w| w.contains("`Frames:` says 3069")).count();
        assert_eq!(frames, 1, "{warnings:#?}");
        assert!(warnings[0].contains("has 3070 complete data rows"), "{warnings:#?}");
        let mut unique = warnings.clone();
        unique.sort();
        unique.dedup();
        assert_eq!(unique.len(), warnings.len(), "{warnings:#?}");
        // A Latin-1 file's decoding warning comes first, once.
        let mut bytes = std::fs::read(&path).expect("fixture");
        let at = bytes.windows(4).position(|w| w == b"ROOT").expect("ROOT") + 5;
        bytes.insert(at, 0xe4);
        let loaded = load_bytes("latin1.bvh", &bytes, &mut |_| {}).expect("loads");
        let warnings = loaded.warnings();
        assert!(warnings[0].contains("not valid UTF-8"), "{warnings:#?}");
        assert_eq!(warnings.iter().filter(|w| w.contains("UTF-8")).count(), 1, "{warnings:#?}");
        assert_eq!(warnings.iter().filter(|w| w.contains("`Frames:` says")).count(), 1, "{warnings:#?}");
    }

    #[test]
    fn utf8_decodes_without_copy_or_warning() {
        let (text, warning) = decode("ROOT mixamorig:Hips".as_bytes());
        assert!(matches!(text, std::borrow::Cow::Borrowed(_)));
        assert!(warning.is_none());
    }
}
