/**
 * 3D Slicer markups opened together. Slicer saves each markup node (a closed curve drawn on one
 * short-axis slice, a curve on a long-axis view) in a file of its own (`LV_ENDO_3.mrk.json`), so a
 * study is a folder of them: opened one file per entry, each would be a single curve the core
 * cannot reconstruct from. Dropped or picked together, they are joined here into one markups file
 * (`Slicer markups (32 files).mrk.json`), which the core reads as one set (heartmesh-core
 * `io::markups`, as the command line reads a folder of them). A file that is no valid markups JSON
 * is left out of the join and opened on its own, so the core's refusal names it and its line.
 *
 * Slicer's legacy point list files (`.fcsv`, one contour clicked point by point per file before
 * Slicer had curves) and its control points tables (`label,l,p,s,defined,...` CSV) join as the
 * point list Slicer itself makes of one when it loads it and saves it as `.mrk.json`; the core
 * then tells landmarks from contours (`point_list_is_contour`).
 */

/** What the core looks for in a file's start (heartmesh-core `io::markups::is_markups`). */
const SCHEMA_MARK = 'markups-schema';

/** How much of a file's start is looked into for it. */
const HEAD_BYTES = 4096;

/** How many of a point list file's first lines are looked into for its header (as the core). */
const FCSV_HEADER_LINES = 8;

/** A header comment's value when its key (compared without spaces and case) is `key`. */
function valueOf(comment: string, key: string): string | null {
  const at = comment.indexOf('=');
  if (at < 0) return null;
  return comment.slice(0, at).replace(/\s+/g, '').toLowerCase() === key.toLowerCase() ? comment.slice(at + 1).trim() : null;
}

function columnsOf(value: string): string[] {
  return value.split(',').map((c) => c.trim().toLowerCase());
}

/** Whether a text's start is a Slicer point list file's (`.fcsv`), as the core tells one (`io::markups::fcsv::is_fcsv`). */
export function isFcsvText(text: string): boolean {
  return text
    .replace(/^\uFEFF/, '')
    .split(/\r?\n|\r/)
    .slice(0, FCSV_HEADER_LINES)
    .map((l) => l.trimStart())
    .filter((l) => l.startsWith('#'))
    .some((l) => {
      const c = l.slice(1);
      if (c.toLowerCase().includes('markups fiducial file')) return true;
      const v = valueOf(c, 'columns');
      const names = v === null ? [] : columnsOf(v);
      return names[0] === 'id' && ['x', 'y', 'z'].every((w) => names.includes(w));
    });
}

/** Splits a row at commas outside double quotes (Slicer quotes a description holding commas). */
function fields(row: string): string[] {
  const out: string[] = [];
  let start = 0;
  let quoted = false;
  for (let i = 0; i < row.length; i++) {
    if (row[i] === '"') quoted = !quoted;
    else if (row[i] === ',' && !quoted) {
      out.push(row.slice(start, i));
      start = i + 1;
    }
  }
  out.push(row.slice(start));
  return out.map((f) => f.trim().replace(/^"(.*)"$/, '$1').trim());
}

/**
 * A point list file as the markups JSON point list Slicer makes of it (named `name`), or null when
 * a row cannot be read: such a file is opened alone, so the core's refusal names its line.
 */
export function fcsvMarkup(name: string, text: string): Record<string, unknown> | null {
  let frame = 'RAS'; // what the versions that stated no frame used
  let columns = ['id', 'x', 'y', 'z', 'ow', 'ox', 'oy', 'oz', 'vis', 'sel', 'lock', 'label', 'desc', 'associatednodeid'];
  const controlPoints: { label: string; position: number[] }[] = [];
  for (const raw of text.replace(/^\uFEFF/, '').split(/\r?\n|\r/)) {
    const row = raw.trim();
    if (row.startsWith('#')) {
      const system = valueOf(row.slice(1), 'CoordinateSystem');
      const cols = valueOf(row.slice(1), 'columns');
      if (system !== null) {
        const s = system.toUpperCase();
        if (s === 'RAS' || s === '0') frame = 'RAS';
        else if (s === 'LPS' || s === '1') frame = 'LPS';
        else return null;
      } else if (cols !== null) columns = columnsOf(cols);
      continue;
    }
    if (row === '') continue;
    const f = fields(row);
    const at = (c: string) => columns.indexOf(c);
    const position = [at('x'), at('y'), at('z')].map((k) => (k < 0 || k >= f.length || f[k] === '' ? NaN : Number(f[k].replace(/\u2212/g, '-'))));
    if (!position.every(Number.isFinite)) return null;
    const label = at('label') >= 0 ? (f[at('label')] ?? '') : '';
    controlPoints.push({ label: label || `${name}-${controlPoints.length + 1}`, position });
  }
  return { type: 'Fiducial', name, coordinateSystem: frame, controlPoints };
}

