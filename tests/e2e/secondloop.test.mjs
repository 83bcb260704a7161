// Browser end-to-end test (dist/, Debian's chromium) of "Leave out second loops" (the CLI's
// --drop-second-loops, session 30): the bundled patient 1 ED with a closed loop of 5 mm radius
// beside the basal LV ring, in its plane (built here, tests/e2e/secondLoop.mjs). At the default the
// load-time warning names it, a note says where the option is, and the mesh is pulled out round the
// loop; ticked, the mesh is the mesh of the file without the loop (same volume and triangles), the
// note says the loops are left out, and the URL, the exports and a session carry it.
import { describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { download as downloadFrom, gotoEmpty, ROOT, runAndWait, SHOTS } from './lib.mjs';
import { appForFile } from './perFile.mjs';
import { withSecondLoop } from './secondLoop.mjs';

let server;
let page;
appForFile({ goto: false }, (app) => ({ server, page } = app));

const RADIUS_MM = 5;
const GAP_MM = 8;
const loop = withSecondLoop(readFileSync(join(ROOT, 'public', 'samples', 'patient1-ED.csv'), 'utf8'), { radiusMm: RADIUS_MM, gapMm: GAP_MM });
const NAME = 'patient1-ED-second-loop.csv';
const drop = () => page.setInputFiles('[data-testid=file-input]', { name: NAME, mimeType: 'text/csv', buffer: Buffer.from(loop.csv) });
const warnings = async () => (await page.textContent('#slot-warnings')) ?? '';

/** The current mesh: volume, triangles, whether the loop's contour is among the run's, and the nearest vertex to the loop's centre (mm). */
const mesh = () =>
  page.evaluate(({ centre, id }) => {
    const r = window.heartmesh.currentResult();
    const p = r.positionsF64 ?? r.positions;
    let nearest = Infinity;
    for (let i = 0; i < p.length; i += 3) nearest = Math.min(nearest, Math.hypot(p[i] - centre[0], p[i + 1] - centre[1], p[i + 2] - centre[2]));
    return { volumeMl: r.volumeMl, triangles: r.indices.length / 3, hasLoop: r.contours.some((c) => c.id === id), nearestMm: nearest };
  }, { centre: loop.centre, id: loop.id });

describe('a second closed loop in a short-axis slice', () => {
  it('is warned about and pulls the mesh; "Leave out second loops" gives the mesh of the file without it', async () => {
    await gotoEmpty(page, server.url);
    assert.equal(await page.isChecked('[data-testid=param-drop-second-loops]'), false, 'off by default');
    assert.match((await page.textContent('label[for=param-drop-second-loops]')) ?? '', /^Leave out second loops$/);

    // The file without the loop: the mesh the option must give back.
    await runAndWait(page, () => page.click('[data-testid=sample-patient1-ED]'), 120000);
    const clean = await mesh();
    assert.equal(clean.hasLoop, false);

    // With the loop, at the default: named with its line and distance; the mesh wraps round it.
    await gotoEmpty(page, server.url);
    await runAndWait(page, drop, 120000);
    assert.equal(await page.inputValue('[data-testid=surface-picker]'), 'LV_ENDO');
    const warned = await warnings();
    assert.match(warned, new RegExp(`contour "${loop.id}" \\(line ${loop.line}, \\d+ mm from "${loop.mainId}"\\) is a second closed loop in a short-axis slice`));
    assert.match(warned, /the option Leave out second loops \(Parameters\) follows each slice's main loop only/);
    const kept = await mesh();
    assert.equal(kept.hasLoop, true);
    assert.ok(kept.nearestMm < RADIUS_MM, `the surface reaches into the loop: nearest vertex ${kept.nearestMm.toFixed(2)} mm from its centre`);
    assert.ok(Math.abs(kept.volumeMl - clean.volumeMl) > 0.5, `another mesh: ${kept.volumeMl} vs ${clean.volumeMl} ml`);
    await page.screenshot({ path: join(SHOTS, 'second-loop-kept.png') });

    // Ticked: a new run without the loop, the file's mesh without it to the last digit.
    await runAndWait(page, () => page.check('[data-testid=param-drop-second-loops]'), 120000);
    assert.match(page.url(), /drop_second_loops=1/);
    const left = await mesh();
    assert.equal(left.hasLoop, false);
    assert.ok(left.nearestMm > RADIUS_MM + GAP_MM, `the surface stays at the basal ring: nearest vertex ${left.nearestMm.toFixed(2)} mm from the loop's centre`);
    assert.ok(Math.abs(left.volumeMl - clean.volumeMl) < 1e-9, `${left.volumeMl} vs ${clean.volumeMl} ml`);
    assert.equal(left.triangles, clean.triangles);
    assert.match(await warnings(), /Leave out second loops is on: the loops named above are left out of the reconstruction/);
    console.log(`# second loop: kept ${kept.volumeMl.toFixed(1)} ml, nearest ${kept.nearestMm.toFixed(1)} mm; left out ${left.volumeMl.toFixed(1)} ml (file without it ${clean.volumeMl.toFixed(1)} ml), nearest ${left.nearestMm.toFixed(1)} mm`);
    await page.screenshot({ path: join(SHOTS, 'second-loop-left-out.png') });

    // The exports and a session carry the option; the session opens again with it ticked.
    assert.equal(JSON.parse((await downloadFrom(page, 'export-json')).bytes.toString('utf8')).drop_second_loops, true);
    assert.match((await downloadFrom(page, 'export-obj')).bytes.toString('utf8'), /drop_second_loops=true/);
    const session = await downloadFrom(page, 'export-session');
    assert.equal(JSON.parse(session.bytes.toString('utf8')).parameters.drop_second_loops, true);
    await gotoEmpty(page, server.url);
    assert.equal(await page.isChecked('[data-testid=param-drop-second-loops]'), false);
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', { name: session.name, mimeType: 'application/json', buffer: session.bytes }), 120000);
    assert.equal(await page.isChecked('[data-testid=param-drop-second-loops]'), true);
    assert.ok(Math.abs((await mesh()).volumeMl - clean.volumeMl) < 1e-9);
  });
});
