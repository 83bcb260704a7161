/**
 * The LV wall as layers of hexahedra (the command line's `myocardium --hex-mesh`): the LV_ENDO and
 * LV_EPI meshes of the LV wall each laid out on the anatomical grid (rings from the apex to the
 * base, each starting at the septum) and joined ring by ring into cells through the wall, wedges
 * round the apex, for finite-element simulation. Built in the worker from the same meshes as the
 * LV wall, so it can be built when the wall can (export/wall.ts). What the row checks before asking
 * the core (whole numbers in the core's ranges: the core checks them again and its message is the
 * one that counts), the file name, the header lines, the figures line and the wording of the
 * core's refusals. Pure functions: the row (HexRow.ts) and the controller only wire them.
 */
import type { HexSummary } from '../../core-client/protocol';
import { checkLayout, type AnatomicalLayout } from './anatomical';
import { headerLines, type ExportInfo } from './header';
import { WALL_WHAT, wallBaseName } from './wall';

/** Cells through the wall: the core's default (`hex_wall::DEFAULT_LAYERS`) and range (`LAYERS`), inclusive. */
export const HEX_DEFAULT_LAYERS = 3;
export const HEX_LAYERS = { min: 1, max: 20 } as const;

/** The layout of both surfaces and the layers between them. */
export interface HexLayout extends AnatomicalLayout {
  layers: number;
}

/**
 * The smallest mesh, built once the wall can be to learn whether the core can build one at all
 * (a file without RV landmarks or contours cannot say where the septum is: its refusal is the
 * row's text); the core alone decides, and this costs it least.
 */
export const HEX_PROBE: HexLayout = { rings: 2, points: 8, layers: 1 };

/** What the row says under its title: what the mesh is for, in one line. */
export const HEX_HINT = 'layers of hexahedra for finite-element simulation (transmural, longitudinal, circumferential coordinates; rule-based fibres, +60° to −60°; AHA segment per cell)';

/** What the row is, in its tooltips. */
export const HEX_WHAT = 'The LV wall as layers of hexahedra (wedges round the apex) between the LV_ENDO and LV_EPI meshes, a VTK unstructured grid';

export type HexCheck = { ok: true; layout: HexLayout } | { ok: false; message: string };

/**
 * The layout and layers typed in the three fields (their text), or what is wrong with them: whole
 * numbers in the core's ranges (the anatomical layout's for rings and points), so that a Save is
 * never a call the core is sure to refuse.
 */
export function checkHex(rings: string, points: string, layers: string): HexCheck {
  const layout = checkLayout(rings, points);
  const t = layers.trim();
  const n = /^\d+$/.test(t) ? Number(t) : NaN;
  const layersOk = Number.isInteger(n) && n >= HEX_LAYERS.min && n <= HEX_LAYERS.max;
  const wrong = [...(layout.ok ? [] : [layout.message]), ...(layersOk ? [] : [`Layers: a whole number from ${HEX_LAYERS.min} to ${HEX_LAYERS.max}`])];
  if (!layout.ok || !layersOk) return { ok: false, message: wrong.join('; ') };
  return { ok: true, layout: { ...layout.layout, layers: n } };
}

/** The cells of a layout: per layer, a wedge per point of the apex ring and a hexahedron per quad above it. */
export function hexCounts(l: HexLayout): { hexahedra: number; wedges: number; points: number } {
  return { hexahedra: l.layers * (l.rings - 1) * l.points, wedges: l.layers * l.points, points: (l.layers + 1) * (l.rings * l.points + 1) };
}

/** `patient1-ED-LV_wall-hex-24x48x3.vtk` (the LV wall's name, the time frame after it, then the layout and layers). */
export function hexFileName(info: ExportInfo, l: HexLayout): string {
  return `${wallBaseName(info)}-hex-${l.rings}x${l.points}x${l.layers}.vtk`;
}

/** The app's lines in the file's header, after the command line's comment (which spells out the layout and arrays). */
export function hexHeaderLines(info: ExportInfo, endo: string, epi: string): string[] {
  return headerLines({ ...info, surface: `${endo} + ${epi}` });
}

