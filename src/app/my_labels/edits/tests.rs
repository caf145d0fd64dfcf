//! The tests of [`super`]: every edit, its refusals, its undo and redo, and the row as labels and as a
//! segmentation. Shared with the stored form's tests: [`sample`].

use super::*;
use crate::app::my_labels::spans::MIN_SPAN;
use crate::app::my_labels::vocabulary::is_reserved;

#[test]
fn the_row_as_a_segmentation_has_labelled_actions_and_unlabelled_transitions() {
    let mut m = MyLabels::new(100);
    m.copy_from(&[(0, 39, "walk".into()), (40, 59, "x".into()), (70, 99, "run".into())]).unwrap();
    m.select(Some(1));
    m.relabel("").unwrap();
    let seg = m.to_segmentation("a.bvh", 120.0);
    seg.validate().unwrap();
    assert_eq!((seg.file.as_str(), seg.frames, seg.method.as_str()), ("a.bvh", 100, "my-labels"));
    let levels: Vec<_> = seg.segments.iter().map(|s| (s.start, s.end, s.level)).collect();
    assert_eq!(levels, [(0, 39, Level::Action), (40, 59, Level::Transition), (70, 99, Level::Action)]);
    assert_eq!(Segmentation::from_json(&seg.to_json()).unwrap(), seg);
}

/// An SSSM-like row of `frames` at 30 Hz: actions `A0`/`B1` with a transition between each
/// pair (as `sssm` labels them) and DT-FCN-like `unknown` actions.
fn sssm_like(parts: &[(usize, usize, &str, Level)], frames: usize) -> Segmentation {
    Segmentation {
        file: "t.bvh".into(),
        fps: 30.0,
        frames,
        method: "sssm".into(),
        params: serde_json::json!({}),
        segments: parts
            .iter()
            .map(|&(start, end, label, level)| Segment {
                start,
                end,
                label: label.into(),
                level,
                cluster: (level == Level::Action).then(|| usize::from(label == "B1")),
                score: None,
                mirror_of: None,
                effort: None,
            })
            .collect(),
    }
}

#[test]
fn a_copied_row_scores_as_the_row_itself_transitions_and_unknowns_are_gaps() {
    use crate::segment::metrics::{evaluate, Tolerances};
    use crate::segment::truth::{Truth, TruthSegment};
    use Level::{Action, Transition};
    let frames = 600;
    // the issue's case: SSSM's row, copied, scored 0.833 → 0.444 at F1@1s — its transitions
    // had become segments labelled "transition"
    let row = sssm_like(
        &[
            (0, 89, "A0", Action),
            (90, 129, "transition", Transition),
            (130, 259, "B1", Action),
            (260, 289, "transition", Transition),
            (290, 419, "A0", Action),
            (420, 459, "transition", Transition),
            (460, 599, "B1", Action),
        ],
        frames,
    );
    let cut =
        |start: usize, end: usize, label: &str| TruthSegment { start, end, label: label.into(), end_window: None };
    let truth = Truth {
        trial: "t".into(),
        frames,
        segments: vec![cut(0, 109, "walk"), cut(110, 274, "jump"), cut(275, 439, "walk"), cut(440, 599, "punch")],
    };
    let tol = Tolerances::default();
    let own = evaluate(&row, &truth, &tol).unwrap();
    let mut m = MyLabels::new(frames);
    let copied: Vec<(usize, usize, String)> = row.segments.iter().map(|s| (s.start, s.end, s.label.clone())).collect();
    m.copy_from(&copied).unwrap();
    assert_eq!(spans(&m), vec![(0, 89, "A0"), (130, 259, "B1"), (290, 419, "A0"), (460, 599, "B1")]);
    let mine = evaluate(&m.to_segmentation("t.bvh", 30.0), &truth, &tol).unwrap();
    assert_eq!(mine.boundaries[1].f1, own.boundaries[1].f1, "F1@1s");
    assert_eq!(mine.boundaries[0].f1, own.boundaries[0].f1, "F1@0.5s");
    assert_eq!(mine.covering, own.covering);
    assert_eq!(mine.labelling, own.labelling);
    assert_eq!(mine.hungarian_accuracy, own.hungarian_accuracy);
    assert!(own.boundaries[1].f1 > 0.99, "the fixture's row finds every cut: {:?}", own.boundaries[1]);

    // a labeller's unknowns and a truth's unlabelled parts are gaps as well; none is a class
    m.copy_from(&row_of(&[(0, 49, "walk"), (50, 99, "unknown"), (100, 199, ""), (200, 599, "Unknown ")])).unwrap();
    assert_eq!(spans(&m), vec![(0, 49, "walk")]);
    assert_eq!(MyLabels::new(10).copy_from(&row_of(&[(0, 9, "transition")])), Err(EditError::NothingToCopy));
}

