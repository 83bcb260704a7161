// Browser end-to-end test (dist/, Debian's chromium) of the walls' View toggle: the myocardium
// solid the Export panel builds, shown in the 3D view in place of the reconstructed surface before
// it is saved. On the Patient 1 · ED example after BiV epicardium then All: View is greyed with the
// export buttons' title until the wall can be built; pressed, the view draws the LV wall, whose
// vertex and triangle counts (the canvas's data attributes) are the OBJ export's, coloured by
// thickness with a scale from 0 to between the wall's 95th percentile and its maximum thickness
// (the figures line's, filled as after an export), or by region in exactly 3 colours (4 for the
// biventricular wall); the hover read-out gives the thickness and the region; the clipping plane
// cuts the wall open and the cut faces show (pixels of the section colour: none unclipped); the
// opacity reaches it. Pressed again, the surface's triangle count is back, framed as before the
// wall widened the view; pressed again, the same
// build is shown without asking the worker. The biventricular wall's View takes over from the
// LV wall's (one at a time); a parameter changed hides it. A wall that cannot be built says why on
// the figures line and in the banner, the surface stays and the next View works. Screenshots
// (clipped part-way): lv-wall-view.png and biventricular-wall-view.png in SHOTS.
import { describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { download, gotoEmpty, nextFrames, readResult, runAndWait, setField, waitForDone, SHOTS } from './lib.mjs';
import { appForFile } from './perFile.mjs';
import { parseObj } from './meshFiles.mjs';

let app;
let page;
const pageErrors = [];
appForFile({ onPageError: (m) => pageErrors.push(m) }, (a) => ({ page } = app = a));

const canvas = '[data-testid=viewport-canvas]';
const lvFigures = '[data-testid=wall-figures]';
const bivFigures = '[data-testid=biv-wall-figures]';

/** What the view drew last: `data-shown` (surface or wall), the row id of the wall, counts and colours. */
async function drawn() {
  await nextFrames(page);
  return page.$eval(canvas, (c) => ({
    shown: c.dataset.shown,
    wall: c.dataset.wall ?? '',
    vertices: Number(c.dataset.vertices),
    triangles: Number(c.dataset.triangles),
    colouring: c.dataset.wallColouring,
    colours: Number(c.dataset.wallColours),
  }));
}

/** Waits until the view draws `shown` ('wall' or 'surface'). */
async function waitShown(shown, timeout = 60000) {
  await page.waitForFunction((s) => document.querySelector('[data-testid=viewport-canvas]')?.dataset.shown === s, shown, { timeout });
  return drawn();
}

/**
 * Pixels of the view in the cut faces' flat colour (the key's swatch for them, within 3 per
 * channel), read from the viewer's own PNG (it renders and captures in one task).
 */
async function sectionPixels() {
  return page.evaluate(async () => {
    const swatch = document.querySelector('.wall-legend:not([hidden]) .wall-section-row .swatch');
    const rgb = getComputedStyle(swatch).backgroundColor.match(/\d+/g).map(Number);
    const blob = await window.heartmeshViewer.screenshot();
    const bitmap = await createImageBitmap(blob);
    const c = new OffscreenCanvas(bitmap.width, bitmap.height);
    const g = c.getContext('2d');
    g.drawImage(bitmap, 0, 0);
    const { data } = g.getImageData(0, 0, bitmap.width, bitmap.height);
    let n = 0;
    for (let i = 0; i < data.length; i += 4) if ([0, 1, 2].every((k) => Math.abs(data[i + k] - rgb[k]) <= 3)) n++;
    return n;
  });
}

/** Counts the app's wall builds (the Export panel's requests to the worker) from now on. */
async function countBuilds() {
  await page.evaluate(() => {
    const app = window.heartmesh;
    window.wallBuilds = [];
    for (const name of ['wallFile', 'bivWallFile']) {
      const real = app[name].bind(app);
      app[name] = (format) => {
        window.wallBuilds.push(`${name}:${format}`);
        return real(format);
      };
    }
  });
}

const builds = () => page.evaluate(() => window.wallBuilds);
const pressed = (id) => page.getAttribute(`[data-testid=view-${id}]`, 'aria-pressed');

describe('viewing the myocardium wall', () => {
  it('the LV wall in place of the surface: the OBJ\'s counts, thickness and region colours, hover, clip and opacity, off again', async () => {
    await page.setViewportSize({ width: 1280, height: 900 });
    await gotoEmpty(page, app.server.url);
    assert.equal(await page.isDisabled('[data-testid=view-wall]'), true, 'no file');
    await runAndWait(page, () => page.getByRole('button', { name: 'Patient 1 · ED' }).first().click());
    // LV_ENDO alone: View greyed like the export buttons, with their title.
    assert.equal(await page.isDisabled('[data-testid=view-wall]'), true);
    assert.equal(await page.getAttribute('[data-testid=view-wall]', 'title'), await page.getAttribute('[data-testid=export-wall-obj]', 'title'));
    assert.match(await page.getAttribute('[data-testid=view-wall]', 'title'), /run LV_EPI too/);

    // BiV epicardium, then All: both walls can be built.
    await runAndWait(page, () => page.selectOption('[data-testid=surface-picker]', 'BIV_EPI'), 120000);
    await page.click('[data-testid=run-all-surfaces]');
    await page.waitForFunction(() => document.querySelector('[data-testid=view-others-count]')?.textContent === ' (4)', null, { timeout: 180000 });
    await waitForDone(page, 180000);
    for (const id of ['wall', 'biv-wall']) {
      assert.equal(await page.isDisabled(`[data-testid=view-${id}]`), false, id);
      assert.equal(await page.isDisabled(`[data-testid=export-${id}-obj]`), false, id);
      assert.equal(await pressed(id), 'false');
    }
    const surface = await drawn();
    const result = await readResult(page);
    assert.equal(surface.shown, 'surface');
    assert.equal(surface.triangles, result.triangles, 'the surface drawn is the run\'s');
    assert.equal(await page.isVisible('[data-testid=wall-colour]'), false, 'no wall: no wall colour menu');
    // Where the camera stands and looks, to see the surface framed again as it was once the wall goes.
    const camera = () => page.evaluate(() => [...window.heartmeshViewer.camera.position.toArray(), ...window.heartmeshViewer.controls.target.toArray()]);
    const cameraBefore = await camera();

    // View: the LV wall in place of the surface, coloured by thickness; the figures as after an export.
    await countBuilds();
    await page.click('[data-testid=view-wall]');
    const wall = await waitShown('wall');
    assert.equal(await pressed('wall'), 'true');
    assert.equal(wall.wall, 'wall');
    assert.deepEqual(await builds(), ['wallFile:ply']);
    await page.waitForSelector(`${lvFigures}[data-state=done]`);
    const figures = await page.$eval(lvFigures, (el) => ({
      text: el.textContent, triangles: Number(el.dataset.triangles), mean: Number(el.dataset.thicknessMm),
      p95: Number(el.dataset.thicknessP95Mm), max: Number(el.dataset.thicknessMaxMm),
    }));
    assert.equal(figures.text, 'Wall 99.5 ml · mass 104.5 g · cavity 135.0 ml (both below the base) · thickness 7.1 mm mean');
    assert.equal(wall.triangles, figures.triangles);
    assert.equal(wall.colouring, 'thickness');
    assert.ok(wall.colours > 50, `${wall.colours} thickness colours`);
    assert.equal(await page.isVisible('[data-testid=legend-wall-thickness]'), true);
    assert.equal(await page.isVisible('[data-testid=legend-mesh]'), false, 'the surface\'s scale goes with it');
    assert.equal(await page.isVisible('[data-testid=legend-wall-regions]'), false);
    const legendMax = Number(await page.getAttribute('[data-testid=legend-wall-thickness]', 'data-max-mm'));
    console.log(`# LV wall: ${wall.vertices} vertices, ${wall.triangles} triangles; thickness scale 0-${legendMax} mm (mean ${figures.mean.toFixed(2)}, p95 ${figures.p95.toFixed(2)}, max ${figures.max.toFixed(2)})`);
    assert.ok(legendMax >= figures.p95 && legendMax <= Math.ceil(figures.max), `scale top ${legendMax} mm, p95 ${figures.p95}, max ${figures.max}`);
    assert.ok(Math.abs(legendMax - figures.max) <= 5, `scale top ${legendMax} mm within 5 mm of the thickest ${figures.max}`);

    // The OBJ the export writes is the solid on screen.
    const obj = parseObj((await download(page, 'export-wall-obj')).bytes.toString('utf8'));
    assert.equal(wall.triangles, obj.faces.length);
    assert.equal(wall.vertices, obj.v.length);
    assert.equal((await drawn()).shown, 'wall', 'an export leaves the view as it is');

    // The hover read-out at the middle of the view: the epicardium's thickness there.
    const box = await page.locator(canvas).boundingBox();
    await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
    await page.waitForSelector('[data-testid=hover-readout]:not([hidden])');
    const hover = await page.textContent('[data-testid=hover-readout]');
    const m = /(\d+\.\d) mm wall thickness · (\w+)/.exec(hover);
    assert.ok(m, hover);
    assert.ok(Number(m[1]) > 0 && Number(m[1]) <= figures.max + 0.05, hover);
    assert.equal(m[2], 'epicardium', hover);
    await page.mouse.move(box.x + 5, box.y + box.height - 5);

    // Region colouring: exactly the three regions' colours, the key naming each.
    await page.selectOption('[data-testid=wall-colour]', 'region');
    const regions = await drawn();
    assert.equal(regions.colouring, 'region');
    assert.equal(regions.colours, 3);
    assert.equal(await page.getAttribute('[data-testid=legend-wall-regions]', 'data-regions'), 'epicardium,endocardium,base');
    assert.equal(await page.isVisible('[data-testid=legend-wall-thickness]'), false);
    // The link carries the colouring (and drops it again at the default).
    assert.equal(await page.evaluate(() => new URLSearchParams(location.search).get('wall_colour')), 'region');

    // Clip and opacity reach the wall: unclipped, the closed solid shows no cut face (but for a
    // stray pixel on its outline, where a face turning away can cover a pixel's centre first);
    // clipped, the section shows.
    await page.selectOption('[data-testid=wall-colour]', 'thickness');
    assert.equal(await page.evaluate(() => new URLSearchParams(location.search).get('wall_colour')), null);
    const uncut = await sectionPixels();
    assert.ok(uncut <= 10, `${uncut} pixels of cut faces on the uncut solid`);
    await setField(page, 'view-clip', 55);
    const cut = await sectionPixels();
    console.log(`# cut-face pixels: ${uncut} uncut, ${cut} clipped at 55 %`);
    assert.ok(cut > 2000, `${cut} pixels of cut faces`);
    await setField(page, 'view-opacity', 60);
    assert.equal(await page.evaluate(() => window.heartmeshViewer.wallLayer.materials[0].opacity), 0.6);
    await setField(page, 'view-opacity', 100);
    // Cut open, across the middle of the view: the first point on a surface of the wall (not a cut face) reads its thickness.
    let inside = null;
    for (let f = 0.3; f < 0.7 && !inside; f += 0.01) {
      await page.mouse.move(box.x + box.width * f, box.y + box.height / 2);
      await nextFrames(page, 1);
      inside = /(\d+\.\d) mm wall thickness · (\w+)/.exec(await page.evaluate(() => document.querySelector('[data-testid=hover-readout]:not([hidden])')?.textContent ?? ''));
    }
    assert.ok(inside && ['epicardium', 'endocardium', 'base'].includes(inside[2]), `read out inside the cut wall: ${inside?.[0]}`);
    await page.locator('[data-testid=wall-export]').scrollIntoViewIfNeeded();
    await nextFrames(page);
    await page.screenshot({ path: join(SHOTS, 'lv-wall-view.png') });
    await page.mouse.move(box.x + 5, box.y + box.height - 5);

    // Pressed again: the surface is back, with its own triangles; again: the same build, no new request.
    await page.click('[data-testid=view-wall]');
    const back = await waitShown('surface');
    assert.equal(back.triangles, surface.triangles);
    const cameraBack = await camera();
    assert.ok(cameraBack.every((v, i) => Math.abs(v - cameraBefore[i]) < 1e-6), `framed as before the wall: ${cameraBack} vs ${cameraBefore}`);
    assert.equal(await pressed('wall'), 'false');
    assert.equal(await page.isVisible('[data-testid=wall-colour]'), false);
    assert.equal(await page.isVisible('[data-testid=legend-mesh]'), true);
    await page.click('[data-testid=view-wall]');
    assert.equal((await waitShown('wall')).triangles, obj.faces.length);
    assert.deepEqual(await builds(), ['wallFile:ply', 'wallFile:obj'], 'the View build was shown again');
    assert.deepEqual(pageErrors, []);
  });

  it('the biventricular wall takes over, in four region colours; a parameter change hides it; a wall that cannot be built leaves the surface', async () => {
    // The biventricular wall's View: the LV wall's is released, one wall at a time.
    await page.click('[data-testid=view-biv-wall]');
    await page.waitForFunction(() => document.querySelector('[data-testid=viewport-canvas]')?.dataset.wall === 'biv-wall', null, { timeout: 60000 });
    assert.equal(await pressed('biv-wall'), 'true');
    assert.equal(await pressed('wall'), 'false');
    const biv = await drawn();
    assert.equal(biv.shown, 'wall');
    const obj = parseObj((await download(page, 'export-biv-wall-obj')).bytes.toString('utf8'));
    assert.equal(biv.triangles, obj.faces.length);
    assert.equal(biv.vertices, obj.v.length);
    await page.waitForSelector(`${bivFigures}[data-state=done]`);
    const fig = await page.$eval(bivFigures, (el) => ({ p95: Number(el.dataset.thicknessP95Mm), max: Number(el.dataset.thicknessMaxMm), triangles: Number(el.dataset.triangles) }));
    assert.equal(biv.triangles, fig.triangles);
    const legendMax = Number(await page.getAttribute('[data-testid=legend-wall-thickness]', 'data-max-mm'));
    console.log(`# biventricular wall: ${biv.vertices} vertices, ${biv.triangles} triangles; thickness scale 0-${legendMax} mm (p95 ${fig.p95.toFixed(2)}, max ${fig.max.toFixed(2)})`);
    assert.ok(legendMax >= fig.p95 && legendMax <= Math.ceil(fig.max), `scale top ${legendMax} mm, p95 ${fig.p95}, max ${fig.max}`);

    await page.selectOption('[data-testid=wall-colour]', 'region');
    const regions = await drawn();
    assert.equal(regions.colours, 4);
    assert.equal(await page.getAttribute('[data-testid=legend-wall-regions]', 'data-regions'), 'epicardium,lv_endocardium,rv_endocardium,base');
    assert.ok((await sectionPixels()) > 2000, 'still clipped: the cut faces show');
    await page.locator('[data-testid=biv-wall-export]').scrollIntoViewIfNeeded();
    await page.mouse.move(0, 0);
    await nextFrames(page);
    await page.screenshot({ path: join(SHOTS, 'biventricular-wall-view.png') });

    // A parameter changed: the meshes are stale, the wall leaves the view at once, View is greyed.
    await runAndWait(page, async () => {
      await page.uncheck('[data-testid=param-soften-conflicts]');
      const now = await waitShown('surface', 5000);
      assert.equal(now.wall, '');
      assert.equal(await pressed('biv-wall'), 'false');
      assert.equal(await page.isDisabled('[data-testid=view-biv-wall]'), true);
    }, 120000);
    assert.equal((await drawn()).triangles, (await readResult(page)).triangles, 'the new run\'s surface');
    await runAndWait(page, () => page.check('[data-testid=param-soften-conflicts]'), 120000);
    assert.equal(await page.isDisabled('[data-testid=view-wall]'), false, 'the LV meshes are of these settings again');

    // A wall the core cannot build (the epicardium lifted 300 mm off the base plane): the figures
    // line and the banner say why, the surface stays, the worker goes on and the next View works.
    await page.evaluate(() => {
      const app = window.heartmesh;
      const real = app.wallFile.bind(app);
      app.wallFile = (format) => {
        const w = app.wallReadiness();
        const m = (k) => ({ surface: k.surface, positions: k.positions64 ?? Float64Array.from(k.positions), indices: k.indices });
        const epi = m(w.epi);
        epi.positions = Float64Array.from(epi.positions, (x, i) => (i % 3 === 2 ? x + 300 : x));
        app.wallFile = real;
        return app.coreClient.wallFile(app.runSettings(), { endo: m(w.endo), epi, minThicknessMm: 1, format, header: [] });
      };
    });
    const before = await drawn();
    await page.click('[data-testid=view-wall]');
    await page.waitForSelector(`${lvFigures}[data-state=error]`);
    assert.match(await page.textContent(lvFigures), /^⚠ The LV wall could not be built: degenerate input: the base plane does not cut the epicardium/);
    assert.match(await page.textContent('[data-testid=error-text]'), /the base plane does not cut the epicardium/);
    const after = await drawn();
    assert.equal(after.shown, 'surface');
    assert.equal(after.triangles, before.triangles);
    assert.equal(await pressed('wall'), 'false');
    assert.equal(await page.isDisabled('[data-testid=view-wall]'), false);
    await page.click('[data-testid=view-wall]');
    assert.equal((await waitShown('wall')).wall, 'wall');
    await page.waitForSelector(`${lvFigures}[data-state=done]`);
    assert.deepEqual(pageErrors, []);
  });
});
