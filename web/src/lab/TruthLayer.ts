/**
 * The Lab's ground truths in the 3D view (one, or several surfaces of one heart, each in its
 * tint): translucent while contours and the reconstruction are shown over them; the truth the
 * reconstruction was measured against turns opaque and coloured by its distance to it (viridis,
 * mm) once the metrics are in, plus a highlighted contour (the one selected in the leave-one-out chart). Lives in
 * the viewer's scene beside the app's layers; owns its GPU resources (`dispose()`).
 */
import * as THREE from 'three';
import { colorizeU8 } from '../viewer/colormap';

/** Each truth's tint while translucent (the panel's list shows the same swatches), in order. */
export const TRUTH_TINTS: readonly (readonly [number, number, number])[] = [
  [150, 190, 230],
  [235, 160, 140],
  [160, 215, 150],
  [225, 200, 130],
  [200, 165, 225],
];
/** Where nothing was measured (above the most basal SAX plane). */
const UNMEASURED_RGB = [92, 99, 110];
const HIGHLIGHT = 0xff4081;

/** One truth surface: its geometry and its own material (one may be opaque while others are not). */
interface Surface {
  mesh: THREE.Mesh;
  geometry: THREE.BufferGeometry;
  material: THREE.MeshPhongMaterial;
  tint: readonly [number, number, number];
}

export class TruthLayer {
  readonly group = new THREE.Group();
  private surfaces: Surface[] = [];
  private shown = false;
  private highlight: THREE.Object3D | null = null;
  private readonly lineMaterial = new THREE.LineBasicMaterial({ color: HIGHLIGHT, depthTest: false, transparent: true });
  private readonly pointMaterial = new THREE.PointsMaterial({ color: HIGHLIGHT, size: 6, sizeAttenuation: false, depthTest: false, transparent: true });

  /** Shows one truth surface (xyz mm, outward triangles), translucent and uncoloured. */
  setSurface(positions: Float32Array, indices: Uint32Array): void {
    this.setSurfaces([{ positions, indices }]);
  }

  /** Shows the truths (several surfaces of one heart), each translucent in its tint. */
  setSurfaces(list: readonly { positions: Float32Array; indices: Uint32Array }[]): void {
    this.clearSurfaces();
    list.forEach((s, i) => {
      const geometry = new THREE.BufferGeometry();
      geometry.setAttribute('position', new THREE.BufferAttribute(s.positions, 3));
      geometry.setIndex(new THREE.BufferAttribute(s.indices, 1));
      geometry.computeVertexNormals();
      geometry.computeBoundingSphere();
      const material = new THREE.MeshPhongMaterial({ vertexColors: true, transparent: true, opacity: 0.28, depthWrite: false, side: THREE.DoubleSide, shininess: 10 });
      const mesh = new THREE.Mesh(geometry, material);
      mesh.name = i === 0 ? 'truth' : `truth-${i}`;
      mesh.renderOrder = 2;
      this.group.add(mesh);
      this.surfaces.push({ mesh, geometry, material, tint: TRUTH_TINTS[i % TRUTH_TINTS.length] });
    });
    this.shown = list.length > 0;
    this.setDistances(null, 1);
  }

  /**
   * Colours truth `index` by distance in [0, maxMm] and makes it opaque (the others stay
   * translucent); null: all translucent again.
   */
  setDistances(distances: Float32Array | null, maxMm: number, index = 0): void {
    this.surfaces.forEach((s, i) => {
      const count = s.geometry.getAttribute('position').count;
      const mine = distances !== null && i === index && distances.length === count ? distances : null;
      let bytes: Uint8Array;
      if (mine) {
        bytes = colorizeU8(mine, 0, maxMm);
        for (let k = 0; k < count; k++) if (!Number.isFinite(mine[k])) bytes.set(UNMEASURED_RGB, k * 3);
      } else {
        bytes = new Uint8Array(count * 3);
        for (let k = 0; k < count; k++) bytes.set(s.tint, k * 3);
      }
      s.geometry.setAttribute('color', new THREE.BufferAttribute(bytes, 3, true));
      const opaque = mine !== null;
      // Beside the truth whose map is shown, the others fade further so the map stands out.
      s.material.transparent = !opaque;
      s.material.opacity = opaque ? 1 : distances !== null ? 0.08 : 0.28;
      s.material.depthWrite = opaque;
      s.material.needsUpdate = true;
      s.mesh.visible = this.shown;
    });
  }

  setVisible(on: boolean): void {
    this.shown = on && this.surfaces.length > 0;
    for (const s of this.surfaces) s.mesh.visible = this.shown;
  }

  get visible(): boolean {
    return this.shown;
  }

  /** Draws one contour (flat xyz mm, consecutive points; closed loops repeat nothing) on top. */
  setHighlight(points: Float32Array | null, closed = true): void {
    if (this.highlight) {
      this.group.remove(this.highlight);
      this.highlight.traverse((o) => (o as THREE.Line).geometry?.dispose());
      this.highlight = null;
    }
    if (!points || points.length < 6) return;
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(points, 3));
    const holder = new THREE.Group();
    const line = closed ? new THREE.LineLoop(g, this.lineMaterial) : new THREE.Line(g, this.lineMaterial);
    const dots = new THREE.Points(g, this.pointMaterial);
    line.renderOrder = dots.renderOrder = 5;
    holder.add(line, dots);
    holder.name = 'highlight';
    this.highlight = holder;
    this.group.add(holder);
  }

  private clearSurfaces(): void {
    for (const s of this.surfaces) {
      this.group.remove(s.mesh);
      s.geometry.dispose();
      s.material.dispose();
    }
    this.surfaces = [];
  }

  dispose(): void {
    this.setHighlight(null);
    this.clearSurfaces();
    this.lineMaterial.dispose();
    this.pointMaterial.dispose();
  }
}
