#!/usr/bin/env node
// Benchmark of the wasm build (web/pkg) under Node: median wall time of a full default
// reconstruction of the SurFCo example (start -> done, after one warm-up run), and per-phase
// totals summed from the step timings. With the native CLI built, its time is shown for scale.
//
//   node bench/wasm-bench.mjs [runs=7] [contours.csv] [--surface NAME]
import { execFileSync } from 'node:child_process';
import { existsSync, mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { CLI, SURFCO, loadWasm, reconstruct } from '../tests/node/helpers.mjs';

const args = process.argv.slice(2);
const surfaceAt = args.indexOf('--surface');
const surface = surfaceAt >= 0 ? args.splice(surfaceAt, 2)[1] : null;
const runs = Math.max(1, Number(args.find((a) => /^\d+$/.test(a)) ?? 7));
const input = args.find((a) => !/^\d+$/.test(a)) ?? SURFCO();

const median = (xs) => {
  const s = [...xs].sort((a, b) => a - b);
  const m = s.length >> 1;
  return s.length % 2 ? s[m] : (s[m - 1] + s[m]) / 2;
};
const PHASES = ['attractors_ms', 'closest_ms', 'solve_ms', 'apply_ms', 'remesh_ms', 'total_ms'];

const wasm = await loadWasm();
const one = () => {
  const cpu0 = process.cpuUsage();
  const { session, reports, ms } = reconstruct(wasm, input, { surface });
  const cpu = process.cpuUsage(cpu0);
  const cpuMs = (cpu.user + cpu.system) / 1000;
  const totals = Object.fromEntries(PHASES.map((p) => [p, reports.reduce((s, r) => s + r.timings[p], 0)]));
  const last = reports.at(-1);
  const result = JSON.parse(session.result_json());
  session.free();
  return { ms, cpuMs, totals, steps: reports.length, vertices: last.vertices, triangles: last.triangles, mean: result.overall.mean };
};

one(); // warm-up: the engine optimises the hot functions during the first calls
const samples = [];
for (let i = 0; i < runs; i++) samples.push(one());

const name = input.split('/').at(-1) + (surface ? ` (${surface})` : '');
const rows = [
  ['full reconstruction (wall)', median(samples.map((s) => s.ms))],
  // CPU time of the process: steadier than the wall clock on a loaded machine.
  ['full reconstruction (CPU)', median(samples.map((s) => s.cpuMs))],
  ...PHASES.map((p) => [`  sum of step ${p.replace('_ms', '')}`, median(samples.map((s) => s.totals[p]))]),
];
const first = samples[0];
console.log(`heartmesh wasm benchmark: ${name}, default parameters, ${runs} runs after 1 warm-up (Node ${process.version})`);
console.log(`${first.steps} steps, final mesh ${first.vertices} vertices / ${first.triangles} triangles, contour-to-mesh mean ${first.mean.toFixed(3)} mm`);
console.log('| measure | median ms | min ms | max ms |');
console.log('|---|---:|---:|---:|');
for (const [label, value] of rows) {
  const key = label.trim().startsWith('full') ? null : PHASES.find((p) => label.includes(p.replace('_ms', '')));
  const cpuRow = label.includes('(CPU)');
  const xs = samples.map((s) => (key ? s.totals[key] : cpuRow ? s.cpuMs : s.ms));
  console.log(`| ${label} | ${value.toFixed(1)} | ${Math.min(...xs).toFixed(1)} | ${Math.max(...xs).toFixed(1)} |`);
}

if (existsSync(CLI)) {
  const tmp = mkdtempSync(join(tmpdir(), 'heartmesh-bench-'));
  try {
    const times = [];
    for (let i = 0; i < 3; i++) {
      const report = join(tmp, 'r.json');
      const extra = surface ? ['--surface', surface] : [];
      execFileSync(CLI, ['reconstruct', input, '-o', join(tmp, 'm.obj'), '--report', report, '--quiet', ...extra]);
      times.push(JSON.parse(readFileSync(report, 'utf8')).seconds * 1000);
    }
    console.log(`| native CLI (median of 3, for scale) | ${median(times).toFixed(1)} | ${Math.min(...times).toFixed(1)} | ${Math.max(...times).toFixed(1)} |`);
  } finally {
    rmSync(tmp, { recursive: true, force: true });
  }
}
