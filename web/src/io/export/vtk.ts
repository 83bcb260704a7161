/**
 * Legacy VTK writer (ASCII POLYDATA, readable by ParaView and VTK-based tools); line 2 is the
 * title holding the metadata (max 256 characters by the format), the full parameters follow as
 * FIELD data so nothing is lost. Vertex distances become POINT_DATA scalars.
 *
 * The FIELD block goes right after `DATASET POLYDATA`, where VTK's own writer puts the dataset's
 * field data: after POINT_DATA a FIELD block belongs to the point data, so VTK read each
 * parameter as a one-value point array beside the N-value `distance`.
 */
import { DISTANCE_NAME, headerLines, type ExportInfo, type MeshData } from './header';
import { distanceSource, vertexSource } from './vertices';

export function writeVtk(mesh: MeshData, info: ExportInfo): string {
  const nv = mesh.positions.length / 3;
  const nf = mesh.indices.length / 3;
  const title = headerLines(info).join(' | ').slice(0, 255);
  const lines = ['# vtk DataFile Version 3.0', title, 'ASCII', 'DATASET POLYDATA'];
  // Parameters as field data on the dataset: one single-value array per parameter.
  const names = Object.keys(info.params);
  if (names.length > 0) lines.push(`FIELD heartmesh_params ${names.length}`);
  for (const n of names) lines.push(`${n} 1 1 double`, String(info.params[n]));
  const { values: p, text, double } = vertexSource(mesh);
  lines.push(`POINTS ${nv} ${double ? 'double' : 'float'}`);
  for (let i = 0; i < p.length; i += 3) lines.push(`${text(p[i])} ${text(p[i + 1])} ${text(p[i + 2])}`);
  lines.push(`POLYGONS ${nf} ${nf * 4}`);
  const f = mesh.indices;
  for (let i = 0; i < f.length; i += 3) lines.push(`3 ${f[i]} ${f[i + 1]} ${f[i + 2]}`);
  const d = distanceSource(mesh, nv);
  if (d) {
    lines.push(`POINT_DATA ${nv}`, `SCALARS ${DISTANCE_NAME} ${d.double ? 'double' : 'float'} 1`, 'LOOKUP_TABLE default');
    for (let i = 0; i < nv; i++) lines.push(d.text(d.values[i]));
  }
  lines.push('');
  return lines.join('\n');
}
