/**
 * One contour picked out in the 3D view (the Contours panel's row under the pointer, or clicked):
 * drawn over everything in white, its line and large discs at its points (WebGL lines are one
 * pixel wide whatever is asked, so the discs are what makes it stand out), so the contour a row
 * names is found in the heart even inside the mesh. Built from the geometry the contour layers
 * draw (the run's contours, or those left out); the viewer rebuilds it when they change.
 */
import * as THREE from 'three';
import type { ContourInfo } from '../core-client/protocol';
import { warmupGeometry } from './ContourLayer';
import { discTexture } from './discTexture';
import { givenSegments } from './GivenContourLayer';

export const HIGHLIGHT_COLOR = '#ffffff';

export class ContourHighlight {
  readonly group = new THREE.Group();
  /** The contour shown (null: none). */
  private shownId: string | null = null;
  private lines: THREE.LineSegments | null = null;
  private discs: THREE.Points | null = null;
  private readonly lineMaterial = new THREE.LineBasicMaterial({ color: HIGHLIGHT_COLOR, transparent: true, opacity: 0.95, depthTest: false, depthWrite: false });
  private readonly discMaterial = new THREE.PointsMaterial({
    color: HIGHLIGHT_COLOR, size: 9, sizeAttenuation: false, map: discTexture(), alphaTest: 0.5, transparent: true, depthTest: false, depthWrite: false,
  });

  constructor() {
    this.group.name = 'contour-highlight';
  }

  /** The id of the contour drawn (null: none). */
  get id(): string | null {
    return this.shownId;
  }

  /** Draws `contour` (its pieces index `points`, xyz mm) as contour `id`; null clears. */
  show(id: string | null, found: { contour: ContourInfo; points: Float32Array } | null): void {
    this.clear();
    if (id === null || !found || found.contour.pieces.length === 0) return;
    const { contour, points } = found;
    const segments = givenSegments([contour], points, null);
    if (segments.length > 0) {
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.BufferAttribute(segments, 3));
      this.lines = new THREE.LineSegments(g, this.lineMaterial);
      this.lines.renderOrder = 6;
      this.group.add(this.lines);
    }
    const xyz: number[] = [];
    for (const p of contour.pieces) for (let k = 0; k < p.count; k++) xyz.push(...points.subarray((p.start + k) * 3, (p.start + k) * 3 + 3));
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.Float32BufferAttribute(xyz, 3));
    this.discs = new THREE.Points(g, this.discMaterial);
    this.discs.renderOrder = 6;
    this.group.add(this.discs);
    this.shownId = id;
  }

  /** The materials, for compiling their shaders ahead of the first frame. */
  get materialObjects(): THREE.Object3D[] {
    const g = warmupGeometry();
    return [new THREE.LineSegments(g, this.lineMaterial), new THREE.Points(g, this.discMaterial)];
  }

  clear(): void {
    for (const o of [this.lines, this.discs]) {
      if (!o) continue;
      o.geometry.dispose();
      this.group.remove(o);
    }
    this.lines = null;
    this.discs = null;
    this.shownId = null;
  }

  dispose(): void {
    this.clear();
    this.lineMaterial.dispose();
    this.discMaterial.dispose();
  }
}
