// The anatomical mesh's request through the worker protocol: what the worker hands the binding
// (the run's settings as the params JSON, the surface and its mesh, the layout, the format, the
// header), its answer, the core's refusal as a typed error that leaves the worker working, a
// malformed request refused before the binding sees it (wasm-bindgen's own throw would be taken
// for a crash), a core without the call; and the client's side (a copy of the mesh transferred,
// no run surface sent, resolved with the figures and the file, rejected with the core's error).
import { beforeEach, describe, expect, it } from 'vitest';
import {
  DEFAULT_OPTIONS, isFromWorker, isToWorker, runIdOf, transferablesOf, type AnatomicalExportRequest, type AnatomicalSummary, type FromWorker,
} from '../../../web/src/core-client/protocol';
import { malformedAnatomical } from '../../../web/src/core-client/workerCore';
import { FakeWorker, loadedClient, recordedCall, stubSession, workerFor } from './fakes';

const summary = { rings: 10, points: 16, vertices: 162, triangles: 320, septum_from: 'the RV contours\' centre (934)', volume_ml: 130.1 } as unknown as AnatomicalSummary;
const REFUSED = 'the anatomical mesh: degenerate input: the anatomical layout is the LV\'s (LV_ENDO, LV_EPI); RV_ENDO has no centre for its rays';

/** Just enough of a session: `anatomical_mesh` records its arguments and answers, or throws what it is told to. */
function fakeSession(throws: unknown = null, withCall = true) {
  const { call, calls } = recordedCall(() => ({ summary: JSON.stringify(summary), bytes: new TextEncoder().encode('# vtk DataFile Version 3.0\n') }), throws);
  return { session: stubSession(withCall ? { anatomical_mesh: call } : {}), calls };
}

function request(reqId = 7, over: Partial<AnatomicalExportRequest> = {}): AnatomicalExportRequest {
  return {
    type: 'anatomical-export',
    reqId,
    fileName: 'p1.csv',
    params: { beta: 0.2 },
    lids: 'auto',
    options: { ...DEFAULT_OPTIONS, align_slices: true },
    leaveOut: ['s07'],
    mesh: { surface: 'LV_ENDO', positions: new Float64Array([1, 2, 3]), indices: new Uint32Array([0, 0, 0]) },
    rings: 10,
    points: 16,
    format: 'vtk',
    header: ['heartmesh 0.1.0 (core 0.1.0), units: mm', 'lids: auto beta=0.2'],
    ...over,
  };
}

