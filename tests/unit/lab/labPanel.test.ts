// The Lab panel's leave-one-out buttons with a fake core client and the fake DOM: Cancel, enabled
// by the click that starts the batch, must cancel it even before the worker said it started (the
// e2e test clicks it at once; on a loaded machine the worker's "started" can come later).
import { afterEach, beforeEach, describe, expect, it, vi } from 'vitest';
import type { Controller } from '../../../web/src/app/controller';
import type { LabBatchHandle } from '../../../web/src/core-client/CoreClient';
import type { CoreErrorData, LabBatchInfo } from '../../../web/src/core-client/protocol';
import { LabPanel } from '../../../web/src/lab/LabPanel';
import { FakeElement, fakeDocument } from '../fakeDom';

/** A batch the test starts and settles by hand; cancel() settles it as CoreClient's does. */
function fakeBatch(runId: number) {
  let started!: { resolve: (i: LabBatchInfo) => void; reject: (e: CoreErrorData) => void };
  let done!: { resolve: () => void; reject: (e: CoreErrorData) => void };
  const startedP = new Promise<LabBatchInfo>((resolve, reject) => (started = { resolve, reject }));
  const doneP = new Promise<void>((resolve, reject) => (done = { resolve, reject }));
  startedP.catch(() => undefined);
  doneP.catch(() => undefined);
  const cancel = vi.fn(() => {
    const e = { code: 'cancelled', message: 'the batch was cancelled' };
    started.reject(e);
    done.reject(e);
  });
  const handle: LabBatchHandle = { runId, started: startedP, done: doneP, cancel };
  return { handle, started, done, cancel };
}

function makePanel(leaveOut: string[] = []) {
  const batches: ReturnType<typeof fakeBatch>[] = [];
  const jobs: unknown[] = [];
  const client = {
    labBatch: (job: unknown) => {
      jobs.push(job);
      const b = fakeBatch(batches.length + 1);
      batches.push(b);
      return b.handle;
    },
  };
  const controller = {
    coreClient: client,
    onResult: () => undefined,
    runSettings: () => ({ fileName: 'lab.csv', surface: null, params: {}, lids: 'auto', options: {} }),
    currentResult: () => null,
    leaveOutNow: () => leaveOut,
    debug: { historyLength: 0 },
  } as unknown as Controller;
  const panel = new LabPanel({ controller, viewer: null, legendSlot: new FakeElement('div') as unknown as HTMLElement });
  const el = panel.element as unknown as FakeElement;
  const byId = (id: string) => {
    const e = el.byTestId(id);
    if (!e) throw new Error(`no ${id}`);
    return e as FakeElement & { disabled?: boolean };
  };
  return { batches, byId, jobs };
}

const settle = () => new Promise((r) => setTimeout(r, 0));

describe('the Lab panel leave-one-out', () => {
  beforeEach(() => vi.stubGlobal('document', fakeDocument));
  afterEach(() => vi.unstubAllGlobals());

  it('Cancel stops a batch the worker has not started yet', async () => {
    const { batches, byId } = makePanel();
    byId('lab-loo-run').fire('click');
    expect(batches).toHaveLength(1);
    expect(byId('lab-loo-cancel').disabled).toBe(false);
    expect(byId('lab-loo-run').disabled).toBe(true);
    // No "started" from the worker yet: the click must still reach the batch.
    byId('lab-loo-cancel').fire('click');
    expect(batches[0].cancel).toHaveBeenCalledTimes(1);
    await settle();
    expect(byId('lab-loo-info').textContent).toBe('cancelled');
    expect(byId('lab-loo-run').disabled).toBe(false);
    expect(byId('lab-loo-cancel').disabled).toBe(true);
  });

  it('Cancel after the start stops the batch too, and a batch that finishes is done', async () => {
    const { batches, byId } = makePanel();
    byId('lab-loo-run').fire('click');
    batches[0].started.resolve({ total: 2, contours: [], points: new Float32Array() } as unknown as LabBatchInfo);
    await settle();
    byId('lab-loo-cancel').fire('click');
    expect(batches[0].cancel).toHaveBeenCalledTimes(1);
    await settle();
    expect(byId('lab-loo-info').textContent).toBe('cancelled');

    byId('lab-loo-run').fire('click');
    batches[1].started.resolve({ total: 0, contours: [], points: new Float32Array() } as unknown as LabBatchInfo);
    batches[1].done.resolve();
    await settle();
    expect(byId('lab-loo-info').dataset.done).toBe('1');
    expect(byId('lab-loo-cancel').disabled).toBe(true);
    expect(batches[1].cancel).not.toHaveBeenCalled();
  });

  it('leaves out of every rebuild what the Contours panel left out, and says so when done', async () => {
    const { batches, byId, jobs } = makePanel(['s07', 's08']);
    byId('lab-loo-run').fire('click');
    expect(jobs[0]).toMatchObject({ kind: 'loo', fileName: 'lab.csv', leaveOut: ['s07', 's08'] });
    batches[0].started.resolve({ total: 0, contours: [], points: new Float32Array() } as unknown as LabBatchInfo);
    batches[0].done.resolve();
    await settle();
    expect(byId('lab-loo-info').textContent).toBe('done: 0 contours; worst –; without the 2 contours you left out in the Contours panel');
    const none = makePanel();
    none.byId('lab-loo-run').fire('click');
    expect(none.jobs[0]).toMatchObject({ kind: 'loo', leaveOut: [] });
  });

  it('the sweep takes the file\'s whole list, another surface\'s ids with it (the controller\'s leaveOutNow)', async () => {
    const { batches, byId, jobs } = makePanel(['s07_LAX_LV_ENDOCARDIAL', 'r1_RV_ENDO']);
    // The fake DOM keeps a `value` attribute apart from the property: the grid's values by hand.
    for (const [id, v] of [['lambda', '1e5'], ['smoothing', '50'], ['reduction', '0.6'], ['spacing', '0']]) (byId(`lab-grid-${id}`) as unknown as { value: string }).value = v;
    byId('lab-sweep-run').fire('click');
    expect(jobs[0]).toMatchObject({ kind: 'sweep', leaveOut: ['s07_LAX_LV_ENDOCARDIAL', 'r1_RV_ENDO'] });
    batches[0].started.resolve({ total: 0 } as unknown as LabBatchInfo);
    batches[0].done.resolve();
    await settle();
    expect(byId('lab-sweep-info').textContent).toBe('done: 0 runs; without the 2 contours you left out in the Contours panel');
  });
});
