// Browser end-to-end tests of the built site (dist/, served by `vite preview`) in Debian's chromium
// via playwright-core: every bundled sample reaches done with contour-to-mesh mean <= 1 mm, a slider
// restarts the run, the smoothing options reach the core (and a bad combination is a clear error),
// exports parse, errors name file and line, the site works offline after the first
// visit, and no request ever leaves the origin. Screenshots go to a scratch folder (docs/screenshots/ with `npm run screenshots`).
import { after, before, describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { existsSync, mkdirSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import {
  ROOT, download as downloadFrom, gotoEmpty, nextFrames, openApp, readResult, runAndWait, sharedDir, startStatic, statusRunId, waitForDone, waitForNewRun,
  watchRequests, SHOTS,
} from './lib.mjs';

const SAMPLES = ['patient1-ED', 'patient1-ES', 'patient2-ED'];

let app;
let server;
let browser;
let requests;
let page;

before(async () => {
  app = await openApp({ watch: true });
  ({ server, browser, requests, page } = app);
});

after(async () => {
  await app?.close();
});

function parseBinaryStl(buf) {
  const dv = new DataView(buf.buffer, buf.byteOffset, buf.byteLength);
  const n = dv.getUint32(80, true);
  assert.equal(buf.byteLength, 84 + 50 * n, 'STL size matches its triangle count');
  let volume = 0;
  for (let t = 0; t < n; t++) {
    const o = 84 + t * 50 + 12;
    const p = [];
    for (let k = 0; k < 9; k++) p.push(dv.getFloat32(o + k * 4, true));
    volume += (p[0] * (p[4] * p[8] - p[5] * p[7]) - p[1] * (p[3] * p[8] - p[5] * p[6]) + p[2] * (p[3] * p[7] - p[4] * p[6])) / 6;
  }
  return { triangles: n, header: Buffer.from(buf.subarray(0, 80)).toString('latin1'), volumeMm3: volume };
}

const download = (testid) => downloadFrom(page, testid);

const CLI = join(ROOT, 'wasm-core', 'target', 'release', 'heartmesh');

/**
 * The app's mesh files of the last sample against the command line's of the same file and surface
 * at the defaults: the same vertices and faces spelled the same (OBJ, VTK) and the same STL and PLY
 * bodies (normals, float32 corners and distances), byte for byte. Only the headers' comments and titles
 * differ (the app says more).
 */
function sameAsCli(surface, app) {
  assert.ok(existsSync(CLI), `${CLI} missing: cd wasm-core && cargo build --release -p heartmesh-cli`);
  const dir = mkdtempSync(join(tmpdir(), 'heartmesh-export-'));
  try {
    const cli = {};
    for (const ext of ['obj', 'vtk', 'stl', 'ply']) {
      const out = join(dir, `mesh.${ext}`);
      execFileSync(CLI, ['reconstruct', join(ROOT, 'public', 'samples', `${SAMPLES.at(-1)}.csv`), '--surface', surface, '-o', out, '--quiet']);
      cli[ext] = readFileSync(out);
    }
    const body = (text, keep) => text.split('\n').filter(keep);
    const objLines = (l) => l.startsWith('v ') || l.startsWith('f ');
    const appObj = body(app.obj, objLines);
    assert.ok(appObj.length > 1000, `${appObj.length} OBJ v/f lines`);
    assert.deepEqual(appObj, body(cli.obj.toString('utf8'), objLines), 'OBJ vertices and faces as the CLI writes them');
    // VTK: from POINTS to the end (points, polygons and the distances, doubles named `distance`).
    const points = (text) => text.slice(text.indexOf('\nPOINTS '));
    assert.ok(points(app.vtk).length > 10000);
    assert.match(app.vtk, /\nSCALARS distance double 1\n/);
    assert.equal(points(app.vtk), points(cli.vtk.toString('utf8')), 'VTK points, polygons and distances as the CLI writes them');
    assert.equal(app.stl.length, cli.stl.length);
    assert.ok(app.stl.subarray(80).equals(cli.stl.subarray(80)), 'STL facets byte for byte the CLI\'s');
    // PLY: the vertices (float32 xyz and distance) and faces after the header, byte for byte.
    const plyBody = (b) => b.subarray(b.indexOf('end_header\n') + 'end_header\n'.length);
    assert.ok(plyBody(app.ply).length > 20000);
    assert.ok(plyBody(app.ply).equals(plyBody(cli.ply)), 'PLY vertices, distances and faces byte for byte the CLI\'s');
    // ... under the same elements and properties (the comments aside).
    const plyDeclared = (b) => b.subarray(0, b.indexOf('end_header\n')).toString('latin1').split('\n').filter((l) => /^(element|property) /.test(l));
    assert.deepEqual(plyDeclared(app.ply), plyDeclared(cli.ply));
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
}

describe('heartmesh in the browser', () => {
  for (const id of SAMPLES) {
    it(`sample ${id}: reaches done with contour-to-mesh mean <= 1 mm`, async () => {
      const t0 = Date.now();
      await runAndWait(page, () => page.click(`[data-testid=sample-${id}]`));
      const r = await readResult(page);
      console.log(`# ${id}: ${r.vertices} vertices, ${r.triangles} triangles, mean ${r.meanMm.toFixed(3)} mm, max ${r.maxMm.toFixed(3)} mm, ${Date.now() - t0} ms`);
      assert.ok(r.vertices > 100, `vertices ${r.vertices}`);
      assert.ok(r.triangles > 100, `triangles ${r.triangles}`);
      assert.equal(r.triangles, 2 * r.vertices - 4, 'closed genus-0 surface: T = 2V - 4');
      assert.ok(r.meanMm > 0 && r.meanMm <= 1, `mean ${r.meanMm} mm`);
      assert.ok(Number.isFinite(r.maxMm) && r.maxMm >= r.meanMm, `max ${r.maxMm} mm`);
      assert.match(page.url(), new RegExp(`sample=${id}`));
      await page.mouse.move(0, 0);
      await page.screenshot({ path: join(SHOTS, `sample-${id}.png`) });
    });
  }

  it('exports STL, OBJ, PLY, VTK, CSV and JSON that parse and record parameters and version', async () => {
    const r = await readResult(page);
    const stl = parseBinaryStl((await download('export-stl')).bytes);
    assert.equal(stl.triangles, r.triangles);
    assert.match(stl.header, /^heartmesh \d+\.\d+\.\d+/);
    assert.ok(stl.volumeMm3 > 1000, `outward-oriented closed mesh has positive volume (${stl.volumeMm3} mm^3)`);
    const obj = (await download('export-obj')).bytes.toString('utf8');
    assert.equal(obj.split('\n').filter((l) => l.startsWith('v ')).length, r.vertices);
    assert.equal(obj.split('\n').filter((l) => l.startsWith('f ')).length, r.triangles);
    assert.match(obj, /# lids: auto iterations=250 lambda=100000 beta=0.1 /);
    const ply = (await download('export-ply')).bytes;
    const plyHead = ply.subarray(0, 1024).toString('latin1');
    assert.match(plyHead, new RegExp(`element vertex ${r.vertices}\\n`));
    assert.match(plyHead, new RegExp(`element face ${r.triangles}\\n`));
    const vtk = (await download('export-vtk')).bytes.toString('utf8');
    assert.match(vtk, new RegExp(`POINTS ${r.vertices} double`));
    assert.match(vtk, new RegExp(`POLYGONS ${r.triangles} ${r.triangles * 4}`));
    const csv = (await download('export-csv')).bytes.toString('utf8');
    const rows = csv.split('\n').filter((l) => l && !l.startsWith('#'));
    assert.equal(rows[0], 'contour,x,y,z,surface,kind,distance_mm');
    const d = rows.slice(1).map((l) => Number(l.split(',').at(-1)));
    const mean = d.reduce((a, b) => a + b, 0) / d.length;
    assert.ok(Math.abs(mean - r.meanMm) < 1e-3, `CSV mean ${mean} vs shown ${r.meanMm} mm`);
    const json = JSON.parse((await download('export-json')).bytes.toString('utf8'));
    assert.equal(json.params.lambda, 100000);
    sameAsCli(json.surface, { obj, vtk, stl: (await download('export-stl')).bytes, ply });
    assert.equal(json.result.vertices, r.vertices);
    const png = (await download('export-png')).bytes;
    assert.equal(png.subarray(1, 4).toString('latin1'), 'PNG');
    // A cleared (blank) canvas compresses to a few KB; a rendered heart does not.
    assert.ok(png.length > 20000, `PNG of ${png.length} bytes looks blank`);
    mkdirSync(join(ROOT, 'test-results'), { recursive: true });
    writeFileSync(join(ROOT, 'test-results', 'export.png'), png);
  });

  it('moving a slider restarts the run (debounced) and puts the value in the URL', async () => {
    const before = await statusRunId(page);
    const slider = page.locator('[data-testid=param-lambda]');
    await slider.focus();
    for (let i = 0; i < 20; i++) await page.keyboard.press('ArrowLeft'); // one decade down: 1e4
    await waitForNewRun(page, before, { timeout: 30000 });
    // On a slow machine the debounce can expire between two presses: the run waited for is the
    // one of the last value (waitForDone waits for the result of the settings in the panel).
    await waitForDone(page);
    assert.match(page.url(), /lambda=1e4/);
    const r = await readResult(page);
    assert.ok(r.meanMm <= 1.5, `lambda 1e4 mean ${r.meanMm} mm`);
    await runAndWait(page, async () => {
      await page.click('[data-testid=reset-params]');
      await page.waitForFunction(() => !location.search.includes('lambda='), null, { timeout: 10000 });
    });
  });

  it('smoothing options: soften off changes the result, is exported and reopened; Taubin with factor 0.8 is a clear error', async () => {
    const base = await readResult(page);
    await runAndWait(page, () => page.uncheck('[data-testid=param-soften-conflicts]'));
    assert.match(page.url(), /soften_conflicts=0/);
    const off = await readResult(page);
    console.log(`# ${SAMPLES.at(-1)} soften on: mean ${base.meanMm.toFixed(4)} max ${base.maxMm.toFixed(4)} mm; off: mean ${off.meanMm.toFixed(4)} max ${off.maxMm.toFixed(4)} mm`);
    assert.ok(Math.abs(off.meanMm - base.meanMm) > 1e-4 || Math.abs(off.maxMm - base.maxMm) > 1e-4, 'soften_conflicts=false gives another mesh');
    const json = JSON.parse((await download('export-json')).bytes.toString('utf8'));
    assert.equal(json.soften_conflicts, false);
    assert.equal(json.smoothing_method, 'laplacian-affine');
    const session = await download('export-session');
    const saved = JSON.parse(session.bytes.toString('utf8'));
    assert.equal(saved.heartmesh_session, 1);
    assert.equal(saved.parameters.soften_conflicts, false);
    assert.equal(saved.parameters.smoothing_method, 'laplacian-affine');
    // Taubin is unstable above a factor of 0.6: the core refuses, the banner says why.
    await page.selectOption('[data-testid=param-smoothing-method]', 'taubin');
    await page.$eval('[data-testid=param-smoothing_factor]', (el) => {
      el.value = String(Math.round(0.8 * Number(el.max)));
      el.dispatchEvent(new Event('input'));
    });
    assert.equal(await page.textContent('output[for=param-smoothing_factor]'), '0.8');
    // After the restart's debounce, the core refuses the run in the worker.
    await page.waitForFunction(() => document.querySelector('[data-testid=status]')?.textContent?.startsWith('error'), null, { timeout: 30000 });
    assert.equal(await page.isVisible('[data-testid=error-banner]'), true);
    const text = await page.textContent('[data-testid=error-text]');
    assert.match(text, /smoothing_factor = 0\.8 is out of range \(allowed 0 to 0\.6\)/);
    assert.match(text, /Taubin/);
    assert.match(page.url(), /smoothing_method=taubin/);
    await page.mouse.move(0, 0);
    await page.screenshot({ path: join(SHOTS, 'error-taubin-factor.png') });
    // The user fixes it: back to Laplacian + affine, the run finishes and the banner goes away.
    await page.selectOption('[data-testid=param-smoothing-method]', 'laplacian-affine');
    await page.waitForFunction(() => document.querySelector('[data-testid=status]')?.textContent === 'done', null, { timeout: 90000 });
    assert.equal(await page.isVisible('[data-testid=error-banner]'), false);
    await runAndWait(page, () => page.click('[data-testid=reset-params]'));
    assert.equal(await page.isChecked('[data-testid=param-soften-conflicts]'), true);
    assert.equal(await page.inputValue('[data-testid=param-smoothing-method]'), 'laplacian-affine');
    assert.doesNotMatch(page.url(), /soften_conflicts|smoothing_method|smoothing_factor/);
    const again = await readResult(page);
    assert.equal(again.meanMm, base.meanMm, 'reset gives the default result back');
    // Opening the saved session brings its settings back, and with them the same mesh.
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', { name: session.name, mimeType: 'application/json', buffer: session.bytes }));
    assert.equal(await page.isChecked('[data-testid=param-soften-conflicts]'), false);
    assert.match(page.url(), /soften_conflicts=0/);
    const reopened = await readResult(page);
    assert.ok(Math.abs(reopened.meanMm - off.meanMm) < 1e-9 && reopened.vertices === off.vertices, `session ${reopened.meanMm} vs ${off.meanMm} mm`);
    await runAndWait(page, () => page.click('[data-testid=reset-params]'));
  });

  it('timeline: slow replay, keyboard pause and step, scrub, back to live', async () => {
    await page.selectOption('[data-testid=tl-speed]', '10');
    const before = await statusRunId(page);
    await page.click('[data-testid=sample-patient1-ES]');
    // Until the example is read and its run starts, the label still shows the previous run's last step.
    await waitForNewRun(page, before, { timeout: 60000 });
    await page.waitForFunction(() => /iteration [1-9]/.test(document.querySelector('[data-testid=tl-label]')?.textContent ?? ''), null, { timeout: 30000 });
    await page.waitForTimeout(600);
    await page.mouse.move(0, 0);
    await page.screenshot({ path: join(SHOTS, 'replay-in-progress.png') });
    const iteration = async () => Number(/iteration (\d+)/.exec((await page.textContent('[data-testid=tl-label]')) ?? '')?.[1]);
    await page.evaluate(() => (document.activeElement instanceof HTMLElement ? document.activeElement.blur() : undefined));
    await page.keyboard.press('Space');
    assert.match(await page.textContent('[data-testid=status]'), /^paused|^done/);
    await nextFrames(page); // the label of the step it paused on
    const paused = await iteration();
    await page.waitForTimeout(400);
    assert.equal(await iteration(), paused, 'paused display does not move');
    // The replay may have caught up with the computation, so step back first, then forward.
    // The label follows on the next animation frame.
    const until = async (pred, what) => {
      for (let t = 0; t < 200; t++) {
        const it = await iteration();
        if (pred(it)) return it;
        await page.waitForTimeout(50);
      }
      assert.fail(`${what}; label: ${await page.textContent('[data-testid=tl-label]')}`);
    };
    await page.keyboard.press('ArrowLeft');
    await page.keyboard.press('ArrowLeft');
    await until((it) => it < paused, 'arrow left steps back');
    // Both presses must have landed before `back` is read (each label update waits for a frame).
    await nextFrames(page);
    const back = await iteration();
    await page.keyboard.press('ArrowRight');
    await until((it) => it > back, 'arrow right steps forward');
    const scrub = page.locator('[data-testid=tl-scrubber]');
    await scrub.evaluate((el) => { el.value = '0'; el.dispatchEvent(new Event('input', { bubbles: true })); });
    // The first recorded step (iteration 0, or 1 when the display skipped the very first frame).
    const first = await until((it) => it < back, 'scrubbed to the first recorded step');
    assert.ok(first <= 10, `first recorded iteration ${first}`);
    await page.selectOption('[data-testid=tl-speed]', 'live');
    await page.click('[data-testid=tl-latest]');
    await waitForDone(page);
    await page.waitForFunction(() => {
      // The last step: "iteration 250 / 250", or "converged at iteration 243 (of 250)" when it stopped early.
      const m = /^(converged at )?iteration (\d+) (?:\/ |\(of )(\d+)/.exec(document.querySelector('[data-testid=tl-label]')?.textContent ?? '');
      return m && (m[1] ? Number(m[2]) < Number(m[3]) : m[2] === m[3]);
    }, null, { timeout: 10000 });
  });

  it('a link with parameters reproduces the view', async () => {
    await page.goto(`${server.url}?sample=patient1-ED&surface=LV_EPI&iterations=120&wireframe=1`);
    await waitForDone(page);
    assert.equal(await page.inputValue('[data-testid=surface-picker]'), 'LV_EPI');
    assert.equal(await page.isChecked('[data-testid=view-wireframe]'), true);
    assert.equal(await page.textContent('output[for=param-iterations]'), '120');
    await page.mouse.move(0, 0);
    await page.screenshot({ path: join(SHOTS, 'link-LV_EPI-wireframe.png') });
    await gotoEmpty(page, server.url); // back to the defaults for the tests that follow
  });

  it('opens the canonical CSV through the file input (SurFCo example, not shipped)', async () => {
    const file = join(sharedDir(), 'data', 'contours', 'surfco-example.csv');
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', file));
    const r = await readResult(page);
    console.log(`# surfco-example: ${r.vertices} vertices, mean ${r.meanMm.toFixed(3)} mm, max ${r.maxMm.toFixed(3)} mm`);
    assert.ok(r.meanMm <= 1, `mean ${r.meanMm} mm`);
    assert.doesNotMatch(page.url(), /sample=/);
    await page.screenshot({ path: join(SHOTS, 'surfco-example.png') });
  });

  it("a link's surface applies to a dropped file; a surface the file lacks falls back with a notice", async () => {
    const file = join(sharedDir(), 'data', 'contours', 'bivme-example-patient1', 'patient1-ED.csv');
    await page.goto(`${server.url}?surface=RV_ENDO&iterations=40`);
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', file));
    assert.equal(await page.inputValue('[data-testid=surface-picker]'), 'RV_ENDO');
    // The picker lists LV before RV whatever the file's order (this file has RV first).
    const surfaces = await page.$$eval('[data-testid=surface-picker] option', (os) => os.map((o) => o.value));
    // ... then the biventricular epicardium the core makes of the two epicardia.
    assert.deepEqual(surfaces, ['LV_ENDO', 'LV_EPI', 'RV_ENDO', 'RV_EPI', 'BIV_EPI']);
    assert.equal(await page.isVisible('#slot-warnings'), false);
    assert.match(page.url(), /surface=RV_ENDO/);
    await page.goto(`${server.url}?surface=LA_ENDO&iterations=40`);
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', file));
    assert.equal(await page.inputValue('[data-testid=surface-picker]'), 'LV_ENDO');
    assert.equal(await page.textContent('#slot-warnings'), '⚠ surface LA_ENDO is not in patient1-ED.csv: showing LV_ENDO');
    await gotoEmpty(page, server.url); // back to the defaults for the tests that follow
  });

  it('opens a DICOM RT structure set in the worker and draws its 23 landmarks (biv-me patient 1)', async () => {
    const file = join(ROOT, 'wasm-core', 'crates', 'heartmesh-core', 'tests', 'data', 'patient1-ED-rtstruct.dcm');
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', file));
    const r = await readResult(page);
    console.log(`# patient1-ED-rtstruct.dcm: ${r.vertices} vertices, mean ${r.meanMm.toFixed(3)} mm`);
    assert.ok(r.meanMm > 0 && r.meanMm <= 1, `mean ${r.meanMm} mm`);
    // ROI names are the surfaces; the default pick is LV_ENDO.
    const surfaces = await page.$$eval('[data-testid=surface-picker] option', (os) => os.map((o) => o.value));
    assert.deepEqual([...surfaces].sort(), ['BIV_EPI', 'LV_ENDO', 'LV_EPI', 'RV_ENDO', 'RV_EPI']);
    // POINT ROIs: 23 landmarks drawn (6 mitral, 2 tricuspid, 2 aortic, 2 pulmonary, 1 apex, 10 RV inserts).
    const legend = page.locator('[data-testid=landmark-legend]');
    assert.equal(await legend.getAttribute('data-count'), '23');
    assert.equal(await legend.isVisible(), true);
    assert.match((await legend.textContent()) ?? '', /APEX_POINT/);
    await page.mouse.move(0, 0);
    await page.screenshot({ path: join(SHOTS, 'rtstruct-landmarks.png') });
    // The toggle hides the points and the legend.
    await page.click('[data-testid=view-landmarks]');
    assert.equal(await legend.isVisible(), false);
    await page.click('[data-testid=view-landmarks]');
    assert.equal(await legend.isVisible(), true);
  });

  it('a bad file shows an error naming file and line, and the app stays usable', async () => {
    await page.setInputFiles('[data-testid=file-input]', {
      name: 'broken.csv', mimeType: 'text/csv',
      buffer: Buffer.from('contour,x,y,z\nc1,1,2,3\nc1,1,oops,3\n'),
    });
    await page.waitForFunction(() => document.querySelector('[data-testid=status]')?.textContent?.startsWith('error'), null, { timeout: 30000 });
    const text = await page.textContent('[data-testid=status]');
    assert.match(text, /broken\.csv/);
    assert.match(text, /line 3/);
    assert.equal(await page.isVisible('[data-testid=error-banner]'), true);
    await page.screenshot({ path: join(SHOTS, 'error-bad-file.png') });
    await runAndWait(page, () => page.click('[data-testid=sample-patient1-ED]'));
  });

  it('keeps working offline after the first visit (service worker precache)', async () => {
    await page.goto(server.url);
    await page.evaluate(async () => {
      const reg = await navigator.serviceWorker.ready;
      if (!navigator.serviceWorker.controller) await new Promise((r) => navigator.serviceWorker.addEventListener('controllerchange', r, { once: true }));
      return reg.active?.state;
    });
    await browser.context.setOffline(true);
    try {
      await page.reload();
      await page.waitForFunction(() => document.querySelector('[data-testid=status]')?.textContent === 'no file loaded', null, { timeout: 30000 });
      await runAndWait(page, () => page.click('[data-testid=sample-patient1-ES]'));
      const r = await readResult(page);
      assert.ok(r.meanMm <= 1, `offline mean ${r.meanMm} mm`);
    } finally {
      await browser.context.setOffline(false);
    }
  });

  it('works from a sub-path of another static server (relative paths, service worker scope)', async () => {
    const other = await startStatic('/some/deep/path/heartmesh/');
    const sub = await browser.context.newPage();
    try {
      await sub.goto(`${other.url}?sample=patient1-ES&iterations=100`);
      await waitForDone(sub);
      const r = await readResult(sub);
      assert.ok(r.vertices > 100 && r.meanMm <= 1.5, `sub-path run: ${JSON.stringify(r)}`);
      const scope = await sub.evaluate(async () => (await navigator.serviceWorker.ready).scope);
      assert.equal(scope, other.url);
    } finally {
      await sub.close();
      other.stop();
    }
  });

  it('no request ever left the page origin', () => {
    const all = requests.all();
    assert.ok(all.length > 5, `saw ${all.length} requests`);
    assert.deepEqual(requests.foreign(), []);
  });
});

describe('request watcher (the origin check above can fail)', () => {
  it('flags a request to another origin and accepts same-origin and worker requests', () => {
    const handlers = [];
    const w = watchRequests({ on: (_e, f) => handlers.push(f) });
    const emit = (url, page) => handlers.forEach((f) => f({ url: () => url, frame: () => { if (!page) throw new Error('no frame'); return { page: () => ({ url: () => page }) }; } }));
    emit('http://127.0.0.1:5000/index.html', 'http://127.0.0.1:5000/');
    emit('http://127.0.0.1:5000/assets/x.wasm', null); // worker request
    emit('data:image/png;base64,AAAA', 'http://127.0.0.1:5000/');
    assert.deepEqual(w.foreign(), []);
    emit('https://cdn.example.com/font.woff2', 'http://127.0.0.1:5000/');
    emit('https://tracker.example.com/t', null);
    assert.equal(w.foreign().length, 2);
  });
});
