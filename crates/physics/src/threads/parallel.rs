//! Shared access to flat arrays from the step's workers, and the stage board that runs the
//! solver's stages on them. Unsafe code is denied crate-wide and allowed only where needed: here,
//! in the solver's calls into these accessors, in `solver::wide::LaneWriter` (concurrent
//! per-lane writes) and in `solver::lanes` (AVX2 intrinsics); each states its contract.
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

use crate::body::BodyState;
use crate::threads::crew::Crew;

/// One value per body shared by the workers of one solver run: the body states
/// ([`BodyStates`]), and the restitution passes' marks ([`BodyMarks`],
/// `contact_solver::BounceMarks`).
#[derive(Clone, Copy)]
pub struct PerBody<'a, T> {
    ptr: *mut T,
    len: usize,
    _borrow: PhantomData<&'a mut [T]>,
}

/// Body states shared by the workers of one solver run.
pub type BodyStates<'a> = PerBody<'a, BodyState>;

/// For each body, the last restitution pass a fast rebound moved it in.
pub type BodyMarks<'a> = PerBody<'a, u32>;

// SAFETY: access follows the contract of `PerBody::shared`.
unsafe impl<T: Send> Send for PerBody<'_, T> {}
// SAFETY: as above.
unsafe impl<T: Send> Sync for PerBody<'_, T> {}

impl<'a, T: Copy> PerBody<'a, T> {
    /// Exclusive access from one thread; always sound.
    pub fn exclusive(values: &'a mut [T]) -> Self {
        Self {
            ptr: values.as_mut_ptr(),
            len: values.len(),
            _borrow: PhantomData,
        }
    }

    /// Shared access for concurrent workers.
    ///
    /// # Safety
    /// Within one stage of a [`StageBoard`], a body's value written by one worker (`set`,
    /// `set_velocity`) is neither read nor written by any other worker. The solver ensures
    /// this by colouring (a dynamic body is in at most one constraint per colour, and only
    /// dynamic bodies are written) and by giving each block of an integration stage its own
    /// range of bodies.
    pub unsafe fn shared(values: &'a mut [T]) -> Self {
        Self::exclusive(values)
    }

    /// Reads a body's value.
    #[inline(always)]
    pub fn get(&self, i: usize) -> T {
        assert!(i < self.len);
        // SAFETY: in bounds; no concurrent writer of this body (contract of `shared`).
        unsafe { self.ptr.add(i).read() }
    }

    /// Writes a body's value.
    #[inline(always)]
    pub fn set(&self, i: usize, value: T) {
        assert!(i < self.len);
        // SAFETY: in bounds; this worker is the body's only user (contract of `shared`).
        unsafe { self.ptr.add(i).write(value) }
    }
}

impl PerBody<'_, BodyState> {
    /// Writes a body's first 16 bytes, its velocity, spin and padding word (`BodyState`'s
    /// layout: `v`, `w`, `flags`), as one store: `row` holds them in that order, the
    /// padding word as the bits of a float.
    #[inline(always)]
    pub fn set_motion_row(&self, i: usize, row: wide::f32x4) {
        assert!(i < self.len);
        // SAFETY: as in `set`; `BodyState` is `repr(C, align(32))` with `v: Vec2`, `w: f32`,
        // `flags: u32` first, so its first 16 bytes are those four words and are aligned
        // for an `f32x4`.
        unsafe { self.ptr.add(i).cast::<wide::f32x4>().write(row) }
    }

    /// Writes a body's last 16 bytes, its substep translation and rotation (`dp`, `dq`), as
    /// one store: `row` holds `dp.x`, `dp.y`, `dq.c`, `dq.s`.
    #[inline(always)]
    pub fn set_delta_row(&self, i: usize, row: wide::f32x4) {
        assert!(i < self.len);
        // SAFETY: as in `set_motion_row`; `dp` and `dq` are the last 16 bytes, aligned.
        unsafe { self.ptr.add(i).cast::<wide::f32x4>().add(1).write(row) }
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

    /// Its length.
    pub fn len(&self) -> usize {
        self.len
    }

    /// The address of element `i`, not checked and not dereferenced: for cache hints.
    pub fn as_ptr_at(&self, i: usize) -> *const T {
        self.ptr.wrapping_add(i)
    }

    /// A mutable view of element `i`.
    ///
    /// # Safety
    /// No other live view (on any thread) reaches element `i`.
    #[allow(clippy::mut_from_ref)]
    #[inline]
    pub unsafe fn at_mut(&self, i: u32) -> &mut T {
        let i = i as usize;
        assert!(i < self.len);
        // SAFETY: in bounds; exclusivity is the caller's contract.
        unsafe { &mut *self.ptr.add(i) }
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

/// How widely a step's stages may spread: over the world's crew (the caller's thread and its
/// followers), or inline on the caller's thread (no crew: no atomics, nothing but the
/// stage's own loop).
#[derive(Clone, Copy)]
pub struct Spread<'a> {
    crew: Option<&'a Crew>,
    workers: usize,
}

impl std::fmt::Debug for Spread<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Spread({} workers)", self.workers)
    }
}

