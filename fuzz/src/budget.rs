//! The fuzz targets' allocation budget (see `lib.rs`): a global allocator that aborts when one allocation, or the
//! bytes allocated at once, pass the limit set by [`set_limit`] (none until then). Its own file so that the main
//! crate's `tests/fuzz_targets.rs` runs the targets under it too.

use std::alloc::{GlobalAlloc, Layout, System};
use std::io::Write as _;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Sets the budget, in bytes.
pub fn set_limit(bytes: usize) {
    LIMIT.store(bytes, Ordering::Relaxed);
}

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
