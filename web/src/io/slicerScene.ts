/**
 * 3D Slicer scenes opened whole: the folder Slicer saves a scene into, or the same folder as one
 * `.mrb` bundle (a ZIP, unpacked by io/zipArchive.ts first). The scene file (`.mrml`) names the
 * data files beside it and holds no contours, so the contours come from those: the markups curves
 * when there are any (joined by io/markupsStudy.ts), else the segmentations. The scene file, and
 * with curves every other file (scans, segmentations, screenshots), are set aside and named in the
 * banner; without curves, the point lists are set aside and the rest opened as any dropped files
 * (a scan among them is told by the core and set aside as an image). The core reads a scene the
 * same way on the command line (heartmesh-core `io::slicer_scene`).
 */
import { isMarkupsHead, isPointListText, markupsStem, pointListMarkup } from './markupsStudy';

/** How much of a file's start is looked into. */
const HEAD_BYTES = 4096;

/** Whether a file's first bytes are a Slicer scene file's (XML whose root element is `MRML`), as the core tells one. */
export function isMrmlHead(head: Uint8Array): boolean {
  let rest = new TextDecoder().decode(head.subarray(0, HEAD_BYTES)).replace(/^\uFEFF/, '');
  // The XML declaration and comments may come before the root.
  for (;;) {
    rest = rest.trimStart();
    const close = rest.startsWith('<?') ? '?>' : rest.startsWith('<!--') ? '-->' : null;
    if (close === null) break;
    const at = rest.indexOf(close);
    if (at < 0) return false;
    rest = rest.slice(at + close.length);
  }
  return /^<mrml[\s>/]/i.test(rest);
}

/** Words that make a point's or a list's name a landmark's (as the core's `LANDMARK_WORDS`). */
const LANDMARK_WORDS = new Set(['apex', 'valve', 'insert', 'insertion', 'insertions', 'mitral', 'tricuspid', 'aorta', 'aortic', 'pulmonary', 'pulmonic', 'landmark', 'landmarks', 'phantom', 'extent']);

function namesLandmark(name: string): boolean {
  return name.split(/[^A-Za-z0-9]+/).some((w) => LANDMARK_WORDS.has(w.toLowerCase()));
}

/** How far (mm) a contour's points may stray from their plane (the core's `NON_PLANAR_MM`). */
const NON_PLANAR_MM = 2.5;

/** Whether points lie in one plane: Newell's normal of their polygon, then each point's distance to the plane through their centroid. */
function inOnePlane(points: number[][]): boolean {
  const n = [0, 0, 0];
  points.forEach((p, k) => {
    const q = points[(k + 1) % points.length];
    n[0] += (p[1] - q[1]) * (p[2] + q[2]);
    n[1] += (p[2] - q[2]) * (p[0] + q[0]);
    n[2] += (p[0] - q[0]) * (p[1] + q[1]);
  });
  const length = Math.hypot(...n);
  if (!(length > 0)) return false;
  const c = [0, 1, 2].map((i) => points.reduce((a, p) => a + p[i], 0) / points.length);
  return points.every((p) => Math.abs(p.reduce((a, v, i) => a + (v - c[i]) * n[i], 0) / length) <= NON_PLANAR_MM);
}

/**
 * The wall a list's name says it traces (the core's `named_wall`): a side (LV/left, RV/right, or
 * glued as in `lvendo`) and a wall (endo..., epi..., or an RV free wall or septum). A list so
 * named is a contour whatever its number of points, as the core reads it.
 */
export function namesWall(name: string): boolean {
  const wallOf = (t: string): 'endo' | 'epi' | 'rvpart' | null =>
    t.startsWith('endo') ? 'endo' : t.startsWith('epi') ? 'epi' : t === 'free' || t.startsWith('freewall') || t === 'fw' || t.startsWith('sept') ? 'rvpart' : null;
  let lv: boolean | null = null;
  let wall: 'endo' | 'epi' | 'rvpart' | null = null;
  for (const t of name.split(/[^A-Za-z0-9]+/).filter((w) => w !== '').map((w) => w.toLowerCase())) {
    let side: boolean | null = t === 'lv' || t === 'left' ? true : t === 'rv' || t === 'right' ? false : null;
    let rest: string | null = side === null ? t : null;
    if (side === null && (t.startsWith('lv') || t.startsWith('rv')) && wallOf(t.slice(2)) !== null) {
      side = t.startsWith('lv');
      rest = t.slice(2);
    }
    lv ??= side;
    wall ??= rest === null ? null : wallOf(rest);
  }
  return lv !== null && wall !== null && !(lv && wall === 'rvpart');
}

