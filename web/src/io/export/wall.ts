/**
 * The LV wall export (the command line's `heartmesh myocardium`): the LV_ENDO and LV_EPI meshes of
 * the current file, cut at the base and joined into one closed solid in the worker. What decides
 * whether it can be built now (both surfaces run, with the settings in the panel: a mesh of other
 * parameters must not be used), what the button's title says instead, the file name, the header
 * lines, and the line of figures shown once it is built. Pure functions: the panel and the
 * controller only wire them.
 */
import type { WallFormat, WallSummary } from '../../core-client/protocol';
import { exportBaseName, headerLines, type ExportInfo } from './header';

/** The surfaces the wall is made of (matched to the file's names whatever their case). */
export const WALL_ENDO = 'LV_ENDO';
export const WALL_EPI = 'LV_EPI';

/**
 * Endocardial vertices closer to the epicardium than this (mm), or outside it, are moved this far
 * under it before the wall is built: the command line's `--min-thickness` default.
 */
export const WALL_MIN_THICKNESS_MM = 1;

/** A finished mesh the app keeps for a surface (keptSurfaces.ts), as far as the wall needs it. */
export interface WallMesh {
  surface: string;
  positions: Float32Array;
  indices: Uint32Array;
  positions64?: Float64Array;
  /** Its run's settings key. */
  settings: string;
}

export type WallReadiness =
  | { ready: true; endo: WallMesh; epi: WallMesh; title: string; key: string }
  | { ready: false; title: string; key: string };

/** How the wall's titles begin (the hexahedra's row says what it is instead, export/hexWall.ts). */
export const WALL_WHAT = 'The LV wall: the LV_ENDO and LV_EPI meshes cut at the base and joined into one closed solid';
const WHAT = WALL_WHAT;
const RUN_THEM = '(Surface menu, or All)';

/**
 * Whether the wall can be built now: the file (`surfaces`: its surfaces; null: no file) has both,
 * and the kept mesh of each (`kept`) was run with the settings in the panel (`settings`: the
 * controller's key, the file and frame's contours left out by the user among them). The title
 * says what is missing; `key` changes whenever the meshes the wall would be built of do.
 */
export function wallReadiness(surfaces: readonly string[] | null, kept: (surface: string) => WallMesh | undefined, settings: string): WallReadiness {
  if (surfaces === null) return { ready: false, title: `${WHAT}: open a file with LV_ENDO and LV_EPI contours`, key: '' };
  const find = (wanted: string) => surfaces.find((s) => s.toUpperCase() === wanted);
  const names = [find(WALL_ENDO), find(WALL_EPI)];
  const lacking = [WALL_ENDO, WALL_EPI].filter((_, i) => names[i] === undefined);
  if (lacking.length > 0) {
    return { ready: false, title: `${WHAT}: this file has no ${lacking.join(' and no ')} contours`, key: '' };
  }
  const [endoName, epiName] = names as [string, string];
  const meshes = [kept(endoName), kept(epiName)];
  const missing = [endoName, epiName].filter((_, i) => meshes[i] === undefined);
  if (missing.length === 2) return { ready: false, title: `${WHAT}: run ${endoName} and ${epiName} first ${RUN_THEM}`, key: '' };
  if (missing.length === 1) return { ready: false, title: `${WHAT}: run ${missing[0]} too ${RUN_THEM}`, key: '' };
  const [endo, epi] = meshes as [WallMesh, WallMesh];
  const stale = [endo, epi].filter((m) => m.settings !== settings).map((m) => m.surface);
  if (stale.length > 0) {
    const were = stale.length === 1 ? `${stale[0]} was` : `${stale.join(' and ')} were`;
    return { ready: false, title: `${WHAT}: ${were} last run with other parameters; run ${stale.length === 1 ? 'it' : 'them'} again with these ${RUN_THEM}`, key: '' };
  }
  return {
    ready: true,
    endo,
    epi,
    title: `${WHAT} (their last runs, with these parameters); regions epicardium, endocardium, base; wall thickness per vertex (mm)`,
    key: JSON.stringify([settings, endo.surface, endo.positions.length, endo.indices.length, epi.surface, epi.positions.length, epi.indices.length]),
  };
}

