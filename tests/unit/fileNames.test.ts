// Names of opened files (web/src/app/fileNames.ts): another file of a name already open gets
// "name (2).ext"; the same file again keeps its name.
import { describe, expect, it } from 'vitest';
import { distinctName, fileIdentity, renamedText } from '../../web/src/app/fileNames';

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
  it('says which file got which name', () => {
    expect(renamedText([])).toBe('');
    expect(renamedText([{ given: 'a.txt', as: 'a (2).txt' }, { given: 'b.txt', as: 'b (2).txt' }])).toBe(
      'Files with names already open are listed under new names in the File picker: a.txt as a (2).txt, b.txt as b (2).txt.',
    );
  });
});
