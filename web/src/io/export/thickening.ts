/**
 * The LV wall's systolic thickening by AHA segment, as the Function panel shows it under its
 * table (the command line's `heartmesh volumes`: the JSON's `wall_thickening`, the
 * `--thickening-plot` drawing): the caption, the tooltip, the note said when there is none, the
 * two files' names and the Thickening CSV. The CSV carries the `#` header of the app's other
 * segment table (the wall's Segments CSV: app and core versions, the input files, the lids, every
 * parameter and option, the walls' minimum thickness) and lines saying which phases were end-
 * diastole and end-systole and where each phase's septum came from, so the percentages stay tied
 * to the measurement they came from. Pure functions: ThickeningView.ts only wires them.
 */
import type { LidsMode, ParamValues, PhaseSpec, ReconOptions, WallThickening } from '../../core-client/protocol';
import type { PhasePlan } from '../../app/phases';
import { splitExtension } from '../fileExtension';
import { mm4 } from './contourCsv';
import { csvField } from './csvField';
import { commentedCsv, septumSourceText } from './segments';
import { WALL_ENDO, WALL_EPI, WALL_MIN_THICKNESS_MM, wallHeaderLines } from './wall';

/** The columns, named as the fields of `volumes --json`'s `wall_thickening.segments`. */
export const THICKENING_CSV_COLUMNS = 'segment,name,ed_mm,es_mm,thickening_percent';

/** What a phases measurement was made of and with: the CSV's header says it. */
export interface ThickeningProvenance {
  plan: PhasePlan;
  params: ParamValues;
  lids: LidsMode;
  options: ReconOptions;
  appVersion: string;
  /** The core's version (null: not known, e.g. the worker never said). */
  coreVersion: string | null;
}

/**
 * The base name of the Function panel's files: a sequence's file name without its extension
 * (`cine`), or `phases` when the phases are several files; made safe for a file name.
 */
export function phasesBaseName(plan: PhasePlan): string {
  const first = plan.phases[0];
  const base = plan.kind === 'frames' && first ? splitExtension(first.file)[0] : 'phases';
  return base.replace(/[^A-Za-z0-9._-]+/g, '_');
}

/** `phases-LV_wall-thickening.svg`: the core's bullseye, saved as it drew it. */
export function thickeningSvgFileName(plan: PhasePlan): string {
  return `${phasesBaseName(plan)}-LV_wall-thickening.svg`;
}

/** `phases-LV_wall-thickening.csv`. */
export function thickeningCsvFileName(plan: PhasePlan): string {
  return `${phasesBaseName(plan)}-LV_wall-thickening.csv`;
}

/** A percentage to the nearest whole number, as the bullseye draws it ("-0" is "0"). */
function wholePercent(v: number): string {
  const r = Math.round(v);
  return String(r === 0 ? 0 : r);
}

/** The line under the bullseye: "LV wall thickening patient1-ED → patient1-ES: mean 55 %". */
export function thickeningCaption(t: WallThickening): string {
  const head = `LV wall thickening ${t.ed_phase} → ${t.es_phase}`;
  return t.mean_percent !== null && Number.isFinite(t.mean_percent) ? `${head}: mean ${wholePercent(t.mean_percent)} %` : head;
}

/** Where the septum was placed from: once when both phases say the same, else at ED and at ES. */
export function septumText(t: WallThickening): string {
  const [ed, es] = t.septum_from.map(septumSourceText);
  return ed === es ? `Septum placed from ${ed}` : `Septum placed from ${ed} at ED, ${es} at ES`;
}

/** The caption's tooltip: what is drawn, which phases, the septum, what the buttons save. */
export function thickeningTitle(t: WallThickening): string {
  return [
    'Systolic wall thickening by AHA segment: 100 x (ES − ED) / ED of each segment\'s mean wall thickness; anterior up, septum left, apex in the middle (hover a segment for its name)',
    `ED: ${t.ed_phase}, ES: ${t.es_phase} (the phases of the LV's largest and smallest volume); the walls built as the LV wall export builds them, ${WALL_MIN_THICKNESS_MM} mm minimum thickness`,
    septumText(t),
    'Thickening SVG saves this drawing; Thickening CSV each segment\'s ED and ES thickness (mm) and its thickening (%)',
  ].join('\n');
}

/** Said instead of the bullseye when the core measured no thickening (`note`: its reason). */
export function noThickeningText(note: string | undefined): string {
  return note ? `No wall thickening: ${note}` : 'No wall thickening for these phases';
}

/** A phase as the header names it: "patient1-ED (patient1-ED.csv)", "ED (cine.csv frame ED; leave_out=a,b)". */
function phaseText(name: string, plan: PhasePlan): string {
  const p: PhaseSpec | undefined = plan.phases.find((x) => x.name === name);
  if (!p) return name;
  const where = `${p.file}${p.frame !== undefined ? ` frame ${p.frame}` : ''}`;
  const left = p.leave_out && p.leave_out.length > 0 ? `; leave_out=${p.leave_out.join(',')}` : '';
  return `${name} (${where}${left})`;
}

/**
 * The CSV's header lines (without comment markers): the wall files' lines (io/export/wall.ts,
 * the input being the ED and ES phases' files), then the phases and the septum's source.
 */
export function thickeningHeaderLines(t: WallThickening, p: ThickeningProvenance): string[] {
  const files = [...new Set([t.ed_phase, t.es_phase].map((name) => p.plan.phases.find((x) => x.name === name)?.file ?? name))];
  const info = { appVersion: p.appVersion, coreVersion: p.coreVersion ?? 'unknown', fileName: files.join(', '), surface: null, lids: p.lids, options: p.options, params: p.params };
  const [ed, es] = t.septum_from;
  return [
    ...wallHeaderLines(info, WALL_ENDO, WALL_EPI, WALL_MIN_THICKNESS_MM),
    `thickening: 100 x (ES - ED) / ED of each segment's mean wall thickness; ED ${phaseText(t.ed_phase, p.plan)}, ES ${phaseText(t.es_phase, p.plan)}`,
    `segments: AHA 17, septum from ${ed === es ? ed : `${ed} at ED, ${es} at ES`}`,
  ];
}

/** A percentage to two decimals (empty where there is none: a segment without wall, not 0). */
function percent2(v: number | null): string {
  return v !== null && Number.isFinite(v) ? v.toFixed(2) : '';
}

/** The Thickening CSV: one row per AHA segment, in their order, under `header`'s lines. */
export function writeThickeningCsv(t: WallThickening, header: readonly string[]): string {
  const rows = t.segments.map((s) => [s.id, csvField(s.name), mm4(s.ed_mm), mm4(s.es_mm), percent2(s.thickening_percent)].join(','));
  return commentedCsv(header, THICKENING_CSV_COLUMNS, rows);
}
