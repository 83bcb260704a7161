/**
 * The file's contours as given, drawn faint and dashed behind the contours the mesh follows. Only
 * shown after a run with breath-hold alignment: the run's contours are then the shifted ones, and
 * this layer lets the user see what moved and by how much (a toggle in the view controls).
 */
import * as THREE from 'three';
import type { ContourInfo } from '../core-client/protocol';
import { warmupGeometry } from './ContourLayer';
import { partOf } from '../core-client/derivedSurfaces';

/** Segment end points (xyz pairs) of the pieces of `contours` whose surface is `surface` (all when null). */
export function givenSegments(contours: readonly ContourInfo[], points: ArrayLike<number>, surface: string | null): Float32Array {
  const out: number[] = [];
  for (const c of contours) {
    if (!partOf(c.surface, surface)) continue;
    for (const piece of c.pieces) {
      const n = piece.count;
      const segments = piece.closed ? n : n - 1;
      for (let k = 0; k < segments; k++) {
        for (const i of [piece.start + k, piece.start + ((k + 1) % n)]) out.push(points[i * 3], points[i * 3 + 1], points[i * 3 + 2]);
      }
    }
  }
  return new Float32Array(out);
}

export class GivenContourLayer {
  readonly group = new THREE.Group();
  private lines: THREE.LineSegments | null = null;
  private readonly material = new THREE.LineDashedMaterial({
    color: 0xffffff, transparent: true, opacity: 0.8, dashSize: 1.5, gapSize: 1, depthWrite: false,
  });

  constructor() {
    this.group.name = 'contours-as-given';
  }

  /** Shows these contours (indices into `points`, xyz mm) of `surface`; an empty set clears. */
  set(contours: readonly ContourInfo[], points: ArrayLike<number>, surface: string | null): void {
    this.clear();
    const segments = givenSegments(contours, points, surface);
    if (segments.length === 0) return;
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(segments, 3));
    this.lines = new THREE.LineSegments(geometry, this.material);
    this.lines.computeLineDistances();
    this.lines.renderOrder = 1;
    this.group.add(this.lines);
  }

  /** Dash lengths in proportion to the framed scene (see ContourLayer.setDashScale). */
  setDashScale(scale: number): void {
    const s = Number.isFinite(scale) && scale > 0 ? scale : 1;
    this.material.dashSize = 1.5 * s;
    this.material.gapSize = 1 * s;
  }

  get shown(): boolean {
    return this.lines !== null && this.group.visible;
  }

  setVisible(on: boolean): void {
    this.group.visible = on;
  }

  /** The material, for compiling its shader ahead of the first frame. */
  get materialObject(): THREE.Object3D {
    const lines = new THREE.LineSegments(warmupGeometry(), this.material);
    lines.computeLineDistances();
    return lines;
  }

  clear(): void {
    if (this.lines) {
      this.lines.geometry.dispose();
      this.group.remove(this.lines);
      this.lines = null;
    }
  }

  dispose(): void {
    this.clear();
    this.material.dispose();
  }
}
