// Time frames through the worker's logic with the real wasm, against the native CLI: a GPFile of
// biv-me patient 1's frames 0 and 9 (built from GPFile_000.txt and GPFile_009.txt, tests/e2e/
// twoFrames.mjs) loads with its frames listed and frame 0 read; loaded again as frame 9 (the Frame
// picker's load), its LV endocardium is the CLI's `reconstruct --frame 9` (vertices, triangles,
// contour-to-mesh mean and volume to 1e-9) and GPFile_009.txt's on its own. A frame the file lacks
// is refused with the frames it has, leaving the file as it was read; a session of frame 9 says so.
// Phases written as text (patient 1's ED and ES CSVs in one file with a `phase` column, built by
// twoFrames.mjs): frame ES, asked for as listed or in another case, is the CLI's `--frame ES` and
// patient1-ES.csv's mesh on its own; a session of it records `ES` and loads back as ES.
import { beforeAll, describe, expect, it } from 'vitest';
import { DEFAULT_OPTIONS, type LoadedFile, type RunResult } from '../../web/src/core-client/protocol';
import { cliReport, dataDir, loadWasm, readText, writeScratch } from './helpers.mjs';
import { FRAMES, PHASES, PHASES_NAME, phasesCsv, TWO_FRAMES_NAME, twoFrameGpFile } from '../e2e/twoFrames.mjs';
import { askingCore, type Ask } from './askCore';

type Wasm = typeof import('../../web/pkg/heartmesh_wasm.js');
let wasm: Wasm;
let twoPath = '';
let twoText = '';
let esPath = '';
let phasesPath = '';
let phasesText = '';
let esCsvPath = '';

beforeAll(async () => {
  wasm = await loadWasm();
  const dir = `${dataDir()}/contours/bivme-example-patient1`;
  esPath = `${dir}/GPFile_009.txt`;
  twoText = twoFrameGpFile(readText(`${dir}/GPFile_000.txt`), readText(esPath));
  twoPath = writeScratch(TWO_FRAMES_NAME, twoText);
  esCsvPath = `${dir}/patient1-ES.csv`;
  phasesText = phasesCsv(readText(`${dir}/patient1-ED.csv`), readText(esCsvPath));
  phasesPath = writeScratch(PHASES_NAME, phasesText);
});

async function load(ask: Ask, fileName: string, text: string, frame?: string): Promise<LoadedFile> {
  const bytes = new TextEncoder().encode(text).buffer as ArrayBuffer;
  const m = await ask({ type: 'load', reqId: 1, fileName, bytes, ...(frame === undefined ? {} : { frame }) }, 'loaded', 'error');
  if (m.type === 'error') throw new Error(m.error.message);
  return m.file;
}

async function run(ask: Ask, runId: number, fileName: string): Promise<RunResult> {
  const m = await ask({ type: 'run', runId, fileName, surface: 'LV_ENDO', params: {}, lids: 'auto', options: { ...DEFAULT_OPTIONS } }, 'done', 'error');
  if (m.type === 'error') throw new Error(m.error.message);
  return m.result;
}

const relative = (a: number, b: number) => Math.abs(a - b) / Math.max(Math.abs(b), 1e-12);

/** The worker's result is the CLI's report: the mesh's counts, the figures to 1e-9. */
// eslint-disable-next-line @typescript-eslint/no-explicit-any
function expectSame(r: RunResult, native: Record<string, any>): void {
  expect(r.positions.length / 3).toBe(native.vertices);
  expect(r.indices.length / 3).toBe(native.triangles);
  expect(relative(r.overall.mean, native.contour_to_mesh.mean)).toBeLessThanOrEqual(1e-9);
  expect(relative(r.volumeMl, native.volume_ml)).toBeLessThanOrEqual(1e-9);
}

