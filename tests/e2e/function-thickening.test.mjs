// Browser end-to-end test (dist/, Debian's chromium) of the LV wall's systolic thickening in the
// Function section: biv-me patient 1's ED and ES examples open together, "Measure all phases",
// and under the table the core's thickening bullseye is drawn in the page (an SVG element, its 17
// segments as paths, its gradient's id prefixed `function-thickening-` apart from the wall
// bullseye's, nothing executable), at most 230 px wide and in proportion, captioned with the
// phases and the mean (the CLI's "mean 60 %"); segment 1's value as drawn is the Thickening CSV's
// thickening_percent of segment 1 rounded to a whole number; Thickening SVG saves the core's
// drawing as it is. A parameter changed greys it with the table (changed back, current again);
// measuring again takes it away with the table's cells until the new summary comes. The same
// files without their RV contours: the core's reason as a muted line instead of a bullseye.
// Screenshot: function-thickening.png (1280 x 900) in SHOTS.
import { describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { download, gotoEmpty, runAndWait, sharedDir, SHOTS, functionMeasured, measurePhases } from './lib.mjs';
import { appForFile } from './perFile.mjs';

let server;
let page;
const pageErrors = [];
appForFile({ goto: false, onPageError: (m) => pageErrors.push(m) }, (app) => ({ server, page } = app));

const FN = '[data-testid=function]';
const BOX = '[data-testid=function-thickening]';
const DRAWING = '[data-testid=function-thickening-svg]';

const fnState = () => page.getAttribute(FN, 'data-state');
const waitMeasured = (timeout) => functionMeasured(page, timeout);
/** Measure all phases, to the end. */
const measure = () => measurePhases(page);
const opacity = (sel) => page.$eval(sel, (e) => getComputedStyle(e).opacity);

/** The Thickening CSV's rows by segment id (`#` lines apart), its header lines and its columns. */
function parseCsv(text) {
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

const sample = (name) => readFileSync(join(sharedDir(), 'data', 'contours', 'bivme-example-patient1', name), 'utf8');

describe('Function: the LV wall\'s thickening by AHA segment', () => {
  it('patient 1 ED + ES: the core\'s bullseye under the table, segment 1 as the CSV has it; greyed with the table, gone when measured again', async () => {
    await page.setViewportSize({ width: 1280, height: 900 });
    await gotoEmpty(page, server.url);
    await runAndWait(page, () => page.getByRole('button', { name: 'Patient 1 · ED' }).first().click());
    await runAndWait(page, () => page.getByRole('button', { name: 'Patient 1 · ES' }).first().click());
    assert.equal(await page.isVisible(FN), true);
    assert.equal(await page.isVisible(BOX), false, 'nothing measured: no thickening');
    await measure();
    await page.waitForSelector(`${BOX}[data-state=bullseye]`, { timeout: 10000 });

    const shown = await page.$eval(DRAWING, (el) => {
      const svg = el.querySelector('svg');
      const paths = [...svg.querySelectorAll('path')];
      const p1 = paths.find((p) => p.querySelector('title')?.textContent.startsWith('1 '));
      const box = svg.getBoundingClientRect();
      const gradient = svg.querySelector('linearGradient');
      return {
        namespace: svg.namespaceURI,
        paths: paths.length,
        titles: paths.map((p) => p.querySelector('title')?.textContent ?? ''),
        value1: p1?.nextElementSibling?.textContent ?? '',
        width: box.width,
        height: box.height,
        gradientId: gradient?.id ?? '',
        scaleFill: svg.querySelector('rect[fill^="url("]')?.getAttribute('fill') ?? '',
        executable: svg.querySelectorAll('script, foreignObject').length + [...svg.querySelectorAll('*')].filter((e) => [...e.attributes].some((a) => a.name.startsWith('on'))).length,
        texts: [...svg.querySelectorAll('text')].map((t) => t.textContent),
      };
    });
    assert.equal(shown.namespace, 'http://www.w3.org/2000/svg');
    assert.equal(shown.paths, 17, '17 segments');
    assert.deepEqual(shown.titles.map((t) => Number(t.split(' ')[0])), Array.from({ length: 17 }, (_, i) => i + 1));
    assert.match(shown.titles[0], /^1 basal anterior: -?\d+ %$/);
    assert.ok(shown.width > 150 && shown.width <= 230.5, `width ${shown.width}`);
    assert.ok(Math.abs(shown.height / shown.width - 530 / 460) < 0.01, `in proportion: ${shown.width} x ${shown.height}`);
    assert.equal(shown.gradientId, 'function-thickening-viridis');
    assert.equal(shown.scaleFill, 'url(#function-thickening-viridis)');
    assert.equal(shown.executable, 0);
    assert.ok(shown.texts.includes('Systolic wall thickening by AHA segment (%)'), shown.texts.join(' | '));
    assert.ok(shown.texts.includes('ED patient1-ED to ES patient1-ES'), shown.texts.join(' | '));
    // The CLI's line for these files: "mean 60 %, from 20 % (9 mid inferoseptal) to 92 % (6 basal anterolateral)".
    assert.equal(await page.textContent('[data-testid=function-thickening-caption]'), 'LV wall thickening patient1-ED → patient1-ES: mean 60 %');
    assert.equal(await page.isVisible('[data-testid=function-thickening-note]'), false);
    // Under the table and the EF lines.
    const below = await page.$eval(BOX, (e) => {
      const y = e.getBoundingClientRect().top;
      return ['[data-testid=function-table]', '[data-testid=function-summary]'].map((s) => document.querySelector(s).getBoundingClientRect().bottom <= y);
    });
    assert.deepEqual(below, [true, true]);

    // The CSV: a `#` header, the columns, one row per segment; segment 1's value as drawn.
    const csv = await download(page, 'function-thickening-save-csv');
    assert.equal(csv.name, 'phases-LV_wall-thickening.csv');
    const { header, columns, byId } = parseCsv(csv.bytes.toString('utf8'));
    assert.match(header[0], /^# heartmesh \S+ \(core \S+\), units: mm$/);
    assert.doesNotMatch(header[0], /core unknown/);
    assert.equal(header[1], '# input: patient1-ED.csv, patient1-ES.csv surface: LV_ENDO + LV_EPI');
    assert.match(header[2], /^# lids: auto /);
    assert.ok(header.includes('# min_thickness=1 mm (endocardial vertices closer to the epicardium moved under it)'), header.join('\n'));
    assert.ok(header.includes("# thickening: 100 x (ES - ED) / ED of each segment's mean wall thickness; ED patient1-ED (patient1-ED.csv), ES patient1-ES (patient1-ES.csv)"), header.join('\n'));
    assert.match(header.at(-1), /^# segments: AHA 17, septum from the RV contours' centre \(\d+\)/);
    assert.equal(columns, 'segment,name,ed_mm,es_mm,thickening_percent');
    assert.deepEqual([...byId.keys()], Array.from({ length: 17 }, (_, i) => i + 1));
    assert.equal(byId.get(1).name, 'basal anterior');
    const t1 = Number(byId.get(1).thickening_percent);
    assert.ok(Number.isFinite(t1), byId.get(1).thickening_percent);
    assert.equal(Number(shown.value1), Math.round(t1), `drawn ${shown.value1}, CSV ${t1}`);
    assert.equal(shown.titles[0], `1 basal anterior: ${Math.round(t1)} %`);
    // Its thickening is its ES thickness over its ED thickness (to the CSV's 4 decimals).
    const { ed_mm: ed1, es_mm: es1 } = byId.get(1);
    assert.ok(Math.abs((100 * (Number(es1) - Number(ed1))) / Number(ed1) - t1) < 0.01, `${ed1} -> ${es1} mm: ${t1} %`);
    console.log(`segment 1: ${ed1} -> ${es1} mm, ${t1} % (drawn ${shown.value1})`);

    // The SVG as the core drew it: its own ids, 17 segments.
    const svg = await download(page, 'function-thickening-save-svg');
    assert.equal(svg.name, 'phases-LV_wall-thickening.svg');
    const svgText = svg.bytes.toString('utf8');
    assert.match(svgText, /^<svg xmlns="http:\/\/www\.w3\.org\/2000\/svg" width="460" height="530" viewBox="0 0 460 530"/);
    assert.equal(svgText.match(/<path /g).length, 17);
    assert.ok(svgText.includes('id="viridis"') && svgText.includes('<title>1 basal anterior: '));

    // The screenshot: the column scrolled so the section's bottom (the bullseye and its buttons) shows.
    await page.locator(FN).evaluate((e) => {
      const column = e.closest('.sidebar');
      column.scrollTop += e.getBoundingClientRect().bottom - column.getBoundingClientRect().bottom + 10;
    });
    await page.mouse.move(0, 0);
    const inView = await page.$eval(BOX, (e) => {
      const r = e.getBoundingClientRect();
      return r.top >= 0 && r.bottom <= window.innerHeight;
    });
    assert.ok(inView, 'the thickening in the view for the screenshot');
    await page.screenshot({ path: join(SHOTS, 'function-thickening.png') });

    // A parameter changed: greyed with the table, kept; changed back, current again.
    assert.equal(await opacity(`${BOX} .bullseye`), '1');
    await runAndWait(page, () => page.check('[data-testid=param-keep-specks]'), 120000);
    assert.equal(await page.getAttribute(FN, 'data-stale'), '1');
    assert.equal(await opacity('[data-testid=function-table]'), '0.5');
    assert.equal(await opacity(`${BOX} .bullseye`), '0.5');
    assert.equal(await page.isVisible(BOX), true);
    await runAndWait(page, () => page.uncheck('[data-testid=param-keep-specks]'), 120000);
    assert.equal(await page.getAttribute(FN, 'data-stale'), '0');
    assert.equal(await opacity(`${BOX} .bullseye`), '1');

    // Measured again (with the setting changed): gone with the table's cells, back with the new summary.
    await runAndWait(page, () => page.check('[data-testid=param-keep-specks]'), 120000);
    await page.click('[data-testid=function-measure]');
    const during = await page.evaluate(([box, drawing]) => ({
      hidden: document.querySelector(box).hidden,
      svgs: document.querySelectorAll(`${drawing} svg`).length,
      caption: document.querySelector('[data-testid=function-thickening-caption]').textContent,
    }), [BOX, DRAWING]);
    assert.deepEqual(during, { hidden: true, svgs: 0, caption: '' });
    await waitMeasured();
    await page.waitForSelector(`${BOX}[data-state=bullseye]`, { timeout: 10000 });
    assert.equal(await page.getAttribute(FN, 'data-stale'), '0');
    assert.equal(await page.$$eval(`${DRAWING} svg path`, (ps) => ps.length), 17);
    assert.equal(await opacity(`${BOX} .bullseye`), '1');
    await runAndWait(page, () => page.uncheck('[data-testid=param-keep-specks]'), 120000);
    assert.deepEqual(pageErrors, []);
  });

  it('patient 1 without its RV contours: the core\'s reason instead of a bullseye', async () => {
    const lvOnly = (name) => {
      const lines = sample(name).split('\n');
      return `${[lines[0], ...lines.slice(1).filter((l) => /,LV_(ENDO|EPI)\s*$/.test(l))].join('\n')}\n`;
    };
    await gotoEmpty(page, server.url);
    for (const name of ['patient1-ED', 'patient1-ES']) {
      await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', { name: `${name}-lv.csv`, mimeType: 'text/csv', buffer: Buffer.from(lvOnly(`${name}.csv`)) }));
    }
    assert.equal(await page.textContent(`${FN} .function-source`), '2 phases: the 2 open files');
    await measure();
    await page.waitForSelector(`${BOX}[data-state=note]`, { timeout: 10000 });
    const note = (await page.textContent('[data-testid=function-thickening-note]')) ?? '';
    assert.match(note, /^No wall thickening: .*RV/);
    console.log(note);
    // Muted, as the section's other muted line (its source).
    const colour = (sel) => page.$eval(sel, (e) => getComputedStyle(e).color);
    assert.equal(await colour('[data-testid=function-thickening-note]'), await colour(`${FN} .function-source`));
    assert.equal(await page.isVisible('[data-testid=function-thickening-bullseye]'), false);
    assert.equal(await page.isVisible('[data-testid=function-thickening-save-svg]'), false);
    assert.equal(await page.isVisible('[data-testid=function-thickening-save-csv]'), false);
    // The LV's function is there all the same.
    assert.equal(await page.$$eval('[data-testid=function-ventricle]', (ls) => ls.map((l) => l.getAttribute('data-surface'))).then((s) => s.includes('LV_ENDO')), true);
    assert.deepEqual(pageErrors, []);
  });
});
