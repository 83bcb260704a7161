/**
 * Pure layout of the Lab's two charts (no DOM, unit-tested): a linear mm axis with round ticks for
 * the leave-one-out bar chart, and linear or logarithmic axes for the parallel-coordinates plot of
 * the parameter sweep (Inselberg 1985). Coordinates are SVG user units, y growing downwards.
 */
import { niceTicks } from '../viewer/colormap';

export interface Tick {
  value: number;
  /** Position along the axis in user units. */
  pos: number;
  label: string;
}

/** Short label of a tick or value: at most 3 significant digits, exponent form for big/small logs. */
export function formatTick(v: number): string {
  if (!Number.isFinite(v)) return '–';
  if (v !== 0 && (Math.abs(v) >= 1e4 || Math.abs(v) < 1e-3)) return v.toExponential(0).replace('e+', 'e');
  return String(Number(v.toPrecision(3)));
}

export interface Bar {
  index: number;
  x: number;
  y: number;
  width: number;
  height: number;
  /** null: that contour could not be measured (the rebuild without it failed). */
  value: number | null;
  worst: boolean;
}

export interface BarLayout {
  bars: Bar[];
  ticks: Tick[];
  /** Top of the mm axis. */
  max: number;
  plot: { left: number; top: number; width: number; height: number };
}

/**
 * Bars of `values` (mm) in a `width` x `height` box with room for the axis on the left and labels
 * below; the axis starts at 0 and ends at a round number above the largest value. The worst
 * (largest) value is flagged.
 */
export function barLayout(values: readonly (number | null)[], width: number, height: number): BarLayout {
  const plot = { left: 34, top: 8, width: Math.max(1, width - 40), height: Math.max(1, height - 30) };
  const finite = values.filter((v): v is number => v !== null && Number.isFinite(v));
  const top = finite.length ? Math.max(...finite) : 0;
  const { max, ticks: tickValues } = roundAxis(top);
  const y = (v: number) => plot.top + plot.height * (1 - v / max);
  const worstValue = finite.length ? top : NaN;
  let worstIndex = -1;
  values.forEach((v, i) => {
    if (worstIndex < 0 && v === worstValue) worstIndex = i;
  });
  const n = Math.max(1, values.length);
  const slot = plot.width / n;
  const barWidth = Math.max(1, slot * 0.72);
  const bars = values.map((v, i) => {
    const val = v !== null && Number.isFinite(v) ? v : null;
    const yTop = val === null ? plot.top + plot.height : y(val);
    return {
      index: i,
      x: plot.left + i * slot + (slot - barWidth) / 2,
      y: yTop,
      width: barWidth,
      height: plot.top + plot.height - yTop,
      value: val,
      worst: i === worstIndex,
    };
  });
  return { bars, ticks: tickValues.map((t) => ({ value: t, pos: y(t), label: formatTick(t) })), max, plot };
}

/** An axis from 0 to a round number at or above `top` (1 when there is nothing to show). */
export function roundAxis(top: number): { max: number; ticks: number[] } {
  if (!(top > 0) || !Number.isFinite(top)) return { max: 1, ticks: [0, 0.5, 1] };
  const ticks = niceTicks(0, top, 5);
  const step = ticks.length > 1 ? ticks[1] - ticks[0] : top;
  const steps = Math.max(1, Math.ceil(top / step - 1e-9));
  const out: number[] = [];
  for (let k = 0; k <= steps; k++) out.push(Number((k * step).toPrecision(12)));
  return { max: out[out.length - 1], ticks: out };
}

export interface AxisSpec {
  key: string;
  label: string;
  log: boolean;
}

export interface ParallelAxis extends AxisSpec {
  x: number;
  min: number;
  max: number;
  ticks: Tick[];
  /** y of a value on this axis (mid-height when the axis has a single value). */
  y(v: number): number;
  /** The value at height y (inverse of `y`; the axis minimum when it has a single value). */
  value(y: number): number;
}

/** Vertical axes spread over the width, each scaled to the finite values of its key in `rows`. */
export function parallelAxes(
  specs: readonly AxisSpec[],
  rows: readonly Record<string, number | null | undefined>[],
  width: number,
  height: number,
): ParallelAxis[] {
  const top = 22;
  const bottom = height - 22;
  const left = 30;
  const right = width - 30;
  return specs.map((spec, k) => {
    const x = specs.length > 1 ? left + ((right - left) * k) / (specs.length - 1) : (left + right) / 2;
    const vals = rows
      .map((r) => r[spec.key])
      .filter((v): v is number => typeof v === 'number' && Number.isFinite(v) && (!spec.log || v > 0));
    const min = vals.length ? Math.min(...vals) : 0;
    const max = vals.length ? Math.max(...vals) : 1;
    const t = (v: number) => (spec.log ? Math.log10(v) : v);
    const lo = t(min);
    const hi = t(max);
    const y = (v: number) => {
      if (!(hi > lo)) return (top + bottom) / 2;
      const f = (t(v) - lo) / (hi - lo);
      return bottom - f * (bottom - top);
    };
    const value = (yy: number) => {
      if (!(hi > lo)) return min;
      const tv = lo + ((bottom - yy) / (bottom - top)) * (hi - lo);
      return spec.log ? Math.pow(10, tv) : tv;
    };
    const tickValues = distinct(vals).length <= 4 ? distinct(vals) : spec.log ? [min, max] : niceTicks(min, max, 4).filter((v) => v >= min && v <= max);
    return { ...spec, x, min, max, y, value, ticks: tickValues.map((v) => ({ value: v, pos: y(v), label: formatTick(v) })) };
  });
}

function distinct(values: number[]): number[] {
  return [...new Set(values)].sort((a, b) => a - b);
}

/** SVG polyline points of one row across the axes; null when a value is missing. */
export function rowPath(axes: readonly ParallelAxis[], row: Record<string, number | null | undefined>): string | null {
  const parts: string[] = [];
  for (const a of axes) {
    const v = row[a.key];
    if (typeof v !== 'number' || !Number.isFinite(v) || (a.log && v <= 0)) return null;
    parts.push(`${a.x.toFixed(1)},${a.y(v).toFixed(1)}`);
  }
  return parts.join(' ');
}

/** A brushed value range per axis key (inclusive). */
export type Brushes = ReadonlyMap<string, readonly [number, number]>;

/** Whether a row lies inside every brush (a row missing a brushed value is outside). */
export function inBrushes(row: Record<string, number | null | undefined>, brushes: Brushes): boolean {
  for (const [key, [a, b]] of brushes) {
    const v = row[key];
    const lo = Math.min(a, b);
    const hi = Math.max(a, b);
    // A small relative tolerance, so a brush drawn exactly over a grid value keeps it.
    const tol = 1e-9 * Math.max(1, Math.abs(lo), Math.abs(hi));
    if (typeof v !== 'number' || !Number.isFinite(v) || v < lo - tol || v > hi + tol) return false;
  }
  return true;
}
