//! SSSM segmentation (Krüger et al. 2017: activities §IV-B, primitives §IV-C, mirror §V,
//! clusters §VI) on synthetic feature sequences with known answers, on
//! hand-made neighbour lists, and end to end on fixture takes.
//!
//! The same tests run natively (`cargo test --test sssm`) and in headless Chromium
//! (`cargo test --target wasm32-unknown-unknown --test sssm`, runner in `.cargo/config.toml`):
//! fixtures are embedded with `include_bytes!`, and in wasm `#[test]` is wasm-bindgen-test's.

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;
#[cfg(target_arch = "wasm32")]
wasm_bindgen_test::wasm_bindgen_test_configure!(run_in_browser);

use mocapseg::methods::sssm::activities::RegionGrowing;
use mocapseg::methods::sssm::primitives::PrimitiveSearch;
use mocapseg::methods::sssm::{
    segment, segment_features, segment_features_within, FeatureMatrix, MirrorMap, Sssm, SssmError, SssmOutcome,
    SssmParams,
};
use mocapseg::segment::Level;
use mocapseg::similarity::neighbours::{FarSearch, StackedSearch};
use mocapseg::similarity::paths::NeighbourhoodGraph;
use mocapseg::similarity::Span;
use std::f32::consts::TAU;

/// Deterministic noise in [-0.5, 0.5).
struct Noise(mocapseg::stats::Rng);

impl Noise {
    fn new(seed: u64) -> Self {
        Noise(mocapseg::stats::Rng::new(seed))
    }

    fn next(&mut self) -> f32 {
        self.0.next_f32() - 0.5
    }
}

/// One frame of the 15 end-effector values `[LH, RH, LF, RF, Head] × (x, y, z)` in inches
/// (x lateral, left side at +x; y up; z forward), as `motion::normalize` produces them.
type Pose = [f32; 15];

fn matrix(poses: &[Pose], noise: &mut Noise, amplitude: f32) -> FeatureMatrix {
    let rows: Vec<Pose> = poses.iter().map(|p| p.map(|v| v + amplitude * noise.next())).collect();
    FeatureMatrix::from_rows(&rows).unwrap()
}

/// Arms circling in front of the body, feet still; `period` frames per circle.
fn arm_circles(t: f32, period: f32) -> Pose {
    let a = TAU * t / period;
    [
        12.0 + 10.0 * a.cos(),
        20.0 + 10.0 * a.sin(),
        10.0, // left hand
        -12.0 - 10.0 * a.cos(),
        20.0 + 10.0 * a.sin(),
        10.0, // right hand
        8.0,
        -35.0,
        0.0, // left foot
        -8.0,
        -35.0,
        0.0, // right foot
        0.0,
        25.0,
        0.0, // head
    ]
}

/// Squats: the body goes down and up, hands reach forward at the bottom; `period` frames each.
fn squats(t: f32, period: f32) -> Pose {
    let depth = 0.5 - 0.5 * (TAU * t / period).cos(); // 0 standing … 1 bottom
    [
        10.0,
        -10.0 + 25.0 * depth,
        5.0 + 20.0 * depth, // hands rise forward as the hips drop
        -10.0,
        -10.0 + 25.0 * depth,
        5.0 + 20.0 * depth,
        9.0,
        -35.0 + 15.0 * depth,
        2.0 * depth, // feet come closer to the hips
        -9.0,
        -35.0 + 15.0 * depth,
        2.0 * depth,
        0.0,
        25.0,
        6.0 * depth,
    ]
}

/// Walking in place: each foot swings forward and lifts, the arms swing against the legs, the
/// right side half a cycle after the left: frame `t` mirrored is frame `t + period/2`.
fn gait(t: f32, period: f32) -> Pose {
    let side = |phase: f32, sign: f32| {
        let a = TAU * phase;
        let foot = [sign * 8.0, -35.0 + 4.0 * a.sin().max(0.0), 14.0 * a.sin()];
        let hand = [sign * 17.0, -2.0, -12.0 * a.sin()];
        (foot, hand)
    };
    let (lf, lh) = side(t / period, 1.0);
    let (rf, rh) = side(t / period + 0.5, -1.0);
    let bob = 1.0 * (2.0 * TAU * t / period).cos();
    [lh[0], lh[1], lh[2], rh[0], rh[1], rh[2], lf[0], lf[1], lf[2], rf[0], rf[1], rf[2], 0.0, 25.0 + bob, 0.0]
}

