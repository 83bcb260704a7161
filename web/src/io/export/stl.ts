/**
 * Binary STL writer. The 80-byte header holds the app version, units, surface, frame, input name
 * and as many parameters as fit (`stlHeader`)
 * (STL has no other place for metadata); facet normals are computed from the CCW winding.
 */
import { stlHeader, type ExportInfo, type MeshData } from './header';
import { vertexSource } from './vertices';

export function writeStl(mesh: MeshData, info: ExportInfo): ArrayBuffer {
  const triangles = mesh.indices.length / 3;
  const buffer = new ArrayBuffer(84 + 50 * triangles);
  const view = new DataView(buffer);
  const header = stlHeader(info);
  for (let i = 0; i < 80; i++) {
    const c = i < header.length ? header.charCodeAt(i) : 32;
    view.setUint8(i, c < 128 ? c : 63); // ASCII only; '?' for anything else
  }
  view.setUint32(80, triangles, true);
  // Normals from the full-precision vertices when known, computed as the core does (no hypot:
  // the root of the summed squares), so the file is byte for byte the command line's.
  const { values: p } = vertexSource(mesh);
  let o = 84;
  for (let t = 0; t < triangles; t++) {
    const a = mesh.indices[t * 3] * 3;
    const b = mesh.indices[t * 3 + 1] * 3;
    const c = mesh.indices[t * 3 + 2] * 3;
    const ux = p[b] - p[a], uy = p[b + 1] - p[a + 1], uz = p[b + 2] - p[a + 2];
    const vx = p[c] - p[a], vy = p[c + 1] - p[a + 1], vz = p[c + 2] - p[a + 2];
    let nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
    const len = Math.sqrt(nx * nx + ny * ny + nz * nz) || 1;
    nx /= len; ny /= len; nz /= len;
    for (const v of [nx, ny, nz, p[a], p[a + 1], p[a + 2], p[b], p[b + 1], p[b + 2], p[c], p[c + 1], p[c + 2]]) {
      view.setFloat32(o, v, true);
      o += 4;
    }
    view.setUint16(o, 0, true);
    o += 2;
  }
  return buffer;
}
