//! Running two independent pieces of work at once where the platform has threads.
//!
//! Natively [`join`] runs its second closure on a scoped thread while the first runs on the
//! calling thread (the CLI segments a take on two cores). In wasm, where the page already runs
//! the method in a web worker and threads would need cross-origin isolation, it runs them one
//! after the other. Either way the results are the same.

/// Runs `a` and `b` (concurrently natively: `a` on the calling thread, so it may hold
/// non-`Send` state such as a progress callback) and returns both results.
#[cfg(not(target_arch = "wasm32"))]
pub fn join<A, B: Send>(a: impl FnOnce() -> A, b: impl FnOnce() -> B + Send) -> (A, B) {
    std::thread::scope(|scope| {
        let other = scope.spawn(b);
        let first = a();
        match other.join() {
            Ok(second) => (first, second),
            Err(panic) => std::panic::resume_unwind(panic),
        }
    })
}

/// Runs `a` then `b` and returns both results.
#[cfg(target_arch = "wasm32")]
pub fn join<A, B>(a: impl FnOnce() -> A, b: impl FnOnce() -> B) -> (A, B) {
    let first = a();
    (first, b())
}

#[cfg(test)]
mod tests {
    #[test]
    fn both_results_come_back_in_order() {
        let data = [1, 2, 3];
        let (sum, len) = super::join(|| data.iter().sum::<i32>(), || data.len());
        assert_eq!((sum, len), (6, 3));
    }
}
