//! Raw bytes → decode (UTF-8, else Latin-1) → BVH parser. A file that parses must be
//! consistent, must write back with the crate's writer, and that text must parse to the same
//! take (bit-identical numbers: the writer prints every value in its shortest exact form).

use mocapseg::bvh::{self, Bvh, JointKind, ParseLimits};
use mocapseg::load::decode;

/// One input of the target (what `fuzz_targets/bvh_parse.rs` hands libFuzzer's bytes to).
pub fn run(data: &[u8]) {
    let (text, _) = decode(data);
    let mut last = 0.0f64;
    let parsed = bvh::parse_with_progress(&text, &ParseLimits::default(), &mut |p| {
        assert!((0.0..=1.0).contains(&p) && p >= last, "progress {p} after {last}");
        last = p;
    });
    let b = match parsed {
        Ok(b) => b,
        Err(e) => {
            let lines = text.split(['\n', '\r']).count().max(1);
            assert!(e.line >= 1 && e.line <= lines + 1 && e.column >= 1, "{e} (the text has {lines} lines)");
            assert!(!e.message.is_empty());
            return;
        }
    };
    consistent(&b);
    let again = bvh::parse(&bvh::write(&b)).unwrap_or_else(|e| panic!("the written take does not parse: {e}"));
    same(&b, &again);
}

/// What the parser promises about a take it returns.
fn consistent(b: &Bvh) {
    assert!(b.frame_time.is_finite() && b.frame_time > 0.0, "frame time {}", b.frame_time);
    let mut channels = 0;
    for (i, j) in b.joints.iter().enumerate() {
        match j.parent {
            None => assert_eq!(j.kind, JointKind::Root, "node {i}"),
            Some(p) => assert!(p < i && b.joints[p].kind != JointKind::EndSite, "node {i} has parent {p}"),
        }
        assert!(j.kind != JointKind::EndSite || j.channels.is_empty());
        assert_eq!(j.channel_start, channels, "node {i}");
        channels += j.channels.len();
    }
    assert_eq!(channels, b.channels_per_frame);
    if channels > 0 {
        assert_eq!(b.values.len() % channels, 0);
    } else {
        assert!(b.values.is_empty() && b.frames() <= 1);
    }
    assert!(b.values.iter().all(|v| v.is_finite()), "a non-finite frame value was accepted");
}

/// `back` (the written and re-parsed take) is `b`.
fn same(b: &Bvh, back: &Bvh) {
    assert_eq!(b.joints.len(), back.joints.len());
    for (x, y) in b.joints.iter().zip(&back.joints) {
        assert_eq!((&x.name, x.kind, x.parent, &x.channels), (&y.name, y.kind, y.parent, &y.channels));
        let bits = |o: &[f64; 3]| o.map(f64::to_bits);
        assert_eq!(bits(&x.offset), bits(&y.offset), "offset of {}", x.name);
    }
    assert_eq!(b.frame_time.to_bits(), back.frame_time.to_bits());
    assert_eq!(b.frames(), back.frames());
    assert_eq!(b.channels_per_frame, back.channels_per_frame);
    assert!(b.values.iter().zip(&back.values).all(|(x, y)| x.to_bits() == y.to_bits()), "frame values changed");
}

/// The target's seeds, `(name, bytes)`.
pub fn seeds() -> Vec<(String, Vec<u8>)> {
    crate::bvh_seeds()
}
