//! Small fixture takes and BVH seeds, for the targets (`crate::repo()` is the repository's root: the fuzz
//! crate's, or the main crate's in tests/fuzz_targets.rs, which compiles this file too).

use mocapseg::bvh::{self, Bvh};

/// The BVH fixtures, `(file name, text)`, smallest first.
pub fn fixtures() -> Vec<(String, String)> {
    let mut out: Vec<(String, String)> = std::fs::read_dir(crate::repo().join("tests/fixtures"))
        .expect("tests/fixtures")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "bvh"))
        .map(|p| {
            let bytes = std::fs::read(&p).expect("a fixture");
            (p.file_name().unwrap().to_string_lossy().into_owned(), String::from_utf8_lossy(&bytes).into_owned())
        })
        .collect();
    out.sort_by_key(|(_, t)| t.len());
    out
}

/// `bvh` with only its first `frames` frames.
pub fn first_frames(bvh: &Bvh, frames: usize) -> Bvh {
    let mut b = bvh.clone();
    let keep = frames.min(b.frames()) * b.channels_per_frame;
    b.values.truncate(keep);
    b.declared_frames = b.frames();
    b.warnings.clear();
    b
}

/// The text of a fixture as its exporter wrote it (tabs, line endings, number formats), cut
/// after `rows` data rows of its MOTION section (the `Frames:` line then disagrees: a warning).
pub fn raw_prefix(text: &str, rows: usize) -> String {
    let Some(at) = text.find("MOTION") else { return text.chars().take(8192).collect() };
    let mut end = at;
    // MOTION, Frames:, Frame Time: and then `rows` rows
    for _ in 0..3 + rows {
        match text[end..].find('\n') {
            Some(n) => end += n + 1,
            None => return text.to_string(),
        }
    }
    text[..end].to_string()
}

/// Small seeds of every BVH fixture: its first 30 frames as the crate writes them, and its
/// first 10 rows as its exporter wrote them.
pub fn bvh_seeds() -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    for (name, text) in fixtures() {
        out.push((format!("raw-{name}"), raw_prefix(&text, 10).into_bytes()));
        if let Ok(b) = bvh::parse(&text) {
            out.push((format!("written-{name}"), bvh::write(&first_frames(&b, 30)).into_bytes()));
        }
    }
    out
}

/// A fixture's take cut to its first `frames` frames, parsed (for targets that need a motion).
pub fn small_take(fixture: &str, frames: usize) -> Bvh {
    let text = std::fs::read_to_string(crate::repo().join("tests/fixtures").join(fixture)).expect("the fixture");
    first_frames(&bvh::parse(&text).expect("the fixture parses"), frames)
}
