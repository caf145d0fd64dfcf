//! The boundary search on the deviance map (Bouchard & Badler §4.2, Figs. 5–6): "the frames that
//! correspond to dark vertical bands … are found by summing all rows and columns and searching for
//! local minima … The locations of the troughs are found by smoothing the sums and searching for
//! local minima. Redundant local minima are culled by removing those that are not followed by a
//! change in the deviation sum that exceeds [a] threshold … A segmentation is produced by matching
//! each start boundary local minimum with the closest subsequent end boundary local minimum";
//! then the two arms' segmentations are merged, "replacing segments that have similar boundaries
//! with the average of the two segments".
//!
//! Two readings of the paper's words: a row's (column's) *mean* stands for its sum, because rows
//! near the take's ends and, in the pruned search, rows of different boundaries hold different
//! numbers of candidates; and the culling threshold is a share of the profile's own spread
//! (its 10th to 90th percentile), since deviance units depend on the classifiers.

pub use crate::stats::gaussian_smooth as smooth;

/// Mean deviance of candidate segments `start..=end`, `min_len ≤ end − start ≤ max_len` frames:
/// one row per start frame; `None` where a candidate was not computed (the pruned search).
#[derive(Debug, Clone, PartialEq)]
pub struct DevianceMap {
    pub frames: usize,
    pub min_len: usize,
    pub max_len: usize,
    values: Vec<f32>,
}

impl DevianceMap {
    /// A map of `frames` frames with nothing computed yet.
    pub fn new(frames: usize, min_len: usize, max_len: usize) -> DevianceMap {
        let max_len = max_len.max(min_len);
        DevianceMap { frames, min_len, max_len, values: vec![f32::NAN; frames * (max_len - min_len + 1)] }
    }

    fn index(&self, start: usize, end: usize) -> Option<usize> {
        let len = end.checked_sub(start)?;
        (start < self.frames && end < self.frames && (self.min_len..=self.max_len).contains(&len))
            .then(|| start * (self.max_len - self.min_len + 1) + len - self.min_len)
    }

    /// Sets the deviance of `start..=end` (ignored outside the map).
    pub fn set(&mut self, start: usize, end: usize, deviance: f32) {
        if let Some(i) = self.index(start, end) {
            self.values[i] = deviance;
        }
    }

    /// The deviance of `start..=end`, if computed.
    pub fn get(&self, start: usize, end: usize) -> Option<f32> {
        self.index(start, end).map(|i| self.values[i]).filter(|v| !v.is_nan())
    }

    /// Every computed candidate `(start, end, deviance)`.
    pub fn candidates(&self) -> impl Iterator<Item = (usize, usize, f32)> + '_ {
        let width = self.max_len - self.min_len + 1;
        self.values
            .iter()
            .enumerate()
            .filter(|(_, v)| !v.is_nan())
            .map(move |(i, &v)| (i / width, i / width + self.min_len + i % width, v))
    }

    /// Per start frame the mean deviance of its row, per end frame of its column (`NaN` where
    /// nothing was computed): the plots on the top and right of the paper's Fig. 5 — each taken
    /// after removing the other's means (a row's profile averages `d(s, e) − column mean(e)`, a
    /// column's `d(s, e) − row mean(s)`), so a few rows of high deviance (a T-pose, a jump at
    /// the take's start) do not lift every column they cross into a false slope.
    pub fn profiles(&self) -> (Vec<f64>, Vec<f64>) {
        let means = |centre: &[Vec<f64>; 2]| {
            let mut sums = [vec![0.0; self.frames], vec![0.0; self.frames]];
            let mut counts = [vec![0usize; self.frames], vec![0usize; self.frames]];
            for (start, end, v) in self.candidates() {
                for (k, (t, other)) in [(start, end), (end, start)].into_iter().enumerate() {
                    sums[k][t] += v as f64 - centre[1 - k][other];
                    counts[k][t] += 1;
                }
            }
            [0, 1].map(|k| {
                sums[k].iter().zip(&counts[k]).map(|(&s, &c)| if c > 0 { s / c as f64 } else { f64::NAN }).collect()
            })
        };
        let raw: [Vec<f64>; 2] = means(&[vec![0.0; self.frames], vec![0.0; self.frames]]);
        let [rows, cols] = means(&raw);
        (rows, cols)
    }
}

