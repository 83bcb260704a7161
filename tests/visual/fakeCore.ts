/**
 * TEST-ONLY synthetic core for the visual harness (never shipped, never the product path): it
 * implements the CoreClient interface with a made-up "reconstruction" (a sphere morphing into an
 * ellipsoid, remeshed twice), so the viewer, timeline, colour maps and layout can be looked at in
 * Chromium before the real WebAssembly core exists, and with deterministic pictures afterwards.
 */
import type { Frame, LidsMode, LoadedFile, ParamSpec, ParamValues, ReconOptions, RunResult, StepReport, ContourInfo } from '../../web/src/core-client/protocol';
import paramsRs from '../../wasm-core/crates/heartmesh-core/src/params.rs?raw';

function schemaFromRust(): ParamSpec[] {
  const re = /ParamSpec\s*\{\s*name:\s*"([^"]+)",\s*default:\s*([^,]+),\s*min:\s*([^,]+),\s*max:\s*([^,]+),\s*log:\s*(true|false),\s*integer:\s*(true|false),\s*unit:\s*"([^"]*)",\s*help:\s*"([^"]*)"/g;
  return [...(paramsRs as string).matchAll(re)].map((m) => ({
    name: m[1], default: Number(m[2]), min: Number(m[3]), max: Number(m[4]), log: m[5] === 'true', integer: m[6] === 'true', unit: m[7], help: m[8],
  }));
}

/** UV sphere with `rings` x `segments`, radius 1, CCW from outside. */
function sphere(rings: number, segments: number): { positions: Float32Array; indices: Uint32Array } {
  const pos: number[] = [0, 0, 1];
  for (let r = 1; r < rings; r++) {
    const th = (Math.PI * r) / rings;
    for (let s = 0; s < segments; s++) {
      const ph = (2 * Math.PI * s) / segments;
      pos.push(Math.sin(th) * Math.cos(ph), Math.sin(th) * Math.sin(ph), Math.cos(th));
    }
  }
  pos.push(0, 0, -1);
  const idx: number[] = [];
  const ring = (r: number, s: number) => 1 + (r - 1) * segments + (s % segments);
  const south = pos.length / 3 - 1;
  for (let s = 0; s < segments; s++) idx.push(0, ring(1, s), ring(1, s + 1));
  for (let r = 1; r < rings - 1; r++)
    for (let s = 0; s < segments; s++) {
      idx.push(ring(r, s), ring(r + 1, s), ring(r + 1, s + 1), ring(r, s), ring(r + 1, s + 1), ring(r, s + 1));
    }
  for (let s = 0; s < segments; s++) idx.push(south, ring(rings - 1, s + 1), ring(rings - 1, s));
  return { positions: new Float32Array(pos), indices: new Uint32Array(idx) };
}

/** Target shape: an ellipsoid 25 x 22 x 45 mm (half axes) with a flat-ish base. */
function shape(x: number, y: number, z: number, t: number, out: Float32Array, o: number): void {
  const s = 10 + t * 15;
  out[o] = x * s;
  out[o + 1] = y * (10 + t * 12);
  out[o + 2] = z * (10 + t * 35) * (z > 0 ? 0.8 : 1);
}

function contours(): { info: ContourInfo[]; points: Float32Array } {
  const pts: number[] = [];
  const info: ContourInfo[] = [];
  const tmp = new Float32Array(3);
  for (let k = 0; k < 6; k++) {
    const z = -0.75 + k * 0.28;
    const r = Math.sqrt(1 - z * z);
    const start = pts.length / 3;
    for (let i = 0; i < 40; i++) {
      const a = (2 * Math.PI * i) / 40;
      shape(r * Math.cos(a), r * Math.sin(a), z, 1, tmp, 0);
      pts.push(tmp[0] + Math.sin(5 * a) * 0.6, tmp[1], tmp[2]);
    }
    info.push({ id: `sax${k + 1}`, surface: 'LV_ENDO', kind: null, pieces: [{ closed: true, start, count: 40 }] });
  }
  for (const phi of [0.3, 1.9]) {
    const start = pts.length / 3;
    for (let i = 0; i <= 50; i++) {
      const th = 0.35 + (i / 50) * (2 * Math.PI - 0.7);
      shape(Math.sin(th) * Math.cos(phi), Math.sin(th) * Math.sin(phi), Math.cos(th), 1, tmp, 0);
      pts.push(tmp[0], tmp[1], tmp[2]);
    }
    info.push({ id: `lax${info.length - 5}`, surface: 'LV_ENDO', kind: null, pieces: [{ closed: false, start, count: 51 }] });
  }
  // An epicardium ring set for the surface picker.
  for (let k = 0; k < 3; k++) {
    const start = pts.length / 3;
    for (let i = 0; i < 40; i++) {
      const a = (2 * Math.PI * i) / 40;
      pts.push(30 * Math.cos(a), 27 * Math.sin(a), -20 + k * 15);
    }
    info.push({ id: `epi${k + 1}`, surface: 'LV_EPI', kind: null, pieces: [{ closed: true, start, count: 40 }] });
  }
  return { info, points: new Float32Array(pts) };
}

const timings = { attractors_ms: 0.1, closest_ms: 0.3, solve_ms: 1.2, apply_ms: 0.5, remesh_ms: 0, total_ms: 2.1 };

