// A test input with a speck (session 14: a short-axis ring under a tenth of the ring one slice
// away, not at the apex, which the core leaves out by default): a contour CSV of the bundled
// samples plus a 3-point loop about 2 mm around in a short-axis plane of its own one slice past the
// base, near the basal ring's centre (a stray click past the base). Built in the test from the
// bundled sample, so no fixture is committed. Used by tests/e2e/setaside.test.mjs and
// tests/node/setAside.test.ts.

/** Mean of 3-vectors. */
function mean(points) {
  const s = [0, 0, 0];
  for (const p of points) for (let k = 0; k < 3; k++) s[k] += p[k];
  return s.map((v) => v / points.length);
}

const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const unit = (a) => {
  const n = Math.hypot(...a);
  return a.map((v) => v / n);
};

/** Unit normal of a closed polygon (Newell's method). */
function polygonNormal(points) {
  const n = [0, 0, 0];
  for (let i = 0; i < points.length; i++) {
    const p = points[i];
    const q = points[(i + 1) % points.length];
    n[0] += (p[1] - q[1]) * (p[2] + q[2]);
    n[1] += (p[2] - q[2]) * (p[0] + q[0]);
    n[2] += (p[0] - q[0]) * (p[1] + q[1]);
  }
  return unit(n);
}

function ringLength(points) {
  let s = 0;
  for (let i = 0; i < points.length; i++) s += Math.hypot(...sub(points[(i + 1) % points.length], points[i]));
  return s;
}

/**
 * The short-axis stack of `surface` in `csv` (contours whose id holds `idPart`): the stack's unit
 * normal, its basal ring (centre, length around, height along the normal, id, points), the ring one
 * slice below it, and two unit vectors spanning the slices' plane. Shared by the fixtures built on a
 * bundled sample (this file's speck, secondLoop.mjs).
 */
export function basalStack(csv, surface, idPart) {
  const rings = new Map();
  for (const line of csv.split('\n').slice(1)) {
    const f = line.split(',');
    if (f.length < 5 || f[4].trim() !== surface || !f[0].includes(idPart)) continue;
    if (!rings.has(f[0])) rings.set(f[0], []);
    rings.get(f[0]).push([Number(f[1]), Number(f[2]), Number(f[3])]);
  }
  const list = [...rings.entries()].filter(([, r]) => r.length >= 3);
  if (list.length < 3) throw new Error(`no short-axis stack of ${surface} in the file`);
  const normal = polygonNormal(list[0][1]);
  // Rings along the stack's normal; the base is the end with the longer ring.
  const stack = list
    .map(([id, points]) => ({ id, points, centre: mean(points), length: ringLength(points) }))
    .map((r) => ({ ...r, h: dot(r.centre, normal) }));
  stack.sort((a, b) => a.h - b.h);
  const baseAtTop = stack.at(-1).length > stack[0].length;
  const base = baseAtTop ? stack.at(-1) : stack[0];
  const next = baseAtTop ? stack.at(-2) : stack[1];
  const u = unit(cross(normal, Math.abs(normal[0]) < 0.9 ? [1, 0, 0] : [0, 1, 0]));
  return { normal, base, next, u, w: cross(normal, u) };
}

/** `rows` (CSV lines) appended to `csv`, with the 1-based line of the first one. */
export function appendRows(csv, rows) {
  const body = csv.endsWith('\n') ? csv : `${csv}\n`;
  const line = body.split('\n').length; // the first appended row's 1-based line
  return { csv: `${body}${rows.join('\n')}\n`, line };
}

/**
 * `csv` (a heartmesh contour CSV with `contour,x,y,z,surface` rows) with a speck added to the
 * short-axis stack of `surface` (contours whose id holds `idPart`): returns the new text, the
 * speck's id, its file line (1-based, of its first point) and its length around (mm).
 */
export function withSpeck(csv, { surface = 'LV_ENDO', idPart = 'SAX_LV_ENDOCARDIAL', id = 'speck_past_base', aroundMm = 2 } = {}) {
  const { normal, base, next, u, w } = basalStack(csv, surface, idPart);
  const step = base.h - next.h; // one slice spacing, signed away from the apex
  const centre = base.centre.map((v, k) => v + normal[k] * step);
  // An equilateral triangle `aroundMm` around, in the slice's plane.
  const r = aroundMm / (3 * Math.sqrt(3));
  const rows = [0, 1, 2].map((i) => {
    const t = (2 * Math.PI * i) / 3;
    const p = centre.map((c, k) => c + r * (Math.cos(t) * u[k] + Math.sin(t) * w[k]));
    return `${id},${p.map((v) => v.toFixed(4)).join(',')},${surface}`;
  });
  return { ...appendRows(csv, rows), id, aroundMm };
}
