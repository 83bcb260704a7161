// Browser end-to-end tests (dist/, Debian's chromium) of the timeline holding every deformation step
// (issue 3): a bundled example at the defaults computes 250 iterations in well under a second, and
// yet the timeline holds every one of them (0..250: the scrubber and the step buttons reach each)
// and the live plot has one point per step; the SurFCo example still reaches done promptly.
import { describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { runAndWait, sharedDir, SHOTS } from './lib.mjs';
import { appForFile } from './perFile.mjs';

let page;
const pageErrors = [];
appForFile({ onPageError: (m) => pageErrors.push(m) }, (app) => ({ page } = app));

/** The timeline's state as the page shows it. */
const timeline = () =>
  page.evaluate(() => ({
    label: document.querySelector('[data-testid=tl-label]')?.textContent ?? '',
    max: Number(document.querySelector('[data-testid=tl-scrubber]')?.getAttribute('max')),
    kept: document.querySelector('[data-testid=tl-kept]')?.hidden === false,
    plotPoints: Number(document.querySelector('[data-testid=live-plot]')?.getAttribute('data-points')),
  }));

describe('the timeline holds every deformation step', () => {
  it('a bundled example at the defaults: iterations 0..250 on the timeline, one plot point per step', async () => {
    await runAndWait(page, () => page.click('[data-testid=sample-patient1-ED]'));
    // The label follows on the next animation frame after done.
    await page.waitForFunction(() => document.querySelector('[data-testid=tl-label]')?.textContent === 'iteration 250 / 250', null, { timeout: 10000 });
    const t = await timeline();
    assert.equal(t.max, 250, 'the scrubber spans 251 recorded steps (0..250)');
    assert.equal(t.plotPoints, 251, 'the live plot has every step');
    assert.equal(t.kept, false, 'no thinning note: every step is kept');
    // Step back from the end with the button, one step at a time: every iteration shows in turn.
    const back = await page.evaluate(async () => {
      const label = document.querySelector('[data-testid=tl-label]');
      const button = document.querySelector('[data-testid=tl-back]');
      const frame = () => new Promise((r) => requestAnimationFrame(() => r(undefined)));
      const seen = [];
      for (let k = 0; k < 250; k++) {
        button.click();
        await frame();
        await frame();
        seen.push(Number(/iteration (\d+)/.exec(label.textContent ?? '')?.[1]));
      }
      return seen;
    });
    assert.deepEqual(back, Array.from({ length: 250 }, (_, i) => 249 - i), 'step back walks 249, 248, ..., 0');
    // The scrubber reaches every iteration too.
    const scrubbed = await page.evaluate(async () => {
      const label = document.querySelector('[data-testid=tl-label]');
      const scrubber = document.querySelector('[data-testid=tl-scrubber]');
      const frame = () => new Promise((r) => requestAnimationFrame(() => r(undefined)));
      const seen = [];
      for (let i = 0; i <= 250; i++) {
        scrubber.value = String(i);
        scrubber.dispatchEvent(new Event('input', { bubbles: true }));
        await frame();
        await frame();
        seen.push(Number(/iteration (\d+)/.exec(label.textContent ?? '')?.[1]));
      }
      return seen;
    });
    assert.deepEqual(scrubbed, Array.from({ length: 251 }, (_, i) => i), 'scrubber position i shows iteration i');
    // Mid-scrub: the step on screen, marked on the plot (someone looks at this screenshot).
    await page.locator('[data-testid=tl-scrubber]').evaluate((el) => {
      el.value = '37';
      el.dispatchEvent(new Event('input', { bubbles: true }));
    });
    await page.waitForFunction(() => /iteration 37 \//.test(document.querySelector('[data-testid=tl-label]')?.textContent ?? ''), null, { timeout: 10000 });
    await page.mouse.move(0, 0);
    await page.waitForTimeout(100);
    await page.screenshot({ path: join(SHOTS, 'timeline-mid-scrub.png') });
    // Back to the end: the final result is on screen again.
    await page.click('[data-testid=tl-latest]');
    await page.waitForFunction(() => document.querySelector('[data-testid=tl-label]')?.textContent === 'iteration 250 / 250', null, { timeout: 10000 });
  });

  it('the SurFCo example still reaches done promptly (recording every step costs next to nothing)', async () => {
    const file = join(sharedDir(), 'data', 'contours', 'surfco-example.csv');
    const t0 = Date.now();
    // (The status still says done from the example above until the drop is read: wait for the new run.)
    await runAndWait(page, () => page.setInputFiles('[data-testid=file-input]', file));
    const ms = Date.now() - t0;
    const coreMs = await page.evaluate(() => (window.heartmesh?.currentResult()?.seconds ?? NaN) * 1000);
    const t = await timeline();
    console.log(`# SurFCo: drop -> done ${ms} ms (core ${coreMs.toFixed(0)} ms), ${t.max + 1} steps recorded, ${t.plotPoints} plot points`);
    // Issue 3's bar is 2 s from the drop (npm run bench:browser measures it, on an idle machine);
    // a test on a shared, loaded machine only bounds what the app adds to the core's own time, very
    // generously (about 0.3 s here): a run held back by its display would take seconds more.
    assert.ok(Number.isFinite(coreMs), 'a result');
    assert.ok(ms - coreMs < 5000, `the app added ${(ms - coreMs).toFixed(0)} ms to the core's ${coreMs.toFixed(0)} ms`);
    assert.equal(t.plotPoints, t.max + 1, 'every step recorded and plotted');
    assert.ok(t.max > 50, `${t.max + 1} steps`);
  });

  it('no page errors', () => {
    assert.deepEqual(pageErrors, []);
  });
});
