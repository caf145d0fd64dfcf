//! The k-nearest-neighbour labeller the DT-FCN issue puts beside the network: each frame's label
//! is the majority of its `k` nearest training frames, a frame being the ±1 s window of the motion
//! image around it (the canonical joints at 30 Hz, hip-relative, facing-aligned, in inches of the
//! reference body), sampled every `stride` frames and rotated onto its leading principal axes
//! (nalgebra), searched with a kiddo kd-tree. The confidence of a frame is the share of votes its
//! label won.
//!
//! Not yet a registered method: it becomes one with the DT-FCN's model files and label set.
//! `cargo run --release --example eval_knn` scores it leave-one-take-out on the shared takes.

use kiddo::immutable::float::kdtree::ImmutableKdTree;
use kiddo::SquaredEuclidean;

use crate::features::end_effectors::canonical_joints;
use crate::features::pca::principal_axes;
use crate::features::{stack, FeatureMatrix};
use crate::motion::joints::Canonical;
use crate::motion::Motion;
use crate::segment::frames::WorkingFrames;

/// Principal coordinates the tree searches.
pub const DIMS: usize = 32;

/// How frames are described and voted on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KnnParams {
    pub fps: f64,
    /// Half the window, in working frames (30 = ±1 s at 30 Hz).
    pub half_window: i32,
    /// Every this many frames of the window are kept.
    pub stride: i32,
    pub k: usize,
}

impl Default for KnnParams {
    fn default() -> Self {
        KnnParams { fps: 30.0, half_window: 30, stride: 5, k: 5 }
    }
}

/// A labelled take for fitting: the motion and one label index per file frame.
pub struct Labelled<'a> {
    pub motion: &'a Motion,
    pub labels: &'a [usize],
}

/// The fitted labeller.
pub struct Knn {
    params: KnnParams,
    mean: Vec<f32>,
    /// `DIMS × d` leading principal axes.
    axes: Vec<f32>,
    tree: ImmutableKdTree<f32, u32, DIMS, 32>,
    labels: Vec<usize>,
}

/// The stacked window of every working frame of `motion` and the working frames' file positions.
fn windows(motion: &Motion, p: &KnnParams) -> Result<(FeatureMatrix, Vec<f64>), String> {
    let f = canonical_joints(motion, p.fps, true, &Canonical::ALL).map_err(|e| format!("{}: {e}", motion.name))?;
    let offsets: Vec<i32> = (-p.half_window..=p.half_window).step_by(p.stride.max(1) as usize).collect();
    Ok((stack(&f.base, &offsets), f.source_frames))
}

fn project(x: &[f32], mean: &[f32], axes: &[f32]) -> [f32; DIMS] {
    let d = mean.len();
    std::array::from_fn(|k| {
        axes.get(k * d..(k + 1) * d).map_or(0.0, |a| a.iter().zip(x).zip(mean).map(|((a, x), m)| a * (x - m)).sum())
    })
}

impl Knn {
    /// Fits on `takes` (every working frame with the label of its file frame).
    pub fn fit(takes: &[Labelled], params: KnnParams) -> Result<Knn, String> {
        let mut rows: Vec<f32> = Vec::new();
        let mut labels = Vec::new();
        let mut dim = 0;
        for t in takes {
            let (w, source) = windows(t.motion, &params)?;
            dim = w.dim();
            for (i, &s) in source.iter().enumerate() {
                let f = (s.round() as usize).min(t.labels.len().saturating_sub(1));
                if let Some(&l) = t.labels.get(f) {
                    rows.extend_from_slice(w.row(i));
                    labels.push(l);
                }
            }
        }
        let all = FeatureMatrix::new(labels.len(), dim, rows).map_err(|e| format!("k-NN training frames: {e}"))?;
        let (mean, axes) = principal_axes(&all);
        let points: Vec<[f32; DIMS]> = (0..all.frames()).map(|i| project(all.row(i), &mean, &axes)).collect();
        let tree = ImmutableKdTree::new_from_slice(&points);
        Ok(Knn { params, mean, axes, tree, labels })
    }

    /// Per file frame of `motion`: the voted label and the share of the `k` votes it won.
    pub fn predict(&self, motion: &Motion) -> Result<Vec<(usize, f32)>, String> {
        let (w, source) = windows(motion, &self.params)?;
        let k = self.params.k.max(1);
        let working: Vec<(usize, f32)> = (0..w.frames())
            .map(|i| {
                let q = project(w.row(i), &self.mean, &self.axes);
                let found = self.tree.nearest_n::<SquaredEuclidean>(
                    &q,
                    std::num::NonZero::new(k).unwrap_or(std::num::NonZero::<usize>::MIN),
                );
                // votes in order of distance: ties go to the label whose nearest vote is nearer
                let mut votes: Vec<(usize, usize, usize)> = Vec::new(); // (label, count, rank of first)
                for (rank, n) in found.iter().enumerate() {
                    let l = self.labels[n.item as usize];
                    match votes.iter_mut().find(|v| v.0 == l) {
                        Some(v) => v.1 += 1,
                        None => votes.push((l, 1, rank)),
                    }
                }
                let best = votes.iter().max_by_key(|v| (v.1, std::cmp::Reverse(v.2))).copied().unwrap_or((0, 0, 0));
                (best.0, best.1 as f32 / found.len().max(1) as f32)
            })
            .collect();
        let frames = WorkingFrames { source: &source, file_frames: motion.frames() };
        Ok((0..motion.frames()).map(|f| working[frames.working_frame(f)]).collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh;

    fn motion(name: &str, text: &str) -> Motion {
        Motion::from_bvh(name, &bvh::parse(text).unwrap()).unwrap()
    }

    #[test]
    fn a_take_is_labelled_as_its_copy_in_other_units_was_taught() {
        let taught = motion("131_01.bvh", include_str!("../../tests/fixtures/131_01.bvh"));
        // the same take written in metres: the reference-body scaling makes it the same frames
        let asked = motion("metres.bvh", include_str!("../../tests/fixtures/cmu_131_01_scaled_meters.bvh"));
        let half = taught.frames() / 2;
        let labels: Vec<usize> = (0..taught.frames()).map(|f| usize::from(f >= half)).collect();
        let knn = Knn::fit(&[Labelled { motion: &taught, labels: &labels }], KnnParams::default()).unwrap();
        let predicted = knn.predict(&asked).unwrap();
        assert_eq!(predicted.len(), asked.frames());
        let right = predicted.iter().zip(&labels).filter(|(p, &l)| p.0 == l).count() as f64 / labels.len() as f64;
        assert!(right > 0.95, "{right}");
        // far from the change of label, all five votes agree
        assert_eq!(predicted[50].1, 1.0);
        // a take without the canonical joints is refused by name
        let stick = motion("stick.bvh", include_str!("../../tests/fixtures/bvh_anim_test_simple.bvh"));
        assert!(knn.predict(&stick).unwrap_err().starts_with("stick.bvh:"));
    }
}
