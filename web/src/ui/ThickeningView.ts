/**
 * The LV wall's systolic thickening under the Function panel's table: the bullseye the core drew
 * of it (the same SVG as `heartmesh volumes --thickening-plot`), a one-line caption with the
 * phases and the mean, and Thickening SVG and Thickening CSV to save them; or, when the core
 * measured none (no RV to place the septum by, a biventricular epicardium), its reason as a muted
 * line; nothing at all when the phases have no LV_EPI. The panel hands it each render's summary,
 * so it is of the same measurement as the table: it goes when the table's measurement is replaced
 * and is greyed with the table when that is stale (bullseye.css).
 */
import type { FunctionSummary, WallThickening } from '../core-client/protocol';
import { download } from '../io/download';
import {
  noThickeningText, thickeningCaption, thickeningCsvFileName, thickeningHeaderLines, thickeningSvgFileName, thickeningTitle, writeThickeningCsv,
  type ThickeningProvenance,
} from '../io/export/thickening';
import { importSvg } from '../io/svgImport';
import { h } from './dom';
import '../io/bullseye.css';

/** The prefix of the bullseye's ids on the page: apart from the wall bullseye's `wall-bullseye`. */
const ID_PREFIX = 'function-thickening';

export class ThickeningView {
  readonly element: HTMLElement;
  private readonly figure: HTMLElement;
  private readonly drawing: HTMLElement;
  private readonly caption: HTMLElement;
  private readonly buttons: HTMLElement;
  /** Why there is no thickening. */
  private readonly note: HTMLElement;
  /** The summary shown (null: none): the same one again is not imported again. */
  private summary: FunctionSummary | null = null;

  /** `provenance`: what the shown summary's measurement was made of (the files' names, the CSV's header). */
  constructor(private readonly provenance: () => ThickeningProvenance | null) {
    const button = (label: string, testid: string, title: string, fn: () => void) => {
      const b = h('button', { type: 'button', class: 'small', 'data-testid': testid, title }, label);
      b.addEventListener('click', fn);
      return b;
    };
    this.drawing = h('div', { class: 'bullseye-drawing', 'data-testid': 'function-thickening-svg' });
    this.caption = h('figcaption', { class: 'bullseye-caption', 'data-testid': 'function-thickening-caption' });
    this.figure = h('figure', { class: 'bullseye', 'data-testid': 'function-thickening-bullseye' }, this.drawing, this.caption);
    this.buttons = h(
      'div',
      { class: 'bullseye-buttons' },
      button('Thickening SVG', 'function-thickening-save-svg', 'The thickening bullseye as drawn here (SVG, the command line\'s volumes --thickening-plot drawing)', () => this.saveSvg()),
      button('Thickening CSV', 'function-thickening-save-csv', 'One row per AHA segment: the mean wall thickness at ED and at ES (mm) and the thickening (%), under the measurement\'s settings', () => this.saveCsv()),
    );
    this.note = h('p', { class: 'function-thickening-note', 'data-testid': 'function-thickening-note' });
    this.element = h('div', { class: 'function-thickening', 'data-testid': 'function-thickening', hidden: true }, this.figure, this.buttons, this.note);
  }

  /** Shows `summary`'s thickening, or its note; clears for a summary without one (or none). */
  show(summary: FunctionSummary | null): void {
    if (summary === this.summary) return;
    // No LV_EPI (the key absent), or no summary yet: nothing to say either way.
    if (!summary || summary.wall_thickening === undefined) return this.clear();
    this.summary = summary;
    const t = summary.wall_thickening;
    if (t === null) return this.showNote(noThickeningText(summary.wall_thickening_note));
    this.showBullseye(t, summary.thickening_svg);
  }

  clear(): void {
    this.summary = null;
    this.element.hidden = true;
    delete this.element.dataset.state;
    this.drawing.replaceChildren();
    this.caption.textContent = '';
    this.note.textContent = '';
  }

  private showBullseye(t: WallThickening, svgText: string | undefined): void {
    const svg = svgText ? importSvg(svgText, ID_PREFIX) : null;
    this.element.hidden = false;
    this.element.dataset.state = 'bullseye';
    this.drawing.replaceChildren(...(svg ? [svg] : []));
    this.drawing.hidden = svg === null;
    const caption = thickeningCaption(t);
    this.caption.textContent = svg ? caption : `${caption} (the bullseye could not be drawn here; Thickening SVG saves it)`;
    this.figure.title = thickeningTitle(t);
    this.figure.hidden = false;
    this.buttons.hidden = false;
    this.note.hidden = true;
    this.note.textContent = '';
  }

  private showNote(text: string): void {
    this.element.hidden = false;
    this.element.dataset.state = 'note';
    this.drawing.replaceChildren();
    this.caption.textContent = '';
    this.figure.hidden = true;
    this.buttons.hidden = true;
    this.note.hidden = false;
    this.note.textContent = text;
  }

  /** The core's SVG text as it is (what `volumes --thickening-plot` writes). */
  private saveSvg(): void {
    const p = this.provenance();
    const svg = this.summary?.thickening_svg;
    if (p && svg) download(svg, thickeningSvgFileName(p.plan), 'image/svg+xml');
  }

  private saveCsv(): void {
    const p = this.provenance();
    const t = this.summary?.wall_thickening;
    if (p && t) download(writeThickeningCsv(t, thickeningHeaderLines(t, p)), thickeningCsvFileName(p.plan), 'text/csv');
  }
}
