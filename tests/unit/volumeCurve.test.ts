// The Function panel's volume curve (web/src/ui/volumeCurve.ts): the y axis covers the volumes,
// the phase labels along x never overlap at the chart's width (first and last always there), a
// phase without a volume breaks its line instead of dropping to zero, ED and ES are ringed where
// the summary says, and two phases give no curve at all.
import { describe, expect, it } from 'vitest';
import type { FunctionSummary } from '../../web/src/core-client/protocol';
import { CURVE_BOX, cavities, cavitySeries, curveLayout, extent, type CurveSeries, type XLabel } from '../../web/src/ui/volumeCurve';

const series = (surface: string, volumes: (number | null)[], ed: string | null = null, es: string | null = null): CurveSeries => ({ surface, volumes, ed, es });
const frames = (n: number) => Array.from({ length: n }, (_, i) => String(i));
/** A smooth cycle of `n` frames: ED at frame 0, ES half way. */
const cycle = (n: number, edv: number, esv: number) => frames(n).map((_, i) => esv + ((edv - esv) * (1 + Math.cos((2 * Math.PI * i) / n))) / 2);

/** The x labels of `phases` (one flat line: only the labels matter). */
function labels(phases: string[]): XLabel[] {
  return curveLayout(phases, [series('LV_ENDO', phases.map(() => 100))])!.xLabels;
}

/** Each label ends before the next begins, and none leaves the chart. */
function expectApart(ls: XLabel[]): void {
  for (let j = 1; j < ls.length; j++) expect(extent(ls[j - 1])[1], `${ls[j - 1].text} | ${ls[j].text}`).toBeLessThan(extent(ls[j])[0]);
  expect(extent(ls[0])[0]).toBeGreaterThanOrEqual(0);
  expect(extent(ls[ls.length - 1])[1]).toBeLessThanOrEqual(CURVE_BOX.width);
}

