import { describe, expect, it } from 'vitest';
import { BIV_EPI, partOf } from '../../web/src/core-client/derivedSurfaces';
import { warningsFor } from '../../web/src/app/fileWarnings';

describe('the biventricular epicardium in the app', () => {
  it('is drawn and warned about with the LV and RV epicardial curves it is made of', () => {
    expect(partOf('LV_EPI', BIV_EPI)).toBe(true);
    expect(partOf('rv_epi', 'biv_epi')).toBe(true);
    expect(partOf('LV_ENDO', BIV_EPI)).toBe(false);
    expect(partOf('RV_ENDO', BIV_EPI)).toBe(false);
    // Surfaces of their own stay apart; unlabelled curves and "no surface" take everything.
    expect(partOf('LV_EPI', 'LV_EPI')).toBe(true);
    expect(partOf('RV_EPI', 'LV_EPI')).toBe(false);
    expect(partOf(null, 'LV_ENDO')).toBe(true);
    expect(partOf('LV_ENDO', null)).toBe(true);
    const file = {
      warnings: ['two images of LV epi slice 3', 'a speck in the RV epi', 'an LV endo stray', 'units'],
      surfaceWarnings: [
        { surface: 'LV_EPI', text: 'two images of LV epi slice 3' },
        { surface: 'RV_EPI', text: 'a speck in the RV epi' },
        { surface: 'LV_ENDO', text: 'an LV endo stray' },
      ],
    };
    expect(warningsFor(file, BIV_EPI)).toEqual(['two images of LV epi slice 3', 'a speck in the RV epi', 'units']);
    expect(warningsFor(file, 'LV_ENDO')).toEqual(['an LV endo stray', 'units']);
  });
});
