//! One adapter for the unsupervised methods (SSSM and the kinematic baselines: velocity, KCS, PCA): each says who
//! it is, its parameters and what it needs ([`Segmenter`]), and segments a take ([`Segmenter::segment`]); the
//! [`Method`] around it — the info, the check, the echo of the checked parameters, the segmentation at the file's
//! frame rate — is [`Unsupervised`]'s, written once.

use serde::de::DeserializeOwned;
use serde::Serialize;

use super::bounds::Valid;
use super::{
    Curve, Details, Method, MethodError, MethodInfo, MethodOutput, ParamSpec, Picture, Progress, RunOptions, Work,
};
use crate::motion::Motion;
use crate::segment::frames::WorkingFrames;
use crate::segment::{Segment, Segmentation};

/// Who a method is, as [`MethodInfo`] says it (an unsupervised method runs by itself after each load).
#[derive(Debug, Clone, Copy)]
pub struct About {
    pub name: &'static str,
    pub short: &'static str,
    pub paper: &'static str,
    pub summary: &'static str,
}

/// Parameters that know their own check.
pub trait Checkable: Sized {
    /// The checked parameters, what the method runs on.
    type Valid: Echo + Send + Sync + 'static;
    /// Validates; a refusal names the parameter and what is accepted.
    fn check(self) -> Result<Self::Valid, MethodError>;
}

/// Checked parameters as a segmentation's `params` echoes them.
pub trait Echo {
    fn echo(&self) -> serde_json::Value;
}

impl<P: Serialize> Echo for Valid<P> {
    fn echo(&self) -> serde_json::Value {
        serde_json::to_value(&**self).unwrap_or_default()
    }
}

/// The checked parameters of segmenter `S`.
pub type Checked<S> = <<S as Segmenter>::Params as Checkable>::Valid;

/// What a segmenter found: its segments (file frames), the summary line, its curves (one value per file frame:
/// [`at_file_rate`]) and its pictures (drawn only when the run asks for them).
pub struct Found {
    pub segments: Vec<Segment>,
    pub summary: String,
    pub curves: Vec<Curve>,
    pub pictures: Vec<Picture>,
}

/// An unsupervised method: [`Method`] comes from [`Unsupervised`].
pub trait Segmenter: Send + Sync + 'static {
    type Params: Checkable + Serialize + DeserializeOwned + Default + Clone + Send + Sync + 'static;
    const ABOUT: About;
    /// Every parameter with its help, bounds and default.
    fn param_specs(&self) -> Vec<ParamSpec>;
    /// What a run needs per working frame ([`Method::work`]).
    fn work(&self, params: &Checked<Self>) -> Work;
    /// Segments `motion` (the pictures only if `options.pictures`).
    fn segment(
        &self,
        motion: &Motion,
        params: &Checked<Self>,
        options: &RunOptions,
        progress: &mut dyn Progress,
    ) -> Result<Found, MethodError>;
}

/// The [`Method`] of a [`Segmenter`].
#[derive(Debug, Clone, Copy, Default)]
pub struct Unsupervised<S>(pub S);

impl<S: Segmenter> Method for Unsupervised<S> {
    type Params = S::Params;
    type Checked = Checked<S>;

    fn info(&self) -> MethodInfo {
        let a = S::ABOUT;
        MethodInfo {
            name: a.name.into(),
            short: a.short.into(),
            paper: a.paper.into(),
            summary: a.summary.into(),
            auto_run: true,
        }
    }

    fn param_specs(&self) -> Vec<ParamSpec> {
        self.0.param_specs()
    }

    fn check(&self, params: S::Params) -> Result<Checked<S>, MethodError> {
        params.check()
    }

    fn echo(&self, params: &Checked<S>) -> serde_json::Value {
        params.echo()
    }

    fn work(&self, params: &Checked<S>) -> Work {
        self.0.work(params)
    }

    fn run(
        &self,
        motion: &Motion,
        params: &Checked<S>,
        options: &RunOptions,
        progress: &mut dyn Progress,
    ) -> Result<MethodOutput, MethodError> {
        let found = self.0.segment(motion, params, options, progress)?;
        let segmentation = Segmentation {
            file: motion.name.clone(),
            fps: motion.fps,
            frames: motion.frames(),
            method: S::ABOUT.name.into(),
            params: params.echo(),
            segments: found.segments,
        };
        let details =
            Details { summary: found.summary, pictures: found.pictures, curves: found.curves, take_fit: None };
        Ok(MethodOutput { segmentation, details })
    }
}

/// A curve of working-rate `values` as one value per file frame of `frames`.
pub fn at_file_rate(id: String, title: String, values: &[f32], frames: &WorkingFrames) -> Curve {
    Curve { id, title, values: (0..frames.file_frames).map(|f| values[frames.working_frame(f)]).collect() }
}
