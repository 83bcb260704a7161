import { describe, expect, it } from 'vitest';
import { fitView } from '../../web/src/viewer/fitView';

describe('fitView', () => {
  it('finds centre, radius and the long axis of an elongated cloud', () => {
    // Rings of radius 20 mm stacked along a tilted axis from -40 to +40 mm around (10, -5, 3).
    const axis = [1 / Math.sqrt(2), 0, 1 / Math.sqrt(2)];
    const u = [0, 1, 0];
    const w = [axis[1] * u[2] - axis[2] * u[1], axis[2] * u[0] - axis[0] * u[2], axis[0] * u[1] - axis[1] * u[0]];
    const pts: number[] = [];
    for (let h = -40; h <= 40; h += 10) {
      for (let k = 0; k < 36; k++) {
        const a = (k / 36) * 2 * Math.PI;
        for (let c = 0; c < 3; c++) pts.push([10, -5, 3][c] + h * axis[c] + 20 * (Math.cos(a) * u[c] + Math.sin(a) * w[c]));
      }
    }
    const fit = fitView(pts);
    fit.center.forEach((v, i) => expect(v).toBeCloseTo([10, -5, 3][i], 6));
    expect(fit.radius).toBeCloseTo(Math.hypot(40, 20), 6);
    expect(Math.abs(fit.axis[0] * axis[0] + fit.axis[1] * axis[1] + fit.axis[2] * axis[2])).toBeCloseTo(1, 6);
    expect(Math.abs(fit.side[0] * axis[0] + fit.side[1] * axis[1] + fit.side[2] * axis[2])).toBeLessThan(1e-9);
  });
  it('survives empty and non-finite input', () => {
    expect(fitView([]).radius).toBe(50);
    expect(fitView([NaN, 0, 0, 1, 2, 3]).center).toEqual([1, 2, 3]);
    // bounding-box centre, not the centroid of unevenly dense samples
    expect(fitView([0, 0, 0, 0, 0, 0, 0, 0, 0, 10, 0, 0]).center).toEqual([5, 0, 0]);
  });
});
