//! The kinematic centroid segmentation behind the common [`Method`] interface.

use super::{centroid, segment_limbs, KcsParams, ValidParams, PARAMS};
use crate::features::end_effectors::canonical_joints;
use crate::method::bounds;
use crate::method::plot::{self, Series};
use crate::method::unsupervised::{at_file_rate, About, Found, Segmenter};
use crate::method::{MethodError, ParamSpec, Progress, RunOptions, Work};
use crate::motion::joints::Canonical as C;
use crate::motion::Motion;
use crate::segment::frames::WorkingFrames;
use crate::segment::{cuts, Level};

/// Kinematic Centroid Segmentation (Jenkins & Matarić 2003), as Bouchard & Badler's baseline.
#[derive(Debug, Clone, Copy, Default)]
pub struct Kcs;

/// The limbs: name, joints whose mean is the centroid, plot colour.
const LIMBS: [(&str, [C; 3], [u8; 3]); 4] = [
    ("left arm", [C::LeftShoulder, C::LeftElbow, C::LeftHand], [30, 90, 235]),
    ("right arm", [C::RightShoulder, C::RightElbow, C::RightHand], [215, 30, 40]),
    ("left leg", [C::LeftHip, C::LeftKnee, C::LeftFoot], [0, 150, 90]),
    ("right leg", [C::RightHip, C::RightKnee, C::RightFoot], [200, 130, 0]),
];

impl Segmenter for Kcs {
    type Params = KcsParams;
    const ABOUT: About = About {
        name: "kcs",
        short: "KCS",
        paper: "Jenkins & Matarić 2003",
        summary: "Kinematic baseline: each limb a pendulum, a cut at the far end of every swing of its centroid.",
    };

    fn param_specs(&self) -> Vec<ParamSpec> {
        let d = KcsParams::default();
        let mut specs = bounds::specs(&PARAMS, |n| d.value(n));
        let help = "Scale every take to the reference body (distances in its inches).";
        specs.insert(1, bounds::switch("body_scale", help, d.body_scale, false));
        specs.push(bounds::switch("legs", "Segment the legs too, not only the arms.", d.legs, true));
        specs
    }

    fn work(&self, params: &ValidParams) -> Work {
        // bone vectors and the KCS distance curve: 1.0 kB per frame measured (tests/limits.rs)
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
        let limbs = &LIMBS[..if params.legs { 4 } else { 2 }];
        let joints: Vec<C> = limbs.iter().flat_map(|(_, j, _)| *j).collect();
        let f = canonical_joints(motion, params.fps, params.body_scale, &joints)
            .map_err(|e| MethodError::Failed(e.to_string()))?;
        let centroids: Vec<Vec<glam::Vec3>> = (0..limbs.len()).map(|l| centroid(&f.base, 9 * l, 3)).collect();
        let (cut_frames, curves) = segment_limbs(&centroids, params, &mut |stage, x| progress.step(stage, x))?;
        let frames = WorkingFrames { source: &f.source_frames, file_frames: motion.frames() };
        let reach = |a: usize, b: usize| curves.iter().flat_map(|c| &c[a..=b]).fold(0.0f32, |x, &y| x.max(y));
        let segments = cuts::segments(
            &frames,
            &cut_frames,
            |_| "swing".into(),
            Level::Primitive,
            |_, a, b| Some((reach(a, b) as f64 * 10.0).round() / 10.0),
        );
        let mut pictures = Vec::new();
        if options.pictures {
            progress.step("plot", 0.95)?;
            let series: Vec<Series> =
                curves.iter().zip(limbs).map(|(values, (_, _, colour))| Series { values, colour: *colour }).collect();
            pictures.push(plot::lines(
                "swings",
                "Limb centroid displacement",
                &format!(
                    "Time across ({} Hz), up: how far each limb's centroid is from where it was at the start of its \
                     segment (inches). Blue: left arm, red: right arm{}; black: cuts.",
                    params.fps,
                    if params.legs { ", green: left leg, orange: right leg" } else { "" }
                ),
                &series,
                &[],
                &cut_frames,
            ));
        }
        let summary = format!(
            "{} · {}",
            crate::method::counted(segments.len(), "swing"),
            crate::method::counted(cut_frames.len(), "cut")
        );
        let curves = curves
            .iter()
            .zip(limbs)
            .map(|(c, (name, _, _))| {
                let (id, title) =
                    (name.replace(' ', "-") + "-displacement", format!("{name} centroid displacement (in)"));
                at_file_rate(id, title, c, &frames)
            })
            .collect();
        Ok(Found { segments, summary, curves, pictures })
    }
}
