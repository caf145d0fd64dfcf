//! Per-frame feature matrices shared by the segmentation methods: a dense [`FeatureMatrix`],
//! its stacking over a window of frame offsets (Krüger et al. 2017, §IV-A: `[p_{i−f1}, …, p_i,
//! …, p_{i+f2}]`), the [`MirrorMap`] that swaps left and right (§V), and in [`pca`] the
//! principal axes the kd-tree searches (§IV-A) and the feature bundling (§III) rotate onto.
//!
//! Which features a method computes from a take is the method's own business (the SSSM's are in
//! [`crate::methods::sssm::features`]); this module only holds and transforms them.

pub mod end_effectors;
pub mod kinematics;
pub mod pca;

/// What is wrong with a feature matrix or a mirror map.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FeatureError {
    #[error("the take has no frames")]
    NoFrames,
    #[error("invalid features: {0}")]
    Bad(String),
}

/// A dense `frames × dim` matrix of `f32` features, frame-major.
#[derive(Debug, Clone, PartialEq)]
pub struct FeatureMatrix {
    frames: usize,
    dim: usize,
    data: Vec<f32>,
}

impl FeatureMatrix {
    /// Wraps `data` (frame-major, `frames × dim` values); every value must be finite.
    pub fn new(frames: usize, dim: usize, data: Vec<f32>) -> Result<Self, FeatureError> {
        if frames == 0 {
            return Err(FeatureError::NoFrames);
        }
        if dim == 0 {
            return Err(FeatureError::Bad("features have 0 values per frame".into()));
        }
        if frames.checked_mul(dim) != Some(data.len()) {
            return Err(FeatureError::Bad(format!(
                "{} values do not make {frames} frames of {dim} values",
                data.len()
            )));
        }
        if let Some(k) = data.iter().position(|v| !v.is_finite()) {
            return Err(FeatureError::Bad(format!(
                "frame {} (0-based), value {}: {} is not a finite number",
                k / dim,
                k % dim,
                data[k]
            )));
        }
        Ok(FeatureMatrix { frames, dim, data })
    }

    /// Builds a matrix from equally long rows.
    pub fn from_rows<R: AsRef<[f32]>>(rows: &[R]) -> Result<Self, FeatureError> {
        let dim = rows.first().map_or(0, |r| r.as_ref().len());
        if let Some((i, r)) = rows.iter().enumerate().find(|(_, r)| r.as_ref().len() != dim) {
            return Err(FeatureError::Bad(format!("frame {i} has {} values, frame 0 has {dim}", r.as_ref().len())));
        }
        let data = rows.iter().flat_map(|r| r.as_ref().iter().copied()).collect();
        Self::new(rows.len(), dim, data)
    }

    /// Number of frames.
    pub fn frames(&self) -> usize {
        self.frames
    }

    /// Values per frame.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// The values of frame `i`.
    pub fn row(&self, i: usize) -> &[f32] {
        &self.data[i * self.dim..(i + 1) * self.dim]
    }

    /// All values, frame-major.
    pub fn as_slice(&self) -> &[f32] {
        &self.data
    }

    /// Mutable rows (for in-place transforms inside a method; keeps finiteness the caller's
    /// responsibility).
    pub(crate) fn row_mut(&mut self, i: usize) -> &mut [f32] {
        &mut self.data[i * self.dim..(i + 1) * self.dim]
    }

    /// Multiplies every value by `factor`.
    pub fn scale(&mut self, factor: f32) {
        self.data.iter_mut().for_each(|v| *v *= factor);
    }
}

/// Stacks each frame with its neighbours at `offsets` (SSSM §IV-A): row `i` of the result is
/// `[row(i+o₁), row(i+o₂), …]`, with `i+o` clamped to the take (the first and last frames
/// repeat at the ends).
pub fn stack(base: &FeatureMatrix, offsets: &[i32]) -> FeatureMatrix {
    let n = base.frames();
    let d = base.dim();
    let mut data = Vec::with_capacity(n * d * offsets.len());
    for i in 0..n {
        for &o in offsets {
            let src = (i as i64 + o as i64).clamp(0, n as i64 - 1) as usize;
            data.extend_from_slice(base.row(src));
        }
    }
    FeatureMatrix { frames: n, dim: d * offsets.len(), data }
}

/// How a per-frame feature vector looks in a mirror (SSSM §V): value `c` of the mirrored vector is
/// `sign[c] · value source[c]` of the original (swap left and right, flip the lateral axis).
#[derive(Debug, Clone, PartialEq)]
pub struct MirrorMap {
    source: Vec<usize>,
    sign: Vec<f32>,
}

impl MirrorMap {
    /// A mirror map; `source` must be a permutation that is its own inverse (mirroring twice
    /// is the identity) and `sign` must be ±1.
    pub fn new(source: Vec<usize>, sign: Vec<f32>) -> Result<Self, FeatureError> {
        let d = source.len();
        if sign.len() != d {
            return Err(FeatureError::Bad(format!("mirror map has {d} sources but {} signs", sign.len())));
        }
        for (c, &s) in source.iter().enumerate() {
            if s >= d || source[s] != c {
                return Err(FeatureError::Bad(format!(
                    "mirror map: value {c} comes from {s}, which is not a self-inverse permutation of 0..{d}"
                )));
            }
            if sign[c] != 1.0 && sign[c] != -1.0 || sign[c] != sign[s] {
                return Err(FeatureError::Bad(format!(
                    "mirror map: sign of value {c} must be ±1 and equal to the sign of its partner"
                )));
            }
        }
        Ok(MirrorMap { source, sign })
    }

