/**
 * The contours a run left out of the reconstruction (the core's strays and specks), drawn after the
 * run in a "not used" style: grey, dashed and faded lines with grey discs at their points, and a
 * grey ring around each (a speck is a 3-point loop of a few millimetres, too small to find as a line
 * alone), never coloured by distance. A key beside the distance legends names each one ("left out:
 * speck · sax10"), and the hover read-out names the one under the pointer, with how far the mesh
 * built without it passes. Distinct from GivenContourLayer (white dashes: the file's contours
 * before the breath-hold shifts), which is about the alignment.
 */
import * as THREE from 'three';
import type { ContourInfo, SetAsideEntry } from '../core-client/protocol';
import { h } from '../ui/dom';
import { leftOutDetail, leftOutLabel } from '../ui/runText';
import { warmupGeometry } from './ContourLayer';
import { discTexture, ringTexture } from './discTexture';
import { givenSegments } from './GivenContourLayer';

export const SET_ASIDE_COLOR = '#9aa4b2';

/** One drawn contour left out: its entry, its geometry and the range of its points in the layer's point order. */
interface Drawn {
  entry: SetAsideEntry;
  contour: ContourInfo;
  start: number;
  count: number;
}

/**
 * The contours to draw for `list`, paired with their geometry (`contours`, as the binding sends
 * them: one per entry, in order; each entry takes the first contour of its id not yet taken, so an
 * entry without geometry is skipped without shifting the others), each with the range of its
 * points in `points` (point index, not float index) so a picked point names its contour.
 */
export function pairSetAside(list: readonly SetAsideEntry[], contours: readonly ContourInfo[]): { entry: SetAsideEntry; contour: ContourInfo; start: number; count: number }[] {
  const out: { entry: SetAsideEntry; contour: ContourInfo; start: number; count: number }[] = [];
  const taken = new Set<number>();
  for (const entry of list) {
    const i = contours.findIndex((c, k) => !taken.has(k) && c.id === entry.id);
    if (i < 0) continue;
    taken.add(i);
    const contour = contours[i];
    if (contour.pieces.length === 0) continue;
    const start = Math.min(...contour.pieces.map((p) => p.start));
    const end = Math.max(...contour.pieces.map((p) => p.start + p.count));
    out.push({ entry, contour, start, count: end - start });
  }
  return out;
}

export class SetAsideLayer {
  readonly group = new THREE.Group();
  /** The key (one row per contour left out); hidden when nothing is drawn. `data-count`: how many. */
  readonly legend: HTMLElement;
  private lines: THREE.LineSegments | null = null;
  private pointsObject: THREE.Points | null = null;
  private rings: THREE.Points | null = null;
  private drawn: Drawn[] = [];
  private points: Float32Array = new Float32Array(0);
  private distances: Float32Array | null = null;
  /** Bumped whenever what is drawn changes (see ContourLayer.version). */
  version = 0;
  private readonly lineMaterial = new THREE.LineDashedMaterial({
    color: SET_ASIDE_COLOR, transparent: true, opacity: 0.75, dashSize: 1, gapSize: 0.7, depthWrite: false,
  });
  private readonly pointMaterial = new THREE.PointsMaterial({
    color: SET_ASIDE_COLOR, size: 7, sizeAttenuation: false, map: discTexture(), alphaTest: 0.5, transparent: true, opacity: 0.9, depthTest: false,
  });
  private readonly ringMaterial = new THREE.PointsMaterial({
    color: '#e3e8ee', size: 32, sizeAttenuation: false, map: ringTexture(), alphaTest: 0.3, transparent: true, opacity: 0.95, depthTest: false,
  });

  constructor() {
    this.group.name = 'contours-set-aside';
    this.legend = h('div', { class: 'legend set-aside-legend', 'data-testid': 'set-aside-legend', hidden: true });
    this.legend.dataset.count = '0';
  }

  /** Number of contours left out that are drawn (tests read it through the key's `data-count`). */
  get count(): number {
    return this.drawn.length;
  }

