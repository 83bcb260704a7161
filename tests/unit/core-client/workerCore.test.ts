import { describe, expect, it } from 'vitest';
import { stepsOf, transferablesOf, type FromWorker } from '../../../web/src/core-client/protocol';
import { WorkerCore, wasmErrorData, type SessionApi, type WasmApi } from '../../../web/src/core-client/workerCore';
import { stepReport } from './fakes';
import { DEFAULT_END_CAPS } from '../../../web/src/core-client/protocol';

/** A scripted session: `total` iterations, remesh at `remeshAt`, attractors re-sampled at `resampleAt`. */
class FakeSession implements SessionApi {
  iteration = -1;
  clock: { t: number };
  failAt: number | null = null;
  trapAt: number | null = null;
  /** The stop threshold is met at this iteration (null: the run does all `total`). */
  convergeAt: number | null = null;
  /** What result_json says about the alignment (the core sends null when the option is off). */
  alignment: unknown = null;
  /** What result_json says about the contours left out (absent: an older core). */
  setAside: unknown = undefined;
  /** The core's growth note once the tube exists (undefined: the run stays below the cap). */
  growthNote: string | undefined = undefined;
  constructor(clock: { t: number }, private total = 20, private remeshAt = [7], private resampleAt = [0, 12]) {
    this.clock = clock;
  }
  /** The frame argument of each load. */
  frames: (string | undefined)[] = [];
  load(fileName: string, bytes: Uint8Array, frame?: string): string {
    this.frames.push(frame);
    if (bytes.length === 0) throw JSON.stringify({ code: 'parse', message: 'line 1: empty file', line: 1 });
    return JSON.stringify({ fileName, surfaces: [], contours: [], landmarks: [], warnings: [] });
  }
  file_points(): Float32Array {
    return new Float32Array([1, 2, 3]);
  }
  start(_f: string, surface: string | null | undefined): void {
    if (surface === 'RV_EPI') throw JSON.stringify({ code: 'unknown_surface', message: 'no RV_EPI', available: ['LV_ENDO'] });
    this.iteration = -1;
  }
  step(): string {
    this.clock.t += 1; // every step costs 1 ms
    this.iteration += 1;
    if (this.iteration === this.failAt) throw JSON.stringify({ code: 'numerical', message: 'factorisation failed' });
    if (this.iteration === this.trapAt) throw new Error('unreachable');
    const i = this.iteration;
    const end = this.convergeAt ?? this.total;
    return JSON.stringify(
      stepReport(i, {
        total_iterations: this.total,
        topology_changed: i === 0 || this.remeshAt.includes(i),
        done: i >= end,
        phase: i >= end ? 'done' : i === 0 ? 'initial_tube' : 'deform',
      }),
    );
  }
  growth_note(): string | undefined {
    return this.iteration >= 0 ? this.growthNote : undefined;
  }
  attractors_changed(): boolean {
    return this.resampleAt.includes(this.iteration);
  }
  positions(): Float32Array {
    return new Float32Array([this.iteration, 0, 0]);
  }
  indices(): Uint32Array {
    return new Uint32Array([0, 1, this.iteration]);
  }
  attractors(): Float32Array {
    return new Float32Array([this.iteration, 1, 1]);
  }
  contour_points(): Float32Array {
    return new Float32Array(6);
  }
  point_distances(): Float32Array {
    return new Float32Array(2);
  }
  vertex_distances(): Float32Array {
    return new Float32Array(1);
  }
  set_aside_points(): Float32Array {
    return this.setAside ? new Float32Array([5, 0, 8, 4.4, 0.6, 8, 4.4, -0.6, 8]) : new Float32Array(0);
  }
  /** Each of those points' distance to the mesh (undefined: a core from before the read-out gave it). */
  set_aside_point_distances?: () => Float32Array = () => (this.setAside ? new Float32Array([8.1, 8.25, 8.4]) : new Float32Array(0));
  /** Echoes its arguments, so the test sees what the worker passed (options inside the params JSON). */
  session_json(fileName: string, surface: string | null | undefined, paramsJson: string, lids: string, appVersion: string): Uint8Array {
    if (fileName === 'missing.csv') throw JSON.stringify({ code: 'not_loaded', message: 'missing.csv has not been loaded' });
    return new TextEncoder().encode(JSON.stringify({ fileName, surface, params: JSON.parse(paramsJson), lids, appVersion }));
  }
  result_json(): string {
    return JSON.stringify({
      surface: null, contours: [], perContour: [], overall: { mean: 0.3, median: 0.2, p95: 0.8, max: 1, min: 0, count: 2 },
      volumeMl: 50, areaMm2: 7000, watertight: true, params: {}, lids: 'auto', version: '0.1.0',
      options: { smoothing_method: 'laplacian-affine', soften_conflicts: true },
      alignment: this.alignment,
      ...(this.alignment ? { contour_to_mesh_as_given: { mean: 0.6, median: 0.5, max: 2.1 } } : {}),
      ...(this.setAside !== undefined
        ? { set_aside: this.setAside, set_aside_contours: [{ id: 'speck', surface: 'LV_ENDO', kind: null, pieces: [{ closed: true, start: 0, count: 3 }] }] }
        : {}),
    });
  }
}

