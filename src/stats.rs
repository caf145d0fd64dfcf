//! Small statistics helpers shared across the crate: medians and one deterministic
//! pseudo-random generator for tests and synthetic data (no OS entropy, so it runs the same
//! natively and in wasm32).

use std::cmp::Ordering;

/// Values with a total order for [`median`]: integers by `Ord`, floats by `total_cmp`.
pub trait TotalOrder: Copy {
    fn total_order(&self, other: &Self) -> Ordering;
}

macro_rules! total_order_by_ord {
    ($($t:ty),*) => {
        $(impl TotalOrder for $t {
            fn total_order(&self, other: &Self) -> Ordering {
                self.cmp(other)
            }
        })*
    };
}
total_order_by_ord!(u8, u16, u32, u64, usize, i8, i16, i32, i64, isize);

impl TotalOrder for f32 {
    fn total_order(&self, other: &Self) -> Ordering {
        self.total_cmp(other)
    }
}

impl TotalOrder for f64 {
    fn total_order(&self, other: &Self) -> Ordering {
        self.total_cmp(other)
    }
}

/// The (upper) median of `values`: the value at index `len / 2` once sorted (`values` is
/// reordered). `None` if empty.
pub fn median<T: TotalOrder>(values: &mut [T]) -> Option<T> {
    if values.is_empty() {
        return None;
    }
    let k = values.len() / 2;
    Some(*values.select_nth_unstable_by(k, T::total_order).1)
}

/// The median of `values` with an even count taken as the mean of the two middle values
/// (`values` is reordered). `None` if empty.
pub fn median_midpoint(values: &mut [f64]) -> Option<f64> {
    let upper = median(values)?;
    let n = values.len();
    if n % 2 == 1 {
        return Some(upper);
    }
    // after the selection the lower middle value is the largest of the first half
    let lower = values[..n / 2].iter().copied().max_by(f64::total_cmp).expect("n ≥ 2");
    Some(0.5 * (lower + upper))
}

/// A small deterministic pseudo-random generator: Knuth's MMIX linear congruential generator
/// (`s ← 6364136223846793005·s + 1442695040888963407`), read from its high bits only (its low
/// bits have short periods). Good enough for noise and fuzz inputs; not for anything secret.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Rng(u64);

impl Rng {
    /// A generator started at `seed` (the same seed gives the same sequence everywhere).
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }

    fn step(&mut self) -> u64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        self.0
    }

    /// The next 32 random bits.
    pub fn next_u32(&mut self) -> u32 {
        (self.step() >> 32) as u32
    }

    /// The next 64 random bits (two steps).
    pub fn next_u64(&mut self) -> u64 {
        ((self.next_u32() as u64) << 32) | self.next_u32() as u64
    }

    /// Uniform in `[0, 1)` with 24 bits (exactly representable as `f32`).
    pub fn next_f32(&mut self) -> f32 {
        (self.step() >> 40) as f32 / (1u64 << 24) as f32
    }

    /// Uniform in `0..n` (0 if `n` is 0).
    pub fn below(&mut self, n: usize) -> usize {
        ((self.next_u64() as u128 * n as u128) >> 64) as usize
    }
}

/// The mean of `values` and its percentile-bootstrap 95 % interval: `resamples` means of `values.len()` values drawn
/// with replacement (deterministic from `seed`), their 2.5th and 97.5th percentiles (Efron & Tibshirani 1993, §13.3).
/// With few values (four or five takes) the interval is coarse and can be too narrow; it is still the honest spread
/// of a mean over them. `None` for no value or a non-finite one.
pub fn bootstrap_mean(values: &[f64], resamples: usize, seed: u64) -> Option<(f64, f64, f64)> {
    if values.is_empty() || values.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let n = values.len();
    let mean = values.iter().sum::<f64>() / n as f64;
    let mut rng = Rng::new(seed);
    let mut means: Vec<f64> =
        (0..resamples.max(1)).map(|_| (0..n).map(|_| values[rng.below(n)]).sum::<f64>() / n as f64).collect();
    means.sort_by(f64::total_cmp);
    let at = |q: f64| means[((q * (means.len() - 1) as f64).round() as usize).min(means.len() - 1)];
    Some((mean, at(0.025), at(0.975)))
}

/// The mean of a grid of scores — `values[run][take]`, every run (a trained model's seed) scored on every take — and
/// its two-way percentile-bootstrap 95 % interval: each resample draws the takes *and* the runs with replacement and
/// averages the drawn runs' scores on the drawn takes, so the interval holds the luck of the seed beside that of the
/// takes. One run is [`bootstrap_mean`] over its takes, the same interval. `None` for no value, rows of different
/// lengths or a non-finite value.
pub fn bootstrap_grid_mean(values: &[Vec<f64>], resamples: usize, seed: u64) -> Option<(f64, f64, f64)> {
    let n = values.first()?.len();
    if n == 0 || values.iter().any(|r| r.len() != n || r.iter().any(|v| !v.is_finite())) {
        return None;
    }
    if values.len() == 1 {
        return bootstrap_mean(&values[0], resamples, seed);
    }
    let runs = values.len();
    let mean = values.iter().flatten().sum::<f64>() / (runs * n) as f64;
    let mut rng = Rng::new(seed);
    let mut means: Vec<f64> = (0..resamples.max(1))
        .map(|_| {
            let takes: Vec<usize> = (0..n).map(|_| rng.below(n)).collect();
            let drawn: Vec<usize> = (0..runs).map(|_| rng.below(runs)).collect();
            drawn.iter().map(|&r| takes.iter().map(|&t| values[r][t]).sum::<f64>()).sum::<f64>() / (runs * n) as f64
        })
        .collect();
    means.sort_by(f64::total_cmp);
    let at = |q: f64| means[((q * (means.len() - 1) as f64).round() as usize).min(means.len() - 1)];
    Some((mean, at(0.025), at(0.975)))
}

