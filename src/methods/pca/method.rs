//! The PCA segmentation behind the common [`Method`] interface: its parameters, the segmentation
//! at the file's frame rate, the normalised error derivative as a per-frame curve, and a plot of
//! the projection error and its derivative with the cuts.

use super::{poses, scan, PcaParams, Scan, ValidParams, PARAMS};
use crate::method::bounds;
use crate::method::unsupervised::{at_file_rate, About, Found, Segmenter};
use crate::method::{MethodError, ParamSpec, Picture, Progress, RunOptions, Work};
use crate::motion::Motion;
use crate::segment::frames::WorkingFrames;
use crate::segment::{cuts, Level};

/// PCA segmentation (Barbič et al. 2004), as Bouchard & Badler's baseline.
#[derive(Debug, Clone, Copy, Default)]
pub struct Pca;

/// Height in pixels of the plot.
const PLOT_HEIGHT: usize = 120;
/// Widest plot in pixels (longer takes put several working frames in a column, keeping the largest).
const PLOT_MAX_WIDTH: usize = 1500;
/// The plot's derivative ratio axis runs from 0 to this (the cut threshold is 1).
const RATIO_TOP: f64 = 2.0;

impl Segmenter for Pca {
    type Params = PcaParams;
    const ABOUT: About = About {
        name: "pca",
        short: "PCA",
        paper: "Barbič et al. 2004",
        summary:
            "In-line baseline: a cut wherever the poses since the last cut stop fitting a low-dimensional hyperplane \
                  (the PCA projection error suddenly rises faster).",
    };

    fn param_specs(&self) -> Vec<ParamSpec> {
        let d = PcaParams::default();
        bounds::specs(&PARAMS, |n| d.value(n))
    }

    fn work(&self, params: &ValidParams) -> Work {
        // the pose matrix and windows: 1.3 kB per frame measured (tests/limits.rs)
        Work::memory(params.fps, 2_000, 1 << 20, "")
    }

    fn segment(
        &self,
        motion: &Motion,
        params: &ValidParams,
        options: &RunOptions,
        progress: &mut dyn Progress,
    ) -> Result<Found, MethodError> {
        progress.step("poses", 0.0)?;
        let p = poses(motion, params.fps).map_err(|e| MethodError::Failed(e.to_string()))?;
        let s = scan(&p.data, p.dim, params, &mut |stage, f| progress.step(stage, f))?;
        progress.step("segments", 0.9)?;
        let frames = WorkingFrames { source: &p.source_frames, file_frames: motion.frames() };
        let cut_frames: Vec<usize> = s.cuts.iter().map(|c| c.frame).collect();
        let segments = cuts::segments(
            &frames,
            &cut_frames,
            |k| format!("B{}", k + 1),
            Level::Action,
            |k, _, _| k.checked_sub(1).map(|c| (s.cuts[c].ratio * 100.0).round() / 100.0),
        );
        let ratio: Vec<f32> = s.ratio.iter().map(|&r| r as f32).collect();
        let curves = vec![at_file_rate(
            "error-derivative".into(),
            "PCA error derivative / cut threshold".into(),
            &ratio,
            &frames,
        )];
        let mut pictures = Vec::new();
        if options.pictures {
            progress.step("plot", 0.95)?;
            pictures.push(plot(&s, params));
        }
        let dims: Vec<String> = s.dims.iter().map(usize::to_string).collect();
        let summary = format!(
            "{} · {} · {} · segment dimensions {}",
            crate::method::counted(segments.len(), "behaviour"),
            crate::method::counted(s.cuts.len(), "cut"),
            crate::method::counted(p.dim, "pose dimension"),
            dims.join(", ")
        );
        Ok(Found { segments, summary, curves, pictures })
    }
}

