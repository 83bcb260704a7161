/**
 * Where to put the camera for a set of points: their centre, bounding radius and principal axis
 * (largest eigenvector of the covariance, found by power iteration). For a heart the principal axis
 * of the contour points is close to the long axis, so the default view looks at the ventricle from
 * the side with the long axis pointing up, whatever the scanner coordinates are. Pure and tested.
 */

export interface ViewFit {
  /** Centre of the bounding box (the centroid would lean towards densely sampled curves). */
  center: [number, number, number];
  radius: number;
  /** Unit vector along the largest spread. */
  axis: [number, number, number];
  /** Unit vector along the second largest spread (perpendicular to axis). */
  side: [number, number, number];
}

type V3 = [number, number, number];

/** The view of an empty scene (and of points that cannot be framed). */
function defaultFit(): ViewFit {
  return { center: [0, 0, 0], radius: 50, axis: [0, 0, 1], side: [1, 0, 0] };
}

function normalize(v: V3): V3 {
  const n = Math.hypot(v[0], v[1], v[2]);
  return n > 0 ? [v[0] / n, v[1] / n, v[2] / n] : [0, 0, 1];
}

function mul(c: number[], v: V3): V3 {
  return [c[0] * v[0] + c[1] * v[1] + c[2] * v[2], c[3] * v[0] + c[4] * v[1] + c[5] * v[2], c[6] * v[0] + c[7] * v[1] + c[8] * v[2]];
}

function powerIteration(c: number[], start: V3): V3 {
  let v = normalize(start);
  for (let i = 0; i < 100; i++) v = normalize(mul(c, v));
  return v;
}

/** Fits a view to xyz triples (NaN/inf skipped). */
export function fitView(points: ArrayLike<number>): ViewFit {
  let n = 0;
  const m: V3 = [0, 0, 0];
  const lo: V3 = [Infinity, Infinity, Infinity];
  const hi: V3 = [-Infinity, -Infinity, -Infinity];
  for (let i = 0; i + 2 < points.length; i += 3) {
    const p = [points[i], points[i + 1], points[i + 2]];
    if (!p.every(Number.isFinite)) continue;
    for (let k = 0; k < 3; k++) {
      m[k] += p[k];
      lo[k] = Math.min(lo[k], p[k]);
      hi[k] = Math.max(hi[k], p[k]);
    }
    n++;
  }
  if (n === 0) return defaultFit();
  const mean: V3 = [m[0] / n, m[1] / n, m[2] / n];
  const center: V3 = [(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2];
  const c = [0, 0, 0, 0, 0, 0, 0, 0, 0];
  let r2 = 0;
  for (let i = 0; i + 2 < points.length; i += 3) {
    const d = [points[i] - mean[0], points[i + 1] - mean[1], points[i + 2] - mean[2]];
    if (!d.every(Number.isFinite)) continue;
    for (let a = 0; a < 3; a++) for (let b = 0; b < 3; b++) c[a * 3 + b] += d[a] * d[b];
    const e = [points[i] - center[0], points[i + 1] - center[1], points[i + 2] - center[2]];
    r2 = Math.max(r2, e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
  }
  const radius = viewRadius(Math.sqrt(r2));
  if (!Number.isFinite(radius) || !center.every(Number.isFinite)) return defaultFit();
  // Start away from any exact eigenvector of axis-aligned data.
  const axis = powerIteration(c, [0.577, 0.577, 0.578]);
  // Deflate to get the second direction.
  const lambda1 = mul(c, axis).reduce((s, v, i) => s + v * axis[i], 0);
  const c2 = c.map((v, k) => v - lambda1 * axis[Math.floor(k / 3)] * axis[k % 3]);
  let side = powerIteration(c2, [0.6, -0.3, 0.74]);
  // Make side exactly perpendicular to axis.
  const dot = side[0] * axis[0] + side[1] * axis[1] + side[2] * axis[2];
  side = normalize([side[0] - dot * axis[0], side[1] - dot * axis[1], side[2] - dot * axis[2]]);
  return { center, radius, axis, side };
}

/**
 * The framing radius for points whose bounding sphere has radius `r` (mm). The points' own size,
 * however small or large: a file in metres (a heart spans about 0.1) is refused by the core, but its
 * contours stay on screen and must fill the view like any other, so the user sees what was refused.
 * Only a single point (r = 0) gets 1 mm; a non-finite span (coordinates near 1e308) cannot be
 * framed and gets the default view.
 */
export function viewRadius(r: number): number {
  if (!Number.isFinite(r)) return NaN;
  return r > 0 ? Math.max(r, 1e-6) : 1;
}

/**
 * Scale of dash lengths (drawn in mm) for a scene of this framing radius: 1 for hearts in mm (radius
 * 25-200 mm, the drawing is unchanged there), proportional outside, so dashed curves of a file in
 * metres or micrometres do not turn solid or dissolve.
 */
export function dashScale(radius: number): number {
  if (!(radius > 0) || !Number.isFinite(radius)) return 1;
  if (radius < 25) return radius / 25;
  if (radius > 200) return radius / 200;
  return 1;
}

/**
 * Camera distance and clipping planes that show a bounding sphere of `radius` whole in the
 * narrower field of view (the mesh may reach a little past the contours at the lids). Near and far
 * scale with the distance, so a tiny or huge scene is neither clipped nor lost in depth precision.
 */
export function cameraPlacement(radius: number, fovDeg: number, aspect: number): { distance: number; near: number; far: number } {
  const halfFov = (fovDeg * Math.PI) / 360;
  const fovFit = Math.min(halfFov, Math.atan(Math.tan(halfFov) * aspect));
  const distance = (radius / Math.sin(fovFit)) * 1.05;
  return { distance, near: distance / 100, far: distance * 10 };
}
