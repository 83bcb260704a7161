/**
 * The LV wall's thickness by the 17 AHA segments (the command line's `heartmesh myocardium
 * --report`'s `segments`, `--bullseye`'s drawing): what the Export panel says under the wall's
 * figures, the names of the two files it saves, and the Segments CSV. The CSV carries the wall
 * file's `#` header (the input, the settings, the minimum thickness) and a line on how the
 * segments were placed, so the regional figures stay tied to the solid they were measured on.
 * Pure functions: Bullseye.ts (the panel's part) only wires them.
 */
import type { WallSegments, WallSummary } from '../../core-client/protocol';
import { mm4 } from './contourCsv';
import { csvField } from './csvField';
import { exportBaseName, type ExportInfo } from './header';
import { wallHeaderLines } from './wall';

/** The columns, named as the CLI report's segment fields are. */
export const SEGMENTS_CSV_COLUMNS = 'segment,name,mean_mm,min_mm,max_mm,area_mm2';

/** The wall files' base name (`patient1-ED-LV_wall`, its frame after it): the segments belong to that solid. */
function wallBase(info: ExportInfo): string {
  return exportBaseName({ ...info, surface: 'LV_wall' });
}

/** `patient1-ED-LV_wall-segments.svg`: the core's bullseye, saved as it drew it. */
export function bullseyeFileName(info: ExportInfo): string {
  return `${wallBase(info)}-segments.svg`;
}

/** `patient1-ED-LV_wall-segments.csv`. */
export function segmentsCsvFileName(info: ExportInfo): string {
  return `${wallBase(info)}-segments.csv`;
}

/** The level borders' depths below the base, `0.0, 25.9, ... mm`. */
function depths(s: WallSegments): string {
  return `${s.level_depths_mm.map((d) => d.toFixed(1)).join(', ')} mm`;
}

/** How the segments were placed, one header line: where the septum came from, the levels' depths. */
export function segmentsHeaderLine(s: WallSegments): string {
  return `segments: AHA 17, septum from ${s.septum_from}; level borders ${depths(s)} below the base`;
}

/**
 * The CSV of `summary`'s segments (null when it has none), one row per segment in the AHA order,
 * under the wall file's header lines as the app writes them (`info`: the run the wall was built of).
 */
export function writeSegmentsCsv(summary: WallSummary, info: ExportInfo): string | null {
  const s = summary.segments;
  if (!s) return null;
  const header = [
    ...wallHeaderLines(info, summary.surfaces.endo, summary.surfaces.epi, summary.endocardium_moved.min_thickness_mm),
    segmentsHeaderLine(s),
  ];
  const rows = s.segments.map((g) =>
    [g.id, csvField(g.name), mm4(g.mean_mm), mm4(g.min_mm), mm4(g.max_mm), Number.isFinite(g.area_mm2) ? g.area_mm2.toFixed(2) : ''].join(','),
  );
  return commentedCsv(header, SEGMENTS_CSV_COLUMNS, rows);
}

/**
 * A CSV of segments: `header`'s lines as `#` comments (each kept to one line), the column names,
 * the rows, a final newline. Shared with the Function panel's Thickening CSV (thickening.ts), so
 * the two segment tables read alike.
 */
export function commentedCsv(header: readonly string[], columns: string, rows: readonly string[]): string {
  return [...header.map((l) => `# ${l.replace(/[\r\n]+/g, ' ')}`), columns, ...rows, ''].join('\n');
}

/**
 * The core's septum source with its count of points spelled out: "the RV contours' centre (934)"
 * is "the RV contours' centre (934 points)".
 */
export function septumSourceText(from: string): string {
  return from.replace(/\((\d+)\)$/, (_, n: string) => `(${n} ${n === '1' ? 'point' : 'points'})`);
}

/**
 * The line under the bullseye: where the septum was placed from (the drawing's own title says
 * what it shows), the core's count of points spelled out: "the RV contours' centre (934 points)".
 */
export function segmentsCaption(s: WallSegments): string {
  return `Septum placed from ${septumSourceText(s.septum_from)}`;
}

/** The caption's tooltip: the orientation and the levels, as the SVG's footer gives them. */
export function segmentsTitle(s: WallSegments): string {
  return [
    'The AHA 17-segment bullseye: anterior up, septum left, apex in the middle (hover a segment for its name)',
    `levels: thirds of the cavity below the base; borders at ${depths(s)}`,
    'Bullseye SVG saves this drawing; Segments CSV each segment\'s mean, min and max thickness and its area',
  ].join('\n');
}

/** Said instead of the bullseye when the core placed no segments (`note`: its reason). */
export function noSegmentsText(note: string | undefined): string {
  return note ? `No AHA segments: ${note}` : 'No AHA segments for this wall';
}