#[test]
fn transition_and_unknown_never_become_training_classes() {
    // labels stored before copies left gaps, or typed: unlabelled frames for training and scores
    let stored = r#"{"format":"mocapseg-my-labels","version":1,"frames":100,"segments":[
        {"start":0,"end":29,"label":"walk"},{"start":30,"end":39,"label":"transition"},
        {"start":40,"end":59,"label":"unknown"},{"start":60,"end":99,"label":"run"}]}"#;
    let m = MyLabels::from_json(stored, 100).unwrap();
    let rows = m.label_rows("t.bvh");
    let classes: Vec<&str> = rows.iter().map(|r| r.label.as_str()).collect();
    assert_eq!(classes, ["walk", "run"]);
    let seg = m.to_segmentation("t.bvh", 30.0);
    let levels: Vec<Level> = seg.segments.iter().map(|s| s.level).collect();
    assert_eq!(levels, [Level::Action, Level::Transition, Level::Transition, Level::Action]);
    assert!(is_reserved(" Transition") && is_reserved("UNKNOWN") && is_reserved("unlabelled") && !is_reserved("walk"));
}

fn row_of(list: &[(usize, usize, &str)]) -> Vec<(usize, usize, String)> {
    row(list)
}

fn spans(m: &MyLabels) -> Vec<(usize, usize, &str)> {
    m.spans().iter().map(|s| (s.start, s.end, s.label.as_str())).collect()
}

fn row(list: &[(usize, usize, &str)]) -> Vec<(usize, usize, String)> {
    list.iter().map(|(s, e, l)| (*s, *e, l.to_string())).collect()
}

/// `a 0..=9 | b 10..=29 | gap 30..=39 | c 40..=99` on a 100-frame take.
pub(crate) fn sample() -> MyLabels {
    let mut m = MyLabels::new(100);
    m.copy_from(&row(&[(0, 9, "a"), (10, 29, "b"), (40, 99, "c")])).unwrap();
    m
}

#[test]
fn copy_normalises_the_row_and_is_undoable() {
    let mut m = MyLabels::new(50);
    assert!(!m.can_undo() && m.spans().is_empty());
    // unsorted, overlapping, past the end, reversed: sorted, cut, clipped, dropped
    m.copy_from(&row(&[(20, 60, "c"), (0, 9, "a"), (5, 14, "b"), (70, 80, "x"), (9, 3, "bad"), (8, 8, "in")])).unwrap();
    assert_eq!(spans(&m), vec![(0, 9, "a"), (10, 14, "b"), (20, 49, "c")]);
    assert_eq!(m.selected(), None);
    assert!(m.can_undo());
    assert_eq!(MyLabels::new(50).copy_from(&row(&[(60, 70, "x")])), Err(EditError::NothingToCopy));
    assert_eq!(MyLabels::new(0).copy_from(&row(&[(0, 0, "x")])), Err(EditError::NoFrames));
    m.undo().unwrap();
    assert!(m.spans().is_empty());
}

