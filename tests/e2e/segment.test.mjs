// Browser end-to-end test (dist/, Debian's chromium) of a Segment (Medviso) study file: the core's
// fixture (biv-me patient 1 saved as Segment saves a study: a compressed MAT-file whose setstruct
// holds a short-axis cine stack with its image, four long-axis views, a scout and a rotated stack;
// scripts/segment_fixture.py). Dropped, it opens at the study's end-diastole (frame 1): the notes
// say how many images and name the study's ED and ES frames, the warnings the rotated stack left
// out, LV_ENDO reconstructs closed as the command line's mesh (1041 vertices, 171.56 ml; its three
// long-axis curves, closed across the valve as Segment draws them, fitted opened there: the result
// panel's Valve chords row); frame 10 picked reads the end-systole (64.32 ml), and Function
// measures both frames as the phases (the command line's LV EF, 62.5 %). A damaged copy is refused with the core's words and the study on
// screen stays.
import { describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync, writeFileSync, mkdtempSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { dropPaths, gotoEmpty, meshOnScreen, readResult, ROOT, runAndWait, SHOTS, textOf, waitForError, measurePhases } from './lib.mjs';
import { appForFile } from './perFile.mjs';

let server;
let page;
const pageErrors = [];
appForFile({ goto: false, onPageError: (m) => pageErrors.push(m) }, (app) => ({ server, page } = app));

const STUDY = join(ROOT, 'wasm-core', 'crates', 'heartmesh-core', 'tests', 'data', 'segment-patient1', 'patient1.mat');
const PICKER = '[data-testid=frame-picker]';
const text = (selector) => textOf(page, selector);

describe('a Segment study file', () => {
  it('opens at its end-diastole; frame 10 reads the end-systole; Function gives the EF', async () => {
    await page.setViewportSize({ width: 1280, height: 720 });
    await gotoEmpty(page, server.url);
    await dropPaths(page, [STUDY]);
    assert.equal(await page.inputValue('[data-testid=file-picker]'), 'patient1.mat');
    assert.equal(await page.inputValue('[data-testid=surface-picker]'), 'LV_ENDO');
    const ed = await meshOnScreen(page);
    const r = await readResult(page);
    assert.equal(ed.contourPoints, 632, "LV_ENDO's 632 contour points (heartmesh info)");
    assert.equal(ed.contours, 8, '5 short-axis rings and 3 long-axis views');
    assert.equal(ed.watertight, true);
    assert.equal(r.vertices, 1041, 'the command line\'s mesh (reconstruct --surface LV_ENDO)');
    assert.ok(Math.abs(ed.volumeMl - 171.56) < 0.01, `${ed.volumeMl} ml`);
    assert.equal(await text('[data-testid=result-valve-chords]'), '3 opened');
    assert.match(
      await page.getAttribute('[data-testid=result-valve-chords]', 'title'),
      /^"s06_Endo", "s07_Endo", "s08_Endo" closed across the valve: the mesh is fitted to them opened there/,
    );
    assert.ok(r.meanMm > 0 && r.meanMm <= 0.5, `contour-to-mesh mean ${r.meanMm} mm`);
    assert.match(await text('[data-testid=notes-first]'), /^Segment study read with 180 images: contours on 17 of them, in 9 cine slices/);
    assert.match(await text('[data-testid=notes]'), /end-diastole is frame 1, its end-systole frame 10 \(stack 1 \(Short-axis\)\)/);
    assert.match(await text('#slot-warnings'), /stack 7 \(2CH\): a rotated \(radial\) stack/);
    assert.deepEqual(await page.$$eval(`${PICKER} option`, (os) => os.map((o) => [o.value, o.textContent])), [['1', 'frame 1 · ED'], ['10', 'frame 10 · ES']]);
    assert.equal(await page.inputValue(PICKER), '1');

    await runAndWait(page, () => page.selectOption(PICKER, '10'));
    const es = await meshOnScreen(page);
    assert.equal(es.watertight, true);
    assert.ok(Math.abs(es.volumeMl - 64.32) < 0.01, `frame 10 (end-systole): ${es.volumeMl} ml`);
    console.log(`# Segment fixture: LV_ENDO ${ed.volumeMl.toFixed(2)} ml at frame 1, ${es.volumeMl.toFixed(2)} ml at frame 10`);
    await runAndWait(page, () => page.selectOption(PICKER, '1'));
    assert.equal((await meshOnScreen(page)).volumeMl, ed.volumeMl);
    await page.click('[data-testid=notes] summary');
    await page.mouse.move(0, 0);
    if (SHOTS) await page.screenshot({ path: join(SHOTS, 'segment.png') });

    const FN = '[data-testid=function]';
    assert.equal(await text(`${FN} .function-source`), '2 phases: the 2 frames of patient1.mat');
    await measurePhases(page);
    const ef = Number(await page.getAttribute('[data-testid=function-ventricle][data-surface=LV_ENDO]', 'data-ef'));
    assert.ok(Math.abs(ef - 62.5) < 0.1, `LV EF ${ef} % (heartmesh volumes: 62.5 %)`);
    assert.deepEqual(pageErrors, []);
  });

  it('refuses a damaged copy with the reason, keeping the study on screen', async () => {
    await page.setViewportSize({ width: 1280, height: 720 });
    await gotoEmpty(page, server.url);
    await dropPaths(page, [STUDY]);
    const before = await meshOnScreen(page);
    const dir = mkdtempSync(join(tmpdir(), 'heartmesh-segment-'));
    const cut = join(dir, 'damaged.mat');
    const bytes = readFileSync(STUDY);
    writeFileSync(cut, bytes.subarray(0, bytes.length >> 1));
    await page.setInputFiles('[data-testid=file-input]', cut);
    await waitForError(page, 'damaged.mat');
    assert.match(await text('[data-testid=error-banner]'), /truncated/);
    assert.equal((await meshOnScreen(page)).volumeMl, before.volumeMl, 'the study on screen stays');
    assert.deepEqual(pageErrors, []);
  });
});
