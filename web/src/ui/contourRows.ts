/**
 * The rows of the Contours panel from a finished run: one per contour the run used (its
 * `perContour` stats, in the core's order) and one per contour it left out (`set_aside`: the core's
 * strays and specks, and those the user left out, with how far the mesh built without them
 * passes), each where the file has it among the others so that a row unticked stays in its place
 * after the run; and their order when the user sorts a column. Pure (no DOM), so the figures, the
 * words and the orders are unit-tested.
 */
import type { ContourInfo, ContourKindName, RunResult, SetAsideReason } from '../core-client/protocol';
import { robustMax } from '../viewer/colormap';
import { farDetail, farNote, isFigure, LEFT_OUT_BY_USER, leftOutDetail, leftOutLabel, offPlaneDetail, offPlaneNote, spikeDetail, spikeNote } from './runText';

/** `used`: in the reconstruction; otherwise why it is not (the core's reasons, `by_user` the user's). */
export type ContourRowState = 'used' | SetAsideReason;

export interface ContourRow {
  id: string;
  kind: ContourKindName | null;
  state: ContourRowState;
  /** Contour points (of a contour left out: its points as the file gives them). */
  count: number;
  /**
   * Contour-to-mesh distance of its points, mm; of a contour left out, to the mesh built without it
   * (a held-out figure). Null: no figure (a result of an older core, or not finite).
   */
  meanMm: number | null;
  /** The median of the same distances (the Contours CSV: a mean pulled up by a few points far off shows against it). */
  medianMm: number | null;
  maxMm: number | null;
  /** The file line of a contour left out, as the core gives it (null: used, or not from a file). */
  line: number | null;
  /** "left out: speck", "left out by you" (null: used). */
  reason: string | null;
  /** A used contour's points left out as damaged values: "1 point left out: spike", "... far off", "... off its plane" (null: none). */
  note: string | null;
  /** Points left out as spikes (0: none). */
  spikes: number;
  /** Points left out as far from the rest of the surface (0: none). */
  far: number;
  /** Points left out as off the plane of the rest of the contour (0: none). */
  offPlane: number;
  /** Tooltip: of a row left out, its line and why (leftOutDetail); of a row with damaged values, them (spikeDetail, farDetail, offPlaneDetail). */
  detail: string | null;
}

/** The texts present, joined by `sep`; null when none is (a row without a note). */
function joined(texts: readonly (string | undefined)[], sep: string): string | null {
  const present = texts.filter((t): t is string => typeof t === 'string');
  return present.length > 0 ? present.join(sep) : null;
}

/** Points of a contour as its pieces index them. */
function pointCount(c: ContourInfo | undefined): number {
  return c ? c.pieces.reduce((n, p) => n + p.count, 0) : 0;
}

/** A contour of the surface as the file holds it: its id and the core's SAX/LAX split at load. */
export interface FileContour {
  id: string;
  kind: ContourKindName | null;
}

/**
 * The rows for `r`. `file` (the surface's contours as the file holds them, the ones left out among
 * them) places every row and gives a contour left out its kind when the run does not; without it,
 * or for an id it lacks, a left-out row follows the used ones in the core's order.
 */
