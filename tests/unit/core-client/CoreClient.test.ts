import { afterEach, beforeEach, describe, expect, it, vi } from 'vitest';
import { CANCEL_GRACE_MS, CoreClient } from '../../../web/src/core-client/CoreClient';
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
    areaMm2: 9000, watertight: true, seconds: 0.8, params: { beta: 0.1 }, lids: 'auto', options: { smoothing_method: 'laplacian-affine', soften_conflicts: true, align_slices: false, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true, drop_second_loops: false }, version: '0.1.0',
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

  it('reads a file again as a time frame, and a new worker is sent that frame; a frame that fails leaves the one before', async () => {
    const { client, worker } = await readyClient(new ManualScheduler());
    const bytes = await loadFile(client, worker);
    const nine = client.loadFrame('a.csv', '9');
    const req = worker.of('load').at(-1)!;
    expect(req.frame).toBe('9');
    expect(new Uint8Array(req.bytes)).toEqual(new Uint8Array(bytes));
    worker.emit({ type: 'loaded', reqId: req.reqId, file: loaded });
    await nine;
    // Frame ES cannot be read: the worker keeps frame 9, and so does what a new worker is sent.
    const three = client.loadFrame('a.csv', 'ES');
    worker.emit({ type: 'error', reqId: worker.of('load').at(-1)!.reqId, error: { code: 'parse', message: 'line 9: bad number', line: 9 } });
    await expect(three).rejects.toMatchObject({ code: 'parse' });
    worker.crash();
    client.run({ fileName: 'a.csv', surface: null, params: {}, lids: 'auto' }, () => {}).done.catch(() => undefined);
    const w2 = FakeWorker.instances[1];
    expect(w2.of('load')[0].frame).toBe('9');
    // The file opened again is read as it comes (no frame), as is the first-of-each choice.
    await loadFile(client, w2);
    expect(w2.of('load').at(-1)!.frame).toBeUndefined();
    void client.loadFrame('a.csv', null);
    expect('frame' in w2.of('load').at(-1)!).toBe(false);
    await expect(client.loadFrame('b.csv', '1')).rejects.toMatchObject({ code: 'not_loaded' });
  });

  it('a stack loaded with long-axis views: every reload (another frame, a new worker) carries them; views added merge by name; one that fails leaves those before', async () => {
    const { client, worker } = await readyClient(new ManualScheduler());
    const enc = (t: string) => new TextEncoder().encode(t).buffer as ArrayBuffer;
    const text = (b: ArrayBuffer) => new TextDecoder().decode(b);
    const viewsOf = (m: { views?: { name: string; bytes: ArrayBuffer }[] }) => (m.views ?? []).map((v) => `${v.name}=${text(v.bytes)}`);
    const la = enc('2ch');
    const p = client.load('sa.nii.gz', enc('stack'), undefined, [{ name: 'la_2ch.nii.gz', bytes: la }, { name: 'la_4ch.nii.gz', bytes: enc('4ch') }]);
    const req = worker.of('load').at(-1)!;
    expect(viewsOf(req)).toEqual(['la_2ch.nii.gz=2ch', 'la_4ch.nii.gz=4ch']);
    // Copies, transferred with the stack's.
    expect(req.views?.[0].bytes).not.toBe(la);
    expect(worker.transfers.at(-1)).toEqual([req.bytes, ...(req.views ?? []).map((v) => v.bytes)]);
    worker.emit({ type: 'loaded', reqId: req.reqId, file: { ...loaded, fileName: 'sa.nii.gz' } });
    await p;
    expect(client.viewsOf('sa.nii.gz')).toEqual(['la_2ch.nii.gz', 'la_4ch.nii.gz']);

    // The Frame picker's reload: the same views.
    void client.loadFrame('sa.nii.gz', '1');
    expect(viewsOf(worker.of('load').at(-1)!)).toEqual(['la_2ch.nii.gz=2ch', 'la_4ch.nii.gz=4ch']);
    worker.emit({ type: 'loaded', reqId: worker.of('load').at(-1)!.reqId, file: loaded });

    // Views added: a new 4ch replaces the older, a 3ch joins (in name order); read as frame 1 still.
    const added = client.addViews('sa.nii.gz', [{ name: 'la_4ch.nii.gz', bytes: enc('4ch new') }, { name: 'la_3ch.nii.gz', bytes: enc('3ch') }]);
    const addReq = worker.of('load').at(-1)!;
    expect(text(addReq.bytes)).toBe('stack');
    expect(addReq.frame).toBe('1');
    expect(viewsOf(addReq)).toEqual(['la_2ch.nii.gz=2ch', 'la_3ch.nii.gz=3ch', 'la_4ch.nii.gz=4ch new']);
    worker.emit({ type: 'loaded', reqId: addReq.reqId, file: loaded });
    await added;
    expect(client.viewsOf('sa.nii.gz')).toEqual(['la_2ch.nii.gz', 'la_3ch.nii.gz', 'la_4ch.nii.gz']);

    // A damaged view: refused, the views before kept.
    const bad = client.addViews('sa.nii.gz', [{ name: 'cut.nii.gz', bytes: enc('x') }]);
    worker.emit({ type: 'error', reqId: worker.of('load').at(-1)!.reqId, error: { code: 'parse', message: 'cut.nii.gz: the gzip data is damaged', file: 'sa.nii.gz' } });
    await expect(bad).rejects.toMatchObject({ message: 'cut.nii.gz: the gzip data is damaged' });
    expect(client.viewsOf('sa.nii.gz')).toEqual(['la_2ch.nii.gz', 'la_3ch.nii.gz', 'la_4ch.nii.gz']);

    // A new worker is sent the stack with its views, as frame 1.
    worker.crash();
    client.run({ fileName: 'sa.nii.gz', surface: null, params: {}, lids: 'auto' }, () => {}).done.catch(() => undefined);
    const w2 = FakeWorker.instances[1];
    expect(w2.of('load')[0].frame).toBe('1');
    expect(viewsOf(w2.of('load')[0])).toEqual(['la_2ch.nii.gz=2ch', 'la_3ch.nii.gz=3ch', 'la_4ch.nii.gz=4ch new']);

    // Opened again alone: its views are forgotten.
    w2.emit({ type: 'ready' });
    const again = client.load('sa.nii.gz', enc('stack'));
    expect('views' in w2.of('load').at(-1)!).toBe(false);
    w2.emit({ type: 'loaded', reqId: w2.of('load').at(-1)!.reqId, file: loaded });
    await again;
    expect(client.viewsOf('sa.nii.gz')).toEqual([]);
    await expect(client.addViews('b.nii', [])).rejects.toMatchObject({ code: 'not_loaded' });
  });

  it('asks the worker for a label map\'s grid', async () => {
    const { client, worker } = await readyClient(new ManualScheduler());
    const bytes = new Uint8Array([0x1f, 0x8b, 1]).buffer;
    const p = client.labelMapGrid(bytes);
    const req = worker.of('grid')[0];
    expect(req.bytes).not.toBe(bytes);
    expect(new Uint8Array(req.bytes)).toEqual(new Uint8Array([0x1f, 0x8b, 1]));
    worker.emit({ type: 'grid', reqId: req.reqId, grid: { dims: [102, 88, 1], frames: 1 } });
    expect(await p).toEqual({ dims: [102, 88, 1], frames: 1 });
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

  describe('a worker stuck in a long step', () => {
    afterEach(() => vi.useRealTimers());

    /** A client whose worker is inside a step that never returns: it sees no message any more. */
    async function stuckClient() {
      vi.useFakeTimers();
      const crashes: CoreErrorData[] = [];
      let restarts = 0;
      const created = CoreClient.create({ createWorker: () => new FakeWorker(), schedule: new ManualScheduler().schedule, onWorkerCrash: (e) => crashes.push(e), onWorkerRestart: () => restarts++ });
      const worker = FakeWorker.instances[0];
      worker.emit({ type: 'ready' });
      const client = await created;
      const bytes = await loadFile(client, worker);
      const a = client.run({ fileName: 'a.csv', surface: null, params: {}, lids: 'auto' }, () => {});
      a.done.catch(() => undefined); // cancelled in most of these tests
      worker.emit(frameMsg(a.runId, 1)); // step 0 came back; step 1 never will
      worker.acksCancels = false;
      return { client, worker, bytes, a, crashes, restarts: () => restarts };
    }

    it('is replaced when a cancel goes unacknowledged for the grace period; the next run starts on a new worker, no crash', async () => {
      const { client, worker, bytes, a, crashes, restarts } = await stuckClient();
      const b = client.run({ fileName: 'a.csv', surface: null, params: { beta: 0.3 }, lids: 'auto' }, () => {});
      await expect(a.done).rejects.toMatchObject({ code: 'cancelled' }); // at once, as before
      expect(worker.of('cancel')).toEqual([{ type: 'cancel', runId: a.runId }]);
      expect(worker.of('run').at(-1)?.runId).toBe(b.runId); // queued behind the step
      await vi.advanceTimersByTimeAsync(CANCEL_GRACE_MS - 10);
      expect(FakeWorker.instances).toHaveLength(1);
      expect(worker.terminated).toBe(false);
      await vi.advanceTimersByTimeAsync(20);
      // Terminated on purpose: a new worker, nothing rejected, nobody told of a crash.
      expect(worker.terminated).toBe(true);
      expect(FakeWorker.instances).toHaveLength(2);
      expect(crashes).toEqual([]);
      expect(restarts()).toBe(1);
      const w2 = FakeWorker.instances[1];
      // The file first (the new worker has none), then the run that was waiting, with its settings.
      expect(w2.sent.map((m) => m.type)).toEqual(['load', 'run']);
      expect(new Uint8Array(w2.of('load')[0].bytes)).toEqual(new Uint8Array(bytes));
      expect(w2.of('run')[0]).toMatchObject({ runId: b.runId, params: { beta: 0.3 } });
      w2.emit({ type: 'ready' });
      w2.emit({ type: 'loaded', reqId: w2.of('load')[0].reqId, file: loaded });
      w2.emit({ type: 'done', result: result(b.runId) });
      expect((await b.done).runId).toBe(b.runId);
      // The stuck worker's late output is ignored.
      worker.emit(frameMsg(a.runId, 2));
      worker.emit({ type: 'cancelled', runId: a.runId });
      expect(FakeWorker.instances).toHaveLength(2);
    });

    it('after Stop, a file opened next is read by the new worker instead of waiting for the step', async () => {
      const { client, worker, a, crashes } = await stuckClient();
      a.cancel();
      await expect(a.done).rejects.toMatchObject({ code: 'cancelled' });
      const other = new TextEncoder().encode('contour,x,y,z\nb,1,2,3\n').buffer as ArrayBuffer;
      const p = client.load('b.csv', other);
      expect(worker.of('load').at(-1)?.fileName).toBe('b.csv');
      await vi.advanceTimersByTimeAsync(CANCEL_GRACE_MS + 1);
      const w2 = FakeWorker.instances[1];
      expect(w2.sent.map((m) => (m.type === 'load' ? m.fileName : m.type))).toEqual(['b.csv']);
      expect(new Uint8Array(w2.of('load')[0].bytes)).toEqual(new Uint8Array(other));
      w2.emit({ type: 'ready' });
      w2.emit({ type: 'loaded', reqId: w2.of('load')[0].reqId, file: { ...loaded, fileName: 'b.csv' } });
      expect((await p).fileName).toBe('b.csv');
      expect(crashes).toEqual([]);
      // Both files still run: a.csv is re-sent to the new worker when asked for.
      const run = client.run({ fileName: 'a.csv', surface: null, params: {}, lids: 'auto' }, () => {});
      expect(w2.sent.slice(-2).map((m) => (m.type === 'load' ? m.fileName : m.type))).toEqual(['a.csv', 'run']);
      expect(w2.of('run')[0].runId).toBe(run.runId);
    });

    it('a phases batch waiting behind the step goes to the new worker after every phase\'s file', async () => {
      const { client, worker, a, crashes } = await stuckClient();
      await loadFile(client, worker, 'b.csv');
      a.cancel();
      const batch = client.measurePhases({ kind: 'phases', phases: [{ name: 'ED', file: 'a.csv' }, { name: 'ES', file: 'b.csv' }], params: {}, lids: 'auto' }, () => undefined);
      batch.done.catch(() => undefined);
      expect(worker.of('lab-batch')).toHaveLength(1); // queued behind the step
      await vi.advanceTimersByTimeAsync(CANCEL_GRACE_MS + 1);
      expect(worker.terminated).toBe(true);
      const w2 = FakeWorker.instances.at(-1)!;
      // Both phases' files first (the new worker has none), then the batch: none fails as "not loaded".
      expect(w2.sent.map((m) => (m.type === 'load' ? m.fileName : m.type)).filter((t) => t !== 'lab-restore')).toEqual(['a.csv', 'b.csv', 'lab-batch']);
      expect(crashes).toEqual([]);
    });

    it('a cancel acknowledged in time keeps the worker', async () => {
      const { client, worker, a } = await stuckClient();
      worker.acksCancels = true;
      a.cancel();
      await vi.advanceTimersByTimeAsync(CANCEL_GRACE_MS * 5);
      expect(worker.terminated).toBe(false);
      expect(FakeWorker.instances).toHaveLength(1);
      void client;
    });

    it('a file waiting behind a long step calls back (the caller cancels, the new worker reads it); one the worker is reading does not', async () => {
      const { client, worker, a, crashes } = await stuckClient();
      const bytes = new TextEncoder().encode('contour,x,y,z\nb,1,2,3\n').buffer as ArrayBuffer;
      let called = 0;
      const p = client.load('b.csv', bytes, () => {
        called++;
        a.cancel(); // what the app does: Stop
      });
      await vi.advanceTimersByTimeAsync(CANCEL_GRACE_MS / 2);
      expect(called).toBe(0); // the step has not lasted long yet
      // performance.now is not faked: pretend the silence is long by a frame whose step took seconds.
      worker.emit(frameMsg(a.runId, 2, { report: stepReport(1, { timings: { attractors_ms: 0, closest_ms: 0, solve_ms: 4000, apply_ms: 0, remesh_ms: 0, total_ms: 4100 } }) }));
      await vi.advanceTimersByTimeAsync(CANCEL_GRACE_MS);
      expect(called).toBe(1);
      await vi.advanceTimersByTimeAsync(CANCEL_GRACE_MS * 2);
      const w2 = FakeWorker.instances.at(-1)!;
      expect(w2).not.toBe(worker);
      expect(w2.of('load').map((m) => m.fileName)).toContain('b.csv');
      w2.emit({ type: 'ready' });
      for (const m of w2.of('load')) w2.emit({ type: 'loaded', reqId: m.reqId, file: { ...loaded, fileName: m.fileName } });
      expect((await p).fileName).toBe('b.csv');
      expect(called).toBe(1);
      expect(crashes).toEqual([]);
    });

    it('a worker that says it is reading a file is not inside a step, and is not replaced meanwhile', async () => {
      const { client, worker, a } = await stuckClient();
      const bytes = new TextEncoder().encode('contour,x,y,z\n').buffer as ArrayBuffer;
      let called = 0;
      const p = client.load('big.csv', bytes, () => called++);
      worker.emit({ type: 'started', reqId: worker.of('load').at(-1)!.reqId });
      expect(client.isInLongStep(performance.now() + 10000)).toBe(false);
      a.cancel();
      await vi.advanceTimersByTimeAsync(CANCEL_GRACE_MS * 5); // a parse of seconds
      expect(called).toBe(0);
      expect(worker.terminated).toBe(false);
      worker.emit({ type: 'loaded', reqId: worker.of('load').at(-1)!.reqId, file: { ...loaded, fileName: 'big.csv' } });
      await p;
      // Parsed; the worker then went into a step of the cancelled run and never acknowledged: replaced.
      await vi.advanceTimersByTimeAsync(CANCEL_GRACE_MS + 1);
      expect(worker.terminated).toBe(true);
    });

    it('says when the run in progress is inside a long step', async () => {
      const { client, worker, a } = await stuckClient();
      const now = performance.now();
      expect(client.isInLongStep(now)).toBe(false);
      expect(client.isInLongStep(now + CANCEL_GRACE_MS + 50)).toBe(true); // silent for longer than the grace
      worker.emit(frameMsg(a.runId, 2, { report: stepReport(1, { timings: { attractors_ms: 0, closest_ms: 0, solve_ms: 4000, apply_ms: 0, remesh_ms: 0, total_ms: 4100 } }) }));
      expect(client.isInLongStep(performance.now())).toBe(true); // its last step took seconds
      a.cancel();
      expect(client.isInLongStep(now + 10000)).toBe(false); // no run
    });
  });
});
