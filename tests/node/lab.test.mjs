// Node tests of the validation lab's wasm binding (heartmesh-wasm/src/lab.rs): the parametric LV
// sliced like a CMR acquisition and rebuilt is within a fraction of a mm of itself, the comparison
// is exact on an identical surface, bad truth meshes are clear errors, and leave-one-out / sweep
// batches report one item per contour / grid point.
import assert from 'node:assert/strict';
import { before, describe, it } from 'node:test';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { dataDir, loadWasm, thrownError } from './helpers.mjs';

let wasm;
before(async () => {
  wasm = await loadWasm();
});

/** A Session with the lab's simulated contours loaded under `name`. */
function loadSimulated(lab, name) {
  const session = new wasm.Session();
  session.load(name, lab.simulated_csv());
  return session;
}

function runToEnd(session, name, params = {}) {
  session.start(name, null, JSON.stringify(params), 'auto');
  for (let guard = 0; guard < 100000; guard++) if (JSON.parse(session.step()).done) return;
  throw new Error('run did not finish');
}

function drainBatch(lab) {
  const items = [];
  let last;
  for (let guard = 0; guard < 1_000_000; guard++) {
    last = JSON.parse(lab.batch_step());
    if (last.item) items.push(last.item);
    if (last.done) return { items, last };
  }
  throw new Error('batch did not finish');
}

