/**
 * The read-out under the pointer: distance to the mesh in mm (after a run; on a contour point, with
 * the contour's id; on a contour left out, to the mesh built without it, with why and its id) and
 * position in mm; on the myocardium wall (shown from the Export panel), its thickness in mm and its
 * region.
 */
import type { HoverInfo } from '../viewer/Viewer';
import { cssColorAt } from '../viewer/colormap';
import { h, mm } from './dom';
import { LEFT_OUT_TO_MESH } from './runText';

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
    if (info.what === 'wall') {
      // The wall: its thickness there and its region, the swatch its colour in the view.
      const sw = h('span', { class: 'swatch' });
      sw.style.background = info.tint ?? '';
      const thick = info.thicknessMm;
      children.push(sw, ...(thick === null || thick === undefined ? [] : [h('strong', {}, mm(thick, 1)), ' wall thickness · ']), info.label ?? 'wall', h('br'));
    } else if (info.what === 'other surface') {
      // Another surface of the file, drawn faint: which one (its last run; no distances of its own here).
      const sw = h('span', { class: 'swatch' });
      sw.style.background = info.tint ?? '';
      children.push(sw, ' ', h('strong', {}, info.label ?? ''), ' (other surface)', h('br'));
    } else if (info.what === 'left out') {
      // A contour the run left out: grey as drawn (the colour scale is the used contours'), how far
      // the mesh built without it passes where the run says, then why and which.
      const why = info.label ?? 'left out';
      const which = info.id ? ` · ${info.id}` : '';
      const d = info.distanceMm;
      const text = d === null ? [h('strong', {}, why), which] : [h('strong', {}, mm(d, 2)), ` ${LEFT_OUT_TO_MESH} · ${why}${which}`];
      children.push(h('span', { class: 'swatch set-aside-swatch' }), ' ', ...text, h('br'));
    } else if (info.distanceMm !== null) {
      const sw = h('span', { class: 'swatch' });
      sw.style.background = cssColorAt(info.distanceMm, 0, scaleMaxMm);
      // A contour point names its contour ("0.84 mm to mesh · s05_SAX_LV_ENDOCARDIAL"): its row in the Contours panel.
      const contour = info.what === 'contour point' && info.id ? ` · ${info.id}` : '';
      children.push(sw, h('strong', {}, mm(info.distanceMm, 2)), ` ${info.what === 'mesh' ? 'to nearest contour' : 'to mesh'}${contour}`, h('br'));
    } else {
      children.push(h('strong', {}, info.what), h('br'));
    }
    children.push(h('span', { class: 'muted' }, pos));
    this.element.replaceChildren(...children);
    this.element.hidden = false;
    // Measured once shown, from the view's left edge (where it may be as wide as the view: the
    // text wraps only in a view narrower than one line), then put beside the pointer on the side
    // where the view has room for it.
    this.element.style.left = '0px';
    this.element.style.top = '0px';
    const view = this.element.offsetParent;
    const at = readoutPlacement(info.x, info.y, this.element.offsetWidth, this.element.offsetHeight, view?.clientWidth ?? Infinity, view?.clientHeight ?? Infinity);
    this.element.style.left = `${at.left}px`;
    this.element.style.top = `${at.top}px`;
  }
}

/** Gap between the pointer and the read-out, px. */
const GAP_PX = 14;

/**
 * Where the read-out box (`width` x `height`) goes for a pointer at (`x`, `y`) in a view of
 * `viewWidth` x `viewHeight` (px): below right of the pointer, flipped to the left (above) where it
 * would run past the right (bottom) edge of the view, which clips it; never past the top left.
 */
export function readoutPlacement(x: number, y: number, width: number, height: number, viewWidth: number, viewHeight: number): { left: number; top: number } {
  const place = (p: number, size: number, room: number) => (p + GAP_PX + size <= room ? p + GAP_PX : Math.max(0, Math.min(p - GAP_PX - size, room - size)));
  return { left: place(x, width, viewWidth), top: place(y, height, viewHeight) };
}
