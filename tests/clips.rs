//! Clips: a segment cut from a take is a BVH with the take's hierarchy, channel order and frame
//! time whose frames, read back through the loader, are the take's frames; moved to the origin it
//! starts on the floor's origin facing +Z and keeps its shape and path.
#![cfg(not(target_arch = "wasm32"))]

use std::path::Path;

use glam::Vec3;
use mocapseg::bvh;
use mocapseg::clips::{clips, cut, ClipOptions, Which};
use mocapseg::load::{load_bytes, load_path};
use mocapseg::motion::joints::map_joints;
use mocapseg::motion::normalize::facing_yaw;
use mocapseg::segment::{Level, Segment, Segmentation};

fn fixture(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures").join(name)
}

fn segment(start: usize, end: usize, level: Level, label: &str) -> Segment {
    serde_json::from_value(serde_json::json!({
        "start": start, "end": end, "label": label, "level": level, "cluster": null, "score": null
    }))
    .unwrap()
}

#[test]
fn a_clip_read_back_gives_the_same_frames() {
    for take in ["131_03.bvh", "02_01.amc", "pybvh_bvh_test1.bvh"] {
        let loaded = load_path(&fixture(take)).unwrap();
        let frames = loaded.motion.frames();
        let (start, end) = (frames / 3, frames / 3 + frames / 4);
        let clip = cut(&loaded.bvh, start, end).unwrap();
        let text = bvh::write(&clip);
        let back = load_bytes("clip.bvh", text.as_bytes(), &mut |_| {}).unwrap();
        assert!(back.bvh.warnings.is_empty(), "{take}: {:?}", back.bvh.warnings);
        assert_eq!(back.bvh.joints, loaded.bvh.joints, "{take}: the hierarchy and channel order");
        assert_eq!(back.bvh.frame_time, loaded.bvh.frame_time, "{take}");
        assert_eq!(back.motion.frames(), end - start + 1);
        let original = &loaded.motion.positions[start * loaded.motion.joints()..(end + 1) * loaded.motion.joints()];
        assert_eq!(back.motion.positions, original, "{take}: the positions, bit for bit");
    }
}

#[test]
fn a_clip_moved_to_the_origin_starts_there_facing_plus_z_with_its_shape_and_path() {
    let loaded = load_path(&fixture("131_03.bvh")).unwrap();
    let m = &loaded.motion;
    let seg = Segmentation {
        file: "131_03.bvh".into(),
        fps: m.fps,
        frames: m.frames(),
        method: "test".into(),
        params: serde_json::json!({}),
        segments: vec![segment(300, 699, Level::Action, "hop"), segment(700, 1000, Level::Transition, "transition")],
    };
    let options = ClipOptions { which: Which::Actions, to_origin: true };
    let cut_clips = clips(&loaded.bvh, m, &seg, "131_03", &options).unwrap();
    assert_eq!(cut_clips.len(), 1, "transitions are left out of the actions");
    assert_eq!(cut_clips[0].file, "131_03_01_hop.bvh");
    let back = load_bytes("clip.bvh", bvh::write(&cut_clips[0].bvh).as_bytes(), &mut |_| {}).unwrap().motion;
    let map = map_joints(&back.skeleton).unwrap();
    let root = |mo: &mocapseg::motion::Motion, f: usize| mo.position(f, 0);
    // the first frame: root over the origin, at its height, facing +Z
    let r0 = root(&back, 0);
    assert!(r0.x.abs() < 1e-3 && r0.z.abs() < 1e-3, "{r0}");
    assert!((r0.y - root(m, 300).y).abs() < 1e-3);
    let yaw = facing_yaw(back.frame(0), &map).unwrap();
    assert!(yaw.abs() < 1e-4, "facing yaw {yaw}");
    // the shape (every joint relative to the root) and the path are the original's, turned
    let turn = glam::Quat::from_rotation_y(-facing_yaw(m.frame(300), &map).unwrap());
    for f in 0..back.frames() {
        for j in 0..back.joints() {
            let expected = turn * (m.position(300 + f, j) - root(m, 300)) + Vec3::new(0.0, root(m, 300).y, 0.0);
            let got = back.position(f, j);
            assert!((got - expected).length() < 2e-3, "frame {f} joint {j}: {got} vs {expected}");
        }
    }
}

#[test]
fn clips_are_refused_for_another_take_or_an_empty_choice() {
    let loaded = load_path(&fixture("131_03.bvh")).unwrap();
    let seg = Segmentation {
        file: "x.bvh".into(),
        fps: 120.0,
        frames: 10,
        method: "test".into(),
        params: serde_json::json!({}),
        segments: vec![segment(0, 9, Level::Action, "a")],
    };
    let e = clips(&loaded.bvh, &loaded.motion, &seg, "x", &ClipOptions::default()).unwrap_err().to_string();
    assert!(e.contains("take of 10 frames, this take has 1102"), "{e}");
    let seg = Segmentation { frames: 1102, ..seg };
    let options = ClipOptions { which: Which::Primitives, to_origin: false };
    let e = clips(&loaded.bvh, &loaded.motion, &seg, "x", &options).unwrap_err().to_string();
    assert_eq!(e, "the segmentation has no primitive segments");
    assert!(cut(&loaded.bvh, 5, 1102).unwrap_err().to_string().contains("not inside the take (0–1101)"));
}