#[test]
fn place_puts_one_segment_in_and_trims_what_it_covers() {
    let mut m = MyLabels::new(100);
    // on an empty row: the segment alone, gaps around it
    m.place(10, 19, "punch").unwrap();
    assert_eq!(spans(&m), vec![(10, 19, "punch")]);
    assert_eq!(m.selected(), Some(0));
    m.copy_from(&row(&[(0, 29, "walk"), (30, 59, "jump"), (60, 99, "walk")])).unwrap();
    // across a boundary: both neighbours trimmed, their labels kept outside it
    m.place(20, 39, "punch").unwrap();
    assert_eq!(spans(&m), vec![(0, 19, "walk"), (20, 39, "punch"), (40, 59, "jump"), (60, 99, "walk")]);
    assert_eq!(m.selected_span().map(|s| s.label.as_str()), Some("punch"));
    // inside one segment: it splits around it
    m.place(70, 79, "kick").unwrap();
    assert_eq!(
        spans(&m),
        vec![
            (0, 19, "walk"),
            (20, 39, "punch"),
            (40, 59, "jump"),
            (60, 69, "walk"),
            (70, 79, "kick"),
            (80, 99, "walk")
        ]
    );
    // one undoable edit each
    m.undo().unwrap();
    assert_eq!(spans(&m), vec![(0, 19, "walk"), (20, 39, "punch"), (40, 59, "jump"), (60, 99, "walk")]);
    // past the take's end: clipped; refused outside it or with a bad label
    m.place(90, 500, "rest").unwrap();
    assert_eq!(spans(&m).last(), Some(&(90, 99, "rest")));
    assert_eq!(m.place(100, 120, "x"), Err(EditError::NothingToCopy));
    assert_eq!(m.place(1, 2, "a\nb"), Err(EditError::LabelControl));
}

#[test]
fn start_empty_is_one_unlabelled_segment_over_the_take() {
    let mut m = sample();
    m.start_empty().unwrap();
    assert_eq!(spans(&m), vec![(0, 99, "")]);
    assert_eq!(m.selected(), Some(0));
    assert!(m.label_rows("t.bvh").is_empty(), "unlabelled segments are not training rows");
    assert_eq!(MyLabels::new(0).start_empty(), Err(EditError::NoFrames));
    m.undo().unwrap();
    assert_eq!(spans(&m), spans(&sample()));
}

#[test]
fn a_shared_boundary_moves_both_segments_and_is_clamped() {
    let mut m = sample();
    assert_eq!(m.boundaries(), vec![0, 10, 30, 40, 100]);
    assert_eq!(m.move_boundary(10, 14), Ok(14));
    assert_eq!(spans(&m)[..2], [(0, 13, "a"), (14, 29, "b")]);
    // never empties a segment: at most to the right one's last frame, at least past the left one's first
    assert_eq!(m.move_boundary(14, 95), Ok(29));
    assert_eq!(spans(&m)[..2], [(0, 28, "a"), (29, 29, "b")], "b keeps one frame");
    assert_eq!(m.move_boundary(29, 0), Ok(1));
    assert_eq!(spans(&m)[..2], [(0, 0, "a"), (1, 29, "b")], "a keeps one frame");
    assert_eq!(m.undo_depth(), 4);
    // dropped where it was: nothing recorded
    assert_eq!(m.move_boundary(1, 1), Ok(1));
    assert_eq!(m.undo_depth(), 4);
    assert_eq!(m.move_boundary(7, 8), Err(EditError::NoBoundary(7)));
}

#[test]
fn an_edge_next_to_a_gap_moves_into_the_gap_up_to_the_next_segment() {
    let mut m = sample();
    // b's end (cut 30) into the gap, stopped at c's start
    assert_eq!(m.move_boundary(30, 80), Ok(40));
    assert_eq!(spans(&m)[1..], [(10, 39, "b"), (40, 99, "c")]);
    m.undo().unwrap();
    // c's start (cut 40) back into the gap, stopped at b's end
    assert_eq!(m.move_boundary(40, 3), Ok(30));
    assert_eq!(spans(&m)[1..], [(10, 29, "b"), (30, 99, "c")]);
    m.undo().unwrap();
    // the first and last frames: cut 0 and cut 100 (the take's edges) stay put when nothing is outside
    assert_eq!(m.move_boundary(0, 5), Ok(5));
    assert_eq!(spans(&m)[0], (5, 9, "a"));
    assert_eq!(m.move_boundary(5, 0), Ok(0), "back to the first frame, not before");
    assert_eq!(m.move_boundary(100, 500), Ok(100), "the last frame is the end");
    assert_eq!(m.move_boundary(100, 60), Ok(60));
    assert_eq!(spans(&m)[2], (40, 59, "c"));
}

