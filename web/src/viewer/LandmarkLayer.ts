/**
 * Landmarks a file carries (biv-me valves, apex, RV inserts; POINT ROIs of a DICOM RT structure
 * set): large discs, one colour per name, with a legend naming each colour and its count. They
 * orient the viewer (where the base and apex are) and show which apex point `lids=apex` uses.
 */
import * as THREE from 'three';
import type { Landmark } from '../core-client/protocol';
import { discTexture } from './discTexture';
import { h } from '../ui/dom';

/** Known biv-me names first (stable colours), anything else from the rest of the palette. */
const NAMED: Record<string, string> = {
  APEX_POINT: '#ff5252',
  // Newer biv-me files mark the apex on each wall instead.
  APEX_ENDO_POINT: '#ff5252',
  APEX_EPI_POINT: '#ff9e80',
  MITRAL_VALVE: '#69f0ae',
  AORTA_VALVE: '#ffd740',
  TRICUSPID_VALVE: '#40c4ff',
  PULMONARY_VALVE: '#e040fb',
  RV_INSERT: '#ffab40',
};
const OTHERS = ['#b2ff59', '#18ffff', '#ff80ab', '#8c9eff', '#f4ff81', '#a7ffeb'];

/** Distinct names in order of first appearance, each with its colour and count. */
export function landmarkGroups(landmarks: readonly Landmark[]): { name: string; color: string; count: number }[] {
  const out: { name: string; color: string; count: number }[] = [];
  let other = 0;
  for (const l of landmarks) {
    const g = out.find((x) => x.name === l.name);
    if (g) {
      g.count++;
      continue;
    }
    const color = NAMED[l.name] ?? OTHERS[other++ % OTHERS.length];
    out.push({ name: l.name, color, count: 1 });
  }
  return out;
}

export class LandmarkLayer {
  readonly group = new THREE.Group();
  /** The legend (names, colours, counts); hidden when there is nothing to show. */
  readonly legend: HTMLElement;
  private points: THREE.Points | null = null;
  private drawn = 0;
  private readonly material = new THREE.PointsMaterial({ vertexColors: true, size: 11, sizeAttenuation: false, map: discTexture(), alphaTest: 0.5, depthTest: false, transparent: true });

  constructor() {
    this.legend = h('div', { class: 'legend landmark-legend', 'data-testid': 'landmark-legend', hidden: true });
    this.legend.dataset.count = '0';
  }

  /** Number of landmark points currently in the scene (tests read it through the legend). */
  get count(): number {
    return this.drawn;
  }

  set(landmarks: readonly Landmark[]): void {
    this.clear();
    if (landmarks.length === 0) return;
    const groups = landmarkGroups(landmarks);
    const positions = new Float32Array(landmarks.length * 3);
    const colors = new Float32Array(landmarks.length * 3);
    const tmp = new THREE.Color();
    landmarks.forEach((l, i) => {
      positions.set([l.x, l.y, l.z], i * 3);
      tmp.set(groups.find((g) => g.name === l.name)?.color ?? '#ffffff');
      colors.set([tmp.r, tmp.g, tmp.b], i * 3);
    });
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
    geometry.setAttribute('color', new THREE.BufferAttribute(colors, 3));
    this.points = new THREE.Points(geometry, this.material);
    // Drawn over the mesh: a valve point inside the surface must still be seen.
    this.points.renderOrder = 4;
    this.group.add(this.points);
    this.drawn = landmarks.length;
    this.legend.replaceChildren(
      h('div', { class: 'legend-title' }, 'landmarks'),
      ...groups.map((g) => {
        const sw = h('span', { class: 'swatch' });
        sw.style.background = g.color;
        return h('div', { class: 'landmark-row' }, sw, `${g.name}${g.count > 1 ? ` × ${g.count}` : ''}`);
      }),
    );
    this.legend.dataset.count = String(this.drawn);
    this.legend.hidden = !this.group.visible;
  }

  setVisible(on: boolean): void {
    this.group.visible = on;
    this.legend.hidden = !on || this.drawn === 0;
  }

  clear(): void {
    if (this.points) {
      this.points.geometry.dispose();
      this.group.remove(this.points);
      this.points = null;
    }
    this.drawn = 0;
    this.legend.replaceChildren();
    this.legend.dataset.count = '0';
    this.legend.hidden = true;
  }

  dispose(): void {
    this.clear();
    this.material.dispose();
  }
}
