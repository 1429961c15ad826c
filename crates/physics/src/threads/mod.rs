//! Threading, in one place: where the step's worker threads come from (`source`: std
//! threads, or the web's Web Workers), the crew that shares a wide step's stages (`crew`),
//! and the lock-free ways a stage splits its work over them (`parallel`: per-part and
//! per-index slots, never a lock in the hot path).

pub(crate) mod crew;
pub(crate) mod parallel;
pub(crate) mod payoff;
mod source;

pub use source::{SpawnWorker, default_thread_count, set_thread_source};
pub(crate) use source::{THREAD_SOURCE, start_crew};