describe('the anatomical-export request', () => {
  it('belongs to the protocol; the mesh\'s two arrays are transferred, the answer\'s file too', () => {
    const r = request();
    expect(isToWorker(r)).toBe(true);
    expect(transferablesOf(r)).toEqual([r.mesh.positions.buffer, r.mesh.indices.buffer]);
    const answer: FromWorker = { type: 'anatomical-file', reqId: 7, summary, bytes: new Uint8Array(4) };
    expect(isFromWorker(answer)).toBe(true);
    expect(runIdOf(answer)).toBeUndefined();
    expect(transferablesOf(answer)).toHaveLength(1);
  });

  it('hands the binding the settings as the params JSON, the surface, its mesh, the layout, the format and the header', () => {
    const { session, calls } = fakeSession();
    const { core, out } = workerFor(session);
    const r = request();
    core.handle(r);
    expect(calls).toHaveLength(1);
    const [file, params, lids, surface, positions, indices, rings, points, format, header] = calls[0];
    expect([file, lids, surface, rings, points, format]).toEqual(['p1.csv', 'auto', 'LV_ENDO', 10, 16, 'vtk']);
    expect(JSON.parse(params as string)).toEqual({ beta: 0.2, ...DEFAULT_OPTIONS, align_slices: true, leave_out: ['s07'] });
    expect([positions, indices]).toEqual([r.mesh.positions, r.mesh.indices]);
    expect(header).toBe('heartmesh 0.1.0 (core 0.1.0), units: mm\nlids: auto beta=0.2');
    expect(out).toEqual([{ type: 'anatomical-file', reqId: 7, summary, bytes: new TextEncoder().encode('# vtk DataFile Version 3.0\n') }]);
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
    const bad: [Partial<AnatomicalExportRequest>, string][] = [
      [{ rings: 2.5 }, 'the layout must be two whole numbers (got 2.5x16)'],
      [{ points: -8 }, 'the layout must be two whole numbers (got 10x-8)'],
      [{ rings: '24' as unknown as number }, 'the layout must be two whole numbers (got 24x16)'],
      [{ mesh: { surface: 'LV_ENDO', positions: new Float32Array(3) as unknown as Float64Array, indices: new Uint32Array(3) } }, 'the mesh must be a Float64Array of positions and a Uint32Array of indices'],
      [{ mesh: undefined as unknown as AnatomicalExportRequest['mesh'] }, 'the request names no surface'],
      [{ header: undefined as unknown as string[] }, 'the request has no format or no header'],
    ];
    bad.forEach(([over, message], i) => {
      expect(malformedAnatomical(request(i, over))).toBe(message);
      core.handle(request(i, over));
      expect(out.at(-1)).toEqual({ type: 'error', reqId: i, error: { code: 'protocol', message: `the anatomical mesh: ${message}`, file: 'p1.csv' } });
    });
    expect(calls).toHaveLength(0);
    expect(malformedAnatomical(request())).toBeNull();
    core.handle(request(20));
    expect(out.at(-1)).toMatchObject({ type: 'anatomical-file', reqId: 20 });
  });

  it('a core without the call says so instead of crashing', () => {
    const { session } = fakeSession(null, false);
    const { core, out } = workerFor(session);
    core.handle(request(5));
    expect(out).toEqual([{ type: 'error', reqId: 5, error: { code: 'anatomical_unavailable', message: 'this core cannot build the anatomical mesh', file: 'p1.csv' } }]);
  });
});

describe('CoreClient.anatomicalFile', () => {
  beforeEach(() => {
    FakeWorker.instances = [];
  });

  const loaded = () => loadedClient('p1.csv', ['LV_ENDO', 'LV_EPI']);
  const opts = { fileName: 'p1.csv', surface: 'LV_ENDO', params: { beta: 0.2 }, lids: 'auto' as const, options: { ...DEFAULT_OPTIONS }, leaveOut: ['s07'] };
  const layout = () => ({
    mesh: { surface: 'LV_ENDO', positions: new Float64Array([1, 2, 3]), indices: new Uint32Array([0, 1, 2]) },
    rings: 10,
    points: 16,
    format: 'vtk' as const,
    header: ['a', 'b'],
  });

  it('posts a copy of the mesh with the run\'s settings (no run surface) and resolves with the figures and the file', async () => {
    const { client, w } = await loaded();
    const mine = layout();
    const p = client.anatomicalFile(opts, mine);
    const sent = w.of('anatomical-export')[0];
    expect(sent).toMatchObject({ fileName: 'p1.csv', params: { beta: 0.2 }, lids: 'auto', leaveOut: ['s07'], rings: 10, points: 16, format: 'vtk', header: ['a', 'b'] });
    expect('surface' in sent).toBe(false);
    expect(sent.mesh.surface).toBe('LV_ENDO');
    expect(sent.mesh.positions).toEqual(mine.mesh.positions);
    expect(sent.mesh.positions).not.toBe(mine.mesh.positions);
    expect(w.transfers.at(-1)).toHaveLength(2);
    const bytes = new Uint8Array([1, 2, 3]);
    w.emit({ type: 'anatomical-file', reqId: sent.reqId, summary, bytes });
    expect(await p).toEqual({ summary, bytes });
  });

  it('rejects with the core\'s refusal, and for a file never loaded', async () => {
    const { client, w } = await loaded();
    const p = client.anatomicalFile(opts, layout());
    const sent = w.of('anatomical-export')[0];
    const error = { code: 'degenerate', message: REFUSED, file: 'p1.csv' };
    w.emit({ type: 'error', reqId: sent.reqId, error });
    await expect(p).rejects.toEqual(error);
    await expect(client.anatomicalFile({ ...opts, fileName: 'none.csv' }, layout())).rejects.toMatchObject({ code: 'not_loaded', file: 'none.csv' });
  });
});
