// The myocardium wall in the 3D view, its pure parts: the PLY the worker writes read back (the
// vertices, triangles, thickness and regions, the region names of the header), the colours (region
// -> tint, per triangle corner; thickness -> viridis with its scale top), and the corners with
// normals smoothed within a region but not across a region border.
import { describe, expect, it } from 'vitest';
import { readPly } from '../../web/src/io/readPly';
import { wallSolidFromPly } from '../../web/src/io/wallSolid';
import { VIRIDIS_LUT_U8, niceTicks } from '../../web/src/viewer/colormap';
import {
  REGION_TINTS, SECTION_TINT, distinctColours, hexBytes, regionCornerColours, regionPalette, regionTint, thicknessCornerColours, thicknessScaleMax,
} from '../../web/src/viewer/wallColours';
import { wallCorners } from '../../web/src/viewer/wallGeometry';
import { boxPly, wallPly } from './plyFixture';

describe('the wall PLY read back', () => {
  it('gives the vertices, triangles, thickness per vertex, region per triangle and the region names', () => {
    const solid = wallSolidFromPly(boxPly(10, 4));
    expect(solid.positions.length).toBe(24);
    expect(Array.from(solid.positions.subarray(18, 21))).toEqual([10, 10, 4]);
    expect(solid.indices.length).toBe(36);
    expect(Array.from(solid.indices.subarray(0, 6))).toEqual([0, 2, 1, 0, 3, 2]);
    expect(Array.from(solid.thickness!)).toEqual([0, 0, 0, 0, 4, 4, 4, 4]);
    expect(Array.from(solid.regions!)).toEqual([2, 2, 3, 3, 1, 1, 1, 1, 1, 1, 1, 1]);
    expect(solid.regionNames).toEqual([{ id: 1, name: 'epicardium' }, { id: 2, name: 'endocardium' }, { id: 3, name: 'base' }]);
  });

  it('keeps the header comments (a file named end_header.csv does not end the header) and every element', () => {
    const ply = readPly(boxPly());
    expect(ply.comments.slice(0, 3)).toEqual(['heartmesh 0.1.0', 'input: end_header.csv', 'region 1 epicardium']);
    expect(ply.elements.get('vertex')?.count).toBe(8);
    const face = ply.elements.get('face')!;
    expect(face.count).toBe(12);
    expect(Array.from(face.lists.get('vertex_indices')!.offsets.subarray(0, 4))).toEqual([0, 3, 6, 9]);
  });

  it('without thickness or regions, says so with null; refuses what it cannot read', () => {
    const plain = wallSolidFromPly(wallPly({ positions: [0, 0, 0, 1, 0, 0, 0, 1, 0], faces: [[0, 1, 2]] }));
    expect(plain.thickness).toBeNull();
    expect(plain.regions).toBeNull();
    expect(plain.regionNames).toEqual([]);
    const ascii = new TextEncoder().encode('ply\nformat ascii 1.0\nelement vertex 0\nend_header\n');
    expect(() => readPly(ascii)).toThrow(/only binary_little_endian is read, not ascii/);
    const whole = boxPly();
    expect(() => readPly(whole.subarray(0, whole.length - 5))).toThrow(/ends before its last element/);
    const quad = wallPly({ positions: [0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0], faces: [[0, 1, 2, 3]] });
    expect(() => wallSolidFromPly(quad)).toThrow(/face 0 of the wall is no triangle/);
    const far = wallPly({ positions: [0, 0, 0, 1, 0, 0, 0, 1, 0], faces: [[0, 1, 7]] });
    expect(() => wallSolidFromPly(far)).toThrow(/names vertex 7 of 3/);
  });
});

