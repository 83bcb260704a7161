import { describe, expect, it } from 'vitest';
import {
  DEFAULT_END_CAPS,
  assertNever,
  isFatal,
  isFromWorker,
  isToWorker,
  frameOfSteps,
  mergeFrames,
  runIdOf,
  stepsOf,
  toCoreErrorData,
  transferablesOf,
  type Frame,
  type FromWorker,
  type StepFrame,
  type StepReport,
} from '../../../web/src/core-client/protocol';

const report: StepReport = {
  iteration: 3,
  total_iterations: 250,
  phase: 'deform',
  topology_changed: false,
  max_distance_mm: 4.5,
  mean_distance_mm: 1.25,
  vertices: 4,
  triangles: 4,
  attractors: 150,
  timings: { attractors_ms: 0, closest_ms: 0.1, solve_ms: 1, apply_ms: 0.2, remesh_ms: 0, total_ms: 1.3 },
  done: false,
};

function frame(seq: number, extra: Partial<Frame> = {}): Frame {
  return { runId: 1, seq, report, positions: new Float32Array([seq, 0, 0]), ...extra };
}

describe('protocol helpers', () => {
  it('lists each transferable buffer once', () => {
    const positions = new Float32Array(9);
    const indices = new Uint32Array(3);
    const msg: FromWorker = { type: 'frame', ...frame(1), positions, indices };
    const t = transferablesOf(msg);
    expect(t).toHaveLength(2);
    expect(t).toContain(positions.buffer);
    expect(t).toContain(indices.buffer);
    // Two views on one buffer are one transferable.
    const shared = new Float32Array(6);
    const done: FromWorker = {
      type: 'done',
      result: {
        runId: 1, surface: null, contours: [], contourPoints: shared, positions: shared.subarray(0, 3),
        indices: new Uint32Array(0), pointDistances: new Float32Array(2), vertexDistances: new Float32Array(1),
        perContour: [], overall: { mean: 0, median: 0, p95: 0, max: 0, min: 0, count: 0 }, volumeMl: 1,
        areaMm2: 1, watertight: true, seconds: 0.5, params: {}, lids: 'auto', options: { smoothing_method: 'laplacian-affine', soften_conflicts: true, align_slices: false, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true, drop_second_loops: false }, version: '0.1.0',
      },
    };
    // The empty index buffer is not listed (nothing to transfer), the shared one only once.
    expect(transferablesOf(done)).toHaveLength(3);
    expect(transferablesOf({ type: 'load', reqId: 1, fileName: 'a.csv', bytes: new ArrayBuffer(5) })).toHaveLength(1);
    expect(transferablesOf({ type: 'ack', runId: 1, seq: 2 })).toHaveLength(0);
  });

  it('merging a skipped frame keeps its topology and attractors', () => {
    const indices = new Uint32Array([0, 1, 2]);
    const attractors = new Float32Array([1, 2, 3]);
    const merged = mergeFrames(frame(1, { indices, attractors }), frame(2));
    expect(merged.seq).toBe(2);
    expect(merged.positions[0]).toBe(2);
    expect(merged.indices).toBe(indices);
    expect(merged.attractors).toBe(attractors);
    const newer = new Uint32Array([2, 1, 0]);
    expect(mergeFrames(frame(1, { indices }), frame(2, { indices: newer })).indices).toBe(newer);
    expect(mergeFrames(frame(1), frame(2)).indices).toBeUndefined();
  });
  it('a batched frame transfers every step\'s buffers and merges keep every step in order', () => {
    const step = (it: number, extra: Partial<StepFrame> = {}): StepFrame => ({ report: { ...report, iteration: it }, positions: new Float32Array([it, 0, 0]), ...extra });
    const topo = new Uint32Array([0, 1, 2]);
    const attr = new Float32Array([7, 7, 7]);
    const f = frameOfSteps(1, 1, [step(0, { indices: topo, attractors: attr }), step(1), step(2)]);
    expect(f.report.iteration).toBe(2);
    expect(f.positions[0]).toBe(2);
    expect(f.earlier?.map((x) => x.report.iteration)).toEqual([0, 1]);
    expect(f.indices).toBe(topo); // the newest names the topology it is drawn with
    expect(f.attractors).toBe(attr);
    expect(frameOfSteps(1, 2, [step(3)]).earlier).toBeUndefined();
    expect(() => frameOfSteps(1, 3, [])).toThrow();
    // 3 positions + indices + attractors, each once although the newest names indices and attractors again.
    const t = transferablesOf({ type: 'frame', ...f });
    expect(t).toHaveLength(5);
    for (const st of stepsOf(f)) expect(t).toContain(st.positions.buffer);
    const g = frameOfSteps(1, 2, [step(3), step(4)]);
    const merged = mergeFrames(f, g);
    expect(stepsOf(merged).map((x) => x.report.iteration)).toEqual([0, 1, 2, 3, 4]);
    expect(merged.seq).toBe(2);
    expect(merged.indices).toBe(topo);
    expect(stepsOf(merged)[0].indices).toBe(topo);
  });

  it('the growth note on a first frame survives a skipped frame', () => {
    expect(mergeFrames(frame(1, { growthNote: 'cap by about iteration 980' }), frame(2)).growthNote).toBe('cap by about iteration 980');
    expect(mergeFrames(frame(1), frame(2)).growthNote).toBeUndefined();
  });

  it('an aligned run\'s contours on its first frame survive a skipped frame and are transferred', () => {
    const runContours = { contours: [], points: new Float32Array([4, 5, 6]) };
    expect(mergeFrames(frame(1, { runContours }), frame(2)).runContours).toBe(runContours);
    const msg = { type: 'frame' as const, ...frame(1, { runContours }) };
    expect(transferablesOf(msg)).toContain(runContours.points.buffer);
    expect(transferablesOf(msg)).toHaveLength(2);
  });

  it('normalises thrown values into CoreErrorData', () => {
    expect(toCoreErrorData('{"code":"parse","message":"line 3: bad","line":3}', 'a.csv')).toEqual({
      code: 'parse', message: 'line 3: bad', line: 3, file: 'a.csv',
    });
    expect(toCoreErrorData(new Error('boom'))).toEqual({ code: 'internal', message: 'boom' });
    expect(toCoreErrorData({ code: 'x', message: 'y', file: 'b' }, 'a')).toEqual({ code: 'x', message: 'y', file: 'b' });
    expect(toCoreErrorData(42).code).toBe('internal');
    expect(isFatal({ code: 'worker_crashed', message: '' })).toBe(true);
    expect(isFatal({ code: 'parse', message: '' })).toBe(false);
  });

  it('recognises messages and their runs', () => {
    expect(isFromWorker({ type: 'ready' })).toBe(true);
    expect(isFromWorker({ type: 'load' })).toBe(false);
    expect(isFromWorker(null)).toBe(false);
    expect(isToWorker({ type: 'cancel', runId: 3 })).toBe(true);
    expect(isToWorker({ type: 'frame' })).toBe(false);
    expect(runIdOf({ type: 'frame', ...frame(4) })).toBe(1);
    expect(runIdOf({ type: 'error', runId: 7, error: { code: 'a', message: 'b' } })).toBe(7);
    expect(runIdOf({ type: 'ready' })).toBeUndefined();
  });

  it('assertNever throws on an unexpected message', () => {
    expect(() => assertNever({ type: 'bogus' } as never)).toThrow(/bogus/);
  });
});
