// Browser end-to-end test (dist/, Debian's chromium) of ZIP archives opened in the page
// (io/zipArchive.ts), as UK Biobank hands a subject out: the cvi42 workspace in `1000001_cvi42.zip`,
// the DICOM images in `1000001_images.zip` (the core's fixture, biv-me patient 1 drawn in the
// pixels of 110 header-only cine images). Opened together (the Open dialog) or as the subject's
// folder dropped, they give the unzipped study's LV_ENDO mesh (tests/e2e/cvi42.test.mjs: 1041
// vertices, mean 0.380 mm, 173.2 ml) and its frame picker (0, 9). A zipped contour file
// (patient1-ED.zip: export/patient1-ED.csv and a macOS resource fork) gives the file's own mesh.
// A cut archive is refused with a banner naming it, and the page goes on.
import { describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { copyFileSync, mkdirSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { dropPaths, gotoEmpty, meshOnScreen, readResult, ROOT, runAndWait, textOf, waitForError } from './lib.mjs';
import { pickFrameNine } from './cvi42Frames.mjs';
import { appForFile } from './perFile.mjs';

let server;
let page;
const pageErrors = [];
appForFile({ goto: false, onPageError: (m) => pageErrors.push(m) }, (app) => ({ server, page } = app));

const ZIPPED = join(ROOT, 'wasm-core', 'crates', 'heartmesh-core', 'tests', 'data', 'cvi42-patient1', 'zipped');
const WORKSPACE_ZIP = join(ZIPPED, '1000001_cvi42.zip');
const IMAGES_ZIP = join(ZIPPED, '1000001_images.zip');
const CONTOURS_ZIP = join(ROOT, 'wasm-core', 'crates', 'heartmesh-cli', 'tests', 'data', 'patient1-ED.zip');
const CONTOURS = join(ROOT, 'public', 'samples', 'patient1-ED.csv'); // the same bytes as the archive's export/patient1-ED.csv
const PICKER = '[data-testid=frame-picker]';
const CUT = 'no end of central directory: truncated or not an archive';

const current = () => meshOnScreen(page);
const text = (selector) => textOf(page, selector);

/** The zipped study on screen: the unzipped study's LV_ENDO at frame 0, read with its 110 images. */
async function assertStudy(label) {
  assert.equal(await page.inputValue('[data-testid=file-picker]'), '1000001_cvi42.cvi42wsx', label);
  assert.equal(await page.inputValue('[data-testid=surface-picker]'), 'LV_ENDO', label);
  assert.match(await text('[data-testid=notes-first]'), /^workspace read with 110 DICOM images: contours on 17 of them, in 9 cine slices/, label);
  const r = await readResult(page);
  const m = await current();
  assert.equal(r.vertices, 1041, `${label}: the unzipped study's mesh`);
  assert.equal(r.meanMm.toFixed(3), '0.380', `${label}: contour-to-mesh mean ${r.meanMm} mm`);
  assert.equal(m.volumeMl.toFixed(1), '173.2', `${label}: ${m.volumeMl} ml`);
  assert.equal(m.contourPoints, 441, label);
  assert.equal(m.watertight, true, label);
  return { ...r, ...m };
}

/** A temporary folder; removed by the caller. */
const scratch = () => mkdtempSync(join(tmpdir(), 'heartmesh-zip-'));

describe('ZIP archives', () => {
  it("opens UK Biobank's two archives together: the unzipped study's LV_ENDO, frame 9 picked reads the images again", async () => {
    await page.setViewportSize({ width: 1280, height: 720 });
    await gotoEmpty(page, server.url);
    const started = Date.now();
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', [WORKSPACE_ZIP, IMAGES_ZIP]));
    const seconds = (Date.now() - started) / 1000;
    const zero = await assertStudy('two archives');
    assert.equal(await page.isVisible('[data-testid=error-banner]'), false, 'nothing to warn of');
    console.log(`# 1000001_cvi42.zip + 1000001_images.zip, LV_ENDO frame 0: ${zero.vertices} vertices, mean ${zero.meanMm} mm, ${zero.volumeMl.toFixed(1)} ml (opened and run in ${seconds.toFixed(1)} s)`);

    const nine = await pickFrameNine(page, zero);
    await runAndWait(page, () => page.selectOption(PICKER, '0'));
    assert.equal((await current()).volumeMl, zero.volumeMl);
    assert.deepEqual(pageErrors, []);
  });

  it("opens a subject's folder of archives dropped on the page", async () => {
    await gotoEmpty(page, server.url);
    const root = scratch();
    try {
      const dir = join(root, '1000001');
      mkdirSync(dir);
      copyFileSync(WORKSPACE_ZIP, join(dir, '1000001_cvi42.zip'));
      copyFileSync(IMAGES_ZIP, join(dir, '1000001_20209_2_0.zip'));
      await dropPaths(page, [dir]);
      await assertStudy('dropped folder of archives');
      assert.deepEqual(pageErrors, []);
    } finally {
      rmSync(root, { recursive: true, force: true });
    }
  });

  it('opens a zipped contour file as the file itself (its resource fork left out)', async () => {
    await gotoEmpty(page, server.url);
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', CONTOURS));
    const plain = { ...(await readResult(page)), ...(await current()) };
    await gotoEmpty(page, server.url);
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', CONTOURS_ZIP));
    assert.equal(await page.inputValue('[data-testid=file-picker]'), 'patient1-ED.csv');
    assert.deepEqual(await page.$$eval('[data-testid=file-picker] option', (os) => os.map((o) => o.value)), ['patient1-ED.csv']);
    assert.equal(await page.inputValue('[data-testid=surface-picker]'), 'LV_ENDO');
    const zipped = { ...(await readResult(page)), ...(await current()) };
    assert.deepEqual(zipped, plain);
    assert.equal(await page.isVisible('[data-testid=error-banner]'), false);
    console.log(`# patient1-ED.zip: ${zipped.vertices} vertices, ${zipped.contours} contours, ${zipped.contourPoints} contour points, mean ${zipped.meanMm} mm (as patient1-ED.csv)`);
    assert.ok(zipped.vertices > 0 && zipped.contours > 0);
    assert.deepEqual(pageErrors, []);
  });

  it('refuses a cut archive with a banner naming it; the page goes on', async () => {
    await gotoEmpty(page, server.url);
    const root = scratch();
    try {
      const bytes = readFileSync(IMAGES_ZIP);
      const cut = join(root, '1000001_images.zip');
      writeFileSync(cut, bytes.subarray(0, Math.floor(bytes.length / 2)));
      await page.setInputFiles('[data-testid=file-input]', cut);
      const status = await waitForError(page, '1000001_images.zip');
      assert.equal(status, `error: 1000001_images.zip: ZIP archive: ${CUT}`);
      const banner = await text('[data-testid=error-banner]');
      assert.match(banner, new RegExp(`1000001_images\\.zip: ZIP archive: no end of central directory: truncated or not an archive\\.? Not opened\\.`));

      // With the workspace's archive: the workspace waits for its images, the cut archive named.
      await page.setInputFiles('[data-testid=file-input]', [WORKSPACE_ZIP, cut]);
      await waitForError(page, '1000001_cvi42.cvi42wsx');
      assert.match(await text('[data-testid=error-banner]'), new RegExp(`Open its images next .*: they are read with it\\. 1 archive not opened: 1000001_images\\.zip: ZIP archive: ${CUT}\\.`));

      // The page goes on: the good images' archive opened next is read with the waiting workspace.
      await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', IMAGES_ZIP));
      await assertStudy('images opened after a cut archive');
      assert.equal(await page.isVisible('[data-testid=error-banner]'), false, 'the refusal is gone');
      assert.deepEqual(pageErrors, []);
    } finally {
      rmSync(root, { recursive: true, force: true });
    }
  });
});
