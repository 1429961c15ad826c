//! The step's worker threads: how many, where they come from (std threads, or the web's Web
//! Workers), and the crew that shares a wide step's stages.

use super::crew::Crew;

/// Number of cores, the default thread count (as [`set_thread_source`] says, where it was
/// called). Read once: the solver asks every step, and the standard library's answer reads
/// the cgroup files each time (a file read and allocations in every step).
pub fn default_thread_count() -> usize {
    static CORES: std::sync::OnceLock<usize> = std::sync::OnceLock::new();
    match THREAD_SOURCE.get() {
        Some(&(cores, _)) => cores.max(1),
        None => *CORES.get_or_init(|| std::thread::available_parallelism().map_or(1, |n| n.get())),
    }
}

/// Starts one worker thread of a step's pool (a rayon spawn handler).
pub type SpawnWorker = fn(rayon::ThreadBuilder) -> std::io::Result<()>;

pub(crate) static THREAD_SOURCE: std::sync::OnceLock<(usize, Option<SpawnWorker>)> =
    std::sync::OnceLock::new();

/// For a platform where `std::thread` cannot start threads (the web, whose threads are Web
/// Workers): `cores` is what [`default_thread_count`] returns from now on, and `spawn` starts
/// each worker of the pools built from now on; with `None` there are no threads, and every
/// step runs on the calling thread. Natively nothing calls it and rayon starts std threads.
/// Returns false if a source was set already (the first one stays).
pub fn set_thread_source(cores: usize, spawn: Option<SpawnWorker>) -> bool {
    THREAD_SOURCE.set((cores, spawn)).is_ok()
}

/// The crew for `threads` threads: the caller's and `threads - 1` followers.
pub(crate) fn start_crew(threads: usize) -> Option<std::sync::Arc<Crew>> {
    if threads <= 1 {
        return None;
    }
    let builder = rayon::ThreadPoolBuilder::new()
        .num_threads(threads - 1)
        .thread_name(|i| format!("tumble-step-{i}"));
    let pool = match THREAD_SOURCE.get() {
        None => builder.build(),
        Some(&(_, Some(spawn))) => builder.spawn_handler(spawn).build(),
        Some(&(_, None)) => return None,
    }
    // Starting threads only fails if the OS refuses them; then nothing can run.
    .expect("the OS refused to start the step's worker threads");
    Some(std::sync::Arc::new(Crew::start(pool)))
}
