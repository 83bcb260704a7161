/**
 * The Contours panel as CSV: one row per contour with its state and its mean, median and max
 * distance to the mesh, the table a researcher keeps for quality control (which contour the mesh
 * misses, which were left out and how far the others predict them). The rows come in the order
 * the panel shows them (its sort), so the file reads as the table did; the `#` header is every
 * export's, so the figures stay tied to the run and its parameters.
 */
import type { ContourRow } from '../../ui/contourRows';
import { csvField } from './csvField';
import { exportBaseName, headerLines, type ExportInfo } from './header';

/**
 * The columns, named as the CLI report's figures are (mm in the name: the file has no other place
 * for units); the last three count the points the core left out of a contour used as damaged values
 * (0 for none): `spike_points` out of the curve and straight back (the report's `per_contour`
 * `spikes.points`), `far_points` far from the rest of the surface (`far.points`) and
 * `off_plane_points` off the plane of the rest of the contour (`off_plane.points`).
 */
export const CONTOUR_CSV_COLUMNS = 'contour,kind,state,line,points,mean_mm,median_mm,max_mm,spike_points,far_points,off_plane_points';

/**
 * A distance to 4 decimals (as the Distances CSV); empty when there is no figure (a spreadsheet
 * reads that as missing, not 0). Shared with the other tables' CSVs (the AHA segments').
 */
export function mm4(v: number | null): string {
  return v !== null && Number.isFinite(v) ? v.toFixed(4) : '';
}

function contourLine(row: ContourRow): string {
  return [csvField(row.id), row.kind ?? '', row.state, row.line ?? '', row.count, mm4(row.meanMm), mm4(row.medianMm), mm4(row.maxMm), row.spikes, row.far, row.offPlane].join(',');
}

/** The CSV of `rows`, in their order, under the header lines of the run they come from (`info`). */
export function writeContourCsv(rows: readonly ContourRow[], info: ExportInfo): string {
  return [...headerLines(info).map((l) => `# ${l}`), CONTOUR_CSV_COLUMNS, ...rows.map(contourLine), ''].join('\n');
}

/** `patient1-ED-LV_ENDO-contours.csv`: named as the other exports of the run (with its frame when the file has several). */
export function contourCsvFileName(info: ExportInfo): string {
  return `${exportBaseName(info)}-contours.csv`;
}