fn run(base: &FeatureMatrix, mirror: bool, params: SssmParams) -> SssmOutcome {
    let valid = params.mirror(mirror).check().unwrap();
    let map = MirrorMap::end_effectors();
    segment_features(base, Some(&map), &valid, &mut |_, _| Ok(())).unwrap()
}

/// Boundaries between consecutive actions, each transition split at its middle (how the
/// action level is scored).
fn action_boundaries(o: &SssmOutcome) -> Vec<usize> {
    o.actions.windows(2).map(|w| (w[0].span.end + 1 + w[1].span.start) / 2).collect()
}

fn median(mut v: Vec<usize>) -> usize {
    mocapseg::stats::median(&mut v).expect("some values")
}

#[test]
fn two_periodic_activities_back_to_back_give_one_cut_at_the_switch() {
    let poses: Vec<Pose> =
        (0..1200).map(|t| if t < 600 { arm_circles(t as f32, 31.3) } else { squats(t as f32, 43.7) }).collect();
    let o = run(&matrix(&poses, &mut Noise::new(1), 1.0), true, SssmParams::new());
    assert_eq!(o.actions.len(), 2, "actions: {:?}", o.actions);
    let b = action_boundaries(&o);
    // Each stacked feature spans ±10 frames, so the 20 frames around the switch mix both
    // activities; a stop after w = 5 empty scan lines adds at most 5 frames: ±15 frames.
    assert!(b[0].abs_diff(600) <= 15, "boundary at {} instead of 600", b[0]);
    // both actions nearly fill their halves (the first period has nothing to repeat yet)
    assert!(o.actions[0].span.start <= 45 && o.actions[1].span.end >= 1150, "{:?}", o.actions);
    // different kinds of action
    assert_ne!(o.actions[0].cluster, o.actions[1].cluster);
}

#[test]
fn arm_circles_reversed_halfway_are_one_action_when_merging_by_poses() {
    // circles forward, then the same circles backward (the stacked features see two activities,
    // the poses one), then squats
    let poses: Vec<Pose> = (0..1500)
        .map(|t| match t {
            0..600 => arm_circles(t as f32, 31.3),
            600..1000 => arm_circles(-(t as f32), 31.3),
            _ => squats(t as f32, 43.7),
        })
        .collect();
    let base = matrix(&poses, &mut Noise::new(7), 1.0);
    let paper = run(&base, true, SssmParams::new().pose_merge(0.0));
    assert_eq!(paper.actions.len(), 3, "without merging: {:?}", paper.actions);
    let merged = run(&base, true, SssmParams::new());
    assert_eq!(merged.actions.len(), 2, "with merging: {:?}", merged.actions);
    let b = action_boundaries(&merged);
    assert!(b[0].abs_diff(1000) <= 15, "boundary at {} instead of 1000", b[0]);
}

#[test]
fn a_periodic_motion_is_cut_into_primitives_of_its_period() {
    let period = 40.0;
    let poses: Vec<Pose> = (0..900).map(|t| squats(t as f32, period)).collect();
    let o = run(&matrix(&poses, &mut Noise::new(2), 1.0), false, SssmParams::new());
    assert_eq!(o.actions.len(), 1, "actions: {:?}", o.actions);
    let a = o.actions[0].span;
    assert!(a.start <= 40 && a.end >= 860, "the action covers the take: {a:?}");
    let lengths: Vec<usize> = o.primitives.iter().map(|p| p.span.len()).collect();
    // inner primitives (the first and last may be partial cycles)
    let inner = lengths[1..lengths.len() - 1].to_vec();
    assert!(inner.len() >= 18, "{} primitives for 22 cycles: {lengths:?}", lengths.len());
    assert_eq!(median(inner.clone()), 40, "primitive lengths {lengths:?}");
    assert!(inner.iter().all(|&l| l.abs_diff(40) <= 3), "primitive lengths {lengths:?}");
    // all full cycles are one cluster
    let c = o.primitives[1].cluster;
    assert!(o.primitives[1..o.primitives.len() - 1].iter().all(|p| p.cluster == c), "{:?}", o.primitives);
}

