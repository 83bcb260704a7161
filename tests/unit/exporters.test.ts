// Each exporter's output is parsed back by an independent minimal reader and compared with the input.
import { describe, expect, it } from 'vitest';
import { writeStl } from '../../web/src/io/export/stl';
import { writeObj, writeObjSurfaces } from '../../web/src/io/export/obj';
import { writePly } from '../../web/src/io/export/ply';
import { writeVtk } from '../../web/src/io/export/vtk';
import { writeDistancesCsv } from '../../web/src/io/export/csv';
import { writeParamsJson } from '../../web/src/io/export/json';
import { f32 } from '../../web/src/io/export/float32';
import { f64 } from '../../web/src/io/export/float64';
import { exportBaseName, stlHeader, type ExportInfo, type MeshData } from '../../web/src/io/export/header';
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
    // The surface whole (it was cut to "LV_END"), the units, then whole parameters only.
    expect(header.trimEnd()).toBe('heartmesh 0.1.0 mm LV_ENDO patient1-ED.csv lids=auto iterations=250');
    const dv = new DataView(buf);
    expect(dv.getUint32(80, true)).toBe(4);
    // Triangle 0 = (0,2,1) lies in z=0 and faces -z.
    expect([dv.getFloat32(84, true), dv.getFloat32(88, true), dv.getFloat32(92, true)]).toEqual([0, 0, -1]);
    const positions: number[] = [];
    for (let t = 0; t < 4; t++) for (let k = 0; k < 9; k++) positions.push(dv.getFloat32(84 + t * 50 + 12 + k * 4, true));
    expect(signedVolume(positions, [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11])).toBeCloseTo(1000 / 6, 4);
  });

  it('STL header: 80 ASCII bytes with the surface and frame whole, a long name shortened, no parameter cut', () => {
    const long = stlHeader({ ...info, fileName: 'a-very-long-export-name-from-the-scanner-workstation-2024-05-01.csv', frame: 'ES' });
    expect(long.length).toBeLessThanOrEqual(80);
    expect(long.startsWith('heartmesh 0.1.0 mm LV_ENDO frame ES a-very-long')).toBe(true);
    expect(long.endsWith('~')).toBe(true);
    const full = stlHeader({ ...info, params: { iterations: 250, lambda: 100000, beta: 0.1, attractors: 0, smoothing_iterations: 200 } });
    expect(full.length).toBeLessThanOrEqual(80);
    for (const item of full.split(' ').slice(5)) expect(item).toMatch(/^[a-z_]+=[\w.-]+$/);
    expect(stlHeader({ ...info, fileName: 'é.csv' })).toMatch(/^[\x20-\x7e]+$/);
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

  it('OBJ of several surfaces: one named object each, face indices counting on across objects', () => {
    const shifted = { positions: mesh.positions.map((x, i) => (i % 3 === 0 ? x + 100 : x)), indices: mesh.indices };
    const text = writeObjSurfaces([{ name: 'LV_EPI', mesh }, { name: 'RV ENDO', mesh: shifted }], info, ['objects: LV_EPI (this run), RV ENDO (its last run)']);
    expect(text).toContain('# objects: LV_EPI (this run), RV ENDO (its last run)\n');
    expect(text).toContain('# lids: auto iterations=250');
    const objects: { name: string; v: number[]; f: number[] }[] = [];
    const all: number[] = [];
    for (const line of text.split('\n')) {
      const parts = line.trim().split(/\s+/);
      if (parts[0] === 'o') objects.push({ name: parts[1], v: [], f: [] });
      if (parts[0] === 'v') { objects.at(-1)!.v.push(...parts.slice(1).map(Number)); all.push(...parts.slice(1).map(Number)); }
      if (parts[0] === 'f') objects.at(-1)!.f.push(...parts.slice(1).map((x) => Number(x) - 1));
    }
    expect(objects.map((o) => o.name)).toEqual(['LV_EPI', 'RV_ENDO']);
    // The same names as groups, right after each object line (VTK's reader splits by group).
    expect(text.match(/^g .*$/gm)).toEqual(['g LV_EPI', 'g RV_ENDO']);
    expect(text).toContain('o LV_EPI\ng LV_EPI\nv ');
    const n = mesh.positions.length / 3;
    expect(objects[0].f).toEqual(Array.from(mesh.indices));
    expect(objects[1].f).toEqual(Array.from(mesh.indices, (i) => i + n));
    // Each object's faces index its own vertices: the second is the first moved 100 mm in x.
    for (const i of objects[1].f) expect(all[3 * i]).toBeCloseTo(mesh.positions[3 * (i - n)] + 100, 4);
    expect(signedVolume(all.slice(3 * n), Array.from(mesh.indices))).toBeCloseTo(1000 / 6, 3);
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
    expect(header).toContain('property float distance'); // the command line's name
    expect(header).not.toContain('distance_mm');
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
    const si = lines.indexOf('SCALARS distance float 1');
    // Written as the shortest decimal of each float32: it reads back as the same float32.
    expect(lines.slice(si + 2, si + 6).map((l) => Math.fround(Number(l)))).toEqual(Array.from(mesh.vertexDistances ?? []));
    const field = lines.indexOf('FIELD heartmesh_params 3');
    expect(lines[field + 3]).toBe('lambda 1 1 double');
    expect(Number(lines[field + 4])).toBe(100000);
  });

  it('VTK legacy: the parameters are the dataset\'s field data (before POINTS), not point arrays', () => {
    // In a legacy file a FIELD block after POINT_DATA belongs to the point data: VTK 9.7 read the
    // parameters there as 1-value point arrays beside the 4-value distance (a broken dataset).
    const lines = writeVtk(mesh, info).split('\n');
    const dataset = lines.indexOf('DATASET POLYDATA');
    const field = lines.indexOf('FIELD heartmesh_params 3');
    const points = lines.indexOf('POINTS 4 float');
    const pointData = lines.indexOf('POINT_DATA 4');
    expect([field, points]).toEqual([dataset + 1, dataset + 8]);
    expect(lines.slice(field + 1, points)).toEqual(['iterations 1 1 double', '250', 'lambda 1 1 double', '100000', 'beta 1 1 double', '0.1']);
    // After POINT_DATA: one scalar array of 4 values, then the end of the file.
    expect(lines.slice(pointData + 1)).toEqual(['SCALARS distance float 1', 'LOOKUP_TABLE default', '0.1', '0.2', '0.3', '0.45', '']);
    expect(lines.filter((l) => l.startsWith('FIELD'))).toHaveLength(1);
  });

  it('text exports write float32 coordinates as the shortest decimal that reads back the same', () => {
    // The file's -32.83557, as the worker hands it over (a Float32Array), is -32.8355712890625 as a double.
    const x = new Float32Array([-32.83557, 35, 0.1, -1e-7, 123456.789, 3.4e38]);
    expect(Array.from(x, f32)).toEqual(['-32.83557', '35', '0.1', '-1e-7', '123456.79', '3.4e+38']);
    let seed = 7;
    for (let i = 0; i < 2000; i++) {
      seed = (seed * 1103515245 + 12345) % 2147483648;
      const v = Math.fround(((seed / 2147483648) - 0.5) * 10 ** ((i % 12) - 4));
      expect(Math.fround(Number(f32(v)))).toBe(v); // lossless
      expect(f32(v).replace(/^-|\.|e.*$/g, '').replace(/^0+/, '').length).toBeLessThanOrEqual(9);
    }
    const obj = writeObj({ ...mesh, positions: new Float32Array([-32.83557, -27.42256, 35, 1, 2, 3, 4, 5, 6, 7, 8, 9]) }, info);
    expect(obj).toContain('\nv -32.83557 -27.42256 35\n');
    const csv = writeDistancesCsv([{ id: 'c1', surface: null, kind: 'SAX', pieces: [{ closed: true, start: 0, count: 1 }] }], new Float32Array([-32.83557, -27.42256, 35]), new Float32Array([0.0024]), info);
    expect(csv).toContain('\nc1,-32.83557,-27.42256,35,,SAX,0.0024\n');
    expect(writeVtk(mesh, info).split('\n')).toContain('0.45'); // a distance scalar, not 0.44999998807907104
  });

  it('full-precision coordinates are spelled as the command line spells them (Rust\'s shortest, its exponent range and ties)', () => {
    // Expected texts printed by the core's fmt_num (Rust `{}` between 1e-5 and 1e15, `{:e}` outside).
    const cases: [number, string][] = [
      [0, '0'], [-0, '-0'], [35, '35'], [-32.8355712890625, '-32.8355712890625'], [0.1 + 0.2, '0.30000000000000004'],
      [1e-5, '0.00001'], [9.99e-6, '9.99e-6'], [-1.5e-7, '-1.5e-7'], [5e-324, '5e-324'], [123456.789, '123456.789'],
      [9.999999999999999e14, '999999999999999.9'], [1e15, '1e15'], [2.5e20, '2.5e20'], [1.7976931348623157e308, '1.7976931348623157e308'],
      // Exactly halfway between two shortest spellings: Rust rounds away from zero, JavaScript to even.
      [-693287890264804.25, '-693287890264804.3'], [145813204409221.625, '145813204409221.63'], [1878070117635333.25, '1.8780701176353333e15'],
    ];
    for (const [v, text] of cases) expect(f64(v)).toBe(text);
    let seed = 11;
    for (let i = 0; i < 5000; i++) {
      seed = (seed * 1103515245 + 12345) % 2147483648;
      const v = ((seed / 2147483648) - 0.5) * 10 ** ((i % 40) - 20);
      expect(Number(f64(v))).toBe(v); // lossless
      expect(f64(v)).not.toMatch(/e\+|^-?0\d/);
    }
  });

  it('with the full-precision vertices, OBJ and VTK write doubles and STL takes its normals from them', () => {
    const exact = new Float64Array([0.1 + 0.2, 0, 0, 10.000000000000002, 0, 0, 0, 10, 0, 0, 0, 10]);
    const full: MeshData = { ...mesh, positions: Float32Array.from(exact), positions64: exact };
    const obj = writeObj(full, info).split('\n');
    expect(obj.filter((l) => l.startsWith('v '))).toEqual(['v 0.30000000000000004 0 0', 'v 10.000000000000002 0 0', 'v 0 10 0', 'v 0 0 10']);
    const vtk = writeVtk(full, info).split('\n');
    const pi = vtk.indexOf('POINTS 4 double');
    expect(vtk.slice(pi + 1, pi + 3)).toEqual(['0.30000000000000004 0 0', '10.000000000000002 0 0']);
    // Without them (or with a stale array of another length): float32, as before.
    expect(writeVtk({ ...full, positions64: new Float64Array(3) }, info).split('\n')).toContain('POINTS 4 float');
    // The distances likewise: doubles as the command line writes them, float32 without them.
    const d64 = new Float64Array([0.1 + 0.2, 1e-7, 2.5, 1 / 3]);
    const withD = writeVtk({ ...full, vertexDistances: Float32Array.from(d64), vertexDistances64: d64 }, info).split('\n');
    expect(withD.slice(withD.indexOf('POINT_DATA 4'))).toEqual([
      'POINT_DATA 4', 'SCALARS distance double 1', 'LOOKUP_TABLE default', '0.30000000000000004', '1e-7', '2.5', '0.3333333333333333', '',
    ]);
    const staleD = writeVtk({ ...full, vertexDistances: Float32Array.from(d64), vertexDistances64: new Float64Array(2) }, info).split('\n');
    expect(staleD.slice(staleD.indexOf('POINT_DATA 4'), -1)).toEqual(['POINT_DATA 4', 'SCALARS distance float 1', 'LOOKUP_TABLE default', '0.3', '1e-7', '2.5', '0.33333334']);
    expect(writeObj({ ...mesh }, info)).toContain('\nv 10 0 0\n');
    // Triangle 3 = (1,2,3): its normal from the doubles, rounded once to float32.
    const dv = new DataView(writeStl(full, info));
    const [ax, bx, cy, dz] = [exact[3], 0, 10, 10];
    const u = [bx - ax, cy, 0];
    const w = [bx - ax, 0, dz];
    const n = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]];
    const len = Math.sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    const o = 84 + 3 * 50;
    expect([dv.getFloat32(o, true), dv.getFloat32(o + 4, true), dv.getFloat32(o + 8, true)]).toEqual(n.map((x) => Math.fround(x / len)));
    // The coordinates stay float32 (STL has no other), the same as from the float32 vertices.
    expect(dv.getFloat32(o + 12, true)).toBe(Math.fround(exact[3]));
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
    const taubin: ExportInfo = { ...info, options: { smoothing_method: 'taubin', soften_conflicts: false, align_slices: false, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true, drop_second_loops: false } };
    const doc = JSON.parse(writeParamsJson(taubin, null));
    expect(doc.smoothing_method).toBe('taubin');
    expect(doc.soften_conflicts).toBe(false);
    expect(doc.params).toEqual(info.params);
    const old = JSON.parse(writeParamsJson(info, null));
    expect(old.smoothing_method).toBe('laplacian-affine');
    expect(old.soften_conflicts).toBe(true);
    expect(writeObj(mesh, taubin)).toContain(`# lids: auto iterations=250 lambda=100000 beta=0.1 smoothing_method=taubin soften_conflicts=false align_slices=false end_caps=${DEFAULT_END_CAPS} keep_specks=false apex_floor=true\n`);
  });

  it('names downloads after the input and surface', () => {
    expect(exportBaseName(info)).toBe('patient1-ED-LV_ENDO');
    expect(exportBaseName({ ...info, fileName: 'my file.csv', surface: null })).toBe('my_file');
    // A compressed label map's name loses its whole extension, not only the .gz.
    expect(exportBaseName({ ...info, fileName: 'cardiomesh-spasm-seg.nii.gz', surface: 'LV_EPI' })).toBe('cardiomesh-spasm-seg-LV_EPI');
    expect(exportBaseName({ ...info, fileName: 'seg (2).nii.gz', surface: null })).toBe('seg_2_');
    expect(exportBaseName({ ...info, fileName: 'sub-01_seg.nii', surface: 'RV_ENDO', frame: '12' })).toBe('sub-01_seg-RV_ENDO-frame12');
  });

  it('says the patient frame where 3D Slicer reads it, when the input fixes it, and only then', () => {
    const ras = { ...info, fileName: 'seg.nii.gz', coordinateSystem: 'RAS' as const };
    // STL: within the 80 bytes, right after the version; OBJ and PLY: a comment line of its own.
    expect(stlHeader(ras)).toMatch(/^heartmesh 0\.1\.0 mm SPACE=RAS LV_ENDO seg\.nii\.gz /);
    expect(writeObj(mesh, ras).split('\n').slice(0, 3)).toEqual(['# heartmesh 0.1.0 (core 0.1.0-core), units: mm', '# SPACE=RAS', '# input: seg.nii.gz surface: LV_ENDO']);
    expect(new TextDecoder().decode(writePly(mesh, { ...ras, coordinateSystem: 'LPS' }))).toContain('\ncomment SPACE=LPS\n');
    // VTK: in the title line (the header Slicer reads), early enough to survive its cut.
    expect(writeVtk(mesh, ras).split('\n')[1]).toMatch(/^heartmesh 0\.1\.0 \(core 0\.1\.0-core\), units: mm \| SPACE=RAS \| input: seg\.nii\.gz/);
    expect(JSON.parse(writeParamsJson(ras, null))).toMatchObject({ coordinate_system: 'RAS' });
    // Unknown (a CSV): nothing said, as before.
    for (const unknown of [info, { ...info, coordinateSystem: null }]) {
      expect(stlHeader(unknown)).not.toContain('SPACE');
      expect(writeObj(mesh, unknown)).not.toContain('SPACE');
      expect(JSON.parse(writeParamsJson(unknown, null))).not.toHaveProperty('coordinate_system');
    }
  });

  it('records the time frame of a file that holds several beside the file and surface, and only then', () => {
    const nine = { ...info, fileName: 'cine.txt', frame: '9' };
    expect(exportBaseName(nine)).toBe('cine-LV_ENDO-frame9');
    expect(writeObj(mesh, nine)).toContain('# input: cine.txt surface: LV_ENDO frame: 9\n');
    expect(new TextDecoder().decode(writePly(mesh, nine))).toContain('comment input: cine.txt surface: LV_ENDO frame: 9\n');
    expect(JSON.parse(writeParamsJson(nine, null))).toMatchObject({ input: 'cine.txt', surface: 'LV_ENDO', frame: '9' });
    // A frame written as text, as the file writes it (a file name keeps only safe characters).
    const es = { ...info, fileName: 'phases.csv', frame: 'ES' };
    expect(exportBaseName(es)).toBe('phases-LV_ENDO-frameES');
    expect(writeObj(mesh, es)).toContain('# input: phases.csv surface: LV_ENDO frame: ES\n');
    expect(JSON.parse(writeParamsJson(es, null))).toMatchObject({ frame: 'ES' });
    expect(exportBaseName({ ...es, frame: 'end systole/2' })).toBe('phases-LV_ENDO-frameend_systole_2');
    // One frame: no frame anywhere (as before frames were recorded).
    for (const one of [info, { ...info, frame: null }]) {
      expect(JSON.parse(writeParamsJson(one, null))).not.toHaveProperty('frame');
      expect(writeObj(mesh, one)).not.toContain('frame');
      expect(exportBaseName(one)).toBe('patient1-ED-LV_ENDO');
    }
  });
});
