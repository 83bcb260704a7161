import { beforeEach, describe, expect, it } from 'vitest';
import { CoreClient } from '../../../web/src/core-client/CoreClient';
import { frameOfSteps, stepsOf, type CoreErrorData, type Frame, type LoadedFile, type RunResult, type StepFrame } from '../../../web/src/core-client/protocol';
import { FakeWorker, ManualScheduler, flush, stepReport } from './fakes';
import { DEFAULT_END_CAPS } from '../../../web/src/core-client/protocol';

const loaded: LoadedFile = {
  fileName: 'a.csv', surfaces: ['LV_ENDO'], contours: [], points: new Float32Array(3), landmarks: [], warnings: [],
};

function result(runId: number): RunResult {
  return {
    runId, surface: null, contours: [], contourPoints: new Float32Array(3), positions: new Float32Array(9),
    indices: new Uint32Array([0, 1, 2]), pointDistances: new Float32Array(1), vertexDistances: new Float32Array(3),
    perContour: [], overall: { mean: 0.5, median: 0.4, p95: 1, max: 1.2, min: 0, count: 1 }, volumeMl: 80,
    areaMm2: 9000, watertight: true, seconds: 0.8, params: { beta: 0.1 }, lids: 'auto', options: { smoothing_method: 'laplacian-affine', soften_conflicts: true, align_slices: false, end_caps: DEFAULT_END_CAPS }, version: '0.1.0',
  };
}

async function readyClient(sched: ManualScheduler, onWorkerCrash?: (e: CoreErrorData) => void) {
  const opts = { createWorker: () => new FakeWorker(), schedule: sched.schedule, onWorkerCrash };
  const created = CoreClient.create(opts);
  const worker = FakeWorker.instances.at(-1)!;
  worker.emit({ type: 'ready' });
  return { client: await created, worker };
}

async function loadFile(client: CoreClient, worker: FakeWorker, name = 'a.csv') {
  const bytes = new TextEncoder().encode('contour,x,y,z\n').buffer as ArrayBuffer;
  const p = client.load(name, bytes);
  const req = worker.of('load').at(-1)!;
  worker.emit({ type: 'loaded', reqId: req.reqId, file: { ...loaded, fileName: name } });
  await p;
  return bytes;
}

function frameMsg(runId: number, seq: number, extra: Partial<Frame> = {}) {
  return {
    type: 'frame' as const, runId, seq, report: stepReport(seq - 1),
    positions: new Float32Array([seq, seq, seq]), ...extra,
  };
}

beforeEach(() => {
  FakeWorker.instances = [];
});

