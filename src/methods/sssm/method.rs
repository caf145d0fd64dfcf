//! The SSSM method behind the common [`Method`] interface: the parameters of [`SssmParams`],
//! the segmentation at the file's frame rate (actions, transitions, primitives with their
//! clusters and mirror pairs) and the SSSM picture of [`super::image`].

use super::{Span, SssmError, SssmOutcome, SssmParams, ValidParams};
use crate::method::unsupervised::{About, Checkable, Echo, Found, Segmenter};
use crate::method::{counted, MethodError, ParamSpec, Picture, Progress, RunOptions, Work};
use crate::motion::Motion;
use crate::segment::frames::WorkingFrames;
use crate::segment::{Level, Segment, Segmentation};

/// Sparse self-similarity segmentation (Krüger et al. 2017).
#[derive(Debug, Clone, Copy, Default)]
pub struct Sssm;

impl From<SssmError> for MethodError {
    fn from(e: SssmError) -> Self {
        match e {
            SssmError::InvalidParam { name, .. } => MethodError::param(name, e.to_string()),
            SssmError::Cancelled => MethodError::Cancelled,
            other => MethodError::Failed(other.to_string()),
        }
    }
}

impl Checkable for SssmParams {
    type Valid = ValidParams;
    fn check(self) -> Result<ValidParams, MethodError> {
        Ok(SssmParams::check(self)?)
    }
}

impl Echo for ValidParams {
    fn echo(&self) -> serde_json::Value {
        self.to_json()
    }
}

impl Segmenter for Sssm {
    type Params = SssmParams;
    const ABOUT: About = About {
        name: "sssm",
        short: "SSSM",
        paper: "Krüger et al. 2017",
        summary:
            "Unsupervised: actions (repetitive activities) and the transitions between them, each action cut into \
                  motion primitives, primitives clustered, mirror pairs (left/right step) found.",
    };

    fn param_specs(&self) -> Vec<ParamSpec> {
        super::params::param_specs()
    }

    fn work(&self, params: &ValidParams) -> Work {
        work(params)
    }

    fn segment(
        &self,
        motion: &Motion,
        params: &ValidParams,
        options: &RunOptions,
        progress: &mut dyn Progress,
    ) -> Result<Found, MethodError> {
        let max_entries = entry_limit(motion, params, &options.limits);
        let result = super::segment_valid(motion, params, max_entries, &mut |stage, f| progress.step(stage, f))?;
        let o = &result.outcome;
        let s = &result.segmentation;
        let summary = format!(
            "{} · {} · {} in {} · SSSM of {} at {} Hz",
            counted(s.level(Level::Action).count(), "action"),
            counted(s.level(Level::Transition).count(), "transition"),
            counted(s.level(Level::Primitive).count(), "primitive"),
            counted(o.clusters.len(), "cluster"),
            counted(o.frames, "frame"),
            o.fps
        ) + &no_action_reason(s.level(Level::Action).count(), o.frames, o.fps, params);
        let mut pictures = Vec::new();
        if options.pictures {
            progress.step("image", 0.99)?;
            let image = super::image::render(o);
            pictures.push(Picture {
                id: "image".into(),
                title: "Sparse self-similarity matrix".into(),
                caption: format!(
                    "Frame i down, frame j across ({} Hz{}). Grey: neighbours within the search radius, darker = \
                     closer. Coloured squares: actions (colour = kind of action); orange squares: transitions; blue \
                     lines: primitive cuts; red lines: cuts found only in the mirrored features. Farther apart than \
                     the search horizon, only the blocks of actions that may repeat each other are searched. Click a \
                     pixel to go to its pair of frames.",
                    o.fps,
                    if image.block > 1 { format!(", {} frames per pixel", image.block) } else { String::new() }
                ),
                width: image.size,
                height: image.size,
                rgba: image.rgba,
                // a pixel spans `block` working frames, each `file fps / working fps` file frames
                frames_per_pixel: Some(image.block as f64 * motion.fps / o.fps),
            });
        }
        Ok(Found { segments: result.segmentation.segments, summary, curves: Vec::new(), pictures })
    }
}

/// The method's result at the file's frame rate: actions (`A<kind>`), transitions and
/// primitives (`P<cluster>`, with their mirror cluster), sorted by start frame.
pub(crate) fn to_segmentation(motion: &Motion, params: &ValidParams, o: &SssmOutcome, source: &[f64]) -> Segmentation {
    let frames = WorkingFrames { source, file_frames: motion.frames() };
    let mut segments = Vec::new();
    let mut push = |span: Span, label: String, level: Level, cluster: Option<usize>, mirror_of: Option<usize>| {
        let working =
            Segment { start: span.start, end: span.end, label, level, cluster, score: None, mirror_of, effort: None };
        segments.extend(frames.to_file(working));
    };
    for a in &o.actions {
        push(a.span, format!("A{}", a.cluster), Level::Action, Some(a.cluster), None);
    }
    for t in &o.activities.transitions {
        push(*t, "transition".into(), Level::Transition, None, None);
    }
    for p in &o.primitives {
        let mirror_of = o.clusters[p.cluster].mirror_of;
        let label = match mirror_of {
            Some(m) => format!("P{} mirrors P{m}", p.cluster),
            None => format!("P{}", p.cluster),
        };
        push(p.span, label, Level::Primitive, Some(p.cluster), mirror_of);
    }
    segments.sort_by_key(|s| (s.start, s.level != Level::Primitive, s.end));
    Segmentation {
        file: motion.name.clone(),
        fps: motion.fps,
        frames: motion.frames(),
        method: "sssm".into(),
        params: params.to_json(),
        segments,
    }
}

/// Why a run found no action, for its summary (empty when it found some): an action is a stretch
/// of frames that come back (§IV-B: a block of off-diagonal SSSM entries), so a take in which no
/// movement repeats — one too short to hold a movement twice — has none.
fn no_action_reason(actions: usize, frames: usize, fps: f64, params: &ValidParams) -> String {
    if actions > 0 {
        return String::new();
    }
    format!(
        " — no action found: SSSM finds an action where the movement repeats, a block of more than {} neighbour \
         pairs at least {} apart; nothing in these {:.1} s repeats that much (a take needs a movement done at least \
         twice, usually several seconds)",
        params.min_action_entries(),
        counted(params.band_frames(), "frame"),
        frames as f64 / fps
    )
}
/// What a run needs besides its neighbour entries: features, kd-tree and refinement, 7.8 kB per
/// working frame measured on a repetitive take. The entries — up to `max_neighbours` per frame,
/// twice with the mirror SSSM, plus the bundling's `bundling_k` — are not declared for their
/// worst case (every frame alike, which no real take of minutes comes near: it refused a 10-minute
/// take at the defaults); the searches count them as they find them against what the budget
/// leaves ([`entry_limit`]) and stop when they pass it.
pub(super) fn work(params: &ValidParams) -> Work {
    Work::memory(params.fps, 8_000, 4 << 20, "or lower max_neighbours")
}

/// The neighbour entries a run on `motion` may draw: what `limits` leave after [`work`], at
/// [`super::BYTES_PER_ENTRY`] each.
pub fn entry_limit(motion: &Motion, params: &ValidParams, limits: &crate::method::WorkLimits) -> usize {
    let work = work(params);
    limits.max_bytes.saturating_sub(work.bytes(work.frames(motion), motion.joints())) / super::BYTES_PER_ENTRY
}