/// The projection error `e_i` (blue, each segment scaled to its own largest error), the
/// derivative over the threshold `d_i / (mean + k_σ·std)` (red, 0 to [`RATIO_TOP`], threshold 1
/// dashed grey) and the cuts (black); time across at the working rate.
fn plot(s: &Scan, params: &ValidParams) -> Picture {
    let n = s.error.len().max(1);
    let per_column = n.div_ceil(PLOT_MAX_WIDTH).max(1);
    let width = n.div_ceil(per_column);
    let y_of = |v: f64| PLOT_HEIGHT - 1 - (v.clamp(0.0, 1.0) * (PLOT_HEIGHT - 1) as f64).round() as usize;
    let mut rgba = vec![255u8; width * PLOT_HEIGHT * 4];
    let mut set = |x: usize, y: usize, c: [u8; 3]| {
        let k = (y * width + x) * 4;
        rgba[k..k + 3].copy_from_slice(&c);
    };
    let y = y_of(1.0 / RATIO_TOP);
    (0..width).filter(|x| x % 4 < 2).for_each(|x| set(x, y, [190; 3]));
    for c in &s.cuts {
        (0..PLOT_HEIGHT).for_each(|y| set(c.frame / per_column, y, [40, 40, 40]));
    }
    // the error, scaled per segment (it restarts from 0 at every cut)
    let mut scaled = vec![0.0; s.error.len()];
    let bounds: Vec<usize> =
        std::iter::once(0).chain(s.cuts.iter().map(|c| c.frame)).chain(std::iter::once(s.error.len())).collect();
    for w in bounds.windows(2) {
        let top = s.error[w[0]..w[1]].iter().fold(0.0f64, |a, &b| a.max(b));
        if top > 0.0 {
            (w[0]..w[1]).for_each(|t| scaled[t] = s.error[t] / top);
        }
    }
    let ratio: Vec<f64> = s.ratio.iter().map(|r| r / RATIO_TOP).collect();
    for (values, colour) in [(&scaled, [30u8, 90, 235]), (&ratio, [215, 30, 40])] {
        let mut last: Option<usize> = None;
        for x in 0..width {
            let chunk = &values[(x * per_column).min(values.len())..((x + 1) * per_column).min(values.len())];
            let y = y_of(chunk.iter().fold(0.0f64, |a, &b| a.max(b)));
            let (a, b) = last.map_or((y, y), |l| (l.min(y), l.max(y)));
            (a..=b).for_each(|yy| set(x, yy, colour));
            last = Some(y);
        }
    }
    Picture {
        id: "error".into(),
        title: "PCA projection error".into(),
        caption: format!(
            "Time across ({} Hz{}). Blue: projection error of the poses since the last cut onto their best \
             hyperplane, scaled per segment; red: its derivative over {} s divided by the cut threshold (mean + {} \
             standard deviations), 0 to {RATIO_TOP}; dashed grey: the threshold; black: cuts.",
            params.fps,
            if per_column > 1 { format!(", {per_column} frames per pixel") } else { String::new() },
            params.lag_s,
            params.k_sigma
        ),
        width,
        height: PLOT_HEIGHT,
        rgba,
        frames_per_pixel: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::load::load_bytes;
    use crate::method::unsupervised::{Checkable, Unsupervised};
    use crate::method::Method;

    #[test]
    fn a_walk_is_one_behaviour_at_the_file_rate_with_its_curve_plot_and_progress() {
        let motion =
            load_bytes("12_01.bvh", include_bytes!("../../../tests/fixtures/12_01.bvh"), &mut |_| {}).unwrap().motion;
        let params = PcaParams::default().check().unwrap();
        let mut stages: Vec<String> = Vec::new();
        let mut progress = |stage: &str, _: f64| stages.push(stage.to_string());
        let out = Unsupervised(Pca)
            .run(&motion, &params, &RunOptions { pictures: true, ..RunOptions::default() }, &mut progress)
            .unwrap();
        // 524 frames at 120 Hz: 131 working frames, a single walk, no cut
        let seg = &out.segmentation;
        assert_eq!(seg.segments.len(), 1, "{:?}", seg.segments);
        let s = &seg.segments[0];
        assert_eq!(
            (s.start, s.end, s.label.as_str(), s.level, s.cluster, s.score),
            (0, 523, "B1", Level::Action, None, None)
        );
        assert_eq!(out.details.curves[0].values.len(), 524);
        let p = &out.details.pictures[0];
        assert_eq!((p.width, p.height, p.rgba.len()), (131, PLOT_HEIGHT, 131 * PLOT_HEIGHT * 4));
        // every stage reported, the scan at least every 64 working frames
        assert_eq!(stages.first().map(String::as_str), Some("poses"));
        assert!(stages.iter().filter(|s| *s == "scan").count() >= 131 / 64, "{stages:?}");
        assert!(stages.contains(&"segments".to_string()) && stages.contains(&"plot".to_string()));
    }

    #[test]
    fn raised_hands_after_a_walk_are_a_second_behaviour_cut_near_the_change() {
        use crate::motion::normalize::body_size;
        use crate::motion::units::UpAxis;
        let walk =
            load_bytes("12_01.bvh", include_bytes!("../../../tests/fixtures/12_01.bvh"), &mut |_| {}).unwrap().motion;
        // the same walk again with both hands a third of the body higher
        let map = walk.joint_map().unwrap();
        let up = match walk.up_axis {
            UpAxis::Y => glam::Vec3::Y,
            UpAxis::Z => glam::Vec3::Z,
        };
        let lift = up * (body_size(&walk.skeleton, &map) / 3.0) as f32;
        let mut raised = walk.clone();
        for frame in raised.positions.chunks_exact_mut(walk.joints()) {
            frame[map.left_hand] += lift;
            frame[map.right_hand] += lift;
        }
        let motion = crate::motion::Motion::concatenate(&[walk, raised], 1048).unwrap();
        let params = PcaParams::default().check().unwrap();
        let out =
            Unsupervised(Pca).run(&motion, &params, &RunOptions::default(), &mut crate::method::NoProgress).unwrap();
        let segs = &out.segmentation.segments;
        assert_eq!(segs.len(), 2, "{segs:?}");
        // file frames (120 Hz): the change at 524, found within 10 working frames (40 file frames)
        assert!(segs[1].start.abs_diff(524) <= 40, "{segs:?}");
        assert_eq!((segs[0].start, segs[0].end + 1, segs[1].end), (0, segs[1].start, 1047));
        assert_eq!((segs[1].label.as_str(), segs[0].score), ("B2", None));
        assert!(segs[1].score.unwrap() > 1.0, "{segs:?}");
        // the curve passes the threshold (1) at the cut
        let cut = segs[1].start;
        assert!(out.details.curves[0].values[cut.saturating_sub(2)..cut + 3].iter().any(|&v| v > 1.0));
    }
}
