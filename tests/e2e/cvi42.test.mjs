// Browser end-to-end test (dist/, Debian's chromium) of a Circle cvi42 study: the core's fixture
// (biv-me patient 1 drawn in the pixels of 110 header-only cine images, contours at frames 0 and 9).
// The workspace alone is refused with the core's words and the page goes on (its images folder
// dropped next is read with it); opened with its 110
// images (the Open dialog), the notes line says it was read with 110 DICOM images, the warning line
// names the contour types skipped, and LV_ENDO reconstructs closed within 1 mm of its contours, as
// the command line's mesh (1041 vertices); frame 9 picked reads the images again (7 contours, 269
// points). A workspace saved as Contours.xml opens with its images the same way (found by its
// content). The study's folder, dropped (a native drag through the DevTools protocol) or picked with
// the folder button, opens the same way, its hidden file counted and its notes file set aside.
import { describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { cpSync, mkdirSync, mkdtempSync, readdirSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { dropPaths, gotoEmpty, meshOnScreen, readResult, ROOT, runAndWait, SHOTS, textOf, waitForDone, waitForError } from './lib.mjs';
import { pickFrameNine } from './cvi42Frames.mjs';
import { appForFile } from './perFile.mjs';

let server;
let page;
const pageErrors = [];
appForFile({ goto: false, onPageError: (m) => pageErrors.push(m) }, (app) => ({ server, page } = app));

const FIXTURE = join(ROOT, 'wasm-core', 'crates', 'heartmesh-core', 'tests', 'data', 'cvi42-patient1');
const WSX = join(FIXTURE, 'Contours.cvi42wsx');
const IMAGES = readdirSync(join(FIXTURE, 'dicom')).sort().map((n) => join(FIXTURE, 'dicom', n));
const PICKER = '[data-testid=frame-picker]';

const current = () => meshOnScreen(page);
const text = (selector) => textOf(page, selector);

/** The result panel's figures of a closed LV endocardium near its contours, as the command line's. */
async function assertLvEndo(label) {
  const r = await readResult(page);
  const m = await current();
  assert.equal(await page.inputValue('[data-testid=surface-picker]'), 'LV_ENDO', label);
  assert.equal(m.contourPoints, 441, `${label}: LV_ENDO's 441 contour points`);
  assert.equal(m.watertight, true, label);
  assert.match(await text('[data-testid=result-triangles]'), /\(closed\)$/, label);
  assert.equal(r.triangles, 2 * r.vertices - 4, `${label}: a closed genus-0 surface`);
  assert.equal(r.vertices, 1041, `${label}: the command line's mesh (reconstruct --surface LV_ENDO)`);
  assert.ok(r.meanMm > 0 && r.meanMm <= 1, `${label}: contour-to-mesh mean ${r.meanMm} mm`);
  return { ...r, ...m };
}

/** The notes line and the warning line of a workspace read with its 110 images. */
async function assertReadWithImages(label) {
  assert.match(await text('[data-testid=notes-first]'), /^workspace read with 110 DICOM images: contours on 17 of them, in 9 cine slices/, label);
  const warnings = await text('#slot-warnings');
  assert.match(warnings, /the file holds 2 time frames \(0, 9\): frame 0 read, 1204 points of other frames left out; choose another with the Frame picker/, label);
  assert.match(warnings, /contours of type saPapMuscContour skipped/, label);
  // The reference points are read (the RV insertions), not skipped.
  assert.doesNotMatch(warnings, /RefPoint/, label);
  return warnings;
}

/**
 * A copy of the study folder (the workspace and its dicom/ folder; not the fixture's zipped/ copy
 * of them, opened in zip.test.mjs) with a hidden file and a notes file, as a real export may hold.
 */
function studyFolder() {
  const root = mkdtempSync(join(tmpdir(), 'heartmesh-cvi42-'));
  const dir = join(root, 'patient1');
  mkdirSync(dir);
  cpSync(WSX, join(dir, 'Contours.cvi42wsx'));
  cpSync(join(FIXTURE, 'dicom'), join(dir, 'dicom'), { recursive: true });
  writeFileSync(join(dir, '.DS_Store'), '');
  writeFileSync(join(dir, 'README.txt'), 'exported from cvi42');
  return { root, dir };
}

/** Where the value of the element with tag bytes `tag` (explicit VR, 2-byte length) begins, and its length. */
function valueOf(bytes, tag) {
  const at = bytes.indexOf(Buffer.from(tag));
  assert.ok(at > 0, `tag ${tag} not found`);
  return { at: at + 8, length: bytes.readUInt16LE(at + 6) };
}

/**
 * 400 images of 128 KiB of pixels each, as a study's folder holds them: the fixture's 110 and 290
 * of other series (same planes, their own SOP Instance UIDs and series numbers, no contours).
 */
function bigStudy() {
  const root = mkdtempSync(join(tmpdir(), 'heartmesh-cvi42-400-'));
  const pixels = 128 * 1024;
  const paths = [];
  const write = (name, header) => {
    const element = Buffer.from([0xe0, 0x7f, 0x10, 0x00, 0x4f, 0x57, 0, 0, 0, 0, 0, 0]);
    element.writeUInt32LE(pixels, 8);
    const path = join(root, name);
    writeFileSync(path, Buffer.concat([header, element, Buffer.alloc(pixels)]));
    paths.push(path);
  };
  const headers = IMAGES.map((p) => readFileSync(p).subarray(0, -20)); // less the 8-byte pixel element
  headers.forEach((h, i) => write(`IM_${String(i).padStart(4, '0')}`, h));
  for (let c = 0; c < 290; c++) {
    const h = Buffer.from(headers[c % 110]);
    const variant = Math.floor(c / 110);
    const uid = valueOf(h, [0x08, 0x00, 0x18, 0x00, 0x55, 0x49]);
    h[uid.at + 2] = 0x33 + variant; // 1.2.826... -> 1.3.826..., 1.4..., 1.5...: unique, same length
    const series = valueOf(h, [0x20, 0x00, 0x11, 0x00, 0x49, 0x53]);
    h.write(`9${variant}`.padEnd(series.length, ' '), series.at, 'latin1');
    write(`IM_${String(110 + c).padStart(4, '0')}`, h);
  }
  mkdirSync(join(root, 'ws'));
  cpSync(WSX, join(root, 'ws', 'Contours.cvi42wsx'));
  return { root, paths, workspace: join(root, 'ws', 'Contours.cvi42wsx') };
}

describe('a cvi42 study', () => {
  it('refuses the workspace alone, then opens it with its 110 images: LV_ENDO closed within 1 mm; frame 9 reads them again', async () => {
    await page.setViewportSize({ width: 1280, height: 720 });
    await gotoEmpty(page, server.url);

    await page.setInputFiles('[data-testid=file-input]', WSX);
    const status = await waitForError(page, 'Contours.cvi42wsx');
    assert.match(status, /open it together with the DICOM images it was drawn on/);
    assert.match(await text('[data-testid=error-banner]'), /Contours\.cvi42wsx: cvi42 workspace: a cvi42 workspace holds its contours in the pixels of its images: open it together with the DICOM images it was drawn on \(the study's folder\)/);

    // The page goes on: the workspace with its images opens and runs.
    const started = Date.now();
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', [WSX, ...IMAGES]));
    const seconds = (Date.now() - started) / 1000;
    assert.equal(await page.inputValue('[data-testid=file-picker]'), 'Contours.cvi42wsx');
    assert.equal(await page.isVisible('[data-testid=error-banner]'), false, 'the refusal is gone');
    const zero = await assertLvEndo('frame 0');
    await assertReadWithImages('opened with its images');
    console.log(`# Contours.cvi42wsx + 110 images, LV_ENDO frame 0: ${zero.vertices} vertices, mean ${zero.meanMm} mm, ${zero.volumeMl.toFixed(1)} ml (opened and run in ${seconds.toFixed(1)} s)`);

    // The frames of the workspace: 0 read, 9 picked reads the images again and runs.
    const nine = await pickFrameNine(page, zero);
    const r9 = await readResult(page);
    assert.ok(r9.meanMm > 0 && r9.meanMm <= 1, `frame 9 contour-to-mesh mean ${r9.meanMm} mm`);
    assert.match(page.url(), /[?&]frame=9(&|$)/);
    assert.doesNotMatch(await text('#slot-warnings'), /time frames/, 'a frame chosen leaves nothing to warn of');
    console.log(`# frame 9: ${nine.vertices} vertices, mean ${r9.meanMm} mm, ${nine.volumeMl.toFixed(1)} ml`);

    // Back to frame 0: the images are sent again once more, the same mesh.
    await runAndWait(page, () => page.selectOption(PICKER, '0'));
    assert.equal((await current()).volumeMl, zero.volumeMl);
    assert.deepEqual(pageErrors, []);
  });

  it('opens the study folder dropped on the page, its hidden file counted and its notes file set aside', async () => {
    await page.setViewportSize({ width: 1280, height: 720 });
    await gotoEmpty(page, server.url);
    const { root, dir } = studyFolder();
    try {
      await dropPaths(page, [dir]);
      assert.equal(await page.inputValue('[data-testid=file-picker]'), 'Contours.cvi42wsx');
      await assertLvEndo('dropped folder');
      assert.match(await text('[data-testid=notes-first]'), /^workspace read with 110 DICOM images: .*; 1 other file given with it set aside/);
      const warnings = await assertReadWithImages('dropped folder');
      assert.match(warnings, /1 file set aside: not DICOM \(README\.txt\)/);
      assert.match(await text('[data-testid=error-banner]'), /1 other file in the dropped folder was not read \(hidden, or past the first 4000 files\)/);
      // The notes opened, for the picture: every note in full.
      await page.click('[data-testid=notes] summary');
      await page.mouse.move(0, 0);
      await page.screenshot({ path: join(SHOTS, 'cvi42-study.png') });
      assert.deepEqual(pageErrors, []);
    } finally {
      rmSync(root, { recursive: true, force: true });
    }
  });

  it('reads the images folder dropped after the workspace alone was refused', async () => {
    await gotoEmpty(page, server.url);
    await page.setInputFiles('[data-testid=file-input]', WSX);
    await waitForError(page, 'Contours.cvi42wsx');
    assert.match(await text('[data-testid=error-banner]'), /Not opened\. Open its images next \(drop them, or the folder that holds them\): they are read with it\./);
    await dropPaths(page, [join(FIXTURE, 'dicom')]);
    await assertLvEndo('images dropped after the workspace');
    await assertReadWithImages('images dropped after the workspace');
    assert.deepEqual(pageErrors, []);
  });

  it('opens a workspace saved under another name with its images, told by its content', async () => {
    await gotoEmpty(page, server.url);
    const root = mkdtempSync(join(tmpdir(), 'heartmesh-cvi42-renamed-'));
    try {
      const renamed = join(root, 'Contours.xml');
      cpSync(WSX, renamed);
      await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', [...IMAGES.slice(0, 3), renamed, ...IMAGES.slice(3)]));
      await assertLvEndo('workspace renamed Contours.xml');
      await assertReadWithImages('workspace renamed Contours.xml');
      if (SHOTS) await page.screenshot({ path: join(SHOTS, 'cvi42-renamed-workspace.png') });
      assert.equal(await page.isVisible('[data-testid=error-banner]'), false, 'no file refused');
      assert.deepEqual(pageErrors, []);
    } finally {
      rmSync(root, { recursive: true, force: true });
    }
  });

  it('reads 400 images of 128 KiB without freezing the page: headers only, the same mesh', async () => {
    await page.setViewportSize({ width: 1280, height: 720 });
    await gotoEmpty(page, server.url);
    const { root, paths, workspace } = bigStudy();
    try {
      // The longest time between two animation frames while the files are read and the run starts.
      await page.evaluate(() => {
        const w = window;
        w.__gaps = { last: performance.now(), longest: 0, on: true };
        const tick = (t) => {
          w.__gaps.longest = Math.max(w.__gaps.longest, t - w.__gaps.last);
          w.__gaps.last = t;
          if (w.__gaps.on) requestAnimationFrame(tick);
        };
        requestAnimationFrame(tick);
      });
      const started = Date.now();
      await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', [workspace, ...paths]), 120000);
      const seconds = (Date.now() - started) / 1000;
      const longest = await page.evaluate(() => ((window.__gaps.on = false), window.__gaps.longest));
      console.log(`# 400 images of 128 KiB: opened and run in ${seconds.toFixed(1)} s; longest gap between frames ${longest.toFixed(0)} ms`);
      assert.ok(longest < 1000, `the page froze for ${longest.toFixed(0)} ms`);
      assert.match(await text('[data-testid=notes-first]'), /^workspace read with 400 DICOM images/);
      const r = await assertLvEndo('400 images');
      assert.equal(r.contours, 8);
      assert.deepEqual(pageErrors, []);
    } finally {
      rmSync(root, { recursive: true, force: true });
    }
  });

  it('places the LV wall\'s AHA segments from the workspace\'s reference points (the RV insertions)', async () => {
    await page.setViewportSize({ width: 1280, height: 900 });
    await gotoEmpty(page, server.url);
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', [WSX, ...IMAGES]));
    await page.click('[data-testid=run-all-surfaces]');
    await page.waitForFunction(() => document.querySelector('[data-testid=view-others-count]')?.textContent === ' (3)', null, { timeout: 120000 });
    await waitForDone(page, 120000);
    await page.click('[data-testid=view-wall]');
    await page.waitForSelector('[data-testid=wall-figures][data-state=done]', { timeout: 60000 });
    await page.waitForSelector('[data-testid=wall-segments][data-state=segments]');
    // cvi42's superior and inferior SAX reference points, 5 slices of 2 at frame 0: the septum's
    // source, as the command line's `myocardium --bullseye` reports it.
    assert.equal(await text('[data-testid=wall-bullseye-caption]'), 'Septum placed from anterior and inferior RV insertion points (10 points)');
    const paths = await page.$$eval('[data-testid=wall-bullseye-svg] svg path', (ps) => ps.length);
    assert.equal(paths, 17);
    assert.deepEqual(pageErrors, []);
    if (SHOTS) await page.screenshot({ path: join(SHOTS, 'cvi42-bullseye.png') });
  });

  it('opens the study folder picked with the folder button', async () => {
    await gotoEmpty(page, server.url);
    const { root, dir } = studyFolder();
    try {
      assert.equal(await page.getAttribute('[data-testid=open-folder]', 'aria-label'), 'Open a folder');
      await runAndWait(page, () => page.setInputFiles('[data-testid=folder-input]', dir), 120000);
      await assertLvEndo('picked folder');
      await assertReadWithImages('picked folder');
      assert.deepEqual(pageErrors, []);
    } finally {
      rmSync(root, { recursive: true, force: true });
    }
  });
});
