//! A steady scene's step allocates nothing (issue 14): every buffer of the step is kept from
//! one step to the next. Counted by a global allocator of this test binary.

// A global allocator is an `unsafe impl`; this one only counts and forwards to the system's.
#![allow(unsafe_code)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use tumble_tests::{all_finite, run, world};

/// Allocations (and reallocations) made by any thread of this process.
static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

struct Counting;

// SAFETY: every call is forwarded unchanged to the system allocator.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        // SAFETY: the caller's contract is the system allocator's.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: as above.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        // SAFETY: as above.
        unsafe { System.realloc(ptr, layout, size) }
    }
}

#[global_allocator]
static COUNTING: Counting = Counting;

#[test]
fn a_resting_pyramid_steps_without_allocating_on_one_thread() {
    // The 20-row pyramid has settled by step 300 (its contacts are recycled and its touching
    // pairs repeat, so the colouring is kept). Before this test existed its step allocated
    // 20 times (the touching list's parallel gather, the solver's stage plan, the core count
    // read from the cgroup files each step): 2,000 in 100 steps. What is left is rayon's: the
    // step runs in the world's pool (`ThreadPool::install` from outside it), whose job queue
    // takes a new block every 63 jobs, so 100 steps may allocate twice. One allocation more
    // per step makes 100 or more.
    let scene = tumble_scene::builtin::build("pyramid").expect("pyramid");
    let mut w = world(&scene);
    w.set_thread_count(1);
    run(&mut w, &scene, 300);
    let before = ALLOCATIONS.load(Ordering::Relaxed);
    run(&mut w, &scene, 100);
    let allocations = ALLOCATIONS.load(Ordering::Relaxed) - before;
    assert!(all_finite(&w), "pyramid: non-finite state");
    assert!(
        allocations <= 2,
        "100 steps of a resting pyramid allocated {allocations} times; at most 2 (rayon's queue)"
    );
}
