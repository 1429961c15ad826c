//! A steady scene's step allocates nothing (issue 14): every buffer of the step is kept from
//! one step to the next. Counted by a global allocator of this test binary.

// A global allocator is an `unsafe impl`; this one only counts and forwards to the system's.
#![allow(unsafe_code)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use tumble_physics::WideThresholds;
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

/// The count is the process's: the tests of this binary take turns, each holding its turn
/// until it has asserted (a failing test's panic message allocates too).
fn turn() -> std::sync::MutexGuard<'static, ()> {
    static SERIAL: std::sync::Mutex<()> = std::sync::Mutex::new(());
    SERIAL.lock().unwrap_or_else(|e| e.into_inner())
}

/// Allocations in 100 steps of `scene` on `threads` threads after `settle` steps, with the
/// stage thresholds `wide`; and whether every one of those steps ran inline.
fn allocations_in_100_steps(
    name: &str,
    settle: u32,
    threads: usize,
    wide: WideThresholds,
) -> (usize, bool) {
    let (allocations, inline, _) = allocations_in_steps(name, settle, 100, threads, wide);
    (allocations, inline)
}

/// Allocations in `steps` steps of `scene` after `settle`, whether every one of those steps
/// ran inline, and whether any solved on one worker and any on several (`[one, several]`).
fn allocations_in_steps(
    name: &str,
    settle: u32,
    steps: u32,
    threads: usize,
    wide: WideThresholds,
) -> (usize, bool, [bool; 2]) {
    let scene = tumble_scene::builtin::build(name).expect(name);
    let mut w = world(&scene);
    w.set_thread_count(threads);
    w.set_wide_thresholds(wide);
    run(&mut w, &scene, settle);
    let before = ALLOCATIONS.load(Ordering::Relaxed);
    let mut inline = true;
    let mut solved_on = [false; 2];
    for _ in 0..steps {
        w.step(scene.dt, scene.substeps);
        inline &= w.profile().inline;
        solved_on[usize::from(w.profile().solver_workers > 1)] = true;
    }
    let allocations = ALLOCATIONS.load(Ordering::Relaxed) - before;
    assert!(all_finite(&w), "{name}: non-finite state");
    (allocations, inline, solved_on)
}

#[test]
fn a_resting_pyramid_steps_without_allocating_on_one_thread() {
    // The 20-row pyramid has settled by step 300 (its contacts are recycled and its touching
    // pairs repeat, so the colouring is kept). Before issue 14 its step allocated 20 times
    // (the touching list's parallel gather, the solver's stage plan, the core count read from
    // the cgroup files), then twice in 100 steps (rayon's job queue: a step ran in a pool of
    // one thread). On one thread a step now runs inline and must not allocate at all.
    let _turn = turn();
    let (allocations, inline) =
        allocations_in_100_steps("pyramid", 300, 1, WideThresholds::default());
    assert!(inline, "a one-thread step ran in a pool");
    assert_eq!(allocations, 0, "100 steps of a resting pyramid allocated");
}

#[test]
fn a_small_scene_on_two_threads_runs_inline_without_allocating() {
    // The 20-row pyramid's stages are all below their default thresholds (210 bodies, about
    // 400 touching contacts): on two threads it runs inline, as on one.
    let _turn = turn();
    let (allocations, inline) =
        allocations_in_100_steps("pyramid", 300, 2, WideThresholds::default());
    assert!(inline, "the small pyramid woke the pool");
    assert_eq!(allocations, 0, "100 inline steps allocated");
}

#[test]
fn a_wide_step_allocates_nothing() {
    // Every stage split over two workers: the caller's thread and a follower of the world's
    // crew. Publishing a stage, its parts (kept on the caller's stack) and the stage board
    // allocate nothing. (Before the crew, the step went through rayon's job queue, which took
    // a new block every 63 steps: 2 in 100.)
    let _turn = turn();
    let (allocations, inline) = allocations_in_100_steps("pyramid", 300, 2, WideThresholds::ALWAYS);
    assert!(!inline, "no step went wide");
    assert_eq!(allocations, 0, "100 wide steps allocated");
}

#[test]
fn jointed_scenes_step_without_allocating() {
    // The bridge (one chain of 161 hinges, solved as one system) and the stretched chain
    // pulling itself together, after 300 steps (at 60 the swinging bridge still grew the
    // broad phase's moved list three times in 100 steps): their joint lists, chains and
    // stage order repeat, so the solver prepares its kept joint copies in place; inline on
    // one thread and with every stage split over two, nothing is allocated.
    let _turn = turn();
    for (name, wide) in [
        ("bridge", WideThresholds::default()),
        ("stretched_chain", WideThresholds::default()),
        ("bridge", WideThresholds::ALWAYS),
    ] {
        let threads = if wide == WideThresholds::ALWAYS { 2 } else { 1 };
        let (allocations, _) = allocations_in_100_steps(name, 300, threads, wide);
        assert_eq!(allocations, 0, "{name}: 100 steps allocated");
    }
}

#[test]
fn a_solve_timed_both_ways_allocates_nothing() {
    // large_pyramid at 2 threads with the default thresholds: its ~15,000 touching contacts
    // split the substeps, which `WideThresholds::solve_by_payoff` times on one worker now and
    // then (at least every 258 steps), so 300 steps after it settles hold split and
    // one-worker solves both, whichever the clock prefers, and a switch of plan between them:
    // none of it allocates.
    let _turn = turn();
    let (allocations, _, solved_on) =
        allocations_in_steps("large_pyramid", 300, 300, 2, WideThresholds::default());
    if tumble_physics::default_thread_count() > 1 {
        assert_eq!(solved_on, [true, true], "both ways ran (one worker, two)");
    }
    assert_eq!(allocations, 0, "300 steps timed both ways allocated");
}
