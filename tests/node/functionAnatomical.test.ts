// The study's anatomical meshes (the app's Function panel, "Anatomical meshes") in the wasm build
// against the native CLI's `heartmesh volumes --anatomical-meshes` on the same files: after the
// phases batch of biv-me patient 1's ED and ES, the Lab's `phases_anatomical` gives the CLI's four
// layouts, its report's septum and figures (1e-9), and the ED LV_ENDO file's vertices to 1e-9 (every
// other line of the VTK the same); through the worker's logic (the app's path: a
// 'lab-phases-anatomical' request after the 'lab-batch'), the same report and files, the bytes
// transferred. Refusals are the core's errors, with its reason, and leave the worker usable: no
// finished batch yet, a study of the SurFCo example (no RV to place the septum by), a malformed
// request.
import { beforeAll, describe, expect, it } from 'vitest';
import type { AnatomicalStudyReport, FromWorker, LabProgress } from '../../web/src/core-client/protocol';
import { WorkerCore, wasmApiOf } from '../../web/src/core-client/workerCore';
import { PATIENT1_ED, SURFCO, cliVolumes, loadWasm, readBytes, readText, writeScratch } from './helpers.mjs';

type Wasm = typeof import('../../web/pkg/heartmesh_wasm.js');
let wasm: Wasm;
const ED = () => PATIENT1_ED();
const ES = () => PATIENT1_ED().replace('patient1-ED.csv', 'patient1-ES.csv');

/** What the CLI wrote: its JSON's `anatomical_meshes` and the folder of files. */
// eslint-disable-next-line @typescript-eslint/no-explicit-any
let cli: { report: Record<string, any>; dir: string };

beforeAll(async () => {
  wasm = await loadWasm();
  // A folder of the scratch folder (the CLI makes it).
  const dir = writeScratch('p1-study.placeholder', '').replace(/[^/\\]+$/, 'p1-study-meshes');
  cli = { report: cliVolumes([ED(), ES()], ['--anatomical-meshes', dir], 'p1-study').anatomical_meshes, dir };
});

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

/** Runs the Lab's batch to its end. */
function drain(lab: InstanceType<Wasm['Lab']>): void {
  for (let guard = 0; guard < 1_000_000; guard++) {
    const p = JSON.parse(lab.batch_step()) as LabProgress & { done: boolean };
    if (p.done) return;
  }
  throw new Error('the batch does not finish');
}

/** The report against the CLI's: files, septum, every layout's figures (1e-9). */
function expectCliReport(r: AnatomicalStudyReport): void {
  const { files, ...rest } = r;
  expect(Object.keys(rest).sort()).toEqual(Object.keys(cli.report).filter((k) => k !== 'directory').sort());
  expect([r.format, r.layout, r.displacement_from_phase]).toEqual([cli.report.format, cli.report.layout, cli.report.displacement_from_phase]);
  expect([r.septum.phase, r.septum.surface, r.septum.source]).toEqual([cli.report.septum.phase, cli.report.septum.surface, cli.report.septum.source]);
  expectClose(r.septum.direction, cli.report.septum.direction);
  expect(r.layouts).toHaveLength(4);
  expect(files.map((f) => f.name)).toEqual(cli.report.layouts.map((l: { file: string }) => l.file));
  r.layouts.forEach((l, i) => {
    const want = cli.report.layouts[i];
    expect([l.phase, l.surface, l.file]).toEqual([want.phase, want.surface, want.file]);
    expect(typeof l.septum_turn_deg).toBe('number');
    expectClose([l.septum_turn_deg as number, l.displacement_mean_mm as number, l.displacement_max_mm as number], [want.septum_turn_deg, want.displacement_mean_mm, want.displacement_max_mm]);
    expect(l.summary?.vertices).toBe(1154);
    expectClose([l.summary?.volume_ml as number, l.summary?.to_surface_mean_mm as number], [want.summary.volume_ml, want.summary.to_surface_mean_mm]);
  });
}

/** The ED LV_ENDO file against the CLI's: its coordinates to 1e-9, every other line the same. */
function expectCliVtk(bytes: Uint8Array, name: string): void {
  const mine = vtkParts(new TextDecoder().decode(bytes));
  const theirs = vtkParts(readText(`${cli.dir}/${name}`));
  expect(mine.points).toHaveLength(3 * 1154);
  expectClose(mine.points, theirs.points);
  expect(mine.lines).toEqual(theirs.lines);
  expect(mine.lines.some((l) => l.startsWith('SCALARS displacement_mm') || l.startsWith('displacement_mm'))).toBe(true);
}