describe('region colours', () => {
  it('give each region of the LV wall and of the biventricular wall its own tint, the other-surfaces key\'s where it is one of those', () => {
    const lv = regionPalette([{ id: 1, name: 'epicardium' }, { id: 2, name: 'endocardium' }, { id: 3, name: 'base' }]);
    expect([...lv]).toEqual([[1, '#ffb74d'], [2, '#ef9a9a'], [3, '#78909c']]);
    const biv = regionPalette([{ id: 4, name: 'base' }, { id: 1, name: 'epicardium' }, { id: 2, name: 'lv_endocardium' }, { id: 3, name: 'rv_endocardium' }]);
    expect([...biv]).toEqual([[1, '#ffb74d'], [2, '#ef9a9a'], [3, '#90caf9'], [4, '#78909c']]);
    expect(new Set(biv.values()).size).toBe(4);
    // The cut faces' colour is none of them.
    expect(Object.values(REGION_TINTS)).not.toContain(SECTION_TINT);
    // Names not known take the spares in turn, whatever their case.
    const odd = regionPalette([{ id: 1, name: 'septum' }, { id: 2, name: 'Apex' }, { id: 3, name: 'EPICARDIUM' }]);
    expect(odd.get(3)).toBe('#ffb74d');
    expect(odd.get(1)).not.toBe(odd.get(2));
    expect(regionTint('Base', 0)).toBe('#78909c');
  });

  it('colour every corner of a triangle in its region\'s tint: as many colours as regions', () => {
    const palette = regionPalette([{ id: 1, name: 'epicardium' }, { id: 2, name: 'endocardium' }, { id: 3, name: 'base' }]);
    const rgb = regionCornerColours([2, 1, 3, 1], palette);
    expect(rgb.length).toBe(4 * 9);
    expect(Array.from(rgb.subarray(0, 9))).toEqual([...hexBytes('#ef9a9a'), ...hexBytes('#ef9a9a'), ...hexBytes('#ef9a9a')]);
    expect(Array.from(rgb.subarray(18, 21))).toEqual([0x78, 0x90, 0x9c]);
    expect(distinctColours(rgb)).toBe(3);
    // A region missing from the palette still gets a colour of its own.
    expect(distinctColours(regionCornerColours([1, 9], palette))).toBe(2);
  });
});

describe('thickness colours and their scale', () => {
  it('tops the scale at the 98th percentile rounded up to a whole mm, the legend ticking 0 to it', () => {
    const ramp = Array.from({ length: 101 }, (_, i) => i / 10); // 0 .. 10 mm
    expect(thicknessScaleMax(ramp)).toBe(10); // p98 = 9.8
    // A few very thick vertices do not stretch the scale.
    const wall = [...Array(990).fill(6.3), ...Array(10).fill(40)];
    expect(thicknessScaleMax(wall)).toBe(7);
    expect(thicknessScaleMax([0, 0, Number.NaN])).toBe(1);
    expect(thicknessScaleMax([])).toBe(1);
    expect(niceTicks(0, 14, 5)).toEqual([0, 5, 10]);
  });

  it('colours each corner by its vertex\'s thickness: 0 at the bottom of viridis, the top and above at the top', () => {
    const rgb = thicknessCornerColours([0, 1, 2], [0, 14, 30], 14);
    const top = (VIRIDIS_LUT_U8.length / 3 - 1) * 3;
    expect(Array.from(rgb.subarray(0, 3))).toEqual(Array.from(VIRIDIS_LUT_U8.subarray(0, 3)));
    expect(Array.from(rgb.subarray(3, 6))).toEqual(Array.from(VIRIDIS_LUT_U8.subarray(top, top + 3)));
    expect(Array.from(rgb.subarray(6, 9))).toEqual(Array.from(rgb.subarray(3, 6)));
    expect(distinctColours(rgb)).toBe(2);
  });
});

describe('the wall\'s corners', () => {
  it('one per triangle corner, normals smoothed within a region and not across its border', () => {
    const solid = wallSolidFromPly(boxPly(10, 4));
    const { positions, normals } = wallCorners(solid.positions, solid.indices, solid.regions);
    expect(positions.length).toBe(12 * 9);
    // Triangle 2 (top, region 3), corner 0 is vertex 4 at (0, 0, 4): straight up, not bent towards the sides.
    expect(Array.from(positions.subarray(18, 21))).toEqual([0, 0, 4]);
    expect(Array.from(normals.subarray(18, 21))).toEqual([0, 0, 1]);
    // The sides (region 1) meet at vertex 0 at a right angle: their corners there share the
    // area-weighted mean of two triangles of the -y face and one of the -x face, level (no z).
    const side = Array.from(normals.subarray(4 * 9, 4 * 9 + 3));
    expect(side[0]).toBeCloseTo(-1 / Math.sqrt(5), 6);
    expect(side[1]).toBeCloseTo(-2 / Math.sqrt(5), 6);
    expect(side[2]).toBeCloseTo(0, 6);
    expect(Array.from(normals.subarray(10 * 9 + 3, 10 * 9 + 6))).toEqual(side); // triangle 10's corner at vertex 0
    for (let i = 0; i < normals.length; i += 3) expect(Math.hypot(normals[i], normals[i + 1], normals[i + 2])).toBeCloseTo(1, 6);
    // As one region the top corner leans out over the sides.
    const one = wallCorners(solid.positions, solid.indices, null);
    expect(one.normals[20]).toBeLessThan(0.99);
  });
});
