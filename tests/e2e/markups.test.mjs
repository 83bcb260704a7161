// Browser end-to-end test (dist/, Debian's chromium) of 3D Slicer markups: the core's fixture
// (biv-me patient 1's ED curves as a Slicer user leaves them, one `.mrk.json` per curve with a
// control point every 8 mm, and the RV insertions as a point list; scripts/markups_fixture.py)
// dropped as a folder with one damaged file beside them. The 41 markups files open as one entry,
// the banner says so and names the damaged file with the core's words; every surface is there,
// and LV_ENDO reconstructs closed as the command line's mesh of the same folder (1041 vertices,
// 174.41 ml: `heartmesh reconstruct slicer-markups-patient1 --surface LV_ENDO`). The same
// study as Slicer 4's point list files (`.fcsv`, half of them RAS) opens the same way, as the
// command line reads those files.
import { describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { cpSync, mkdirSync, mkdtempSync, readdirSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { dropPaths, gotoEmpty, meshOnScreen, readResult, ROOT, runAndWait, SHOTS, textOf, waitForError } from './lib.mjs';
import { appForFile } from './perFile.mjs';
import { FCSV_LV_ENDO_ML, fcsvFiles } from './fcsvFixture.mjs';

let server;
let page;
const pageErrors = [];
appForFile({ goto: false, onPageError: (m) => pageErrors.push(m) }, (app) => ({ server, page } = app));

const FIXTURE = join(ROOT, 'wasm-core', 'crates', 'heartmesh-core', 'tests', 'data', 'slicer-markups-patient1');
const JOINED = 'Slicer markups (41 files).mrk.json';

/** Every surface of the patient offered; LV_ENDO chosen, reconstructed closed from its 8 curves. */
async function lvEndoOfTheSet() {
  const surfaces = await page.$$eval('[data-testid=surface-picker] option', (os) => os.map((o) => o.value));
  for (const s of ['LV_ENDO', 'LV_EPI', 'RV_ENDO', 'RV_EPI']) assert.ok(surfaces.includes(s), `${s} in ${surfaces}`);
  if ((await page.inputValue('[data-testid=surface-picker]')) !== 'LV_ENDO') {
    await runAndWait(page, () => page.selectOption('[data-testid=surface-picker]', 'LV_ENDO'));
  }
  const m = await meshOnScreen(page);
  const r = await readResult(page);
  assert.equal(m.watertight, true);
  assert.equal(m.contours, 8, 'LV_ENDO: 5 short-axis rings and 3 long-axis curves');
  return { m, r };
}

describe('3D Slicer markups', () => {
  it('opens a folder of .mrk.json curves as one contour set and reconstructs it as the command line does', async () => {
    await page.setViewportSize({ width: 1280, height: 720 });
    await gotoEmpty(page, server.url);
    const root = mkdtempSync(join(tmpdir(), 'heartmesh-markups-'));
    const dir = join(root, 'patient1-ED');
    cpSync(FIXTURE, dir, { recursive: true });
    writeFileSync(join(dir, 'damaged.mrk.json'), '{"@schema": "markups-schema-v1.0.3", "markups": [\n{"type": "ClosedCurve",\n');
    try {
      await dropPaths(page, [dir]);
      assert.deepEqual(await page.$$eval('[data-testid=file-picker] option', (os) => os.map((o) => o.value)), [JOINED]);
      const banner = await textOf(page, '[data-testid=error-banner]');
      assert.match(banner, /^1 of 2 files not opened: damaged\.mrk\.json, line 3: not valid JSON/, banner);
      assert.match(banner, /41 Slicer markups files were read as one contour set: Slicer markups \(41 files\)\.mrk\.json\./, banner);
      const { m, r } = await lvEndoOfTheSet();
      assert.equal(m.contourPoints, 1419, 'the splines through the control points (heartmesh info: 1419 points)');
      assert.equal(r.vertices, 1041, 'the command line mesh of the folder');
      assert.ok(Math.abs(m.volumeMl - 174.41) < 0.01, `${m.volumeMl} ml (command line: 174.41 ml)`);
      assert.ok(r.meanMm > 0 && r.meanMm <= 0.5, `contour-to-mesh mean ${r.meanMm} mm`);
      console.log(`# Slicer markups fixture: LV_ENDO ${m.volumeMl.toFixed(2)} ml, contour-to-mesh mean ${r.meanMm.toFixed(3)} mm`);
      await page.mouse.move(0, 0);
      if (SHOTS) await page.screenshot({ path: join(SHOTS, 'slicer-markups.png') });
      assert.deepEqual(pageErrors, []);
    } finally {
      rmSync(root, { recursive: true, force: true });
    }
  });

  it('opens a folder of Slicer 4 point list files (.fcsv) as the curves they were clicked along', async () => {
    await gotoEmpty(page, server.url);
    const root = mkdtempSync(join(tmpdir(), 'heartmesh-fcsv-'));
    const dir = join(root, 'patient1-ED');
    mkdirSync(dir);
    for (const [name, text] of Object.entries(fcsvFiles({ ras: true }))) writeFileSync(join(dir, name), text);
    try {
      await dropPaths(page, [dir]);
      assert.deepEqual(await page.$$eval('[data-testid=file-picker] option', (os) => os.map((o) => o.value)), [JOINED]);
      const banner = await textOf(page, '[data-testid=error-banner]');
      assert.match(banner, /41 Slicer markups files were read as one contour set/, banner);
      const notes = await textOf(page, '#slot-notes');
      assert.match(notes, /Slicer point lists read as contours \(drawn point by point: no point is named as a landmark\): s02_SAX_LV_ENDOCARDIAL, .*\(40 in all\)/, notes);
      const { m, r } = await lvEndoOfTheSet();
      assert.equal(r.vertices, 1041, 'the command line mesh of the same files');
      assert.ok(Math.abs(m.volumeMl - FCSV_LV_ENDO_ML) < 0.01, `${m.volumeMl} ml (command line: ${FCSV_LV_ENDO_ML} ml)`);
      assert.ok(r.meanMm > 0 && r.meanMm <= 0.5, `contour-to-mesh mean ${r.meanMm} mm`);
      console.log(`# Slicer .fcsv folder: LV_ENDO ${m.volumeMl.toFixed(2)} ml, contour-to-mesh mean ${r.meanMm.toFixed(3)} mm`);
      await page.mouse.move(0, 0);
      if (SHOTS) await page.screenshot({ path: join(SHOTS, 'slicer-fcsv.png') });
      assert.deepEqual(pageErrors, []);
    } finally {
      rmSync(root, { recursive: true, force: true });
    }
  });

  it('says what to open when one curve file of the folder is opened alone', async () => {
    await gotoEmpty(page, server.url);
    await page.setInputFiles('[data-testid=file-input]', join(FIXTURE, 's03_SAX_LV_ENDOCARDIAL.mrk.json'));
    const status = await waitForError(page, 's03_SAX_LV_ENDOCARDIAL.mrk.json');
    assert.match(status, /too few contours/, status);
    const shown = `${await textOf(page, '[data-testid=error-banner]')} ${await textOf(page, '#slot-warnings')}`;
    assert.match(shown, /3D Slicer saves each curve in a file of its own; open the folder, or all its \.mrk\.json \(\.fcsv\) files together/, shown);
    assert.deepEqual(pageErrors, []);
  });

  it('opens a patient folder of ED/ and ES/ markups folders as two entries, one per phase', async () => {
    await gotoEmpty(page, server.url);
    const root = mkdtempSync(join(tmpdir(), 'heartmesh-markups-'));
    const patient = join(root, 'patient1');
    cpSync(FIXTURE, join(patient, 'ED'), { recursive: true });
    // End-systole: the same curves drawn 10 % closer to each curve's centre (a smaller cavity).
    mkdirSync(join(patient, 'ES'));
    for (const name of readdirSync(FIXTURE)) {
      const doc = JSON.parse(readFileSync(join(FIXTURE, name), 'utf8'));
      for (const m of doc.markups) {
        const ps = m.controlPoints.map((p) => p.position);
        const c = [0, 1, 2].map((i) => ps.reduce((a, p) => a + p[i], 0) / ps.length);
        if (m.type !== 'Fiducial') for (const p of m.controlPoints) p.position = p.position.map((v, i) => c[i] + 0.9 * (v - c[i]));
      }
      writeFileSync(join(patient, 'ES', name), JSON.stringify(doc));
    }
    try {
      await dropPaths(page, [patient]);
      const entries = await page.$$eval('[data-testid=file-picker] option', (os) => os.map((o) => o.value));
      assert.deepEqual(entries, ['ED (41 Slicer markups).mrk.json', 'ES (41 Slicer markups).mrk.json']);
      const banner = (await textOf(page, '[data-testid=error-banner]')).replace(/✕$/, '');
      assert.equal(banner, `82 Slicer markups files were read as 2 contour sets, one per folder (the folders' curves share names: a phase or a patient each): ${entries.join(', ')}.`);
      const volumes = {};
      for (const entry of entries) {
        if ((await page.inputValue('[data-testid=file-picker]')) !== entry) await runAndWait(page, () => page.selectOption('[data-testid=file-picker]', entry));
        if ((await page.inputValue('[data-testid=surface-picker]')) !== 'LV_ENDO') {
          await runAndWait(page, () => page.selectOption('[data-testid=surface-picker]', 'LV_ENDO'));
        }
        const m = await meshOnScreen(page);
        assert.equal(m.watertight, true);
        assert.equal(m.contourPoints > 1000, true, `${m.contourPoints} points`);
        volumes[entry] = m.volumeMl;
      }
      const [ed, es] = entries.map((e) => volumes[e]);
      console.log(`# Slicer markups ED/ES folders: LV_ENDO ${ed.toFixed(2)} / ${es.toFixed(2)} ml`);
      assert.ok(Math.abs(ed - 174.41) < 0.01, `ED ${ed} ml (command line: 174.41 ml)`);
      // Each curve 0.9 x about its own centre: the rings' areas 0.81 x and the long-axis curves
      // 0.9 x as long, about 0.73 x the volume (measured 131.33 / 174.41 = 0.753).
      assert.ok(es / ed > 0.7 && es / ed < 0.8, `ES/ED ${es / ed}`);
      await page.mouse.move(0, 0);
      if (SHOTS) await page.screenshot({ path: join(SHOTS, 'slicer-markups-phases.png') });
      assert.deepEqual(pageErrors, []);
    } finally {
      rmSync(root, { recursive: true, force: true });
    }
  });
});
