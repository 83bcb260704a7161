/**
 * Perceptual colour map for distances in mm: viridis (van der Walt & Smith, matplotlib 2015),
 * rebuilt here from its eleven published anchor colours and linearly interpolated into a 256-entry
 * lookup table. Viridis is perceptually uniform and readable by colour-blind users, which matters
 * because the colour is the only cue for how far a contour is from the mesh.
 *
 * Pure module: no three.js, no DOM, so it can be unit-tested in node.
 */

/** sRGB anchors of viridis at t = 0, 0.1, ..., 1. */
const VIRIDIS_ANCHORS: readonly string[] = [
  '#440154', '#482475', '#414487', '#355f8d', '#2a788e', '#21918c',
  '#22a884', '#44bf70', '#7ad151', '#bddf26', '#fde725',
];

export const LUT_SIZE = 256;

function hexToRgb(hex: string): [number, number, number] {
  const v = parseInt(hex.slice(1), 16);
  return [((v >> 16) & 255) / 255, ((v >> 8) & 255) / 255, (v & 255) / 255];
}

/** Lookup table: LUT_SIZE x rgb in [0, 1], built once. */
export const VIRIDIS_LUT: Float32Array = (() => {
  const anchors = VIRIDIS_ANCHORS.map(hexToRgb);
  const lut = new Float32Array(LUT_SIZE * 3);
  const segments = anchors.length - 1;
  for (let i = 0; i < LUT_SIZE; i++) {
    const t = (i / (LUT_SIZE - 1)) * segments;
    const k = Math.min(Math.floor(t), segments - 1);
    const f = t - k;
    const a = anchors[k];
    const b = anchors[k + 1];
    for (let c = 0; c < 3; c++) lut[i * 3 + c] = a[c] + (b[c] - a[c]) * f;
  }
  return lut;
})();

/** Index into the LUT for a value in [min, max]; clamps outside, maps NaN to 0. */
export function lutIndex(value: number, min: number, max: number): number {
  const span = max - min;
  if (!Number.isFinite(value) || !(span > 0)) return 0;
  const t = (value - min) / span;
  const clamped = t < 0 ? 0 : t > 1 ? 1 : t;
  return Math.round(clamped * (LUT_SIZE - 1));
}

/** Colour of one value as rgb in [0, 1]. */
export function colorAt(value: number, min: number, max: number): [number, number, number] {
  const i = lutIndex(value, min, max) * 3;
  return [VIRIDIS_LUT[i], VIRIDIS_LUT[i + 1], VIRIDIS_LUT[i + 2]];
}

/** CSS colour of one value (for the legend and the hover read-out). */
export function cssColorAt(value: number, min: number, max: number): string {
  const [r, g, b] = colorAt(value, min, max);
  return `rgb(${Math.round(r * 255)}, ${Math.round(g * 255)}, ${Math.round(b * 255)})`;
}

/**
 * Fills `out` (length 3 x values.length) with colours of `values` in [min, max]; the array can then
 * back a normalized colour attribute. Returns `out` (allocated when absent or of the wrong size).
 */
export function colorize(values: ArrayLike<number>, min: number, max: number, out?: Float32Array): Float32Array {
  const target = out && out.length === values.length * 3 ? out : new Float32Array(values.length * 3);
  for (let v = 0; v < values.length; v++) {
    const i = lutIndex(values[v], min, max) * 3;
    target[v * 3] = VIRIDIS_LUT[i];
    target[v * 3 + 1] = VIRIDIS_LUT[i + 1];
    target[v * 3 + 2] = VIRIDIS_LUT[i + 2];
  }
  return target;
}

/**
 * "Nice" tick values covering [min, max] (steps of 1, 2 or 5 x 10^k), for a legend in mm.
 * Always returns at least two ticks when max > min.
 */
export function niceTicks(min: number, max: number, maxTicks = 6): number[] {
  if (!Number.isFinite(min) || !Number.isFinite(max) || max <= min) return [min];
  const raw = (max - min) / Math.max(1, maxTicks - 1);
  const mag = Math.pow(10, Math.floor(Math.log10(raw)));
  const step = [1, 2, 5, 10].map((m) => m * mag).find((s) => s >= raw) ?? 10 * mag;
  const first = Math.ceil(min / step - 1e-9) * step;
  const ticks: number[] = [];
  for (let t = first; t <= max + step * 1e-9; t += step) ticks.push(Number(t.toPrecision(12)));
  if (ticks.length < 2) return [min, max];
  return ticks;
}

/**
 * The 98th percentile of the finite values (null when there are none): the top of a colour scale
 * that one outlier should not stretch, so that the rest of the map keeps its contrast.
 */
export function percentile98(values: ArrayLike<number>): number | null {
  const finite: number[] = [];
  for (let i = 0; i < values.length; i++) if (Number.isFinite(values[i])) finite.push(values[i]);
  if (finite.length === 0) return null;
  finite.sort((a, b) => a - b);
  return finite[Math.min(finite.length - 1, Math.floor(0.98 * (finite.length - 1)))];
}

/**
 * Upper end of the colour scale: a robust maximum (the 98th percentile, rounded up to a nice
 * number) so that one outlier contour point does not wash out the whole map.
 */
export function robustMax(values: ArrayLike<number>): number {
  const p = percentile98(values);
  if (p === null || p <= 0) return 1;
  const mag = Math.pow(10, Math.floor(Math.log10(p)));
  const nice = [1, 1.5, 2, 2.5, 3, 4, 5, 6, 8, 10].map((m) => m * mag).find((s) => s >= p - 1e-12);
  return nice ?? 10 * mag;
}

/** The LUT as bytes, for compact normalized Uint8 colour attributes. */
export const VIRIDIS_LUT_U8: Uint8Array = Uint8Array.from(VIRIDIS_LUT, (v) => Math.round(v * 255));

/** Like `colorize`, but into bytes (3 per value) for a normalized Uint8 colour attribute. */
export function colorizeU8(values: ArrayLike<number>, min: number, max: number, out?: Uint8Array): Uint8Array {
  const target = out && out.length === values.length * 3 ? out : new Uint8Array(values.length * 3);
  for (let v = 0; v < values.length; v++) {
    const i = lutIndex(values[v], min, max) * 3;
    target[v * 3] = VIRIDIS_LUT_U8[i];
    target[v * 3 + 1] = VIRIDIS_LUT_U8[i + 1];
    target[v * 3 + 2] = VIRIDIS_LUT_U8[i + 2];
  }
  return target;
}
