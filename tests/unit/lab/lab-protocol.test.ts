// Units of the Lab's protocol additions (protocol.ts) and CoreClient's lab calls over a fake worker:
// transferables, routing of batch progress, cancel, crash recovery (truth replayed).
import { beforeEach, describe, expect, it } from 'vitest';
import { CoreClient } from '../../../web/src/core-client/CoreClient';
import { isFromWorker, isToWorker, runIdOf, transferablesOf, type LabProgress } from '../../../web/src/core-client/protocol';
import { FakeWorker, ManualScheduler } from '../core-client/fakes';

describe('lab messages', () => {
  it('transfer their bulk buffers exactly once', () => {
    const positions = new Float32Array(9);
    const indices = new Uint32Array(3);
    expect(transferablesOf({ type: 'lab-compare', reqId: 1, positions, indices })).toEqual([positions.buffer, indices.buffer]);
    const bytes = new ArrayBuffer(8);
    expect(transferablesOf({ type: 'lab-truth', reqId: 1, source: { kind: 'file', fileName: 'a.obj', bytes } })).toEqual([bytes]);
    expect(transferablesOf({ type: 'lab-truth', reqId: 1, source: { kind: 'parametric', lv: {} } })).toEqual([]);
    const csv = new ArrayBuffer(4);
    const clip = { origin: [0, 0, 0] as [number, number, number], normal: [0, 0, 1] as [number, number, number] };
    expect(transferablesOf({ type: 'lab-simulated', reqId: 2, acquisition: { sax: 1, lax: 0, points: 3, surfaces: [], clip, csv } })).toEqual([csv]);
    const d = new Float32Array(4);
    const stats = { mean: 0, median: 0, p95: 0, max: 0, max_at: [0, 0, 0] as [number, number, number], min: 0, count: 1 };
    const report = { mesh_to_truth: stats, truth_to_mesh: stats, hausdorff: 0, volume_truth_ml: 1, volume_mesh_ml: 1, clipped: true };
    expect(transferablesOf({ type: 'lab-compared', reqId: 3, comparison: { report, truthIndex: 0, truthLabel: null, truthName: 't.obj', truthDistances: d } })).toEqual([d.buffer]);
    expect(transferablesOf({ type: 'lab-progress', runId: 4, progress: { completed: 1, total: 2 } })).toEqual([]);
  });

  it('are recognised on both sides and batch messages carry their run id', () => {
    for (const type of ['lab-truth', 'lab-truth-edit', 'lab-simulate', 'lab-compare', 'lab-batch']) expect(isToWorker({ type })).toBe(true);
    for (const type of ['lab-truth', 'lab-truths', 'lab-simulated', 'lab-compared', 'lab-batch-started', 'lab-progress', 'lab-batch-done']) {
      expect(isFromWorker({ type })).toBe(true);
    }
    expect(isToWorker({ type: 'lab-bogus' })).toBe(false);
    expect(runIdOf({ type: 'lab-batch-done', runId: 7 })).toBe(7);
    expect(runIdOf({ type: 'lab-progress', runId: 8, progress: { completed: 0, total: 1 } })).toBe(8);
  });
});

