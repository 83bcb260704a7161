/**
 * Geometry of the Function panel's volume curve (no DOM, unit-tested): each cavity's volume over
 * the phases, in SVG user units with y growing downwards. A table of 20-50 frames hides the shape
 * of the cycle; a line per cavity shows it at a glance, with each ventricle's end-diastole and
 * end-systole (the summary's, so the curve and the words below the table always agree).
 */
import type { FunctionSummary } from '../core-client/protocol';
import { formatTick, roundAxis, type Tick } from '../lab/chartScale';

/** The chart's box: the right column's width (~260 px), scaled with it on a phone. */
export const CURVE_BOX = { width: 260, height: 130 };
/** Text size in user units (styles.css `.function-curve text`). */
const FONT = 8;
/**
 * A character's width at FONT, a little over the average of the app's sans-serif (digits and
 * capitals are ~0.55 em), so estimated labels are never narrower than drawn ones.
 */
const CHAR = FONT * 0.62;
/** A capital's height at FONT. */
const CAP = FONT * 0.75;
/** The radius of an ED or ES ring. */
export const RING = 4.5;
/** The least space between two labels. */
const GAP = 4;
/** How far the first and last phases sit inside the plot: their rings and labels stay in the box. */
const INSET = 6;
/** Fewer phases than this give no curve: two phases are a line the summary already says. */
const MIN_PHASES = 3;

/** One cavity's volumes (ml, null: none in that phase) and, for a ventricle, its ED and ES phases. */
export interface CurveSeries {
  surface: string;
  volumes: (number | null)[];
  ed: string | null;
  es: string | null;
}

export interface CurvePoint {
  phase: string;
  index: number;
  ml: number;
  x: number;
  y: number;
}

/** A ring on a ventricle's ED or ES point. */
export interface CurveMarker extends CurvePoint {
  kind: 'ED' | 'ES';
  surface: string;
}

/** An "ED" or "ES" beside its rings: one per phase and kind, however many ventricles share it. */
export interface MarkerLabel {
  kind: 'ED' | 'ES';
  x: number;
  /** Baseline. */
  y: number;
  surfaces: string[];
}

export interface CurveLine {
  surface: string;
  /** Runs of two or more consecutive phases with a volume; a phase without one breaks the line. */
  segments: CurvePoint[][];
  dots: CurvePoint[];
}

export interface XLabel {
  index: number;
  x: number;
  text: string;
  anchor: 'start' | 'middle' | 'end';
}

export interface CurveLayout {
  plot: { left: number; top: number; width: number; height: number };
  yTicks: Tick[];
  xLabels: XLabel[];
  lines: CurveLine[];
  markers: CurveMarker[];
  markerLabels: MarkerLabel[];
}

/** The surfaces the summary treats as cavities: those with a function, and those measured once. */
export function cavities(summary: FunctionSummary): string[] {
  return [...summary.ventricles.map((v) => v.surface), ...summary.single.map((s) => s.surface)];
}

/** The series of `surfaces` (cavities, in the order drawn), volumes by phase index from `volume`. */
export function cavitySeries(summary: FunctionSummary, surfaces: readonly string[], phaseCount: number, volume: (phase: number, surface: string) => number | null): CurveSeries[] {
  return surfaces.map((surface) => {
    const v = summary.ventricles.find((x) => x.surface === surface);
    const volumes = Array.from({ length: phaseCount }, (_, i) => {
      const ml = volume(i, surface);
      return ml !== null && Number.isFinite(ml) ? ml : null;
    });
    return { surface, volumes, ed: v?.ed_phase ?? null, es: v?.es_phase ?? null };
  });
}

/** The curve of `series` over `phases` in CURVE_BOX, or null when there is nothing worth a curve. */
export function curveLayout(phases: readonly string[], series: readonly CurveSeries[]): CurveLayout | null {
  const all = series.flatMap((s) => s.volumes).filter((v): v is number => v !== null);
  if (phases.length < MIN_PHASES || all.length === 0) return null;
  const axis = roundAxis(Math.max(...all));
  const labels = axis.ticks.map(formatTick);
  const left = Math.max(...labels.map((l) => l.length)) * CHAR + 6;
  // Room above for the unit and the ED labels, below for the phase labels.
  const plot = { left, top: 12, width: CURVE_BOX.width - left - 2, height: CURVE_BOX.height - 12 - 14 };
  const x = (i: number) => plot.left + INSET + ((plot.width - 2 * INSET) * i) / (phases.length - 1);
  const y = (ml: number) => plot.top + plot.height * (1 - ml / axis.max);
  const lines = series.map((s) => line(s, phases, x, y));
  const markers = series.flatMap((s, k) => markersOf(s, lines[k].dots));
  return {
    plot,
    yTicks: axis.ticks.map((value, k) => ({ value, pos: y(value), label: labels[k] })),
    xLabels: thinLabels(phases, x),
    lines,
    markers,
    markerLabels: labelMarkers(markers),
  };
}