#[test]
fn a_nudged_boundary_rolls_like_a_drag_and_never_sticks_or_leaves_a_sliver() {
    // a 0..=9 | b 10..=29 | gap 30..=39 | c 40..=99
    let mut m = sample();
    // one frame at a time to the right: b shrinks to two frames, then the next press crosses it
    let mut cut = 10;
    for _ in 0..18 {
        cut = m.nudge_boundary(cut, 1).unwrap();
    }
    assert_eq!(cut, 28);
    assert_eq!(spans(&m)[..2], [(0, 27, "a"), (28, 29, "b")]);
    cut = m.nudge_boundary(cut, 1).unwrap();
    assert_eq!(cut, 30, "b crossed: removed, never a one-frame b");
    assert_eq!(spans(&m)[..2], [(0, 29, "a"), (40, 99, "c")]);
    // on through the gap: it never leaves a one-frame gap (39 → the segments touch at 40)
    for _ in 0..8 {
        cut = m.nudge_boundary(cut, 1).unwrap();
    }
    assert_eq!(cut, 38);
    assert_eq!(m.nudge_boundary(cut, 1).unwrap(), 40);
    // at the take's end it stops
    let mut end = sample();
    assert_eq!(end.nudge_boundary(100, 1).unwrap(), 100);
    // every walk, either way, by one frame or a second, leaves no one-frame segment or gap
    for start in [0, 10, 30, 40, 100] {
        for by in [-30, -1, 1, 30] {
            let mut m = sample();
            let mut cut = start;
            for _ in 0..120 {
                let next = m.nudge_boundary(cut, by).unwrap_or_else(|e| {
                    panic!(
                        "{start} by {by} at {cut}: {e:?} in {:?}",
                        m.spans().iter().map(|s| (s.start, s.end)).collect::<Vec<_>>()
                    )
                });
                let covered: Vec<(usize, usize)> = m.spans().iter().map(|s| (s.start, s.end)).collect();
                assert!(covered.iter().all(|(a, b)| b + 1 - a >= MIN_SPAN), "{start} by {by}: {covered:?}");
                for w in covered.windows(2) {
                    let gap = w[1].0 - (w[0].1 + 1);
                    assert!(gap == 0 || gap >= MIN_SPAN, "{start} by {by}: a {gap}-frame gap in {covered:?}");
                }
                // stuck at the take's edge, or the segment it edged was crossed and the boundary is gone
                if next == cut || m.boundary_limits(next).is_err() {
                    break;
                }
                cut = next;
            }
        }
    }
}