/// The troughs of `profile` (ignoring `NaN`s): local minima of its defined values, each kept only
/// when the profile rises by more than `min_rise` × its spread (10th to 90th percentile) after it,
/// before the next minimum.
pub fn troughs(profile: &[f64], min_rise: f64) -> Vec<usize> {
    let defined: Vec<usize> = (0..profile.len()).filter(|&t| !profile[t].is_nan()).collect();
    let mut sorted: Vec<f64> = defined.iter().map(|&t| profile[t]).collect();
    if sorted.len() < 3 {
        return Vec::new();
    }
    sorted.sort_by(f64::total_cmp);
    let at = |q: f64| sorted[((sorted.len() - 1) as f64 * q).round() as usize];
    let threshold = min_rise * (at(0.9) - at(0.1));
    let value = |k: usize| profile[defined[k]];
    // local minima among the defined values (plateaus: their first frame)
    let minima: Vec<usize> =
        (1..defined.len() - 1).filter(|&k| value(k) <= value(k - 1) && value(k) < value(k + 1)).collect();
    minima
        .iter()
        .enumerate()
        .filter(|&(m, &k)| {
            let next = minima.get(m + 1).copied().unwrap_or(defined.len() - 1);
            let peak = (k..=next).map(value).fold(f64::MIN, f64::max);
            peak - value(k) > threshold
        })
        .map(|(_, &k)| defined[k])
        .collect()
}

/// Each start matched with the closest end after it at least `min_len` and at most `max_len`
/// frames later (a start with none is dropped).
pub fn pair(starts: &[usize], ends: &[usize], min_len: usize, max_len: usize) -> Vec<(usize, usize)> {
    let mut ends = ends.to_vec();
    ends.sort_unstable();
    starts
        .iter()
        .filter_map(|&s| {
            let k = ends.partition_point(|&e| e < s + min_len);
            ends.get(k).filter(|&&e| e - s <= max_len).map(|&e| (s, e))
        })
        .collect()
}

/// Two arms' segments merged: a segment of `a` whose start and end both lie within `within`
/// frames of a segment of `b` (the closest such) becomes their average, marked `both`; the rest
/// are kept with their arm (`false` = a, `true` = b). Sorted by start, duplicates dropped.
pub fn merge_arms(a: &[(usize, usize)], b: &[(usize, usize)], within: usize) -> Vec<(usize, usize, Arms)> {
    let mut used = vec![false; b.len()];
    let mut out = Vec::new();
    for &(s, e) in a {
        let close = (0..b.len())
            .filter(|&k| !used[k] && b[k].0.abs_diff(s) <= within && b[k].1.abs_diff(e) <= within)
            .min_by_key(|&k| b[k].0.abs_diff(s) + b[k].1.abs_diff(e));
        match close {
            Some(k) => {
                used[k] = true;
                out.push(((s + b[k].0).div_ceil(2), (e + b[k].1) / 2, Arms::Both));
            }
            None => out.push((s, e, Arms::First)),
        }
    }
    out.extend(b.iter().zip(&used).filter(|(_, &u)| !u).map(|(&(s, e), _)| (s, e, Arms::Second)));
    out.sort_by_key(|&(s, e, _)| (s, e));
    out.dedup_by_key(|&mut (s, e, _)| (s, e));
    out
}

