// The pictures of `isoforge figures`: serves the figure directory DIR (written by isoforge, with
// the viewer copied to DIR/viewer/) on 127.0.0.1, opens each figure's viewer link in headless
// Chromium (Debian's, driven by npm playwright-core, WebGL through SwiftShader) with the side
// panel hidden, and saves the canvas as DIR/STEM/STEM.png. Prints one line per figure on stdout:
//   rendered STEM <fraction of the model's region drawn>
//   failed STEM <why>
// Usage: node render_figures.mjs DIR [CHROMIUM] [WIDTH HEIGHT]
import { createServer } from 'node:http';
import { mkdtempSync, readFileSync, rmSync, existsSync, statSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { chromium } from 'playwright-core';

const [dir, chromiumPath = '/usr/bin/chromium', width = '800', height = '600'] = process.argv.slice(2);
if (!dir) {
  console.error('usage: node render_figures.mjs DIR [CHROMIUM] [WIDTH HEIGHT]');
  process.exit(2);
}
const root = path.resolve(dir);
const figures = JSON.parse(readFileSync(path.join(root, 'figures.json'), 'utf8'));

const types = {
  '.html': 'text/html', '.js': 'text/javascript', '.mjs': 'text/javascript', '.css': 'text/css',
  '.json': 'application/json', '.glb': 'model/gltf-binary', '.wasm': 'application/wasm',
  '.png': 'image/png',
};
// Files under root only: the decoded path must stay inside it.
const server = createServer((req, res) => {
  const url = new URL(req.url, 'http://localhost');
  const file = path.resolve(root, '.' + decodeURIComponent(url.pathname));
  if (!file.startsWith(root + path.sep) || !existsSync(file) || !statSync(file).isFile()) {
    res.writeHead(404);
    res.end();
    return;
  }
  res.writeHead(200, { 'Content-Type': types[path.extname(file)] || 'application/octet-stream' });
  res.end(readFileSync(file));
});
await new Promise((resolve) => server.listen(0, '127.0.0.1', resolve));
const base = `http://127.0.0.1:${server.address().port}/`;

const profile = mkdtempSync(path.join(tmpdir(), 'isoforge-figures-'));
let context;
let failures = 0;
try {
  context = await chromium.launchPersistentContext(profile, {
    executablePath: chromiumPath,
    headless: true,
    viewport: { width: Number(width), height: Number(height) },
    deviceScaleFactor: 1,
    args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
           '--disable-background-networking', '--disable-component-update', '--disable-sync'],
  });
  const page = await context.newPage();
  const errors = [];
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('pageerror', (e) => errors.push(String(e)));
  for (const fig of figures) {
    errors.length = 0;
    try {
      await page.goto(`${base}viewer/index.html?${fig.query}&panel=0`);
      await page.waitForFunction(() => window.isoforgeViewer && window.isoforgeViewer.ready, null,
                                 { timeout: 120000 });
      const state = await page.evaluate(() => ({ error: window.isoforgeViewer.error,
                                                 meshes: window.isoforgeViewer.meshes.length }));
      if (state.error || errors.length) throw new Error(state.error || errors.join(' | '));
      if (state.meshes === 0) throw new Error('the page shows no mesh');
      const region = await page.evaluate(() => window.isoforgeViewer.modelRegion());
      const pixels = await page.evaluate((r) => window.isoforgeViewer.regionPixels(r), region);
      const drawn = pixels.differing / Math.max(pixels.total, 1);
      await page.locator('#view canvas').screenshot({ path: path.join(root, fig.stem, `${fig.stem}.png`) });
      console.log(`rendered ${fig.stem} ${(100 * drawn).toFixed(1)}% drawn`);
    } catch (e) {
      failures += 1;
      console.log(`failed ${fig.stem} ${String(e && e.message ? e.message : e).split('\n')[0]}`);
    }
  }
} catch (e) {
  console.error(`render_figures: ${e && e.stack ? e.stack : e}`);
  failures += 1;
} finally {
  if (context) await context.close();
  rmSync(profile, { recursive: true, force: true });
  server.close();
}
process.exit(failures ? 1 : 0);
