// Units of the Lab's pure chart layout (web/src/lab/chartScale.ts) and sweep CSV (sweepCsv.ts).
import { describe, expect, it } from 'vitest';
import { barLayout, formatTick, parallelAxes, roundAxis, rowPath } from '../../../web/src/lab/chartScale';
import { parseValueList, sweepCsv, SWEEP_COLUMNS } from '../../../web/src/lab/sweepCsv';
import type { SweepItem } from '../../../web/src/core-client/protocol';

describe('roundAxis', () => {
  it('ends at a round number at or above the data, ticks evenly spaced from 0', () => {
    expect(roundAxis(3.21)).toEqual({ max: 4, ticks: [0, 1, 2, 3, 4] });
    expect(roundAxis(1.7)).toEqual({ max: 2, ticks: [0, 0.5, 1, 1.5, 2] });
    expect(roundAxis(0.42).max).toBeCloseTo(0.6, 12); // steps of 0.2
    expect(roundAxis(4).max).toBe(4);
    expect(roundAxis(0)).toEqual({ max: 1, ticks: [0, 0.5, 1] });
    expect(roundAxis(NaN).max).toBe(1);
  });
});

describe('barLayout', () => {
  it('maps mm to heights on a shared axis and flags the worst bar', () => {
    const l = barLayout([0.5, 2, null, 1], 300, 150);
    expect(l.bars).toHaveLength(4);
    expect(l.max).toBe(2);
    const [a, b, c, d] = l.bars;
    expect(b.worst).toBe(true);
    expect(a.worst || c.worst || d.worst).toBe(false);
    // The full-height bar is the axis maximum; heights are proportional to the value.
    expect(b.height).toBeCloseTo(l.plot.height, 9);
    expect(a.height / b.height).toBeCloseTo(0.25, 9);
    expect(c.value).toBeNull();
    expect(c.height).toBe(0);
    // Bars are left to right, inside the plot, not overlapping.
    for (let i = 1; i < l.bars.length; i++) expect(l.bars[i].x).toBeGreaterThan(l.bars[i - 1].x + l.bars[i - 1].width);
    expect(l.bars[3].x + l.bars[3].width).toBeLessThanOrEqual(l.plot.left + l.plot.width + 1e-9);
    // Ticks: 0 at the bottom of the plot, the maximum at its top.
    expect(l.ticks[0]).toMatchObject({ value: 0, pos: l.plot.top + l.plot.height });
    expect(l.ticks.at(-1)).toMatchObject({ value: 2, pos: l.plot.top });
  });

  it('survives no data and a tie (the first worst wins)', () => {
    expect(barLayout([], 300, 150).bars).toEqual([]);
    const l = barLayout([null, null], 300, 150);
    expect(l.bars.every((b) => !b.worst && b.height === 0)).toBe(true);
    const tie = barLayout([1, 3, 3], 300, 150);
    expect(tie.bars.map((b) => b.worst)).toEqual([false, true, false]);
  });
});

