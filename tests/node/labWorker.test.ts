// The Lab through the worker's logic (WorkerCore + LabWorker) with the real wasm: truth,
// acquisition, a leave-one-out whose items equal the direct wasm Lab's, a cancel that stops a
// batch between steps, and errors that come back as data without killing the worker.
import { beforeAll, describe, expect, it } from 'vitest';
import type { FromWorker, LabAcquisition, LooItem, ToWorker } from '../../web/src/core-client/protocol';
import { WorkerCore, wasmApiOf } from '../../web/src/core-client/workerCore';
import { loadWasm } from './helpers.mjs';

type Wasm = typeof import('../../web/pkg/heartmesh_wasm.js');
let wasm: Wasm;

beforeAll(async () => {
  wasm = await loadWasm();
});

function makeCore() {
  const inbox: FromWorker[] = [];
  const waiters: (() => void)[] = [];
  const api = wasmApiOf(wasm);
  const core = new WorkerCore(
    api,
    (msg) => {
      inbox.push(msg);
      for (const w of waiters.splice(0)) w();
    },
    { yieldToEventLoop: (cb) => setTimeout(cb, 0), now: () => performance.now() },
  );
  /** Sends a message, then waits for the first new message matching `pred`. */
  async function until<T extends FromWorker>(pred: (m: FromWorker) => m is T, send?: ToWorker, timeoutMs = 60000): Promise<T> {
    const start = inbox.length;
    if (send) core.handle(send);
    const deadline = Date.now() + timeoutMs;
    for (;;) {
      const hit = inbox.slice(start).find(pred);
      if (hit) return hit;
      if (Date.now() > deadline) throw new Error(`timed out; got ${inbox.slice(start).map((m) => m.type).join(', ')}`);
      await new Promise<void>((r) => {
        waiters.push(r);
        setTimeout(r, 50);
      });
    }
  }
  return { core, inbox, until };
}

const is =
  <K extends FromWorker['type']>(type: K) =>
  (m: FromWorker): m is Extract<FromWorker, { type: K }> =>
    m.type === type;

describe('lab through the worker', () => {
  it('simulates, loads the contours, runs leave-one-out like the direct Lab, and cancels a batch', async () => {
    const { core, inbox, until } = makeCore();
    const truth = await until(is('lab-truth'), { type: 'lab-truth', reqId: 1, source: { kind: 'parametric', lv: {} } });
    expect(truth.truth.positions.length).toBe(truth.truth.vertices * 3);
    const sim = await until(is('lab-simulated'), { type: 'lab-simulate', reqId: 2, acquisition: { sax_count: 4, lax_count: 1 } });
    const acq: LabAcquisition = sim.acquisition;
    expect([acq.sax, acq.lax]).toEqual([4, 1]);
    await until(is('loaded'), { type: 'load', reqId: 3, fileName: 'lab.csv', bytes: acq.csv });

    const params = { iterations: 40 };
    const started = await until(is('lab-batch-started'), {
      type: 'lab-batch',
      runId: 10,
      job: { kind: 'loo', fileName: 'lab.csv', surface: null, params, lids: 'auto' },
    });
    expect(started.info.total).toBe(5);
    expect(started.info.contours).toHaveLength(5);
    await until(is('lab-batch-done'), undefined, 120000);
    const items = inbox
      .filter(is('lab-progress'))
      .filter((m) => m.runId === 10 && m.progress.item)
      .map((m) => m.progress.item as LooItem);
    expect(items.map((i) => i.index)).toEqual([0, 1, 2, 3, 4]);

    // The same analysis directly on the wasm Lab gives the same numbers.
    const lab = new wasm.Lab();
    const session = new wasm.Session();
    session.load('lab.csv', new Uint8Array(acq.csv));
    lab.make_parametric('{}');
    lab.start_leave_one_out(session, 'lab.csv', null, JSON.stringify(params), 'auto');
    const direct: LooItem[] = [];
    for (;;) {
      const p = JSON.parse(lab.batch_step());
      if (p.item) direct.push(p.item);
      if (p.done) break;
    }
    expect(items.map((i) => i.stats?.mean)).toEqual(direct.map((i) => i.stats?.mean));

    // Cancel: no item of the cancelled batch after the cancel is handled.
    await until(is('lab-batch-started'), {
      type: 'lab-batch',
      runId: 11,
      job: { kind: 'sweep', fileName: 'lab.csv', surface: null, params: { iterations: 200 }, lids: 'auto', grid: { lambda: [1e3, 1e4, 1e5] }, withTruth: true },
    });
    core.handle({ type: 'cancel', runId: 11 });
    const mark = inbox.length;
    await new Promise((r) => setTimeout(r, 300));
    expect(inbox.slice(mark).filter((m) => 'runId' in m && m.runId === 11)).toEqual([]);

    // Errors are data; the worker keeps serving.
    const err = await until(is('error'), { type: 'lab-batch', runId: 12, job: { kind: 'loo', fileName: 'missing.csv', surface: null, params, lids: 'auto' } });
    expect(err.runId).toBe(12);
    expect(err.error.code).toBe('not_loaded');
    const bad = await until(is('error'), { type: 'lab-truth', reqId: 13, source: { kind: 'file', fileName: 'bad.ply', bytes: new TextEncoder().encode('ply\nformat nonsense\n').buffer as ArrayBuffer } });
    expect(bad.error.file).toBe('bad.ply');
    expect(bad.error.code).not.toBe('worker_crashed');
    const again = await until(is('lab-compared'), {
      type: 'lab-compare',
      reqId: 14,
      positions: truth.truth.positions.slice(),
      indices: truth.truth.indices.slice(),
    });
    expect(again.comparison.report.hausdorff).toBeLessThan(1e-4);
  });
});
