// Names of opened files (web/src/app/fileNames.ts): another file of a name already open gets
// "name (2).ext"; the same file again keeps its name.
import { describe, expect, it } from 'vitest';
import { distinctName, fileIdentity, renamedText } from '../../web/src/app/fileNames';
import { splitExtension } from '../../web/src/io/fileExtension';

describe('distinctName', () => {
  const open = new Map([
    ['GPFile_000.txt', fileIdentity({ size: 10, lastModified: 1 })],
    ['GPFile_000 (2).txt', fileIdentity({ size: 11, lastModified: 2 })],
    ['notes', 'file:1:1'],
  ]);
  it('keeps a free name and the name of the same file', () => {
    expect(distinctName('a.csv', 'file:1:1', open)).toBe('a.csv');
    expect(distinctName('GPFile_000.txt', fileIdentity({ size: 10, lastModified: 1 }), open)).toBe('GPFile_000.txt');
    expect(distinctName('GPFile_000.txt', fileIdentity({ size: 11, lastModified: 2 }), open)).toBe('GPFile_000 (2).txt');
  });
  it('numbers another file of a name in use before its extension', () => {
    expect(distinctName('GPFile_000.txt', fileIdentity({ size: 12, lastModified: 3 }), open)).toBe('GPFile_000 (3).txt');
    expect(distinctName('notes', 'file:2:2', open)).toBe('notes (2)');
  });
  it('numbers a compressed label map before its whole extension (.nii.gz)', () => {
    const maps = new Map([['seg.nii.gz', 'file:1:1'], ['Seg.NII.GZ', 'file:2:2']]);
    expect(distinctName('seg.nii.gz', 'file:3:3', maps)).toBe('seg (2).nii.gz');
    expect(distinctName('Seg.NII.GZ', 'file:3:3', maps)).toBe('Seg (2).NII.GZ');
    expect(distinctName('seg.nii.gz', 'file:1:1', maps)).toBe('seg.nii.gz');
    // A compressed CSV likewise: the core reads `contours (2).csv` inside.
    expect(distinctName('contours.csv.gz', 'file:3:3', new Map([['contours.csv.gz', 'file:1:1']]))).toBe('contours (2).csv.gz');
  });
  it('says which file got which name', () => {
    expect(renamedText([])).toBe('');
    expect(renamedText([{ given: 'a.txt', as: 'a (2).txt' }, { given: 'b.txt', as: 'b (2).txt' }])).toBe(
      'Files with names already open are listed under new names in the File picker: a.txt as a (2).txt, b.txt as b (2).txt.',
    );
  });
});

describe('splitExtension', () => {
  it('keeps a compressed file\'s extension whole (.nii.gz, .csv.gz) and splits other names at their last dot', () => {
    expect(splitExtension('seg.nii.gz')).toEqual(['seg', '.nii.gz']);
    expect(splitExtension('Segmentation.seg.nrrd')).toEqual(['Segmentation', '.seg.nrrd']);
    expect(splitExtension('label.nrrd')).toEqual(['label', '.nrrd']);
    expect(splitExtension('a.b.NII.GZ')).toEqual(['a.b', '.NII.GZ']);
    expect(splitExtension('x.nii')).toEqual(['x', '.nii']);
    expect(splitExtension('contours.csv.gz')).toEqual(['contours', '.csv.gz']);
    expect(splitExtension('images.tar.gz')).toEqual(['images', '.tar.gz']);
    expect(splitExtension('notes.backup.gz')).toEqual(['notes.backup', '.gz']);
    expect(splitExtension('GPFile_000.txt')).toEqual(['GPFile_000', '.txt']);
    expect(splitExtension('notes')).toEqual(['notes', '']);
    expect(splitExtension('.nii.gz')).toEqual(['.nii', '.gz']);
    expect(splitExtension('.hidden')).toEqual(['.hidden', '']);
  });
});
