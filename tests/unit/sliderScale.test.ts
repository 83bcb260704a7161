import { describe, expect, it } from 'vitest';
import { formatValue, LOG_STEPS_PER_DECADE, SLIDER_STEPS, sliderSteps, sliderToValue, valueToSlider } from '../../web/src/ui/sliderScale';
import { rustSchema } from './rustSchema';

const schema = rustSchema();
const spec = (name: string) => {
  const s = schema.find((x) => x.name === name);
  if (!s) throw new Error(`${name} missing`);
  return s;
};

describe('slider scale', () => {
  it('lambda moves by decades on a log slider', () => {
    const lambda = spec('lambda'); // 1e-2 .. 1e9: 11 decades
    expect(sliderSteps(lambda)).toBe(11 * LOG_STEPS_PER_DECADE);
    expect(valueToSlider(lambda, 1e-2)).toBe(0);
    expect(valueToSlider(lambda, 1e9)).toBe(sliderSteps(lambda));
    expect(valueToSlider(lambda, 1e5)).toBe(7 * LOG_STEPS_PER_DECADE);
    for (let d = -2; d <= 9; d++) expect(sliderToValue(lambda, valueToSlider(lambda, 10 ** d))).toBe(10 ** d);
    expect(sliderToValue(lambda, 7 * LOG_STEPS_PER_DECADE + 10)).toBe(3.2e5);
    expect(sliderToValue(lambda, 0)).toBe(1e-2);
  });
  it('integer parameters give whole numbers within range', () => {
    const it = spec('iterations');
    expect(sliderSteps(it)).toBe(SLIDER_STEPS);
    for (let p = 0; p <= SLIDER_STEPS; p += 37) {
      const v = sliderToValue(it, p);
      expect(Number.isInteger(v)).toBe(true);
      expect(v).toBeGreaterThanOrEqual(it.min);
      expect(v).toBeLessThanOrEqual(it.max);
    }
  });
  it('every default survives value -> slider -> value within one slider step', () => {
    for (const s of schema) {
      const back = sliderToValue(s, valueToSlider(s, s.default));
      if (s.log) expect(Math.abs(Math.log10(back) - Math.log10(s.default))).toBeLessThan(0.02);
      else expect(Math.abs(back - s.default)).toBeLessThanOrEqual((s.max - s.min) / sliderSteps(s) + 1e-9);
    }
  });
  it('formats values with units', () => {
    expect(formatValue(spec('lambda'), 1e5)).toBe('1e5');
    expect(formatValue(spec('beta'), 0.1)).toBe('0.1');
    expect(formatValue(spec('attractor_spacing'), 2.5)).toBe('2.5 mm');
    expect(formatValue(spec('iterations'), 250)).toBe('250');
  });
});
