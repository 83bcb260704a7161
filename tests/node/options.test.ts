// The two non-numeric options (smoothing method, conflict softening) through the worker's logic
// with the real wasm: they reach the run and both lab batches inside the params JSON object, the
// result reports them, a bad combination comes back as the core's error, and a saved session
// brings them back on load (older sessions: the defaults).
import { beforeAll, describe, expect, it } from 'vitest';
import type { LoadedFile, ReconOptions, RunResult } from '../../web/src/core-client/protocol';
import { PATIENT1_ED, dataDir, loadWasm, readBytes } from './helpers.mjs';
import { DEFAULT_END_CAPS } from '../../web/src/core-client/protocol';
import { askingCore } from './askCore';

type Wasm = typeof import('../../web/pkg/heartmesh_wasm.js');
let wasm: Wasm;

beforeAll(async () => {
  wasm = await loadWasm();
});

/** A worker core whose answers are awaited one request at a time. */
function makeCore() {
  return askingCore(wasm);
}

const PATIENT = 'patient1-ED.csv';

async function loaded(ask: ReturnType<typeof makeCore>['ask'], fileName: string, bytes: Uint8Array): Promise<LoadedFile> {
  const m = await ask({ type: 'load', reqId: 1, fileName, bytes: bytes.slice().buffer as ArrayBuffer }, 'loaded', 'error');
  if (m.type === 'error') throw new Error(m.error.message);
  return m.file;
}

async function run(ask: ReturnType<typeof makeCore>['ask'], runId: number, options?: ReconOptions, params = {}, surface = 'LV_ENDO') {
  const m = await ask({ type: 'run', runId, fileName: PATIENT, surface, params, lids: 'auto', options }, 'done', 'error');
  return m.type === 'done' ? { result: m.result as RunResult, error: null } : { result: null, error: m.error };
}

