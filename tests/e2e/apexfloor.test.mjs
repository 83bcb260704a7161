// Browser end-to-end test (dist/, Debian's chromium) of the apex floor (session 14: on by default in
// the core) in the app. A short-axis-only ellipsoid (built here, tests/e2e/saxOnly.mjs): no
// long-axis curve reaches its apex, so at the defaults the apex gets the floor and the result
// panel's "Closed ends" row says "apex floor"; unticking "Apex floor (short-axis-only stacks)"
// runs again without it (the row no longer says it, the volume changes, the link says
// apex_floor=0), the exports and a session record it, and the session opens again with it
// unticked. The panel's option rows do not overlap at 1280x720 and 1024x700.
import { describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { download as downloadFrom, gotoEmpty, runAndWait, SHOTS } from './lib.mjs';
import { appForFile } from './perFile.mjs';
import { SAX_ONLY_NAME, saxOnlyEllipsoid } from './saxOnly.mjs';

let server;
let page;
appForFile({ goto: false }, (app) => ({ server, page } = app));

const { csv } = saxOnlyEllipsoid();
const drop = () => page.setInputFiles('[data-testid=file-input]', { name: SAX_ONLY_NAME, mimeType: 'text/csv', buffer: Buffer.from(csv) });
const dataset = () => page.locator('[data-testid=result]').evaluate((el) => ({ ...el.dataset }));
const closedEnds = async () => (await page.textContent('[data-testid=result-end-caps]')) ?? '';
const volumeRow = async () => (await page.locator('[data-testid=result] dt:text-is("Volume") + dd').textContent()) ?? '';
const volumeMl = () => page.evaluate(() => window.heartmesh.currentResult().volumeMl);
const BOX = '[data-testid=param-apex-floor]';

/** The parameter panel's option rows (checkboxes and the smoothing select) at this window size: none overlaps another or spills sideways. */
async function optionRowsFit(label) {
  const boxes = await page.$$eval('section.params .param-option, section.params .panel-actions', (rows) => rows.map((r) => {
    const b = r.getBoundingClientRect();
    return { text: r.textContent.slice(0, 40), top: b.top, bottom: b.bottom, left: b.left, right: b.right };
  }));
  const sidebar = await page.$eval('.sidebar.left', (s) => ({ ...s.getBoundingClientRect().toJSON(), scrollWidth: s.scrollWidth, clientWidth: s.clientWidth }));
  assert.ok(boxes.length >= 6, `${boxes.length} option rows`);
  for (let i = 1; i < boxes.length; i++) {
    assert.ok(boxes[i].top >= boxes[i - 1].bottom - 0.5, `${label}: "${boxes[i].text}" overlaps "${boxes[i - 1].text}"`);
  }
  for (const b of boxes) assert.ok(b.left >= sidebar.left - 0.5 && b.right <= sidebar.right + 0.5, `${label}: "${b.text}" leaves the panel`);
  assert.ok(sidebar.scrollWidth <= sidebar.clientWidth, `${label}: the panel scrolls sideways (${sidebar.scrollWidth} > ${sidebar.clientWidth})`);
  // The label itself stays on one line beside its checkbox.
  const label1 = await page.$eval('label[for=param-apex-floor]', (l) => l.getBoundingClientRect().height);
  assert.ok(label1 < 40, `${label}: the label is ${label1} px tall`);
}

describe('the apex floor in the browser', () => {
  it('a short-axis-only ellipsoid: "apex floor" in Closed ends; unticked, another run without it', async () => {
    await gotoEmpty(page, server.url);
    assert.equal(await page.isChecked(BOX), true, 'on by default');
    assert.equal(await page.isDisabled(BOX), false);
    assert.equal(await page.textContent('label[for=param-apex-floor]'), 'Apex floor (short-axis-only stacks)');
    const tip = (await page.locator(BOX).locator('xpath=ancestor::div[contains(@class, "param-row")][1]').getAttribute('title')) ?? '';
    assert.match(tip, /for short-axis-only stacks \(no long-axis curve reaches the apex\)/);
    assert.match(tip, /on by default/);
    // The panel fits with the new row at the smaller windows the app supports.
    for (const [width, height] of [[1280, 720], [1024, 700]]) {
      await page.setViewportSize({ width, height });
      await optionRowsFit(`${width}x${height}`);
      await page.locator('[data-testid=reset-params]').scrollIntoViewIfNeeded();
      await page.screenshot({ path: join(SHOTS, `params-panel-${width}x${height}.png`) });
    }
    await page.setViewportSize({ width: 1280, height: 720 });

    // Floor on (the default): one point at the tip, named in the row.
    await runAndWait(page, drop, 120000);
    assert.equal(await page.inputValue('[data-testid=surface-picker]'), 'LV_ENDO');
    const on = await dataset();
    assert.equal(on.endCapsApexFloor, '1');
    assert.equal(on.endCapsBase, '1');
    const onRow = await closedEnds();
    assert.match(onRow, /^base · apex floor · \d+ pts$/);
    assert.match((await page.getAttribute('[data-testid=result-end-caps]', 'title')) ?? '', /apex floored .*one lid point at the tip the apical rings' taper predicts/);
    assert.equal(await page.evaluate(() => window.heartmesh.currentResult().options.apex_floor), true);
    const onVolume = await volumeMl();
    const onVolumeText = await volumeRow();
    assert.equal(onVolumeText, `${onVolume.toFixed(1)} ml`);
    assert.doesNotMatch(page.url(), /apex_floor/, 'the default is not written into the link');
    // The floored apex is not flagged amber as extrapolated; past 5 mm the tooltip says the floor placed it.
    const pastTitle = (await page.getAttribute('[data-testid=result-past-data]', 'title')) ?? '';
    // Neither end is amber: the base is under the ceiling of a base no long-axis curve reaches
    // (one slice spacing past the top ring, by design) and the apex is floored; the tooltip says both.
    assert.equal(on.endCapsBaseCeiling, '1');
    assert.equal(await page.getAttribute('[data-testid=result-past-data]', 'class'), null,
      `not amber (base ${on.pastBaseMm} mm, apex ${on.pastApexMm} mm)`);
    if (Number(on.pastBaseMm) > 5) assert.match(pastTitle, /a ceiling one slice spacing beyond that ring/);
    else assert.doesNotMatch(pastTitle, /ceiling/);
    if (Number(on.pastApexMm) > 5) assert.match(pastTitle, /the apex floor placed the tip/);
    else assert.doesNotMatch(pastTitle, /apex floor/);
    await page.mouse.move(0, 0);
    await page.screenshot({ path: join(SHOTS, 'apex-floor.png') });

    // Unticked: a new run without it; the row says the base only, the mesh stops higher, the volume changes.
    await runAndWait(page, () => page.uncheck(BOX), 120000);
    assert.match(page.url(), /apex_floor=0/);
    const off = await dataset();
    assert.equal(off.endCapsApexFloor, '0');
    const offRow = await closedEnds();
    assert.doesNotMatch(offRow, /apex floor/);
    assert.match(offRow, /^base · \d+ pts$/);
    assert.equal(Number(offRow.match(/(\d+) pts/)[1]), Number(onRow.match(/(\d+) pts/)[1]) - 1, 'one lid point fewer');
    assert.equal(await page.evaluate(() => window.heartmesh.currentResult().options.apex_floor), false);
    const offVolume = await volumeMl();
    assert.notEqual(offVolume, onVolume);
    assert.notEqual(await volumeRow(), onVolumeText, 'the shown volume changes');
    assert.ok(Number(off.pastApexMm) < Number(on.pastApexMm), `the apex stops higher without the floor (${off.pastApexMm} vs ${on.pastApexMm} mm)`);
    console.log(`# ${SAX_ONLY_NAME}: "${onRow}" ${onVolume.toFixed(2)} ml, apex ${Number(on.pastApexMm).toFixed(2)} mm past the lowest ring; ` +
      `unticked "${offRow}" ${offVolume.toFixed(2)} ml, ${Number(off.pastApexMm).toFixed(2)} mm`);

    // The exports record it; a session keeps it and opens again with it unticked.
    const json = JSON.parse((await downloadFrom(page, 'export-json')).bytes.toString('utf8'));
    assert.equal(json.apex_floor, false);
    assert.equal(json.result.end_caps.apex_floor, undefined);
    const obj = (await downloadFrom(page, 'export-obj')).bytes.toString('utf8');
    assert.match(obj, /apex_floor=false/);
    const session = await downloadFrom(page, 'export-session');
    assert.equal(JSON.parse(session.bytes.toString('utf8')).parameters.apex_floor, false);
    await gotoEmpty(page, server.url);
    assert.equal(await page.isChecked(BOX), true);
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', { name: session.name, mimeType: 'application/json', buffer: session.bytes }), 120000);
    assert.equal(await page.isChecked(BOX), false, 'the session\'s apex_floor: false unticks it');
    assert.match(page.url(), /apex_floor=0/);
    assert.doesNotMatch(await closedEnds(), /apex floor/);

    // Ticked again: the floor is back. Without Close open ends it has nothing to act through: greyed out.
    await runAndWait(page, () => page.check(BOX), 120000);
    assert.doesNotMatch(page.url(), /apex_floor/);
    assert.match(await closedEnds(), /apex floor/);
    assert.equal((await volumeMl()).toFixed(6), onVolume.toFixed(6));
    await runAndWait(page, () => page.uncheck('[data-testid=param-end-caps]'), 120000);
    assert.equal(await page.isDisabled(BOX), true);
    assert.equal(await page.isChecked(BOX), true);
    assert.equal(await page.locator('[data-testid=result-end-caps]').count(), 0);
  });
});