#[test]
fn a_mirrored_gait_alternates_between_two_mirror_clusters() {
    let period = 36.0;
    let poses: Vec<Pose> = (0..900).map(|t| gait(t as f32, period)).collect();
    let base = matrix(&poses, &mut Noise::new(3), 0.5);

    // without the mirror, primitives are whole cycles
    let plain = run(&base, false, SssmParams::new());
    assert_eq!(plain.actions.len(), 1);
    let inner: Vec<usize> = plain.primitives[1..plain.primitives.len() - 1].iter().map(|p| p.span.len()).collect();
    assert_eq!(median(inner), 36, "{:?}", plain.primitives);

    // with it, every cycle splits into two steps that alternate between mirror clusters
    let o = run(&base, true, SssmParams::new());
    assert_eq!(o.actions.len(), 1);
    let steps = &o.primitives[1..o.primitives.len() - 1];
    assert!(steps.len() >= 40, "{} steps", steps.len());
    assert_eq!(median(steps.iter().map(|p| p.span.len()).collect()), 18, "{:?}", o.primitives);
    let (a, b) = (steps[0].cluster, steps[1].cluster);
    assert_ne!(a, b);
    for (k, p) in steps.iter().enumerate() {
        assert_eq!(p.cluster, if k % 2 == 0 { a } else { b }, "step {k}: {:?}", o.primitives);
    }
    assert_eq!(o.clusters[a].mirror_of, Some(b));
    assert_eq!(o.clusters[b].mirror_of, Some(a));
    assert_eq!(o.actions[0].symmetry, mocapseg::methods::sssm::SymmetryKind::PhaseShifted);
}

#[test]
fn region_growing_on_hand_made_lists() {
    // Frames 0..=99: a repeated block 10..=59 (frame i matches i ± 20, ± 40) and nothing else
    // but the main diagonal.
    let n = 100;
    let mut lists = vec![Vec::new(); n];
    for (i, list) in lists.iter_mut().enumerate() {
        list.push((i as u32, 0.0));
        for k in [20i64, 40] {
            for j in [i as i64 - k, i as i64 + k] {
                if (10..60).contains(&(i as i64)) && (10..60).contains(&j) {
                    list.push((j as u32, 2.0));
                }
            }
        }
    }
    let s = Sssm::from_lists(&lists).unwrap();
    let grow = RegionGrowing { sssm: &s, mirror: None, band: 10, stop_window: 5, min_entries: 10, relative: Some(1.5) };
    let forward = grow.forward();
    assert_eq!(forward.len(), 1);
    // scan line i counts j in [0, i − 10]: i − 20 for i in 30..=59, i − 40 for i in 50..=59
    assert_eq!((forward[0].seed, forward[0].end, forward[0].entries), (0, 59, 40));
    let act = grow.activities(mocapseg::methods::sssm::BoundaryRule::Paper);
    assert_eq!(act.backward_starts, vec![10]);
    assert_eq!(act.actions, vec![Span { start: 10, end: 59 }]);
    assert_eq!(act.transitions, vec![Span { start: 0, end: 9 }, Span { start: 60, end: 99 }]);
}

#[test]
fn warping_paths_outside_the_slope_limits_give_no_cut() {
    // one action 0..=99; a diagonal j = i + 30 (slope 1) and a steep stretch j = 3(i − 10) + 50
    // (slope 3) for i in 10..=25
    let n = 100;
    let mut lists = vec![Vec::new(); n];
    for (i, list) in lists.iter_mut().enumerate().take(70) {
        list.push(((i + 30) as u32, 1.0));
    }
    for (i, list) in lists.iter_mut().enumerate().take(26).skip(10) {
        for j in 3 * (i - 10) + 50..3 * (i - 10) + 53 {
            if !list.iter().any(|&(c, _)| c as usize == j) {
                list.push((j as u32, 0.5));
            }
        }
    }
    let s = Sssm::from_lists(&lists).unwrap();
    let graph = NeighbourhoodGraph::new(&s);
    let search = PrimitiveSearch { nu: 2.0, min_path_frames: 5, min_cut_distance: 5 };
    let cuts = search.cuts(&graph, &[Span { start: 0, end: 99 }]);
    assert_eq!(cuts[0].iter().map(|c| c.frame).collect::<Vec<_>>(), vec![30]);
    assert_eq!(cuts[0][0].path.slope(), Some(1.0));
    // with ν = 4 the steep path is valid too; its cheapest route enters row 10 at (10, 52)
    // and leaves row 25 at (25, 95): slope 43/15 ≈ 2.9, and a second cut at 52
    let loose = PrimitiveSearch { nu: 4.0, ..search };
    let cuts = loose.cuts(&graph, &[Span { start: 0, end: 99 }]);
    assert_eq!(cuts[0].iter().map(|c| c.frame).collect::<Vec<_>>(), vec![30, 52]);
    assert_eq!((cuts[0][1].path.start, cuts[0][1].path.end), ((10, 52), (25, 95)));
}

