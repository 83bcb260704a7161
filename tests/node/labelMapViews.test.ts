// NIfTI long-axis views read with their short-axis stack, through the worker's logic with the real
// wasm, on files the native CLI makes (`heartmesh segment ... --lax 3`, tests/e2e/laxViews.mjs):
// the core's label_map_grid tells the stack (all dimensions over 1) from the single-slice views; a
// load carrying the views (the core's load_study) adds one long-axis curve per surface each view
// shows, says how each view was read in `notes` (not among the warnings), and the LV endocardium
// reconstructs closed, near its curves, and as the CLI's `reconstruct seg.nii.gz seg_lax*.nii.gz`
// does; a damaged view refuses the load, named first in the message. A 4D cine with 4D views
// keeps its views when another frame is read, the systolic one a smaller LV cavity.
import { beforeAll, describe, expect, it } from 'vitest';
import { curveArea } from './curveArea';
import { DEFAULT_OPTIONS, type LoadedFile, type RunResult, type ViewFile } from '../../web/src/core-client/protocol';
import { framePicker } from '../../web/src/app/timeFrames';
import { cliReport, loadWasm } from './helpers.mjs';
import { askingCore, type Ask } from './askCore';
import { cineName, cineOf, dicomSegBytes, makeSlicerSegmentation, makeStudy, STACK, VIEW_CURVES, VIEWS } from '../e2e/laxViews.mjs';
import { pixelDataOffset } from '../../web/src/io/dicomHeaders';

type Wasm = typeof import('../../web/pkg/heartmesh_wasm.js');
let wasm: Wasm;
let study: ReturnType<typeof makeStudy>;

beforeAll(async () => {
  wasm = await loadWasm();
  study = makeStudy();
});

/** A copy of `bytes` in an ArrayBuffer of its own (as `File.arrayBuffer()` gives it). */
const buffer = (bytes: Uint8Array) => bytes.slice().buffer as ArrayBuffer;
const viewFiles = (names: string[], bytes: (n: string) => Uint8Array = (n) => study.bytes[n]): ViewFile[] =>
  names.map((name) => ({ name, bytes: buffer(bytes(name)) }));

async function load(ask: Ask, fileName: string, bytes: Uint8Array, views: ViewFile[], frame?: string): Promise<LoadedFile> {
  const m = await ask({ type: 'load', reqId: 1, fileName, bytes: buffer(bytes), views, ...(frame === undefined ? {} : { frame }) }, 'loaded', 'error');
  if (m.type === 'error') throw new Error(m.error.message);
  return m.file;
}

async function run(ask: Ask, runId: number, fileName: string, surface: string): Promise<RunResult> {
  const m = await ask({ type: 'run', runId, fileName, surface, params: {}, lids: 'auto', options: { ...DEFAULT_OPTIONS } }, 'done', 'error');
  if (m.type === 'error') throw new Error(m.error.message);
  return m.result;
}

/** Curves of each surface of `kind`. */
function curves(file: LoadedFile, kind: 'SAX' | 'LAX'): Record<string, number> {
  const out: Record<string, number> = {};
  for (const c of file.contours.filter((x) => x.kind === kind && x.surface !== null)) out[c.surface as string] = (out[c.surface as string] ?? 0) + 1;
  return out;
}

/** Enclosed area (mm2) of the file's curves of `surface` named after `view`. */
function viewArea(file: LoadedFile, surface: string, view: string): number {
  return curveArea(file, (c) => c.surface === surface && c.id.startsWith(view));
}

/**
 * Mean distance (mm) of each LV_ENDO long-axis curve of `file` to the mesh of `r`, by brute force
 * over its vertices (the nearest vertex: an upper bound of the distance to the surface).
 */
function distancesTo(file: LoadedFile, r: RunResult): number[] {
  const out: number[] = [];
  for (const c of file.contours.filter((x) => x.kind === 'LAX' && x.surface === 'LV_ENDO')) {
    let sum = 0;
    let n = 0;
    for (const piece of c.pieces) {
      for (let a = 0; a < piece.count; a++) {
        const p = 3 * (piece.start + a);
        let best = Infinity;
        for (let v = 0; v < r.positions.length; v += 3) {
          const d = Math.hypot(file.points[p] - r.positions[v], file.points[p + 1] - r.positions[v + 1], file.points[p + 2] - r.positions[v + 2]);
          if (d < best) best = d;
        }
        sum += best;
        n++;
      }
    }
    out.push(sum / n);
  }
  return out;
}

const relative = (a: number, b: number) => Math.abs(a - b) / Math.max(Math.abs(b), 1e-12);

