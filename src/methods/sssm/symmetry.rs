//! Symmetry of motion data (Krüger et al. 2017, §V).
//!
//! The mirrored features (left and right swapped, the lateral axis flipped — see
//! [`MirrorMap`](super::features::MirrorMap)) are searched against the original ones, which
//! gives a second SSSM. Its diagonals mark where a frame resembles the *mirror image* of
//! another: in walking, each left step resembles the mirrored right step half a cycle later.
//! The primitive search on that SSSM yields the mirror cuts; those not within
//! `min_cut_distance` of a cut of the original features are added, which splits a gait cycle
//! into its two steps. Comparing both sets of cuts classifies each action (§V, Appendix A).

use serde::{Deserialize, Serialize};

/// How an action relates to its mirror image (§V).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SymmetryKind {
    /// The mirror step did not run (`mirror` off, or no mirror map for the features).
    Unchecked,
    /// Neither the original nor the mirrored features show repetitions.
    NoRepetition,
    /// The mirrored features give exactly the cuts of the original ones.
    Symmetric,
    /// The mirrored features give cuts, none of them shared with the original ones.
    PhaseShifted,
    /// The mirrored features give no cuts at all.
    Asymmetric,
    /// Some cuts shared, some not.
    Mixed,
}

/// The cuts of the original features plus the mirror cuts at least `min_distance` frames away
/// from all of them, ascending (`main` must be ascending).
pub fn merge_cuts(main: &[usize], mirror: &[usize], min_distance: usize) -> Vec<usize> {
    let mut out: Vec<usize> = main.to_vec();
    out.extend(mirror.iter().copied().filter(|&m| nearest_gap(main, m) >= min_distance));
    out.sort_unstable();
    out.dedup();
    out
}

/// Distance from `frame` to the nearest of the ascending `cuts` (`usize::MAX` if none).
fn nearest_gap(cuts: &[usize], frame: usize) -> usize {
    let k = cuts.partition_point(|&c| c < frame);
    let after = cuts.get(k).map_or(usize::MAX, |&c| c - frame);
    let before = k.checked_sub(1).map_or(usize::MAX, |b| frame - cuts[b]);
    after.min(before)
}

/// Classifies an action by its original and mirror cuts (both ascending); cuts closer than
/// `tolerance` frames count as shared.
pub fn classify(main: &[usize], mirror: &[usize], tolerance: usize) -> SymmetryKind {
    let shared = |c: usize, other: &[usize]| nearest_gap(other, c) < tolerance;
    match (main.is_empty(), mirror.is_empty()) {
        (true, true) => SymmetryKind::NoRepetition,
        (false, true) => SymmetryKind::Asymmetric,
        _ => {
            let mirror_shared = mirror.iter().filter(|&&m| shared(m, main)).count();
            let main_shared = main.iter().filter(|&&c| shared(c, mirror)).count();
            if mirror_shared == 0 {
                SymmetryKind::PhaseShifted
            } else if mirror_shared == mirror.len() && main_shared == main.len() {
                SymmetryKind::Symmetric
            } else {
                SymmetryKind::Mixed
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mirror_cuts_fill_the_gaps_between_original_cuts() {
        assert_eq!(merge_cuts(&[30, 60, 90], &[15, 45, 62, 75], 5), vec![15, 30, 45, 60, 75, 90]);
        assert_eq!(merge_cuts(&[], &[15, 45], 5), vec![15, 45]);
        assert_eq!(merge_cuts(&[30], &[], 5), vec![30]);
        assert_eq!(merge_cuts(&[30], &[35], 5), vec![30, 35], "5 frames apart is not closer than 5");
    }

    #[test]
    fn symmetry_kinds() {
        assert_eq!(classify(&[], &[], 5), SymmetryKind::NoRepetition);
        assert_eq!(classify(&[30, 60], &[], 5), SymmetryKind::Asymmetric);
        assert_eq!(classify(&[30, 60], &[31, 59], 5), SymmetryKind::Symmetric);
        assert_eq!(classify(&[30, 60], &[15, 45], 5), SymmetryKind::PhaseShifted);
        assert_eq!(classify(&[30, 60], &[30, 45], 5), SymmetryKind::Mixed);
        assert_eq!(classify(&[], &[15], 5), SymmetryKind::PhaseShifted);
    }
}
