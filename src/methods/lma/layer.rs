//! Effort for every row — the paper's conclusion (§6): "the LMA classifier could act as a first pass for a more
//! high-level, application-dependent classifier … Using the LMA segmentation as the middle layer in a hierarchical
//! segmentation scheme". Here the other way round as well: any segment of any method (or of a user's labels) gets
//! its Laban Effort from the classifier family — the family's mean output (eq. 2) over its 121 boundary-shifted
//! classifiers on the segment, read on the arm whose hand travels further in it (as a user's Effort label row picks
//! its arm, [`super::corpus`]). The classifiers learnt segments of 0.67–3.33 s; a longer segment's Effort is the
//! same statistics over more frames, an extrapolation the caller should say. [`annotate`] is LMA's annotation of
//! any segmentation ([`crate::method::Method::annotate`]): what the page's Effort bars under every row show, with
//! the learnt lengths so that they can mark the extrapolations.

use super::body::upper_body;
use super::classifier::{effort, EffortModel};
use super::features::Pool;
use super::method::rounded;
use crate::method::{Annotated, Annotations, MethodError, NoProgress, Progress};
use crate::motion::Motion;
use crate::segment::{Effort, Segment};

/// The Effort of each of `segments` (file frames of `motion`, inclusive), in order; `None` for a segment shorter
/// than two frames at the family's rate. Fails only when the take has no arms to read.
pub fn effort_of(model: &EffortModel, motion: &Motion, segments: &[Segment]) -> Result<Vec<Option<Effort>>, String> {
    efforts(model, motion, segments, &mut NoProgress).map_err(|e| e.to_string())
}

/// [`effort_of`] reporting progress to `progress` (every few segments) and stopping when it asks.
fn efforts(
    model: &EffortModel,
    motion: &Motion,
    segments: &[Segment],
    progress: &mut dyn Progress,
) -> Result<Vec<Option<Effort>>, MethodError> {
    let fps = model.fps;
    progress.step("arms", 0.0)?;
    let body = upper_body(motion, fps).map_err(|e| MethodError::Failed(format!("{}: {e}", motion.name)))?;
    let n = body.arms[0].hand().len();
    let to_working = |f: usize| ((f as f64 * fps / motion.fps).round() as usize).min(n.saturating_sub(1));
    let longest = segments.iter().map(|s| to_working(s.end).saturating_sub(to_working(s.start))).max().unwrap_or(0);
    progress.step("features", 0.1)?;
    let pools: Vec<Pool> = body.arms.iter().map(|a| Pool::of(a, fps, longest + 2 * model.max_shift + 1)).collect();
    let mut out = Vec::with_capacity(segments.len());
    for (i, s) in segments.iter().enumerate() {
        if i % 16 == 0 {
            progress.step("effort", 0.2 + 0.8 * i as f64 / segments.len() as f64)?;
        }
        let (a, b) = (to_working(s.start), to_working(s.end));
        if b < a + 2 {
            out.push(None);
            continue;
        }
        let travel = |k: usize| body.arms[k].hand()[a..=b].windows(2).map(|w| w[0].distance(w[1])).sum::<f64>();
        let arm = if travel(0) >= travel(1) { 0 } else { 1 };
        out.push(Some(rounded(effort(&model.assess(&pools[arm], a, b).1))));
    }
    Ok(out)
}

/// The Effort of each of `segments` as the method's annotation ([`crate::method::Method::annotate`]): a segment
/// too short to read says why, and the lengths the family learnt are given, so that a segment outside them can be
/// marked an extrapolation. `by` names the family ("LMA, shipped family").
pub fn annotate(
    model: &EffortModel,
    motion: &Motion,
    segments: &[Segment],
    by: String,
    progress: &mut dyn Progress,
) -> Result<Annotations, MethodError> {
    let efforts = efforts(model, motion, segments, progress)?;
    let fps = model.fps;
    let annotated = efforts
        .into_iter()
        .map(|effort| Annotated {
            effort,
            why: effort
                .is_none()
                .then(|| format!("shorter than the 3 frames at {fps:.0} fps the classifiers need to read a segment")),
        })
        .collect();
    Ok(Annotations {
        segments: annotated,
        learnt_s: Some([model.min_len as f64 / fps, model.max_len as f64 / fps]),
        by,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::segment::Level;

    fn segment(start: usize, end: usize) -> Segment {
        Segment {
            start,
            end,
            label: "x".into(),
            level: Level::Action,
            cluster: None,
            score: None,
            mirror_of: None,
            effort: None,
        }
    }

    #[test]
    fn every_segment_of_any_length_gets_the_familys_effort_and_a_too_short_one_none() {
        let model = &crate::methods::lma::shipped_model().unwrap();
        let motion =
            crate::load::load_bytes("12_01.bvh", include_bytes!("../../../tests/fixtures/12_01.bvh"), &mut |_| {})
                .unwrap()
                .motion;
        let last = motion.frames() - 1;
        let segments = [segment(0, 200), segment(100, 101), segment(0, last), segment(300, last)];
        let efforts = effort_of(model, &motion, &segments).unwrap();
        assert_eq!(efforts.len(), 4);
        assert!(efforts[1].is_none(), "a segment of two file frames is under two working frames");
        for e in [efforts[0], efforts[2], efforts[3]] {
            let e = e.unwrap();
            for v in [e.space, e.time, e.weight, e.flow] {
                assert!((-1.0..=1.0).contains(&v), "{e:?}");
            }
        }
        // what the family says of the segment on the arm that travels further, as it scores a candidate
        let body = upper_body(&motion, model.fps).unwrap();
        let (a, b) = (0, (200.0 * model.fps / motion.fps).round() as usize);
        let pools: Vec<Pool> = body.arms.iter().map(|arm| Pool::of(arm, model.fps, 200)).collect();
        let by_arm: Vec<Effort> = pools.iter().map(|p| rounded(effort(&model.assess(p, a, b).1))).collect();
        assert!(by_arm.contains(&efforts[0].unwrap()), "{:?} not in {by_arm:?}", efforts[0]);
        assert_eq!(effort_of(model, &motion, &segments).unwrap(), efforts, "deterministic");
    }
}
