// Browser end-to-end test (dist/, Debian's chromium) of the LV wall as hexahedra (the command
// line's `myocardium --hex-mesh` in the app): under the LV wall's row, greyed with the LV wall's
// reason until the Patient 1 · ED example's LV_ENDO and LV_EPI have both run; after All, 0 layers
// disables Save and says the range; 2 layers saved as `patient1-ED-LV_wall-hex-24x48x2.vtk` is a
// VTK unstructured grid of 3 x (24 x 48 + 1) = 3459 points and 2 x 24 x 48 = 2304 cells (2208
// hexahedra, 96 wedges), the transmural coordinate 0-1 and an AHA segment 1-17 per cell, and the
// figures line gives those counts and a volume close to the LV wall's. A file without RV contours
// (patient 1's LV contours alone): the core's reason greyed in place of Save. Screenshot:
// hex-wall-export.png in SHOTS.
import { describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { download, gotoEmpty, runAndWait, setField, sharedDir, waitForDone, SHOTS } from './lib.mjs';
import { appForFile } from './perFile.mjs';
import { vtkBlock } from './meshFiles.mjs';

let app;
let page;
const pageErrors = [];
appForFile({ onPageError: (m) => pageErrors.push(m) }, (a) => ({ page } = app = a));

const row = '[data-testid=hex-export]';
const save = '[data-testid=export-hex]';
const figures = '[data-testid=hex-figures]';
const reason = '[data-testid=hex-reason]';

/** Waits until the row has the core's answer for the meshes on hand (`ready` or `refused`). */
async function rowState(state, timeout = 30000) {
  await page.waitForSelector(`${row}[data-state=${state}]`, { timeout, state: 'attached' });
}

/** Runs every surface of the file open (All) and waits until all have finished. */
async function runAll(others) {
  await page.click('[data-testid=run-all-surfaces]');
  await page.waitForFunction((n) => document.querySelector('[data-testid=view-others-count]')?.textContent === ` (${n})`, others, { timeout: 120000 });
  await waitForDone(page, 120000);
}

describe('the LV wall as hexahedra', () => {
  it('Patient 1 · ED: greyed until both LV surfaces ran; 24 x 48 x 2 saved as a VTK unstructured grid, its figures', async () => {
    await page.setViewportSize({ width: 1280, height: 900 });
    await gotoEmpty(page, app.server.url);
    assert.equal(await page.isDisabled(save), true, 'no file');
    await runAndWait(page, () => page.getByRole('button', { name: 'Patient 1 · ED' }).first().click());
    // LV_ENDO alone: greyed, the tooltip the LV wall's reason.
    assert.equal(await page.isDisabled(save), true);
    assert.match(await page.getAttribute(save, 'title'), /^The LV wall as layers of hexahedra .*: run LV_EPI too \(Surface menu, or All\)$/);
    assert.equal(await page.textContent(save), 'Hexahedra VTK');
    assert.equal(await page.textContent('[data-testid=hex-hint]'), 'layers of hexahedra for finite-element simulation (transmural, longitudinal, circumferential coordinates; rule-based fibres, +60° to −60°; AHA segment per cell)');
    // Directly under the LV wall's row.
    assert.equal(await page.$eval(row, (el) => el.previousElementSibling?.getAttribute('data-testid')), 'wall-export');

    await runAll(3);
    await rowState('ready');
    assert.equal(await page.isDisabled(save), false);
    assert.equal(await page.isDisabled('[data-testid=export-wall-vtk]'), false, 'the LV wall can be built too');
    assert.deepEqual(
      await Promise.all(['hex-rings', 'hex-points', 'hex-layers'].map((t) => page.inputValue(`[data-testid=${t}]`))),
      ['24', '48', '3'],
    );

    // 0 layers: no Save, the range said.
    await setField(page, 'hex-layers', 0);
    assert.equal(await page.isDisabled(save), true);
    assert.equal(await page.textContent('[data-testid=hex-input-error]'), 'Layers: a whole number from 1 to 20');

    // 2 layers: the core's file.
    await setField(page, 'hex-layers', 2);
    assert.equal(await page.isVisible('[data-testid=hex-input-error]'), false);
    const vtk = await download(page, 'export-hex');
    assert.equal(vtk.name, 'patient1-ED-LV_wall-hex-24x48x2.vtk');
    const lines = vtk.bytes.toString('utf8').split('\n');
    assert.equal(lines[0], '# vtk DataFile Version 3.0');
    assert.match(lines[1], /LV myocardium hexahedra 24x48x2 of patient1-ED\.csv \(LV_ENDO \+ LV_EPI\)/);
    assert.equal(lines[3], 'DATASET UNSTRUCTURED_GRID');
    const points = 3 * (24 * 48 + 1);
    assert.equal(lines[4], `POINTS ${points} double`);
    const cells = 2 * 24 * 48;
    const cellTypes = lines.find((l) => l.startsWith('CELL_TYPES '));
    assert.equal(cellTypes, `CELL_TYPES ${cells}`);
    assert.match(lines.find((l) => l.startsWith('CELLS ')), new RegExp(`^CELLS ${cells} \\d+$`));
    // VTK_HEXAHEDRON 12 above the apex ring, VTK_WEDGE 13 round the apex.
    const types = vtkBlock(lines, 'CELL_TYPES', cells);
    assert.deepEqual([12, 13].map((t) => types.filter((x) => x === t).length), [2 * 23 * 48, 2 * 48]);
    assert.ok(lines.includes(`POINT_DATA ${points}`) && lines.includes(`CELL_DATA ${cells}`));
    const transmural = vtkBlock(lines, 'SCALARS transmural', points);
    assert.ok(transmural.every((t) => t >= 0 && t <= 1), 'transmural 0-1');
    assert.deepEqual([...new Set(transmural)].sort(), [0, 0.5, 1], 'two layers: the endocardium, the middle, the epicardium');
    // Rule-based fibres and the sheet: unit vectors, one per point.
    for (const name of ['fibre', 'sheet']) {
      const at = lines.indexOf(`VECTORS ${name} double`);
      assert.ok(at > 0, `VECTORS ${name}`);
      const vectors = lines.slice(at + 1, at + 1 + points).map((l) => l.split(' ').map(Number));
      assert.ok(vectors.every((v) => v.length === 3 && Math.abs(Math.hypot(...v) - 1) < 1e-9), `${name}: unit vectors`);
    }
    const segments = vtkBlock(lines, 'SCALARS aha_segment', cells);
    assert.deepEqual([...new Set(segments)].sort((a, b) => a - b), Array.from({ length: 17 }, (_, i) => i + 1), 'every AHA segment');

    await page.waitForSelector(`${figures}[data-state=done]`);
    const shown = await page.$eval(figures, (el) => ({ text: el.textContent, hexahedra: Number(el.dataset.hexahedra), wedges: Number(el.dataset.wedges), points: Number(el.dataset.points), ml: Number(el.dataset.volumeMl), inverted: Number(el.dataset.inverted), warn: el.classList.contains('warn') }));
    assert.deepEqual([shown.hexahedra, shown.wedges, shown.points], [2208, 96, points]);
    assert.equal(shown.hexahedra + shown.wedges, cells);
    assert.match(shown.text, new RegExp(`^2208 hexahedra \\+ 96 wedges · ${points} points · \\d+\\.\\d ml · min scaled Jacobian -?\\d\\.\\d\\d$`));
    // The LV wall the CLI measures (99.5 ml), as the cells measure it.
    assert.ok(Math.abs(shown.ml - 99.5) < 3, `${shown.ml} ml`);
    assert.equal(shown.warn, shown.inverted > 0);
    console.log(`hexahedra 24x48x2: ${shown.text}`);

    // The default layers again: the figures of 2 layers go.
    await setField(page, 'hex-layers', 3);
    assert.equal(await page.isVisible(figures), false);
    const three = await download(page, 'export-hex');
    assert.equal(three.name, 'patient1-ED-LV_wall-hex-24x48x3.vtk');
    await page.waitForSelector(`${figures}[data-state=done]`);
    assert.match(await page.textContent(figures), /^3312 hexahedra \+ 144 wedges · 4612 points · \d+\.\d ml · min scaled Jacobian \d\.\d\d$/);

    await page.locator(row).scrollIntoViewIfNeeded();
    await page.screenshot({ path: join(SHOTS, 'hex-wall-export.png') });

    // A parameter changed: LV_ENDO reruns, LV_EPI's mesh is of the old settings: greyed, the figures gone.
    await runAndWait(page, () => page.uncheck('[data-testid=param-soften-conflicts]'));
    assert.equal(await page.isDisabled(save), true);
    assert.match(await page.getAttribute(save, 'title'), /LV_EPI was last run with other parameters; run it again with these/);
    assert.equal(await page.isVisible(figures), false);
    assert.deepEqual(pageErrors, []);
  });

  it('LV contours alone (no RV contours, no RV_INSERT landmarks): the core\'s reason instead of Save', async () => {
    await gotoEmpty(page, app.server.url);
    const csv = readFileSync(join(sharedDir(), 'data', 'contours', 'bivme-example-patient1', 'patient1-ED.csv'), 'utf8')
      .split('\n')
      .filter((l, i) => i === 0 || /,LV_(ENDO|EPI)$/.test(l.trim()))
      .join('\n');
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', { name: 'patient1-ED-LV.csv', mimeType: 'text/csv', buffer: Buffer.from(csv) }));
    await runAll(1);
    await rowState('refused', 60000);
    assert.equal(await page.isDisabled('[data-testid=export-wall-vtk]'), false, 'the LV wall itself can be built');
    assert.equal(await page.textContent(reason), 'Its cells are laid out from the septum: the file has no RV_INSERT landmarks and no RV contours');
    assert.equal(await page.isVisible(save), false);
    assert.equal(await page.getAttribute(row, 'title'), 'Its cells are laid out from the septum: the file has no RV_INSERT landmarks and no RV contours');
    assert.deepEqual(pageErrors, []);
  });
});
