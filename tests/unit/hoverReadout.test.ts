// Where the hover read-out goes (web/src/ui/HoverReadout.ts): beside the pointer, flipped to the
// other side near the right or bottom edge of the 3D view, which clips anything past it.
import { describe, expect, it } from 'vitest';
import { readoutPlacement } from '../../web/src/ui/HoverReadout';

describe('hover read-out placement', () => {
  it('below right of the pointer where the view has room', () => {
    expect(readoutPlacement(100, 80, 200, 44, 534, 604)).toEqual({ left: 114, top: 94 });
  });

  it('left of the pointer near the right edge, above it near the bottom edge', () => {
    // The pointer 30 px from the right edge of a 534 x 604 view (the box used to end 200 px past it).
    expect(readoutPlacement(504, 302, 207, 44, 534, 604)).toEqual({ left: 504 - 14 - 207, top: 316 });
    expect(readoutPlacement(267, 584, 207, 44, 534, 604)).toEqual({ left: 281, top: 584 - 14 - 44 });
    const corner = readoutPlacement(520, 590, 207, 44, 534, 604);
    expect(corner.left + 207).toBeLessThanOrEqual(534);
    expect(corner.top + 44).toBeLessThanOrEqual(604);
  });

  it('never past the top left, even in a view narrower than the box', () => {
    expect(readoutPlacement(50, 10, 207, 44, 120, 40)).toEqual({ left: 0, top: 0 });
  });
});
