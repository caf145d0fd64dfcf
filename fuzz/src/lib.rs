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

use std::alloc::{GlobalAlloc, Layout, System};
use std::io::Write as _;
use std::path::{Path, PathBuf};

mod seeds;
pub mod targets;
pub use seeds::*;
use std::sync::atomic::{AtomicUsize, Ordering};


/// The system allocator with the budget above.
pub struct Budgeted;

static LIVE: AtomicUsize = AtomicUsize::new(0);
/// Bytes; `usize::MAX` until [`init`] reads the budget.
static LIMIT: AtomicUsize = AtomicUsize::new(usize::MAX);

#[cold]
fn over_budget(kind: &str, bytes: usize) -> ! {
    // No allocation here: stderr is unbuffered and the texts are static.
    let mut e = std::io::stderr().lock();
    let _ = e.write_all(b"\n==mocapseg-fuzz== allocation budget exceeded: ");
    let _ = e.write_all(kind.as_bytes());
    let _ = e.write_all(b" of ");
    let mut digits = [0u8; 20];
    let mut n = bytes;
    let mut at = digits.len();
    loop {
        at -= 1;
        digits[at] = b'0' + (n % 10) as u8;
        n /= 10;
        if n == 0 {
            break;
        }
    }
    let _ = e.write_all(&digits[at..]);
    let _ = e.write_all(b" bytes (MOCAPSEG_FUZZ_MALLOC_MB)\n");
    std::process::abort()
}

#[inline]
fn grow(by: usize) {
    let limit = LIMIT.load(Ordering::Relaxed);
    if by > limit {
        over_budget("one allocation", by);
    }
    let now = LIVE.fetch_add(by, Ordering::Relaxed) + by;
    if now > limit {
        over_budget("live heap", now);
    }
}

unsafe impl GlobalAlloc for Budgeted {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        grow(layout.size());
        unsafe { System.alloc(layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        grow(layout.size());
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) };
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if new_size > layout.size() {
            grow(new_size - layout.size());
        } else {
            LIVE.fetch_sub(layout.size() - new_size, Ordering::Relaxed);
        }
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static ALLOCATOR: Budgeted = Budgeted;

/// The budget in bytes from `MOCAPSEG_FUZZ_MALLOC_MB` (default 256 MiB).
fn budget_from_env() -> usize {
    let mb = std::env::var("MOCAPSEG_FUZZ_MALLOC_MB").ok().and_then(|v| v.parse::<usize>().ok()).unwrap_or(256);
    mb.saturating_mul(1 << 20)
}

/// Every target's init: sets the allocation budget, and writes the target's seeds (`seeds()`,
/// `(name, bytes)`) into `MOCAPSEG_FUZZ_SEED_DIR` when that is set.
pub fn init(seeds: impl FnOnce() -> Vec<(String, Vec<u8>)>) {
    LIMIT.store(budget_from_env(), Ordering::Relaxed);
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