/// `profile` convolved with a Gaussian of `sigma` samples (truncated at 3σ), over its defined
/// (non-`NaN`) values, each output renormalised by the weights present (so the ends and gaps
/// are not pulled towards 0); `NaN` where the profile is; unchanged for `sigma < 0.5`. Shared by
/// the hand-speed baseline and the LMA search.
pub fn gaussian_smooth(profile: &[f64], sigma: f64) -> Vec<f64> {
    if sigma < 0.5 {
        return profile.to_vec();
    }
    let half = (3.0 * sigma).ceil() as usize;
    let kernel: Vec<f64> = (0..=half).map(|k| (-0.5 * (k as f64 / sigma).powi(2)).exp()).collect();
    (0..profile.len())
        .map(|t| {
            if profile[t].is_nan() {
                return f64::NAN;
            }
            let (mut sum, mut weight) = (0.0, 0.0);
            for u in t.saturating_sub(half)..(t + half + 1).min(profile.len()) {
                if !profile[u].is_nan() {
                    let w = kernel[u.abs_diff(t)];
                    sum += w * profile[u];
                    weight += w;
                }
            }
            sum / weight
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn medians_of_even_odd_and_empty() {
        assert_eq!(median(&mut [3.0f64, 1.0, 2.0]), Some(2.0));
        assert_eq!(median(&mut [4usize, 1, 2, 3]), Some(3));
        assert_eq!(median::<f32>(&mut []), None);
        assert_eq!(median(&mut [f32::INFINITY, 0.5, 2.0]), Some(2.0));
        assert_eq!(median_midpoint(&mut [3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median_midpoint(&mut [4.0, 1.0, 2.0, 3.0]), Some(2.5));
        assert_eq!(median_midpoint(&mut []), None);
    }

    #[test]
    fn the_generator_is_deterministic_and_in_range() {
        let (mut a, mut b) = (Rng::new(7), Rng::new(7));
        for _ in 0..1000 {
            let x = a.next_f32();
            assert_eq!(x, b.next_f32());
            assert!((0.0..1.0).contains(&x));
            assert!(a.below(10) < 10 && b.below(10) < 10);
        }
        assert_eq!(Rng::new(1).below(0), 0);
        // the sequence the SSSM tests' noise was built on: (s >> 40) / 2^24 after one step
        let s = 5u64.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        assert_eq!(Rng::new(5).next_f32(), (s >> 40) as f32 / (1u64 << 24) as f32);
    }

    /// The interval holds the mean, lies within the values' range, is a point for equal values, and widens with the
    /// values' spread; the same seed gives the same interval.
    #[test]
    fn the_bootstrap_interval_brackets_the_mean_and_widens_with_spread() {
        let (m, lo, hi) = bootstrap_mean(&[0.5; 4], 2000, 1).unwrap();
        assert_eq!((m, lo, hi), (0.5, 0.5, 0.5));
        let tight = bootstrap_mean(&[0.80, 0.82, 0.84, 0.86], 2000, 1).unwrap();
        let wide = bootstrap_mean(&[0.55, 0.84, 0.90, 0.98], 2000, 1).unwrap();
        for (m, lo, hi) in [tight, wide] {
            assert!(lo <= m && m <= hi, "{lo} {m} {hi}");
        }
        assert!(tight.1 >= 0.80 && tight.2 <= 0.86);
        assert!(wide.2 - wide.1 > 2.0 * (tight.2 - tight.1), "{wide:?} {tight:?}");
        assert_eq!(bootstrap_mean(&[0.55, 0.84, 0.90, 0.98], 2000, 1), Some(wide));
        assert_eq!(bootstrap_mean(&[], 2000, 1), None);
        assert_eq!(bootstrap_mean(&[f64::NAN, 1.0], 2000, 1), None);
    }

    /// The two-way bootstrap: one run is the takes' bootstrap; runs that disagree widen the interval beyond what the
    /// takes' means alone give (the seed's luck counted), runs that agree do not; ragged or empty grids have none.
    #[test]
    fn a_grid_bootstrap_counts_the_runs_spread_beside_the_takes() {
        let takes = [0.80, 0.85, 0.90, 0.95];
        assert_eq!(bootstrap_grid_mean(&[takes.to_vec()], 2000, 1), bootstrap_mean(&takes, 2000, 1));
        let same = bootstrap_grid_mean(&[takes.to_vec(), takes.to_vec(), takes.to_vec()], 2000, 1).unwrap();
        // seeds 0.10 apart: the mean is the grid's, the interval wider than the per-take means' (which average the
        // seeds away)
        let apart: Vec<Vec<f64>> = [-0.05, 0.0, 0.05].iter().map(|d| takes.iter().map(|t| t + d).collect()).collect();
        let grid = bootstrap_grid_mean(&apart, 2000, 1).unwrap();
        let averaged = bootstrap_mean(&takes, 2000, 1).unwrap();
        assert!((grid.0 - 0.875).abs() < 1e-12 && (same.0 - 0.875).abs() < 1e-12);
        assert!(grid.2 - grid.1 > averaged.2 - averaged.1 + 0.01, "{grid:?} vs {averaged:?}");
        assert!((same.2 - same.1) <= (averaged.2 - averaged.1) + 0.01, "{same:?} vs {averaged:?}");
        assert_eq!(bootstrap_grid_mean(&[vec![0.5, 0.6], vec![0.5]], 2000, 1), None);
        assert_eq!(bootstrap_grid_mean(&[], 2000, 1), None);
    }
}
