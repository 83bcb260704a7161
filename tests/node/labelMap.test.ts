// NIfTI label maps (segmentations) through the worker's logic with the real wasm: the bytes the app
// hands over, gzip as stored or inflated (what a server sending `.gz` with `Content-Encoding: gzip`
// gives fetch), read to the same contours of LV_ENDO, LV_EPI and RV_ENDO with the reading line
// first; the LV endocardium reconstructs closed, near its contours and near the volume of its
// voxels (the reading in `notes`, not among the warnings). A 4D cine offers its labelled frames to the Frame picker, and its systolic frame reads to
// a smaller LV cavity around the same epicardium. A damaged download, an image and a NIfTI-2 file
// are refused with one clear line each. A compressed CSV reads as the CSV. Label maps:
// tests/e2e/labelMaps.mjs.
import { beforeAll, describe, expect, it } from 'vitest';
import { curveArea } from './curveArea';
import { DEFAULT_OPTIONS, type LoadedFile, type RunResult } from '../../web/src/core-client/protocol';
import { framePicker } from '../../web/src/app/timeFrames';
import { loadWasm, readBytes, ROOT } from './helpers.mjs';
import { askingCore, type Ask } from './askCore';
import {
  CINE_FRAMES, CINE_NAME, cineCounts, cineLabelMap, damagedSample, gzipped, imageLikeSample, inflatedSample, SAMPLE_NAME, SAMPLE_READING, sampleBytes,
} from '../e2e/labelMaps.mjs';

type Wasm = typeof import('../../web/pkg/heartmesh_wasm.js');
let wasm: Wasm;

beforeAll(async () => {
  wasm = await loadWasm();
});

/** A copy of `bytes` in an ArrayBuffer of its own (as `File.arrayBuffer()` gives it). */
const buffer = (bytes: Uint8Array) => bytes.slice().buffer as ArrayBuffer;

async function load(ask: Ask, fileName: string, bytes: Uint8Array, frame?: string): Promise<LoadedFile> {
  const m = await ask({ type: 'load', reqId: 1, fileName, bytes: buffer(bytes), ...(frame === undefined ? {} : { frame }) }, 'loaded', 'error');
  if (m.type === 'error') throw new Error(m.error.message);
  return m.file;
}

async function refusal(ask: Ask, fileName: string, bytes: Uint8Array): Promise<string> {
  const m = await ask({ type: 'load', reqId: 1, fileName, bytes: buffer(bytes) }, 'loaded', 'error');
  if (m.type !== 'error') throw new Error(`${fileName} was read`);
  expect(m.error.code).toBe('parse');
  return m.error.message;
}

async function run(ask: Ask, runId: number, fileName: string, surface: string): Promise<RunResult> {
  const m = await ask({ type: 'run', runId, fileName, surface, params: {}, lids: 'auto', options: { ...DEFAULT_OPTIONS } }, 'done', 'error');
  if (m.type === 'error') throw new Error(m.error.message);
  return m.result;
}

/** Enclosed area (mm2) of the file's closed curves of `surface`, summed (Newell's vector area). */
function area(file: LoadedFile, surface: string): number {
  return curveArea(file, (c) => c.surface === surface);
}

/** Voxels of 1.25 x 1.25 x 10 mm, in ml. */
const ml = (voxels: number) => (voxels * 15.625) / 1000;

