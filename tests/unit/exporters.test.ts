// Each exporter's output is parsed back by an independent minimal reader and compared with the input.
import { describe, expect, it } from 'vitest';
import { writeStl } from '../../web/src/io/export/stl';
import { writeObj } from '../../web/src/io/export/obj';
import { writePly } from '../../web/src/io/export/ply';
import { writeVtk } from '../../web/src/io/export/vtk';
import { writeDistancesCsv } from '../../web/src/io/export/csv';
import { writeParamsJson } from '../../web/src/io/export/json';
import { exportBaseName, type ExportInfo, type MeshData } from '../../web/src/io/export/header';
import type { ContourInfo } from '../../web/src/core-client/protocol';
import { DEFAULT_END_CAPS } from '../../web/src/core-client/protocol';

// A tetrahedron with CCW-from-outside triangles, edge 10 mm.
const mesh: MeshData = {
  positions: new Float32Array([0, 0, 0, 10, 0, 0, 0, 10, 0, 0, 0, 10]),
  indices: new Uint32Array([0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3]),
  vertexDistances: new Float32Array([0.1, 0.2, 0.3, 0.45]),
};
const info: ExportInfo = {
  appVersion: '0.1.0', coreVersion: '0.1.0-core', fileName: 'patient1-ED.csv', surface: 'LV_ENDO', lids: 'auto',
  params: { iterations: 250, lambda: 100000, beta: 0.1 },
};

function signedVolume(p: ArrayLike<number>, f: ArrayLike<number>): number {
  let v = 0;
  for (let t = 0; t < f.length; t += 3) {
    const a = f[t] * 3, b = f[t + 1] * 3, c = f[t + 2] * 3;
    v += (p[a] * (p[b + 1] * p[c + 2] - p[b + 2] * p[c + 1]) - p[a + 1] * (p[b] * p[c + 2] - p[b + 2] * p[c]) + p[a + 2] * (p[b] * p[c + 1] - p[b + 1] * p[c])) / 6;
  }
  return v;
}

