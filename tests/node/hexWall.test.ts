// The LV wall as hexahedra in the wasm build against the native CLI's `heartmesh myocardium
// --hex-mesh`: biv-me patient 1 ED's LV_ENDO and LV_EPI reconstructed in wasm (the CLI's meshes:
// the same runs, as wall.test.ts has them) and fed to the binding's `Session.hex_wall` give the
// report's `hex_mesh` (every count equal, the volumes and the smallest scaled Jacobian to 1e-9)
// and, with no app header, the CLI's VTK unstructured grid: every line of text the same and every
// number (the points, the cells and their types, the transmural / longitudinal /
// circumferential_deg point data, the fibre and sheet vectors, the AHA segment per cell) to 1e-9
// (a few coordinates differ in the last digit: the
// binding takes the base plane from the file's contours, the command line from its
// reconstructions), at the default 24x48x3 and at --hex-layout 10x16 --layers 2. Through the
// worker's logic (the app's path: runs to 'done', their full-precision meshes, a 'hex-export'
// request) the same figures come back as a 'hex-file'. Refusals are the core's typed errors with
// its reason and leave the session usable: the SurFCo example (no RV landmarks or contours to lay
// the cells out from the septum by), 0 layers, a layout out of range; a malformed request is
// refused before wasm sees it.
import { beforeAll, describe, expect, it } from 'vitest';
import type { FromWorker, HexExportRequest, HexSummary, RunResult } from '../../web/src/core-client/protocol';
import { WorkerCore, wasmApiOf } from '../../web/src/core-client/workerCore';
import { PATIENT1_ED, SURFCO, cliHexWall, loadWasm, readBytes, reconstruct, thrownError } from './helpers.mjs';

type Wasm = typeof import('../../web/pkg/heartmesh_wasm.js');
type Session = InstanceType<Wasm['Session']>;
let wasm: Wasm;

/** What the CLI wrote at 24x48x3 (the defaults) and at 10x16x2: its report and the VTK text. */
// eslint-disable-next-line @typescript-eslint/no-explicit-any
let cli: { report: Record<string, any>; vtk: string };
// eslint-disable-next-line @typescript-eslint/no-explicit-any
let cliSmall: { report: Record<string, any>; vtk: string };

beforeAll(async () => {
  wasm = await loadWasm();
  const text = (o: { report: Record<string, unknown>; vtk: Uint8Array }) => ({ report: o.report, vtk: new TextDecoder().decode(o.vtk) });
  cli = text(cliHexWall(PATIENT1_ED(), [], 'p1-hex'));
  cliSmall = text(cliHexWall(PATIENT1_ED(), ['--hex-layout', '10x16', '--layers', '2'], 'p1-hex-small'));
});

type Mesh = { positions: Float64Array; indices: Uint32Array };

/** Runs `surface` of the file loaded in `session` to the end; its mesh in full precision. */
function run(session: Session, surface: string): Mesh {
  session.start('patient1-ED.csv', surface, '{}', 'auto');
  for (let guard = 0; guard < 100_000; guard++) if (JSON.parse(session.step()).done) break;
  return { positions: session.positions_f64(), indices: session.indices() };
}

function hexOf(session: Session, endo: Mesh, epi: Mesh, rings = 24, points = 48, layers = 3) {
  const out = session.hex_wall('patient1-ED.csv', '{}', 'auto', 'LV_ENDO', endo.positions, endo.indices, 'LV_EPI', epi.positions, epi.indices, rings, points, layers, '');
  return { summary: JSON.parse(out.summary) as HexSummary, bytes: out.bytes };
}

/**
 * A legacy VTK file's lines with every line of numbers (coordinates, fibre and sheet vectors,
 * point data, cells) replaced by how many numbers it holds, and those numbers in order: the
 * text must match exactly, the numbers to 1e-9 (integers such as cell indices then exactly).
 */
function vtkParts(text: string): { lines: string[]; points: number[] } {
  const lines: string[] = [];
  const points: number[] = [];
  for (const line of text.split('\n')) {
    const cells = line.trim().split(/\s+/);
    if (line.trim() !== '' && cells.every((c) => c !== '' && Number.isFinite(Number(c)))) {
      points.push(...cells.map(Number));
      lines.push(`#${cells.length}`);
    } else {
      lines.push(line);
    }
  }
  return { lines, points };
}

function expectClose(mine: number[], theirs: number[], tolerance = 1e-9): void {
  expect(mine).toHaveLength(theirs.length);
  mine.forEach((x, i) => expect(Math.abs(x - theirs[i]) / Math.max(Math.abs(theirs[i]), 1), `#${i}: ${x} vs ${theirs[i]}`).toBeLessThanOrEqual(tolerance));
}

const COUNTS = ['rings', 'points_per_ring', 'layers', 'points', 'hexahedra', 'wedges', 'inverted_cells'] as const;
const REALS = ['volume_ml', 'layouts_volume_ml', 'min_scaled_jacobian'] as const;

