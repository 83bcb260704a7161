/**
 * Contour-to-mesh distances as CSV: the canonical contour CSV (contour,x,y,z,surface) plus kind and
 * distance_mm columns, with `#` comment metadata, so the file can be loaded back into heartmesh.
 */
import type { ContourInfo } from '../../core-client/protocol';
import { csvField } from './csvField';
import { f32 } from './float32';
import { headerLines, type ExportInfo } from './header';

export function writeDistancesCsv(
  contours: readonly ContourInfo[],
  points: Float32Array,
  distances: Float32Array,
  info: ExportInfo,
): string {
  const lines = headerLines(info).map((l) => `# ${l}`);
  lines.push('contour,x,y,z,surface,kind,distance_mm');
  for (const c of contours) {
    for (const piece of c.pieces) {
      for (let k = 0; k < piece.count; k++) {
        const i = piece.start + k;
        lines.push(
          [
            csvField(c.id),
            f32(points[i * 3]),
            f32(points[i * 3 + 1]),
            f32(points[i * 3 + 2]),
            csvField(c.surface ?? ''),
            c.kind ?? '',
            Number.isFinite(distances[i]) ? distances[i].toFixed(4) : '',
          ].join(','),
        );
      }
    }
  }
  lines.push('');
  return lines.join('\n');
}