#[test]
fn parameters_are_checked_with_readable_errors() {
    let e = SssmParams::new().radius(-1.0).check().unwrap_err();
    assert_eq!(e.to_string(), "invalid SSSM parameter radius = -1: expected a positive radius in inches");
    let e = SssmParams::new().offsets(vec![-5, 0, 0]).check().unwrap_err();
    assert!(matches!(e, SssmError::InvalidParam { name: "offsets", .. }), "{e}");
    assert!(e.to_string().contains("distinct frame offsets"));
    let e = SssmParams::new().nu(0.9).check().unwrap_err();
    assert!(e.to_string().contains("ν ≥ 1"), "{e}");
    let ok = SssmParams::new().check().unwrap();
    assert!((ok.search_radius() - 19.0 * 5f64.sqrt()).abs() < 1e-9);
}

#[test]
fn features_of_the_wrong_shape_are_rejected() {
    let base = FeatureMatrix::from_rows(&[[0.0f32; 6]; 40]).unwrap();
    let valid = SssmParams::new().check().unwrap();
    let e = segment_features(&base, Some(&MirrorMap::end_effectors()), &valid, &mut |_, _| Ok(())).unwrap_err();
    assert!(e.to_string().contains("mirror map is for 15 values"), "{e}");
    // without a mirror map the same features are fine (a still take: no action)
    let o = segment_features(&base, None, &valid, &mut |_, _| Ok(())).unwrap();
    assert!(o.actions.is_empty());
    assert_eq!(o.activities.transitions, vec![Span { start: 0, end: 39 }]);
}

#[test]
fn tiny_still_and_huge_inputs_are_handled() {
    let valid = SssmParams::new().check().unwrap();
    let map = MirrorMap::end_effectors();
    for n in [1, 2, 5, 31] {
        let base = matrix(&vec![squats(0.0, 40.0); n], &mut Noise::new(n as u64), 0.1);
        let o = segment_features(&base, Some(&map), &valid, &mut |_, _| Ok(())).unwrap();
        assert!(o.actions.is_empty() && o.primitives.is_empty(), "{n} frames");
        assert_eq!(o.activities.transitions, vec![Span { start: 0, end: n - 1 }]);
    }
    // a perfectly still take: every frame is every frame's neighbour, capped
    let still = FeatureMatrix::from_rows(&vec![squats(0.0, 40.0); 900]).unwrap();
    let o = segment_features(&still, Some(&map), &valid, &mut |_, _| Ok(())).unwrap();
    assert!((0..900).all(|i| o.sssm.row(i).0.len() <= 600));
    assert!(o.actions.len() <= 1);
    // more neighbours than the entry budget: a still take of 3000 frames draws about 3000 × 600
    // entries in its near search (the upper triangle within the 20 s horizon, capped at 600 a row)
    // and about twice as many in the far block of its one long action; refused with a budget of a
    // million, naming it and what to do, and run within eight million
    let still = FeatureMatrix::new(3_000, 1, vec![0.0; 3_000]).unwrap();
    let e = segment_features_within(&still, None, &valid, 1_000_000, &mut |_, _| Ok(())).unwrap_err();
    assert!(matches!(e, SssmError::TooLarge { limit: 1_000_000, max_neighbours: 600, .. }), "{e}");
    assert!(e.to_string().contains("1000000 entries") && e.to_string().contains("lower max_neighbours"), "{e}");
    let o = segment_features_within(&still, None, &valid, 8_000_000, &mut |_, _| Ok(())).unwrap();
    assert!((0..3_000).all(|i| o.sssm.row(i).0.len() <= 600) && o.sssm.entries() > 1_500_000);
    // a cancel is still a cancel, not the budget
    let e = segment_features_within(&still, None, &valid, 1_000_000, &mut |stage, _| {
        if stage == "neighbours" {
            Err(mocapseg::method::Cancelled)
        } else {
            Ok(())
        }
    })
    .unwrap_err();
    assert!(matches!(e, SssmError::Cancelled), "{e}");
}

