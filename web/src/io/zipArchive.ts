/**
 * ZIP archives opened in the page, as studies are handed out: UK Biobank delivers each subject's
 * cvi42 workspace (`1234_cvi42.zip`) and each DICOM series (`1234_20209_2_0.zip`) as a `.zip`.
 * An archive dropped, opened or found in a folder (told by its first bytes, not its name) is
 * replaced by the files in it before anything else looks at them: a workspace among them makes
 * the others its images (io/cvi42Study.ts), a zipped contour file opens as that file.
 *
 * Memory: an image series' archive is 50-100 MB of pixels, and the core needs each image's header
 * only (io/dicomHeaders.ts). So the archive is read in slices of the File, never whole, member by
 * member: a DICOM member is inflated until its pixel data begins and the rest is never touched;
 * any other member (the workspace, a contour file, a DICOM file without pixels such as an RT
 * structure set) is kept whole, its CRC checked.
 *
 * Bounds, as the core's reader (heartmesh-core `io::zip`): members are found through the central
 * directory (PKWARE APPNOTE 4.3.12, 4.3.16), stored or deflated (fflate's streaming Inflate); every
 * offset is checked against the archive; no member inflates past the size it declares, nor past
 * `MAX_MEMBER` kept whole, and one opening inflates at most `MAX_UNPACKED` bytes in all: a damaged,
 * encrypted or bomb archive is refused with a message naming it, the page goes on.
 */
import { Inflate } from 'fflate';
import type { CoreErrorData } from '../core-client/protocol';
import { isSegmentationHeader, looksDicom, pixelDataOffset } from './dicomHeaders';
import { STUDY_FILE_LIMIT, pathInFolder, setPathInFolder } from './folderDrop';

/** Most bytes inflated for one opening, over all its archives (the core's cap for one archive). */
export const MAX_UNPACKED = 2 ** 30;
/** Most bytes of one member kept whole (a workspace, a contour file; a DICOM file without pixel data). */
export const MAX_MEMBER = 256 * 2 ** 20;
/** Most files taken from one archive (as from a study's folder). */
export const MAX_MEMBERS = STUDY_FILE_LIMIT;

const LOCAL = 0x04034b50;
const CENTRAL = 0x02014b50;
const END = 0x06054b50;
/** Bytes of the archive read at once (several small members' worth). */
const WINDOW = 256 * 1024;
/** Compressed bytes inflated at once: at deflate's largest ratio (1032:1), at most 16 MiB out. */
const PIECE = 16 * 1024;
/** Inflated bytes between two pauses that let the page draw. */
const PAUSE_EVERY = 8 * 2 ** 20;

/**
 * Containers that are ZIP archives inside but no archive of files to open (a spreadsheet, numpy's
 * `.npz`): handed over as they are, and the core says what they are.
 */
const NOT_ARCHIVES = /\.(xlsx|xlsm|docx|pptx|odt|ods|odp|npz|jar|apk|epub)$/i;

/** Why an archive is refused (the message follows "ZIP archive: "). */
export class ZipError extends Error {}

/** Whether bytes (the first 4 are enough) begin a ZIP archive: a local file header, or an empty archive's end. */
export function looksZip(head: Uint8Array): boolean {
  return head.length >= 4 && head[0] === 0x50 && head[1] === 0x4b && ((head[2] === 3 && head[3] === 4) || (head[2] === 5 && head[3] === 6));
}

/** A member's path with `/` between folders (some Windows packers write `\`), without a leading `./`. */
export function memberPath(raw: string): string {
  return raw.replace(/\\/g, '/').replace(/^(\.\/)+/, '');
}

/** Folders, macOS' resource forks (`__MACOSX/`) and hidden files (or files in hidden folders): not opened. */
export function isClutter(path: string): boolean {
  if (path.endsWith('/')) return true;
  return path.split('/').some((part) => part === '__MACOSX' || part.startsWith('.'));
}

/** One file of an archive as the central directory describes it. */
interface Entry {
  path: string;
  flags: number;
  method: number;
  crc: number;
  /** Its bytes in the archive. */
  packed: number;
  /** Its bytes unpacked, as declared. */
  size: number;
  /** Where its local header begins. */
  local: number;
  /** Its modification time (ms since 1970, read as local time). */
  modified: number;
}

