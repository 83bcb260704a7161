import { describe, expect, it } from 'vitest';
import { cameraPlacement, dashScale, fitView } from '../../web/src/viewer/fitView';

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
  it('frames a refused file at its own scale: a heart in metres fills the view like one in mm', () => {
    // Two rings of radius 0.02 (metres) 0.08 apart: the bounding sphere's radius is hypot(0.04, 0.02).
    const ring = (z: number, r: number) => Array.from({ length: 24 }, (_, k) => [r * Math.cos(k / 3.82), r * Math.sin(k / 3.82), z]).flat();
    const metres = fitView([...ring(0, 0.02), ...ring(0.08, 0.02)]);
    expect(metres.radius).toBeCloseTo(Math.hypot(0.04, 0.02), 3);
    const mm = fitView([...ring(0, 20), ...ring(80, 20)]);
    expect(mm.radius / metres.radius).toBeCloseTo(1000, 0);
    // Near and far scale with the scene: nothing of the sphere is clipped, at any scale.
    for (const r of [metres.radius, mm.radius, 5e4]) {
      const p = cameraPlacement(r, 35, 1.6);
      expect(p.near).toBeLessThan(p.distance - r);
      expect(p.far).toBeGreaterThan(p.distance + r);
      expect(p.distance / r).toBeCloseTo(cameraPlacement(1, 35, 1.6).distance, 9);
    }
    // A single point gets 1 mm; coordinates whose span overflows cannot be framed: the default view.
    expect(fitView([3, 4, 5]).radius).toBe(1);
    const overflow = fitView([-1e308, 0, 0, 1e308, 0, 0]);
    expect(overflow).toEqual(fitView([]));
    // Dashes keep their mm length for hearts, and scale with the scene outside that range.
    expect([dashScale(60), dashScale(25), dashScale(200)]).toEqual([1, 1, 1]);
    expect(dashScale(metres.radius)).toBeCloseTo(metres.radius / 25, 12);
    expect(dashScale(5e4)).toBe(250);
    expect([dashScale(0), dashScale(NaN), dashScale(Infinity)]).toEqual([1, 1, 1]);
  });
});
