// Which files are a cvi42 workspace's images (every other file opened with it, only when a
// workspace is among them), which files of a dropped or picked folder are opened, and the header
// slices the app reads of each image (io/dicomHeaders.ts).
import { describe, expect, it } from 'vitest';
import workspaceXml from '../../wasm-core/crates/heartmesh-core/tests/data/cvi42-patient1/Contours.cvi42wsx?raw';
import { asksForImages, cvi42Study, isSunnybrookName, isWorkspaceHead, isWorkspaceName, workspaceTest, WORKSPACE_HEAD_BYTES } from '../../web/src/io/cvi42Study';
import { FIRST_SLICE, headerSlice, imageHeaders, imageNames, looksDicom, pixelDataOffset } from '../../web/src/io/dicomHeaders';
import { filesOfEntries, filesOfPickedFolder, nameless, pathInFolder, selectFolderFiles, STUDY_FILE_LIMIT, type EntryLike } from '../../web/src/io/folderDrop';
import { fileEntry, folderEntry } from './fakeEntries';
import { lostText, skippedText } from '../../web/src/app/fileNames';

const named = (...names: string[]) => names.map((name) => ({ name }));

/** How a DICOM file starts: a 128-byte preamble, `DICM`, then its elements. */
function dicomStart(): Uint8Array<ArrayBuffer> {
  const bytes = new Uint8Array(4096);
  bytes.set(new TextEncoder().encode('DICM'), 128);
  return bytes;
}

describe('a cvi42 workspace and its images', () => {
  it('tells a workspace by its extension, in any case', () => {
    for (const yes of ['Contours.cvi42wsx', 'study.CVI42WSX', 'a.b.cvi42wsx']) expect(isWorkspaceName(yes)).toBe(true);
    for (const no of ['Contours.cvi42ws', 'cvi42wsx', 'x.cvi42wsx.txt', 'IM_0001', 'rt.dcm']) expect(isWorkspaceName(no)).toBe(false);
  });

  it('makes every other file opened with a workspace one of its images, in the order given', () => {
    const study = cvi42Study(named('IM_0002', 'Contours.cvi42wsx', 'IM_0001', 'DICOMDIR', 'notes.txt'));
    expect(study?.workspaces.map((f) => f.name)).toEqual(['Contours.cvi42wsx']);
    expect(study?.images.map((f) => f.name)).toEqual(['IM_0002', 'IM_0001', 'DICOMDIR', 'notes.txt']);
    // Alone: a workspace without images (the core refuses it, saying what to open).
    expect(cvi42Study(named('Contours.cvi42wsx'))).toEqual({ workspaces: [{ name: 'Contours.cvi42wsx' }], images: [] });
  });

  it('leaves files without a workspace as they were: a DICOM file alone may be an RTSTRUCT', () => {
    expect(cvi42Study(named('rtstruct.dcm'))).toBeNull();
    expect(cvi42Study(named('IM_0001.dcm', 'IM_0002.dcm', 'GPFile_000.txt'))).toBeNull();
    expect(cvi42Study([])).toBeNull();
  });

  it('tells a workspace by its first bytes, as the core does: XML declaring cvi42\'s namespace', () => {
    const wsx = new TextEncoder().encode(workspaceXml);
    const image = dicomStart();
    const enc = (s: string) => new TextEncoder().encode(s);
    expect(isWorkspaceHead(wsx)).toBe(true);
    expect(isWorkspaceHead(new Uint8Array([0xef, 0xbb, 0xbf, ...enc('\n  '), ...wsx]))).toBe(true);
    expect(isWorkspaceHead(image)).toBe(false);
    expect(isWorkspaceHead(enc('<?xml version="1.0"?>\n<VTKFile type="PolyData">'))).toBe(false);
    // The namespace quoted in a text file is no workspace; nor is one past the first 4 KiB.
    expect(isWorkspaceHead(enc('notes: http://www.circlecvi.com/cvi42/Workspace/'))).toBe(false);
    expect(isWorkspaceHead(enc(`<?xml version="1.0"?>${' '.repeat(WORKSPACE_HEAD_BYTES)}<a xmlns="http://www.circlecvi.com/cvi42/Workspace/"/>`))).toBe(false);
  });

  it('finds a workspace saved under another name among files opened together, and takes the others for its images', async () => {
    const wsx = new TextEncoder().encode(workspaceXml);
    const image = dicomStart();
    const renamed = new File([wsx], 'Contours.xml');
    const images = [new File([image], 'IM_0001'), new File([image], 'IM_0002.dcm'), new File(['exported'], 'notes.txt')];
    const files = [images[0], renamed, images[1], images[2]];
    const study = cvi42Study(files, await workspaceTest(files));
    expect(study?.workspaces).toEqual([renamed]);
    expect(study?.images).toEqual([images[0], images[1], images[2]]);
    // Without one, by content or by name, the files open as before.
    expect(cvi42Study(images, await workspaceTest(images))).toBeNull();
    // Alone, it is left to the core (whose refusal asks for the images).
    expect(cvi42Study([renamed], await workspaceTest([renamed]))).toBeNull();
    // Files named as another kind are not read for it (a PACS folder's .dcm images).
    const asDicom = new File([wsx], 'Contours.dcm');
    expect(cvi42Study([asDicom, images[0]], await workspaceTest([asDicom, images[0]]))).toBeNull();
    // A workspace named as such decides by name: the others are not read for theirs.
    const named = new File(['not read'], 'C.cvi42wsx');
    const byName = cvi42Study([renamed, named], await workspaceTest([renamed, named]));
    expect(byName?.workspaces).toEqual([named]);
    expect(byName?.images).toEqual([renamed]);
  });

  it('gives two workspaces the same images (each places the contours of its own by UID)', () => {
    const study = cvi42Study(named('reader1.cvi42wsx', 'IM_1', 'reader2.cvi42wsx', 'IM_2'));
    expect(study?.workspaces.map((f) => f.name)).toEqual(['reader1.cvi42wsx', 'reader2.cvi42wsx']);
    expect(study?.images.map((f) => f.name)).toEqual(['IM_1', 'IM_2']);
  });
});

