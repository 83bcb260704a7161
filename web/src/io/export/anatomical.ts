/**
 * The anatomical mesh export (the command line's `reconstruct --anatomical-mesh`): the finished LV
 * surface resampled in the worker onto a fixed grid of rings from the apex to the base, each ring
 * starting at the septum, so that every heart and every phase gives the same vertices in the same
 * order (shape analysis, ED→ES motion vertex by vertex). What the row checks before asking the
 * core (the layout's numbers: the core checks them again and its message is the one that counts),
 * the file name, the header lines, the figures line and the wording of the core's refusals. Pure
 * functions: the row (AnatomicalRow.ts) and the controller only wire them.
 */
import type { AnatomicalFormat, AnatomicalSummary } from '../../core-client/protocol';
import { exportBaseName, headerLines, type ExportInfo } from './header';

/** Rings from the apex to the base plane, vertices per ring. */
export interface AnatomicalLayout {
  rings: number;
  points: number;
}

/** The core's default (`Layout::DEFAULT`): rings 2-6 mm apart and vertices 2-4 mm apart on an adult LV, 1154 vertices. */
export const ANATOMICAL_DEFAULT: AnatomicalLayout = { rings: 24, points: 48 };
/** The core's ranges (`Layout::RINGS`, `Layout::POINTS`), inclusive. */
export const ANATOMICAL_RINGS = { min: 2, max: 200 } as const;
export const ANATOMICAL_POINTS = { min: 8, max: 720 } as const;

/**
 * The smallest layout, built once a run finishes only to learn whether the core can build one at
 * all (its refusal, e.g. an RV surface or a file that does not say where the septum is, is the
 * row's text): the core alone decides, and this costs it least.
 */
export const PROBE_LAYOUT: AnatomicalLayout = { rings: ANATOMICAL_RINGS.min, points: ANATOMICAL_POINTS.min };

/** What the row says under its title: what the mesh is for, in one sentence. */
export const ANATOMICAL_HINT = 'Same vertices for every heart: shape analysis, ED→ES motion.';

export type LayoutCheck = { ok: true; layout: AnatomicalLayout } | { ok: false; message: string };

/**
 * The layout typed in the two fields (their text), or what is wrong with it: whole numbers in the
 * core's ranges, so that a Save is never a call the core is sure to refuse.
 */
export function checkLayout(rings: string, points: string): LayoutCheck {
  const one = (text: string, what: string, range: { min: number; max: number }): number | string => {
    const t = text.trim();
    const v = /^\d+$/.test(t) ? Number(t) : NaN;
    return Number.isInteger(v) && v >= range.min && v <= range.max ? v : `${what}: a whole number from ${range.min} to ${range.max}`;
  };
  const r = one(rings, 'Rings', ANATOMICAL_RINGS);
  const p = one(points, 'Points per ring', ANATOMICAL_POINTS);
  const wrong = [r, p].filter((v): v is string => typeof v === 'string');
  if (wrong.length > 0) return { ok: false, message: wrong.join('; ') };
  return { ok: true, layout: { rings: r as number, points: p as number } };
}

/** Vertices of a layout: the apex, the rings, the base lid's centre. */
export function layoutVertices(l: AnatomicalLayout): number {
  return l.rings * l.points + 2;
}

/** `patient1-ED-LV_ENDO-anatomical-24x48.vtk` (the time frame after the surface, as the surface exports have it). */
export function anatomicalFileName(info: ExportInfo, layout: AnatomicalLayout, format: AnatomicalFormat): string {
  return `${exportBaseName(info)}-anatomical-${layout.rings}x${layout.points}.${format}`;
}

/** The app's lines in the file's header, after the command line's comment (which spells the layout out). */
export function anatomicalHeaderLines(info: ExportInfo): string[] {
  return headerLines(info);
}

/** The title of a format in the select. */
export function anatomicalFormatTitle(format: AnatomicalFormat): string {
  switch (format) {
    case 'vtk':
      return 'Legacy VTK: cell data region (1 wall, 2 base)';
    case 'vtp':
      return 'VTK XML PolyData (ParaView, VTK readers): cell data region (1 wall, 2 base)';
    case 'ply':
      return 'Binary PLY: face property region (1 wall, 2 base)';
    case 'obj':
      return 'Wavefront OBJ: g wall, g base';
    case 'stl':
      return 'Binary STL: the triangles alone, no regions';
  }
}

const mm = (v: number) => (v < 0.1 ? v.toFixed(2) : v.toFixed(1));

/**
 * The figures of a built mesh (its size, its volume, how far it lies from the surface), each kept
 * whole on the narrow column, and then where the septum came from, a line of its own.
 */
export function anatomicalFigures(s: AnatomicalSummary): { figures: string[]; septum: string } {
  return {
    figures: [`${s.vertices} vertices`, `${s.volume_ml.toFixed(1)} ml`, `to the surface ${mm(s.to_surface_mean_mm)} mm mean, ${mm(s.to_surface_max_mm)} mm max`],
    septum: `Septum from ${s.septum_from}`,
  };
}

/** The figures line as one text (the unit tests', the console's). */
export function anatomicalFiguresText(s: AnatomicalSummary): string {
  const { figures, septum } = anatomicalFigures(s);
  return `${figures.join(' · ')}. ${septum}`;
}

/** The figures' tooltip: the layout, the triangles, the length and both volumes. */
export function anatomicalFiguresTitle(s: AnatomicalSummary): string {
  return [
    `${s.rings} rings of ${s.points} from the apex to the base plane: ${s.vertices} vertices (vertex 0 the apex, last the base lid's centre), ${s.triangles} triangles, regions wall and base`,
    `apex to base ${s.length_mm.toFixed(1)} mm along the long axis`,
    `volume ${s.volume_ml.toFixed(1)} ml closed at the base plane; the surface's below it ${s.surface_volume_ml.toFixed(1)} ml (the grid's chords cut a little off)`,
    `distance between the grid and the surface below the base: ${s.to_surface_mean_mm.toFixed(3)} mm mean, ${s.to_surface_max_mm.toFixed(3)} mm max`,
  ].join('\n');
}

/**
 * The core's reason as a sentence ("the anatomical mesh: the anatomical layout is the LV's ..."
 * -> "The anatomical layout is the LV's ..."; the study's "the anatomical meshes: ..." alike): its
 * words, without the prefix that says which export it is (the row says that already).
 */
export function anatomicalReason(message: string): string {
  const text = message.replace(/^the anatomical mesh(?:es)?:\s*/i, '').trim();
  return text.charAt(0).toUpperCase() + text.slice(1);
}

/** Why a Save failed, on the figures line. */
export function anatomicalErrorText(message: string): string {
  return `⚠ The anatomical mesh could not be built: ${anatomicalReason(message)}`;
}

/**
 * Whether a failure of the probe is the core saying this surface or file can have no anatomical
 * mesh (its typed refusal, or a core without the call), rather than something in between (a
 * worker restarted, a file not loaded yet), which must not grey the row.
 */
export function isRefusal(e: { code: string; message: string }): boolean {
  return e.code === 'anatomical_unavailable' || /^the anatomical mesh:/i.test(e.message);
}
