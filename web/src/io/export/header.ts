/**
 * What every export records about how it was made: app and core version, input file, surface,
 * lids mode, the options (smoothing, softening, breath-hold alignment) and every parameter value. One place, so that all formats say the same thing.
 */
import { withDefaultOptions, type CoordinateSystem, type LidsMode, type ParamValues, type ReconOptions } from '../../core-client/protocol';
import { splitExtension } from '../fileExtension';

export interface ExportInfo {
  appVersion: string;
  coreVersion: string;
  fileName: string;
  surface: string | null;
  /** The time frame read of a file that holds several (null or absent: the file holds one). */
  frame?: string | null;
  lids: LidsMode;
  /** Smoothing method, conflict softening, alignment (missing in callers that predate them: defaults). */
  options?: ReconOptions;
  params: ParamValues;
  /**
   * The contour ids the user left out of the run (the Contours panel); absent or empty: none. Not
   * an option: the ids belong to this file.
   */
  leaveOut?: readonly string[];
  /**
   * The input's patient frame (LPS, RAS) when known: written as `SPACE=...`, where 3D Slicer
   * reads it to place the mesh (it takes LPS otherwise, mirroring a NIfTI's RAS mesh).
   */
  coordinateSystem?: CoordinateSystem | null;
}

/**
 * The per-vertex distance's name in PLY and VTK files: the command line's, so a script reading
 * either's file finds the same array (mm, as every length in heartmesh's files).
 */
export const DISTANCE_NAME = 'distance';

export interface MeshData {
  /** xyz per vertex, mm. */
  positions: Float32Array;
  /**
   * The same vertices in full precision, when the core gave them: the text formats (OBJ, VTK)
   * write these and STL's facet normals come from them, so the app's file is the command line's.
   * Binary STL and PLY store float32 coordinates either way.
   */
  positions64?: Float64Array;
  /** three vertex indices per triangle, counter-clockwise seen from outside. */
  indices: Uint32Array;
  /** per-vertex contour distance in mm (optional in PLY/VTK). */
  vertexDistances?: Float32Array;
  /** The same in full precision, when the core gave them: VTK writes these as the command line does. */
  vertexDistances64?: Float64Array;
}

/** Parameters as `name=value` pairs in schema order. */
export function paramText(params: ParamValues): string {
  return Object.keys(params)
    .map((k) => `${k}=${params[k]}`)
    .join(' ');
}

/**
 * ` smoothing_method=... soften_conflicts=... align_slices=... end_caps=... keep_specks=... apex_floor=...` when known,
 * then ` drop_second_loops=true` when on (as the CLI writes it: only when on).
 */
function optionText(options: ReconOptions | undefined): string {
  if (!options) return '';
  const o = withDefaultOptions(options);
  return ` smoothing_method=${o.smoothing_method} soften_conflicts=${o.soften_conflicts} align_slices=${o.align_slices} end_caps=${o.end_caps} keep_specks=${o.keep_specks} apex_floor=${o.apex_floor}${o.drop_second_loops ? ' drop_second_loops=true' : ''}`;
}

/** ` leave_out=ID,ID` when the user left contours out (as drop_second_loops: only when there is something to say). */
function leaveOutText(ids: readonly string[] | undefined): string {
  return ids && ids.length > 0 ? ` leave_out=${ids.join(',')}` : '';
}

/** Header lines (without comment markers), each free of newlines. */
export function headerLines(info: ExportInfo): string[] {
  const clean = (s: string) => s.replace(/[\r\n]+/g, ' ');
  return [
    `heartmesh ${clean(info.appVersion)} (core ${clean(info.coreVersion)}), units: mm`,
    ...(info.coordinateSystem ? [`SPACE=${info.coordinateSystem}`] : []),
    `input: ${clean(info.fileName)}${info.surface ? ` surface: ${clean(info.surface)}` : ''}${info.frame != null ? ` frame: ${clean(info.frame)}` : ''}`,
    `lids: ${info.lids} ${paramText(info.params)}${optionText(info.options)}${clean(leaveOutText(info.leaveOut))}`,
  ];
}

/**
 * The binary STL's 80-byte header, ASCII: the app version, the units, the surface and the time
 * frame always (a surface cut to "LV_END" told nothing), then the input's name and as many whole
 * `name=value` parameters as fit, never one cut short. STL has no other place for metadata; the
 * other formats and the Parameters JSON carry everything.
 */
export function stlHeader(info: ExportInfo): string {
  const clean = (s: string) => s.replace(/[^\x20-\x7e]/g, '?');
  let text = `heartmesh ${clean(info.appVersion)} mm`;
  // First, so that the 80 bytes always hold it: 3D Slicer reads the patient frame from here.
  if (info.coordinateSystem) text += ` SPACE=${info.coordinateSystem}`;
  if (info.surface) text += ` ${clean(info.surface)}`;
  if (info.frame != null) text += ` frame ${clean(info.frame)}`;
  const room = 80 - text.length - 1;
  const name = clean(info.fileName).replace(/ /g, '_');
  if (room > 0) text += ` ${name.length <= room ? name : `${name.slice(0, Math.max(0, room - 1))}~`}`;
  const o = info.options ? withDefaultOptions(info.options) : null;
  // Contours left out change the mesh more than any one parameter: right after the mesh ends, when the whole list fits.
  const leaveOut = clean(leaveOutText(info.leaveOut).trim());
  const fits = leaveOut !== '' && text.length + `lids=${info.lids}`.length + leaveOut.length + 2 <= 80;
  const items = [`lids=${info.lids}`, ...(fits ? [leaveOut] : []), ...Object.keys(info.params).map((k) => `${k}=${info.params[k]}`)];
  if (o) items.push(`smoothing_method=${o.smoothing_method}`, `end_caps=${o.end_caps}`, `align_slices=${o.align_slices}`);
  for (const item of items) {
    if (text.length + 1 + item.length > 80) break;
    text += ` ${item}`;
  }
  return text.slice(0, 80);
}

/** Base name for downloads: input name without extension (`seg.nii.gz`: `seg`), plus surface and time frame. */
export function exportBaseName(info: ExportInfo): string {
  const safe = (s: string) => s.replace(/[^A-Za-z0-9._-]+/g, '_');
  const base = safe(splitExtension(info.fileName)[0]) || 'heartmesh';
  const surface = info.surface ? `-${safe(info.surface)}` : '';
  const frame = info.frame != null ? `-frame${safe(info.frame)}` : '';
  return `${base}${surface}${frame}`;
}