describe('a Sunnybrook case: contour files and the images they were drawn on', () => {
  it('tells a contour file by its name, as the core does', () => {
    for (const yes of ['IM-0001-0048-icontour-manual.txt', 'IM-0001-0220-ocontour-manual.txt', 'im-0001-0007-p1contour-auto.TXT', 'IM-0001-0060-icontour.txt']) {
      expect(isSunnybrookName(yes)).toBe(true);
    }
    for (const no of ['IM-0001-0048.dcm', 'IM-0001-0048-icontour-manual.csv', 'contours.txt', 'IM-0001-0048-i-manual.txt', 'IM-0001--icontour-manual.txt', 'IM-0001-0048-contour-manual.txt', 'GPFile_000.txt']) {
      expect(isSunnybrookName(no)).toBe(false);
    }
  });

  it('reads the first contour file by name, with the other contour files and the images as its images', () => {
    const study = cvi42Study(named('IM-0003-0001.dcm', 'IM-0001-0020-icontour-manual.txt', 'IM-0001-0001-ocontour-manual.txt', 'IM-0003-0002.dcm', 'IM-0001-0001-icontour-manual.txt'));
    expect(study?.workspaces.map((f) => f.name)).toEqual(['IM-0001-0001-icontour-manual.txt']);
    expect(study?.images.map((f) => f.name)).toEqual(['IM-0003-0001.dcm', 'IM-0001-0020-icontour-manual.txt', 'IM-0001-0001-ocontour-manual.txt', 'IM-0003-0002.dcm']);
    // A workspace among them takes every other file, as before.
    expect(cvi42Study(named('IM-0001-0001-icontour-manual.txt', 'C.cvi42wsx'))?.workspaces.map((f) => f.name)).toEqual(['C.cvi42wsx']);
  });

  it("hears the core ask for the images of either kind", () => {
    expect(asksForImages('cvi42 workspace: a cvi42 workspace holds its contours in the pixels of its images: open it together with the DICOM images it was drawn on (the study\'s folder)')).toBe(true);
    expect(asksForImages('Sunnybrook contours: Sunnybrook contours are in the pixels of their images: open the contour files together with the DICOM images they were drawn on (the case\'s contours folder and its short-axis cine series, both at once)')).toBe(true);
    expect(asksForImages('line 2: x: "a" is not a number')).toBe(false);
  });

  it('reads a folder holding contour files whole, as a workspace study\'s', () => {
    const found = [
      ...Array.from({ length: 300 }, (_, i) => ({ item: `i${i}`, path: `case/CINESAX_300/IM-0003-${String(i + 1).padStart(4, '0')}.dcm`, depth: 2 })),
      { item: 'c1', path: 'case/contours-manual/IRCCI-expert/IM-0001-0001-icontour-manual.txt', depth: 3 },
      { item: 'u1', path: 'case/CINESAX_300/DICOMDIR', depth: 2 },
    ];
    const picked = selectFolderFiles(found);
    expect(picked.study).toBe(true);
    expect(picked.kept.length).toBe(302);
    expect(picked.skipped).toBe(0);
  });
});

