// Browser end-to-end test (dist/, Debian's chromium) of the biventricular wall export (the command
// line's `heartmesh myocardium --biventricular` in the app): greyed, saying what is missing, until
// the Patient 1 · ED example's LV_ENDO, RV_ENDO and BIV_EPI (the core's join of its LV_EPI and
// RV_EPI curves) have all run with the settings in the panel: BIV_EPI from the Surface menu, then
// All (which runs BIV_EPI only while it is the current surface). Then the OBJ has the four region
// groups and the command line's header comment, is closed (every edge in exactly two faces) and
// encloses the volume shown, which is the CLI's (133.6 ml, 140.3 g, LV cavity 135.0 ml, RV cavity
// 127.1 ml); the VTK holds one region per triangle in 1..4. A wall the core cannot build is shown
// on the figures line and the banner; the worker goes on and the next export (PLY) works. Patient
// 2 · ED has no RV_EPI: the row says BIV_EPI needs LV_EPI and RV_EPI curves. Screenshot:
// biventricular-wall-export.png in SHOTS.
import { describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { download, gotoEmpty, runAndWait, waitForDone, SHOTS } from './lib.mjs';
import { appForFile } from './perFile.mjs';
import { openEdges, parseObj, volumeMl, vtkBlock } from './meshFiles.mjs';

let app;
let page;
const pageErrors = [];
appForFile({ onPageError: (m) => pageErrors.push(m) }, (a) => ({ page } = app = a));

/**
 * `heartmesh myocardium public/samples/patient1-ED.csv --biventricular -o biv.obj --report biv.json`
 * (wall_volume_ml, myocardial_mass_g, cavities[].volume_ml, vertices, triangles, regions).
 */
const CLI = {
  wallMl: 133.5789290808014,
  massG: 140.25787553484147,
  lvCavityMl: 135.00492042807693,
  rvCavityMl: 127.09252539737463,
  vertices: 2167,
  triangles: 4330,
  regions: [1280, 1495, 1317, 238],
};
const GROUPS = ['epicardium', 'lv_endocardium', 'rv_endocardium', 'base'];
const FORMATS = ['stl', 'obj', 'ply', 'vtk'];

const bivButton = (fmt) => `[data-testid=export-biv-wall-${fmt}]`;
const figures = '[data-testid=biv-wall-figures]';
const WHAT = 'The biventricular wall: the BIV_EPI mesh less the LV_ENDO and RV_ENDO cavities, cut at the base into one closed solid';





const close = (got, want, rel, what) => assert.ok(Math.abs(got - want) <= rel * Math.abs(want), `${what}: ${got} vs ${want}`);

describe('the biventricular wall export', () => {
  it('greyed until LV_ENDO, RV_ENDO and BIV_EPI ran with these settings; OBJ and VTK of the solid; its figures are the CLI\'s; a failure survived', async () => {
    await page.setViewportSize({ width: 1280, height: 900 });
    await gotoEmpty(page, app.server.url);
    assert.equal(await page.isDisabled(bivButton('obj')), true, 'no file');
    assert.equal(await page.getAttribute(bivButton('obj'), 'title'), `${WHAT}: open a file with LV_ENDO, RV_ENDO, LV_EPI and RV_EPI contours`);
    await runAndWait(page, () => page.getByRole('button', { name: 'Patient 1 · ED' }).first().click());
    // BIV_EPI is offered (joined from LV_EPI and RV_EPI); LV_ENDO alone has run.
    assert.ok((await page.$$eval('[data-testid=surface-picker] option', (o) => o.map((x) => x.value))).includes('BIV_EPI'));
    for (const fmt of FORMATS) assert.equal(await page.isDisabled(bivButton(fmt)), true, fmt);
    assert.equal(
      await page.getAttribute(bivButton('obj'), 'title'),
      `${WHAT}: run RV_ENDO and BIV_EPI too (pick BiV epicardium in the Surface menu, then All: All leaves it out unless it is the current surface)`,
    );
    assert.equal(await page.isVisible(figures), false);

    // BIV_EPI from the Surface menu: RV_ENDO still missing.
    await runAndWait(page, () => page.selectOption('[data-testid=surface-picker]', 'BIV_EPI'), 120000);
    assert.equal(await page.isDisabled(bivButton('obj')), true);
    assert.equal(await page.getAttribute(bivButton('obj'), 'title'), `${WHAT}: run RV_ENDO too (Surface menu, or All)`);

    // All with BIV_EPI current: every surface in turn, back on BIV_EPI.
    await page.click('[data-testid=run-all-surfaces]');
    await page.waitForFunction(() => document.querySelector('[data-testid=view-others-count]')?.textContent === ' (4)', null, { timeout: 180000 });
    await waitForDone(page, 180000);
    assert.equal(await page.inputValue('[data-testid=surface-picker]'), 'BIV_EPI');
    for (const fmt of FORMATS) assert.equal(await page.isDisabled(bivButton(fmt)), false, fmt);
    assert.equal(await page.isDisabled('[data-testid=export-wall-obj]'), false, 'the LV wall too');
    assert.match(await page.getAttribute(bivButton('vtk'), 'title'), /cell data region \(1 epicardium, 2 lv_endocardium, 3 rv_endocardium, 4 base\)/);

    // OBJ: the four regions as groups, the command line's comment, closed, the CLI's size.
    const obj = await download(page, 'export-biv-wall-obj');
    assert.equal(obj.name, 'patient1-ED-BiV_wall.obj');
    const text = obj.bytes.toString('utf8');
    const head = text.split('\n').slice(0, 6);
    assert.match(head[0], /^# heartmesh \S+$/);
    assert.equal(head[1], "# biventricular myocardium of patient1-ED.csv (LV_ENDO + BIV_EPI + RV_ENDO); units mm, the contour file's coordinates; region 1 epicardium, 2 lv_endocardium, 3 rv_endocardium, 4 base");
    assert.match(head[2], /^# heartmesh \S+ \(core \S+\), units: mm$/);
    assert.equal(head[3], '# input: patient1-ED.csv surface: LV_ENDO + BIV_EPI + RV_ENDO');
    assert.match(text, /\n# min_thickness=1 mm \(endocardial vertices closer to the epicardium or to the other cavity moved away from it\)\n/);
    const { v, faces, groups } = parseObj(text);
    assert.deepEqual(groups, GROUPS);
    assert.equal(v.length, CLI.vertices);
    assert.equal(faces.length, CLI.triangles);
    const { open, edges } = openEdges(faces);
    assert.equal(open, 0, `${open} of ${edges} edges not in exactly two faces`);
    assert.deepEqual(GROUPS.map((g) => faces.filter((f) => f.group === g).length), CLI.regions);

    // The figures shown: the file's volume, and the CLI's to 1e-6 (the app builds the wall of the
    // worker's full-precision meshes, as the CLI of its own).
    await page.waitForSelector(`${figures}[data-state=done]`);
    const shown = await page.$eval(figures, (el) => ({
      text: el.textContent,
      title: el.title,
      ml: Number(el.dataset.wallMl),
      mass: Number(el.dataset.massG),
      lv: Number(el.dataset.lvCavityMl),
      rv: Number(el.dataset.rvCavityMl),
      crossings: Number(el.dataset.crossings),
      triangles: Number(el.dataset.triangles),
      warn: el.classList.contains('warn'),
    }));
    const fileMl = volumeMl(v, faces);
    close(shown.ml, fileMl, 1e-9, "shown wall vs the file's volume");
    close(fileMl, CLI.wallMl, 1e-6, "the file's volume vs the CLI's");
    close(shown.mass, CLI.massG, 1e-6, 'mass');
    close(shown.lv, CLI.lvCavityMl, 1e-6, 'LV cavity');
    close(shown.rv, CLI.rvCavityMl, 1e-6, 'RV cavity');
    assert.equal(shown.triangles, faces.length);
    assert.equal(shown.crossings, 0);
    assert.equal(shown.warn, false);
    assert.equal(
      shown.text,
      'Wall 133.6 ml · mass 140.3 g · LV cavity 135.0 ml · RV cavity 127.1 ml · thickness 5.3 mm mean. Volumes below the base. ' +
        '23 vertices of the endocardia moved up to 3.09 mm under the epicardium and apart from the other cavity, ' +
        '3 vertices of the epicardium up to 0.14 mm out over the endocardia, to keep the wall at least 1 mm thick',
    );
    assert.match(shown.title, /^LV_ENDO \+ BIV_EPI \+ RV_ENDO: 2167 vertices, 4330 triangles, closed\nregions \(triangles\): 1 epicardium 1280, 2 lv_endocardium 1495, 3 rv_endocardium 1317, 4 base 238\n/);

    // VTK: one region per triangle in 1..4, as many of each as the OBJ's groups; a thickness per vertex.
    const vtk = await download(page, 'export-biv-wall-vtk');
    assert.equal(vtk.name, 'patient1-ED-BiV_wall.vtk');
    const lines = vtk.bytes.toString('utf8').split('\n');
    assert.ok(lines.includes(`CELL_DATA ${CLI.triangles}`));
    const regions = vtkBlock(lines, 'SCALARS region int 1', CLI.triangles);
    assert.equal(regions.length, CLI.triangles);
    assert.ok(regions.every((r) => Number.isInteger(r) && r >= 1 && r <= 4), 'regions in 1..4');
    assert.deepEqual([1, 2, 3, 4].map((k) => regions.filter((r) => r === k).length), CLI.regions);
    assert.ok(lines.includes(`POINT_DATA ${CLI.vertices}`));
    const thickness = vtkBlock(lines, 'SCALARS thickness', CLI.vertices);
    assert.equal(thickness.length, CLI.vertices);
    const mean = thickness.reduce((a, b) => a + b, 0) / thickness.length;
    assert.ok(Math.abs(mean - 5.311) < 0.01 && Math.min(...thickness) > 0.99, `thickness mean ${mean}, min ${Math.min(...thickness)}`);
    await page.locator('[data-testid=biv-wall-export]').scrollIntoViewIfNeeded();
    await page.screenshot({ path: join(SHOTS, 'biventricular-wall-export.png') });

    // A wall the core cannot build (the biventricular epicardium lifted 300 mm off the base
    // plane): the real worker's error on the figures line and in the banner; the worker goes on.
    await page.evaluate(() => {
      const app = window.heartmesh;
      const real = app.bivWallFile.bind(app);
      app.bivWallFile = (format) => {
        const w = app.bivWallReadiness();
        const m = (k) => ({ surface: k.surface, positions: k.positions64 ?? Float64Array.from(k.positions), indices: k.indices });
        const lifted = m(w.bivEpi);
        lifted.positions = Float64Array.from(lifted.positions, (x, i) => (i % 3 === 2 ? x + 300 : x));
        app.bivWallFile = real;
        return app.coreClient.bivWallFile(app.runSettings(), { lvEndo: m(w.lvEndo), rvEndo: m(w.rvEndo), bivEpi: lifted, minThicknessMm: 1, format, header: [] });
      };
    });
    await page.click(bivButton('stl'));
    await page.waitForSelector(`${figures}[data-state=error]`);
    assert.match(await page.textContent(figures), /^⚠ The biventricular wall could not be built: degenerate input: the base plane does not cut the epicardium/);
    assert.match(await page.textContent('[data-testid=error-text]'), /the biventricular wall: degenerate input: the base plane does not cut the epicardium/);
    assert.equal(await page.isDisabled(bivButton('ply')), false);
    const ply = await download(page, 'export-biv-wall-ply');
    assert.equal(ply.name, 'patient1-ED-BiV_wall.ply');
    const header = ply.bytes.subarray(0, ply.bytes.indexOf('end_header')).toString('latin1');
    for (const line of ['format binary_little_endian 1.0', `element vertex ${CLI.vertices}`, `element face ${CLI.triangles}`, 'comment region 2 lv_endocardium', 'comment region 4 base', 'property float thickness', 'property int region']) {
      assert.ok(header.includes(`${line}\n`), `${line} in ${header}`);
    }
    await page.waitForSelector(`${figures}[data-state=done]`);
    close(Number(await page.getAttribute(figures, 'data-wall-ml')), CLI.wallMl, 1e-6, 'after the failure');
    // A parameter changed: BIV_EPI reruns, LV_ENDO's and RV_ENDO's meshes are of the old settings.
    await runAndWait(page, () => page.uncheck('[data-testid=param-soften-conflicts]'), 120000);
    assert.equal(await page.isDisabled(bivButton('obj')), true);
    assert.equal(await page.getAttribute(bivButton('obj'), 'title'), `${WHAT}: LV_ENDO and RV_ENDO were last run with other parameters; run them again with these (Surface menu, or All)`);
    assert.equal(await page.isVisible(figures), false);
    assert.deepEqual(pageErrors, []);
  });

  it('Patient 2 · ED has no RV_EPI: the row says BIV_EPI needs LV_EPI and RV_EPI curves, and the LV wall still works', async () => {
    await gotoEmpty(page, app.server.url);
    await runAndWait(page, () => page.getByRole('button', { name: 'Patient 2 · ED' }).first().click());
    assert.ok(!(await page.$$eval('[data-testid=surface-picker] option', (o) => o.map((x) => x.value))).includes('BIV_EPI'));
    for (const fmt of FORMATS) assert.equal(await page.isDisabled(bivButton(fmt)), true, fmt);
    assert.equal(await page.getAttribute(bivButton('obj'), 'title'), `${WHAT}: BIV_EPI needs LV_EPI and RV_EPI curves, and this file has no RV_EPI`);
    await runAndWait(page, () => page.selectOption('[data-testid=surface-picker]', 'LV_EPI'));
    assert.equal(await page.isDisabled('[data-testid=export-wall-obj]'), false);
    assert.equal(await page.isDisabled(bivButton('obj')), true);
    assert.deepEqual(pageErrors, []);
  });
});
