import { describe, expect, it } from 'vitest';
import { warningsFor } from '../../web/src/app/fileWarnings';

const file = {
  warnings: [
    'coordinates span 0.0500; expected mm',
    '"s18" (line 10) and "s19" (line 40): two images of one slice position',
    '"rv3" (line 90, only 1 point) is not a curve',
  ],
  surfaceWarnings: [
    { surface: 'LV_ENDO', text: '"s18" (line 10) and "s19" (line 40): two images of one slice position' },
    { surface: 'RV_ENDO', text: '"rv3" (line 90, only 1 point) is not a curve' },
  ],
};

describe('warningsFor', () => {
  it('keeps the file-wide warnings and those of the surface run, in file order', () => {
    expect(warningsFor(file, 'LV_ENDO')).toEqual([file.warnings[0], file.warnings[1]]);
    expect(warningsFor(file, 'rv_endo')).toEqual([file.warnings[0], file.warnings[2]]);
  });

  it('leaves out every surface warning for a surface the file names none of', () => {
    expect(warningsFor(file, 'LV_EPI')).toEqual([file.warnings[0]]);
  });

  it('shows everything with no surface chosen or no scoping from the core', () => {
    expect(warningsFor(file, null)).toHaveLength(3);
    expect(warningsFor({ warnings: file.warnings }, 'LV_EPI')).toHaveLength(3);
  });
});