describe('CoreClient lab calls', () => {
  let client: CoreClient;
  let sched: ManualScheduler;
  const worker = () => FakeWorker.instances.at(-1)!;

  beforeEach(async () => {
    FakeWorker.instances = [];
    sched = new ManualScheduler();
    client = new CoreClient({ createWorker: () => new FakeWorker(), schedule: sched.schedule });
    const ready = client.whenReady();
    worker().emit({ type: 'ready' });
    await ready;
  });

  async function loadFile(name: string) {
    const p = client.load(name, new ArrayBuffer(4));
    const req = worker().of('load').at(-1)!;
    worker().emit({ type: 'loaded', reqId: req.reqId, file: { fileName: name, surfaces: [], contours: [], points: new Float32Array(), landmarks: [], warnings: [] } });
    await p;
  }

  it('routes a batch: started, progress items, done; a second batch cancels the first', async () => {
    await loadFile('c.csv');
    const seen: LabProgress[] = [];
    const base = { fileName: 'c.csv', surface: null, params: { iterations: 5 }, lids: 'auto' as const };
    const h = client.labBatch({ kind: 'loo', ...base }, (p) => seen.push(p));
    const msg = worker().of('lab-batch').at(-1)!;
    expect(msg.runId).toBe(h.runId);
    expect(msg.job).toMatchObject({ kind: 'loo', fileName: 'c.csv' });
    worker().emit({ type: 'lab-batch-started', runId: h.runId, info: { total: 2, contours: [], points: new Float32Array(3) } });
    expect((await h.started).total).toBe(2);
    const item = { index: 0, id: 'a', kind: 'SAX' as const, stats: null, error: 'x' };
    worker().emit({ type: 'lab-progress', runId: h.runId, progress: { completed: 1, total: 2, item } });
    worker().emit({ type: 'lab-progress', runId: h.runId + 100, progress: { completed: 1, total: 2 } }); // stale: ignored
    worker().emit({ type: 'lab-batch-done', runId: h.runId });
    await h.done;
    expect(seen).toEqual([{ completed: 1, total: 2, item }]);

    const first = client.labBatch({ kind: 'sweep', ...base, grid: { lambda: [1, 2] }, withTruth: false }, () => undefined);
    const second = client.labBatch({ kind: 'loo', ...base }, () => undefined);
    await expect(first.done).rejects.toMatchObject({ code: 'cancelled' });
    expect(worker().of('cancel').map((c) => c.runId)).toContain(first.runId);
    second.cancel();
    await expect(second.done).rejects.toMatchObject({ code: 'cancelled' });
  });

  it('measures phases: files as loaded, frames from the bytes kept here (transferred copies); the summary reaches the caller', async () => {
    await loadFile('a.csv');
    await loadFile('b.csv');
    const files = client.measurePhases({ kind: 'phases', phases: [{ name: 'a', file: 'a.csv' }, { name: 'b', file: 'b.csv' }], params: {}, lids: 'auto' }, () => undefined);
    const posted = worker().of('lab-batch').at(-1)!;
    expect(posted.runId).toBe(files.runId);
    expect(posted.job).toEqual({ kind: 'phases', phases: [{ name: 'a', file: 'a.csv' }, { name: 'b', file: 'b.csv' }], params: {}, lids: 'auto' });
    expect(transferablesOf(posted)).toEqual([]);

    const seen: LabProgress[] = [];
    const frames = client.measurePhases({ kind: 'phases', phases: [{ name: 'ED', file: 'a.csv', frame: 'ED' }, { name: 'ES', file: 'a.csv', frame: 'ES' }], params: {}, lids: 'auto' }, (p) => seen.push(p));
    await expect(files.done).rejects.toMatchObject({ code: 'cancelled' });
    const msg = worker().of('lab-batch').at(-1)!;
    const job = msg.job as { sequence?: { bytes: ArrayBuffer; views: unknown[] } };
    expect(job.sequence?.bytes.byteLength).toBe(4);
    expect(job.sequence?.views).toEqual([]);
    expect(transferablesOf(msg)).toEqual([job.sequence?.bytes]);
    const summary = { ventricles: [], single: [], lv_mass: null };
    worker().emit({ type: 'lab-progress', runId: frames.runId, progress: { completed: 2, total: 2, summary } });
    worker().emit({ type: 'lab-batch-done', runId: frames.runId });
    await frames.done;
    expect(seen).toEqual([{ completed: 2, total: 2, summary }]);

    const missing = client.measurePhases({ kind: 'phases', phases: [{ name: 'x', file: 'x.csv' }, { name: 'a', file: 'a.csv' }], params: {}, lids: 'auto' }, () => undefined);
    await expect(missing.done).rejects.toMatchObject({ code: 'not_loaded', file: 'x.csv' });
  });

  it('rejects a batch on a file that was never loaded, and a batch error', async () => {
    const h = client.labBatch({ kind: 'loo', fileName: 'nope.csv', surface: null, params: {}, lids: 'auto' }, () => undefined);
    await expect(h.done).rejects.toMatchObject({ code: 'not_loaded' });
    await loadFile('c.csv');
    const g = client.labBatch({ kind: 'loo', fileName: 'c.csv', surface: null, params: {}, lids: 'auto' }, () => undefined);
    worker().emit({ type: 'error', runId: g.runId, error: { code: 'too_few_contours', message: 'too few' } });
    await expect(g.started).rejects.toMatchObject({ code: 'too_few_contours' });
    await expect(g.done).rejects.toMatchObject({ code: 'too_few_contours' });
  });

  it('sends copies to compare, and replays the truth and acquisition to a recreated worker', async () => {
    const t = client.labTruth({ kind: 'parametric', lv: { length_mm: 70 } });
    const tr = worker().of('lab-truth').at(-1)!;
    worker().emit({ type: 'lab-truth', reqId: tr.reqId, truth: { name: 'parametric LV', label: null, index: 0, vertices: 3, triangles: 1, volumeMl: 0, closed: false, positions: new Float32Array(9), indices: new Uint32Array(3) } });
    expect((await t).name).toBe('parametric LV');
    const s = client.labSimulate({ sax_count: 8, lax_count: 2 });
    const sr = worker().of('lab-simulate').at(-1)!;
    const clip = { origin: [0, 0, 0] as [number, number, number], normal: [0, 0, 1] as [number, number, number] };
    worker().emit({ type: 'lab-simulated', reqId: sr.reqId, acquisition: { sax: 8, lax: 2, points: 10, surfaces: [], clip, csv: new ArrayBuffer(2) } });
    expect((await s).sax).toBe(8);

    const positions = new Float32Array([1, 2, 3]);
    const indices = new Uint32Array([0, 0, 0]);
    void client.labCompare(positions, indices).catch(() => undefined);
    const cr = worker().of('lab-compare').at(-1)!;
    expect(cr.positions).not.toBe(positions);
    expect(Array.from(cr.positions)).toEqual([1, 2, 3]);

    const old = worker();
    old.crash();
    void client.labCompare(positions, indices).catch(() => undefined);
    const fresh = worker();
    expect(fresh).not.toBe(old);
    expect(fresh.sent.map((m) => m.type)).toEqual(['lab-truth', 'lab-simulate', 'lab-compare']);
    expect(fresh.of('lab-truth')[0].source).toEqual({ kind: 'parametric', lv: { length_mm: 70 } });
    expect(fresh.of('lab-simulate')[0].acquisition).toEqual({ sax_count: 8, lax_count: 2 });
  });
  it('replays several truths in order, with their labels as edited, and sends the surface to compare', async () => {
    const truth = (name: string, index: number, label: string | null) => ({ name, label, index, vertices: 3, triangles: 1, volumeMl: 0, closed: false, positions: new Float32Array(9), indices: new Uint32Array(3) });
    const answer = (name: string, index: number, label: string | null) => {
      const r = worker().of('lab-truth').at(-1)!;
      worker().emit({ type: 'lab-truth', reqId: r.reqId, truth: truth(name, index, label) });
    };
    const file = (fileName: string) => ({ kind: 'file' as const, fileName, bytes: new ArrayBuffer(4) });
    const a = client.labTruth(file('lv.obj'), { label: 'LV_ENDO' });
    answer('lv.obj', 0, 'LV_ENDO');
    await a;
    const b = client.labTruth(file('rv.obj'), { add: true, label: 'RV_ENDO' });
    expect(worker().of('lab-truth').at(-1)).toMatchObject({ add: true, label: 'RV_ENDO' });
    answer('rv.obj', 1, 'RV_ENDO');
    await b;
    const c = client.labTruth(file('epi.obj'), { add: true });
    answer('epi.obj', 2, null);
    await c;
    const e = client.labEditTruth({ index: 2, label: 'BIV_EPI' });
    const er = worker().of('lab-truth-edit').at(-1)!;
    expect(er.edit).toEqual({ index: 2, label: 'BIV_EPI' });
    worker().emit({ type: 'lab-truths', reqId: er.reqId, truths: [] });
    await e;
    const r = client.labEditTruth({ index: 0, remove: true });
    worker().emit({ type: 'lab-truths', reqId: worker().of('lab-truth-edit').at(-1)!.reqId, truths: [] });
    await r;
    void client.labCompare(new Float32Array(9), new Uint32Array(3), 'RV_ENDO').catch(() => undefined);
    expect(worker().of('lab-compare').at(-1)!.surface).toBe('RV_ENDO');

    worker().crash();
    void client.labCompare(new Float32Array(9), new Uint32Array(3), 'RV_ENDO').catch(() => undefined);
    const fresh = worker();
    expect(fresh.sent.map((m) => m.type)).toEqual(['lab-truth', 'lab-truth', 'lab-compare']);
    const [first, second] = fresh.of('lab-truth');
    expect([first.source.kind === 'file' && first.source.fileName, first.add, first.label]).toEqual(['rv.obj', undefined, 'RV_ENDO']);
    expect([second.source.kind === 'file' && second.source.fileName, second.add, second.label]).toEqual(['epi.obj', true, 'BIV_EPI']);
  });
});
