// The recorded steps of a run (app/history.ts): every step while it fits the byte budget, shared
// topology and attractors counted once, even thinning (every 2nd, 4th, ... step) past the budget,
// and a plot series that keeps every step's distances.
import { describe, expect, it } from 'vitest';
import { FrameHistory, HISTORY_BUDGET_BYTES, type HistoryEntry } from '../../web/src/app/history';
import type { StepReport } from '../../web/src/core-client/protocol';

function report(iteration: number, vertices = 10): StepReport {
  return {
    iteration, total_iterations: 250, phase: 'deform', topology_changed: false,
    max_distance_mm: 10 / (iteration + 1), mean_distance_mm: 2 / (iteration + 1), vertices, triangles: 16,
    attractors: 150, timings: { attractors_ms: 0, closest_ms: 0, solve_ms: 0, apply_ms: 0, remesh_ms: 0, total_ms: 1 }, done: false,
  };
}

const sharedIndices = new Uint32Array(48);

function entry(iteration: number, vertices = 10, indices = sharedIndices, attractors: Float32Array | null = null): HistoryEntry {
  return { report: report(iteration, vertices), positions: new Float32Array(vertices * 3), indices, attractors };
}

const iterations = (h: FrameHistory) => Array.from({ length: h.length }, (_, i) => h.at(i)!.report.iteration);

describe('frame history', () => {
  it('keeps every step of a default run (251 steps of 3000 vertices) within the default budget', () => {
    const h = new FrameHistory();
    let dropped = 0;
    for (let i = 0; i <= 250; i++) dropped += h.push(entry(i, 3000));
    expect(dropped).toBe(0);
    expect(h.length).toBe(251);
    expect(iterations(h)).toEqual(Array.from({ length: 251 }, (_, i) => i));
    expect(h.stride).toBe(1);
    expect(h.series()).toHaveLength(251);
    // Also the longest run the app allows (2000 iterations) of a 3000-vertex mesh: 72 MB.
    const long = new FrameHistory();
    for (let i = 0; i <= 2000; i++) long.push(entry(i, 3000));
    expect(long.length).toBe(2001);
    expect(long.byteLength).toBeLessThan(HISTORY_BUDGET_BYTES);
  });

  it('shares indices and attractors between steps and counts each array once', () => {
    const h = new FrameHistory();
    const topoA = new Uint32Array(300);
    const topoB = new Uint32Array(600);
    const attr = new Float32Array(90);
    for (let i = 0; i < 10; i++) h.push(entry(i, 100, i < 5 ? topoA : topoB, attr));
    // 10 x 1200 bytes of positions + 1200 + 2400 bytes of indices + 360 bytes of attractors.
    expect(h.byteLength).toBe(10 * 1200 + 1200 + 2400 + 360);
    expect(h.at(0)!.indices).toBe(h.at(4)!.indices);
    expect(h.at(5)!.indices).toBe(topoB);
    h.clear();
    expect(h.byteLength).toBe(0);
    expect(h.length).toBe(0);
    expect(h.series()).toHaveLength(0);
  });

  it('past its budget keeps every 2nd step, then every 4th, always the first and the newest', () => {
    // Room for 10 steps of 100 vertices (1200 bytes each) besides the shared indices (192 bytes).
    const h = new FrameHistory(10 * 1200 + 192);
    for (let i = 0; i < 10; i++) expect(h.push(entry(i, 100))).toBe(0);
    expect(h.stride).toBe(1);
    // The 11th step does not fit: every 2nd step of the run stays, and the newest.
    expect(h.push(entry(10, 100))).toBe(5);
    expect(h.stride).toBe(2);
    expect(iterations(h)).toEqual([0, 2, 4, 6, 8, 10]);
    // The newest step is kept off the stride until the next one comes.
    h.push(entry(11, 100));
    expect(iterations(h)).toEqual([0, 2, 4, 6, 8, 10, 11]);
    h.push(entry(12, 100));
    expect(iterations(h)).toEqual([0, 2, 4, 6, 8, 10, 12]);
    // Step 19 makes 11 kept steps (0, 2, ..., 18, 19): every 4th stays.
    for (let i = 13; i <= 36; i++) h.push(entry(i, 100));
    expect(h.stride).toBe(4);
    expect(iterations(h)).toEqual([0, 4, 8, 12, 16, 20, 24, 28, 32, 36]);
    expect(h.byteLength).toBe(10 * 1200 + 192);
    h.push(entry(37, 100));
    expect(h.stride).toBe(8);
    expect(iterations(h)).toEqual([0, 8, 16, 24, 32, 37]);
    expect(h.byteLength).toBeLessThanOrEqual(h.maxBytes);
    // Evenly spaced: every kept step but the newest is on the stride.
    for (const it of iterations(h).slice(0, -1)) expect(it % h.stride).toBe(0);
    // The plot still has every step.
    expect(h.series().map((p) => p.iteration)).toEqual(Array.from({ length: 38 }, (_, i) => i));
    expect(h.series()[7]).toEqual({ iteration: 7, max: 10 / 8, mean: 2 / 8 });
  });

  it('frees a topology once no kept step uses it', () => {
    const h = new FrameHistory(6 * 1200 + 2 * 400);
    const topo = () => new Uint32Array(100); // a remesh at every step: 400 bytes each
    for (let i = 0; i < 30; i++) h.push(entry(i, 100, topo()));
    expect(h.byteLength).toBe(h.length * (1200 + 400));
    expect(h.byteLength).toBeLessThanOrEqual(h.maxBytes);
  });

  it('finds the kept step nearest an iteration', () => {
    const h = new FrameHistory();
    for (const i of [0, 5, 10, 20]) h.push(entry(i));
    expect(h.indexOfIteration(12)).toBe(2);
    expect(h.indexOfIteration(15)).toBe(2); // a tie goes to the earlier step
    expect(h.indexOfIteration(16)).toBe(3);
    expect(h.indexOfIteration(100)).toBe(3);
    expect(h.indexOfIteration(-4)).toBe(0);
    expect(h.indexOfIteration(5)).toBe(1);
    h.clear();
    expect(h.indexOfIteration(3)).toBe(-1);
  });

  it('also thins to a cap on the number of kept steps', () => {
    const h = new FrameHistory(Infinity, 8);
    for (let i = 0; i <= 250; i++) h.push(entry(i));
    expect(h.length).toBeLessThanOrEqual(8);
    expect(h.at(0)?.report.iteration).toBe(0);
    expect(h.last()?.report.iteration).toBe(250);
  });
});
