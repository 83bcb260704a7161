/**
 * Parallel-coordinates plot of the parameter sweep (Inselberg 1985): one vertical axis per swept
 * parameter and per measure, one polyline per grid point, coloured by the last measure (viridis,
 * brighter = lower distance). Drag along an axis to brush a range (lines outside it fade; several
 * axes combine), click an axis without dragging to clear its brush. Hovering a line shows its
 * values. Hand-written SVG over chartScale.parallelAxes.
 */
import type { SweepItem } from '../core-client/protocol';
import { cssColorAt } from '../viewer/colormap';
import { formatTick, inBrushes, parallelAxes, rowPath, type AxisSpec, type ParallelAxis } from './chartScale';
import { s } from './svg';

const WIDTH = 300;
const HEIGHT = 180;

const PARAM_AXES: AxisSpec[] = [
  { key: 'lambda', label: 'λ', log: true },
  { key: 'smoothing_iterations', label: 'smooth', log: false },
  { key: 'target_reduction', label: 'reduce', log: false },
  { key: 'attractor_spacing', label: 'spacing', log: false },
];

type Row = Record<string, number | null | undefined>;

export class SweepPlot {
  readonly element: SVGSVGElement;
  private rows: readonly SweepItem[] = [];
  private readonly brushes = new Map<string, [number, number]>();
  /** Told how many rows are inside the brushes (all when there is none). */
  onBrush: ((selected: number, total: number) => void) | null = null;

  constructor() {
    this.element = s('svg', { class: 'lab-chart', viewBox: `0 0 ${WIDTH} ${HEIGHT}`, 'data-testid': 'sweep-plot', role: 'img', 'aria-label': 'parameter sweep, parallel coordinates' });
  }

  render(rows: readonly SweepItem[]): void {
    if (rows.length === 0) this.brushes.clear();
    this.rows = rows;
    this.draw();
  }

  /** Rows inside every brush. */
  selected(): SweepItem[] {
    return this.rows.filter((r) => inBrushes(r as unknown as Row, this.brushes));
  }

  private draw(): void {
    const rows = this.rows;
    const withTruth = rows.some((r) => typeof r.truth_mean === 'number');
    const specs: AxisSpec[] = [
      ...PARAM_AXES,
      { key: 'contour_mean', label: 'contour', log: false },
      ...(withTruth ? [{ key: 'truth_mean', label: 'truth', log: false }] : []),
    ];
    for (const k of [...this.brushes.keys()]) if (!specs.some((a) => a.key === k)) this.brushes.delete(k);
    const records = rows.map((r) => r as unknown as Row);
    const axes = parallelAxes(specs, records, WIDTH, HEIGHT);
    const colourAxis = axes[axes.length - 1];
    const nodes: SVGElement[] = [];
    const key = (r: Row) => (r[colourAxis.key] as number | undefined) ?? 0;
    let inside = 0;
    for (const rec of [...records].sort((a, b) => key(b) - key(a))) {
      const pts = rowPath(axes, rec);
      if (!pts) continue;
      const on = inBrushes(rec, this.brushes);
      if (on) inside++;
      const v = key(rec);
      const line = s(
        'polyline',
        {
          points: pts,
          class: on ? 'pc-line' : 'pc-line faded',
          stroke: cssColorAt(colourAxis.max - v, 0, Math.max(1e-9, colourAxis.max - colourAxis.min)),
          'data-testid': 'sweep-line',
          'data-selected': on ? '1' : '0',
        },
        s('title', {}, specs.map((a) => `${a.label} ${formatTick(rec[a.key] ?? NaN)}`).join(' · ')),
      );
      nodes.push(line);
    }
    for (const a of axes) nodes.push(...this.axisNodes(a));
    nodes.push(s('text', { x: WIDTH / 2, y: HEIGHT - 2, 'text-anchor': 'middle', class: 'tick' }, `mean distance, mm${withTruth ? ' (truth: mesh → truth)' : ''}; brighter = lower`));
    this.element.replaceChildren(...nodes);
    this.onBrush?.(inside, records.filter((r) => rowPath(axes, r) !== null).length);
  }

  private axisNodes(a: ParallelAxis): SVGElement[] {
    const top = 22;
    const bottom = HEIGHT - 22;
    const out: SVGElement[] = [s('line', { x1: a.x, x2: a.x, y1: top, y2: bottom, class: 'axis' })];
    out.push(s('text', { x: a.x, y: 10, 'text-anchor': 'middle', class: 'axis-label' }, a.label));
    for (const t of a.ticks) out.push(s('text', { x: a.x + 3, y: t.pos + 3, class: 'tick' }, t.label));
    const b = this.brushes.get(a.key);
    if (b) {
      const y0 = a.y(Math.max(b[0], b[1]));
      const y1 = a.y(Math.min(b[0], b[1]));
      out.push(s('rect', { x: a.x - 5, y: Math.min(y0, y1) - 2, width: 10, height: Math.abs(y1 - y0) + 4, class: 'brush', 'data-testid': `brush-${a.key}` }));
    }
    // A wide transparent strip catches the drags.
    const hit = s('rect', { x: a.x - 9, y: top - 4, width: 18, height: bottom - top + 8, class: 'axis-hit', 'data-testid': `axis-${a.key}` });
    hit.addEventListener('pointerdown', (e) => this.startBrush(e, a));
    out.push(hit);
    return out;
  }

  /** Drag: brush from the press to the release; a click (no movement) clears the axis' brush. */
  private startBrush(e: PointerEvent, a: ParallelAxis): void {
    e.preventDefault();
    const toY = (ev: PointerEvent) => {
      const box = this.element.getBoundingClientRect();
      return ((ev.clientY - box.top) / Math.max(1, box.height)) * HEIGHT;
    };
    const y0 = toY(e);
    let moved = false;
    // On the window: redrawing replaces the axis' elements during the drag.
    const move = (ev: PointerEvent) => {
      const y1 = toY(ev);
      if (Math.abs(y1 - y0) < 2) return;
      moved = true;
      this.brushes.set(a.key, [a.value(y0), a.value(y1)]);
      this.draw();
    };
    const up = (ev: PointerEvent) => {
      window.removeEventListener('pointermove', move);
      window.removeEventListener('pointerup', up);
      if (!moved) this.brushes.delete(a.key);
      else move(ev);
      this.draw();
    };
    window.addEventListener('pointermove', move);
    window.addEventListener('pointerup', up);
  }
}