/** A file taken from an archive: its path inside it, its bytes (a DICOM file's header only), its time. */
export interface ZipMember {
  path: string;
  bytes: Uint8Array<ArrayBuffer>;
  lastModified: number;
}

/** What is left to inflate of the opening's `MAX_UNPACKED` bytes (shared by its archives). */
export interface Budget {
  left: number;
}

const u16 = (b: Uint8Array, at: number) => b[at] | (b[at + 1] << 8);
const u32 = (b: Uint8Array, at: number) => (b[at] | (b[at + 1] << 8) | (b[at + 2] << 16) | (b[at + 3] << 24)) >>> 0;
const mib = (n: number) => `${Math.round(n / 2 ** 20)} MiB`;
const pause = () => new Promise<void>((ok) => setTimeout(ok, 0));

/** A DOS date and time (the archive's) as ms since 1970; 0 when unset. */
function dosTime(date: number, time: number): number {
  if (date === 0) return 0;
  return new Date(1980 + (date >> 9), ((date >> 5) & 15) - 1, date & 31, time >> 11, (time >> 5) & 63, (time & 31) * 2).getTime();
}

/** Reads parts of a Blob, a window at a time (members laid out one after another share a read). */
class BlobReader {
  private start = 0;
  private bytes = new Uint8Array(0);
  constructor(private readonly blob: Blob) {}

  get size(): number {
    return this.blob.size;
  }

  async read(at: number, length: number, what: string): Promise<Uint8Array> {
    if (at < 0 || length < 0 || at + length > this.blob.size) throw new ZipError(`${what} runs past the end (byte ${at + length} of ${this.blob.size}): truncated`);
    if (at >= this.start && at + length <= this.start + this.bytes.length) return this.bytes.subarray(at - this.start, at - this.start + length);
    const end = Math.min(this.blob.size, at + Math.max(length, WINDOW));
    this.bytes = new Uint8Array(await this.blob.slice(at, end).arrayBuffer());
    this.start = at;
    return this.bytes.subarray(0, length);
  }
}

/** The central directory: every member but the clutter, in its order. */
async function centralDirectory(reader: BlobReader): Promise<Entry[]> {
  const tailLength = Math.min(reader.size, 22 + 0xffff);
  const tail = await reader.read(reader.size - tailLength, tailLength, 'the end record');
  let end = -1;
  for (let i = tail.length - 22; i >= 0; i--) {
    if (u32(tail, i) === END) {
      end = i;
      break;
    }
  }
  if (end < 0) throw new ZipError('no end of central directory: truncated or not an archive');
  const count = u16(tail, end + 10);
  const dirSize = u32(tail, end + 12);
  const dirAt = u32(tail, end + 16);
  if (count === 0xffff || dirSize === 0xffffffff || dirAt === 0xffffffff) throw new ZipError('a ZIP64 archive (over 4 GB or 65535 files): unpack it first');
  const dir = await reader.read(dirAt, dirSize, 'the central directory');
  const names = new TextDecoder();
  const entries: Entry[] = [];
  let at = 0;
  for (let k = 0; k < count; k++) {
    if (at + 46 > dir.length || u32(dir, at) !== CENTRAL) throw new ZipError(`central directory entry expected at byte ${dirAt + at}: damaged`);
    const nameLength = u16(dir, at + 28);
    const next = at + 46 + nameLength + u16(dir, at + 30) + u16(dir, at + 32);
    if (next > dir.length) throw new ZipError(`central directory entry at byte ${dirAt + at} runs past the directory: damaged`);
    const path = memberPath(names.decode(dir.subarray(at + 46, at + 46 + nameLength)));
    const entry: Entry = {
      path,
      flags: u16(dir, at + 8),
      method: u16(dir, at + 10),
      modified: dosTime(u16(dir, at + 14), u16(dir, at + 12)),
      crc: u32(dir, at + 16),
      packed: u32(dir, at + 20),
      size: u32(dir, at + 24),
      local: u32(dir, at + 42),
    };
    at = next;
    if (isClutter(path)) continue;
    if (entry.packed === 0xffffffff || entry.size === 0xffffffff || entry.local === 0xffffffff) throw new ZipError(`${path} is a ZIP64 member (over 4 GB): unpack it first`);
    if (entry.flags & 1) throw new ZipError(`${path} is encrypted: unpack it first`);
    if (entry.method !== 0 && entry.method !== 8) throw new ZipError(`${path} is packed with method ${entry.method}; only stored and deflated files are read`);
    entries.push(entry);
  }
  return entries;
}

