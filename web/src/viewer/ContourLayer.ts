/**
 * The input contours in 3D. Short-axis curves are solid light blue, long-axis curves dashed orange,
 * so the two are told apart by colour and by dash (also when distance colours replace the hues).
 * Contours of other surfaces in the same file are drawn faintly for context. After a run the
 * contour points are coloured by their distance to the mesh (viridis, mm).
 */
import * as THREE from 'three';
import type { ContourInfo } from '../core-client/protocol';
import { colorizeU8 } from './colormap';
import { discTexture } from './discTexture';
import { partOf } from '../core-client/derivedSurfaces';

export const SAX_COLOR = new THREE.Color('#4fc3f7');
export const LAX_COLOR = new THREE.Color('#ffb74d');


interface Built {
  positions: number[];
  colors: number[];
}

function pushSegments(out: Built, c: ContourInfo, points: Float32Array, colorOf: (i: number) => THREE.Color): void {
  for (const piece of c.pieces) {
    const n = piece.count;
    const segments = piece.closed ? n : n - 1;
    for (let k = 0; k < segments; k++) {
      for (const i of [piece.start + k, piece.start + ((k + 1) % n)]) {
        out.positions.push(points[i * 3], points[i * 3 + 1], points[i * 3 + 2]);
        const col = colorOf(i);
        out.colors.push(col.r, col.g, col.b);
      }
    }
  }
}

/** A one-triangle geometry with colours, only for compiling shaders. */
export function warmupGeometry(): THREE.BufferGeometry {
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.Float32BufferAttribute([0, 0, 0, 1, 0, 0, 0, 1, 0], 3));
  g.setAttribute('color', new THREE.BufferAttribute(new Uint8Array(9), 3, true));
  return g;
}

export class ContourLayer {
  readonly group = new THREE.Group();
  private objects: THREE.Object3D[] = [];
  private pointsObject: THREE.Points | null = null;
  private distances: Float32Array | null = null;
  /** The highlighted (current surface's) contours and their points, to name a picked point and to find a contour by id. */
  private selected: readonly ContourInfo[] = [];
  private points: Float32Array = new Float32Array(0);
  /** Bumped whenever what is drawn changes: an overlay made of these contours knows when to follow. */
  version = 0;
  private readonly materials = {
    sax: new THREE.LineBasicMaterial({ vertexColors: true }),
    lax: new THREE.LineDashedMaterial({ vertexColors: true, dashSize: 3, gapSize: 2 }),
    other: new THREE.LineBasicMaterial({ color: 0x7a8594, transparent: true, opacity: 0.28, depthWrite: false }),
    points: new THREE.PointsMaterial({ vertexColors: true, size: 5, sizeAttenuation: false, map: discTexture(), alphaTest: 0.5 }),
  };

  /**
   * Shows `contours` (indices into `points`, xyz mm). Those whose surface is `surface` (or all when
   * null) are highlighted; `distances` (per point, mm) colours them in [0, maxMm].
   */
  set(contours: readonly ContourInfo[], points: Float32Array, surface: string | null, distances: Float32Array | null, maxMm = 1): void {
    this.clear();
    const isSelected = (c: ContourInfo) => partOf(c.surface, surface);
    const selected = contours.filter(isSelected);
    const others = contours.filter((c) => !isSelected(c));
    this.selected = selected;
    this.points = points;
    const colorBytes = distances ? colorizeU8(distances, 0, maxMm) : null;
    const tmp = new THREE.Color();
    const colorOf = (kind: 'SAX' | 'LAX') => (i: number) =>
      colorBytes ? tmp.setRGB(colorBytes[i * 3] / 255, colorBytes[i * 3 + 1] / 255, colorBytes[i * 3 + 2] / 255) : kind === 'SAX' ? SAX_COLOR : LAX_COLOR;
    const sax: Built = { positions: [], colors: [] };
    const lax: Built = { positions: [], colors: [] };
    for (const c of selected) {
      // The core's split (given at load, replaced by the run's); undecidable ones drawn solid.
      const kind = c.kind ?? 'SAX';
      pushSegments(kind === 'SAX' ? sax : lax, c, points, colorOf(kind));
    }
    const other: Built = { positions: [], colors: [] };
    for (const c of others) pushSegments(other, c, points, () => SAX_COLOR);
    this.addLines(sax, this.materials.sax, false);
    this.addLines(lax, this.materials.lax, true);
    this.addLines(other, this.materials.other, false);

    if (distances && colorBytes) {
      // Points only for the highlighted contours: the read-out picks them by index.
      const pos = new Float32Array(points.length);
      pos.set(points);
      const geometry = new THREE.BufferGeometry();
      geometry.setAttribute('position', new THREE.BufferAttribute(pos, 3));
      geometry.setAttribute('color', new THREE.BufferAttribute(colorBytes, 3, true));
      this.pointsObject = new THREE.Points(geometry, this.materials.points);
      this.pointsObject.name = 'contour-points';
      this.group.add(this.pointsObject);
      this.distances = distances;
    }
  }

  private addLines(b: Built, material: THREE.Material, dashed: boolean): void {
    if (b.positions.length === 0) return;
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.Float32BufferAttribute(b.positions, 3));
    geometry.setAttribute('color', new THREE.Float32BufferAttribute(b.colors, 3));
    const lines = new THREE.LineSegments(geometry, material);
    if (dashed) lines.computeLineDistances();
    lines.renderOrder = 2;
    this.group.add(lines);
    this.objects.push(lines);
  }

  /**
   * Dash lengths in proportion to the framed scene (`scale` = 1 for a heart of radius 50 mm), so
   * long-axis curves stay dashed for a file in metres or micrometres too.
   */
  setDashScale(scale: number): void {
    const s = Number.isFinite(scale) && scale > 0 ? scale : 1;
    this.materials.lax.dashSize = 3 * s;
    this.materials.lax.gapSize = 2 * s;
  }

  /** Line and point materials, for compiling their shaders ahead of the first frame. */
  get materialObjects(): THREE.Object3D[] {
    const g = warmupGeometry();
    const m = this.materials;
    const lax = new THREE.LineSegments(g, m.lax);
    lax.computeLineDistances();
    return [new THREE.LineSegments(g, m.sax), lax, new THREE.LineSegments(g, m.other), new THREE.Points(g, m.points)];
  }

  get pickable(): THREE.Points | null {
    return this.pointsObject;
  }

  distanceOfPoint(index: number): number | null {
    return this.distances && index < this.distances.length ? this.distances[index] : null;
  }

  /** The id of the (current surface's) contour point `index` belongs to (null: none). */
  contourOfPoint(index: number): string | null {
    return this.selected.find((c) => c.pieces.some((p) => index >= p.start && index < p.start + p.count))?.id ?? null;
  }

  /** The current surface's contour `id` as drawn: its pieces and the points they index (null: not drawn). */
  contourById(id: string): { contour: ContourInfo; points: Float32Array } | null {
    const contour = this.selected.find((c) => c.id === id);
    return contour ? { contour, points: this.points } : null;
  }

  clear(): void {
    this.version++;
    this.selected = [];
    this.points = new Float32Array(0);
    for (const o of this.objects) {
      (o as THREE.LineSegments).geometry.dispose();
      this.group.remove(o);
    }
    this.objects = [];
    if (this.pointsObject) {
      this.pointsObject.geometry.dispose();
      this.group.remove(this.pointsObject);
      this.pointsObject = null;
    }
    this.distances = null;
  }

  dispose(): void {
    this.clear();
    for (const m of Object.values(this.materials)) m.dispose();
  }
}