#[test]
fn a_dragged_boundary_rolls_its_neighbour_and_never_leaves_a_sliver() {
    // a 0..=9 | b 10..=29 | gap 30..=39 | c 40..=99
    let dragged = |cut: usize, to: usize| {
        let mut m = sample();
        let landed = m.drag_boundary(cut, to).unwrap();
        (landed, spans(&m).into_iter().map(|(s, e, l)| (s, e, l.to_string())).collect::<Vec<_>>())
    };
    let own = |list: &[(usize, usize, &str)]| list.iter().map(|(s, e, l)| (*s, *e, l.to_string())).collect::<Vec<_>>();
    // within the neighbour: it shrinks, like a move
    assert_eq!(dragged(10, 20), (20, own(&[(0, 19, "a"), (20, 29, "b"), (40, 99, "c")])));
    // onto its last frame: it keeps MIN_SPAN frames until the boundary passes its end
    assert_eq!(dragged(10, 29), (28, own(&[(0, 27, "a"), (28, 29, "b"), (40, 99, "c")])));
    // fully across it: removed, the gap after it is taken up to where the pointer is
    assert_eq!(dragged(10, 30), (30, own(&[(0, 29, "a"), (40, 99, "c")])));
    assert_eq!(dragged(10, 35), (35, own(&[(0, 34, "a"), (40, 99, "c")])));
    // a gap narrowed to one frame closes: the segments touch
    assert_eq!(dragged(10, 39), (40, own(&[(0, 39, "a"), (40, 99, "c")])));
    assert_eq!(dragged(30, 39), (40, own(&[(0, 9, "a"), (10, 39, "b"), (40, 99, "c")])));
    // on over the next segment: rolled in turn
    assert_eq!(dragged(10, 60), (60, own(&[(0, 59, "a"), (60, 99, "c")])));
    assert_eq!(dragged(10, 99), (98, own(&[(0, 97, "a"), (98, 99, "c")])));
    assert_eq!(dragged(10, 100), (100, own(&[(0, 99, "a")])));
    // to the left: the segment on the right grows, the ones on the left roll
    assert_eq!(dragged(10, 1), (2, own(&[(0, 1, "a"), (2, 29, "b"), (40, 99, "c")])));
    assert_eq!(dragged(10, 0), (0, own(&[(0, 29, "b"), (40, 99, "c")])));
    assert_eq!(dragged(40, 31), (30, own(&[(0, 9, "a"), (10, 29, "b"), (30, 99, "c")])), "the gap closes");
    assert_eq!(dragged(40, 5), (5, own(&[(0, 4, "a"), (5, 99, "c")])));
    // an edge next to a gap moved away from it: the gap grows, never by a single frame at the take's edges
    assert_eq!(
        dragged(0, 1),
        (
            0,
            own(&[(0, 9, "a"), (10, 29, "b"), (30, 39, ""), (40, 99, "c")]).into_iter().filter(|s| s.2 != "").collect()
        )
    );
    assert_eq!(dragged(0, 2).0, 2);
    assert_eq!(dragged(100, 99).0, 100, "no one-frame gap at the end");
    assert_eq!(dragged(100, 98), (98, own(&[(0, 9, "a"), (10, 29, "b"), (40, 97, "c")])));
    assert_eq!(dragged(30, 12), (12, own(&[(0, 9, "a"), (10, 11, "b"), (40, 99, "c")])));
    assert_eq!(dragged(30, 11), (12, own(&[(0, 9, "a"), (10, 11, "b"), (40, 99, "c")])), "b keeps two frames");
    assert_eq!(dragged(30, 10), (10, own(&[(0, 9, "a"), (40, 99, "c")])), "crossed: b removed");
    assert_eq!(dragged(0, 60), (10, own(&[(10, 29, "b"), (40, 99, "c")])), "a gap's edge crosses its own segment only");
    assert_eq!(dragged(40, 35).1, own(&[(0, 9, "a"), (10, 29, "b"), (35, 99, "c")]));
    // no drag leaves a segment or a gap of one frame
    for cut in [0, 10, 30, 40, 100] {
        for to in 0..=100 {
            let (_, after) = dragged(cut, to);
            assert!(after.iter().all(|s| s.1 + 1 - s.0 >= MIN_SPAN), "{cut} → {to}: {after:?}");
            let edges = after.first().zip(after.last()).map(|(f, l)| [f.0, 99 - l.1]).unwrap_or_default();
            let gaps = after.windows(2).map(|w| w[1].0 - w[0].1 - 1).chain(edges);
            assert!(gaps.into_iter().all(|g| g == 0 || g >= MIN_SPAN), "{cut} → {to}: {after:?}");
        }
    }
    // one undoable edit, the selection follows its segment
    let mut m = sample();
    m.select(Some(2));
    assert_eq!(m.drag_boundary(10, 35), Ok(35));
    assert_eq!(m.selected_span().map(|s| s.label.as_str()), Some("c"));
    m.select(Some(0));
    assert_eq!(m.drag_boundary(35, 3), Ok(3), "a's end into its own frames: the gap grows");
    assert_eq!(m.selected_span().map(|s| s.label.as_str()), Some("a"));
    m.drag_boundary(3, 0).unwrap();
    assert_eq!(m.selected(), None, "a removed");
    assert_eq!(spans(&m), vec![(40, 99, "c")]);
    assert_eq!(m.undo_depth(), 4);
    m.undo().unwrap();
    assert_eq!(spans(&m), vec![(0, 2, "a"), (40, 99, "c")]);
    assert_eq!(m.drag_boundary(3, 3), Ok(3));
    assert_eq!(m.undo_depth(), 3, "dropped where it was: no edit");
    assert_eq!(m.drag_boundary(7, 8), Err(EditError::NoBoundary(7)));
}

