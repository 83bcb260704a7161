// Browser end-to-end test (dist/, Debian's chromium) of session 51's contours of several slices
// under one name: the bundled patient 1 ED with every short-axis LV endocardium contour renamed
// "LV endo" (one name for the whole stack, as a contour column holding the surface gives). The
// core reads one contour per image plane, the warning names them, and the mesh is the file's own
// (same volume, same number of contours and points).
import { describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { gotoEmpty, readResult, ROOT, runAndWait, SHOTS, textOf } from './lib.mjs';
import { appForFile } from './perFile.mjs';

let server;
let page;
appForFile({ goto: false }, (app) => ({ server, page } = app));

const original = readFileSync(join(ROOT, 'public', 'samples', 'patient1-ED.csv'), 'utf8');
const renamed = original.replace(/^s\d+_SAX_LV_ENDOCARDIAL,/gm, 'LV endo,');
const drop = (name, text) => page.setInputFiles('[data-testid=file-input]', { name, mimeType: 'text/csv', buffer: Buffer.from(text) });
const onScreen = () => page.evaluate(() => {
  const r = window.heartmesh.currentResult();
  return { volumeMl: r.volumeMl, contours: r.contours.length, points: r.contourPoints.length / 3 };
});

describe('one contour name for several slices', () => {
  it('reads each slice\'s curve as a contour, says so, and gives the mesh of the file as drawn', async () => {
    assert.ok(renamed !== original && (renamed.match(/^LV endo,/gm) ?? []).length > 100, 'the stack renamed');
    await gotoEmpty(page, server.url);
    await runAndWait(page, () => drop('patient1-ED.csv', original), 120000);
    const want = await onScreen();
    const wantResult = await readResult(page);
    await runAndWait(page, () => drop('patient1-ED-one-name.csv', renamed), 120000);
    assert.equal(await page.inputValue('[data-testid=surface-picker]'), 'LV_ENDO');
    const warning = await textOf(page, '#slot-warnings');
    assert.match(warning, /contour "LV endo" \(line \d+, 5 image planes, read as "LV endo", "LV endo \(2\)", "LV endo \(3\)", "LV endo \(4\)", "LV endo \(5\)"\) holds the curves of several slices under one name/);
    const got = await onScreen();
    assert.deepEqual(got, want);
    const result = await readResult(page);
    assert.equal(result.vertices, wantResult.vertices);
    assert.equal(result.meanMm, wantResult.meanMm);
    await page.screenshot({ path: join(SHOTS, 'one-name-several-slices.png') });
  });
});
