// The viewer in a real browser: headless Chromium (Debian's, driven by npm playwright-core)
// loads the page `isoforge view` serves for two generated .glb files (the default codec and
// meshopt) and the page must report the triangle count and bounding box isoforge computes, and
// draw something where the model is. The screenshot stays in OUT_DIR/viewer.png.
// Usage: node browser_test.mjs ISOFORGE DATA_DIR OUT_DIR [CHROMIUM]
import { spawn, execFileSync } from 'node:child_process';
import { existsSync, mkdirSync, mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { chromium } from 'playwright-core';

const [isoforge, data, out, chromiumPath = '/usr/bin/chromium'] = process.argv.slice(2);
if (!isoforge || !data || !out) {
  console.error('usage: node browser_test.mjs ISOFORGE DATA_DIR OUT_DIR [CHROMIUM]');
  process.exit(2);
}
let failures = 0;
const fail = (what) => { console.log(`FAIL: ${what}`); failures += 1; };
if (!existsSync(chromiumPath)) {
  console.log(`FAIL: no Chromium at ${chromiumPath}: install Debian's chromium (make deps)`);
  process.exit(1);
}
rmSync(out, { recursive: true, force: true });
mkdirSync(out, { recursive: true });

// The inputs, written by isoforge, and what isoforge's own reader says they hold.
const run = (...args) => execFileSync(isoforge, args, { encoding: 'utf8', stdio: ['ignore', 'pipe', 'pipe'] });
const files = [
  { name: 'fran', input: path.join(data, 'fran_cut.vtk'), args: [] },
  { name: 'bunny', input: path.join(data, 'bunny.ply'),
    args: ['--codec', 'meshopt', '--color-by', 'intensity', '--colormap', 'plasma'] },
];
let triangles = 0;
const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
for (const f of files) {
  f.glb = path.join(out, `${f.name}.glb`);
  run('-q', 'convert', f.input, f.glb, ...f.args);
  const info = run('info', f.glb);
  const cells = info.match(/^cells: \d+ \((\d+) triangle\)/m);
  const bounds = info.match(/^bounds: x \[(\S+), (\S+)\]\s+y \[(\S+), (\S+)\]\s+z \[(\S+), (\S+)\]/m);
  if (!cells || !bounds) throw new Error(`unexpected isoforge info output:\n${info}`);
  triangles += Number(cells[1]);
  for (let k = 0; k < 3; ++k) {
    lo[k] = Math.min(lo[k], Number(bounds[1 + 2 * k]));
    hi[k] = Math.max(hi[k], Number(bounds[2 + 2 * k]));
  }
}
const diagonal = Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);

// Serve them.
const server = spawn(isoforge, ['view', ...files.map((f) => f.glb), '--port', '0'],
                     { stdio: ['ignore', 'pipe', 'pipe'] });
let serverErr = '';
server.stderr.on('data', (d) => { serverErr += d; });
const exited = new Promise((resolve) => server.on('exit', (code, signal) => resolve({ code, signal })));
const url = await new Promise((resolve, reject) => {
  let text = '';
  server.stdout.on('data', (d) => {
    text += d;
    const m = text.match(/^(http:\/\/127\.0\.0\.1:\d+\/)$/m);
    if (m) resolve(m[1]);
  });
  exited.then(() => reject(new Error(`isoforge view exited before printing a URL: ${serverErr}`)));
  setTimeout(() => reject(new Error('isoforge view printed no URL within 60 s')), 60000);
});
console.log(`serving at ${url}`);

