// A test input with a second closed loop in a short-axis slice (session 13's held-out family
// `second-loop-base`: an outflow tract or another structure drawn under the same label beside the
// basal ring): a contour CSV of a bundled sample plus a circle in the plane of the basal ring of
// one surface, clear of that ring. Built in the test from the sample, so no fixture is committed.
// Used by tests/e2e/secondloop.test.mjs.
import { appendRows, basalStack } from './speck.mjs';

/**
 * `csv` with a closed circular loop `radiusMm` in radius added, as contour `id`, to the basal
 * short-axis slice of `surface` (contours whose id holds `idPart`), its nearest point `gapMm`
 * beyond the farthest point of the basal ring from that ring's centre. Returns the new text, the
 * loop's id, its file line, its centre (mm) and the basal ring's id.
 */
export function withSecondLoop(
  csv,
  { surface = 'LV_ENDO', idPart = 'SAX_LV_ENDOCARDIAL', id = 'second_loop', radiusMm = 5, gapMm = 8, points = 24 } = {},
) {
  const { base, u, w } = basalStack(csv, surface, idPart);
  const reach = Math.max(...base.points.map((p) => Math.hypot(p[0] - base.centre[0], p[1] - base.centre[1], p[2] - base.centre[2])));
  const centre = base.centre.map((c, k) => c + (reach + gapMm + radiusMm) * u[k]);
  const rows = Array.from({ length: points }, (_, i) => {
    const t = (2 * Math.PI * i) / points;
    const p = centre.map((c, k) => c + radiusMm * (Math.cos(t) * u[k] + Math.sin(t) * w[k]));
    return `${id},${p.map((v) => v.toFixed(4)).join(',')},${surface}`;
  });
  return { ...appendRows(csv, rows), id, centre, mainId: base.id };
}
