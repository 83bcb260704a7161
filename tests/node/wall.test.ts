// The LV wall in the wasm build against the native CLI's `heartmesh myocardium`: biv-me patient 1
// ED's LV_ENDO and LV_EPI reconstructed in wasm, then joined by the binding's `Session.wall`, give
// the CLI's wall: the same vertex and triangle counts, regions and moved vertices, and the same
// volumes, mass, thickness and base plane to 1e-9 relative; the OBJ the same groups and faces as the
// CLI's file, its vertices to 1e-9; patient 2 ED's one endocardial vertex moved under the
// epicardium is moved alike. Through the worker's logic (the app's path: runs to 'done',
// their full-precision meshes, a 'wall-export' request) the VTK holds one region per triangle and
// the thickness per vertex; from the display's f32 meshes the figures still agree to 1e-6. A wall
// the core cannot build is a typed error that leaves the session usable. The AHA segments are the
// CLI report's (each segment's mean, min, max and area to 1e-9, the septum placed from the same
// source), the bullseye SVG the file `--bullseye` writes but for its title line, and patient 1's
// basal anteroseptal wall is thicker than its basal anterolateral wall, as the CLI has it; a file
// without RV contours gets no segments and the CLI report's note instead.
import { beforeAll, describe, expect, it } from 'vitest';
import type { FromWorker, RunResult, WallSummary } from '../../web/src/core-client/protocol';
import { WorkerCore, wasmApiOf } from '../../web/src/core-client/workerCore';
import { PATIENT1_ED, PATIENT2_ES, cliMyocardium, loadWasm, readBytes, readText, thrownError, writeScratch } from './helpers.mjs';

type Wasm = typeof import('../../web/pkg/heartmesh_wasm.js');
type Session = InstanceType<Wasm['Session']>;
let wasm: Wasm;

// eslint-disable-next-line @typescript-eslint/no-explicit-any
let cli: { report: Record<string, any>; obj: string; bullseye?: string };
const PATIENT2_ED = () => PATIENT2_ES().replace('patient2-ES.csv', 'patient2-ED.csv');

beforeAll(async () => {
  wasm = await loadWasm();
  cli = cliMyocardium(PATIENT1_ED(), [], 'p1-wall', { bullseye: true });
});

function relative(a: number, b: number): number {
  return Math.abs(a - b) / Math.max(Math.abs(b), 1e-12);
}

/** Runs `surface` of the loaded file (`file`) to the end; its mesh in full precision. */
function run(session: Session, surface: string, file = 'patient1-ED.csv'): { positions: Float64Array; positions32: Float32Array; indices: Uint32Array } {
  session.start(file, surface, '{}', 'auto');
  for (let guard = 0; guard < 100_000; guard++) if (JSON.parse(session.step()).done) break;
  return { positions: session.positions_f64(), positions32: session.positions(), indices: session.indices() };
}

function wallOf(session: Session, endo: ReturnType<typeof run>, epi: ReturnType<typeof run>, format = 'obj', f32 = false, file = 'patient1-ED.csv') {
  const p = (m: ReturnType<typeof run>) => (f32 ? Float64Array.from(m.positions32) : m.positions);
  const out = session.wall(file, '{}', 'auto', 'LV_ENDO', p(endo), endo.indices, 'LV_EPI', p(epi), epi.indices, 1, format, '');
  return { summary: JSON.parse(out.summary) as WallSummary, bytes: out.bytes };
}

/** The OBJ's lines by kind. */
function objParts(text: string) {
  const lines = text.split('\n');
  return {
    comments: lines.filter((l) => l.startsWith('#')),
    vertices: lines.filter((l) => l.startsWith('v ')).flatMap((l) => l.slice(2).split(' ').map(Number)),
    structure: lines.filter((l) => l.startsWith('f ') || l.startsWith('g ')),
  };
}

