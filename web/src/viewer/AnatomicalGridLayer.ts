/**
 * The anatomical mesh (the Export panel's View on it) drawn as its edges over the reconstructed
 * surface, so the user sees where its rings and meridians fall before saving it. Its vertices lie
 * on the surface but its edges are chords that sag under it, so the lines are drawn twice: bright
 * where nothing is in front of them, and faint through the surface, so a sagging chord still reads
 * as one line instead of a dotted one. The viewer's clipping plane cuts it like the surface.
 * Owns its GPU resources: call `dispose()`.
 */
import * as THREE from 'three';

/** Amber (the palette's second accent): apart from every viridis colour of the surface under it. */
const GRID_COLOUR = 0xffb74d;

/** Each edge of the triangles once (pairs of vertex indices), for LineSegments. */
export function uniqueEdges(indices: ArrayLike<number>): Uint32Array {
  const seen = new Set<string>();
  const out: number[] = [];
  for (let t = 0; t + 2 < indices.length; t += 3) {
    for (let k = 0; k < 3; k++) {
      const a = indices[t + k];
      const b = indices[t + ((k + 1) % 3)];
      const key = a < b ? `${a},${b}` : `${b},${a}`;
      if (seen.has(key)) continue;
      seen.add(key);
      out.push(a, b);
    }
  }
  return Uint32Array.from(out);
}

export class AnatomicalGridLayer {
  readonly group = new THREE.Group();
  private readonly visibleLines: THREE.LineSegments;
  private readonly hiddenLines: THREE.LineSegments;
  private readonly materials: THREE.LineBasicMaterial[];
  private geometry: THREE.BufferGeometry | null = null;
  private vertexCount = 0;

  constructor(clippingPlanes: THREE.Plane[]) {
    this.group.name = 'anatomical-grid';
    const bright = new THREE.LineBasicMaterial({ color: GRID_COLOUR, clippingPlanes });
    const faint = new THREE.LineBasicMaterial({ color: GRID_COLOUR, transparent: true, opacity: 0.3, depthTest: false, depthWrite: false, clippingPlanes });
    this.materials = [bright, faint];
    const empty = new THREE.BufferGeometry();
    this.hiddenLines = new THREE.LineSegments(empty, faint);
    this.visibleLines = new THREE.LineSegments(empty, bright);
    // The faint pass after everything opaque, so the surface does not cover it.
    this.hiddenLines.renderOrder = 10;
    this.group.add(this.visibleLines, this.hiddenLines);
    this.group.visible = false;
  }

  /** Draws the mesh of `positions` (xyz, mm) and `indices` (three per triangle) as its edges. */
  show(positions: Float32Array, indices: Uint32Array): void {
    this.geometry?.dispose();
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(positions, 3));
    g.setIndex(new THREE.BufferAttribute(uniqueEdges(indices), 1));
    g.computeBoundingSphere();
    this.geometry = g;
    this.visibleLines.geometry = g;
    this.hiddenLines.geometry = g;
    this.vertexCount = positions.length / 3;
    this.group.visible = true;
  }

  clear(): void {
    this.group.visible = false;
    this.geometry?.dispose();
    this.geometry = null;
    const empty = new THREE.BufferGeometry();
    this.visibleLines.geometry = empty;
    this.hiddenLines.geometry = empty;
    this.vertexCount = 0;
  }

  /** Vertices of the grid drawn (0: none). */
  get vertices(): number {
    return this.vertexCount;
  }

  dispose(): void {
    this.clear();
    for (const m of this.materials) m.dispose();
  }
}