describe('NIfTI label maps through the worker', () => {
  it('the example, gzip or inflated, reads as LV_ENDO, LV_EPI and RV_ENDO, one closed curve a slice, the reading in the notes', async () => {
    const { ask } = askingCore(wasm);
    const gz = await load(ask, SAMPLE_NAME, sampleBytes());
    expect([...gz.surfaces].sort()).toEqual(['LV_ENDO', 'LV_EPI', 'RV_ENDO']);
    // The reading is information (the notes line), not a warning.
    expect(gz.notes).toEqual([SAMPLE_READING]);
    expect(gz.warnings).not.toContain(SAMPLE_READING);
    expect(gz.timeFrames ?? null).toBeNull();
    // One curve per slice holding the structure (of the 10: the LV cavity in slices 1-6, the
    // myocardium in 0-7, the RV cavity in 0-6), each closed.
    const curves = (s: string) => gz.contours.filter((c) => c.surface === s);
    expect(Object.fromEntries(['LV_ENDO', 'LV_EPI', 'RV_ENDO'].map((s) => [s, curves(s).length]))).toEqual({ LV_ENDO: 6, LV_EPI: 8, RV_ENDO: 7 });
    expect(gz.contours.every((c) => c.pieces.length === 1 && c.pieces[0].closed && c.pieces[0].count >= 20)).toBe(true);
    // The curves enclose about the structures' pixels (1.25 mm): 10 mm apart, their areas make
    // about the voxels' volumes.
    const { diastole } = cineCounts();
    expect(area(gz, 'LV_ENDO') * 10 / 1000 / ml(diastole[3])).toBeCloseTo(1, 1);
    expect(area(gz, 'LV_EPI') * 10 / 1000 / ml(diastole[3] + diastole[2])).toBeCloseTo(1, 1);
    expect(area(gz, 'RV_ENDO') * 10 / 1000 / ml(diastole[1])).toBeCloseTo(1, 1);

    // Inflated by the server on the way (vite's preview does): the same contours, point for point.
    const raw = await load(ask, 'inflated.nii.gz', inflatedSample());
    expect(raw.surfaces).toEqual(gz.surfaces);
    expect(raw.contours).toEqual(gz.contours);
    expect(raw.points).toEqual(gz.points);
    // By content, whatever the name.
    const unnamed = await load(ask, 'download', sampleBytes());
    expect(unnamed.points).toEqual(gz.points);
  });

  it('the LV endocardium: closed, within 1 mm of its contours, within 6 % of its voxels\' volume', async () => {
    const { ask } = askingCore(wasm);
    await load(ask, SAMPLE_NAME, sampleBytes());
    const lv = await run(ask, 1, SAMPLE_NAME, 'LV_ENDO');
    const voxels = ml(cineCounts().diastole[3]);
    console.log(`# label map LV_ENDO: ${lv.volumeMl.toFixed(1)} ml (voxels ${voxels.toFixed(1)} ml), mean ${lv.overall.mean.toFixed(3)} mm, ${lv.positions.length / 3} vertices`);
    expect(lv.watertight).toBe(true);
    expect(lv.overall.mean).toBeLessThan(1);
    expect(Math.abs(lv.volumeMl - voxels) / voxels).toBeLessThan(0.06);
  });

  it('a 4D cine: its labelled frames offered, the first read; the systolic frame\'s LV cavity smaller, its epicardium the same', async () => {
    const { ask } = askingCore(wasm);
    const cine = cineLabelMap();
    const first = await load(ask, CINE_NAME, cine);
    expect(first.timeFrames).toEqual({ frames: CINE_FRAMES, count: 2, read: ['1'], firsts: ['1'], chosen: false, leftOut: 0, sequence: true });
    expect(first.notes).toEqual([SAMPLE_READING]);
    expect(first.warnings).toContain('the label map holds 2 labelled time frames (1, 2): frame 1 read; choose another with the Frame picker');
    expect(framePicker(first)?.options.map((o) => o.label)).toEqual(['frame 1', 'frame 2']);
    // Frame 1 is the example itself.
    const example = await load(ask, SAMPLE_NAME, sampleBytes());
    expect(first.points).toEqual(example.points);

    const second = await load(ask, CINE_NAME, cine, '2');
    expect(second.timeFrames).toMatchObject({ read: ['2'], chosen: true });
    expect(second.warnings.some((w) => w.includes('time frames'))).toBe(false);
    const { diastole, systole } = cineCounts();
    const shrink = area(second, 'LV_ENDO') / area(first, 'LV_ENDO');
    console.log(`# cine LV_ENDO curve area frame 2 / frame 1: ${shrink.toFixed(3)} (voxels ${(systole[3] / diastole[3]).toFixed(3)})`);
    expect(shrink).toBeLessThan(0.95);
    expect(shrink).toBeGreaterThan(0.75);
    expect(area(second, 'LV_EPI')).toBeCloseTo(area(first, 'LV_EPI'), 6);
    // Cut short (an uncompressed download that stopped): the header's size against the bytes present.
    expect(await refusal(ask, CINE_NAME, cine.slice(0, 400))).toMatch(/^the file is truncated: .*100 x 108 x 10 x 3 voxels.*\(324000 bytes\) but 48 follow/);
  });

  it('a compressed contour file (contours.csv.gz, as the Open dialog\'s .gz offers it) reads as what it holds', async () => {
    const { ask } = askingCore(wasm);
    const csv = readBytes(`${ROOT}/public/samples/patient1-ED.csv`);
    const plain = await load(ask, 'patient1-ED.csv', csv);
    const gz = await load(ask, 'patient1-ED (2).csv.gz', gzipped(csv));
    expect(gz.surfaces).toEqual(plain.surfaces);
    expect(gz.contours).toEqual(plain.contours);
    expect(gz.points).toEqual(plain.points);
  });

  it('a damaged download, an image and a NIfTI-2 file are refused with one clear line', async () => {
    const { ask } = askingCore(wasm);
    const damaged = await refusal(ask, SAMPLE_NAME, damagedSample());
    expect(damaged).toMatch(/^the gzip data is damaged/);
    expect(damaged).not.toContain('\n');
    const image = await refusal(ask, 'cine_4d.nii', imageLikeSample());
    expect(image).toMatch(/^this NIfTI is an image, not a label map \(segmentation\): it holds more than 64 values/);
    const two = new Uint8Array(540 + 16);
    new DataView(two.buffer).setInt32(0, 540, true);
    two.set(new TextEncoder().encode('n+2\0\r\n\x1a\n'), 4);
    expect(await refusal(ask, 'seg.nii', two)).toMatch(/NIfTI-2 files are not read; save the label map as NIfTI-1/);
  });
});
