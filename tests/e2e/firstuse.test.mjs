// Browser end-to-end tests (dist/, Debian's chromium) of a first-use audit: keyboard-only use
// (the first Tab stop is Open…, Space presses a button reached with Tab and stays play/pause after
// a mouse click), the view settings folded on a phone, the Lab's simulation kept out of the
// Function phases, a picture opened by mistake, a decimation that would shrink the mesh (held at the
// tube's triangles), and the STL header's surface kept whole. Screenshots go to the scratch folder.
import { describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { writeFileSync, mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { download, gotoEmpty, readResult, runAndWait, statusRunId, waitForDone, waitForError, SHOTS } from './lib.mjs';
import { appForFile } from './perFile.mjs';

let app;
let page;
const pageErrors = [];
appForFile({ onPageError: (m) => pageErrors.push(m) }, (a) => ({ page } = app = a));

const focused = () => page.evaluate(() => document.activeElement?.getAttribute('data-testid') ?? document.activeElement?.textContent?.trim() ?? null);

async function fresh(viewport = { width: 1280, height: 720 }) {
  await page.setViewportSize(viewport);
  await gotoEmpty(page, app.server.url);
}

describe('a first use of the app', () => {
  it('keyboard only: Open… is the first Tab stop, its folder button the next, Space presses an example reached with Tab, and stays play/pause after a click', async () => {
    await fresh();
    await page.keyboard.press('Tab');
    // Not the hidden file input (a focus nobody sees), but its visible label.
    assert.equal(await focused(), 'Open…');
    // Then its folder button (a cvi42 study's folder, a biv-me patient's), then the examples.
    await page.keyboard.press('Tab');
    assert.equal(await focused(), 'open-folder');
    await page.keyboard.press('Tab');
    await page.keyboard.press('Tab');
    assert.equal(await focused(), 'sample-patient1-ES');
    await runAndWait(page, () => page.keyboard.press('Space'));
    assert.equal((await readResult(page)).vertices, 868);
    // The Lab tab, reached with Tab, opens with Space.
    await page.focus('[data-testid=tab-params]');
    await page.keyboard.press('Tab');
    assert.equal(await focused(), 'tab-lab');
    await page.keyboard.press('Space');
    assert.equal(await page.getAttribute('[data-testid=tab-lab]', 'aria-selected'), 'true');
    await page.click('[data-testid=tab-params]');
    // Clicked with the mouse, then Space: play/pause, the example is not loaded again.
    await runAndWait(page, () => page.click('[data-testid=sample-patient1-ED]'));
    const run = await statusRunId(page);
    await page.keyboard.press('Space');
    await page.waitForFunction(() => document.querySelector('[data-testid=tl-play]')?.title === 'Play (space)', null, { timeout: 10000 });
    await page.waitForTimeout(500);
    assert.equal(await statusRunId(page), run, 'no new run');
    assert.deepEqual(pageErrors, []);
  });

  it('on a 390 px phone the view settings fold to a View button clear of the heart; on a wide window they are open', async () => {
    await fresh({ width: 390, height: 844 });
    await runAndWait(page, () => page.click('[data-testid=sample-patient1-ED]'));
    assert.equal(await page.$eval('.view-controls', (d) => d.open), false);
    const folded = await page.locator('.view-controls').boundingBox();
    assert.ok(folded.height < 40 && folded.width < 120, `folded ${JSON.stringify(folded)}`);
    assert.equal(await page.isVisible('[data-testid=view-wireframe]'), false);
    await page.screenshot({ path: join(SHOTS, 'firstuse-phone-view-folded.png') });
    await page.click('.view-summary');
    assert.equal(await page.isVisible('[data-testid=view-wireframe]'), true);
    // The Lab open on the phone: its column as wide as the window (it kept the desktop's 340 px).
    await page.click('[data-testid=tab-lab]');
    const left = await page.locator('#slot-left').boundingBox();
    const viewport = await page.locator('#slot-viewport').boundingBox();
    assert.ok(left.width >= 389 && viewport.width >= 389, `Lab column ${left.width} px, view ${viewport.width} px on a 390 px phone`);
    await page.click('[data-testid=tab-params]');
    await page.setViewportSize({ width: 1280, height: 720 });
    await page.waitForFunction(() => document.querySelector('.view-controls')?.open === true, null, { timeout: 5000 });
    assert.equal(await page.isVisible('.view-summary'), false, 'no summary on a wide window');
    assert.equal(await page.isVisible('[data-testid=view-wireframe]'), true);
  });

  it('the Lab\'s simulated acquisition is no phase of the patient\'s heart in the Function section', async () => {
    await fresh();
    await runAndWait(page, () => page.click('[data-testid=sample-patient1-ED]'));
    await runAndWait(page, () => page.click('[data-testid=sample-patient1-ES]'));
    assert.equal(await page.textContent('.function-source'), '2 phases: the 2 open files');
    await page.click('[data-testid=tab-lab]');
    await page.click('[data-testid=lab-simulate]');
    await page.waitForFunction(() => /lab-parametric/.test(document.querySelector('[data-testid=lab-acq-info]')?.textContent ?? ''), null, { timeout: 30000 });
    const options = await page.$$eval('[data-testid=file-picker] option', (os) => os.map((o) => o.value));
    assert.equal(options.length, 3);
    assert.equal(await page.textContent('.function-source'), '2 phases: the 2 open files');
    await page.click('[data-testid=tab-params]');
  });

  it('a picture opened by mistake says it is a picture and what to open; the file on screen stays', async () => {
    await fresh();
    await runAndWait(page, () => page.click('[data-testid=sample-patient1-ED]'));
    const dir = mkdtempSync(join(tmpdir(), 'heartmesh-png-'));
    try {
      const png = join(dir, 'slice.png');
      writeFileSync(png, Buffer.from('89504e470d0a1a0a0000000d49484452000000010000000108020000009077053e', 'hex'));
      await page.setInputFiles('[data-testid=file-input]', png);
      await waitForError(page, 'slice.png');
      assert.equal(await page.textContent('[data-testid=error-text]'),
        'slice.png, line 1: binary data at byte 0: this is a PNG picture, not contours. Instead, open the contours drawn on the images (CSV, biv-me GPFile, a Segment or SurFCo .mat, DICOM RT structure set) or their segmentation (a NIfTI label map). Not opened; still showing patient1-ED.csv.');
      assert.equal((await readResult(page)).vertices, 1041);
    } finally {
      rmSync(dir, { recursive: true, force: true });
    }
  });

  it('a target reduction of 0.95 keeps the initial tube\'s triangles: the warning line says so; the defaults say nothing', async () => {
    await fresh();
    await runAndWait(page, () => page.click('[data-testid=sample-patient1-ED]'));
    assert.equal(await page.isVisible('#slot-warnings'), false);
    await runAndWait(page, async () => {
      await page.focus('[data-testid=param-target_reduction]');
      await page.keyboard.press('End');
    });
    const r = await readResult(page);
    // The core holds the mesh at the tube's 600 triangles (50 ring points x 6 rings x 2), not a tetrahedron.
    assert.ok(r.triangles >= 590 && r.triangles <= 610, `triangles ${r.triangles}`);
    assert.ok(r.meanMm < 1.0, `mean ${r.meanMm}`);
    assert.equal(await page.textContent('#slot-warnings'),
      "⚠ each remesh keeps 0.20x the triangles (x4 subdivision, 5 % kept), so the mesh is held at the initial tube's 600 triangles instead of shrinking at every remesh; a target reduction of 0.75 or less lets it refine");
    await page.screenshot({ path: join(SHOTS, 'firstuse-coarse-mesh.png') });
    // Back to the defaults: the note goes with the run that made it.
    await page.click('[data-testid=reset-params]');
    await page.waitForTimeout(400);
    await waitForDone(page);
    assert.equal(await page.isVisible('#slot-warnings'), false);
  });

  it('the STL header keeps the surface whole and the units, then whole parameters', async () => {
    await fresh();
    await runAndWait(page, () => page.click('[data-testid=sample-patient1-ED]'));
    const stl = await download(page, 'export-stl');
    assert.equal(stl.bytes.subarray(0, 80).toString('latin1').trimEnd(), 'heartmesh 0.1.0 mm LV_ENDO patient1-ED.csv lids=auto iterations=250');
    assert.equal(stl.bytes.length, 84 + 50 * stl.bytes.readUInt32LE(80));
    assert.deepEqual(pageErrors, []);
  });
});
