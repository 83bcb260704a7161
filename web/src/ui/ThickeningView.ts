/**
 * The LV wall's systolic thickening under the Function panel's table: the bullseye the core drew
 * of it (the same SVG as `heartmesh volumes --thickening-plot`), a one-line caption with the
 * phases and the mean, and Thickening SVG and Thickening CSV to save them; or, when the core
 * measured none (no RV to place the septum by, a biventricular epicardium), its reason as a muted
 * line; nothing at all when the phases have no LV_EPI. The panel hands it each render's summary,
 * so it is of the same measurement as the table: it goes when the table's measurement is replaced
 * and is greyed with the table when that is stale (bullseye.css).
 */
import type { FunctionSummary } from '../core-client/protocol';
import { BullseyeFigure } from '../io/BullseyeFigure';
import { download } from '../io/download';
import {
  noThickeningText, thickeningCaption, thickeningCsvFileName, thickeningHeaderLines, thickeningSvgFileName, thickeningTitle, writeThickeningCsv,
  type ThickeningProvenance,
} from '../io/export/thickening';

export class ThickeningView {
  readonly element: HTMLElement;
  /** The bullseye, its caption and buttons, or why there is no thickening. */
  private readonly figure: BullseyeFigure;
  /** The summary shown (null: none): the same one again is not imported again. */
  private summary: FunctionSummary | null = null;

  /** `provenance`: what the shown summary's measurement was made of (the files' names, the CSV's header). */
  constructor(private readonly provenance: () => ThickeningProvenance | null) {
    this.figure = new BullseyeFigure({
      // Apart from the wall bullseye's `wall-bullseye`.
      idPrefix: 'function-thickening',
      classes: { wrapper: 'function-thickening', note: 'function-thickening-note' },
      testids: {
        wrapper: 'function-thickening', figure: 'function-thickening-bullseye', drawing: 'function-thickening-svg', caption: 'function-thickening-caption',
        note: 'function-thickening-note',
      },
      drawnState: 'bullseye',
      buttons: [
        { label: 'Thickening SVG', testid: 'function-thickening-save-svg', title: 'The thickening bullseye as drawn here (SVG, the command line\'s volumes --thickening-plot drawing)', onClick: () => this.saveSvg() },
        { label: 'Thickening CSV', testid: 'function-thickening-save-csv', title: 'One row per AHA segment: the mean wall thickness at ED and at ES (mm) and the thickening (%), under the measurement\'s settings', onClick: () => this.saveCsv() },
      ],
    });
    this.element = this.figure.element;
  }

  /** Shows `summary`'s thickening, or its note; clears for a summary without one (or none). */
  show(summary: FunctionSummary | null): void {
    if (summary === this.summary) return;
    // No LV_EPI (the key absent), or no summary yet: nothing to say either way.
    if (!summary || summary.wall_thickening === undefined) return this.clear();
    this.summary = summary;
    const t = summary.wall_thickening;
    if (t === null) return this.figure.showNote(noThickeningText(summary.wall_thickening_note));
    this.figure.showDrawing(summary.thickening_svg, thickeningCaption(t), thickeningTitle(t));
  }

  clear(): void {
    this.summary = null;
    this.figure.clear();
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
