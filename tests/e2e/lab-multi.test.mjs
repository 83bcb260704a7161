// Browser end-to-end test of the Lab with two truths (session 29) on the built site in Debian's
// chromium: biv-me patient 1's LV and RV cavities at ED dropped together become two truths
// labelled from their names, one acquisition slices both (the CSV's surface column), and each
// surface's reconstruction is compared with its own truth: LV mean < 0.3 mm, RV mean < 0.6 mm,
// each measured on the truth of its label (the RV's numbers are not the LV truth's). A label
// another truth has is refused with a message and the truths stay. The same two surfaces saved by
// tools in different patient frames (the LV stating LPS, the RV mirrored into RAS and stating it)
// are sliced in one frame: the RV taken into the LV's, said on the truth line, the acquisition the
// same as the untagged pair's. The screenshots lab-two-surfaces.png and lab-frames.png go to the
// screenshot folder (tests/e2e/lib.mjs SHOTS).
import { after, before, describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { openApp, runAndWait, sharedDir, SHOTS, setField } from './lib.mjs';

const MESHES = ['bivme-patient1-ED-LV_ENDO-closed.obj', 'bivme-patient1-ED-RV_ENDO-closed.obj'];

let app;
let page;
const pageErrors = [];
/** The acquisition rows of the untagged pair (the first test), for the pair in two frames. */
let untaggedRows;

/** `text` (an OBJ) stating `space` first; `mirror`: every vertex taken to the other frame. */
function inFrame(text, space, mirror) {
  const body = text
    .split('\n')
    .map((line) => {
      if (!mirror || !line.startsWith('v ')) return line;
      const [x, y, z] = line.slice(2).trim().split(/\s+/).map(Number);
      return `v ${-x} ${-y} ${z}`;
    })
    .join('\n');
  return `# SPACE=${space}\n${body}`;
}

before(async () => {
  app = await openApp({ viewport: { width: 1440, height: 900 }, onPageError: (m) => pageErrors.push(m) });
  ({ page } = app);
});

after(async () => {
  await app?.close();
});

/** Sets a Lab form field (see `setField`). */
const setValue = (testid, value) => setField(page, testid, value);

/** Drops files `names` holding `bodies` (OBJ text) on the page, as a user drags meshes in. */
async function dropMeshes(names, bodies) {
  await page.evaluate(
    ([ns, bs]) => {
      const dt = new DataTransfer();
      ns.forEach((n, i) => dt.items.add(new File([bs[i]], n, { type: 'model/obj' })));
      document.body.dispatchEvent(new DragEvent('drop', { dataTransfer: dt, bubbles: true, cancelable: true }));
    },
    [names, bodies],
  );
}

/** Simulates 8 SAX + 2 LAX images of the truths held; each surface's row of the acquisition. */
async function simulateEightAndTwo() {
  await setValue('lab-sax', 8);
  await setValue('lab-lax', 2);
  await page.click('[data-testid=lab-simulate]');
  await page.waitForFunction(() => document.querySelectorAll('[data-testid=lab-acq-surface]').length === 2, null, { timeout: 30000 });
  return page.locator('[data-testid=lab-acq-surface]').evaluateAll((els) =>
    els.map((e) => ({ label: e.getAttribute('data-label'), sax: Number(e.getAttribute('data-sax')), lax: Number(e.getAttribute('data-lax')), points: Number(e.getAttribute('data-points')) })),
  );
}

/** The metrics of the comparison of `surface` once they are in (after a run of it). */
async function metricsOf(surface) {
  await page.waitForFunction(
    (s) => {
      const info = document.querySelector('[data-testid=lab-compare-info]');
      return info?.getAttribute('data-surface') === s && info.getAttribute('data-truth') !== null &&
        document.querySelector('[data-testid=lab-metrics]')?.hasAttribute('data-mean') && info.textContent !== '';
    },
    surface,
    { timeout: 60000 },
  );
  return page.evaluate(() => {
    const m = document.querySelector('[data-testid=lab-metrics]');
    const info = document.querySelector('[data-testid=lab-compare-info]');
    return {
      m2t: Number(m?.getAttribute('data-m2t')),
      t2m: Number(m?.getAttribute('data-t2m')),
      truth: info?.getAttribute('data-truth'),
      text: info?.textContent ?? '',
      volumes: m?.querySelector('[data-testid=lab-volumes]')?.textContent ?? '',
    };
  });
}

describe('the Lab with two truths', () => {
  it('LV and RV dropped together: one acquisition, each surface compared with its own truth', async () => {
    await page.click('[data-testid=tab-lab]');
    await page.waitForSelector('[data-testid=lab-truth-info][data-vertices]', { timeout: 30000 });
    const texts = MESHES.map((name) => readFileSync(join(sharedDir(), 'data', 'meshes', name), 'utf8'));
    await dropMeshes(MESHES, texts);
    await page.waitForSelector('[data-testid=lab-truth-info][data-count="2"]', { timeout: 30000 });
    const labels = await page.locator('[data-testid=lab-truth-label]').evaluateAll((els) => els.map((e) => e.value));
    assert.deepEqual(labels, ['LV_ENDO', 'RV_ENDO'], 'labels guessed from the file names');
    assert.equal((await page.textContent('[data-testid=lab-message]')) ?? '', '');

    const rows = await simulateEightAndTwo();
    console.log(`# lab two truths: ${(await page.textContent('[data-testid=lab-acq-info]')) ?? ''}; ${JSON.stringify(rows)}`);
    assert.deepEqual(rows.map((r) => r.label), ['LV_ENDO', 'RV_ENDO']);
    untaggedRows = rows;
    for (const r of rows) assert.ok(r.sax >= 5 && r.lax === 2 && r.points > 100, JSON.stringify(r));
    // The app lists the file's surfaces, as for any multi-surface file.
    const surfaces = await page.locator('[data-testid=surface-picker] option').evaluateAll((els) => els.map((e) => e.value));
    assert.ok(surfaces.includes('LV_ENDO') && surfaces.includes('RV_ENDO'), `surfaces ${surfaces}`);

    if ((await page.inputValue('[data-testid=surface-picker]')) === 'LV_ENDO') {
      await runAndWait(page, () => page.click('[data-testid=lab-reconstruct]'));
    } else {
      await runAndWait(page, () => page.selectOption('[data-testid=surface-picker]', 'LV_ENDO'));
    }
    const lv = await metricsOf('LV_ENDO');
    await runAndWait(page, () => page.selectOption('[data-testid=surface-picker]', 'RV_ENDO'));
    const rv = await metricsOf('RV_ENDO');
    console.log(`# lab LV_ENDO: mesh->truth ${lv.m2t.toFixed(3)} mm, truth->mesh ${lv.t2m.toFixed(3)} mm, ${lv.volumes} (${lv.text})`);
    console.log(`# lab RV_ENDO: mesh->truth ${rv.m2t.toFixed(3)} mm, truth->mesh ${rv.t2m.toFixed(3)} mm, ${rv.volumes} (${rv.text})`);
    assert.equal(lv.truth, 'LV_ENDO');
    assert.equal(rv.truth, 'RV_ENDO');
    assert.ok(lv.m2t > 0 && lv.m2t < 0.3 && lv.t2m > 0 && lv.t2m < 0.3, `LV means ${lv.m2t} ${lv.t2m}`);
    assert.ok(rv.m2t > 0 && rv.m2t < 0.6 && rv.t2m > 0 && rv.t2m < 0.6, `RV means ${rv.m2t} ${rv.t2m}`);
    assert.notEqual(rv.m2t, lv.m2t, 'the RV is measured against its own truth');
    assert.notEqual(rv.volumes, lv.volumes, 'the RV truth volume is not the LV truth volume');
    assert.equal(await page.isVisible('[data-testid=legend-truth]'), true, 'distance map on the RV truth');
    await page.locator('[data-testid=lab-compare]').scrollIntoViewIfNeeded();
    await page.mouse.move(0, 0);
    await page.screenshot({ path: join(SHOTS, 'lab-two-surfaces.png') });

    // Leave-one-out and the sweep act on the current surface (RV_ENDO), the sweep against its truth.
    await page.click('[data-testid=lab-loo-run]');
    await page.waitForSelector('[data-testid=lab-loo-info][data-done="1"]', { timeout: 240000 });
    const rvRow = rows.find((r) => r.label === 'RV_ENDO');
    assert.equal(await page.locator('[data-testid=loo-bar]').count(), rvRow.sax + rvRow.lax, 'one bar per RV contour');
    await setValue('lab-grid-lambda', '1e3, 1e5');
    await setValue('lab-grid-smoothing', '200');
    await setValue('lab-grid-reduction', '0.72');
    await setValue('lab-grid-spacing', '0');
    await page.click('[data-testid=lab-sweep-run]');
    await page.waitForSelector('[data-testid=lab-sweep-info][data-done="1"]', { timeout: 240000 });
    const [dl] = await Promise.all([page.waitForEvent('download'), page.click('[data-testid=lab-sweep-csv]')]);
    const csv = readFileSync(await dl.path(), 'utf8');
    assert.match(csv, /^# heartmesh parameter sweep of lab-LV_ENDO-RV_ENDO-8sax-2lax\.csv \(RV_ENDO\) against bivme-patient1-ED-RV_ENDO-closed\.obj/);
    const lines = csv.split('\n').filter((l) => l && !l.startsWith('#'));
    const header = lines[0].split(',');
    const sweepMeans = lines.slice(1).map((l) => Number(l.split(',')[header.indexOf('truth_mean')]));
    console.log(`# lab sweep of RV_ENDO: truth means ${sweepMeans.map((m) => m.toFixed(3)).join(', ')} mm`);
    assert.equal(sweepMeans.length, 2);
    for (const m of sweepMeans) assert.ok(m > 0 && m < 3, `sweep truth mean ${m}`);
    // λ 1e5 with these settings is the run on screen: the same distance to the same (RV) truth.
    assert.ok(Math.abs(sweepMeans[1] - rv.m2t) < 0.02, `sweep λ 1e5 ${sweepMeans[1]} vs run ${rv.m2t}`);

    // A label the other truth has: refused with a message naming it, the truths unchanged.
    await page.locator('[data-testid=lab-truth]').scrollIntoViewIfNeeded();
    await page.locator('[data-testid=lab-truth-label]').nth(1).evaluate((el) => {
      el.value = 'lv_endo';
      el.dispatchEvent(new Event('change', { bubbles: true }));
    });
    await page.waitForFunction(() => document.querySelector('[data-testid=lab-message]')?.classList.contains('error'), null, { timeout: 10000 });
    assert.match((await page.textContent('[data-testid=lab-message]')) ?? '', /RV_ENDO-closed\.obj: the label lv_endo is already truth 1's/);
    const after = await page.locator('[data-testid=lab-truth-label]').evaluateAll((els) => els.map((e) => e.value));
    assert.deepEqual(after, ['LV_ENDO', 'RV_ENDO']);

    // A dropped file that is no mesh (a face naming a missing vertex): said in a message naming
    // it, the two truths kept, the page alive.
    await page.evaluate(() => {
      const dt = new DataTransfer();
      dt.items.add(new File(['v 0 0 0\nv 1 0 0\nf 1 2 9\n'], 'broken-LV_EPI.obj', { type: 'model/obj' }));
      document.body.dispatchEvent(new DragEvent('drop', { dataTransfer: dt, bubbles: true, cancelable: true }));
    });
    await page.waitForFunction(() => /broken-LV_EPI\.obj/.test(document.querySelector('[data-testid=lab-message]')?.textContent ?? ''), null, { timeout: 15000 });
    const said = (await page.textContent('[data-testid=lab-message]')) ?? '';
    console.log(`# lab broken truth: ${said}`);
    // The file and its line said once each.
    assert.match(said, /^broken-LV_EPI\.obj, line 3: face refers to vertex 9/);
    assert.equal(await page.getAttribute('[data-testid=lab-truth-info]', 'data-count'), '2');
    const kept = await page.locator('[data-testid=lab-truth-label]').evaluateAll((els) => els.map((e) => e.value));
    assert.deepEqual(kept, ['LV_ENDO', 'RV_ENDO']);
    assert.deepEqual(pageErrors, []);
  });
  it('an RV saved in RAS beside an LV in LPS is sliced in the LV\'s frame, and the line says so', async () => {
    await page.locator('[data-testid=lab-truth]').scrollIntoViewIfNeeded();
    // Dropped beside truths from files, meshes join them: remove those first.
    while ((await page.locator('[data-testid=lab-truth-remove]').count()) > 0) {
      const n = await page.locator('[data-testid=lab-truth-remove]').count();
      await page.locator('[data-testid=lab-truth-remove]').first().click();
      await page.waitForFunction((k) => document.querySelectorAll('[data-testid=lab-truth-remove]').length === k - 1, n, { timeout: 10000 });
    }
    const texts = MESHES.map((name) => readFileSync(join(sharedDir(), 'data', 'meshes', name), 'utf8'));
    const bodies = [inFrame(texts[0], 'LPS', false), inFrame(texts[1], 'RAS', true)];
    const names = ['heart-LV_ENDO-lps.obj', 'heart-RV_ENDO-ras.obj'];
    await dropMeshes(names, bodies);
    await page.waitForFunction(() => (document.querySelector('[data-testid=lab-truth-info]')?.textContent ?? '').includes('taken into'), null, { timeout: 30000 });
    const info = (await page.textContent('[data-testid=lab-truth-info]')) ?? '';
    assert.equal(
      info,
      "2 surfaces of one heart (LV_ENDO, RV_ENDO), sliced on one acquisition planned on the first; RV_ENDO's file is in RAS: taken into LPS, the first's frame (x and y negated)",
    );
    const converted = await page.locator('[data-testid=lab-truth-row]').evaluateAll((els) => els.map((e) => e.getAttribute('data-converted-from')));
    assert.deepEqual(converted, [null, 'RAS']);
    const rows = await simulateEightAndTwo();
    console.log(`# lab in two frames: ${JSON.stringify(rows)} (untagged pair ${JSON.stringify(untaggedRows)})`);
    // The RV lies where the untagged pair's does: the same slices hit it with the same points.
    assert.deepEqual(rows, untaggedRows);
    await page.mouse.move(0, 0);
    await page.screenshot({ path: join(SHOTS, 'lab-frames.png') });
    assert.deepEqual(pageErrors, []);
  });
});