function setup(total = 20) {
  const clock = { t: 0 };
  const session = new FakeSession(clock, total);
  const out: FromWorker[] = [];
  const ticks: (() => void)[] = [];
  const wasm: WasmApi = {
    createSession: () => session,
    schemaJson: () => '[]',
    version: () => '9.9.9',
    takePanicMessage: () => 'panicked at src/x.rs:1: index out of bounds',
  };
  const core = new WorkerCore(wasm, (m) => out.push(m), {
    yieldToEventLoop: (cb) => ticks.push(cb),
    now: () => clock.t,
    sliceMs: 4,
  });
  const runTicks = (max = 1000) => {
    for (let i = 0; i < max && ticks.length > 0; i++) ticks.shift()!();
  };
  const frames = () => out.filter((m): m is Extract<FromWorker, { type: 'frame' }> => m.type === 'frame');
  return { core, session, out, runTicks, frames, ticks };
}

const runMsg = { type: 'run' as const, runId: 5, fileName: 'a.csv', surface: null, params: {}, lids: 'auto' as const };

describe('WorkerCore', () => {
  it('writes a session file with the options inside the params JSON; errors name the file', () => {
    const { core, out } = setup(5);
    const options = { smoothing_method: 'taubin' as const, soften_conflicts: false, align_slices: false, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true, drop_second_loops: false };
    core.handle({ type: 'session-export', reqId: 3, fileName: 'a.csv', surface: 'LV_ENDO', params: { beta: 0.2 }, lids: 'none', options, appVersion: '9.9.9' });
    const m = out.at(-1)!;
    expect(m.type).toBe('session-json');
    if (m.type !== 'session-json') return;
    expect(m.reqId).toBe(3);
    expect(JSON.parse(new TextDecoder().decode(m.bytes))).toEqual({
      fileName: 'a.csv', surface: 'LV_ENDO', params: { beta: 0.2, smoothing_method: 'taubin', soften_conflicts: false, align_slices: false, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true, drop_second_loops: false }, lids: 'none', appVersion: '9.9.9',
    });
    core.handle({ type: 'session-export', reqId: 4, fileName: 'missing.csv', surface: null, params: {}, lids: 'auto', appVersion: '9.9.9' });
    const e = out.at(-1)!;
    expect(e).toMatchObject({ type: 'error', reqId: 4, error: { code: 'not_loaded', file: 'missing.csv' } });
  });

  it('marks a run that met the stop threshold early as converged, and passes the alignment through', () => {
    const { core, session, out, runTicks } = setup(20);
    session.convergeAt = 13;
    session.alignment = { rounds: 9, residual_before_mm: 2.2, residual_after_mm: 0.7, groups: [{ kind: 'SAX', label: 'SAX 1', contour_ids: ['s1'], shift_mm: [1, 0, 0] }] };
    core.handle(runMsg);
    runTicks();
    const done = out.at(-1)!;
    if (done.type !== 'done') throw new Error(done.type);
    expect(done.result.iterations_done).toBe(13);
    expect(done.result.converged).toBe(true);
    expect(done.result.alignment?.residual_after_mm).toBe(0.7);
    expect(done.result.contour_to_mesh_as_given).toEqual({ mean: 0.6, median: 0.5, max: 2.1 });
    // An older core's options without align_slices read as the default (off).
    expect(done.result.options).toEqual({ smoothing_method: 'laplacian-affine', soften_conflicts: true, align_slices: false, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true, drop_second_loops: false });
    // An aligned run sends its (shifted) contours once, on its first frame; others never do.
    const aligned = setup(20);
    aligned.core.handle({ ...runMsg, options: { smoothing_method: 'laplacian-affine', soften_conflicts: true, align_slices: true, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true, drop_second_loops: false } });
    aligned.runTicks();
    const withContours = aligned.frames().filter((f) => f.runContours);
    expect(withContours.map((f) => f.seq)).toEqual([1]);
    expect(withContours[0].runContours?.points).toEqual(new Float32Array(6));
    expect(withContours[0].runContours?.contours).toEqual([]);
    const full = setup(20);
    full.core.handle(runMsg);
    full.runTicks();
    const all = full.out.at(-1)!;
    if (all.type !== 'done') throw new Error(all.type);
    expect([all.result.iterations_done, all.result.converged, all.result.alignment, all.result.contour_to_mesh_as_given]).toEqual([20, false, null, null]);
    expect(full.frames().some((f) => f.runContours)).toBe(false);
  });

  it('passes the contours left out through with their points and distances (transferred); an older core reads as none', () => {
    const { core, session, out, runTicks } = setup(5);
    session.setAside = [{ id: 'speck', line: 544, reason: 'speck', perimeter_mm: 2.9, next_id: 's6', next_perimeter_mm: 157 }];
    core.handle(runMsg);
    runTicks();
    const done = out.at(-1)!;
    if (done.type !== 'done') throw new Error(done.type);
    expect(done.result.set_aside).toEqual([{ id: 'speck', line: 544, reason: 'speck', perimeter_mm: 2.9, next_id: 's6', next_perimeter_mm: 157 }]);
    expect(done.result.set_aside_contours?.map((c) => c.id)).toEqual(['speck']);
    expect(Array.from(done.result.setAsidePoints ?? [])).toEqual([5, 0, 8, 4.4, 0.6, 8, 4.4, -0.6, 8].map(Math.fround));
    expect(transferablesOf(done)).toContain(done.result.setAsidePoints!.buffer);
    // Their distances to the mesh built without them, one per point, transferred too.
    expect(Array.from(done.result.setAsidePointDistances ?? [])).toEqual([8.1, 8.25, 8.4].map(Math.fround));
    expect(transferablesOf(done)).toContain(done.result.setAsidePointDistances!.buffer);
    expect(transferablesOf(done).length).toBe(new Set(transferablesOf(done)).size);
    // A core without them: the points still come, the result has no distances (the read-out names the contour only).
    const earlier = setup(5);
    earlier.session.setAside = session.setAside;
    earlier.session.set_aside_point_distances = undefined;
    earlier.core.handle(runMsg);
    earlier.runTicks();
    const e = earlier.out.at(-1)!;
    if (e.type !== 'done') throw new Error(e.type);
    expect(e.result.setAsidePoints?.length).toBe(9);
    expect('setAsidePointDistances' in e.result).toBe(false);
    const older = setup(5);
    older.core.handle(runMsg);
    older.runTicks();
    const d = older.out.at(-1)!;
    if (d.type !== 'done') throw new Error(d.type);
    expect([d.result.set_aside, d.result.set_aside_contours]).toEqual([[], []]);
  });

  it('keeps at most two frames unacknowledged, batches the steps meanwhile and always sends the final one', () => {
    const { core, out, runTicks, frames } = setup(20);
    core.handle(runMsg);
    runTicks();
    const f = frames();
    // Two frames while nobody acks, then the final frame with every step computed meanwhile.
    expect(f.map((x) => x.seq)).toEqual([1, 2, 3]);
    expect(f[0].report.iteration).toBe(0);
    expect(f[0].indices).toBeDefined();
    expect(f[0].attractors).toBeDefined();
    expect(f[0].earlier).toBeUndefined();
    expect(f[1].indices).toBeUndefined();
    const last = f[2];
    expect(last.report.done).toBe(true);
    expect(last.report.iteration).toBe(20);
    expect(last.earlier?.map((s) => s.report.iteration)).toEqual([2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19]);
    // The remesh at iteration 7 and the re-sampling at 12 travel with those steps (taken from the
    // session right after them), and the newest step names them too, so it can be drawn alone.
    const at = (it: number) => last.earlier!.find((s) => s.report.iteration === it)!;
    expect(at(7).indices).toEqual(new Uint32Array([0, 1, 7]));
    expect(at(12).attractors).toEqual(new Float32Array([12, 1, 1]));
    expect(last.earlier!.filter((s) => s.indices).map((s) => s.report.iteration)).toEqual([7]);
    expect(last.earlier!.filter((s) => s.attractors).map((s) => s.report.iteration)).toEqual([12]);
    expect(last.indices).toBe(at(7).indices);
    expect(last.attractors).toBe(at(12).attractors);
    const done = out.at(-1)!;
    expect(done.type).toBe('done');
    if (done.type === 'done') {
      expect(done.result.runId).toBe(5);
      expect(done.result.volumeMl).toBe(50);
      expect(done.result.seconds).toBeCloseTo(0.021, 6); // 21 steps at 1 ms
    }
  });

  it('the first frame carries the core\'s growth note, and no later frame does; none without one', () => {
    const { core, session, runTicks, frames } = setup(20);
    session.growthNote = 'each remesh keeps 1.12x the triangles';
    core.handle(runMsg);
    runTicks();
    const f = frames();
    expect(f[0].growthNote).toBe('each remesh keeps 1.12x the triangles');
    expect(f.slice(1).map((x) => x.growthNote)).toEqual(f.slice(1).map(() => undefined));
    const quiet = setup(20);
    quiet.core.handle(runMsg);
    quiet.runTicks();
    expect(quiet.frames().every((x) => x.growthNote === undefined)).toBe(true);
  });

  it('an ack releases the newest state at once', () => {
    const { core, runTicks, frames, ticks } = setup(100);
    core.handle(runMsg);
    ticks.shift()!(); // first slice: iterations 0..3, frames 1 and 2 sent
    expect(frames().map((x) => x.report.iteration)).toEqual([0, 1]);
    core.handle({ type: 'ack', runId: 5, seq: 1 });
    // One slot free: the steps computed meanwhile (iterations 2 and 3) go out immediately.
    expect(frames().map((x) => x.report.iteration)).toEqual([0, 1, 3]);
    expect(frames()[2].earlier?.map((s) => s.report.iteration)).toEqual([2]);
    core.handle({ type: 'ack', runId: 99, seq: 3 }); // another run's ack: ignored
    expect(frames()).toHaveLength(3);
    core.handle({ type: 'ack', runId: 5, seq: 3 });
    ticks.shift()!(); // iterations 4..7; two slots free -> frames for 4 and 5
    expect(frames().map((x) => x.report.iteration)).toEqual([0, 1, 3, 4, 5]);
    runTicks();
    expect(frames().at(-1)!.report.done).toBe(true);
    // Every step reached the receiver exactly once, in order.
    expect(frames().flatMap(stepsOf).map((s) => s.report.iteration)).toEqual(Array.from({ length: 101 }, (_, i) => i));
  });

  it('sends every step once, each with its own positions, whatever the acks (no ack, slow, prompt)', () => {
    for (const policy of ['never', 'every third', 'always'] as const) {
      const { core, runTicks, frames, ticks, out } = setup(60);
      core.handle(runMsg);
      let acked = 0;
      for (let i = 0; i < 1000 && ticks.length > 0; i++) {
        ticks.shift()!();
        const sent = frames();
        const ack = (seq: number) => core.handle({ type: 'ack', runId: 5, seq });
        if (policy === 'always' && sent.length > acked) ack((acked = sent.length));
        if (policy === 'every third' && i % 3 === 2 && sent.length > acked) ack((acked = sent.length));
      }
      runTicks();
      expect(out.at(-1)?.type).toBe('done');
      const steps = frames().flatMap(stepsOf);
      expect(steps.map((s) => s.report.iteration)).toEqual(Array.from({ length: 61 }, (_, i) => i));
      // Each step's positions are its own state (the fake writes the iteration), in a buffer of its own.
      expect(steps.map((s) => s.positions[0])).toEqual(steps.map((s) => s.report.iteration));
      expect(new Set(steps.map((s) => s.positions.buffer)).size).toBe(61);
      // Two topologies, taken at the first step and at the remesh (7), and two attractor sets (0
      // and 12); a frame's newest step may name the latest of them again (the same array).
      const firstWith = (key: 'indices' | 'attractors') => {
        const seen = new Map<unknown, number>();
        for (const s of steps) if (s[key] && !seen.has(s[key])) seen.set(s[key], s.report.iteration);
        return [...seen.values()];
      };
      expect(firstWith('indices')).toEqual([0, 7]);
      expect(firstWith('attractors')).toEqual([0, 12]);
      if (policy === 'never') expect(frames()).toHaveLength(3);
      else expect(frames().length).toBeGreaterThan(3);
    }
  });

  it('stops computing when the run is cancelled or replaced', () => {
    const { core, session, out, runTicks, ticks } = setup(1000);
    core.handle(runMsg);
    ticks.shift()!();
    const at = session.iteration;
    core.handle({ type: 'cancel', runId: 5 });
    // Acknowledged at once (the client replaces a worker that does not answer within its grace period).
    expect(out.at(-1)).toEqual({ type: 'cancelled', runId: 5 });
    runTicks();
    expect(session.iteration).toBe(at);
    expect(out.some((m) => m.type === 'done')).toBe(false);
    // A new run replaces the previous one.
    core.handle({ ...runMsg, runId: 6 });
    core.handle({ ...runMsg, runId: 7 });
    runTicks();
    const doneIds = out.filter((m) => m.type === 'done').map((m) => (m.type === 'done' ? m.result.runId : 0));
    expect(doneIds).toEqual([7]);
  });

  it('passes the time frame of a load to the core by its label; a frame that is no text (a foreign message) reads as none', () => {
    const { core, session, out } = setup(5);
    const bytes = () => new TextEncoder().encode('contour,x,y,z\n').buffer as ArrayBuffer;
    core.handle({ type: 'load', reqId: 1, fileName: 'a.csv', bytes: bytes() });
    core.handle({ type: 'load', reqId: 2, fileName: 'a.csv', bytes: bytes(), frame: '9' });
    core.handle({ type: 'load', reqId: 3, fileName: 'a.csv', bytes: bytes(), frame: 'ES' });
    for (const frame of [9, -1, null, { label: 'ES' }] as unknown as string[]) core.handle({ type: 'load', reqId: 4, fileName: 'a.csv', bytes: bytes(), frame });
    expect(session.frames).toEqual([undefined, '9', 'ES', undefined, undefined, undefined, undefined]);
    expect(out.filter((m) => m.type === 'loaded')).toHaveLength(7);
  });

  it('reports core errors as data and stays usable', () => {
    const { core, session, out, runTicks } = setup(10);
    core.handle({ type: 'load', reqId: 1, fileName: 'empty.csv', bytes: new ArrayBuffer(0) });
    expect(out.at(-1)).toEqual({
      type: 'error', reqId: 1, error: { code: 'parse', message: 'line 1: empty file', line: 1, file: 'empty.csv' },
    });
    core.handle({ ...runMsg, surface: 'RV_EPI' });
    expect(out.at(-1)).toMatchObject({ type: 'error', runId: 5, error: { code: 'unknown_surface', available: ['LV_ENDO'] } });
    session.failAt = 3;
    core.handle(runMsg);
    runTicks();
    expect(out.at(-1)).toMatchObject({ type: 'error', runId: 5, error: { code: 'numerical' } });
    session.failAt = null;
    core.handle({ ...runMsg, runId: 6 });
    runTicks();
    expect(out.at(-1)).toMatchObject({ type: 'done' });
    core.handle({ type: 'schema', reqId: 2 });
    expect(out.at(-1)).toEqual({ type: 'schema', reqId: 2, schema: [], version: '9.9.9' });
  });

  it('treats a trap as fatal and refuses further work', () => {
    const { core, session, out, runTicks } = setup(10);
    session.trapAt = 2;
    core.handle(runMsg);
    runTicks();
    const err = out.at(-1)!;
    expect(err).toMatchObject({ type: 'error', runId: 5, error: { code: 'worker_crashed' } });
    if (err.type === 'error') expect(err.error.message).toContain('index out of bounds');
    core.handle({ type: 'schema', reqId: 3 });
    expect(out.at(-1)).toMatchObject({ type: 'error', reqId: 3, error: { code: 'worker_crashed' } });
  });

  it('parses only JSON CoreErrorData strings as core errors', () => {
    expect(wasmErrorData('{"code":"parse","message":"m"}')).toEqual({ code: 'parse', message: 'm' });
    expect(wasmErrorData('{"nope":1}')).toBeNull();
    expect(wasmErrorData('{broken')).toBeNull();
    expect(wasmErrorData(new Error('x'))).toBeNull();
  });
});