/// Which arm's segmentation a merged segment came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Arms {
    First,
    Second,
    Both,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A map whose deviance falls (additively) for segments that start near one of `starts` and end near one of `ends`.
    fn synthetic(frames: usize, starts: &[usize], ends: &[usize]) -> DevianceMap {
        let mut map = DevianceMap::new(frames, 20, 100);
        let near = |t: usize, set: &[usize]| set.iter().map(|&b| b.abs_diff(t)).min().unwrap_or(99).min(10) as f32;
        for s in 0..frames {
            for e in s + 20..=(s + 100).min(frames - 1) {
                map.set(s, e, 0.1 * (near(s, starts) + near(e, ends)));
            }
        }
        map
    }

    #[test]
    fn the_map_keeps_only_candidates_of_the_allowed_lengths() {
        let mut map = DevianceMap::new(200, 20, 100);
        map.set(10, 40, 0.5);
        map.set(10, 25, 0.7); // too short
        map.set(10, 150, 0.7); // too long
        map.set(190, 230, 0.7); // past the end
        assert_eq!(map.get(10, 40), Some(0.5));
        assert_eq!(map.get(10, 25), None);
        assert_eq!(map.get(11, 40), None);
        assert_eq!(map.candidates().collect::<Vec<_>>(), vec![(10, 40, 0.5)]);
        // one candidate: its row and its column each hold it alone, so centred they are 0
        let (rows, cols) = map.profiles();
        assert_eq!(rows[10], 0.0);
        assert_eq!(cols[40], 0.0);
        assert!(rows[11].is_nan() && cols[39].is_nan());
    }

    #[test]
    fn the_search_finds_the_segments_of_a_synthetic_map() {
        let (starts, ends) = ([30, 120, 230], [90, 200, 300]);
        let map = synthetic(400, &starts, &ends);
        let (rows, cols) = map.profiles();
        let s = troughs(&smooth(&rows, 2.0), 0.1);
        let e = troughs(&smooth(&cols, 2.0), 0.1);
        // within a frame (a column near the take's start holds fewer candidates than its neighbour)
        let within_one = |found: &[usize], truth: &[usize]| {
            found.len() == truth.len() && found.iter().zip(truth).all(|(f, t)| f.abs_diff(*t) <= 1)
        };
        assert!(within_one(&s, &starts), "{s:?}");
        assert!(within_one(&e, &ends), "{e:?}");
        let pairs = pair(&s, &e, 20, 100);
        assert_eq!(pairs.len(), 3);
        assert!(within_one(&pairs.iter().map(|p| p.1).collect::<Vec<_>>(), &ends), "{pairs:?}");
    }

    #[test]
    fn shallow_minima_are_culled() {
        // two deep troughs at 20 and 80, a ripple at 50 that rises by 0.01 only
        let mut p: Vec<f64> = (0..100).map(|t| 1.0 - (-((t as f64 - 20.0) / 6.0).powi(2)).exp()).collect();
        for (t, v) in p.iter_mut().enumerate() {
            *v -= (-((t as f64 - 80.0) / 6.0).powi(2)).exp();
            *v += if t == 50 { -0.01 } else { 0.0 };
        }
        assert_eq!(troughs(&p, 0.0), vec![20, 50, 80]);
        assert_eq!(troughs(&p, 0.05), vec![20, 80]);
        // the last trough is followed by no rise inside the profile: kept only without a threshold
        assert_eq!(troughs(&[1.0, 2.0, 1.0, 3.0, 0.5, 0.6, 0.7], 0.0), vec![2, 4]);
        assert!(troughs(&[f64::NAN, 1.0], 0.0).is_empty());
    }

    #[test]
    fn smoothing_skips_missing_values() {
        let p = [f64::NAN, 1.0, f64::NAN, 3.0, f64::NAN];
        let s = smooth(&p, 1.0);
        assert!(s[0].is_nan() && s[2].is_nan());
        assert!(s[1] > 1.0 && s[1] < 2.0 && s[3] > 2.0 && s[3] < 3.0, "{s:?}");
    }

    #[test]
    fn starts_pair_with_the_closest_end_long_enough() {
        // 50's closest end far enough (200) is too far
        assert_eq!(pair(&[0, 50], &[10, 30, 60, 200], 20, 100), vec![(0, 30)]);
        assert_eq!(pair(&[0, 40], &[10, 30, 60, 200], 20, 100), vec![(0, 30), (40, 60)]);
        assert_eq!(pair(&[0], &[150], 20, 100), vec![]);
    }

    #[test]
    fn arms_merge_where_both_boundaries_are_close() {
        let left = [(10, 50), (100, 160)];
        let right = [(14, 46), (300, 350)];
        let merged = merge_arms(&left, &right, 5);
        assert_eq!(merged, vec![(12, 48, Arms::Both), (100, 160, Arms::First), (300, 350, Arms::Second)]);
        // too far apart: both kept
        assert_eq!(merge_arms(&[(10, 50)], &[(10, 60)], 5).len(), 2);
    }
}
