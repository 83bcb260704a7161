/**
 * The attractor points currently pulling the mesh (farthest-point samples of the contours). They
 * change only when re-sampled, so the geometry is rebuilt only when a new array arrives.
 */
import * as THREE from 'three';
import { discTexture } from './discTexture';

export class AttractorLayer {
  readonly group = new THREE.Group();
  private points: THREE.Points | null = null;
  private current: Float32Array | null = null;
  private readonly material = new THREE.PointsMaterial({ color: 0xff4fd8, size: 6, sizeAttenuation: false, map: discTexture(), alphaTest: 0.5, transparent: true, opacity: 0.85 });

  set(attractors: Float32Array | null): void {
    if (attractors === this.current) return;
    this.clear();
    this.current = attractors;
    if (!attractors || attractors.length === 0) return;
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(attractors, 3));
    this.points = new THREE.Points(geometry, this.material);
    this.points.renderOrder = 3;
    this.group.add(this.points);
  }

  get materialObject(): THREE.Object3D {
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.Float32BufferAttribute([0, 0, 0], 3));
    return new THREE.Points(g, this.material);
  }

  setVisible(on: boolean): void {
    this.group.visible = on;
  }

  clear(): void {
    if (this.points) {
      this.points.geometry.dispose();
      this.group.remove(this.points);
      this.points = null;
    }
    this.current = null;
  }

  dispose(): void {
    this.clear();
    this.material.dispose();
  }
}