  /**
   * Shows the contours `list` names (`contours`, indexing `points`, xyz mm); an empty list clears.
   * `distances` (mm, one per point: to the mesh built without them) are for the hover read-out
   * only: the lines stay grey, as the colour scale is that of the contours used. A list of another
   * length is dropped, so that no point reads another's figure.
   */
  set(list: readonly SetAsideEntry[], contours: readonly ContourInfo[], points: Float32Array, distances: Float32Array | null = null): void {
    this.clear();
    const pairs = pairSetAside(list, contours);
    if (pairs.length === 0) return;
    const segments = givenSegments(pairs.map((p) => p.contour), points, null);
    if (segments.length > 0) {
      const geometry = new THREE.BufferGeometry();
      geometry.setAttribute('position', new THREE.BufferAttribute(segments, 3));
      this.lines = new THREE.LineSegments(geometry, this.lineMaterial);
      this.lines.computeLineDistances();
      this.lines.renderOrder = 3;
      this.group.add(this.lines);
    }
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(points), 3));
    this.pointsObject = new THREE.Points(geometry, this.pointMaterial);
    this.pointsObject.name = 'set-aside-points';
    // Over the mesh: a speck past the base may sit inside the lid.
    this.pointsObject.renderOrder = 4;
    this.group.add(this.pointsObject);
    // A ring around each, at the middle of its points.
    const centres = new Float32Array(pairs.length * 3);
    pairs.forEach(({ start, count }, i) => {
      for (let k = 0; k < 3; k++) {
        let s = 0;
        for (let j = start; j < start + count; j++) s += points[j * 3 + k];
        centres[i * 3 + k] = s / count;
      }
    });
    const ringGeometry = new THREE.BufferGeometry();
    ringGeometry.setAttribute('position', new THREE.BufferAttribute(centres, 3));
    this.rings = new THREE.Points(ringGeometry, this.ringMaterial);
    this.rings.renderOrder = 4;
    this.group.add(this.rings);
    this.drawn = pairs.map(({ entry, contour, start, count }) => ({ entry, contour, start, count }));
    this.points = points;
    this.distances = distances && distances.length * 3 === points.length ? distances : null;
    this.legend.replaceChildren(
      h('div', { class: 'legend-title' }, 'not used by the mesh'),
      ...this.drawn.map(({ entry }) =>
        h(
          'div',
          { class: 'set-aside-row', title: leftOutDetail(entry), 'data-testid': 'set-aside-row', 'data-reason': entry.reason },
          h('span', { class: 'swatch set-aside-swatch' }),
          `${leftOutLabel(entry.reason)} · ${entry.id}`,
        ),
      ),
    );
    this.legend.dataset.count = String(this.drawn.length);
    this.legend.hidden = !this.group.visible;
  }

  /** The contour left out that point `index` (of the picked points) belongs to. */
  entryOfPoint(index: number): SetAsideEntry | null {
    return this.drawn.find((d) => index >= d.start && index < d.start + d.count)?.entry ?? null;
  }

  /** Distance (mm) from point `index` to the mesh built without it (null: the run did not say). */
  distanceOfPoint(index: number): number | null {
    return this.distances?.[index] ?? null;
  }

  get pickable(): THREE.Points | null {
    return this.pointsObject;
  }

  /** The contour left out `id` as drawn: its pieces and the points they index (null: not drawn). */
  contourById(id: string): { contour: ContourInfo; points: Float32Array } | null {
    const d = this.drawn.find((x) => x.entry.id === id);
    return d ? { contour: d.contour, points: this.points } : null;
  }

  /** Dash lengths in proportion to the framed scene (see ContourLayer.setDashScale). */
  setDashScale(scale: number): void {
    const s = Number.isFinite(scale) && scale > 0 ? scale : 1;
    this.lineMaterial.dashSize = 1 * s;
    this.lineMaterial.gapSize = 0.7 * s;
  }

  setVisible(on: boolean): void {
    this.group.visible = on;
    this.legend.hidden = !on || this.drawn.length === 0;
  }

  /** The materials, for compiling their shaders ahead of the first frame. */
  get materialObjects(): THREE.Object3D[] {
    const g = warmupGeometry();
    const lines = new THREE.LineSegments(g, this.lineMaterial);
    lines.computeLineDistances();
    return [lines, new THREE.Points(g, this.pointMaterial), new THREE.Points(g, this.ringMaterial)];
  }

  clear(): void {
    this.version++;
    this.points = new Float32Array(0);
    this.distances = null;
    for (const o of [this.lines, this.pointsObject, this.rings]) {
      if (!o) continue;
      o.geometry.dispose();
      this.group.remove(o);
    }
    this.lines = null;
    this.pointsObject = null;
    this.rings = null;
    this.drawn = [];
    this.legend.replaceChildren();
    this.legend.dataset.count = '0';
    this.legend.hidden = true;
  }

  dispose(): void {
    this.clear();
    this.lineMaterial.dispose();
    this.pointMaterial.dispose();
    this.ringMaterial.dispose();
  }
}