impl<'a> Spread<'a> {
    /// Everything on the calling thread.
    pub const INLINE: Spread<'static> = Spread {
        crew: None,
        workers: 1,
    };

    /// The caller's thread and `crew`'s followers.
    pub fn over(crew: &'a Crew) -> Spread<'a> {
        Spread {
            crew: Some(crew),
            workers: crew.followers() + 1,
        }
    }

    /// Workers a stage may use.
    pub fn workers(self) -> usize {
        self.workers
    }

    /// The crew, when there is one.
    pub fn crew(self) -> Option<&'a Crew> {
        self.crew
    }

    /// Whether a stage of `items` items is split: only when every worker gets at least
    /// `min_per_worker` of them (the work that pays for handing it out and waiting for it).
    pub fn goes_wide(self, items: usize, min_per_worker: usize) -> bool {
        self.workers > 1 && items >= 2 * min_per_worker.max(1)
    }

    /// This spread for a stage of `items` items that [`goes wide`](Self::goes_wide) at
    /// `min_per_worker`, else inline: for a stage whose own loops split by other counts.
    pub fn for_stage(self, items: usize, min_per_worker: usize) -> Spread<'a> {
        if self.goes_wide(items, min_per_worker) {
            self
        } else {
            Spread::INLINE
        }
    }
}

/// Data a stage can cut into parts that workers process independently: slices, shared or
/// mutable, index ranges, and tuples of those of one length (zipped).
pub trait Split: Send + Sized {
    /// Items in it.
    fn item_count(&self) -> usize;
    /// The first `mid` items and the rest.
    fn split_at(self, mid: usize) -> (Self, Self);
}

impl<T: Send> Split for &mut [T] {
    fn item_count(&self) -> usize {
        <[T]>::len(self)
    }
    fn split_at(self, mid: usize) -> (Self, Self) {
        self.split_at_mut(mid)
    }
}

impl<T: Sync> Split for &[T] {
    fn item_count(&self) -> usize {
        <[T]>::len(self)
    }
    fn split_at(self, mid: usize) -> (Self, Self) {
        <[T]>::split_at(self, mid)
    }
}

impl Split for Range<usize> {
    fn item_count(&self) -> usize {
        self.end - self.start
    }
    fn split_at(self, mid: usize) -> (Self, Self) {
        let mid = self.start + mid;
        (self.start..mid, mid..self.end)
    }
}

macro_rules! split_tuple {
    ($($name:ident $idx:tt),+) => {
        impl<$($name: Split),+> Split for ($($name,)+) {
            fn item_count(&self) -> usize {
                let len = self.0.item_count();
                $(debug_assert_eq!(self.$idx.item_count(), len, "zipped parts differ in length");)+
                len
            }
            #[allow(non_snake_case)]
            fn split_at(self, mid: usize) -> (Self, Self) {
                $(let $name = self.$idx.split_at(mid);)+
                (($($name.0,)+), ($($name.1,)+))
            }
        }
    };
}
split_tuple!(A 0, B 1);
split_tuple!(A 0, B 1, C 2);
split_tuple!(A 0, B 1, C 2, D 3);
split_tuple!(A 0, B 1, C 2, D 3, E 4);

