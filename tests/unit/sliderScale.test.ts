import { describe, expect, it } from 'vitest';
import { formatValue, linearStep, LOG_STEPS_PER_DECADE, sliderSteps, sliderToValue, valueToSlider } from '../../web/src/ui/sliderScale';
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
  it('integer parameters move by one and stay whole and in range', () => {
    const it = spec('iterations'); // 1..2000
    expect(linearStep(it)).toBe(1);
    expect(sliderSteps(it)).toBe(1999);
    for (let p = 0; p <= sliderSteps(it); p += 37) {
      const v = sliderToValue(it, p);
      expect(Number.isInteger(v)).toBe(true);
      expect(v).toBeGreaterThanOrEqual(it.min);
      expect(v).toBeLessThanOrEqual(it.max);
    }
    expect(sliderToValue(it, valueToSlider(it, 250) + 1)).toBe(251);
  });
  it('linear float parameters move by round steps', () => {
    const beta = spec('beta'); // 0.01..1
    expect(linearStep(beta)).toBe(0.005);
    expect(sliderToValue(beta, valueToSlider(beta, 0.1) + 1)).toBe(0.105);
    expect(sliderToValue(beta, sliderSteps(beta))).toBe(1);
    expect(linearStep(spec('attractor_spacing'))).toBe(0.5); // 0..50 mm in 100 stops
  });
  it('every default of the Rust schema is exactly reachable', () => {
    for (const s of schema) expect(sliderToValue(s, valueToSlider(s, s.default))).toBe(s.default);
  });
  it('formats values with units', () => {
    expect(formatValue(spec('lambda'), 1e5)).toBe('1e5');
    expect(formatValue(spec('beta'), 0.1)).toBe('0.1');
    expect(formatValue(spec('attractor_spacing'), 2.5)).toBe('2.5 mm');
    expect(formatValue(spec('iterations'), 250)).toBe('250');
  });
});