    /// The mirror of the end-effector features of
    /// [`end_effector_features`](crate::motion::normalize::end_effector_features): five points
    /// `[left hand, right hand, left foot, right foot, head]` × `(x, y, z)`, facing-aligned
    /// (body towards +Z, up +Y), so `x` is the lateral axis. Mirroring at the sagittal plane
    /// swaps left and right and changes the sign of `x`.
    pub fn end_effectors() -> Self {
        let points = [1usize, 0, 3, 2, 4];
        let mut source = Vec::with_capacity(15);
        let mut sign = Vec::with_capacity(15);
        for p in points {
            for axis in 0..3 {
                source.push(p * 3 + axis);
                sign.push(if axis == 0 { -1.0 } else { 1.0 });
            }
        }
        MirrorMap { source, sign }
    }

    /// Values per frame this map applies to.
    pub fn dim(&self) -> usize {
        self.source.len()
    }

    /// Mirrors a matrix whose rows are blocks of `dim()` values each (a stacked matrix built
    /// from features this map describes): every block is mirrored on its own.
    pub fn apply(&self, features: &FeatureMatrix) -> Result<FeatureMatrix, FeatureError> {
        let b = self.dim();
        if features.dim() % b != 0 {
            return Err(FeatureError::Bad(format!(
                "mirror map for {b} values does not fit features of {} values",
                features.dim()
            )));
        }
        let mut data = vec![0f32; features.as_slice().len()];
        for (out, src) in data.chunks_exact_mut(b).zip(features.as_slice().chunks_exact(b)) {
            for c in 0..b {
                out[c] = self.sign[c] * src[self.source[c]];
            }
        }
        Ok(FeatureMatrix { frames: features.frames(), dim: features.dim(), data })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stacking_clamps_at_both_ends() {
        let base = FeatureMatrix::from_rows(&[[0.0f32, 10.0], [1.0, 11.0], [2.0, 12.0]]).unwrap();
        let s = stack(&base, &[-2, 0, 1]);
        assert_eq!(s.dim(), 6);
        assert_eq!(s.row(0), &[0.0, 10.0, 0.0, 10.0, 1.0, 11.0]);
        assert_eq!(s.row(1), &[0.0, 10.0, 1.0, 11.0, 2.0, 12.0]);
        assert_eq!(s.row(2), &[0.0, 10.0, 2.0, 12.0, 2.0, 12.0]);
    }

    #[test]
    fn bad_matrices_are_rejected_with_the_position() {
        let e = FeatureMatrix::new(2, 2, vec![0.0, 1.0, f32::NAN, 3.0]).unwrap_err().to_string();
        assert!(e.contains("frame 1") && e.contains("value 0"), "{e}");
        assert!(FeatureMatrix::new(2, 2, vec![0.0; 3]).is_err());
        assert!(matches!(FeatureMatrix::new(0, 2, vec![]), Err(FeatureError::NoFrames)));
        let e = FeatureMatrix::from_rows(&[vec![1.0f32, 2.0], vec![1.0]]).unwrap_err().to_string();
        assert!(e.contains("frame 1 has 1 values"), "{e}");
    }

    #[test]
    fn end_effector_mirror_swaps_sides_and_flips_x() {
        let m = MirrorMap::end_effectors();
        let row: Vec<f32> = (0..15).map(|v| v as f32 + 1.0).collect();
        let f = stack(&FeatureMatrix::from_rows(&[row]).unwrap(), &[0, 1]);
        let mm = m.apply(&f).unwrap();
        // left hand (values 0..3) ← right hand (3..6) with x negated, and back
        assert_eq!(&mm.row(0)[0..3], &[-4.0, 5.0, 6.0]);
        assert_eq!(&mm.row(0)[3..6], &[-1.0, 2.0, 3.0]);
        // left foot ← right foot
        assert_eq!(&mm.row(0)[6..9], &[-10.0, 11.0, 12.0]);
        assert_eq!(&mm.row(0)[9..12], &[-7.0, 8.0, 9.0]);
        // the head stays, mirrored in x
        assert_eq!(&mm.row(0)[12..15], &[-13.0, 14.0, 15.0]);
        // the second stacked block is mirrored the same way
        assert_eq!(&mm.row(0)[15..18], &[-4.0, 5.0, 6.0]);
        // mirroring twice is the identity
        assert_eq!(m.apply(&mm).unwrap(), f);
    }

    #[test]
    fn mirror_maps_must_be_involutions() {
        assert!(MirrorMap::new(vec![1, 2, 0], vec![1.0; 3]).is_err());
        assert!(MirrorMap::new(vec![1, 0], vec![1.0, -1.0]).is_err());
        assert!(MirrorMap::new(vec![1, 0], vec![-1.0, -1.0]).is_ok());
        let m = MirrorMap::new(vec![0, 1], vec![1.0, 1.0]).unwrap();
        let f = FeatureMatrix::from_rows(&[[1.0f32, 2.0, 3.0]]).unwrap();
        assert!(m.apply(&f).is_err());
    }
}
