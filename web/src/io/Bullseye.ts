/**
 * The LV wall's AHA segments under its figures in the Export panel: the bullseye the core drew
 * (the same SVG as `heartmesh myocardium --bullseye`), a caption saying where the septum was placed
 * from, and Bullseye SVG and Segments CSV to save them; or, when the core could place no segments
 * (an LV-only file says nothing of where the septum is), its reason as a muted line. The wall row
 * (WallRow.ts) shows and clears it together with the figures line, so the bullseye is never of
 * other meshes or settings than the figures above it.
 */
import type { WallSummary } from '../core-client/protocol';
import { h } from '../ui/dom';
import { download } from './download';
import type { ExportInfo } from './export/header';
import { bullseyeFileName, noSegmentsText, segmentsCaption, segmentsCsvFileName, segmentsTitle, writeSegmentsCsv } from './export/segments';
import { importSvg } from './svgImport';
import type { WallDetails } from './WallRow';
import './bullseye.css';

/** The prefix of the bullseye's ids on the page (its colour scale's gradient). */
const ID_PREFIX = 'wall-bullseye';

export class BullseyeView implements WallDetails {
  readonly element: HTMLElement;
  /** The bullseye and its caption. */
  private readonly figure: HTMLElement;
  private readonly drawing: HTMLElement;
  private readonly caption: HTMLElement;
  private readonly buttons: HTMLElement;
  /** Why there are no segments. */
  private readonly note: HTMLElement;
  /** The wall whose segments are shown (null: none). */
  private summary: WallSummary | null = null;

  /** `info`: the run the wall was built of (the files' names and the CSV's header). */
  constructor(private readonly info: () => ExportInfo | null) {
    const button = (label: string, testid: string, title: string, fn: () => void) => {
      const b = h('button', { type: 'button', class: 'small', 'data-testid': testid, title }, label);
      b.addEventListener('click', fn);
      return b;
    };
    this.drawing = h('div', { class: 'bullseye-drawing', 'data-testid': 'wall-bullseye-svg' });
    this.caption = h('figcaption', { class: 'bullseye-caption', 'data-testid': 'wall-bullseye-caption' });
    this.figure = h('figure', { class: 'bullseye', 'data-testid': 'wall-bullseye' }, this.drawing, this.caption);
    this.buttons = h(
      'div',
      { class: 'bullseye-buttons' },
      button('Bullseye SVG', 'export-wall-bullseye', 'The bullseye as drawn here (SVG, the command line\'s --bullseye drawing)', () => this.saveSvg()),
      button('Segments CSV', 'export-wall-segments', 'One row per AHA segment: mean, min and max wall thickness (mm) and wall area (mm²), under the wall\'s settings', () => this.saveCsv()),
    );
    this.note = h('p', { class: 'wall-segments-note', 'data-testid': 'wall-segments-note' });
    this.element = h('div', { class: 'wall-segments', 'data-testid': 'wall-segments', hidden: true }, this.figure, this.buttons, this.note);
  }

  show(summary: WallSummary): void {
    const segments = summary.segments;
    if (!segments) {
      // A summary without the field at all (an older core) has nothing to say either way.
      if (summary.segments === undefined) return this.clear();
      this.summary = null;
      this.showOnly('note', noSegmentsText(summary.segments_note));
      return;
    }
    const svg = summary.bullseye_svg ? importSvg(summary.bullseye_svg, ID_PREFIX) : null;
    this.summary = summary;
    this.element.hidden = false;
    this.element.dataset.state = 'segments';
    this.drawing.replaceChildren(...(svg ? [svg] : []));
    this.drawing.hidden = svg === null;
    this.caption.textContent = svg ? segmentsCaption(segments) : `${segmentsCaption(segments)} (the bullseye could not be drawn here; Bullseye SVG saves it)`;
    this.figure.title = segmentsTitle(segments);
    this.figure.hidden = false;
    this.buttons.hidden = false;
    this.note.hidden = true;
    this.note.textContent = '';
  }

  clear(): void {
    this.summary = null;
    this.element.hidden = true;
    delete this.element.dataset.state;
    this.drawing.replaceChildren();
    this.caption.textContent = '';
    this.note.textContent = '';
  }

  /** Shows the note alone (`state` note). */
  private showOnly(state: 'note', text: string): void {
    this.element.hidden = false;
    this.element.dataset.state = state;
    this.drawing.replaceChildren();
    this.caption.textContent = '';
    this.figure.hidden = true;
    this.buttons.hidden = true;
    this.note.hidden = false;
    this.note.textContent = text;
  }

  /** The core's SVG text as it is (what the command line's --bullseye writes but for the title line). */
  private saveSvg(): void {
    const info = this.info();
    const svg = this.summary?.bullseye_svg;
    if (!info || !svg) return;
    download(svg, bullseyeFileName(info), 'image/svg+xml');
  }

  private saveCsv(): void {
    const info = this.info();
    const csv = this.summary && info ? writeSegmentsCsv(this.summary, info) : null;
    if (info && csv !== null) download(csv, segmentsCsvFileName(info), 'text/csv');
  }
}
