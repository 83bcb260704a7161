/** A small round sprite so points draw as discs instead of GL's default squares (made once, shared). */
import * as THREE from 'three';

let texture: THREE.DataTexture | null = null;

export function discTexture(): THREE.DataTexture {
  if (texture) return texture;
  const n = 32;
  const data = new Uint8Array(n * n * 4);
  for (let y = 0; y < n; y++) {
    for (let x = 0; x < n; x++) {
      const d = Math.hypot(x + 0.5 - n / 2, y + 0.5 - n / 2) / (n / 2);
      const a = Math.max(0, Math.min(1, (1 - d) * 8)); // anti-aliased rim
      data.set([255, 255, 255, Math.round(a * 255)], (y * n + x) * 4);
    }
  }
  texture = new THREE.DataTexture(data, n, n, THREE.RGBAFormat);
  texture.needsUpdate = true;
  return texture;
}
