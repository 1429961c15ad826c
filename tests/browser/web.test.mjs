// tumble's web build in a real browser: Debian's chromium, driven by playwright-core, once
// with WebGL2 (SwiftShader) and once with WebGPU. `cargo xtask test` (step `web`) builds the
// bundle, serves it and runs this with Node's test runner:
//
//   TUMBLE_URL               the bundle, served with the cross-origin isolation headers
//   TUMBLE_URL_NOT_ISOLATED  the same bundle without them (optional)
//   TUMBLE_OUT               where screenshots go (optional)
//   TUMBLE_NATIVE_HASH       `tumble-bench run falling_circles --steps 120 --threads 1`'s
//                            `state_hash`, which the page must reproduce at 1 and 2 threads
//   TUMBLE_PLATFORMER_HASH   `tumble-bench run platformer --keys demo --steps S --threads 1`'s
//   TUMBLE_PLATFORMER_STEPS  S: the page's scripted platformer must end there, at that hash
//
// By hand: `cargo xtask web --release`, then in this folder
// `npm ci && TUMBLE_URL=http://127.0.0.1:8080/ node --test web.test.mjs`.
//
// The app publishes its state on `window.tumble` every frame (CONTRACT.md, section 4). The
// thread slider is driven with real mouse events at the place the app reports for it
// (`window.tumble.threads_slider`, CSS pixels): egui reads the pointer like any user's.

