// ZIP archives opened in the page (io/zipArchive.ts): the files of each archive instead of it,
// named as in it, clutter left out, DICOM files as their headers (the pixels never inflated), the
// others whole; damaged, cut, encrypted and bomb archives refused with a message naming them.
import { describe, expect, it } from 'vitest';
import { Zip, ZipDeflate, zipSync, type Zippable } from 'fflate';
import { expandArchives, isClutter, looksZip, MAX_MEMBER, memberPath, zipMembers, crc32 } from '../../web/src/io/zipArchive';
import { pathInFolder, setPathInFolder } from '../../web/src/io/folderDrop';
import { isSegmentationHeader, pixelDataOffset } from '../../web/src/io/dicomHeaders';

const ascii = (s: string) => new TextEncoder().encode(s);
const concat = (...parts: Uint8Array[]) => {
  const out = new Uint8Array(parts.reduce((n, p) => n + p.length, 0));
  let at = 0;
  for (const p of parts) (out.set(p, at), (at += p.length));
  return out;
};
/** An explicit VR little endian element with a 2-byte length. */
const short = (group: number, element: number, vr: string, value: Uint8Array) => {
  const head = new Uint8Array(8);
  const v = new DataView(head.buffer);
  v.setUint16(0, group, true);
  v.setUint16(2, element, true);
  head.set(ascii(vr), 4);
  v.setUint16(6, value.length, true);
  return concat(head, value);
};
/** An explicit VR little endian element with a 4-byte length (OB, OW). */
const long = (group: number, element: number, vr: string, value: Uint8Array) => {
  const head = new Uint8Array(12);
  const v = new DataView(head.buffer);
  v.setUint16(0, group, true);
  v.setUint16(2, element, true);
  head.set(ascii(vr), 4);
  v.setUint32(8, value.length, true);
  return concat(head, value);
};
/** A DICOM file: preamble, magic, a SOP Instance UID, `privateBytes` of a private group, then `pixels` bytes of pixel data (none: no pixel element). */
function dicom(uid: string, pixels: number | null, privateBytes = 0): { file: Uint8Array; header: Uint8Array } {
  const parts = [new Uint8Array(128), ascii('DICM'), short(0x0008, 0x0018, 'UI', ascii(uid.length % 2 ? `${uid}\0` : uid))];
  if (privateBytes > 0) parts.push(long(0x0029, 0x1010, 'OB', new Uint8Array(privateBytes).fill(0x11)));
  const header = concat(...parts);
  if (pixels === null) return { file: header, header };
  // Pixels that do not compress to nothing (a counter), as an image's.
  const values = new Uint8Array(pixels).map((_, i) => (i * 7 + (i >> 9)) & 0xff);
  return { file: concat(header, long(0x7fe0, 0x0010, 'OW', values)), header };
}
const text = (bytes: Uint8Array) => new TextDecoder().decode(bytes);
const zipFile = (name: string, bytes: Uint8Array, lastModified = 1_700_000_000_000) => new File([bytes.slice()], name, { lastModified });
const bytesOf = async (f: Blob) => new Uint8Array(await f.arrayBuffer());
/** A Blob that counts the bytes read of it. */
class Counting extends Blob {
  read = 0;
  slice(start?: number, end?: number, type?: string): Blob {
    const part = super.slice(start, end, type);
    this.read += part.size;
    return part;
  }
}

/** Where the central directory entry of `name` begins in archive `bytes`. */
function centralEntry(bytes: Uint8Array, name: string): number {
  const sig = [0x50, 0x4b, 0x01, 0x02];
  for (let i = 0; i + 46 < bytes.length; i++) {
    if (sig.every((b, k) => bytes[i + k] === b) && text(bytes.subarray(i + 46, i + 46 + name.length)) === name) return i;
  }
  throw new Error(`no entry ${name}`);
}

const WSX = ascii('<?xml version="1.0"?><workspace>' + 'contour '.repeat(2000) + '</workspace>');
const IMAGE_1 = dicom('1.2.3.1', 200_000);
const IMAGE_2 = dicom('1.2.3.22', 200_000);