/** Folders whose readers hand their entries over three at a time. */
const file = fileEntry;
const folder = (name: string, children: EntryLike[]): EntryLike => folderEntry(name, children, 3);

describe('a cvi42 study folder', () => {
  it('opens every file of a dropped study folder, however deep and whatever the name, hidden ones left', async () => {
    const study = folder('study', [
      file('Contours.cvi42wsx'),
      file('.DS_Store'),
      file('DICOMDIR'),
      folder('DICOM', [folder('PA000000', [folder('ST000000', [folder('SE000001', [file('IM000002'), file('IM000001'), file('IM000010')])])])]),
      folder('.thumbnails', [file('a.png')]),
    ]);
    const { files, skipped, study: isStudy } = await filesOfEntries([study]);
    expect(isStudy).toBe(true);
    // In name order, numbers as numbers: the folder DICOM before the file DICOMDIR.
    expect(files.map((f) => f.name)).toEqual(['Contours.cvi42wsx', 'IM000001', 'IM000002', 'IM000010', 'DICOMDIR']);
    expect(skipped).toBe(2); // .DS_Store, .thumbnails/a.png
    expect(pathInFolder(files[1])).toBe('study/DICOM/PA000000/ST000000/SE000001/IM000001');
    expect(pathInFolder(files[0])).toBe('study/Contours.cvi42wsx');
    expect(skippedText(skipped, true)).toBe(`2 other files in the dropped folder were not read (hidden, or past the first ${STUDY_FILE_LIMIT} files).`);
  });

  it('takes a workspace dropped beside a folder of images as the study', async () => {
    const { files, skipped, study } = await filesOfEntries([file('Contours.cvi42wsx'), folder('dicom', [file('IM_1'), file('IM_2')])]);
    expect(study).toBe(true);
    expect(files.map((f) => f.name)).toEqual(['Contours.cvi42wsx', 'IM_1', 'IM_2']);
    expect(skipped).toBe(0);
  });

  it('keeps a folder of DICOM images without a workspace to the contour kinds, as before', async () => {
    const { files, skipped, study } = await filesOfEntries([folder('dicom', [file('IM_1'), file('rt.dcm'), file('IM_2')])]);
    expect(study).toBe(false);
    expect(files.map((f) => f.name)).toEqual(['rt.dcm']);
    expect(skipped).toBe(2);
  });

  it('hands over every file of a folder while the app waits for a refused workspace\'s images', async () => {
    const dicom = folder('dicom', [file('IM_2'), file('IM_1'), file('.DS_Store')]);
    const waiting = await filesOfEntries([dicom], undefined, true);
    expect(waiting.study).toBe(true);
    expect(waiting.files.map((f) => f.name)).toEqual(['IM_1', 'IM_2']);
    expect(waiting.skipped).toBe(1);
    // Not waiting: the same folder holds no contour file.
    const alone = await filesOfEntries([dicom]);
    expect(alone.files).toEqual([]);
    expect(alone.skipped).toBe(3);
  });

  it('stops a study folder at its limit, counting the rest', () => {
    const found = [{ item: 'ws', path: 'f/a.cvi42wsx', depth: 1 }, ...Array.from({ length: STUDY_FILE_LIMIT + 5 }, (_, i) => ({ item: `i${i}`, path: `f/s/IM_${i}`, depth: 2 }))];
    const picked = selectFolderFiles(found);
    expect(picked.kept.length).toBe(STUDY_FILE_LIMIT);
    expect(picked.skipped).toBe(6);
  });

  it('picks a folder with the folder button as it would be dropped (paths from webkitRelativePath)', () => {
    const inFolder = (path: string) => {
      const f = new File(['x'], path.slice(path.lastIndexOf('/') + 1));
      Object.defineProperty(f, 'webkitRelativePath', { value: path });
      return f;
    };
    const picked = filesOfPickedFolder([inFolder('p1/dicom/IM_10'), inFolder('p1/Contours.cvi42wsx'), inFolder('p1/dicom/IM_9'), inFolder('p1/.hidden')]);
    expect(picked.study).toBe(true);
    expect(picked.kept.map((f) => f.webkitRelativePath)).toEqual(['p1/Contours.cvi42wsx', 'p1/dicom/IM_9', 'p1/dicom/IM_10']);
    expect(picked.skipped).toBe(1);
    const biv = filesOfPickedFolder([inFolder('p/GPFile_000.txt'), inFolder('p/IM_1'), inFolder('p/SliceInfoFile.txt')]);
    expect(biv.study).toBe(false);
    expect(biv.kept.map((f) => f.name)).toEqual(['GPFile_000.txt', 'SliceInfoFile.txt']);
    // IM_1's name says nothing: looked into before it is opened or counted.
    expect(biv.unnamed.map((f) => f.name)).toEqual(['IM_1']);
    expect(biv.skipped).toBe(0);
  });

  it('opens the DICOM segmentations among a folder\'s nameless files (a PACS export), not its images', async () => {
    const ascii = (t: string) => new TextEncoder().encode(t);
    /** A DICOM file: preamble, magic, its SOP Class UID (even length), then 4 bytes of pixel data. */
    const dicom = (sopClass: string) => {
      const uid = ascii(sopClass.length % 2 ? `${sopClass}\0` : sopClass);
      const element = new Uint8Array(8 + uid.length);
      element.set([0x08, 0x00, 0x16, 0x00, 0x55, 0x49, uid.length, 0]);
      element.set(uid, 8);
      const pixels = new Uint8Array([0xe0, 0x7f, 0x10, 0x00, 0x4f, 0x42, 0, 0, 4, 0, 0, 0, 1, 2, 3, 4]);
      const out = new Uint8Array(132 + element.length + pixels.length);
      out.set(ascii('DICM'), 128);
      out.set(element, 132);
      out.set(pixels, 132 + element.length);
      return out;
    };
    const withBytes = (name: string, bytes: Uint8Array): EntryLike => ({ isFile: true, isDirectory: false, name, file: (ok) => ok(new File([bytes.slice()], name)) });
    const exported = folder('export', [
      withBytes('1.2.826.0.1.3680043.8.498.1', dicom('1.2.840.10008.5.1.4.1.1.66.4')), // a SEG named by its UID
      withBytes('IM000001', dicom('1.2.840.10008.5.1.4.1.1.4')), // an MR image
      withBytes('SEG2', dicom('1.2.840.10008.5.1.4.1.1.66.7')), // a label map SEG
      file('notes'), // not DICOM
      file('report.pdf'), // a kind not read
    ]);
    const { files, skipped, study } = await filesOfEntries([exported]);
    expect(study).toBe(false);
    expect(files.map((f) => f.name)).toEqual(['1.2.826.0.1.3680043.8.498.1', 'SEG2']);
    expect(skipped).toBe(3);
    expect(nameless('IM000001') && nameless('1.2.3.44') && !nameless('a.pdf') && !nameless('x.dcm')).toBe(true);
  });
});