describe('the LV wall in wasm, against heartmesh myocardium', () => {
  let session: Session;
  let endo: ReturnType<typeof run>;
  let epi: ReturnType<typeof run>;

  beforeAll(() => {
    session = new wasm.Session();
    session.load('patient1-ED.csv', readBytes(PATIENT1_ED()));
    endo = run(session, 'LV_ENDO');
    epi = run(session, 'LV_EPI');
  });

  it('patient 1 ED: the same solid and figures as the CLI (1e-9)', () => {
    const { summary: s, bytes } = wallOf(session, endo, epi);
    const r = cli.report;
    expect([s.vertices, s.triangles]).toEqual([r.vertices, r.triangles]);
    expect(r.vertices).toBeGreaterThan(1000);
    expect(s.regions).toEqual(r.regions);
    expect(s.endocardium_moved.vertices).toBe(r.endocardium_moved.vertices);
    expect(s.endocardium_moved.min_thickness_mm).toBe(1);
    expect(s.epicardium_moved.vertices).toBe(r.epicardium_moved.vertices);
    expect(s.thickness_mm.count).toBe(r.vertices);
    expect(s.endo_epi_crossings).toBe(r.endo_epi_crossings);
    expect(s.folded_edges).toBe(r.quality.folded_edges);
    for (const [mine, theirs] of [
      [s.wall_volume_ml, r.wall_volume_ml],
      [s.myocardial_mass_g, r.myocardial_mass_g],
      [s.cavity_volume_ml, r.cavity_volume_ml],
      [s.thickness_mm.mean, r.thickness_mm.mean],
      [s.thickness_mm.median, r.thickness_mm.median],
      [s.thickness_mm.min, r.thickness_mm.min],
      [s.thickness_mm.max, r.thickness_mm.max],
      ...s.base_plane.origin.map((x, i) => [x, r.base_plane.origin[i]]),
      ...s.base_plane.normal.map((x, i) => [x, r.base_plane.normal[i]]),
    ]) {
      expect(relative(mine, theirs), `${mine} vs ${theirs}`).toBeLessThanOrEqual(1e-9);
    }
    // Sanity of the figures themselves: a real LV wall (CLI: 99.5 ml, 104.5 g, cavity 135.0 ml).
    expect(s.wall_volume_ml).toBeGreaterThan(50);
    expect(s.wall_volume_ml).toBeLessThan(200);
    expect(relative(s.myocardial_mass_g, 1.05 * s.wall_volume_ml)).toBeLessThan(1e-12);

    // The file: the CLI's comment, groups and faces; vertices to 1e-9.
    const mine = objParts(new TextDecoder().decode(bytes));
    const theirs = objParts(cli.obj);
    expect(mine.comments).toEqual(theirs.comments);
    expect(mine.structure).toEqual(theirs.structure);
    expect(mine.structure.filter((l) => l.startsWith('g '))).toEqual(['g epicardium', 'g endocardium', 'g base']);
    expect(mine.vertices.length).toBe(theirs.vertices.length);
    let worst = 0;
    mine.vertices.forEach((x, i) => (worst = Math.max(worst, Math.abs(x - theirs.vertices[i]) / Math.max(Math.abs(theirs.vertices[i]), 1))));
    expect(worst).toBeLessThanOrEqual(1e-9);
  });

  it('patient 2 ED: the endocardial vertex the CLI moves under the epicardium is moved alike', () => {
    const theirs = cliMyocardium(PATIENT2_ED(), [], 'p2-wall').report;
    const s2 = new wasm.Session();
    s2.load('patient2-ED.csv', readBytes(PATIENT2_ED()));
    const e2 = run(s2, 'LV_ENDO', 'patient2-ED.csv');
    const p2 = run(s2, 'LV_EPI', 'patient2-ED.csv');
    const { summary: s } = wallOf(s2, e2, p2, 'ply', false, 'patient2-ED.csv');
    expect(theirs.endocardium_moved.vertices).toBe(1);
    expect(s.endocardium_moved.vertices).toBe(1);
    expect(relative(s.endocardium_moved.max_mm, theirs.endocardium_moved.max_mm)).toBeLessThanOrEqual(1e-9);
    expect(s.epicardium_moved.vertices).toBe(theirs.epicardium_moved.vertices);
    expect([s.vertices, s.triangles]).toEqual([theirs.vertices, theirs.triangles]);
    expect(relative(s.wall_volume_ml, theirs.wall_volume_ml)).toBeLessThanOrEqual(1e-9);
    expect(relative(s.cavity_volume_ml, theirs.cavity_volume_ml)).toBeLessThanOrEqual(1e-9);
  });

  it('patient 1 ED: the AHA segments are the CLI report\'s (1e-9), the bullseye its --bullseye file but for the title line', () => {
    const { summary: s } = wallOf(session, endo, epi, 'ply');
    const theirs = cli.report.segments;
    const mine = s.segments;
    if (!mine) throw new Error(`no segments: ${s.segments_note}`);
    expect(s.segments_note).toBeUndefined();
    expect(mine.septum_from).toBe(theirs.septum_from);
    expect(mine.septum_from).toMatch(/^the RV contours' centre \(\d+\)$/);
    expect(mine.segments.map((g) => [g.id, g.name])).toEqual(theirs.segments.map((g: { id: number; name: string }) => [g.id, g.name]));
    expect(mine.segments).toHaveLength(17);
    for (const [k, g] of mine.segments.entries()) {
      const t = theirs.segments[k];
      for (const f of ['mean_mm', 'min_mm', 'max_mm', 'area_mm2'] as const) {
        expect(g[f], `segment ${g.id} ${f}`).not.toBeNull();
        expect(relative(g[f]!, t[f]), `segment ${g.id} ${f}: ${g[f]} vs ${t[f]}`).toBeLessThanOrEqual(1e-9);
      }
    }
    // The frame they were placed in (the base's depth, 0, compared absolutely).
    const ours = [...mine.septum_direction, ...mine.anterior_direction, ...mine.axis, ...mine.level_depths_mm];
    const cliFrame = [...theirs.septum_direction, ...theirs.anterior_direction, ...theirs.axis, ...theirs.level_depths_mm];
    expect(ours).toHaveLength(cliFrame.length);
    ours.forEach((x, i) => expect(Math.abs(x - cliFrame[i]) / Math.max(Math.abs(cliFrame[i]), 1), `frame ${i}`).toBeLessThanOrEqual(1e-9));

    // The drawing: the CLI's file line for line, but for the subtitle naming the input (the CLI
    // gives its path's base name, the app the file's name: here both patient1-ED.csv).
    const svg = s.bullseye_svg!;
    const file = cli.bullseye!;
    const isTitle = (l: string) => l.includes('(LV_ENDO + LV_EPI)</text>');
    const [a, b] = [svg.split('\n'), file.split('\n')];
    expect(a.filter(isTitle)).toEqual(['<text x="230" y="40" text-anchor="middle" font-size="12" fill="#444">patient1-ED.csv (LV_ENDO + LV_EPI)</text>']);
    expect(b.filter(isTitle)).toHaveLength(1);
    expect(b.filter(isTitle)[0]).toMatch(/>patient1-ED\.csv \(LV_ENDO \+ LV_EPI\)<\/text>$/);
    expect(a.findIndex(isTitle)).toBe(b.findIndex(isTitle));
    expect(a.filter((l) => !isTitle(l))).toEqual(b.filter((l) => !isTitle(l)));
    expect(a.length).toBeGreaterThan(40);
    expect(svg).toMatch(/^<svg xmlns="http:\/\/www\.w3\.org\/2000\/svg" width="460" height="530" viewBox="0 0 460 530"/);
    expect(svg.match(/<path /g)).toHaveLength(17);
  });

  it('patient 1 ED: the basal anteroseptal wall (segment 2) is thicker than the basal anterolateral (6), as the CLI has it', () => {
    const mean = (segs: { id: number; mean_mm: number | null }[], id: number) => segs.find((g) => g.id === id)!.mean_mm!;
    const theirs = cli.report.segments.segments;
    // The command line's figures first: the ordering asserted is the data's.
    expect(mean(theirs, 2)).toBeGreaterThan(mean(theirs, 6));
    const mine = wallOf(session, endo, epi, 'stl').summary.segments!.segments;
    expect(mean(mine, 2)).toBeGreaterThan(mean(mine, 6));
    // The septum is the thickest of the basal ring here (12.3 mm against 6.0 to 8.8 mm).
    expect(Math.max(...mine.slice(0, 6).map((g) => g.mean_mm!))).toBe(mean(mine, 2));
  });

  it('a file without RV contours: no segments, and the CLI report\'s reason', () => {
    const lines = readText(PATIENT1_ED()).split('\n');
    const lvOnly = [lines[0], ...lines.slice(1).filter((l) => /,LV_(ENDO|EPI)\s*$/.test(l))];
    expect(lvOnly.length).toBeGreaterThan(800);
    const path = writeScratch('patient1-ED-lv-only.csv', `${lvOnly.join('\n')}\n`);
    const theirs = cliMyocardium(path, [], 'p1-lv-only').report;
    expect(theirs.segments).toBeNull();
    expect(theirs.segments_note).toMatch(/no RV_INSERT landmarks and no RV contours/);
    const s3 = new wasm.Session();
    s3.load('patient1-ED-lv-only.csv', readBytes(path));
    const e3 = run(s3, 'LV_ENDO', 'patient1-ED-lv-only.csv');
    const p3 = run(s3, 'LV_EPI', 'patient1-ED-lv-only.csv');
    const { summary: s } = wallOf(s3, e3, p3, 'obj', false, 'patient1-ED-lv-only.csv');
    expect(s.segments).toBeNull();
    expect(s.segments_note).toBe(theirs.segments_note);
    expect(s.bullseye_svg).toBeUndefined();
    // The wall itself is built all the same.
    expect(relative(s.wall_volume_ml, theirs.wall_volume_ml)).toBeLessThanOrEqual(1e-9);
  });

  it('from the display\'s f32 meshes the figures agree to 1e-6', () => {
    const { summary: s } = wallOf(session, endo, epi, 'stl', true);
    const r = cli.report;
    expect([s.vertices, s.triangles]).toEqual([r.vertices, r.triangles]);
    expect(relative(s.wall_volume_ml, r.wall_volume_ml)).toBeLessThan(1e-6);
    expect(relative(s.cavity_volume_ml, r.cavity_volume_ml)).toBeLessThan(1e-6);
  });

  it('a wall the core cannot build is a typed error; the session goes on', () => {
    const lifted = { ...epi, positions: epi.positions.map((x, i) => (i % 3 === 2 ? x + 300 : x)) };
    // A plane in another place entirely: whichever surface it misses, it says so.
    const e = thrownError(() => wallOf(session, endo, lifted));
    expect(e.code).toBe('degenerate');
    expect(e.message).toMatch(/^the LV wall: degenerate input: the base plane does not cut the epicardium/);
    const bad = thrownError(() => session.wall('patient1-ED.csv', '{}', 'auto', 'LV_ENDO', endo.positions, endo.indices.slice(1), 'LV_EPI', epi.positions, epi.indices, 1, 'obj', ''));
    expect(bad.code).toBe('invalid_mesh');
    expect(bad.message).toMatch(/the LV_ENDO mesh: .* not whole vertices and triangles/);
    expect(thrownError(() => session.wall('other.csv', '{}', 'auto', 'LV_ENDO', endo.positions, endo.indices, 'LV_EPI', epi.positions, epi.indices, 1, 'obj', '')).code).toBe('not_loaded');
    expect(thrownError(() => wallOf(session, endo, epi, 'gltf')).code).toBe('param_invalid');
    expect(wallOf(session, endo, epi).summary.triangles).toBe(cli.report.triangles);
  });
});

describe('the LV wall through the worker\'s logic', () => {
  it('runs to done, then a wall-export of their full-precision meshes: the VTK has a region per triangle and a thickness per vertex', async () => {
    const results = new Map<number, RunResult>();
    const waiting = new Map<number, (m: FromWorker) => void>();
    const core: WorkerCore = new WorkerCore(
      wasmApiOf(wasm),
      (msg: FromWorker) => {
        if (msg.type === 'frame') setTimeout(() => core.handle({ type: 'ack', runId: msg.runId, seq: msg.seq }), 0);
        const id = msg.type === 'done' ? msg.result.runId : 'reqId' in msg ? msg.reqId : 'runId' in msg ? msg.runId : undefined;
        if (id !== undefined && (msg.type === 'done' || msg.type === 'error' || msg.type === 'wall-file' || msg.type === 'loaded')) waiting.get(id)?.(msg);
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
    expect(e.positionsF64).toBeInstanceOf(Float64Array);
    expect(e.positionsF64!.length).toBe(e.positions.length);
    const m = await answer(20, () =>
      core.handle({
        type: 'wall-export', reqId: 20, fileName: 'patient1-ED.csv', params: {}, lids: 'auto',
        endo: { surface: 'LV_ENDO', positions: e.positionsF64!, indices: e.indices },
        epi: { surface: 'LV_EPI', positions: p.positionsF64!, indices: p.indices },
        minThicknessMm: 1, format: 'vtk', header: ['heartmesh test'],
      }),
    );
    if (m.type !== 'wall-file') throw new Error(JSON.stringify(m));
    const r = cli.report;
    expect(relative(m.summary.wall_volume_ml, r.wall_volume_ml)).toBeLessThanOrEqual(1e-9);
    const text = new TextDecoder().decode(m.bytes);
    // The legacy VTK's one title line holds the command line's comment (cut at 160 characters).
    expect(text.split('\n')[1]).toMatch(/^heartmesh \S+ \| LV myocardium wall of patient1-ED\.csv \(LV_ENDO \+ LV_EPI\); units mm/);
    const lines = text.split('\n');
    const cells = lines.findIndex((l) => l.startsWith('CELL_DATA'));
    expect(lines[cells]).toBe(`CELL_DATA ${r.triangles}`);
    expect(lines[cells + 1]).toBe('SCALARS region int 1');
    const regions = lines.slice(cells + 3, cells + 3 + r.triangles).map(Number);
    expect(regions.every((v) => v >= 1 && v <= 3)).toBe(true);
    expect([1, 2, 3].map((k) => regions.filter((v) => v === k).length)).toEqual(r.regions.map((x: { triangles: number }) => x.triangles));
    expect(text).toContain(`POINT_DATA ${r.vertices}`);
    expect(text).toMatch(/SCALARS thickness (double|float) 1/);
  });
});
