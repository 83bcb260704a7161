// Browser end-to-end test (dist/, Debian's chromium) of 3D Slicer scenes opened whole, as Slicer
// users keep and share their work: a Medical Reality Bundle (`.mrb`, the scene's folder zipped)
// picked in the Open dialog. A scene of markups curves (the core's fixture, biv-me patient 1's ED
// curves, with the scene file, a scan and a screenshot) opens as the markups folder does (one
// entry, LV_ENDO 1041 vertices, 174.41 ml: `heartmesh reconstruct Patient1.mrb --surface
// LV_ENDO`), the other files named as set aside; a scene of a segmentation (`heartmesh segment -o
// seg.seg.nrrd`, with a scan, a point list and the scene file) opens the segmentation alone, the
// scan set aside as an image and the rest named, dropped as the scene's folder (its screenshot
// counted as not read) or picked as its `.mrb`, the same mesh either way. A Slicer 4 scene's
// folder (its point lists as `.fcsv` files, one per curve, tests/e2e/fcsvFixture.mjs) opens as
// those lists, read as the curves they were clicked along.
import { describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { mkdirSync, mkdtempSync, readdirSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { dirname } from 'node:path';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { zipSync } from 'fflate';
import { dropPaths, gotoEmpty, meshOnScreen, readResult, ROOT, runAndWait, SHOTS, textOf } from './lib.mjs';
import { makeSlicerSegmentation } from './laxViews.mjs';
import { appForFile } from './perFile.mjs';
import { FCSV_LV_ENDO_ML, fcsvFiles } from './fcsvFixture.mjs';

let server;
let page;
const pageErrors = [];
appForFile({ goto: false, onPageError: (m) => pageErrors.push(m) }, (app) => ({ server, page } = app));

const FIXTURE = join(ROOT, 'wasm-core', 'crates', 'heartmesh-core', 'tests', 'data', 'slicer-markups-patient1');
const SCENE = '<?xml version="1.0" encoding="UTF-8"?>\n<MRML  version="Slicer4.4.0" userTags="">\n</MRML>\n';

/** A scan as Slicer saves one (`cine.nrrd`, 16-bit intensities 0-999). */
function scan() {
  const head = 'NRRD0004\ntype: short\ndimension: 3\nspace: left-posterior-superior\nsizes: 64 64 4\n'
    + 'space directions: (1.4,0,0) (0,1.4,0) (0,0,10)\nkinds: domain domain domain\nendian: little\n'
    + 'encoding: raw\nspace origin: (0,0,0)\n\n';
  const voxels = new Int16Array(64 * 64 * 4).map((_, v) => (v * 37) % 1000);
  return new Uint8Array([...new TextEncoder().encode(head), ...new Uint8Array(voxels.buffer)]);
}

/** `files` (path in the scene folder -> bytes) bundled as Slicer does, written to a scratch folder. */
function bundle(name, files) {
  const dir = mkdtempSync(join(tmpdir(), 'heartmesh-mrb-'));
  const path = join(dir, `${name}.mrb`);
  writeFileSync(path, zipSync(Object.fromEntries(Object.entries(files).map(([p, b]) => [`${name}/${p}`, b]))));
  return { dir, path };
}

const text = (s) => new TextEncoder().encode(s);

describe('3D Slicer scenes', () => {
  it('opens a .mrb of markups curves as the markups, its scene file, scan and screenshot named as set aside', async () => {
    await page.setViewportSize({ width: 1280, height: 720 });
    await gotoEmpty(page, server.url);
    const files = { 'Patient1.mrml': text(SCENE), 'Data/cine.nrrd': scan(), 'Patient1.png': new Uint8Array([0x89, 0x50, 0x4e, 0x47]) };
    for (const f of readdirSync(FIXTURE)) files[`Data/${f}`] = new Uint8Array(readFileSync(join(FIXTURE, f)));
    const { dir, path } = bundle('Patient1', files);
    try {
      await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', path), 120000);
      assert.deepEqual(await page.$$eval('[data-testid=file-picker] option', (os) => os.map((o) => o.value)), ['Slicer markups (41 files).mrk.json']);
      const banner = (await textOf(page, '[data-testid=error-banner]')).replace(/✕$/, '');
      assert.equal(
        banner,
        '41 Slicer markups files were read as one contour set: Slicer markups (41 files).mrk.json. 3 other files of the Slicer scene set aside (the contours come from the Slicer markups): Patient1.mrml, cine.nrrd, Patient1.png.',
      );
      if ((await page.inputValue('[data-testid=surface-picker]')) !== 'LV_ENDO') {
        await runAndWait(page, () => page.selectOption('[data-testid=surface-picker]', 'LV_ENDO'));
      }
      const m = await meshOnScreen(page);
      const r = await readResult(page);
      assert.equal(m.watertight, true);
      assert.equal(r.vertices, 1041, 'the command line mesh of the bundle');
      assert.ok(Math.abs(m.volumeMl - 174.41) < 0.01, `${m.volumeMl} ml (command line: 174.41 ml)`);
      console.log(`# Slicer scene (.mrb) of markups: LV_ENDO ${m.volumeMl.toFixed(2)} ml, contour-to-mesh mean ${r.meanMm.toFixed(3)} mm`);
      await page.mouse.move(0, 0);
      if (SHOTS) await page.screenshot({ path: join(SHOTS, 'slicer-scene.png') });
      assert.deepEqual(pageErrors, []);
    } finally {
      rmSync(dir, { recursive: true, force: true });
    }
  });

  it('opens the folder of a Slicer 4 scene as its point list files (.fcsv), clicked along each curve', async () => {
    await gotoEmpty(page, server.url);
    const root = mkdtempSync(join(tmpdir(), 'heartmesh-scene4-'));
    const dir = join(root, 'Patient1');
    mkdirSync(join(dir, 'Data'), { recursive: true });
    writeFileSync(join(dir, 'Patient1.mrml'), SCENE);
    writeFileSync(join(dir, 'Data', 'cine.nrrd'), scan());
    for (const [name, body] of Object.entries(fcsvFiles())) writeFileSync(join(dir, 'Data', name), body);
    try {
      await dropPaths(page, [dir]);
      assert.deepEqual(await page.$$eval('[data-testid=file-picker] option', (os) => os.map((o) => o.value)), ['Slicer markups (41 files).mrk.json']);
      const banner = (await textOf(page, '[data-testid=error-banner]')).replace(/✕$/, '');
      // The files set aside in the order the folder gave them.
      const [joined, aside] = banner.split(' 2 other files of the Slicer scene set aside (the contours come from the Slicer markups): ');
      assert.equal(joined, '41 Slicer markups files were read as one contour set: Slicer markups (41 files).mrk.json.', banner);
      assert.deepEqual(aside.replace(/\.$/, '').split(', ').sort(), ['Patient1.mrml', 'cine.nrrd'], banner);
      if ((await page.inputValue('[data-testid=surface-picker]')) !== 'LV_ENDO') {
        await runAndWait(page, () => page.selectOption('[data-testid=surface-picker]', 'LV_ENDO'));
      }
      const m = await meshOnScreen(page);
      assert.equal(m.watertight, true);
      assert.ok(Math.abs(m.volumeMl - FCSV_LV_ENDO_ML) < 0.01, `${m.volumeMl} ml (command line: ${FCSV_LV_ENDO_ML} ml)`);
      assert.deepEqual(pageErrors, []);
    } finally {
      rmSync(root, { recursive: true, force: true });
    }
  });

  it('opens a .mrb of a segmentation, or its folder dropped, as the segmentation, its scan set aside as an image', async () => {
    await gotoEmpty(page, server.url);
    const seg = makeSlicerSegmentation();
    const points = readFileSync(join(FIXTURE, 'RV insertions.mrk.json'));
    const files = { 'Scene.mrml': text(SCENE), 'Data/cine.nrrd': scan(), 'Data/Segmentation.seg.nrrd': seg.bytes, 'Data/F.mrk.json': new Uint8Array(points) };
    const { dir, path } = bundle('Scene', files);
    // The same scene as Slicer leaves it on disk, with its screenshot (not a kind the app reads).
    const folder = join(dir, 'Scene');
    for (const [p, b] of Object.entries({ ...files, 'Scene.png': new Uint8Array([0x89, 0x50, 0x4e, 0x47]) })) {
      mkdirSync(dirname(join(folder, p)), { recursive: true });
      writeFileSync(join(folder, p), b);
    }
    try {
      await dropPaths(page, [folder]);
      assert.deepEqual(await page.$$eval('[data-testid=file-picker] option', (os) => os.map((o) => o.value)), ['Segmentation.seg.nrrd']);
      assert.equal(
        (await textOf(page, '[data-testid=error-banner]')).replace(/✕$/, ''),
        '1 image set aside: images, not contours (the contours come from Segmentation.seg.nrrd). 2 other files of the Slicer scene set aside (the contours come from its segmentations): F.mrk.json, Scene.mrml. 1 other file in the dropped folder was not read (not a contour file, or past the first 200 files).',
      );
      const dropped = await readResult(page);
      await gotoEmpty(page, server.url);
      await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', path), 120000);
      assert.deepEqual(await page.$$eval('[data-testid=file-picker] option', (os) => os.map((o) => o.value)), ['Segmentation.seg.nrrd']);
      const banner = (await textOf(page, '[data-testid=error-banner]')).replace(/✕$/, '');
      assert.equal(
        banner,
        '1 image set aside: images, not contours (the contours come from Segmentation.seg.nrrd). 2 other files of the Slicer scene set aside (the contours come from its segmentations): Scene.mrml, F.mrk.json.',
      );
      const r = await readResult(page);
      const m = await meshOnScreen(page);
      assert.equal(m.watertight, true);
      assert.ok(r.vertices > 500, `${r.vertices} vertices`);
      assert.deepEqual(r, dropped, 'the folder dropped gives the mesh of its bundle');
      console.log(`# Slicer scene (.mrb) of a segmentation: ${await page.inputValue('[data-testid=surface-picker]')} ${m.volumeMl.toFixed(2)} ml, ${r.vertices} vertices`);
      assert.deepEqual(pageErrors, []);
    } finally {
      rmSync(dir, { recursive: true, force: true });
      rmSync(join(seg.path, '..'), { recursive: true, force: true });
    }
  });
});
