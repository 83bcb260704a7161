// Breath-hold alignment through the worker's logic with the real wasm (session 9): the option
// reaches the core inside the params JSON, the result carries the alignment (residual falls) and
// the distance to the contours as given, the run's contour points are the file's moved by their
// group's shift, the worker marks early convergence, and a session keeps the option.
import { beforeAll, describe, expect, it } from 'vitest';
import { DEFAULT_OPTIONS, type FromWorker, type LoadedFile, type RunResult } from '../../web/src/core-client/protocol';
import { PATIENT1_ED, SURFCO, loadWasm, readBytes } from './helpers.mjs';
import { askingCore } from './askCore';

type Wasm = typeof import('../../web/pkg/heartmesh_wasm.js');
let wasm: Wasm;

beforeAll(async () => {
  wasm = await loadWasm();
});

/** Frames seen, for checking what the first frame of an aligned run carries. */
const frames: Extract<FromWorker, { type: 'frame' }>[] = [];

function makeCore() {
  return askingCore(wasm, (m) => frames.push(m)).ask;
}

const NAME = 'patient1-ED.csv';

async function load(ask: ReturnType<typeof makeCore>, fileName: string, bytes: Uint8Array): Promise<LoadedFile> {
  const m = await ask({ type: 'load', reqId: 1, fileName, bytes: bytes.slice().buffer as ArrayBuffer }, 'loaded', 'error');
  if (m.type === 'error') throw new Error(m.error.message);
  return m.file;
}

async function run(ask: ReturnType<typeof makeCore>, runId: number, align: boolean, params = {}): Promise<RunResult> {
  const options = { ...DEFAULT_OPTIONS, align_slices: align };
  const m = await ask({ type: 'run', runId, fileName: NAME, surface: 'LV_ENDO', params, lids: 'auto', options }, 'done', 'error');
  if (m.type === 'error') throw new Error(m.error.message);
  return m.result;
}

/** xyz triples of a contour's pieces. */
function pointsOf(points: Float32Array, c: LoadedFile['contours'][number]): number[][] {
  return c.pieces.flatMap((p) => Array.from({ length: p.count }, (_, k) => [0, 1, 2].map((j) => points[(p.start + k) * 3 + j])));
}

describe('breath-hold alignment through the worker', () => {
  it('aligned run: residual falls, contours move by their shifts, as-given distance reported', async () => {
    const ask = makeCore();
    const file = await load(ask, NAME, readBytes(PATIENT1_ED()));
    const off = await run(ask, 1, false);
    expect(off.alignment).toBeNull();
    expect(off.contour_to_mesh_as_given ?? null).toBeNull();
    expect(off.options.align_slices).toBe(false);
    const on = await run(ask, 2, true);
    expect(on.options.align_slices).toBe(true);
    const a = on.alignment;
    if (!a) throw new Error('no alignment in the result');
    expect(a.residual_after_mm).toBeLessThan(a.residual_before_mm);
    // Every run reports how far apart the images cross (the alignment's starting residual, 1.88 mm
    // here); off, that is enough to suggest the alignment; on, nothing to suggest.
    expect(off.crossing_residual_mm).toBe(a.residual_before_mm);
    expect(off.crossing_residual_mm).toBeGreaterThan(1.5);
    expect(off.suggest_alignment).toBe(true);
    expect(on.suggest_alignment).toBe(false);
    // Each slice's part of its shift along the long axis is in the result too (views: 0).
    expect(a.groups.filter((g) => g.kind === 'LAX').every((g) => g.through_plane_mm === 0)).toBe(true);
    expect(Math.max(...a.groups.map((g) => Math.abs(g.through_plane_mm ?? 0)))).toBeGreaterThan(0.3);
    expect(a.groups.some((g) => g.kind === 'SAX')).toBe(true);
    expect(a.groups.some((g) => g.kind === 'LAX')).toBe(true);
    // The distance to the contours as given (shown beside the usual figure when the core sends it):
    // the mesh follows the shifted contours, so it is the larger of the two.
    const given = on.contour_to_mesh_as_given;
    if (given) expect(given.mean).toBeGreaterThan(on.overall.mean);
    // Every point of the run's contours is the file's point plus its group's shift.
    let worst = 0;
    let checked = 0;
    for (const g of a.groups) {
      for (const id of g.contour_ids) {
        const runC = on.contours.find((c) => c.id === id);
        const fileC = file.contours.filter((c) => c.id === id && c.surface === runC?.surface);
        if (!runC || fileC.length === 0) continue;
        const q = fileC.flatMap((c) => pointsOf(file.points, c));
        for (const p of pointsOf(on.contourPoints, runC)) {
          let best = Infinity;
          for (const r of q) best = Math.min(best, Math.hypot(p[0] - g.shift_mm[0] - r[0], p[1] - g.shift_mm[1] - r[1], p[2] - g.shift_mm[2] - r[2]));
          worst = Math.max(worst, best);
          checked++;
        }
      }
    }
    expect(checked).toBe(on.overall.count);
    expect(worst).toBeLessThan(1e-3);
    // The first frame already carried these shifted contours (the display shows them while it runs).
    const first = frames.filter((f) => f.runId === 2 && f.runContours);
    expect(first.map((f) => f.seq)).toEqual([1]);
    expect(first[0].runContours?.points).toEqual(on.contourPoints);
    expect(first[0].runContours?.contours.map((c) => c.id)).toEqual(on.contours.map((c) => c.id));
    expect(frames.some((f) => f.runId === 1 && f.runContours)).toBe(false);
  });

  it('a session keeps align_slices and brings it back on load', async () => {
    const ask = makeCore();
    await load(ask, NAME, readBytes(PATIENT1_ED()));
    const options = { ...DEFAULT_OPTIONS, align_slices: true };
    const written = await ask({ type: 'session-export', reqId: 2, fileName: NAME, surface: 'LV_ENDO', params: {}, lids: 'auto', options, appVersion: '9.9.9' }, 'session-json', 'error');
    if (written.type !== 'session-json') throw new Error(written.error.message);
    expect(JSON.parse(new TextDecoder().decode(written.bytes)).parameters.align_slices).toBe(true);
    const back = await load(ask, 'saved.json', written.bytes);
    expect(back.session?.options).toEqual(options);
  });

  it('the worker marks a run that met the stop threshold before its last iteration (SurFCo)', async () => {
    const ask = makeCore();
    await load(ask, 'surfco.csv', readBytes(SURFCO()));
    const m = await ask({ type: 'run', runId: 3, fileName: 'surfco.csv', surface: null, params: {}, lids: 'auto', options: DEFAULT_OPTIONS }, 'done', 'error');
    if (m.type === 'error') throw new Error(m.error.message);
    expect(m.result.converged).toBe(true);
    expect(m.result.iterations_done).toBeGreaterThan(0);
    expect(m.result.iterations_done).toBeLessThan(m.result.params.iterations);
    // With every iteration forced (no stop threshold reached in 40), it is not converged.
    const short = await ask({ type: 'run', runId: 4, fileName: 'surfco.csv', surface: null, params: { iterations: 40 }, lids: 'auto', options: DEFAULT_OPTIONS }, 'done', 'error');
    if (short.type === 'error') throw new Error(short.error.message);
    expect([short.result.iterations_done, short.result.converged]).toEqual([40, false]);
  });
});
