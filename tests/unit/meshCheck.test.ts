// The result panel's mesh-check rows (session 13): self-intersections from `result_json().quality`
// are flagged, folds reported. The real core's counts are exercised in tests/node and the CLI tests.
import { describe, expect, it } from 'vitest';
import { meshCheckText } from '../../web/src/ui/runText';

describe('meshCheckText', () => {
  it('says a clean mesh has no self-intersections and does not warn', () => {
    const c = meshCheckText({ folded_edges: 0, self_intersections: 0 });
    expect(c.crossings.text).toBe('none');
    expect(c.crossings.warn).toBe(false);
    expect(c.folds.text).toBe('0');
  });

  it('reports folds without warning', () => {
    const c = meshCheckText({ folded_edges: 4, self_intersections: 0 });
    expect(c.crossings.warn).toBe(false);
    expect(c.folds.text).toBe('4');
    expect(c.folds.title).toContain('more than 90°');
  });

  it('warns when triangles cross, with the count', () => {
    const one = meshCheckText({ folded_edges: 1, self_intersections: 1 });
    expect(one.crossings.text).toBe('1 pair');
    expect(one.crossings.warn).toBe(true);
    const many = meshCheckText({ folded_edges: 0, self_intersections: 6 });
    expect(many.crossings.text).toBe('6 pairs');
    expect(many.crossings.title).toContain('6 pairs of triangles cross');
  });
});
