// Enclosed area of a loaded file's curves, for tests that compare frames of a cine: Newell's
// vector area of each closed piece, summed.
import type { LoadedFile } from '../../web/src/core-client/protocol';

/** Enclosed area (mm2) of the curves of `file` that `pick` keeps, summed over their pieces. */
export function curveArea(file: LoadedFile, pick: (c: LoadedFile['contours'][number]) => boolean): number {
  let total = 0;
  for (const c of file.contours.filter(pick)) {
    for (const piece of c.pieces) {
      const n = [0, 0, 0];
      for (let a = 0; a < piece.count; a++) {
        const p = 3 * (piece.start + a);
        const q = 3 * (piece.start + ((a + 1) % piece.count));
        const [x1, y1, z1, x2, y2, z2] = [file.points[p], file.points[p + 1], file.points[p + 2], file.points[q], file.points[q + 1], file.points[q + 2]];
        n[0] += y1 * z2 - z1 * y2;
        n[1] += z1 * x2 - x1 * z2;
        n[2] += x1 * y2 - y1 * x2;
      }
      total += Math.hypot(n[0], n[1], n[2]) / 2;
    }
  }
  return total;
}
