/**
 * How the myocardium wall is coloured in the 3D view: by wall thickness (mm, the app's viridis
 * map, 0 to a scale top that ignores the few thickest vertices) or by region (one flat tint per
 * labelled region, the tints of the other-surfaces key where a region is one of those surfaces,
 * so the LV endocardium is the same pink in both). The solid is drawn one triangle corner per
 * vertex (a region is a property of the triangle: a rim vertex is epicardium on one side and base
 * on the other), so every colour array here has 3 bytes per corner, 9 per triangle.
 *
 * Pure module: no three.js, no DOM (unit-tested in node).
 */
import { colorizeU8, percentile98 } from './colormap';
import type { WallRegion } from '../io/wallSolid';

export type WallColouring = 'thickness' | 'region';

/** Region tints by the core's region names (`mesh::wall` REGION_NAMES, BIV_REGION_NAMES). */
export const REGION_TINTS: Readonly<Record<string, string>> = {
  epicardium: '#ffb74d',
  endocardium: '#ef9a9a',
  lv_endocardium: '#ef9a9a',
  rv_endocardium: '#90caf9',
  base: '#78909c',
};
/** Tints of regions of other names, in turn. */
const SPARE = ['#ce93d8', '#a5d6a7', '#e6ee9c', '#80deea'];

/**
 * The flat colour of the cut faces: inside the solid, where the clipping plane opens it, the far
 * side of the wall is seen from within and drawn unlit in this colour, so a section reads as a
 * solid band between the surfaces. Apart from every tint above and from viridis.
 */
export const SECTION_TINT = '#a1887f';

/** A region's tint: its name's, else the `index`th spare one. */
export function regionTint(name: string, index: number): string {
  return REGION_TINTS[name.toLowerCase()] ?? SPARE[index % SPARE.length];
}

/** Each region's tint by id, the spares handed out in id order to the names not known. */
export function regionPalette(regions: readonly WallRegion[]): Map<number, string> {
  const palette = new Map<number, string>();
  let spare = 0;
  for (const r of [...regions].sort((a, b) => a.id - b.id)) {
    const known = REGION_TINTS[r.name.toLowerCase()];
    palette.set(r.id, known ?? SPARE[spare++ % SPARE.length]);
  }
  return palette;
}

/** `#rrggbb` as three bytes. */
export function hexBytes(hex: string): [number, number, number] {
  const v = parseInt(hex.slice(1), 16);
  return [(v >> 16) & 255, (v >> 8) & 255, v & 255];
}

/**
 * Colours by region: every corner of triangle `t` in its region's tint (`palette`; a region
 * missing from it, e.g. none named in the file, takes a spare tint of its own).
 */
export function regionCornerColours(regions: ArrayLike<number>, palette: ReadonlyMap<number, string>): Uint8Array {
  const out = new Uint8Array(regions.length * 9);
  const bytes = new Map<number, [number, number, number]>();
  let spare = palette.size;
  for (let t = 0; t < regions.length; t++) {
    const id = regions[t];
    let rgb = bytes.get(id);
    if (!rgb) {
      rgb = hexBytes(palette.get(id) ?? SPARE[spare++ % SPARE.length]);
      bytes.set(id, rgb);
    }
    for (let k = 0; k < 3; k++) out.set(rgb, t * 9 + k * 3);
  }
  return out;
}

/** Colours by thickness: each corner the viridis colour of its vertex's thickness in [0, `maxMm`]. */
export function thicknessCornerColours(indices: ArrayLike<number>, thickness: ArrayLike<number>, maxMm: number): Uint8Array {
  const corner = new Float32Array(indices.length);
  for (let i = 0; i < indices.length; i++) corner[i] = thickness[indices[i]];
  return colorizeU8(corner, 0, maxMm);
}

/**
 * Top of the thickness scale, mm: the 98th percentile of the vertices' thickness rounded up to a
 * whole millimetre (a few very thick vertices would otherwise squeeze the rest of the wall into
 * the bottom of the map); at least 1. Values above share the top colour.
 */
export function thicknessScaleMax(thickness: ArrayLike<number>): number {
  const p98 = percentile98(thickness);
  return p98 === null ? 1 : Math.max(1, Math.ceil(p98 - 1e-9));
}

/** How many different colours an rgb byte array holds (the tests count the regions drawn). */
export function distinctColours(rgb: Uint8Array): number {
  const seen = new Set<number>();
  for (let i = 0; i + 2 < rgb.length; i += 3) seen.add((rgb[i] << 16) | (rgb[i + 1] << 8) | rgb[i + 2]);
  return seen.size;
}
