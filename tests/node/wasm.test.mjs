// Tests of the built wasm module (web/pkg) under Node: the Session API on real contour files,
// the errors it throws, and the differential test against the native CLI (same mesh to 1e-9).
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { existsSync, mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, describe, it } from 'node:test';
import {
  CLI,
  PATIENT1_ED,
  ROOT,
  SURFCO,
  loadWasm,
  maxRelativeDifference,
  readObj,
  reconstruct,
  thrownError,
} from './helpers.mjs';

let wasm;
let tmp;
before(async () => {
  wasm = await loadWasm();
  tmp = mkdtempSync(join(tmpdir(), 'heartmesh-node-'));
});
after(() => rmSync(tmp, { recursive: true, force: true }));

/** Checks a finished run: done, closed, close to its contours; returns the small result. */
function checkFinished({ session, reports }, label) {
  const last = reports.at(-1);
  assert.equal(last.done, true, `${label}: not done`);
  assert.equal(session.is_done(), true);
  assert.equal(reports[0].phase, 'initial_tube');
  assert.equal(reports[0].topology_changed, true);
  const result = JSON.parse(session.result_json());
  const positions = session.positions();
  const indices = session.indices();
  assert.ok(positions instanceof Float32Array && indices instanceof Uint32Array);
  assert.equal(positions.length, last.vertices * 3, `${label}: vertex count`);
  assert.equal(indices.length, last.triangles * 3, `${label}: triangle count`);
  assert.ok(positions.every(Number.isFinite), `${label}: non-finite vertex`);
  assert.ok(indices.every((i) => i < last.vertices), `${label}: index out of range`);
  assert.equal(result.watertight, true, `${label}: mesh not closed`);
  assert.ok(result.volumeMl > 10 && result.volumeMl < 1000, `${label}: volume ${result.volumeMl} ml`);
  assert.ok(result.overall.mean <= 1.0, `${label}: contour-to-mesh mean ${result.overall.mean} mm > 1 mm`);
  const pointDistances = session.point_distances();
  assert.equal(pointDistances.length, result.overall.count);
  assert.equal(session.contour_points().length, pointDistances.length * 3);
  assert.equal(session.vertex_distances().length, last.vertices);
  const pieceTotal = result.contours.flatMap((c) => c.pieces).reduce((n, p) => n + p.count, 0);
  assert.equal(pieceTotal, pointDistances.length, `${label}: pieces do not index the points`);
  for (const c of result.contours) assert.ok(c.kind === 'SAX' || c.kind === 'LAX');
  return result;
}

/** Runs the native CLI on the same input and compares mesh, volume, area and distances. */
function compareWithCli(run, result, input, args, label) {
  assert.ok(existsSync(CLI), `${CLI} missing: cargo build --release -p heartmesh-cli`);
  const obj = join(tmp, `${label}.obj`);
  const reportPath = join(tmp, `${label}.json`);
  execFileSync(CLI, ['reconstruct', input, '-o', obj, '--report', reportPath, '--quiet', ...args]);
  const native = readObj(readFileSync(obj, 'utf8'));
  const report = JSON.parse(readFileSync(reportPath, 'utf8'));
  const wasmPositions = run.session.positions_f64();
  assert.deepEqual(Array.from(run.session.indices()), Array.from(native.indices), `${label}: triangles differ`);
  const dPos = maxRelativeDifference(wasmPositions, native.positions);
  const dVol = Math.abs(result.volumeMl - report.volume_ml) / Math.abs(report.volume_ml);
  const dArea = Math.abs(result.areaMm2 - report.area_mm2) / Math.abs(report.area_mm2);
  let diag = `${label}: wasm vs native relative differences: positions ${dPos.toExponential(2)}, ` +
    `volume ${dVol.toExponential(2)}, area ${dArea.toExponential(2)}`;
  // The mesh checks agree too (same mesh, same counts); every real case is free of crossings.
  assert.deepEqual(result.quality, {
    folded_edges: report.quality.folded_edges,
    self_intersections: report.quality.self_intersections,
  }, `${label}: mesh checks differ`);
  assert.equal(result.quality.self_intersections, 0, `${label}: self-intersecting triangles`);
  const c2m = report.contour_to_mesh;
  let dMean = 0;
  let dMax = 0;
  if (c2m) {
    dMean = Math.abs(result.overall.mean - c2m.mean) / Math.max(c2m.mean, 1e-3);
    dMax = Math.abs(result.overall.max - c2m.max) / Math.max(c2m.max, 1e-3);
    diag += `, contour-to-mesh mean ${dMean.toExponential(2)}, max ${dMax.toExponential(2)}`;
  }
  console.log(diag);
  assert.ok(c2m, `${label}: the CLI report has no contour_to_mesh (${diag})`);
  for (const d of [dPos, dVol, dArea, dMean, dMax]) assert.ok(d <= 1e-9, diag);
}

