import { describe, expect, it } from 'vitest';
import { landmarkGroups } from '../../web/src/viewer/LandmarkLayer';

describe('landmark legend groups', () => {
  it('groups by name in order of appearance with counts and stable colours', () => {
    const p = (name: string) => ({ name, x: 0, y: 0, z: 0 });
    const g = landmarkGroups([p('MITRAL_VALVE'), p('APEX_POINT'), p('MITRAL_VALVE'), p('Apex ROI'), p('RV_INSERT'), p('Other')]);
    expect(g.map((x) => [x.name, x.count])).toEqual([
      ['MITRAL_VALVE', 2],
      ['APEX_POINT', 1],
      ['Apex ROI', 1],
      ['RV_INSERT', 1],
      ['Other', 1],
    ]);
    expect(g[1].color).toBe('#ff5252');
    // Unknown names take distinct colours from the rest of the palette.
    expect(g[2].color).not.toBe(g[4].color);
    expect(landmarkGroups([])).toEqual([]);
  });
});
