// Label maps (NIfTI-1 segmentations) for the tests, built from the bundled example
// public/samples/cardiomesh-spasm-seg.nii.gz (100 x 108 x 10 voxels of 1.25 x 1.25 x 10 mm; 3 LV
// cavity, 2 myocardium, 1 RV cavity), so no other fixture is committed:
// - a cine: a 4D file of three time frames, frame 0 unlabelled (as a network's output between the
//   frames it segmented), frame 1 the example, frame 2 the example with its LV cavity one pixel
//   smaller all round in every slice (the ring of cavity pixels next to another label becomes
//   myocardium: a heart in systole, its epicardium unchanged);
// - a damaged download: the example's first half;
// - an image: the example with every voxel's value spread over 0-199 (MRI intensities);
// and any file gzip-compressed (a `contours.csv.gz`).
// Used by tests/e2e/labelmap.test.mjs and tests/node/labelMap.test.ts.
import { readFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { gunzipSync, gzipSync } from 'node:zlib';

export const SAMPLE_NAME = 'cardiomesh-spasm-seg.nii.gz';
export const SAMPLE_PATH = join(dirname(fileURLToPath(import.meta.url)), '..', '..', 'public', 'samples', SAMPLE_NAME);
/** The reading the core reports first for the example (and for each frame of the cine). */
export const SAMPLE_READING = 'label map read as 3 LV cavity (LV_ENDO), 2 myocardium (LV_EPI around both), 1 RV cavity (RV_ENDO); '
  + "traced across the k axis, 10.0 mm apart, 1.25 x 1.25 mm pixels; coordinates from the header's sform";
export const CINE_NAME = 'spasm-cine-seg.nii';
/** The cine's frames holding labels (frame 0 holds none). */
export const CINE_FRAMES = ['1', '2'];

const DIMS = [100, 108, 10];
const VOXELS = DIMS[0] * DIMS[1] * DIMS[2];

/** The example as stored (gzip). */
export function sampleBytes() {
  return new Uint8Array(readFileSync(SAMPLE_PATH));
}

/** The example inflated: what a server sending `.gz` with `Content-Encoding: gzip` hands over. */
export function inflatedSample() {
  return new Uint8Array(gunzipSync(sampleBytes()));
}

/** Header (with its 4 extension bytes) and voxels (uint8, i fastest) of the inflated example. */
function parts() {
  const nii = inflatedSample();
  const view = new DataView(nii.buffer, nii.byteOffset, nii.byteLength);
  const offset = view.getFloat32(108, true);
  if (view.getInt16(70, true) !== 2 || nii.length - offset !== VOXELS) throw new Error('the example is no longer uint8 100 x 108 x 10');
  return { header: nii.slice(0, offset), voxels: nii.slice(offset) };
}

/** The LV cavity (3) one pixel smaller in every slice: cavity next to any other label becomes myocardium (2). */
function systole(voxels) {
  const out = voxels.slice();
  const [ni, nj] = DIMS;
  const at = (i, j, k) => voxels[i + ni * (j + nj * k)];
  for (let k = 0; k < DIMS[2]; k++) {
    for (let j = 1; j < nj - 1; j++) {
      for (let i = 1; i < ni - 1; i++) {
        if (at(i, j, k) !== 3) continue;
        if (at(i - 1, j, k) !== 3 || at(i + 1, j, k) !== 3 || at(i, j - 1, k) !== 3 || at(i, j + 1, k) !== 3) out[i + ni * (j + nj * k)] = 2;
      }
    }
  }
  return out;
}

/** Voxels of each label 0-3 in `voxels`. */
export function labelCounts(voxels) {
  const n = [0, 0, 0, 0];
  for (const v of voxels) n[v]++;
  return n;
}

/** The example's and the systolic frame's label counts (for volumes: 15.625 mm3 a voxel). */
export function cineCounts() {
  const { voxels } = parts();
  return { diastole: labelCounts(voxels), systole: labelCounts(systole(voxels)) };
}

/** The 4D cine (uncompressed .nii): frame 0 empty, 1 the example, 2 its systole. */
export function cineLabelMap() {
  const { header, voxels } = parts();
  const out = new Uint8Array(header.length + 3 * VOXELS);
  out.set(header);
  const view = new DataView(out.buffer);
  view.setInt16(40, 4, true); // dim[0]: four dimensions
  view.setInt16(48, 3, true); // dim[4]: three time frames
  view.setFloat32(92, 40, true); // pixdim[4]: 40 ms between frames
  out.set(voxels, header.length + VOXELS);
  out.set(systole(voxels), header.length + 2 * VOXELS);
  return out;
}

/** `bytes` gzip-compressed (a `contours.csv.gz`). */
export function gzipped(bytes) {
  return new Uint8Array(gzipSync(bytes));
}

/** The example's first half (a download cut short). */
export function damagedSample() {
  const bytes = sampleBytes();
  return bytes.slice(0, Math.floor(bytes.length / 2));
}

/** The example as an image: every voxel a value of 0-199 (more values than a label map holds). */
export function imageLikeSample() {
  const { header, voxels } = parts();
  const out = new Uint8Array(header.length + VOXELS);
  out.set(header);
  for (let n = 0; n < VOXELS; n++) out[header.length + n] = (voxels[n] * 50 + (n % 50)) % 200;
  return out;
}