/** An images archive as UK Biobank's: DICOM files in a folder, a manifest, and a packer's clutter. */
function imagesArchive(level: 0 | 6 = 6): Uint8Array {
  const files: Zippable = {
    'dicom/': new Uint8Array(0),
    'dicom/IM_01.dcm': IMAGE_1.file,
    'dicom/IM_02.dcm': IMAGE_2.file,
    'manifest.cvs': ascii('filename,series\nIM_01.dcm,CINE\n'),
    '__MACOSX/dicom/._IM_01.dcm': ascii('resource fork'),
    '.DS_Store': ascii('finder'),
    'dicom/.hidden.dcm': IMAGE_1.file,
  };
  return zipSync(files, { level, mtime: new Date(2020, 4, 6, 7, 8, 10) });
}

describe('ZIP archives: what is one, what is in it', () => {
  it('are told by their first bytes', () => {
    expect(looksZip(ascii('PK\x03\x04rest'))).toBe(true);
    expect(looksZip(ascii('PK\x05\x06'))).toBe(true); // an empty archive
    expect(looksZip(ascii('PK\x01\x02'))).toBe(false);
    expect(looksZip(ascii('PK'))).toBe(false);
    expect(looksZip(ascii('contour,x,y,z'))).toBe(false);
  });

  it('leave out folders, macOS resource forks and hidden files; paths use /', () => {
    for (const no of ['dicom/', '__MACOSX/export/._a.csv', '.DS_Store', 'dicom/.hidden', '.git/config', 'a/__MACOSX/b']) expect(isClutter(no)).toBe(true);
    for (const ok of ['1234_cvi42.cvi42wsx', 'dicom/IM_01_00.dcm', 'export/patient1-ED.csv', 'a.b/c']) expect(isClutter(ok)).toBe(false);
    expect(memberPath('dicom\\IM_01.dcm')).toBe('dicom/IM_01.dcm');
    expect(memberPath('./export/a.csv')).toBe('export/a.csv');
  });

  it('CRC-32 is ZIP\'s', () => {
    expect(crc32(ascii('123456789'))).toBe(0xcbf43926);
    expect(crc32(new Uint8Array(0))).toBe(0);
  });
});