import { after, before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { mkdirSync } from 'node:fs';
import path from 'node:path';
import { chromium } from 'playwright-core';

const URL = process.env.TUMBLE_URL ?? 'http://127.0.0.1:8080/';
const URL_NOT_ISOLATED = process.env.TUMBLE_URL_NOT_ISOLATED;
const OUT = process.env.TUMBLE_OUT;
const CHROMIUM = process.env.CHROMIUM ?? '/usr/bin/chromium';

// Headless chromium with software rendering: WebGL2 through SwiftShader; WebGPU through
// SwiftShader's Vulkan (docs/web.md, "Headless chromium"). Nothing may reach the network.
const BASE_FLAGS = [
  '--headless',
  '--no-sandbox',
  '--disable-gpu',
  '--disable-quic',
  '--no-first-run',
  '--disable-background-networking',
  '--disable-component-update',
  '--disable-sync',
  '--enable-unsafe-swiftshader',
];
const WEBGPU_FLAGS = ['--enable-unsafe-webgpu', '--enable-features=Vulkan', '--use-angle=swiftshader'];

const BACKENDS = [
  { name: 'WebGL2', flags: BASE_FLAGS, backend: 'Gl' },
  { name: 'WebGPU', flags: [...BASE_FLAGS, ...WEBGPU_FLAGS], backend: 'WebGpu' },
];

/// Loading 10 MB of WebAssembly and compiling it on a busy 2-core machine takes a while.
const LOAD_TIMEOUT = 120_000;
/// No test may hang the suite.
const TEST_TIMEOUT = 240_000;

/// A page that records every console error and uncaught exception.
async function openPage(browser, url, { width = 1280, height = 800, deviceScaleFactor = 1 } = {}) {
  const page = await browser.newPage({ viewport: { width, height }, deviceScaleFactor });
  await page.addInitScript(canvasReadback);
  const errors = [];
  page.on('console', (message) => {
    if (message.type() === 'error') errors.push(`console.error: ${message.text()}`);
  });
  page.on('pageerror', (error) => errors.push(`page error: ${error.message}`));
  await page.goto(url);
  await page.waitForFunction(() => window.tumble && window.tumble.frames > 2, null, {
    timeout: LOAD_TIMEOUT,
    polling: 200,
  });
  return { page, errors };
}

const state = (page) => page.evaluate(() => ({ ...window.tumble }));

/// Waits until the JavaScript expression `predicate` holds in the page, then returns
/// `window.tumble`.
async function until(page, predicate, timeout = 90_000) {
  await page.waitForFunction(predicate, null, { timeout, polling: 100 });
  return state(page);
}

/// Runs in the page before the app: a WebGL2 context keeps its drawing buffer, so the test
/// can copy the canvas and count its pixels. (A WebGPU canvas cannot be read back this way in
/// headless chromium: a copy or a screenshot of it comes out blank or white, and mapping a
/// buffer of the app's device fails with "A valid external Instance reference no longer
/// exists"; the WebGPU run checks everything else.)
function canvasReadback() {
  const getContext = HTMLCanvasElement.prototype.getContext;
  HTMLCanvasElement.prototype.getContext = function (type, attributes) {
    if (type === 'webgl2' || type === 'webgl') attributes = { ...attributes, preserveDrawingBuffer: true };
    return getContext.call(this, type, attributes);
  };
}

/// How many of the canvas's pixels are strongly coloured (bodies), read back in the page.
function colouredPixels(page) {
  return page.evaluate(async () => {
    const count = ({ data, width, height }) => {
      let coloured = 0;
      for (let i = 0; i < data.length; i += 4) {
        const max = Math.max(data[i], data[i + 1], data[i + 2]);
        const min = Math.min(data[i], data[i + 1], data[i + 2]);
        if (max - min > 60) coloured += 1;
      }
      return { coloured, width, height };
    };
    const canvas = document.getElementById('tumble-canvas');
    const copy = new OffscreenCanvas(canvas.width, canvas.height);
    const context = copy.getContext('2d');
    context.drawImage(canvas, 0, 0);
    return count(context.getImageData(0, 0, canvas.width, canvas.height));
  });
}

for (const backend of BACKENDS) {
  describe(`web build, ${backend.name}`, () => {
    let browser;
    before(async () => {
      browser = await chromium.launch({ executablePath: CHROMIUM, args: backend.flags, headless: true });
    });
    after(async () => {
      await browser?.close();
    });

    test('loads with no console error; frames advance; the default scene steps; bodies fall', { timeout: TEST_TIMEOUT }, async () => {
      const { page, errors } = await openPage(browser, URL);
      const first = await state(page);
      assert.equal(first.backend, backend.backend, 'the backend the UI shows');
      assert.equal(first.cross_origin_isolated, true);
      assert.equal(first.threads_enabled, true, 'threads on Web Workers');
      assert.equal(first.scene, 'falling_circles', 'the intro runs the default scene');
      assert.ok(first.bodies > 0, 'bodies');
      const later = await until(
        page,
        `window.tumble.frames >= ${first.frames + 30} && window.tumble.steps >= ${first.steps + 30}`,
      );
      assert.ok(later.frames > first.frames, 'frames advance');
      assert.ok(later.steps > first.steps, 'the scene steps');
      assert.ok(later.sim_time > first.sim_time, 'simulated time advances');
      assert.ok(
        later.mean_y < first.mean_y,
        `bodies fall: mean height ${first.mean_y.toFixed(3)} m, then ${later.mean_y.toFixed(3)} m`,
      );
      for (const key of ['frames', 'steps', 'bodies', 'threads', 'step_ms_mean']) {
        assert.equal(typeof later[key], 'number', key);
      }
      assert.ok(later.step_ms_mean > 0, 'step_ms_mean');
      assert.equal(later.non_finite_bodies, 0, 'the NaN guard stopped no body');
      assert.deepEqual(errors, [], 'no console errors');
      await page.close();
    });

    test('the thread slider, dragged from 1 to 2 with the mouse, changes the threads; stepping goes on', { timeout: TEST_TIMEOUT }, async () => {
      const { page, errors } = await openPage(browser, `${URL}?scene=pyramid&threads=1`);
      let s = await until(page, 'window.tumble.state === "Simulation" && window.tumble.threads_slider !== null');
      assert.equal(s.scene, 'pyramid');
      assert.equal(s.threads, 1, 'threads=1 from the address');
      assert.ok(s.max_threads >= 2, `the machine offers ${s.max_threads} threads; the test needs 2`);
      const slider = s.threads_slider;
      const y = slider.y + slider.height / 2;
      // Press at the handle (value 1, the left end), drag right until the engine reports 2.
      await page.mouse.move(slider.x + 4, y);
      await page.mouse.down();
      for (let f = 0.05; f <= 1.0001 && s.threads < 2; f += 0.05) {
        await page.mouse.move(slider.x + f * slider.width, y, { steps: 2 });
        await page.waitForTimeout(100);
        s = await state(page);
      }
      await page.mouse.up();
      if (s.threads !== 2) s = await until(page, 'window.tumble.threads === 2', 5_000);
      assert.equal(s.threads, 2, 'the engine reports 2 threads');
      const after2 = await until(page, `window.tumble.steps >= ${s.steps + 20}`);
      assert.ok(after2.steps > s.steps, 'the simulation keeps stepping on 2 threads');
      assert.equal(after2.threads, 2);
      // The slider's value persists (localStorage).
      const saved = await until(page, 'localStorage.getItem("tumble.settings")?.includes("threads: 2")', 5_000).then(
        () => page.evaluate(() => localStorage.getItem('tumble.settings')),
      );
      assert.match(saved, /threads: 2/);

      if (backend.backend === 'Gl') {
        const pixels = await colouredPixels(page);
        assert.equal(pixels.width, 1280 * (await page.evaluate(() => devicePixelRatio)), 'the canvas fills the window');
        assert.ok(pixels.coloured > 2000, `the canvas shows bodies: ${pixels.coloured} coloured pixels`);
      }
      if (OUT && backend.backend === 'Gl') {
        mkdirSync(OUT, { recursive: true });
        await page.screenshot({ path: path.join(OUT, 'web-webgl2.png') });
      }
      assert.deepEqual(errors, [], 'no console errors');
      await page.close();
    });
  });
}

describe('web build, the canvas', () => {
  let browser;
  before(async () => {
    // A real device-pixel ratio of 2 (Playwright's emulation alone changes devicePixelRatio
    // but not the canvas's device-pixel size that the ResizeObserver reports).
    browser = await chromium.launch({
      executablePath: CHROMIUM,
      args: [...BASE_FLAGS, '--force-device-scale-factor=2'],
      headless: true,
    });
  });
  after(async () => {
    await browser?.close();
  });

  test('fills the window and follows its size and device-pixel ratio', { timeout: TEST_TIMEOUT }, async () => {
    const { page, errors } = await openPage(browser, `${URL}?scene=pyramid`, {
      width: 800,
      height: 600,
      deviceScaleFactor: 2,
    });
    let s = await until(page, 'window.tumble.size[0] === 1600 && window.tumble.size[1] === 1200');
    assert.deepEqual(s.size, [1600, 1200], 'physical pixels at a device-pixel ratio of 2');
    await page.setViewportSize({ width: 640, height: 480 });
    s = await until(page, 'window.tumble.size[0] === 1280 && window.tumble.size[1] === 960');
    assert.deepEqual(s.size, [1280, 960], 'after the window shrank');
    const frames = s.frames;
    s = await until(page, `window.tumble.frames >= ${frames + 5}`);
    assert.ok(s.frames > frames, 'frames go on after the resize');
    assert.deepEqual(errors, [], 'no console errors');
    await page.close();
  });
});

describe('web build, the same state as the native build', () => {
  let browser;
  before(async () => {
    browser = await chromium.launch({ executablePath: CHROMIUM, args: BASE_FLAGS, headless: true });
  });
  after(async () => {
    await browser?.close();
  });

  // The step is deterministic on any thread count, and the wasm build runs the same
  // arithmetic as the native one (no fused multiply-add, the 8-lane kernels as portable
  // SIMD, which equals the AVX2 and scalar paths bit for bit), so after the same steps the
  // state hash is the native runner's, at 1 and at 2 threads (falling_circles: 300 bodies,
  // over 256 touching contacts by step 120, so 2 threads solve in parallel).
  for (const threads of [1, 2]) {
    test(`falling_circles after 120 steps on ${threads} thread(s) hashes as natively`, { timeout: TEST_TIMEOUT }, async () => {
      const native = process.env.TUMBLE_NATIVE_HASH;
      assert.match(native ?? '', /^[0-9a-f]{16}$/, 'TUMBLE_NATIVE_HASH (set by cargo xtask test) is the native state hash');
      const page = await browser.newPage();
      const errors = [];
      page.on('pageerror', (error) => errors.push(`page error: ${error.message}`));
      await page.goto(`${URL}?bench=falling_circles&threads=${threads}&steps=120`);
      await page.waitForFunction(() => window.tumble_bench !== undefined, null, { timeout: LOAD_TIMEOUT, polling: 200 });
      const result = await page.evaluate(() => window.tumble_bench);
      assert.equal(result.cross_origin_isolated, true);
      assert.equal(result.state_hash, native, `the page's state after 120 steps at ${threads} thread(s)`);
      assert.deepEqual(errors, [], 'no page errors');
      await page.close();
    });
  }
});

// The platformer, played in the page: by the scripted keys of its demo run (the same keys at
// the same steps as the native runner, so the same state, bit for bit), and by real key
// presses sent to the canvas.
describe('web build, the platformer', () => {
  let browser;
  before(async () => {
    browser = await chromium.launch({ executablePath: CHROMIUM, args: BASE_FLAGS, headless: true });
  });
  after(async () => {
    await browser?.close();
  });

  const sample = (s) => JSON.parse(s.sample).Platformer;

  test('the scripted run takes the coins, reaches the flag and ends at the native state', { timeout: TEST_TIMEOUT }, async () => {
    const native = process.env.TUMBLE_PLATFORMER_HASH;
    const steps = Number(process.env.TUMBLE_PLATFORMER_STEPS);
    assert.match(native ?? '', /^[0-9a-f]{16}$/, 'TUMBLE_PLATFORMER_HASH (set by cargo xtask test)');
    assert.ok(steps > 0, 'TUMBLE_PLATFORMER_STEPS (set by cargo xtask test)');
    const { page, errors } = await openPage(browser, `${URL}?scene=platformer&threads=2&keys=demo&steps=${steps}`);
    const s = await until(page, `window.tumble.scene_steps >= ${steps}`, 180_000);
    assert.equal(s.scene_steps, steps, 'stops at its steps');
    const p = sample(s);
    assert.equal(p.coins, 3);
    assert.ok(p.reached_flag !== null && p.reached_flag < steps, `the flag: ${p.reached_flag}`);
    assert.ok(p.deepest <= 0.01, `never a centimetre into the ground: ${p.deepest}`);
    assert.equal(s.state_hash, native, 'the same state as the native run');
    assert.deepEqual(errors, [], 'no console errors');
    await page.close();
  });

  test('the arrow keys walk the character and Space jumps (it does not pause)', { timeout: TEST_TIMEOUT }, async () => {
    const { page, errors } = await openPage(browser, `${URL}?scene=platformer&threads=1`);
    await page.locator('#tumble-canvas').click({ position: { x: 900, y: 700 } });
    const start = sample(await state(page));
    await page.keyboard.down('ArrowRight');
    let s = await until(page, `JSON.parse(window.tumble.sample).Platformer.position[0] > ${start.position[0] + 3}`);
    await page.keyboard.up('ArrowRight');
    const walked = sample(s);
    assert.ok(walked.position[0] > start.position[0] + 3, `walked right: ${start.position} -> ${walked.position}`);
    await page.keyboard.down('Space');
    s = await until(page, `JSON.parse(window.tumble.sample).Platformer.position[1] > ${walked.position[1] + 0.5}`);
    await page.keyboard.up('Space');
    const stepsThen = s.steps;
    s = await until(page, `window.tumble.steps > ${stepsThen + 10}`);
    assert.ok(s.steps > stepsThen, 'still stepping after Space');
    assert.deepEqual(errors, [], 'no console errors');
    await page.close();
  });
});

describe('web build, a panic', () => {
  let browser;
  before(async () => {
    browser = await chromium.launch({ executablePath: CHROMIUM, args: BASE_FLAGS, headless: true });
  });
  after(async () => {
    await browser?.close();
  });

  test('shows its message over the page and in the console', { timeout: TEST_TIMEOUT }, async () => {
    const { page, errors } = await openPage(browser, `${URL}?scene=pyramid`);
    assert.equal(await page.locator('#tumble-error').isVisible(), false, 'no error box before');
    // The module's test hook panics in Rust (the same instance the page runs).
    await page.evaluate(async () => {
      const pkg = await import(new URL('pkg/tumble.js', location.href).href);
      try {
        pkg.testPanic();
      } catch {
        // The panic aborts the call: WebAssembly's `unreachable`.
      }
    });
    const box = page.locator('#tumble-error');
    assert.equal(await box.isVisible(), true, 'the error box shows');
    assert.match(await box.textContent(), /tumble stopped: .*a test asked for this panic/s);
    assert.ok(errors.some((e) => e.includes('a test asked for this panic')), 'and the console has it');
    await page.close();
  });
});

describe('web build, not cross-origin isolated', { skip: !URL_NOT_ISOLATED && 'TUMBLE_URL_NOT_ISOLATED is not set' }, () => {
  let browser;
  before(async () => {
    browser = await chromium.launch({ executablePath: CHROMIUM, args: BASE_FLAGS, headless: true });
  });
  after(async () => {
    await browser?.close();
  });

  test('runs on one thread and says why', { timeout: TEST_TIMEOUT }, async () => {
    const { page, errors } = await openPage(browser, `${URL_NOT_ISOLATED}?scene=pyramid&threads=2`);
    const first = await until(page, 'window.tumble.state === "Simulation"');
    assert.equal(first.cross_origin_isolated, false);
    assert.equal(first.threads_enabled, false);
    assert.equal(first.threads, 1);
    assert.equal(first.max_threads, 1);
    assert.match(first.threads_note ?? '', /not cross-origin isolated/);
    const later = await until(page, `window.tumble.steps >= ${first.steps + 30}`);
    assert.ok(later.steps > first.steps, 'it steps');
    assert.deepEqual(errors, [], 'no console errors');
    await page.close();
  });
});
