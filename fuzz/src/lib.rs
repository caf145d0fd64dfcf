//! The fuzz targets (`targets`, one module each) and what they share: the allocation budget, seed writing
//! and small fixture takes (`seeds.rs`).
//!
//! **Allocation budget.** `scripts/fuzz.sh` runs the targets with `--sanitizer none` (Rust code
//! is memory-safe; the sanitizers would cost throughput and find nothing safe Rust can do), and
//! libFuzzer's `-malloc_limit_mb` needs a sanitizer's malloc hooks to act. So the budget is kept
//! here: a global allocator that aborts — a crash libFuzzer saves as an artifact — when one
//! allocation, or the bytes allocated at once, pass `MOCAPSEG_FUZZ_MALLOC_MB` (the script passes
//! the same number it gives libFuzzer; 256 when unset). `-rss_limit_mb` still watches the process.
//!
//! **Seeds.** With `MOCAPSEG_FUZZ_SEED_DIR` set, a target's init writes its seeds there (made
//! from `tests/fixtures` and `models/` with the crate's own reader and writer, so they are small
//! and valid) and the script then runs it on that corpus.

use std::path::{Path, PathBuf};

mod seeds;
pub mod targets;
pub use seeds::*;


#[global_allocator]
static ALLOCATOR: Budgeted = Budgeted;

mod budget;
pub use budget::Budgeted;

/// The budget in bytes from `MOCAPSEG_FUZZ_MALLOC_MB` (default 256 MiB).
fn budget_from_env() -> usize {
    let mb = std::env::var("MOCAPSEG_FUZZ_MALLOC_MB").ok().and_then(|v| v.parse::<usize>().ok()).unwrap_or(256);
    mb.saturating_mul(1 << 20)
}

/// Every target's init: sets the allocation budget, and writes the target's seeds (`seeds()`,
/// `(name, bytes)`) into `MOCAPSEG_FUZZ_SEED_DIR` when that is set.
pub fn init(seeds: impl FnOnce() -> Vec<(String, Vec<u8>)>) {
    budget::set_limit(budget_from_env());
    if let Some(dir) = std::env::var_os("MOCAPSEG_FUZZ_SEED_DIR") {
        let dir = PathBuf::from(dir);
        std::fs::create_dir_all(&dir).expect("the seed folder");
        let seeds = seeds();
        for (name, bytes) in &seeds {
            std::fs::write(dir.join(name), bytes).expect("writing a seed");
        }
        eprintln!("mocapseg-fuzz: wrote {} seeds to {}", seeds.len(), dir.display());
    }
}

/// The repository's root (the fuzz crate sits in `fuzz/`).
pub fn repo() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}
