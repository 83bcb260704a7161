/**
 * biv-me patient folders: each GPFile (guide points) is read with the `SliceInfoFile.txt` beside
 * it, as the command line reads it, so the core checks every contour against its image's plane
 * (a SliceInfoFile of another acquisition, through-plane motion correction). Told by content, as
 * the core tells them; the SliceInfoFile goes to the worker as the GPFile's companion (the
 * channel a label map's long-axis views take) instead of being opened, and refused, as contours.
 */

/** How much of a file is read to tell what it is (the core's `detect_contour_format` reads 4 KiB). */
const HEAD_BYTES = 4096;

/** Whether a text file's head is a biv-me SliceInfoFile (the core's `looks_like_slice_info`). */
export function isSliceInfoText(head: string): boolean {
  return head.includes('ImagePositionPatient') && head.includes('ImageOrientationPatient');
}

/** biv-me's single-point row types and its curves of no ventricle (the core's `is_landmark`, `not_a_surface`). */
function isGpPointOrOther(kind: string): boolean {
  return (
    /^(MITRAL_VALVE|TRICUSPID_VALVE|AORTA_VALVE|PULMONARY_VALVE|APEX_POINT|RV_INSERT)$/.test(kind) ||
    /_(PHANTOM|EXTENT)$/.test(kind) ||
    /^APEX_.*_POINT$/.test(kind) ||
    /^(LA|RA|RV_OUTLET|REMOVED|EXCLUDED|OUTLET_.*)$/.test(kind)
  );
}

/**
 * Whether a text file's head is a GPFile (the core's `looks_like_gpfile`): a header naming the
 * contour type, or a first row of three numbers and a SAX_/LAX_ contour type or a biv-me point.
 */
export function isGpFileText(head: string): boolean {
  const first = head.replace(/^\uFEFF/, '').split(/\r\n|\r|\n/).find((l) => l.trim() !== '');
  if (first === undefined) return false;
  const lower = first.toLowerCase();
  if (lower.includes('contour type') || lower.includes('contour_type')) return true;
  const f = first.includes('\t') ? first.split('\t').map((v) => v.trim()) : first.includes(',') ? first.split(',').map((v) => v.trim()) : first.trim().split(/\s+/);
  return f.length >= 4 && f.slice(0, 3).every((v) => v !== '' && Number.isFinite(Number(v))) && (/^(SAX|LAX)_/.test(f[3]) || isGpPointOrOther(f[3]));
}

async function headOf(file: File): Promise<string | null> {
  if (!/\.txt$/i.test(file.name)) return null;
  try {
    return new TextDecoder().decode(await file.slice(0, HEAD_BYTES).arrayBuffer());
  } catch {
    return null; // unreadable: opened (and refused, named) as any other file
  }
}

export interface GpStudy {
  /** The files to open: those given, less the SliceInfoFiles read with a GPFile. */
  files: File[];
  /** Each GPFile's SliceInfoFile (the one in its folder). */
  sliceInfo: Map<File, File>;
}

/**
 * Pairs each GPFile with the SliceInfoFile of its folder (`folderOf`: a dropped file's folder).
 * A folder with no GPFile, or with two SliceInfoFiles, keeps its files as they are (the core
 * names a SliceInfoFile opened alone as such).
 */
export async function pairSliceInfo(given: readonly File[], folderOf: (f: File) => string): Promise<GpStudy> {
  const infos = new Map<string, File[]>();
  const gpFiles: File[] = [];
  for (const file of given) {
    const head = await headOf(file);
    if (head === null) continue;
    if (isSliceInfoText(head)) infos.set(folderOf(file), [...(infos.get(folderOf(file)) ?? []), file]);
    else if (isGpFileText(head)) gpFiles.push(file);
  }
  const sliceInfo = new Map<File, File>();
  const used = new Set<File>();
  for (const gp of gpFiles) {
    const here = infos.get(folderOf(gp)) ?? [];
    if (here.length !== 1) continue;
    sliceInfo.set(gp, here[0]);
    used.add(here[0]);
  }
  return { files: given.filter((f) => !used.has(f)), sliceInfo };
}

/** The banner's note on the SliceInfoFiles read with GPFiles (`pairs`: GPFile name, SliceInfoFile name). */
export function sliceInfoReadText(pairs: readonly { gp: string; info: string }[]): string {
  if (pairs.length === 0) return '';
  const infos = new Set(pairs.map((p) => p.info));
  const gps = pairs.map((p) => p.gp);
  const which = infos.size === 1 ? [...infos][0] : `${infos.size} SliceInfoFiles`;
  const named = gps.length <= 3 ? gps.join(', ') : `${gps.slice(0, 3).join(', ')} and ${gps.length - 3} more`;
  return `${which} read with ${named}: each contour checked against its image plane.`;
}