describe('exporters parse back', () => {
  it('the fixture is a positive-volume tetrahedron (1000/6 mm^3)', () => {
    expect(signedVolume(mesh.positions, mesh.indices)).toBeCloseTo(1000 / 6, 6);
  });

  it('STL binary: header, count, outward normals, vertices', () => {
    const buf = writeStl(mesh, info);
    expect(buf.byteLength).toBe(84 + 50 * 4);
    const header = new TextDecoder().decode(new Uint8Array(buf, 0, 80));
    expect(header.startsWith('heartmesh 0.1.0')).toBe(true);
    const dv = new DataView(buf);
    expect(dv.getUint32(80, true)).toBe(4);
    // Triangle 0 = (0,2,1) lies in z=0 and faces -z.
    expect([dv.getFloat32(84, true), dv.getFloat32(88, true), dv.getFloat32(92, true)]).toEqual([0, 0, -1]);
    const positions: number[] = [];
    for (let t = 0; t < 4; t++) for (let k = 0; k < 9; k++) positions.push(dv.getFloat32(84 + t * 50 + 12 + k * 4, true));
    expect(signedVolume(positions, [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11])).toBeCloseTo(1000 / 6, 4);
  });

  it('OBJ: comments record parameters; v/f lines give the same mesh', () => {
    const text = writeObj(mesh, info);
    expect(text).toContain('# lids: auto iterations=250 lambda=100000 beta=0.1');
    const v: number[] = [];
    const f: number[] = [];
    for (const line of text.split('\n')) {
      const parts = line.trim().split(/\s+/);
      if (parts[0] === 'v') v.push(...parts.slice(1).map(Number));
      if (parts[0] === 'f') f.push(...parts.slice(1).map((s) => Number(s) - 1));
    }
    expect(v).toEqual(Array.from(mesh.positions));
    expect(f).toEqual(Array.from(mesh.indices));
  });

  it('PLY binary: header with comments and distance property; body decodes', () => {
    const buf = writePly(mesh, info);
    const bytes = new Uint8Array(buf);
    const text = new TextDecoder().decode(bytes);
    const end = text.indexOf('end_header\n') + 'end_header\n'.length;
    const header = text.slice(0, end);
    expect(header).toContain('format binary_little_endian 1.0');
    expect(header).toContain('comment heartmesh 0.1.0');
    expect(header).toContain('element vertex 4');
    expect(header).toContain('property float distance_mm');
    expect(header).toContain('element face 4');
    const dv = new DataView(buf, end);
    const xyz: number[] = [];
    const d: number[] = [];
    for (let i = 0; i < 4; i++) {
      for (let k = 0; k < 3; k++) xyz.push(dv.getFloat32(i * 16 + k * 4, true));
      d.push(dv.getFloat32(i * 16 + 12, true));
    }
    expect(xyz).toEqual(Array.from(mesh.positions));
    expect(d).toEqual(Array.from(mesh.vertexDistances ?? []));
    const faces: number[] = [];
    for (let t = 0; t < 4; t++) {
      expect(dv.getUint8(64 + t * 13)).toBe(3);
      for (let k = 0; k < 3; k++) faces.push(dv.getUint32(64 + t * 13 + 1 + k * 4, true));
    }
    expect(faces).toEqual(Array.from(mesh.indices));
    expect(end + 64 + 52).toBe(buf.byteLength);
  });

  it('VTK legacy: points, polygons, distance scalars, parameter fields', () => {
    const lines = writeVtk(mesh, info).split('\n');
    expect(lines[0]).toBe('# vtk DataFile Version 3.0');
    expect(lines[1]).toContain('heartmesh 0.1.0');
    expect(lines[1].length).toBeLessThan(256);
    const pi = lines.indexOf('POINTS 4 float');
    const pts = lines.slice(pi + 1, pi + 5).flatMap((l) => l.split(' ').map(Number));
    expect(pts).toEqual(Array.from(mesh.positions));
    const fi = lines.indexOf('POLYGONS 4 16');
    const polys = lines.slice(fi + 1, fi + 5).map((l) => l.split(' ').map(Number));
    expect(polys.every((p) => p[0] === 3)).toBe(true);
    expect(polys.flatMap((p) => p.slice(1))).toEqual(Array.from(mesh.indices));
    const si = lines.indexOf('SCALARS distance_mm float 1');
    expect(lines.slice(si + 2, si + 6).map(Number)).toEqual(Array.from(mesh.vertexDistances ?? []).map((x) => Math.fround(x)).map(Number));
    const field = lines.indexOf('FIELD heartmesh_params 3');
    expect(lines[field + 3]).toBe('lambda 1 1 double');
    expect(Number(lines[field + 4])).toBe(100000);
  });

  it('distance CSV: canonical columns + distance, readable again', () => {
    const contours: ContourInfo[] = [
      { id: 'sax,1', surface: 'LV_ENDO', kind: 'SAX', pieces: [{ closed: true, start: 0, count: 2 }] },
      { id: 'lax', surface: 'LV_ENDO', kind: 'LAX', pieces: [{ closed: false, start: 2, count: 1 }] },
    ];
    const pts = new Float32Array([1, 2, 3, 4, 5, 6, 7, 8, 9]);
    const text = writeDistancesCsv(contours, pts, new Float32Array([0.25, 0.5, 1.125]), info);
    const rows = text.split('\n').filter((l) => l && !l.startsWith('#'));
    expect(rows[0]).toBe('contour,x,y,z,surface,kind,distance_mm');
    expect(rows[1]).toBe('"sax,1",1,2,3,LV_ENDO,SAX,0.2500');
    expect(rows[3]).toBe('lax,7,8,9,LV_ENDO,LAX,1.1250');
    expect(rows.length).toBe(4);
  });

  it('parameters JSON round-trips', () => {
    const doc = JSON.parse(writeParamsJson(info, {
      vertices: 4, triangles: 4, volumeMl: 0.17, areaMm2: 236.6, watertight: true, seconds: 0.8,
      overall: { mean: 0.3, median: 0.25, p95: 0.44, max: 0.45, min: 0.1, count: 4 },
    }));
    expect(doc.params).toEqual(info.params);
    expect(doc.units).toBe('mm');
    expect(doc.result.contourToMeshMm.max).toBe(0.45);
    expect(doc.generator).toBe('heartmesh 0.1.0');
  });

  it('parameters JSON and headers record the smoothing options (defaults when unknown)', () => {
    const taubin: ExportInfo = { ...info, options: { smoothing_method: 'taubin', soften_conflicts: false, align_slices: false, end_caps: DEFAULT_END_CAPS } };
    const doc = JSON.parse(writeParamsJson(taubin, null));
    expect(doc.smoothing_method).toBe('taubin');
    expect(doc.soften_conflicts).toBe(false);
    expect(doc.params).toEqual(info.params);
    const old = JSON.parse(writeParamsJson(info, null));
    expect(old.smoothing_method).toBe('laplacian-affine');
    expect(old.soften_conflicts).toBe(true);
    expect(writeObj(mesh, taubin)).toContain(`# lids: auto iterations=250 lambda=100000 beta=0.1 smoothing_method=taubin soften_conflicts=false align_slices=false end_caps=${DEFAULT_END_CAPS}\n`);
  });

  it('names downloads after the input and surface', () => {
    expect(exportBaseName(info)).toBe('patient1-ED-LV_ENDO');
    expect(exportBaseName({ ...info, fileName: 'my file.csv', surface: null })).toBe('my_file');
  });
});