#[test]
fn segmenting_a_take_gives_a_valid_segmentation_at_the_file_rate() {
    let motion = &load("131_01.bvh", include_bytes!("fixtures/131_01.bvh"));
    let mut stages = Vec::new();
    let r = mocapseg::methods::sssm::segment_with_progress(motion, &SssmParams::new(), &mut |s, f| {
        stages.push((s.to_string(), f));
        Ok(())
    })
    .unwrap();
    let seg = &r.segmentation;
    seg.validate().unwrap();
    assert_eq!((seg.fps, seg.frames, seg.method.as_str()), (motion.fps, motion.frames(), "sssm"));
    assert_eq!(seg.params["radius"], 19.0);
    assert_eq!(stages.first().map(|s| s.0.as_str()), Some("features"));
    assert_eq!(stages.last().map(|s| s.1), Some(1.0));
    // progress never goes back, and the neighbour search reports as it goes
    assert!(stages.windows(2).all(|w| w[0].1 <= w[1].1), "{stages:?}");
    assert!(stages.iter().filter(|s| s.0 == "neighbours").count() >= 3, "{stages:?}");
    // actions and transitions tile the take
    let mut top: Vec<_> = seg.segments.iter().filter(|s| s.level != Level::Primitive).collect();
    top.sort_by_key(|s| s.start);
    assert_eq!(top.first().unwrap().start, 0);
    assert_eq!(top.last().unwrap().end, motion.frames() - 1);
    for w in top.windows(2) {
        assert_eq!(w[0].end + 1, w[1].start, "{:?} then {:?}", w[0], w[1]);
    }
    // primitives tile the actions
    for a in seg.level(Level::Action) {
        let prims: Vec<_> = seg.level(Level::Primitive).filter(|p| p.start >= a.start && p.end <= a.end).collect();
        assert_eq!(prims.first().unwrap().start, a.start);
        assert_eq!(prims.last().unwrap().end, a.end);
        assert_eq!(prims.iter().map(|p| p.end + 1 - p.start).sum::<usize>(), a.end + 1 - a.start);
    }
    // 131_01 is "start, walk, stop": one walking action between standing still
    let actions: Vec<_> = seg.level(Level::Action).collect();
    assert_eq!(actions.len(), 1, "{actions:?}");
    let t = |f: usize| f as f64 / motion.fps;
    assert!(t(actions[0].start) > 0.5 && t(actions[0].end) < t(motion.frames()) - 0.5, "{:?}", actions[0]);
    // primitives name their cluster's mirror partner (SSSM §V) in the schema's `mirror_of`
    for p in seg.level(Level::Primitive) {
        let c = p.cluster.unwrap();
        assert_eq!(p.mirror_of, r.outcome.clusters[c].mirror_of, "{p:?}");
        assert_eq!(p.label.contains("mirrors"), p.mirror_of.is_some(), "{p:?}");
    }
    // 02_01 walks: its steps are left and right steps, mirror images of each other
    let walk = segment(&load("02_01.bvh", include_bytes!("fixtures/02_01.bvh")), &SssmParams::new()).unwrap();
    let steps: Vec<_> = walk.segmentation.level(Level::Primitive).collect();
    assert!(steps.len() >= 2 && steps.iter().all(|p| p.mirror_of.is_some()), "{steps:?}");
    assert_eq!(steps[0].mirror_of, steps[1].cluster, "{steps:?}");
    // the working rate maps back: 120 Hz file, 30 Hz working frames
    assert_eq!(r.outcome.fps, 30.0);
    assert_eq!(r.source_frames[3], 12.0);
    assert!(segment(motion, &SssmParams::new().radius(0.0)).is_err());
}

fn load(name: &str, bytes: &[u8]) -> mocapseg::motion::Motion {
    mocapseg::load::load_bytes(name, bytes, &mut |_| {}).unwrap().motion
}

