// Browser end-to-end test (dist/, Debian's chromium) of the LV wall's AHA bullseye in the Export
// panel. Patient 1 · ED after All, View: under the wall's figures, the core's bullseye drawn in the
// page (an SVG element, its 17 segments as paths, its gradient's id prefixed and referred to by the
// prefixed id, nothing executable), at most 230 px wide and in proportion, captioned with the
// septum's source; segment 2's value as drawn equals the Segments CSV's mean_mm of segment 2 (to
// 0.05: the drawing rounds to 0.1), and the septum (2) is thicker than the lateral wall (6) in
// the CSV; Bullseye SVG saves the core's drawing; a parameter changed takes it away with the
// figures. The SurFCo example has no LV_EPI (nor any surface name): its wall cannot be built and
// no bullseye shows; patient 1 without its RV contours (the same file, LV rows only)
// shows the core's reason instead of a bullseye. Screenshot: bullseye.png in SHOTS.
import { describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { download, gotoEmpty, runAndWait, sharedDir, waitForDone, SHOTS } from './lib.mjs';
import { appForFile } from './perFile.mjs';

let app;
let page;
const pageErrors = [];
appForFile({ onPageError: (m) => pageErrors.push(m) }, (a) => ({ page } = app = a));

const figures = '[data-testid=wall-figures]';
const segments = '[data-testid=wall-segments]';
const drawing = '[data-testid=wall-bullseye-svg]';

/** The Segments CSV's rows by segment id (`#` lines apart), and its header lines. */
function parseSegmentsCsv(text) {
  const lines = text.split('\n').filter((l) => l !== '');
  const header = lines.filter((l) => l.startsWith('#'));
  const [columns, ...rows] = lines.filter((l) => !l.startsWith('#'));
  const names = columns.split(',');
  const byId = new Map(rows.map((r) => {
    const cells = r.split(',');
    const row = Object.fromEntries(names.map((n, i) => [n, cells[i]]));
    return [Number(row.segment), row];
  }));
  return { header, columns, byId };
}

/** Builds the LV wall with View and waits for its figures. */
async function viewWall() {
  await page.click('[data-testid=view-wall]');
  await page.waitForSelector(`${figures}[data-state=done]`, { timeout: 60000 });
}

describe('the LV wall\'s AHA bullseye', () => {
  it('Patient 1 · ED: the core\'s bullseye under the figures, segment 2 as the CSV has it; gone with a parameter change', async () => {
    await page.setViewportSize({ width: 1280, height: 900 });
    await gotoEmpty(page, app.server.url);
    await runAndWait(page, () => page.getByRole('button', { name: 'Patient 1 · ED' }).first().click());
    assert.equal(await page.isVisible(segments), false, 'no wall, no bullseye');
    await page.click('[data-testid=run-all-surfaces]');
    await page.waitForFunction(() => document.querySelector('[data-testid=view-others-count]')?.textContent === ' (3)', null, { timeout: 120000 });
    await waitForDone(page, 120000);
    assert.equal(await page.isVisible(segments), false, 'not built yet');
    await viewWall();
    await page.waitForSelector(`${segments}[data-state=segments]`);

    const shown = await page.$eval(drawing, (el) => {
      const svg = el.querySelector('svg');
      const paths = [...svg.querySelectorAll('path')];
      const p2 = paths.find((p) => p.querySelector('title')?.textContent.startsWith('2 '));
      const box = svg.getBoundingClientRect();
      const gradient = svg.querySelector('linearGradient');
      return {
        namespace: svg.namespaceURI,
        paths: paths.length,
        titles: paths.map((p) => p.querySelector('title')?.textContent ?? ''),
        value2: p2?.nextElementSibling?.textContent ?? '',
        width: box.width,
        height: box.height,
        gradientId: gradient?.id ?? '',
        scaleFill: svg.querySelector('rect[fill^="url("]')?.getAttribute('fill') ?? '',
        executable: svg.querySelectorAll('script, foreignObject').length + [...svg.querySelectorAll('*')].filter((e) => [...e.attributes].some((a) => a.name.startsWith('on'))).length,
        subtitle: [...svg.querySelectorAll('text')].map((t) => t.textContent).find((t) => t.includes('LV_ENDO + LV_EPI')) ?? '',
      };
    });
    assert.equal(shown.namespace, 'http://www.w3.org/2000/svg');
    assert.equal(shown.paths, 17, '17 segments');
    assert.deepEqual(shown.titles.map((t) => Number(t.split(' ')[0])), Array.from({ length: 17 }, (_, i) => i + 1));
    assert.match(shown.titles[1], /^2 basal anteroseptal: \d+\.\d mm$/);
    assert.ok(shown.width > 150 && shown.width <= 230.5, `width ${shown.width}`);
    assert.ok(Math.abs(shown.height / shown.width - 530 / 460) < 0.01, `in proportion: ${shown.width} x ${shown.height}`);
    assert.equal(shown.gradientId, 'wall-bullseye-viridis');
    assert.equal(shown.scaleFill, 'url(#wall-bullseye-viridis)');
    assert.equal(shown.executable, 0);
    assert.equal(shown.subtitle, 'patient1-ED.csv (LV_ENDO + LV_EPI)');
    assert.match(await page.textContent('[data-testid=wall-bullseye-caption]'), /^Septum placed from the RV contours' centre \(\d+ points\)$/);
    assert.equal(await page.isVisible('[data-testid=wall-segments-note]'), false);

    // The CSV: the wall's header, one row per segment; segment 2's mean as drawn (0.1 mm rounding).
    const csv = await download(page, 'export-wall-segments');
    assert.equal(csv.name, 'patient1-ED-LV_wall-segments.csv');
    const { header, columns, byId } = parseSegmentsCsv(csv.bytes.toString('utf8'));
    assert.match(header[0], /^# heartmesh \S+ \(core \S+\), units: mm$/);
    assert.equal(header[1], '# input: patient1-ED.csv surface: LV_ENDO + LV_EPI');
    assert.ok(header.includes('# min_thickness=1 mm (endocardial vertices closer to the epicardium moved under it)'));
    assert.match(header.at(-1), /^# segments: AHA 17, septum from the RV contours' centre \(\d+\); level borders 0\.0, /);
    assert.equal(columns, 'segment,name,mean_mm,min_mm,max_mm,area_mm2');
    assert.deepEqual([...byId.keys()], Array.from({ length: 17 }, (_, i) => i + 1));
    assert.equal(byId.get(2).name, 'basal anteroseptal');
    const mean2 = Number(byId.get(2).mean_mm);
    const drawn2 = Number(shown.value2);
    assert.ok(Number.isFinite(drawn2) && Math.abs(drawn2 - mean2) <= 0.05, `drawn ${shown.value2}, CSV ${mean2}`);
    assert.ok(mean2 > Number(byId.get(6).mean_mm), `septum ${mean2} mm, lateral ${byId.get(6).mean_mm} mm`);
    console.log(`segment 2 mean ${mean2} mm (drawn ${shown.value2}), segment 6 mean ${byId.get(6).mean_mm} mm`);

    // The SVG as the core drew it: its own ids, 17 segments, the input named.
    const svg = await download(page, 'export-wall-bullseye');
    assert.equal(svg.name, 'patient1-ED-LV_wall-segments.svg');
    const svgText = svg.bytes.toString('utf8');
    assert.match(svgText, /^<svg xmlns="http:\/\/www\.w3\.org\/2000\/svg" width="460" height="530" viewBox="0 0 460 530"/);
    assert.equal(svgText.match(/<path /g).length, 17);
    assert.ok(svgText.includes('id="viridis"') && svgText.includes('>patient1-ED.csv (LV_ENDO + LV_EPI)</text>'));

    await page.locator(segments).scrollIntoViewIfNeeded();
    await page.screenshot({ path: join(SHOTS, 'bullseye.png') });

    // A parameter changed: the figures and the bullseye go together.
    await runAndWait(page, () => page.uncheck('[data-testid=param-soften-conflicts]'));
    assert.equal(await page.isVisible(figures), false);
    assert.equal(await page.isVisible(segments), false);
    assert.equal(await page.$$eval(`${drawing} svg`, (s) => s.length), 0);
    assert.deepEqual(pageErrors, []);
  });

  it('SurFCo: no LV_EPI, so no wall to segment', async () => {
    await gotoEmpty(page, app.server.url);
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', join(sharedDir(), 'data', 'contours', 'surfco-example.csv')));
    assert.equal(await page.isDisabled('[data-testid=view-wall]'), true);
    assert.match(await page.getAttribute('[data-testid=view-wall]', 'title'), /this file has no LV_ENDO and no LV_EPI contours$/);
    assert.equal(await page.isVisible(segments), false);
  });

  it('patient 1 without its RV contours: the core\'s reason instead of a bullseye', async () => {
    const lines = readFileSync(join(sharedDir(), 'data', 'contours', 'bivme-example-patient1', 'patient1-ED.csv'), 'utf8').split('\n');
    const lvOnly = [lines[0], ...lines.slice(1).filter((l) => /,LV_(ENDO|EPI)\s*$/.test(l))].join('\n');
    await gotoEmpty(page, app.server.url);
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', { name: 'patient1-ED-lv-only.csv', mimeType: 'text/csv', buffer: Buffer.from(`${lvOnly}\n`) }));
    assert.equal(await page.inputValue('[data-testid=surface-picker]'), 'LV_ENDO');
    await runAndWait(page, () => page.selectOption('[data-testid=surface-picker]', 'LV_EPI'));
    await viewWall();
    await page.waitForSelector(`${segments}[data-state=note]`);
    assert.equal(await page.textContent('[data-testid=wall-segments-note]'), 'No AHA segments: the file has no RV_INSERT landmarks and no RV contours to place the septum by');
    assert.equal(await page.isVisible('[data-testid=wall-bullseye]'), false);
    assert.equal(await page.isVisible('[data-testid=export-wall-bullseye]'), false);
    assert.equal(await page.isVisible('[data-testid=export-wall-segments]'), false);
    assert.deepEqual(pageErrors, []);
  });
});
