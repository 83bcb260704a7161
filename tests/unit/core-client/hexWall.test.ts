// The hexahedral LV wall's request through the worker protocol: what the worker hands the binding
// (the run's settings as the params JSON, both surfaces and their meshes, the layout, the layers,
// the header), its answer, the core's refusal as a typed error that leaves the worker working, a
// malformed request refused before the binding sees it (wasm-bindgen's own throw would be taken
// for a crash), a core without the call; and the client's side (copies of both meshes
// transferred, no run surface sent, resolved with the figures and the file, rejected with the
// core's error).
import { beforeEach, describe, expect, it } from 'vitest';
import {
  DEFAULT_OPTIONS, isFromWorker, isToWorker, runIdOf, transferablesOf, type FromWorker, type HexExportRequest, type HexSummary,
} from '../../../web/src/core-client/protocol';
import { malformedHex } from '../../../web/src/core-client/workerCore';
import { FakeWorker, loadedClient, recordedCall, stubSession, workerFor } from './fakes';

const summary: HexSummary = {
  rings: 10, points_per_ring: 16, layers: 2, points: 483, hexahedra: 288, wedges: 32, volume_ml: 98.7, layouts_volume_ml: 98.8, min_scaled_jacobian: 0.07, inverted_cells: 0, helix_deg: [60, -60], endocardium_moved: 0,
};
const REFUSED = 'the hexahedral wall: its cells are laid out from the septum: the file has no RV_INSERT landmarks and no RV contours';
const VTK = new TextEncoder().encode('# vtk DataFile Version 3.0\n');

/** Just enough of a session: `hex_wall` records its arguments and answers, or throws what it is told to. */
function fakeSession(throws: unknown = null, withCall = true) {
  const { call, calls } = recordedCall(() => ({ summary: JSON.stringify(summary), bytes: VTK }), throws);
  return { session: stubSession(withCall ? { hex_wall: call } : {}), calls };
}

function request(reqId = 7, over: Partial<HexExportRequest> = {}): HexExportRequest {
  return {
    type: 'hex-export',
    reqId,
    fileName: 'p1.csv',
    params: { beta: 0.2 },
    lids: 'auto',
    options: { ...DEFAULT_OPTIONS, align_slices: true },
    leaveOut: ['s07'],
    endo: { surface: 'LV_ENDO', positions: new Float64Array([1, 2, 3]), indices: new Uint32Array([0, 0, 0]) },
    epi: { surface: 'LV_EPI', positions: new Float64Array([4, 5, 6]), indices: new Uint32Array([0, 0, 0]) },
    rings: 10,
    points: 16,
    layers: 2,
    header: ['heartmesh 0.1.0 (core 0.1.0), units: mm', 'lids: auto beta=0.2'],
    ...over,
  };
}

