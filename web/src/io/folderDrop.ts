/**
 * Folders dropped on the page: a biv-me patient is a folder (`GPFile_000.txt` ... one per time
 * frame, and its `SliceInfoFile.txt`), and dragging the folder is what a user tries first (an ACDC
 * or M&Ms subject folder too: its `.nii.gz` label maps open, its images are set aside). The
 * browser hands a dropped folder over as an entry of the File and Directory Entries API
 * (`DataTransferItem.webkitGetAsEntry`); its files are read here and opened like a multi-file drop.
 * A cvi42 study's folder (a `.cvi42wsx` workspace with the DICOM images it was drawn on), or a
 * Sunnybrook case's (its contour files and image series), is read whole instead: its images are
 * what the contours need, whatever their names.
 */
import { ACCEPT } from './FileBar';
import { isPixelContourName } from './cvi42Study';
import { isSegmentationFile } from './dicomHeaders';

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
 * A cvi42 study's folder: every file in it is one of the workspace's images (io/cvi42Study.ts),
 * whatever its name (DICOM files often have none), as deep as a PACS export nests its series
 * (study / patient / date / series / image), at most this many; the app reads only their headers.
 */
export const STUDY_FILE_LIMIT = 4000;
const STUDY_DEPTH = 6;
/**
 * Files of a folder whose names say nothing (a PACS export's `IM000001`, or a SOP Instance UID)
 * looked into at most: each may be a DICOM segmentation, which is read (its header tells; an
 * image's pixels are not read). Past this many they are counted as not read.
 */
export const MAX_LOOKED_INTO = 1000;
/** Files looked at in the dropped folders at most (a home folder dropped by mistake ends here). */
const ENTRY_LIMIT = 20000;
/** Files handed over by the browser at once. */
const FILE_BATCH = 32;

/**
 * The Open dialog's extensions, but a bare `.gz`: in a folder, a compressed file is read only as
 * one of the kinds the core reads compressed (`seg.nii.gz`, `contours.csv.gz`); any other (an
 * tarball, a compressed image series) is clutter, left out and counted rather than read and refused.
 * A `.zip` is read: UK Biobank's subject folders hold their workspace and images zipped
 * (io/zipArchive.ts unpacks them).
 */
const EXTENSIONS = ACCEPT.split(',').filter((a) => a.startsWith('.') && a !== '.gz');

/** Whether a file found inside a folder is one the app may read (by its extension; not hidden). */
export function readableInFolder(name: string): boolean {
  if (name.startsWith('.')) return false;
  const lower = name.toLowerCase();
  const held = lower.endsWith('.gz') ? lower.slice(0, -'.gz'.length) : lower;
  return EXTENSIONS.some((ext) => lower.endsWith(ext) || held.endsWith(ext));
}

/** A file found in what was dropped or picked: `depth` 0 beside the folders, 1 in one, ... */
export interface FoundFile<T> {
  item: T;
  /** Its path from the dropped or picked folder, that folder's name first (`patient1/GPFile_000.txt`). */
  path: string;
  depth: number;
}

/** Which of the files found are opened, how many are not (`skipped`), and whether they are a cvi42 study. */
export interface FolderSelection<T> {
  kept: T[];
  skipped: number;
  study: boolean;
  /**
   * Files of no readable kind by name whose names say nothing (`nameless`): opened if their
   * header says they are DICOM segmentations (`withSegmentations`), else counted as skipped.
   */
  unnamed: T[];
}

/** A name that says nothing of a file's kind: no extension, or a DICOM UID (digits and dots). */
export function nameless(name: string): boolean {
  return !name.includes('.') || /^[0-9.]+$/.test(name);
}

/**
 * `selection` with its `unnamed` files that are DICOM segmentations added to the files kept
 * (the others counted as skipped); `fileOf` gives each one's File.
 */
export async function withSegmentations<T>(selection: FolderSelection<T>, fileOf: (item: T) => Promise<File | null>): Promise<FolderSelection<T>> {
  const kept = [...selection.kept];
  let skipped = selection.skipped;
  for (const item of selection.unnamed) {
    const file = await fileOf(item);
    if (file && (await isSegmentationFile(file).catch(() => false))) kept.push(item);
    else skipped++;
  }
  return { ...selection, kept, skipped, unnamed: [] };
}

/**
 * The files of folders that are opened. Files given beside the folders always are. With a cvi42
 * workspace among them, or when the app waits for the images of one refused without them
 * (`images`), every file in the folders (not hidden, nor in a hidden folder) is one of its
 * images, up to `STUDY_FILE_LIMIT`; else those of the readable kinds (`readableInFolder`) up to
 * `limit`, those whose names say nothing set apart to be looked into (`unnamed`: a PACS export's
 * segmentations), the others within `MAX_DEPTH` counted as skipped.
 */
