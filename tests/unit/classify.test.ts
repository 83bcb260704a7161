import { describe, expect, it } from 'vitest';
import { axisAngleDeg, classifyContours, planeNormal } from '../../web/src/viewer/classify';
import type { ContourInfo } from '../../web/src/core-client/protocol';

describe('display-side SAX/LAX split', () => {
  it('finds plane normals and sign-free angles', () => {
    const pts = [0, 0, 5, 10, 0, 5, 0, 10, 5, 10, 10, 5];
    const n = planeNormal(pts, [0, 1, 2, 3]);
    expect(n && Math.abs(n[2])).toBeCloseTo(1, 9);
    expect(axisAngleDeg([0, 0, 1], [0, 0, -1])).toBeCloseTo(0, 9);
    expect(axisAngleDeg([0, 0, 1], [1, 0, 0])).toBeCloseTo(90, 9);
    expect(planeNormal(pts, [0, 1])).toBeNull();
  });
  it('splits 5 slightly tilted rings from 2 orthogonal long-axis curves', () => {
    const pts: number[] = [];
    const contours: ContourInfo[] = [];
    for (let k = 0; k < 5; k++) {
      const start = pts.length / 3;
      const tilt = (k - 2) * 0.05; // up to ~6 degrees
      for (let i = 0; i < 30; i++) {
        const a = (2 * Math.PI * i) / 30;
        const x = 20 * Math.cos(a), y = 20 * Math.sin(a);
        pts.push(x, y, k * 10 + tilt * x);
      }
      contours.push({ id: `c${k}`, surface: null, kind: null, pieces: [{ closed: true, start, count: 30 }] });
    }
    for (const phi of [0, Math.PI / 2]) {
      const start = pts.length / 3;
      for (let i = 0; i < 40; i++) {
        const t = Math.PI * (0.1 + (0.8 * i) / 39);
        const r = 20 * Math.sin(t);
        pts.push(r * Math.cos(phi), r * Math.sin(phi), 20 - 25 * Math.cos(t));
      }
      contours.push({ id: `l${phi}`, surface: null, kind: null, pieces: [{ closed: false, start, count: 40 }] });
    }
    expect(classifyContours(contours, pts)).toEqual(['SAX', 'SAX', 'SAX', 'SAX', 'SAX', 'LAX', 'LAX']);
    contours[0].kind = 'LAX';
    expect(classifyContours(contours, pts)[0]).toBe('LAX'); // the core's kind wins
  });
});
