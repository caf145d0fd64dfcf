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
    /// Parser warnings followed by motion warnings, as text.
    pub fn warnings(&self) -> Vec<String> {
        let mut w: Vec<String> = self.bvh.warnings.iter().map(Warning::to_string).collect();
        w.extend(self.motion.warnings.iter().cloned());
        w
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

/// Parses `bytes` (the content of `file`) and computes its motion, reporting parse progress 0..1.
pub fn load_bytes(file: &str, bytes: &[u8], progress: &mut dyn FnMut(f64)) -> Result<Loaded, LoadError> {
    let (text, decode_warning) = decode(bytes);
    let mut bvh = bvh::parse_with_progress(&text, &ParseLimits::default(), progress)
        .map_err(|source| LoadError::Parse { file: file.to_string(), source })?;
    if let Some(w) = decode_warning {
        bvh.warnings.insert(0, w);
    }
    let motion = Motion::from_bvh(file, &bvh).map_err(|source| LoadError::Motion { file: file.to_string(), source })?;
    Ok(Loaded { bvh, motion })
}

/// Reads and loads a file from disk (native only).
#[cfg(not(target_arch = "wasm32"))]
pub fn load_path(path: &std::path::Path) -> Result<Loaded, LoadError> {
    let file = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| path.display().to_string());
    let bytes =
        std::fs::read(path).map_err(|e| LoadError::Io { file: path.display().to_string(), message: e.to_string() })?;
    load_bytes(&file, &bytes, &mut |_| {})
}

#[cfg(test)]
mod tests {
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

    #[test]
    fn utf8_decodes_without_copy_or_warning() {
        let (text, warning) = decode("ROOT mixamorig:Hips".as_bytes());
        assert!(matches!(text, std::borrow::Cow::Borrowed(_)));
        assert!(warning.is_none());
    }
}