describe('the anatomical meshes of a study, against volumes --anatomical-meshes', () => {
  it('patient 1 ED + ES: the CLI\'s four layouts, its figures (1e-9) and the ED LV_ENDO file (vertices 1e-9)', () => {
    const session = new wasm.Session();
    session.load('patient1-ED.csv', readBytes(ED()));
    session.load('patient1-ES.csv', readBytes(ES()));
    const lab = new wasm.Lab();
    const phases = [
      { name: 'patient1-ED', file: 'patient1-ED.csv' },
      { name: 'patient1-ES', file: 'patient1-ES.csv' },
    ];
    lab.start_phases(session, JSON.stringify(phases), '{}', 'auto', new Uint8Array(0), [], []);
    drain(lab);
    const r = JSON.parse(lab.phases_anatomical('24x48', 'vtk')) as AnatomicalStudyReport;
    expectCliReport(r);
    expect(r.septum.phase).toBe('patient1-ED');
    const es = r.layouts.find((l) => l.phase === 'patient1-ES' && l.surface === 'LV_ENDO');
    // The LV contracts: ~12.6 mm mean displacement of the endocardium from ED (CLI: the same).
    expect(es?.displacement_mean_mm).toBeGreaterThan(5);
    expect(es?.displacement_mean_mm).toBeLessThan(20);
    const k = r.files.findIndex((f) => f.name === 'patient1-ED-LV_ENDO.vtk');
    expect(k).toBeGreaterThanOrEqual(0);
    expectCliVtk(lab.phases_anatomical_file(k), 'patient1-ED-LV_ENDO.vtk');
  });

  it('through the worker: the same report and files, refusals as the core\'s errors, the worker going on', async () => {
    const inbox: FromWorker[] = [];
    const core = new WorkerCore(wasmApiOf(wasm), (m) => inbox.push(m), { yieldToEventLoop: (cb) => setTimeout(cb, 0), now: () => performance.now() });
    const ask = (reqId: number, rings: unknown, points: unknown, format: unknown) => {
      core.handle({ type: 'lab-phases-anatomical', reqId, rings: rings as number, points: points as number, format: format as 'vtk' });
      return inbox.find((m) => (m.type === 'lab-phases-anatomical' || m.type === 'error') && m.reqId === reqId);
    };
    const errorOf = (m: FromWorker | undefined) => (m?.type === 'error' ? m.error : null);
    // Before any batch: refused, saying why.
    expect(errorOf(ask(1, 24, 48, 'vtk'))).toMatchObject({ code: 'no_phases', message: 'the anatomical meshes: no finished phases batch: measure all phases first' });
    const load = (reqId: number, name: string, path: string) => core.handle({ type: 'load', reqId, fileName: name, bytes: readBytes(path).slice().buffer });
    load(2, 'patient1-ED.csv', ED());
    load(3, 'patient1-ES.csv', ES());
    const run = async (runId: number, phases: { name: string; file: string }[]) => {
      core.handle({ type: 'lab-batch', runId, job: { kind: 'phases', phases, params: {}, lids: 'auto' } });
      const deadline = Date.now() + 100_000;
      while (!inbox.some((m) => (m.type === 'lab-batch-done' || m.type === 'error') && m.runId === runId)) {
        if (Date.now() > deadline) throw new Error('the batch did not finish');
        await new Promise((r) => setTimeout(r, 20));
      }
    };
    await run(10, [
      { name: 'patient1-ED', file: 'patient1-ED.csv' },
      { name: 'patient1-ES', file: 'patient1-ES.csv' },
    ]);
    const got = ask(11, 24, 48, 'vtk');
    expect(got?.type, JSON.stringify(errorOf(got))).toBe('lab-phases-anatomical');
    if (got?.type !== 'lab-phases-anatomical') return;
    expectCliReport(got.study.report);
    expect(got.study.files.map((f) => f.name)).toEqual(['patient1-ED-LV_EPI.vtk', 'patient1-ED-LV_ENDO.vtk', 'patient1-ES-LV_EPI.vtk', 'patient1-ES-LV_ENDO.vtk']);
    for (const f of got.study.files) expect(f.bytes).toBeInstanceOf(ArrayBuffer);
    const endo = got.study.files[1];
    expectCliVtk(new Uint8Array(endo.bytes), endo.name);
    // Another format and layout of the same batch: every file, the vertex count of that layout.
    const ply = ask(12, 12, 24, 'ply');
    expect(ply?.type === 'lab-phases-anatomical' && ply.study.report.layouts.map((l) => l.summary?.vertices)).toEqual([290, 290, 290, 290]);
    // Refusals: a layout out of range (the core's words), a malformed request (refused before wasm).
    expect(errorOf(ask(13, 1, 48, 'vtk'))?.message).toMatch(/^the anatomical meshes: .*2-200 rings of 8-720 points \(got 1x48\)/);
    expect(errorOf(ask(14, 'x', 48, 'vtk'))).toMatchObject({ code: 'protocol' });
    expect(errorOf(ask(15, 24, 48, 7))).toMatchObject({ code: 'protocol' });

    // The SurFCo example twice: no phase says where the septum is.
    load(20, 'a.csv', SURFCO());
    load(21, 'b.csv', SURFCO());
    await run(22, [
      { name: 'a', file: 'a.csv' },
      { name: 'b', file: 'b.csv' },
    ]);
    expect(errorOf(ask(23, 24, 48, 'vtk'))).toMatchObject({
      code: 'degenerate',
      message: "the anatomical meshes: every layout starts at the septum, and no phase's file has RV_INSERT landmarks or RV contours to place it by",
    });
    // The worker goes on: a request after the refusals is answered.
    core.handle({ type: 'schema', reqId: 30 });
    expect(inbox.some((m) => m.type === 'schema' && m.reqId === 30)).toBe(true);
    expect(inbox.some((m) => m.type === 'error' && m.error.code === 'worker_crashed')).toBe(false);
  }, 200_000);
});
