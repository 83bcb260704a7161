/**
 * Small live plot (canvas) of the attractor-to-mesh distance against iteration: max and mean, on a
 * log scale in mm (distances fall over orders of magnitude), with a marker at the step on screen.
 */
import { h } from './dom';

export interface PlotPoint {
  iteration: number;
  max: number;
  mean: number;
}

const MAX_COLOR = '#ffb74d';
const MEAN_COLOR = '#4fc3f7';

export class LivePlot {
  readonly element: HTMLElement;
  private readonly canvas: HTMLCanvasElement;
  private points: readonly PlotPoint[] = [];
  private total = 1;
  private marker: number | null = null;
  private pending = false;

  constructor() {
    this.canvas = h('canvas', { class: 'plot', 'data-testid': 'live-plot', 'aria-label': 'distance against iteration' });
    const legend = h(
      'div',
      { class: 'plot-legend' },
      h('span', { class: 'swatch', style: `background:${MAX_COLOR}` }),
      h('span', {}, 'max'),
      h('span', { class: 'swatch', style: `background:${MEAN_COLOR}` }),
      h('span', {}, 'mean attractor distance, mm (log) vs iteration'),
    );
    this.element = h('div', { class: 'plot-box' }, this.canvas, legend);
  }

  /** Every step's distances so far (one point per step; drawn at the next animation frame). */
  set(points: readonly PlotPoint[], total: number, marker: number | null): void {
    this.points = points;
    this.canvas.dataset.points = String(points.length);
    this.total = Math.max(1, total);
    this.marker = marker;
    if (!this.pending) {
      this.pending = true;
      requestAnimationFrame(() => {
        this.pending = false;
        this.draw();
      });
    }
  }

  private draw(): void {
    const c = this.canvas;
    const dpr = Math.min(2, window.devicePixelRatio || 1);
    const w = c.clientWidth || 240;
    const hgt = c.clientHeight || 100;
    if (c.width !== Math.round(w * dpr) || c.height !== Math.round(hgt * dpr)) {
      c.width = Math.round(w * dpr);
      c.height = Math.round(hgt * dpr);
    }
    const g = c.getContext('2d');
    if (!g) return;
    g.setTransform(dpr, 0, 0, dpr, 0, 0);
    g.clearRect(0, 0, w, hgt);
    const left = 34, right = 6, top = 6, bottom = 16;
    const pw = w - left - right, ph = hgt - top - bottom;
    const values = this.points.flatMap((p) => [p.max, p.mean]).filter((v) => v > 0 && Number.isFinite(v));
    const lo = Math.pow(10, Math.floor(Math.log10(values.length ? Math.min(...values) : 0.1)));
    const hi = Math.pow(10, Math.ceil(Math.log10(values.length ? Math.max(...values) : 10)));
    const ly0 = Math.log10(lo), ly1 = Math.max(ly0 + 1, Math.log10(hi));
    const X = (it: number) => left + (it / this.total) * pw;
    const Y = (v: number) => top + (1 - (Math.log10(Math.max(v, lo)) - ly0) / (ly1 - ly0)) * ph;
    g.font = '10px system-ui, sans-serif';
    g.fillStyle = '#8b96a5';
    g.strokeStyle = '#2a323d';
    g.lineWidth = 1;
    for (let e = ly0; e <= ly1; e++) {
      const y = Math.round(Y(Math.pow(10, e))) + 0.5;
      g.beginPath();
      g.moveTo(left, y);
      g.lineTo(left + pw, y);
      g.stroke();
      const v = Math.pow(10, e);
      g.fillText(v >= 1 ? `${v}` : `${Number(v.toPrecision(1))}`, 2, y + 3);
    }
    g.fillText('mm', 2, hgt - 4);
    g.fillText(`${this.total}`, left + pw - 18, hgt - 4);
    g.fillText('0', left, hgt - 4);
    const line = (key: 'max' | 'mean', color: string) => {
      g.strokeStyle = color;
      g.lineWidth = 1.5;
      g.beginPath();
      this.points.forEach((p, i) => {
        const x = X(p.iteration), y = Y(p[key]);
        if (i === 0) g.moveTo(x, y);
        else g.lineTo(x, y);
      });
      g.stroke();
    };
    line('max', MAX_COLOR);
    line('mean', MEAN_COLOR);
    if (this.marker !== null) {
      const x = Math.round(X(this.marker)) + 0.5;
      g.strokeStyle = '#e6edf3';
      g.lineWidth = 1;
      g.beginPath();
      g.moveTo(x, top);
      g.lineTo(x, top + ph);
      g.stroke();
    }
  }
}