interface PointList {
  type?: unknown;
  name?: unknown;
  controlPoints?: { label?: unknown; position?: unknown; positionStatus?: unknown }[];
}

/**
 * Whether a point list is a contour clicked point by point, as the core reads one
 * (`point_list_is_contour`): four placed points or more in one plane, neither the list nor a
 * point named as a landmark; or named after a wall ([`namesWall`]) with any placed point.
 */
function clickedContour(m: PointList, name: string): boolean {
  const placed = (m.controlPoints ?? []).filter((p) => (p.positionStatus ?? 'defined') === 'defined');
  const points = placed.map((p) => p.position).filter((p): p is number[] => Array.isArray(p) && p.length === 3 && p.every(Number.isFinite));
  const listName = typeof m.name === 'string' && m.name.trim() !== '' ? m.name : name;
  if (points.length !== placed.length || namesLandmark(listName) || placed.some((p) => typeof p.label === 'string' && namesLandmark(p.label))) return false;
  if (namesWall(listName)) return points.length > 0;
  return points.length >= 4 && inOnePlane(points);
}

/**
 * Whether a markups file's text holds a curve or a closed curve (not only point lists, lines,
 * planes), or a point list clicked along a contour (`.mrk.json`, a legacy `.fcsv` or a control
 * points table): what the core reads a scene's contours from. `name` is the file's name
 * without its extension.
 */
export function holdsCurves(text: string, name = ''): boolean {
  if (isPointListText(text)) {
    const m = pointListMarkup(name, text) as PointList | null;
    // A damaged point list file is still markups: opened with them, the core names it.
    return m === null || clickedContour(m, name);
  }
  if (/"type"\s*:\s*"(Closed)?Curve"/.test(text)) return true;
  try {
    const doc = JSON.parse(text) as { markups?: PointList[] };
    return (doc.markups ?? []).some((m) => m?.type === 'Fiducial' && clickedContour(m, name));
  } catch {
    return false;
  }
}

/** The files of a scene to open, and those set aside. */
export interface Scene<T> {
  files: T[];
  aside: string[];
  /** What the contours come from, for the banner. */
  source: 'the Slicer markups' | 'its segmentations';
}

/** The banner's note on the files of a scene set aside; a segmentation among them is said to open alone (its curves won). */
export function sceneAsideText(aside: readonly string[], source: string): string {
  const n = aside.length;
  const named = aside.map((a) => (/\.seg\.nrrd$/i.test(a) ? `${a} (a segmentation: open it alone to read it instead)` : a));
  return `${n === 1 ? '1 other file' : `${n} other files`} of the Slicer scene set aside (the contours come from ${source}): ${named.join(', ')}.`;
}

type Named = Blob & { name: string };

async function textOf(file: Blob, bytes?: number): Promise<string | null> {
  try {
    return bytes === undefined ? await file.text() : new TextDecoder().decode(await file.slice(0, bytes).arrayBuffer());
  } catch {
    return null; // unreadable: opened (and refused, named) as any other file
  }
}

/**
 * What to open of `files` when a Slicer scene file is among them (null: none is, the files open
 * as they are). Files that cannot be read are kept, so their refusal is said as for any file.
 */
export async function sceneOf<T extends Named>(files: readonly T[]): Promise<Scene<T> | null> {
  const heads = await Promise.all(files.map((f) => textOf(f, HEAD_BYTES)));
  const bytes = (k: number) => new TextEncoder().encode(heads[k] ?? '');
  const scenes = files.filter((_, k) => heads[k] !== null && isMrmlHead(bytes(k)));
  if (scenes.length === 0) return null;
  const markups = files.filter((_, k) => heads[k] !== null && isMarkupsHead(bytes(k)));
  let curves = false;
  for (const m of markups) {
    const text = await textOf(m);
    // A damaged markups file is still markups: opened with them, the core names it.
    if (text === null || holdsCurves(text, markupsStem(m.name)) || (!isPointListText(text) && !isJson(text))) curves = true;
    if (curves) break;
  }
  let opened = curves ? markups : files.filter((f) => !scenes.includes(f) && !markups.includes(f));
  // Nothing else: the point lists (the core says they hold no curve), else the scene file itself
  // (the core says what to open instead).
  if (opened.length === 0) opened = markups.length > 0 ? markups : scenes;
  const aside = files.filter((f) => !opened.includes(f)).map((f) => f.name);
  return { files: [...opened], aside, source: curves ? 'the Slicer markups' : 'its segmentations' };
}

function isJson(text: string): boolean {
  try {
    JSON.parse(text);
    return true;
  } catch {
    return false;
  }
}