describe('wasm Lab', () => {
  it('parametric LV, 8 SAX + 2 LAX, rebuilt at defaults: mean distance < 0.3 mm both ways', () => {
    const lab = new wasm.Lab();
    const truth = JSON.parse(lab.make_parametric('{}'));
    assert.equal(truth.closed, true);
    assert.equal(lab.truth_positions(0).length, truth.vertices * 3);
    assert.equal(lab.truth_indices(0).length, truth.triangles * 3);
    // 80 x 25 mm spheroid cut at a 20 mm base: volume between the inscribed cone and the cylinder.
    assert.ok(truth.volumeMl > 60 && truth.volumeMl < 157, `volume ${truth.volumeMl} ml`);
    const acq = JSON.parse(lab.simulate(JSON.stringify({ sax_count: 8, lax_count: 2 })));
    assert.equal(acq.sax, 8);
    assert.equal(acq.lax, 2);
    // Clip plane: normal along the long axis (+z for the built-in LV), below the 80 mm base.
    assert.ok(Math.abs(Math.abs(acq.clip.normal[2]) - 1) < 1e-6, `normal ${acq.clip.normal}`);
    assert.ok(acq.clip.origin[2] > 60 && acq.clip.origin[2] < 80, `clip at z ${acq.clip.origin[2]}`);

    const session = loadSimulated(lab, 'lv.csv');
    runToEnd(session, 'lv.csv');
    const report = JSON.parse(lab.compare(null, session.positions(), session.indices()));
    console.log(
      `# parametric LV 8 SAX + 2 LAX: mesh->truth mean ${report.mesh_to_truth.mean.toFixed(3)} p95 ${report.mesh_to_truth.p95.toFixed(3)} max ${report.mesh_to_truth.max.toFixed(3)}; truth->mesh mean ${report.truth_to_mesh.mean.toFixed(3)}; Hausdorff ${report.hausdorff.toFixed(3)} mm; volume ${report.volume_truth_ml.toFixed(2)} / ${report.volume_mesh_ml.toFixed(2)} ml`,
    );
    assert.equal(report.clipped, true);
    assert.ok(report.mesh_to_truth.mean < 0.3, `mesh->truth mean ${report.mesh_to_truth.mean}`);
    assert.ok(report.truth_to_mesh.mean < 0.3, `truth->mesh mean ${report.truth_to_mesh.mean}`);
    assert.ok(report.hausdorff >= report.mesh_to_truth.max && report.hausdorff < 3, `hausdorff ${report.hausdorff}`);
    assert.ok(Math.abs(report.volume_mesh_ml - report.volume_truth_ml) / report.volume_truth_ml < 0.03, 'clipped volumes within 3 %');
    const d = lab.truth_distances();
    assert.equal(d.length, truth.vertices);
    // Measured below the most basal SAX plane, NaN (not measured) above it.
    const pos = lab.truth_positions(0);
    const zClip = acq.clip.origin[2] * Math.sign(acq.clip.normal[2]);
    let measured = 0;
    for (let i = 0; i < d.length; i++) {
      const above = pos[i * 3 + 2] * Math.sign(acq.clip.normal[2]) > zClip + 1e-3;
      const below = pos[i * 3 + 2] * Math.sign(acq.clip.normal[2]) < zClip - 1e-3;
      if (above) assert.ok(Number.isNaN(d[i]), `vertex ${i} above the clip: ${d[i]}`);
      if (below) {
        assert.ok(Number.isFinite(d[i]) && d[i] >= 0 && d[i] < 2, `vertex ${i}: ${d[i]} mm`);
        measured++;
      }
    }
    assert.ok(measured > truth.vertices * 0.8, `${measured} of ${truth.vertices} measured`);
  });

  it('a surface compared with itself: zero distances, equal volumes', () => {
    const lab = new wasm.Lab();
    lab.make_parametric(JSON.stringify({ length_mm: 70, radius_mm: 22, base_radius_mm: 18, bulge_mm: 4 }));
    lab.simulate(JSON.stringify({ sax_spacing_mm: 10, lax_count: 1 }));
    const r = JSON.parse(lab.compare(null, lab.truth_positions(0), lab.truth_indices(0)));
    assert.ok(r.hausdorff < 1e-4, `hausdorff ${r.hausdorff}`);
    assert.ok(Math.abs(r.volume_truth_ml - r.volume_mesh_ml) < 1e-3);
  });

  it('bad inputs are errors with codes, and the Lab stays usable', () => {
    const lab = new wasm.Lab();
    assert.equal(thrownError(() => lab.simulate('{}')).code, 'no_truth');
    const garbage = new TextEncoder().encode('solid x\nfacet normal 0 0 1\nnot a vertex\n');
    const e = thrownError(() => lab.load_truth('broken.stl', garbage));
    assert.ok(e.message.length > 5, e.message);
    const tri = new TextEncoder().encode('v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n');
    assert.equal(thrownError(() => lab.load_truth('one-triangle.obj', tri)).code, 'degenerate');
    assert.equal(thrownError(() => lab.make_parametric(JSON.stringify({ base_radius_mm: 30 }))).code, 'degenerate');
    lab.make_parametric('{}');
    assert.equal(thrownError(() => lab.simulate(JSON.stringify({ lax_count: 9 }))).code, 'param_out_of_range');
    assert.equal(thrownError(() => lab.compare(null, new Float32Array(9), new Uint32Array([0, 1, 5]))).code, 'invalid_mesh');
    // An OBJ truth read through the core's mesh readers.
    const obj = ['v 0 0 0', 'v 10 0 0', 'v 0 10 0', 'v 0 0 10', 'f 1 3 2', 'f 1 2 4', 'f 2 3 4', 'f 3 1 4'].join('\n');
    const t = JSON.parse(lab.load_truth('tet.obj', new TextEncoder().encode(obj)));
    assert.equal(t.vertices, 4);
    assert.ok(Math.abs(t.volumeMl - 1000 / 6 / 1000) < 1e-9, `tetrahedron volume ${t.volumeMl}`);
  });

  it('several truths: labels checked across the boundary, one acquisition, the truth of the surface compared', () => {
    const lab = new wasm.Lab();
    const mesh = (name) => readFileSync(join(dataDir(), 'meshes', name));
    lab.load_truth('lv.obj', mesh('bivme-patient1-ED-LV_ENDO-closed.obj'));
    lab.set_truth_label(0, 'LV_ENDO');
    const rv = JSON.parse(lab.add_truth('rv.obj', 'RV_ENDO', mesh('bivme-patient1-ED-RV_ENDO-closed.obj')));
    assert.equal(rv.index, 1);
    assert.equal(thrownError(() => lab.add_truth('x.obj', 'lv_endo', mesh('bivme-patient1-ED-LV_ENDO-closed.obj'))).code, 'label_taken');
    assert.equal(thrownError(() => lab.set_truth_label(1, 'RV ENDO')).code, 'label_invalid');
    const acq = JSON.parse(lab.simulate(JSON.stringify({ sax_count: 8, lax_count: 2 })));
    assert.deepEqual(acq.surfaces.map((s) => s.label), ['LV_ENDO', 'RV_ENDO']);
    assert.match(new TextDecoder().decode(lab.simulated_csv()).split('\n').find((l) => !l.startsWith('#')), /surface/);
    const r = JSON.parse(lab.compare('RV_ENDO', lab.truth_positions(1), lab.truth_indices(1)));
    assert.equal(r.truth_label, 'RV_ENDO');
    assert.ok(r.mesh_to_truth.mean < 1e-4);
    assert.equal(lab.truth_distances().length, rv.vertices);
    assert.equal(thrownError(() => lab.compare('LV_EPI', lab.truth_positions(1), lab.truth_indices(1))).code, 'no_truth_for_surface');
    assert.equal(JSON.parse(lab.remove_truth(0)).length, 1);
  });

  it('leave-one-out reports one item per contour; a sweep one per grid point', () => {
    const lab = new wasm.Lab();
    lab.make_parametric('{}');
    lab.simulate(JSON.stringify({ sax_count: 4, lax_count: 1 }));
    const session = loadSimulated(lab, 'small.csv');
    const params = JSON.stringify({ iterations: 60 });
    const info = JSON.parse(lab.start_leave_one_out(session, 'small.csv', null, params, 'auto'));
    assert.equal(info.total, 5);
    assert.equal(info.contours.length, 5);
    const pointCount = info.contours.reduce((n, c) => n + c.pieces.reduce((m, p) => m + p.count, 0), 0);
    assert.equal(lab.batch_points().length, pointCount * 3);
    const { items, last } = drainBatch(lab);
    assert.equal(items.length, 5);
    assert.equal(last.completed, 5);
    assert.deepEqual(items.map((i) => i.index), [0, 1, 2, 3, 4]);
    for (const it of items) {
      assert.equal(it.error, null);
      assert.ok(it.stats.mean > 0 && it.stats.mean < 4, `${it.id}: mean ${it.stats.mean} mm`);
    }
    assert.equal(items.filter((i) => i.kind === 'LAX').length, 1);
    assert.equal(thrownError(() => lab.batch_step()).code, 'no_batch');

    const sweepJson = JSON.stringify({ grid: { lambda: [1e3, 1e5], target_reduction: [0.6, 0.72] }, with_truth: true });
    assert.equal(JSON.parse(lab.start_sweep(session, 'small.csv', null, params, 'auto', sweepJson)).total, 4);
    const sweep = drainBatch(lab).items;
    assert.equal(sweep.length, 4);
    for (const r of sweep) {
      assert.ok(r.contour_mean > 0 && r.contour_mean < 2, `contour mean ${r.contour_mean}`);
      assert.ok(r.truth_mean > 0 && r.truth_mean < 3, `truth mean ${r.truth_mean}`);
      assert.ok(r.hausdorff >= r.truth_mean);
    }
    assert.equal(thrownError(() => lab.start_sweep(session, 'small.csv', null, params, 'auto', '{"grid":{"beta":[1]}}')).code, 'param_invalid');
    assert.equal(thrownError(() => lab.start_leave_one_out(session, 'missing.csv', null, params, 'auto')).code, 'not_loaded');
  });
});