describe('parallel coordinates', () => {
  const rows = [
    { lambda: 1e3, smooth: 50, err: 0.4 },
    { lambda: 1e5, smooth: 200, err: 0.1 },
    { lambda: 1e4, smooth: 100, err: null },
  ];
  const axes = parallelAxes(
    [
      { key: 'lambda', label: 'λ', log: true },
      { key: 'smooth', label: 's', log: false },
      { key: 'err', label: 'mm', log: false },
    ],
    rows,
    300,
    180,
  );

  it('spreads axes over the width and scales log axes by decade', () => {
    expect(axes.map((a) => a.x)).toEqual([30, 150, 270]);
    const l = axes[0];
    expect(l.min).toBe(1e3);
    expect(l.max).toBe(1e5);
    // 1e4 is half way between 1e3 and 1e5 on a log axis.
    expect(l.y(1e4)).toBeCloseTo((l.y(1e3) + l.y(1e5)) / 2, 9);
    expect(l.y(1e5)).toBeLessThan(l.y(1e3)); // larger values higher up
    const s = axes[1];
    expect(s.y(125)).toBeCloseTo((s.y(50) + s.y(200)) / 2, 9);
  });

  it('draws a row only when every value is present', () => {
    expect(rowPath(axes, rows[0])?.split(' ')).toHaveLength(3);
    expect(rowPath(axes, rows[2])).toBeNull();
  });

  it('puts a constant axis at mid-height', () => {
    const [a] = parallelAxes([{ key: 'k', label: 'k', log: false }], [{ k: 2 }, { k: 2 }], 100, 180);
    expect(a.y(2)).toBeCloseTo((22 + 158) / 2, 9);
  });

  it('formats ticks compactly', () => {
    expect(formatTick(100000)).toBe('1e5');
    expect(formatTick(0.72)).toBe('0.72');
    expect(formatTick(0.12345)).toBe('0.123');
    expect(formatTick(NaN)).toBe('–');
  });
});

describe('sweep CSV', () => {
  const item = (index: number, extra: Partial<SweepItem>): SweepItem => ({
    index,
    lambda: 1e5,
    smoothing_iterations: 200,
    target_reduction: 0.72,
    attractor_spacing: 0,
    error: null,
    ...extra,
  });

  it('writes a header, one row per grid point in grid order, and quotes text', () => {
    const text = sweepCsv(
      [item(1, { contour_mean: 0.25, truth_mean: 0.1, hausdorff: 0.9 }), item(0, { lambda: 1000, error: 'too few, "really"' })],
      ['sweep of a.csv'],
    );
    const lines = text.trimEnd().split('\n');
    expect(lines[0]).toBe('# sweep of a.csv');
    expect(lines[1]).toBe(SWEEP_COLUMNS.join(','));
    expect(lines[2]).toBe('1000,200,0.72,0,,,,,,,"too few, ""really"""');
    expect(lines[3]).toBe('100000,200,0.72,0,0.25,,0.1,0.9,,,');
    expect(lines).toHaveLength(4);
  });

  it('parses value lists and names a bad entry', () => {
    expect(parseValueList('1e3, 1e5;2e5  7', 'λ')).toEqual([1e3, 1e5, 2e5, 7]);
    expect(parseValueList('  ', 'λ')).toEqual([]);
    expect(() => parseValueList('1, x', 'λ')).toThrow('λ: "x" is not a number');
  });
});

describe('brushing', () => {
  it('keeps rows inside every brushed range, inclusive, in either drag direction', async () => {
    const { inBrushes } = await import('../../../web/src/lab/chartScale');
    const row = { lambda: 1e5, err: 0.2 };
    expect(inBrushes(row, new Map())).toBe(true);
    expect(inBrushes(row, new Map([['lambda', [1e4, 1e5] as const]]))).toBe(true);
    expect(inBrushes(row, new Map([['lambda', [1e6, 1e4] as const]]))).toBe(true);
    expect(inBrushes(row, new Map([['lambda', [1e4, 1e5] as const], ['err', [0.3, 0.5] as const]]))).toBe(false);
    expect(inBrushes({ lambda: 1e5 }, new Map([['err', [0, 1] as const]]))).toBe(false);
  });

  it('inverts the axis scale (log and linear)', () => {
    const [l, s] = parallelAxes(
      [
        { key: 'lambda', label: 'λ', log: true },
        { key: 'smooth', label: 's', log: false },
      ],
      [
        { lambda: 1e3, smooth: 50 },
        { lambda: 1e5, smooth: 200 },
      ],
      300,
      180,
    );
    for (const v of [1e3, 3e3, 1e4, 1e5]) expect(l.value(l.y(v)) / v).toBeCloseTo(1, 9);
    for (const v of [50, 77, 200]) expect(s.value(s.y(v))).toBeCloseTo(v, 9);
  });
});
