/**
 * Display-only SAX/LAX split of freshly loaded contours (the core classifies them for the run; its
 * kinds replace these once a result arrives). Same rule as the method (Villard et al. 2018, as
 * restated in METHOD.md section 1): least-squares plane normal per contour, the central direction is
 * the normal minimising sum log(180 + angle in degrees) to all others, and contours within 20
 * degrees of it are short-axis. Pure and tested.
 */
import type { ContourInfo } from '../core-client/protocol';

type V3 = [number, number, number];

/** Unit normal of the least-squares plane through the points (smallest covariance eigenvector). */
export function planeNormal(points: ArrayLike<number>, indices: number[]): V3 | null {
  const n = indices.length;
  if (n < 3) return null;
  let mx = 0, my = 0, mz = 0;
  for (const i of indices) { mx += points[i * 3]; my += points[i * 3 + 1]; mz += points[i * 3 + 2]; }
  mx /= n; my /= n; mz /= n;
  const c = [0, 0, 0, 0, 0, 0, 0, 0, 0];
  for (const i of indices) {
    const d = [points[i * 3] - mx, points[i * 3 + 1] - my, points[i * 3 + 2] - mz];
    for (let a = 0; a < 3; a++) for (let b = 0; b < 3; b++) c[a * 3 + b] += d[a] * d[b];
  }
  // The smallest eigenvector of C is the largest of (trace * I - C), found by power iteration.
  const tr = c[0] + c[4] + c[8];
  if (!(tr > 0)) return null;
  const m = c.map((v, k) => (k % 4 === 0 ? tr - v : -v));
  let v: V3 = [0.48, 0.6, 0.64];
  for (let it = 0; it < 200; it++) {
    const w: V3 = [m[0] * v[0] + m[1] * v[1] + m[2] * v[2], m[3] * v[0] + m[4] * v[1] + m[5] * v[2], m[6] * v[0] + m[7] * v[1] + m[8] * v[2]];
    const len = Math.hypot(...w);
    if (!(len > 0)) return null;
    v = [w[0] / len, w[1] / len, w[2] / len];
  }
  return v;
}

/** Acute angle in degrees between two sign-free directions. */
export function axisAngleDeg(a: V3, b: V3): number {
  const d = Math.min(1, Math.abs(a[0] * b[0] + a[1] * b[1] + a[2] * b[2]));
  return (Math.acos(d) * 180) / Math.PI;
}

/** Kinds per contour (the core's when given, else by the rule above). */
export function classifyContours(contours: readonly ContourInfo[], points: ArrayLike<number>): ('SAX' | 'LAX')[] {
  const normals = contours.map((c) => planeNormal(points, c.pieces.flatMap((p) => Array.from({ length: p.count }, (_, k) => p.start + k))));
  const valid = normals.filter((n): n is V3 => n !== null);
  let central: V3 | null = null;
  let best = Infinity;
  for (const nk of valid) {
    const cost = valid.reduce((s, nj) => s + Math.log(180 + axisAngleDeg(nk, nj)), 0);
    if (cost < best) { best = cost; central = nk; }
  }
  return contours.map((c, i) => {
    if (c.kind) return c.kind;
    const n = normals[i];
    if (!n || !central) return 'SAX';
    return axisAngleDeg(n, central) <= 20 ? 'SAX' : 'LAX';
  });
}
