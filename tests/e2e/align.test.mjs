// Browser end-to-end tests (dist/, Debian's chromium) of session 9's app work: the "Align
// breath-holds" option on a real biv-me file (residual falls, the shifted contours are the file's
// moved by the reported shifts, the contours as given are offered in the view, exports and URL
// carry the option), the framing of a file the core refuses, and the banner of a file refused at
// load. One aligned run and one refused run keep it to a few seconds of compute.
import { after, before, describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { download as downloadFrom, openApp, readResult, runAndWait, sharedDir, waitForError, SHOTS } from './lib.mjs';

let app;
let page;
/** The aligned run's residual before the shifts (patient 2 ED): what the run without alignment reports. */
let before2 = NaN;

before(async () => {
  app = await openApp();
  ({ page } = app);
});

after(async () => {
  await app?.close();
});

const download = async (testid) => (await downloadFrom(page, testid)).bytes;

describe('breath-hold alignment in the browser', () => {
  it('biv-me patient 2 ED, aligned: residual falls, contours move by the reported shifts', async () => {
    // Checked before any file: nothing runs yet; the option is in the URL at once.
    await page.check('[data-testid=param-align-slices]');
    assert.match(page.url(), /align_slices=1/);
    // The parameter panel for the README and user guide (a taller window so it fits whole).
    await page.setViewportSize({ width: 1280, height: 1000 });
    await page.mouse.move(0, 0);
    await page.locator('section.params').screenshot({ path: join(SHOTS, 'params.png') });
    await page.setViewportSize({ width: 1280, height: 720 });
    const gp = join(sharedDir(), 'data', 'contours', 'bivme-test-patient2', 'GPFile_000.txt');
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', gp), 120000);
    const r = await readResult(page);
    const d = await page.locator('[data-testid=result]').evaluate((el) => ({ ...el.dataset }));
    const before = Number(d.residualBeforeMm);
    before2 = before;
    const afterMm = Number(d.residualAfterMm);
    // The distance to the contours as given, when the core sends it (larger: the mesh follows the shifted ones).
    const given = d.givenMeanMm === undefined ? null : Number(d.givenMeanMm);
    console.log(`# patient2 GPFile_000 aligned: residual ${before.toFixed(3)} -> ${afterMm.toFixed(3)} mm; contour-to-mesh mean ${r.meanMm.toFixed(3)} (shifted), ${given?.toFixed(3) ?? 'not sent'} mm (as given)`);
    assert.ok(before > 0 && afterMm >= 0 && afterMm < before, `residual ${before} -> ${afterMm}`);
    assert.ok(r.meanMm > 0 && r.meanMm <= 1, `mean to the shifted contours ${r.meanMm}`);
    if (given !== null) assert.ok(given > r.meanMm, `mean to the contours as given ${given} vs shifted ${r.meanMm}`);
    // The panel shows the same numbers, and one row per group, largest shift first.
    assert.equal(await page.textContent('[data-testid=result-residual]'), `${before.toFixed(2)} → ${afterMm.toFixed(2)} mm (${(await page.evaluate(() => window.heartmesh.currentResult().alignment.rounds))} rounds)`.replace('(1 rounds)', '(1 round)'));
    const shown = await page.$$eval('[data-testid=alignment-groups] tbody tr td:last-child', (tds) => tds.map((td) => Number(td.textContent)));
    assert.ok(shown.length >= 2, `${shown.length} groups`);
    assert.deepEqual(shown, [...shown].sort((a, b) => b - a));

    // The run's contours are the file's contours moved by their group's shift (float32 exact).
    const check = await page.evaluate(() => {
      const res = window.heartmesh.currentResult();
      const file = window.heartmesh.currentFileData();
      const pts = (points, c) => c.pieces.flatMap((p) => Array.from({ length: p.count }, (_, k) => [0, 1, 2].map((j) => points[(p.start + k) * 3 + j])));
      let worst = 0;
      let checked = 0;
      let largest = 0;
      for (const g of res.alignment.groups) {
        const s = g.shift_mm;
        largest = Math.max(largest, Math.hypot(...s));
        for (const id of g.contour_ids) {
          const run = res.contours.find((c) => c.id === id);
          const mine = file.contours.filter((c) => c.id === id && (c.surface === run?.surface));
          if (!run || mine.length === 0) continue; // another surface's contour: not in this run
          const given = mine.flatMap((c) => pts(file.points, c));
          for (const p of pts(res.contourPoints, run)) {
            let best = Infinity;
            for (const q of given) best = Math.min(best, Math.hypot(p[0] - s[0] - q[0], p[1] - s[1] - q[1], p[2] - s[2] - q[2]));
            worst = Math.max(worst, best);
            checked++;
          }
        }
      }
      return { worst, checked, largest };
    });
    console.log(`# shifted vs as given: ${check.checked} points, largest shift ${check.largest.toFixed(3)} mm, worst mismatch after undoing the shift ${check.worst.toExponential(2)} mm`);
    assert.ok(check.checked > 100, `${check.checked} points checked`);
    assert.ok(check.largest > 0.1, `largest shift ${check.largest} mm`);
    assert.ok(check.worst < 1e-3, `shifted point not the given point + shift: ${check.worst} mm`);

    // The contours as given are offered (and on) in the view controls.
    assert.equal(await page.isEnabled('[data-testid=view-as-given]'), true);
    assert.equal(await page.isChecked('[data-testid=view-as-given]'), true);
    // The picture for the user guide: attractors and landmarks off so the shifted (coloured) and
    // as-given (dashed) contours show, the alignment table in view.
    await page.uncheck('[data-testid=view-attractors]');
    await page.uncheck('[data-testid=view-landmarks]');
    const opacity = (v) => page.$eval('[data-testid=view-opacity]', (el, x) => { el.value = String(x); el.dispatchEvent(new Event('input')); }, v);
    await opacity(45);
    await page.locator('[data-testid=alignment-groups]').scrollIntoViewIfNeeded();
    await page.mouse.move(0, 0);
    await page.waitForTimeout(200);
    await page.screenshot({ path: join(SHOTS, 'align-breath-holds.png') });
    await opacity(100);
    await page.check('[data-testid=view-attractors]');
    await page.check('[data-testid=view-landmarks]');
    assert.doesNotMatch(page.url(), /opacity|attractors_shown|landmarks_shown/);
    // Exports say so.
    const json = JSON.parse((await download('export-json')).toString('utf8'));
    assert.equal(json.align_slices, true);
    assert.equal(json.result.alignment.groups.length, shown.length);
    assert.equal(json.result.contourToMeshAsGivenMm?.mean ?? null, given);
    const obj = (await download('export-obj')).toString('utf8');
    assert.match(obj, /align_slices=true/);
  });

  it('turning it off: no alignment, the as-given toggle is disabled', async () => {
    await runAndWait(page, () => page.uncheck('[data-testid=param-align-slices]'));
    assert.doesNotMatch(page.url(), /align_slices/);
    const d = await page.locator('[data-testid=result]').evaluate((el) => ({ ...el.dataset }));
    assert.equal(d.residualBeforeMm, undefined);
    assert.equal(await page.isVisible('[data-testid=result-alignment]'), false);
    assert.equal(await page.isEnabled('[data-testid=view-as-given]'), false);
    // Off, the panel says how far apart the images cross: the aligned run's residual before, flagged.
    assert.equal(Number(d.crossingResidualMm), before2);
    assert.equal(d.suggestAlignment, '1');
    assert.equal(await page.textContent('[data-testid=result-crossing]'), `${before2.toFixed(2)} mm align`);
    assert.equal(await page.getAttribute('[data-testid=result-crossing]', 'class'), 'warn');
    // Its "align" button ticks the option and runs again: aligned, the row gives way to the alignment box.
    await runAndWait(page, () => page.click('[data-testid=result-align-suggest]'));
    assert.match(page.url(), /align_slices=1/);
    assert.equal(await page.isChecked('[data-testid=param-align-slices]'), true);
    assert.equal(await page.isVisible('[data-testid=result-alignment]'), true);
    assert.equal(await page.$('[data-testid=result-crossing]'), null);
    await runAndWait(page, () => page.uncheck('[data-testid=param-align-slices]'));
  });

  it('a run that meets the stop threshold early says it converged (SurFCo example)', async () => {
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', join(sharedDir(), 'data', 'contours', 'surfco-example.csv')));
    const d = await page.locator('[data-testid=result]').evaluate((el) => ({ ...el.dataset }));
    const detail = (await page.textContent('[data-testid=status-detail]')) ?? '';
    console.log(`# surfco-example: ${detail} | result iterations ${d.iterations}, converged ${d.converged}`);
    assert.equal(d.converged, '1');
    const n = Number(d.iterations);
    assert.ok(n > 0 && n < 250, `iterations ${n}`);
    assert.ok(detail.startsWith(`converged at iteration ${n} (of 250)`), detail);
    assert.equal(await page.textContent('[data-testid=result-iterations]'), `${n} (converged)`);
    const json = JSON.parse((await download('export-json')).toString('utf8'));
    assert.equal(json.result.iterations, n);
    assert.equal(json.result.converged, true);
  });

  it('a file in metres is refused by the core but framed at its own size; a file refused at load keeps it', async () => {
    const csv = readFileSync(join(sharedDir(), 'data', 'contours', 'surfco-example.csv'), 'utf8');
    // The SurFCo example in metres: every coordinate / 1000 (the header row stays).
    const metres = csv.split('\n').map((line, i) => (i === 0 || !line ? line : line.split(',').map((v, k) => (k === 0 ? v : String(Number(v) / 1000))).join(','))).join('\n');
    await page.setInputFiles('[data-testid=file-input]', { name: 'surfco-metres.csv', mimeType: 'text/csv', buffer: Buffer.from(metres) });
    await page.waitForFunction(() => document.querySelector('[data-testid=status]')?.textContent?.startsWith('error'), null, { timeout: 20000 });
    assert.match(await page.textContent('[data-testid=status]'), /metres\?/);
    const radius = Number(await page.getAttribute('[data-testid=viewport-canvas]', 'data-view-radius'));
    console.log(`# surfco in metres: framed radius ${radius}`);
    assert.ok(radius > 0.005 && radius < 0.2, `framed radius ${radius} (a heart in metres)`);
    await page.mouse.move(0, 0);
    await page.screenshot({ path: join(SHOTS, 'refused-metres.png') });
    // A file that cannot be read at all: not opened, the view keeps the refused-but-loaded file.
    await page.setInputFiles('[data-testid=file-input]', { name: 'broken.csv', mimeType: 'text/csv', buffer: Buffer.from('contour,x,y,z\nc1,1,2,3\nc1,1,oops,3\n') });
    // The status reads "loading broken.csv" first, with the metres refusal still in the banner: wait for its own error.
    await waitForError(page, 'broken.csv');
    assert.match(await page.textContent('[data-testid=error-text]'), /Not opened; still showing surfco-metres\.csv\./);
    assert.equal(Number(await page.getAttribute('[data-testid=viewport-canvas]', 'data-view-radius')), radius);
  });
});
