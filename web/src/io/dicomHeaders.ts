/**
 * The headers of the DICOM images opened with a cvi42 workspace. The core needs only each image's
 * header (its plane, its place in the cine) and stops at the pixel data, so the app reads a slice
 * of each file, never the pixels: a study's folder holds hundreds of cine images of 100-500 KB,
 * and every byte handed over is copied into the worker and into wasm memory. A header is usually
 * 2-10 KB, Siemens' private groups make it 20-60 KB: the first slice is 64 KiB, and a DICOM file
 * whose pixel data does not begin inside it is read further (1 MiB, then 4 MiB). Each slice ends
 * where the pixel data begins, so what is kept is the header alone.
 */
import type { ViewFile } from '../core-client/protocol';

/** The first slice read of each file. */
export const FIRST_SLICE = 64 * 1024;
/** Read further when the pixel data has not begun yet (an enhanced header, a big private group). */
const LONGER_SLICES = [1024 * 1024, 4 * 1024 * 1024];
/** Files read at once: enough to keep the disk busy, few enough not to hold hundreds of reads. */
export const HEADER_BATCH = 32;

/** DICOM's magic at 128 (after the preamble) or at 0 (no preamble), as the core tells DICOM. */
export function looksDicom(bytes: Uint8Array): boolean {
  return dicomStart(bytes) >= 0;
}

/** Where a DICOM file's elements begin (after the magic), or -1 when the bytes are not DICOM. */
function dicomStart(bytes: Uint8Array): number {
  const at = (o: number) => bytes.length >= o + 4 && bytes[o] === 0x44 && bytes[o + 1] === 0x49 && bytes[o + 2] === 0x43 && bytes[o + 3] === 0x4d;
  return at(128) ? 132 : at(0) ? 4 : -1;
}

/** SOP classes of DICOM segmentations (Segmentation, Label Map Segmentation): label maps. */
const SEGMENTATION_CLASSES = ['1.2.840.10008.5.1.4.1.1.66.4', '1.2.840.10008.5.1.4.1.1.66.7'].map((uid) => new TextEncoder().encode(uid));

/**
 * Whether a DICOM header names a segmentation's SOP class (in its file meta or its SOP Class
 * UID): such a file is a label map, read whole, pixels and all, unlike an image whose header
 * alone is needed. The UID must end there (no digit or dot follows), so a longer UID that begins
 * alike is no match.
 */
export function isSegmentationHeader(header: Uint8Array): boolean {
  return SEGMENTATION_CLASSES.some((uid) => {
    for (let i = header.indexOf(uid[0]); i >= 0 && i + uid.length <= header.length; i = header.indexOf(uid[0], i + 1)) {
      let same = true;
      for (let k = 1; k < uid.length && same; k++) same = header[i + k] === uid[k];
      const next = header[i + uid.length];
      const continues = next !== undefined && (next === 0x2e || (next >= 0x30 && next <= 0x39));
      if (same && !continues) return true;
    }
    return false;
  });
}

/**
 * Whether a file is a DICOM segmentation (a label map), told from its first bytes and, for a
 * DICOM file, its header: an image's pixels are never read for this.
 */
export async function isSegmentationFile(file: Blob): Promise<boolean> {
  const head = new Uint8Array(await file.slice(0, 132).arrayBuffer());
  return looksDicom(head) && isSegmentationHeader(new Uint8Array(await headerSlice(file)));
}

/** The value representations the pixel data element is written with (explicit VR). */
const PIXEL_VRS = new Set(['OB', 'OW', 'OF', 'OD', 'OL', 'OV', 'UN']);

/**
 * Where the pixel data element (7FE0,0010) begins in `bytes`, or -1 if not in them. A match of
 * its four tag bytes counts only if an explicit VR of pixel data follows, or an implicit length
 * that is undefined or fits in the file (`fileSize`): four bytes of a private binary value that
 * happen to look like the tag do not cut a header short. `from`: where to begin looking (bytes before
 * it were looked at already, as a ZIP member's header is inflated piece by piece: io/zipArchive.ts).
 */
export function pixelDataOffset(bytes: Uint8Array, fileSize: number, from = 0): number {
  const start = dicomStart(bytes);
  if (start < 0) return -1;
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  for (let i = Math.max(start, from); i + 8 <= bytes.length; i++) {
    const little = bytes[i] === 0xe0 && bytes[i + 1] === 0x7f && bytes[i + 2] === 0x10 && bytes[i + 3] === 0x00;
    const big = bytes[i] === 0x7f && bytes[i + 1] === 0xe0 && bytes[i + 2] === 0x00 && bytes[i + 3] === 0x10;
    if (!little && !big) continue;
    if (PIXEL_VRS.has(String.fromCharCode(bytes[i + 4], bytes[i + 5]))) return i;
    const length = view.getUint32(i + 4, little);
    if (length === 0xffffffff || i + 8 + length <= fileSize) return i;
  }
  return -1;
}

/**
 * The header of one file: its first bytes up to where the pixel data begins. A file that is not
 * DICOM gives its first slice (the core sets it aside, naming it); a DICOM file whose pixel data
 * is not within 4 MiB gives those 4 MiB (the core reads what header they hold).
 */
export async function headerSlice(file: Blob): Promise<ArrayBuffer> {
  for (const size of [FIRST_SLICE, ...LONGER_SLICES]) {
    const bytes = new Uint8Array(await file.slice(0, size).arrayBuffer());
    const at = pixelDataOffset(bytes, file.size);
    if (at >= 0) return bytes.slice(0, at).buffer;
    if (bytes.length >= file.size || !looksDicom(bytes) || size === LONGER_SLICES[LONGER_SLICES.length - 1]) return bytes.buffer;
  }
  throw new Error('unreachable');
}

/**
 * The names the images go by: each file's name, or where two share one (`IM_0001` in every series
 * folder), its path in the dropped folder (`pathOf`), else the name numbered (`IM_0001 (2)`).
 * The core names set-aside files by them.
 */
export function imageNames(files: readonly { name: string }[], pathOf: (i: number) => string | null): string[] {
  const count = new Map<string, number>();
  for (const f of files) count.set(f.name, (count.get(f.name) ?? 0) + 1);
  const used = new Set<string>();
  return files.map((f, i) => {
    let name = f.name;
    if ((count.get(name) ?? 0) > 1) name = pathOf(i) ?? name;
    for (let k = 2; used.has(name); k++) name = `${f.name} (${k})`;
    used.add(name);
    return name;
  });
}

/**
 * The headers of `files` (`headerSlice`), read `HEADER_BATCH` at a time, named by `imageNames`;
 * `unreadable`: the names of files that could not be read (moved or without permission since the
 * drop), left out.
 */
export async function imageHeaders(
  files: readonly File[],
  pathOf: (f: File) => string | null = () => null,
  batch = HEADER_BATCH,
): Promise<{ images: ViewFile[]; unreadable: string[] }> {
  const names = imageNames(files, (i) => pathOf(files[i]));
  const images: ViewFile[] = [];
  const unreadable: string[] = [];
  for (let start = 0; start < files.length; start += batch) {
    const part = files.slice(start, start + batch);
    const read = await Promise.all(part.map((f) => headerSlice(f).then((bytes) => bytes, () => null)));
    read.forEach((bytes, k) => {
      if (bytes) images.push({ name: names[start + k], bytes });
      else unreadable.push(names[start + k]);
    });
  }
  return { images, unreadable };
}
