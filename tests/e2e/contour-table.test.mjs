// Browser end-to-end test (dist/, Debian's chromium) of the Contours panel: the bundled Patient 1 ·
// ED (LV_ENDO) lists its 8 contours (5 SAX, 3 LAX) with each one's distance to the mesh, the
// largest of them the result panel's max; a row hovered highlights its contour in the 3D view and a
// contour point hovered names its contour and lights its row; unticking a long-axis contour runs
// again without it (the core's `leave_out`: "left out by you" in the table, the result panel's Left
// out row, the key and the read-out, which gives how far the mesh built without it passes the
// point under the pointer; another volume), its row then shows how far that mesh passes the
// whole contour (s07_LAX: mean 1.83, max 7.66 mm, the Lab's leave-one-out figures for it), a
// click on the max header sorts the rows by it both ways and back to the file's order, the
// panel's CSV holds the table's figures in its order, the exports and a saved session record it, the session opened again leaves it out again, and
// ticking it back (or Use all) gives the first mesh again to the last digit. One list serves
// every surface of the file, as the CLI's --leave-out: with Align breath-holds on, the LV_ENDO
// contour left out is out of the RV_ENDO run's alignment too (its volume the CLI's, computed by
// tests/node/leaveOutFile.test.ts), and without alignment the RV mesh is the one of every contour.
import { describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { download as downloadFrom, gotoEmpty, nextFrames, readResult, runAndWait, SHOTS } from './lib.mjs';
import { appForFile } from './perFile.mjs';

let server;
let page;
appForFile({ goto: false }, (app) => ({ server, page } = app));

const ROW = '[data-testid=contour-row]';
const row = (id) => `${ROW}[data-id="${id}"]`;

/** The table as the page shows it: each row's data and cells, and the panel's attributes. */
const readTable = () =>
  page.evaluate((sel) => {
    const details = document.querySelector('[data-testid=contour-table]');
    const rows = [...document.querySelectorAll(sel)].map((tr) => ({
      id: tr.dataset.id,
      kind: tr.dataset.kind,
      state: tr.dataset.state,
      count: Number(tr.dataset.count),
      meanMm: tr.dataset.meanMm === undefined ? null : Number(tr.dataset.meanMm),
      maxMm: tr.dataset.maxMm === undefined ? null : Number(tr.dataset.maxMm),
      cells: [...tr.querySelectorAll('td')].map((td) => td.textContent),
      checked: tr.querySelector('[data-testid=contour-use]').checked,
      disabled: tr.querySelector('[data-testid=contour-use]').disabled,
      highlighted: tr.classList.contains('highlighted'),
    }));
    return { rows, count: details.dataset.count, stale: details.dataset.stale, heading: details.querySelector('h2').textContent, useAllHidden: document.querySelector('[data-testid=contour-use-all]').hidden };
  }, ROW);

/** The run on screen: its volume in full precision and what it left out at the user's request. */
const mesh = () => page.evaluate(() => {
  const r = window.heartmesh.currentResult();
  return {
    volumeMl: r.volumeMl,
    leaveOut: r.leave_out,
    setAside: r.set_aside.map((s) => [s.id, s.reason]),
    asideFigures: r.set_aside.map((s) => ({ mean: s.mean, max: s.max })),
    contours: r.contours.map((c) => c.id),
  };
});

/** The panel's CSV (its button): the file's name, its `#` lines and its rows as objects by column. */
async function contourCsv() {
  const { name, bytes } = await downloadFrom(page, 'contour-csv');
  const lines = bytes.toString('utf8').trimEnd().split('\n');
  const comments = lines.filter((l) => l.startsWith('#'));
  const [columns, ...data] = lines.filter((l) => !l.startsWith('#'));
  // Patient 1's ids hold no comma: no quoted fields to read.
  const rows = data.map((l) => Object.fromEntries(l.split(',').map((v, i) => [columns.split(',')[i], v])));
  return { name, comments, columns, rows };
}

/** The Contours panel's sorted header: its label and aria-sort (null: the file's order). */
const sortedHeader = () => page.evaluate(() => {
  const th = document.querySelector('section.contours th[aria-sort]');
  return th ? [th.querySelector('button').firstChild.textContent, th.getAttribute('aria-sort')] : null;
});

/** The Lab's leave-one-out of the surface on screen, each contour's mean (full precision) and max (its bar's title, 2 decimals), by id. */
async function labLeaveOneOut() {
  await page.click('[data-testid=tab-lab]');
  await page.click('[data-testid=lab-loo-run]');
  await page.waitForSelector('[data-testid=lab-loo-info][data-done="1"]', { timeout: 600000 });
  const bars = await page.locator('[data-testid=loo-bar]').evaluateAll((els) => els.map((e) => [e.querySelector('title').textContent, Number(e.getAttribute('data-mean'))]));
  await page.click('[data-testid=tab-params]');
  return new Map(bars.map(([title, mean]) => {
    const m = /^(\S+) \((?:SAX|LAX)\): mean [\d.]+ mm, max ([\d.]+) mm$/.exec(title);
    assert.ok(m, title);
    return [m[1], { mean, max: Number(m[2]) }];
  }));
}

/** The contour highlighted in the 3D view: the canvas's attribute and the layer's own word. */
const highlighted = () => page.evaluate(() => ({
  attr: document.querySelector('[data-testid=viewport-canvas]').dataset.highlight,
  layer: window.heartmeshViewer.contourHighlight.id,
}));

/** Moves the pointer onto the 3D view at the screen position of `xyz` (mm). */
async function pointAt(xyz) {
  const at = await page.evaluate((p) => window.heartmeshViewer.screenPosition(p[0], p[1], p[2]), xyz);
  const canvas = await page.locator('[data-testid=viewport-canvas]').boundingBox();
  await page.mouse.move(canvas.x + at.x, canvas.y + at.y);
}

describe('the Contours panel', () => {
  it('lists each contour\'s distance to the mesh, highlights it both ways, and leaves one out by hand', async () => {
    await gotoEmpty(page, server.url);
    assert.equal(await page.textContent('[data-testid=contour-note]'), 'no result yet');
    await runAndWait(page, () => page.click('[data-testid=sample-patient1-ED]'), 120000);
    assert.equal(await page.inputValue('[data-testid=surface-picker]'), 'LV_ENDO');

    // Eight rows, 5 SAX and 3 LAX, all used; the largest max is the result panel's max.
    const first = await readTable();
    const result = await readResult(page);
    assert.equal(first.count, '8');
    assert.equal(first.heading.replace(/^\W+/, ''), 'Contours (8)');
    assert.equal(first.rows.length, 8);
    assert.deepEqual(first.rows.map((r) => r.kind).sort(), ['LAX', 'LAX', 'LAX', 'SAX', 'SAX', 'SAX', 'SAX', 'SAX']);
    assert.ok(first.rows.every((r) => r.state === 'used' && r.checked && !r.disabled), JSON.stringify(first.rows));
    const maxOfRows = Math.max(...first.rows.map((r) => r.maxMm));
    assert.ok(Math.abs(maxOfRows - result.maxMm) < 0.001, `rows' max ${maxOfRows} vs result ${result.maxMm}`);
    const points = await page.evaluate(() => window.heartmesh.currentResult().overall.count);
    assert.equal(first.rows.reduce((n, r) => n + r.count, 0), points, 'every contour point is in one row');
    for (const r of first.rows) {
      assert.equal(r.cells[4], r.meanMm.toFixed(2));
      assert.equal(r.cells[5], r.maxMm.toFixed(2));
    }
    const worst = first.rows.find((r) => r.maxMm === maxOfRows);
    console.log(`# contours: ${first.rows.map((r) => `${r.id} ${r.kind} ${r.count} pts mean ${r.meanMm.toFixed(2)} max ${r.maxMm.toFixed(2)}`).join('; ')}; worst ${worst.id}, result max ${result.maxMm.toFixed(3)} mm`);
    const before = await mesh();
    assert.deepEqual(before.leaveOut, []);

    // A row hovered: its contour highlighted in the 3D view; the pointer gone, no highlight.
    const lax = first.rows.filter((r) => r.kind === 'LAX');
    const target = lax[lax.length - 1].id;
    await page.hover(row(target));
    await nextFrames(page);
    assert.deepEqual(await highlighted(), { attr: target, layer: target });
    assert.equal((await readTable()).rows.find((r) => r.id === target).highlighted, true);
    await page.mouse.move(0, 0);
    await nextFrames(page);
    assert.deepEqual(await highlighted(), { attr: '', layer: null });

    // A contour point hovered in the view: the read-out names its contour, whose row lights up.
    const sax = first.rows.find((r) => r.kind === 'SAX' && r.id !== worst.id) ?? first.rows[0];
    const point = await page.evaluate((id) => {
      const r = window.heartmesh.currentResult();
      const c = r.contours.find((k) => k.id === id);
      const i = c.pieces[0].start + Math.floor(c.pieces[0].count / 3);
      return { xyz: [...r.contourPoints.slice(i * 3, i * 3 + 3)], mm: r.pointDistances[i] };
    }, sax.id);
    await pointAt(point.xyz);
    await page.waitForSelector('[data-testid=hover-readout]:not([hidden])', { timeout: 10000 });
    const readout = (await page.textContent('[data-testid=hover-readout]')) ?? '';
    const named = /(\d+\.\d\d) mm to mesh · (\S+?)\(/.exec(readout);
    assert.ok(named, readout);
    assert.ok(first.rows.some((r) => r.id === named[2]), `the read-out names a contour of the table: ${readout}`);
    assert.equal((await readTable()).rows.find((r) => r.id === named[2]).highlighted, true);
    console.log(`# hovered a point of ${sax.id} (${point.mm.toFixed(2)} mm): read-out "${readout.trim()}"`);
    await page.mouse.move(0, 0);

    // Unticked: a new run without it, "left out by you" in the table, the Left out row, the key.
    await runAndWait(page, () => page.uncheck(`${row(target)} [data-testid=contour-use]`), 120000);
    const left = await readTable();
    const without = await mesh();
    assert.deepEqual(without.leaveOut, [target]);
    assert.deepEqual(without.setAside, [[target, 'by_user']]);
    assert.ok(!without.contours.includes(target));
    assert.equal(left.count, '8', 'the contour left out keeps its row');
    const leftRow = left.rows.find((r) => r.id === target);
    assert.deepEqual([leftRow.state, leftRow.kind, leftRow.checked, leftRow.disabled, leftRow.cells[1]], ['by_user', 'LAX', false, false, `${target}left out by you`]);
    // Its row: how far the mesh built without it passes (held out), the core's figures, to two decimals.
    assert.equal(target, 's07_LAX_LV_ENDOCARDIAL');
    assert.deepEqual(without.asideFigures, [{ mean: leftRow.meanMm, max: leftRow.maxMm }]);
    assert.ok(leftRow.meanMm > 1.7 && leftRow.meanMm < 2.0, `held-out mean ${leftRow.meanMm}`);
    assert.ok(leftRow.maxMm > 7.5 && leftRow.maxMm < 7.8, `held-out max ${leftRow.maxMm}`);
    assert.deepEqual(leftRow.cells.slice(4), [leftRow.meanMm.toFixed(2), leftRow.maxMm.toFixed(2)]);
    console.log(`# ${target} held out: mean ${leftRow.meanMm.toFixed(3)} mm, max ${leftRow.maxMm.toFixed(3)} mm`);
    assert.deepEqual(left.rows.map((r) => r.id), first.rows.map((r) => r.id), 'the rows keep their order');
    assert.equal(left.useAllHidden, false);
    assert.equal(await page.textContent('[data-testid=result-set-aside]'), `1 contour (by you) · ${target}`);
    assert.equal(await page.textContent('[data-testid=result-set-aside] >> xpath=preceding-sibling::dt[1]'), 'Left out');
    assert.equal(await page.textContent('[data-testid=set-aside-row]'), `left out by you · ${target}`);
    assert.ok(Math.abs(without.volumeMl - before.volumeMl) > 0.01, `another mesh: ${without.volumeMl} vs ${before.volumeMl} ml`);
    console.log(`# ${target} left out: ${before.volumeMl.toFixed(3)} ml -> ${without.volumeMl.toFixed(3)} ml`);

    // The CSV button: the table as the panel shows it (the file's order here), under the exports' header.
    assert.equal(await page.isEnabled('[data-testid=contour-table] summary [data-testid=contour-csv]'), true);
    const csv = await contourCsv();
    assert.equal(csv.name, 'patient1-ED-LV_ENDO-contours.csv');
    assert.equal(csv.columns, 'contour,kind,state,line,points,mean_mm,median_mm,max_mm,spike_points,far_points,off_plane_points');
    assert.match(csv.comments.join('\n'), new RegExp(`^# lids: auto .* leave_out=${target}$`, 'm'));
    assert.equal(csv.rows.length, 8);
    assert.deepEqual(csv.rows.map((r) => r.contour), left.rows.map((r) => r.id));
    const medians = await page.evaluate(() => {
      const r = window.heartmesh.currentResult();
      return Object.fromEntries([...r.perContour.map((c) => [c.id, c.stats.median]), ...r.set_aside.map((s) => [s.id, s.median])]);
    });
    const near = (csvValue, mm, what) => assert.ok(Math.abs(Number(csvValue) - mm) < 1e-4, `${what}: CSV ${csvValue} vs ${mm}`);
    for (const r of csv.rows) {
      const shown = left.rows.find((x) => x.id === r.contour);
      assert.deepEqual([r.kind, r.state, Number(r.points)], [shown.kind, shown.state, shown.count], r.contour);
      assert.match(r.mean_mm, /^\d+\.\d{4}$/);
      near(r.mean_mm, shown.meanMm, `${r.contour} mean`);
      near(r.max_mm, shown.maxMm, `${r.contour} max`);
      near(r.median_mm, medians[r.contour], `${r.contour} median`);
      assert.ok(Number(r.median_mm) <= Number(r.max_mm), r.contour);
    }
    const heldOut = csv.rows.find((r) => r.contour === target);
    assert.equal(heldOut.state, 'by_user');
    assert.ok(Number(heldOut.line) > 1, `the file line of ${target}: ${heldOut.line}`);
    assert.ok(csv.rows.every((r) => r.contour === target || (r.state === 'used' && r.line === '')), 'used rows have no line');
    assert.ok(csv.rows.every((r) => r.spike_points === '0' && r.far_points === '0' && r.off_plane_points === '0'), 'no damaged values in the sample');
    console.log(`# contours CSV: ${target} line ${heldOut.line}, mean ${heldOut.mean_mm} median ${heldOut.median_mm} max ${heldOut.max_mm} mm`);

    // Hovered in the view, the contour left out says so, with how far the mesh built without it
    // passes that point: one of its points' figures, within its row's max.
    const aside = await page.evaluate(() => {
      const r = window.heartmesh.currentResult();
      return { xyz: [...r.setAsidePoints.slice(0, 3)], mm: [...r.setAsidePointDistances] };
    });
    assert.equal(aside.mm.length, leftRow.count, 'one distance per point of the contour left out');
    await pointAt(aside.xyz);
    await page.waitForFunction(() => /left out by you/.test(document.querySelector('[data-testid=hover-readout]')?.textContent ?? ''), null, { timeout: 10000 });
    const asideReadout = (await page.textContent('[data-testid=hover-readout]')) ?? '';
    const heldOutAt = new RegExp(`^\\s*(\\d+\\.\\d\\d) mm to mesh \\(built without it\\) · left out by you · ${target}\\(`).exec(asideReadout);
    assert.ok(heldOutAt, asideReadout);
    const asideMm = Number(heldOutAt[1]);
    assert.ok(asideMm >= 0 && asideMm <= leftRow.maxMm + 0.01, `${asideMm} mm within 0..${leftRow.maxMm} mm`);
    assert.ok(aside.mm.some((d) => d.toFixed(2) === heldOutAt[1]), `${heldOutAt[1]} mm is one of ${target}'s points' figures`);
    console.log(`# hovered a point of ${target} left out: read-out "${asideReadout.trim()}" (point 0: ${aside.mm[0].toFixed(3)} mm)`);
    await page.screenshot({ path: join(tmpdir(), 'heartmesh-left-out-readout.png') });
    await page.mouse.move(0, 0);
    // In a narrow window the view is narrower than the read-out's one line: it wraps inside the
    // view rather than running off its right edge.
    await page.setViewportSize({ width: 900, height: 700 });
    // The view re-renders at its new size before its points are where `pointAt` projects them.
    await page.waitForFunction(() => document.querySelector('[data-testid=viewport-canvas]').clientWidth < 500, null, { timeout: 10000 });
    await page.evaluate(() => new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(done))));
    // The point of the contour lowest in the view (the apex end): clear of the view's panels.
    const lowest = await page.evaluate((flat) => {
      let best = null;
      for (let i = 0; i < flat.length; i += 3) {
        const at = window.heartmeshViewer.screenPosition(flat[i], flat[i + 1], flat[i + 2]);
        if (!best || at.y > best.y) best = { y: at.y, xyz: [flat[i], flat[i + 1], flat[i + 2]] };
      }
      return best.xyz;
    }, [...(await page.evaluate(() => window.heartmesh.currentResult().setAsidePoints))]);
    await pointAt(lowest);
    await page.waitForSelector('[data-testid=hover-readout]:not([hidden])', { timeout: 10000 });
    assert.match((await page.textContent('[data-testid=hover-readout]')) ?? '', /left out by you/);
    const phoneView = await page.locator('#slot-viewport').boundingBox();
    const phoneReadout = await page.locator('[data-testid=hover-readout]').boundingBox();
    assert.ok(phoneReadout.x >= phoneView.x - 0.5 && phoneReadout.x + phoneReadout.width <= phoneView.x + phoneView.width + 0.5, `read-out ${JSON.stringify(phoneReadout)} inside the view ${JSON.stringify(phoneView)}`);
    await page.screenshot({ path: join(tmpdir(), 'heartmesh-left-out-readout-narrow.png') });
    await page.mouse.move(0, 0);
    await page.setViewportSize({ width: 1280, height: 720 });

    // A click on the max header: the rows by their max, largest first (the one left out among them),
    // again smallest first (rows without a figure last either way), a third time the file's order.
    const ids = (rows) => rows.map((r) => r.id);
    const maxOrder = [...left.rows].sort((a, b) => b.maxMm - a.maxMm).map((r) => r.id);
    const sortMax = () => page.click('section.contours th.c-max button');
    await sortMax();
    assert.deepEqual(ids((await readTable()).rows), maxOrder);
    assert.deepEqual(await sortedHeader(), ['max', 'descending']);
    await sortMax();
    assert.deepEqual(ids((await readTable()).rows), [...maxOrder].reverse());
    assert.deepEqual(await sortedHeader(), ['max', 'ascending']);
    await sortMax();
    assert.deepEqual(ids((await readTable()).rows), first.rows.map((r) => r.id));
    assert.equal(await sortedHeader(), null);
    console.log(`# by max: ${maxOrder.join(', ')}`);
    // Sorted again for the screenshot; the boxes still follow their rows.
    await sortMax();
    const sorted = await readTable();
    assert.deepEqual(sorted.rows.map((r) => [r.id, r.checked]), maxOrder.map((id) => [id, id !== target]));
    // Sorted, the CSV follows the panel's order.
    assert.deepEqual((await contourCsv()).rows.map((r) => r.contour), maxOrder);

    // The table fits its column on a phone, at the narrow window (250 px column: no points column there) and at the usual one.
    for (const [width, height] of [[390, 844], [1024, 700], [1280, 720]]) {
      await page.setViewportSize({ width, height });
      await nextFrames(page);
      const fit = await page.evaluate(() => {
        const side = document.querySelector('#slot-right');
        const panel = document.querySelector('section.contours').getBoundingClientRect();
        const cells = [...document.querySelectorAll('section.contours th, section.contours td')].filter((c) => c.offsetParent !== null).map((c) => c.getBoundingClientRect());
        // The heading's buttons (Use all shows: a contour is left out) on its line, inside the panel.
        const h2 = document.querySelector('section.contours h2').getBoundingClientRect();
        const buttons = [...document.querySelectorAll('section.contours summary button')].map((b) => b.getBoundingClientRect());
        const heading = buttons.length === 2 && buttons.every((b) => b.top < h2.bottom && b.bottom > h2.top && b.left >= h2.right && b.right <= panel.right + 0.5);
        return { sideways: side.scrollWidth > side.clientWidth, inside: cells.every((c) => c.left >= panel.left - 0.5 && c.right <= panel.right + 0.5), heading, pts: getComputedStyle(document.querySelector('th.c-pts')).display };
      });
      assert.deepEqual(fit, { sideways: false, inside: true, heading: true, pts: width < 1100 && width >= 860 ? 'none' : 'table-cell' }, `${width}x${height}`);
      if (width < 860) await page.locator('section.contours').screenshot({ path: join(tmpdir(), 'heartmesh-contour-table-phone.png') });
    }

    // The panel, sorted by max, the contour left out greyed with its figures and a row highlighted (screenshot for the docs).
    await page.hover(row(worst.id));
    await nextFrames(page);
    assert.equal((await highlighted()).attr, worst.id);
    await page.locator('section.contours').screenshot({ path: join(SHOTS, 'contour-table.png') });
    await page.screenshot({ path: join(SHOTS, 'contour-table-view.png') });
    await page.mouse.move(0, 0);

    // The exports and a session record it.
    const json = JSON.parse((await downloadFrom(page, 'export-json')).bytes.toString('utf8'));
    assert.deepEqual(json.leave_out, [target]);
    assert.deepEqual(json.result.set_aside.map((s) => [s.id, s.reason, s.mean, s.max]), [[target, 'by_user', leftRow.meanMm, leftRow.maxMm]]);
    assert.match((await downloadFrom(page, 'export-obj')).bytes.toString('utf8'), new RegExp(`^# lids: auto .* leave_out=${target}$`, 'm'));
    const session = await downloadFrom(page, 'export-session');
    const saved = JSON.parse(session.bytes.toString('utf8'));
    assert.deepEqual(saved.parameters.leave_out, [target]);
    assert.doesNotMatch(page.url(), /leave_out|LAX/);

    // Ticked back: the first mesh again, to the last digit.
    await runAndWait(page, () => page.check(`${row(target)} [data-testid=contour-use]`), 120000);
    const back = await mesh();
    assert.deepEqual(back.leaveOut, []);
    assert.ok(Math.abs(back.volumeMl - before.volumeMl) < 1e-9, `${back.volumeMl} vs ${before.volumeMl} ml`);
    assert.equal((await readTable()).useAllHidden, true);
    assert.equal(await page.isVisible('[data-testid=result-set-aside]'), false);

    // The Lab's leave-one-out of every contour (separate runs of its own worker): the figures of
    // the contour held out there are those its row showed.
    const loo = (await labLeaveOneOut()).get(target);
    console.log(`# Lab leave-one-out ${target}: mean ${loo.mean.toFixed(3)} mm, max ${loo.max.toFixed(2)} mm`);
    assert.ok(Math.abs(loo.mean - leftRow.meanMm) < 0.01, `Lab ${loo.mean} vs row ${leftRow.meanMm}`);
    assert.ok(Math.abs(loo.max - leftRow.maxMm) < 0.01, `Lab ${loo.max} vs row ${leftRow.maxMm}`);

    // The session opened again: the contour is left out again, the same mesh as before.
    await gotoEmpty(page, server.url);
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', { name: session.name, mimeType: 'application/json', buffer: session.bytes }), 120000);
    const reopened = await readTable();
    assert.deepEqual(reopened.rows.filter((r) => !r.checked).map((r) => [r.id, r.state]), [[target, 'by_user']]);
    assert.ok(Math.abs((await mesh()).volumeMl - without.volumeMl) < 1e-9);

    // Use all: every contour again, in one run.
    await runAndWait(page, () => page.click('[data-testid=contour-use-all]'), 120000);
    assert.ok(Math.abs((await mesh()).volumeMl - before.volumeMl) < 1e-9);
    assert.ok((await readTable()).rows.every((r) => r.checked && r.state === 'used'));
    assert.equal(await page.getAttribute('[data-testid=contour-table]', 'open'), '', 'the button in the heading does not fold the panel');
    // The heading folds it.
    await page.click('[data-testid=contour-table] summary h2');
    assert.equal(await page.getAttribute('[data-testid=contour-table]', 'open'), null);
    assert.equal(await page.isVisible(ROW), false);
  });

  it('Measure all phases leaves out of each phase what was left out of its file', async () => {
    const FN = '[data-testid=function]';
    await gotoEmpty(page, server.url);
    await runAndWait(page, () => page.getByRole('button', { name: 'Patient 1 · ED' }).first().click(), 120000);
    const edFile = await page.inputValue('[data-testid=file-picker]');
    await runAndWait(page, () => page.getByRole('button', { name: 'Patient 1 · ES' }).first().click(), 120000);
    await runAndWait(page, () => page.selectOption('[data-testid=file-picker]', edFile), 120000);
    const target = 's07_LAX_LV_ENDOCARDIAL';
    await runAndWait(page, () => page.uncheck(`${row(target)} [data-testid=contour-use]`), 120000);
    const onScreen = (await mesh()).volumeMl;
    assert.match((await page.textContent('[data-testid=function-left-out]')) ?? '', new RegExp(`^Left out, as in the Contours panel: one contour \\(${edFile}: ${target}\\)$`));
    await page.click('[data-testid=function-measure]');
    await page.waitForFunction((sel) => document.querySelector(sel)?.getAttribute('data-state') === 'done', FN, { timeout: 240000, polling: 100 });
    const cells = await page.$$eval('[data-testid=function-table] td', (tds) => tds.map((t) => [t.getAttribute('data-phase'), t.getAttribute('data-surface'), Number(t.getAttribute('data-volume-ml'))]));
    const cell = (phase, surface) => cells.find(([p, s]) => p === phase && s === surface)?.[2];
    const ed = edFile.replace(/\.[^.]+$/, '');
    const es = cells.map(([p]) => p).find((p) => p !== ed);
    console.log(`# ${ed} LV_ENDO ${cell(ed, 'LV_ENDO')} ml (on screen ${onScreen}), ${es} LV_ENDO ${cell(es, 'LV_ENDO')} ml`);
    // ED's LV_ENDO is the run on screen; its other surfaces and ES are the full measurement's
    // (tests/e2e/function.test.mjs: 182.993, 65.86 ml).
    assert.ok(Math.abs(cell(ed, 'LV_ENDO') - onScreen) < 1e-6, `${cell(ed, 'LV_ENDO')} vs ${onScreen}`);
    assert.ok(Math.abs(cell(ed, 'LV_ENDO') - 173.724) > 1, 'not the measurement of every contour');
    assert.ok(Math.abs(cell(ed, 'RV_ENDO') - 182.993) < 0.01);
    assert.ok(Math.abs(cell(es, 'LV_ENDO') - 65.86) < 0.01);
    assert.equal(await page.getAttribute(FN, 'data-stale'), '0');
    // Put back: the table's settings are no longer those on screen.
    await runAndWait(page, () => page.check(`${row(target)} [data-testid=contour-use]`), 120000);
    assert.equal(await page.getAttribute(FN, 'data-stale'), '1');
    assert.equal(await page.isVisible('[data-testid=function-left-out]'), false);
  });

  it('one list per file: an LV_ENDO contour left out is out of the RV_ENDO run and its alignment (the CLI\'s volume)', async () => {
    // `heartmesh reconstruct patient1-ED.csv --surface RV_ENDO --align-slices [--leave-out ID]`
    // (native, checked against the wasm to 1e-9 by tests/node/leaveOutFile.test.ts); without
    // alignment the RV volume is 182.9926737608299 ml with or without the LV contour.
    const CLI_RV_ALIGNED_LV_OUT = 185.2253659818156;
    const CLI_RV_ALIGNED = 189.71522303358213;
    const CLI_RV = 182.9926737608299;
    const target = 's07_LAX_LV_ENDOCARDIAL';
    const SURFACE = '[data-testid=surface-picker]';
    const marked = () => page.getAttribute('[data-testid=other-surfaces-legend]', 'data-other-settings');
    await gotoEmpty(page, server.url);
    await runAndWait(page, () => page.click('[data-testid=sample-patient1-ED]'), 120000);
    await runAndWait(page, () => page.check('[data-testid=param-align-slices]'), 120000);
    await runAndWait(page, () => page.selectOption(SURFACE, 'RV_ENDO'), 120000);
    const every = await mesh();
    assert.deepEqual(every.leaveOut, []);
    assert.ok(Math.abs(every.volumeMl - CLI_RV_ALIGNED) < 1e-6, `RV aligned, every contour: ${every.volumeMl} vs CLI ${CLI_RV_ALIGNED}`);

    // Left out in the LV_ENDO panel: the kept RV run (the Other surfaces key) was run with it in, as with another parameter.
    await runAndWait(page, () => page.selectOption(SURFACE, 'LV_ENDO'), 120000);
    await page.check('[data-testid=view-others]');
    assert.equal(await marked(), '');
    await runAndWait(page, () => page.uncheck(`${row(target)} [data-testid=contour-use]`), 120000);
    assert.deepEqual((await mesh()).leaveOut, [target]);
    assert.equal(await marked(), 'RV_ENDO');

    // RV_ENDO run: its leave_out holds the LV id; nothing of its own is unticked, so no Use all.
    await runAndWait(page, () => page.selectOption(SURFACE, 'RV_ENDO'), 120000);
    const rv = await mesh();
    const table = await readTable();
    console.log(`# RV_ENDO aligned: ${every.volumeMl} ml, ${rv.volumeMl} ml with ${target} left out (CLI ${CLI_RV_ALIGNED_LV_OUT})`);
    assert.deepEqual(rv.leaveOut, [target]);
    assert.deepEqual(rv.setAside.filter(([, reason]) => reason === 'by_user'), []);
    assert.ok(Math.abs(rv.volumeMl - CLI_RV_ALIGNED_LV_OUT) < 1e-6, `${rv.volumeMl} vs CLI ${CLI_RV_ALIGNED_LV_OUT}`);
    assert.ok(Math.abs(rv.volumeMl - every.volumeMl) > 2, 'out of the alignment: another RV mesh');
    assert.equal(table.count, '16');
    assert.ok(table.rows.every((r) => r.checked), 'the RV panel lists its own contours, all used');
    assert.equal(table.useAllHidden, true);
    assert.equal(await marked(), '', 'the LV_ENDO ghost was run with the same list');
    // The exports and a session saved from RV_ENDO record it.
    const json = JSON.parse((await downloadFrom(page, 'export-json')).bytes.toString('utf8'));
    assert.deepEqual([json.surface, json.leave_out], ['RV_ENDO', [target]]);
    assert.match((await downloadFrom(page, 'export-obj')).bytes.toString('utf8'), new RegExp(`^# lids: auto .* leave_out=${target}$`, 'm'));
    const saved = JSON.parse((await downloadFrom(page, 'export-session')).bytes.toString('utf8'));
    assert.deepEqual(saved.parameters.leave_out, [target]);

    // Without alignment the LV contour changes nothing of the RV: the mesh of every contour.
    await runAndWait(page, () => page.uncheck('[data-testid=param-align-slices]'), 120000);
    const plain = await mesh();
    assert.deepEqual(plain.leaveOut, [target]);
    assert.ok(Math.abs(plain.volumeMl - CLI_RV) < 1e-6, `${plain.volumeMl} vs CLI ${CLI_RV}`);
    console.log(`# RV_ENDO unaligned with ${target} left out: ${plain.volumeMl} ml (CLI, every contour: ${CLI_RV})`);
    await page.uncheck('[data-testid=view-others]');
  });
});
