/**
 * The reconstructed surface. One BufferGeometry: while the vertex count is unchanged each frame
 * only swaps the position array and flags it for upload (no GPU reallocation); when the topology
 * changes (remeshing) a new geometry is built and the old one disposed, as three-mesh-bvh does.
 * Shaded with an optional wireframe overlay that shares the geometry, opacity, and a distance
 * colour map (viridis LUT into a normalized Uint8 colour attribute).
 */
import * as THREE from 'three';
import { colorizeU8 } from './colormap';

const BASE_COLOR = new THREE.Color('#c9a27e');

export class MeshLayer {
  readonly group = new THREE.Group();
  private geometry: THREE.BufferGeometry | null = null;
  private indices: Uint32Array | null = null;
  private readonly material: THREE.MeshStandardMaterial;
  private readonly wireMaterial: THREE.MeshBasicMaterial;
  private readonly mesh: THREE.Mesh;
  private readonly wire: THREE.Mesh;
  /** Per-vertex distances currently shown as colours (null: uniform colour). */
  private distances: Float32Array | null = null;

  constructor(clippingPlanes: THREE.Plane[]) {
    this.material = new THREE.MeshStandardMaterial({
      color: BASE_COLOR,
      roughness: 0.55,
      metalness: 0.05,
      side: THREE.DoubleSide,
      clippingPlanes,
      polygonOffset: true,
      polygonOffsetFactor: 1,
      polygonOffsetUnits: 1,
    });
    this.wireMaterial = new THREE.MeshBasicMaterial({
      color: 0x10141a,
      wireframe: true,
      transparent: true,
      opacity: 0.35,
      clippingPlanes,
    });
    const empty = new THREE.BufferGeometry();
    this.mesh = new THREE.Mesh(empty, this.material);
    this.wire = new THREE.Mesh(empty, this.wireMaterial);
    this.wire.visible = false;
    this.mesh.name = 'mesh';
    this.group.add(this.mesh, this.wire);
    this.group.visible = false;
  }

  /** Shows `positions` (xyz, mm) with `indices`; rebuilds the geometry only when they changed. */
  update(positions: Float32Array, indices: Uint32Array): void {
    const geometry = this.geometry;
    const position = geometry?.getAttribute('position') as THREE.BufferAttribute | undefined;
    if (geometry && position && indices === this.indices && position.array.length === positions.length) {
      position.array = positions;
      position.needsUpdate = true;
      geometry.computeVertexNormals();
      geometry.computeBoundingSphere();
    } else {
      this.rebuild(positions, indices);
    }
    this.group.visible = true;
  }

  private rebuild(positions: Float32Array, indices: Uint32Array): void {
    const old = this.geometry;
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
    geometry.setIndex(new THREE.BufferAttribute(indices, 1));
    geometry.computeVertexNormals();
    geometry.computeBoundingSphere();
    this.geometry = geometry;
    this.indices = indices;
    this.mesh.geometry = geometry;
    this.wire.geometry = geometry;
    this.distances = null;
    this.applyColors(null, 0, 1);
    old?.dispose();
  }

  /** Colours vertices by distance in [min, max] mm; null returns to the uniform colour. */
  setDistances(distances: Float32Array | null, min: number, max: number): void {
    this.applyColors(distances, min, max);
  }

  private applyColors(distances: Float32Array | null, min: number, max: number): void {
    const geometry = this.geometry;
    if (!geometry) return;
    const count = geometry.getAttribute('position').count;
    if (distances && distances.length === count) {
      const attr = geometry.getAttribute('color') as THREE.BufferAttribute | undefined;
      const bytes = colorizeU8(distances, min, max, attr?.array instanceof Uint8Array ? attr.array : undefined);
      if (attr && attr.array === bytes) attr.needsUpdate = true;
      else geometry.setAttribute('color', new THREE.BufferAttribute(bytes, 3, true));
      this.distances = distances;
      if (!this.material.vertexColors) {
        this.material.vertexColors = true;
        this.material.color.set(0xffffff);
        this.material.needsUpdate = true;
      }
    } else {
      if (geometry.getAttribute('color')) geometry.deleteAttribute('color');
      this.distances = null;
      if (this.material.vertexColors) {
        this.material.vertexColors = false;
        this.material.color.copy(BASE_COLOR);
        this.material.needsUpdate = true;
      }
    }
  }

  setWireframe(on: boolean): void {
    this.wire.visible = on;
  }

  setOpacity(opacity: number): void {
    const transparent = opacity < 0.999;
    this.material.opacity = opacity;
    if (this.material.transparent !== transparent) {
      this.material.transparent = transparent;
      this.material.depthWrite = !transparent;
      this.material.needsUpdate = true;
    }
  }

  /** The three.js object to raycast against for the hover read-out. */
  get pickable(): THREE.Mesh {
    return this.mesh;
  }

  /** Distance (mm) at a surface point of triangle (a, b, c), interpolated barycentrically. */
  distanceAt(a: number, b: number, c: number, point: THREE.Vector3): number | null {
    const d = this.distances;
    const position = this.geometry?.getAttribute('position');
    if (!d || !position || Math.max(a, b, c) >= d.length) return null;
    const pa = new THREE.Vector3().fromBufferAttribute(position, a);
    const pb = new THREE.Vector3().fromBufferAttribute(position, b);
    const pc = new THREE.Vector3().fromBufferAttribute(position, c);
    const bary = THREE.Triangle.getBarycoord(point, pa, pb, pc, new THREE.Vector3());
    if (!bary) return null;
    return d[a] * bary.x + d[b] * bary.y + d[c] * bary.z;
  }

  clear(): void {
    this.group.visible = false;
    this.geometry?.dispose();
    this.geometry = null;
    this.indices = null;
    this.distances = null;
    const empty = new THREE.BufferGeometry();
    this.mesh.geometry = empty;
    this.wire.geometry = empty;
  }

  dispose(): void {
    this.clear();
    this.material.dispose();
    this.wireMaterial.dispose();
  }
}
