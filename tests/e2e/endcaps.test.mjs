// Browser end-to-end test (dist/, Debian's chromium) of session 10's "Close open ends" option on a
// real biv-me file: patient 2 ES right ventricle has no RV long-axis curve, so its base is open and
// the mesh runs on past the top slice; ticking the option closes that end with lid points, the
// result panel says so, the mesh stops near the data, and the URL, the exports and a session carry
// the option. Two runs of one surface keep it to a few seconds of compute.
import { describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { download as downloadFrom, gotoEmpty, readResult, runAndWait, sharedDir, SHOTS } from './lib.mjs';
import { appForFile } from './perFile.mjs';

let server;
let page;
appForFile({ goto: false }, (app) => ({ server, page } = app));

const download = (testid) => downloadFrom(page, testid);

const count = () => page.evaluate(() => window.heartmesh.currentResult().overall.count);
const dataset = () => page.locator('[data-testid=result]').evaluate((el) => ({ ...el.dataset }));

describe('close open ends in the browser', () => {
  it('patient 2 ES RV: the open base is closed, the mesh stops at the data, the option travels', async () => {
    const csv = join(sharedDir(), 'data', 'contours', 'bivme-test-patient2', 'patient2-ES.csv');
    await page.goto(`${server.url}?surface=RV_ENDO&end_caps=off`);
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', csv), 120000);
    assert.equal(await page.inputValue('[data-testid=surface-picker]'), 'RV_ENDO');
    assert.equal(await page.isChecked('[data-testid=param-end-caps]'), false);
    const off = await dataset();
    const offResult = await readResult(page);
    assert.equal(await page.locator('[data-testid=result-end-caps]').count(), 0, 'no "Closed ends" row with the option off');
    const offCount = await count();
    assert.ok(offCount > 0);
    await page.screenshot({ path: join(SHOTS, 'past-data-rv.png') });

    await runAndWait(page, () => page.check('[data-testid=param-end-caps]'), 120000);
    // Ticked is the app's default (auto): the link no longer needs to say it.
    assert.doesNotMatch(page.url(), /end_caps/);
    const on = await dataset();
    const onResult = await readResult(page);
    console.log(`# patient2-ES RV: past the data base ${Number(off.pastBaseMm).toFixed(1)} -> ${Number(on.pastBaseMm).toFixed(1)} mm, ` +
      `${on.endCapsPoints} lid points; contour-to-mesh mean ${offResult.meanMm.toFixed(3)} -> ${onResult.meanMm.toFixed(3)} mm`);
    assert.equal(on.endCapsBase, '1');
    assert.ok(Number(on.endCapsPoints) > 0, `lid points ${on.endCapsPoints}`);
    assert.ok(Number(on.pastBaseMm) < Number(off.pastBaseMm), `base past the data ${off.pastBaseMm} -> ${on.pastBaseMm}`);
    assert.ok(Number(off.pastBaseMm) > 5, `the base is open without the option (${off.pastBaseMm} mm)`);
    const row = (await page.textContent('[data-testid=result-end-caps]')) ?? '';
    assert.match(row, /^(base|both) · \d+ pts?$/);
    assert.match((await page.getAttribute('[data-testid=result-end-caps]', 'title')) ?? '', /closed \(\d+ lid points?\)/);
    // Lid points are not data: the contour-to-mesh figures count the file's points only.
    assert.equal(await count(), offCount);
    // The mesh a volume mesher would take: closed, no triangles through each other (session 13).
    assert.equal(on.selfIntersections, '0');
    assert.equal(await page.textContent('[data-testid=result-self-intersections]'), 'none');
    assert.equal(await page.getAttribute('[data-testid=result-self-intersections]', 'class'), null);
    assert.equal(await page.textContent('[data-testid=result-folded-edges]'), on.foldedEdges);
    await page.mouse.move(0, 0);
    await page.screenshot({ path: join(SHOTS, 'close-open-ends.png') });

    // Exports record it; a session brings it back.
    const json = JSON.parse((await download('export-json')).bytes.toString('utf8'));
    assert.equal(json.end_caps, 'auto');
    const obj = (await download('export-obj')).bytes.toString('utf8');
    assert.match(obj, /end_caps=auto/);
    const session = await download('export-session');
    assert.equal(JSON.parse(session.bytes.toString('utf8')).parameters.end_caps, 'auto');
    await gotoEmpty(page, `${server.url}?end_caps=off`);
    assert.equal(await page.isChecked('[data-testid=param-end-caps]'), false);
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', { name: session.name, mimeType: 'application/json', buffer: session.bytes }), 120000);
    assert.equal(await page.isChecked('[data-testid=param-end-caps]'), true);
    assert.equal((await dataset()).endCapsBase, '1');
    // Unticked (not the default), the link says so.
    await runAndWait(page, () => page.uncheck('[data-testid=param-end-caps]'), 120000);
    assert.match(page.url(), /end_caps=off/);
  });

  it('patient 1 ED RV: a base with no room for a lid gets one nearer the rim once it runs on (100 attractors), is said open when not even that fits (20)', async () => {
    const csv = join(sharedDir(), 'data', 'contours', 'bivme-example-patient1', 'patient1-ED.csv');
    const volume = () => page.evaluate(() => window.heartmesh.currentResult().volumeMl);
    const endCaps = async () => ({
      text: (await page.textContent('[data-testid=result-end-caps]')) ?? '',
      cls: await page.getAttribute('[data-testid=result-end-caps]', 'class'),
      title: (await page.getAttribute('[data-testid=result-end-caps]', 'title')) ?? '',
    });
    const runAt = async (query) => {
      await gotoEmpty(page, `${server.url}?surface=RV_ENDO${query}`);
      await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', csv), 120000);
      assert.equal(await page.inputValue('[data-testid=surface-picker]'), 'RV_ENDO');
      return { d: await dataset(), ml: await volume(), caps: await endCaps() };
    };
    const few = await runAt('&attractors=20');
    assert.equal(few.d.endCapsBaseTooNarrow, '1');
    assert.equal(few.d.endCapsBaseRimLidAt, '');
    assert.equal(few.d.endCapsPoints, '0');
    assert.equal(few.caps.text, 'base open');
    assert.equal(few.caps.cls, 'warn');
    assert.match(few.caps.title, /^base left open: no contour closes the base, and at this attractor spacing \(\d+\.\d mm\) its outline has no room for lid points, even near its rim/);
    await page.mouse.move(0, 0);
    await page.screenshot({ path: join(SHOTS, 'base-open.png') });
    const late = await runAt('&attractors=100');
    assert.equal(late.d.endCapsBaseTooNarrow, '1');
    const at = Number(late.d.endCapsBaseRimLidAt);
    assert.ok(at > 50 && (at - 1) % 25 === 0, `rim lid at step ${late.d.endCapsBaseRimLidAt}`);
    assert.ok(Number(late.d.endCapsPoints) >= 1);
    assert.match(late.caps.text, /^(rim lid|both, rim) · \d+ pts$/);
    assert.equal(late.caps.cls, null);
    assert.match(late.caps.title, new RegExp(`at step ${at} its lid was laid nearer the rim$`));
    await page.mouse.move(0, 0);
    await page.screenshot({ path: join(SHOTS, 'base-rim-lid.png') });
    // At the default count the base gets its lid from the start; the rim lid's volume is near it.
    const lidded = await runAt('');
    console.log(`# patient1-ED RV: base past the data ${Number(few.d.pastBaseMm).toFixed(1)} mm open (20 attractors), ` +
      `${Number(late.d.pastBaseMm).toFixed(1)} mm with the rim lid at step ${at} (100), ${Number(lidded.d.pastBaseMm).toFixed(1)} mm ` +
      `lidded (${lidded.d.endCapsPoints} points, defaults); ${few.ml.toFixed(1)} / ${late.ml.toFixed(1)} / ${lidded.ml.toFixed(1)} ml`);
    assert.equal(lidded.d.endCapsBaseTooNarrow, '0');
    assert.match(lidded.caps.text, /^base · \d+ pts$/);
    assert.ok(Number(few.d.pastBaseMm) > Number(lidded.d.pastBaseMm) + 3, `${few.d.pastBaseMm} vs ${lidded.d.pastBaseMm}`);
    assert.ok(Number(late.d.pastBaseMm) < 2, late.d.pastBaseMm);
    assert.ok(few.ml > lidded.ml * 1.1, `${few.ml} vs ${lidded.ml} ml`);
    assert.ok(Math.abs(late.ml - lidded.ml) < 0.05 * lidded.ml, `${late.ml} vs ${lidded.ml} ml`);
  });
});