export function contourRows(r: RunResult, file: readonly FileContour[] = []): ContourRow[] {
  const used: ContourRow[] = r.perContour.map((c) => ({
    id: c.id,
    kind: c.kind,
    state: 'used',
    count: c.stats.count,
    meanMm: c.stats.mean,
    medianMm: c.stats.median,
    maxMm: c.stats.max,
    line: null,
    reason: null,
    note: joined([c.spikes && spikeNote(c.spikes), c.far && farNote(c.far), c.off_plane && offPlaneNote(c.off_plane)], ' · '),
    spikes: c.spikes?.points ?? 0,
    far: c.far?.points ?? 0,
    offPlane: c.off_plane?.points ?? 0,
    detail: joined(
      [c.spikes && spikeDetail(c.id, c.spikes), c.far && farDetail(c.id, c.far), c.off_plane && offPlaneDetail(c.id, c.off_plane)],
      '\n',
    ),
  }));
  const asideContours = r.set_aside_contours ?? [];
  const taken = new Set<number>();
  const aside: ContourRow[] = (r.set_aside ?? []).map((e) => {
    // One geometry per entry, in order (as SetAsideLayer pairs them): the first of its id not yet taken.
    const i = asideContours.findIndex((c, k) => !taken.has(k) && c.id === e.id);
    if (i >= 0) taken.add(i);
    const contour = i >= 0 ? asideContours[i] : undefined;
    const kind = contour?.kind ?? file.find((c) => c.id === e.id)?.kind ?? null;
    const figure = (v: number | null | undefined) => (isFigure(v) ? v : null);
    return {
      id: e.id,
      kind,
      state: e.reason,
      count: pointCount(contour),
      meanMm: figure(e.mean),
      medianMm: figure(e.median),
      maxMm: figure(e.max),
      line: e.line > 0 ? e.line : null,
      reason: leftOutLabel(e.reason),
      note: null,
      spikes: 0,
      far: 0,
      offPlane: 0,
      detail: leftOutDetail(e),
    };
  });
  const rows = [...used, ...aside];
  const at = new Map<string, number>();
  file.forEach((c, i) => {
    if (!at.has(c.id)) at.set(c.id, i);
  });
  // Stable: rows the file does not place keep their order after those it does.
  return rows
    .map((row, i) => ({ row, i, f: at.get(row.id) ?? Number.POSITIVE_INFINITY }))
    .sort((a, b) => (a.f === b.f ? a.i - b.i : a.f - b.f))
    .map((x) => x.row);
}

/** The top of the contour colour scale for `r`: the contour legend's (runDisplay.finished), so a row's swatch matches the points. */
export function contourScaleMax(r: RunResult): number {
  return robustMax(r.pointDistances);
}

/** The columns the user can sort the rows by. */
export type SortColumn = 'id' | 'kind' | 'count' | 'mean' | 'max';

/** A column sorted, and which way (no sort: the file's order). */
export interface RowSort {
  column: SortColumn;
  descending: boolean;
}

/** Columns of figures sort largest first (the contour the mesh misses on top), text A to Z. */
export function sortsDescendingFirst(column: SortColumn): boolean {
  return column === 'count' || column === 'mean' || column === 'max';
}

/**
 * The sort after a click on `column`'s header: a first click sorts it (figures largest first, text
 * A to Z), a second reverses, a third goes back to the file's order (null). The header's title
 * says so (ContourTable).
 */
export function nextSort(current: RowSort | null, column: SortColumn): RowSort | null {
  const first = sortsDescendingFirst(column);
  if (current?.column !== column) return { column, descending: first };
  return current.descending === first ? { column, descending: !first } : null;
}

/** A row's value in `column` (null: none, sorted last either way). */
function sortValue(row: ContourRow, column: SortColumn): number | string | null {
  if (column === 'id') return row.id;
  if (column === 'kind') return row.kind;
  if (column === 'count') return row.count;
  return column === 'mean' ? row.meanMm : row.maxMm;
}

/**
 * `rows` in the order of `sort` (null: as given, the file's order). Rows without a value go last
 * in both directions, ties keep their order; ids compare their digits as numbers (s2 before s10).
 */
export function sortRows(rows: readonly ContourRow[], sort: RowSort | null): ContourRow[] {
  if (!sort) return [...rows];
  const sign = sort.descending ? -1 : 1;
  return rows
    .map((row) => ({ row, v: sortValue(row, sort.column) }))
    .sort((a, b) => {
      if (a.v === null || b.v === null) return a.v === b.v ? 0 : a.v === null ? 1 : -1;
      const d = typeof a.v === 'number' && typeof b.v === 'number' ? a.v - b.v : String(a.v).localeCompare(String(b.v), 'en', { numeric: true });
      return sign * d;
    })
    .map((x) => x.row);
}

/** "0.84" (two decimals, mm implied by the column), "–" when there is no figure. */
export function mm2(v: number | null): string {
  return v === null || !Number.isFinite(v) ? '–' : v.toFixed(2);
}

/** Why a core's left-out row cannot be ticked, and what uses it. */
export const CORE_LEFT_OUT_TITLE = 'left out by the core (a speck or a stray): the option Keep specks and strays (Parameters) uses it';

/** The checkbox's tooltip for a row in `state`, `on` when the next run uses it. */
export function useTitle(state: ContourRowState, on: boolean): string {
  if (state !== 'used' && state !== 'by_user') return CORE_LEFT_OUT_TITLE;
  return on ? 'used by the reconstruction: untick to leave this contour out and run again' : `${LEFT_OUT_BY_USER}: tick to use it again (runs again)`;
}
