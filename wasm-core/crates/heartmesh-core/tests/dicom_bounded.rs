//! The RTSTRUCT reader never allocates more than a small multiple of its input, whatever the
//! declared lengths say (the fuzz target found four files that made dicom-rs reserve gigabytes).
//! A counting allocator records the largest single request while hostile variants are read; this
//! binary holds this one test so that no other test allocates meanwhile.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use heartmesh_core::io::rtstruct::read_rtstruct;

struct Counting;

static LARGEST: AtomicUsize = AtomicUsize::new(0);

// SAFETY: forwards to the system allocator unchanged; only records the request size.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        LARGEST.fetch_max(layout.size(), Ordering::Relaxed);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        LARGEST.fetch_max(layout.size(), Ordering::Relaxed);
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        LARGEST.fetch_max(new_size, Ordering::Relaxed);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static ALLOC: Counting = Counting;

/// Largest single allocation while reading `bytes` (the result itself is not the point).
fn largest_allocation(bytes: &[u8]) -> usize {
    LARGEST.store(0, Ordering::Relaxed);
    let _ = std::hint::black_box(read_rtstruct(bytes));
    LARGEST.load(Ordering::Relaxed)
}

#[test]
fn hostile_lengths_never_allocate_beyond_the_input() {
    let root = env!("CARGO_MANIFEST_DIR");
    let mut files: Vec<Vec<u8>> = Vec::new();
    for e in std::fs::read_dir(format!("{root}/../../fuzz/regressions")).unwrap() {
        files.push(std::fs::read(e.unwrap().path()).unwrap());
    }
    assert_eq!(files.len(), 4);
    let sample = std::fs::read(format!("{root}/tests/data/patient1-ED-rtstruct.dcm")).unwrap();
    // The sample reads (1791 points); its allocations are the baseline.
    let base = largest_allocation(&sample);
    assert!(read_rtstruct(&sample).unwrap().point_count() == 1791);
    let limit = 4 * sample.len() + (1 << 16);
    assert!(base <= limit, "sample: {base} bytes at once");
    // Every regression file as it is, then every 4 bytes of the first 3 KB of each file
    // (regressions and sample) overwritten with a huge length, in both byte orders.
    let mut worst = 0;
    let mut variants = 0;
    files.push(sample);
    for f in &files {
        worst = worst.max(largest_allocation(f));
        for at in (0..f.len().min(3000).saturating_sub(4)).step_by(2) {
            for huge in [0xFFFF_FFF0u32.to_le_bytes(), 0x7FFF_FFF0u32.to_be_bytes()] {
                let mut g = f.clone();
                g[at..at + 4].copy_from_slice(&huge);
                worst = worst.max(largest_allocation(&g));
                variants += 1;
            }
        }
    }
    assert!(variants > 9_000, "{variants}");
    assert!(
        worst <= limit,
        "{worst} bytes allocated at once (limit {limit})"
    );
}
