// The banner's note on the SliceInfoFiles set aside in a drop: two biv-me patient folders dropped
// together gave "SliceInfoFile.txt, SliceInfoFile.txt set aside: ...".
import { describe, expect, it } from 'vitest';
import { setAsideText } from '../../web/src/app/errors';

describe('setAsideText', () => {
  it('names one file, and counts files of one name instead of repeating it', () => {
    expect(setAsideText(['SliceInfoFile.txt'], 'GPFile_000.txt')).toBe(
      'SliceInfoFile.txt set aside: image planes, not contours (the contours come from GPFile_000.txt; only the command line reads the planes, to check that each contour lies in its own).',
    );
    expect(setAsideText(['SliceInfoFile.txt', 'SliceInfoFile.txt'], 'GPFile_000.txt')).toMatch(/^2 files named SliceInfoFile\.txt set aside: image planes/);
    expect(setAsideText(['SliceInfoFile.txt', 'SliceInfo_ES.txt', 'SliceInfoFile.txt'], 'a.txt')).toMatch(/^2 files named SliceInfoFile\.txt, SliceInfo_ES\.txt set aside/);
  });
});
