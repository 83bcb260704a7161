/** The read-out under the pointer: distance to the mesh in mm (after a run) and position in mm. */
import type { HoverInfo } from '../viewer/Viewer';
import { cssColorAt } from '../viewer/colormap';
import { h, mm } from './dom';

export class HoverReadout {
  readonly element: HTMLElement;

  constructor() {
    this.element = h('div', { class: 'hover-readout', hidden: true, 'data-testid': 'hover-readout' });
  }

  show(info: HoverInfo | null, scaleMaxMm: number): void {
    if (!info) {
      this.element.hidden = true;
      return;
    }
    const p = info.point;
    const pos = `(${p.x.toFixed(1)}, ${p.y.toFixed(1)}, ${p.z.toFixed(1)}) mm`;
    const children: (Node | string)[] = [];
    if (info.distanceMm !== null) {
      const sw = h('span', { class: 'swatch' });
      sw.style.background = cssColorAt(info.distanceMm, 0, scaleMaxMm);
      children.push(sw, h('strong', {}, mm(info.distanceMm, 2)), ` ${info.what === 'mesh' ? 'to nearest contour' : 'to mesh'}`, h('br'));
    } else {
      children.push(h('strong', {}, info.what), h('br'));
    }
    children.push(h('span', { class: 'muted' }, pos));
    this.element.replaceChildren(...children);
    this.element.style.left = `${info.x + 14}px`;
    this.element.style.top = `${info.y + 14}px`;
    this.element.hidden = false;
  }
}
