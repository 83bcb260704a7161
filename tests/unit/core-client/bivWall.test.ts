// The biventricular wall's request through the worker protocol: what the worker hands the binding
// (settings as the params JSON, the three meshes in LV_ENDO, RV_ENDO, BIV_EPI order, the minimum
// thickness, the header), its answer (the LV wall's 'wall-file'), a wall the core cannot build as a
// typed error that leaves the worker working, a core without it, and the client's side (copies
// transferred, resolved with the figures and the file, rejected with the core's error).
import { beforeEach, describe, expect, it } from 'vitest';
import { DEFAULT_OPTIONS, isToWorker, transferablesOf, type BivWallExportRequest, type WallSummary } from '../../../web/src/core-client/protocol';
import { FakeWorker, loadedClient, recordedCall, stubSession, workerFor } from './fakes';

const summary = { surfaces: { endo: 'LV_ENDO', epi: 'BIV_EPI', rv_endo: 'RV_ENDO' }, format: 'obj', vertices: 2140, triangles: 4276, wall_volume_ml: 132.5 } as unknown as WallSummary;

/** Just enough of a session: `biventricular_wall` echoes its arguments, or throws what it is told to; `wall` must not be called. */
function fakeSession(throws: unknown = null, withBiv = true) {
  const lv = recordedCall(() => ({ summary: '{}', bytes: new Uint8Array(0) }));
  const { call, calls } = recordedCall(() => ({ summary: JSON.stringify(summary), bytes: new TextEncoder().encode('# heartmesh\n') }), throws);
  return { session: stubSession({ wall: lv.call, ...(withBiv ? { biventricular_wall: call } : {}) }), calls, lvCalls: lv.calls };
}

const m = (surface: string, x: number) => ({ surface, positions: new Float64Array([x, x + 1, x + 2]), indices: new Uint32Array([0, 0, 0]) });

function request(reqId = 7): BivWallExportRequest {
  return {
    type: 'biv-wall-export',
    reqId,
    fileName: 'p1.csv',
    params: { beta: 0.2 },
    lids: 'auto',
    options: { ...DEFAULT_OPTIONS, align_slices: true },
    lvEndo: m('LV_ENDO', 1),
    rvEndo: m('RV_ENDO', 4),
    bivEpi: m('BIV_EPI', 7),
    minThicknessMm: 1,
    format: 'vtk',
    header: ['heartmesh 0.1.0 (core 0.1.0), units: mm', 'input: p1.csv surface: LV_ENDO + BIV_EPI + RV_ENDO'],
  };
}