describe('smoothing options through the worker', () => {
  it('reach the run: soften off gives another mesh; Taubin runs at 0.5 and is refused at 0.8', async () => {
    const { ask } = makeCore();
    await loaded(ask, PATIENT, readBytes(PATIENT1_ED()));
    // The RV endocardium, whose septum curves disagree between SAX and LAX: softening acts there.
    const on = (await run(ask, 1, undefined, {}, 'RV_ENDO')).result;
    const off = (await run(ask, 2, { smoothing_method: 'laplacian-affine', soften_conflicts: false, align_slices: false, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true, drop_second_loops: false }, {}, 'RV_ENDO')).result;
    expect(on?.options).toEqual({ smoothing_method: 'laplacian-affine', soften_conflicts: true, align_slices: false, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true, drop_second_loops: false });
    expect(off?.options).toEqual({ smoothing_method: 'laplacian-affine', soften_conflicts: false, align_slices: false, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true, drop_second_loops: false });
    if (!on || !off) throw new Error('runs failed');
    // Same sample, same numbers otherwise: only the softening differs (0.445 vs 0.408 mm natively).
    expect(on.overall.mean - off.overall.mean).toBeGreaterThan(0.01);
    expect(on.overall.mean).toBeLessThan(1);
    expect(off.overall.mean).toBeLessThan(1);

    const taubin = await run(ask, 3, { smoothing_method: 'taubin', soften_conflicts: true, align_slices: false, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true, drop_second_loops: false }, { smoothing_factor: 0.5 });
    expect(taubin.result?.options.smoothing_method).toBe('taubin');
    expect(taubin.result?.overall.mean).toBeLessThan(1.5);
    const bad = await run(ask, 4, { smoothing_method: 'taubin', soften_conflicts: true, align_slices: false, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true, drop_second_loops: false }, { smoothing_factor: 0.8 });
    expect(bad.error?.code).toBe('param_out_of_range');
    expect(bad.error?.message).toMatch(/smoothing_factor = 0\.8 .*allowed 0 to 0\.6/);
  });

  it('run the local corrections (HC, twicing) and refuse twicing above its 0.5 factor limit', async () => {
    const { ask } = makeCore();
    await loaded(ask, PATIENT, readBytes(PATIENT1_ED()));
    const base = (await run(ask, 1)).result;
    const opts = (smoothing_method: ReconOptions['smoothing_method']): ReconOptions =>
      ({ smoothing_method, soften_conflicts: true, align_slices: false, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true, drop_second_loops: false });
    const hc = (await run(ask, 2, opts('laplacian-hc'))).result;
    const twicing = (await run(ask, 3, opts('laplacian-twicing'))).result;
    if (!base || !hc || !twicing) throw new Error('runs failed');
    expect(hc.options.smoothing_method).toBe('laplacian-hc');
    expect(twicing.options.smoothing_method).toBe('laplacian-twicing');
    // Other smoothing, other meshes; all of them follow the contours (VALIDATION, session 11).
    expect(Math.abs(hc.overall.mean - base.overall.mean)).toBeGreaterThan(1e-3);
    expect(Math.abs(twicing.overall.mean - base.overall.mean)).toBeGreaterThan(1e-3);
    for (const r of [base, hc, twicing]) {
      expect(r.overall.mean).toBeLessThan(1);
      expect(r.watertight).toBe(true);
    }
    const bad = await run(ask, 4, opts('laplacian-twicing'), { smoothing_factor: 0.8 });
    expect(bad.error?.code).toBe('param_out_of_range');
    expect(bad.error?.message).toMatch(/smoothing_factor = 0\.8 .*allowed 0 to 0\.5/);
  });

  it('reach leave-one-out and the sweep (the same refusal, from the lab)', async () => {
    const { ask } = makeCore();
    await loaded(ask, PATIENT, readBytes(PATIENT1_ED()));
    const base = { fileName: PATIENT, surface: 'LV_ENDO', params: { smoothing_factor: 0.8 }, lids: 'auto' as const };
    const taubin: ReconOptions = { smoothing_method: 'taubin', soften_conflicts: false, align_slices: false, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true, drop_second_loops: false };
    const loo = await ask({ type: 'lab-batch', runId: 5, job: { kind: 'loo', ...base, options: taubin } }, 'lab-batch-started', 'error');
    expect(loo.type === 'error' && loo.error.code).toBe('param_out_of_range');
    const sweep = await ask(
      { type: 'lab-batch', runId: 6, job: { kind: 'sweep', ...base, options: taubin, grid: { lambda: [1e4] }, withTruth: false } },
      'lab-batch-started',
      'error',
    );
    expect(sweep.type === 'error' && sweep.error.code).toBe('param_out_of_range');
    // The same factor with the default method is accepted.
    const ok = await ask({ type: 'lab-batch', runId: 7, job: { kind: 'sweep', ...base, grid: { lambda: [1e4] }, withTruth: false } }, 'lab-batch-started', 'error');
    expect(ok.type).toBe('lab-batch-started');
  });

  it('a saved session brings its options back on load; an older one the defaults (end caps off, as made)', async () => {
    const { ask } = makeCore();
    const ring = (z: number) => Array.from({ length: 12 }, (_, i) => [20 * Math.cos(i / 2), 20 * Math.sin(i / 2), z]);
    const contours = [0, 10, 20].map((z) => ({ id: `sax${z}`, surface: 'LV_ENDO', points: ring(z) }));
    const session = (parameters: object) =>
      new TextEncoder().encode(JSON.stringify({ heartmesh_session: 1, app_version: '0.1.0', contours, parameters }));
    const saved = await loaded(ask, 'saved.json', session({ beta: 0.3, lids: 'none', smoothing_method: 'taubin', soften_conflicts: false, surface: 'LV_ENDO' }));
    // No end_caps key: saved before end caps existed, so read back without them (as it was made);
    // no apex_floor key: saved before sessions stored it, when the floor was off (core io::session).
    expect(saved.session?.options).toEqual({ smoothing_method: 'taubin', soften_conflicts: false, align_slices: false, end_caps: 'off', keep_specks: false, apex_floor: false, drop_second_loops: false });
    expect(saved.session?.lids).toBe('none');
    expect(saved.session?.surface).toBe('LV_ENDO');
    expect(saved.session?.params.beta).toBe(0.3);
    expect(saved.session?.params.lambda).toBe(1e5);
    const old = await loaded(ask, 'old.json', session({ beta: 0.3, lids: 'auto', surface: null }));
    expect(old.session?.options).toEqual({ smoothing_method: 'laplacian-affine', soften_conflicts: true, align_slices: false, end_caps: 'off', keep_specks: false, apex_floor: false, drop_second_loops: false });
    const bad = await loaded(ask, 'bad.json', session({ smoothing_method: 'gaussian' }));
    expect(bad.session ?? null).toBeNull();
    expect(bad.warnings.join(' ')).toMatch(/not applied: parameter smoothing_method: unknown method "gaussian" \(allowed: laplacian-affine, taubin, laplacian-hc, laplacian-twicing\)/);
    const csv = await loaded(ask, PATIENT, readBytes(PATIENT1_ED()));
    expect(csv.session ?? null).toBeNull();
  });

  it('a session written by the worker opens again with the same settings and contours', async () => {
    const { ask } = makeCore();
    const file = await loaded(ask, PATIENT, readBytes(PATIENT1_ED()));
    // Keep specks and strays on and the apex floor off too: a session keeps both (core io::session, since session 14).
    const options: ReconOptions = { smoothing_method: 'taubin', soften_conflicts: false, align_slices: false, end_caps: DEFAULT_END_CAPS, keep_specks: true, apex_floor: false, drop_second_loops: false };
    const written = await ask(
      { type: 'session-export', reqId: 2, fileName: PATIENT, surface: 'LV_EPI', params: { beta: 0.2, smoothing_factor: 0.4 }, lids: 'none', options, appVersion: '9.9.9' },
      'session-json',
      'error',
    );
    if (written.type !== 'session-json') throw new Error(written.error.message);
    const doc = JSON.parse(new TextDecoder().decode(written.bytes));
    expect(doc.app_version).toBe('9.9.9');
    expect(doc.parameters).toMatchObject({ smoothing_method: 'taubin', soften_conflicts: false, keep_specks: true, apex_floor: false, lids: 'none', surface: 'LV_EPI', beta: 0.2 });
    const back = await loaded(ask, 'saved.json', written.bytes);
    expect(back.session).toMatchObject({ lids: 'none', surface: 'LV_EPI', options });
    expect(back.session?.params.smoothing_factor).toBe(0.4);
    expect(back.surfaces).toEqual(file.surfaces);
    expect(back.contours.map((c) => c.id)).toEqual(file.contours.map((c) => c.id));
    expect(back.points).toEqual(file.points);
    // A bad combination is refused with the core's error, not written.
    const bad = await ask(
      { type: 'session-export', reqId: 3, fileName: PATIENT, surface: null, params: { smoothing_factor: 0.8 }, lids: 'auto', options, appVersion: '9.9.9' },
      'session-json',
      'error',
    );
    expect(bad.type === 'error' && bad.error.code).toBe('param_out_of_range');
  });

  it('a session of a .mat study reproduces its mesh to the last bit', async () => {
    // The .mat's coordinates are single-precision values with 17 significant digits as doubles:
    // the session must give back the very doubles, or 250 spline steps would make another mesh.
    const { ask } = makeCore();
    const mat = 'surfco-example.mat';
    await loaded(ask, mat, readBytes(`${dataDir()}/contours/${mat}`));
    const finished = async (runId: number, fileName: string) => {
      const m = await ask({ type: 'run', runId, fileName, surface: null, params: {}, lids: 'auto' }, 'done', 'error');
      if (m.type === 'error') throw new Error(m.error.message);
      return m.result as RunResult;
    };
    const first = await finished(1, mat);
    const written = await ask({ type: 'session-export', reqId: 2, fileName: mat, surface: null, params: {}, lids: 'auto', appVersion: '9.9.9' }, 'session-json', 'error');
    if (written.type !== 'session-json') throw new Error(written.error.message);
    await loaded(ask, 'saved.json', written.bytes);
    const again = await finished(3, 'saved.json');
    expect(again.positionsF64?.length).toBeGreaterThan(3000);
    const a = first.positionsF64 ?? [];
    const b = again.positionsF64 ?? [];
    expect(b.length).toBe(a.length);
    expect(a.filter((x, i) => x !== b[i]).length).toBe(0);
    expect(again.volumeMl).toBe(first.volumeMl);
  });
});
