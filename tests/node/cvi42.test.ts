// A Circle cvi42 workspace read with its DICOM images through the worker's logic and the real
// wasm, on the core's fixture (biv-me patient 1 drawn in the pixels of 110 header-only cine
// images: 11 slices x 10 frames, contours at frames 0 and 9). The images go in as the app hands
// them over, header slices read by io/dicomHeaders.ts: of the fixture's files, of the same files
// with 256 KiB of pixels, and with a 100 KB private group before the image plane (a header longer
// than the first slice, the plane past it, holding bytes that look like the pixel data tag). Each reading
// equals the whole files', and the command line's (`heartmesh info --json`, `reconstruct`).
import { beforeAll, describe, expect, it } from 'vitest';
import { DEFAULT_OPTIONS, type LoadedFile, type RunResult, type ViewFile } from '../../web/src/core-client/protocol';
import { FIRST_SLICE, imageHeaders } from '../../web/src/io/dicomHeaders';
import { ROOT, cliInfo, cliReport, filesIn, loadWasm, readBytes } from './helpers.mjs';
import { askingCore, type Ask } from './askCore';

const DIR = `${ROOT}/wasm-core/crates/heartmesh-core/tests/data/cvi42-patient1`;
const WSX = `${DIR}/Contours.cvi42wsx`;
const DICOM = `${DIR}/dicom`;
const PIXELS = 256 * 1024;

type Wasm = typeof import('../../web/pkg/heartmesh_wasm.js');
let wasm: Wasm;
let names: string[];
let wholes: Uint8Array[];

beforeAll(async () => {
  wasm = await loadWasm();
  names = filesIn(DICOM);
  wholes = names.map((n) => readBytes(`${DICOM}/${n}`));
});

const buffer = (bytes: Uint8Array) => bytes.slice().buffer as ArrayBuffer;
const le32 = (n: number) => new Uint8Array(new Uint32Array([n]).buffer);
const concat = (...parts: Uint8Array[]) => {
  const out = new Uint8Array(parts.reduce((n, p) => n + p.length, 0));
  let at = 0;
  for (const p of parts) (out.set(p, at), (at += p.length));
  return out;
};
const ascii = (s: string) => new TextEncoder().encode(s);

/** A fixture image's header: all but its pixel data element (tag, OW, length 8, 8 bytes) at the end. */
function headerOf(file: Uint8Array): Uint8Array {
  const at = file.length - 20;
  expect([...file.subarray(at, at + 6)]).toEqual([0xe0, 0x7f, 0x10, 0x00, 0x4f, 0x57]);
  return file.subarray(0, at);
}

/** The image with `PIXELS` bytes of pixel data. */
function withPixels(file: Uint8Array): Uint8Array {
  return concat(headerOf(file), new Uint8Array([0xe0, 0x7f, 0x10, 0x00, 0x4f, 0x57, 0, 0]), le32(PIXELS), new Uint8Array(PIXELS));
}

/** Where the first element of `group` (or a later one) begins in an explicit VR little endian file. */
function elementOffset(file: Uint8Array, group: number): number {
  const view = new DataView(file.buffer, file.byteOffset, file.byteLength);
  const long = new Set(['OB', 'OW', 'OF', 'OD', 'OL', 'OV', 'SQ', 'UT', 'UN', 'UC', 'UR', 'SV', 'UV']);
  for (let at = 132; at + 8 <= file.length; ) {
    if (view.getUint16(at, true) >= group) return at;
    const vr = String.fromCharCode(file[at + 4], file[at + 5]);
    at += long.has(vr) ? 12 + view.getUint32(at + 8, true) : 8 + view.getUint16(at + 6, true);
  }
  throw new Error(`no element of group ${group.toString(16)}`);
}

/**
 * The image with a private group (0019) of 100 KB before its plane (group 0020) and 256 KiB of
 * pixels: the header outgrows the first slice, and the elements the core needs lie past it. The
 * group's value repeats the pixel data tag's bytes followed by what is neither a VR nor a length
 * that fits the file: no place to cut.
 */
