// The core client in a real browser: the harness page (tests/browser/harness) runs CoreClient
// with the real module worker and the built wasm in Debian's chromium (playwright-core).
// Checks: the SurFCo example reconstructs through the worker with frames and a final result
// that agree, cancel works with no late frames, file errors arrive as data with file and line.
import assert from 'node:assert/strict';
import { createReadStream, existsSync, readFileSync, statSync } from 'node:fs';
import { createServer } from 'node:http';
import { extname, join, normalize } from 'node:path';
import { after, before, describe, it } from 'node:test';
import { build } from 'vite';
import { chromium } from 'playwright-core';
import { ROOT, SURFCO, loadWasm } from '../node/helpers.mjs';

const OUT = join(ROOT, '.cache', 'harness');
const CHROMIUM = process.env.CHROMIUM_PATH || '/usr/bin/chromium';
const FLAGS = ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
  '--disable-background-networking', '--disable-component-update', '--disable-sync'];
const TYPES = { '.html': 'text/html', '.js': 'text/javascript', '.wasm': 'application/wasm', '.css': 'text/css' };

let server;
let browser;
let page;
let origin;
const foreign = [];

before(async () => {
  assert.ok(existsSync(CHROMIUM), `${CHROMIUM} missing: run scripts/setup.sh`);
  await build({ configFile: join(ROOT, 'tests', 'browser', 'vite.config.mjs') });
  server = createServer((req, res) => {
    const path = normalize(decodeURIComponent(new URL(req.url, 'http://x').pathname)).replace(/^(\.\.[/\\])+/, '');
    let file = join(OUT, path);
    if (existsSync(file) && statSync(file).isDirectory()) file = join(file, 'index.html');
    if (!file.startsWith(OUT) || !existsSync(file)) {
      res.writeHead(404).end();
      return;
    }
    res.writeHead(200, { 'content-type': TYPES[extname(file)] ?? 'application/octet-stream' });
    createReadStream(file).pipe(res);
  });
  await new Promise((r) => server.listen(0, '127.0.0.1', r));
  origin = `http://127.0.0.1:${server.address().port}`;
  browser = await chromium.launch({ executablePath: CHROMIUM, headless: true, args: FLAGS });
  page = await browser.newPage();
  page.on('request', (r) => {
    if (!r.url().startsWith(origin) && !r.url().startsWith('data:') && !r.url().startsWith('blob:')) foreign.push(r.url());
  });
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  await page.goto(`${origin}/index.html`);
  await page.waitForFunction(() => document.getElementById('status')?.textContent === 'ready', null, { timeout: 20000 });
  assert.deepEqual(errors, []);
});

after(async () => {
  await browser?.close();
  server?.close();
});

describe('CoreClient in chromium', () => {
  it('serves the Rust parameter schema', async () => {
    const wasm = await loadWasm();
    const { schema, version } = await page.evaluate(() => window.harness.schema());
    assert.deepEqual(schema, JSON.parse(wasm.schema_json()));
    assert.equal(version, wasm.version());
  });

  it('reconstructs the SurFCo example through the worker', async () => {
    const text = readFileSync(SURFCO(), 'utf8');
    const s = await page.evaluate(([t]) => window.harness.run('surfco.csv', t, null, {}), [text]);
    console.log(`chromium worker: SurFCo done in ${s.msToDone.toFixed(0)} ms (load + run + transfer), first frame after ` +
      `${s.msToFirstFrame.toFixed(0)} ms, ${s.frames} frames shown, longest gap between frames ${s.maxFrameGapMs.toFixed(0)} ms; ${s.vertices} vertices, mean ${s.mean.toFixed(3)} mm, ` +
      `max ${s.max.toFixed(3)} mm, ${s.volumeMl.toFixed(2)} ml`);
    assert.equal(s.watertight, true);
    assert.ok(s.mean <= 1.0, `mean ${s.mean} mm`);
    assert.equal(s.finalFrameDone, true, 'the last frame handed over is the final one');
    assert.equal(s.positionsMatchResult, true, 'final frame positions equal the result');
    assert.ok(s.frames >= 5, `only ${s.frames} frames shown`);
    // The product target is 2 s on an idle machine (issue 3); a shared test machine gets 3x.
    assert.ok(s.msToDone < 6000, `took ${s.msToDone} ms`);
    assert.deepEqual(foreign, [], 'no request may leave the origin');
  });

  it('cancels a run without late frames and runs again', async () => {
    const text = readFileSync(SURFCO(), 'utf8');
    const r = await page.evaluate(([t]) => window.harness.cancelThenRun('surfco.csv', t, 3), [text]);
    assert.equal(r.firstError, 'cancelled');
    assert.equal(r.lateFrames, 0);
    assert.ok(r.secondVertices > 100, `${r.secondVertices} vertices`);
  });

  it('reports a bad file with its name and line', async () => {
    const e = await page.evaluate(() => window.harness.loadError('bad.csv', 'contour,x,y,z\nc1,1,2,3\nc1,1,two,3\n'));
    assert.equal(e.code, 'parse');
    assert.equal(e.line, 3);
    assert.equal(e.file, 'bad.csv');
  });
});
