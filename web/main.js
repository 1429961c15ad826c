// tumble's loader: downloads and compiles the WebAssembly (with a progress bar), starts the
// step's threads (Web Workers; only where the page is cross-origin isolated), then starts the
// app in the canvas. Any failure shows in #tumble-error instead of a blank page.

import init, { benchResult, benchStart, initThreadPool, start, takePanic } from './pkg/tumble.js';

const bar = document.getElementById('loading-bar');
const text = document.getElementById('loading-text');
const loading = document.getElementById('loading');

function fail(error) {
  const box = document.getElementById('tumble-error');
  // A panic's hook has already written its message; keep it.
  if (!box.hidden && box.textContent) return;
  const message = error && error.message ? error.message : String(error);
  box.textContent = message.startsWith('tumble') ? message : `tumble could not run: ${message}`;
  box.hidden = false;
  loading.classList.add('done');
}

window.addEventListener('error', (e) => fail(e.error || e.message));
window.addEventListener('unhandledrejection', (e) => fail(e.reason));

/// Fetches the module, showing how much has arrived, and compiles it.
async function compile(url) {
  const response = await fetch(url);
  if (!response.ok) throw new Error(`${url}: HTTP ${response.status}`);
  const total = Number(response.headers.get('Content-Length')) || 0;
  const chunks = [];
  let received = 0;
  const reader = response.body.getReader();
  for (;;) {
    const { done, value } = await reader.read();
    if (done) break;
    chunks.push(value);
    received += value.length;
    const mb = (received / 1048576).toFixed(1);
    text.textContent = total ? `Downloading… ${mb} of ${(total / 1048576).toFixed(1)} MB` : `Downloading… ${mb} MB`;
    if (total) bar.style.width = `${Math.min(100, (100 * received) / total)}%`;
  }
  text.textContent = 'Compiling…';
  bar.style.width = '';
  bar.classList.add('busy');
  return WebAssembly.compile(await new Blob(chunks).arrayBuffer());
}

async function main() {
  const module = await compile(new URL('./pkg/tumble_bg.wasm', import.meta.url));
  await init({ module_or_path: module });
  // A panic on a worker cannot reach the page itself: it leaves its message here.
  setInterval(() => {
    const message = takePanic();
    if (message !== undefined) fail(message);
  }, 500);
  // The thread slider goes up to the cores the browser reports; without cross-origin
  // isolation initThreadPool resolves to false and the step runs on one thread.
  text.textContent = 'Starting threads…';
  await initThreadPool(navigator.hardwareConcurrency || 1);
  const params = new URLSearchParams(location.search);
  if (params.has('bench')) return bench(params);
  if (params.has('scene') && Number(params.get('warmup') || 0) > 0) await warmUp(params);
  text.textContent = 'Starting…';
  start();
  // The loading screen goes once the first frame is drawn.
  const waitForFrame = () => {
    if (window.tumble && window.tumble.frames > 0) loading.classList.add('done');
    else requestAnimationFrame(waitForFrame);
  };
  waitForFrame();
}

/// `?bench=SCENE&threads=T&steps=N[&warmup=K]`: times the step alone (no frames drawn), as
/// `tumble-bench run` does natively, and publishes the result on `window.tumble_bench`;
/// `warmup` untimed steps of a throwaway world first let the browser compile the hot code.
async function bench(params) {
  const scene = params.get('bench') || 'large_pyramid';
  const threads = Number(params.get('threads') || 1);
  const steps = Number(params.get('steps') || 300);
  const warmup = Number(params.get('warmup') || 0);
  text.textContent = `Benchmark: ${scene}, ${threads} thread(s), ${steps} steps…`;
  // Let the page paint the message before the step takes the thread.
  await new Promise((resolve) => setTimeout(resolve, 50));
  benchStart(scene, threads, steps, warmup);
  let result;
  while ((result = benchResult()) === undefined) {
    await new Promise((resolve) => setTimeout(resolve, 100));
  }
  const profile = JSON.parse(result);
  window.tumble_bench = { scene, threads, steps, warmup, ...profile, cross_origin_isolated: self.crossOriginIsolated };
  bar.classList.remove('busy');
  text.textContent = `${scene}: ${profile.step_ms_mean.toFixed(3)} ms per step on ${threads} thread(s), mean of ${steps} steps`;
}

/// `?scene=SCENE&threads=T&warmup=K`: before the viewer starts, a throwaway world of the scene
/// steps K times untimed (`benchStart`'s warm-up, on a worker), so the viewer's steps, and
/// its `step_ms_mean`, run code the browser has compiled, as `?bench=` does with `&warmup`.
async function warmUp(params) {
  const scene = params.get('scene');
  const threads = Number(params.get('threads') || 1);
  const warmup = Number(params.get('warmup'));
  text.textContent = `Warming up: ${scene}, ${warmup} steps…`;
  await new Promise((resolve) => setTimeout(resolve, 50));
  try {
    benchStart(scene, threads, 1, warmup);
  } catch (e) {
    // A scene the runner cannot load: the viewer says why once it starts.
    return;
  }
  while (benchResult() === undefined) {
    await new Promise((resolve) => setTimeout(resolve, 100));
  }
}

main().catch(fail);
