/**
 * Mapping between a parameter's value and an `<input type=range>` position (0..sliderSteps).
 * Log-scale parameters (lambda spans 1e-2..1e9) move 20 stops per decade, so every power of ten is
 * exact; whole-number parameters move by 1; other linear ones by a round step (1, 2 or 5 x 10^k,
 * about 200 stops), so arrow keys give values people can type back (0.1 -> 0.105, not 0.101).
 * Pure and tested.
 */
import type { ParamSpec } from '../core-client/protocol';

/** Log sliders stop 20 times per decade, so every power of ten (1e5, the default) is reachable exactly. */
export const LOG_STEPS_PER_DECADE = 20;
/** Target number of stops of a linear, non-integer slider. */
export const LINEAR_STOPS = 200;

function isLog(spec: ParamSpec): boolean {
  return spec.log && spec.min > 0 && spec.max > spec.min;
}

/** Value change per slider stop of a linear parameter. */
export function linearStep(spec: ParamSpec): number {
  const range = spec.max - spec.min;
  if (!(range > 0)) return 1;
  if (spec.integer) return Math.max(1, niceStep(range / 5000));
  return niceStep(range / LINEAR_STOPS);
}

/** Smallest of 1, 2, 5 x 10^k that is >= x. */
function niceStep(x: number): number {
  const mag = Math.pow(10, Math.floor(Math.log10(x)));
  for (const m of [1, 2, 5, 10]) if (m * mag >= x * (1 - 1e-12)) return m * mag;
  return 10 * mag;
}

/** Number of slider positions for a parameter (the range input's max). */
export function sliderSteps(spec: ParamSpec): number {
  if (isLog(spec)) return Math.max(1, Math.round((Math.log10(spec.max) - Math.log10(spec.min)) * LOG_STEPS_PER_DECADE));
  if (!(spec.max > spec.min)) return 1;
  return Math.ceil((spec.max - spec.min) / linearStep(spec) - 1e-9);
}

export function valueToSlider(spec: ParamSpec, value: number): number {
  const v = Math.min(spec.max, Math.max(spec.min, value));
  if (isLog(spec)) {
    const t = (Math.log10(v) - Math.log10(spec.min)) / (Math.log10(spec.max) - Math.log10(spec.min));
    return Math.round(t * sliderSteps(spec));
  }
  return Math.min(sliderSteps(spec), Math.round((v - spec.min) / linearStep(spec)));
}

export function sliderToValue(spec: ParamSpec, position: number): number {
  const steps = sliderSteps(spec);
  const p = Math.min(steps, Math.max(0, Math.round(position)));
  let v: number;
  if (isLog(spec)) {
    const lo = Math.log10(spec.min);
    const hi = Math.log10(spec.max);
    v = Number(Math.pow(10, lo + (p / steps) * (hi - lo)).toPrecision(2)); // 1e5, 3.2e4
  } else {
    v = spec.min + p * linearStep(spec);
    v = spec.integer ? Math.round(v) : Number(v.toPrecision(10)); // no 0.30000000000000004
  }
  return Math.min(spec.max, Math.max(spec.min, v));
}

/** Display of a value with its unit ("0.1", "1e5", "2.5 mm"). */
export function formatValue(spec: ParamSpec, value: number): string {
  let text: string;
  if (spec.integer) text = String(Math.round(value));
  else if (value !== 0 && (Math.abs(value) >= 1e4 || Math.abs(value) < 1e-3)) text = value.toExponential(1).replace('e+', 'e').replace('.0e', 'e');
  else text = String(Number(value.toPrecision(3)));
  return spec.unit ? `${text} ${spec.unit}` : text;
}
