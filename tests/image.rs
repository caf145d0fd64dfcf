//! Tests of the DT-FCN motion image (`mocapseg::image`): layout, per-axis scaling, the
//! constant-axis rule, PNG round trip, and the image of a real CMU take.

use mocapseg::bvh::{self, Bvh, BvhJoint, Channel, JointKind};
use mocapseg::image::{scale_to_byte, ImageError, MotionImage};
use mocapseg::motion::Motion;

use Channel::{Xposition as XP, Yposition as YP, Zposition as ZP, Zrotation as ZR};

fn joint(
    name: &str,
    kind: JointKind,
    parent: Option<usize>,
    offset: [f64; 3],
    channels: &[Channel],
    start: usize,
) -> BvhJoint {
    BvhJoint { name: name.into(), kind, parent, offset, channels: channels.to_vec(), channel_start: start }
}

/// Root (moving, rotating) → Child (position channels, so its root-relative position is
/// exactly its channel values) → End Site; plus a second child "Still" that never moves.
fn small_take() -> Motion {
    let joints = vec![
        joint("Root", JointKind::Root, None, [0.0; 3], &[XP, YP, ZP], 0),
        joint("Child", JointKind::Joint, Some(0), [9.0, 9.0, 9.0], &[XP, YP, ZP], 3),
        joint("Child_End", JointKind::EndSite, Some(1), [0.0, 5.0, 0.0], &[], 6),
        joint("Still", JointKind::Joint, Some(0), [0.0, 0.0, 0.0], &[ZR], 6),
    ];
    // Root moves around; Child relative to root: x −1, 0, 3; y 2, −2, 1; z 0 throughout.
    let values = vec![
        10.0, 0.0, 5.0, /**/ -1.0, 2.0, 0.0, /**/ 45.0, //
        20.0, 1.0, 6.0, /**/ 0.0, -2.0, 0.0, /**/ 0.0, //
        30.0, 2.0, 7.0, /**/ 3.0, 1.0, 0.0, /**/ -90.0,
    ];
    let bvh = Bvh { joints, frame_time: 0.1, declared_frames: 3, channels_per_frame: 7, values, warnings: vec![] };
    Motion::from_bvh("small", &bvh).unwrap()
}

#[test]
fn layout_is_frames_by_joints_without_end_sites() {
    let img = MotionImage::from_motion(&small_take());
    assert_eq!(img.width, 3);
    assert_eq!(img.height, 3);
    assert_eq!(img.rows, vec!["Root", "Child", "Still"]);
    assert_eq!(img.rgba.len(), 3 * 3 * 4);
    assert!(img.rgba.chunks(4).all(|p| p[3] == 255));
}

#[test]
fn each_axis_is_scaled_min_to_0_max_to_255_and_constant_axis_is_128() {
    let img = MotionImage::from_motion(&small_take());
    // X over the take (all rows): −1 … 3; Y: −2 … 2; Z: always 0 → 128.
    // Root row: root-relative (0, 0, 0) every frame.
    let root = [
        ((0.0f64 + 1.0) / 4.0 * 255.0).round() as u8, // 63.75 → 64
        ((0.0f64 + 2.0) / 4.0 * 255.0).round() as u8, // 127.5 → 128
        128,
        255,
    ];
    assert_eq!(root, [64, 128, 128, 255]);
    for x in 0..3 {
        assert_eq!(img.pixel(x, 0), root);
        assert_eq!(img.pixel(x, 2), root, "the still joint sits on the root");
    }
    assert_eq!(img.pixel(0, 1), [0, 255, 128, 255]); // x = −1 (min), y = 2 (max)
    assert_eq!(img.pixel(1, 1), [64, 0, 128, 255]); // x = 0, y = −2 (min)
    assert_eq!(img.pixel(2, 1), [255, 191, 128, 255]); // x = 3 (max), y = 1 → 191.25
}

#[test]
fn scale_to_byte_rules() {
    assert_eq!(scale_to_byte(-1.0, -1.0, 3.0), 0);
    assert_eq!(scale_to_byte(3.0, -1.0, 3.0), 255);
    assert_eq!(scale_to_byte(1.0, -1.0, 3.0), 128);
    assert_eq!(scale_to_byte(5.0, 5.0, 5.0), 128);
}

