// One leave-out list per file (the app's Contours panel, as the CLI's --leave-out): through the
// worker's logic with the real wasm, against the native CLI on the bundled patient 1 ED. An
// LV_ENDO contour left out reaches the RV_ENDO run: with Align breath-holds on it is out of the
// alignment, so the RV volume is the CLI's `--surface RV_ENDO --align-slices --leave-out ID` (to
// 1e-9) and not the one with it in; with alignment off the RV mesh is the one of every contour,
// vertex for vertex. A session saved from RV_ENDO keeps both surfaces' ids and brings them back.
import { beforeAll, describe, expect, it } from 'vitest';
import { DEFAULT_OPTIONS, type RunResult } from '../../web/src/core-client/protocol';
import { ROOT, cliReport, loadWasm, readBytes } from './helpers.mjs';
import { askingCore, type Ask } from './askCore';

type Wasm = typeof import('../../web/pkg/heartmesh_wasm.js');
let wasm: Wasm;
const NAME = 'patient1-ED.csv';
const INPUT = `${ROOT}/public/samples/${NAME}`;
const LV = 's07_LAX_LV_ENDOCARDIAL';
const RV = 's02_SAX_RV_FREEWALL';

beforeAll(async () => {
  wasm = await loadWasm();
});

function relative(a: number, b: number): number {
  return Math.abs(a - b) / Math.max(Math.abs(b), 1e-12);
}

/** A worker core with patient 1 ED loaded. */
async function loadedCore(): Promise<Ask> {
  const { ask } = askingCore(wasm);
  const bytes = readBytes(INPUT);
  const loaded = await ask({ type: 'load', reqId: 1, fileName: NAME, bytes: bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength) as ArrayBuffer }, 'loaded', 'error');
  if (loaded.type === 'error') throw new Error(loaded.error.message);
  return ask;
}

let runId = 0;
async function run(ask: Ask, surface: string, align: boolean, leaveOut: string[]): Promise<RunResult> {
  runId += 1;
  const m = await ask({ type: 'run', runId, fileName: NAME, surface, params: {}, lids: 'auto', options: { ...DEFAULT_OPTIONS, align_slices: align }, leaveOut }, 'done', 'error');
  if (m.type === 'error') throw new Error(m.error.message);
  return m.result;
}

describe('one leave-out list for every surface of the file, as the CLI', () => {
  it('an LV_ENDO contour left out is out of the RV_ENDO run\'s alignment: the CLI\'s volume', async () => {
    const ask = await loadedCore();
    const aligned = await run(ask, 'RV_ENDO', true, [LV]);
    const native = cliReport(INPUT, ['--surface', 'RV_ENDO', '--align-slices', '--leave-out', LV], 'rv-aligned-lv-out');
    const nativeAll = cliReport(INPUT, ['--surface', 'RV_ENDO', '--align-slices'], 'rv-aligned');
    console.log(`# RV_ENDO aligned: ${aligned.volumeMl} ml with ${LV} left out (CLI ${native.volume_ml}), ${nativeAll.volume_ml} ml with it in`);
    expect(aligned.leave_out).toEqual([LV]);
    // Not an RV contour: nothing of the RV is set aside by the user, every RV contour is used.
    expect((aligned.set_aside ?? []).filter((s) => s.reason === 'by_user')).toEqual([]);
    expect(aligned.contours).toHaveLength(16);
    expect(native.parameters.leave_out).toEqual([LV]);
    expect(relative(aligned.volumeMl, native.volume_ml)).toBeLessThanOrEqual(1e-9);
    expect(aligned.positions.length / 3).toBe(native.vertices);
    expect(relative(aligned.overall.mean, native.contour_to_mesh.mean)).toBeLessThanOrEqual(1e-9);
    // The figures: 185.225 ml without the LV contour in the alignment, 189.715 ml with it.
    expect(native.volume_ml).toBeCloseTo(185.2254, 3);
    expect(nativeAll.volume_ml).toBeCloseTo(189.7152, 3);
    expect(Math.abs(aligned.volumeMl - nativeAll.volume_ml)).toBeGreaterThan(2);
  });

  it('without alignment the LV id leaves the RV mesh as it is, vertex for vertex', async () => {
    const ask = await loadedCore();
    const without = await run(ask, 'RV_ENDO', false, [LV]);
    const every = await run(ask, 'RV_ENDO', false, []);
    expect(without.leave_out).toEqual([LV]);
    expect(every.leave_out).toEqual([]);
    expect(Array.from(without.positions)).toEqual(Array.from(every.positions));
    expect(without.volumeMl).toBe(every.volumeMl);
    expect(every.volumeMl).toBeCloseTo(182.9927, 3);
  });

  it('a session saved from RV_ENDO keeps the LV_ENDO id with the RV one, and brings both back', async () => {
    const ask = await loadedCore();
    const saved = await ask(
      { type: 'session-export', reqId: 2, fileName: NAME, surface: 'RV_ENDO', params: {}, lids: 'auto', options: { ...DEFAULT_OPTIONS }, leaveOut: [LV, RV], appVersion: 'test' },
      'session-json',
      'error',
    );
    if (saved.type === 'error') throw new Error(saved.error.message);
    const json = JSON.parse(new TextDecoder().decode(saved.bytes));
    expect(json.parameters.leave_out).toEqual([LV, RV]);
    const reopened = await ask({ type: 'load', reqId: 3, fileName: 'session.json', bytes: saved.bytes.slice().buffer as ArrayBuffer }, 'loaded', 'error');
    if (reopened.type === 'error') throw new Error(reopened.error.message);
    expect(reopened.file.session?.surface).toBe('RV_ENDO');
    expect(reopened.file.session?.leave_out).toEqual([LV, RV]);
  });
});
