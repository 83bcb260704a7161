// Browser end-to-end tests (dist/, Debian's chromium) of NIfTI label maps (segmentations) in the
// app: the bundled example (its button, and the same file chosen with Open…: the gzip bytes as
// stored, where the button's fetch gets them inflated from a server that sends `.gz` with
// `Content-Encoding: gzip`, as vite's does) offers LV_ENDO, LV_EPI and RV_ENDO, says how it read
// the labels (on the notes line, not among the warnings), and each surface reconstructs closed,
// within 1 mm of its contours and near the volume of its voxels; the epicardium, drawn with the
// others around it, is the user guide's picture (label-map.png in the screenshot folder). A
// damaged download and an image are refused in one line, the reconstruction on screen kept. A 4D
// cine (built from the example, labelMaps.mjs) gets the Frame picker, its systolic frame a smaller
// LV cavity. Offline, the example comes from the service worker's precache. The same map as 3D
// Slicer saves it (`.seg.nrrd`, written by the CLI to a scratch folder) gives the same LV_EPI,
// its segments named on the notes line; so does the same map as a DICOM SEG (the core's fixture).
// No file is written under tests/e2e: the variants go in as buffers.
import { describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { download, gotoEmpty, runAndWait, waitForError, SHOTS } from './lib.mjs';
import { appForFile } from './perFile.mjs';
import { DICOM_SEG, makeSlicerSegmentation } from './laxViews.mjs';
import {
  CINE_NAME, cineCounts, cineLabelMap, damagedSample, imageLikeSample, SAMPLE_NAME, SAMPLE_PATH, SAMPLE_READING, sampleBytes,
} from './labelMaps.mjs';

let app;
let page;
const pageErrors = [];
appForFile({ onPageError: (m) => pageErrors.push(m) }, (a) => ({ page } = app = a));

/** The run on screen: surface, closed or not, contour-to-mesh mean and max, volume, mesh size. */
const current = () => page.evaluate(() => {
  const r = window.heartmesh.currentResult();
  return r && {
    surface: r.surface, watertight: r.watertight, meanMm: r.overall.mean, maxMm: r.overall.max,
    volumeMl: r.volumeMl, vertices: r.positions.length / 3, triangles: r.indices.length / 3,
  };
});
const surfaces = () => page.$$eval('[data-testid=surface-picker] option', (os) => os.map((o) => o.value));
const warnings = async () => (await page.isVisible('#slot-warnings')) ? (await page.textContent('#slot-warnings')) ?? '' : '';
/** Voxels of 1.25 x 1.25 x 10 mm, in ml. */
const ml = (voxels) => (voxels * 15.625) / 1000;
const { diastole, systole } = cineCounts();
/** What each surface's voxels hold (ml): LV cavity (3), with the myocardium (2), RV cavity (1). */
const VOXEL_ML = { LV_ENDO: ml(diastole[3]), LV_EPI: ml(diastole[3] + diastole[2]), RV_ENDO: ml(diastole[1]) };

/** Each run of the example, by surface (the button's), for the Open… run to match. */
const runs = {};

describe('NIfTI label maps', () => {
  it('the example\'s button: LV_ENDO, LV_EPI and RV_ENDO offered, the reading shown, each surface closed, near its contours and its voxels', async () => {
    await page.setViewportSize({ width: 1280, height: 720 });
    await gotoEmpty(page, app.server.url);
    // What the page's fetch gets: the file as stored (gzip), or inflated by a server that sends
    // `.gz` files with `Content-Encoding: gzip` (vite's preview does); the core reads both.
    const fetched = await page.evaluate(async (name) => {
      const r = await fetch(`samples/${name}`);
      const b = new Uint8Array(await r.arrayBuffer());
      return { encoding: r.headers.get('content-encoding'), length: b.length, gzip: b[0] === 0x1f && b[1] === 0x8b, magic: String.fromCharCode(...b.slice(344, 347)) };
    }, SAMPLE_NAME);
    console.log(`# the example fetched: ${JSON.stringify(fetched)}`);
    assert.ok((fetched.gzip && fetched.length === sampleBytes().length) || (fetched.magic === 'n+1' && fetched.length === 352 + 100 * 108 * 10), JSON.stringify(fetched));

    await runAndWait(page, () => page.click('[data-testid=sample-spasm-seg]'), 120000);
    assert.deepEqual(await surfaces(), ['LV_ENDO', 'LV_EPI', 'RV_ENDO']);
    assert.equal(await page.inputValue('[data-testid=surface-picker]'), 'LV_EPI', 'the example opens on the epicardium');
    assert.equal(await page.isVisible('[data-testid=frame-picker]'), false, 'one time frame: no picker');
    // How the labels were read: information on the notes line, not on the warning line.
    assert.equal(await page.isVisible('[data-testid=notes]'), true);
    assert.deepEqual(await page.$$eval('[data-testid=notes-list] .note', (ps) => ps.map((p) => p.textContent)), [SAMPLE_READING]);
    assert.ok(!(await warnings()).includes(SAMPLE_READING), await warnings());

    for (const surface of ['LV_EPI', 'LV_ENDO', 'RV_ENDO']) {
      if (surface !== 'LV_EPI') await runAndWait(page, () => page.selectOption('[data-testid=surface-picker]', surface), 120000);
      const r = await current();
      runs[surface] = r;
      console.log(`# label map ${surface}: ${r.volumeMl.toFixed(1)} ml (voxels ${VOXEL_ML[surface].toFixed(1)} ml), `
        + `contour-to-mesh mean ${r.meanMm.toFixed(3)} mm, max ${r.maxMm.toFixed(2)} mm, ${r.vertices} vertices, closed ${r.watertight}`);
      assert.equal(r.surface, surface);
      assert.equal(r.watertight, true, `${surface} closed`);
      assert.equal(r.triangles, 2 * r.vertices - 4, `${surface}: a closed genus-0 mesh`);
      assert.ok(r.meanMm > 0 && r.meanMm < 1, `${surface}: mean ${r.meanMm} mm`);
      assert.ok(r.maxMm < 5, `${surface}: max ${r.maxMm} mm`);
    }
    // The cavity and the cavity with its wall within 8 % of their voxels (the RV's thin crescent
    // ends are rounded off, within 25 %); the epicardium holds the cavity and its myocardium.
    for (const s of ['LV_ENDO', 'LV_EPI', 'RV_ENDO']) assert.ok(Math.abs(runs[s].volumeMl / VOXEL_ML[s] - 1) < 0.08, `${s}: ${runs[s].volumeMl} ml vs voxels ${VOXEL_ML[s]} ml`);
    assert.ok(runs.LV_EPI.volumeMl > 1.8 * runs.LV_ENDO.volumeMl, `LV_EPI ${runs.LV_EPI.volumeMl} ml, LV_ENDO ${runs.LV_ENDO.volumeMl} ml`);

    // The user guide's picture: the epicardium see-through, the cavities inside it, the traced
    // slices on it (the attractors off: they would hide them).
    await page.check('[data-testid=view-others]');
    await page.uncheck('[data-testid=view-attractors]');
    await runAndWait(page, () => page.selectOption('[data-testid=surface-picker]', 'LV_EPI'), 120000);
    assert.equal(await page.getAttribute('[data-testid=other-surfaces-legend]', 'data-surfaces'), 'LV_ENDO,RV_ENDO');
    const again = await current();
    assert.equal(again.vertices, runs.LV_EPI.vertices, 'the same run again');
    await page.locator('[data-testid=view-opacity]').fill('40');
    await page.waitForTimeout(300);
    await page.mouse.move(0, 0);
    await page.screenshot({ path: join(SHOTS, 'label-map.png') });
    await page.check('[data-testid=view-attractors]');
  });

  it('the same file chosen with Open… (gzip as stored): the same meshes; listed and downloaded under names that keep .nii.gz whole', async () => {
    const STL = 'cardiomesh-spasm-seg-LV_EPI.stl';
    const first = await download(page, 'export-stl');
    assert.equal(first.name, STL);
    // NIfTI's RAS said where 3D Slicer reads it (else it takes LPS and mirrors the mesh).
    assert.match(first.bytes.subarray(0, 80).toString('latin1'), /^heartmesh \S+ mm SPACE=RAS LV_EPI /);
    // Not the example's entry (a file of the user's, of the same name): kept beside it, numbered
    // before the whole extension.
    const SECOND = 'cardiomesh-spasm-seg (2).nii.gz';
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', SAMPLE_PATH), 120000);
    assert.deepEqual(await page.$$eval('[data-testid=file-picker] option', (os) => os.map((o) => o.value)), [SAMPLE_NAME, SECOND]);
    assert.equal(await page.inputValue('[data-testid=file-picker]'), SECOND);
    assert.match((await page.textContent('[data-testid=error-banner]')) ?? '', /this one is listed as cardiomesh-spasm-seg \(2\)\.nii\.gz in the File picker/);
    assert.equal(await page.inputValue('[data-testid=surface-picker]'), 'LV_EPI', 'the surface last chosen');
    const r = await current();
    for (const k of ['vertices', 'triangles', 'volumeMl', 'meanMm']) assert.equal(r[k], runs.LV_EPI[k], `${k}: Open… ${r[k]}, button ${runs.LV_EPI[k]}`);
    const stl = await download(page, 'export-stl');
    assert.equal(stl.name, 'cardiomesh-spasm-seg_2_-LV_EPI.stl');
    assert.equal(stl.bytes.readUInt32LE(80), r.triangles);
  });

  it('a damaged download and an image are refused in one line, the reconstruction on screen kept', async () => {
    const before = await current();
    await page.setInputFiles('[data-testid=file-input]', { name: 'cut-seg.nii.gz', mimeType: 'application/gzip', buffer: Buffer.from(damagedSample()) });
    const status = await waitForError(page, 'cut-seg.nii.gz');
    const text = (await page.textContent('[data-testid=error-text]')) ?? '';
    console.log(`# damaged: ${text}`);
    assert.match(status, /the gzip data is damaged/);
    assert.match(text, /cut-seg\.nii\.gz: the gzip data is damaged/);
    assert.match(text, /Not opened; still showing cardiomesh-spasm-seg \(2\)\.nii\.gz\./);
    assert.deepEqual(await current(), before, 'the reconstruction on screen is kept');
    assert.deepEqual(await page.$$eval('[data-testid=file-picker] option', (os) => os.map((o) => o.value)), [SAMPLE_NAME, 'cardiomesh-spasm-seg (2).nii.gz'], 'the damaged file is not listed');

    await page.setInputFiles('[data-testid=file-input]', { name: 'cine_4d.nii', mimeType: 'application/octet-stream', buffer: Buffer.from(imageLikeSample()) });
    await waitForError(page, 'cine_4d.nii');
    const image = (await page.textContent('[data-testid=error-text]')) ?? '';
    assert.match(image, /cine_4d\.nii: this NIfTI is an image, not a label map \(segmentation\)/);
    assert.match(image, /Not opened; still showing cardiomesh-spasm-seg \(2\)\.nii\.gz\./);
    assert.deepEqual(await current(), before);
  });

  it('a 4D cine: the Frame picker offers its labelled frames; the systolic frame\'s LV cavity is smaller', async () => {
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', { name: CINE_NAME, mimeType: 'application/octet-stream', buffer: Buffer.from(cineLabelMap()) }), 120000);
    assert.equal(await page.isVisible('[data-testid=frame-picker]'), true);
    assert.deepEqual(await page.$$eval('[data-testid=frame-picker] option', (os) => os.map((o) => o.textContent)), ['frame 1', 'frame 2']);
    assert.equal(await page.inputValue('[data-testid=frame-picker]'), '1');
    assert.match(await warnings(), /the label map holds 2 labelled time frames \(1, 2\): frame 1 read; choose another with the Frame picker/);
    await runAndWait(page, () => page.selectOption('[data-testid=surface-picker]', 'LV_ENDO'), 120000);
    const one = await current();
    assert.equal(one.volumeMl, runs.LV_ENDO.volumeMl, 'frame 1 is the example');
    await runAndWait(page, () => page.selectOption('[data-testid=frame-picker]', '2'), 120000);
    const two = await current();
    assert.match(page.url(), /frame=2/);
    const ratio = two.volumeMl / one.volumeMl;
    console.log(`# cine LV_ENDO: frame 1 ${one.volumeMl.toFixed(1)} ml, frame 2 ${two.volumeMl.toFixed(1)} ml (ratio ${ratio.toFixed(3)}; voxels ${(systole[3] / diastole[3]).toFixed(3)})`);
    assert.ok(two.watertight && two.meanMm < 1, JSON.stringify(two));
    assert.ok(ratio > 0.8 && ratio < 0.95, `frame 2 / frame 1 LV cavity ${ratio}`);
  });

  it('offline after the first visit: the example comes from the precache', async () => {
    await gotoEmpty(page, app.server.url);
    await page.evaluate(async () => {
      await navigator.serviceWorker.ready;
      if (!navigator.serviceWorker.controller) await new Promise((r) => navigator.serviceWorker.addEventListener('controllerchange', r, { once: true }));
    });
    await page.context().setOffline(true);
    try {
      await page.reload();
      await page.waitForFunction(() => document.querySelector('[data-testid=status]')?.textContent === 'no file loaded', null, { timeout: 30000 });
      await runAndWait(page, () => page.click('[data-testid=sample-spasm-seg]'), 120000);
      const r = await current();
      assert.equal(r.surface, 'LV_EPI');
      assert.equal(r.volumeMl, runs.LV_EPI.volumeMl, 'offline: the same mesh');
    } finally {
      await page.context().setOffline(false);
    }
    assert.deepEqual(pageErrors, []);
  });

  it('the same segmentation as 3D Slicer saves it (.seg.nrrd): the same surfaces and LV_EPI, the segments named, exported as seg-LV_EPI.stl', async () => {
    const { path } = makeSlicerSegmentation();
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', path), 120000);
    assert.equal(await page.inputValue('[data-testid=file-picker]'), 'seg.seg.nrrd');
    assert.deepEqual(await surfaces(), ['LV_ENDO', 'LV_EPI', 'RV_ENDO']);
    const notes = await page.$$eval('[data-testid=notes-list] .note', (ps) => ps.map((p) => p.textContent));
    assert.match(notes[0] ?? '', /space directions \(LPS, as 3D Slicer saves\); segments 3 LV, 2 Myocardium, 1 RV$/);
    const r = await current();
    console.log(`# .seg.nrrd LV_EPI: ${r.volumeMl.toFixed(2)} ml (the NIfTI example ${runs.LV_EPI.volumeMl.toFixed(2)} ml), mean ${r.meanMm.toFixed(3)} mm`);
    assert.equal(r.surface, 'LV_EPI');
    assert.equal(r.watertight, true);
    assert.ok(Math.abs(r.volumeMl - runs.LV_EPI.volumeMl) < 0.2, `${r.volumeMl} vs ${runs.LV_EPI.volumeMl}`);
    assert.ok(Math.abs(r.meanMm - runs.LV_EPI.meanMm) < 0.01, `${r.meanMm} vs ${runs.LV_EPI.meanMm}`);
    const stl = await download(page, 'export-stl');
    assert.equal(stl.name, 'seg-LV_EPI.stl');
    assert.match(stl.bytes.subarray(0, 80).toString('latin1'), /^heartmesh \S+ mm SPACE=LPS LV_EPI /);
    const obj = await download(page, 'export-obj');
    assert.deepEqual(obj.bytes.toString('utf8').split('\n').slice(1, 3), ['# SPACE=LPS', '# input: seg.seg.nrrd surface: LV_EPI']);
  });

  it('the same segmentation as a DICOM SEG (the core\'s fixture, LPS): the same surfaces and LV_EPI, read from the frames\' positions', async () => {
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', DICOM_SEG), 120000);
    assert.equal(await page.inputValue('[data-testid=file-picker]'), 'spasm-seg.dcm');
    assert.deepEqual(await surfaces(), ['LV_ENDO', 'LV_EPI', 'RV_ENDO']);
    const notes = await page.$$eval('[data-testid=notes-list] .note', (ps) => ps.map((p) => p.textContent));
    assert.match(notes[0] ?? '', /coordinates from the header's frame positions \(DICOM SEG, LPS\); segments 1 label 1, 2 label 2, 3 label 3$/);
    const r = await current();
    console.log(`# DICOM SEG LV_EPI: ${r.volumeMl.toFixed(2)} ml (the NIfTI example ${runs.LV_EPI.volumeMl.toFixed(2)} ml), mean ${r.meanMm.toFixed(3)} mm`);
    assert.equal(r.surface, 'LV_EPI');
    assert.equal(r.watertight, true);
    // As on the command line (label_maps_cli.rs): the NIfTI's mesh turned to LPS, to the spread
    // of two samplings of pixel-traced curves.
    assert.ok(Math.abs(r.volumeMl - runs.LV_EPI.volumeMl) < 0.01 * runs.LV_EPI.volumeMl, `${r.volumeMl} vs ${runs.LV_EPI.volumeMl}`);
    assert.ok(Math.abs(r.meanMm - runs.LV_EPI.meanMm) < 0.02, `${r.meanMm} vs ${runs.LV_EPI.meanMm}`);
    assert.deepEqual(pageErrors, []);
  });
});