/** The summary against the report's `hex_mesh`: the same keys (but `file`), counts equal, the rest to 1e-9. */
// eslint-disable-next-line @typescript-eslint/no-explicit-any
function expectReport(s: HexSummary, hexMesh: Record<string, any>): void {
  const { file: _file, ...theirs } = hexMesh;
  expect(Object.keys(s).sort()).toEqual(Object.keys(theirs).sort());
  expect(COUNTS.map((k) => s[k])).toEqual(COUNTS.map((k) => theirs[k]));
  expectClose(REALS.map((k) => s[k]), REALS.map((k) => theirs[k]));
}

/** The file against the CLI's: every line the same but the points' coordinates, and those to 1e-9. */
function expectFile(bytes: Uint8Array, cliText: string, points: number): void {
  const mine = vtkParts(new TextDecoder().decode(bytes));
  const theirs = vtkParts(cliText);
  expect(mine.lines).toEqual(theirs.lines);
  expect(mine.lines).toContain(`POINTS ${points} double`);
  expectClose(mine.points, theirs.points);
}

describe('the hexahedral LV wall in wasm, against heartmesh myocardium --hex-mesh', () => {
  let session: Session;
  let endo: Mesh;
  let epi: Mesh;

  beforeAll(() => {
    session = new wasm.Session();
    session.load('patient1-ED.csv', readBytes(PATIENT1_ED()));
    endo = run(session, 'LV_ENDO');
    epi = run(session, 'LV_EPI');
  });

  it('patient 1 ED, 24x48x3: the report\'s hex_mesh (1e-9) and the CLI\'s VTK, the coordinates to 1e-9 and every other line the same', () => {
    const { summary: s, bytes } = hexOf(session, endo, epi);
    const r = cli.report;
    expect(r.hex_mesh.file).toBe('p1-hex-hex.vtk');
    expectReport(s, r.hex_mesh);
    // The layout's cells: per layer a wedge per point round the apex, a hexahedron per quad above.
    expect([s.rings, s.points_per_ring, s.layers, s.points, s.hexahedra, s.wedges, s.inverted_cells]).toEqual([24, 48, 3, 4612, 3312, 144, 0]);
    // A real LV wall, as the wall solid measures it (CLI: 99.5 ml), and cells that are not flat.
    expect(Math.abs(s.volume_ml - r.wall_volume_ml) / r.wall_volume_ml).toBeLessThan(0.03);
    expect(s.min_scaled_jacobian).toBeGreaterThan(0);
    expectFile(bytes, cli.vtk, 4612);
    const lines = cli.vtk.split('\n');
    expect(lines.slice(0, 5)).toEqual([
      '# vtk DataFile Version 3.0',
      'heartmesh 0.1.0 | LV myocardium hexahedra 24x48x3 of patient1-ED.csv (LV_ENDO + LV_EPI); units mm, the contour file\'s coordinates ...',
      'ASCII',
      'DATASET UNSTRUCTURED_GRID',
      'POINTS 4612 double',
    ]);
    expect(lines).toContain('CELL_TYPES 3456');
    for (const a of ['SCALARS transmural double 1', 'SCALARS longitudinal double 1', 'SCALARS circumferential_deg double 1', 'VECTORS fibre double', 'VECTORS sheet double', 'SCALARS aha_segment int 1']) expect(lines).toContain(a);
  });

  it('--hex-layout 10x16 --layers 2: the same figures and file', () => {
    const { summary: s, bytes } = hexOf(session, endo, epi, 10, 16, 2);
    expectReport(s, cliSmall.report.hex_mesh);
    expect([s.points, s.hexahedra, s.wedges]).toEqual([3 * (10 * 16 + 1), 2 * 9 * 16, 2 * 16]);
    expectFile(bytes, cliSmall.vtk, 3 * 161);
  });

  it('0 layers, 21 layers and a layout out of range are refused with the core\'s reason; the session goes on', () => {
    const zero = thrownError(() => hexOf(session, endo, epi, 24, 48, 0));
    expect(zero.code).toBe('param_invalid');
    expect(zero.message).toBe('the hexahedral wall: parameter layers: 1-20 layers through the wall (got 0)');
    expect(thrownError(() => hexOf(session, endo, epi, 24, 48, 21)).message).toMatch(/^the hexahedral wall: .*1-20 layers through the wall \(got 21\)$/);
    expect(thrownError(() => hexOf(session, endo, epi, 1, 48, 3)).message).toMatch(/^the hexahedral wall: .*2-200 rings of 8-720 points \(got 1x48\)/);
    expect(hexOf(session, endo, epi, 10, 16, 1).summary.hexahedra).toBe(9 * 16);
  });

  it('the SurFCo example is refused: nothing says where its septum is; the session goes on', () => {
    const { session: s } = reconstruct(wasm, SURFCO());
    const positions = s.positions_f64();
    const indices = s.indices();
    const e = thrownError(() => s.hex_wall('surfco-example.csv', '{}', 'auto', 'LV', positions, indices, 'LV', positions, indices, 24, 48, 3, ''));
    expect(e.message).toBe('the hexahedral wall: its cells are laid out from the septum: the file has no RV_INSERT landmarks and no RV contours');
    expect(s.positions_f64()).toHaveLength(positions.length);
  });
});