#[test]
fn split_at_a_frame_keeps_the_label_and_selects_the_right_part() {
    let mut m = sample();
    m.split_at(50).unwrap();
    assert_eq!(spans(&m)[2..], [(40, 49, "c"), (50, 99, "c")]);
    assert_eq!(m.selected(), Some(3));
    assert_eq!(m.split_at(50), Err(EditError::SplitAtStart(50)));
    assert_eq!(m.split_at(35), Err(EditError::NotInSegment(35)), "a gap");
    // the last frame of a segment: a one-frame right part; a one-frame segment cannot be split
    m.split_at(99).unwrap();
    assert_eq!(spans(&m).last(), Some(&(99, 99, "c")));
    assert_eq!(m.split_at(99), Err(EditError::SplitAtStart(99)));
    assert_eq!(m.split_at(0), Err(EditError::SplitAtStart(0)));
    assert_eq!(m.split_at(100), Err(EditError::NotInSegment(100)));
}

#[test]
fn an_accepted_boundary_splits_my_segment_or_starts_the_row() {
    // no labels yet: the row starts, unlabelled, cut there — one edit, undone at once
    let mut m = MyLabels::new(100);
    m.add_boundary(30).unwrap();
    assert_eq!(spans(&m), [(0, 29, ""), (30, 99, "")]);
    assert_eq!(m.selected(), Some(1));
    assert_eq!(m.undo_depth(), 1);
    m.undo().unwrap();
    assert!(m.spans().is_empty());
    // in a segment: split, the label on both parts
    let mut m = sample();
    m.add_boundary(60).unwrap();
    assert_eq!(spans(&m)[2..], [(40, 59, "c"), (60, 99, "c")]);
    assert_eq!(m.selected(), Some(3));
    // already a boundary (between two segments, at a gap's edge, the one just added): refused, nothing recorded
    let depth = m.undo_depth();
    for cut in [10, 30, 40, 60] {
        assert_eq!(m.add_boundary(cut), Err(EditError::AlreadyBoundary(cut)), "cut {cut}");
    }
    assert_eq!(m.add_boundary(35), Err(EditError::BoundaryInGap(35)));
    assert_eq!(m.add_boundary(0), Err(EditError::AtTheEdge(0)));
    assert_eq!(m.add_boundary(100), Err(EditError::AtTheEdge(100)));
    assert_eq!(m.undo_depth(), depth);
    assert!(EditError::BoundaryInGap(35).to_string().contains("frame 36"));
    assert_eq!(MyLabels::new(0).add_boundary(1), Err(EditError::NoFrames));
}

#[test]
fn merge_joins_the_next_segment_and_the_gap_between() {
    let mut m = sample();
    assert_eq!(m.merge_with_next(), Err(EditError::NoSelection));
    m.select(Some(1));
    m.merge_with_next().unwrap();
    assert_eq!(spans(&m), vec![(0, 9, "a"), (10, 99, "b")], "b takes the gap and c");
    assert_eq!(m.merge_with_next(), Err(EditError::NoNext));
    // an unlabelled segment takes the next one's label
    let mut m = MyLabels::new(20);
    m.copy_from(&row(&[(0, 4, "x"), (5, 19, "walk")])).unwrap();
    m.select(Some(0));
    m.relabel("").unwrap();
    m.merge_with_next().unwrap();
    assert_eq!(spans(&m), vec![(0, 19, "walk")]);
    assert_eq!(m.selected(), Some(0));
}

#[test]
fn relabel_trims_refuses_bad_labels_and_skips_no_change() {
    let mut m = sample();
    assert_eq!(m.relabel("x"), Err(EditError::NoSelection));
    m.select(Some(0));
    m.relabel("  kick, left  ").unwrap();
    assert_eq!(spans(&m)[0], (0, 9, "kick, left"));
    let depth = m.undo_depth();
    m.relabel("kick, left").unwrap();
    assert_eq!(m.undo_depth(), depth, "the same label is no edit");
    assert_eq!(m.relabel("a\nb"), Err(EditError::LabelControl));
    assert_eq!(m.relabel(&"é".repeat(121)), Err(EditError::LabelTooLong(121)));
    m.relabel(&"é".repeat(120)).unwrap();
    m.relabel("").unwrap();
    assert_eq!(spans(&m)[0], (0, 9, ""), "empty: unlabelled");
    assert_eq!(m.labels_used(), vec!["b", "c"]);
}