describe('expandArchives', () => {
  it('replaces an archive by its files in place, named as in it, its path kept; DICOM files as their headers', async () => {
    const before = zipFile('notes.csv', ascii('contour,x,y,z'));
    const after = zipFile('GPFile_000.txt', ascii('x y z'));
    const archive = zipFile('1234_20209_2_0.zip', imagesArchive());
    const { files, refused, archives } = await expandArchives([before, archive, after]);
    expect(refused).toEqual([]);
    expect(archives).toBe(1);
    expect(files.map((f) => f.name)).toEqual(['notes.csv', 'IM_01.dcm', 'IM_02.dcm', 'manifest.cvs', 'GPFile_000.txt']);
    expect(files[0]).toBe(before); // not an archive: the same File
    expect(files[4]).toBe(after);
    expect(files.slice(1, 4).map(pathInFolder)).toEqual(['1234_20209_2_0.zip/dicom/IM_01.dcm', '1234_20209_2_0.zip/dicom/IM_02.dcm', '1234_20209_2_0.zip/manifest.cvs']);
    // The DICOM files end where their pixel data begins (200 kB of pixels never kept).
    expect(await bytesOf(files[1])).toEqual(IMAGE_1.header);
    expect(await bytesOf(files[2])).toEqual(IMAGE_2.header);
    expect(files[1].size).toBe(IMAGE_1.header.length);
    expect(text(await bytesOf(files[3]))).toBe('filename,series\nIM_01.dcm,CINE\n');
    // The archive's time is each file's (DOS time: 2 s steps, local time).
    expect(files[1].lastModified).toBe(new Date(2020, 4, 6, 7, 8, 10).getTime());
  });

  it('reads stored members and members written with data descriptors (a streaming packer) alike', async () => {
    const stored = await expandArchives([zipFile('stored.zip', imagesArchive(0))]);
    expect(stored.files.map((f) => f.name)).toEqual(['IM_01.dcm', 'IM_02.dcm', 'manifest.cvs']);
    expect(await bytesOf(stored.files[0])).toEqual(IMAGE_1.header);

    // fflate's streaming Zip leaves the sizes and CRC to a data descriptor after each member.
    const chunks: Uint8Array[] = [];
    const zip = new Zip((err, chunk) => {
      if (err) throw err;
      chunks.push(chunk);
    });
    for (const [name, bytes] of [['1234_cvi42.cvi42wsx', WSX], ['dicom/IM_01.dcm', IMAGE_1.file]] as const) {
      const member = new ZipDeflate(name, { level: 6 });
      zip.add(member);
      member.push(bytes, true);
    }
    zip.end();
    const streamed = concat(...chunks);
    expect(streamed[6] & 8).toBe(8); // bit 3: sizes in a data descriptor
    const { files, refused } = await expandArchives([zipFile('1234_cvi42.zip', streamed)]);
    expect(refused).toEqual([]);
    expect(files.map((f) => f.name)).toEqual(['1234_cvi42.cvi42wsx', 'IM_01.dcm']);
    expect(await bytesOf(files[0])).toEqual(WSX);
    expect(await bytesOf(files[1])).toEqual(IMAGE_1.header);
  });

  it('tells an archive by its bytes: a ZIP named otherwise is unpacked, a .zip that is none is handed over', async () => {
    const unnamed = zipFile('download', zipSync({ 'export/patient1-ED.csv': ascii('contour,x,y,z\n') }));
    const fake = zipFile('contours.zip', ascii('contour,x,y,z\n'));
    const sheet = zipFile('contours.xlsx', zipSync({ 'xl/workbook.xml': ascii('<x/>') }));
    const { files, refused, archives } = await expandArchives([unnamed, fake, sheet]);
    expect(refused).toEqual([]);
    expect(archives).toBe(1);
    expect(files.map((f) => f.name)).toEqual(['patient1-ED.csv', 'contours.zip', 'contours.xlsx']);
    expect(files[1]).toBe(fake);
    expect(files[2]).toBe(sheet); // a spreadsheet is a ZIP inside: the core says what it is
  });

  it('prefixes the path of an archive found in a folder; files of one name in two archives keep theirs', async () => {
    const a = zipFile('1234_20209_2_0.zip', zipSync({ 'manifest.cvs': ascii('a') }));
    const b = zipFile('1234_20208_2_0.zip', zipSync({ 'manifest.cvs': ascii('b') }));
    setPathInFolder(a, 'subject/1234_20209_2_0.zip');
    const { files } = await expandArchives([a, b]);
    expect(files.map((f) => [f.name, pathInFolder(f)])).toEqual([
      ['manifest.cvs', 'subject/1234_20209_2_0.zip/manifest.cvs'],
      ['manifest.cvs', '1234_20208_2_0.zip/manifest.cvs'],
    ]);
  });

  it('keeps a DICOM file without pixel data whole (an RT structure set), and finds pixel data past a long header', async () => {
    const rt = dicom('1.2.9', null, 300_000);
    const long = dicom('1.2.10', 100_000, 150_000); // the pixel data begins past the first pieces inflated
    const { files } = await expandArchives([zipFile('x.zip', zipSync({ 'rt.dcm': rt.file, 'long.dcm': long.file }, { level: 0 }))]);
    expect(await bytesOf(files[0])).toEqual(rt.file);
    expect(await bytesOf(files[1])).toEqual(long.header);
    expect(pixelDataOffset(long.file, long.file.length)).toBe(long.header.length);
  });

  it('keeps a DICOM segmentation whole, pixels and all (its pixels are its label map); an image beside it as its header', async () => {
    // A SEG's header names its SOP class (Segmentation Storage) before the pixel data.
    const segClass = (uid: string) => short(0x0008, 0x0016, 'UI', ascii(uid.length % 2 ? `${uid}\0` : uid));
    const seg = (uid: string) => {
      const header = concat(new Uint8Array(128), ascii('DICM'), segClass(uid), short(0x0008, 0x0018, 'UI', ascii('1.2.77\0')));
      return { header, file: concat(header, long(0x7fe0, 0x0010, 'OB', new Uint8Array(5000).fill(0x0f))) };
    };
    const binary = seg('1.2.840.10008.5.1.4.1.1.66.4');
    const labelMap = seg('1.2.840.10008.5.1.4.1.1.66.7');
    const surface = seg('1.2.840.10008.5.1.4.1.1.66.5'); // Surface Segmentation: no label map
    const longer = seg('1.2.840.10008.5.1.4.1.1.66.41'); // begins alike, another UID
    const archive = zipSync({ 'seg.dcm': binary.file, 'labels.dcm': labelMap.file, 'surface.dcm': surface.file, 'other.dcm': longer.file, 'IM_01.dcm': IMAGE_1.file }, { level: 6 });
    const { files } = await expandArchives([zipFile('study.zip', archive)]);
    expect(files.map((f) => f.name)).toEqual(['seg.dcm', 'labels.dcm', 'surface.dcm', 'other.dcm', 'IM_01.dcm']);
    expect(await bytesOf(files[0])).toEqual(binary.file);
    expect(await bytesOf(files[1])).toEqual(labelMap.file);
    expect(await bytesOf(files[2])).toEqual(surface.header);
    expect(await bytesOf(files[3])).toEqual(longer.header);
    expect(await bytesOf(files[4])).toEqual(IMAGE_1.header);
    expect([binary, labelMap, surface, longer].map((d) => isSegmentationHeader(d.header))).toEqual([true, true, false, false]);
  });

  it('reads the archive in slices: of 40 images with 1 MB of pixels each, little more than their headers', async () => {
    const members: Zippable = {};
    for (let i = 0; i < 40; i++) members[`dicom/IM_${i}.dcm`] = dicom(`1.2.${i}`, 1_000_000).file;
    const bytes = zipSync(members, { level: 0 }); // stored: 40 MB
    const blob = new Counting([bytes]);
    const got = await zipMembers(blob);
    expect(got).toHaveLength(40);
    expect(got.every((m) => m.bytes.length < 200)).toBe(true);
    expect(bytes.length).toBeGreaterThan(40_000_000);
    // A window of 256 KiB per member and the central directory: a quarter of the archive at most.
    expect(blob.read).toBeLessThan(40 * 256 * 1024 + 70_000);
    expect(blob.read).toBeLessThan(bytes.length / 3);
  });
});