fn mean_abs(f: &FeatureMatrix) -> f64 {
    f.as_slice().iter().map(|v| v.abs() as f64).sum::<f64>() / f.as_slice().len() as f64
}

#[test]
fn features_are_in_inches_whatever_the_file_units() {
    // the same take in CMU ASF units and in metres
    let asf = load("131_01.bvh", include_bytes!("fixtures/131_01.bvh"));
    let metres = load("scaled.bvh", include_bytes!("fixtures/cmu_131_01_scaled_meters.bvh"));
    for body_scale in [false, true] {
        let valid = SssmParams::new().body_scale(body_scale).check().unwrap();
        let a = mocapseg::methods::sssm::features::from_motion(&asf, &valid).unwrap();
        let m = mocapseg::methods::sssm::features::from_motion(&metres, &valid).unwrap();
        assert_eq!(a.base.dim(), 15);
        assert_eq!(a.base.frames(), 249, "994 frames at 120 Hz → 249 at 30 Hz");
        let (ma, mm) = (mean_abs(&a.base), mean_abs(&m.base));
        assert!((ma / mm - 1.0).abs() < 0.01, "body_scale {body_scale}: {ma} vs {mm} inches");
        // hands, feet and head lie within a body's reach of the hips: 5–30 inches on average
        assert!((5.0..30.0).contains(&ma), "{ma}");
    }
    // without body scaling the factor is inches per ASF unit (1/0.45)
    let valid = SssmParams::new().body_scale(false).check().unwrap();
    let a = mocapseg::methods::sssm::features::from_motion(&asf, &valid).unwrap();
    assert!((a.scale - 0.056444 / 0.0254).abs() < 1e-9, "{}", a.scale);
}

#[test]
fn a_skeleton_without_hands_and_feet_is_refused_with_a_message() {
    let motion = load("simple.bvh", include_bytes!("fixtures/bvh_anim_test_simple.bvh"));
    let e = segment(&motion, &SssmParams::new()).unwrap_err();
    assert!(matches!(e, SssmError::MissingJoints(_)), "{e}");
    assert!(e.to_string().contains("hands, feet, head and hips"), "{e}");
}

#[test]
fn the_bundled_sample_is_cut_where_its_annotation_says() {
    // www/sample.bvh = CMU 13_30; mocap6 annotation (Fox et al. 2014): JumpJack, Twist,
    // KneeRaise, Squat, Jog, boundaries at AMC frames 217, 805, 1417, 1933 (1-based, 120 Hz)
    let motion = load("sample.bvh", include_bytes!("../www/sample.bvh"));
    let r = segment(&motion, &SssmParams::new()).unwrap();
    let actions: Vec<_> = r.segmentation.level(Level::Action).collect();
    assert_eq!(actions.len(), 5, "{actions:?}");
    let bounds: Vec<usize> = actions.windows(2).map(|w| (w[0].end + 1 + w[1].start) / 2).collect();
    for (found, truth) in bounds.iter().zip([216, 804, 1416, 1932]) {
        assert!(found.abs_diff(truth) <= 60, "boundary at {found}, annotated at {truth} (±0.5 s)");
    }
    // five different exercises: five kinds of action
    let mut kinds: Vec<_> = actions.iter().map(|a| a.cluster).collect();
    kinds.sort_unstable();
    kinds.dedup();
    assert_eq!(kinds.len(), 5);
}