/** A byte buffer that grows as inflated pieces come in. */
class Growing {
  private buffer = new Uint8Array(0);
  length = 0;

  push(piece: Uint8Array): void {
    if (this.length + piece.length > this.buffer.length) {
      const bigger = new Uint8Array(Math.max(this.buffer.length * 2, this.length + piece.length, 4096));
      bigger.set(this.buffer.subarray(0, this.length));
      this.buffer = bigger;
    }
    this.buffer.set(piece, this.length);
    this.length += piece.length;
  }

  view(): Uint8Array {
    return this.buffer.subarray(0, this.length);
  }

  /** The first `n` bytes, in a buffer of their own (the rest let go). */
  take(n: number): Uint8Array<ArrayBuffer> {
    return this.buffer.slice(0, n);
  }
}

let crcTable: Uint32Array | null = null;

/** CRC-32 (ISO 3309, as ZIP stores it). */
export function crc32(bytes: Uint8Array): number {
  if (!crcTable) {
    crcTable = new Uint32Array(256);
    for (let n = 0; n < 256; n++) {
      let c = n;
      for (let k = 0; k < 8; k++) c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1;
      crcTable[n] = c >>> 0;
    }
  }
  let c = 0xffffffff;
  for (let i = 0; i < bytes.length; i++) c = crcTable[(c ^ bytes[i]) & 0xff] ^ (c >>> 8);
  return (c ^ 0xffffffff) >>> 0;
}

/**
 * One member's bytes: a DICOM image's up to where its pixel data begins (the rest is not
 * inflated), any other whole (its size and CRC checked), a DICOM segmentation included.
 */
async function unpackMember(reader: BlobReader, e: Entry, budget: Budget): Promise<Uint8Array<ArrayBuffer>> {
  const head = await reader.read(e.local, 30, `${e.path}'s local header`);
  if (u32(head, 0) !== LOCAL) throw new ZipError(`${e.path}: no local header at byte ${e.local}: damaged`);
  const dataAt = e.local + 30 + u16(head, 26) + u16(head, 28);
  const dataEnd = dataAt + e.packed;
  if (dataEnd > reader.size) throw new ZipError(`${e.path} runs past the end (byte ${dataEnd} of ${reader.size}): truncated`);
  const out = new Growing();
  let dicom: boolean | null = null;
  let scanned = 0;
  let sincePause = 0;
  const inflater = e.method === 8 ? new Inflate((piece) => out.push(piece)) : null;
  for (let at = dataAt; ; ) {
    const n = Math.min(PIECE, dataEnd - at);
    const piece = await reader.read(at, n, e.path);
    at += n;
    const final = at >= dataEnd;
    const before = out.length;
    if (inflater) {
      try {
        inflater.push(piece, final);
      } catch {
        throw new ZipError(`${e.path}: corrupt deflate data: damaged`);
      }
    } else {
      out.push(piece);
    }
    const grown = out.length - before;
    budget.left -= grown;
    sincePause += grown;
    if (out.length > e.size) throw new ZipError(`${e.path} unpacks to more than the ${e.size} bytes the archive says: damaged`);
    if (budget.left < 0) throw new ZipError(`${e.path}: the archives unpack to more than the ${mib(MAX_UNPACKED)} read at once (a zip bomb?)`);
    if (dicom === null && (out.length >= 132 || final)) {
      dicom = looksDicom(out.view());
      if (!dicom && e.size > MAX_MEMBER) throw new ZipError(`${e.path} unpacks to ${mib(e.size)}, more than the ${mib(MAX_MEMBER)} read of one file`);
    }
    if (dicom) {
      const pixels = pixelDataOffset(out.view(), e.size, scanned);
      // A segmentation's pixels are its label map: read it whole, as any other file.
      if (pixels >= 0 && isSegmentationHeader(out.view().subarray(0, pixels))) {
        dicom = false;
        if (e.size > MAX_MEMBER) throw new ZipError(`${e.path} unpacks to ${mib(e.size)}, more than the ${mib(MAX_MEMBER)} read of one file`);
      } else if (pixels >= 0) return out.take(pixels);
      scanned = Math.max(0, out.length - 8);
      if (out.length > MAX_MEMBER) throw new ZipError(`${e.path}: no pixel data in its first ${mib(MAX_MEMBER)}`);
    }
    if (final) break;
    if (sincePause >= PAUSE_EVERY) {
      sincePause = 0;
      await pause();
    }
  }
  if (out.length !== e.size) throw new ZipError(`${e.path} unpacks to ${out.length} bytes, not the ${e.size} the archive says: damaged`);
  const bytes = out.take(out.length);
  if (crc32(bytes) !== e.crc) throw new ZipError(`${e.path}: CRC mismatch: damaged`);
  return bytes;
}

