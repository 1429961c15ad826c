//! Threads on the web. `std::thread` cannot start a thread in a browser; Web Workers can. The
//! page awaits [`init_thread_pool`] (`initThreadPool(n)` in JavaScript) before it starts the
//! app: it starts Web Workers that instantiate this same module on the same shared memory
//! (`threads.js`) and then wait for jobs here. The physics engine builds each world's rayon
//! pool with [`spawn_worker`] as its spawn handler, so every pool thread runs on one of those
//! workers, and a pool of any size can be built and dropped live, as the thread slider does.
//!
//! wasm-bindgen-rayon does the same for rayon's one global pool, but tumble's worlds own
//! their pools (sized by the slider), and a thread serving rayon's global pool cannot also
//! serve another pool, so the workers here serve plain jobs, pool threads among them.
//!
//! A page without cross-origin isolation has no `SharedArrayBuffer`, so workers cannot share
//! the memory: the engine is told there are no threads, and every step runs on the page's own
//! thread (the UI says why).

use std::collections::VecDeque;
use std::sync::atomic::{AtomicBool, Ordering};

use js_sys::{JsString, Promise};
use wasm_bindgen::prelude::*;
use wasm_sync::{Condvar, Mutex};

pub use crate::app::Job;

/// The most threads the step may use on the web, whatever the machine reports.
pub const MAX_THREADS: usize = 16;

struct Queue {
    jobs: VecDeque<Job>,
    /// Workers waiting for a job.
    idle: usize,
    /// Workers started that have not yet come to wait for jobs.
    starting: usize,
}

static QUEUE: Mutex<Queue> = Mutex::new(Queue {
    jobs: VecDeque::new(),
    idle: 0,
    starting: 0,
});
static WAKE: Condvar = Condvar::new();
static ENABLED: AtomicBool = AtomicBool::new(false);

#[wasm_bindgen(module = "/src/web/threads.js")]
extern "C" {
    #[wasm_bindgen(js_name = startWorkers)]
    fn start_workers(module: JsValue, memory: JsValue, main_js: JsString, count: usize) -> Promise;
}

#[wasm_bindgen]
extern "C" {
    /// The URL of wasm-bindgen's JavaScript for this module, which each worker imports.
    #[wasm_bindgen(thread_local_v2, js_namespace = ["import", "meta"], js_name = url)]
    static MAIN_JS: JsString;
}

/// Whether the page may share memory with workers (`crossOriginIsolated`).
pub fn cross_origin_isolated() -> bool {
    js_sys::Reflect::get(&js_sys::global(), &JsValue::from_str("crossOriginIsolated"))
        .ok()
        .and_then(|v| v.as_bool())
        .unwrap_or(false)
}

/// Whether the step can use threads here.
pub fn enabled() -> bool {
    ENABLED.load(Ordering::Acquire)
}

/// Sets up threads for `threads` step threads (the thread slider's maximum): tells the
/// engine where its threads come from and starts the workers. The promise resolves to
/// whether threads are on, once every worker is ready; without cross-origin isolation (or in
/// a build without atomics) it resolves to false at once, and the step runs on one thread.
#[wasm_bindgen(js_name = initThreadPool)]
pub fn init_thread_pool(threads: usize) -> Promise {
    if !cfg!(target_feature = "atomics") || !cross_origin_isolated() || threads == 0 {
        tumble_physics::set_thread_source(1, None);
        return Promise::resolve(&JsValue::FALSE);
    }
    let threads = threads.clamp(1, MAX_THREADS);
    if !tumble_physics::set_thread_source(threads, Some(spawn_worker)) {
        return Promise::reject(&JsValue::from_str("initThreadPool was called twice"));
    }
    ENABLED.store(true, Ordering::Release);
    // A world's pool, the pool replacing it (the old one's threads leave a moment later), a
    // second world while a scene loads, and the thread sweep: room for all at once.
    let workers = 2 * threads + 2;
    start(workers)
}

/// Starts `count` more workers.
fn start(count: usize) -> Promise {
    if let Ok(mut queue) = QUEUE.lock() {
        queue.starting += count;
    }
    let main_js = MAIN_JS.with(JsString::clone);
    start_workers(
        wasm_bindgen::module(),
        wasm_bindgen::memory(),
        main_js,
        count,
    )
}

/// Runs `job` on a worker; hands it back where there are no threads.
pub fn spawn(job: Job) -> Result<(), Job> {
    if !enabled() {
        return Err(job);
    }
    let short = {
        let Ok(mut queue) = QUEUE.lock() else {
            return Err(job);
        };
        queue.jobs.push_back(job);
        queue.jobs.len() > queue.idle + queue.starting
    };
    WAKE.notify_one();
    if short {
        // More jobs than workers: one more (it starts once the page's thread is free).
        let _ = start(1);
    }
    Ok(())
}

/// The spawn handler of the step's rayon pools (see `tumble_physics::set_thread_source`).
fn spawn_worker(thread: rayon::ThreadBuilder) -> std::io::Result<()> {
    spawn(Box::new(move || thread.run()))
        .map_err(|_| std::io::Error::new(std::io::ErrorKind::Unsupported, "no threads here"))
}

/// A worker's life: wait for a job, run it, repeat. `threads.js` calls it in each worker
/// once the module is instantiated; it never returns.
#[wasm_bindgen]
#[doc(hidden)]
pub fn tumble_thread_main() {
    let mut first = true;
    loop {
        let job = {
            let Ok(mut queue) = QUEUE.lock() else {
                return;
            };
            if first {
                queue.starting = queue.starting.saturating_sub(1);
                first = false;
            }
            queue.idle += 1;
            while queue.jobs.is_empty() {
                queue = match WAKE.wait(queue) {
                    Ok(q) => q,
                    Err(_) => return,
                };
            }
            queue.idle -= 1;
            queue.jobs.pop_front()
        };
        if let Some(job) = job {
            job();
        }
    }
}
