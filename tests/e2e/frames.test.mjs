// Browser end-to-end test (dist/, Debian's chromium) of the Frame picker: a GPFile holding biv-me
// patient 1's frames 0 and 9 (built here, twoFrames.mjs) shows the picker beside the Surface picker
// with both frames and frame 0 read, and the warning line points to the picker, not to the command
// line. Frame 9 picked with the keyboard reads the file again and runs: the volume and the vertex
// count change and equal those of GPFile_009.txt dropped on its own, which (one phase) shows no
// picker. The frame goes in the link, the exports and the session. The top bar's pickers clear the
// privacy badge and each other at 1280x720 and 1024x700 (frame-picker.png in the screenshot folder).
// Phases written as text (patient 1's ED and ES CSVs in one file with a `phase` column, built here
// by twoFrames.mjs): both are offered and enabled; ES picked gives patient1-ES.csv's mesh on its
// own (vertices, triangles, mean distance, volume), goes in the link (frame=ES), the exports and a
// session, and the session opened again is that mesh.
import { describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { download, gotoEmpty, readResult, runAndWait, sharedDir, SHOTS } from './lib.mjs';
import { appForFile } from './perFile.mjs';
import { PHASES_NAME, phasesCsv, TWO_FRAMES_NAME, twoFrameGpFile } from './twoFrames.mjs';
import { saxOnlyEllipsoid } from './saxOnly.mjs';

let server;
let page;
const pageErrors = [];
appForFile({ goto: false, onPageError: (m) => pageErrors.push(m) }, (app) => ({ server, page } = app));

const patient1 = (name) => join(sharedDir(), 'data', 'contours', 'bivme-example-patient1', name);
const two = twoFrameGpFile(readFileSync(patient1('GPFile_000.txt'), 'utf8'), readFileSync(patient1('GPFile_009.txt'), 'utf8'));
const phases = phasesCsv(readFileSync(patient1('patient1-ED.csv'), 'utf8'), readFileSync(patient1('patient1-ES.csv'), 'utf8'));
const PICKER = '[data-testid=frame-picker]';
const mesh = () => page.evaluate(() => {
  const r = window.heartmesh.currentResult();
  return { volumeMl: r.volumeMl, vertices: r.positions.length / 3 };
});
const box = (sel) => page.locator(sel).first().boundingBox();
const overlapping = (a, b) => a.x < b.x + b.width - 1 && b.x < a.x + a.width - 1 && a.y < b.y + b.height - 1 && b.y < a.y + a.height - 1;

/** The visible top-bar controls (`controls`) neither overlap nor leave the window. */
async function topBarFits(label, controls = ['[data-testid=file-picker]', '[data-testid=surface-picker]', PICKER, '[data-testid=privacy]']) {
  const width = page.viewportSize()?.width ?? 0;
  const boxes = [];
  for (const sel of controls) {
    const b = await box(sel);
    assert.ok(b, `${label}: ${sel} is not shown`);
    assert.ok(b.x >= 0 && b.x + b.width <= width + 1, `${label}: ${sel} leaves the window (${b.x}..${b.x + b.width} of ${width})`);
    boxes.push([sel, b]);
  }
  for (let i = 0; i < boxes.length; i++) {
    for (let j = i + 1; j < boxes.length; j++) {
      assert.equal(overlapping(boxes[i][1], boxes[j][1]), false, `${label}: ${boxes[i][0]} overlaps ${boxes[j][0]}`);
    }
  }
}

describe('the Frame picker', () => {
  it('a two-frame GPFile: both frames listed; frame 9 picked runs the file\'s ES phase, as GPFile_009.txt alone', async () => {
    await page.setViewportSize({ width: 1280, height: 720 });
    await gotoEmpty(page, server.url);

    // One phase: no picker.
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', patient1('GPFile_009.txt')));
    assert.equal(await page.isVisible(PICKER), false, 'GPFile_009.txt alone holds one phase');
    assert.equal(await page.inputValue('[data-testid=surface-picker]'), 'LV_ENDO');
    const es = await mesh();

    // Two frames: the picker beside the surface picker, frame 0 read.
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', { name: TWO_FRAMES_NAME, mimeType: 'text/plain', buffer: Buffer.from(two) }));
    assert.equal(await page.isVisible(PICKER), true);
    assert.deepEqual(await page.$$eval(`${PICKER} option`, (os) => os.map((o) => [o.value, o.textContent])), [['0', 'frame 0'], ['9', 'frame 9']]);
    assert.equal(await page.inputValue(PICKER), '0');
    assert.equal(await page.getAttribute(PICKER, 'aria-label'), 'Time frame');
    const next = await page.$eval(PICKER, (el) => el.parentElement?.previousElementSibling?.querySelector('select')?.getAttribute('data-testid'));
    assert.equal(next, 'surface-picker', 'beside the surface picker');
    const warning = (await page.textContent('#slot-warnings')) ?? '';
    assert.match(warning, /the file holds 2 time frames \(0, 9\): frame 0 read, 1225 points of other frames left out; choose another with the Frame picker/);
    assert.doesNotMatch(warning, /--frame|command line/);
    const ed = await mesh();
    assert.doesNotMatch(page.url(), /frame=/);

    // The top bar holds all three pickers at the window sizes the app supports.
    await page.mouse.move(0, 0);
    for (const [width, height] of [[1024, 700], [1280, 720]]) {
      await page.setViewportSize({ width, height });
      await topBarFits(`${width}x${height}`);
    }
    await page.screenshot({ path: join(SHOTS, 'frame-picker.png') });

    // Frame 9, with the keyboard: the file is read again and runs.
    await page.focus(PICKER);
    await runAndWait(page, () => page.keyboard.press('ArrowDown'));
    assert.equal(await page.inputValue(PICKER), '9');
    assert.equal(await page.evaluate(() => document.activeElement?.getAttribute('data-testid')), 'frame-picker', 'the focus stays on the picker');
    const nine = await mesh();
    assert.notEqual(nine.volumeMl, ed.volumeMl, 'the volume changes');
    assert.notEqual(nine.vertices, ed.vertices, 'the vertex count changes');
    assert.equal(nine.volumeMl, es.volumeMl, 'frame 9 is GPFile_009.txt');
    assert.equal(nine.vertices, es.vertices);
    assert.equal(await page.isVisible('#slot-warnings'), false, 'a frame chosen leaves nothing to warn of');
    assert.match(page.url(), /[?&]frame=9(&|$)/);
    console.log(`# ${TWO_FRAMES_NAME} LV endo: frame 0 ${ed.volumeMl.toFixed(2)} ml, ${ed.vertices} vertices; frame 9 ${nine.volumeMl.toFixed(2)} ml, ${nine.vertices} vertices (GPFile_009.txt: ${es.volumeMl.toFixed(2)} ml, ${es.vertices})`);

    // The exports and the session name the frame beside the file and surface.
    const json = await download(page, 'export-json');
    assert.match(json.name, /^GPFile_000-009-LV_ENDO-frame9/);
    assert.deepEqual(Object.fromEntries(Object.entries(JSON.parse(json.bytes.toString('utf8'))).filter(([k]) => ['input', 'surface', 'frame'].includes(k))),
      { input: TWO_FRAMES_NAME, surface: 'LV_ENDO', frame: '9' });
    assert.match((await download(page, 'export-obj')).bytes.toString('utf8'), new RegExp(`# input: ${TWO_FRAMES_NAME} surface: LV_ENDO frame: 9\n`));
    const session = await download(page, 'export-session');
    assert.equal(JSON.parse(session.bytes.toString('utf8')).frame, '9');

    // Back to the one-phase file in the File picker: the Frame picker goes; and back again, frame 9.
    await runAndWait(page, () => page.selectOption('[data-testid=file-picker]', 'GPFile_009.txt'));
    assert.equal(await page.isVisible(PICKER), false);
    await runAndWait(page, () => page.selectOption('[data-testid=file-picker]', TWO_FRAMES_NAME));
    assert.equal(await page.inputValue(PICKER), '9');
    assert.equal((await mesh()).volumeMl, es.volumeMl);
    assert.deepEqual(pageErrors, []);
  });

  it('a one-surface CSV with a frame column beside another file: the file and frame pickers fit, and frame 1 runs', async () => {
    // The sax-only ellipsoid as frame 0, and shrunk to 80 % across as frame 1 (a systole of sorts).
    const rows = saxOnlyEllipsoid().csv.trim().split('\n');
    const framed = (frame, scale) => rows.slice(1).map((r) => {
      const [c, x, y, z, surface] = r.split(',');
      return [c, (Number(x) * scale).toFixed(4), (Number(y) * scale).toFixed(4), z, surface, frame].join(',');
    });
    const csv = ['contour,x,y,z,surface,frame', ...framed(0, 1), ...framed(1, 0.8)].join('\n');
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', { name: 'ellipsoid-frames.csv', mimeType: 'text/csv', buffer: Buffer.from(csv) }));
    assert.equal(await page.isVisible('[data-testid=surface-picker]'), false, 'one surface');
    assert.equal(await page.isVisible('[data-testid=file-picker]'), true);
    // The link's frame 9 (from the test before) is not in this file: frame 0 runs, and the warning line says so.
    assert.equal(await page.inputValue(PICKER), '0');
    assert.match((await page.textContent('#slot-warnings')) ?? '', /^⚠ frame 9 is not in ellipsoid-frames\.csv: showing frame 0 · the file holds 2 time frames \(0, 1\)/);
    for (const [width, height] of [[1024, 700], [1280, 720]]) {
      await page.setViewportSize({ width, height });
      await topBarFits(`${width}x${height}, no surface picker`, ['[data-testid=file-picker]', PICKER, '[data-testid=privacy]']);
    }
    const zero = await mesh();
    await runAndWait(page, () => page.selectOption(PICKER, '1'));
    const one = await mesh();
    assert.ok(one.volumeMl < 0.7 * zero.volumeMl, `frame 1 is the smaller cavity (${one.volumeMl.toFixed(1)} vs ${zero.volumeMl.toFixed(1)} ml)`);
    assert.match(page.url(), /[?&]frame=1(&|$)/);
    assert.deepEqual(pageErrors, []);
  });

  it('phases written as text (ED, ES): both can be chosen, and ES is patient1-ES.csv alone, in the link, the exports and a session', async () => {
    await page.setViewportSize({ width: 1280, height: 720 });
    await gotoEmpty(page, server.url);
    // The ES phase on its own: no frame column, no picker.
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', patient1('patient1-ES.csv')));
    assert.equal(await page.isVisible(PICKER), false);
    assert.equal(await page.inputValue('[data-testid=surface-picker]'), 'LV_ENDO');
    const esAlone = { ...(await readResult(page)), ...(await mesh()) };

    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', { name: PHASES_NAME, mimeType: 'text/csv', buffer: Buffer.from(phases) }));
    assert.equal(await page.isVisible(PICKER), true);
    assert.deepEqual(await page.$$eval(`${PICKER} option`, (os) => os.map((o) => [o.value, o.textContent, o.disabled])), [['ED', 'frame ED', false], ['ES', 'frame ES', false]]);
    assert.equal(await page.inputValue(PICKER), 'ED');
    assert.match((await page.textContent('#slot-warnings')) ?? '', /the file holds 2 time frames \(ED, ES\): frame ED read, 1204 points of other frames left out; choose another with the Frame picker/);
    const ed = { ...(await readResult(page)), ...(await mesh()) };

    await runAndWait(page, () => page.selectOption(PICKER, 'ES'));
    assert.equal(await page.inputValue(PICKER), 'ES');
    const es = { ...(await readResult(page)), ...(await mesh()) };
    assert.notEqual(es.vertices, ed.vertices, 'another phase');
    for (const key of ['vertices', 'triangles', 'meanMm', 'volumeMl']) assert.equal(es[key], esAlone[key], `frame ES is patient1-ES.csv: ${key}`);
    assert.equal(await page.isVisible('#slot-warnings'), false, 'a frame chosen leaves nothing to warn of');
    assert.match(page.url(), /[?&]frame=ES(&|$)/);
    console.log(`# ${PHASES_NAME} LV endo: ED ${ed.vertices} vertices, ${ed.triangles} triangles, mean ${ed.meanMm.toFixed(3)} mm, ${ed.volumeMl.toFixed(2)} ml; ES ${es.vertices}, ${es.triangles}, ${es.meanMm.toFixed(3)} mm, ${es.volumeMl.toFixed(2)} ml (patient1-ES.csv: ${esAlone.vertices}, ${esAlone.triangles}, ${esAlone.meanMm.toFixed(3)} mm, ${esAlone.volumeMl.toFixed(2)} ml)`);

    const json = await download(page, 'export-json');
    assert.match(json.name, /^patient1-ED-ES-LV_ENDO-frameES/);
    assert.equal(JSON.parse(json.bytes.toString('utf8')).frame, 'ES');
    assert.match((await download(page, 'export-obj')).bytes.toString('utf8'), new RegExp(`# input: ${PHASES_NAME} surface: LV_ENDO frame: ES\n`));
    const session = await download(page, 'export-session');
    assert.equal(JSON.parse(session.bytes.toString('utf8')).frame, 'ES');

    // The session opened again: one phase (no picker), the ES mesh, named ES in the exports.
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', { name: 'es-session.json', mimeType: 'application/json', buffer: session.bytes }));
    assert.equal(await page.isVisible(PICKER), false);
    const back = { ...(await readResult(page)), ...(await mesh()) };
    for (const key of ['vertices', 'triangles', 'meanMm', 'volumeMl']) assert.equal(back[key], esAlone[key], `the session: ${key}`);
    assert.equal(JSON.parse((await download(page, 'export-json')).bytes.toString('utf8')).frame, 'ES');
    assert.deepEqual(pageErrors, []);
  });
});
