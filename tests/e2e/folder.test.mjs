// Browser end-to-end test (dist/, Debian's chromium) of session 20's folder drop: a biv-me patient
// folder dragged onto the page from the file manager (a native drag, sent through the DevTools
// protocol: a page script cannot make a folder entry) opens its contour files in name order, reads
// each GPFile with its SliceInfoFile, and counts in the banner the files it did not read (an image, a hidden
// file, a file in a sub-folder of images).
import { describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { copyFileSync, mkdirSync, mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { dropPaths, gotoEmpty, readResult, sharedDir, SHOTS } from './lib.mjs';
import { appForFile } from './perFile.mjs';

let app;
let page;
appForFile({}, (a) => ({ page } = app = a));

/** A patient folder as biv-me lays it out, with the clutter a real one may hold. */
function patientFolder() {
  const root = mkdtempSync(join(tmpdir(), 'heartmesh-folder-'));
  const dir = join(root, 'patient1');
  mkdirSync(join(dir, 'images'), { recursive: true });
  const src = join(sharedDir(), 'data', 'contours', 'bivme-example-patient1');
  for (const f of ['GPFile_009.txt', 'GPFile_000.txt', 'SliceInfoFile.txt']) copyFileSync(join(src, f), join(dir, f));
  writeFileSync(join(dir, 'IM_0001'), 'DICM');
  writeFileSync(join(dir, '.DS_Store'), '');
  writeFileSync(join(dir, 'images', 'cine.png'), 'png');
  return { root, dir };
}

describe('a folder dropped on the page', () => {
  it('opens a biv-me patient folder: its GPFiles in name order, each read with the SliceInfoFile, the rest counted', async () => {
    await page.setViewportSize({ width: 1280, height: 720 });
    await gotoEmpty(page, app.server.url);
    const { root, dir } = patientFolder();
    try {
      await dropPaths(page, [dir]);
      const names = await page.$$eval('[data-testid=file-picker] option', (os) => os.map((o) => o.value));
      assert.deepEqual(names, ['GPFile_000.txt', 'GPFile_009.txt']);
      assert.equal(await page.inputValue('[data-testid=file-picker]'), 'GPFile_000.txt');
      const banner = (await page.textContent('[data-testid=error-banner]')) ?? '';
      assert.match(banner, /SliceInfoFile\.txt read with GPFile_000\.txt, GPFile_009\.txt: each contour checked against its image plane\./);
      assert.match(banner, /3 other files in the dropped folder were not read/);
      const r = await readResult(page);
      assert.ok(r.vertices > 500 && r.meanMm < 1, JSON.stringify(r));
      await page.screenshot({ path: join(SHOTS, 'folder-drop.png') });
    } finally {
      rmSync(root, { recursive: true, force: true });
    }
  });
});