/// Most parts a stage is cut into (its slots live on the leader's stack).
pub(crate) const MAX_PARTS: usize = 64;

/// One part of a stage and its result, each touched by the one worker that claimed it.
struct PartSlot<S, R> {
    part: std::cell::UnsafeCell<Option<(usize, S)>>,
    result: std::cell::UnsafeCell<Option<R>>,
}

/// The parts of one stage, claimed by index.
struct Parts<S, R> {
    slots: [PartSlot<S, R>; MAX_PARTS],
    count: usize,
    next: AtomicUsize,
}

// SAFETY: a slot is touched only by the worker that claimed its index from `next` (each index
// is handed out once), and by the leader after every worker is done (`Crew::run` returns).
unsafe impl<S: Send, R: Send> Sync for Parts<S, R> {}

/// Runs `f(offset, part)` over parts of `data` that cover it once each (`offset`: the part's
/// first index) and folds their results with `reduce` in part order. One part, on this
/// thread, unless `spread` goes wide for `data`'s length (see [`Spread::goes_wide`]); then
/// the parts are claimed by the caller's thread and the crew's followers. Nothing allocates.
///
/// The result is the same either way when `f` writes only its part and `reduce` is exact and
/// associative (integer sums, `or`, concatenation): the tests of determinism rely on it.
pub fn for_parts<S: Split, R: Send>(
    spread: Spread<'_>,
    data: S,
    min_per_worker: usize,
    f: &(impl Fn(usize, S) -> R + Sync),
    reduce: &(impl Fn(R, R) -> R + Sync),
) -> R {
    let len = data.item_count();
    let crew = match spread.crew {
        Some(crew) if spread.goes_wide(len, min_per_worker) => crew,
        _ => return f(0, data),
    };
    // Four parts a worker, so one that finishes early takes another's last ones, and none
    // below the minimum that pays for a part.
    let count = (4 * spread.workers)
        .min(len / min_per_worker.max(1))
        .clamp(1, MAX_PARTS);
    let parts = Parts {
        slots: std::array::from_fn(|_| PartSlot {
            part: std::cell::UnsafeCell::new(None),
            result: std::cell::UnsafeCell::new(None),
        }),
        count,
        next: AtomicUsize::new(0),
    };
    let mut rest = Some(data);
    for (k, slot) in parts.slots[..count].iter().enumerate() {
        let (start, end) = (len * k / count, len * (k + 1) / count);
        let (part, tail) = rest.take().expect("parts remain").split_at(end - start);
        // SAFETY: no worker runs yet; the leader owns every slot.
        unsafe { *slot.part.get() = Some((start, part)) };
        rest = Some(tail);
    }
    // The closure takes `Parts` whole (its fields alone are not `Sync`).
    let shared = &parts;
    crew.run(&|| {
        let parts = shared;
        loop {
            let k = parts.next.fetch_add(1, Ordering::Relaxed);
            if k >= parts.count {
                break;
            }
            let slot = &parts.slots[k];
            // SAFETY: index k was handed to this worker alone (see `Parts`).
            let (offset, part) = unsafe { (*slot.part.get()).take() }.expect("a part per slot");
            let r = f(offset, part);
            // SAFETY: as above.
            unsafe { *slot.result.get() = Some(r) };
        }
    });
    // SAFETY: every run of the job has returned (`Crew::run`): the leader owns the slots.
    let mut results = parts.slots[..count]
        .iter()
        .map(|slot| unsafe { (*slot.result.get()).take() }.expect("every part ran"));
    let first = results.next().expect("at least one part");
    results.fold(first, reduce)
}

