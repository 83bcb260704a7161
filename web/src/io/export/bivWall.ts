/**
 * The biventricular wall export (the command line's `heartmesh myocardium --biventricular`): the
 * biventricular epicardium (BIV_EPI, which the core joins from the file's LV_EPI and RV_EPI curves)
 * less the LV_ENDO and RV_ENDO cavities, cut at the base into one closed solid in the worker. What
 * decides whether it can be built now (the three surfaces run with the settings in the panel: a
 * mesh of other parameters must not be used), what the button's title says instead, the file name,
 * the header lines, and the line of figures shown once it is built. Pure functions, as
 * export/wall.ts is for the LV wall: the panel and the controller only wire them.
 */
import type { WallFormat, WallSummary } from '../../core-client/protocol';
import { BIV_EPI } from '../../core-client/derivedSurfaces';
import { exportBaseName, headerLines, type ExportInfo } from './header';
import type { WallMesh } from './wall';

/** The surfaces the biventricular wall is made of (matched to the file's names whatever their case). */
export const BIV_LV_ENDO = 'LV_ENDO';
export const BIV_RV_ENDO = 'RV_ENDO';
export { BIV_EPI };
/** The curves BIV_EPI is joined from (core `contours/biv_epi.rs`). */
const EPI_PARTS = ['LV_EPI', 'RV_EPI'] as const;

export type BivWallReadiness =
  | { ready: true; lvEndo: WallMesh; rvEndo: WallMesh; bivEpi: WallMesh; title: string; key: string }
  | { ready: false; title: string; key: string };

const WHAT = 'The biventricular wall: the BIV_EPI mesh less the LV_ENDO and RV_ENDO cavities, cut at the base into one closed solid';
const RUN_THEM = '(Surface menu, or All)';
/** BIV_EPI's name in the Surface menu (FileBar's label). */
const BIV_MENU = 'BiV epicardium';
/**
 * "All" runs BIV_EPI only when it is the current surface (controller `runAllSurfaces`): whenever
 * it must run, say where it is in the menu, and with others that All then runs them.
 */
const RUN_BIV = `(pick ${BIV_MENU} in the Surface menu)`;
const RUN_BIV_THEN_ALL = `(pick ${BIV_MENU} in the Surface menu, then All: All leaves it out unless it is the current surface)`;

/** "A", "A and B", "A, B and C". */
function andList(names: readonly string[]): string {
  return names.length < 2 ? names.join('') : `${names.slice(0, -1).join(', ')} and ${names[names.length - 1]}`;
}

/**
 * Whether the biventricular wall can be built now: the file (`surfaces`: its surfaces, BIV_EPI
 * among them when the core can join it; null: no file) has LV_ENDO, RV_ENDO and BIV_EPI, and the
 * kept mesh of each (`kept`) was run with the settings in the panel (`settings`: the controller's
 * key, the file and frame's contours left out by the user among them). The title says what is
 * missing; `key` changes whenever the meshes the wall would be built of do.
 */
