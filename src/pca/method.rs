//! The PCA segmentation behind the common [`Method`] interface: its parameters, the segmentation
//! at the file's frame rate, the normalised error derivative as a per-frame curve, and a plot of
//! the projection error and its derivative with the cuts.

use super::{poses, scan, PcaParams, Scan, ValidParams, BOUNDS};
use crate::method::{
    Curve, Details, Method, MethodError, MethodInfo, MethodOutput, ParamKind, ParamSpec, Picture, Progress, RunOptions,
};
use crate::motion::Motion;
use crate::segment::frames::WorkingFrames;
use crate::segment::{Level, Segment, Segmentation};

/// PCA segmentation (Barbič et al. 2004), as Bouchard & Badler's baseline.
#[derive(Debug, Clone, Copy, Default)]
pub struct Pca;

/// Height in pixels of the plot.
const PLOT_HEIGHT: usize = 120;
/// Widest plot in pixels (longer takes put several working frames in a column, keeping the largest).
const PLOT_MAX_WIDTH: usize = 1500;
/// The plot's derivative ratio axis runs from 0 to this (the cut threshold is 1).
const RATIO_TOP: f64 = 2.0;

impl Method for Pca {
    type Params = PcaParams;
    type Checked = ValidParams;

    fn info(&self) -> MethodInfo {
        MethodInfo {
            name: "pca".into(),
            short: "PCA".into(),
            paper: "Barbič et al. 2004".into(),
            summary: "In-line baseline: a cut wherever the poses since the last cut stop fitting a low-dimensional \
                      hyperplane (the PCA projection error suddenly rises faster)."
                .into(),
            auto_run: true,
        }
    }

    fn param_specs(&self) -> Vec<ParamSpec> {
        let d = PcaParams::default();
        let help = |name: &str| match name {
            "fps" => "Frame rate the method works at; takes are resampled to it.",
            "tau" => "Fraction of the variance of a segment's first frames its principal directions must keep.",
            "window_s" => "Seconds that fix a segment's dimension; also the shortest segment.",
            "lag_s" => "The error's derivative is taken over this many seconds (at most half of window_s).",
            _ => "A cut where the error's derivative exceeds its mean by this many standard deviations.",
        };
        BOUNDS
            .iter()
            .map(|&(name, min, max, unit)| ParamSpec {
                name: name.into(),
                help: help(name).into(),
                kind: ParamKind::Number { min, max },
                default: serde_json::json!(d.value(name)),
                unit: (!unit.is_empty()).then(|| unit.into()),
                basic: matches!(name, "tau" | "window_s" | "k_sigma"),
            })
            .collect()
    }

    fn check(&self, params: PcaParams) -> Result<ValidParams, MethodError> {
        params.check().map_err(|e| MethodError::Params(e.to_string()))
    }

    fn echo(&self, params: &ValidParams) -> serde_json::Value {
        serde_json::to_value(&**params).unwrap_or_default()
    }

    fn run(
        &self,
        motion: &Motion,
        params: &ValidParams,
        options: &RunOptions,
        progress: &mut dyn Progress,
    ) -> Result<MethodOutput, MethodError> {
        progress.step("poses", 0.0)?;
        let p = poses(motion, params.fps).map_err(|e| MethodError::Failed(e.to_string()))?;
        let s = scan(&p.data, p.dim, params, &mut |stage, f| progress.step(stage, f))?;
        progress.step("segments", 0.9)?;
        let frames = WorkingFrames { source: &p.source_frames, file_frames: motion.frames() };
        let n = p.frames();
        let starts: Vec<usize> = std::iter::once(0).chain(s.cuts.iter().map(|c| c.frame)).collect();
        let mut segments = Vec::new();
        for (k, &start) in starts.iter().enumerate() {
            let end = starts.get(k + 1).map_or(n - 1, |&next| next - 1);
            let working = Segment {
                start,
                end,
                label: format!("B{}", k + 1),
                level: Level::Action,
                cluster: None,
                score: k.checked_sub(1).map(|c| (s.cuts[c].ratio * 100.0).round() / 100.0),
                mirror_of: None,
            };
            segments.extend(frames.to_file(working));
        }
        let segmentation = Segmentation {
            file: motion.name.clone(),
            fps: motion.fps,
            frames: motion.frames(),
            method: "pca".into(),
            params: self.echo(params),
            segments,
        };
        let curves = vec![Curve {
            id: "error-derivative".into(),
            title: "PCA error derivative / cut threshold".into(),
            values: (0..motion.frames()).map(|f| s.ratio[frames.working_frame(f)] as f32).collect(),
        }];
        let mut pictures = Vec::new();
        if options.pictures {
            progress.step("plot", 0.95)?;
            pictures.push(plot(&s, params));
        }
        let dims: Vec<String> = s.dims.iter().map(usize::to_string).collect();
        let summary = format!(
            "{} behaviours · {} cuts · {} pose dimensions · segment dimensions {}",
            segmentation.segments.len(),
            s.cuts.len(),
            p.dim,
            dims.join(", ")
        );
        Ok(MethodOutput { segmentation, details: Details { summary, pictures, curves } })
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
    }
}