/// [`for_parts`] for a stage that returns nothing.
pub fn for_each_part<S: Split>(
    spread: Spread<'_>,
    data: S,
    min_per_worker: usize,
    f: &(impl Fn(usize, S) + Sync),
) {
    for_parts(spread, data, min_per_worker, f, &|(), ()| ());
}

/// The share of `range` that worker `index` of `count` works on: contiguous, disjoint, and
/// covering the range, so every item is processed exactly once whatever the thread count.
pub fn worker_range(range: &Range<usize>, index: usize, count: usize) -> Range<usize> {
    let n = range.end - range.start;
    let start = range.start + n * index / count;
    let end = range.start + n * (index + 1) / count;
    start..end
}

/// Waiting for a condition another worker makes true: spinning, since the solver's stages are
/// microseconds long, far shorter than putting a thread to sleep and waking it (Box2D v3
/// spins the same way); yielding once the wait grows; and blocking once it has lasted
/// [`BLOCK_AFTER`], so that on a busy machine the worker we wait for, descheduled, can have
/// this core (a spinning or yielding waiter keeps it: measured on 2 cores beside a compiler,
/// `pile_3200`'s 2-thread step took 2.6 ms spinning against 1.1 blocking in rayon). In a Web
/// Worker `yield_now` does nothing, so there it only spins, and blocks after
/// [`WASM_BLOCK_AFTER`] (measured in chromium at 2 threads on a busy machine: spinning without
/// end, 40.9 ms per step; blocking after a few µs, 3.5).
#[derive(Default)]
pub(crate) struct Parking {
    sleepers: AtomicUsize,
    lock: std::sync::Mutex<()>,
    wake: std::sync::Condvar,
}

/// How long a waiter spins and yields before it blocks (natively). Long enough to outlast the
/// step's serial stretches (the touch update, colouring: 60 to 150 µs where contacts churn),
/// so that the followers are awake for the parallel stage after one: a blocked follower
/// takes tens of µs to wake, and the leader does most of a short stage alone meanwhile.
/// Measured at 2 threads, 500 µs ÷ 50 µs, medians of 6 interleaved pairs (Intel Xeon, 2
/// vCPUs): junkyard 0.906, tumbler 0.917, washer 0.954, pile_1000 0.976, pile_3000 0.983;
/// 2000 µs gained nothing more (tumbler 1.12). Beside two busy processes the medians were
/// 0.87 and 1.01, with spreads of 0.7 to 2.4 either way.
const BLOCK_AFTER: std::time::Duration = std::time::Duration::from_micros(500);
/// [`BLOCK_AFTER`] in a Web Worker, which cannot yield: it only spins until then. It blocked
/// after 4096 spins, a few µs, so most gaps between the solver's stages put it to sleep, and a
/// blocked worker takes tens of µs to wake. Measured in chromium (`?bench=large_pyramid`, 2
/// threads, after `&warmup=300`; a 2-vCPU Intel Xeon, shared and busy), 200 µs ÷ 4096 spins:
/// median 0.82 of 10 interleaved pairs (8 under 0.9, least 0.53, most 1.11); 500 µs ÷ 200 µs
/// 1.17 and 100 µs ÷ 200 µs 1.25 (4 pairs each, spreads of 0.6 to 1.4).
const WASM_BLOCK_AFTER: std::time::Duration = std::time::Duration::from_micros(200);

#[cfg(not(target_arch = "wasm32"))]
fn now() -> std::time::Instant {
    std::time::Instant::now()
}

#[cfg(target_arch = "wasm32")]
fn now() -> web_time::Instant {
    web_time::Instant::now()
}

