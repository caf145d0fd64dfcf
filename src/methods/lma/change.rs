//! Effort change: segment boundaries where the family's Effort changes — the paper's premise read the other way.
//!
//! Bouchard & Badler (§3.1): "LMA Effort is also a particularly useful marker for semantic segment boundaries
//! because it depends on some motion qualities that manifest at the beginning or end of a motion". Their search
//! (§4.2, [`super::search`]) looks for segments on which the 121 boundary-shifted classifiers *agree*. Measured on
//! spliced takes whose seams keep moving (`examples/accuracy.rs`, docs/methods/lma.md), that agreement does not
//! tell true segments from others here (the classifiers learn stand-in labels of segments cut at hand-speed minima,
//! so every pruned candidate looks like a training segment), while the family's *Effort* — its mean output, eq. 2's
//! `m` — does change across true boundaries. So this search, chosen against the paper's by nested validation:
//!
//! 1. at every candidate boundary `b` (the pruned search's hand-speed minima of both hands, or every frame in the
//!    exhaustive search), the **Effort change** `g(b) = max over the arms ‖m(b − w ..= b) − m(b ..= b + w)‖`: the
//!    distance between the family's mean 12-value output on the `w` frames before and after (`w` = the shortest
//!    segment, 0.67 s);
//! 2. a **threshold relative to the take**: `τ` = the `quantile` of `g` over the take's candidates (no fixed number
//!    that fits one take's speed and not another's);
//! 3. a **chain** of boundaries chosen by dynamic programming over the sparse candidates: maximise `Σ (g(b) − τ)` over
//!    boundaries at least the shortest segment apart; two chosen boundaries at most the longest segment apart bound a
//!    segment, farther apart they bound a gap (gestures need not tile the take).

use super::classifier::{Assessor, EffortModel};
use super::features::Pool;
use crate::method::Cancelled;

/// Boundaries whose mean outputs are computed together: their candidates (both sides, one pool: 64,
/// what an [`Assessor`] reads at once) go through each classifier in one batch, and the shifted
/// segments that nearby boundaries share are projected once.
const BLOCK: usize = 32;

/// `g(b)` at each of `boundaries`: the largest change over the arms' `pools` of the family's mean output from the
/// `window` frames before `b` to the `window` frames after (`0` where either side leaves the take). Boundaries go
/// in blocks of [`BLOCK`] ([`Assessor`]); the values are those of each boundary's sides assessed on their own
/// ([`EffortModel::assess_with`]), bit for bit.
pub fn strengths(
    model: &EffortModel,
    pools: &[Pool],
    boundaries: &[usize],
    window: usize,
    progress: &mut dyn FnMut(f64) -> Result<(), Cancelled>,
) -> Result<Vec<f64>, Cancelled> {
    let frames = pools.iter().map(Pool::frames).min().unwrap_or(0);
    let inside = |b: usize| b >= window && b + window < frames && window >= 2;
    let mut assessor = Assessor::new(model);
    let (mut candidates, mut assessed) = (Vec::new(), Vec::new());
    let mut out = vec![0.0; boundaries.len()];
    for (k, (block, g)) in boundaries.chunks(BLOCK).zip(out.chunks_mut(BLOCK)).enumerate() {
        progress((k * BLOCK) as f64 / boundaries.len() as f64)?;
        // both sides of each boundary inside the take: the candidates whose `m` the block needs
        candidates.clear();
        candidates.extend(block.iter().filter(|&&b| inside(b)).flat_map(|&b| [(b - window, b), (b, b + window)]));
        for pool in pools {
            assessor.assess(pool, &candidates, &mut assessed);
            let inner = g.iter_mut().zip(block).filter(|(_, &b)| inside(b));
            for ((g, _), sides) in inner.zip(assessed.chunks_exact(2)) {
                let (before, after) = (&sides[0].1, &sides[1].1);
                let change = before.iter().zip(after).map(|(x, y)| ((x - y) as f64).powi(2)).sum::<f64>().sqrt();
                *g = f64::max(*g, change);
            }
        }
    }
    Ok(out)
}

/// The `quantile` (0–1) of `values` (0 when empty).
pub fn relative_threshold(values: &[f64], quantile: f64) -> f64 {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * quantile.clamp(0.0, 1.0)).round() as usize]
}

