/**
 * Parallel-coordinates plot of the parameter sweep (Inselberg 1985): one vertical axis per swept
 * parameter and per measure, one polyline per grid point, coloured by the last measure (viridis,
 * low = good). Hovering a line shows its values. Hand-written SVG over chartScale.parallelAxes.
 */
import type { SweepItem } from '../core-client/protocol';
import { cssColorAt } from '../viewer/colormap';
import { parallelAxes, rowPath, formatTick, type AxisSpec } from './chartScale';
import { s } from './svg';

const WIDTH = 300;
const HEIGHT = 180;

const PARAM_AXES: AxisSpec[] = [
  { key: 'lambda', label: 'λ', log: true },
  { key: 'smoothing_iterations', label: 'smooth', log: false },
  { key: 'target_reduction', label: 'reduce', log: false },
  { key: 'attractor_spacing', label: 'spacing', log: false },
];

export class SweepPlot {
  readonly element: SVGSVGElement;

  constructor() {
    this.element = s('svg', { class: 'lab-chart', viewBox: `0 0 ${WIDTH} ${HEIGHT}`, 'data-testid': 'sweep-plot', role: 'img', 'aria-label': 'parameter sweep, parallel coordinates' });
  }

  render(rows: readonly SweepItem[]): void {
    const withTruth = rows.some((r) => typeof r.truth_mean === 'number');
    const specs: AxisSpec[] = [
      ...PARAM_AXES,
      { key: 'contour_mean', label: 'contour', log: false },
      ...(withTruth ? [{ key: 'truth_mean', label: 'truth', log: false }] : []),
    ];
    const records = rows.map((r) => r as unknown as Record<string, number | null | undefined>);
    const axes = parallelAxes(specs, records, WIDTH, HEIGHT);
    const colourAxis = axes[axes.length - 1];
    const nodes: SVGElement[] = [];
    const ordered = [...rows].sort((a, b) => ((b as unknown as Record<string, number>)[colourAxis.key] ?? 0) - ((a as unknown as Record<string, number>)[colourAxis.key] ?? 0));
    for (const r of ordered) {
      const rec = r as unknown as Record<string, number | null | undefined>;
      const pts = rowPath(axes, rec);
      if (!pts) continue;
      const v = rec[colourAxis.key] ?? 0;
      const line = s('polyline', { points: pts, class: 'pc-line', stroke: cssColorAt(colourAxis.max - v, 0, Math.max(1e-9, colourAxis.max - colourAxis.min)), 'data-testid': 'sweep-line' },
        s('title', {}, specs.map((a) => `${a.label} ${formatTick(rec[a.key] ?? NaN)}`).join(' · ')));
      nodes.push(line);
    }
    for (const a of axes) {
      nodes.push(s('line', { x1: a.x, x2: a.x, y1: a.y(a.max), y2: a.y(a.min), class: 'axis' }));
      if (a.min === a.max) nodes.push(s('line', { x1: a.x, x2: a.x, y1: 22, y2: HEIGHT - 22, class: 'axis' }));
      nodes.push(s('text', { x: a.x, y: 10, 'text-anchor': 'middle', class: 'axis-label' }, a.label));
      for (const t of a.ticks) {
        nodes.push(s('text', { x: a.x + 3, y: t.pos + 3, class: 'tick' }, t.label));
      }
    }
    nodes.push(s('text', { x: WIDTH / 2, y: HEIGHT - 2, 'text-anchor': 'middle', class: 'tick' }, `mean distance, mm${withTruth ? ' (truth: mesh → truth)' : ''}; brighter = lower`));
    this.element.replaceChildren(...nodes);
  }
}
