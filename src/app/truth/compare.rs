//! The metrics panel's comparison table: which line is best in each column, and the order of the
//! lines when a column is sorted. Kept out of the web layer so it is tested natively.
//!
//! A column is compared on the values *as shown* (rounded to the column's decimals), so two lines
//! that read the same are both marked best rather than one of them by a difference nobody sees.
//! Lines that are not candidates (a reference such as a chance row, or a line whose scoring failed)
//! are never marked; a value that is not a number is never best.

use std::cmp::Ordering;

/// Which way a column improves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Better {
    Higher,
    Lower,
}

/// `value` rounded to `digits` decimals the way the table prints it (`format!("{:.*}")`).
pub fn as_shown(value: f64, digits: usize) -> f64 {
    format!("{value:.digits$}").parse().unwrap_or(f64::NAN)
}

/// For one column: whether each line holds the best value. `values[i]` is `None` for a line
/// that is not a candidate; ties (as shown) are all best; no line is best when none is a number.
pub fn best_in_column(values: &[Option<f64>], digits: usize, better: Better) -> Vec<bool> {
    let shown: Vec<Option<f64>> =
        values.iter().map(|v| v.map(|v| as_shown(v, digits)).filter(|v| v.is_finite())).collect();
    let best = shown.iter().flatten().copied().reduce(|a, b| match better {
        Better::Higher => a.max(b),
        Better::Lower => a.min(b),
    });
    shown.iter().map(|v| best.is_some() && *v == best).collect()
}

/// The order in which to show lines sorted on one column: best first when `best_first`, else
/// worst first; lines without a number (`None` or NaN) last either way; equal values keep their
/// original order (the sort is stable).
pub fn sorted_order(values: &[Option<f64>], better: Better, best_first: bool) -> Vec<usize> {
    let mut order: Vec<usize> = (0..values.len()).collect();
    let key = |i: usize| values[i].filter(|v| !v.is_nan());
    order.sort_by(|&a, &b| match (key(a), key(b)) {
        (Some(x), Some(y)) => {
            let ascending = x.partial_cmp(&y).unwrap_or(Ordering::Equal);
            let higher_first = ascending.reverse();
            match (better, best_first) {
                (Better::Higher, true) | (Better::Lower, false) => higher_first,
                (Better::Higher, false) | (Better::Lower, true) => ascending,
            }
        }
        (Some(_), None) => Ordering::Less,
        (None, Some(_)) => Ordering::Greater,
        (None, None) => Ordering::Equal,
    });
    order
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_highest_is_best_and_ties_as_shown_are_all_best() {
        let v = [Some(0.5), Some(0.8333), Some(0.83321), Some(0.2)];
        // 0.8333 and 0.83321 both read 0.833
        assert_eq!(best_in_column(&v, 3, Better::Higher), [false, true, true, false]);
        // at four decimals they differ
        assert_eq!(best_in_column(&v, 4, Better::Higher), [false, true, false, false]);
    }

    #[test]
    fn the_lowest_is_best_where_lower_is_better() {
        let v = [Some(3.0), Some(-1.5), Some(2.0)];
        assert_eq!(best_in_column(&v, 1, Better::Lower), [false, true, false]);
        assert_eq!(best_in_column(&v, 1, Better::Higher), [true, false, false]);
    }

    #[test]
    fn lines_that_are_not_candidates_or_not_numbers_are_never_best() {
        // the first line (say a chance row) has the highest value but is not a candidate
        let v = [None, Some(0.4), Some(f64::NAN), Some(0.6)];
        assert_eq!(best_in_column(&v, 2, Better::Higher), [false, false, false, true]);
        assert_eq!(best_in_column(&[None, Some(f64::NAN)], 2, Better::Higher), [false, false]);
        assert_eq!(best_in_column(&[], 2, Better::Higher), Vec::<bool>::new());
        // negative values (a segment score) compare as numbers
        assert_eq!(best_in_column(&[Some(-7.5), Some(-2.0)], 1, Better::Higher), [false, true]);
    }

    #[test]
    fn sorting_puts_the_best_first_or_last_and_non_numbers_last() {
        let v = [Some(0.2), None, Some(0.9), Some(0.5), Some(f64::NAN), Some(0.5)];
        assert_eq!(sorted_order(&v, Better::Higher, true), [2, 3, 5, 0, 1, 4]);
        assert_eq!(sorted_order(&v, Better::Higher, false), [0, 3, 5, 2, 1, 4]);
        assert_eq!(sorted_order(&v, Better::Lower, true), [0, 3, 5, 2, 1, 4]);
        assert_eq!(sorted_order(&v, Better::Lower, false), [2, 3, 5, 0, 1, 4]);
    }

    #[test]
    fn as_shown_rounds_as_the_table_prints() {
        assert_eq!(as_shown(0.8336, 3), 0.834);
        assert_eq!(as_shown(-2.04, 1), -2.0);
        assert_eq!(as_shown(100.0, 2), 100.0);
        assert!(as_shown(f64::NAN, 2).is_nan());
    }
}
