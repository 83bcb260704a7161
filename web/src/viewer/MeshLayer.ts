/**
 * The reconstructed surface. One BufferGeometry: while the vertex count is unchanged each frame
 * only swaps the position array and flags it for upload (no GPU reallocation); when the topology
 * changes (remeshing) a new geometry is built and the old one disposed, as three-mesh-bvh does.
 * Shaded with an optional wireframe overlay that shares the geometry, opacity, and a distance
 * colour map (viridis LUT into a normalized Uint8 colour attribute).
 */
import * as THREE from 'three';
import { colorizeU8 } from './colormap';

/** Uniform surface colour (sRGB bytes) while no distances are shown. */
const BASE_RGB = [201, 162, 126];

export class MeshLayer {
  readonly group = new THREE.Group();
  private geometry: THREE.BufferGeometry | null = null;
  private indices: Uint32Array | null = null;
  private readonly material: THREE.MeshPhongMaterial;
  private readonly wireMaterial: THREE.MeshBasicMaterial;
  private readonly mesh: THREE.Mesh;
  private readonly wire: THREE.Mesh;
  /** Per-vertex distances currently shown as colours (null: uniform colour). */
  private distances: Float32Array | null = null;

  constructor(clippingPlanes: THREE.Plane[]) {
    // Phong and always per-vertex colours: one shader program for the whole session (a CPU
    // rasteriser needs about a second to compile a PBR program, which would freeze the page).
    this.material = new THREE.MeshPhongMaterial({
      vertexColors: true,
      shininess: 18,
      specular: 0x222222,
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
    const attr = geometry.getAttribute('color') as THREE.BufferAttribute | undefined;
    const reuse = attr && attr.array instanceof Uint8Array && attr.array.length === count * 3 ? attr.array : undefined;
    let bytes: Uint8Array;
    if (distances && distances.length === count) {
      bytes = colorizeU8(distances, min, max, reuse);
      this.distances = distances;
    } else {
      bytes = reuse ?? new Uint8Array(count * 3);
      for (let i = 0; i < count; i++) bytes.set(BASE_RGB, i * 3);
      this.distances = null;
    }
    if (attr && attr.array === bytes) attr.needsUpdate = true;
    else geometry.setAttribute('color', new THREE.BufferAttribute(bytes, 3, true));
  }

  /** The materials, for compiling their shaders ahead of the first frame. */
  get materials(): THREE.Material[] {
    return [this.material, this.wireMaterial];
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

  /** Vertices and triangles of the mesh shown (0 and 0 when none is). */
  get counts(): { vertices: number; triangles: number } {
    const g = this.geometry;
    if (!g || !this.group.visible) return { vertices: 0, triangles: 0 };
    return { vertices: g.getAttribute('position').count, triangles: (g.getIndex()?.count ?? 0) / 3 };
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
