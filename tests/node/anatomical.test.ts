// The anatomical mesh in the wasm build against the native CLI's `reconstruct --anatomical-mesh`:
// the CLI reconstructs biv-me patient 1 ED's LV_ENDO and writes the layout and its report; its
// finished mesh (read back from its OBJ) fed to the binding's `Session.anatomical_mesh` with the
// same (default) parameters gives the report's `anatomical_mesh` figures to 1e-9 and, with no app
// header, the CLI's VTK: every line the same but the vertices' coordinates, which agree to 1e-9
// (a few differ in the last digit: the binding takes the base plane from the file's contours
// (`clip_plane_from_contours`), the command line from its reconstruction (`basal_plane`)). The mesh
// of a wasm run of its own (the one the app holds) gives the same figures. Through the worker's
// logic (the app's path: an 'anatomical-export' request) the same figures come back, the app's
// header lines after the command line's comment. Refusals are the core's typed errors with its
// reason, and leave the session usable: the SurFCo example (no RV landmarks or contours to place
// the septum by), an RV_ENDO surface, a layout out of range; a malformed request is refused before
// wasm sees it.
import { beforeAll, describe, expect, it } from 'vitest';
import type { AnatomicalExportRequest, AnatomicalSummary, FromWorker } from '../../web/src/core-client/protocol';
import { WorkerCore, wasmApiOf } from '../../web/src/core-client/workerCore';
import { PATIENT1_ED, SURFCO, cliAnatomical, loadWasm, readBytes, readObj, reconstruct, thrownError } from './helpers.mjs';

type Wasm = typeof import('../../web/pkg/heartmesh_wasm.js');
let wasm: Wasm;

/** What the CLI wrote: its report's `anatomical_mesh`, the layout's VTK and the surface's OBJ. */
// eslint-disable-next-line @typescript-eslint/no-explicit-any
let cli: { summary: Record<string, any>; vtk: string; obj: string };

beforeAll(async () => {
  wasm = await loadWasm();
  const out = cliAnatomical(PATIENT1_ED(), ['--surface', 'LV_ENDO'], 'p1-anat');
  cli = { summary: out.report.anatomical_mesh, vtk: new TextDecoder().decode(out.grid), obj: out.obj };
});

/** The summary's numbers, flattened in a fixed order (directions and the apex by component). */
function numbers(s: AnatomicalSummary | Record<string, unknown>): number[] {
  const a = s as AnatomicalSummary;
  return [a.length_mm, a.volume_ml, a.surface_volume_ml, a.to_surface_mean_mm, a.to_surface_max_mm, ...a.septum_direction, ...a.anterior_direction, ...a.axis, ...a.apex];
}

/** A legacy VTK file's lines but its POINTS block's coordinates, and those coordinates. */
function vtkParts(text: string): { lines: string[]; points: number[] } {
  const all = text.split('\n');
  const at = all.findIndex((l) => l.startsWith('POINTS '));
  const n = Number(all[at].split(' ')[1]);
  const points: number[] = [];
  let end = at + 1;
  while (points.length < 3 * n) points.push(...all[end++].trim().split(/\s+/).map(Number));
  return { lines: [...all.slice(0, at + 1), ...all.slice(end)], points };
}

function expectClose(mine: number[], theirs: number[], tolerance = 1e-9): void {
  expect(mine).toHaveLength(theirs.length);
  mine.forEach((x, i) => expect(Math.abs(x - theirs[i]) / Math.max(Math.abs(theirs[i]), 1), `#${i}: ${x} vs ${theirs[i]}`).toBeLessThanOrEqual(tolerance));
}