#[test]
fn the_stacked_search_and_the_kd_tree_give_the_same_segmentation() {
    use mocapseg::methods::sssm::NeighbourSearchKind;
    let motion = load("sample.bvh", include_bytes!("../www/sample.bvh"));
    // the kd-tree searches every pair: compare with the stacked search without a horizon
    let stacked = segment(&motion, &SssmParams::new().horizon_s(0.0)).unwrap();
    let tree = segment(&motion, &SssmParams::new().neighbour_search(NeighbourSearchKind::KdTree)).unwrap();
    assert_eq!(stacked.outcome.sssm.to_lists().len(), tree.outcome.sssm.to_lists().len());
    // the same neighbours (distances agree to rounding: summed per frame vs over all values)
    let (a, b) = (&stacked.outcome.sssm, &tree.outcome.sssm);
    assert!(a.entries() > 10 * a.frames(), "the take needs real neighbours, got {}", a.entries());
    assert_eq!(a.cols(), b.cols());
    assert!(a.dists().iter().zip(b.dists()).all(|(x, y)| (x - y).abs() < 1e-3));
    let (ma, mb) = (stacked.outcome.mirror_sssm.as_ref().unwrap(), tree.outcome.mirror_sssm.as_ref().unwrap());
    assert_eq!(ma.cols(), mb.cols());
    let spans = |r: &mocapseg::methods::sssm::SssmResult| -> Vec<(usize, usize, Level)> {
        r.segmentation.segments.iter().map(|s| (s.start, s.end, s.level)).collect()
    };
    assert_eq!(spans(&stacked), spans(&tree));
    assert_eq!(stacked.segmentation.params["neighbour_search"], "stacked");
    assert_eq!(tree.segmentation.params["neighbour_search"], "kd_tree");
}

#[test]
fn with_a_search_horizon_an_activity_repeated_far_away_is_still_one_kind() {
    // arm circles, squats for 40 s, arm circles again: the two circling actions are farther
    // apart than a 10 s horizon, so only a far block can tell they are one kind
    let poses: Vec<Pose> = (0..2400)
        .map(|t| if (600..1800).contains(&t) { squats(t as f32, 43.7) } else { arm_circles(t as f32, 31.3) })
        .collect();
    let base = matrix(&poses, &mut Noise::new(4), 1.0);
    let exact = run(&base, true, SssmParams::new().horizon_s(0.0));
    let near = run(&base, true, SssmParams::new().horizon_s(10.0));
    assert_eq!(exact.actions.len(), 3, "{:?}", exact.actions);
    assert_eq!(exact.actions[0].cluster, exact.actions[2].cluster);
    // the same actions, kinds, primitives and clusters as without a horizon
    assert_eq!(near.actions, exact.actions);
    assert_eq!(near.primitives, exact.primitives);
    assert_eq!(near.clusters, exact.clusters);
    assert!(near.primitives.len() >= 60, "{} primitives", near.primitives.len());
    // the far block between the two circling actions linked them
    assert!(near.far_pairs.contains(&(0, 2, true)), "{:?}", near.far_pairs);
    // beyond 10 s the SSSM only holds the far block and each action's own block
    let h = 300;
    let block = |i: usize, j: usize| {
        let of = |f: usize| near.actions.iter().position(|a| a.span.contains(f));
        let (a, b) = (of(i), of(j));
        a.is_some() && (a == b || (a, b) == (Some(2), Some(0)))
    };
    let mut far = 0;
    for i in 0..near.frames {
        for &j in near.sssm.row(i).0 {
            let (i, j) = (i.max(j as usize), i.min(j as usize));
            assert!(i - j <= h || block(i, j), "entry ({i}, {j}) beyond the horizon");
            far += usize::from(i - j > h);
        }
    }
    assert!(far > 1000, "{far} far entries");
    assert!(exact.sssm.entries() > near.sssm.entries());
}

/// Runs `segment_features` with a callback that cancels at the first report of `stage` past
/// `from`; returns the result and every report seen (the cancelling one last).
fn cancelled_at(base: &FeatureMatrix, params: SssmParams, stage: &str, from: f64) -> (SssmError, Vec<(String, f64)>) {
    let valid = params.check().unwrap();
    let mut seen = Vec::new();
    let r = segment_features(base, Some(&MirrorMap::end_effectors()), &valid, &mut |s, f| {
        seen.push((s.to_string(), f));
        if s == stage && f > from {
            Err(mocapseg::method::Cancelled)
        } else {
            Ok(())
        }
    });
    (r.expect_err("the run was cancelled"), seen)
}

