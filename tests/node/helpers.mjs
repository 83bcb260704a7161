// Shared helpers of the Node tests of the built wasm (web/pkg, from scripts/build-wasm.sh) and of
// the wasm benchmark: load the module synchronously, find the shared test data, run a
// reconstruction to the end through the Session, read OBJ files.
import { execFileSync } from 'node:child_process';
import { existsSync, mkdtempSync, readdirSync, readFileSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

export const ROOT = resolve(dirname(fileURLToPath(import.meta.url)), '..', '..');
export const PKG = join(ROOT, 'web', 'pkg');
export const CLI = join(ROOT, 'wasm-core', 'target', 'release', 'heartmesh');

/** The wasm module, initialised synchronously from web/pkg. */
export async function loadWasm() {
  const glue = join(PKG, 'heartmesh_wasm.js');
  if (!existsSync(glue)) throw new Error(`${glue} is missing: run scripts/build-wasm.sh first`);
  const wasm = await import(glue);
  wasm.initSync({ module: readFileSync(join(PKG, 'heartmesh_wasm_bg.wasm')) });
  return wasm;
}

/** The shared data folder: $HEARTMESH_DATA, or shared/data beside the repository (CI layout), or
 * two levels up (git worktrees under wt/). Missing data is an error, never a skipped test. */
export function dataDir() {
  const candidates = [
    process.env.HEARTMESH_DATA,
    join(ROOT, '..', 'shared', 'data'),
    join(ROOT, '..', '..', 'shared', 'data'),
  ].filter(Boolean);
  const found = candidates.find((d) => existsSync(join(d, 'contours')));
  if (!found) throw new Error(`test data not found; looked in ${candidates.join(', ')}`);
  return found;
}

export const SURFCO = () => join(dataDir(), 'contours', 'surfco-example.csv');
export const PATIENT1_ED = () => join(dataDir(), 'contours', 'bivme-example-patient1', 'patient1-ED.csv');
export const PATIENT2_ES = () => join(dataDir(), 'contours', 'bivme-test-patient2', 'patient2-ES.csv');

/** A file's bytes. */
export function readBytes(path) {
  return new Uint8Array(readFileSync(path));
}

/** The CoreErrorData a Session call threw (errors cross as JSON strings). */
export function thrownError(f) {
  try {
    f();
  } catch (e) {
    if (typeof e !== 'string') throw e;
    return JSON.parse(e);
  }
  throw new Error('expected the call to throw');
}

/**
 * Loads `path`, runs a full reconstruction and returns the session with the step reports.
 * `params` maps schema names to numbers.
 */
export function reconstruct(wasm, path, { surface = null, params = {}, lids = 'auto' } = {}) {
  const session = new wasm.Session();
  const name = path.split('/').at(-1);
  session.load(name, readFileSync(path));
  const t0 = performance.now();
  session.start(name, surface, JSON.stringify(params), lids);
  const reports = [];
  for (let guard = 0; guard < 100000; guard++) {
    const report = JSON.parse(session.step());
    reports.push(report);
    if (report.done) break;
  }
  const ms = performance.now() - t0;
  return { session, reports, ms };
}

/** Vertices (flat f64 xyz) and triangles (flat, 0-based) of an OBJ file. */
export function readObj(text) {
  const positions = [];
  const indices = [];
  for (const line of text.split('\n')) {
    const f = line.trim().split(/\s+/);
    if (f[0] === 'v') positions.push(Number(f[1]), Number(f[2]), Number(f[3]));
    else if (f[0] === 'f') for (const c of f.slice(1, 4)) indices.push(parseInt(c, 10) - 1);
  }
  return { positions: Float64Array.from(positions), indices: Uint32Array.from(indices) };
}

/** Largest |a - b| / max(|b|, floor) over two equally long arrays. */
export function maxRelativeDifference(a, b, floor = 1) {
  if (a.length !== b.length) throw new Error(`length ${a.length} != ${b.length}`);
  let worst = 0;
  for (let i = 0; i < a.length; i++) {
    const d = Math.abs(a[i] - b[i]) / Math.max(Math.abs(b[i]), floor);
    if (!(d <= worst)) worst = Number.isNaN(d) ? Infinity : d;
  }
  return worst;
}

/** A file's text. */
export function readText(path) {
  return readFileSync(path, 'utf8');
}

let scratch = null;

/** Writes `text` as `name` in a scratch folder of this process and returns its path. */
export function writeScratch(name, text) {
  scratch ??= mkdtempSync(join(tmpdir(), 'heartmesh-node-'));
  const path = join(scratch, name);
  writeFileSync(path, text);
  return path;
}

/** The native CLI's `reconstruct` report (JSON) of `input` with `args` (the mesh goes to the scratch folder). */
export function cliReport(input, args, label) {
  if (!existsSync(CLI)) throw new Error(`${CLI} missing: cd wasm-core && cargo build --release`);
  const report = writeScratch(`${label}.json`, '');
  execFileSync(CLI, ['reconstruct', input, '-o', writeScratch(`${label}.obj`, ''), '--report', report, '--quiet', ...args]);
  return JSON.parse(readFileSync(report, 'utf8'));
}

/** The native CLI's `volumes --json` document of the phases `inputs` (files, or one sequence) with `args`. */
export function cliVolumes(inputs, args, label) {
  if (!existsSync(CLI)) throw new Error(`${CLI} missing: cd wasm-core && cargo build --release`);
  const json = writeScratch(`${label}.json`, '');
  execFileSync(CLI, ['volumes', ...inputs, '--json', json, '--quiet', ...args]);
  return JSON.parse(readFileSync(json, 'utf8'));
}

/**
 * The native CLI's `myocardium` of `input` with `args`: its report (JSON) and the wall as OBJ text;
 * with `bullseye`, also the AHA bullseye it writes with `--bullseye` (SVG text).
 */
export function cliMyocardium(input, args, label, { bullseye = false } = {}) {
  if (!existsSync(CLI)) throw new Error(`${CLI} missing: cd wasm-core && cargo build --release`);
  const obj = writeScratch(`${label}.obj`, '');
  const report = writeScratch(`${label}.json`, '');
  const svg = bullseye ? writeScratch(`${label}-segments.svg`, '') : null;
  execFileSync(CLI, ['myocardium', input, '-o', obj, '--report', report, '--quiet', ...(svg ? ['--bullseye', svg] : []), ...args]);
  const out = { report: JSON.parse(readFileSync(report, 'utf8')), obj: readFileSync(obj, 'utf8') };
  return svg ? { ...out, bullseye: readFileSync(svg, 'utf8') } : out;
}

/**
 * The native CLI's `myocardium` of `input` with `--hex-mesh` (`args`: `--hex-layout`, `--layers`
 * and other options): its report (JSON) and the hexahedral mesh's VTK file (bytes).
 */
export function cliHexWall(input, args, label) {
  if (!existsSync(CLI)) throw new Error(`${CLI} missing: cd wasm-core && cargo build --release`);
  const report = writeScratch(`${label}.json`, '');
  const hex = writeScratch(`${label}-hex.vtk`, '');
  execFileSync(CLI, ['myocardium', input, '-o', writeScratch(`${label}.obj`, ''), '--report', report, '--hex-mesh', hex, '--quiet', ...args]);
  return { report: JSON.parse(readFileSync(report, 'utf8')), vtk: new Uint8Array(readFileSync(hex)) };
}

/**
 * The native CLI's `reconstruct` of `input` with `--anatomical-mesh` (`args`: its surface and
 * options): its report (JSON), the reconstructed mesh as OBJ text and the anatomical mesh's file
 * (bytes) in the format of `ext`.
 */
export function cliAnatomical(input, args, label, ext = 'vtk') {
  if (!existsSync(CLI)) throw new Error(`${CLI} missing: cd wasm-core && cargo build --release`);
  const obj = writeScratch(`${label}.obj`, '');
  const report = writeScratch(`${label}.json`, '');
  const grid = writeScratch(`${label}-grid.${ext}`, '');
  execFileSync(CLI, ['reconstruct', input, '-o', obj, '--report', report, '--anatomical-mesh', grid, '--quiet', ...args]);
  return { report: JSON.parse(readFileSync(report, 'utf8')), obj: readFileSync(obj, 'utf8'), grid: new Uint8Array(readFileSync(grid)) };
}

/** The native CLI's `segment` (`args`: its surfaces and options) into the scratch folder as `name`; returns its path. */
export function cliSegment(args, name) {
  if (!existsSync(CLI)) throw new Error(`${CLI} missing: cd wasm-core && cargo build --release`);
  const out = writeScratch(name, '');
  execFileSync(CLI, ['segment', ...args, '-o', out, '--quiet']);
  return out;
}

/** The native CLI's `simulate` of the truth mesh `truth` with `args`, into the scratch folder as `name`; returns its path. */
export function cliSimulate(truth, args, name) {
  if (!existsSync(CLI)) throw new Error(`${CLI} missing: cd wasm-core && cargo build --release`);
  const out = writeScratch(name, '');
  execFileSync(CLI, ['simulate', truth, '-o', out, '--quiet', ...args]);
  return out;
}

/** The native CLI's `info` of `inputs` (files, or a folder of them) with `args`, as `--json` prints it. */
export function cliInfo(inputs, args = []) {
  if (!existsSync(CLI)) throw new Error(`${CLI} missing: cd wasm-core && cargo build --release`);
  return JSON.parse(execFileSync(CLI, ['info', ...inputs, '--json', ...args], { encoding: 'utf8' }));
}

/** The names of the files in folder `dir`, in name order. */
export function filesIn(dir) {
  return readdirSync(dir).sort();
}
