//! The kinematic feature pool of Bouchard & Badler's LMA Effort classifiers (their §4, Fig. 1):
//! per-frame kinematic quantities of a joint ([`Kinematics`], shared with the other methods in
//! [`crate::features::kinematics`]: speed, acceleration, jerk, curvature, distance from the torso), each weighted to emphasise the beginning, middle or end of
//! a candidate segment ([`Weighting`]) and reduced to one scalar by a statistic ([`Stat`]: mean,
//! sum, max, min, standard deviation).
//!
//! The segmentation scores every candidate segment between 0.67 s and 3.33 s — the exhaustive
//! search is tens of thousands of candidates per take — so a candidate's features must cost O(1)
//! each: [`Prefix`] keeps cumulative sums of `x`, `t·x`, `x²`, `t·x²` (every weighting here is
//! linear in `t` on each half of the segment, so its weighted sums follow from those) and sparse
//! tables for range maxima and minima. Weighted max / min are the max / min of the unweighted
//! values (a weight that varies along the segment has no O(1) range maximum); the paper leaves
//! which combinations its 4500 permutations hold unstated.

pub use crate::features::kinematics::Kinematics;

/// Which part of a segment a feature emphasises (`u` = 0 at its first frame, 1 at its last).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Weighting {
    /// Every frame alike.
    Uniform,
    /// `1 − u`: "the velocity of each frame scaled by its normalized distance from the last frame".
    Beginning,
    /// `1 − |2u − 1|`.
    Middle,
    /// `u`.
    End,
}

/// How a weighted feature becomes one scalar.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stat {
    /// Weighted mean `Σ w x / Σ w`.
    Mean,
    /// `Σ w x`.
    Sum,
    /// Largest value (unweighted, see the module docs).
    Max,
    /// Smallest value (unweighted).
    Min,
    /// Weighted standard deviation.
    Std,
}

/// Cumulative sums and range-extremum tables of one per-frame series, for O(1) segment statistics.
#[derive(Debug, Clone)]
pub struct Prefix {
    /// `c[k][i]` = Σ over frames `< i` of `x`, `t·x`, `x²`, `t·x²`, `1`, `t` (k = 0..6).
    c: [Vec<f64>; 6],
    max: Vec<Vec<f64>>,
    min: Vec<Vec<f64>>,
}

impl Prefix {
    pub fn new(x: &[f64]) -> Prefix {
        let n = x.len();
        let mut c: [Vec<f64>; 6] = std::array::from_fn(|_| vec![0.0; n + 1]);
        for (t, &v) in x.iter().enumerate() {
            let tf = t as f64;
            let terms = [v, tf * v, v * v, tf * v * v, 1.0, tf];
            for (k, term) in terms.iter().enumerate() {
                c[k][t + 1] = c[k][t] + term;
            }
        }
        let table = |pick: fn(f64, f64) -> f64| {
            let mut levels = vec![x.to_vec()];
            let mut width = 1;
            while 2 * width <= n {
                let prev = &levels[levels.len() - 1];
                let next: Vec<f64> = (0..=n - 2 * width).map(|i| pick(prev[i], prev[i + width])).collect();
                levels.push(next);
                width *= 2;
            }
            levels
        };
        Prefix { c, max: table(f64::max), min: table(f64::min) }
    }

    /// Σ over frames `a..b` (exclusive) of term `k`.
    fn range(&self, k: usize, a: usize, b: usize) -> f64 {
        self.c[k][b] - self.c[k][a]
    }

    /// `(Σ w, Σ w x, Σ w x²)` over frames `a..b` for the weight `w(t) = p + q·t`.
    fn linear(&self, a: usize, b: usize, p: f64, q: f64) -> (f64, f64, f64) {
        let w = p * self.range(4, a, b) + q * self.range(5, a, b);
        let wx = p * self.range(0, a, b) + q * self.range(1, a, b);
        let wx2 = p * self.range(2, a, b) + q * self.range(3, a, b);
        (w, wx, wx2)
    }

    fn extremum(levels: &[Vec<f64>], a: usize, b: usize, pick: fn(f64, f64) -> f64) -> f64 {
        let len = b - a;
        let level = (usize::BITS - 1 - len.leading_zeros()) as usize;
        pick(levels[level][a], levels[level][b - (1 << level)])
    }

