/**
 * The wall solid laid out for drawing: one vertex per triangle corner (so that a colour can be
 * per triangle, as the regions are), with normals smoothed over each region but not across region
 * borders. The rim where the epicardium meets the flat base ring is a right-angled edge: normals
 * averaged across it would shade both sides as a rounded bevel, hiding where the surfaces end.
 *
 * Pure module: no three.js, no DOM (unit-tested in node).
 */

export interface WallCorners {
  /** xyz per corner (3 corners per triangle, in triangle order), mm. */
  positions: Float32Array;
  /** Unit normal per corner. */
  normals: Float32Array;
}

/**
 * Corners of every triangle of `indices` over `positions`, with each corner's normal the
 * area-weighted mean of the normals of the triangles around its vertex in the same region
 * (`regions`, one per triangle; null: one region).
 */
export function wallCorners(positions: ArrayLike<number>, indices: ArrayLike<number>, regions: ArrayLike<number> | null): WallCorners {
  const triangles = Math.floor(indices.length / 3);
  // Accumulated normal per (vertex, region), found through a key of both.
  const slot = new Map<number, number>();
  const sums: number[] = [];
  const cornerSlot = new Uint32Array(triangles * 3);
  const out = new Float32Array(triangles * 9);
  for (let t = 0; t < triangles; t++) {
    const [a, b, c] = [indices[t * 3], indices[t * 3 + 1], indices[t * 3 + 2]];
    const ux = positions[b * 3] - positions[a * 3];
    const uy = positions[b * 3 + 1] - positions[a * 3 + 1];
    const uz = positions[b * 3 + 2] - positions[a * 3 + 2];
    const vx = positions[c * 3] - positions[a * 3];
    const vy = positions[c * 3 + 1] - positions[a * 3 + 1];
    const vz = positions[c * 3 + 2] - positions[a * 3 + 2];
    // The cross product's length is twice the area: the weight comes with it.
    const n = [uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx];
    const region = regions ? regions[t] : 0;
    [a, b, c].forEach((v, k) => {
      const key = v * 64 + (region & 63);
      let s = slot.get(key);
      if (s === undefined) {
        s = sums.length / 3;
        slot.set(key, s);
        sums.push(0, 0, 0);
      }
      sums[s * 3] += n[0];
      sums[s * 3 + 1] += n[1];
      sums[s * 3 + 2] += n[2];
      cornerSlot[t * 3 + k] = s;
      out[t * 9 + k * 3] = positions[v * 3];
      out[t * 9 + k * 3 + 1] = positions[v * 3 + 1];
      out[t * 9 + k * 3 + 2] = positions[v * 3 + 2];
    });
  }
  const normals = new Float32Array(triangles * 9);
  for (let i = 0; i < cornerSlot.length; i++) {
    const s = cornerSlot[i] * 3;
    const len = Math.hypot(sums[s], sums[s + 1], sums[s + 2]) || 1;
    normals[i * 3] = sums[s] / len;
    normals[i * 3 + 1] = sums[s + 1] / len;
    normals[i * 3 + 2] = sums[s + 2] / len;
  }
  return { positions: out, normals };
}
