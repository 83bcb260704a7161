// Browser benchmark: time from dropping the SurFCo example on the page to "done" (status line),
// animation included, in headless Chromium against the built dist/. The example is read from
// shared/ at bench time (its GPL licence forbids shipping it). Prints every run and the median of 5.
//   usage: npm run build && node bench/browser-bench.mjs [runs=5]
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { launch, requireDist, sharedDir, startPreview } from '../tests/e2e/lib.mjs';

const RUNS = Number(process.argv[2] || 5);
const BUDGET_MS = 2000;

requireDist();
const csv = readFileSync(join(sharedDir(), 'data', 'contours', 'surfco-example.csv'), 'utf8');
const server = await startPreview();
const browser = await launch();
const times = [];
try {
  const page = await browser.context.newPage();
  page.on('pageerror', (e) => console.error('pageerror:', e.message));
  for (let run = 0; run <= RUNS; run++) {
    await page.goto(server.url);
    // Wait until the core is up (schema loaded), as a user would before dropping a file.
    await page.waitForFunction(() => document.querySelector('[data-testid=status]')?.textContent === 'no file loaded', null, { timeout: 30000 });
    const ms = await page.evaluate(async (text) => {
      const status = document.querySelector('[data-testid=status]');
      const done = new Promise((resolve, reject) => {
        const check = () => {
          const s = status?.textContent ?? '';
          if (s === 'done') resolve(performance.now());
          else if (s.startsWith('error')) reject(new Error(s));
        };
        new MutationObserver(check).observe(status, { childList: true, characterData: true, subtree: true });
      });
      const dt = new DataTransfer();
      dt.items.add(new File([text], 'surfco-example.csv', { type: 'text/csv' }));
      const t0 = performance.now();
      for (const type of ['dragenter', 'dragover', 'drop']) {
        document.body.dispatchEvent(new DragEvent(type, { dataTransfer: dt, bubbles: true, cancelable: true }));
      }
      return (await done) - t0;
    }, csv);
    const r = await page.locator('[data-testid=result]').evaluate((el) => `${el.dataset.vertices} vertices, mean ${Number(el.dataset.meanMm).toFixed(3)} mm, max ${Number(el.dataset.maxMm).toFixed(3)} mm`);
    console.log(`${run === 0 ? 'warm-up' : `run ${run}`}: ${ms.toFixed(0)} ms drop -> done (${r})`);
    if (run > 0) times.push(ms);
  }
} finally {
  await browser.close();
  server.stop();
}
times.sort((a, b) => a - b);
const median = times[Math.floor(times.length / 2)];
console.log(`median of ${times.length}: ${median.toFixed(0)} ms (budget ${BUDGET_MS} ms: ${median <= BUDGET_MS ? 'met' : 'NOT met'})`);
