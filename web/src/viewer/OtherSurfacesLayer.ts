/**
 * The file's other surfaces, as their last finished runs left them, faint around the surface being
 * reconstructed: a run shows one surface at a time, and a biventricular file's LV endo- and
 * epicardium and RV make sense together (is the RV where it should be against the septum? does
 * the endocardium sit inside the epicardium?). Flat tints, no distance colours, not picked by the
 * hover read-out; clipped with the rest. A key beside the distance legends names each one.
 */
import * as THREE from 'three';
import { h } from '../ui/dom';

/** Tints of the usual labels; any other label takes the next of `SPARE`. */
const TINTS: Record<string, string> = {
  LV_ENDO: '#ef9a9a',
  LV_EPI: '#ffcc80',
  RV_ENDO: '#90caf9',
  RV_EPI: '#a5d6a7',
};
const SPARE = ['#ce93d8', '#80deea', '#e6ee9c', '#bcaaa4'];
const OPACITY = 0.28;

export function tintOf(surface: string, index: number): string {
  return TINTS[surface.toUpperCase()] ?? SPARE[index % SPARE.length];
}

/**
 * Of the `shown` surfaces, those whose kept run had other settings than the current surface's
 * kept run (none when the current surface has no run kept: nothing to compare with).
 */
export function otherSettings(settings: ReadonlyMap<string, string>, shown: readonly string[], current: string | null): string[] {
  const mine = current === null ? undefined : settings.get(current);
  return mine === undefined ? [] : shown.filter((s) => settings.get(s) !== mine);
}

interface Kept {
  mesh: THREE.Mesh;
  tint: string;
  /** The run's settings (see `runSignature`): the key says when they differ from the current. */
  settings: string;
}

export class OtherSurfacesLayer {
  readonly group = new THREE.Group();
  /**
   * The key (one row per surface shown); hidden when none is. `data-surfaces`: their labels;
   * `data-other-settings`: those whose last run had other settings than the current surface's.
   */
  readonly legend: HTMLElement;
  private readonly kept = new Map<string, Kept>();
  private current: string | null = null;
  private on = false;

  constructor(private readonly clippingPlanes: THREE.Plane[]) {
    this.group.name = 'other-surfaces';
    this.legend = h('div', { class: 'legend other-surfaces-legend', 'data-testid': 'other-surfaces-legend', hidden: true });
    this.legend.dataset.surfaces = '';
  }

  /**
   * Keeps `surface`'s mesh (xyz mm, triangle indices), replacing the one kept before; `settings`
   * identifies the parameters it was run with.
   */
  set(surface: string, positions: Float32Array, indices: Uint32Array, settings = ''): void {
    this.remove(surface);
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(positions.slice(), 3));
    geometry.setIndex(new THREE.BufferAttribute(indices.slice(), 1));
    geometry.computeVertexNormals();
    const tint = tintOf(surface, this.kept.size);
    const material = new THREE.MeshPhongMaterial({
      color: tint,
      transparent: true,
      opacity: OPACITY,
      depthWrite: false,
      side: THREE.DoubleSide,
      shininess: 10,
      clippingPlanes: this.clippingPlanes,
    });
    const mesh = new THREE.Mesh(geometry, material);
    mesh.name = `other-surface:${surface}`;
    this.group.add(mesh);
    this.kept.set(surface, { mesh, tint, settings });
    this.refresh();
  }

  /** The surfaces kept, in the order they were first kept. */
  get surfaces(): string[] {
    return [...this.kept.keys()];
  }

  /** The surfaces drawn now: every one kept but the current, while the layer is on. */
  get shown(): string[] {
    return this.on ? this.surfaces.filter((s) => s !== this.current) : [];
  }

  /**
   * Shows the kept surfaces (`on`) except `current`, whose own run is on screen; returns those
   * (whether shown or not: what the toggle would show).
   */
  show(on: boolean, current: string | null): string[] {
    this.on = on;
    this.current = current;
    this.refresh();
    return this.surfaces.filter((s) => s !== current);
  }

  /**
   * The shown surface under `raycaster`'s ray, nearest first, at a point `visible` accepts (not
   * clipped away): the hover read-out names it. Null when none is.
   */
  pick(raycaster: THREE.Raycaster, visible: (p: THREE.Vector3) => boolean): { surface: string; tint: string; point: THREE.Vector3 } | null {
    if (!this.group.visible) return null;
    let best: { surface: string; tint: string; point: THREE.Vector3; distance: number } | null = null;
    for (const [surface, k] of this.kept) {
      if (!k.mesh.visible) continue;
      const hit = raycaster.intersectObject(k.mesh, false).find((h) => visible(h.point));
      if (hit && (!best || hit.distance < best.distance)) best = { surface, tint: k.tint, point: hit.point.clone(), distance: hit.distance };
    }
    return best && { surface: best.surface, tint: best.tint, point: best.point };
  }

  /** Forgets every surface (another file or time frame). */
  clear(): void {
    for (const s of this.surfaces) this.remove(s);
    this.refresh();
  }

  dispose(): void {
    this.clear();
  }

  private remove(surface: string): void {
    const k = this.kept.get(surface);
    if (!k) return;
    this.group.remove(k.mesh);
    k.mesh.geometry.dispose();
    (k.mesh.material as THREE.Material).dispose();
    this.kept.delete(surface);
  }

  private refresh(): void {
    const shown = new Set(this.shown);
    for (const [s, k] of this.kept) k.mesh.visible = shown.has(s);
    this.group.visible = shown.size > 0;
    // A ghost run with other parameters than the surface on screen is not a like-for-like
    // comparison (a smoother epicardium around a sharper endocardium): the key says so.
    const settings = new Map([...this.kept].map(([s, k]) => [s, k.settings]));
    const differs = otherSettings(settings, [...shown], this.current);
    this.legend.replaceChildren(
      h('div', { class: 'legend-title' }, 'other surfaces (last runs)'),
      ...[...shown].map((s) =>
        h(
          'div',
          { class: 'other-surface-row' },
          h('span', { class: 'swatch', style: `background:${this.kept.get(s)?.tint}` }),
          s,
          differs.includes(s) ? h('span', { class: 'other-settings', title: 'last run with other parameters than the surface on screen' }, '· other parameters') : null,
        ),
      ),
    );
    this.legend.hidden = shown.size === 0;
    this.legend.dataset.surfaces = [...shown].join(',');
    this.legend.dataset.otherSettings = differs.join(',');
  }
}
