//! The one module with unsafe code: shared access to flat arrays from the step's workers, and
//! the spin barrier that separates the solver's stages.
//!
//! Why unsafe: inside one graph colour, constraints touch disjoint dynamic bodies (that is what
//! the colouring guarantees) and only read static and kinematic ones, so workers may update
//! body states in place with no lock, as Box2D v3 does. Rust cannot see that disjointness
//! through a `&mut [T]`, so the accessors here hold raw pointers, and their constructors are
//! `unsafe` with the contract stated on them.
#![allow(unsafe_code)]

use std::marker::PhantomData;
use std::ops::Range;
use std::sync::atomic::{AtomicUsize, Ordering};

use crate::solver::contact_solver::BodyState;

/// Body states shared by the workers of one solver run.
#[derive(Clone, Copy)]
pub struct BodyStates<'a> {
    ptr: *mut BodyState,
    len: usize,
    _borrow: PhantomData<&'a mut [BodyState]>,
}

// SAFETY: access follows the contract of `BodyStates::new`.
unsafe impl Send for BodyStates<'_> {}
// SAFETY: as above.
unsafe impl Sync for BodyStates<'_> {}

impl<'a> BodyStates<'a> {
    /// Exclusive access from one thread; always sound.
    pub fn exclusive(states: &'a mut [BodyState]) -> Self {
        Self {
            ptr: states.as_mut_ptr(),
            len: states.len(),
            _borrow: PhantomData,
        }
    }

    /// Shared access for concurrent workers.
    ///
    /// # Safety
    /// Between two barriers, a body written by one worker (`set`, `set_velocity`) is neither
    /// read nor written by any other worker. The solver ensures this by colouring (a dynamic
    /// body is in at most one constraint per colour, and only dynamic bodies are written) and
    /// by giving each worker its own range of bodies in the integration stages.
    pub unsafe fn shared(states: &'a mut [BodyState]) -> Self {
        Self::exclusive(states)
    }

    /// Reads a body's state.
    #[inline(always)]
    pub fn get(&self, i: usize) -> BodyState {
        assert!(i < self.len);
        // SAFETY: in bounds; no concurrent writer of this body (contract of `shared`).
        unsafe { self.ptr.add(i).read() }
    }

    /// Writes a body's state.
    #[inline(always)]
    pub fn set(&self, i: usize, state: BodyState) {
        assert!(i < self.len);
        // SAFETY: in bounds; this worker is the body's only user (contract of `shared`).
        unsafe { self.ptr.add(i).write(state) }
    }

    /// Writes a body's velocities only.
    #[inline(always)]
    pub fn set_velocity(&self, i: usize, v: glam::Vec2, w: f32) {
        assert!(i < self.len);
        // SAFETY: as in `set`.
        unsafe {
            let s = self.ptr.add(i);
            (*s).v = v;
            (*s).w = w;
        }
    }
}

/// A slice whose disjoint sub-ranges workers mutate concurrently.
pub struct SharedSlice<'a, T> {
    ptr: *mut T,
    len: usize,
    _borrow: PhantomData<&'a mut [T]>,
}

// SAFETY: access follows the contract of `SharedSlice::range_mut`.
unsafe impl<T: Send> Send for SharedSlice<'_, T> {}
// SAFETY: as above.
unsafe impl<T: Send> Sync for SharedSlice<'_, T> {}

impl<'a, T> SharedSlice<'a, T> {
    /// Wraps a slice.
    pub fn new(slice: &'a mut [T]) -> Self {
        Self {
            ptr: slice.as_mut_ptr(),
            len: slice.len(),
            _borrow: PhantomData,
        }
    }

    /// The address of element `i`, not checked and not dereferenced: for cache hints.
    pub fn as_ptr_at(&self, i: usize) -> *const T {
        self.ptr.wrapping_add(i)
    }

    /// A mutable view of `range`.
    ///
    /// # Safety
    /// No other live view (on any thread) overlaps `range`.
    #[allow(clippy::mut_from_ref)]
    pub unsafe fn range_mut(&self, range: Range<usize>) -> &mut [T] {
        assert!(range.start <= range.end && range.end <= self.len);
        // SAFETY: in bounds; exclusivity is the caller's contract.
        unsafe {
            std::slice::from_raw_parts_mut(self.ptr.add(range.start), range.end - range.start)
        }
    }
}

/// Asks the CPU to start loading `value` into the cache (a hint: no effect on results, and
/// nothing where the target has no prefetch instruction).
#[inline(always)]
pub fn prefetch<T>(value: &T) {
    prefetch_ptr(value as *const T);
}

