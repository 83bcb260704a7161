// Browser end-to-end tests (dist/, Debian's chromium) of the other-surfaces view (session 19): a
// biventricular file's surfaces are run one at a time; each finished run is kept, and the view
// toggle "Other surfaces" draws the kept ones faint around the current one, with a key; another
// file forgets them; "All surfaces OBJ" exports them with the current one. Asserted on the toggle,
// the key, the pixels of the 3D view and the exported file's objects.
import { describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { download, gotoEmpty, readResult, runAndWait, waitForDone, SHOTS } from './lib.mjs';
import { appForFile } from './perFile.mjs';

let app;
let page;
appForFile({}, (a) => ({ page } = app = a));

const legend = () => page.getAttribute('[data-testid=other-surfaces-legend]', 'data-surfaces');
const count = () => page.textContent('[data-testid=view-others-count]');

describe('other surfaces of the file', () => {
  it('are kept run by run and drawn faint around the current surface, with their key', async () => {
    await page.setViewportSize({ width: 1280, height: 720 });
    await gotoEmpty(page, app.server.url);
    await runAndWait(page, () => page.getByRole('button', { name: 'Patient 1 · ED' }).first().click());
    assert.equal(await page.isDisabled('[data-testid=view-others]'), true, 'nothing else run yet');
    assert.equal(await page.isDisabled('[data-testid=export-all-obj]'), true);
    await runAndWait(page, () => page.selectOption('[data-testid=surface-picker]', 'RV_ENDO'));
    const rv = await readResult(page);
    assert.ok(rv.vertices > 500 && rv.meanMm < 1, JSON.stringify(rv));
    assert.equal(await page.isDisabled('[data-testid=view-others]'), false);
    assert.equal(await count(), ' (1)');
    assert.equal(await page.isVisible('[data-testid=other-surfaces-legend]'), false, 'off by default');

    const canvas = page.locator('[data-testid=viewport-canvas]');
    const before = await canvas.screenshot();
    await page.check('[data-testid=view-others]');
    assert.equal(await legend(), 'LV_ENDO');
    assert.equal(await page.isVisible('[data-testid=other-surfaces-legend]'), true);
    assert.match(page.url(), /others_shown=1/);
    const after = await canvas.screenshot();
    const changed = await changedPixels(before, after);
    assert.ok(changed > 2000, `the LV drawn beside the RV changed ${changed} pixels`);

    // The hover read-out names the faint surface under the pointer: tried at the LV's vertices
    // farthest from the RV's centre (not behind the RV, whose own read-out comes first).
    const targets = await page.evaluate(() => {
      const lv = window.heartmesh.otherSurfaceMeshes()[0].positions;
      const rv = window.heartmesh.currentResult().positions;
      const c = [0, 1, 2].map((k) => { let t = 0; for (let i = k; i < rv.length; i += 3) t += rv[i]; return t / (rv.length / 3); });
      const order = [];
      for (let i = 0; i < lv.length; i += 3) order.push([Math.hypot(lv[i] - c[0], lv[i + 1] - c[1], lv[i + 2] - c[2]), i]);
      order.sort((a, b) => b[0] - a[0]);
      return order.slice(0, 40).map(([, i]) => window.heartmeshViewer.screenPosition(lv[i], lv[i + 1], lv[i + 2]));
    });
    const box = await canvas.boundingBox();
    let named = null;
    for (const at of targets) {
      if (at.x < 5 || at.y < 5 || at.x > box.width - 5 || at.y > box.height - 5) continue;
      await page.mouse.move(box.x + at.x, box.y + at.y);
      await page.waitForTimeout(30);
      if (await page.isVisible('[data-testid=hover-readout]')) {
        const text = (await page.textContent('[data-testid=hover-readout]')) ?? '';
        if (text.includes('(other surface)')) { named = text; break; }
      }
    }
    assert.match(named ?? 'none of 40 tried', /^\s*LV_ENDO \(other surface\)\(/);
    await page.screenshot({ path: join(SHOTS, 'other-surface-hover.png') });
    await page.mouse.move(0, 0);

    // A third surface: both earlier ones around it; the current one is never its own ghost.
    await runAndWait(page, () => page.selectOption('[data-testid=surface-picker]', 'LV_EPI'));
    assert.equal(await count(), ' (2)');
    assert.equal(await legend(), 'LV_ENDO,RV_ENDO');
    await page.screenshot({ path: join(SHOTS, 'other-surfaces.png') });
    await runAndWait(page, () => page.selectOption('[data-testid=surface-picker]', 'LV_ENDO'));
    assert.equal(await legend(), 'RV_ENDO,LV_EPI');

    // All surfaces in one OBJ: one named object each, each a closed mesh of its own vertices.
    const lv = await readResult(page);
    const { name, bytes } = await download(page, 'export-all-obj');
    assert.equal(name, 'patient1-ED-surfaces.obj');
    const objects = [];
    for (const line of bytes.toString('utf8').split('\n')) {
      const p = line.trim().split(/\s+/);
      if (p[0] === 'o') objects.push({ name: p[1], v: 0, f: [] });
      if (p[0] === 'v') objects.at(-1).v++;
      if (p[0] === 'f') objects.at(-1).f.push(p.slice(1).map(Number));
    }
    assert.deepEqual(objects.map((o) => o.name), ['LV_ENDO', 'RV_ENDO', 'LV_EPI']);
    assert.equal(objects[0].v, lv.vertices);
    assert.equal(objects[0].f.length, lv.triangles);
    let first = 1;
    for (const o of objects) {
      assert.ok(o.v > 500, `${o.name}: ${o.v} vertices`);
      assert.equal(o.f.length, 2 * o.v - 4, `${o.name}: a closed genus-0 mesh has 2V - 4 triangles`);
      for (const t of o.f) assert.ok(t.every((i) => i >= first && i < first + o.v), `${o.name}: face ${t} outside its vertices`);
      first += o.v;
    }

    // The same settings throughout: no ghost marked. Re-run the current surface with other
    // settings: both ghosts are now marked as run with other parameters.
    const marked = () => page.getAttribute('[data-testid=other-surfaces-legend]', 'data-other-settings');
    assert.equal(await marked(), '');
    await runAndWait(page, () => page.uncheck('[data-testid=param-soften-conflicts]'));
    assert.equal(await marked(), 'RV_ENDO,LV_EPI');
    assert.match(await page.textContent('[data-testid=other-surfaces-legend]'), /RV_ENDO· other parameters/);
    await runAndWait(page, () => page.check('[data-testid=param-soften-conflicts]'));
    assert.equal(await marked(), '');

    // Unticked: nothing drawn, the key hidden.
    await page.uncheck('[data-testid=view-others]');
    assert.equal(await page.isVisible('[data-testid=other-surfaces-legend]'), false);
    assert.equal(await legend(), '');

    // Another file: the meshes kept were of patient 1.
    await page.check('[data-testid=view-others]');
    await runAndWait(page, () => page.getByRole('button', { name: 'Patient 2 · ED' }).first().click());
    assert.equal(await page.isDisabled('[data-testid=view-others]'), true);
    assert.equal(await page.isDisabled('[data-testid=export-all-obj]'), true);
    assert.equal(await legend(), '');
  });

  it('"All" runs every surface of the file in turn, ending on the one picked, and shows them together', async () => {
    await gotoEmpty(page, app.server.url);
    await runAndWait(page, () => page.getByRole('button', { name: 'Patient 1 · ES' }).first().click());
    assert.equal(await page.inputValue('[data-testid=surface-picker]'), 'LV_ENDO');
    assert.equal(await page.isChecked('[data-testid=view-others]'), false);
    await page.click('[data-testid=run-all-surfaces]');
    // Three other surfaces, then the LV endocardium again: done when all three are kept.
    await page.waitForFunction(() => document.querySelector('[data-testid=view-others-count]')?.textContent === ' (3)', null, { timeout: 120000 });
    await waitForDone(page, 120000);
    assert.equal(await page.inputValue('[data-testid=surface-picker]'), 'LV_ENDO');
    assert.equal(await page.isChecked('[data-testid=view-others]'), true, 'switched on to show them');
    assert.equal(await legend(), 'LV_EPI,RV_ENDO,RV_EPI');
    const lv = await readResult(page);
    assert.ok(lv.vertices > 500 && lv.meanMm < 1, JSON.stringify(lv));
    await page.screenshot({ path: join(SHOTS, 'all-surfaces.png') });

    // The biventricular epicardium (not part of All): one closed surface around both ventricles,
    // drawn with the LV and RV epicardial curves it is made of, holding more than either.
    const volumes = await page.evaluate(() => Object.fromEntries(window.heartmesh.otherSurfaceMeshes().map((m) => {
      let v = 0;
      const p = m.positions;
      for (let t = 0; t < m.indices.length; t += 3) {
        const [a, b, c] = [m.indices[t] * 3, m.indices[t + 1] * 3, m.indices[t + 2] * 3];
        v += p[a] * (p[b + 1] * p[c + 2] - p[b + 2] * p[c + 1]) - p[a + 1] * (p[b] * p[c + 2] - p[b + 2] * p[c]) + p[a + 2] * (p[b] * p[c + 1] - p[b + 1] * p[c]);
      }
      return [m.surface, Math.abs(v) / 6000];
    })));
    assert.deepEqual(Object.keys(volumes).sort(), ['LV_EPI', 'RV_ENDO', 'RV_EPI']);
    await runAndWait(page, () => page.selectOption('[data-testid=surface-picker]', 'BIV_EPI'));
    const biv = await page.evaluate(() => {
      const r = window.heartmesh.currentResult();
      return { surface: r.surface, watertight: r.watertight, volumeMl: r.volumeMl, meanMm: r.overall.mean };
    });
    assert.ok(biv.surface === 'BIV_EPI' && biv.watertight && biv.meanMm < 1, JSON.stringify(biv));
    assert.ok(biv.volumeMl > 1.2 * volumes.LV_EPI && biv.volumeMl > 1.2 * volumes.RV_EPI, `${biv.volumeMl} ml vs ${JSON.stringify(volumes)}`);
    assert.equal(await legend(), 'LV_EPI,RV_ENDO,RV_EPI,LV_ENDO');
    // The user guide's picture: see-through, the endocardia inside.
    await page.locator('[data-testid=view-opacity]').fill('55');
    await page.waitForTimeout(300);
    await page.screenshot({ path: join(SHOTS, 'biv-epi.png') });
  });
});

/** Pixels (of the same-size PNG screenshots) whose colour differs by more than a few levels. */
async function changedPixels(a, b) {
  return page.evaluate(async ([pa, pb]) => {
    const load = async (bytes) => {
      const bmp = await createImageBitmap(new Blob([new Uint8Array(bytes)], { type: 'image/png' }));
      const c = new OffscreenCanvas(bmp.width, bmp.height);
      const g = c.getContext('2d');
      g.drawImage(bmp, 0, 0);
      return g.getImageData(0, 0, bmp.width, bmp.height).data;
    };
    const [x, y] = [await load(pa), await load(pb)];
    let n = 0;
    for (let i = 0; i < x.length; i += 4) {
      if (Math.abs(x[i] - y[i]) + Math.abs(x[i + 1] - y[i + 1]) + Math.abs(x[i + 2] - y[i + 2]) > 12) n++;
    }
    return n;
  }, [[...a], [...b]]);
}
