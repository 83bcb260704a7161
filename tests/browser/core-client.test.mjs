// The core client in a real browser: the harness page (tests/browser/harness) runs CoreClient
// with the real module worker and the built wasm in Debian's chromium (playwright-core).
// Checks: the SurFCo example reconstructs through the worker with frames and a final result
// that agree, cancel works with no late frames, file errors arrive as data with file and line.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { after, before, describe, it } from 'node:test';
import { SURFCO, loadWasm } from '../node/helpers.mjs';
import { openHarness } from './lib.mjs';

let h;
let page;
let foreign;

before(async () => {
  h = await openHarness();
  page = h.page;
  foreign = h.foreign;
  assert.deepEqual(h.pageErrors, []);
});

after(async () => {
  await h?.close();
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
    // Time is measured by `npm run bench:core-browser` (medians, issue 3's 2 s target), not
    // asserted here: a shared test machine's load would make a bound flaky or meaningless.
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
