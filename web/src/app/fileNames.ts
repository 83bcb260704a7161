/**
 * The names the app keys opened files by (the File picker, the core client, the worker's session).
 * Every biv-me patient folder has a `GPFile_000.txt`: a different file whose name is already open
 * is kept beside it as `GPFile_000 (2).txt` (the download managers' convention, the extension kept
 * so the core still reads the format from it), never silently put in its place. The same file
 * opened again (same name, size and modification time: the browser gives no path) replaces its
 * own entry, as a bundled example clicked again does.
 */
import { splitExtension } from '../io/fileExtension';
import { FOLDER_FILE_LIMIT, STUDY_FILE_LIMIT } from '../io/folderDrop';

/** What tells two files of one name apart: a File's size and modification time, or a tag. */
export function fileIdentity(f: { size: number; lastModified: number }): string {
  return `file:${f.size}:${f.lastModified}`;
}

/**
 * `name`, or `name (2)`, `name (3)`, ... before the extension: the first that is not open, or is
 * open with this same `identity` (`open` maps the names in use to their identities).
 */
export function distinctName(name: string, identity: string, open: ReadonlyMap<string, string>): string {
  const free = (n: string) => !open.has(n) || open.get(n) === identity;
  if (free(name)) return name;
  const [stem, ext] = splitExtension(name);
  for (let k = 2; ; k++) {
    const candidate = `${stem} (${k})${ext}`;
    if (free(candidate)) return candidate;
  }
}

/** The note that says which names were given to files whose name was already open. */
export function renamedText(renamed: readonly { given: string; as: string }[]): string {
  if (renamed.length === 0) return '';
  const list = renamed.map((r) => `${r.given} as ${r.as}`).join(', ');
  return renamed.length === 1
    ? `A file named ${renamed[0].given} was already open: this one is listed as ${renamed[0].as} in the File picker.`
    : `Files with names already open are listed under new names in the File picker: ${list}.`;
}

/**
 * The banner's note on files of dropped folders that were not read (see `io/folderDrop.ts`); of a
 * cvi42 study's folder (`study`), every file is read but hidden ones and those past the limit.
 */
export function skippedText(skipped: number, study = false): string {
  if (skipped <= 0) return '';
  if (study) {
    const what = skipped === 1 ? '1 other file in the dropped folder was' : `${skipped} other files in the dropped folder were`;
    return `${what} not read (hidden, or past the first ${STUDY_FILE_LIMIT} files).`;
  }
  return skipped === 1
    ? `1 other file in the dropped folder was not read (not a contour file, or past the first ${FOLDER_FILE_LIMIT} files).`
    : `${skipped} other files in the dropped folder were not read (not contour files, or past the first ${FOLDER_FILE_LIMIT} files).`;
}

/** The banner's note on images of a cvi42 study that could not be read (moved since the drop). */
export function lostText(names: readonly string[]): string {
  if (names.length === 0) return '';
  const shown = names.slice(0, 3).join(', ') + (names.length > 3 ? ', ...' : '');
  return `${names.length === 1 ? '1 file' : `${names.length} files`} could not be read (${shown}): moved, or without permission.`;
}
