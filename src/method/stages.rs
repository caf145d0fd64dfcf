//! Where a run's time goes: a [`Progress`] that notes when each stage a method reports began,
//! on a clock the caller gives (`Instant` natively, `performance.now()` in the browser), so that
//! the native benchmarks and the wasm ones profile a run the same way (`make bench`'s "where the
//! time goes" table, `examples/profile_methods.rs`).

use super::Progress;

/// A progress sink that records each stage's start in milliseconds on `clock` (a stage reported
/// again in a row is one stage; a stage met again later is summed with its first time).
pub struct Stages<C: FnMut() -> f64> {
    clock: C,
    start: f64,
    marks: Vec<(String, f64)>,
}

impl<C: FnMut() -> f64> Stages<C> {
    /// Starts timing now; `clock` returns milliseconds from any fixed origin.
    pub fn new(mut clock: C) -> Stages<C> {
        let start = clock();
        Stages { clock, start, marks: Vec::new() }
    }

    /// Milliseconds since [`Stages::new`].
    pub fn elapsed_ms(&mut self) -> f64 {
        (self.clock)() - self.start
    }

    /// Milliseconds per stage name for a run that took `total_ms`, in the order first met; the
    /// time before the first report is "(before the first report)" (only when there is some).
    pub fn durations(&self, total_ms: f64) -> Vec<(String, f64)> {
        let mut out: Vec<(String, f64)> = Vec::new();
        let mut add = |name: &str, ms: f64| match out.iter_mut().find(|(n, _)| n == name) {
            Some((_, t)) => *t += ms,
            None => out.push((name.to_string(), ms)),
        };
        let first = self.marks.first().map_or(total_ms, |m| m.1);
        if first > 0.0 || self.marks.is_empty() {
            add("(before the first report)", first);
        }
        for (i, (stage, at)) in self.marks.iter().enumerate() {
            let end = self.marks.get(i + 1).map_or(total_ms, |m| m.1);
            add(stage, end - at);
        }
        out
    }
}

impl<C: FnMut() -> f64> Progress for Stages<C> {
    fn report(&mut self, stage: &str, _fraction: f64) {
        if self.marks.last().is_none_or(|(s, _)| s != stage) {
            let at = self.elapsed_ms();
            self.marks.push((stage.to_string(), at));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cell::Cell;

    #[test]
    fn stages_are_timed_from_one_report_to_the_next_and_summed_by_name() {
        let now = Cell::new(100.0);
        let mut s = Stages::new(|| now.get());
        now.set(102.0);
        s.report("features", 0.1);
        now.set(105.0);
        s.report("features", 0.2); // the same stage again in a row: still one stage
        now.set(110.0);
        s.report("search", 0.5);
        now.set(111.0);
        s.report("features", 0.9); // met again later: summed with its first time
        now.set(120.0);
        let total = s.elapsed_ms();
        assert_eq!(total, 20.0);
        assert_eq!(
            s.durations(total),
            vec![
                ("(before the first report)".to_string(), 2.0),
                ("features".to_string(), 8.0 + 9.0),
                ("search".to_string(), 1.0),
            ]
        );
        let sum: f64 = s.durations(total).iter().map(|(_, t)| t).sum();
        assert_eq!(sum, total);
    }

    #[test]
    fn a_run_without_reports_is_one_unnamed_stage() {
        let now = Cell::new(0.0);
        let mut s = Stages::new(|| now.get());
        now.set(7.0);
        let total = s.elapsed_ms();
        assert_eq!(s.durations(total), vec![("(before the first report)".to_string(), 7.0)]);
    }
}
