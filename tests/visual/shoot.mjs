// TEST-ONLY: screenshots of the page driven by the synthetic core, for looking at the layout.
// usage: node tests/visual/shoot.mjs   (writes test-results/harness-*.png; synthetic data, not for docs)
import { createServer } from 'vite';
import { join } from 'node:path';
import { mkdirSync } from 'node:fs';
import { ROOT, launch } from '../e2e/lib.mjs';

const OUT = join(ROOT, 'test-results');
mkdirSync(OUT, { recursive: true });

const server = await createServer({ configFile: join(ROOT, 'tests', 'visual', 'vite.config.mjs'), server: { port: 5199, host: '127.0.0.1' }, logLevel: 'error' });
await server.listen();
const { context, close } = await launch();
const page = await context.newPage();
page.on('pageerror', (e) => console.log('pageerror:', e.message));
page.on('console', (m) => { if (m.type() === 'error') console.log('console error:', m.text()); });
try {
  await page.goto('http://127.0.0.1:5199/harness.html?sample=patient1-ED');
  await page.waitForSelector('[data-testid=status]:has-text("done")', { timeout: 30000 });
  await page.waitForTimeout(300);
  await page.screenshot({ path: join(OUT, 'harness-done.png') });
  await page.mouse.move(640, 380);
  await page.waitForTimeout(200);
  await page.screenshot({ path: join(OUT, 'harness-hover.png') });
  await page.click('[data-testid=tl-first]');
  await page.click('[data-testid=view-wireframe]');
  await page.waitForTimeout(200);
  await page.screenshot({ path: join(OUT, 'harness-first-wire.png') });
  console.log('status:', await page.textContent('[data-testid=status]'));
  console.log('url:', page.url());
} finally {
  await close();
  await server.close();
}
