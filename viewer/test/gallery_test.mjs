// The figure gallery in a real browser: `isoforge view DIR` serves the directory written by
// `isoforge figures`, headless Chromium opens its index.html, every figure's picture must load,
// and each "open in the viewer" link must open the viewer on that figure's meshes without an
// error or a request outside the server. Prints "gallery test passed: ..." or FAIL lines.
// Usage: node gallery_test.mjs ISOFORGE DIR [CHROMIUM]
import { spawn } from 'node:child_process';
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { chromium } from 'playwright-core';

const [isoforge, dir, chromiumPath = '/usr/bin/chromium'] = process.argv.slice(2);
if (!isoforge || !dir) {
  console.error('usage: node gallery_test.mjs ISOFORGE DIR [CHROMIUM]');
  process.exit(2);
}
let failures = 0;
const fail = (what) => { console.log(`FAIL: ${what}`); failures += 1; };

const server = spawn(isoforge, ['view', dir, '--port', '0'], { stdio: ['ignore', 'pipe', 'pipe'] });
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
  // unref: the timer must not keep node running once the URL came.
  setTimeout(() => reject(new Error('isoforge view printed no URL within 60 s')), 60000).unref();
});

const profile = mkdtempSync(path.join(tmpdir(), 'isoforge-gallery-'));
let context;
let opened = 0, pictures = 0;
try {
  context = await chromium.launchPersistentContext(profile, {
    executablePath: chromiumPath, headless: true, viewport: { width: 1000, height: 800 },
    args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
           '--disable-background-networking', '--disable-component-update', '--disable-sync'],
  });
  const page = await context.newPage();
  const errors = [];
  const foreign = [];
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('request', (r) => { if (!r.url().startsWith(url) && !r.url().startsWith('data:') && !r.url().startsWith('blob:')) foreign.push(r.url()); });
  await page.goto(url);
  // Every picture decoded (lazy images: scrolled into view first).
  const images = await page.locator('.fig img').all();
  for (const img of images) {
    await img.scrollIntoViewIfNeeded();
    const ok = await img.evaluate((el) => el.decode().then(() => el.naturalWidth > 0, () => false));
    if (!ok) fail(`picture ${await img.getAttribute('src')} does not load`);
    else pictures += 1;
  }
  if (images.length === 0) fail('the gallery shows no picture');
  const links = await page.locator('.fig a.viewer:not(:has(img))').evaluateAll(
    (as) => as.map((a) => ({ href: a.href, fig: a.closest('.fig').id })));
  if (links.length === 0) fail('the gallery has no viewer link');
  for (const link of links) {
    errors.length = 0;
    await page.goto(link.href);
    await page.waitForFunction(() => window.isoforgeViewer && window.isoforgeViewer.ready, null,
                               { timeout: 120000 });
    const s = await page.evaluate(() => ({ error: window.isoforgeViewer.error,
                                           meshes: window.isoforgeViewer.meshes.length }));
    if (s.error || errors.length) fail(`${link.fig}: the viewer reports ${s.error || errors.join(' | ')}`);
    else if (s.meshes === 0) fail(`${link.fig}: the viewer shows no mesh`);
    else opened += 1;
  }
  if (foreign.length) fail(`requests outside the server: ${foreign.join(', ')}`);
} catch (e) {
  fail(String(e && e.stack ? e.stack : e));
} finally {
  if (context) await context.close();
  rmSync(profile, { recursive: true, force: true });
}
server.kill('SIGINT');
const { code } = await exited;
if (code !== 0) fail(`isoforge view ended with status ${code}: ${serverErr}`);
if (failures) {
  console.log(`${failures} gallery check(s) failed`);
  process.exit(1);
}
console.log(`gallery test passed: ${pictures} pictures, ${opened} viewer links opened`);
