// Browser end-to-end test (dist/, Debian's chromium) of the Function section: biv-me patient 1's
// ED and ES examples open together, "Measure all phases" reconstructs the four surfaces of both in
// the worker while the view keeps reconstructing, then shows the CLI's figures (`heartmesh volumes`:
// LV EF 62.1 %, RV EF 60.9 %, LV mass 134.0 g at ED and 131.6 g at ES) and a CSV of the eight cells
// in the CLI's columns. A parameter changed marks the table stale (and changed back, current
// again); a broken file opened beside them is a failed row while the others are measured again.
// One file holding both phases (a `phase` column) measures its frames, to the same figures. Two
// phases draw no volume curve; a file of four frames (cycleFrames.mjs) draws one line per cavity,
// its dots the table's volumes, a gap where the RV has none, ED and ES ringed where the summary
// says. Screenshots: function.png (1280 x 720), function-curve.png (the curve) and
// function-narrow.png (a 390 px phone) in SHOTS.
import { describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { download, gotoEmpty, ROOT, runAndWait, sharedDir, SHOTS, statusNow, functionMeasured } from './lib.mjs';
import { CYCLE_FRAMES, CYCLE_NAME, cycleCsv } from './cycleFrames.mjs';
import { appForFile } from './perFile.mjs';
import { PHASES_NAME, phasesCsv } from './twoFrames.mjs';

let server;
let page;
const pageErrors = [];
appForFile({ goto: false, onPageError: (m) => pageErrors.push(m) }, (app) => ({ server, page } = app));

const FN = '[data-testid=function]';
const CURVE = '[data-testid=function-curve]';
/** Volumes of patient 1 (ml), the CLI's and the core's (heartmesh-wasm's phases test). */
const VOLUMES = {
  'patient1-ED': { RV_ENDO: 182.993, RV_EPI: 284.123, LV_EPI: 301.336, LV_ENDO: 173.724 },
  'patient1-ES': { RV_ENDO: 71.604, RV_EPI: 129.51, LV_EPI: 191.163, LV_ENDO: 65.86 },
};

const fnState = () => page.getAttribute(FN, 'data-state');
const waitMeasured = (timeout) => functionMeasured(page, timeout);
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
    near(await num(ventricle('RV_ENDO'), 'data-ef'), 60.9, 0.1, 'RV EF');
    near(await num(ventricle('LV_ENDO'), 'data-edv-ml'), 173.7, 0.1, 'LV EDV');
    const lvText = (await ventricle('LV_ENDO').textContent()) ?? '';
    assert.match(lvText, /^LV_ENDO: EDV 173\.7 ml · ESV 65\.9 ml · SV 107\.9 ml · EF 62\.1 %ED: patient1-ED · ES: patient1-ES$/);
    assert.equal(await page.locator(CURVE).count(), 0, 'two phases: no volume curve');
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
    near(await num(ventricle('RV_ENDO'), 'data-ef'), 60.9, 0.1, 'RV EF of the frames');
    assert.equal(await page.textContent('[data-testid=function-mass]'), 'LV mass 134.0 g at ED · 131.6 g at ES');
    assert.deepEqual(await page.$$eval('[data-testid=function-table] tbody th', (ths) => ths.map((t) => t.textContent)), ['ED', 'ES']);
    assert.equal(await page.locator(CURVE).count(), 0, 'two frames: no volume curve');
    const csvOut = await download(page, 'function-csv');
    assert.equal(csvOut.name, `${PHASES_NAME.replace(/\.csv$/, '')}-volumes.csv`);
    // The frame on screen is still ED: picking ES reads it and the table stays current.
    await runAndWait(page, () => page.selectOption('[data-testid=frame-picker]', 'ES'), 120000);
    assert.equal(await page.getAttribute(FN, 'data-stale'), '0');
    assert.deepEqual(pageErrors, []);
  });

  it('four frames: a volume curve of each cavity, its dots the table\'s volumes, a gap for a frame without the RV, ED and ES ringed', async () => {
    const sample = (name) => readFileSync(join(ROOT, 'public', 'samples', name), 'utf8');
    const csv = cycleCsv(sample('patient1-ED.csv'), sample('patient1-ES.csv'));
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', { name: CYCLE_NAME, mimeType: 'text/csv', buffer: Buffer.from(csv) }));
    // Frame ES, picked in the last file, is none of this one's: show its ES, frame 3.
    await runAndWait(page, () => page.selectOption('[data-testid=frame-picker]', '3'), 120000);
    assert.equal(await page.textContent(`${FN} .function-source`), `4 phases: the 4 frames of ${CYCLE_NAME}`);
    await page.click('[data-testid=function-measure]');
    await waitMeasured();

    // The table's volumes of the cavities: frame 0 is ED, frame 3 ES, frames 1-2 between them.
    const table = await page.$$eval('[data-testid=function-table] td', (tds) => tds.map((t) => [t.getAttribute('data-surface'), t.getAttribute('data-phase'), t.getAttribute('data-volume-ml'), t.textContent]));
    const volume = (surface, phase) => table.find(([s, p]) => s === surface && p === phase);
    near(Number(volume('LV_ENDO', '0')[2]), VOLUMES['patient1-ED'].LV_ENDO, 0.01, 'LV frame 0');
    near(Number(volume('RV_ENDO', '3')[2]), VOLUMES['patient1-ES'].RV_ENDO, 0.01, 'RV frame 3');
    assert.deepEqual(volume('RV_ENDO', '1').slice(2), [null, '–'], 'frame 1 has no RV');

    // One dot per phase with a volume per cavity, each the table's cell; no epicardium drawn.
    const dots = await page.$$eval(`${CURVE} circle[data-ml]`, (cs) => cs.map((c) => [c.getAttribute('data-surface'), c.getAttribute('data-phase'), Number(c.getAttribute('data-ml')), c.querySelector('title')?.textContent]));
    assert.deepEqual(dots.map(([s, p]) => `${s} ${p}`), ['LV_ENDO 0', 'LV_ENDO 1', 'LV_ENDO 2', 'LV_ENDO 3', 'RV_ENDO 0', 'RV_ENDO 2', 'RV_ENDO 3']);
    for (const [surface, phase, ml, title] of dots) {
      const [, , cell, text] = volume(surface, phase);
      near(ml, Number(cell), 0.05, `dot ${surface} ${phase}`);
      assert.equal(title, `${phase} · ${surface} ${text} ml`);
    }
    // A line through the LV's four frames; the RV's breaks at frame 1 (frame 0 a dot alone).
    const lines = await page.$$eval(`${CURVE} polyline`, (ps) => ps.map((p) => [p.getAttribute('data-surface'), p.getAttribute('points').trim().split(/\s+/).length]));
    assert.deepEqual(lines, [['LV_ENDO', 4], ['RV_ENDO', 2]]);
    // The y axis covers the largest volume; the phase labels do not overlap.
    const ticks = await page.$$eval(`${CURVE} text:not(.phase-label):not(.mark-label):not(.unit)`, (ts) => ts.map((t) => Number(t.textContent)));
    assert.deepEqual(ticks, [0, 50, 100, 150, 200]);
    const labels = await page.$$eval(`${CURVE} text.phase-label`, (ts) => ts.map((t) => { const b = t.getBBox(); return [t.textContent, b.x, b.x + b.width]; }));
    assert.deepEqual(labels.map(([t]) => t), CYCLE_FRAMES);
    for (let j = 1; j < labels.length; j++) assert.ok(labels[j - 1][2] < labels[j][1], `labels ${JSON.stringify(labels)}`);

    // ED and ES ringed on the phases the summary names, on the dots.
    const named = await page.$$eval('[data-testid=function-ventricle]', (ls) => ls.map((l) => [l.getAttribute('data-surface'), l.querySelector('.function-phases')?.textContent]));
    assert.deepEqual(named, [['LV_ENDO', 'ED: 0 · ES: 3'], ['RV_ENDO', 'ED: 0 · ES: 3']]);
    const rings = await page.$$eval('[data-testid=function-curve-marker]', (rs) => rs.map((r) => [r.getAttribute('data-surface'), r.getAttribute('data-kind'), r.getAttribute('data-phase'), r.getAttribute('cx'), r.getAttribute('cy')]));
    const expected = named.flatMap(([surface, text]) => {
      const [, ed, es] = /^ED: (.*) · ES: (.*)$/.exec(text);
      return [[surface, 'ED', ed], [surface, 'ES', es]];
    });
    assert.deepEqual(rings.map((r) => r.slice(0, 3)), expected);
    for (const [surface, , phase, cx, cy] of rings) {
      const at = await page.$eval(`${CURVE} circle[data-ml][data-surface=${surface}][data-phase="${phase}"]`, (c) => [c.getAttribute('cx'), c.getAttribute('cy')]);
      assert.deepEqual([cx, cy], at, `${surface} ring at ${phase}`);
    }
    assert.deepEqual(await page.$$eval(`${CURVE} text.mark-label`, (ts) => ts.map((t) => t.textContent)), ['ED', 'ES']);

    // Across the column, above the table.
    const box = await page.locator(CURVE).boundingBox();
    const panel = await page.locator(FN).boundingBox();
    const tableBox = await page.locator('[data-testid=function-table]').boundingBox();
    assert.ok(box.width >= panel.width - 2 && box.height > 100 && box.height < 160, `curve ${JSON.stringify(box)} in ${JSON.stringify(panel)}`);
    assert.ok(box.y + box.height <= tableBox.y, 'above the table');
    // The column scrolled to the section's top (scrolling it into view would move the page too).
    await page.locator(FN).evaluate((e) => {
      const column = e.closest('.sidebar');
      column.scrollTop += e.getBoundingClientRect().top - column.getBoundingClientRect().top - 10;
    });
    await page.mouse.move(0, 0);
    await page.screenshot({ path: join(SHOTS, 'function-curve.png') });

    // A changed parameter greys the curve with the table.
    await runAndWait(page, () => page.check('[data-testid=param-keep-specks]'), 120000);
    assert.equal(await page.$eval('.function-curve-box', (e) => getComputedStyle(e).opacity), '0.5');
    await runAndWait(page, () => page.uncheck('[data-testid=param-keep-specks]'), 120000);
    assert.equal(await page.$eval('.function-curve-box', (e) => getComputedStyle(e).opacity), '1');
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
    const curve = await page.locator(CURVE).boundingBox();
    assert.ok(curve && curve.x >= panel.x - 1 && curve.x + curve.width <= panel.x + panel.width + 1, `curve ${JSON.stringify(curve)} in ${JSON.stringify(panel)}`);
    await page.screenshot({ path: join(SHOTS, 'function-narrow.png') });
    assert.deepEqual(pageErrors, []);
  });
});
