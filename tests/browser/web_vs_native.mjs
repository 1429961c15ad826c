// The measurement of docs/bench/web.md (not a test: `cargo xtask test` does not run it).
//
//   node web_vs_native.mjs BUNDLE TUMBLE_BENCH TUMBLE REPEATS SCENE:THREADS ...
//
// BUNDLE: a release web bundle (`cargo xtask web --release` writes target/web-bundle/), served
// here with the cross-origin isolation headers; TUMBLE_BENCH and TUMBLE: the native
// `tumble-bench` and viewer of the same commit. For each repeat and case, in turn: native
// `?bench=` (`tumble-bench run SCENE --threads N --steps 300`), web `?bench=` (the page
// `?bench=SCENE&threads=N&steps=300&warmup=300`: the timed steps run compiled code), the
// native viewer (300 frames under Xvfb), the web viewer (the page
// `?scene=SCENE&threads=N&warmup=300`, `window.tumble.step_ms_mean` 10 s after its first
// frames). One JSON line per case on stdout, all of them in
// web_vs_native_TIME.json. Needs `npm ci` in this folder, chromium and xvfb-run.
import http from 'node:http';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { execFileSync } from 'node:child_process';
import { chromium } from 'playwright-core';

const [bundle, bench, viewer, repeats, ...cases] = process.argv.slice(2);
const types = { '.html': 'text/html', '.js': 'text/javascript', '.wasm': 'application/wasm', '.css': 'text/css' };
const server = http.createServer((req, res) => {
  const url = new URL(req.url, 'http://x');
  let file = path.join(bundle, decodeURIComponent(url.pathname));
  if (fs.existsSync(file) && fs.statSync(file).isDirectory()) file = path.join(file, 'index.html');
  if (!fs.existsSync(file)) { res.writeHead(404); res.end(); return; }
  res.writeHead(200, {
    'Content-Type': types[path.extname(file)] ?? 'application/octet-stream',
    'Cross-Origin-Opener-Policy': 'same-origin',
    'Cross-Origin-Embedder-Policy': 'require-corp',
    'Cross-Origin-Resource-Policy': 'same-origin',
  });
  fs.createReadStream(file).pipe(res);
});
await new Promise((r) => server.listen(0, '127.0.0.1', r));
const port = server.address().port;
const FLAGS = ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
  '--disable-background-networking', '--disable-component-update', '--disable-sync', '--enable-unsafe-swiftshader'];
const load = () => fs.readFileSync('/proc/loadavg', 'utf8').split(' ').slice(0, 3).join(' ');
async function web(query, viewerMode) {
  const browser = await chromium.launch({ executablePath: '/usr/bin/chromium', args: FLAGS, headless: true });
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  await page.goto(`http://127.0.0.1:${port}/?${query}`);
  let out;
  if (viewerMode) {
    await page.waitForFunction(() => window.tumble && window.tumble.frames > 2, null, { timeout: 300000, polling: 200 });
    await new Promise((r) => setTimeout(r, 10000));
    out = await page.evaluate(() => ({ step_ms_mean: window.tumble.step_ms_mean, frames: window.tumble.frames, steps: window.tumble.steps }));
  } else {
    await page.waitForFunction(() => window.tumble_bench !== undefined, null, { timeout: 300000, polling: 200 });
    out = await page.evaluate(() => window.tumble_bench);
  }
  await browser.close();
  return out;
}
function nativeViewer(scene, threads) {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'tv-'));
  const stats = path.join(dir, 'stats.json');
  execFileSync('xvfb-run', ['-a', '-s', '-screen 0 1280x800x24', viewer, '--scene', scene, '--threads', threads, '--frames', '300', '--stats', stats],
    { env: { ...process.env, XDG_RUNTIME_DIR: dir, TUMBLE_CONFIG_DIR: dir }, stdio: 'ignore', timeout: 300000 });
  return JSON.parse(fs.readFileSync(stats, 'utf8'));
}
const rows = [];
for (let r = 0; r < Number(repeats); r++) {
  for (const c of cases) {
    const [scene, threads] = c.split(':');
    const before = load();
    const nb = JSON.parse(execFileSync(bench, ['run', scene, '--threads', threads, '--steps', '300']));
    const wb = await web(`bench=${scene}&threads=${threads}&steps=300&warmup=300`, false);
    const nv = nativeViewer(scene, threads);
    const wv = await web(`scene=${scene}&threads=${threads}&warmup=300`, true);
    const row = { repeat: r, scene, threads: Number(threads), load_before: before, load_after: load(),
      native_bench: nb.profile.step_ms_mean, web_bench: wb.step_ms_mean, native_hash: nb.state_hash, web_hash: wb.state_hash,
      isolated: wb.cross_origin_isolated, native_viewer: nv.step_ms_mean, web_viewer: wv.step_ms_mean, web_viewer_steps: wv.steps, web_viewer_frames: wv.frames };
    rows.push(row);
    console.log(JSON.stringify(row));
  }
}
fs.writeFileSync(`web_vs_native_${Date.now()}.json`, JSON.stringify(rows, null, 1));
server.close();