    /// The statistic `stat` of the series weighted by `weighting` over the segment of frames
    /// `start..=end` (`start ≤ end` inside the series), in O(1).
    pub fn stat(&self, start: usize, end: usize, weighting: Weighting, stat: Stat) -> f64 {
        let (a, b) = (start, end + 1);
        match stat {
            Stat::Max => return Self::extremum(&self.max, a, b, f64::max),
            Stat::Min => return Self::extremum(&self.min, a, b, f64::min),
            _ => {}
        }
        // u(t) = (t − start) / span; every weighting is linear in t on [start, mid] and [mid, end]
        let span = (end - start).max(1) as f64;
        let s = start as f64;
        let (w, wx, wx2) = match weighting {
            Weighting::Uniform => self.linear(a, b, 1.0, 0.0),
            Weighting::End => self.linear(a, b, -s / span, 1.0 / span),
            Weighting::Beginning => self.linear(a, b, 1.0 + s / span, -1.0 / span),
            Weighting::Middle => {
                // 2u on the first half, 2 − 2u on the second (the middle frame in the first)
                let mid = start + (end - start) / 2;
                let first = self.linear(a, mid + 1, -2.0 * s / span, 2.0 / span);
                let second = self.linear(mid + 1, b, 2.0 + 2.0 * s / span, -2.0 / span);
                (first.0 + second.0, first.1 + second.1, first.2 + second.2)
            }
        };
        match stat {
            Stat::Sum => wx,
            Stat::Mean if w > 0.0 => wx / w,
            Stat::Std if w > 0.0 => (wx2 / w - (wx / w).powi(2)).max(0.0).sqrt(),
            _ => 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stats::Rng;

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol * (1.0 + b.abs())
    }

    /// The statistic computed frame by frame, as the definition reads.
    fn direct(x: &[f64], start: usize, end: usize, weighting: Weighting, stat: Stat) -> f64 {
        let span = (end - start).max(1) as f64;
        let w = |t: usize| {
            let u = (t - start) as f64 / span;
            match weighting {
                Weighting::Uniform => 1.0,
                Weighting::Beginning => 1.0 - u,
                Weighting::End => u,
                Weighting::Middle => 1.0 - (2.0 * u - 1.0).abs(),
            }
        };
        let frames = start..=end;
        let sw: f64 = frames.clone().map(w).sum();
        let swx: f64 = frames.clone().map(|t| w(t) * x[t]).sum();
        let swx2: f64 = frames.clone().map(|t| w(t) * x[t] * x[t]).sum();
        match stat {
            Stat::Sum => swx,
            Stat::Mean | Stat::Std if sw == 0.0 => 0.0,
            Stat::Mean => swx / sw,
            Stat::Std => (swx2 / sw - (swx / sw).powi(2)).max(0.0).sqrt(),
            Stat::Max => frames.map(|t| x[t]).fold(f64::MIN, f64::max),
            Stat::Min => frames.map(|t| x[t]).fold(f64::MAX, f64::min),
        }
    }

    #[test]
    fn prefix_statistics_equal_the_direct_computation() {
        let mut rng = Rng::new(11);
        let x: Vec<f64> = (0..300).map(|_| rng.next_f32() as f64 * 10.0 - 3.0).collect();
        let prefix = Prefix::new(&x);
        for _ in 0..400 {
            let start = rng.below(290);
            let end = start + 1 + rng.below(299 - start);
            for weighting in [Weighting::Uniform, Weighting::Beginning, Weighting::Middle, Weighting::End] {
                for stat in [Stat::Mean, Stat::Sum, Stat::Max, Stat::Min, Stat::Std] {
                    let (fast, slow) =
                        (prefix.stat(start, end, weighting, stat), direct(&x, start, end, weighting, stat));
                    // a standard deviation near 0 is the square root of a difference of sums: its
                    // rounding shows (1e-5 on values of 10); everything else agrees to 1e-9
                    let ok = match stat {
                        Stat::Std => (fast - slow).abs() < 1e-4,
                        _ => close(fast, slow, 1e-9),
                    };
                    assert!(ok, "{start}..={end} {weighting:?} {stat:?}: {fast} vs {slow}");
                }
            }
        }
        // a one-frame segment: its value, whatever the weighting's shape
        assert_eq!(prefix.stat(7, 7, Weighting::Uniform, Stat::Mean), x[7]);
        assert_eq!(prefix.stat(7, 7, Weighting::Uniform, Stat::Max), x[7]);
    }
}