#[test]
fn delete_leaves_a_gap_and_selects_the_next_segment() {
    let mut m = sample();
    assert_eq!(m.delete(), Err(EditError::NoSelection));
    m.select(Some(1));
    m.delete().unwrap();
    assert_eq!(spans(&m), vec![(0, 9, "a"), (40, 99, "c")]);
    assert_eq!(m.selected(), Some(1), "c, now second");
    m.delete().unwrap();
    assert_eq!(m.selected(), Some(0), "the last one deleted: the one before");
    m.delete().unwrap();
    assert_eq!(m.selected(), None);
    assert!(m.spans().is_empty());
    // a gap filled again: up to the segments either side
    let mut m = sample();
    m.fill_gap(33).unwrap();
    assert_eq!(spans(&m)[2], (30, 39, ""));
    assert_eq!(m.selected(), Some(2));
    assert_eq!(m.fill_gap(33), Err(EditError::NotAGap(33)));
    let mut m = MyLabels::new(10);
    m.fill_gap(4).unwrap();
    assert_eq!(spans(&m), vec![(0, 9, "")], "an empty row: the whole take");
    assert_eq!(m.fill_gap(10), Err(EditError::NotInSegment(10)));
}

#[test]
fn undo_and_redo_walk_every_edit_back_and_forth() {
    let mut m = MyLabels::new(100);
    let mut states = vec![m.clone()];
    m.copy_from(&row(&[(0, 49, "a"), (50, 99, "b")])).unwrap();
    states.push(m.clone());
    m.move_boundary(50, 60).unwrap();
    states.push(m.clone());
    m.split_at(30).unwrap();
    states.push(m.clone());
    m.relabel("c").unwrap();
    states.push(m.clone());
    m.merge_with_next().unwrap();
    states.push(m.clone());
    m.delete().unwrap();
    states.push(m.clone());
    m.fill_gap(50).unwrap();
    states.push(m.clone());
    m.clear();
    states.push(m.clone());
    let same = |a: &MyLabels, b: &MyLabels| a.spans() == b.spans() && a.selected() == b.selected();
    for want in states.iter().rev().skip(1) {
        m.undo().unwrap();
        assert!(same(&m, want), "undo: {:?} != {:?}", spans(&m), spans(want));
    }
    assert_eq!(m.undo(), Err(EditError::NothingToUndo));
    for want in states.iter().skip(1) {
        m.redo().unwrap();
        assert!(same(&m, want), "redo: {:?} != {:?}", spans(&m), spans(want));
    }
    assert_eq!(m.redo(), Err(EditError::NothingToRedo));
    // a new edit after an undo clears redo
    m.undo().unwrap();
    m.undo().unwrap();
    assert!(m.can_redo());
    m.select(Some(0));
    m.relabel("new").unwrap();
    assert!(!m.can_redo());
    // clearing an empty row is no edit
    let mut e = MyLabels::new(5);
    e.clear();
    assert!(!e.can_undo());
}

#[test]
fn the_history_is_bounded() {
    let mut m = MyLabels::new(1000);
    m.start_empty().unwrap();
    for k in 0..HISTORY_LIMIT + 50 {
        m.relabel(&format!("l{k}")).unwrap();
    }
    assert_eq!(m.undo_depth(), HISTORY_LIMIT);
    for _ in 0..HISTORY_LIMIT {
        m.undo().unwrap();
    }
    assert_eq!(m.undo(), Err(EditError::NothingToUndo));
    assert_eq!(m.spans()[0].label, "l49", "the oldest edits are forgotten");
}

#[test]
fn selection_and_lookup_stay_in_range() {
    let mut m = sample();
    m.select(Some(7));
    assert_eq!(m.selected(), None);
    m.select(Some(2));
    assert_eq!(m.selected_span().map(|s| s.len()), Some(60));
    assert_eq!(m.index_at(0), Some(0));
    assert_eq!(m.index_at(9), Some(0));
    assert_eq!(m.index_at(10), Some(1));
    assert_eq!(m.index_at(35), None);
    assert_eq!(m.index_at(99), Some(2));
    assert_eq!(m.index_at(100), None);
    assert_eq!(m.index_of(40, 99), Some(2));
    assert_eq!(m.index_of(40, 98), None);
}