/// The chain of boundaries (sorted `boundaries` with their `strength`) that maximises `Σ (strength − tau)` with
/// consecutive chosen boundaries at least `min_len` frames apart; the segments between consecutive chosen
/// boundaries at most `max_len` apart. The take's first and last frame (`frames`) count as boundaries of strength
/// `tau` (free to use, never required).
pub fn chain(
    boundaries: &[usize],
    strength: &[f64],
    frames: usize,
    (min_len, max_len): (usize, usize),
    tau: f64,
) -> Vec<(usize, usize)> {
    // nodes: the take's start, the candidates strictly inside, the take's end
    let mut nodes: Vec<(usize, f64)> = vec![(0, 0.0)];
    let mut inner: Vec<(usize, f64)> = boundaries
        .iter()
        .zip(strength)
        .filter(|(&b, _)| b > 0 && b + 1 < frames)
        .map(|(&b, &g)| (b, if g.is_finite() { g - tau } else { f64::NEG_INFINITY }))
        .collect();
    inner.sort_by_key(|x| x.0);
    inner.dedup_by_key(|x| x.0);
    nodes.extend(inner);
    if frames > 0 {
        nodes.push((frames - 1, 0.0));
    }
    let n = nodes.len();
    if n < 2 {
        return Vec::new();
    }
    // best[k]: the best sum of a chain from the start ending at node k; from[k]: its previous node
    let mut best = vec![f64::NEG_INFINITY; n];
    let mut from = vec![usize::MAX; n];
    best[0] = 0.0;
    // the best chain value among nodes at least `min_len` behind, found with a moving pointer (nodes are sorted)
    let (mut reach, mut top, mut top_at) = (0usize, f64::NEG_INFINITY, usize::MAX);
    for k in 1..n {
        while reach < k && nodes[reach].0 + min_len <= nodes[k].0 {
            if best[reach] > top {
                top = best[reach];
                top_at = reach;
            }
            reach += 1;
        }
        if top_at != usize::MAX && nodes[k].1.is_finite() {
            best[k] = top + nodes[k].1;
            from[k] = top_at;
        }
    }
    // the chain ends at the best node (the take's end is always reachable from the start when the take is long enough)
    let mut k = (0..n).max_by(|&a, &b| best[a].total_cmp(&best[b])).unwrap_or(0);
    let mut chosen = vec![nodes[k].0];
    while from[k] != usize::MAX {
        k = from[k];
        chosen.push(nodes[k].0);
    }
    chosen.reverse();
    chosen.windows(2).filter(|w| w[1] - w[0] <= max_len).map(|w| (w[0], w[1])).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::methods::lma::body::upper_body;
    use crate::methods::lma::classifier::Projector;

    /// The Effort change as it was computed before the blocks: each side of each boundary assessed on its own.
    fn strengths_one_at_a_time(model: &EffortModel, pools: &[Pool], boundaries: &[usize], window: usize) -> Vec<f64> {
        let frames = pools.iter().map(Pool::frames).min().unwrap_or(0);
        let mut projector = Projector::new(model);
        let mut mean_output =
            |pool: &Pool, start: usize, end: usize| model.assess_with(&mut projector, pool, start, end).1;
        boundaries
            .iter()
            .map(|&b| {
                if b < window || b + window >= frames || window < 2 {
                    return 0.0;
                }
                pools
                    .iter()
                    .map(|pool| {
                        let (before, after) = (mean_output(pool, b - window, b), mean_output(pool, b, b + window));
                        before.iter().zip(&after).map(|(x, y)| ((x - y) as f64).powi(2)).sum::<f64>().sqrt()
                    })
                    .fold(0.0, f64::max)
            })
            .collect()
    }

    /// The blocks change nothing: on a real take, at every frame as a boundary (those whose window leaves the take,
    /// whose shifted sides are clamped to its ends, blocks with and without such boundaries) and at boundaries out of
    /// order and repeated, the same bits as each boundary assessed on its own.
    #[test]
    fn strengths_in_blocks_are_the_boundaries_assessed_one_at_a_time() {
        let model = &crate::methods::lma::shipped_model().unwrap();
        let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/131_01.bvh")).unwrap();
        let motion = crate::motion::Motion::from_bvh("131_01.bvh", &crate::bvh::parse(&text).unwrap()).unwrap();
        let body = upper_body(&motion, model.fps).unwrap();
        let window = 20;
        let pools: Vec<Pool> = body.arms.iter().map(|arm| Pool::of(arm, model.fps, 111)).collect();
        let frames = pools[0].frames();
        let mut boundaries: Vec<usize> = (0..frames).collect();
        boundaries.extend([130, 40, 40, 200, 7, frames - 22, 25]);
        let fast = strengths(model, &pools, &boundaries, window, &mut |_| Ok(())).unwrap();
        let slow = strengths_one_at_a_time(model, &pools, &boundaries, window);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<u64>>();
        assert_eq!(bits(&fast), bits(&slow));
        assert!(slow.iter().filter(|&&g| g > 0.0).count() > frames / 2, "the take has changes to compare");
        // one arm, and a window too short for any boundary
        assert_eq!(
            bits(&strengths(model, &pools[1..], &boundaries, 25, &mut |_| Ok(())).unwrap()),
            bits(&strengths_one_at_a_time(model, &pools[1..], &boundaries, 25))
        );
        assert!(strengths(model, &pools, &boundaries, 1, &mut |_| Ok(())).unwrap().iter().all(|&g| g == 0.0));
    }

    #[test]
    fn the_chain_takes_the_strong_boundaries_far_enough_apart() {
        // strong changes at 30, 80, 130; weaker ones beside them and one too close to 80
        let b = [10, 30, 50, 75, 80, 130, 170];
        let g = [0.1, 1.0, 0.2, 0.9, 1.2, 0.8, 0.1];
        let segments = chain(&b, &g, 200, (20, 100), 0.5);
        assert_eq!(segments, vec![(0, 30), (30, 80), (80, 130), (130, 199)]);
        // a threshold above every change: no inner boundary, the take one segment if short enough, else nothing
        assert_eq!(chain(&b, &g, 200, (20, 100), 5.0), vec![]);
        assert_eq!(chain(&b, &g, 90, (20, 100), 5.0), vec![(0, 89)]);
        // boundaries farther apart than the longest segment bound a gap, not a segment
        let segments = chain(&[20, 60, 300, 340], &[1.0; 4], 400, (20, 100), 0.5);
        assert_eq!(segments, vec![(0, 20), (20, 60), (300, 340), (340, 399)]);
        // nothing to choose from
        assert!(chain(&[], &[], 0, (20, 100), 0.0).is_empty());
        assert_eq!(chain(&[5], &[f64::NAN], 50, (20, 100), 0.0), vec![(0, 49)]);
    }

    #[test]
    fn thresholds_are_quantiles_of_the_take() {
        let v: Vec<f64> = (0..11).map(f64::from).collect();
        assert_eq!(relative_threshold(&v, 0.5), 5.0);
        assert_eq!(relative_threshold(&v, 0.0), 0.0);
        assert_eq!(relative_threshold(&v, 1.0), 10.0);
        assert_eq!(relative_threshold(&[], 0.5), 0.0);
    }
}
