// The LV wall's request through the worker protocol: what the worker hands the binding (settings
// as the params JSON, the two meshes, the minimum thickness, the header), its answer, a wall the
// core cannot build as a typed error that leaves the worker working, and the client's side
// (copies transferred, resolved with the figures and the file, rejected with the core's error).
import { beforeEach, describe, expect, it } from 'vitest';
import {
  DEFAULT_OPTIONS, isFromWorker, isToWorker, runIdOf, transferablesOf, type FromWorker, type WallExportRequest, type WallSummary,
} from '../../../web/src/core-client/protocol';
import { FakeWorker, loadedClient, recordedCall, stubSession, workerFor } from './fakes';

const summary = { surfaces: { endo: 'LV_ENDO', epi: 'LV_EPI' }, format: 'obj', vertices: 8, triangles: 12, wall_volume_ml: 99.5 } as unknown as WallSummary;

/** Just enough of a session for the wall: `wall` echoes its arguments, or throws what it is told to. */
function fakeSession(throws: unknown = null, withWall = true) {
  const { call, calls } = recordedCall(() => ({ summary: JSON.stringify(summary), bytes: new TextEncoder().encode('# heartmesh\n') }), throws);
  return { session: stubSession(withWall ? { wall: call } : {}), calls };
}

function request(reqId = 7): WallExportRequest {
  return {
    type: 'wall-export',
    reqId,
    fileName: 'p1.csv',
    params: { beta: 0.2 },
    lids: 'auto',
    options: { ...DEFAULT_OPTIONS, align_slices: true },
    endo: { surface: 'LV_ENDO', positions: new Float64Array([1, 2, 3]), indices: new Uint32Array([0, 0, 0]) },
    epi: { surface: 'LV_EPI', positions: new Float64Array([4, 5, 6]), indices: new Uint32Array([0, 0, 0]) },
    minThicknessMm: 1,
    format: 'obj',
    header: ['heartmesh 0.1.0 (core 0.1.0), units: mm', 'lids: auto beta=0.2'],
  };
}

describe('the wall-export request', () => {
  it('belongs to the protocol; its four mesh arrays are transferred, the answer\'s file too', () => {
    const r = request();
    expect(isToWorker(r)).toBe(true);
    expect(transferablesOf(r)).toEqual([r.endo.positions.buffer, r.endo.indices.buffer, r.epi.positions.buffer, r.epi.indices.buffer]);
    const answer: FromWorker = { type: 'wall-file', reqId: 7, summary, bytes: new Uint8Array(4) };
    expect(isFromWorker(answer)).toBe(true);
    expect(runIdOf(answer)).toBeUndefined();
    expect(transferablesOf(answer)).toHaveLength(1);
  });

  it('hands the binding the settings as the params JSON, both meshes, the thickness and the header', () => {
    const { session, calls } = fakeSession();
    const { core, out } = workerFor(session);
    const r = request();
    core.handle(r);
    expect(calls).toHaveLength(1);
    const [file, params, lids, endo, endoP, endoI, epi, epiP, epiI, min, format, header] = calls[0];
    expect([file, lids, endo, epi, min, format]).toEqual(['p1.csv', 'auto', 'LV_ENDO', 'LV_EPI', 1, 'obj']);
    expect(JSON.parse(params as string)).toEqual({ beta: 0.2, ...DEFAULT_OPTIONS, align_slices: true });
    expect([endoP, endoI, epiP, epiI]).toEqual([r.endo.positions, r.endo.indices, r.epi.positions, r.epi.indices]);
    expect(header).toBe('heartmesh 0.1.0 (core 0.1.0), units: mm\nlids: auto beta=0.2');
    expect(out).toEqual([{ type: 'wall-file', reqId: 7, summary, bytes: new TextEncoder().encode('# heartmesh\n') }]);
    // Off: the binding's undefined.
    core.handle({ ...request(8), minThicknessMm: null });
    expect(calls[1][9]).toBeUndefined();
  });

  it('a wall the core cannot build is its typed error, naming the file; the worker goes on', () => {
    const { session } = fakeSession(JSON.stringify({ code: 'degenerate', message: 'the LV wall: degenerate input: the base plane cuts the epicardium in 2 outlines, not one' }));
    const { core, out } = workerFor(session);
    core.handle(request(3));
    expect(out).toEqual([{ type: 'error', reqId: 3, error: { code: 'degenerate', message: 'the LV wall: degenerate input: the base plane cuts the epicardium in 2 outlines, not one', file: 'p1.csv' } }]);
    core.handle({ type: 'schema', reqId: 4 });
    expect(out.at(-1)).toMatchObject({ type: 'schema', reqId: 4 });
  });

  it('a core without the wall says so instead of crashing', () => {
    const { session } = fakeSession(null, false);
    const { core, out } = workerFor(session);
    core.handle(request(5));
    expect(out).toEqual([{ type: 'error', reqId: 5, error: { code: 'wall_unavailable', message: 'this core cannot build the LV wall', file: 'p1.csv' } }]);
  });
});

describe('CoreClient.wallFile', () => {
  beforeEach(() => {
    FakeWorker.instances = [];
  });

  const loaded = () => loadedClient('p1.csv', ['LV_ENDO', 'LV_EPI']);
  const opts = { fileName: 'p1.csv', surface: 'RV_ENDO', params: { beta: 0.2 }, lids: 'auto' as const, options: { ...DEFAULT_OPTIONS } };
  const wall = () => ({
    endo: { surface: 'LV_ENDO', positions: new Float64Array([1, 2, 3]), indices: new Uint32Array([0, 1, 2]) },
    epi: { surface: 'LV_EPI', positions: new Float64Array([4, 5, 6]), indices: new Uint32Array([0, 1, 2]) },
    minThicknessMm: 1,
    format: 'vtk' as const,
    header: ['a', 'b'],
  });

  it('posts copies of the meshes with the settings (no surface) and resolves with the figures and the file', async () => {
    const { client, w } = await loaded();
    const mine = wall();
    const p = client.wallFile(opts, mine);
    const sent = w.of('wall-export')[0];
    expect(sent).toMatchObject({ fileName: 'p1.csv', params: { beta: 0.2 }, lids: 'auto', minThicknessMm: 1, format: 'vtk', header: ['a', 'b'] });
    expect('surface' in sent).toBe(false);
    expect(sent.endo.positions).toEqual(mine.endo.positions);
    expect(sent.endo.positions).not.toBe(mine.endo.positions);
    expect(w.transfers.at(-1)).toHaveLength(4);
    const bytes = new Uint8Array([1, 2, 3]);
    w.emit({ type: 'wall-file', reqId: sent.reqId, summary, bytes });
    expect(await p).toEqual({ summary, bytes });
  });

  it('rejects with the core\'s error, and for a file never loaded', async () => {
    const { client, w } = await loaded();
    const p = client.wallFile(opts, wall());
    const sent = w.of('wall-export')[0];
    const error = { code: 'degenerate', message: 'the LV wall: degenerate input: the base plane does not cut the epicardium', file: 'p1.csv' };
    w.emit({ type: 'error', reqId: sent.reqId, error });
    await expect(p).rejects.toEqual(error);
    await expect(client.wallFile({ ...opts, fileName: 'none.csv' }, wall())).rejects.toMatchObject({ code: 'not_loaded', file: 'none.csv' });
  });
});
