/**
 * Mapping between a parameter's value and an `<input type=range>` position (0..STEPS). Log-scale
 * parameters (lambda spans 1e-2..1e9) move by decades; linear ones by equal steps. Pure and tested.
 */
import type { ParamSpec } from '../core-client/protocol';

export const SLIDER_STEPS = 1000;
/** Log sliders stop 20 times per decade, so every power of ten (1e5, the default) is reachable exactly. */
export const LOG_STEPS_PER_DECADE = 20;

/** Number of slider positions for a parameter (the range input's max). */
export function sliderSteps(spec: ParamSpec): number {
  if (spec.log && spec.min > 0) {
    return Math.max(1, Math.round((Math.log10(spec.max) - Math.log10(spec.min)) * LOG_STEPS_PER_DECADE));
  }
  return SLIDER_STEPS;
}

export function valueToSlider(spec: ParamSpec, value: number): number {
  const v = Math.min(spec.max, Math.max(spec.min, value));
  let t: number;
  if (spec.log && spec.min > 0) {
    t = (Math.log10(v) - Math.log10(spec.min)) / (Math.log10(spec.max) - Math.log10(spec.min));
  } else {
    t = spec.max > spec.min ? (v - spec.min) / (spec.max - spec.min) : 0;
  }
  return Math.round(t * sliderSteps(spec));
}

export function sliderToValue(spec: ParamSpec, position: number): number {
  const t = Math.min(1, Math.max(0, position / sliderSteps(spec)));
  let v: number;
  if (spec.log && spec.min > 0) {
    const lo = Math.log10(spec.min);
    const hi = Math.log10(spec.max);
    v = Math.pow(10, lo + t * (hi - lo));
    v = Number(v.toPrecision(2)); // 1e5, 3.2e4: values people can type back
  } else {
    v = spec.min + t * (spec.max - spec.min);
    v = spec.integer ? Math.round(v) : Number(v.toPrecision(3));
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
