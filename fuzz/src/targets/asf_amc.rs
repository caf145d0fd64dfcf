//! The ASF + AMC importer (`load::load_asf_amc`, what the command line reads for an `.amc`) and
//! the clip export of what it loads: bytes → ASF skeleton + AMC motion (a 4 MiB budget) →
//! `Motion`; then the whole take cut as one clip, written, and parsed back to the same file.
//!
//! The input is split at its first `\0`: the ASF before it, the AMC after (no `\0` makes an
//! empty AMC). Errors are fine and must name the file they are in; a panic, a hang or an
//! allocation past the budget is a finding.

use mocapseg::bvh;
use mocapseg::clips::cut;
use mocapseg::load::{load_asf_amc, MemoryBudget};

const BUDGET: MemoryBudget = MemoryBudget { max_bytes: 4 << 20 };

/// The CMU subject 02 skeleton with the first `frames` frames of its walk.
fn seed(frames: usize) -> Vec<u8> {
    let dir = crate::repo().join("tests/fixtures");
    let asf = std::fs::read(dir.join("02.asf")).expect("the ASF fixture");
    let amc = String::from_utf8(std::fs::read(dir.join("02_01.amc")).expect("the AMC fixture")).expect("ASCII");
    // the header lines, then `frames` frames (a frame number line and its 29 bone lines)
    let mut kept = String::new();
    let mut seen = 0;
    for line in amc.lines() {
        if line.trim().bytes().all(|b| b.is_ascii_digit()) && !line.trim().is_empty() {
            seen += 1;
            if seen > frames {
                break;
            }
        }
        kept += line;
        kept.push('\n');
    }
    [asf, vec![0], kept.into_bytes()].concat()
}

pub fn seeds() -> Vec<(String, Vec<u8>)> {
    vec![("asf-amc-1".into(), seed(1)), ("asf-amc-5".into(), seed(5))]
}

/// One input of the target (what `fuzz_targets/asf_amc.rs` hands libFuzzer's bytes to).
pub fn run(data: &[u8]) {
    let (asf, amc) = match data.iter().position(|&b| b == 0) {
        Some(at) => (&data[..at], &data[at + 1..]),
        None => (data, &data[data.len()..]),
    };
    let loaded = match load_asf_amc(("s.asf", asf), ("m.amc", amc), &BUDGET) {
        Ok(l) => l,
        Err(e) => {
            let m = e.to_string();
            assert!(m.starts_with("s.asf: ") || m.starts_with("m.amc: "), "{m}");
            return;
        }
    };
    let motion = &loaded.motion;
    assert!(motion.frames() >= 1);
    assert_eq!(motion.positions.len(), motion.frames() * motion.joints());
    let whole = cut(&loaded.bvh, 0, motion.frames() - 1).expect("the whole take is inside the take");
    let text = bvh::write(&whole);
    let back = bvh::parse(&text).unwrap_or_else(|e| panic!("a clip of an ASF/AMC take does not parse: {e}"));
    assert_eq!(back.joints, whole.joints);
    assert_eq!(back.values, whole.values);
}
