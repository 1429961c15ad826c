// tumble's threads on the web: Web Workers that instantiate the same WebAssembly module on
// the same (shared) memory, then run the jobs Rust queues for them (src/web/threads.rs). This
// file is both the page-side helper that starts them and the script each worker runs.

function waitFor(target, type) {
  return new Promise((resolve) => {
    target.addEventListener('message', function onMessage({ data }) {
      if (data == null || data.type !== type) return;
      target.removeEventListener('message', onMessage);
      resolve(data);
    });
  });
}

// In a worker: wait for the module and the memory, instantiate, and serve jobs forever.
if (typeof WorkerGlobalScope !== 'undefined' && self instanceof WorkerGlobalScope) {
  waitFor(self, 'tumble_thread_init').then(async ({ module, memory, mainJS }) => {
    const pkg = await import(mainJS);
    pkg.initSync({ module, memory });
    postMessage({ type: 'tumble_thread_ready' });
    pkg.tumble_thread_main();
  });
}

/// Starts `count` workers; resolves to true once every one has instantiated the module.
export function startWorkers(module, memory, mainJS, count) {
  const init = { type: 'tumble_thread_init', module, memory, mainJS };
  return Promise.all(
    Array.from({ length: count }, (_, i) => {
      const worker = new Worker(new URL(import.meta.url), {
        type: 'module',
        name: `tumble-thread-${i}`,
      });
      const ready = new Promise((resolve, reject) => {
        waitFor(worker, 'tumble_thread_ready').then(resolve);
        worker.addEventListener('error', (e) =>
          reject(new Error(`a thread's Web Worker failed to start: ${e.message || e}`)),
        );
      });
      worker.postMessage(init);
      return ready;
    }),
  ).then(() => true);
}
