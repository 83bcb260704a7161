/**
 * The Lab's ground truth in the 3D view: translucent while contours and the reconstruction are
 * shown over it, opaque and coloured by its distance to the reconstruction (viridis, mm) once the
 * metrics are in, plus a highlighted contour (the one selected in the leave-one-out chart). Lives in
 * the viewer's scene beside the app's layers; owns its GPU resources (`dispose()`).
 */
import * as THREE from 'three';
import { colorizeU8 } from '../viewer/colormap';

const TRUTH_RGB = [150, 190, 230];
/** Where nothing was measured (above the most basal SAX plane). */
const UNMEASURED_RGB = [92, 99, 110];
const HIGHLIGHT = 0xff4081;

export class TruthLayer {
  readonly group = new THREE.Group();
  private geometry: THREE.BufferGeometry | null = null;
  private readonly material = new THREE.MeshPhongMaterial({
    vertexColors: true,
    transparent: true,
    opacity: 0.28,
    depthWrite: false,
    side: THREE.DoubleSide,
    shininess: 10,
  });
  private readonly mesh = new THREE.Mesh(new THREE.BufferGeometry(), this.material);
  private highlight: THREE.Object3D | null = null;
  private readonly lineMaterial = new THREE.LineBasicMaterial({ color: HIGHLIGHT, depthTest: false, transparent: true });
  private readonly pointMaterial = new THREE.PointsMaterial({ color: HIGHLIGHT, size: 6, sizeAttenuation: false, depthTest: false, transparent: true });

  constructor() {
    this.mesh.name = 'truth';
    this.mesh.renderOrder = 2;
    this.group.add(this.mesh);
    this.mesh.visible = false;
  }

  /** Shows a new truth surface (xyz mm, outward triangles), translucent and uncoloured. */
  setSurface(positions: Float32Array, indices: Uint32Array): void {
    const old = this.geometry;
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(positions, 3));
    g.setIndex(new THREE.BufferAttribute(indices, 1));
    g.computeVertexNormals();
    g.computeBoundingSphere();
    this.geometry = g;
    this.mesh.geometry = g;
    this.setDistances(null, 1);
    old?.dispose();
    this.mesh.visible = true;
  }

  /** Colours by distance in [0, maxMm] and makes the surface opaque; null: translucent again. */
  setDistances(distances: Float32Array | null, maxMm: number): void {
    const g = this.geometry;
    if (!g) return;
    const count = g.getAttribute('position').count;
    let bytes: Uint8Array;
    if (distances && distances.length === count) {
      bytes = colorizeU8(distances, 0, maxMm);
      for (let i = 0; i < count; i++) if (!Number.isFinite(distances[i])) bytes.set(UNMEASURED_RGB, i * 3);
    } else {
      bytes = new Uint8Array(count * 3);
      for (let i = 0; i < count; i++) bytes.set(TRUTH_RGB, i * 3);
    }
    g.setAttribute('color', new THREE.BufferAttribute(bytes, 3, true));
    const opaque = distances !== null;
    this.material.transparent = !opaque;
    this.material.opacity = opaque ? 1 : 0.28;
    this.material.depthWrite = opaque;
    this.material.needsUpdate = true;
  }

  setVisible(on: boolean): void {
    this.mesh.visible = on && this.geometry !== null;
  }

  get visible(): boolean {
    return this.mesh.visible;
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

  dispose(): void {
    this.setHighlight(null);
    this.geometry?.dispose();
    this.material.dispose();
    this.lineMaterial.dispose();
    this.pointMaterial.dispose();
  }
}
