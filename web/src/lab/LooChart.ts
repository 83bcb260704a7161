/**
 * Leave-one-out bar chart (Villard et al. 2018, Figures 10-11): one bar per contour, its mean
 * distance (mm) to the mesh rebuilt without it; the worst bar is highlighted. Clicking a bar (or
 * focusing it and pressing Enter) selects that contour. Hand-written SVG over chartScale.barLayout.
 */
import type { LooItem } from '../core-client/protocol';
import { barLayout } from './chartScale';
import { s } from './svg';

const WIDTH = 300;
const HEIGHT = 150;

export class LooChart {
  readonly element: SVGSVGElement;
  private items: (LooItem | null)[] = [];
  private selected = -1;

  constructor(private readonly onSelect: (index: number) => void) {
    this.element = s('svg', { class: 'lab-chart', viewBox: `0 0 ${WIDTH} ${HEIGHT}`, 'data-testid': 'loo-chart', role: 'group', 'aria-label': 'leave-one-out distance per contour' });
  }

  /** `count` contours; items fill in as they finish. */
  reset(count: number): void {
    this.items = new Array<LooItem | null>(count).fill(null);
    this.selected = -1;
    this.render();
  }

  add(item: LooItem): void {
    if (item.index >= 0 && item.index < this.items.length) this.items[item.index] = item;
    this.render();
  }

  select(index: number): void {
    this.selected = index;
    this.render();
  }

  /** Index of the largest mean so far (-1 if none). */
  worst(): number {
    let best = -1;
    let max = -Infinity;
    this.items.forEach((it, i) => {
      const m = it?.stats?.mean;
      if (m !== undefined && m > max) {
        max = m;
        best = i;
      }
    });
    return best;
  }

  private render(): void {
    const values = this.items.map((it) => it?.stats?.mean ?? null);
    const layout = barLayout(values, WIDTH, HEIGHT);
    const { plot } = layout;
    const nodes: SVGElement[] = [];
    for (const t of layout.ticks) {
      nodes.push(s('line', { x1: plot.left - 3, x2: plot.left + plot.width, y1: t.pos, y2: t.pos, class: 'grid' }));
      nodes.push(s('text', { x: plot.left - 5, y: t.pos + 3, 'text-anchor': 'end', class: 'tick' }, t.label));
    }
    nodes.push(s('text', { x: 2, y: plot.top + plot.height / 2, class: 'axis-label', transform: `rotate(-90 8 ${plot.top + plot.height / 2})`, 'text-anchor': 'middle' }, 'mean mm'));
    for (const b of layout.bars) {
      const item = this.items[b.index];
      const cls = ['bar', b.worst ? 'worst' : '', b.index === this.selected ? 'selected' : '', item?.error ? 'failed' : '', item ? '' : 'pending']
        .filter(Boolean)
        .join(' ');
      const title = item
        ? item.stats
          ? `${item.id ?? `#${b.index + 1}`} (${item.kind}): mean ${item.stats.mean.toFixed(2)} mm, max ${item.stats.max.toFixed(2)} mm`
          : `${item.id ?? `#${b.index + 1}`}: not rebuilt (${item.error ?? 'unknown'})`
        : `contour ${b.index + 1}: waiting`;
      const rect = s('rect', {
        x: b.x,
        y: item ? b.y : plot.top + plot.height - 1,
        width: b.width,
        height: item ? Math.max(1, b.height) : 1,
        class: cls,
        tabindex: 0,
        'data-testid': 'loo-bar',
        'data-index': b.index,
        'data-mean': b.value ?? '',
      }, s('title', {}, title));
      rect.addEventListener('click', () => this.onSelect(b.index));
      rect.addEventListener('keydown', (e) => {
        if (e.key === 'Enter' || e.key === ' ') this.onSelect(b.index);
      });
      nodes.push(rect);
      if (layout.bars.length <= 24) {
        const label = item?.kind === 'LAX' ? `L${b.index + 1}` : `${b.index + 1}`;
        nodes.push(s('text', { x: b.x + b.width / 2, y: plot.top + plot.height + 11, 'text-anchor': 'middle', class: 'tick' }, label));
      }
    }
    nodes.push(s('line', { x1: plot.left, x2: plot.left + plot.width, y1: plot.top + plot.height, y2: plot.top + plot.height, class: 'axis' }));
    this.element.replaceChildren(...nodes);
  }
}