describe('long-axis views with their stack through the worker', () => {
  it('label_map_grid: the stack\'s three dimensions, each view a single slice, other files none', async () => {
    const { ask } = askingCore(wasm);
    const grid = async (bytes: Uint8Array) => (await ask({ type: 'grid', reqId: 1, bytes: buffer(bytes) }, 'grid')).grid;
    expect(await grid(study.bytes[STACK])).toEqual({ dims: [100, 108, 10], frames: 1 });
    for (const v of VIEWS) {
      const g = await grid(study.bytes[v]);
      console.log(`# ${v}: ${JSON.stringify(g)}`);
      expect(g?.frames).toBe(1);
      expect(g?.dims.filter((d) => d === 1)).toEqual([1]);
    }
    expect(await grid(cineOf(study.bytes[STACK]))).toEqual({ dims: [100, 108, 10], frames: 2 });
    expect(await grid(new TextEncoder().encode('contour,x,y,z\nc,1,2,3\n'))).toBeNull();
    // The free function as the worker calls it.
    expect(wasm.label_map_grid(study.bytes[VIEWS[0]])).toMatch(/^\{"dims":\[\d+,\d+,1\],"frames":1\}$/);
    // A DICOM SEG of the same stack (the core's fixture), from the whole file and from its header
    // alone (the bytes before its pixel data: what the app reads of a DICOM file first): the 8
    // labelled slices (a SEG has no frames for the empty end slices); a NRRD's from its header.
    const seg = dicomSegBytes();
    expect(await grid(seg)).toEqual({ dims: [100, 108, 8], frames: 1 });
    expect(await grid(seg.slice(0, pixelDataOffset(seg, seg.length)))).toEqual({ dims: [100, 108, 8], frames: 1 });
    const nrrd = makeSlicerSegmentation().bytes;
    const headerEnd = nrrd.findIndex((b, i) => b === 0x0a && nrrd[i + 1] === 0x0a) + 2;
    expect(headerEnd).toBeGreaterThan(100);
    expect(await grid(nrrd.slice(0, headerEnd))).toEqual({ dims: [100, 108, 10], frames: 1 });
  });

  it('the stack with its 3 views: one LAX curve per surface per view, the reading in notes, LV_ENDO closed and the CLI\'s', async () => {
    const { ask } = askingCore(wasm);
    const alone = await load(ask, STACK, study.bytes[STACK], []);
    const withViews = await load(ask, STACK, study.bytes[STACK], viewFiles(VIEWS));
    expect(withViews.surfaces).toEqual(alone.surfaces);
    expect(curves(alone, 'LAX')).toEqual({});
    expect(curves(withViews, 'SAX')).toEqual(curves(alone, 'SAX'));
    expect(curves(withViews, 'LAX')).toEqual(VIEW_CURVES);
    // Named after the view files.
    const laxIds = withViews.contours.filter((c) => c.kind === 'LAX').map((c) => c.id);
    expect(laxIds.every((id) => /^seg_lax[123] (LV_ENDO|LV_EPI|RV_ENDO)$/.test(id))).toBe(true);
    expect(withViews.contours.filter((c) => c.kind === 'LAX').every((c) => c.pieces.length === 1 && c.pieces[0].closed && c.pieces[0].count >= 50)).toBe(true);
    // The notes: the stack's reading first, then one line per view; none of it among the warnings.
    const notes = withViews.notes ?? [];
    console.log(`# notes:\n#   ${notes.join('\n#   ')}`);
    expect(notes).toHaveLength(4);
    expect(notes[0]).toMatch(/^label map read as 3 LV cavity \(LV_ENDO\), 2 myocardium/);
    VIEWS.forEach((v, i) => expect(notes[i + 1]).toMatch(new RegExp(`^long-axis view ${v.replace(/\./g, '\\.')} read as .* by where its pixels lie in the stack; ${i === 0 ? 2 : 3} curves added`)));
    expect(withViews.warnings.some((w) => w.includes(' read as '))).toBe(false);

    const lv = await run(ask, 1, STACK, 'LV_ENDO');
    const native = cliReport(study.paths[STACK], [...VIEWS.map((v) => study.paths[v]), '--surface', 'LV_ENDO'], 'lax-views-LV_ENDO');
    await load(ask, STACK, study.bytes[STACK], []);
    const sax = await run(ask, 2, STACK, 'LV_ENDO');
    console.log(`# LV_ENDO with views: ${lv.volumeMl.toFixed(1)} ml, mean ${lv.overall.mean.toFixed(3)} mm, max ${lv.overall.max.toFixed(2)} mm, ${lv.positions.length / 3} vertices; `
      + `CLI ${native.volume_ml.toFixed(1)} ml; stack alone ${sax.volumeMl.toFixed(1)} ml`);
    expect(lv.watertight).toBe(true);
    expect(lv.overall.mean).toBeLessThan(1);
    expect(lv.overall.max).toBeLessThan(5);
    // The long-axis curves are among the contours the distances are measured to.
    expect(lv.perContour.filter((c) => /^seg_lax/.test(c.id)).length).toBe(VIEW_CURVES.LV_ENDO);
    expect(lv.positions.length / 3).toBe(native.vertices);
    expect(relative(lv.volumeMl, native.volume_ml)).toBeLessThanOrEqual(1e-9);
    expect(relative(lv.overall.mean, native.contour_to_mesh.mean)).toBeLessThanOrEqual(1e-9);
    // The mesh follows the long-axis curves too (each within 1 mm on average); the stack alone,
    // its apex extrapolated and its base capped one slice above the basal slice, misses them.
    const laxMeans = lv.perContour.filter((c) => c.kind === 'LAX').map((c) => c.stats.mean);
    const saxAtLax = distancesTo(withViews, sax);
    console.log(`# LAX curves to the LV_ENDO mesh: with views ${laxMeans.map((m) => m.toFixed(2)).join(', ')} mm; stack alone's mesh ${saxAtLax.map((m) => m.toFixed(2)).join(', ')} mm`);
    expect(Math.max(...laxMeans)).toBeLessThan(1);
    expect(Math.min(...saxAtLax)).toBeGreaterThan(2 * Math.max(...laxMeans));
    // The same cavity with what lies beyond the stack's slices: 0-30 % more than the stack alone's.
    expect(lv.volumeMl / sax.volumeMl).toBeGreaterThan(1);
    expect(lv.volumeMl / sax.volumeMl).toBeLessThan(1.3);
  });

  it('a damaged view refuses the load, its name first in the message; the stack stays as read', async () => {
    const { ask } = askingCore(wasm);
    const before = await load(ask, STACK, study.bytes[STACK], viewFiles(VIEWS.slice(0, 1)));
    const cut = study.bytes[VIEWS[1]].slice(0, 200);
    const m = await ask({ type: 'load', reqId: 1, fileName: STACK, bytes: buffer(study.bytes[STACK]), views: [...viewFiles(VIEWS.slice(0, 1)), { name: 'cut_lax.nii.gz', bytes: buffer(cut) }] }, 'loaded', 'error');
    if (m.type !== 'error') throw new Error('the damaged view was read');
    console.log(`# damaged view: ${JSON.stringify(m.error)}`);
    expect(m.error.code).toBe('parse');
    expect(m.error.message).toMatch(/^cut_lax\.nii\.gz: the gzip data is damaged/);
    expect(m.error.file).toBe(STACK);
    // The worker keeps its earlier reading: a run has the one view's curves.
    const r = await run(ask, 1, STACK, 'LV_ENDO');
    expect(r.perContour.filter((c) => /^seg_lax/.test(c.id)).map((c) => c.id)).toEqual(['seg_lax1 LV_ENDO']);
    expect(before.contours.length).toBeGreaterThan(0);
  });

  it('a 4D cine with 4D views: frames offered; read as frame 1 it keeps the views, its LV cavity and view curves smaller', async () => {
    const { ask } = askingCore(wasm);
    const stack = cineOf(study.bytes[STACK]);
    const views = viewFiles(VIEWS.map(cineName), (n) => cineOf(study.bytes[VIEWS[VIEWS.map(cineName).indexOf(n)]]));
    const name = cineName(STACK);
    const first = await load(ask, name, stack, views);
    expect(framePicker(first)?.options.map((o) => o.label)).toEqual(['frame 0', 'frame 1']);
    expect(curves(first, 'LAX')).toEqual(VIEW_CURVES);
    const ed = await run(ask, 1, name, 'LV_ENDO');
    // The Frame picker's load: the same views with another frame.
    const second = await load(ask, name, stack, views, '1');
    expect(second.timeFrames).toMatchObject({ read: ['1'], chosen: true });
    expect(curves(second, 'LAX')).toEqual(VIEW_CURVES);
    const shrink = viewArea(second, 'LV_ENDO', 'seg_lax2') / viewArea(first, 'LV_ENDO', 'seg_lax2');
    const es = await run(ask, 2, name, 'LV_ENDO');
    console.log(`# cine with views LV_ENDO: frame 0 ${ed.volumeMl.toFixed(1)} ml, frame 1 ${es.volumeMl.toFixed(1)} ml (ratio ${(es.volumeMl / ed.volumeMl).toFixed(3)}); seg_lax2 LV_ENDO curve area ratio ${shrink.toFixed(3)}`);
    expect(shrink).toBeLessThan(0.97);
    expect(shrink).toBeGreaterThan(0.7);
    expect(ed.watertight && es.watertight).toBe(true);
    expect(es.perContour.filter((c) => /^seg_lax/.test(c.id)).length).toBe(VIEW_CURVES.LV_ENDO);
    expect(es.volumeMl / ed.volumeMl).toBeLessThan(0.95);
    expect(es.volumeMl / ed.volumeMl).toBeGreaterThan(0.7);
  });
});
