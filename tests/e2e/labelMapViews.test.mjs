// Browser end-to-end tests (dist/, Debian's chromium) of long-axis views read with their
// short-axis stack: label maps the native CLI makes (`heartmesh segment ... --lax 3`,
// laxViews.mjs: seg.nii.gz and seg_lax1..3.nii.gz) chosen together with Open… open as one file,
// the stack, its contours holding each view's long-axis curves (LAX) and the notes line saying how
// each view was read; LV_ENDO reconstructs closed, within 1 mm of its curves and as the CLI's
// `reconstruct seg.nii.gz seg_lax*.nii.gz` (the user guide's picture, label-map-views.png in the
// screenshot folder, is its LV_EPI). A view opened alone is added to the stack on screen (a blue
// note says so); a damaged one is refused, the stack and its run kept. A 4D cine with 4D views
// (built from the CLI's files) keeps its views when the Frame picker reads another frame. The
// study's folder dropped on the page opens the stack with its views.
import { describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { copyFileSync, mkdirSync, mkdtempSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { zipSync } from 'fflate';
import { dropPaths, gotoEmpty, ROOT, runAndWait, SHOTS, waitForError } from './lib.mjs';
import { appForFile } from './perFile.mjs';
import { cineName, cineOf, DICOM_SEG, dicomSegBytes, makeStudy, STACK, VIEW_CURVES, VIEWS } from './laxViews.mjs';
import { cliReport } from '../node/helpers.mjs';

/** An MR cine image (the cvi42 fixture's). */
const IMAGE = join(ROOT, 'wasm-core', 'crates', 'heartmesh-core', 'tests', 'data', 'cvi42-patient1', 'dicom', 'IM_01_00.dcm');

let app;
let page;
const pageErrors = [];
appForFile({ onPageError: (m) => pageErrors.push(m) }, (a) => ({ page } = app = a));
const study = makeStudy();

/** The run on screen: surface, closed or not, contour-to-mesh mean and max, volume, mesh size, LAX curves' means. */
const current = () => page.evaluate(() => {
  const r = window.heartmesh.currentResult();
  return r && {
    surface: r.surface, watertight: r.watertight, meanMm: r.overall.mean, maxMm: r.overall.max,
    volumeMl: r.volumeMl, vertices: r.positions.length / 3, triangles: r.indices.length / 3,
    lax: r.perContour.filter((c) => c.kind === 'LAX').map((c) => [c.id, c.stats.mean]),
  };
});
/** The current file's long-axis curves per surface, and its name. */
const laxCurves = () => page.evaluate(() => {
  const f = window.heartmesh.currentFileData();
  const out = {};
  for (const c of f.contours.filter((x) => x.kind === 'LAX')) out[c.surface] = (out[c.surface] ?? 0) + 1;
  return { file: f.fileName, lax: out, ids: f.contours.filter((x) => x.kind === 'LAX').map((c) => c.id) };
});
const listed = () => page.$$eval('[data-testid=file-picker] option', (os) => os.map((o) => o.value));
const visibleText = async (sel) => ((await page.isVisible(sel)) ? (await page.textContent(sel)) ?? '' : '');
/** The notes line's notes (none when it is hidden). */
const notes = async () => ((await page.isVisible('[data-testid=notes]')) ? page.$$eval('[data-testid=notes-list] .note', (ps) => ps.map((p) => p.textContent)) : []);
const warnings = () => visibleText('#slot-warnings');
const banner = async () => ((await page.isVisible('[data-testid=error-banner]')) ? (await page.textContent('[data-testid=error-text]')) ?? '' : '');
const relative = (a, b) => Math.abs(a - b) / Math.abs(b);

/** LV_EPI of the stack with the three views, for the later tests to compare with. */
let epiWithViews = null;

describe('NIfTI long-axis views with their stack', () => {
  it('a stack and its 3 views chosen together: one file, each surface gets its views\' curves; LV_ENDO closed, near them and the CLI\'s', async () => {
    await page.setViewportSize({ width: 1280, height: 720 });
    await gotoEmpty(page, app.server.url);
    // Views before and after the stack: each goes with it whatever the order (read in name order).
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', [VIEWS[1], STACK, VIEWS[0], VIEWS[2]].map((n) => study.paths[n])), 120000);
    assert.deepEqual(await listed(), [STACK], 'the views are not listed as files');
    const { file, lax, ids } = await laxCurves();
    assert.equal(file, STACK);
    assert.deepEqual(lax, VIEW_CURVES);
    assert.deepEqual(ids.sort(), ['seg_lax1 LV_ENDO', 'seg_lax1 LV_EPI', 'seg_lax2 LV_ENDO', 'seg_lax2 LV_EPI', 'seg_lax2 RV_ENDO', 'seg_lax3 LV_ENDO', 'seg_lax3 LV_EPI', 'seg_lax3 RV_ENDO']);
    // How each was read: on the notes line, one line each, not among the warnings.
    const said = await notes();
    console.log(`# notes line:\n#   ${said.join('\n#   ')}`);
    assert.equal(said.length, 4);
    assert.match(said[0], /^label map read as 3 LV cavity \(LV_ENDO\), 2 myocardium/);
    for (const [i, v] of VIEWS.entries()) assert.match(said[i + 1], new RegExp(`^long-axis view ${v.replace(/\./g, '\\.')} read as .*; [23] curves added`));
    // Folded to its first note, with how many follow; a click opens them all.
    assert.equal(await page.textContent('[data-testid=notes-first]'), said[0]);
    assert.match((await page.textContent('.notes-summary')) ?? '', /\+3 more$/);
    assert.equal(await page.isVisible('[data-testid=notes-list]'), false);
    await page.click('.notes-summary');
    assert.equal(await page.isVisible('[data-testid=notes-list]'), true);
    assert.equal(await page.isVisible('[data-testid=notes-first]'), false);
    await page.click('.notes-summary');
    assert.equal(await page.isVisible('[data-testid=notes-list]'), false);
    assert.doesNotMatch(await warnings(), / read as /);

    const r = await current();
    const native = cliReport(study.paths[STACK], [...VIEWS.map((v) => study.paths[v]), '--surface', 'LV_ENDO'], 'e2e-lax-views-LV_ENDO');
    console.log(`# stack + 3 views LV_ENDO: ${r.volumeMl.toFixed(1)} ml (CLI ${native.volume_ml.toFixed(1)} ml), contour-to-mesh mean ${r.meanMm.toFixed(3)} mm, `
      + `max ${r.maxMm.toFixed(2)} mm, ${r.vertices} vertices; LAX curves ${r.lax.map(([id, m]) => `${id} ${m.toFixed(2)}`).join(', ')} mm`);
    assert.equal(r.surface, 'LV_ENDO');
    assert.equal(r.watertight, true);
    assert.equal(r.triangles, 2 * r.vertices - 4, 'a closed genus-0 mesh');
    assert.ok(r.meanMm > 0 && r.meanMm < 1, `mean ${r.meanMm} mm`);
    assert.ok(r.maxMm < 5, `max ${r.maxMm} mm`);
    assert.equal(r.lax.length, VIEW_CURVES.LV_ENDO);
    for (const [id, m] of r.lax) assert.ok(m < 1, `${id}: mean ${m} mm`);
    assert.equal(r.vertices, native.vertices);
    assert.ok(relative(r.volumeMl, native.volume_ml) < 1e-6, `${r.volumeMl} ml vs the CLI's ${native.volume_ml} ml`);
    assert.ok(r.volumeMl > 60 && r.volumeMl < 100, `${r.volumeMl} ml`);

    // The user guide's picture: the epicardium see-through over its short- and long-axis curves.
    await page.uncheck('[data-testid=view-attractors]');
    await runAndWait(page, () => page.selectOption('[data-testid=surface-picker]', 'LV_EPI'), 120000);
    epiWithViews = await current();
    console.log(`# stack + 3 views LV_EPI: ${epiWithViews.volumeMl.toFixed(1)} ml, mean ${epiWithViews.meanMm.toFixed(3)} mm, ${epiWithViews.vertices} vertices`);
    assert.equal(epiWithViews.watertight, true);
    assert.ok(epiWithViews.meanMm < 1 && epiWithViews.lax.length === VIEW_CURVES.LV_EPI, JSON.stringify(epiWithViews));
    assert.ok(epiWithViews.volumeMl > 1.8 * r.volumeMl, `LV_EPI ${epiWithViews.volumeMl} ml, LV_ENDO ${r.volumeMl} ml`);
    await page.locator('[data-testid=view-opacity]').fill('45');
    await page.waitForTimeout(300);
    await page.mouse.move(0, 0);
    await page.screenshot({ path: join(SHOTS, 'label-map-views.png') });
    await page.check('[data-testid=view-attractors]');
  });

  it('views opened alone go onto the stack on screen, a note saying so; the same mesh as all opened together', async () => {
    // The stack opened again alone: read without views (they went with its earlier reading).
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', study.paths[STACK]), 120000);
    assert.deepEqual((await laxCurves()).lax, {});
    assert.equal((await notes()).length, 1);
    const alone = await current();

    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', study.paths[VIEWS[2]]), 120000);
    assert.equal(await banner(), `${VIEWS[2]} added to ${STACK} as a long-axis view.`);
    assert.equal(await page.getAttribute('[data-testid=error-banner]', 'data-kind'), 'info');
    assert.deepEqual((await laxCurves()).lax, { LV_ENDO: 1, LV_EPI: 1, RV_ENDO: 1 });
    assert.equal(await page.inputValue('[data-testid=surface-picker]'), 'LV_EPI', 'the surface on screen runs again');
    const one = await current();
    assert.deepEqual(one.lax.map(([id]) => id), ['seg_lax3 LV_EPI']);

    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', [study.paths[VIEWS[0]], study.paths[VIEWS[1]]]), 120000);
    assert.equal(await banner(), `${VIEWS[0]}, ${VIEWS[1]} added to ${STACK} as long-axis views.`);
    assert.deepEqual((await laxCurves()).lax, VIEW_CURVES);
    assert.deepEqual(await listed(), [STACK]);
    const all = await current();
    console.log(`# LV_EPI: stack alone ${alone.volumeMl.toFixed(1)} ml, + seg_lax3 ${one.volumeMl.toFixed(1)} ml, + all 3 views ${all.volumeMl.toFixed(1)} ml `
      + `(opened together ${epiWithViews.volumeMl.toFixed(1)} ml); LAX curves ${all.lax.map(([id, m]) => `${id} ${m.toFixed(2)}`).join(', ')} mm`);
    assert.equal(all.watertight, true);
    assert.equal(all.lax.length, VIEW_CURVES.LV_EPI);
    // The same curves (the views read in name order however they came): the same mesh.
    assert.equal(all.volumeMl, epiWithViews.volumeMl);
    assert.equal(all.vertices, epiWithViews.vertices);
    // A view of the same name again replaces its older self.
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', study.paths[VIEWS[0]]), 120000);
    assert.deepEqual((await laxCurves()).lax, VIEW_CURVES);
  });

  it('a damaged view is refused: the banner names it, the stack and its run stay', async () => {
    const before = await current();
    const curves = await laxCurves();
    const cut = study.bytes[VIEWS[1]].slice(0, 200);
    await page.setInputFiles('[data-testid=file-input]', { name: 'cut_lax.nii.gz', mimeType: 'application/gzip', buffer: Buffer.from(cut) });
    const status = await waitForError(page, 'cut_lax.nii.gz');
    const text = (await page.textContent('[data-testid=error-text]')) ?? '';
    console.log(`# damaged view: ${text}`);
    assert.match(status, /the gzip data is damaged/);
    assert.match(text, /^cut_lax\.nii\.gz: the gzip data is damaged .*\. Not added to seg\.nii\.gz; still showing it as read before\.$/);
    assert.deepEqual(await current(), before, 'the reconstruction on screen is kept');
    assert.deepEqual(await laxCurves(), curves, 'the stack as it was read');
    assert.deepEqual(await listed(), [STACK]);
  });

  it('a 4D cine with 4D views: the views stay when the Frame picker reads the systolic frame, its LV cavity smaller', async () => {
    const files = [STACK, ...VIEWS].map((n) => ({ name: cineName(n), mimeType: 'application/octet-stream', buffer: Buffer.from(cineOf(study.bytes[n])) }));
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', files), 120000);
    const name = cineName(STACK);
    assert.deepEqual(await listed(), [STACK, name]);
    assert.deepEqual(await page.$$eval('[data-testid=frame-picker] option', (os) => os.map((o) => o.textContent)), ['frame 0', 'frame 1']);
    assert.deepEqual((await laxCurves()).lax, VIEW_CURVES);
    if ((await page.inputValue('[data-testid=surface-picker]')) !== 'LV_ENDO') await runAndWait(page, () => page.selectOption('[data-testid=surface-picker]', 'LV_ENDO'), 120000);
    const ed = await current();
    await runAndWait(page, () => page.selectOption('[data-testid=frame-picker]', '1'), 120000);
    const es = await current();
    const { file, lax } = await laxCurves();
    assert.equal(file, name);
    assert.deepEqual(lax, VIEW_CURVES, 'frame 1 read with its views');
    assert.equal(es.lax.length, VIEW_CURVES.LV_ENDO);
    assert.equal((await notes()).length, 4);
    const ratio = es.volumeMl / ed.volumeMl;
    console.log(`# cine + 4D views LV_ENDO: frame 0 ${ed.volumeMl.toFixed(1)} ml, frame 1 ${es.volumeMl.toFixed(1)} ml (ratio ${ratio.toFixed(3)}), mean ${es.meanMm.toFixed(3)} mm`);
    assert.ok(es.watertight && es.meanMm < 1, JSON.stringify(es));
    assert.ok(ratio > 0.75 && ratio < 0.95, `frame 1 / frame 0 LV cavity ${ratio}`);
    // Back to frame 0: the same mesh as before (the views read again with it).
    await runAndWait(page, () => page.selectOption('[data-testid=frame-picker]', '0'), 120000);
    assert.equal((await current()).volumeMl, ed.volumeMl);
  });

  it('the study\'s folder dropped on the page: the stack opens with its views (not onto the cine on screen)', async () => {
    await dropPaths(page, [study.dir]);
    // The same seg.nii.gz as opened with Open… (same size and date): its entry, read with its views.
    assert.deepEqual(await listed(), [cineName(STACK), STACK]);
    const { file, lax } = await laxCurves();
    assert.equal(file, STACK);
    assert.deepEqual(lax, VIEW_CURVES);
    assert.equal((await notes()).length, 4);
    const r = await current();
    console.log(`# folder drop: ${r.surface} ${r.volumeMl.toFixed(1)} ml, ${r.lax.length} LAX curves, mean ${r.meanMm.toFixed(3)} mm`);
    assert.ok(r.watertight && r.lax.length === VIEW_CURVES[r.surface], JSON.stringify(r));
    assert.deepEqual(pageErrors, []);
  });

  it('the stack as a DICOM SEG (LPS) with the NIfTI views (RAS), chosen together and zipped: the views turned into the stack\'s coordinates, LV_EPI as the NIfTI study\'s', async () => {
    const seg = 'spasm-seg.dcm';
    const check = async (name) => {
      const { file, lax } = await laxCurves();
      assert.equal(file, name);
      assert.deepEqual(lax, VIEW_CURVES);
      const said = await notes();
      assert.equal(said.length, 4);
      assert.match(said[0], /frame positions \(DICOM SEG, LPS\)/);
      for (const [i, v] of VIEWS.entries()) assert.match(said[i + 1], new RegExp(`^long-axis view ${v.replace(/\./g, '\\.')} read as .*; [23] curves added`));
      if ((await page.inputValue('[data-testid=surface-picker]')) !== 'LV_EPI') await runAndWait(page, () => page.selectOption('[data-testid=surface-picker]', 'LV_EPI'), 120000);
      return current();
    };
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', [DICOM_SEG, ...VIEWS.map((n) => study.paths[n])]), 120000);
    const r = await check(seg);
    console.log(`# DICOM SEG stack + 3 NIfTI views LV_EPI: ${r.volumeMl.toFixed(2)} ml (NIfTI study ${epiWithViews.volumeMl.toFixed(2)} ml), mean ${r.meanMm.toFixed(3)} mm`);
    assert.ok(r.watertight && r.lax.length === VIEW_CURVES.LV_EPI, JSON.stringify(r));
    // As on the command line (label_maps_cli.rs): the NIfTI study's mesh to the spread of two
    // samplings of pixel-traced curves.
    assert.ok(relative(r.volumeMl, epiWithViews.volumeMl) < 0.01, `${r.volumeMl} vs ${epiWithViews.volumeMl}`);
    await page.mouse.move(0, 0);
    await page.screenshot({ path: join(SHOTS, 'seg-with-nifti-views.png') });
    // The same files in a ZIP archive: the SEG kept whole (its pixels are its label map), the same mesh.
    const members = { [`study/${seg}`]: dicomSegBytes() };
    for (const v of VIEWS) members[`study/${v}`] = study.bytes[v];
    const zipPath = join(mkdtempSync(join(tmpdir(), 'heartmesh-segzip-')), 'study.zip');
    writeFileSync(zipPath, zipSync(members));
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', zipPath), 120000);
    // Another file of the name on screen (from the archive): kept beside it, numbered.
    const z = await check('spasm-seg (2).dcm');
    assert.equal(z.volumeMl, r.volumeMl);
    assert.deepEqual(pageErrors, []);
  });

  it('a PACS export\'s folder dropped: its segmentation named by a UID opens with the views beside it, its images are not read', async () => {
    // A folder as a PACS hands studies out: files named by their SOP Instance UID or IM00000n,
    // without extensions or as .dcm: the SEG, two MR images, and the NIfTI views.
    const dir = join(mkdtempSync(join(tmpdir(), 'heartmesh-pacs-')), 'export');
    mkdirSync(dir);
    const uid = '1.2.826.0.1.3680043.8.498.10492';
    writeFileSync(join(dir, uid), dicomSegBytes());
    copyFileSync(IMAGE, join(dir, 'IM000001'));
    copyFileSync(IMAGE, join(dir, 'IM000002.dcm'));
    for (const v of VIEWS) writeFileSync(join(dir, v), study.bytes[v]);
    await dropPaths(page, [dir]);
    const { file, lax } = await laxCurves();
    assert.equal(file, uid);
    assert.deepEqual(lax, VIEW_CURVES);
    // The nameless image was looked into, not opened: counted; the one named .dcm was read and
    // set aside as an image (no refusal listed); the study read as chosen.
    assert.equal(await banner(), `1 DICOM image set aside: images, not contours (the contours come from ${uid}). 1 other file in the dropped folder was not read (not a contour file, or past the first 200 files).`);
    assert.equal((await notes()).length, 4);
    await page.mouse.move(0, 0);
    await page.screenshot({ path: join(SHOTS, 'pacs-folder.png') });
    const r = await current();
    console.log(`# PACS folder: ${r.surface} ${r.volumeMl.toFixed(1)} ml, ${r.lax.length} LAX curves`);
    assert.ok(r.watertight && r.lax.length === VIEW_CURVES[r.surface], JSON.stringify(r));
    assert.deepEqual(pageErrors, []);
  });
});

