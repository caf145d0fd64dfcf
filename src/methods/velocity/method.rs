//! The hand-speed segmentation behind the common [`Method`] interface: its parameters, the
//! segmentation at the file's frame rate, both hands' speed as per-frame curves and as a plot.

use super::{boundaries, hand_speed, ValidParams, VelocityParams, PARAMS};
use crate::features::end_effectors::{end_effectors, LEFT_HAND, RIGHT_HAND};
use crate::method::bounds;
use crate::method::plot::{self, Series};
use crate::method::unsupervised::{at_file_rate, About, Found, Segmenter};
use crate::method::{MethodError, ParamSpec, Picture, Progress, RunOptions, Work};
use crate::motion::Motion;
use crate::segment::frames::WorkingFrames;
use crate::segment::{cuts, Level};

/// Hand-speed segmentation (Osaki et al. 2000; Shiratori et al. 2003), as Bouchard & Badler's baseline.
#[derive(Debug, Clone, Copy, Default)]
pub struct Velocity;

impl Segmenter for Velocity {
    type Params = VelocityParams;
    const ABOUT: About = About {
        name: "velocity",
        short: "Velocity",
        paper: "Osaki et al. 2000; Shiratori et al. 2003",
        summary: "Kinematic baseline: a boundary wherever a hand slows down below one speed after moving faster than \
                  another.",
    };

    fn param_specs(&self) -> Vec<ParamSpec> {
        let d = VelocityParams::default();
        let mut specs = bounds::specs(&PARAMS, |n| d.value(n));
        let help = "Scale every take to the reference body (speeds in inches per second of CMU subject 86's body).";
        specs.insert(1, bounds::switch("body_scale", help, d.body_scale, false));
        specs
    }

    fn work(&self, params: &ValidParams) -> Work {
        // end-effector positions and speeds: 1.0 kB per frame measured (tests/limits.rs)
        Work::memory(params.fps, 1_500, 1 << 20, "")
    }

    fn segment(
        &self,
        motion: &Motion,
        params: &ValidParams,
        options: &RunOptions,
        progress: &mut dyn Progress,
    ) -> Result<Found, MethodError> {
        progress.step("features", 0.0)?;
        let e = end_effectors(motion, params.fps, params.body_scale).map_err(|e| MethodError::Failed(e.to_string()))?;
        progress.step("speed", 0.3)?;
        let speeds: Vec<Vec<f32>> =
            [LEFT_HAND, RIGHT_HAND].iter().map(|&c| hand_speed(&e.base, c, params.fps, params.smooth_s)).collect();
        let cuts = boundaries(&speeds, params, &mut |stage, f| progress.step(stage, f))?;
        let frames = WorkingFrames { source: &e.source_frames, file_frames: motion.frames() };
        let peak = |a: usize, b: usize| speeds.iter().flat_map(|s| &s[a..=b]).fold(0.0f32, |x, &y| x.max(y));
        let segments = cuts::segments(
            &frames,
            &cuts,
            |_| "gesture".into(),
            Level::Primitive,
            |_, a, b| Some((peak(a, b) as f64 * 10.0).round() / 10.0),
        );
        let curves = ["left hand", "right hand"]
            .iter()
            .zip(&speeds)
            .map(|(hand, s)| {
                at_file_rate(hand.replace(' ', "-") + "-speed", format!("{hand} speed (in/s)"), s, &frames)
            })
            .collect();
        let mut pictures = Vec::new();
        if options.pictures {
            progress.step("plot", 0.95)?;
            pictures.push(plot(&speeds, &cuts, params));
        }
        let summary = format!(
            "{} · {} · hand speed up to {:.0} in/s",
            crate::method::counted(segments.len(), "gesture"),
            crate::method::counted(cuts.len(), "boundary"),
            speeds.iter().flatten().fold(0.0f32, |a, &b| a.max(b))
        );
        Ok(Found { segments, summary, curves, pictures })
    }
}

/// Both hands' speed over time with the two thresholds and the boundaries.
fn plot(speeds: &[Vec<f32>], cuts: &[usize], params: &ValidParams) -> Picture {
    let series: Vec<Series> =
        speeds.iter().zip([[30u8, 90, 235], [215, 30, 40]]).map(|(values, colour)| Series { values, colour }).collect();
    plot::lines(
        "speed",
        "Hand speed",
        &format!(
            "Time across ({} Hz), speed up (in/s). Blue: left hand, red: right hand; dashed grey: the low and high \
             speed thresholds; black: boundaries.",
            params.fps
        ),
        &series,
        &[params.low_speed as f32, params.high_speed as f32],
        cuts,
    )
}
