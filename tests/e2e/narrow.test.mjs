// Browser end-to-end tests (dist/, Debian's chromium) of the app on a narrow window (session 19):
// a phone (390 x 844) and a tablet held upright (768 x 1024) get one scrolling column, the 3D view
// first and full width (beside two side panels it had no width left), then the timeline, the
// result and the parameters. Asserted on the layout's boxes in CSS pixels; screenshots go to SHOTS.
import { describe, it } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { gotoEmpty, readResult, runAndWait, SHOTS } from './lib.mjs';
import { appForFile } from './perFile.mjs';

let app;
let page;
appForFile({}, (a) => ({ page } = app = a));

const box = async (sel) => {
  const b = await page.locator(sel).first().boundingBox();
  assert.ok(b, `${sel} is not on the page`);
  return b;
};

/** The boxes overlap (by more than a pixel). */
function overlapping(a, b) {
  return a.x < b.x + b.width - 1 && b.x < a.x + a.width - 1 && a.y < b.y + b.height - 1 && b.y < a.y + a.height - 1;
}

for (const [width, height, name] of [[390, 844, 'phone'], [768, 1024, 'tablet']]) {
  describe(`a ${width} x ${height} window (${name})`, () => {
    it('shows the view full width, the timeline under it, then the result and parameters, with nothing cut or overlapping', async () => {
      await page.setViewportSize({ width, height });
      await gotoEmpty(page, app.server.url);
      await runAndWait(page, () => page.getByRole('button', { name: 'Patient 1 · ED' }).first().click());
      const r = await readResult(page);
      assert.ok(r.vertices > 500 && r.meanMm > 0 && r.meanMm < 1, `result ${JSON.stringify(r)}`);

      // Nothing runs off the side of the page.
      const scrollWidth = await page.evaluate(() => document.scrollingElement.scrollWidth);
      assert.ok(scrollWidth <= width, `page ${scrollWidth} px wide in a ${width} px window`);

      // The view takes the window's width and most of a screen's height.
      const view = await box('[data-testid=viewport-canvas]');
      assert.ok(view.width >= width - 2, `view ${view.width} px wide`);
      assert.ok(view.height >= Math.min(320, 0.5 * height), `view ${view.height} px high`);

      // The top bar's controls stand apart.
      const top = ['.brand', '.filebar label.button.primary', '.samples button', '[data-testid=surface-picker]', '[data-testid=privacy]'];
      const boxes = [];
      for (const sel of top) boxes.push([sel, await box(sel)]);
      for (let i = 0; i < boxes.length; i++) {
        assert.ok(boxes[i][1].x >= 0 && boxes[i][1].x + boxes[i][1].width <= width + 1, `${boxes[i][0]} outside the window: ${JSON.stringify(boxes[i][1])}`);
        for (let j = i + 1; j < boxes.length; j++) {
          assert.ok(!overlapping(boxes[i][1], boxes[j][1]), `${boxes[i][0]} overlaps ${boxes[j][0]}`);
        }
      }

      // Legends and view controls inside the view, apart.
      const legend = await box('[data-testid=legend-mesh]');
      const controls = await box('.view-controls');
      assert.ok(!overlapping(legend, controls), `legend ${JSON.stringify(legend)} under the view controls ${JSON.stringify(controls)}`);
      assert.ok(controls.x + controls.width <= view.x + view.width + 1, 'view controls cut at the right');

      // The timeline under the view, its scrubber usable; the result and parameters below it.
      const scrubber = await box('[data-testid=tl-scrubber]');
      assert.ok(scrubber.y >= view.y + view.height - 1, 'scrubber over the view');
      assert.ok(scrubber.width >= 0.8 * width - 40, `scrubber ${scrubber.width} px wide`);
      const result = await box('[data-testid=result]');
      assert.ok(result.y > scrubber.y && result.width >= 0.8 * width - 40, `result panel ${JSON.stringify(result)}`);
      const reset = await box('[data-testid=reset-params]');
      assert.ok(reset.y > result.y, 'parameters above the result');

      // The page scrolls to the parameters, and a slider there still drives a run.
      await page.locator('[data-testid=reset-params]').scrollIntoViewIfNeeded();
      const after = await box('[data-testid=reset-params]');
      assert.ok(after.y >= 0 && after.y + after.height <= height, `Reset to defaults not scrolled into view: ${JSON.stringify(after)}`);
      await page.evaluate(() => window.scrollTo(0, 0));
      await page.screenshot({ path: join(SHOTS, `narrow-${name}.png`) });
    });
  });
}
