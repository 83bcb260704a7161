// The phases batch of a heart's function (the app's Function panel) with the real wasm, against the
// native CLI's `heartmesh volumes --json` on the same files: biv-me patient 1's ED and ES, each
// volume, each cavity's EF and the LV mass equal to 1e-9 relative (native and wasm agree); the same
// phases as the two frames of one file holding both (a `phase` column, built here as the CLI's
// own test builds it), through the worker's logic, give the same volumes without changing the
// frame the worker holds for the view; and a broken phase is failed cells beside measured ones.
// With LV_ENDO and LV_EPI, the batch's summary carries the LV wall's thickening by AHA segment:
// equal to `volumes --json`'s `wall_thickening` (1e-9 relative) and its bullseye to the CLI's
// `--thickening-plot` drawing.
import { beforeAll, describe, expect, it } from 'vitest';
import type { FromWorker, FunctionSummary, LabProgress, PhaseItem, WallThickening } from '../../web/src/core-client/protocol';
import { WorkerCore, wasmApiOf } from '../../web/src/core-client/workerCore';
import { PATIENT1_ED, cliVolumes, loadWasm, readBytes, readText, writeScratch } from './helpers.mjs';

type Wasm = typeof import('../../web/pkg/heartmesh_wasm.js');
let wasm: Wasm;
const ED = () => PATIENT1_ED();
const ES = () => PATIENT1_ED().replace('patient1-ED.csv', 'patient1-ES.csv');

beforeAll(async () => {
  wasm = await loadWasm();
});

function relative(a: number, b: number): number {
  return Math.abs(a - b) / Math.max(Math.abs(b), 1e-12);
}

/** Runs the Lab's batch to its end: the cells and the summary. */
function drain(lab: InstanceType<Wasm['Lab']>): { items: PhaseItem[]; summary: FunctionSummary } {
  const items: PhaseItem[] = [];
  for (let guard = 0; guard < 1_000_000; guard++) {
    const p = JSON.parse(lab.batch_step()) as LabProgress & { done: boolean };
    if (p.item) items.push(p.item as PhaseItem);
    if (p.done) return { items, summary: p.summary as FunctionSummary };
  }
  throw new Error('the batch does not finish');
}

/** One CSV holding both phases in a `phase` column (volumes_cli.rs `one_file_holding_a_sequence`). */
function sequenceCsv(): string {
  let cine = 'contour,x,y,z,surface,phase\n';
  for (const [path, phase] of [[ED(), 'ED'], [ES(), 'ES']]) {
    for (const line of readText(path).split('\n').slice(1)) {
      if (line.trim() !== '' && !line.startsWith('#')) cine += `${line.trimEnd()},${phase}\n`;
    }
  }
  return cine;
}

