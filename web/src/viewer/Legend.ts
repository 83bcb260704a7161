/** Colour bar of the distance map with tick labels in mm (DOM overlay on the viewport). */
import { h } from '../ui/dom';
import { cssColorAt, niceTicks } from './colormap';

export class Legend {
  readonly element: HTMLElement;
  private readonly bar: HTMLElement;
  private readonly ticks: HTMLElement;

  constructor(title: string, testid: string) {
    this.bar = h('div', { class: 'legend-bar' });
    this.ticks = h('div', { class: 'legend-ticks' });
    this.element = h(
      'div',
      { class: 'legend', 'data-testid': testid, hidden: true },
      h('div', { class: 'legend-title' }, title),
      this.bar,
      this.ticks,
    );
    const stops: string[] = [];
    for (let i = 0; i <= 10; i++) stops.push(`${cssColorAt(i / 10, 0, 1)} ${i * 10}%`);
    this.bar.style.background = `linear-gradient(to right, ${stops.join(', ')})`;
  }

  /** Shows the scale 0..max mm (values above max share the top colour). */
  show(maxMm: number): void {
    this.ticks.replaceChildren();
    const ticks = niceTicks(0, maxMm, 5);
    for (const t of ticks) {
      const pct = (t / maxMm) * 100;
      const label = h('span', { class: 'legend-tick' }, `${Number(t.toPrecision(3))}`);
      label.style.left = `${pct}%`;
      this.ticks.append(label);
    }
    const unit = h('span', { class: 'legend-unit' }, 'mm');
    this.ticks.append(unit);
    this.element.hidden = false;
  }

  hide(): void {
    this.element.hidden = true;
  }
}