describe('the biv-wall-export request', () => {
  it('belongs to the protocol; its six mesh arrays are transferred', () => {
    const r = request();
    expect(isToWorker(r)).toBe(true);
    expect(transferablesOf(r)).toEqual([r.lvEndo.positions.buffer, r.lvEndo.indices.buffer, r.rvEndo.positions.buffer, r.rvEndo.indices.buffer, r.bivEpi.positions.buffer, r.bivEpi.indices.buffer]);
  });

  it('hands the binding the settings as the params JSON, the three meshes, the thickness and the header; answers with the wall file', () => {
    const { session, calls, lvCalls } = fakeSession();
    const { core, out } = workerFor(session);
    const r = request();
    core.handle(r);
    expect(lvCalls).toHaveLength(0);
    expect(calls).toHaveLength(1);
    const [file, params, lids, lv, lvP, lvI, rv, rvP, rvI, epi, epiP, epiI, min, format, header] = calls[0];
    expect([file, lids, lv, rv, epi, min, format]).toEqual(['p1.csv', 'auto', 'LV_ENDO', 'RV_ENDO', 'BIV_EPI', 1, 'vtk']);
    expect(JSON.parse(params as string)).toEqual({ beta: 0.2, ...DEFAULT_OPTIONS, align_slices: true });
    expect([lvP, lvI, rvP, rvI, epiP, epiI]).toEqual([r.lvEndo.positions, r.lvEndo.indices, r.rvEndo.positions, r.rvEndo.indices, r.bivEpi.positions, r.bivEpi.indices]);
    expect(header).toBe('heartmesh 0.1.0 (core 0.1.0), units: mm\ninput: p1.csv surface: LV_ENDO + BIV_EPI + RV_ENDO');
    expect(out).toEqual([{ type: 'wall-file', reqId: 7, summary, bytes: new TextEncoder().encode('# heartmesh\n') }]);
    core.handle({ ...request(8), minThicknessMm: null });
    expect(calls[1][12]).toBeUndefined();
  });

  it('a wall the core cannot build is its typed error, naming the file; the worker goes on', () => {
    const message = 'the biventricular wall: degenerate input: the base plane does not cut the epicardium';
    const { session } = fakeSession(JSON.stringify({ code: 'degenerate', message }));
    const { core, out } = workerFor(session);
    core.handle(request(3));
    expect(out).toEqual([{ type: 'error', reqId: 3, error: { code: 'degenerate', message, file: 'p1.csv' } }]);
    core.handle({ type: 'schema', reqId: 4 });
    expect(out.at(-1)).toMatchObject({ type: 'schema', reqId: 4 });
    core.handle(request(5));
    expect(out.at(-1)).toMatchObject({ type: 'error', reqId: 5 });
  });

  it('a core without the biventricular wall says so instead of crashing', () => {
    const { session } = fakeSession(null, false);
    const { core, out } = workerFor(session);
    core.handle(request(5));
    expect(out).toEqual([{ type: 'error', reqId: 5, error: { code: 'wall_unavailable', message: 'this core cannot build the biventricular wall', file: 'p1.csv' } }]);
  });
});

describe('CoreClient.bivWallFile', () => {
  beforeEach(() => {
    FakeWorker.instances = [];
  });

  const loaded = () => loadedClient('p1.csv', ['LV_ENDO', 'RV_ENDO', 'LV_EPI', 'RV_EPI', 'BIV_EPI']);
  const opts = { fileName: 'p1.csv', surface: 'BIV_EPI', params: { beta: 0.2 }, lids: 'auto' as const, options: { ...DEFAULT_OPTIONS } };
  const wall = () => ({ lvEndo: m('LV_ENDO', 1), rvEndo: m('RV_ENDO', 4), bivEpi: m('BIV_EPI', 7), minThicknessMm: 1, format: 'obj' as const, header: ['a', 'b'] });

  it('posts copies of the three meshes with the settings (no surface) and resolves with the figures and the file', async () => {
    const { client, w } = await loaded();
    const mine = wall();
    const p = client.bivWallFile(opts, mine);
    const sent = w.of('biv-wall-export')[0];
    expect(sent).toMatchObject({ fileName: 'p1.csv', params: { beta: 0.2 }, lids: 'auto', minThicknessMm: 1, format: 'obj', header: ['a', 'b'] });
    expect('surface' in sent).toBe(false);
    for (const k of ['lvEndo', 'rvEndo', 'bivEpi'] as const) {
      expect(sent[k].surface).toBe(mine[k].surface);
      expect(sent[k].positions).toEqual(mine[k].positions);
      expect(sent[k].positions).not.toBe(mine[k].positions);
    }
    expect(w.transfers.at(-1)).toHaveLength(6);
    const bytes = new Uint8Array([1, 2, 3]);
    w.emit({ type: 'wall-file', reqId: sent.reqId, summary, bytes });
    expect(await p).toEqual({ summary, bytes });
  });

  it('rejects with the core\'s error, and for a file never loaded', async () => {
    const { client, w } = await loaded();
    const p = client.bivWallFile(opts, wall());
    const sent = w.of('biv-wall-export')[0];
    const error = { code: 'invalid_mesh', message: 'the biventricular wall: invalid mesh: the RV_ENDO mesh: 3 triangles: no closed surface', file: 'p1.csv' };
    w.emit({ type: 'error', reqId: sent.reqId, error });
    await expect(p).rejects.toEqual(error);
    await expect(client.bivWallFile({ ...opts, fileName: 'none.csv' }, wall())).rejects.toMatchObject({ code: 'not_loaded', file: 'none.csv' });
  });
});
