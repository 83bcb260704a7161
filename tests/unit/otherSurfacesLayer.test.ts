import { describe, expect, it } from 'vitest';
import { otherSettings } from '../../web/src/viewer/OtherSurfacesLayer';
import { runSignature } from '../../web/src/app/keptSurfaces';

describe('other surfaces key', () => {
  it('names the ghosts run with other parameters than the surface on screen', () => {
    const base = { params: { lambda: 1e5, iterations: 250 }, lids: 'auto', options: { smoothing_method: 'taubin' } };
    const smoother = { ...base, params: { lambda: 1e3, iterations: 250 } };
    const kept = new Map([
      ['LV_ENDO', runSignature(base)],
      ['LV_EPI', runSignature(base)],
      ['RV_ENDO', runSignature(smoother)],
    ]);
    expect(otherSettings(kept, ['LV_EPI', 'RV_ENDO'], 'LV_ENDO')).toEqual(['RV_ENDO']);
    // The current surface re-run with the smoother settings: now the LV epicardium differs.
    kept.set('LV_ENDO', runSignature(smoother));
    expect(otherSettings(kept, ['LV_EPI', 'RV_ENDO'], 'LV_ENDO')).toEqual(['LV_EPI']);
    // No run of the current surface kept yet (or no surface): nothing to compare with.
    expect(otherSettings(kept, ['LV_ENDO', 'LV_EPI', 'RV_ENDO'], 'RV_EPI')).toEqual([]);
    expect(otherSettings(kept, ['LV_ENDO'], null)).toEqual([]);
  });

  it('signatures ignore the surface and see every setting', () => {
    const a = { params: { lambda: 1 }, lids: 'auto', options: { end_caps: 'auto' } };
    const run = (surface: string) => ({ ...a, surface });
    expect(runSignature(run('LV_ENDO'))).toBe(runSignature(run('RV_ENDO')));
    expect(runSignature(a)).not.toBe(runSignature({ ...a, lids: 'none' }));
    expect(runSignature(a)).not.toBe(runSignature({ ...a, options: { end_caps: 'off' } }));
    expect(runSignature(a)).not.toBe(runSignature({ ...a, params: { lambda: 2 } }));
  });

  it('a run before a contour was left out (of any surface) is marked, as one with other parameters', () => {
    const a = { params: { lambda: 1 }, lids: 'auto', options: { end_caps: 'auto' } };
    expect(runSignature(a)).toBe(runSignature({ ...a, leave_out: [] }));
    expect(runSignature({ ...a, leave_out: ['s07', 'r1'] })).toBe(runSignature({ ...a, leave_out: ['r1', 's07'] }));
    const kept = new Map([
      ['LV_ENDO', runSignature({ ...a, leave_out: ['s07'] })],
      ['RV_ENDO', runSignature(a)],
      ['LV_EPI', runSignature({ ...a, leave_out: ['s07'] })],
    ]);
    expect(otherSettings(kept, ['RV_ENDO', 'LV_EPI'], 'LV_ENDO')).toEqual(['RV_ENDO']);
  });
});