describe('the volume curve', () => {
  it('is not drawn for two phases, nor without a volume', () => {
    expect(curveLayout(['ED', 'ES'], [series('LV_ENDO', [173.7, 65.9], 'ED', 'ES')])).toBeNull();
    expect(curveLayout(['a', 'b', 'c'], [series('LV_ENDO', [null, null, null])])).toBeNull();
    expect(curveLayout(['a', 'b', 'c'], [series('LV_ENDO', [173.7, 120, 65.9])])).not.toBeNull();
  });

  it('has round y ticks from 0 over the largest volume, volumes placed on them', () => {
    const layout = curveLayout(['ED', 'mid', 'ES'], [series('LV_ENDO', [173.7, 120.2, 65.9]), series('RV_ENDO', [180.6, 111.0, 71.7])])!;
    expect(layout.yTicks.map((t) => t.label)).toEqual(['0', '50', '100', '150', '200']);
    const { plot } = layout;
    expect(layout.yTicks[0].pos).toBeCloseTo(plot.top + plot.height, 9);
    expect(layout.yTicks[4].pos).toBeCloseTo(plot.top, 9);
    const rv = layout.lines[1].dots;
    expect(rv.map((d) => d.ml)).toEqual([180.6, 111.0, 71.7]);
    // 180.6 ml is 90.3 % of the way up a 0-200 ml axis.
    expect(rv[0].y).toBeCloseTo(plot.top + plot.height * (1 - 180.6 / 200), 9);
    // The first and last phases 6 units inside the plot, so their rings and labels stay in it.
    expect(rv.map((d) => d.x)).toEqual([plot.left + 6, plot.left + plot.width / 2, plot.left + plot.width - 6]);
    expect(plot.left + plot.width).toBeLessThanOrEqual(CURVE_BOX.width);
    // Larger hearts: the axis grows to cover them.
    expect(curveLayout(frames(3), [series('LV_ENDO', [420, 300, 260])])!.yTicks.map((t) => t.value)).toEqual([0, 200, 400, 600]);
  });

  it('labels 3 phases all, 12 numbered frames all, 50 every fifth (45 too near 49) and the last, never overlapping', () => {
    const three = labels(['patient1-ED', 'patient1-mid', 'patient1-ES']);
    expect(three.map((l) => [l.text, l.anchor])).toEqual([['patient1-ED', 'start'], ['patient1-mid', 'middle'], ['patient1-ES', 'end']]);
    expectApart(three);

    const twelve = labels(frames(12));
    expect(twelve.map((l) => l.index)).toEqual(frames(12).map(Number));
    expectApart(twelve);

    const fifty = labels(frames(50));
    expect(fifty.map((l) => l.text)).toEqual(['0', '5', '10', '15', '20', '25', '30', '35', '40', '49']);
    expectApart(fifty);
  });

  it('thins long names to the first and the last, and shortens names too long for half the width', () => {
    const long = frames(12).map((i) => `patient1-frame-${i.padStart(2, '0')}`);
    const twelve = labels(long);
    expect(twelve.map((l) => l.text)).toEqual(['patient1-frame-00', 'patient1-frame-11']);
    expectApart(twelve);

    const name = (p: string) => `a-very-long-export-name-of-the-study-${p}`;
    const three = labels([name('ED'), name('mid'), name('ES')]);
    expect(three.map((l) => l.index)).toEqual([0, 2]);
    // Half of the 225 units between the first and last phases hold 22 characters of ~5; the end
    // tells the phases apart.
    expect(three.map((l) => l.text)).toEqual(['…-name-of-the-study-ED', '…-name-of-the-study-ES']);
    expectApart(three);
  });

  it('breaks a line at a phase without a volume: no dot there and no zero', () => {
    const layout = curveLayout(frames(6), [series('LV_ENDO', [170, 150, null, 90, 70, 110]), series('RV_ENDO', [180, null, 120, null, 75, 115])])!;
    const [lv, rv] = layout.lines;
    expect(lv.segments.map((seg) => seg.map((p) => p.index))).toEqual([[0, 1], [3, 4, 5]]);
    expect(lv.dots.map((d) => d.phase)).toEqual(['0', '1', '3', '4', '5']);
    // One phase between two gaps is a dot on no line.
    expect(rv.segments.map((seg) => seg.map((p) => p.index))).toEqual([[4, 5]]);
    expect(rv.dots.map((d) => d.index)).toEqual([0, 2, 4, 5]);
    const bottom = layout.plot.top + layout.plot.height;
    expect([...lv.dots, ...rv.dots].every((d) => d.y < bottom - 10)).toBe(true);
  });

  it('rings each ventricle\'s ED and ES where the summary says; one label where they share a phase', () => {
    const lv = series('LV_ENDO', [150, 173.7, 120, 65.9, 100], '1', '3');
    const rv = series('RV_ENDO', [180.6, 170, 110, 80, 71.7], '0', '4');
    const layout = curveLayout(frames(5), [lv, rv])!;
    expect(layout.markers.map((m) => `${m.surface} ${m.kind} ${m.phase} ${m.ml}`)).toEqual(['LV_ENDO ED 1 173.7', 'LV_ENDO ES 3 65.9', 'RV_ENDO ED 0 180.6', 'RV_ENDO ES 4 71.7']);
    const dot = (line: number, index: number) => layout.lines[line].dots.find((d) => d.index === index)!;
    expect([layout.markers[0].x, layout.markers[0].y]).toEqual([dot(0, 1).x, dot(0, 1).y]);
    expect(layout.markerLabels.map((l) => `${l.kind} ${l.surfaces.join('+')}`)).toEqual(['ED LV_ENDO', 'ES LV_ENDO', 'ED RV_ENDO', 'ES RV_ENDO']);
    // ED above its ring, ES below.
    expect(layout.markerLabels[0].y).toBeLessThan(layout.markers[0].y);
    expect(layout.markerLabels[1].y).toBeGreaterThan(layout.markers[1].y);

    const same = curveLayout(frames(3), [series('LV_ENDO', [173.7, 120, 65.9], '0', '2'), series('RV_ENDO', [180.6, 111, 71.7], '0', '2')])!;
    expect(same.markers).toHaveLength(4);
    expect(same.markerLabels.map((l) => `${l.kind} ${l.surfaces.join('+')}`)).toEqual(['ED LV_ENDO+RV_ENDO', 'ES LV_ENDO+RV_ENDO']);
    // Above the higher ring (RV's 180.6 ml), below the lower (LV's 65.9 ml).
    const ring = (surface: string, kind: string) => same.markers.find((m) => m.surface === surface && m.kind === kind)!;
    expect(same.markerLabels[0].y).toBe(ring('RV_ENDO', 'ED').y - 5.5);
    expect(same.markerLabels[1].y).toBeGreaterThan(ring('LV_ENDO', 'ES').y);
  });

  it('moves a label off a ring and another label: two ventricles\' ES one frame apart at the same volume', () => {
    const layout = curveLayout(frames(30), [series('LV_ENDO', cycle(30, 170, 70), '0', '15'), series('RV_ENDO', cycle(30, 180, 70).map((v, i) => (i === 16 ? 69 : v)), '0', '16')])!;
    expect(layout.markers.filter((m) => m.kind === 'ES').map((m) => `${m.phase} ${m.ml.toFixed(1)}`)).toEqual(['15 70.0', '16 69.0']);
    const [lvRing, rvRing] = layout.markers.filter((m) => m.kind === 'ES');
    const [lv, rv] = layout.markerLabels.filter((l) => l.kind === 'ES');
    // Just below the LV's ring (4.5 units, a unit of space, a 6-unit capital) ...
    expect(lv.y).toBeCloseTo(lvRing.y + 11.5, 9);
    // ... and the RV's, 8 units away, below the LV's ring and then below the LV's label.
    expect(rvRing.x - lvRing.x).toBeCloseTo(225.12 / 29, 9);
    expect(rv.y - 6).toBeGreaterThanOrEqual(lvRing.y + 4.5);
    expect(rv.y - 6).toBeGreaterThanOrEqual(lv.y);

    // The LV's ED (frame 0, 170 ml) below the RV's (frame 1, 185 ml): its label goes over the RV's ring.
    const ed = curveLayout(frames(30), [series('LV_ENDO', cycle(30, 170, 70), '0', '15'), series('RV_ENDO', cycle(30, 185, 70).map((v, i) => (i === 0 ? 180 : v)), '1', '16')])!;
    const rvEd = ed.markers.find((m) => m.kind === 'ED' && m.surface === 'RV_ENDO')!;
    const lvEdLabel = ed.markerLabels.find((l) => l.kind === 'ED' && l.surfaces[0] === 'LV_ENDO')!;
    expect(lvEdLabel.y).toBeLessThanOrEqual(rvEd.y - 4.5);
  });
});

describe('the cavities of the summary', () => {
  const summary: FunctionSummary = {
    ventricles: [{ surface: 'RV_ENDO', ed_phase: 'ED', es_phase: 'ES', edv_ml: 180.6, esv_ml: 71.7, sv_ml: 108.9, ef_percent: 60.3, phases_used: 2 }],
    single: [{ surface: 'LA', volume_ml: 60 }],
    lv_mass: null,
  };

  it('are its ventricles and its once-measured cavities, never the epicardia it left out', () => {
    expect(cavities(summary)).toEqual(['RV_ENDO', 'LA']);
  });

  it('take their volumes by phase (not finite: none) and their ED and ES from the summary', () => {
    const table: Record<string, (number | null)[]> = { RV_ENDO: [180.6, 120, 71.7], LA: [null, 60, Number.NaN] };
    const got = cavitySeries(summary, ['LA', 'RV_ENDO'], 3, (i, s) => table[s][i]);
    expect(got).toEqual([
      { surface: 'LA', volumes: [null, 60, null], ed: null, es: null },
      { surface: 'RV_ENDO', volumes: [180.6, 120, 71.7], ed: 'ED', es: 'ES' },
    ]);
  });
});