/**
 * Why the mesh cannot be built now, or what it is: the LV wall's reasons (it is built of the same
 * meshes) with this row's subject in place of the wall's.
 */
export function hexTitle(wall: { ready: boolean; title: string }): string {
  if (wall.ready) return `${HEX_WHAT} (the LV wall's meshes, their last runs with these parameters)`;
  return wall.title.startsWith(WALL_WHAT) ? `${HEX_WHAT}${wall.title.slice(WALL_WHAT.length)}` : wall.title;
}

/** The Save button's title for a layout typed. */
export function hexSaveTitle(l: HexLayout): string {
  const c = hexCounts(l);
  return `Save ${c.hexahedra} hexahedra + ${c.wedges} wedges (${l.rings} rings x ${l.points} points, ${l.layers} ${l.layers === 1 ? 'layer' : 'layers'}) as a VTK unstructured grid: point data transmural, longitudinal, circumferential_deg; cell data aha_segment`;
}

/**
 * The figures of a built mesh, each kept whole on the narrow column (its cells, points, volume and
 * worst corner), and a warning when cells are inverted.
 */
export function hexFigures(s: HexSummary): { figures: string[]; notes: string[] } {
  const figures = [
    `${s.hexahedra} hexahedra + ${s.wedges} wedges`,
    `${s.points} points`,
    `${s.volume_ml.toFixed(1)} ml`,
    `min scaled Jacobian ${s.min_scaled_jacobian.toFixed(2)}`,
  ];
  const n = s.inverted_cells;
  const notes = n > 0 ? [`⚠ ${n} inverted ${n === 1 ? 'cell' : 'cells'}: the endo- and epicardium cross or touch there, a solver would refuse ${n === 1 ? 'it' : 'them'} (try Align breath-holds)`] : [];
  return { figures, notes };
}

/** The figures line as one text (the unit tests', the console's). */
export function hexFiguresText(s: HexSummary): string {
  const { figures, notes } = hexFigures(s);
  return [figures.join(' · '), ...notes].join('. ');
}

/** The figures' tooltip: the layout, the layers, both volumes, the worst corner, the arrays. */
export function hexFiguresTitle(s: HexSummary): string {
  return [
    `${s.rings} rings x ${s.points_per_ring} points per surface, ${s.layers} ${s.layers === 1 ? 'layer' : 'layers'} through the wall: ${s.hexahedra} hexahedra, ${s.wedges} wedges round the apex, ${s.points} points`,
    `volume ${s.volume_ml.toFixed(1)} ml in the cells, ${s.layouts_volume_ml.toFixed(1)} ml between the two layouts' surfaces`,
    `smallest scaled Jacobian ${s.min_scaled_jacobian.toFixed(3)} (1 a cube's corner, 0 flat, below 0 inverted); ${s.inverted_cells} inverted ${s.inverted_cells === 1 ? 'cell' : 'cells'}`,
    'point data transmural 0-1, longitudinal 0-1, circumferential_deg from the septum; cell data aha_segment 1-17',
  ].join('\n');
}

/**
 * The core's reason as a sentence ("the hexahedral wall: its cells are laid out from the septum:
 * ..." -> "Its cells are laid out from the septum: ..."), without the prefix that says which
 * export it is (the row says that already).
 */
export function hexReason(message: string): string {
  const text = message.replace(/^the hexahedral wall:\s*/i, '').trim();
  return text.charAt(0).toUpperCase() + text.slice(1);
}

/** Why a Save failed, on the figures line. */
export function hexErrorText(message: string): string {
  return `⚠ The hexahedra could not be built: ${hexReason(message)}`;
}

/**
 * Whether a failure of the probe is the core saying this file can have no hexahedral wall (its
 * refusal, or a core without the call) rather than something in between (a worker restarted),
 * which must not grey the row.
 */
export function isHexRefusal(e: { code: string; message: string }): boolean {
  return e.code === 'hex_unavailable' || /^the hexahedral wall:/i.test(e.message);
}