impl Parking {
    /// Returns once `ready()` is true. Whatever makes it true calls [`Parking::notify`] after.
    pub(crate) fn wait(&self, mut ready: impl FnMut() -> bool) {
        let mut spins = 0u32;
        let mut since = None;
        while !ready() {
            spins = spins.saturating_add(1);
            if spins <= 64 {
                std::hint::spin_loop();
                continue;
            }
            let block = since.get_or_insert_with(now).elapsed()
                > if cfg!(target_arch = "wasm32") {
                    WASM_BLOCK_AFTER
                } else {
                    BLOCK_AFTER
                };
            if !block {
                // On an oversubscribed machine let the worker we wait for run.
                std::thread::yield_now();
                continue;
            }
            let mut guard = self.lock.lock().unwrap_or_else(|e| e.into_inner());
            self.sleepers.fetch_add(1, Ordering::SeqCst);
            while !ready() {
                // The timeout is a backstop only: `notify` wakes us.
                let timeout = std::time::Duration::from_millis(1);
                guard = match self.wake.wait_timeout(guard, timeout) {
                    Ok((g, _)) => g,
                    Err(e) => e.into_inner().0,
                };
            }
            self.sleepers.fetch_sub(1, Ordering::SeqCst);
            return;
        }
    }

    /// Wakes blocked waiters, if any; called after a `SeqCst` write that may make them ready.
    pub(crate) fn notify(&self) {
        if self.sleepers.load(Ordering::SeqCst) > 0 {
            let _guard = self.lock.lock();
            self.wake.notify_all();
        }
    }
}

/// The solver's stages run as Box2D v3 runs them (`b2ExecuteMainStage`, `b2ExecuteStage`):
/// the first worker to join leads; it walks the stages in order and publishes each, the others
/// follow what it publishes. Each stage is cut into blocks, and every worker has a share of
/// them: it claims the blocks of its own share first, then the blocks left in the others'
/// shares. A stage ends when all its blocks are done, not when every worker has passed a
/// barrier, so a worker the OS has descheduled holds the others up only for a block it has
/// claimed (with a barrier per stage, for its whole time slice), and a worker that is slow
/// in one stage has its last blocks taken by one that is not.
///
/// What a block does is the caller's; blocks of one stage must be independent of each other,
/// and each stage may read what every block of the stages before it wrote.
pub struct StageBoard {
    workers: usize,
    /// Index + 1 of the stage published last; 0 before the first, `FINISHED` after the last.
    current: AtomicUsize,
    /// Per stage and share (`stage * workers + share`): the next block to claim in the share.
    next: Vec<AtomicUsize>,
    /// Per stage: blocks done.
    done: Vec<AtomicUsize>,
    /// Per stage: blocks.
    blocks: Vec<usize>,
    joined: AtomicUsize,
    /// A block panicked: the others stop waiting and the leader panics too (otherwise it
    /// would wait forever for a block that never completes).
    poisoned: std::sync::atomic::AtomicBool,
    parking: Parking,
}

/// Sets the board's `poisoned` flag if dropped while unwinding from a block.
struct PoisonOnPanic<'a>(&'a StageBoard);

impl Drop for PoisonOnPanic<'_> {
    fn drop(&mut self) {
        if std::thread::panicking() {
            self.0.poisoned.store(true, Ordering::SeqCst);
            self.0.parking.notify();
        }
    }
}

const FINISHED: usize = usize::MAX;

impl Default for StageBoard {
    fn default() -> Self {
        StageBoard::new(Vec::new(), 1)
    }
}

/// A board is scratch space between runs: a clone is a fresh, empty one.
impl Clone for StageBoard {
    fn clone(&self) -> Self {
        StageBoard::default()
    }
}

impl std::fmt::Debug for StageBoard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("StageBoard")
            .field("workers", &self.workers)
            .field("stages", &self.blocks.len())
            .finish_non_exhaustive()
    }
}

impl StageBoard {
    /// A board for stages of `blocks[s]` blocks each, run by up to `workers` workers.
    pub fn new(blocks: Vec<usize>, workers: usize) -> StageBoard {
        let mut board = StageBoard {
            workers: 1,
            current: AtomicUsize::new(0),
            next: Vec::new(),
            done: Vec::new(),
            blocks: Vec::new(),
            joined: AtomicUsize::new(0),
            poisoned: std::sync::atomic::AtomicBool::new(false),
            parking: Parking::default(),
        };
        board.reset(blocks, workers);
        board
    }