describe('CoreClient', () => {
  it('resolves create() on ready and caches the schema', async () => {
    const sched = new ManualScheduler();
    const { client, worker } = await readyClient(sched);
    const p = client.schema();
    const req = worker.of('schema')[0];
    const schema = [{ name: 'beta', default: 0.1, min: 0.01, max: 1, log: false, integer: false, unit: '', help: '' }];
    worker.emit({ type: 'schema', reqId: req.reqId, schema, version: '0.1.0' });
    expect(await p).toEqual({ schema, version: '0.1.0' });
    expect(await client.schema()).toEqual({ schema, version: '0.1.0' });
    expect(worker.of('schema')).toHaveLength(1);
  });

  it('sends a copy of the file bytes and rejects bad files with the error data', async () => {
    const { client, worker } = await readyClient(new ManualScheduler());
    const bytes = new Uint8Array([1, 2, 3]).buffer;
    const p = client.load('bad.csv', bytes);
    const req = worker.of('load')[0];
    expect(req.bytes).not.toBe(bytes);
    expect(new Uint8Array(req.bytes)).toEqual(new Uint8Array([1, 2, 3]));
    expect(worker.transfers.at(-1)).toEqual([req.bytes]);
    const error = { code: 'parse', message: 'line 2: bad number', line: 2, file: 'bad.csv' };
    worker.emit({ type: 'error', reqId: req.reqId, error });
    await expect(p).rejects.toEqual(error);
    // A file that failed to load cannot be run.
    const run = client.run({ fileName: 'bad.csv', surface: null, params: {}, lids: 'auto' }, () => {});
    await expect(run.done).rejects.toMatchObject({ code: 'not_loaded' });
  });

  it('hands over at most one frame per display frame, merging skipped ones, and acks it', async () => {
    const sched = new ManualScheduler();
    const { client, worker } = await readyClient(sched);
    await loadFile(client, worker);
    const seen: Frame[] = [];
    const run = client.run({ fileName: 'a.csv', surface: null, params: { beta: 0.2 }, lids: 'auto' }, (f) => seen.push(f));
    const req = worker.of('run')[0];
    expect(req).toMatchObject({ runId: run.runId, fileName: 'a.csv', params: { beta: 0.2 }, lids: 'auto', surface: null });

    const indices = new Uint32Array([0, 1, 2]);
    const attractors = new Float32Array([5, 5, 5]);
    worker.emit(frameMsg(run.runId, 1, { indices, attractors }));
    worker.emit(frameMsg(run.runId, 2));
    worker.emit(frameMsg(run.runId, 3));
    expect(seen).toHaveLength(0);
    expect(sched.pending).toBe(1);
    sched.tick();
    expect(seen).toHaveLength(1);
    expect(seen[0].seq).toBe(3);
    expect(seen[0].positions[0]).toBe(3);
    expect(seen[0].indices).toBe(indices); // topology of the skipped frame is not lost
    expect(seen[0].attractors).toBe(attractors);
    // ... nor are its steps: the receiver records them all, oldest first.
    expect(stepsOf(seen[0]).map((st) => st.report.iteration)).toEqual([0, 1, 2]);
    expect(stepsOf(seen[0])[0].indices).toBe(indices);
    expect(worker.of('ack')).toEqual([{ type: 'ack', runId: run.runId, seq: 3 }]);

    worker.emit(frameMsg(run.runId, 4));
    sched.tick();
    expect(seen.map((f) => f.seq)).toEqual([3, 4]);
    expect(seen[1].indices).toBeUndefined();
    sched.tick(); // nothing new: no call
    expect(seen).toHaveLength(2);

    // The final frame is delivered before done resolves.
    worker.emit(frameMsg(run.runId, 5));
    worker.emit({ type: 'done', result: result(run.runId) });
    let resolved = false;
    void run.done.then(() => (resolved = true));
    await flush();
    expect(resolved).toBe(false);
    sched.tick();
    expect(seen.map((f) => f.seq)).toEqual([3, 4, 5]);
    const r = await run.done;
    expect(r.volumeMl).toBe(80);
    expect(worker.of('ack').map((a) => a.seq)).toEqual([3, 4, 5]);
  });

  it('hands every step of batched frames over once and in order, the newest as the frame itself', async () => {
    const sched = new ManualScheduler();
    const { client, worker } = await readyClient(sched);
    await loadFile(client, worker);
    const seen: Frame[] = [];
    const run = client.run({ fileName: 'a.csv', surface: null, params: {}, lids: 'auto' }, (f) => seen.push(f));
    const step = (it: number, extra: Partial<StepFrame> = {}): StepFrame => ({ report: stepReport(it), positions: new Float32Array([it, 0, 0]), ...extra });
    const remesh = new Uint32Array([0, 2, 1]);
    let next = 0;
    let seq = 0;
    /** A frame of `n` steps, batched as the worker does (earlier ones, then the newest). */
    const emit = (n: number) => {
      const steps = Array.from({ length: n }, (_, i) => step(next + i, next + i === 7 ? { indices: remesh } : {}));
      next += n;
      worker.emit({ type: 'frame', ...frameOfSteps(run.runId, ++seq, steps) });
    };
    // 40 steps in 6 frames over 3 display slots: the display is behind (two frames per slot).
    emit(1);
    emit(6);
    sched.tick();
    emit(9);
    emit(4);
    emit(8);
    sched.tick();
    emit(12);
    sched.tick();
    expect(seen).toHaveLength(3);
    const steps = seen.flatMap(stepsOf);
    expect(steps.map((st) => st.report.iteration)).toEqual(Array.from({ length: 40 }, (_, i) => i));
    expect(steps.map((st) => st.positions[0])).toEqual(Array.from({ length: 40 }, (_, i) => i));
    // Each call's own fields are its newest step, with the topology a skipped frame brought.
    expect(seen.map((f) => f.report.iteration)).toEqual([6, 27, 39]);
    expect(seen[1].indices).toBe(remesh);
    // Step 7 brought it; the newest of each frame (and merge) after it names it again (the same array).
    expect(steps.filter((st) => st.indices === remesh).map((st) => st.report.iteration)).toEqual([7, 15, 19, 27]);
    expect(worker.of('ack').map((a) => a.seq)).toEqual([2, 5, 6]);
  });

  it('a new run cancels the old one and its late frames are dropped', async () => {
    const sched = new ManualScheduler();
    const { client, worker } = await readyClient(sched);
    await loadFile(client, worker);
    const seenA: Frame[] = [];
    const seenB: Frame[] = [];
    const a = client.run({ fileName: 'a.csv', surface: null, params: {}, lids: 'auto' }, (f) => seenA.push(f));
    worker.emit(frameMsg(a.runId, 1));
    const b = client.run({ fileName: 'a.csv', surface: 'LV_ENDO', params: {}, lids: 'none' }, (f) => seenB.push(f));
    await expect(a.done).rejects.toMatchObject({ code: 'cancelled' });
    expect(worker.of('cancel')).toEqual([{ type: 'cancel', runId: a.runId }]);
    worker.emit(frameMsg(a.runId, 2));
    worker.emit({ type: 'done', result: result(a.runId) });
    worker.emit(frameMsg(b.runId, 1));
    sched.tick();
    expect(seenA).toHaveLength(0);
    expect(seenB.map((f) => f.runId)).toEqual([b.runId]);
    // Explicit cancel.
    b.cancel();
    await expect(b.done).rejects.toMatchObject({ code: 'cancelled' });
    expect(worker.of('cancel').map((c) => c.runId)).toEqual([a.runId, b.runId]);
    b.cancel(); // idempotent
    expect(worker.of('cancel')).toHaveLength(2);
  });

  it('rejects a run with the core error the worker reports', async () => {
    const { client, worker } = await readyClient(new ManualScheduler());
    await loadFile(client, worker);
    const run = client.run({ fileName: 'a.csv', surface: null, params: {}, lids: 'auto' }, () => {});
    const error = { code: 'surface_required', message: 'choose one', available: ['LV_ENDO', 'LV_EPI'] };
    worker.emit({ type: 'error', runId: run.runId, error });
    await expect(run.done).rejects.toEqual(error);
    expect(worker.terminated).toBe(false);
  });

  it('recovers from a worker crash with a new worker and re-sends loaded files', async () => {
    const crashes: CoreErrorData[] = [];
    const { client, worker } = await readyClient(new ManualScheduler(), (e) => crashes.push(e));
    const bytes = await loadFile(client, worker);
    const run = client.run({ fileName: 'a.csv', surface: null, params: {}, lids: 'auto' }, () => {});
    const schema = client.schema();
    worker.crash('RuntimeError: unreachable');
    await expect(run.done).rejects.toMatchObject({ code: 'worker_crashed' });
    await expect(schema).rejects.toMatchObject({ code: 'worker_crashed' });
    expect(worker.terminated).toBe(true);
    expect(crashes).toHaveLength(1);
    expect(crashes[0].message).toContain('unreachable');

    const run2 = client.run({ fileName: 'a.csv', surface: null, params: {}, lids: 'auto' }, () => {});
    expect(FakeWorker.instances).toHaveLength(2);
    const w2 = FakeWorker.instances[1];
    expect(w2.sent.map((m) => m.type)).toEqual(['load', 'run']);
    expect(new Uint8Array(w2.of('load')[0].bytes)).toEqual(new Uint8Array(bytes));
    w2.emit({ type: 'ready' });
    w2.emit({ type: 'loaded', reqId: w2.of('load')[0].reqId, file: loaded });
    w2.emit({ type: 'done', result: result(run2.runId) });
    expect((await run2.done).runId).toBe(run2.runId);
    // Messages of the dead worker are ignored.
    worker.emit({ type: 'done', result: result(run.runId) });
  });

  it('treats a worker_crashed error message as fatal', async () => {
    const { client, worker } = await readyClient(new ManualScheduler());
    await loadFile(client, worker);
    const run = client.run({ fileName: 'a.csv', surface: null, params: {}, lids: 'auto' }, () => {});
    worker.emit({ type: 'error', runId: run.runId, error: { code: 'worker_crashed', message: 'panicked at index out of bounds' } });
    await expect(run.done).rejects.toMatchObject({ code: 'worker_crashed', message: expect.stringContaining('panicked') });
    expect(worker.terminated).toBe(true);
  });

  it('rejects create() when the worker cannot start', async () => {
    const p = CoreClient.create({ createWorker: () => new FakeWorker(), schedule: new ManualScheduler().schedule });
    FakeWorker.instances[0].emit({ type: 'error', error: { code: 'worker_crashed', message: 'no wasm' } });
    await expect(p).rejects.toMatchObject({ code: 'worker_crashed', message: 'no wasm' });
  });

  it('dispose() terminates the worker and rejects what is pending', async () => {
    const { client, worker } = await readyClient(new ManualScheduler());
    await loadFile(client, worker);
    const run = client.run({ fileName: 'a.csv', surface: null, params: {}, lids: 'auto' }, () => {});
    client.dispose();
    await expect(run.done).rejects.toMatchObject({ code: 'disposed' });
    expect(worker.terminated).toBe(true);
    await expect(client.load('b.csv', new ArrayBuffer(1))).rejects.toMatchObject({ code: 'disposed' });
  });
});