/** The title of one format's button when the wall can be built. */
export function wallFormatTitle(format: WallFormat): string {
  switch (format) {
    case 'stl':
      return 'LV wall as binary STL, for 3D printing (STL has no place for the regions)';
    case 'obj':
      return 'LV wall as Wavefront OBJ, one group per region (g epicardium, g endocardium, g base)';
    case 'ply':
      return 'LV wall as binary PLY: face property region (1 epicardium, 2 endocardium, 3 base), vertex property thickness (mm)';
    case 'vtk':
      return 'LV wall as legacy VTK: cell data region (1 epicardium, 2 endocardium, 3 base), point data thickness (mm)';
  }
}

/** `patient1-ED-LV_wall.obj` (the time frame after it, as the surface exports have it). */
export function wallFileName(info: ExportInfo, format: WallFormat): string {
  return `${wallBaseName(info)}.${format}`;
}

/** `patient1-ED-LV_wall` (`-frame9` after it): the LV wall's files' names before what follows (a format, the hexahedra's layout). */
export function wallBaseName(info: ExportInfo): string {
  return exportBaseName({ ...info, surface: 'LV_wall' });
}

/** The app's lines in the wall file's header, after the command line's comment. */
export function wallHeaderLines(info: ExportInfo, endo: string, epi: string, minThicknessMm: number | null): string[] {
  const moved = minThicknessMm === null ? 'min_thickness=off' : `min_thickness=${minThicknessMm} mm (endocardial vertices closer to the epicardium moved under it)`;
  return [...headerLines({ ...info, surface: `${endo} + ${epi}` }), moved];
}

const ml = (v: number) => `${v.toFixed(1)} ml`;

/**
 * The line of figures: the wall's volume and mass, the cavity below the base, the mean thickness,
 * then a note when endocardial vertices were moved and a warning when the surfaces cross.
 */
export function wallFiguresText(s: WallSummary): string {
  const { figures, notes } = wallFigures(s);
  return [figures.join(' · '), ...notes].join('. ');
}

/** The figures of `wallFiguresText` one by one, and its notes. */
export function wallFigures(s: WallSummary): { figures: string[]; notes: string[] } {
  const parts = [
    `Wall ${ml(s.wall_volume_ml)}`,
    `mass ${s.myocardial_mass_g.toFixed(1)} g`,
    `cavity ${ml(s.cavity_volume_ml)} (both below the base)`,
  ];
  if (s.thickness_mm.count > 0) parts.push(`thickness ${s.thickness_mm.mean.toFixed(1)} mm mean`);
  const notes: string[] = [];
  const moves: string[] = [];
  const vertices = (n: number) => `${n} ${n === 1 ? 'vertex' : 'vertices'}`;
  const { endocardium_moved: endo, epicardium_moved: epi } = s;
  if (endo.vertices > 0) moves.push(`${vertices(endo.vertices)} of the endocardium moved up to ${endo.max_mm.toFixed(2)} mm under the epicardium`);
  if (epi && epi.vertices > 0) moves.push(`${vertices(epi.vertices)} of the epicardium up to ${epi.max_mm.toFixed(2)} mm out over the endocardium`);
  if (moves.length > 0) notes.push(`${moves.join(', ')}, to keep the wall at least ${endo.min_thickness_mm ?? 0} mm thick`);
  for (const note of s.notes ?? []) notes.push(note.charAt(0).toUpperCase() + note.slice(1));
  if (s.endo_epi_crossings > 0) {
    notes.push(`⚠ the endocardium passes through the epicardium (${s.endo_epi_crossings} crossing triangle pairs): volume meshers will refuse it`);
  }
  return { figures: parts, notes };
}

/** The figures' tooltip: the solid's size, regions and thickness range, and the density. */
export function wallFiguresTitle(s: WallSummary): string {
  const t = s.thickness_mm;
  const regions = s.regions.map((r) => `${r.id} ${r.name} ${r.triangles}`).join(', ');
  return [
    `${s.surfaces.endo} + ${s.surfaces.epi}: ${s.vertices} vertices, ${s.triangles} triangles, closed`,
    `regions (triangles): ${regions}`,
    t.count > 0 ? `thickness min ${t.min.toFixed(1)}, median ${t.median.toFixed(1)}, max ${t.max.toFixed(1)} mm` : 'thickness not measured',
    `mass = ${s.density_g_per_ml} g/ml x wall volume; volumes below the base plane`,
  ].join('\n');
}

/** Why the wall was not built, from the core's message ("the LV wall: the base plane cuts ..."). */
export function wallErrorText(message: string): string {
  return `⚠ The LV wall could not be built: ${message.replace(/^the LV wall: /i, '')}`;
}