/// [`prefetch`] by address: the object need not be readable now (another worker may be
/// writing it); a prefetch never faults and reads nothing architecturally.
#[inline(always)]
pub fn prefetch_ptr<T>(ptr: *const T) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        let start = ptr.cast::<i8>();
        for offset in (0..std::mem::size_of::<T>()).step_by(64) {
            // SAFETY: prefetching any address is sound: it is a hint that cannot fault.
            unsafe { _mm_prefetch::<_MM_HINT_T0>(start.wrapping_add(offset)) };
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = ptr;
}

/// The share of `range` that worker `index` of `count` works on: contiguous, disjoint, and
/// covering the range, so every item is processed exactly once whatever the thread count.
pub fn worker_range(range: &Range<usize>, index: usize, count: usize) -> Range<usize> {
    let n = range.end - range.start;
    let start = range.start + n * index / count;
    let end = range.start + n * (index + 1) / count;
    start..end
}

/// A sense-reversing spin barrier: the solver's stages are microseconds long, far shorter
/// than putting a thread to sleep and waking it (Box2D v3 spins the same way).
pub struct SpinBarrier {
    arrived: AtomicUsize,
    generation: AtomicUsize,
    parties: usize,
    sleepers: AtomicUsize,
    lock: std::sync::Mutex<()>,
    wake: std::sync::Condvar,
}

impl SpinBarrier {
    /// A barrier for `parties` workers.
    pub fn new(parties: usize) -> Self {
        Self {
            arrived: AtomicUsize::new(0),
            generation: AtomicUsize::new(0),
            parties,
            sleepers: AtomicUsize::new(0),
            lock: std::sync::Mutex::new(()),
            wake: std::sync::Condvar::new(),
        }
    }

    /// Waits until every worker has arrived.
    pub fn wait(&self) {
        if self.parties <= 1 {
            return;
        }
        let generation = self.generation.load(Ordering::Acquire);
        if self.arrived.fetch_add(1, Ordering::AcqRel) + 1 == self.parties {
            self.arrived.store(0, Ordering::Relaxed);
            self.generation.fetch_add(1, Ordering::SeqCst);
            if self.sleepers.load(Ordering::SeqCst) > 0 {
                let _guard = self.lock.lock();
                self.wake.notify_all();
            }
        } else {
            let mut spins = 0u32;
            while self.generation.load(Ordering::Acquire) == generation {
                std::hint::spin_loop();
                spins += 1;
                // On an oversubscribed machine let the late worker run.
                if spins > 64 {
                    std::thread::yield_now();
                }
                // In a Web Worker `yield_now` does nothing, so a waiter would burn its whole
                // time slice while the late worker is descheduled: block instead (measured in
                // chromium at 2 threads on a busy machine: 40.9 -> 3.5 ms per step).
                if cfg!(target_arch = "wasm32") && spins > 4096 {
                    let mut guard = self.lock.lock().unwrap_or_else(|e| e.into_inner());
                    self.sleepers.fetch_add(1, Ordering::SeqCst);
                    while self.generation.load(Ordering::SeqCst) == generation {
                        guard = self.wake.wait(guard).unwrap_or_else(|e| e.into_inner());
                    }
                    self.sleepers.fetch_sub(1, Ordering::SeqCst);
                    break;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn worker_ranges_cover_exactly_once() {
        for n in [0usize, 1, 5, 41, 1000] {
            for count in 1..=5 {
                let r = 7..7 + n;
                let mut next = r.start;
                for w in 0..count {
                    let wr = worker_range(&r, w, count);
                    assert_eq!(wr.start, next);
                    next = wr.end;
                }
                assert_eq!(next, r.end);
            }
        }
    }

    #[test]
    fn barrier_orders_phases() {
        use std::sync::atomic::AtomicU64;
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .unwrap();
        let barrier = SpinBarrier::new(3);
        let data: Vec<AtomicU64> = (0..3).map(|_| AtomicU64::new(0)).collect();
        pool.broadcast(|ctx| {
            let i = ctx.index();
            for round in 1..=200u64 {
                data[i].store(round, Ordering::Relaxed);
                barrier.wait();
                // Everyone has written this round before anyone reads it, and nobody writes
                // the next round before everyone has read this one.
                for d in &data {
                    assert_eq!(d.load(Ordering::Relaxed), round);
                }
                barrier.wait();
            }
        });
    }
}
