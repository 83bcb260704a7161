// Browser end-to-end test (dist/, Debian's chromium) of the study's anatomical meshes in the
// Function section (the CLI's `volumes --anatomical-meshes`): biv-me patient 1's ED and ES
// examples open together, "Measure all phases", and under the table the "Anatomical meshes" row:
// a layout (24 x 48), a format (VTK) and "Save (.zip)". The zip (unpacked here with fflate) holds
// the four layouts (ED and ES, LV_EPI and LV_ENDO), each a VTK of 1154 points with point data
// displacement_mm, and anatomical_meshes.json, whose septum is patient1-ED's; the line under the
// row says so ("4 files, 24x48, septum of phase patient1-ED (...); each phase's own within D
// degrees"). A layout out of range is said before any call and Save is off; the row does not
// widen the 250 px column (the 1024 px layout: no sideways scroll). The same files without their
// RV contours: Save is refused with the core's reason (the septum), the page going on.
// Screenshot: function-anatomical.png (1280 x 900) in SHOTS.
import { describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { unzipSync, strFromU8 } from 'fflate';
import { download, gotoEmpty, runAndWait, setField, sharedDir, SHOTS, functionMeasured, measurePhases } from './lib.mjs';
import { appForFile } from './perFile.mjs';

let server;
let page;
const pageErrors = [];
appForFile({ goto: false, onPageError: (m) => pageErrors.push(m) }, (app) => ({ server, page } = app));

const FN = '[data-testid=function]';
const ROW = '[data-testid=function-anatomical]';
const LINE = '[data-testid=function-anatomical-line]';

const waitMeasured = (timeout) => functionMeasured(page, timeout);
const measure = () => measurePhases(page);
/** Waits until the row has settled after a Save (done or refused). */
async function settled() {
  await page.waitForFunction((sel) => ['done', 'refused'].includes(document.querySelector(sel)?.getAttribute('data-state') ?? ''), ROW, { timeout: 60000, polling: 100 });
  return page.getAttribute(ROW, 'data-state');
}

const sample = (name) => readFileSync(join(sharedDir(), 'data', 'contours', 'bivme-example-patient1', name), 'utf8');

/** A legacy VTK file's POINTS count and whether it carries the displacement. */
function vtkFacts(text) {
  const points = text.match(/^POINTS (\d+) /m);
  return { points: points ? Number(points[1]) : NaN, displacement: /displacement_mm/.test(text) };
}

describe('Function: the anatomical meshes of every phase', () => {
  it('patient 1 ED + ES: Save (.zip) gives four 1154-point VTK layouts on the ED septum and the JSON; the line says so', async () => {
    await page.setViewportSize({ width: 1280, height: 900 });
    await gotoEmpty(page, server.url);
    await runAndWait(page, () => page.getByRole('button', { name: 'Patient 1 · ED' }).first().click());
    await runAndWait(page, () => page.getByRole('button', { name: 'Patient 1 · ES' }).first().click());
    assert.equal(await page.isVisible(ROW), false, 'nothing measured: no row');
    await measure();
    await page.waitForSelector(ROW, { state: 'visible', timeout: 10000 });
    assert.equal(await page.getAttribute(ROW, 'data-state'), 'idle');
    assert.equal(await page.inputValue('[data-testid=function-anatomical-rings]'), '24');
    assert.equal(await page.inputValue('[data-testid=function-anatomical-points]'), '48');
    assert.equal(await page.inputValue('[data-testid=function-anatomical-format]'), 'vtk');
    // Under the table and the EF lines.
    const below = await page.$eval(ROW, (e) => {
      const y = e.getBoundingClientRect().top;
      return ['[data-testid=function-table]', '[data-testid=function-summary]'].map((s) => document.querySelector(s).getBoundingClientRect().bottom <= y);
    });
    assert.deepEqual(below, [true, true]);

    // A layout out of range: said at once, Save off; back in range, on again.
    await setField(page, 'function-anatomical-rings', '1');
    assert.equal(await page.isDisabled('[data-testid=function-anatomical-save]'), true);
    assert.match((await page.textContent('[data-testid=function-anatomical-layout-error]')) ?? '', /^Rings: a whole number from 2 to 200$/);
    await setField(page, 'function-anatomical-rings', '24');
    assert.equal(await page.isDisabled('[data-testid=function-anatomical-save]'), false);
    assert.equal(await page.isVisible('[data-testid=function-anatomical-layout-error]'), false);

    const zip = await download(page, 'function-anatomical-save');
    assert.equal(await settled(), 'done', (await page.textContent(LINE)) ?? '');
    assert.equal(zip.name, 'phases-anatomical.zip');
    const files = unzipSync(new Uint8Array(zip.bytes));
    const names = Object.keys(files).sort();
    assert.deepEqual(names, ['anatomical_meshes.json', 'patient1-ED-LV_ENDO.vtk', 'patient1-ED-LV_EPI.vtk', 'patient1-ES-LV_ENDO.vtk', 'patient1-ES-LV_EPI.vtk']);
    for (const n of names.filter((x) => x.endsWith('.vtk'))) {
      const facts = vtkFacts(strFromU8(files[n]));
      assert.equal(facts.points, 1154, n);
      assert.equal(facts.displacement, true, `${n}: point data displacement_mm`);
    }
    const report = JSON.parse(strFromU8(files['anatomical_meshes.json']));
    assert.equal(report.septum.phase, 'patient1-ED');
    assert.equal(report.septum.surface, 'LV_ENDO');
    assert.equal(report.displacement_from_phase, 'patient1-ED');
    assert.deepEqual(report.layout, { rings: 24, points: 48 });
    assert.equal(report.format, 'vtk');
    assert.equal(report.layouts.length, 4);
    const esEndo = report.layouts.find((l) => l.phase === 'patient1-ES' && l.surface === 'LV_ENDO');
    const edEndo = report.layouts.find((l) => l.phase === 'patient1-ED' && l.surface === 'LV_ENDO');
    assert.equal(edEndo.displacement_mean_mm, 0);
    // The LV endocardium moves ~12.6 mm on average from ED to ES (the CLI's figure for these files).
    assert.ok(esEndo.displacement_mean_mm > 5 && esEndo.displacement_mean_mm < 20, String(esEndo.displacement_mean_mm));
    assert.equal(typeof esEndo.septum_turn_deg, 'number');
    console.log(`ES LV_ENDO: displacement mean ${esEndo.displacement_mean_mm.toFixed(3)} mm, max ${esEndo.displacement_max_mm.toFixed(3)} mm, own septum ${esEndo.septum_turn_deg.toFixed(2)} degrees off`);

    // The line: the CLI's words, the figures as data.
    const line = (await page.textContent(LINE)) ?? '';
    const turn = Math.max(...report.layouts.map((l) => l.septum_turn_deg ?? 0));
    assert.equal(line, `4 files, 24x48, septum of phase patient1-ED (${report.septum.source.replace(/ of phase patient1-ED$/, '')}); each phase's own within ${turn.toFixed(1)} degrees`);
    assert.match(line, /septum of phase patient1-ED \(the RV contours' centre \(\d+\)\)/);
    assert.equal(await page.getAttribute(ROW, 'data-files'), '4');
    assert.equal(await page.getAttribute(ROW, 'data-septum-phase'), 'patient1-ED');
    assert.ok(Math.abs(Number(await page.getAttribute(ROW, 'data-turn-deg')) - turn) < 1e-9);
    console.log(line);

    // Another format: PLY files in the zip.
    await page.selectOption('[data-testid=function-anatomical-format]', 'ply');
    const ply = await download(page, 'function-anatomical-save');
    assert.equal(await settled(), 'done');
    assert.deepEqual(Object.keys(unzipSync(new Uint8Array(ply.bytes))).filter((n) => n.endsWith('.ply')).length, 4);
    await page.selectOption('[data-testid=function-anatomical-format]', 'vtk');

    // The screenshot: the column scrolled so the row and its line show.
    await page.locator(ROW).evaluate((e) => {
      const column = e.closest('.sidebar');
      column.scrollTop += e.getBoundingClientRect().bottom - column.getBoundingClientRect().bottom + 10;
    });
    await page.mouse.move(0, 0);
    const inView = await page.$eval(ROW, (e) => {
      const r = e.getBoundingClientRect();
      return r.top >= 0 && r.bottom <= window.innerHeight;
    });
    assert.ok(inView, 'the row in the view for the screenshot');
    await page.screenshot({ path: join(SHOTS, 'function-anatomical.png') });

    // The narrow layout (1024 px): the row wraps inside the column, which never scrolls sideways.
    await page.setViewportSize({ width: 1024, height: 768 });
    const fit = await page.$eval(ROW, (e) => {
      const column = e.closest('.sidebar');
      const r = e.getBoundingClientRect();
      const c = column.getBoundingClientRect();
      const inner = [...e.querySelectorAll('*')].every((x) => x.getBoundingClientRect().right <= c.right + 0.5);
      return { scroll: column.scrollWidth - column.clientWidth, right: r.right - c.right, inner, width: c.width };
    });
    assert.ok(fit.scroll <= 0, `the column scrolls sideways by ${fit.scroll} px (width ${fit.width})`);
    assert.ok(fit.right <= 0.5 && fit.inner, JSON.stringify(fit));
    await page.setViewportSize({ width: 1280, height: 900 });

    // A parameter changed: the table is stale, the row goes (its layouts would be of other runs).
    await runAndWait(page, () => page.check('[data-testid=param-keep-specks]'), 120000);
    assert.equal(await page.getAttribute(FN, 'data-stale'), '1');
    assert.equal(await page.isVisible(ROW), false);
    await runAndWait(page, () => page.uncheck('[data-testid=param-keep-specks]'), 120000);
    assert.equal(await page.isVisible(ROW), true);
    assert.deepEqual(pageErrors, []);
  });

  it('patient 1 without its RV contours: Save refused with the core\'s reason (the septum), the page going on', async () => {
    const lvOnly = (name) => {
      const lines = sample(name).split('\n');
      return `${[lines[0], ...lines.slice(1).filter((l) => /,LV_(ENDO|EPI)\s*$/.test(l))].join('\n')}\n`;
    };
    await gotoEmpty(page, server.url);
    for (const name of ['patient1-ED', 'patient1-ES']) {
      await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', { name: `${name}-lv.csv`, mimeType: 'text/csv', buffer: Buffer.from(lvOnly(`${name}.csv`)) }));
    }
    await measure();
    await page.waitForSelector(ROW, { state: 'visible', timeout: 10000 });
    let downloads = 0;
    page.on('download', () => downloads++);
    await page.click('[data-testid=function-anatomical-save]');
    assert.equal(await settled(), 'refused');
    const line = (await page.textContent(LINE)) ?? '';
    assert.equal(line, "⚠ No anatomical meshes: Every layout starts at the septum, and no phase's file has RV_INSERT landmarks or RV contours to place it by");
    assert.equal(await page.getAttribute(LINE, 'data-state'), 'refused');
    assert.equal(await page.getAttribute(ROW, 'data-files'), null);
    assert.equal(downloads, 0, 'nothing downloaded');
    console.log(line);
    // The page goes on: the EF lines are there and measuring again works.
    assert.equal(await page.getAttribute(FN, 'data-state'), 'done');
    assert.ok((await page.$$('[data-testid=function-ventricle]')).length >= 1);
    await measure();
    assert.equal(await page.getAttribute(ROW, 'data-state'), 'idle', 'a new measurement: the refusal line goes');
    assert.equal(await page.isVisible(LINE), false);
    assert.deepEqual(pageErrors, []);
  });
});
