// Reading the mesh files the app downloads (OBJ with groups, legacy ASCII VTK) in the browser
// tests that check what a user gets: the wall exports' groups, closedness, volume and cell data.

import assert from 'node:assert/strict';

/** Vertices and faces of an OBJ, with the group each face is in. */
export function parseObj(text) {
  const v = [];
  const faces = [];
  const groups = [];
  let group = null;
  for (const line of text.split('\n')) {
    const p = line.trim().split(/\s+/);
    if (p[0] === 'v') v.push(p.slice(1, 4).map(Number));
    else if (p[0] === 'g') groups.push((group = p[1]));
    else if (p[0] === 'f') faces.push({ ids: p.slice(1, 4).map((x) => Number(x) - 1), group });
  }
  return { v, faces, groups };
}

/** Enclosed volume of a closed outward mesh, ml. */
export function volumeMl(v, faces) {
  let sum = 0;
  for (const { ids: [a, b, c] } of faces) {
    const [p, q, r] = [v[a], v[b], v[c]];
    sum += p[0] * (q[1] * r[2] - q[2] * r[1]) - p[1] * (q[0] * r[2] - q[2] * r[0]) + p[2] * (q[0] * r[1] - q[1] * r[0]);
  }
  return sum / 6000;
}

/** The numbers after `header` (a line starting so) up to the next line starting with a letter. */
export function vtkBlock(lines, header, n) {
  const at = lines.findIndex((l) => l.startsWith(header));
  assert.ok(at >= 0, `${header} missing`);
  const out = [];
  for (let i = at + 1; i < lines.length && out.length < n; i++) {
    if (/^[A-Za-z]/.test(lines[i])) continue; // SCALARS / LOOKUP_TABLE lines
    out.push(...lines[i].trim().split(/\s+/).filter(Boolean).map(Number));
  }
  return out.slice(0, n);
}

/** Edges (vertex pairs) not in exactly two faces. */
export function openEdges(faces) {
  const edges = new Map();
  for (const { ids } of faces) {
    for (let k = 0; k < 3; k++) {
      const [a, b] = [ids[k], ids[(k + 1) % 3]];
      const key = a < b ? `${a},${b}` : `${b},${a}`;
      edges.set(key, (edges.get(key) ?? 0) + 1);
    }
  }
  return { open: [...edges.values()].filter((n) => n !== 2).length, edges: edges.size };
}
