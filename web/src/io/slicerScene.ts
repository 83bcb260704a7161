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
import { fcsvMarkup, isFcsvText, isMarkupsHead, markupsStem } from './markupsStudy';

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

/**
 * Whether a markups file's text holds a curve or a closed curve (not only point lists, lines,
 * planes); a legacy point list file (`.fcsv`) does when it is a contour clicked point by point:
 * four points or more, none named as a landmark (the core also asks them to lie in one plane).
 */
export function holdsCurves(text: string, name = ''): boolean {
  if (isFcsvText(text)) {
    const m = fcsvMarkup(name, text) as { name: string; controlPoints: { label: string }[] } | null;
    // A damaged point list file is still markups: opened with them, the core names it.
    if (m === null) return true;
    return m.controlPoints.length >= 4 && !namesLandmark(name) && !m.controlPoints.some((p) => namesLandmark(p.label));
  }
  return /"type"\s*:\s*"(Closed)?Curve"/.test(text);
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
    if (text === null || holdsCurves(text, markupsStem(m.name)) || (!isFcsvText(text) && !isJson(text))) curves = true;
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
