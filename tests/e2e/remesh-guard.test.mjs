// Browser end-to-end test (dist/, Debian's chromium) of the remeshes the core skips because each
// would wreck the surface (`pipeline::remesh_guard`). Smoothing settings that shrink the surface
// away (1000 sweeps of Laplacian + twicing, no affine correction) used to end inside out (-249 ml
// on SurFCo); now every remesh is skipped and the result panel says so in a warning row, with the
// core's sentence as its tooltip, and the default settings bring the row away again. Same figures
// as `heartmesh reconstruct patient2-ED.csv --surface LV_ENDO --smoothing-method laplacian-twicing
// --smoothing-iterations 1000`: 11 remeshes skipped (the tube's and every 20 iterations to 200),
// 302 vertices, 198.4 ml.
import { describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { gotoEmpty, readResult, resultVolume, runAndWait, SHOTS } from './lib.mjs';
import { appForFile } from './perFile.mjs';

let server;
let page;
const pageErrors = [];
appForFile({ goto: false, onPageError: (m) => pageErrors.push(m) }, (app) => ({ server, page } = app));

describe('remeshes that would wreck the surface', () => {
  it('are skipped and named in the result panel; the default settings remesh again', async () => {
    await page.setViewportSize({ width: 1280, height: 720 });
    await gotoEmpty(page, `${server.url}?smoothing_method=laplacian-twicing&smoothing_iterations=1000`);
    assert.equal(await page.inputValue('[data-testid=param-smoothing-method]'), 'laplacian-twicing');
    await runAndWait(page, () => page.click('[data-testid=sample-patient2-ED]'), 120000);
    const row = page.locator('[data-testid=result-skipped-remeshes]');
    assert.equal(await row.textContent(), '11 skipped');
    assert.equal(await row.getAttribute('class'), 'warn');
    const title = await row.getAttribute('title');
    assert.match(title, /^11 remeshes \(iterations 0 \(the initial tube\), 20, 40, 60, 80, 100, 120, 140, 160, 180, 200\) were skipped, the first because it would have changed the enclosed volume from /);
    assert.match(title, /check the contours and the settings$/);
    assert.equal(await page.getAttribute('[data-testid=result]', 'data-skipped-remeshes'), '11');
    const skipped = await readResult(page);
    // The unremeshed tube, deformed: no remesh ever refined it.
    assert.equal(skipped.vertices, 302);
    assert.ok(skipped.meanMm < 0.5, `mean ${skipped.meanMm} mm`);
    const volume = await resultVolume(page);
    assert.ok(Math.abs(volume - 198.4) < 1, `volume ${volume} ml`);
    await page.mouse.move(0, 0);
    await page.screenshot({ path: join(SHOTS, 'remeshes-skipped.png') });
    // The default smoothing remeshes every time: no row, no stale figure.
    await runAndWait(page, () => page.click('[data-testid=reset-params]'));
    assert.equal(await page.locator('[data-testid=result-skipped-remeshes]').count(), 0);
    assert.equal(await page.getAttribute('[data-testid=result]', 'data-skipped-remeshes'), null);
    assert.ok((await readResult(page)).vertices > 1000);
    assert.deepEqual(pageErrors, []);
  });
});
