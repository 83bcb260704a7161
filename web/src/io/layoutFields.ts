/**
 * The anatomical layout's form pieces, shared by the rows that ask the core for layouts (the
 * Export panel's per-file "Anatomical mesh" row, the Function panel's study-wide "Anatomical
 * meshes" row): the two whole-number fields (rings from the apex to the base x points per ring,
 * checked by `checkLayout` before any call) and the format select. Kept in one place so both rows
 * read, validate and look alike (styles.css: `.anatomical-layout`, `.anatomical-number`).
 */
import { ANATOMICAL_FORMATS, type AnatomicalFormat } from '../core-client/protocol';
import { h } from '../ui/dom';
import { ANATOMICAL_DEFAULT, ANATOMICAL_POINTS, ANATOMICAL_RINGS, anatomicalFormatTitle, checkLayout, type LayoutCheck } from './export/anatomical';

export class LayoutFields {
  readonly rings: HTMLInputElement;
  readonly points: HTMLInputElement;
  /** The two fields with the × between them. */
  readonly element: HTMLElement;

  /** `testids`: the two fields' `data-testid`; `onInput`: called whenever either changes. */
  constructor(testids: { rings: string; points: string }, onInput: () => void) {
    const number = (testid: string, label: string, value: number, range: { min: number; max: number }) => {
      const input = h('input', { type: 'number', class: 'anatomical-number', 'data-testid': testid, min: range.min, max: range.max, step: 1, value, 'aria-label': label, title: `${label}: ${range.min}-${range.max}` });
      // Set as a property too: what the row reads back (`value`) is the property, not the attribute.
      input.value = String(value);
      input.addEventListener('input', onInput);
      return input;
    };
    this.rings = number(testids.rings, 'Rings from the apex to the base', ANATOMICAL_DEFAULT.rings, ANATOMICAL_RINGS);
    this.points = number(testids.points, 'Points per ring', ANATOMICAL_DEFAULT.points, ANATOMICAL_POINTS);
    this.element = h('span', { class: 'anatomical-layout' }, this.rings, h('span', { class: 'anatomical-times', 'aria-hidden': 'true' }, '×'), this.points);
  }

  /** The layout typed, or what is wrong with it (whole numbers in the core's ranges). */
  check(): LayoutCheck {
    return checkLayout(this.rings.value, this.points.value);
  }

  set disabled(v: boolean) {
    this.rings.disabled = this.points.disabled = v;
  }
}

/** The formats a layout is written in, the first (VTK) chosen. */
export function formatSelect(testid: string, label: string, onChange: () => void): HTMLSelectElement {
  const select = h('select', { class: 'small', 'data-testid': testid, 'aria-label': label });
  for (const f of ANATOMICAL_FORMATS) select.append(h('option', { value: f, title: anatomicalFormatTitle(f) }, f.toUpperCase()));
  select.value = ANATOMICAL_FORMATS[0];
  select.addEventListener('change', onChange);
  return select;
}

/** The format chosen in a `formatSelect`. */
export function formatOf(select: HTMLSelectElement): AnatomicalFormat {
  return select.value as AnatomicalFormat;
}