#[test]
fn a_callback_that_cancels_stops_the_run_at_once() {
    let poses: Vec<Pose> = (0..2400)
        .map(|t| if (600..1800).contains(&t) { squats(t as f32, 43.7) } else { arm_circles(t as f32, 31.3) })
        .collect();
    let base = matrix(&poses, &mut Noise::new(4), 1.0);
    // inside the stacked neighbour search (its first report past the stage boundary at 0.3),
    // inside the far blocks of a 10 s horizon, inside the kd-tree search and inside the
    // bundling: the callback is never called again, no later stage runs
    let kd = SssmParams::new().neighbour_search(mocapseg::methods::sssm::NeighbourSearchKind::KdTree);
    let cases = [
        ("neighbours", 0.3, SssmParams::new()),
        ("far blocks", 0.5, SssmParams::new().horizon_s(10.0)),
        ("neighbours", 0.3, kd),
        ("bundling", 0.05, SssmParams::new().bundling(true)),
    ];
    for (stage, from, params) in cases {
        let (err, seen) = cancelled_at(&base, params, stage, from);
        assert_eq!(err, SssmError::Cancelled);
        assert_eq!(err.to_string(), "cancelled");
        let (last, f) = seen.last().unwrap();
        assert!(last == stage && *f > from && *f < 1.0, "{seen:?}");
        assert_eq!(seen.iter().filter(|s| s.0 == stage && s.1 > from).count(), 1, "{seen:?}");
    }
    // a take, cancelled at the first report after the neighbour search: the run ends there
    let motion = load("131_01.bvh", include_bytes!("fixtures/131_01.bvh"));
    let mut after = Vec::new();
    let e = mocapseg::methods::sssm::segment_with_progress(&motion, &SssmParams::new(), &mut |s, _| {
        if s == "features" || s == "neighbours" {
            return Ok(());
        }
        after.push(s.to_string());
        Err(mocapseg::method::Cancelled)
    })
    .unwrap_err();
    assert_eq!(e, SssmError::Cancelled);
    assert_eq!(after, ["activities"]);
    // at a stage boundary
    let (err, seen) = cancelled_at(&base, SssmParams::new(), "activities", 0.0);
    assert_eq!(err, SssmError::Cancelled);
    assert_eq!(seen.last().map(|s| s.0.as_str()), Some("activities"), "{seen:?}");
}

#[test]
fn a_huge_search_horizon_is_refused_and_overflows_nothing_inside() {
    let motion = load("131_01.bvh", include_bytes!("fixtures/131_01.bvh"));
    let e = segment(&motion, &SssmParams::new().horizon_s(1e300)).unwrap_err();
    assert!(matches!(e, SssmError::InvalidParam { name: "horizon_s", .. }), "{e}");
    assert!(e.to_string().starts_with("invalid SSSM parameter horizon_s = 1e300: expected "), "{e}");
    // inside, a horizon of usize::MAX frames is no horizon (nothing overflows)
    let poses: Vec<Pose> = (0..300).map(|t| arm_circles(t as f32, 31.3)).collect();
    let base = matrix(&poses, &mut Noise::new(7), 1.0);
    let (offsets, map) = ([-10, -5, 0, 5, 10], MirrorMap::end_effectors());
    let all = StackedSearch::new(&base, &offsets, Some(&map)).unwrap();
    let huge = StackedSearch::new(&base, &offsets, Some(&map)).unwrap().with_horizon(Some(usize::MAX));
    assert_eq!(huge.similarities(40.0, 600), all.similarities(40.0, 600));
    let far = FarSearch::new(&huge, usize::MAX, 40.0, 600, 30.0, 30.0);
    let spans = [Span { start: 0, end: 99 }, Span { start: 200, end: 299 }];
    let found = far.search(&spans, &[Some(6.0); 2], &mut |_| Ok(())).unwrap();
    assert!(found.plain.is_empty() && found.mirror.is_empty() && found.pairs.is_empty(), "{found:?}");
}

#[test]
fn the_bundling_neighbours_count_in_the_entry_budget() {
    // the bundling holds k neighbours of every frame: 24 000 frames × 256 are refused at once by a
    // budget one entry smaller, before any search
    let long = FeatureMatrix::new(24_000, 1, vec![0.0; 24_000]).unwrap();
    let valid = SssmParams::new().bundling(true).bundling_k(256).check().unwrap();
    let mut stages = Vec::new();
    let e = segment_features_within(&long, None, &valid, 24_000 * 256 - 1, &mut |stage, _| {
        stages.push(stage.to_string());
        Ok(())
    })
    .unwrap_err();
    assert!(matches!(e, SssmError::TooLarge { limit: 6_143_999, max_neighbours: 600, .. }), "{e}");
    assert!(stages.is_empty(), "{stages:?}");
}