describe('the hex-export request', () => {
  it('belongs to the protocol; both meshes\' arrays are transferred, the answer\'s file too', () => {
    const r = request();
    expect(isToWorker(r)).toBe(true);
    expect(transferablesOf(r)).toEqual([r.endo.positions.buffer, r.endo.indices.buffer, r.epi.positions.buffer, r.epi.indices.buffer]);
    const answer: FromWorker = { type: 'hex-file', reqId: 7, summary, bytes: new Uint8Array(4) };
    expect(isFromWorker(answer)).toBe(true);
    expect(runIdOf(answer)).toBeUndefined();
    expect(transferablesOf(answer)).toHaveLength(1);
  });

  it('hands the binding the settings as the params JSON, both surfaces and meshes, the layout, the layers and the header', () => {
    const { session, calls } = fakeSession();
    const { core, out } = workerFor(session);
    const r = request();
    core.handle(r);
    expect(calls).toHaveLength(1);
    const [file, params, lids, endo, endoPositions, endoIndices, epi, epiPositions, epiIndices, rings, points, layers, header] = calls[0];
    expect([file, lids, endo, epi, rings, points, layers]).toEqual(['p1.csv', 'auto', 'LV_ENDO', 'LV_EPI', 10, 16, 2]);
    expect(JSON.parse(params as string)).toEqual({ beta: 0.2, ...DEFAULT_OPTIONS, align_slices: true, leave_out: ['s07'] });
    expect([endoPositions, endoIndices, epiPositions, epiIndices]).toEqual([r.endo.positions, r.endo.indices, r.epi.positions, r.epi.indices]);
    expect(header).toBe('heartmesh 0.1.0 (core 0.1.0), units: mm\nlids: auto beta=0.2');
    expect(out).toEqual([{ type: 'hex-file', reqId: 7, summary, bytes: VTK }]);
  });

  it('the core\'s refusal is its typed error, naming the file; the worker goes on', () => {
    const { session } = fakeSession(JSON.stringify({ code: 'degenerate', message: REFUSED }));
    const { core, out } = workerFor(session);
    core.handle(request(3));
    expect(out).toEqual([{ type: 'error', reqId: 3, error: { code: 'degenerate', message: REFUSED, file: 'p1.csv' } }]);
    core.handle({ type: 'schema', reqId: 4 });
    expect(out.at(-1)).toMatchObject({ type: 'schema', reqId: 4 });
  });

  it('a malformed request is refused before the binding sees it; the worker goes on', () => {
    const { session, calls } = fakeSession();
    const { core, out } = workerFor(session);
    const bad: [Partial<HexExportRequest>, string][] = [
      [{ layers: 2.5 }, 'the layout and layers must be whole numbers (got 10x16x2.5)'],
      [{ layers: undefined as unknown as number }, 'the layout and layers must be whole numbers (got 10x16xundefined)'],
      [{ rings: -1 }, 'the layout and layers must be whole numbers (got -1x16x2)'],
      [{ points: '16' as unknown as number }, 'the layout and layers must be whole numbers (got 10x16x2)'],
      [{ endo: { surface: 'LV_ENDO', positions: new Float32Array(3) as unknown as Float64Array, indices: new Uint32Array(3) } }, 'the endocardium mesh must be a Float64Array of positions and a Uint32Array of indices'],
      [{ epi: undefined as unknown as HexExportRequest['epi'] }, 'the request names no epicardium surface'],
      [{ header: undefined as unknown as string[] }, 'the request has no header'],
    ];
    bad.forEach(([over, message], i) => {
      expect(malformedHex(request(i, over))).toBe(message);
      core.handle(request(i, over));
      expect(out.at(-1)).toEqual({ type: 'error', reqId: i, error: { code: 'protocol', message: `the hexahedral wall: ${message}`, file: 'p1.csv' } });
    });
    expect(calls).toHaveLength(0);
    expect(malformedHex(request())).toBeNull();
    // Ranges are the core's to say: 0 layers reaches it.
    expect(malformedHex(request(0, { layers: 0 }))).toBeNull();
    core.handle(request(20));
    expect(out.at(-1)).toMatchObject({ type: 'hex-file', reqId: 20 });
  });

  it('a core without the call says so instead of crashing', () => {
    const { session } = fakeSession(null, false);
    const { core, out } = workerFor(session);
    core.handle(request(5));
    expect(out).toEqual([{ type: 'error', reqId: 5, error: { code: 'hex_unavailable', message: 'this core cannot build the hexahedral wall', file: 'p1.csv' } }]);
  });
});

describe('CoreClient.hexFile', () => {
  beforeEach(() => {
    FakeWorker.instances = [];
  });

  const loaded = () => loadedClient('p1.csv', ['LV_ENDO', 'LV_EPI']);
  const opts = { fileName: 'p1.csv', surface: 'LV_ENDO', params: { beta: 0.2 }, lids: 'auto' as const, options: { ...DEFAULT_OPTIONS }, leaveOut: ['s07'] };
  const hex = () => ({
    endo: { surface: 'LV_ENDO', positions: new Float64Array([1, 2, 3]), indices: new Uint32Array([0, 1, 2]) },
    epi: { surface: 'LV_EPI', positions: new Float64Array([4, 5, 6]), indices: new Uint32Array([0, 1, 2]) },
    rings: 24,
    points: 48,
    layers: 3,
    header: ['a', 'b'],
  });

  it('posts copies of both meshes with the run\'s settings (no run surface) and resolves with the figures and the file', async () => {
    const { client, w } = await loaded();
    const mine = hex();
    const p = client.hexFile(opts, mine);
    const sent = w.of('hex-export')[0];
    expect(sent).toMatchObject({ fileName: 'p1.csv', params: { beta: 0.2 }, lids: 'auto', leaveOut: ['s07'], rings: 24, points: 48, layers: 3, header: ['a', 'b'] });
    expect('surface' in sent).toBe(false);
    expect([sent.endo.surface, sent.epi.surface]).toEqual(['LV_ENDO', 'LV_EPI']);
    expect(sent.epi.positions).toEqual(mine.epi.positions);
    expect(sent.epi.positions).not.toBe(mine.epi.positions);
    expect(w.transfers.at(-1)).toHaveLength(4);
    const bytes = new Uint8Array([1, 2, 3]);
    w.emit({ type: 'hex-file', reqId: sent.reqId, summary, bytes });
    expect(await p).toEqual({ summary, bytes });
  });

  it('rejects with the core\'s refusal, and for a file never loaded', async () => {
    const { client, w } = await loaded();
    const p = client.hexFile(opts, hex());
    const sent = w.of('hex-export')[0];
    const error = { code: 'degenerate', message: REFUSED, file: 'p1.csv' };
    w.emit({ type: 'error', reqId: sent.reqId, error });
    await expect(p).rejects.toEqual(error);
    await expect(client.hexFile({ ...opts, fileName: 'none.csv' }, hex())).rejects.toMatchObject({ code: 'not_loaded', file: 'none.csv' });
  });
});