function withLongHeader(file: Uint8Array): Uint8Array {
  const creator = concat(new Uint8Array([0x19, 0x00, 0x10, 0x00]), ascii('LO'), new Uint8Array([14, 0]), ascii('HEARTMESH TEST'));
  const value = new Uint8Array(100_000);
  for (let i = 0; i + 8 <= value.length; i += 8) value.set([0xe0, 0x7f, 0x10, 0x00, 0xff, 0xff, 0xff, 0x7f], i);
  const big = concat(new Uint8Array([0x19, 0x00, 0x10, 0x10]), ascii('OB'), new Uint8Array([0, 0]), le32(value.length), value);
  const full = withPixels(file);
  const at = elementOffset(full, 0x0020);
  return concat(full.subarray(0, at), creator, big, full.subarray(at));
}

const filesOf = (bytes: Uint8Array[]) => bytes.map((b, i) => new File([buffer(b)], names[i]));

async function load(ask: Ask, views: ViewFile[], frame?: string): Promise<LoadedFile> {
  const m = await ask({ type: 'load', reqId: 1, fileName: 'Contours.cvi42wsx', bytes: buffer(readBytes(WSX)), views, ...(frame === undefined ? {} : { frame }) }, 'loaded', 'error');
  if (m.type === 'error') throw new Error(m.error.message);
  return m.file;
}

async function run(ask: Ask, surface: string): Promise<RunResult> {
  const m = await ask({ type: 'run', runId: 1, fileName: 'Contours.cvi42wsx', surface, params: {}, lids: 'auto', options: { ...DEFAULT_OPTIONS } }, 'done', 'error');
  if (m.type === 'error') throw new Error(m.error.message);
  return m.result;
}

/** Contours and points of each surface as loaded. */
function perSurface(file: LoadedFile): Record<string, [number, number]> {
  const out: Record<string, [number, number]> = {};
  for (const c of file.contours) {
    const s = c.surface ?? '';
    const [n, p] = out[s] ?? [0, 0];
    out[s] = [n + 1, p + c.pieces.reduce((k, piece) => k + piece.count, 0)];
  }
  return out;
}

interface Info {
  contours: number;
  points: number;
  surfaces: { surface: string; contours: number; points: number }[];
}

/** `heartmesh info --json` of the workspace with its image folder (`--frame frame`). */
const info = (frame?: string): Info => cliInfo([WSX, DICOM], frame ? ['--frame', frame] : []) as Info;