/**
 * The files of an archive (folders, `__MACOSX/` and hidden files left out), in its order, DICOM
 * files as their headers; throws a `ZipError` saying why it cannot be read.
 */
export async function zipMembers(archive: Blob, budget: Budget = { left: MAX_UNPACKED }): Promise<ZipMember[]> {
  const reader = new BlobReader(archive);
  const entries = await centralDirectory(reader);
  if (entries.length === 0) throw new ZipError('holds no files (only folders, or hidden files)');
  if (entries.length > MAX_MEMBERS) throw new ZipError(`holds ${entries.length} files, more than the ${MAX_MEMBERS} read of one archive: unpack it and open the folders you need`);
  const members: ZipMember[] = [];
  for (const e of entries) members.push({ path: e.path, bytes: await unpackMember(reader, e, budget), lastModified: e.modified });
  return members;
}

/** Whether a file is to be unpacked: a ZIP archive by its first bytes (an unreadable file is left to the caller). */
async function isArchive(file: File): Promise<boolean> {
  if (NOT_ARCHIVES.test(file.name)) return false;
  try {
    return looksZip(new Uint8Array(await file.slice(0, 4).arrayBuffer()));
  } catch {
    return false;
  }
}

/** Files whose first bytes are read at once. */
const BATCH = 32;

/** The files given with each ZIP archive replaced by its files; `refused`: the archives that could not be read, and why. */
export interface Unpacked {
  files: File[];
  refused: CoreErrorData[];
  /** How many of the files given were archives. */
  archives: number;
}

/**
 * `files` with each ZIP archive among them replaced by its files, in place, each a File named as
 * its name in the archive, its path (`pathInFolder`) the archive's then its own
 * (`1234_images.zip/dicom/IM_01_00.dcm`). An archive that cannot be read is left out and named
 * in `refused` (the core's words: "ZIP archive: ..."). The archives together inflate at most
 * `MAX_UNPACKED` bytes.
 */
export async function expandArchives(files: readonly File[], budget: Budget = { left: MAX_UNPACKED }): Promise<Unpacked> {
  const zipped: boolean[] = [];
  for (let start = 0; start < files.length; start += BATCH) zipped.push(...(await Promise.all(files.slice(start, start + BATCH).map(isArchive))));
  const out: File[] = [];
  const refused: CoreErrorData[] = [];
  let archives = 0;
  for (const [i, file] of files.entries()) {
    if (!zipped[i]) {
      out.push(file);
      continue;
    }
    archives++;
    let members: ZipMember[];
    try {
      members = await zipMembers(file, budget);
    } catch (e) {
      refused.push(
        e instanceof ZipError
          ? { code: 'parse', file: file.name, message: `ZIP archive: ${e.message}` }
          : { code: 'app', file: file.name, message: `could not read the archive: ${e instanceof Error ? e.message : String(e)}` },
      );
      continue;
    }
    const where = pathInFolder(file) ?? file.name;
    for (const m of members) {
      const member = new File([m.bytes], m.path.slice(m.path.lastIndexOf('/') + 1), { lastModified: m.lastModified || file.lastModified });
      setPathInFolder(member, `${where}/${m.path}`);
      out.push(member);
    }
  }
  return { files: out, refused, archives };
}
