// Browser end-to-end test (dist/, Debian's chromium) of the contours the core leaves out (session
// 14: specks and strays). The bundled patient 1 ED with a 2 mm, 3-point loop one slice past the
// base (built here, tests/e2e/speck.mjs): the load-time warning names it, the run leaves it out
// and the result panel says so ("Left out: 1 contour (speck)" with its id), the viewer draws it
// grey and dashed with a key and a hover read-out, and ticking "Keep specks and strays" runs again
// with it used (one contour more, the row gone, the warning line says it is used), in the URL, the
// exports and a session.
import { describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { download as downloadFrom, gotoEmpty, ROOT, runAndWait, SHOTS } from './lib.mjs';
import { appForFile } from './perFile.mjs';
import { withSpeck } from './speck.mjs';

let server;
let page;
appForFile({ goto: false }, (app) => ({ server, page } = app));

const speck = withSpeck(readFileSync(join(ROOT, 'public', 'samples', 'patient1-ED.csv'), 'utf8'));
const NAME = 'patient1-ED-speck.csv';
const drop = () => page.setInputFiles('[data-testid=file-input]', { name: NAME, mimeType: 'text/csv', buffer: Buffer.from(speck.csv) });
const dataset = () => page.locator('[data-testid=result]').evaluate((el) => ({ ...el.dataset }));
const contourCount = () => page.evaluate(() => window.heartmesh.currentResult().contours.length);
const keyCount = () => page.getAttribute('[data-testid=set-aside-legend]', 'data-count');

describe('contours left out in the browser', () => {
  it('a speck past the base: warned, left out, listed, drawn grey; "Keep specks and strays" uses it', async () => {
    await gotoEmpty(page, server.url);
    assert.equal(await page.isChecked('[data-testid=param-keep-specks]'), false, 'off by default');
    assert.match((await page.textContent('label[for=param-keep-specks]')) ?? '', /^Keep specks and strays$/);
    await runAndWait(page, drop, 120000);
    assert.equal(await page.inputValue('[data-testid=surface-picker]'), 'LV_ENDO');

    // The load-time warning names it with its line.
    const warning = (await page.textContent('#slot-warnings')) ?? '';
    assert.ok(warning.includes(`contour "${speck.id}" (line ${speck.line}, 2.0 mm around`), warning);
    assert.match(warning, /is a speck, not a section of the cavity; it is left out of the reconstruction/);

    // The result panel's line, with the id; the data attribute counts it.
    const left = await dataset();
    assert.equal(left.setAside, '1');
    assert.equal(await page.textContent('[data-testid=result-set-aside]'), `1 contour (speck) · ${speck.id}`);
    assert.equal(await page.textContent('[data-testid=result-set-aside] >> xpath=preceding-sibling::dt[1]'), 'Left out');
    assert.match((await page.getAttribute('[data-testid=result-set-aside]', 'title')) ?? '', new RegExp(`"${speck.id}" \\(line ${speck.line}\\): a speck, 2\\.0 mm around`));
    const leftContours = await contourCount();

    // Drawn: the key counts the contours left out on screen and names it.
    assert.equal(await keyCount(), '1');
    assert.equal(await page.isVisible('[data-testid=set-aside-legend]'), true);
    assert.equal(await page.textContent('[data-testid=set-aside-row]'), `left out: speck · ${speck.id}`);
    // The hover read-out names it where it is drawn, after how far the mesh built without it passes
    // the point (one of its points' figures: the mesh does not follow it, 1.91 to 1.96 mm).
    const { at, far } = await page.evaluate(() => {
      const r = window.heartmesh.currentResult();
      const p = r.setAsidePoints;
      return { at: window.heartmeshViewer.screenPosition(p[0], p[1], p[2]), far: [...r.setAsidePointDistances] };
    });
    const canvas = await page.locator('[data-testid=viewport-canvas]').boundingBox();
    await page.mouse.move(canvas.x + at.x, canvas.y + at.y);
    await page.waitForSelector('[data-testid=hover-readout]:not([hidden])', { timeout: 10000 });
    const hover = (await page.textContent('[data-testid=hover-readout]')) ?? '';
    const figure = new RegExp(`^\\s*(\\d+\\.\\d\\d) mm to mesh \\(built without it\\) · left out: speck · ${speck.id}\\(`).exec(hover);
    assert.ok(figure && far.some((d) => d.toFixed(2) === figure[1]), `${hover} (its points: ${far.join(', ')} mm)`);
    await page.mouse.move(0, 0);
    await page.screenshot({ path: join(SHOTS, 'left-out-speck.png') });

    // Exports record the option and what was left out.
    const json = JSON.parse((await downloadFrom(page, 'export-json')).bytes.toString('utf8'));
    assert.equal(json.keep_specks, false);
    assert.deepEqual(json.result.set_aside.map((s) => [s.id, s.line, s.reason]), [[speck.id, speck.line, 'speck']]);

    // Kept: a new run with it, one contour more, no line, nothing drawn grey; the warning says it is used.
    await runAndWait(page, () => page.check('[data-testid=param-keep-specks]'), 120000);
    assert.match(page.url(), /keep_specks=1/);
    const kept = await dataset();
    assert.equal(kept.setAside, '0');
    assert.equal(await page.locator('[data-testid=result-set-aside]').count(), 0, 'no "Left out" row when kept');
    assert.equal(await contourCount(), leftContours + 1);
    assert.ok(await page.evaluate((id) => window.heartmesh.currentResult().contours.some((c) => c.id === id), speck.id));
    assert.equal(await keyCount(), '0');
    assert.equal(await page.isVisible('[data-testid=set-aside-legend]'), false);
    assert.notEqual(kept.vertices, left.vertices, 'another mesh');
    assert.match((await page.textContent('#slot-warnings')) ?? '', /Keep specks and strays is on: the contours named above as left out are used in the reconstruction$/);
    console.log(`# speck: left out ${left.vertices} vertices, mean ${Number(left.meanMm).toFixed(3)} mm; kept ${kept.vertices} vertices, mean ${Number(kept.meanMm).toFixed(3)} mm`);

    // The exports and a session carry the option; the session opens again with it ticked.
    const obj = (await downloadFrom(page, 'export-obj')).bytes.toString('utf8');
    assert.match(obj, /keep_specks=true/);
    const session = await downloadFrom(page, 'export-session');
    assert.equal(JSON.parse(session.bytes.toString('utf8')).parameters.keep_specks, true);
    await gotoEmpty(page, server.url);
    assert.equal(await page.isChecked('[data-testid=param-keep-specks]'), false);
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', { name: session.name, mimeType: 'application/json', buffer: session.bytes }), 120000);
    assert.equal(await page.isChecked('[data-testid=param-keep-specks]'), true);
    assert.equal(await contourCount(), leftContours + 1);
    // Unticked again: left out once more.
    await runAndWait(page, () => page.uncheck('[data-testid=param-keep-specks]'), 120000);
    assert.doesNotMatch(page.url(), /keep_specks/);
    assert.equal((await dataset()).setAside, '1');
    assert.equal(await keyCount(), '1');
  });

  it("another surface's run does not repeat the LV speck's warning (session 18)", async () => {
    await gotoEmpty(page, server.url);
    await runAndWait(page, drop, 120000);
    const speckLine = `contour "${speck.id}" (line ${speck.line}`;
    assert.ok(((await page.textContent('#slot-warnings')) ?? '').includes(speckLine));
    await runAndWait(page, () => page.selectOption('[data-testid=surface-picker]', 'RV_ENDO'), 120000);
    assert.equal((await dataset()).setAside, '0', 'nothing of the RV left out');
    assert.equal(await page.isVisible('#slot-warnings'), false, (await page.textContent('#slot-warnings')) ?? '');
    await page.screenshot({ path: join(SHOTS, 'surface-warnings-rv.png') });
    await runAndWait(page, () => page.selectOption('[data-testid=surface-picker]', 'LV_ENDO'), 120000);
    assert.ok(((await page.textContent('#slot-warnings')) ?? '').includes(speckLine), 'back on the LV: named again');
    assert.equal((await dataset()).setAside, '1');
  });
});
