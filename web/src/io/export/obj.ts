/** Wavefront OBJ writer (text; `#` comment header; 1-based face indices). */
import { f32 } from './float32';
import { headerLines, type ExportInfo, type MeshData } from './header';

export function writeObj(mesh: MeshData, info: ExportInfo): string {
  const lines = headerLines(info).map((l) => `# ${l}`);
  const p = mesh.positions;
  for (let i = 0; i < p.length; i += 3) lines.push(`v ${f32(p[i])} ${f32(p[i + 1])} ${f32(p[i + 2])}`);
  const f = mesh.indices;
  for (let i = 0; i < f.length; i += 3) lines.push(`f ${f[i] + 1} ${f[i + 1] + 1} ${f[i + 2] + 1}`);
  lines.push('');
  return lines.join('\n');
}
