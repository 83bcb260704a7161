/**
 * 3D Slicer markups opened together. Slicer saves each markup node (a closed curve drawn on one
 * short-axis slice, a curve on a long-axis view) in a file of its own (`LV_ENDO_3.mrk.json`), so a
 * study is a folder of them: opened one file per entry, each would be a single curve the core
 * cannot reconstruct from. Dropped or picked together, they are joined here into one markups file
 * (`Slicer markups (32 files).mrk.json`), which the core reads as one set (heartmesh-core
 * `io::markups`, as the command line reads a folder of them). A file that is no valid markups JSON
 * is left out of the join and opened on its own, so the core's refusal names it and its line.
 */

/** What the core looks for in a file's start (heartmesh-core `io::markups::is_markups`). */
const SCHEMA_MARK = 'markups-schema';

/** How much of a file's start is looked into for it. */
const HEAD_BYTES = 4096;

/** Whether a file's first bytes are a Slicer markups file's, as the core tells one. */
export function isMarkupsHead(head: Uint8Array): boolean {
  const text = new TextDecoder().decode(head.subarray(0, HEAD_BYTES)).replace(/^\uFEFF/, '').trimStart();
  if (!text.startsWith('{')) return false;
  const lower = text.toLowerCase();
  return lower.includes(SCHEMA_MARK) || (text.includes('"markups"') && text.includes('"controlPoints"'));
}

/** A file's name without `.mrk.json` / `.json`: the node's name in Slicer when it states none. */
export function markupsStem(name: string): string {
  const m = /^(.+?)(\.mrk)?\.json$/i.exec(name);
  return m ? m[1] : name;
}

/** The joined file's name (`folder`: the folder it was joined from, when there are several). */
export function joinedName(count: number, folder = ''): string {
  // The folder first: a narrow file picker still tells the phases apart.
  return folder ? `${folder} (${count} Slicer markups).mrk.json` : `Slicer markups (${count} files).mrk.json`;
}

/** The banner's note on the files joined (`names`: one joined file per folder whose curves share names with another's). */
export function joinedText(count: number, names: readonly string[]): string {
  if (names.length === 1) return `${count} Slicer markups files were read as one contour set: ${names[0]}.`;
  return `${count} Slicer markups files were read as ${names.length} contour sets, one per folder (the folders' curves share names: a phase or a patient each): ${names.join(', ')}.`;
}

type Named = Blob & { name: string; lastModified: number };

async function headOf(file: Blob): Promise<Uint8Array | null> {
  try {
    return new Uint8Array(await file.slice(0, HEAD_BYTES).arrayBuffer());
  } catch {
    return null; // unreadable: opened (and refused, named) as any other file
  }
}

interface Found<T> {
  file: T;
  doc: { '@schema'?: unknown; markups: Record<string, unknown>[] };
}

/** Each markup named (by its file when it states no name), as the core names it. */
function named<T extends Named>({ file, doc }: Found<T>): Record<string, unknown>[] {
  const stem = markupsStem(file.name);
  return doc.markups.map((m, k) => {
    const has = typeof m?.name === 'string' && m.name.trim() !== '';
    const fallback = doc.markups.length > 1 ? `${stem}-${k + 1}` : stem;
    return has ? m : { ...m, name: fallback };
  });
}

/** One markups file holding every markup of `found` (name order), named `name`. */
function joinedFile<T extends Named>(found: Found<T>[], name: string): File {
  const schema = found.find((f) => typeof f.doc['@schema'] === 'string')?.doc['@schema'];
  return new File([JSON.stringify({ '@schema': schema ?? SCHEMA_MARK, markups: found.flatMap(named) })], name, {
    type: 'application/json',
    // The same files dropped again are the same file (the app tells open files by size and date).
    lastModified: Math.max(...found.map((f) => f.file.lastModified)),
  });
}

/**
 * `found` split by folder when two folders hold curves of the same name (a patient's ED/ and
 * ES/, two patients: joined, each curve would be a ring of each); else one group.
 */
function studies<T extends Named>(found: Found<T>[], folderOf: (f: T) => string): { folder: string; found: Found<T>[] }[] {
  const groups = new Map<string, Found<T>[]>();
  for (const f of found) {
    const folder = folderOf(f.file);
    groups.set(folder, [...(groups.get(folder) ?? []), f]);
  }
  const owner = new Map<string, string>();
  let shared = false;
  for (const [folder, members] of groups) {
    for (const m of members.flatMap(named)) {
      const id = String(m.name).trim();
      const first = owner.get(id);
      if (first === undefined) owner.set(id, folder);
      else if (first !== folder) shared = true;
    }
  }
  if (!shared) return [{ folder: '', found }];
  return [...groups].map(([folder, members]) => ({ folder: folder.slice(folder.lastIndexOf('/') + 1) || folder, found: members }));
}

/**
 * The markups among `files` joined into one file when there are two or more (in name order, as
 * the core orders a folder's; a markup without a `name` takes its file's), with every other file
 * as it was; `joined` counts the files joined (0: nothing joined, the files are as given).
 * `folderOf` gives each file's folder: folders whose curves share names are joined apart, one
 * file each (the core refuses them together for the same reason).
 */
export async function joinMarkups<T extends Named>(
  files: readonly T[],
  folderOf: (f: T) => string = () => '',
): Promise<{ files: (T | File)[]; joined: number; names: string[] }> {
  const unchanged = { files: [...files], joined: 0, names: [] };
  const candidates = files.filter((f) => /\.json$/i.test(f.name));
  if (candidates.length < 2) return unchanged;
  const found: Found<T>[] = [];
  for (const file of candidates) {
    const head = await headOf(file);
    if (!head || !isMarkupsHead(head)) continue;
    try {
      const doc = JSON.parse(await file.text());
      if (doc && Array.isArray(doc.markups)) found.push({ file, doc });
    } catch {
      // Not valid JSON: opened alone, the core says where it breaks.
    }
  }
  if (found.length < 2) return unchanged;
  found.sort((a, b) => (a.file.name < b.file.name ? -1 : a.file.name > b.file.name ? 1 : 0));
  const groups = studies(found, folderOf);
  const joined = groups.map((g) => joinedFile(g.found, joinedName(g.found.length, groups.length > 1 ? g.folder : '')));
  const used = new Set<T>(found.map((f) => f.file));
  return { files: [...joined, ...files.filter((f) => !used.has(f))], joined: found.length, names: joined.map((f) => f.name) };
}
