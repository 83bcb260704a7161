/**
 * PLY writer (binary little endian, the common choice of mesh tools); the header carries the
 * metadata as `comment` lines and, when known, a per-vertex `distance` property (mm), named as the
 * command line names it.
 */
import { DISTANCE_NAME, headerLines, type ExportInfo, type MeshData } from './header';

export function writePly(mesh: MeshData, info: ExportInfo): ArrayBuffer {
  const nv = mesh.positions.length / 3;
  const nf = mesh.indices.length / 3;
  const withDistance = !!mesh.vertexDistances && mesh.vertexDistances.length === nv;
  const head = [
    'ply',
    'format binary_little_endian 1.0',
    ...headerLines(info).map((l) => `comment ${l}`),
    `element vertex ${nv}`,
    'property float x',
    'property float y',
    'property float z',
    ...(withDistance ? [`property float ${DISTANCE_NAME}`] : []),
    `element face ${nf}`,
    // `int` as the command line (and VTK's PLY writer) declares it: one header for both files.
    'property list uchar int vertex_indices',
    'end_header',
    '',
  ].join('\n');
  const headBytes = new TextEncoder().encode(head);
  const vertexSize = withDistance ? 16 : 12;
  const buffer = new ArrayBuffer(headBytes.length + nv * vertexSize + nf * 13);
  new Uint8Array(buffer).set(headBytes, 0);
  const view = new DataView(buffer);
  let o = headBytes.length;
  for (let v = 0; v < nv; v++) {
    view.setFloat32(o, mesh.positions[v * 3], true);
    view.setFloat32(o + 4, mesh.positions[v * 3 + 1], true);
    view.setFloat32(o + 8, mesh.positions[v * 3 + 2], true);
    if (withDistance && mesh.vertexDistances) view.setFloat32(o + 12, mesh.vertexDistances[v], true);
    o += vertexSize;
  }
  for (let t = 0; t < nf; t++) {
    view.setUint8(o, 3);
    view.setInt32(o + 1, mesh.indices[t * 3], true);
    view.setInt32(o + 5, mesh.indices[t * 3 + 1], true);
    view.setInt32(o + 9, mesh.indices[t * 3 + 2], true);
    o += 13;
  }
  return buffer;
}
