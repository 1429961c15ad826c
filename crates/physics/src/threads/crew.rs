//! The world's worker threads: the caller's thread leads each parallel stage and up to
//! `threads - 1` followers help it, Box2D v3's model (its task system runs the stages the
//! caller publishes, and the caller works too) rather than a fork-join pool's, whose caller
//! hands the step to a pool thread and sleeps until it is handed back: measured on this
//! project's 2-core VM, `rayon::ThreadPool::install` costs 15-25 us back to back and ~60 us
//! after 200 us idle, against 0.05-0.8 us for a hand-off to a spinning follower.
//!
//! The leader never waits for a follower to arrive: it publishes a job and starts on it, and
//! a follower that wakes late helps with what is left (or finds nothing). So a follower that
//! sleeps costs the leader a wake-up call, not the wake-up's latency.
//!
//! The threads come from a rayon pool (built with the platform's spawn handler, see
//! `set_thread_source`: Web Workers on the web); each runs one follower loop until the crew
//! is dropped.
#![allow(unsafe_code)]

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicPtr, AtomicUsize, Ordering};

use crate::threads::parallel::Parking;

/// A job as the followers see it: the leader's closure, lifetime erased (see `Crew::run`).
type JobFn = dyn Fn() + Sync;

/// What the leader and its followers share.
#[derive(Default)]
struct Board {
    /// Bumped for each job; a follower runs a job when it sees a new generation.
    generation: AtomicUsize,
    /// The current job: a pointer to the leader's `&JobFn`, valid while `open` and for every
    /// follower counted in `active` (the leader waits for them before its borrow ends).
    job: AtomicPtr<&'static JobFn>,
    /// The job takes new followers.
    open: AtomicBool,
    /// Followers inside the current job.
    active: AtomicUsize,
    /// A follower's job panicked; the leader panics too once the job is closed.
    poisoned: AtomicBool,
    /// The crew is being dropped: followers return.
    exit: AtomicBool,
    /// Followers waiting for a job (they spin briefly, then sleep: see `Parking`; a sleeping
    /// follower costs the leader a wake-up call, not its latency, since the leader starts
    /// each job alone and the follower joins when it is up).
    idle: Parking,
    /// The leader waiting for the followers inside a closed job.
    leaving: Parking,
}

impl Board {
    fn follow(&self) {
        // From the board's first generation, not the current one: a follower whose thread
        // starts late still sees the job published before it (and skips it if closed).
        let mut seen = 0;
        loop {
            self.idle.wait(|| {
                self.generation.load(Ordering::SeqCst) != seen || self.exit.load(Ordering::SeqCst)
            });
            if self.exit.load(Ordering::SeqCst) {
                return;
            }
            seen = self.generation.load(Ordering::SeqCst);
            self.active.fetch_add(1, Ordering::SeqCst);
            // Joined in time: the job is still the one seen, and open. Otherwise leave
            // before touching it (the leader may be past waiting for us).
            if self.open.load(Ordering::SeqCst) && self.generation.load(Ordering::SeqCst) == seen {
                // SAFETY: `job` points at the leader's `&JobFn`, which outlives every follower
                // counted in `active` while the job is open (`Crew::run` waits for them).
                let job: &JobFn = unsafe { *self.job.load(Ordering::SeqCst) };
                if catch_unwind(AssertUnwindSafe(job)).is_err() {
                    self.poisoned.store(true, Ordering::SeqCst);
                }
            }
            self.active.fetch_sub(1, Ordering::SeqCst);
            self.leaving.notify();
        }
    }
}

/// The leader's side of a job: closes it and waits for the followers inside it, also when
/// the leader's own part unwinds (their borrow of the job must end first).
struct CloseOnExit<'a>(&'a Board);

impl Drop for CloseOnExit<'_> {
    fn drop(&mut self) {
        let board = self.0;
        board.open.store(false, Ordering::SeqCst);
        board
            .leaving
            .wait(|| board.active.load(Ordering::SeqCst) == 0);
    }
}

/// Up to `followers` threads that help the caller's thread with the jobs it runs.
pub struct Crew {
    board: Arc<Board>,
    followers: usize,
    /// Keeps the followers' threads; dropped after they are told to exit.
    _pool: rayon::ThreadPool,
}

impl Crew {
    /// Runs one follower on each thread of `pool` (built for this crew alone).
    pub fn start(pool: rayon::ThreadPool) -> Crew {
        let followers = pool.current_num_threads();
        let board = Arc::new(Board::default());
        for _ in 0..followers {
            let board = Arc::clone(&board);
            pool.spawn(move || board.follow());
        }
        Crew {
            board,
            followers,
            _pool: pool,
        }
    }