#[test]
fn every_clip_in_one_zip_reads_back() {
    use std::io::Read;
    let loaded = load_path(&fixture("131_03.bvh")).unwrap();
    let seg = Segmentation {
        file: "131_03.bvh".into(),
        fps: 120.0,
        frames: 1102,
        method: "test".into(),
        params: serde_json::json!({}),
        segments: vec![segment(0, 299, Level::Action, "start"), segment(300, 1101, Level::Action, "hop")],
    };
    let all = clips(&loaded.bvh, &loaded.motion, &seg, "131_03", &ClipOptions::default()).unwrap();
    let bytes = mocapseg::clips::zip(&all).unwrap();
    let text_size: usize = all.iter().map(|c| bvh::write(&c.bvh).len()).sum();
    assert!(bytes.len() < text_size / 2, "deflated: {} of {text_size} bytes", bytes.len());
    let mut archive = zip::ZipArchive::new(std::io::Cursor::new(bytes)).unwrap();
    assert_eq!(archive.len(), 2);
    for (i, clip) in all.iter().enumerate() {
        let mut file = archive.by_index(i).unwrap();
        assert_eq!(file.name().unwrap(), clip.file);
        let mut text = String::new();
        file.read_to_string(&mut text).unwrap();
        assert_eq!(bvh::parse(&text).unwrap(), clip.bvh);
    }
}

#[test]
fn the_page_s_export_is_the_zip_of_every_clip_or_one_clip_under_its_zip_name() {
    use mocapseg::clips::{export, ClipError};
    let loaded = load_path(&fixture("131_03.bvh")).unwrap();
    let m = &loaded.motion;
    let seg = Segmentation {
        file: "131_03.bvh".into(),
        fps: m.fps,
        frames: m.frames(),
        method: "test".into(),
        params: serde_json::json!({}),
        segments: vec![
            segment(0, 299, Level::Action, "start"),
            segment(300, 699, Level::Action, "hop"),
            segment(700, 1101, Level::Transition, "transition"),
        ],
    };
    for to_origin in [false, true] {
        let options = ClipOptions { which: Which::Actions, to_origin };
        let all = clips(&loaded.bvh, m, &seg, "131_03", &options).unwrap();
        let zipped = export(&loaded.bvh, m, &seg, "131_03", &options, None).unwrap();
        assert_eq!(zipped.file, "131_03_actions_clips.zip");
        assert_eq!(zipped.clips, 2);
        assert_eq!(zipped.bytes, mocapseg::clips::zip(&all).unwrap(), "the same zip as `mocapseg clips --zip`");
        let one = export(&loaded.bvh, m, &seg, "131_03", &options, Some((300, 699))).unwrap();
        assert_eq!((one.file.as_str(), one.clips), ("131_03_02_hop.bvh", 1));
        assert_eq!(one.bytes, bvh::write(&all[1].bvh).into_bytes(), "the second clip of the zip, origin {to_origin}");
    }
    let every = ClipOptions { which: Which::All, to_origin: false };
    assert_eq!(export(&loaded.bvh, m, &seg, "131_03", &every, None).unwrap().file, "131_03_all_clips.zip");
    // a transition is not an action; frames that are no segment's
    let actions = ClipOptions::default();
    let e = export(&loaded.bvh, m, &seg, "131_03", &actions, Some((700, 1101))).unwrap_err();
    assert_eq!(e, ClipError::NoSegment { which: "action".into(), start: 700, end: 1101 });
    assert_eq!(e.to_string(), "the segmentation has no action segment at frames 700–1101");
    let other = Segmentation { frames: 50, segments: vec![segment(0, 49, Level::Action, "x")], ..seg.clone() };
    assert!(matches!(
        export(&loaded.bvh, m, &other, "131_03", &actions, Some((0, 49))),
        Err(ClipError::OtherTake { segmentation: 50, take: 1102 })
    ));
}

#[test]
fn a_row_as_a_label_csv_reads_back_as_the_same_rows() {
    use mocapseg::labels::{from_segmentation, read_csv, to_csv};
    let seg = Segmentation {
        file: "a, \"b\".bvh".into(),
        fps: 120.0,
        frames: 1000,
        method: "test".into(),
        params: serde_json::json!({}),
        segments: vec![
            segment(500, 999, Level::Action, "jump, high"),
            segment(0, 199, Level::Action, "walk"),
            segment(200, 499, Level::Transition, ""),
            segment(0, 99, Level::Primitive, "c1"),
        ],
    };
    let actions = from_segmentation(&seg, Which::Actions);
    assert_eq!(actions.iter().map(|r| (r.start_frame, r.end_frame)).collect::<Vec<_>>(), [(0, 199), (500, 999)]);
    assert!(actions.iter().all(|r| r.file == seg.file));
    let all = from_segmentation(&seg, Which::All);
    assert_eq!(all.len(), 4);
    assert_eq!(all[2].label, "unlabelled", "an empty label would not read back");
    for rows in [actions, all, from_segmentation(&seg, Which::Primitives)] {
        assert_eq!(read_csv(&to_csv(&rows), "x.csv").unwrap(), rows);
    }
}