describe('the hexahedral LV wall through the worker\'s logic', () => {
  it('runs to done, then hex-export requests of their full-precision meshes: the CLI\'s figures; refusals and a malformed request are errors, the worker goes on', async () => {
    const results = new Map<number, RunResult>();
    const waiting = new Map<number, (m: FromWorker) => void>();
    const sent: FromWorker[] = [];
    const core: WorkerCore = new WorkerCore(
      wasmApiOf(wasm),
      (msg: FromWorker) => {
        sent.push(msg);
        if (msg.type === 'frame') setTimeout(() => core.handle({ type: 'ack', runId: msg.runId, seq: msg.seq }), 0);
        const id = msg.type === 'done' ? msg.result.runId : 'reqId' in msg ? msg.reqId : 'runId' in msg ? msg.runId : undefined;
        if (id !== undefined && (msg.type === 'done' || msg.type === 'error' || msg.type === 'loaded')) waiting.get(id)?.(msg);
      },
      { yieldToEventLoop: (cb) => setTimeout(cb, 0), now: () => performance.now() },
    );
    const answer = (id: number, send: () => void) => new Promise<FromWorker>((resolve) => {
      waiting.set(id, resolve);
      send();
    });
    await answer(1, () => core.handle({ type: 'load', reqId: 1, fileName: 'patient1-ED.csv', bytes: readBytes(PATIENT1_ED()).slice().buffer as ArrayBuffer }));
    for (const [runId, surface] of [[10, 'LV_ENDO'], [11, 'LV_EPI']] as const) {
      const m = await answer(runId, () => core.handle({ type: 'run', runId, fileName: 'patient1-ED.csv', surface, params: {}, lids: 'auto' }));
      if (m.type !== 'done') throw new Error(JSON.stringify(m));
      results.set(runId, m.result);
    }
    const [e, p] = [results.get(10)!, results.get(11)!];
    const request = (reqId: number, over: Partial<HexExportRequest> = {}): HexExportRequest => ({
      type: 'hex-export', reqId, fileName: 'patient1-ED.csv', params: {}, lids: 'auto',
      endo: { surface: 'LV_ENDO', positions: e.positionsF64!.slice(), indices: e.indices.slice() },
      epi: { surface: 'LV_EPI', positions: p.positionsF64!.slice(), indices: p.indices.slice() },
      rings: 24, points: 48, layers: 3, header: ['heartmesh test (core x), units: mm', 'input: patient1-ED.csv surface: LV_ENDO + LV_EPI'], ...over,
    });
    // Answered at once (no run in progress): the last message is the answer.
    core.handle(request(20));
    const m = sent.at(-1);
    if (m?.type !== 'hex-file') throw new Error(JSON.stringify(m));
    expect(m.reqId).toBe(20);
    expectReport(m.summary, cli.report.hex_mesh);
    const lines = new TextDecoder().decode(m.bytes).split('\n');
    expect(lines[1]).toMatch(/^heartmesh \S+ \| LV myocardium hexahedra 24x48x3 of patient1-ED\.csv \(LV_ENDO \+ LV_EPI\)/);
    expect(lines[3]).toBe('DATASET UNSTRUCTURED_GRID');

    core.handle(request(21, { layers: 0 }));
    expect(sent.at(-1)).toMatchObject({ type: 'error', reqId: 21, error: { code: 'param_invalid', message: 'the hexahedral wall: parameter layers: 1-20 layers through the wall (got 0)' } });
    core.handle(request(22, { layers: 2.5 }));
    expect(sent.at(-1)).toMatchObject({ type: 'error', reqId: 22, error: { code: 'protocol', message: 'the hexahedral wall: the layout and layers must be whole numbers (got 24x48x2.5)' } });
    core.handle(request(23, { epi: { surface: 'LV_EPI', positions: [1, 2, 3] as unknown as Float64Array, indices: new Uint32Array(3) } }));
    expect(sent.at(-1)).toMatchObject({ type: 'error', reqId: 23, error: { code: 'protocol', message: 'the hexahedral wall: the epicardium mesh must be a Float64Array of positions and a Uint32Array of indices' } });
    core.handle(request(24, { rings: 10, points: 16, layers: 2 }));
    const ok = sent.at(-1);
    if (ok?.type !== 'hex-file') throw new Error(JSON.stringify(ok));
    expect([ok.summary.points, ok.summary.hexahedra, ok.summary.wedges]).toEqual([483, 288, 32]);
  });
});
