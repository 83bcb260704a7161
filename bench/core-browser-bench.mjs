#!/usr/bin/env node
// Benchmark of the core path in headless chromium: CoreClient + module worker + wasm (no
// rendering), the SurFCo example at default parameters. Median over N runs after one warm-up of
// the time from handing the file bytes to the client until `done` resolves, the time to the first
// frame, and the number of frames handed to the display. The product target (issue 3) is done
// within 2 s of the drop, animation included.
//
//   node bench/core-browser-bench.mjs [runs=7]
import { readFileSync } from 'node:fs';
import { SURFCO } from '../tests/node/helpers.mjs';
import { openHarness } from '../tests/browser/lib.mjs';

const runs = Math.max(1, Number(process.argv[2] ?? 7));
const median = (xs) => {
  const s = [...xs].sort((a, b) => a - b);
  const m = s.length >> 1;
  return s.length % 2 ? s[m] : (s[m - 1] + s[m]) / 2;
};

const h = await openHarness();
try {
  const text = readFileSync(SURFCO(), 'utf8');
  const once = () => h.page.evaluate(([t]) => window.harness.run('surfco.csv', t, null, {}), [text]);
  await once(); // warm-up
  const samples = [];
  for (let i = 0; i < runs; i++) samples.push(await once());
  const version = h.page.context().browser()?.version() ?? '?';
  console.log(`heartmesh core in chromium ${version}: surfco-example.csv, defaults, ${runs} runs after 1 warm-up`);
  console.log(`${samples[0].vertices} vertices, contour-to-mesh mean ${samples[0].mean.toFixed(3)} mm`);
  console.log('| measure | median | min | max |');
  console.log('|---|---:|---:|---:|');
  for (const [label, key, unit] of [
    ['load + reconstruct until done', 'msToDone', 'ms'],
    ['first frame', 'msToFirstFrame', 'ms'],
    ['longest gap between frames', 'maxFrameGapMs', 'ms'],
    ['frames handed to the display', 'frames', ''],
  ]) {
    const xs = samples.map((s) => s[key]);
    const f = (v) => (unit ? `${v.toFixed(0)} ${unit}` : String(v));
    console.log(`| ${label} | ${f(median(xs))} | ${f(Math.min(...xs))} | ${f(Math.max(...xs))} |`);
  }
} finally {
  await h.close();
}