    /// Threads besides the caller's.
    pub fn followers(&self) -> usize {
        self.followers
    }

    /// Runs `job` on this thread and on every follower that joins before this thread's run
    /// of it returns; returns once every run of it has. `job` must hand out its work so that
    /// any number of runs, from one up, together do all of it (a shared counter of parts).
    /// Panics if a follower's run panicked. Must not be called from inside a job. A follower
    /// that reads the job just as the next one is published may run that next one instead:
    /// harmless, since it is counted and waited for like any other run of it.
    pub fn run(&self, job: &(dyn Fn() + Sync)) {
        let board = &*self.board;
        // SAFETY (lifetime erasure): followers dereference this only while counted in
        // `active` with the job open; `CloseOnExit` closes it and waits for `active` to reach
        // zero before this function returns or unwinds, so no use outlives `job`.
        let erased: &'static JobFn =
            unsafe { std::mem::transmute::<&(dyn Fn() + Sync + '_), &'static JobFn>(job) };
        let slot: *const &'static JobFn = &erased;
        // A job the leader's own part unwound from may have left the flag set.
        board.poisoned.store(false, Ordering::SeqCst);
        board.job.store(slot.cast_mut(), Ordering::SeqCst);
        board.open.store(true, Ordering::SeqCst);
        board.generation.fetch_add(1, Ordering::SeqCst);
        board.idle.notify();
        {
            let _close = CloseOnExit(board);
            job();
        }
        assert!(
            !board.poisoned.swap(false, Ordering::SeqCst),
            "a worker thread panicked in a step stage"
        );
    }
}

impl Drop for Crew {
    fn drop(&mut self) {
        self.board.exit.store(true, Ordering::SeqCst);
        self.board.idle.notify();
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use std::sync::atomic::AtomicU64;

    pub(crate) fn pool(threads: usize) -> rayon::ThreadPool {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
    }

    #[test]
    fn every_part_runs_once_whoever_joins() {
        // 64 parts of ~10 us per job, 200 jobs back to back, and a pause now and then so the
        // followers fall asleep and join late: every part of every job runs exactly once,
        // and the followers do run some of them (a woken follower is up in well under the
        // 0.6 ms a job takes the leader alone, or within the 5 ms backstop of its sleep).
        let leader = std::thread::current().id();
        for followers in 1..=3 {
            let crew = Crew::start(pool(followers));
            let helped = AtomicUsize::new(0);
            for job in 0..200u64 {
                let next = AtomicUsize::new(0);
                let runs: Vec<AtomicU64> = (0..64).map(|_| AtomicU64::new(0)).collect();
                crew.run(&|| {
                    loop {
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        if i >= runs.len() {
                            break;
                        }
                        runs[i].fetch_add(job + 1, Ordering::Relaxed);
                        if std::thread::current().id() != leader {
                            helped.fetch_add(1, Ordering::Relaxed);
                        }
                        // A part is some work, so a follower has the time to join.
                        let start = std::time::Instant::now();
                        while start.elapsed() < std::time::Duration::from_micros(10) {
                            std::hint::spin_loop();
                        }
                    }
                });
                assert!(runs.iter().all(|r| r.load(Ordering::Relaxed) == job + 1));
                if job % 50 == 0 {
                    std::thread::sleep(std::time::Duration::from_millis(3));
                }
            }
            assert!(
                helped.load(Ordering::Relaxed) > 0,
                "no follower ever helped"
            );
        }
    }

    #[test]
    fn a_follower_panic_reaches_the_leader() {
        let crew = Crew::start(pool(1));
        let leader = std::thread::current().id();
        // The leader waits until a follower has run the job, which then panics there.
        let result = catch_unwind(AssertUnwindSafe(|| {
            let followed = AtomicBool::new(false);
            crew.run(&|| {
                if std::thread::current().id() == leader {
                    let start = std::time::Instant::now();
                    while !followed.load(Ordering::SeqCst)
                        && start.elapsed() < std::time::Duration::from_secs(10)
                    {
                        std::hint::spin_loop();
                    }
                } else {
                    followed.store(true, Ordering::SeqCst);
                    panic!("a follower's part fails");
                }
            });
        }));
        assert!(result.is_err(), "the leader did not panic");
        // The crew still works after.
        let count = AtomicUsize::new(0);
        crew.run(&|| {
            count.fetch_add(1, Ordering::SeqCst);
        });
        assert!(count.load(Ordering::SeqCst) >= 1);
    }
}
