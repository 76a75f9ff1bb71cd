//! Heap measurement: a global allocator that counts live bytes, so the bench can report each
//! case's peak and tests can hold the memory budget's estimates ([`crate::memory`]) to the real
//! peak. Binaries install it (`#[global_allocator]`); the library and the Python module do not.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// Runs `work` once and returns its result with its peak heap growth, when the tracking
/// allocator is installed (for tests that compare a memory estimate with the real peak).
pub fn peak_heap<T>(work: impl FnOnce() -> T) -> (T, Option<usize>) {
    let base = CURRENT.load(Ordering::Relaxed);
    PEAK.store(base, Ordering::Relaxed);
    let out = work();
    let peak = TRACKING
        .load(Ordering::Relaxed)
        .then(|| PEAK.load(Ordering::Relaxed).saturating_sub(base));
    (out, peak)
}

static TRACKING: AtomicBool = AtomicBool::new(false);
static CURRENT: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

/// A global allocator that counts live heap bytes, so a run can report its peak.
pub struct TrackingAllocator;

// SAFETY: forwards every call to the system allocator unchanged; only counts sizes.
unsafe impl GlobalAlloc for TrackingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: same contract as the caller's.
        let ptr = unsafe { System.alloc(layout) };
        if !ptr.is_null() {
            grew(layout.size());
        }
        ptr
    }

    // Forwarded too, rather than left to the trait's defaults: `alloc_zeroed` would write every
    // byte of a large zeroed buffer up front (the system's calloc maps fresh zero pages, touched
    // only when used) and `realloc` would always copy, so the bench would time other work than
    // the library does without the tracker.
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        // SAFETY: same contract as the caller's.
        let ptr = unsafe { System.alloc_zeroed(layout) };
        if !ptr.is_null() {
            grew(layout.size());
        }
        ptr
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: same contract as the caller's.
        let moved = unsafe { System.realloc(ptr, layout, new_size) };
        if !moved.is_null() {
            if new_size >= layout.size() {
                grew(new_size - layout.size());
            } else {
                CURRENT.fetch_sub(layout.size() - new_size, Ordering::Relaxed);
            }
        }
        moved
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: same contract as the caller's.
        unsafe { System.dealloc(ptr, layout) };
        CURRENT.fetch_sub(layout.size(), Ordering::Relaxed);
    }
}

/// Counts `bytes` more live heap and raises the peak.
fn grew(bytes: usize) {
    let now = CURRENT.fetch_add(bytes, Ordering::Relaxed) + bytes;
    PEAK.fetch_max(now, Ordering::Relaxed);
}

impl TrackingAllocator {
    /// Tells [`peak_heap`] that the allocator is installed (call once from `main`).
    pub fn enable() {
        TRACKING.store(true, Ordering::Relaxed);
    }
}