export function bivWallReadiness(surfaces: readonly string[] | null, kept: (surface: string) => WallMesh | undefined, settings: string): BivWallReadiness {
  if (surfaces === null) return { ready: false, title: `${WHAT}: open a file with LV_ENDO, RV_ENDO, LV_EPI and RV_EPI contours`, key: '' };
  const find = (wanted: string) => surfaces.find((s) => s.toUpperCase() === wanted);
  const wanted = [BIV_LV_ENDO, BIV_RV_ENDO, BIV_EPI];
  const names = wanted.map(find);
  const lacking: string[] = [];
  const cavities = [BIV_LV_ENDO, BIV_RV_ENDO].filter((_, i) => names[i] === undefined);
  if (cavities.length > 0) lacking.push(`this file has no ${cavities.join(' and no ')} contours`);
  if (names[2] === undefined) {
    const parts = EPI_PARTS.filter((p) => find(p) === undefined);
    // Both parts there and still no BIV_EPI: a core that cannot join them.
    lacking.push(parts.length > 0 ? `BIV_EPI needs LV_EPI and RV_EPI curves, and this file has no ${parts.join(' and no ')}` : 'this core does not join LV_EPI and RV_EPI into BIV_EPI');
  }
  if (lacking.length > 0) return { ready: false, title: `${WHAT}: ${lacking.join('; ')}`, key: '' };
  const found = names as [string, string, string];
  const how = (list: readonly string[]) => (!list.includes(found[2]) ? RUN_THEM : list.length === 1 ? RUN_BIV : RUN_BIV_THEN_ALL);
  const meshes = found.map((n) => kept(n));
  const missing = found.filter((_, i) => meshes[i] === undefined);
  if (missing.length > 0) {
    const run = missing.length === found.length ? `run ${andList(missing)} first` : `run ${andList(missing)} too`;
    return { ready: false, title: `${WHAT}: ${run} ${how(missing)}`, key: '' };
  }
  const [lvEndo, rvEndo, bivEpi] = meshes as [WallMesh, WallMesh, WallMesh];
  const stale = [lvEndo, rvEndo, bivEpi].filter((m) => m.settings !== settings).map((m) => m.surface);
  if (stale.length > 0) {
    const were = stale.length === 1 ? `${stale[0]} was` : `${andList(stale)} were`;
    return { ready: false, title: `${WHAT}: ${were} last run with other parameters; run ${stale.length === 1 ? 'it' : 'them'} again with these ${how(stale)}`, key: '' };
  }
  const size = (m: WallMesh) => [m.surface, m.positions.length, m.indices.length];
  return {
    ready: true,
    lvEndo,
    rvEndo,
    bivEpi,
    title: `${WHAT} (their last runs, with these parameters); regions epicardium, lv_endocardium, rv_endocardium, base; wall thickness per vertex (mm)`,
    key: JSON.stringify([settings, ...size(lvEndo), ...size(rvEndo), ...size(bivEpi)]),
  };
}

const REGIONS = '1 epicardium, 2 lv_endocardium, 3 rv_endocardium, 4 base';

/** The title of one format's button when the wall can be built. */
export function bivWallFormatTitle(format: WallFormat): string {
  switch (format) {
    case 'stl':
      return 'Biventricular wall as binary STL, for 3D printing (STL has no place for the regions)';
    case 'obj':
      return 'Biventricular wall as Wavefront OBJ, one group per region (g epicardium, g lv_endocardium, g rv_endocardium, g base)';
    case 'ply':
      return `Biventricular wall as binary PLY: face property region (${REGIONS}), vertex property thickness (mm)`;
    case 'vtk':
      return `Biventricular wall as legacy VTK: cell data region (${REGIONS}), point data thickness (mm)`;
  }
}

/** `patient1-ED-BiV_wall.obj` (the time frame after it, as the surface exports have it). */
export function bivWallFileName(info: ExportInfo, format: WallFormat): string {
  return `${exportBaseName({ ...info, surface: 'BiV_wall' })}.${format}`;
}

/**
 * The app's lines in the wall file's header, after the command line's comment; the surfaces in
 * the command line's order (LV_ENDO + BIV_EPI + RV_ENDO).
 */
export function bivWallHeaderLines(info: ExportInfo, lvEndo: string, bivEpi: string, rvEndo: string, minThicknessMm: number | null): string[] {
  const moved =
    minThicknessMm === null
      ? 'min_thickness=off'
      : `min_thickness=${minThicknessMm} mm (endocardial vertices closer to the epicardium or to the other cavity moved away from it)`;
  return [...headerLines({ ...info, surface: `${lvEndo} + ${bivEpi} + ${rvEndo}` }), moved];
}

const ml = (v: number) => `${v.toFixed(1)} ml`;

/** A cavity's volume below the base by its region (`lv_endocardium`, `rv_endocardium`), if the summary has it. */
function cavity(s: WallSummary, region: string): number | undefined {
  return s.cavities?.find((c) => c.region === region)?.volume_ml;
}

/** `lv_endocardium` as the command line says it: "lv endocardium". */
const words = (region: string) => region.replace(/_/g, ' ');

