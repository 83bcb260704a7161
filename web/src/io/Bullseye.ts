/**
 * The LV wall's AHA segments under its figures in the Export panel: the bullseye the core drew
 * (the same SVG as `heartmesh myocardium --bullseye`), a caption saying where the septum was placed
 * from, and Bullseye SVG and Segments CSV to save them; or, when the core could place no segments
 * (an LV-only file says nothing of where the septum is), its reason as a muted line. The wall row
 * (WallRow.ts) shows and clears it together with the figures line, so the bullseye is never of
 * other meshes or settings than the figures above it.
 */
import type { WallSummary } from '../core-client/protocol';
import { BullseyeFigure } from './BullseyeFigure';
import { download } from './download';
import type { ExportInfo } from './export/header';
import { bullseyeFileName, noSegmentsText, segmentsCaption, segmentsCsvFileName, segmentsTitle, writeSegmentsCsv } from './export/segments';
import type { WallDetails } from './WallRow';

export class BullseyeView implements WallDetails {
  readonly element: HTMLElement;
  /** The bullseye, its caption and buttons, or why there are no segments. */
  private readonly figure: BullseyeFigure;
  /** The wall whose segments are shown (null: none). */
  private summary: WallSummary | null = null;

  /** `info`: the run the wall was built of (the files' names and the CSV's header). */
  constructor(private readonly info: () => ExportInfo | null) {
    this.figure = new BullseyeFigure({
      idPrefix: 'wall-bullseye',
      classes: { wrapper: 'wall-segments', note: 'wall-segments-note' },
      testids: { wrapper: 'wall-segments', figure: 'wall-bullseye', drawing: 'wall-bullseye-svg', caption: 'wall-bullseye-caption', note: 'wall-segments-note' },
      drawnState: 'segments',
      buttons: [
        { label: 'Bullseye SVG', testid: 'export-wall-bullseye', title: 'The bullseye as drawn here (SVG, the command line\'s --bullseye drawing)', onClick: () => this.saveSvg() },
        { label: 'Segments CSV', testid: 'export-wall-segments', title: 'One row per AHA segment: mean, min and max wall thickness (mm) and wall area (mm²), under the wall\'s settings', onClick: () => this.saveCsv() },
      ],
    });
    this.element = this.figure.element;
  }

  show(summary: WallSummary): void {
    const segments = summary.segments;
    if (!segments) {
      // A summary without the field at all (an older core) has nothing to say either way.
      if (summary.segments === undefined) return this.clear();
      this.summary = null;
      this.figure.showNote(noSegmentsText(summary.segments_note));
      return;
    }
    this.summary = summary;
    this.figure.showDrawing(summary.bullseye_svg, segmentsCaption(segments), segmentsTitle(segments));
  }

  clear(): void {
    this.summary = null;
    this.figure.clear();
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
