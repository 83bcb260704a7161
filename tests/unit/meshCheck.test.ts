// The result panel's "Mesh check" row (session 13): self-intersections from `result_json().quality`
// are flagged, folds reported. The real core's counts are exercised in tests/node and the CLI tests.
import { describe, expect, it } from 'vitest';
import { meshCheckText } from '../../web/src/ui/runText';

describe('meshCheckText', () => {
  it('says a clean closed mesh is closed with no crossings, and does not warn', () => {
    const c = meshCheckText(true, { folded_edges: 0, self_intersections: 0 });
    expect(c.text).toBe('closed, no crossings');
    expect(c.warn).toBe(false);
    expect(c.title).toContain('no creases');
  });

  it('reports folds without warning', () => {
    const c = meshCheckText(true, { folded_edges: 4, self_intersections: 0 });
    expect(c.text).toBe('closed, no crossings · 4 folds');
    expect(c.warn).toBe(false);
    expect(c.title).toContain('4 edges where neighbouring triangles turn more than 90°');
  });

  it('warns when triangles cross, with the count', () => {
    const one = meshCheckText(true, { folded_edges: 1, self_intersections: 1 });
    expect(one.text).toBe('1 crossing · 1 fold');
    expect(one.warn).toBe(true);
    const many = meshCheckText(false, { folded_edges: 0, self_intersections: 6 });
    expect(many.text).toBe('6 crossings');
    expect(many.title).toContain('6 pairs of triangles cross');
  });

  it('says an open mesh is open', () => {
    expect(meshCheckText(false, { folded_edges: 0, self_intersections: 0 }).text).toBe('open, no crossings');
  });
});
