// A wall PLY laid out as the core writes one (wasm-core io/ply.rs `write_ply_with`): binary
// little-endian, comments (the region names as `comment region K NAME`), float x y z and an
// optional float point property, faces as `list uchar int vertex_indices` and an optional
// `int region`. For the tests of the reader and of the wall's view.

export interface PlyFixture {
  positions: number[];
  faces: number[][];
  thickness?: number[];
  regions?: number[];
  /** Region names by id from 1 (`comment region 1 NAME`, ...). */
  names?: string[];
  comments?: string[];
}

export function wallPly(f: PlyFixture): Uint8Array {
  const n = f.positions.length / 3;
  const lines = ['ply', 'format binary_little_endian 1.0', ...(f.comments ?? []).map((c) => `comment ${c}`)];
  (f.names ?? []).forEach((name, k) => lines.push(`comment region ${k + 1} ${name}`));
  lines.push(`element vertex ${n}`, 'property float x', 'property float y', 'property float z');
  if (f.thickness) lines.push('property float thickness');
  lines.push(`element face ${f.faces.length}`, 'property list uchar int vertex_indices');
  if (f.regions) lines.push('property int region');
  lines.push('end_header', '');
  const header = new TextEncoder().encode(lines.join('\n'));
  const perVertex = 12 + (f.thickness ? 4 : 0);
  const faceBytes = f.faces.reduce((sum, face) => sum + 1 + 4 * face.length + (f.regions ? 4 : 0), 0);
  const bytes = new Uint8Array(header.length + perVertex * n + faceBytes);
  bytes.set(header, 0);
  const out = new DataView(bytes.buffer);
  let at = header.length;
  for (let i = 0; i < n; i++) {
    for (let k = 0; k < 3; k++, at += 4) out.setFloat32(at, f.positions[i * 3 + k], true);
    if (f.thickness) {
      out.setFloat32(at, f.thickness[i], true);
      at += 4;
    }
  }
  f.faces.forEach((face, t) => {
    out.setUint8(at++, face.length);
    for (const v of face) {
      out.setInt32(at, v, true);
      at += 4;
    }
    if (f.regions) {
      out.setInt32(at, f.regions[t], true);
      at += 4;
    }
  });
  return bytes;
}

/**
 * A closed triangulated box (8 vertices, 12 triangles, outward) of `w` x `w` x `h` mm: region 1
 * on the sides, 2 on the bottom, 3 on the top; thickness = the vertex's z.
 */
export function boxPly(w = 10, h = 4): Uint8Array {
  const positions = [0, 0, 0, w, 0, 0, w, w, 0, 0, w, 0, 0, 0, h, w, 0, h, w, w, h, 0, w, h];
  const faces = [
    [0, 2, 1], [0, 3, 2], // bottom (-z)
    [4, 5, 6], [4, 6, 7], // top (+z)
    [0, 1, 5], [0, 5, 4], // y = 0 (-y)
    [1, 2, 6], [1, 6, 5], // x = w (+x)
    [2, 3, 7], [2, 7, 6], // y = w (+y)
    [3, 0, 4], [3, 4, 7], // x = 0 (-x)
  ];
  const regions = [2, 2, 3, 3, 1, 1, 1, 1, 1, 1, 1, 1];
  const thickness = [0, 0, 0, 0, h, h, h, h];
  return wallPly({ positions, faces, thickness, regions, names: ['epicardium', 'endocardium', 'base'], comments: ['heartmesh 0.1.0', 'input: end_header.csv'] });
}
