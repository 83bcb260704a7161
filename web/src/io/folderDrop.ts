/**
 * Folders dropped on the page: a biv-me patient is a folder (`GPFile_000.txt` ... one per time
 * frame, and its `SliceInfoFile.txt`), and dragging the folder is what a user tries first (an ACDC
 * or M&Ms subject folder too: its `.nii.gz` label maps open, its images are refused by name). The
 * browser hands a dropped folder over as an entry of the File and Directory Entries API
 * (`DataTransferItem.webkitGetAsEntry`); its files are read here and opened like a multi-file drop.
 */
import { ACCEPT } from './FileBar';

/** The parts of a `FileSystemEntry` the walk uses (an interface, so tests can hand in their own). */
export interface EntryLike {
  readonly isFile: boolean;
  readonly isDirectory: boolean;
  readonly name: string;
  file?(ok: (f: File) => void, fail: (e: unknown) => void): void;
  createReader?(): { readEntries(ok: (entries: EntryLike[]) => void, fail: (e: unknown) => void): void };
}

/**
 * At most this many files come out of one drop's folders: a folder of DICOM images or a whole
 * study would otherwise queue thousands of reads for the files a contour reader refuses anyway.
 */
export const FOLDER_FILE_LIMIT = 200;
/** Folders inside folders are followed this deep (a patient folder inside a study folder). */
const MAX_DEPTH = 3;

/**
 * The Open dialog's extensions, but a bare `.gz`: in a folder, a compressed file is read only as
 * one of the kinds the core reads compressed (`seg.nii.gz`, `contours.csv.gz`); any other (an
 * archive, a compressed image series) is clutter, left out and counted rather than read and refused.
 */
const EXTENSIONS = ACCEPT.split(',').filter((a) => a.startsWith('.') && a !== '.gz');

/** Whether a file found inside a folder is one the app may read (by its extension; not hidden). */
export function readableInFolder(name: string): boolean {
  if (name.startsWith('.')) return false;
  const lower = name.toLowerCase();
  const held = lower.endsWith('.gz') ? lower.slice(0, -'.gz'.length) : lower;
  return EXTENSIONS.some((ext) => lower.endsWith(ext) || held.endsWith(ext));
}

/**
 * The files of `entries` (files as they are, folders walked in name order, keeping only the
 * readable kinds), at most `limit` from folders; `skipped` counts what a folder held beyond that
 * or of other kinds.
 */
export async function filesOfEntries(entries: readonly EntryLike[], limit = FOLDER_FILE_LIMIT): Promise<{ files: File[]; skipped: number }> {
  const files: File[] = [];
  let fromFolders = 0;
  let skipped = 0;
  const walk = async (entry: EntryLike, depth: number): Promise<void> => {
    if (entry.isFile && entry.file) {
      if (depth > 0 && (!readableInFolder(entry.name) || fromFolders >= limit)) {
        skipped++;
        return;
      }
      const file = await new Promise<File | null>((ok) => entry.file?.(ok, () => ok(null)));
      if (file) {
        files.push(file);
        if (depth > 0) fromFolders++;
      }
    } else if (entry.isDirectory && entry.createReader && depth < MAX_DEPTH) {
      for (const child of await readAll(entry)) await walk(child, depth + 1);
    }
  };
  for (const entry of entries) await walk(entry, 0);
  return { files, skipped };
}

/** Every entry of a folder, in name order (`readEntries` hands them over in batches until empty). */
async function readAll(dir: EntryLike): Promise<EntryLike[]> {
  const reader = dir.createReader?.();
  if (!reader) return [];
  const out: EntryLike[] = [];
  for (;;) {
    const batch = await new Promise<EntryLike[]>((ok) => reader.readEntries(ok, () => ok([])));
    if (batch.length === 0) break;
    out.push(...batch);
  }
  return out.sort((a, b) => a.name.localeCompare(b.name, undefined, { numeric: true }));
}

/**
 * The drop's entries when it holds a folder (read synchronously: the items are gone once the drop
 * event returns), else null: plain files are taken from `dataTransfer.files` as before.
 */
export function folderEntries(data: DataTransfer | null): EntryLike[] | null {
  const items = Array.from(data?.items ?? []).filter((i) => i.kind === 'file');
  const entries = items.map((i) => (typeof i.webkitGetAsEntry === 'function' ? (i.webkitGetAsEntry() as EntryLike | null) : null));
  if (!entries.some((e) => e?.isDirectory)) return null;
  return entries.filter((e): e is EntryLike => e !== null);
}