    /// Makes the board ready for a new run of stages of `blocks` blocks each, keeping its
    /// buffers (a steady step allocates nothing).
    pub fn reset(&mut self, blocks: impl IntoIterator<Item = usize>, workers: usize) {
        let workers = workers.max(1);
        self.workers = workers;
        self.blocks.clear();
        self.blocks.extend(blocks);
        self.next.clear();
        let blocks = &self.blocks;
        self.next.extend(
            blocks.iter().flat_map(|&n| {
                (0..workers).map(move |share| AtomicUsize::new(n * share / workers))
            }),
        );
        self.done.clear();
        self.done.extend(blocks.iter().map(|_| AtomicUsize::new(0)));
        *self.current.get_mut() = 0;
        *self.joined.get_mut() = 0;
        *self.poisoned.get_mut() = false;
    }

    /// Joins the run: `Some(0)` for the leader, who must call [`lead`](Self::lead) for every
    /// stage in order and then [`finish`](Self::finish); `Some(share)` for a follower, who
    /// must call [`follow`](Self::follow); `None` once every share is taken.
    pub fn join(&self) -> Option<usize> {
        let share = self.joined.fetch_add(1, Ordering::Relaxed);
        (share < self.workers).then_some(share)
    }

    /// Leader: runs stage `stage` with the followers (`run(stage, block)` for each block, on
    /// whichever worker claims it) and returns when every block of it is done. A stage of
    /// one block runs here alone, unpublished.
    pub fn lead(&self, stage: usize, run: &mut impl FnMut(usize, usize)) {
        if self.blocks[stage] <= 1 {
            if self.blocks[stage] == 1 {
                run(stage, 0);
            }
            return;
        }
        self.current.store(stage + 1, Ordering::SeqCst);
        self.parking.notify();
        self.claim(stage, 0, run);
        let blocks = self.blocks[stage];
        // Acquire: the blocks the followers ran happen before what comes next.
        self.parking.wait(|| {
            self.done[stage].load(Ordering::Acquire) == blocks
                || self.poisoned.load(Ordering::Relaxed)
        });
        assert!(
            !self.poisoned.load(Ordering::Relaxed),
            "a worker panicked in a solver stage"
        );
    }

    /// Leader: tells the followers that the last stage is done.
    pub fn finish(&self) {
        self.current.store(FINISHED, Ordering::SeqCst);
        self.parking.notify();
    }

    /// Follower `share`: runs its part of each stage the leader publishes, until it finishes.
    /// A follower that falls behind skips the stages it missed (their blocks are all done).
    pub fn follow(&self, share: usize, run: &mut impl FnMut(usize, usize)) {
        let mut seen = 0;
        loop {
            let mut current = seen;
            // Acquire: all that the stages before the published one wrote is visible.
            self.parking.wait(|| {
                current = self.current.load(Ordering::Acquire);
                current != seen || self.poisoned.load(Ordering::Relaxed)
            });
            if current == FINISHED || self.poisoned.load(Ordering::Relaxed) {
                return;
            }
            seen = current;
            self.claim(current - 1, share, run);
        }
    }