/** A DICOM file: preamble, DICM, `header` bytes, then the pixel data element of `pixels` bytes. */
function dicom(header: number[], pixels: number): Uint8Array {
  const head = [...new Array(128).fill(0), 0x44, 0x49, 0x43, 0x4d, ...header];
  const element = [0xe0, 0x7f, 0x10, 0x00, 0x4f, 0x57, 0, 0, ...new Uint8Array(new Uint32Array([pixels]).buffer)];
  const out = new Uint8Array(head.length + element.length + pixels);
  out.set([...head, ...element]);
  return out;
}

describe('the header slice of each image', () => {
  it('finds where the pixel data begins, not in bytes that merely look like its tag', () => {
    const f = dicom([0x08, 0x00, 0x18, 0x00, 0x55, 0x49, 0x02, 0x00, 0x31, 0x00], 1000);
    expect(looksDicom(f)).toBe(true);
    expect(pixelDataOffset(f, f.length)).toBe(142);
    // The tag's bytes inside a value, followed by neither a VR nor a length that fits: not it.
    const fake = dicom([0x19, 0x00, 0x10, 0x10, 0x4f, 0x42, 0, 0, 8, 0, 0, 0, 0xe0, 0x7f, 0x10, 0x00, 0xff, 0xff, 0xff, 0x7f], 1000);
    expect(pixelDataOffset(fake, fake.length)).toBe(152);
    // Implicit VR: a length that fits the file.
    const implicit = new Uint8Array([...new Array(128).fill(0), 0x44, 0x49, 0x43, 0x4d, 0xe0, 0x7f, 0x10, 0x00, 4, 0, 0, 0, 1, 2, 3, 4]);
    expect(pixelDataOffset(implicit, implicit.length)).toBe(132);
    expect(pixelDataOffset(implicit, 10)).toBe(-1);
    expect(looksDicom(new TextEncoder().encode('x,y,z\n'))).toBe(false);
  });

  it('keeps the header alone of a large image, the first slice of a file that is not DICOM', async () => {
    const image = dicom([0x08, 0x00, 0x18, 0x00, 0x55, 0x49, 0x02, 0x00, 0x31, 0x00], 300_000);
    expect((await headerSlice(new Blob([image.slice().buffer]))).byteLength).toBe(142);
    const movie = new Uint8Array(200_000).fill(7);
    expect((await headerSlice(new Blob([movie.slice().buffer]))).byteLength).toBe(FIRST_SLICE);
    const small = new TextEncoder().encode('notes');
    expect((await headerSlice(new Blob([small]))).byteLength).toBe(5);
  });

  it('reads further when the pixels do not begin within the first slice', async () => {
    const pad = 70_000;
    const header = [0x19, 0x00, 0x10, 0x10, 0x4f, 0x42, 0, 0, ...new Uint8Array(new Uint32Array([pad]).buffer), ...new Array(pad).fill(0x20)];
    const image = dicom(header, 500_000);
    expect((await headerSlice(new Blob([image.slice().buffer]))).byteLength).toBe(132 + header.length);
  });

  it('names images by name, by their folder path when two share one, else numbered', () => {
    const files = named('IM_1', 'IM_1', 'IM_2', 'IM_1');
    const paths = ['s/a/IM_1', 's/b/IM_1', 's/a/IM_2', null];
    expect(imageNames(files, (i) => paths[i])).toEqual(['s/a/IM_1', 's/b/IM_1', 'IM_2', 'IM_1']);
    expect(imageNames(named('A', 'A'), () => null)).toEqual(['A', 'A (2)']);
  });

  it('reads 400 images in bounded batches, and names those that could not be read', async () => {
    let open = 0;
    let most = 0;
    const image = dicom([0x08, 0x00, 0x18, 0x00, 0x55, 0x49, 0x02, 0x00, 0x31, 0x00], 2000);
    const files = Array.from({ length: 400 }, (_, i) => {
      const f = new File([image.slice().buffer], `IM_${i}`);
      const slice = f.slice.bind(f);
      f.slice = (...args: Parameters<Blob['slice']>) => {
        const part = slice(...args);
        part.arrayBuffer = async () => {
          open++;
          most = Math.max(most, open);
          await new Promise((r) => setTimeout(r, 1));
          open--;
          if (i === 7) throw new Error('gone');
          return Blob.prototype.arrayBuffer.call(part);
        };
        return part;
      };
      return f;
    });
    const { images, unreadable } = await imageHeaders(files, () => null, 32);
    expect(images.length).toBe(399);
    expect(images.every((v) => v.bytes.byteLength === 142)).toBe(true);
    expect(unreadable).toEqual(['IM_7']);
    expect(most).toBeLessThanOrEqual(32);
    expect(most).toBeGreaterThan(1);
    expect(lostText(unreadable)).toBe('1 file could not be read (IM_7): moved, or without permission.');
  });
});
