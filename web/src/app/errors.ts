/**
 * Small helpers of the controller: errors as the protocol's data, the banner's note on a refused
 * file, parameters in schema order for export headers, listeners that may throw.
 */
import type { CoreErrorData, ParamSpec, ParamValues } from '../core-client/protocol';
import { describeError } from './state';

/** What the banner adds when a file is refused at load: which file the view still shows. */
export function keptText(previous: string | null): string {
  return previous ? ` Not opened; still showing ${previous}.` : ' Not opened.';
}

/**
 * A biv-me SliceInfoFile refused as contours (the core's parse message for it). Dropped together
 * with the GPFile it sits beside, it is where biv-me keeps it, not a mistake: set aside, not refused.
 */
export function isSliceInfoRefusal(e: CoreErrorData): boolean {
  return e.code === 'parse' && /biv-me SliceInfoFile/.test(e.message);
}

/** The banner's note on SliceInfoFiles dropped with the contour file `shown`. */
export function setAsideText(names: readonly string[], shown: string): string {
  // Two patient folders dropped together hold one SliceInfoFile.txt each: counted, not listed twice.
  const counts = new Map<string, number>();
  for (const n of names) counts.set(n, (counts.get(n) ?? 0) + 1);
  const them = [...counts].map(([n, k]) => (k > 1 ? `${k} files named ${n}` : n)).join(', ');
  return `${them} set aside: image planes, not contours (the contours come from ${shown}; a SliceInfoFile is read with the GPFile of its folder, to check that each contour lies in its own plane).`;
}

/**
 * A DICOM image refused as contours (the core's message for one). Opened with a file that opened
 * (a segmentation or structure set of its series, in a PACS export's folder), it is the image the
 * contours were drawn on: set aside and counted, not listed as a refusal each.
 */
export function isImageRefusal(e: CoreErrorData): boolean {
  return isDicomImageRefusal(e) || (e.code === 'parse' && /this (NIfTI|NRRD|DICOM SEG) is an image, not a label map/.test(e.message));
}

/** A DICOM image refused as contours (the rest of [isImageRefusal]'s: scans in label-map formats, a Slicer scene's). */
export function isDicomImageRefusal(e: CoreErrorData): boolean {
  return e.code === 'parse' && /this is a DICOM image \(modality [^)]*\), not contours/.test(e.message);
}

/** The banner's note on `count` images (DICOM ones, or scans of other formats) opened with the file `shown`. */
export function imagesAsideText(count: number, shown: string, kind: 'DICOM image' | 'image' = 'DICOM image'): string {
  return `${count === 1 ? `1 ${kind}` : `${count} ${kind}s`} set aside: images, not contours (the contours come from ${shown}).`;
}

/**
 * A dropped file whose bytes could not be read: moved or without permission since the drop, or a
 * folder (a browser hands a dropped folder over as a file without type that fails to read; a
 * biv-me patient folder is the usual one).
 */
export function unreadable(file: { name: string; type: string }, e: unknown): CoreErrorData {
  if (file.type === '' && !/\.[A-Za-z0-9]{1,5}$/.test(file.name)) {
    return { code: 'app', file: file.name, message: 'a folder cannot be opened: open the files inside it (of a biv-me folder, its GPFile_*.txt)' };
  }
  return asCoreError(e, 'could not read the file', file.name);
}

/**
 * A stack refused because of one of the long-axis views read with it: the core starts its message
 * with that view's file name; the error is then the view's (its name where the file goes).
 */
export function viewRefusal(e: CoreErrorData, views: readonly string[]): CoreErrorData {
  const view = views.find((v) => e.message.startsWith(`${v}: `));
  return view ? { ...e, file: view, message: e.message.slice(view.length + 2) } : e;
}

/** Anything thrown or rejected, as the protocol's error data (with the file when known). */
export function asCoreError(e: unknown, fallback: string, file?: string): CoreErrorData {
  if (e && typeof e === 'object' && 'code' in e && 'message' in e) {
    const d = e as CoreErrorData;
    return { ...d, file: d.file ?? file };
  }
  const message = e instanceof Error ? e.message : typeof e === 'string' ? e : fallback;
  return { code: 'app', message: message || fallback, file };
}

/** Parameters in schema order (iterations, lambda, beta, ...), which reads better in file headers than the core's. */
export function schemaOrdered(params: ParamValues, schema: readonly ParamSpec[]): ParamValues {
  const ordered: ParamValues = {};
  for (const s of schema) if (params[s.name] !== undefined) ordered[s.name] = params[s.name];
  for (const k of Object.keys(params)) if (ordered[k] === undefined) ordered[k] = params[k];
  return ordered;
}

/** Runs a listener; an exception is logged, never propagated into the caller's bookkeeping. */
export function callSafely(f: () => void, what: string): void {
  try {
    f();
  } catch (e) {
    console.error(what, e);
  }
}

/** The banner's note on ZIP archives that could not be read (io/zipArchive.ts), each with why. */
export function archivesText(refused: readonly CoreErrorData[]): string {
  if (refused.length === 0) return '';
  const list = refused.map((e) => describeError(e)).join('; ');
  return `${refused.length === 1 ? '1 archive' : `${refused.length} archives`} not opened: ${list}.`;
}
