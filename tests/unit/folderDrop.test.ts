import { describe, expect, it } from 'vitest';
import { filesOfEntries, readableInFolder } from '../../web/src/io/folderDrop';
import { fileEntry, folderEntry } from './fakeEntries';
import { skippedText } from '../../web/src/app/fileNames';

const file = fileEntry;
const folder = folderEntry;

describe('folders dropped on the page', () => {
  it('open a biv-me patient folder: its contour files in name order, images and hidden files left', async () => {
    const patient = folder('patient1', [
      file('GPFile_010.txt'),
      file('SliceInfoFile.txt'),
      file('GPFile_002.txt'),
      file('.DS_Store'),
      file('IM_0001'),
      file('GPFile_000.txt'),
      folder('images', [file('cine.png')]),
    ]);
    const { files, skipped } = await filesOfEntries([patient]);
    expect(files.map((f) => f.name)).toEqual(['GPFile_000.txt', 'GPFile_002.txt', 'GPFile_010.txt', 'SliceInfoFile.txt']);
    expect(skipped).toBe(3); // .DS_Store, IM_0001, images/cine.png
  });

  it('keep files dropped beside a folder as they are, and stop a folder at the limit', async () => {
    const many = folder('study', Array.from({ length: 7 }, (_, i) => file(`c${i}.csv`)));
    const { files, skipped } = await filesOfEntries([file('notes.pdf'), many], 5);
    expect(files.map((f) => f.name)).toEqual(['notes.pdf', 'c0.csv', 'c1.csv', 'c2.csv', 'c3.csv', 'c4.csv']);
    expect(skipped).toBe(2);
    expect(skippedText(skipped)).toMatch(/^2 other files in the dropped folder were not read/);
    expect(skippedText(0)).toBe('');
  });

  it('read the kinds the Open dialog offers, label maps (NIfTI) included', () => {
    for (const ok of ['a.csv', 'GPFile_000.TXT', 'x.vtp', 'rt.dcm', 'ex.mat', 's.json', 'p.xyz', 't.tsv', 'seg.nii.gz', 'x.nii', 'patient001_frame01_gt.NII.GZ', 'Segmentation.seg.nrrd', 'label.NRRD', '1234_cvi42.zip', '1234_20209_2_0.ZIP']) {
      expect(readableInFolder(ok)).toBe(true);
    }
    // Compressed contour files (the core reads what they hold).
    for (const ok of ['contours.csv.gz', 'GPFile_000.txt.gz', 'rt.DCM.GZ']) expect(readableInFolder(ok)).toBe(true);
    // Any other .gz inside a folder is an archive or a compressed image, not contours.
    for (const no of ['IM_0001', 'a.png', '.hidden.csv', 'model.obj', 'images.tar.gz', 'scan.gz', 'model.obj.gz', '.seg.nii.gz', 'seg.nii.gz.part', 'a.gz.gz']) {
      expect(readableInFolder(no)).toBe(false);
    }
  });

  it('open the label maps of an ACDC subject folder beside its images and its Info.cfg', async () => {
    const subject = folder('patient001', [
      file('Info.cfg'),
      file('patient001_4d.nii.gz'),
      file('patient001_frame12_gt.nii.gz'),
      file('patient001_frame01_gt.nii.gz'),
      file('patient001_frame01.nii.gz'),
      file('MANDATORY_CITATION.md'),
      file('backup.tar.gz'),
    ]);
    const { files, skipped } = await filesOfEntries([subject]);
    // The images are read too: the core refuses them by name ("an image, not a label map").
    expect(files.map((f) => f.name)).toEqual([
      'patient001_4d.nii.gz', 'patient001_frame01_gt.nii.gz', 'patient001_frame01.nii.gz', 'patient001_frame12_gt.nii.gz',
    ]);
    expect(skipped).toBe(3); // Info.cfg, MANDATORY_CITATION.md, backup.tar.gz
  });
});
