//! Inputs the fuzz targets (`fuzz/`, `make fuzz`) found to break the crate, minimised and kept in
//! `tests/fixtures/fuzz/`, each with what it must do now.
#![cfg(not(target_arch = "wasm32"))]

use mocapseg::image::MotionImage;
use mocapseg::load::load_bytes;
use mocapseg::method::{MethodError, NoProgress, RunOptions};

fn fixture(name: &str) -> Vec<u8> {
    std::fs::read(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/fuzz").join(name))
        .expect("the fuzz fixture")
}

/// `load_pipeline`: a take whose root is named `Head` panicked in the joint mapping (the path from
/// the hips to the head was one joint long, and the joints between them were sliced as
/// `path[1..0]`) while the loader detected its units. It loads now, and every method gives a
/// result or says why.
#[test]
fn a_root_named_head_loads_and_every_method_answers() {
    let loaded = load_bytes("root-named-head.bvh", &fixture("root-named-head.bvh"), &mut |_| {})
        .expect("a one-joint take whose root is the head loads");
    let motion = &loaded.motion;
    assert_eq!((motion.frames(), motion.joints()), (1, 2));
    assert_eq!(motion.skeleton.names[0], "Head");
    assert_eq!(MotionImage::from_motion(motion).width, 1);
    for m in mocapseg::methods::registry() {
        let name = m.info().name;
        match m.run_json(motion, &serde_json::Value::Null, &RunOptions::default(), &mut NoProgress) {
            Ok(out) => assert_eq!(out.segmentation.frames, 1, "{name}"),
            Err(MethodError::Failed(message)) => assert!(message.len() > 10, "{name}: `{message}`"),
            Err(e) => panic!("{name}: unexpected error kind: {e}"),
        }
    }
}
