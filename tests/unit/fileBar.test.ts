// The surface picker lists the heart's surfaces in one fixed order whatever order the file has them in.
import { describe, expect, it } from 'vitest';
import { ACCEPT, surfaceLabel, surfaceOrder } from '../../web/src/io/FileBar';

describe('surface picker order', () => {
  it('LV endo, LV epi, RV endo, RV epi, then other surfaces in the file order', () => {
    // patient1-ED.csv lists its curves RV first.
    expect(surfaceOrder(['RV_ENDO', 'RV_EPI', 'LV_EPI', 'LV_ENDO'])).toEqual(['LV_ENDO', 'LV_EPI', 'RV_ENDO', 'RV_EPI']);
    expect(surfaceOrder(['LA_ENDO', 'RV_ENDO', 'AORTA', 'LV_ENDO'])).toEqual(['LV_ENDO', 'RV_ENDO', 'LA_ENDO', 'AORTA']);
    expect(surfaceOrder([])).toEqual([]);
    // The biventricular epicardium the core offers comes after the four.
    expect(surfaceOrder(['BIV_EPI', 'RV_EPI', 'LV_EPI', 'LA_ENDO'])).toEqual(['LV_EPI', 'RV_EPI', 'BIV_EPI', 'LA_ENDO']);
    expect(surfaceLabel('BIV_EPI')).toBe('BiV epicardium');
    expect(surfaceLabel('RV_EPI')).toBe('RV epicardium');
    expect(surfaceLabel('LA_ENDO')).toBe('LA_ENDO');
  });
});

describe('the Open dialog', () => {
  it('offers NIfTI label maps, compressed or not, beside the contour formats', () => {
    const kinds = ACCEPT.split(',');
    for (const k of ['.csv', '.txt', '.mat', '.dcm', '.nii', '.nii.gz', '.nrrd', '.gz', '.cvi42wsx', '.zip']) expect(kinds).toContain(k);
    expect(kinds.every((k) => k.startsWith('.') || /^[a-z]+\/[a-z-]+$/.test(k))).toBe(true);
  });
});
