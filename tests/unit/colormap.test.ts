import { describe, expect, it } from 'vitest';
import { colorAt, colorize, colorizeU8, cssColorAt, LUT_SIZE, lutIndex, niceTicks, robustMax, VIRIDIS_LUT } from '../../web/src/viewer/colormap';

const lum = (r: number, g: number, b: number) => 0.2126 * r + 0.7152 * g + 0.0722 * b;

describe('viridis lookup table', () => {
  it('has the published end colours', () => {
    expect(cssColorAt(0, 0, 1)).toBe('rgb(68, 1, 84)'); // #440154
    expect(cssColorAt(1, 0, 1)).toBe('rgb(253, 231, 37)'); // #fde725
    expect(cssColorAt(0.5, 0, 1)).toBe('rgb(33, 145, 140)'); // #21918c
  });
  it('is monotonic in luminance (perceptual ordering)', () => {
    let prev = -1;
    for (let i = 0; i < LUT_SIZE; i++) {
      const l = lum(VIRIDIS_LUT[i * 3], VIRIDIS_LUT[i * 3 + 1], VIRIDIS_LUT[i * 3 + 2]);
      expect(l).toBeGreaterThan(prev);
      prev = l;
    }
  });
  it('clamps out-of-range values and maps NaN to the low end', () => {
    expect(lutIndex(-5, 0, 2)).toBe(0);
    expect(lutIndex(7, 0, 2)).toBe(LUT_SIZE - 1);
    expect(lutIndex(NaN, 0, 2)).toBe(0);
    expect(lutIndex(1, 0, 0)).toBe(0);
    expect(lutIndex(1, 0, 2)).toBe(128);
  });
  it('colorize fills three floats per value and reuses the output array', () => {
    const out = new Float32Array(6);
    const res = colorize([0, 2], 0, 2, out);
    expect(res).toBe(out);
    expect(Array.from(res.slice(3))).toEqual(colorAt(2, 0, 2).map((v) => Math.fround(v)));
    expect(colorize([1, 2, 3], 0, 1).length).toBe(9);
  });
});

describe('legend ticks in mm', () => {
  it('uses 1-2-5 steps covering the range', () => {
    expect(niceTicks(0, 1)).toEqual([0, 0.2, 0.4, 0.6, 0.8, 1]);
    expect(niceTicks(0, 2.5)).toEqual([0, 0.5, 1, 1.5, 2, 2.5]);
    expect(niceTicks(0, 3)).toEqual([0, 1, 2, 3]);
    expect(niceTicks(0, 0.15)).toEqual([0, 0.05, 0.1, 0.15]);
  });
  it('degrades gracefully on empty ranges', () => {
    expect(niceTicks(1, 1)).toEqual([1]);
  });
  it('robust max ignores a single outlier and rounds up to a nice number', () => {
    const v = new Float32Array(1000).map((_, i) => (i / 999) * 0.9);
    v[0] = 50;
    expect(robustMax(v)).toBe(1); // p98 = 0.88 mm, rounded up; the 50 mm outlier is ignored
    expect(robustMax([0.13, 0.21, 0.27])).toBe(0.25); // p98 of three values is the middle one
    expect(robustMax([])).toBe(1);
    expect(robustMax([0, 0])).toBe(1);
  });
});

describe('byte colours', () => {
  it('match the float LUT rounded to bytes', () => {
    const out = colorizeU8([0, 0.5, 1], 0, 1);
    expect(Array.from(out)).toEqual([68, 1, 84, 33, 145, 140, 253, 231, 37]);
  });
});