describe('the phases of a heart, against heartmesh volumes', () => {
  it('patient 1 ED + ES: every volume, EF and LV mass equal to the CLI', () => {
    const cli = cliVolumes([ED(), ES()], [], 'p1-volumes');
    const session = new wasm.Session();
    session.load('patient1-ED.csv', readBytes(ED()));
    session.load('patient1-ES.csv', readBytes(ES()));
    const lab = new wasm.Lab();
    const phases = [
      { name: 'patient1-ED', file: 'patient1-ED.csv' },
      { name: 'patient1-ES', file: 'patient1-ES.csv' },
    ];
    const info = JSON.parse(lab.start_phases(session, JSON.stringify(phases), '{}', 'auto', new Uint8Array(0), [], []));
    expect(info).toEqual({ total: 8, phases: cli.phases, surfaces: cli.surfaces });
    const { items, summary } = drain(lab);
    expect(items).toHaveLength(cli.volumes.length);
    items.forEach((it, i) => {
      const want = cli.volumes[i];
      expect([it.phase, it.surface, it.watertight, it.missing]).toEqual([want.phase, want.surface, want.watertight, want.missing]);
      expect(relative(it.volume_ml as number, want.volume_ml)).toBeLessThan(1e-9);
      expect(relative(it.contour_to_mesh_mean as number, want.contour_to_mesh_mean)).toBeLessThan(1e-9);
    });
    expect(summary.ventricles.map((v) => v.surface)).toEqual(cli.function.map((v: { surface: string }) => v.surface));
    summary.ventricles.forEach((v, i) => {
      const want = cli.function[i];
      expect([v.ed_phase, v.es_phase]).toEqual([want.ed_phase, want.es_phase]);
      for (const k of ['edv_ml', 'esv_ml', 'sv_ml', 'ef_percent'] as const) expect(relative(v[k], want[k])).toBeLessThan(1e-9);
    });
    const lv = summary.ventricles.find((v) => v.surface === 'LV_ENDO');
    const rv = summary.ventricles.find((v) => v.surface === 'RV_ENDO');
    // The figures the CLI prints (and the app shows to one decimal).
    expect(lv?.ef_percent).toBeCloseTo(62.1, 1);
    expect(rv?.ef_percent).toBeCloseTo(60.9, 1);
    const mass = summary.lv_mass;
    expect(relative(mass?.ed_g as number, cli.lv_mass.ed_g)).toBeLessThan(1e-9);
    expect(relative(mass?.es_g as number, cli.lv_mass.es_g)).toBeLessThan(1e-9);
    expect(mass?.ed_g).toBeCloseTo(134.0, 1);
    expect(mass?.es_g).toBeCloseTo(131.6, 1);
  });

  it('patient 1 ED + ES: the LV wall thickening by AHA segment and its bullseye equal to the CLI\'s', () => {
    const plot = writeScratch('p1-thickening.svg', '');
    const cli = cliVolumes([ED(), ES()], ['--thickening-plot', plot], 'p1-thickening');
    const cliSvg = readText(plot);
    const session = new wasm.Session();
    session.load('patient1-ED.csv', readBytes(ED()));
    session.load('patient1-ES.csv', readBytes(ES()));
    const lab = new wasm.Lab();
    // The app names a phase that is a file by the file's name without its extension (app/phases.ts),
    // the CLI by the file's stem: the same names here, so the phases are compared as they are. (A
    // sequence's frames are named by their labels on both sides; only a phase named otherwise, as
    // two files of one stem are in the app, would make the names, and the SVG's lines that carry
    // them, not comparable.)
    const phases = [
      { name: 'patient1-ED', file: 'patient1-ED.csv' },
      { name: 'patient1-ES', file: 'patient1-ES.csv' },
    ];
    lab.start_phases(session, JSON.stringify(phases), '{}', 'auto', new Uint8Array(0), [], []);
    const { summary } = drain(lab);
    const want = cli.wall_thickening as WallThickening;
    const got = summary.wall_thickening as WallThickening;
    expect(want, 'the CLI measured a thickening').toBeTruthy();
    expect(got, summary.wall_thickening_note).toBeTruthy();
    expect(summary.wall_thickening_note).toBeUndefined();
    expect(cli.phases).toEqual(phases.map((p) => p.name));
    expect([got.ed_phase, got.es_phase]).toEqual([want.ed_phase, want.es_phase]);
    expect([got.ed_phase, got.es_phase]).toEqual(['patient1-ED', 'patient1-ES']);
    expect(got.septum_from).toEqual(want.septum_from);
    expect(relative(got.mean_percent as number, want.mean_percent as number)).toBeLessThan(1e-9);
    expect(got.segments.map((g) => [g.id, g.name])).toEqual(want.segments.map((g) => [g.id, g.name]));
    expect(got.segments.map((g) => g.id)).toEqual(Array.from({ length: 17 }, (_, i) => i + 1));
    got.segments.forEach((g, i) => {
      for (const k of ['ed_mm', 'es_mm', 'thickening_percent'] as const) {
        const [a, b] = [g[k], want.segments[i][k]];
        if (b === null) expect(a, `segment ${g.id} ${k}`).toBeNull();
        else expect(relative(a as number, b), `segment ${g.id} ${k}: ${a} vs ${b}`).toBeLessThan(1e-9);
      }
    });
    // What the CLI prints of it ("mean 60 %, from 20 % (9 mid inferoseptal) to 92 % (6 basal anterolateral)"):
    // every segment of this healthy LV thickens.
    expect(got.mean_percent).toBeCloseTo(60.2, 1);
    expect(got.segments[0].thickening_percent).toBeCloseTo(66.7, 1);
    expect(got.segments.every((g) => g.thickening_percent !== null && g.thickening_percent > 15 && g.thickening_percent < 95)).toBe(true);

    // The bullseye: the CLI's drawing line by line, but for the lines naming the phases (equal too
    // here, compared with the names put aside).
    const svg = summary.thickening_svg as string;
    expect(svg.startsWith('<svg xmlns="http://www.w3.org/2000/svg" width="460" height="530"')).toBe(true);
    const names = (t: WallThickening) => [t.ed_phase, t.es_phase];
    const naming = (line: string, t: WallThickening) => names(t).some((n) => line.includes(n));
    const [appLines, cliLines] = [svg.split('\n'), cliSvg.split('\n')];
    expect(appLines.filter((l) => !naming(l, got))).toEqual(cliLines.filter((l) => !naming(l, want)));
    const apart = (lines: string[], t: WallThickening) => lines.filter((l) => naming(l, t)).map((l) => names(t).reduce((x, n, k) => x.split(n).join(`<phase ${k}>`), l));
    expect(apart(appLines, got)).toEqual(apart(cliLines, want));
    expect(apart(appLines, got)).toEqual(['<text x="230" y="40" text-anchor="middle" font-size="12" fill="#444">ED <phase 0> to ES <phase 1></text>']);
    expect(appLines.filter((l) => l.startsWith('<path ')).length).toBe(17);
  });

  it('one file holding ED and ES, through the worker: the same volumes, the worker keeps its frame, a broken phase fails alone', async () => {
    const cine = sequenceCsv();
    const cli = cliVolumes([writeScratch('cine.csv', cine)], [], 'cine-volumes');
    expect(cli.phases).toEqual(['ED', 'ES']);
    const inbox: FromWorker[] = [];
    const core = new WorkerCore(wasmApiOf(wasm), (m) => inbox.push(m), { yieldToEventLoop: (cb) => setTimeout(cb, 0), now: () => performance.now() });
    const bytes = new TextEncoder().encode(cine);
    core.handle({ type: 'load', reqId: 1, fileName: 'cine.csv', bytes: bytes.slice().buffer });
    const loaded = inbox.find((m) => m.type === 'loaded');
    expect(loaded?.type === 'loaded' && loaded.file.timeFrames?.frames).toEqual(['ED', 'ES']);
    // A file whose contours cannot make a surface: one contour.
    const broken = 'contour,x,y,z,surface\na,0,0,0,LV_ENDO\na,10,0,0,LV_ENDO\na,0,10,0,LV_ENDO\n';
    core.handle({ type: 'load', reqId: 2, fileName: 'broken.csv', bytes: new TextEncoder().encode(broken).buffer });
    expect(inbox.filter((m) => m.type === 'loaded')).toHaveLength(2);

    core.handle({
      type: 'lab-batch',
      runId: 10,
      job: {
        kind: 'phases',
        phases: [
          { name: 'ED', file: 'cine.csv', frame: 'ED' },
          { name: 'ES', file: 'cine.csv', frame: 'ES' },
          { name: 'broken', file: 'broken.csv' },
        ],
        params: {},
        lids: 'auto',
        sequence: { bytes: bytes.slice().buffer, views: [] },
      },
    });
    const deadline = Date.now() + 100_000;
    while (!inbox.some((m) => m.type === 'lab-batch-done' || m.type === 'error')) {
      if (Date.now() > deadline) throw new Error('the batch did not finish');
      await new Promise((r) => setTimeout(r, 20));
    }
    expect(inbox.filter((m) => m.type === 'error')).toEqual([]);
    const started = inbox.find((m) => m.type === 'lab-batch-started');
    expect(started?.type === 'lab-batch-started' && started.info).toEqual({ total: 12, phases: ['ED', 'ES', 'broken'], surfaces: cli.surfaces });
    const progress = inbox.filter((m): m is Extract<FromWorker, { type: 'lab-progress' }> => m.type === 'lab-progress');
    const items = progress.map((m) => m.progress.item as PhaseItem | undefined).filter((i): i is PhaseItem => i !== undefined);
    expect(items.map((i) => i.index)).toEqual([...Array(12).keys()]);
    cli.volumes.forEach((want: { volume_ml: number }, i: number) => expect(relative(items[i].volume_ml as number, want.volume_ml)).toBeLessThan(1e-9));
    // broken.csv holds LV_ENDO only: that run fails with the core's reason, its other surfaces are absent.
    const lvEndo = cli.surfaces.indexOf('LV_ENDO');
    items.slice(8).forEach((it, j) => {
      expect(it.volume_ml).toBeNull();
      expect(it.missing).toBe(j === lvEndo ? 'failed' : 'absent');
    });
    expect(items[8 + lvEndo].error).toMatch(/contour/);
    const summary = progress.at(-1)?.progress.summary as FunctionSummary;
    const lv = summary.ventricles.find((v) => v.surface === 'LV_ENDO');
    expect([lv?.ed_phase, lv?.es_phase]).toEqual(['ED', 'ES']);
    const cliLv = cli.function.find((v: { surface: string }) => v.surface === 'LV_ENDO');
    expect(relative(lv?.ef_percent as number, cliLv.ef_percent)).toBeLessThan(1e-9);
    expect(relative(summary.lv_mass?.es_g as number, cli.lv_mass.es_g)).toBeLessThan(1e-9);

    // The worker still holds cine.csv as loaded (frame ED, the view's): its run is ED's mesh.
    core.handle({ type: 'run', runId: 20, fileName: 'cine.csv', surface: 'LV_ENDO', params: {}, lids: 'auto' });
    while (!inbox.some((m) => m.type === 'done' || (m.type === 'error' && m.runId === 20))) {
      if (Date.now() > deadline) throw new Error('the run did not finish');
      await new Promise((r) => setTimeout(r, 20));
    }
    const done = inbox.find((m) => m.type === 'done') as Extract<FromWorker, { type: 'done' }>;
    expect(relative(done.result.volumeMl as number, items[lvEndo].volume_ml as number)).toBeLessThan(1e-9);
  });
});
