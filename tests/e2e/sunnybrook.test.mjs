// Browser end-to-end test (dist/, Debian's chromium) of a Sunnybrook Cardiac Data case: the core's
// fixture (biv-me patient 1's short-axis LV contours as `IM-0001-NNNN-{i,o,p1}contour-manual.txt`
// files in pixels, with the cine short-axis series they were drawn on, 5 slices x 20 frames of
// header-only images, and a long-axis series numbered like the first slice). The two folders
// dropped together open as one study: the notes line says how many images placed the contours,
// the warning line names the papillary muscle skipped, LV_ENDO reconstructs closed as the command
// line's mesh (868 vertices, 159.1 ml); frame 9 picked reads the images again (4 rings, 111
// points), and Function measures both frames as the phases (the command line's LV EF, 69.30 %).
// The contours folder picked alone is refused with the core's words, and the series
// folder dropped next is read with it.
import { describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { dropPaths, gotoEmpty, meshOnScreen, readResult, ROOT, runAndWait, SHOTS, textOf, waitForError, measurePhases } from './lib.mjs';
import { appForFile } from './perFile.mjs';

let server;
let page;
const pageErrors = [];
appForFile({ goto: false, onPageError: (m) => pageErrors.push(m) }, (app) => ({ server, page } = app));

const FIXTURE = join(ROOT, 'wasm-core', 'crates', 'heartmesh-core', 'tests', 'data', 'sunnybrook-patient1');
const CONTOURS = join(FIXTURE, 'contours-manual', 'IRCCI-expert');
const SERIES = join(FIXTURE, 'CINESAX_300');
const PICKER = '[data-testid=frame-picker]';
const text = (selector) => textOf(page, selector);

/** LV_ENDO at end-diastole on screen: closed, the command line's mesh, near its 233 points. */
async function assertEndDiastole(label) {
  assert.equal(await page.inputValue('[data-testid=file-picker]'), 'IM-0001-0001-icontour-manual.txt', label);
  assert.equal(await page.inputValue('[data-testid=surface-picker]'), 'LV_ENDO', label);
  const m = await meshOnScreen(page);
  const r = await readResult(page);
  assert.equal(m.contourPoints, 233, `${label}: LV_ENDO's 233 contour points (heartmesh info)`);
  assert.equal(m.contours, 5, label);
  assert.equal(m.watertight, true, label);
  assert.equal(r.vertices, 868, `${label}: the command line's mesh (reconstruct --surface LV_ENDO)`);
  assert.ok(Math.abs(m.volumeMl - 159.05) < 0.01, `${label}: ${m.volumeMl} ml`);
  assert.ok(r.meanMm > 0 && r.meanMm <= 0.5, `${label}: contour-to-mesh mean ${r.meanMm} mm`);
  assert.match(await text('[data-testid=notes-first]'), /^Sunnybrook contours read with 100 DICOM images: contours on 9 of them, in 5 cine slices/, label);
  const warnings = await text('#slot-warnings');
  assert.match(warnings, /the file holds 2 time frames \(0, 9\): frame 0 read/, label);
  assert.match(warnings, /contours of type p1contour skipped: papillary muscles/, label);
  return m;
}

describe('a Sunnybrook case', () => {
  it('opens its contours folder and series folder dropped together; frame 9 reads the images again', async () => {
    await page.setViewportSize({ width: 1280, height: 720 });
    await gotoEmpty(page, server.url);
    await dropPaths(page, [CONTOURS, SERIES]);
    const zero = await assertEndDiastole('dropped together');
    assert.deepEqual(await page.$$eval(`${PICKER} option`, (os) => os.map((o) => o.value)), ['0', '9']);
    await runAndWait(page, () => page.selectOption(PICKER, '9'));
    const nine = await meshOnScreen(page);
    assert.equal(nine.contourPoints, 111, 'frame 9: 4 rings, as `heartmesh info --frame 9` counts them');
    assert.equal(nine.contours, 4);
    assert.equal(nine.watertight, true);
    assert.ok(Math.abs(nine.volumeMl - 48.83) < 0.01, `frame 9 (systole): ${nine.volumeMl} ml`);
    console.log(`# Sunnybrook fixture: LV_ENDO ${zero.volumeMl.toFixed(2)} ml at frame 0, ${nine.volumeMl.toFixed(2)} ml at frame 9`);
    await runAndWait(page, () => page.selectOption(PICKER, '0'));
    assert.equal((await meshOnScreen(page)).volumeMl, zero.volumeMl);
    await page.click('[data-testid=notes] summary');
    await page.mouse.move(0, 0);
    if (SHOTS) await page.screenshot({ path: join(SHOTS, 'sunnybrook.png') });

    // Function: the two frames are the phases, read with the images again; the command line's EF.
    const FN = '[data-testid=function]';
    assert.equal(await text(`${FN} .function-source`), '2 phases: the 2 frames of IM-0001-0001-icontour-manual.txt');
    await measurePhases(page);
    const ef = Number(await page.getAttribute('[data-testid=function-ventricle][data-surface=LV_ENDO]', 'data-ef'));
    assert.ok(Math.abs(ef - 69.3) < 0.1, `LV EF ${ef} % (heartmesh volumes: 69.30 %)`);
    assert.deepEqual(pageErrors, []);
  });

  it('refuses the contours folder alone, then reads the series folder dropped next with it', async () => {
    await page.setViewportSize({ width: 1280, height: 720 });
    await gotoEmpty(page, server.url);
    await page.setInputFiles('[data-testid=folder-input]', CONTOURS);
    await waitForError(page, 'IM-0001-0001-icontour-manual.txt');
    const banner = await text('[data-testid=error-banner]');
    assert.match(banner, /Sunnybrook contours are in the pixels of their images: open the contour files together with the DICOM images they were drawn on/);
    assert.match(banner, /Open its images next \(drop them, or the folder that holds them\): they are read with it\./);
    await dropPaths(page, [SERIES]);
    await assertEndDiastole('series dropped after the contours');
    assert.equal(await page.isVisible('[data-testid=error-banner]'), false, 'the refusal is gone');
    assert.deepEqual(pageErrors, []);
  });
});
