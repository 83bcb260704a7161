// Browser end-to-end test (dist/, Debian's chromium) of the anatomical mesh in the Export panel
// (the command line's `reconstruct --anatomical-mesh`): greyed before a run; after the Patient 1 ·
// ED example's LV_ENDO run, a layout typed out of range disables Save and says the range; 10 x 16
// saved as VTK is the core's file (`patient1-ED-LV_ENDO-anatomical-10x16.vtk`, 162 points, its
// header naming the layout, two regions) and the figures line gives its vertices, volume, distance
// to the surface and the septum's source; View draws its 162 vertices over the surface and a new
// run takes them away. RV_ENDO: the core's reason greyed, no Save. The SurFCo example (no RV to
// place the septum by): the core's reason. Screenshot: anatomical-mesh.png in SHOTS.
import { describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { download, gotoEmpty, runAndWait, setField, sharedDir, SHOTS } from './lib.mjs';
import { appForFile } from './perFile.mjs';
import { vtkBlock } from './meshFiles.mjs';

let app;
let page;
const pageErrors = [];
appForFile({ onPageError: (m) => pageErrors.push(m) }, (a) => ({ page } = app = a));

const row = '[data-testid=anatomical-export]';
const save = '[data-testid=export-anatomical]';
const figures = '[data-testid=anatomical-figures]';
const reason = '[data-testid=anatomical-reason]';

/** Waits until the row has the core's answer for the run on screen (`ready` or `refused`). */
async function rowState(state) {
  await page.waitForSelector(`${row}[data-state=${state}]`, { timeout: 30000 });
}

describe('the anatomical mesh', () => {
  it('Patient 1 · ED LV_ENDO: 10 x 16 as VTK, its figures, View; RV_ENDO refused with the core\'s reason', async () => {
    await page.setViewportSize({ width: 1280, height: 900 });
    await gotoEmpty(page, app.server.url);
    assert.equal(await page.isDisabled(save), true, 'no run, no Save');
    assert.equal(await page.getAttribute(row, 'data-state'), 'none');
    await runAndWait(page, () => page.getByRole('button', { name: 'Patient 1 · ED' }).first().click());
    assert.equal(await page.inputValue('[data-testid=surface-picker]'), 'LV_ENDO');
    await rowState('ready');
    assert.equal(await page.isEnabled(save), true);
    assert.equal(await page.inputValue('[data-testid=anatomical-rings]'), '24');
    assert.equal(await page.inputValue('[data-testid=anatomical-points]'), '48');
    assert.match(await page.textContent(`${row} .wall-what`), /^Same vertices for every heart: shape analysis, ED→ES motion\.$/);
    assert.equal(await page.isVisible(reason), false);

    // Out of range: no Save, the range said.
    await setField(page, 'anatomical-rings', 1);
    assert.equal(await page.isDisabled(save), true);
    assert.equal(await page.textContent('[data-testid=anatomical-layout-error]'), 'Rings: a whole number from 2 to 200');

    // 10 x 16 as VTK: the core's file, 162 points.
    await setField(page, 'anatomical-rings', 10);
    await setField(page, 'anatomical-points', 16);
    assert.equal(await page.isVisible('[data-testid=anatomical-layout-error]'), false);
    await page.selectOption('[data-testid=anatomical-format]', 'vtk');
    const vtk = await download(page, 'export-anatomical');
    assert.equal(vtk.name, 'patient1-ED-LV_ENDO-anatomical-10x16.vtk');
    const lines = vtk.bytes.toString('utf8').split('\n');
    assert.equal(lines[0], '# vtk DataFile Version 3.0');
    assert.match(lines[1], /anatomical layout 10x16 of LV_ENDO reconstructed from patient1-ED\.csv/);
    assert.ok(lines.includes('POINTS 162 double'), lines.find((l) => l.startsWith('POINTS')));
    const polygons = lines.find((l) => l.startsWith('POLYGONS '));
    const triangles = Number(polygons.split(' ')[1]);
    assert.equal(triangles, 2 * 16 * 10, polygons); // the apex fan, 9 bands of two per quad, the base lid
    assert.ok(lines.includes(`CELL_DATA ${triangles}`));
    const regions = vtkBlock(lines, 'SCALARS region', triangles);
    assert.deepEqual([...new Set(regions)].sort(), [1, 2]);
    const apex = vtkBlock(lines, 'POINTS', 3);
    assert.ok(apex.every(Number.isFinite), `vertex 0 ${apex}`);

    await page.waitForSelector(`${figures}[data-state=done]`);
    const shown = await page.$eval(figures, (el) => ({ text: el.textContent, vertices: Number(el.dataset.vertices), ml: Number(el.dataset.volumeMl), mean: Number(el.dataset.meanMm), max: Number(el.dataset.maxMm) }));
    assert.equal(shown.vertices, 162);
    assert.ok(shown.ml > 80 && shown.ml < 200, `${shown.ml} ml`);
    assert.ok(shown.mean > 0 && shown.mean <= shown.max, `${shown.mean} / ${shown.max} mm`);
    assert.match(shown.text, /^162 vertices · \d+\.\d ml · to the surface \d+\.\d+ mm mean, \d+\.\d+ mm max\. Septum from the RV contours' centre \(\d+\)$/);
    assert.match(await page.textContent('[data-testid=anatomical-septum]'), /^Septum from the RV contours' centre \(\d+\)$/);
    console.log(`anatomical 10x16: ${shown.text}`);

    // View: the grid over the surface, as many vertices as the file's; a new run takes it away.
    await page.click('[data-testid=view-anatomical]');
    await page.waitForFunction(() => document.querySelector('[data-testid=viewport-canvas]')?.dataset.grid === '162', null, { timeout: 30000 });
    assert.equal(await page.getAttribute('[data-testid=view-anatomical]', 'aria-pressed'), 'true');
    assert.equal(await page.getAttribute('[data-testid=viewport-canvas]', 'data-shown'), 'surface');
    // The grid alone over the surface for the picture (the attractors' dots would hide its vertices).
    await page.uncheck('[data-testid=view-attractors]');
    await page.locator(row).scrollIntoViewIfNeeded();
    await page.screenshot({ path: join(SHOTS, 'anatomical-mesh.png') });
    await page.check('[data-testid=view-attractors]');

    // RV_ENDO: the core's reason, greyed, no Save.
    await runAndWait(page, () => page.selectOption('[data-testid=surface-picker]', 'RV_ENDO'));
    await rowState('refused');
    assert.equal(await page.getAttribute('[data-testid=viewport-canvas]', 'data-grid'), '0', 'the grid went with the run');
    assert.equal(await page.isVisible(save), false);
    assert.equal(await page.isVisible('[data-testid=view-anatomical]'), false);
    assert.equal(await page.isVisible(figures), false);
    assert.equal(await page.textContent(reason), 'The anatomical layout is the LV\'s (LV_ENDO, LV_EPI); RV_ENDO has no centre for its rays');
    const grey = await page.$eval(reason, (el) => getComputedStyle(el).color);
    assert.equal(grey, 'rgb(139, 150, 165)', 'muted');
    await page.locator(row).scrollIntoViewIfNeeded();
    await page.screenshot({ path: join(SHOTS, 'anatomical-mesh-refused.png') });

    // Back on LV_EPI: ready again.
    await runAndWait(page, () => page.selectOption('[data-testid=surface-picker]', 'LV_EPI'));
    await rowState('ready');
    assert.equal(await page.isVisible(save), true);
    assert.deepEqual(pageErrors, []);
  });

  it('SurFCo: nothing says where the septum is, the core\'s reason instead of Save', async () => {
    await gotoEmpty(page, app.server.url);
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', join(sharedDir(), 'data', 'contours', 'surfco-example.csv')));
    await rowState('refused');
    assert.equal(await page.textContent(reason), 'The anatomical layout starts at the septum, and the file has no RV_INSERT landmarks and no RV contours to place it by');
    assert.equal(await page.isVisible(save), false);
    assert.deepEqual(pageErrors, []);
  });
});
