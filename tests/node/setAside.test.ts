// Contours the core leaves out (session 14: specks and strays) through the worker's logic with the
// real wasm, against the native CLI on the same file: the bundled patient 1 ED with a 2 mm,
// 3-point loop one slice past the base (tests/e2e/speck.mjs). The result names it as the CLI
// report's `set_aside` does, the load-time warning is the CLI's, the mesh and the figures are the
// CLI's (to 1e-9), its points come back as the file gives them with their distances to the mesh
// (the entry's mean to 1e-5, f32), and `keep_specks` keeps it as `--keep-specks` does.
import { beforeAll, describe, expect, it } from 'vitest';
import { DEFAULT_OPTIONS, type LoadedFile, type RunResult } from '../../web/src/core-client/protocol';
import { ROOT, cliReport, loadWasm, readText, writeScratch } from './helpers.mjs';
import { withSpeck } from '../e2e/speck.mjs';
import { askingCore } from './askCore';

type Wasm = typeof import('../../web/pkg/heartmesh_wasm.js');
let wasm: Wasm;
const NAME = 'patient1-ED-speck.csv';
let input = '';
let speck: { csv: string; id: string; line: number };

beforeAll(async () => {
  wasm = await loadWasm();
  speck = withSpeck(readText(`${ROOT}/public/samples/patient1-ED.csv`));
  input = writeScratch(NAME, speck.csv);
});

function makeCore() {
  return askingCore(wasm).ask;
}

/** The native CLI's report on the same file, LV endocardium (its `warnings` are the lines stderr prefixes). */
function cli(args: string[], label: string) {
  return cliReport(input, ['--surface', 'LV_ENDO', ...args], label);
}

function relative(a: number, b: number): number {
  return Math.abs(a - b) / Math.max(Math.abs(b), 1e-12);
}

describe('contours left out, through the worker, against the CLI', () => {
  it('names the speck, leaves it out as the CLI does, and hands its points back; keep_specks keeps it', async () => {
    const ask = makeCore();
    const loaded = await ask({ type: 'load', reqId: 1, fileName: NAME, bytes: new TextEncoder().encode(speck.csv).buffer as ArrayBuffer }, 'loaded', 'error');
    if (loaded.type === 'error') throw new Error(loaded.error.message);
    const file: LoadedFile = loaded.file;
    const run = async (runId: number, keep: boolean): Promise<RunResult> => {
      const m = await ask({ type: 'run', runId, fileName: NAME, surface: 'LV_ENDO', params: {}, lids: 'auto', options: { ...DEFAULT_OPTIONS, keep_specks: keep } }, 'done', 'error');
      if (m.type === 'error') throw new Error(m.error.message);
      return m.result;
    };

    const left = await run(1, false);
    const native = cli([], 'left');
    // The load-time warning the app shows is the CLI's (the report's warnings, which the run adds none to).
    expect(native.warnings).toEqual(file.warnings);
    expect(file.warnings.some((w) => w.includes(`"${speck.id}" (line ${speck.line}, 2.0 mm around`) && w.endsWith('it is left out of the reconstruction'))).toBe(true);
    // The result's set_aside is the report's, field for field; the distances from the speck to
    // the mesh as native and wasm agree (1e-9).
    const figures = ['mean', 'median', 'max'] as const;
    const entries = (list: unknown): Record<string, unknown>[] => (Array.isArray(list) ? list : []);
    const without = (list: unknown) => entries(list).map((e) => Object.fromEntries(Object.entries(e).filter(([k]) => !(figures as readonly string[]).includes(k))));
    expect(without(left.set_aside)).toEqual(without(native.set_aside));
    for (const k of figures) {
      const a = entries(left.set_aside)[0]?.[k];
      const b = entries(native.set_aside)[0]?.[k];
      expect(typeof a === 'number' && typeof b === 'number' && relative(a, b) <= 1e-9, `${k}: ${a} vs ${b}`).toBe(true);
    }
    // The speck lies 8 mm past the basal ring: the mesh does not reach out to it.
    expect(native.set_aside?.[0]?.mean ?? 0).toBeGreaterThan(1);
    expect(left.set_aside?.map((s) => [s.id, s.line, s.reason])).toEqual([[speck.id, speck.line, 'speck']]);
    // Same mesh and figures as the CLI.
    expect(left.positions.length / 3).toBe(native.vertices);
    expect(left.indices.length / 3).toBe(native.triangles);
    expect(relative(left.overall.mean, native.contour_to_mesh.mean)).toBeLessThanOrEqual(1e-9);
    expect(relative(left.volumeMl, native.volume_ml)).toBeLessThanOrEqual(1e-9);
    expect(left.contours.map((c) => c.id)).not.toContain(speck.id);
    // Its geometry: the three points of the file, in the file's order.
    expect(left.set_aside_contours?.map((c) => [c.id, c.pieces.length, c.pieces[0].count])).toEqual([[speck.id, 1, 3]]);
    const rows = speck.csv.trim().split('\n').slice(-3).map((r) => r.split(',').slice(1, 4).map(Number));
    expect(Array.from(left.setAsidePoints ?? [])).toEqual(rows.flat().map(Math.fround));
    // Each of its points' distance to the mesh built without it (the hover read-out's): one per
    // point, and on average the entry's mean (f32 from f64).
    const far = Array.from(left.setAsidePointDistances ?? []);
    expect(far.length).toBe((left.setAsidePoints?.length ?? 0) / 3);
    expect(far.length).toBe(3);
    const mean = far.reduce((a, b) => a + b, 0) / far.length;
    expect(Math.abs(mean - (left.set_aside?.[0]?.mean ?? NaN))).toBeLessThanOrEqual(1e-5);
    expect(Math.max(...far)).toBeCloseTo(left.set_aside?.[0]?.max ?? NaN, 5);
    console.log(`set aside: ${speck.id} points ${far.map((d) => d.toFixed(4)).join(', ')} mm from the mesh (entry mean ${left.set_aside?.[0]?.mean?.toFixed(4)}, max ${left.set_aside?.[0]?.max?.toFixed(4)})`);

    const kept = await run(2, true);
    const nativeKept = cli(['--keep-specks'], 'kept');
    expect(kept.options.keep_specks).toBe(true);
    expect(kept.set_aside).toEqual([]);
    expect(nativeKept.set_aside).toBeUndefined();
    expect(kept.contours.length).toBe(left.contours.length + 1);
    expect(kept.contours.map((c) => c.id)).toContain(speck.id);
    expect(kept.positions.length / 3).toBe(nativeKept.vertices);
    expect(relative(kept.overall.mean, nativeKept.contour_to_mesh.mean)).toBeLessThanOrEqual(1e-9);
    expect(kept.overall.count).toBe(left.overall.count + 3);
    console.log(`set aside: left out ${left.positions.length / 3} vertices, mean ${left.overall.mean.toFixed(4)} mm; kept ${kept.positions.length / 3} vertices, mean ${kept.overall.mean.toFixed(4)} mm`);
  });
});