/**
 * The line of figures: the wall's volume and mass, the LV and RV cavities, the mean thickness,
 * that the volumes are below the base, then a note when vertices were moved and a warning when
 * surfaces cross (by pair of regions, as the command line warns).
 */
export function bivWallFiguresText(s: WallSummary): string {
  const { figures, notes } = bivWallFigures(s);
  return [figures.join(' · '), ...notes].join('. ');
}

/** The figures of `bivWallFiguresText` one by one, and its notes. */
export function bivWallFigures(s: WallSummary): { figures: string[]; notes: string[] } {
  const lv = cavity(s, 'lv_endocardium') ?? s.cavity_volume_ml;
  const rv = cavity(s, 'rv_endocardium');
  const parts = [`Wall ${ml(s.wall_volume_ml)}`, `mass ${s.myocardial_mass_g.toFixed(1)} g`, `LV cavity ${ml(lv)}`];
  if (rv !== undefined) parts.push(`RV cavity ${ml(rv)}`);
  if (s.thickness_mm.count > 0) parts.push(`thickness ${s.thickness_mm.mean.toFixed(1)} mm mean`);
  // Said once after the figures, not inside one: each figure is kept whole on the narrow column.
  const notes: string[] = ['Volumes below the base'];
  const moves: string[] = [];
  const vertices = (n: number) => `${n} ${n === 1 ? 'vertex' : 'vertices'}`;
  const { endocardium_moved: endo, epicardium_moved: epi } = s;
  if (endo.vertices > 0) moves.push(`${vertices(endo.vertices)} of the endocardia moved up to ${endo.max_mm.toFixed(2)} mm under the epicardium and apart from the other cavity`);
  if (epi && epi.vertices > 0) moves.push(`${vertices(epi.vertices)} of the epicardium up to ${epi.max_mm.toFixed(2)} mm out over the endocardia`);
  if (moves.length > 0) notes.push(`${moves.join(', ')}, to keep the wall at least ${endo.min_thickness_mm ?? 0} mm thick`);
  for (const note of s.notes ?? []) notes.push(note.charAt(0).toUpperCase() + note.slice(1));
  const crossings = (s.crossings ?? []).filter((c) => c.pairs > 0);
  if (crossings.length > 0) {
    const what = crossings.map(({ regions: [a, b], pairs }) => `${a === b ? `the ${words(a)} passes through itself` : `the ${words(b)} passes through the ${words(a)}`} (${pairs} crossing triangle pairs)`);
    notes.push(`⚠ ${what.join(', ')}: volume meshers will refuse it`);
  } else if (s.endo_epi_crossings > 0) {
    notes.push(`⚠ the surfaces pass through each other (${s.endo_epi_crossings} crossing triangle pairs): volume meshers will refuse it`);
  }
  return { figures: parts, notes };
}

/** The figures' tooltip: the solid's surfaces, size, regions and thickness range, and the density. */
export function bivWallFiguresTitle(s: WallSummary): string {
  const t = s.thickness_mm;
  const regions = s.regions.map((r) => `${r.id} ${r.name} ${r.triangles}`).join(', ');
  const made = [s.surfaces.endo, s.surfaces.epi, ...(s.surfaces.rv_endo ? [s.surfaces.rv_endo] : [])].join(' + ');
  return [
    `${made}: ${s.vertices} vertices, ${s.triangles} triangles, closed`,
    `regions (triangles): ${regions}`,
    t.count > 0 ? `thickness min ${t.min.toFixed(1)}, median ${t.median.toFixed(1)}, max ${t.max.toFixed(1)} mm` : 'thickness not measured',
    `mass = ${s.density_g_per_ml} g/ml x wall volume; volumes below the base plane`,
  ].join('\n');
}

/** Why the wall was not built, from the core's message ("the biventricular wall: the base plane ..."). */
export function bivWallErrorText(message: string): string {
  return `⚠ The biventricular wall could not be built: ${message.replace(/^the biventricular wall: /i, '')}`;
}
