// Browser end-to-end test (dist/, Debian's chromium) of the Function section: biv-me patient 1's
// ED and ES examples open together, "Measure all phases" reconstructs the four surfaces of both in
// the worker while the view keeps reconstructing, then shows the CLI's figures (`heartmesh volumes`:
// LV EF 62.1 %, RV EF 60.3 %, LV mass 134.0 g at ED and 131.6 g at ES) and a CSV of the eight cells
// in the CLI's columns. A parameter changed marks the table stale (and changed back, current
// again); a broken file opened beside them is a failed row while the others are measured again.
// One file holding both phases (a `phase` column) measures its frames, to the same figures.
// Screenshots: function.png (1280 x 720) and function-narrow.png (a 390 px phone) in SHOTS.
import { describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { download, gotoEmpty, runAndWait, sharedDir, SHOTS, statusNow } from './lib.mjs';
import { appForFile } from './perFile.mjs';
import { PHASES_NAME, phasesCsv } from './twoFrames.mjs';

let server;
let page;
const pageErrors = [];
appForFile({ goto: false, onPageError: (m) => pageErrors.push(m) }, (app) => ({ server, page } = app));

const FN = '[data-testid=function]';
/** Volumes of patient 1 (ml), the CLI's and the core's (heartmesh-wasm's phases test). */
const VOLUMES = {
  'patient1-ED': { RV_ENDO: 180.583, RV_EPI: 286.039, LV_EPI: 301.336, LV_ENDO: 173.724 },
  'patient1-ES': { RV_ENDO: 71.718, RV_EPI: 131.238, LV_EPI: 191.163, LV_ENDO: 65.86 },
};

const fnState = () => page.getAttribute(FN, 'data-state');
async function waitMeasured(timeout = 240000) {
  await page.waitForFunction((sel) => document.querySelector(sel)?.getAttribute('data-state') !== 'measuring', FN, { timeout, polling: 100 });
  assert.equal(await fnState(), 'done', (await page.textContent(FN)) ?? '');
}
const ventricle = (surface) => page.locator(`[data-testid=function-ventricle][data-surface=${surface}]`);
const num = async (loc, attr) => Number(await loc.getAttribute(attr));
const near = (got, want, tol, what) => assert.ok(Math.abs(got - want) <= tol, `${what}: ${got}, expected ${want} ± ${tol}`);

describe('Function: volumes over the phases', () => {
  it('patient 1 ED + ES: the CLI\'s EF and mass, a CSV of 8 cells, stale on a change, a broken file fails alone', async () => {
    await page.setViewportSize({ width: 1280, height: 720 });
    await gotoEmpty(page, server.url);
    assert.equal(await page.isVisible(FN), false, 'one phase or none: no Function section');
    await runAndWait(page, () => page.getByRole('button', { name: 'Patient 1 · ED' }).first().click());
    assert.equal(await page.isVisible(FN), false, 'one file of one phase: no Function section');
    await runAndWait(page, () => page.getByRole('button', { name: 'Patient 1 · ES' }).first().click());
    assert.equal(await page.isVisible(FN), true);
    assert.match((await page.textContent(`${FN} .function-source`)) ?? '', /^2 phases: the 2 open files$/);
    assert.equal(await fnState(), 'idle');

    // Measuring goes on beside the view: a surface picked meanwhile reconstructs and finishes.
    await page.click('[data-testid=function-measure]');
    assert.equal(await fnState(), 'measuring');
    assert.equal(await page.isVisible('[data-testid=function-stop]'), true);
    await runAndWait(page, () => page.selectOption('[data-testid=surface-picker]', 'RV_ENDO'), 120000);
    const during = await fnState();
    assert.match((await page.textContent('[data-testid=function-progress]')) ?? '', during === 'measuring' ? /^\d \/ 8$/ : /^$/);
    await waitMeasured();
    assert.equal((await statusNow(page)).text.startsWith('done'), true, 'the view\'s run is done');

    // Each cavity's function and the LV mass: the CLI's figures.
    assert.deepEqual(await page.$$eval('[data-testid=function-ventricle]', (ls) => ls.map((l) => l.getAttribute('data-surface'))), ['LV_ENDO', 'RV_ENDO']);
    near(await num(ventricle('LV_ENDO'), 'data-ef'), 62.1, 0.1, 'LV EF');
    near(await num(ventricle('RV_ENDO'), 'data-ef'), 60.3, 0.1, 'RV EF');
    near(await num(ventricle('LV_ENDO'), 'data-edv-ml'), 173.7, 0.1, 'LV EDV');
    const lvText = (await ventricle('LV_ENDO').textContent()) ?? '';
    assert.match(lvText, /^LV_ENDO: EDV 173\.7 ml · ESV 65\.9 ml · SV 107\.9 ml · EF 62\.1 %ED: patient1-ED · ES: patient1-ES$/);
    const mass = page.locator('[data-testid=function-mass]');
    near(await num(mass, 'data-ed-g'), 134.0, 0.2, 'LV mass at ED');
    near(await num(mass, 'data-es-g'), 131.6, 0.2, 'LV mass at ES');
    assert.equal(await mass.textContent(), 'LV mass 134.0 g at ED · 131.6 g at ES');

    // The table: phases x surfaces, LV endocardium first as in the Surface menu.
    const header = await page.$$eval('[data-testid=function-table] thead th', (ths) => ths.map((t) => t.textContent));
    assert.deepEqual(header, ['ml', 'LV_ENDO', 'LV_EPI', 'RV_ENDO', 'RV_EPI']);
    const cells = await page.$$eval('[data-testid=function-table] td', (tds) => tds.map((t) => [t.getAttribute('data-phase'), t.getAttribute('data-surface'), Number(t.getAttribute('data-volume-ml')), t.textContent]));
    assert.equal(cells.length, 8);
    for (const [phase, surface, ml, text] of cells) {
      near(ml, VOLUMES[phase][surface], 0.01, `${phase} ${surface}`);
      assert.equal(text, ml.toFixed(1));
    }

    // The CSV: the CLI's columns, one row per cell in the files' order.
    const csv = await download(page, 'function-csv');
    assert.equal(csv.name, 'phases-volumes.csv');
    const lines = csv.bytes.toString('utf8').trim().split('\n');
    assert.equal(lines[0], 'phase,surface,volume_ml,watertight,contour_to_mesh_mean_mm,seconds');
    assert.equal(lines.length, 9);
    const rows = lines.slice(1).map((l) => l.split(','));
    assert.deepEqual(rows.map((r) => `${r[0]} ${r[1]}`), Object.entries(VOLUMES).flatMap(([p, v]) => Object.keys(v).map((s) => `${p} ${s}`)));
    for (const [phase, surface, ml, watertight, c2m, seconds] of rows) {
      near(Number(ml), VOLUMES[phase][surface], 0.001, `CSV ${phase} ${surface}`);
      assert.equal(watertight, 'true');
      assert.ok(Number(c2m) > 0 && Number(c2m) < 2, `${phase} ${surface}: ${c2m} mm`);
      assert.ok(Number(seconds) > 0, `${phase} ${surface}: ${seconds} s`);
    }

    await page.locator(FN).scrollIntoViewIfNeeded();
    await page.mouse.move(0, 0);
    await page.screenshot({ path: join(SHOTS, 'function.png') });

    // A parameter changed: the table is marked stale; changed back, it is current again.
    assert.equal(await page.getAttribute(FN, 'data-stale'), '0');
    await runAndWait(page, () => page.check('[data-testid=param-keep-specks]'), 120000);
    assert.equal(await page.getAttribute(FN, 'data-stale'), '1');
    assert.equal(await page.textContent('[data-testid=function-stale]'), 'parameters changed — measure again');
    await runAndWait(page, () => page.uncheck('[data-testid=param-keep-specks]'), 120000);
    assert.equal(await page.getAttribute(FN, 'data-stale'), '0');

    // A broken file beside them (one contour: no surface can be made of it) opens, its run fails,
    // and the table is stale until measured again; then its row fails alone.
    const broken = 'contour,x,y,z,surface\na,0,0,0,LV_ENDO\na,10,0,0,LV_ENDO\na,0,10,0,LV_ENDO\n';
    await page.setInputFiles('[data-testid=file-input]', { name: 'broken.csv', mimeType: 'text/csv', buffer: Buffer.from(broken) });
    await page.waitForFunction(() => document.querySelector('[data-testid=status]')?.textContent?.startsWith('error'), null, { timeout: 60000 });
    assert.equal(await page.getAttribute(FN, 'data-stale'), '1');
    assert.equal(await page.textContent('[data-testid=function-stale]'), 'the open phases changed — measure again');
    await page.click('[data-testid=function-measure]');
    await waitMeasured();
    const brokenRow = await page.$$eval('[data-testid=function-table] td[data-phase=broken]', (tds) => tds.map((t) => [t.getAttribute('data-surface'), t.textContent, t.getAttribute('title')]));
    assert.deepEqual(brokenRow.map(([s, t]) => [s, t]), [['LV_ENDO', 'failed'], ['LV_EPI', '–'], ['RV_ENDO', '–'], ['RV_EPI', '–']]);
    assert.match(brokenRow[0][2] ?? '', /contour/, 'the failed cell\'s title says why');
    assert.equal(brokenRow[1][2], 'broken has no LV_EPI contours');
    near(await num(ventricle('LV_ENDO'), 'data-ef'), 62.1, 0.1, 'LV EF with the broken file open');
    assert.equal(await page.textContent('[data-testid=function-mass]'), 'LV mass 134.0 g at ED · 131.6 g at ES');
    assert.equal((await download(page, 'function-csv')).bytes.toString('utf8').trim().split('\n').length, 13);

    // The view still works after it all.
    await runAndWait(page, () => page.selectOption('[data-testid=file-picker]', 'patient1-ED.csv'), 120000);
    assert.deepEqual(pageErrors, []);
  });

  it('one file holding ED and ES (a phase column): its frames are the phases, read without changing the frame on screen', async () => {
    const text = (name) => readFileSync(join(sharedDir(), 'data', 'contours', 'bivme-example-patient1', name), 'utf8');
    const csv = phasesCsv(text('patient1-ED.csv'), text('patient1-ES.csv'));
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', { name: PHASES_NAME, mimeType: 'text/csv', buffer: Buffer.from(csv) }));
    assert.equal(await page.inputValue('[data-testid=frame-picker]'), 'ED');
    assert.equal(await page.textContent(`${FN} .function-source`), `2 phases: the 2 frames of ${PHASES_NAME}`);
    assert.equal(await page.getAttribute(FN, 'data-stale'), '1', 'other phases than those measured');
    await page.click('[data-testid=function-measure]');
    await waitMeasured();
    near(await num(ventricle('LV_ENDO'), 'data-ef'), 62.1, 0.1, 'LV EF of the frames');
    near(await num(ventricle('RV_ENDO'), 'data-ef'), 60.3, 0.1, 'RV EF of the frames');
    assert.equal(await page.textContent('[data-testid=function-mass]'), 'LV mass 134.0 g at ED · 131.6 g at ES');
    assert.deepEqual(await page.$$eval('[data-testid=function-table] tbody th', (ths) => ths.map((t) => t.textContent)), ['ED', 'ES']);
    const csvOut = await download(page, 'function-csv');
    assert.equal(csvOut.name, `${PHASES_NAME.replace(/\.csv$/, '')}-volumes.csv`);
    // The frame on screen is still ED: picking ES reads it and the table stays current.
    await runAndWait(page, () => page.selectOption('[data-testid=frame-picker]', 'ES'), 120000);
    assert.equal(await page.getAttribute(FN, 'data-stale'), '0');
    assert.deepEqual(pageErrors, []);
  });

  it('on a 390 px phone the section fits the column', async () => {
    await page.setViewportSize({ width: 390, height: 844 });
    await page.locator(FN).scrollIntoViewIfNeeded();
    const width = await page.evaluate(() => document.scrollingElement.scrollWidth);
    assert.ok(width <= 390, `page ${width} px wide`);
    const table = await page.locator('[data-testid=function-table]').boundingBox();
    const panel = await page.locator(FN).boundingBox();
    assert.ok(table && panel && table.x >= panel.x - 1 && table.x + table.width <= panel.x + panel.width + 1, `table ${JSON.stringify(table)} in ${JSON.stringify(panel)}`);
    await page.screenshot({ path: join(SHOTS, 'function-narrow.png') });
    assert.deepEqual(pageErrors, []);
  });
});
