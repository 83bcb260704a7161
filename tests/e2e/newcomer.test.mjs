// Browser end-to-end tests (dist/, Debian's chromium) of session 14's pass over the app as a
// newcomer: a biv-me folder's GPFile dropped with its SliceInfoFile runs without a refusal; an
// error holding a 250-character file name wraps inside the status panel and the banner; on a 1024 x 700
// laptop window the top bar's pickers clear the privacy badge and, with the Lab open, the colour
// legends clear the view controls; Esc stops a run from the slider just moved; the hover read-out
// stays inside the 3D view at its right edge. Screenshots go to the screenshot folder (SHOTS).
import { describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { download, gotoEmpty, textOf, nextFrames, readResult, runAndWait, sharedDir, statusRunId, waitForError, waitForNewRun, SHOTS } from './lib.mjs';
import { appForFile } from './perFile.mjs';

let app;
let page;
const pageErrors = [];
appForFile({ onPageError: (m) => pageErrors.push(m) }, (a) => ({ page } = app = a));

const contours = (...p) => join(sharedDir(), 'data', 'contours', ...p);
const status = () => page.textContent('[data-testid=status]');
const box = (sel) => page.locator(sel).first().boundingBox();

/** The boxes overlap (by more than a pixel). */
function overlapping(a, b) {
  return a.x < b.x + b.width - 1 && b.x < a.x + a.width - 1 && a.y < b.y + b.height - 1 && b.y < a.y + a.height - 1;
}

/** `inner` lies within `outer` (to a pixel). */
function inside(inner, outer) {
  return inner.x >= outer.x - 1 && inner.y >= outer.y - 1 && inner.x + inner.width <= outer.x + outer.width + 1 && inner.y + inner.height <= outer.y + outer.height + 1;
}

async function fresh(query = '', viewport = { width: 1280, height: 720 }) {
  await page.setViewportSize(viewport);
  await gotoEmpty(page, `${app.server.url}${query}`);
}

describe('the app for a newcomer (session 14)', () => {
  it('a biv-me GPFile dropped with its SliceInfoFile is read with it (planes checked); another acquisition\'s is warned of', async () => {
    await fresh();
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', [contours('bivme-example-patient1', 'SliceInfoFile.txt'), contours('bivme-example-patient1', 'GPFile_000.txt')]));
    const r = await readResult(page);
    assert.ok(r.vertices > 500 && r.meanMm > 0 && r.meanMm < 1, `result ${JSON.stringify(r)}`);
    assert.equal(await page.isVisible('[data-testid=error-banner]'), true);
    assert.equal(await page.getAttribute('[data-testid=error-banner]', 'data-kind'), 'info');
    assert.equal(await page.textContent('[data-testid=error-text]'), 'SliceInfoFile.txt read with GPFile_000.txt: each contour checked against its image plane.');
    assert.doesNotMatch(await textOf(page, '#slot-warnings'), /image plane/);
    // Patient 2's SliceInfoFile with patient 1's GPFile: the core's check names the mismatch.
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', [contours('bivme-test-patient2', 'SliceInfoFile.txt'), contours('bivme-example-patient1', 'GPFile_000.txt')]));
    assert.match(await textOf(page, '#slot-warnings'), /37 contours lie off the image planes of their slices, up to 91\.4 mm .*is the slice info file from another acquisition\?/);
    // Alone, it is still refused, with what to open instead.
    await page.setInputFiles('[data-testid=file-input]', contours('bivme-example-patient1', 'SliceInfoFile.txt'));
    await waitForError(page, 'SliceInfoFile.txt');
    assert.match(await status(), /^error: SliceInfoFile\.txt, line 1: this is a biv-me SliceInfoFile .*read the GPFile_\*\.txt beside it$/);
  });

  it('an error with a 250-character token wraps inside the status panel and the banner', async () => {
    await fresh();
    const rows = readFileSync(contours('bivme-example-patient1', 'patient1-ED.csv'), 'utf8').split('\n');
    const huge = rows.map((line, i) => {
      const c = line.split(',');
      if (i === 0 || c.length < 4 || line.startsWith('#')) return line;
      for (const k of [1, 2, 3]) c[k] = String(Number(c[k]) * 1e300);
      return c.join(',');
    });
    // The core prints the span in scientific notation; the long unbroken token is the file's name.
    const name = `huge-${'0123456789'.repeat(25)}.csv`;
    await page.setInputFiles('[data-testid=file-input]', { name, mimeType: 'text/csv', buffer: Buffer.from(huge.join('\n')) });
    await page.waitForFunction(() => document.querySelector('[data-testid=status]')?.textContent?.startsWith('error'), null, { timeout: 30000 });
    assert.match(await status(), /coordinates span \d\.\d\de30\d; expected mm/);
    assert.ok((await status()).includes(name), 'the status names the file');
    const right = await box('#slot-right');
    const view = await box('#slot-viewport');
    assert.ok(inside(await box('[data-testid=status]'), right), 'the status word stays in the right panel');
    assert.equal(await page.locator('#slot-right').evaluate((el) => el.scrollWidth <= el.clientWidth), true, 'no sideways scrolling of the right panel');
    assert.ok(inside(await box('[data-testid=error-banner]'), view), 'the banner stays in the 3D view');
    assert.ok(inside(await box('#slot-warnings'), view), 'the warning line stays in the 3D view');
  });

  it('1024 x 700: the file and surface pickers clear the privacy badge; the Lab\'s legends clear the view controls', async () => {
    await fresh('', { width: 1024, height: 700 });
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', [contours('bivme-test-patient2', 'patient2-ED.csv'), contours('bivme-test-patient2', 'patient2-ES.csv')]));
    assert.equal(await page.isVisible('[data-testid=file-picker]'), true);
    assert.equal(await page.isVisible('[data-testid=surface-picker]'), true);
    const badge = await box('[data-testid=privacy]');
    for (const picker of ['[data-testid=file-picker]', '[data-testid=surface-picker]']) {
      assert.equal(overlapping(await box(picker), badge), false, `${picker} runs under the privacy badge`);
    }
    assert.equal(await page.getAttribute('[data-testid=privacy]', 'title') !== null, true, 'the badge still says it on hover');
    await page.click('[data-testid=tab-lab]');
    await page.click('[data-testid=lab-simulate]');
    await page.waitForFunction(() => (document.querySelector('[data-testid=lab-acq-info]')?.textContent ?? '').includes('SAX'), null, { timeout: 30000 });
    await runAndWait(page, () => page.click('[data-testid=lab-reconstruct]'));
    await page.waitForSelector('[data-testid=legend-truth]:not([hidden])', { timeout: 30000 });
    // The Lab's acquisition is a file of one surface: its picker alone beside the four examples
    // ran under the badge's text before session 32.
    assert.equal(overlapping(await box('[data-testid=file-picker]'), await box('[data-testid=privacy]')), false, 'the Lab file\'s picker runs under the privacy badge');
    const controls = await box('.view-controls');
    for (const legend of ['[data-testid=legend-contours]', '[data-testid=legend-truth]']) {
      assert.equal(overlapping(await box(legend), controls), false, `${legend} under the view controls`);
    }
    await page.mouse.move(0, 0);
    await page.screenshot({ path: join(SHOTS, 'lab-1024x700.png') });
    await page.click('[data-testid=tab-params]');
  });

  it('Esc stops the run from the slider that was just moved (it keeps the focus)', async () => {
    await fresh('?iterations=2000');
    await page.setInputFiles('[data-testid=file-input]', contours('bivme-example-patient1', 'patient1-ED.csv'));
    await page.waitForFunction(() => document.querySelector('[data-testid=status]')?.textContent === 'running', null, { timeout: 30000 });
    const lambda = page.locator('#slot-left input[type=range]').nth(1);
    await lambda.focus();
    // The run id before the key: read after it, the debounced restart may already have begun.
    const first = await statusRunId(page);
    await page.keyboard.press('ArrowLeft'); // restarts the run after the debounce
    await waitForNewRun(page, first, { timeout: 30000 });
    assert.equal(await lambda.evaluate((el) => el === document.activeElement), true, 'the slider still has the focus');
    await page.keyboard.press('Escape');
    await page.waitForFunction(() => document.querySelector('[data-testid=status]')?.textContent === 'stopped', null, { timeout: 10000 });
    assert.match(await page.textContent('[data-testid=result]'), /stopped before the end/);
  });

  it('the hover read-out stays inside the 3D view at its right edge', async () => {
    await fresh('', { width: 1024, height: 700 });
    await runAndWait(page, () => page.click('[data-testid=sample-patient1-ED]'));
    const view = await box('#slot-viewport');
    await page.mouse.move(view.x + view.width / 2, view.y + view.height / 2);
    for (let i = 0; i < 6; i++) await page.mouse.wheel(0, -300); // zoomed in: the mesh fills the view
    await nextFrames(page); // drawn zoomed in: the hover's ray follows the camera of the last frame
    let shown = null;
    for (let y = view.y + 0.3 * view.height; y < view.y + 0.8 * view.height && !shown; y += 20) {
      await page.mouse.move(view.x + view.width - 40, y, { steps: 2 });
      await page.waitForTimeout(150);
      if (await page.isVisible('[data-testid=hover-readout]')) shown = await box('[data-testid=hover-readout]');
    }
    assert.ok(shown, 'a read-out near the right edge');
    assert.ok(inside(shown, view), `read-out ${JSON.stringify(shown)} inside the view ${JSON.stringify(view)}`);
    assert.match(await page.textContent('[data-testid=hover-readout]'), /\d+\.\d\d mm .*\) mm$/);
  });

  it('the app\'s own Parameters JSON or mesh dropped back says what to open instead; the result stays', async () => {
    await fresh();
    await runAndWait(page, () => page.click('[data-testid=sample-patient1-ES]'));
    const shown = await readResult(page);
    const params = await download(page, 'export-json');
    await page.setInputFiles('[data-testid=file-input]', { name: params.name, mimeType: 'application/json', buffer: params.bytes });
    await waitForError(page, params.name);
    assert.match(await page.textContent('[data-testid=error-text]'),
      /^patient1-ES-LV_ENDO-params\.json, line \d+: invalid session JSON: missing field `heartmesh_session`\. Only a heartmesh session opens here \(the Session export, …-session\.json\); the Parameters JSON export holds no contours\. Not opened; still showing patient1-ES\.csv\.$/);
    const mesh = await download(page, 'export-stl');
    await page.setInputFiles('[data-testid=file-input]', { name: mesh.name, mimeType: 'model/stl', buffer: mesh.bytes });
    // The status reads "loading NAME" first, and the JSON's error before that: wait for the mesh's own.
    await waitForError(page, mesh.name);
    assert.match(await page.textContent('[data-testid=error-text]'), /not contours\. To measure a reconstruction against a mesh, open it in the Lab tab as the truth\. Not opened/);
    assert.deepEqual(await readResult(page), shown, 'the result on screen stays');
  });

  it('no page errors', () => {
    assert.deepEqual(pageErrors, []);
  });
});
