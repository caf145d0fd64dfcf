//! The whole load path: bytes → `load_bytes_with_budget` (a 4 MiB budget) → Motion → motion
//! image (and its PNG) → every registered method with its default parameters. Errors are fine;
//! a panic, a hang or an allocation past the budget is a finding. What comes out must fit the
//! segmentation schema and cover the take.
//!
//! The methods run on takes of at most `MAX_WORKING` frames at the highest working rate they
//! allow (240 Hz), so one input costs milliseconds; longer takes stop after the motion image.

use mocapseg::image::MotionImage;
use mocapseg::load::{load_bytes_with_budget, MemoryBudget};
use mocapseg::method::{MethodError, NoProgress, RunOptions};

/// The loader's memory budget here (the page's is 1 GiB).
const BUDGET: MemoryBudget = MemoryBudget { max_bytes: 4 << 20 };
/// Frames a method may work on: the take's frames, and its duration at 240 Hz.
const MAX_WORKING: f64 = 600.0;

pub fn seeds() -> Vec<(String, Vec<u8>)> {
    let mut out = crate::bvh_seeds();
    // the methods need a take long enough for their windows: 2 s of a walk, of a boxer, of a dancer
    for (fixture, frames) in [("12_01.bvh", 240), ("assimp_Boxing_Toes_100fps.bvh", 200), ("131_03.bvh", 240)] {
        let take = crate::small_take(fixture, frames);
        out.push((format!("methods-{fixture}"), mocapseg::bvh::write(&take).into_bytes()));
    }
    out
}

/// One input of the target (what `fuzz_targets/load_pipeline.rs` hands libFuzzer's bytes to).
pub fn run(data: &[u8]) {
    let loaded = match load_bytes_with_budget("fuzz.bvh", data, &BUDGET, &mut |_| {}) {
        Ok(l) => l,
        Err(e) => {
            assert!(e.to_string().starts_with("fuzz.bvh: "), "{e}");
            return;
        }
    };
    let motion = &loaded.motion;
    assert!(motion.frames() >= 1);
    assert_eq!(motion.positions.len(), motion.frames() * motion.joints());
    let image = MotionImage::from_motion(motion);
    assert_eq!(image.width, motion.frames());
    assert_eq!(image.rgba.len(), image.width * image.height * 4);
    if let Ok(png) = image.try_to_png() {
        assert!(png.starts_with(b"\x89PNG"));
    }
    let working = (motion.duration_s() * 240.0).max(motion.frames() as f64);
    if !(working <= MAX_WORKING) {
        return;
    }
    for m in mocapseg::methods::registry() {
        let name = m.info().name;
        match m.run_json(
            motion,
            &serde_json::Value::Null,
            &RunOptions { pictures: true, ..RunOptions::default() },
            &mut NoProgress,
        ) {
            Ok(out) => {
                let s = &out.segmentation;
                s.validate().unwrap_or_else(|e| panic!("{name}: the output breaks the schema: {e}"));
                assert_eq!(s.frames, motion.frames(), "{name}");
                for p in &out.details.pictures {
                    assert_eq!(p.rgba.len(), p.width * p.height * 4, "{name}: picture {}", p.id);
                }
                for c in &out.details.curves {
                    assert_eq!(c.values.len(), motion.frames(), "{name}: curve {}", c.id);
                }
            }
            Err(MethodError::Failed(message)) => assert!(!message.trim().is_empty(), "{name}: an empty message"),
            Err(e) => panic!("{name}: unexpected error kind: {e}"),
        }
    }
}
