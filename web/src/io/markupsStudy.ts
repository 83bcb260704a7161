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

/** The joined file's name. */
export function joinedName(count: number): string {
  return `Slicer markups (${count} files).mrk.json`;
}

/** The banner's note on the files joined. */
export function joinedText(count: number, name: string): string {
  return `${count} Slicer markups files were read as one contour set: ${name}.`;
}

type Named = Blob & { name: string; lastModified: number };

async function headOf(file: Blob): Promise<Uint8Array | null> {
  try {
    return new Uint8Array(await file.slice(0, HEAD_BYTES).arrayBuffer());
  } catch {
    return null; // unreadable: opened (and refused, named) as any other file
  }
}

/**
 * The markups among `files` joined into one file when there are two or more (in name order, as
 * the core orders a folder's; a markup without a `name` takes its file's), with every other file
 * as it was; `joined` counts the files joined (0: nothing joined, the files are as given).
 */
export async function joinMarkups<T extends Named>(files: readonly T[]): Promise<{ files: (T | File)[]; joined: number; name: string | null }> {
  const unchanged = { files: [...files], joined: 0, name: null };
  const candidates = files.filter((f) => /\.json$/i.test(f.name));
  if (candidates.length < 2) return unchanged;
  const found: { file: T; doc: { '@schema'?: unknown; markups: Record<string, unknown>[] } }[] = [];
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
  const markups = found.flatMap(({ file, doc }) => {
    const stem = markupsStem(file.name);
    return doc.markups.map((m, k) => {
      const named = typeof m?.name === 'string' && m.name.trim() !== '';
      const fallback = doc.markups.length > 1 ? `${stem}-${k + 1}` : stem;
      return named ? m : { ...m, name: fallback };
    });
  });
  const schema = found.find((f) => typeof f.doc['@schema'] === 'string')?.doc['@schema'];
  const name = joinedName(found.length);
  const joined = new File([JSON.stringify({ '@schema': schema ?? SCHEMA_MARK, markups })], name, {
    type: 'application/json',
    // The same files dropped again are the same file (the app tells open files by size and date).
    lastModified: Math.max(...found.map((f) => f.file.lastModified)),
  });
  const used = new Set<T>(found.map((f) => f.file));
  return { files: [joined, ...files.filter((f) => !used.has(f))], joined: found.length, name };
}
