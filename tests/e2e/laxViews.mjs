// A segmented study with long-axis views for the tests, made by the native CLI from the CardioMesh
// SPASM surfaces in shared/data/meshes (`heartmesh segment ... -o seg.nii.gz --lax 3`): the
// short-axis stack seg.nii.gz (100 x 108 x 10 voxels, 1.25 mm pixels, 10 mm slices; 3 LV cavity,
// 2 myocardium, 1 RV cavity) and seg_lax1..3.nii.gz, single-slice label maps through the apex
// (seg_lax1 shows no RV). Written to a scratch folder, never under tests/. Also a 4D cine of a
// study (built here: the CLI writes 3D files), frame 0 the files themselves and frame 1 the same
// with the LV cavity one pixel smaller all round in each slice (systole), the views alike.
// Used by tests/e2e/labelMapViews.test.mjs and tests/node/labelMapViews.test.ts.
import { execFileSync } from 'node:child_process';
import { existsSync, mkdtempSync, readFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, resolve, dirname } from 'node:path';
import { fileURLToPath } from 'node:url';
import { gunzipSync } from 'node:zlib';

const ROOT = resolve(dirname(fileURLToPath(import.meta.url)), '..', '..');
const CLI = join(ROOT, 'wasm-core', 'target', 'release', 'heartmesh');

export const STACK = 'seg.nii.gz';
/** The core's DICOM SEG fixture: this study's stack (the app's example) in DICOM's LPS (scripts/seg_fixture.py). */
export const DICOM_SEG = join(ROOT, 'wasm-core', 'crates', 'heartmesh-core', 'tests', 'data', 'spasm-seg.dcm');
/** The DICOM SEG fixture's bytes. */
export const dicomSegBytes = () => new Uint8Array(readFileSync(DICOM_SEG));
export const VIEWS = ['seg_lax1.nii.gz', 'seg_lax2.nii.gz', 'seg_lax3.nii.gz'];
/** Long-axis curves each surface gets from the three views (seg_lax1, a 2-chamber view, has no RV). */
export const VIEW_CURVES = { LV_ENDO: 3, LV_EPI: 3, RV_ENDO: 2 };

function meshes() {
  const candidates = [process.env.HEARTMESH_DATA, join(ROOT, '..', 'shared', 'data'), join(ROOT, '..', '..', 'shared', 'data'), '/work/shared/data']
    .filter(Boolean);
  const found = candidates.find((d) => existsSync(join(d, 'meshes', 'cardiomesh-spasm-LV_endo.obj')));
  if (!found) throw new Error(`shared/data/meshes not found (tried ${candidates.join(', ')}); set HEARTMESH_DATA`);
  return join(found, 'meshes');
}

/**
 * Writes the study with the CLI into a scratch folder; returns it, the paths by file name and the
 * bytes by file name.
 */
export function makeStudy() {
  if (!existsSync(CLI)) throw new Error(`${CLI} missing: cd wasm-core && cargo build --release -p heartmesh-cli`);
  const dir = mkdtempSync(join(tmpdir(), 'heartmesh-lax-'));
  const m = meshes();
  execFileSync(CLI, [
    'segment', '--lv-endo', join(m, 'cardiomesh-spasm-LV_endo.obj'), '--lv-epi', join(m, 'cardiomesh-spasm-LV_epi.obj'),
    '--rv-free-wall', join(m, 'cardiomesh-spasm-RV_endo.obj'), '-o', join(dir, STACK), '--lax', '3', '--quiet',
  ]);
  const paths = Object.fromEntries([STACK, ...VIEWS].map((n) => [n, join(dir, n)]));
  const bytes = Object.fromEntries([STACK, ...VIEWS].map((n) => [n, new Uint8Array(readFileSync(paths[n]))]));
  return { dir, paths, bytes };
}

/**
 * The study's stack as 3D Slicer saves a segmentation (`heartmesh segment -o seg.seg.nrrd`: gzip,
 * LPS, segments named), written to a scratch folder; returns its path and bytes.
 */
export function makeSlicerSegmentation() {
  if (!existsSync(CLI)) throw new Error(`${CLI} missing: cd wasm-core && cargo build --release -p heartmesh-cli`);
  const dir = mkdtempSync(join(tmpdir(), 'heartmesh-nrrd-'));
  const m = meshes();
  const path = join(dir, 'seg.seg.nrrd');
  execFileSync(CLI, [
    'segment', '--lv-endo', join(m, 'cardiomesh-spasm-LV_endo.obj'), '--lv-epi', join(m, 'cardiomesh-spasm-LV_epi.obj'),
    '--rv-free-wall', join(m, 'cardiomesh-spasm-RV_endo.obj'), '-o', path, '--quiet',
  ]);
  return { path, bytes: new Uint8Array(readFileSync(path)) };
}

/** Header (with its extension bytes), dims and uint8 voxels of a NIfTI-1 file (gzip or not). */
function parts(bytes) {
  const nii = bytes[0] === 0x1f && bytes[1] === 0x8b ? new Uint8Array(gunzipSync(bytes)) : bytes;
  const view = new DataView(nii.buffer, nii.byteOffset, nii.byteLength);
  const offset = view.getFloat32(108, true);
  const dims = [1, 2, 3].map((i) => view.getInt16(40 + 2 * i, true));
  if (view.getInt16(70, true) !== 2) throw new Error('expected a uint8 label map');
  return { header: nii.slice(0, offset), dims, voxels: nii.slice(offset, offset + dims[0] * dims[1] * dims[2]) };
}

/** The LV cavity (3) one pixel smaller in each i-j slice: cavity next to any other label becomes myocardium (2). */
export function systole(voxels, dims) {
  const out = voxels.slice();
  const [ni, nj, nk] = dims;
  const at = (i, j, k) => voxels[i + ni * (j + nj * k)];
  for (let k = 0; k < nk; k++) {
    for (let j = 1; j < nj - 1; j++) {
      for (let i = 1; i < ni - 1; i++) {
        if (at(i, j, k) !== 3) continue;
        if (at(i - 1, j, k) !== 3 || at(i + 1, j, k) !== 3 || at(i, j - 1, k) !== 3 || at(i, j + 1, k) !== 3) out[i + ni * (j + nj * k)] = 2;
      }
    }
  }
  return out;
}

/** The file as a 4D cine (uncompressed .nii) of two frames: 0 as it is, 1 its systole. */
export function cineOf(bytes) {
  const { header, dims, voxels } = parts(bytes);
  const n = voxels.length;
  const out = new Uint8Array(header.length + 2 * n);
  out.set(header);
  const view = new DataView(out.buffer);
  view.setInt16(40, 4, true); // dim[0]: four dimensions
  view.setInt16(48, 2, true); // dim[4]: two time frames
  view.setFloat32(92, 40, true); // pixdim[4]: 40 ms between frames
  out.set(voxels, header.length);
  out.set(systole(voxels, dims), header.length + n);
  return out;
}

/** The cine names of the study's files (`seg.nii.gz` -> `seg-cine.nii`). */
export const cineName = (name) => name.replace(/\.nii\.gz$/, '-cine.nii');
