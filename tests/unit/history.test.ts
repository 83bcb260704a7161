import { describe, expect, it } from 'vitest';
import { FrameHistory, type HistoryEntry } from '../../web/src/app/history';
import type { StepReport } from '../../web/src/core-client/protocol';

function entry(iteration: number, vertices = 10): HistoryEntry {
  const report: StepReport = {
    iteration, total_iterations: 250, phase: 'deform', topology_changed: false,
    max_distance_mm: 10 / (iteration + 1), mean_distance_mm: 2 / (iteration + 1), vertices, triangles: 16,
    attractors: 150, timings: { attractors_ms: 0, closest_ms: 0, solve_ms: 0, apply_ms: 0, remesh_ms: 0, total_ms: 1 }, done: false,
  };
  return { report, positions: new Float32Array(vertices * 3), indices: new Uint32Array(48), attractors: null };
}

describe('frame history', () => {
  it('keeps everything while under the bound', () => {
    const h = new FrameHistory(10);
    for (let i = 0; i < 10; i++) expect(h.push(entry(i))).toBe(0);
    expect(h.length).toBe(10);
  });
  it('thins old frames but keeps first and latest when full', () => {
    const h = new FrameHistory(8);
    for (let i = 0; i <= 250; i++) h.push(entry(i));
    expect(h.length).toBeLessThanOrEqual(8);
    expect(h.length).toBeGreaterThanOrEqual(4);
    expect(h.at(0)?.report.iteration).toBe(0);
    expect(h.last()?.report.iteration).toBe(250);
    const its = h.series().map((s) => s.iteration);
    expect([...its].sort((a, b) => a - b)).toEqual(its); // still in order
  });
  it('respects a byte bound', () => {
    const h = new FrameHistory(1000, 12 * 100 * 5); // 5 frames of 100 vertices
    for (let i = 0; i < 50; i++) h.push(entry(i, 100));
    expect(h.length).toBeLessThanOrEqual(5);
    expect(h.last()?.report.iteration).toBe(49);
  });
  it('finds the frame nearest an iteration', () => {
    const h = new FrameHistory();
    for (const i of [0, 5, 10, 20]) h.push(entry(i));
    expect(h.indexOfIteration(12)).toBe(2);
    expect(h.indexOfIteration(100)).toBe(3);
    h.clear();
    expect(h.indexOfIteration(3)).toBe(-1);
  });
});