const profile = mkdtempSync(path.join(tmpdir(), 'isoforge-chromium-'));
let context;
try {
  context = await chromium.launchPersistentContext(profile, {
    executablePath: chromiumPath,
    headless: true,
    viewport: { width: 800, height: 600 },
    args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
           '--disable-background-networking', '--disable-component-update', '--disable-sync'],
  });
  const page = await context.newPage();
  const consoleErrors = [];
  page.on('console', (m) => { if (m.type() === 'error') consoleErrors.push(m.text()); });
  page.on('pageerror', (e) => consoleErrors.push(String(e)));
  // Nothing may come from anywhere but the isoforge server.
  const foreign = [];
  page.on('request', (r) => { if (!r.url().startsWith(url) && !r.url().startsWith('data:') && !r.url().startsWith('blob:')) foreign.push(r.url()); });
  await page.goto(url);
  await page.waitForFunction(() => window.isoforgeViewer && window.isoforgeViewer.ready, null,
                             { timeout: 120000 });
  const state = await page.evaluate(() => {
    const s = window.isoforgeViewer;
    return { error: s.error, triangles: s.triangles, bbox: s.bbox, meshes: s.meshes,
             legends: s.legends.map((l) => `${l.mesh}:${l.array}:${l.colormap}:${l.range}`),
             legendBars: document.querySelectorAll('#legends .legend canvas').length };
  });
  if (state.error) fail(`the page reports an error: ${state.error}`);
  if (consoleErrors.length) fail(`console errors: ${consoleErrors.join(' | ')}`);
  if (foreign.length) fail(`requests outside the server: ${foreign.join(', ')}`);
  if (state.triangles !== triangles) fail(`page shows ${state.triangles} triangles, isoforge counts ${triangles}`);
  // The coloured bunny carries a legend (plasma over intensity's range 0 .. 0.5), drawn once.
  if (state.legends.join('|') !== 'bunny:intensity:plasma:0,0.5' || state.legendBars !== 1) {
    fail(`legends ${JSON.stringify(state.legends)} (${state.legendBars} drawn), expected bunny's plasma legend`);
  }
  const names = state.meshes.map((m) => m.name).join(',');
  if (names !== 'fran_cut,bunny') fail(`mesh names '${names}', expected 'fran_cut,bunny' (the inputs' names)`);
  if (!state.bbox) {
    fail('no bounding box');
  } else {
    for (let k = 0; k < 3; ++k) {
      const dmin = Math.abs(state.bbox.min[k] - lo[k]), dmax = Math.abs(state.bbox.max[k] - hi[k]);
      // isoforge info prints 6 significant digits; the page has the file's float32 values.
      if (dmin > 1e-5 * diagonal || dmax > 1e-5 * diagonal) {
        fail(`bbox axis ${k}: page [${state.bbox.min[k]}, ${state.bbox.max[k]}], isoforge [${lo[k]}, ${hi[k]}]`);
      }
    }
  }
  const region = await page.evaluate(() => window.isoforgeViewer.modelRegion());
  const pixels = await page.evaluate((r) => window.isoforgeViewer.regionPixels(r), region);
  const covered = pixels.differing / pixels.total;
  console.log(`model region ${JSON.stringify(region)}: ${pixels.differing} of ${pixels.total} pixels differ from the background`);
  if (pixels.total < 10000) fail(`the model's region is only ${pixels.total} pixels`);
  if (!(covered > 0.1)) fail(`the canvas is blank where the model is (${(100 * covered).toFixed(2)} % drawn)`);
  // Hiding both meshes must leave the region blank: the pixels came from the model.
  await page.locator('#meshes input[type=checkbox]').nth(0).uncheck();
  await page.locator('#meshes input[type=checkbox]').nth(1).uncheck();
  const hidden = await page.evaluate((r) => window.isoforgeViewer.regionPixels(r), region);
  if (hidden.differing !== 0) fail(`${hidden.differing} pixels differ from the background with every mesh hidden`);
  await page.locator('#meshes input[type=checkbox]').nth(0).check();
  await page.locator('#meshes input[type=checkbox]').nth(1).check();
  await page.screenshot({ path: path.join(out, 'viewer.png') });
  console.log(`screenshot: ${path.join(out, 'viewer.png')}`);
} catch (e) {
  fail(String(e && e.stack ? e.stack : e));
} finally {
  if (context) await context.close();
  rmSync(profile, { recursive: true, force: true });
}

// Ctrl-C stops the server cleanly: exit status 0.
server.kill('SIGINT');
const { code, signal } = await exited;
if (code !== 0) fail(`isoforge view ended with ${code === null ? `signal ${signal}` : `status ${code}`}: ${serverErr}`);
if (!/stopped after \d+ request/.test(serverErr)) fail(`isoforge view did not report stopping: ${serverErr}`);

if (failures) {
  console.log(`${failures} browser check(s) failed`);
  process.exit(1);
}
console.log(`browser test passed: ${triangles} triangles, bbox and pixels as expected`);