/** A control points table's header (Slicer's "export to table" saved as CSV): its columns, frame and coordinate columns; null for any other first line. */
function tableHeader(line: string): { columns: string[]; frame: string; xyz: number[] } | null {
  const columns = fields(line).map((c) => c.toLowerCase());
  if (columns[0] !== 'label') return null;
  for (const [frame, axes] of [['LPS', ['l', 'p', 's']], ['RAS', ['r', 'a', 's']]] as const) {
    const xyz = axes.map((a) => columns.indexOf(a));
    if (xyz.every((k) => k >= 0)) return { columns, frame, xyz };
  }
  return null;
}

/** The data lines of a text: not blank, not `#` comments. */
function dataLines(text: string): string[] {
  return text
    .replace(/^\uFEFF/, '')
    .split(/\r?\n|\r/)
    .filter((l) => l.trim() !== '' && !l.trimStart().startsWith('#'));
}

/** Whether a text is a Slicer control points table (`label,l,p,s,defined,...`), as the core tells one (`io::markups::points_table`). */
export function isPointsTableText(text: string): boolean {
  const first = dataLines(text.slice(0, HEAD_BYTES))[0];
  return first !== undefined && tableHeader(first) !== null;
}

/** A control points table as the markups JSON point list Slicer imports from it (points whose `defined` is 0 or false skipped), or null when a row cannot be read. */
export function tableMarkup(name: string, text: string): Record<string, unknown> | null {
  const [head, ...rows] = dataLines(text);
  const header = head === undefined ? null : tableHeader(head);
  if (header === null) return null;
  const at = (c: string) => header.columns.indexOf(c);
  const controlPoints: { label: string; position: number[] }[] = [];
  for (const row of rows) {
    const f = fields(row);
    if (at('defined') >= 0 && ['0', 'false', 'no'].includes((f[at('defined')] ?? '').toLowerCase())) continue;
    const position = header.xyz.map((k) => (k >= f.length || f[k] === '' ? NaN : Number(f[k].replace(/\u2212/g, '-'))));
    if (!position.every(Number.isFinite)) return null;
    controlPoints.push({ label: f[at('label')] || `${name}-${controlPoints.length + 1}`, position });
  }
  return { type: 'Fiducial', name, coordinateSystem: header.frame, controlPoints };
}

/** Whether a text is a point list file that is no JSON (a legacy `.fcsv` or a control points table). */
export function isPointListText(text: string): boolean {
  return isFcsvText(text) || isPointsTableText(text);
}

/** A point list file that is no JSON as the markup Slicer makes of it (null: damaged; the core names the line). */
export function pointListMarkup(name: string, text: string): Record<string, unknown> | null {
  return isFcsvText(text) ? fcsvMarkup(name, text) : tableMarkup(name, text);
}

/** Whether a file's first bytes are a Slicer markups file's (JSON, a legacy `.fcsv` or a control points table), as the core tells one. */
export function isMarkupsHead(head: Uint8Array): boolean {
  const text = new TextDecoder().decode(head.subarray(0, HEAD_BYTES)).replace(/^\uFEFF/, '').trimStart();
  if (!text.startsWith('{')) return isPointListText(text);
  const lower = text.toLowerCase();
  return lower.includes(SCHEMA_MARK) || (text.includes('"markups"') && text.includes('"controlPoints"'));
}

/** A file's name without `.mrk.json` / `.json` / `.fcsv` / `.csv`: the node's name in Slicer when it states none. */
export function markupsStem(name: string): string {
  const m = /^(.+?)((\.mrk)?\.json|\.fcsv|\.csv)$/i.exec(name);
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
  const candidates = files.filter((f) => /\.(json|fcsv|csv)$/i.test(f.name));
  if (candidates.length < 2) return unchanged;
  const found: Found<T>[] = [];
  for (const file of candidates) {
    const head = await headOf(file);
    if (!head || !isMarkupsHead(head)) continue;
    try {
      const text = await file.text();
      if (!text.trimStart().startsWith('{')) {
        // A legacy point list file or a control points table: the point list Slicer makes of it.
        const markup = pointListMarkup(markupsStem(file.name), text);
        if (markup) found.push({ file, doc: { markups: [markup] } });
        continue;
      }
      const doc = JSON.parse(text);
      if (doc && Array.isArray(doc.markups)) found.push({ file, doc });
    } catch {
      // Not valid JSON (or not readable): opened alone, the core says where it breaks.
    }
  }
  if (found.length < 2) return unchanged;
  found.sort((a, b) => (a.file.name < b.file.name ? -1 : a.file.name > b.file.name ? 1 : 0));
  const groups = studies(found, folderOf);
  const joined = groups.map((g) => joinedFile(g.found, joinedName(g.found.length, groups.length > 1 ? g.folder : '')));
  const used = new Set<T>(found.map((f) => f.file));
  return { files: [...joined, ...files.filter((f) => !used.has(f))], joined: found.length, names: joined.map((f) => f.name) };
}