describe('archives that cannot be read are named, the other files go on', () => {
  const refusal = async (bytes: Uint8Array, name = 'x.zip') => {
    const good = zipFile('good.csv', ascii('contour,x,y,z'));
    const { files, refused } = await expandArchives([zipFile(name, bytes), good]);
    expect(files).toEqual([good]);
    expect(refused).toHaveLength(1);
    expect(refused[0].file).toBe(name);
    return refused[0].message;
  };

  it('a cut archive (its end lost in a download)', async () => {
    const whole = imagesArchive();
    expect(await refusal(whole.slice(0, Math.floor(whole.length / 2)), '1234_20209_2_0.zip')).toBe('ZIP archive: no end of central directory: truncated or not an archive');
    // Cut inside the central directory: the end record is gone as well.
    expect(await refusal(whole.slice(0, whole.length - 10))).toBe('ZIP archive: no end of central directory: truncated or not an archive');
  });

  it('a central directory that points past the end, or at no local header', async () => {
    const bytes = imagesArchive();
    // The members' data cut out, the directory kept: its offsets run past the end.
    const at = centralEntry(bytes, 'dicom/');
    const shortened = concat(bytes.subarray(0, 100), bytes.subarray(at));
    expect(await refusal(shortened)).toMatch(/^ZIP archive: the central directory runs past the end \(byte \d+ of \d+\): truncated$/);
    const moved = bytes.slice();
    const entry = centralEntry(moved, 'dicom/IM_01.dcm');
    new DataView(moved.buffer).setUint32(entry + 42, 5, true);
    expect(await refusal(moved)).toBe('ZIP archive: dicom/IM_01.dcm: no local header at byte 5: damaged');
  });

  it('damaged deflate data, a CRC that does not match', async () => {
    const bytes = zipSync({ 'contours.csv': ascii('contour,x,y,z\n' + '1,2,3,LV_ENDO\n'.repeat(3000)) }, { level: 6 });
    const damaged = bytes.slice();
    for (let i = 60; i < 90; i++) damaged[i] ^= 0x5a;
    expect(await refusal(damaged)).toMatch(/^ZIP archive: contours\.csv(: corrupt deflate data| unpacks to .*|: CRC mismatch): damaged$/);
    const stored = zipSync({ 'contours.csv': ascii('contour,x,y,z\n1,2,3,LV_ENDO\n') }, { level: 0 });
    stored[30 + 'contours.csv'.length + 3] ^= 1; // a byte of the stored data
    expect(await refusal(stored)).toBe('ZIP archive: contours.csv: CRC mismatch: damaged');
  });

  it('an encrypted member, a method other than stored or deflated, ZIP64', async () => {
    const bytes = zipSync({ 'a.csv': ascii('contour,x,y,z\n') });
    const encrypted = bytes.slice();
    new DataView(encrypted.buffer).setUint16(centralEntry(encrypted, 'a.csv') + 8, 1, true);
    expect(await refusal(encrypted)).toBe('ZIP archive: a.csv is encrypted: unpack it first');
    const bzip2 = bytes.slice();
    new DataView(bzip2.buffer).setUint16(centralEntry(bzip2, 'a.csv') + 10, 12, true);
    expect(await refusal(bzip2)).toBe('ZIP archive: a.csv is packed with method 12; only stored and deflated files are read');
    const zip64 = bytes.slice();
    new DataView(zip64.buffer).setUint32(centralEntry(zip64, 'a.csv') + 24, 0xffffffff, true);
    expect(await refusal(zip64)).toBe('ZIP archive: a.csv is a ZIP64 member (over 4 GB): unpack it first');
  });

  it('an archive of nothing but clutter', async () => {
    expect(await refusal(zipSync({ '__MACOSX/._a.csv': ascii('x'), 'dir/': new Uint8Array(0) }))).toBe('ZIP archive: holds no files (only folders, or hidden files)');
    expect(await refusal(zipSync({}))).toBe('ZIP archive: holds no files (only folders, or hidden files)');
  });

  it('a zip bomb: a member larger than it says, one too large to keep, archives past the budget', async () => {
    const zeros = new Uint8Array(64 * 2 ** 20); // 64 MiB of zeros: 64 KiB deflated
    const bomb = zipSync({ 'big.csv': zeros }, { level: 9 });
    expect(bomb.length).toBeLessThan(200_000);
    // It says it is 1000 bytes: inflating stops past them.
    const lying = bomb.slice();
    new DataView(lying.buffer).setUint32(centralEntry(lying, 'big.csv') + 24, 1000, true);
    expect(await refusal(lying)).toBe('ZIP archive: big.csv unpacks to more than the 1000 bytes the archive says: damaged');
    // It says it is 300 MiB: not inflated at all (not DICOM, more than a file kept whole).
    const huge = bomb.slice();
    new DataView(huge.buffer).setUint32(centralEntry(huge, 'big.csv') + 24, 300 * 2 ** 20, true);
    expect(MAX_MEMBER).toBe(256 * 2 ** 20);
    expect(await refusal(huge)).toBe('ZIP archive: big.csv unpacks to 300 MiB, more than the 256 MiB read of one file');
    // The truth, over what is left of the budget of the opening: stopped within a piece's worth past it.
    const budget = { left: 32 * 2 ** 20 };
    const { files, refused } = await expandArchives([zipFile('bomb.zip', bomb)], budget);
    expect(files).toEqual([]);
    expect(refused[0].message).toBe('ZIP archive: big.csv: the archives unpack to more than the 1024 MiB read at once (a zip bomb?)');
    expect(budget.left).toBeLessThan(0);
    expect(budget.left).toBeGreaterThan(-17 * 2 ** 20);
  });

  it('a file that cannot be read any more is left to the caller (refused as unreadable there)', async () => {
    const gone = { name: 'moved.zip', size: 10, lastModified: 1, slice: () => ({ arrayBuffer: () => Promise.reject(new Error('gone')) }) } as unknown as File;
    const { files, refused } = await expandArchives([gone]);
    expect(files).toEqual([gone]);
    expect(refused).toEqual([]);
  });
});