fn decode(png_bytes: &[u8]) -> (png::OutputInfo, Vec<u8>) {
    let decoder = png::Decoder::new(png_bytes);
    let mut reader = decoder.read_info().expect("PNG header");
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).expect("PNG data");
    buf.truncate(info.buffer_size());
    (info, buf)
}

#[test]
fn png_decodes_to_the_same_pixels() {
    let img = MotionImage::from_motion(&small_take());
    let bytes = img.try_to_png().expect("encodes");
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    let (info, pixels) = decode(&bytes);
    assert_eq!((info.width, info.height), (3, 3));
    assert_eq!(info.color_type, png::ColorType::Rgba);
    assert_eq!(info.bit_depth, png::BitDepth::Eight);
    assert_eq!(pixels, img.rgba);
}

#[test]
fn inconsistent_hand_built_image_is_an_error_not_a_panic() {
    let bad = MotionImage { width: 2, height: 2, rgba: vec![0; 3], rows: vec![] };
    let err = bad.try_to_png().unwrap_err();
    assert_eq!(err.to_string(), "image is 2 × 2 but has 3 RGBA bytes (expected 16)");
    let empty = MotionImage { width: 0, height: 5, rgba: vec![], rows: vec![] };
    assert_eq!(empty.try_to_png().unwrap_err().to_string(), "image has no pixels (0 × 5)");
}

#[test]
fn images_png_cannot_hold_are_errors_not_panics_or_empty_files() {
    // PNG allows at most 2^31 − 1 columns: a take that long is refused before any pixel is read.
    let wide = MotionImage { width: 1 << 31, height: 1, rgba: vec![], rows: vec![] };
    assert_eq!(wide.try_to_png().unwrap_err().to_string(), format!("image too large for PNG: {} × 1", 1u64 << 31));
    // width × height × 4 overflowing usize was a panic (debug) or a wrong size check (release).
    let huge = MotionImage { width: usize::MAX, height: 2, rgba: vec![], rows: vec![] };
    assert!(matches!(huge.try_to_png(), Err(ImageError::TooLarge { .. })));
    if usize::BITS == 64 {
        let square = MotionImage { width: 1 << 30, height: 1 << 30, rgba: vec![], rows: vec![] };
        assert!(matches!(square.try_to_png(), Err(ImageError::SizeMismatch { .. })));
    }
}

#[test]
fn image_of_a_cmu_take() {
    let path = format!("{}/tests/fixtures/02_01.bvh", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap();
    let m = Motion::from_bvh("02_01.bvh", &bvh::parse(&text).unwrap()).unwrap();
    let img = MotionImage::from_motion(&m);
    assert_eq!((img.width, img.height), (343, 31));
    assert_eq!(img.rows.len(), 31);
    assert_eq!(img.rows[0], "Hips");
    assert_eq!(img.rows[30], "RThumb");
    assert!(img.rows.iter().all(|r| !r.ends_with("_End")));
    // Every channel reaches both ends of the range.
    for c in 0..3 {
        let vals: Vec<u8> = img.rgba.chunks(4).map(|p| p[c]).collect();
        assert_eq!(vals.iter().min(), Some(&0), "channel {c}");
        assert_eq!(vals.iter().max(), Some(&255), "channel {c}");
    }
    // Recompute one pixel independently: LeftHand at frame 100.
    let rows: Vec<usize> = (0..m.joints()).filter(|&j| !m.skeleton.is_end_site[j]).collect();
    let rel = |f: usize, j: usize| m.frame(f)[j] - m.frame(f)[0];
    let mut lo = [f32::MAX; 3];
    let mut hi = [f32::MIN; 3];
    for f in 0..m.frames() {
        for &j in &rows {
            let p = rel(f, j).to_array();
            for a in 0..3 {
                lo[a] = lo[a].min(p[a]);
                hi[a] = hi[a].max(p[a]);
            }
        }
    }
    let row = img.rows.iter().position(|r| r == "LeftHand").unwrap();
    let p = rel(100, rows[row]).to_array();
    let expect: Vec<u8> =
        (0..3).map(|a| ((p[a] as f64 - lo[a] as f64) / (hi[a] as f64 - lo[a] as f64) * 255.0).round() as u8).collect();
    assert_eq!(&img.pixel(100, row)[..3], &expect[..]);
    // PNG round trip on the real image.
    let (info, pixels) = decode(&img.try_to_png().expect("encodes"));
    assert_eq!((info.width, info.height), (343, 31));
    assert_eq!(pixels, img.rgba);
}