export function selectFolderFiles<T>(found: readonly FoundFile<T>[], limit = FOLDER_FILE_LIMIT, images = false): FolderSelection<T> {
  const name = (f: FoundFile<T>) => f.path.slice(f.path.lastIndexOf('/') + 1);
  const study = images || found.some((f) => isPixelContourName(name(f)));
  const kept: T[] = [];
  const unnamed: T[] = [];
  let fromFolders = 0;
  let skipped = 0;
  for (const f of found) {
    if (f.depth === 0) {
      kept.push(f.item);
      continue;
    }
    if (f.depth > (study ? STUDY_DEPTH : MAX_DEPTH)) continue;
    const hidden = f.path.split('/').some((part) => part.startsWith('.'));
    const wanted = study ? !hidden : readableInFolder(name(f));
    const full = fromFolders >= (study ? STUDY_FILE_LIMIT : limit);
    if (!study && !wanted && !hidden && !full && nameless(name(f)) && unnamed.length < MAX_LOOKED_INTO) {
      unnamed.push(f.item);
    } else if (!wanted || full) {
      skipped++;
    } else {
      kept.push(f.item);
      fromFolders++;
    }
  }
  return { kept, skipped, study, unnamed };
}

/** Paths of the files of dropped folders (a dropped file has none), for telling apart files of one name. */
const paths = new WeakMap<File, string>();

/** The path in its dropped or picked folder of a file (null: given as it is). */
export function pathInFolder(file: File): string | null {
  return paths.get(file) ?? (file.webkitRelativePath || null);
}

/** The folder a file came from (its path without its name; '' for a file given alone). */
export function folderOfFile(file: File): string {
  const path = pathInFolder(file) ?? '';
  const at = path.lastIndexOf('/');
  return at < 0 ? '' : path.slice(0, at);
}

/** Records where a file came from: a ZIP archive's member is `1234_images.zip/dicom/IM_01_00.dcm` (io/zipArchive.ts). */
export function setPathInFolder(file: File, path: string): void {
  paths.set(file, path);
}

/**
 * The files of `entries` (files as they are, folders walked in name order), as
 * `selectFolderFiles` keeps them (`images`: the app waits for a workspace's images); `skipped`
 * counts what a folder held beyond that or of other kinds, `study` says they were read as a
 * cvi42 study's.
 */
export async function filesOfEntries(entries: readonly EntryLike[], limit = FOLDER_FILE_LIMIT, images = false): Promise<{ files: File[]; skipped: number; study: boolean }> {
  const found: FoundFile<EntryLike>[] = [];
  const walk = async (entry: EntryLike, path: string, depth: number): Promise<void> => {
    if (found.length >= ENTRY_LIMIT) return;
    if (entry.isFile && entry.file) found.push({ item: entry, path, depth });
    else if (entry.isDirectory && entry.createReader && depth < STUDY_DEPTH) {
      for (const child of await readAll(entry)) await walk(child, `${path}/${child.name}`, depth + 1);
    }
  };
  for (const entry of entries) await walk(entry, entry.name, 0);
  const fileOf = (e: EntryLike) => new Promise<File | null>((ok) => (e.file ? e.file(ok, () => ok(null)) : ok(null)));
  // Of a folder's nameless files, the DICOM segmentations (a PACS export's) are opened too.
  const { kept, skipped, study } = await withSegmentations(selectFolderFiles(found, limit, images), fileOf);
  const pathOf = new Map(found.map((f) => [f.item, f.path]));
  const files: File[] = [];
  for (let start = 0; start < kept.length; start += FILE_BATCH) {
    const part = kept.slice(start, start + FILE_BATCH);
    const got = await Promise.all(part.map(fileOf));
    got.forEach((file, k) => {
      if (!file) return;
      const path = pathOf.get(part[k]);
      if (path?.includes('/')) paths.set(file, path);
      files.push(file);
    });
  }
  return { files, skipped, study };
}

/**
 * The files of a picked folder (`<input type="file" webkitdirectory>`: every file under it, each
 * with its `webkitRelativePath`), in path order, as `selectFolderFiles` keeps them.
 */
export function filesOfPickedFolder(picked: readonly File[], limit = FOLDER_FILE_LIMIT, images = false): FolderSelection<File> {
  const found = picked
    .map((f) => {
      const path = f.webkitRelativePath || f.name;
      return { item: f, path, depth: path.split('/').length - 1 };
    })
    .sort((a, b) => a.path.localeCompare(b.path, undefined, { numeric: true }));
  return selectFolderFiles(found, limit, images);
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
