// The run display (app/runDisplay.ts) records every step a frame carries and draws only the step at
// the cursor: live, the newest, however many steps came since the last animation frame. Stepping
// back walks every iteration; a paused display does not redraw the mesh while the scrubber's range
// and the plot grow; a run past the history's budget says which steps it kept.
import { afterEach, beforeEach, describe, expect, it, vi } from 'vitest';
import { RunDisplay } from '../../web/src/app/runDisplay';
import type { Parts } from '../../web/src/app/parts';
import { frameOfSteps, type Frame, type StepFrame, type StepReport } from '../../web/src/core-client/protocol';

function report(iteration: number, total = 250): StepReport {
  return {
    iteration, total_iterations: total, phase: iteration === 0 ? 'initial_tube' : 'deform', topology_changed: iteration % 20 === 0,
    max_distance_mm: 10 / (iteration + 1), mean_distance_mm: 2 / (iteration + 1), vertices: 4, triangles: 4, attractors: 3,
    timings: { attractors_ms: 0, closest_ms: 0, solve_ms: 0, apply_ms: 0, remesh_ms: 0, total_ms: 0 }, done: iteration === total,
  };
}

/** A stand-in whose every method records its calls. */
function recorder() {
  const calls: Record<string, unknown[][]> = {};
  return new Proxy({} as Record<string, unknown>, {
    get: (_t, key: string) => (key === 'calls' ? calls : (...args: unknown[]) => void (calls[key] ??= []).push(args)),
  }) as unknown as { calls: Record<string, unknown[][]> };
}

let parts: Record<string, { calls: Record<string, unknown[][]> }>;
let layers: Record<string, { calls: Record<string, unknown[][]> }>;
let display: RunDisplay;
/** One topology per 20 iterations (the remeshes), as the worker sends them. */
const topologies = new Map<number, Uint32Array>();

function step(it: number): StepFrame {
  const s: StepFrame = { report: report(it), positions: new Float32Array([it, 0, 0, 0, it, 0, 0, 0, it, it, it, it]) };
  if (it % 20 === 0) {
    const t = new Uint32Array([0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, 2]);
    topologies.set(it, t);
    s.indices = t;
  }
  if (it === 0) s.attractors = new Float32Array(9);
  return s;
}

let seq = 0;
/** A frame of the steps `from..to` (inclusive), batched as the worker sends them. */
function frame(from: number, to: number): Frame {
  return frameOfSteps(1, ++seq, Array.from({ length: to - from + 1 }, (_, i) => step(from + i)));
}

const meshUpdates = () => (layers.meshLayer.calls.update ?? []) as [Float32Array, Uint32Array][];
const lastTimeline = () => parts.timeline.calls.update?.at(-1)?.[0] as { length: number; cursor: number; iteration: number | null; stride: number };
const lastPlot = () => parts.plot.calls.set?.at(-1) as [{ iteration: number }[], number, number | null];
let now = 0;
const animationFrame = () => (display as unknown as { display(now: number): void }).display((now += 16));

function makeDisplay(budget?: number) {
  layers = {};
  const viewer = new Proxy({} as Record<string, unknown>, {
    get: (_t, key: string) => (key.endsWith('Layer') ? (layers[key] ??= recorder()) : () => undefined),
  });
  parts = {
    legend: recorder(), meshLegend: recorder(), timeline: recorder(), status: recorder(), plot: recorder(), result: recorder(),
    exports: recorder(), view: recorder(),
  };
  display = new RunDisplay({ ...parts, viewer } as unknown as Parts, { currentFile: () => null, surface: () => null, iterations: () => 250 }, budget);
}

beforeEach(() => {
  vi.stubGlobal('requestAnimationFrame', () => 0);
  seq = 0;
  makeDisplay();
});

afterEach(() => {
  vi.unstubAllGlobals();
});

describe('run display', () => {
  it('records every step of a frame, draws only the newest, and walks every iteration back', () => {
    display.frame(frame(0, 0));
    display.frame(frame(1, 29)); // the display was behind: 29 steps in one frame
    expect(display.historyLength).toBe(30);
    animationFrame();
    // One mesh drawn for 30 steps: the newest.
    expect(meshUpdates()).toHaveLength(1);
    expect(meshUpdates()[0][0][0]).toBe(29);
    expect(meshUpdates()[0][1]).toBe(topologies.get(20));
    expect(lastTimeline()).toMatchObject({ length: 30, cursor: 29, iteration: 29, stride: 1 });
    expect(lastPlot()[0]).toHaveLength(30);
    // 221 more steps over three frames before the next animation frame: still one draw, the newest.
    display.frame(frame(30, 99));
    display.frame(frame(100, 200));
    display.frame(frame(201, 250));
    animationFrame();
    expect(meshUpdates()).toHaveLength(2);
    expect(meshUpdates()[1][0][0]).toBe(250);
    expect(lastTimeline()).toMatchObject({ length: 251, cursor: 250, iteration: 250 });
    expect(lastPlot()[0].map((p) => p.iteration)).toEqual(Array.from({ length: 251 }, (_, i) => i));
    expect(animationFrame()).toBeUndefined();
    expect(meshUpdates()).toHaveLength(2); // nothing new: nothing drawn
    // Step back one at a time: every iteration 249..0 is on screen in turn, with its topology.
    const seen: number[] = [];
    for (let k = 0; k < 250; k++) {
      display.step(-1);
      animationFrame();
      const [positions, indices] = meshUpdates().at(-1)!;
      expect(indices).toBe(topologies.get(Math.floor(positions[0] / 20) * 20));
      seen.push(lastTimeline().iteration!);
    }
    expect(seen).toEqual(Array.from({ length: 250 }, (_, i) => 249 - i));
    display.step(-1); // at the first step: stays
    animationFrame();
    expect(lastTimeline().iteration).toBe(0);
  });

  it('paused, new steps grow the scrubber and the plot without redrawing the mesh', () => {
    display.frame(frame(0, 10));
    animationFrame();
    display.step(-3); // pauses on iteration 7
    animationFrame();
    const draws = meshUpdates().length;
    expect(lastTimeline()).toMatchObject({ length: 11, iteration: 7 });
    display.frame(frame(11, 40));
    animationFrame();
    expect(meshUpdates()).toHaveLength(draws);
    expect(lastTimeline()).toMatchObject({ length: 41, cursor: 7, iteration: 7 });
    expect(lastPlot()[0]).toHaveLength(41);
    expect(lastPlot()[2]).toBe(7); // the plot's marker stays on the step on screen
  });

  it('a run past the budget keeps every 2nd (4th, ...) step and says so; the plot keeps every step', () => {
    // Room for 40 steps of 48 bytes besides the topologies and attractors.
    makeDisplay(40 * 48 + 13 * 48 + 36);
    display.frame(frame(0, 30));
    animationFrame();
    expect(lastTimeline()).toMatchObject({ length: 31, stride: 1 });
    display.frame(frame(31, 250));
    animationFrame();
    const t = lastTimeline();
    expect(t.stride).toBeGreaterThan(1);
    expect(t.length).toBeLessThanOrEqual(40);
    expect(t.iteration).toBe(250);
    expect(lastPlot()[0]).toHaveLength(251);
    // The first kept step is iteration 0, the next `stride` later.
    display.seek(1);
    animationFrame();
    expect(lastTimeline().iteration).toBe(t.stride);
  });
});