describe('wasm Session', () => {
  it('exposes the parameter schema and the version', () => {
    const schema = JSON.parse(wasm.schema_json());
    const names = schema.map((s) => s.name);
    for (const n of ['iterations', 'lambda', 'beta', 'remesh_every', 'target_reduction']) assert.ok(names.includes(n), n);
    const lambda = schema.find((s) => s.name === 'lambda');
    assert.equal(lambda.default, 1e5);
    assert.equal(lambda.log, true);
    assert.match(wasm.version(), /^\d+\.\d+\.\d+/);
    assert.equal(wasm.take_panic_message(), undefined, 'no panic recorded');
  });

  it('loads a contour file and describes it', () => {
    const session = new wasm.Session();
    const info = JSON.parse(session.load('surfco-example.csv', readFileSync(SURFCO())));
    assert.equal(info.fileName, 'surfco-example.csv');
    assert.equal(info.contours.length, 8, 'surfco: 6 SAX + 2 LAX contours');
    const points = session.file_points('surfco-example.csv');
    const count = info.contours.flatMap((c) => c.pieces).reduce((n, p) => n + p.count, 0);
    assert.equal(points.length, count * 3);
    assert.ok(count > 2000 && count < 4000, `surfco has ~3000 points, got ${count}`);
    assert.ok(points.every(Number.isFinite));
    // The core's SAX/LAX split, at load (no run yet).
    assert.deepEqual(info.contours.map((c) => c.kind).sort(), ['LAX', 'LAX', 'SAX', 'SAX', 'SAX', 'SAX', 'SAX', 'SAX']);
  });

  it('throws errors as data with code, line and choices', () => {
    const session = new wasm.Session();
    const bad = new TextEncoder().encode('contour,x,y,z\nc1,1,2,3\nc1,1,oops,3\n');
    const e = thrownError(() => session.load('bad.csv', bad));
    assert.equal(e.code, 'parse');
    assert.equal(e.line, 3);
    session.load('p1.csv', readFileSync(PATIENT1_ED()));
    const s = thrownError(() => session.start('p1.csv', null, '{}', 'auto'));
    assert.equal(s.code, 'surface_required');
    assert.deepEqual([...s.available].sort(), ['LV_ENDO', 'LV_EPI', 'RV_ENDO', 'RV_EPI']);
    const p = thrownError(() => session.start('p1.csv', 'LV_ENDO', '{"beta": 5}', 'auto'));
    assert.equal(p.code, 'param_out_of_range');
    assert.equal(thrownError(() => session.start('nope.csv', null, '{}', 'auto')).code, 'not_loaded');
    assert.equal(thrownError(() => session.step()).code, 'no_run');
  });

  it('reconstructs the SurFCo example within 1 mm, identical to the native CLI', () => {
    const run = reconstruct(wasm, SURFCO());
    const result = checkFinished(run, 'surfco');
    console.log(`surfco: ${run.reports.length} steps in ${run.ms.toFixed(0)} ms, mean ${result.overall.mean.toFixed(3)} mm, ` +
      `max ${result.overall.max.toFixed(3)} mm, ${result.volumeMl.toFixed(2)} ml`);
    compareWithCli(run, result, SURFCO(), [], 'surfco');
  });

  it('reconstructs biv-me patient 1 ED LV endocardium within 1 mm, identical to the native CLI', () => {
    const run = reconstruct(wasm, PATIENT1_ED(), { surface: 'LV_ENDO' });
    const result = checkFinished(run, 'patient1 LV_ENDO');
    assert.equal(result.surface, 'LV_ENDO');
    console.log(`patient1 LV_ENDO: ${run.reports.length} steps in ${run.ms.toFixed(0)} ms, mean ${result.overall.mean.toFixed(3)} mm, ` +
      `max ${result.overall.max.toFixed(3)} mm, ${result.volumeMl.toFixed(2)} ml`);
    compareWithCli(run, result, PATIENT1_ED(), ['--surface', 'LV_ENDO'], 'patient1');
    // The kinds given at load are the run's kinds (per surface, before any run).
    const loaded = JSON.parse(new wasm.Session().load('p1.csv', readFileSync(PATIENT1_ED())));
    const atLoad = new Map(loaded.contours.filter((c) => c.surface === 'LV_ENDO').map((c) => [c.id, c.kind]));
    assert.equal(atLoad.size, result.contours.length);
    for (const c of result.contours) assert.equal(atLoad.get(c.id), c.kind, `kind of ${c.id}`);
    assert.ok(loaded.contours.every((c) => c.kind === 'SAX' || c.kind === 'LAX'));
  });

  it('reconstructs biv-me patient 1 ED RV endocardium (free wall + septum pieces), identical to the native CLI', () => {
    const run = reconstruct(wasm, PATIENT1_ED(), { surface: 'RV_ENDO' });
    const result = checkFinished(run, 'patient1 RV_ENDO');
    console.log(`patient1 RV_ENDO: ${run.reports.length} steps in ${run.ms.toFixed(0)} ms, mean ${result.overall.mean.toFixed(3)} mm, ` +
      `max ${result.overall.max.toFixed(3)} mm, ${result.volumeMl.toFixed(2)} ml`);
    compareWithCli(run, result, PATIENT1_ED(), ['--surface', 'RV_ENDO'], 'patient1-rv');
  });

  it('reconstructs a Segment study (a compressed MAT-file holding its image) at its end-diastole, identical to the native CLI', () => {
    const study = join(ROOT, 'wasm-core', 'crates', 'heartmesh-core', 'tests', 'data', 'segment-patient1', 'patient1.mat');
    const run = reconstruct(wasm, study, { surface: 'RV_ENDO' });
    const result = checkFinished(run, 'segment RV_ENDO');
    console.log(`segment RV_ENDO: ${run.reports.length} steps in ${run.ms.toFixed(0)} ms, ${result.volumeMl.toFixed(2)} ml`);
    assert.ok(Math.abs(result.volumeMl - 193.83) < 0.01, `${result.volumeMl} ml (heartmesh-core tests/segment.rs: 193.83)`);
    compareWithCli(run, result, study, ['--surface', 'RV_ENDO'], 'segment-rv');
  });

  it('applies parameters and lids (an open mesh is not watertight)', () => {
    const run = reconstruct(wasm, SURFCO(), { params: { iterations: 30 }, lids: 'none' });
    const last = run.reports.at(-1);
    assert.equal(last.done, true);
    assert.ok(run.reports.length <= 32, `${run.reports.length} steps for 30 iterations`);
    const result = JSON.parse(run.session.result_json());
    assert.equal(result.params.iterations, 30);
    assert.equal(result.lids, 'none');
    assert.equal(result.watertight, false);
  });
});