function line(s: CurveSeries, phases: readonly string[], x: (i: number) => number, y: (ml: number) => number): CurveLine {
  const dots: CurvePoint[] = [];
  const runs: CurvePoint[][] = [[]];
  s.volumes.forEach((ml, index) => {
    if (ml === null) {
      runs.push([]);
      return;
    }
    const p = { phase: phases[index], index, ml, x: x(index), y: y(ml) };
    dots.push(p);
    runs[runs.length - 1].push(p);
  });
  return { surface: s.surface, segments: runs.filter((r) => r.length > 1), dots };
}

function markersOf(s: CurveSeries, dots: readonly CurvePoint[]): CurveMarker[] {
  const at = (kind: 'ED' | 'ES', phase: string | null): CurveMarker[] => {
    const dot = dots.find((d) => d.phase === phase);
    return dot ? [{ ...dot, kind, surface: s.surface }] : [];
  };
  return [...at('ED', s.ed), ...at('ES', s.es)];
}

interface Box {
  left: number;
  right: number;
  top: number;
  bottom: number;
}

const ringBox = (m: CurveMarker): Box => ({ left: m.x - RING, right: m.x + RING, top: m.y - RING, bottom: m.y + RING });
/** "ED" or "ES": two characters wide, a capital's height above the baseline. */
const labelBox = (l: MarkerLabel): Box => ({ left: l.x - CHAR, right: l.x + CHAR, top: l.y - CAP, bottom: l.y });
const meet = (a: Box, b: Box) => a.left < b.right && b.left < a.right && a.top < b.bottom && b.top < a.bottom;

/**
 * One label per phase and kind: ED just above its highest ring (the largest volume has nothing of
 * its line above it), ES just below its lowest; a label that would cover a ring or another label
 * moves on outwards, so two ventricles' EDs a frame apart stay legible.
 */
function labelMarkers(markers: readonly CurveMarker[]): MarkerLabel[] {
  const placed: MarkerLabel[] = [];
  for (const m of markers) {
    const same = placed.find((l) => l.kind === m.kind && l.x === m.x);
    const y = m.kind === 'ED' ? m.y - RING - 1 : m.y + RING + 1 + CAP;
    if (same) {
      same.surfaces.push(m.surface);
      same.y = m.kind === 'ED' ? Math.min(same.y, y) : Math.max(same.y, y);
    } else placed.push({ kind: m.kind, x: m.x, y, surfaces: [m.surface] });
  }
  const rings = markers.map(ringBox);
  placed.forEach((l, k) => {
    const taken = [...rings, ...placed.slice(0, k).map(labelBox)];
    while (taken.some((b) => meet(labelBox(l), b))) l.y += l.kind === 'ED' ? -(CAP + 1) : CAP + 1;
  });
  return placed;
}

/**
 * The phase labels shown along x: the first (from the axis, rightwards) and the last (ending at
 * the right edge) always, between them every k-th for the smallest round k (1, 2, 5, 10, ...)
 * whose labels leave GAP between each other at this width. Labels longer than half the width lose
 * their start, so that the first and the last always fit side by side.
 */
export function thinLabels(phases: readonly string[], x: (i: number) => number): XLabel[] {
  const n = phases.length;
  const room = Math.floor((x(n - 1) - x(0) - GAP) / 2 / CHAR);
  const label = (index: number): XLabel => ({ index, x: x(index), text: shorten(phases[index], room), anchor: index === 0 ? 'start' : index === n - 1 ? 'end' : 'middle' });
  const last = label(n - 1);
  const everyKth = (k: number): XLabel[] => {
    const shown: XLabel[] = [];
    for (let i = 0; i < n - 1; i += k) shown.push(label(i));
    while (shown.length > 1 && !apart(shown[shown.length - 1], last)) shown.pop();
    return [...shown, last];
  };
  // The last step leaves the first and the last alone, which always fit.
  const choices = roundSteps(n).map(everyKth);
  return choices.find((ls) => ls.every((l, j) => j === 0 || apart(ls[j - 1], l))) ?? choices[choices.length - 1];
}

/** 1, 2, 5, 10, 20, 50, ... up to the first that is at least `n`. */
function roundSteps(n: number): number[] {
  const steps: number[] = [];
  for (let mag = 1; steps.length === 0 || steps[steps.length - 1] < n; mag *= 10) steps.push(mag, 2 * mag, 5 * mag);
  return steps;
}

/** The left and right ends of a label as drawn (its width estimated from its characters). */
export function extent(l: XLabel): [number, number] {
  const w = l.text.length * CHAR;
  const from = l.anchor === 'start' ? l.x : l.anchor === 'end' ? l.x - w : l.x - w / 2;
  return [from, from + w];
}

function apart(a: XLabel, b: XLabel): boolean {
  return extent(a)[1] + GAP <= extent(b)[0];
}

/** Keeps the end of a long name: the phases of one study share the start and differ at the end. */
function shorten(text: string, room: number): string {
  return text.length <= room ? text : `…${text.slice(text.length - Math.max(1, room - 1))}`;
}