describe('the anatomical mesh in wasm, against reconstruct --anatomical-mesh', () => {
  it('patient 1 ED LV_ENDO: the CLI report\'s figures (1e-9) and its VTK, the coordinates to 1e-9 and every other line the same', () => {
    const session = new wasm.Session();
    session.load('patient1-ED.csv', readBytes(PATIENT1_ED()));
    const mesh = readObj(cli.obj);
    const out = session.anatomical_mesh('patient1-ED.csv', '{}', 'auto', 'LV_ENDO', mesh.positions, mesh.indices, 24, 48, 'vtk', '');
    const s = JSON.parse(out.summary) as AnatomicalSummary;
    const { file, ...theirs } = cli.summary;
    expect(file).toBe('p1-anat-grid.vtk');
    expect(Object.keys(s).sort()).toEqual(Object.keys(theirs).sort());
    expect([s.rings, s.points, s.vertices, s.triangles, s.septum_from]).toEqual([theirs.rings, theirs.points, theirs.vertices, theirs.triangles, theirs.septum_from]);
    expect([s.rings, s.points, s.vertices]).toEqual([24, 48, 1154]);
    expect(s.septum_from).toMatch(/^the RV contours' centre \(\d+\)$/);
    expectClose(numbers(s), numbers(theirs));
    // A real LV cavity, and the grid close to the surface it samples.
    expect(s.volume_ml).toBeGreaterThan(80);
    expect(s.volume_ml).toBeLessThan(250);
    expect(s.to_surface_mean_mm).toBeLessThan(0.5);
    const mine = vtkParts(new TextDecoder().decode(out.bytes));
    const cliVtk = vtkParts(cli.vtk);
    expect(mine.lines).toEqual(cliVtk.lines);
    expect(mine.points).toHaveLength(3 * 1154);
    expectClose(mine.points, cliVtk.points);
    expect(cliVtk.lines.slice(0, 5)).toEqual([
      '# vtk DataFile Version 3.0',
      'heartmesh 0.1.0 | anatomical layout 24x48 of LV_ENDO reconstructed from patient1-ED.csv; units mm, the contour file\'s coordinates ...',
      'ASCII',
      'DATASET POLYDATA',
      'POINTS 1154 double',
    ]);
  });

  it('a wasm run\'s own LV_ENDO mesh (the app\'s) gives the same figures (1e-9)', () => {
    const { session } = reconstruct(wasm, PATIENT1_ED(), { surface: 'LV_ENDO' });
    const out = session.anatomical_mesh('patient1-ED.csv', '{}', 'auto', 'LV_ENDO', session.positions_f64(), session.indices(), 24, 48, 'vtk', '');
    const s = JSON.parse(out.summary) as AnatomicalSummary;
    expect([s.vertices, s.septum_from]).toEqual([cli.summary.vertices, cli.summary.septum_from]);
    expectClose(numbers(s), numbers(cli.summary));
  });

  it('the SurFCo example is refused: nothing says where its septum is; the session goes on', () => {
    const { session } = reconstruct(wasm, SURFCO());
    const positions = session.positions_f64();
    const indices = session.indices();
    const e = thrownError(() => session.anatomical_mesh('surfco-example.csv', '{}', 'auto', 'LV', positions, indices, 24, 48, 'vtk', ''));
    expect(e.message).toMatch(/^the anatomical mesh: /);
    expect(e.message).toMatch(/^the anatomical mesh: the anatomical layout starts at the septum, and the file has no RV_INSERT landmarks and no RV contours to place it by$/);
    expect(session.positions_f64()).toHaveLength(positions.length);
  });

  it('an RV_ENDO surface and a layout out of range are refused with the core\'s reason', () => {
    const session = new wasm.Session();
    session.load('patient1-ED.csv', readBytes(PATIENT1_ED()));
    const mesh = readObj(cli.obj);
    const rv = thrownError(() => session.anatomical_mesh('patient1-ED.csv', '{}', 'auto', 'RV_ENDO', mesh.positions, mesh.indices, 24, 48, 'vtk', ''));
    expect(rv.message).toMatch(/^the anatomical mesh: /);
    expect(rv.message).toMatch(/^the anatomical mesh: the anatomical layout is the LV's \(LV_ENDO, LV_EPI\); RV_ENDO has no centre for its rays$/);
    const range = thrownError(() => session.anatomical_mesh('patient1-ED.csv', '{}', 'auto', 'LV_ENDO', mesh.positions, mesh.indices, 1, 48, 'vtk', ''));
    expect(range.message).toMatch(/^the anatomical mesh: .*the anatomical layout must have 2-200 rings of 8-720 points \(got 1x48\)/);
    // Still usable: the next call builds.
    const out = session.anatomical_mesh('patient1-ED.csv', '{}', 'auto', 'LV_ENDO', mesh.positions, mesh.indices, 10, 16, 'obj', '');
    expect(JSON.parse(out.summary).vertices).toBe(162);
  });
});

describe('through the worker (the app\'s path)', () => {
  function worker() {
    const sent: FromWorker[] = [];
    const core = new WorkerCore(wasmApiOf(wasm), (m) => sent.push(m), { yieldToEventLoop: (cb) => setTimeout(cb, 0), now: () => performance.now() });
    core.handle({ type: 'load', reqId: 1, fileName: 'patient1-ED.csv', bytes: readBytes(PATIENT1_ED()).buffer as ArrayBuffer });
    expect(sent.at(-1)?.type).toBe('loaded');
    return { core, sent };
  }

  function request(reqId: number, surface: string, extra: Partial<AnatomicalExportRequest> = {}): AnatomicalExportRequest {
    const mesh = readObj(cli.obj);
    return {
      type: 'anatomical-export', reqId, fileName: 'patient1-ED.csv', params: {}, lids: 'auto',
      mesh: { surface, positions: mesh.positions, indices: mesh.indices }, rings: 24, points: 48, format: 'vtk',
      header: ['heartmesh test (core x), units: mm', 'input: patient1-ED.csv surface: LV_ENDO'], ...extra,
    };
  }

  it('an anatomical-export request: the CLI\'s figures, the app\'s header after the command line\'s comment', () => {
    const { core, sent } = worker();
    core.handle(request(2, 'LV_ENDO', { format: 'obj' }));
    const reply = sent.at(-1);
    if (reply?.type !== 'anatomical-file') throw new Error(`got ${JSON.stringify(reply)}`);
    expect(reply.reqId).toBe(2);
    const { file: _file, ...theirs } = cli.summary;
    expectClose(numbers(reply.summary), numbers(theirs));
    const lines = new TextDecoder().decode(reply.bytes).split('\n');
    expect(lines[1]).toMatch(/^# anatomical layout 24x48 of LV_ENDO reconstructed from patient1-ED\.csv/);
    const comments = lines.filter((l) => l.startsWith('#'));
    expect(comments).toContain('# heartmesh test (core x), units: mm');
    expect(lines.filter((l) => l.startsWith('v '))).toHaveLength(1154);
  });

  it('refusals and a malformed request are errors; the worker goes on', () => {
    const { core, sent } = worker();
    core.handle(request(3, 'RV_ENDO'));
    const rv = sent.at(-1);
    expect(rv).toMatchObject({ type: 'error', reqId: 3, error: { message: expect.stringMatching(/^the anatomical mesh: .*the anatomical layout is the LV's/) } });
    core.handle({ ...request(4, 'LV_ENDO'), rings: 2.5 });
    expect(sent.at(-1)).toMatchObject({ type: 'error', reqId: 4, error: { code: 'protocol', message: 'the anatomical mesh: the layout must be two whole numbers (got 2.5x48)' } });
    core.handle({ ...request(5, 'LV_ENDO'), mesh: { surface: 'LV_ENDO', positions: [1, 2, 3] as unknown as Float64Array, indices: new Uint32Array(3) } });
    expect(sent.at(-1)).toMatchObject({ type: 'error', reqId: 5, error: { code: 'protocol' } });
    core.handle(request(6, 'LV_ENDO', { rings: 10, points: 16 }));
    const ok = sent.at(-1);
    expect(ok?.type).toBe('anatomical-file');
    if (ok?.type === 'anatomical-file') expect(ok.summary.vertices).toBe(162);
  });
});