describe('time frames through the worker, against the CLI', () => {
  it('a two-frame GPFile: frames listed, frame 0 read; frame 9 is the CLI\'s --frame 9 and GPFile_009.txt alone', async () => {
    const { ask } = askingCore(wasm);
    const first = await load(ask, TWO_FRAMES_NAME, twoText);
    expect(first.timeFrames).toEqual({ frames: FRAMES, count: 2, read: ['0'], firsts: ['0'], chosen: false, leftOut: 1225, sequence: true });
    const w = first.warnings.find((x) => x.includes('time frames')) ?? '';
    expect(w).toBe('the file holds 2 time frames (0, 9): frame 0 read, 1225 points of other frames left out; choose another with the Frame picker');
    const zero = await run(ask, 1, TWO_FRAMES_NAME);
    expectSame(zero, cliReport(twoPath, ['--surface', 'LV_ENDO', '--frame', '0'], 'two-frames-0'));

    const nine = await load(ask, TWO_FRAMES_NAME, twoText, '9');
    expect(nine.timeFrames).toMatchObject({ read: ['9'], chosen: true, sequence: true });
    expect(nine.warnings.some((x) => x.includes('time frames'))).toBe(false);
    const r9 = await run(ask, 2, TWO_FRAMES_NAME);
    const native9 = cliReport(twoPath, ['--surface', 'LV_ENDO', '--frame', '9'], 'two-frames-9');
    expectSame(r9, native9);
    expect(r9.volumeMl).not.toBe(zero.volumeMl);

    // GPFile_009.txt on its own: no sequence (slice 8's own frame 1.0 is no phase), the same mesh.
    const alone = await load(ask, 'GPFile_009.txt', readText(esPath));
    expect(alone.timeFrames).toMatchObject({ frames: ['9', '1'], sequence: false, leftOut: 0 });
    const es = await run(ask, 3, 'GPFile_009.txt');
    expect(es.positions.length).toBe(r9.positions.length);
    expect(es.volumeMl).toBe(r9.volumeMl);
    expect(es.overall.mean).toBe(r9.overall.mean);
    console.log(`# ${TWO_FRAMES_NAME} LV endo: frame 0 ${zero.volumeMl.toFixed(2)} ml ${zero.positions.length / 3} vertices; frame 9 ${r9.volumeMl.toFixed(2)} ml ${r9.positions.length / 3} vertices (CLI ${native9.volume_ml.toFixed(2)} ml)`);
  });

  it('a frame the file lacks is refused with the frames it has; the file stays as it was read; a session of frame 9 says so', async () => {
    const { ask } = askingCore(wasm);
    const nine = await load(ask, TWO_FRAMES_NAME, twoText, '9');
    const bytes = new TextEncoder().encode(twoText).buffer as ArrayBuffer;
    const refused = await ask({ type: 'load', reqId: 2, fileName: TWO_FRAMES_NAME, bytes, frame: '3' }, 'loaded', 'error');
    expect(refused.type).toBe('error');
    if (refused.type !== 'error') return;
    expect(refused.error).toMatchObject({ code: 'parse', file: TWO_FRAMES_NAME, message: 'no contour points in frame 3 (frames in the file: 0, 9)' });
    const saved = await ask({ type: 'session-export', reqId: 3, fileName: TWO_FRAMES_NAME, surface: 'LV_ENDO', params: {}, lids: 'auto', options: { ...DEFAULT_OPTIONS }, appVersion: '9.9.9' }, 'session-json', 'error');
    if (saved.type !== 'session-json') throw new Error(saved.error.message);
    const doc = JSON.parse(new TextDecoder().decode(saved.bytes));
    expect(doc.frame).toBe('9');
    const back = await load(ask, 'frame9-session.json', new TextDecoder().decode(saved.bytes));
    expect(back.timeFrames).toMatchObject({ frames: ['9'], read: ['9'], chosen: true, sequence: false });
    // Its contours are frame 9's: the frame refused in between did not replace them.
    expect(back.contours.length).toBe(nine.contours.length);
    expect(back.points).toEqual(nine.points);
  });

  it('phases written as text: ES (asked for in any case) is the CLI\'s --frame ES and patient1-ES.csv alone; a session of it says ES', async () => {
    const { ask } = askingCore(wasm);
    const first = await load(ask, PHASES_NAME, phasesText);
    expect(first.timeFrames).toEqual({ frames: PHASES, count: 2, read: ['ED'], firsts: ['ED'], chosen: false, leftOut: 1204, sequence: true });
    expect(first.warnings).toContain('the file holds 2 time frames (ED, ES): frame ED read, 1204 points of other frames left out; choose another with the Frame picker');
    const ed = await run(ask, 1, PHASES_NAME);
    expectSame(ed, cliReport(phasesPath, ['--surface', 'LV_ENDO'], 'phases-default'));

    const native = cliReport(phasesPath, ['--surface', 'LV_ENDO', '--frame', 'ES'], 'phases-es');
    expect(native.frame).toBe('ES');
    const alone = await load(ask, 'patient1-ES.csv', readText(esCsvPath));
    expect(alone.timeFrames ?? null).toBeNull();
    const esAlone = await run(ask, 2, 'patient1-ES.csv');
    for (const [runId, asked] of [[3, 'ES'], [4, 'es']] as const) {
      const es = await load(ask, PHASES_NAME, phasesText, asked);
      expect(es.timeFrames, asked).toMatchObject({ read: ['ES'], chosen: true, sequence: true, leftOut: 1791 });
      expect(es.warnings.some((x) => x.includes('time frames'))).toBe(false);
      expect(es.points).toEqual(alone.points);
      const r = await run(ask, runId, PHASES_NAME);
      expectSame(r, native);
      expect(r.positions.length).toBe(esAlone.positions.length);
      expect(r.indices.length).toBe(esAlone.indices.length);
      expect(r.volumeMl).toBe(esAlone.volumeMl);
      expect(r.overall.mean).toBe(esAlone.overall.mean);
    }
    expect(native.volume_ml).not.toBe(ed.volumeMl);
    const saved = await ask({ type: 'session-export', reqId: 5, fileName: PHASES_NAME, surface: 'LV_ENDO', params: {}, lids: 'auto', options: { ...DEFAULT_OPTIONS }, appVersion: '9.9.9' }, 'session-json', 'error');
    if (saved.type !== 'session-json') throw new Error(saved.error.message);
    expect(JSON.parse(new TextDecoder().decode(saved.bytes)).frame).toBe('ES');
    const back = await load(ask, 'es-session.json', new TextDecoder().decode(saved.bytes));
    expect(back.timeFrames).toMatchObject({ frames: ['ES'], read: ['ES'], chosen: true, sequence: false });
    expect(back.points).toEqual(alone.points);
    console.log(`# ${PHASES_NAME} LV endo: ED ${ed.volumeMl.toFixed(2)} ml ${ed.positions.length / 3} vertices; ES ${native.volume_ml.toFixed(2)} ml ${native.vertices} vertices (patient1-ES.csv ${esAlone.volumeMl.toFixed(2)} ml ${esAlone.positions.length / 3} vertices)`);
  });
});
