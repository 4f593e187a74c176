//! Peak heap use, counted by a global allocator. Its own test binary, with
//! one test, so the count sees no other test's allocations.

use refract::scenes::{build, SceneKind, SceneOptions};
use refract::spectral::exact::{self, ExactOptions};
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};

/// The system allocator, counting the bytes held now and at the most.
struct Counting;

static NOW: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

// SAFETY: every call is passed on to the system allocator unchanged; the
// counters only add and subtract the sizes asked for.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: the caller's contract is the system allocator's.
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            PEAK.fetch_max(NOW.fetch_add(layout.size(), Relaxed) + layout.size(), Relaxed);
        }
        p
    }

    unsafe fn dealloc(&self, p: *mut u8, layout: Layout) {
        // SAFETY: the caller's contract is the system allocator's.
        unsafe { System.dealloc(p, layout) };
        NOW.fetch_sub(layout.size(), Relaxed);
    }
}

#[global_allocator]
static COUNTING: Counting = Counting;

/// The exact image sums its 64 chunks of wavelengths as many at a time as
/// there are threads: its peak is a few images (the corners' screen
/// points, the sum, one partial a thread), not one image a chunk (it once
/// held all 64: 24 GB at 4096x4096).
#[test]
fn the_exact_image_holds_a_partial_image_a_thread_not_one_a_chunk() {
    let mut o = SceneOptions::new(SceneKind::SinglePrism);
    (o.width, o.height) = (512, 512);
    let scene = build(&o).unwrap();
    let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
    let image = 512 * 512 * std::mem::size_of::<glam::DVec3>();
    let (start, peak) = pool.install(|| {
        let start = NOW.load(Relaxed);
        PEAK.store(start, Relaxed);
        let img = exact::render(&scene, &ExactOptions { wavelengths: 256, ..Default::default() }).unwrap();
        assert!(img.xyz.iter().any(|p| p.y > 0.0), "the strip reaches the screen");
        (start, PEAK.load(Relaxed))
    });
    let held = peak - start;
    assert!(held < 8 * image, "the exact image held {held} bytes at its peak: {:.1} images of 512x512", held as f64 / image as f64);
}