export class FakeCoreClient {
  private runId = 0;
  static create(): Promise<FakeCoreClient> {
    return Promise.resolve(new FakeCoreClient());
  }
  schema(): Promise<{ schema: ParamSpec[]; version: string }> {
    return Promise.resolve({ schema: schemaFromRust(), version: 'fake-core' });
  }
  load(fileName: string, bytes: ArrayBuffer): Promise<LoadedFile> {
    const text = new TextDecoder().decode(bytes);
    if (text.includes('BAD')) return Promise.reject({ code: 'parse', message: 'line 3: x is not a number: "BAD"', line: 3, file: fileName });
    const c = contours();
    return Promise.resolve({ fileName, surfaces: ['LV_ENDO', 'LV_EPI'], contours: c.info, points: c.points, landmarks: [], warnings: [] });
  }
  run(opts: { fileName: string; surface: string | null; params: ParamValues; lids: LidsMode; options?: ReconOptions }, onFrame: (f: Frame) => void) {
    const runId = ++this.runId;
    const total = Math.min(120, opts.params.iterations ?? 60);
    let cancelled = false;
    const done = new Promise<RunResult>((resolve, reject) => {
      let it = 0;
      let mesh = sphere(10, 16);
      let seq = 0;
      const tick = () => {
        if (cancelled) return reject({ code: 'cancelled', message: 'cancelled' });
        const remesh = it === 0 || it === Math.floor(total / 3) || it === Math.floor((2 * total) / 3);
        if (remesh && it > 0) mesh = sphere(10 + it / 2, 16 + it);
        const t = it / total;
        const positions = new Float32Array(mesh.positions.length);
        for (let v = 0; v < positions.length; v += 3) shape(mesh.positions[v], mesh.positions[v + 1], mesh.positions[v + 2], t, positions, v);
        const report: StepReport = {
          iteration: it, total_iterations: total, phase: it === 0 ? 'initial_tube' : it === total ? 'done' : remesh ? 'remesh' : 'deform',
          topology_changed: remesh, max_distance_mm: 20 * Math.exp(-it / 12) + 0.8, mean_distance_mm: 8 * Math.exp(-it / 10) + 0.2,
          vertices: positions.length / 3, triangles: mesh.indices.length / 3, attractors: 150, timings, done: it === total,
        };
        const c = contours();
        onFrame({ runId, seq: seq++, report, positions, indices: remesh ? mesh.indices.slice() : undefined, attractors: it % 25 === 0 ? c.points.slice(0, 450) : undefined });
        if (it === total) {
          const sel = c.info.filter((x) => x.surface === opts.surface);
          let n = 0;
          const idx: number[] = [];
          const contoursOut: ContourInfo[] = sel.map((x) => {
            const pieces = x.pieces.map((p) => {
              const start = n;
              for (let k = 0; k < p.count; k++) idx.push(p.start + k);
              n += p.count;
              return { ...p, start };
            });
            return { ...x, kind: x.id.startsWith('lax') ? 'LAX' : 'SAX', pieces };
          });
          const cp = new Float32Array(idx.length * 3);
          idx.forEach((src, i) => cp.set(c.points.subarray(src * 3, src * 3 + 3), i * 3));
          // Breath-hold alignment: a made-up in-plane shift per contour (SAX in x/y, LAX along z).
          const align = opts.options?.align_slices === true;
          // Close open ends: the fake file's base is open; capping it pulls the mesh back to the data.
          const caps = opts.options?.end_caps === 'auto';
          const groups = contoursOut.map((x, k) => ({
            kind: (x.kind ?? 'SAX') as 'SAX' | 'LAX', label: x.kind === 'LAX' ? x.id : `SAX ${k + 1}`, contour_ids: [x.id],
            shift_mm: (x.kind === 'LAX' ? [0, 0, 0.6 * (k % 2 ? 1 : -1)] : [1.5 * Math.sin(k * 1.7), 1.2 * Math.cos(k * 2.3), 0]) as [number, number, number],
          }));
          if (align) {
            contoursOut.forEach((x, k) => {
              for (const p of x.pieces) for (let i = p.start; i < p.start + p.count; i++) for (let d = 0; d < 3; d++) cp[i * 3 + d] += groups[k].shift_mm[d];
            });
          }
          const pd = new Float32Array(idx.length).map((_, i) => Math.abs(Math.sin(i * 0.37)) * 0.9);
          const vd = new Float32Array(positions.length / 3).map((_, i) => Math.abs(Math.sin(i * 0.05)) * 0.7);
          const stats = { mean: 0.41, median: 0.38, p95: 0.84, max: 0.9, min: 0.0, count: idx.length };
          resolve({
            runId, surface: opts.surface, contours: contoursOut, contourPoints: cp, positions, indices: mesh.indices, pointDistances: pd,
            vertexDistances: vd, perContour: contoursOut.map((x) => ({ id: x.id, kind: x.kind ?? 'SAX', stats })), overall: stats,
            volumeMl: 95.2, areaMm2: 11800, watertight: opts.lids === 'auto', seconds: 1.23, params: opts.params, lids: opts.lids, options: opts.options ?? { smoothing_method: 'laplacian-affine', soften_conflicts: true, align_slices: false, end_caps: 'off', keep_specks: false, apex_floor: true, drop_second_loops: false }, version: 'fake-core',
            pastData: caps ? { base_mm: 1.8, apex_mm: 0.3 } : { base_mm: 12.4, apex_mm: 0.3 },
            end_caps: { mode: caps ? 'auto' : 'off', base: caps, apex: false, points: caps ? 64 : 0 },
            iterations_done: total, converged: false,
            alignment: align ? { rounds: 14, residual_before_mm: 2.41, residual_after_mm: 0.62, groups } : null,
            contour_to_mesh_as_given: align ? { mean: 0.93, median: 0.81, max: 2.6 } : null,
          });
          return;
        }
        it++;
        setTimeout(tick, 12);
      };
      setTimeout(tick, 12);
    });
    return { runId, done, cancel: () => { cancelled = true; } };
  }
  dispose(): void {}
}
