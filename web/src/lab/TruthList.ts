/**
 * The Lab's list of truth meshes: one row per dropped or opened surface with its tint (as drawn
 * in 3D), its file name, its surface label (a text field suggesting the known names, since any
 * label the CLI takes is allowed) and a remove button. The panel owns the truths and checks the
 * labels; this only draws the rows and reports edits.
 */
import { h } from '../ui/dom';
import { KNOWN_LABELS } from './truthLabels';
import { TRUTH_TINTS } from './TruthLayer';

export interface TruthRow {
  name: string;
  label: string | null;
  vertices: number;
  volumeMl: number;
  closed: boolean;
  frame?: string | null;
  convertedFrom?: string | null;
}

/**
 * The patient frame a truth's file states, and the conversion the core made when it stated the
 * other frame than the first truth's (surfaces of one heart are sliced in one frame): '' when the
 * file states none.
 */
export function frameText(r: Pick<TruthRow, 'frame' | 'convertedFrom'>): string {
  if (!r.frame) return '';
  return r.convertedFrom ? `, ${r.frame} (its file in ${r.convertedFrom}: x and y negated)` : `, ${r.frame}`;
}

export interface TruthListEvents {
  /** The label field of row `index` was changed to `text` (untrimmed). */
  label(index: number, text: string): void;
  remove(index: number): void;
}

export class TruthList {
  readonly element: HTMLElement;
  private readonly list = h('ul', { class: 'lab-truths', 'data-testid': 'lab-truths' });

  constructor(private readonly events: TruthListEvents) {
    const names = h('datalist', { id: 'lab-label-names' }, ...KNOWN_LABELS.map((l) => h('option', { value: l })));
    this.element = h('div', { class: 'lab-truth-list' }, this.list, names);
    this.element.hidden = true;
  }

  /** Draws `rows` (hidden when `show` is false: the parametric LV has no file or label). */
  render(rows: readonly TruthRow[], show: boolean): void {
    this.element.hidden = !show || rows.length === 0;
    this.list.replaceChildren(...rows.map((r, i) => this.row(r, i, rows.length)));
  }

  private row(r: TruthRow, index: number, count: number): HTMLElement {
    const tint = TRUTH_TINTS[index % TRUTH_TINTS.length];
    const swatch = h('span', { class: 'lab-swatch', 'aria-hidden': 'true' });
    swatch.style.background = `rgb(${tint.join(', ')})`;
    const input = h('input', {
      type: 'text',
      class: 'lab-truth-label',
      list: 'lab-label-names',
      value: r.label ?? '',
      placeholder: count > 1 ? 'label?' : 'label',
      spellcheck: 'false',
      autocomplete: 'off',
      'aria-label': `surface label of ${r.name}`,
      title: 'Surface label (LV_ENDO, LV_EPI, RV_ENDO, RV_EPI, BIV_EPI or your own): the surface column of the simulated file',
      'data-testid': 'lab-truth-label',
    });
    input.value = r.label ?? '';
    input.classList.toggle('missing', count > 1 && r.label === null);
    input.addEventListener('change', () => this.events.label(index, input.value));
    const remove = h('button', { type: 'button', class: 'lab-truth-remove', title: `Remove ${r.name}`, 'aria-label': `remove ${r.name}`, 'data-testid': 'lab-truth-remove' }, '×');
    remove.addEventListener('click', () => this.events.remove(index));
    const meta = `${r.vertices} vertices, ${r.volumeMl.toFixed(1)} ml${r.closed ? '' : ' (open)'}${frameText(r)}`;
    return h(
      'li',
      { class: 'lab-truth', 'data-testid': 'lab-truth-row', 'data-label': r.label ?? '', ...(r.convertedFrom ? { 'data-converted-from': r.convertedFrom } : {}) },
      swatch,
      h('span', { class: 'lab-truth-name', title: `${r.name}: ${meta}` }, shortName(r.name)),
      input,
      remove,
    );
  }
}

/**
 * A file name cut in the middle to fit its row: mesh files of one heart share a long prefix
 * (`bivme-patient1-ED-`) and differ at the end (`LV_ENDO-closed.obj`), which an ellipsis at the end
 * would hide. The full name is the row's tooltip.
 */
export function shortName(name: string, max = 24): string {
  if (name.length <= max) return name;
  const tail = Math.ceil((max - 1) * 0.75);
  return `${name.slice(0, max - 1 - tail)}…${name.slice(name.length - tail)}`;
}
