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

let ring: THREE.DataTexture | null = null;

/**
 * A round ring sprite (made once, shared): a light band edged in black, so that it stands out on
 * a light or a dark surface, marking where something small is without hiding it.
 */
export function ringTexture(): THREE.DataTexture {
  if (ring) return ring;
  const n = 64;
  const data = new Uint8Array(n * n * 4);
  const band = (d: number, centre: number, half: number) => Math.max(0, Math.min(1, (half - Math.abs(d - centre)) * 24));
  for (let y = 0; y < n; y++) {
    for (let x = 0; x < n; x++) {
      const d = Math.hypot(x + 0.5 - n / 2, y + 0.5 - n / 2) / (n / 2);
      const light = band(d, 0.8, 0.06);
      const edge = band(d, 0.8, 0.13);
      const v = Math.round(light * 255);
      data.set([v, v, v, Math.round(Math.max(light, edge * 0.85) * 255)], (y * n + x) * 4);
    }
  }
  ring = new THREE.DataTexture(data, n, n, THREE.RGBAFormat);
  ring.needsUpdate = true;
  return ring;
}
