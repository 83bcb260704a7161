/**
 * The rows of the Contours panel from a finished run: one per contour the run used (its
 * `perContour` stats, in the core's order) and one per contour it left out (`set_aside`: the core's
 * strays and specks, and those the user left out), each where the file has it among the others so
 * that a row unticked stays in its place after the run. Pure (no DOM), so the figures and the words
 * are unit-tested.
 */
import type { ContourInfo, ContourKindName, RunResult, SetAsideReason } from '../core-client/protocol';
import { robustMax } from '../viewer/colormap';
import { LEFT_OUT_BY_USER, leftOutDetail, leftOutLabel } from './runText';

/** `used`: in the reconstruction; otherwise why it is not (the core's reasons, `by_user` the user's). */
export type ContourRowState = 'used' | SetAsideReason;

export interface ContourRow {
  id: string;
  kind: ContourKindName | null;
  state: ContourRowState;
  /** Contour points (of a contour left out: its points as the file gives them). */
  count: number;
  /** Contour-to-mesh distance of its points, mm (null: left out, the mesh does not follow it). */
  meanMm: number | null;
  maxMm: number | null;
  /** "left out: speck", "left out by you" (null: used). */
  reason: string | null;
  /** Tooltip of a row left out: its line and why (leftOutDetail). */
  detail: string | null;
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
    maxMm: c.stats.max,
    reason: null,
    detail: null,
  }));
  const asideContours = r.set_aside_contours ?? [];
  const taken = new Set<number>();
  const aside: ContourRow[] = (r.set_aside ?? []).map((e) => {
    // One geometry per entry, in order (as SetAsideLayer pairs them): the first of its id not yet taken.
    const i = asideContours.findIndex((c, k) => !taken.has(k) && c.id === e.id);
    if (i >= 0) taken.add(i);
    const contour = i >= 0 ? asideContours[i] : undefined;
    const kind = contour?.kind ?? file.find((c) => c.id === e.id)?.kind ?? null;
    return { id: e.id, kind, state: e.reason, count: pointCount(contour), meanMm: null, maxMm: null, reason: leftOutLabel(e.reason), detail: leftOutDetail(e) };
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
