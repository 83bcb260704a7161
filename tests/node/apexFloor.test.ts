// The apex floor (session 14, on by default) through the worker's logic with the real wasm, against
// the native CLI on the same short-axis-only files: the spasm LV endocardium sliced by the CLI's
// `simulate --lax 0` (no long-axis view, so no curve reaches the apex) and the ellipsoid the
// browser test drops (tests/e2e/saxOnly.mjs). At the app's defaults the mesh and its figures are
// the CLI's at its defaults (floor on; to 1e-9) and the result's end_caps the report's, naming the
// floor; with `apex_floor: false` they are `--no-apex-floor`'s. A session keeps the switch, and
// one saved before sessions stored it reads back with it off (core io::session).
import { beforeAll, describe, expect, it } from 'vitest';
import { DEFAULT_OPTIONS, type LoadedFile, type RunResult } from '../../web/src/core-client/protocol';
import { cliReport, cliSimulate, dataDir, loadWasm, readText, writeScratch } from './helpers.mjs';
import { SAX_ONLY_NAME, saxOnlyEllipsoid } from '../e2e/saxOnly.mjs';
import { askingCore } from './askCore';

type Wasm = typeof import('../../web/pkg/heartmesh_wasm.js');
let wasm: Wasm;
/** name -> [path on disk (for the CLI), text (for the worker)] */
const inputs = new Map<string, { path: string; text: string }>();
const SPASM = 'spasm-LV_endo-sax-only.csv';

beforeAll(async () => {
  wasm = await loadWasm();
  const simulated = cliSimulate(`${dataDir()}/meshes/cardiomesh-spasm-LV_endo.obj`, ['--lax', '0'], SPASM);
  inputs.set(SPASM, { path: simulated, text: readText(simulated) });
  const { csv } = saxOnlyEllipsoid();
  inputs.set(SAX_ONLY_NAME, { path: writeScratch(SAX_ONLY_NAME, csv), text: csv });
});

function makeCore() {
  return askingCore(wasm).ask;
}
type Ask = ReturnType<typeof makeCore>;

async function load(ask: Ask, fileName: string, bytes: Uint8Array): Promise<LoadedFile> {
  const m = await ask({ type: 'load', reqId: 1, fileName, bytes: bytes.slice().buffer as ArrayBuffer }, 'loaded', 'error');
  if (m.type === 'error') throw new Error(m.error.message);
  return m.file;
}

async function run(ask: Ask, runId: number, fileName: string, surface: string | null, floor: boolean | undefined): Promise<RunResult> {
  // undefined: the app's defaults as they are (floor on), not named explicitly.
  const options = floor === undefined ? { ...DEFAULT_OPTIONS } : { ...DEFAULT_OPTIONS, apex_floor: floor };
  const m = await ask({ type: 'run', runId, fileName, surface, params: {}, lids: 'auto', options }, 'done', 'error');
  if (m.type === 'error') throw new Error(m.error.message);
  return m.result;
}

function relative(a: number, b: number): number {
  return Math.abs(a - b) / Math.max(Math.abs(b), 1e-12);
}

/** The worker's result is the CLI's report: the mesh's counts, the figures to 1e-9, the end caps. */
// eslint-disable-next-line @typescript-eslint/no-explicit-any
function expectSame(r: RunResult, native: Record<string, any>): void {
  expect(r.positions.length / 3).toBe(native.vertices);
  expect(r.indices.length / 3).toBe(native.triangles);
  expect(relative(r.overall.mean, native.contour_to_mesh.mean)).toBeLessThanOrEqual(1e-9);
  expect(relative(r.overall.max, native.contour_to_mesh.max)).toBeLessThanOrEqual(1e-9);
  expect(relative(r.volumeMl, native.volume_ml)).toBeLessThanOrEqual(1e-9);
  expect(relative(r.pastData?.apex_mm ?? NaN, native.past_data.apex_mm)).toBeLessThanOrEqual(1e-9);
  expect(r.end_caps).toEqual(native.end_caps);
}

describe('the apex floor through the worker, against the CLI', () => {
  for (const [name, surface] of [[SPASM, null], [SAX_ONLY_NAME, 'LV_ENDO']] as const) {
    it(`${name}: on by default as the CLI's default, off as --no-apex-floor`, async () => {
      const ask = makeCore();
      const input = inputs.get(name);
      if (!input) throw new Error(`no input ${name}`);
      await load(ask, name, new TextEncoder().encode(input.text));
      const args = surface ? ['--surface', surface] : [];

      const on = await run(ask, 1, name, surface, undefined);
      const nativeOn = cliReport(input.path, args, `${name}-on`);
      expect(nativeOn.parameters.apex_floor).toBe(true);
      expect(on.options.apex_floor).toBe(true);
      expect(on.end_caps?.apex_floor).toBe(true);
      expect(on.end_caps?.apex).toBe(true);
      // Both stacks are short-axis only: the base lid is the ceiling, named as the CLI names it.
      expect(on.end_caps?.base_ceiling).toBe(true);
      expectSame(on, nativeOn);

      const off = await run(ask, 2, name, surface, false);
      const nativeOff = cliReport(input.path, [...args, '--no-apex-floor'], `${name}-off`);
      expect(nativeOff.parameters.apex_floor).toBe(false);
      expect(off.options.apex_floor).toBe(false);
      expect(off.end_caps?.apex_floor).toBeUndefined();
      expect(off.end_caps?.apex).toBe(false);
      expectSame(off, nativeOff);

      // The floor is one lid point more and reaches further down; the contours' count is the same.
      expect(on.end_caps?.points).toBe((off.end_caps?.points ?? NaN) + 1);
      expect(on.pastData?.apex_mm ?? NaN).toBeGreaterThan(off.pastData?.apex_mm ?? NaN);
      expect(on.volumeMl).not.toBe(off.volumeMl);
      expect(on.overall.count).toBe(off.overall.count);
      console.log(`# ${name}: apex past the lowest ring ${off.pastData?.apex_mm.toFixed(2)} -> ${on.pastData?.apex_mm.toFixed(2)} mm with the floor, volume ${off.volumeMl.toFixed(2)} -> ${on.volumeMl.toFixed(2)} ml, mean ${off.overall.mean.toFixed(4)} -> ${on.overall.mean.toFixed(4)} mm`);
    });
  }

  it('a session keeps apex_floor; one saved before sessions stored it reads back off', async () => {
    const ask = makeCore();
    const input = inputs.get(SAX_ONLY_NAME);
    if (!input) throw new Error('no input');
    await load(ask, SAX_ONLY_NAME, new TextEncoder().encode(input.text));
    for (const floor of [true, false]) {
      const options = { ...DEFAULT_OPTIONS, apex_floor: floor };
      const written = await ask({ type: 'session-export', reqId: 2, fileName: SAX_ONLY_NAME, surface: 'LV_ENDO', params: {}, lids: 'auto', options, appVersion: '9.9.9' }, 'session-json', 'error');
      if (written.type !== 'session-json') throw new Error(written.error.message);
      const doc = JSON.parse(new TextDecoder().decode(written.bytes));
      expect(doc.parameters.apex_floor).toBe(floor);
      const back = await load(ask, `saved-${floor}.json`, written.bytes);
      expect(back.session?.options).toEqual(options);
      // Without the key (an app older than session 14 wrote it): off, as it was made.
      delete doc.parameters.apex_floor;
      const old = await load(ask, `old-${floor}.json`, new TextEncoder().encode(JSON.stringify(doc)));
      expect(old.session?.options.apex_floor).toBe(false);
    }
  });
});
