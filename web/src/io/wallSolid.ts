/**
 * The myocardium wall as the viewer shows it, read from the PLY the worker writes for the wall
 * export (`Session.myocardium_wall` / `biventricular_wall` with format `ply`): its vertices, its
 * triangles, the wall thickness at every vertex (point data `thickness`, mm) and every triangle's
 * region with the region names the header gives (`comment region K NAME`). Reading the saved
 * file's own bytes keeps what is seen and what is saved one and the same solid.
 */
import { readPly } from './readPly';

export interface WallRegion {
  id: number;
  name: string;
}

export interface WallSolid {
  /** xyz per vertex, mm. */
  positions: Float32Array;
  /** Three vertex indices per triangle, outward. */
  indices: Uint32Array;
  /** Wall thickness per vertex, mm (null: the file has none). */
  thickness: Float32Array | null;
  /** Region id per triangle (null: the file has none). */
  regions: Int32Array | null;
  /** The regions the header names, by id. */
  regionNames: WallRegion[];
}

/** `comment region 2 lv_endocardium` -> {id 2, name lv_endocardium}. */
const REGION_COMMENT = /^region\s+(\d+)\s+(\S+)$/;

/** Reads the wall's PLY bytes; throws an Error naming what is missing. */
export function wallSolidFromPly(bytes: Uint8Array): WallSolid {
  const ply = readPly(bytes);
  const vertex = ply.elements.get('vertex');
  const face = ply.elements.get('face');
  if (!vertex || !face) throw new Error('PLY: the wall has no vertex or no face element');
  const [x, y, z] = ['x', 'y', 'z'].map((k) => vertex.scalars.get(k));
  if (!x || !y || !z) throw new Error('PLY: the wall\'s vertices have no x, y, z');
  const positions = new Float32Array(vertex.count * 3);
  for (let i = 0; i < vertex.count; i++) {
    positions[i * 3] = x[i];
    positions[i * 3 + 1] = y[i];
    positions[i * 3 + 2] = z[i];
  }
  const list = face.lists.get('vertex_indices') ?? face.lists.get('vertex_index');
  if (!list) throw new Error('PLY: the wall\'s faces have no vertex_indices');
  const indices = new Uint32Array(face.count * 3);
  for (let f = 0; f < face.count; f++) {
    const from = list.offsets[f];
    if (list.offsets[f + 1] - from !== 3) throw new Error(`PLY: face ${f} of the wall is no triangle`);
    for (let k = 0; k < 3; k++) {
      const v = list.values[from + k];
      if (!(v >= 0 && v < vertex.count)) throw new Error(`PLY: face ${f} of the wall names vertex ${v} of ${vertex.count}`);
      indices[f * 3 + k] = v;
    }
  }
  const t = vertex.scalars.get('thickness');
  const r = face.scalars.get('region');
  const regionNames: WallRegion[] = [];
  for (const c of ply.comments) {
    const m = REGION_COMMENT.exec(c);
    if (m) regionNames.push({ id: Number(m[1]), name: m[2] });
  }
  return {
    positions,
    indices,
    thickness: t ? Float32Array.from(t) : null,
    regions: r ? Int32Array.from(r) : null,
    regionNames: regionNames.sort((a, b) => a.id - b.id),
  };
}