    /// Claims and runs blocks of `stage`: those of share `share` first, then the others'.
    fn claim(&self, stage: usize, share: usize, run: &mut impl FnMut(usize, usize)) {
        let (workers, blocks) = (self.workers, self.blocks[stage]);
        let mut completed = 0;
        let _poison = PoisonOnPanic(self);
        for i in 0..workers {
            let from = (share + i) % workers;
            let end = blocks * (from + 1) / workers;
            let cursor = &self.next[stage * workers + from];
            // Each block index is handed out once; the claim itself orders nothing (what the
            // blocks write is published through `done` and `current`).
            while cursor.load(Ordering::Relaxed) < end {
                let block = cursor.fetch_add(1, Ordering::Relaxed);
                if block >= end {
                    break;
                }
                run(stage, block);
                completed += 1;
            }
        }
        if completed > 0 {
            // Release: this worker's blocks happen before the leader's next stage.
            self.done[stage].fetch_add(completed, Ordering::SeqCst);
            self.parking.notify();
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
    fn parts_cover_every_item_once_inline_and_wide() {
        // 1000 items at 40 per worker: inline, one part on this thread; over the caller and
        // two followers, 12 parts (four a worker) of 83 or 84, at least the 40, that cover
        // 0..1000 once, with offsets matching; the sums agree.
        let data: Vec<u64> = (0..1000).collect();
        let mut out = vec![0u64; 1000];
        let parts = std::sync::Mutex::new(Vec::new());
        let square = |offset: usize, (src, dst): (&[u64], &mut [u64])| {
            parts.lock().unwrap().push(offset..offset + src.len());
            for (k, (s, d)) in src.iter().zip(dst.iter_mut()).enumerate() {
                assert_eq!(*s, (offset + k) as u64);
                *d = s * s;
            }
            src.iter().sum::<u64>()
        };
        let sum = for_parts(
            Spread::INLINE,
            (&data[..], &mut out[..]),
            40,
            &square,
            &|a, b| a + b,
        );
        assert_eq!(sum, 499_500);
        assert_eq!(*parts.lock().unwrap(), vec![0..1000]);
        let crew = Crew::start(crate::threads::crew::tests::pool(2));
        let three = Spread::over(&crew);
        assert!(!three.goes_wide(79, 40) && three.goes_wide(80, 40));

        parts.lock().unwrap().clear();
        out.fill(0);
        let sum = for_parts(three, (&data[..], &mut out[..]), 40, &square, &|a, b| a + b);
        assert_eq!(sum, 499_500);
        assert!(out.iter().enumerate().all(|(i, &v)| v == (i * i) as u64));
        let mut parts = parts.into_inner().unwrap();
        parts.sort_by_key(|r| r.start);
        assert_eq!(parts.len(), 12, "{parts:?}");
        assert!(
            parts.iter().all(|r| r.len() >= 40),
            "a part below the minimum: {parts:?}"
        );
        assert_eq!(parts.first().unwrap().start, 0);
        assert_eq!(parts.last().unwrap().end, 1000);
        assert!(parts.windows(2).all(|w| w[0].end == w[1].start));
    }

    #[test]
    fn every_block_runs_once_and_stages_in_order() {
        use std::sync::atomic::AtomicU64;
        // Stages of 0 to 40 blocks; each block records the stage it ran in and checks that
        // every block of the stage before is done. One worker is slowed now and then, so
        // the others take blocks from its share.
        let blocks: Vec<usize> = (0..60).map(|s| (s * 7) % 41).collect();
        for threads in 1..=4 {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let board = StageBoard::new(blocks.clone(), threads);
            let runs: Vec<Vec<AtomicU64>> = blocks
                .iter()
                .map(|&n| (0..n).map(|_| AtomicU64::new(0)).collect())
                .collect();
            let run = |stage: usize, block: usize| {
                if stage > 0 {
                    for r in &runs[stage - 1] {
                        assert_eq!(r.load(Ordering::Relaxed), 1, "stage {stage} began early");
                    }
                }
                if block.is_multiple_of(5) && stage.is_multiple_of(3) {
                    std::thread::sleep(std::time::Duration::from_micros(200));
                }
                runs[stage][block].fetch_add(1, Ordering::Relaxed);
            };
            pool.broadcast(|_| match board.join() {
                Some(0) => {
                    for stage in 0..blocks.len() {
                        board.lead(stage, &mut |s, b| run(s, b));
                    }
                    board.finish();
                }
                Some(share) => board.follow(share, &mut |s, b| run(s, b)),
                None => {}
            });
            for (stage, r) in runs.iter().enumerate() {
                for (block, n) in r.iter().enumerate() {
                    assert_eq!(n.load(Ordering::Relaxed), 1, "{threads}: {stage}/{block}");
                }
            }
        }
    }
}
