// 3D Slicer segmentations (`.seg.nrrd`) in the app's core: the native CLI paints the CardioMesh
// SPASM surfaces as the same label map twice (`heartmesh segment -o seg.nii.gz` and `-o
// seg.seg.nrrd`); the wasm Session reads the NRRD as it reads the NIfTI: the same surfaces and
// curves, every point within 1e-3 mm (the NIfTI's sform is single precision), its note naming the
// file's LPS space and the segments; a cut-short file is refused with the reason.
import { beforeAll, describe, expect, it } from 'vitest';
import { cliSegment, dataDir, loadWasm, readBytes, thrownError } from './helpers.mjs';

type Wasm = typeof import('../../web/pkg/heartmesh_wasm.js');
let wasm: Wasm;
const files: Record<string, Uint8Array> = {};

beforeAll(async () => {
  wasm = await loadWasm();
  const m = `${dataDir()}/meshes`;
  for (const out of ['seg.nii.gz', 'seg.seg.nrrd']) {
    const args = ['--lv-endo', `${m}/cardiomesh-spasm-LV_endo.obj`, '--lv-epi', `${m}/cardiomesh-spasm-LV_epi.obj`, '--rv-free-wall', `${m}/cardiomesh-spasm-RV_endo.obj`];
    files[out] = readBytes(cliSegment(args, out));
  }
});

interface Loaded {
  surfaces: string[];
  contours: { id: string; surface: string | null }[];
  notes: string[];
  warnings: string[];
}

describe('NRRD label maps (3D Slicer)', () => {
  it('read as the NIfTI of the same segmentation', () => {
    const session = new wasm.Session();
    const read = (name: string) => JSON.parse(session.load(name, files[name], undefined)) as Loaded;
    const nii = read('seg.nii.gz');
    const nrrd = read('seg.seg.nrrd');
    expect(nrrd.surfaces).toEqual(['LV_ENDO', 'LV_EPI', 'RV_ENDO']);
    expect(nrrd.contours.map((c) => c.id)).toEqual(nii.contours.map((c) => c.id));
    const a = session.file_points('seg.nii.gz');
    const b = session.file_points('seg.seg.nrrd');
    expect(b.length).toBe(a.length);
    let worst = 0;
    for (let i = 0; i < a.length; i++) worst = Math.max(worst, Math.abs(a[i] - b[i]));
    expect(worst).toBeLessThan(1e-3);
    expect(nrrd.notes[0]).toMatch(/^label map read as 3 LV cavity .* space directions \(LPS, as 3D Slicer saves\); segments 3 LV, 2 Myocardium, 1 RV$/);
    expect(nrrd.warnings.some((w) => w.startsWith('label map read as'))).toBe(false);
    session.free();
  });

  it('refuses a cut-short file with the reason', () => {
    const session = new wasm.Session();
    const bytes = files['seg.seg.nrrd'];
    const e = thrownError(() => session.load('cut.seg.nrrd', bytes.subarray(0, bytes.length - 400), undefined));
    expect(e.message).toMatch(/gzip data is damaged|truncated/);
    session.free();
  });
});
