/** Wavefront OBJ writer (text; `#` comment header; 1-based face indices). */
import { headerLines, type ExportInfo, type MeshData } from './header';
import { vertexSource } from './vertices';

/**
 * Several surfaces in one OBJ, each its own object (`o LV_ENDO`) with its vertices and faces (face
 * indices count on across objects, as OBJ's are file-wide): what modelling tools import as one
 * heart with named parts. Each is also a group of the same name (`g LV_ENDO`): Blender and
 * three.js split by object, VTK's reader only by group (its `GroupIds`). `notes` go in the header
 * (which run each surface comes from).
 */
export function writeObjSurfaces(parts: readonly { name: string; mesh: MeshData }[], info: ExportInfo, notes: readonly string[] = []): string {
  const lines = [...headerLines(info), ...notes].map((l) => `# ${l}`);
  let base = 1;
  for (const { name, mesh } of parts) {
    const label = name.replace(/\s+/g, '_');
    lines.push(`o ${label}`, `g ${label}`);
    base = pushMesh(lines, mesh, base);
  }
  lines.push('');
  return lines.join('\n');
}

export function writeObj(mesh: MeshData, info: ExportInfo): string {
  const lines = headerLines(info).map((l) => `# ${l}`);
  pushMesh(lines, mesh, 1);
  lines.push('');
  return lines.join('\n');
}

/** Appends `v` and `f` lines, faces numbered from `base` (1-based); returns the next base. */
function pushMesh(lines: string[], mesh: MeshData, base: number): number {
  const { values: p, text } = vertexSource(mesh);
  for (let i = 0; i < p.length; i += 3) lines.push(`v ${text(p[i])} ${text(p[i + 1])} ${text(p[i + 2])}`);
  const f = mesh.indices;
  for (let i = 0; i < f.length; i += 3) lines.push(`f ${f[i] + base} ${f[i + 1] + base} ${f[i + 2] + base}`);
  return base + p.length / 3;
}