describe('a cvi42 workspace opened with its DICOM images', () => {
  it('reads header slices of 256 KiB-pixel images as the whole files, cut where the pixels begin', async () => {
    const whole = filesOf(wholes.map(withPixels));
    const { images, unreadable } = await imageHeaders(whole);
    expect(unreadable).toEqual([]);
    expect(images.map((v) => v.name)).toEqual(names);
    // Each slice is the header alone: the fixture's file less its pixel element (20 bytes).
    images.forEach((v, i) => expect(v.bytes.byteLength).toBe(wholes[i].length - 20));
    const { ask } = askingCore(wasm);
    const sliced = await load(ask, images);
    const full = await load(ask, names.map((name, i) => ({ name, bytes: buffer(withPixels(wholes[i])) })));
    expect(perSurface(sliced)).toEqual(perSurface(full));
    expect(sliced.contours).toEqual(full.contours);
    expect(sliced.notes?.[0]).toMatch(/^workspace read with 110 DICOM images: contours on 17 of them, in 9 cine slices/);
  });

  it('reads further when a header outgrows the first slice, past bytes that only look like the pixel tag', async () => {
    const long = wholes.map(withLongHeader);
    expect(long[0].length).toBeGreaterThan(FIRST_SLICE + PIXELS);
    const { images } = await imageHeaders(filesOf(long));
    // The header (100 KB of private group) is kept whole, the pixels left.
    images.forEach((v, i) => expect(v.bytes.byteLength).toBe(long[i].length - PIXELS - 12));
    const { ask } = askingCore(wasm);
    const sliced = await load(ask, images);
    const plain = await load(ask, wholes.map((b, i) => ({ name: names[i], bytes: buffer(b) })));
    expect(sliced.contours).toEqual(plain.contours);
    expect(sliced.warnings).toEqual(plain.warnings);
    // A first slice alone would have cut the header: the core sets every image aside.
    const cut = long.map((b, i) => ({ name: names[i], bytes: buffer(b.subarray(0, FIRST_SLICE)) }));
    await expect(load(ask, cut)).rejects.toThrow(/none of the 110 files given with it is a DICOM image with an image plane/);
  });

  it('gives each surface the contours and points the command line reads, frame 0 and frame 9', async () => {
    const { images } = await imageHeaders(filesOf(wholes));
    const { ask } = askingCore(wasm);
    const first = await load(ask, images);
    const read = info();
    expect(read.contours).toBe(32);
    expect(read.points).toBe(1791);
    expect(first.contours.length).toBe(read.contours);
    expect(Object.values(perSurface(first)).reduce((n, [, p]) => n + p, 0)).toBe(read.points);
    for (const s of read.surfaces) expect(perSurface(first)[s.surface][0]).toBe(s.contours);
    expect(first.timeFrames?.frames).toEqual(['0', '9']);
    expect(first.warnings.join('\n')).toMatch(/frame 0 read, 1204 points of other frames left out; choose another with the Frame picker/);
    expect(first.warnings.join('\n')).toMatch(/saPapMuscContour skipped/);
    // cvi42's SAX reference points are the RV insertions, its long-axis extent points landmarks.
    expect(first.warnings.join('\n')).not.toMatch(/RefPoint/);
    const names = first.landmarks.map((l) => l.name);
    expect([names.filter((n) => n === 'RV_INSERT_ANTERIOR').length, names.filter((n) => n === 'RV_INSERT_INFERIOR').length, names.filter((n) => n === 'LAX_LV_EXTENT').length]).toEqual([5, 5, 7]);
    // The run's contour points are those `info` counts per surface (after cleaning): 441 of LV_ENDO.
    const r = await run(ask, 'LV_ENDO');
    const lv = read.surfaces.find((s) => s.surface === 'LV_ENDO');
    expect(lv?.points).toBe(441);
    expect(r.contourPoints.length / 3).toBe(441);
    expect(r.watertight).toBe(true);
    expect(r.overall.mean).toBeLessThanOrEqual(1);
    // As the command line reconstructs it: the same mesh (the core is deterministic across targets).
    const report = cliReport(WSX, [DICOM, '--surface', 'LV_ENDO'], 'cvi42-lv-endo');
    expect(r.indices.length / 3).toBe(report.triangles);
    expect(r.positions.length / 3).toBe(report.vertices);
    expect(r.overall.mean).toBeCloseTo(report.contour_to_mesh.mean, 6);
    expect(r.volumeMl).toBeCloseTo(report.volume_ml, 6);

    const nine = await load(ask, images, '9');
    const info9 = info('9');
    expect(nine.timeFrames?.read).toEqual(['9']);
    for (const s of info9.surfaces) expect(perSurface(nine)[s.surface][0]).toBe(s.contours);
    expect(perSurface(nine).LV_ENDO[0]).toBe(7);
    const r9 = await run(ask, 'LV_ENDO');
    expect(r9.contourPoints.length / 3).toBe(info9.surfaces.find((s) => s.surface === 'LV_ENDO')?.points);
    expect(r9.contourPoints.length / 3).toBe(269);
  });

  it('refuses the workspace alone, saying to open it with its images, and files that are no images are set aside', async () => {
    const { ask } = askingCore(wasm);
    await expect(load(ask, [])).rejects.toThrow(/open it together with the DICOM images it was drawn on/);
    const { images } = await imageHeaders([...filesOf(wholes), new File(['just notes'], 'README.txt')]);
    const file = await load(ask, images);
    expect(file.contours.length).toBe(32);
    expect(file.warnings.join('\n')).toMatch(/1 file set aside: not DICOM \(README\.txt\)/);
    expect(file.notes?.[0]).toMatch(/^workspace read with 110 DICOM images: .*; 1 other file given with it set aside$/);
  });
});
