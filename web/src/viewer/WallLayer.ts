/**
 * The myocardium wall (the LV wall or the biventricular one, as the Export panel builds it) in
 * the 3D view, shown in place of the reconstructed surface while the user looks at the solid they
 * are about to save. Coloured by wall thickness (viridis, mm, with its scale) or by region (a key
 * naming each); the viewer's clipping plane cuts it like the rest, and inside the solid, where the
 * cut opens it, the far side of the wall is drawn flat in the section colour, so the cut reads as
 * a filled band of wall between the surfaces (no capping geometry needed: seen through the cut,
 * the first faces behind it are the solid's own inner faces exactly where the section is).
 * Owns its GPU resources: call `dispose()`.
 */
import * as THREE from 'three';
import { h } from '../ui/dom';
import { cssColorAt } from './colormap';
import { Legend } from './Legend';
import type { WallRegion, WallSolid } from '../io/wallSolid';
import { distinctColours, regionCornerColours, regionPalette, SECTION_TINT, thicknessCornerColours, thicknessScaleMax, type WallColouring } from './wallColours';
import { wallCorners } from './wallGeometry';

/** Uniform colour (sRGB bytes) of a wall whose file lacks what the colouring asks for. */
const PLAIN_RGB = [201, 162, 126];

/** What the hover read-out says of the wall under the pointer. */
export interface WallPick {
  point: THREE.Vector3;
  /** The wall thickness there, mm (null: on a cut face, or none in the file). */
  thicknessMm: number | null;
  /** The region's name ("epicardium"), or "cut face" inside the solid. */
  region: string;
  /** Its colour in the view (CSS). */
  tint: string;
  /** On a cut face (inside the solid, opened by the clipping plane). */
  section: boolean;
}

export class WallLayer {
  readonly group = new THREE.Group();
  /** The thickness scale (`legend-wall-thickness`, `data-max-mm`), shown in thickness colouring. */
  readonly thicknessLegend = new Legend('wall thickness', 'legend-wall-thickness');
  /** The key of the regions (`legend-wall-regions`), shown in region colouring. */
  readonly regionKey: HTMLElement;
  private readonly front: THREE.Mesh;
  private readonly back: THREE.Mesh;
  private readonly wire: THREE.Mesh;
  private readonly frontMaterial: THREE.MeshPhongMaterial;
  private readonly backMaterial: THREE.MeshBasicMaterial;
  private readonly wireMaterial: THREE.MeshBasicMaterial;
  private geometry: THREE.BufferGeometry | null = null;
  private solid: WallSolid | null = null;
  private mode: WallColouring = 'thickness';
  private maxMm = 1;
  /** The regions with a triangle in the wall on screen, by id, named by its file (or "region K"). */
  private regions: WallRegion[] = [];
  private palette = new Map<number, string>();
  private colours = 0;

  constructor(clippingPlanes: THREE.Plane[]) {
    this.group.name = 'wall';
    // Phong with per-vertex colours, as the surface (one shader family); front faces only: the
    // back faces are the cut's, drawn by `back`. Front and back faces get no polygon offset but
    // under the wireframe (`setWireframe`), and then the same one: pushed back by a slope-scaled
    // offset of its own, either kind peeks through the other along silhouettes.
    this.frontMaterial = new THREE.MeshPhongMaterial({
      vertexColors: true,
      shininess: 18,
      specular: 0x222222,
      side: THREE.FrontSide,
      clippingPlanes,
      polygonOffsetFactor: 1,
      polygonOffsetUnits: 1,
    });
    this.backMaterial = new THREE.MeshBasicMaterial({ color: SECTION_TINT, side: THREE.BackSide, clippingPlanes, polygonOffsetFactor: 1, polygonOffsetUnits: 1 });
    this.wireMaterial = new THREE.MeshBasicMaterial({ color: 0x10141a, wireframe: true, transparent: true, opacity: 0.35, clippingPlanes });
    const empty = new THREE.BufferGeometry();
    this.front = new THREE.Mesh(empty, this.frontMaterial);
    this.back = new THREE.Mesh(empty, this.backMaterial);
    this.wire = new THREE.Mesh(empty, this.wireMaterial);
    this.front.name = 'wall';
    this.back.name = 'wall-section';
    // The cut faces first: where a front and a back face meet at a silhouette at the same depth,
    // the front one, drawn later, wins the tie (three's depth test passes equal depths).
    this.back.renderOrder = 0;
    this.front.renderOrder = 1;
    this.wire.visible = false;
    this.group.add(this.front, this.back, this.wire);
    this.group.visible = false;
    this.thicknessLegend.element.classList.add('wall-legend');
    this.thicknessLegend.element.append(sectionRow());
    this.regionKey = h('div', { class: 'legend wall-legend wall-regions-legend', 'data-testid': 'legend-wall-regions', hidden: true });
  }

  /** Whether a wall is on screen. */
  get shown(): boolean {
    return this.solid !== null;
  }

  /** The wall on screen: its vertices and triangles (the file's), the colouring, and how many colours it is drawn in. */
  get counts(): { vertices: number; triangles: number; colours: number; mode: WallColouring } | null {
    const s = this.solid;
    return s && { vertices: s.positions.length / 3, triangles: s.indices.length / 3, colours: this.colours, mode: this.mode };
  }

  /** Shows `solid` coloured by `mode`, replacing any wall shown before. */
  show(solid: WallSolid, mode: WallColouring): void {
    const old = this.geometry;
    const corners = wallCorners(solid.positions, solid.indices, solid.regions);
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(corners.positions, 3));
    geometry.setAttribute('normal', new THREE.BufferAttribute(corners.normals, 3));
    geometry.computeBoundingSphere();
    this.geometry = geometry;
    this.front.geometry = geometry;
    this.back.geometry = geometry;
    this.wire.geometry = geometry;
    old?.dispose();
    this.solid = solid;
    this.maxMm = solid.thickness ? thicknessScaleMax(solid.thickness) : 1;
    const ids = solid.regions ? [...new Set(solid.regions)].sort((a, b) => a - b) : [];
    this.regions = ids.map((id) => ({ id, name: solid.regionNames.find((r) => r.id === id)?.name ?? `region ${id}` }));
    this.palette = regionPalette(this.regions);
    this.group.visible = true;
    this.setMode(mode);
  }

  /** Colours the wall on screen by thickness or by region (the legend follows). */
  setMode(mode: WallColouring): void {
    this.mode = mode;
    const s = this.solid;
    const geometry = this.geometry;
    if (!s || !geometry) return;
    let rgb: Uint8Array;
    if (mode === 'thickness' && s.thickness) rgb = thicknessCornerColours(s.indices, s.thickness, this.maxMm);
    else if (mode === 'region' && s.regions) rgb = regionCornerColours(s.regions, this.palette);
    else {
      rgb = new Uint8Array(s.indices.length * 3);
      for (let i = 0; i < s.indices.length; i++) rgb.set(PLAIN_RGB, i * 3);
    }
    geometry.setAttribute('color', new THREE.BufferAttribute(rgb, 3, true));
    this.colours = distinctColours(rgb);
    this.showLegend();
  }

  private showLegend(): void {
    const s = this.solid;
    if (s && this.mode === 'thickness' && s.thickness) {
      this.thicknessLegend.show(this.maxMm);
      this.thicknessLegend.element.dataset.maxMm = String(this.maxMm);
    } else this.thicknessLegend.hide();
    const regions = s && this.mode === 'region' ? this.regions : [];
    this.regionKey.replaceChildren(
      h('div', { class: 'legend-title' }, 'wall regions'),
      ...regions.map((r) =>
        h('div', { class: 'wall-region-row', 'data-region': r.id }, h('span', { class: 'swatch', style: `background:${this.palette.get(r.id)}` }), `${r.id} ${r.name}`),
      ),
      sectionRow(),
    );
    this.regionKey.hidden = regions.length === 0;
    this.regionKey.dataset.regions = regions.map((r) => r.name).join(',');
  }

  /** Forgets the wall (the surface comes back). */
  clear(): void {
    this.solid = null;
    this.regions = [];
    this.group.visible = false;
    this.geometry?.dispose();
    this.geometry = null;
    const empty = new THREE.BufferGeometry();
    this.front.geometry = empty;
    this.back.geometry = empty;
    this.wire.geometry = empty;
    this.colours = 0;
    this.thicknessLegend.hide();
    this.regionKey.hidden = true;
  }

  setOpacity(opacity: number): void {
    const transparent = opacity < 0.999;
    for (const m of [this.frontMaterial, this.backMaterial]) {
      m.opacity = opacity;
      if (m.transparent !== transparent) {
        m.transparent = transparent;
        m.depthWrite = !transparent;
        m.needsUpdate = true;
      }
    }
  }

  /** The wireframe overlay; the faces are then pushed back a little so that its lines show over them. */
  setWireframe(on: boolean): void {
    this.wire.visible = on;
    this.frontMaterial.polygonOffset = on;
    this.backMaterial.polygonOffset = on;
  }

  /** The materials, for compiling their shaders ahead of the first frame. */
  get materials(): THREE.Material[] {
    return [this.frontMaterial, this.backMaterial, this.wireMaterial];
  }

  /** The wall under `raycaster`'s ray, nearest first, at a point `visible` accepts (not clipped away). */
  pick(raycaster: THREE.Raycaster, visible: (p: THREE.Vector3) => boolean): WallPick | null {
    const s = this.solid;
    const position = this.geometry?.getAttribute('position');
    if (!s || !position || !this.group.visible) return null;
    const hit = raycaster.intersectObjects([this.front, this.back], false).find((x) => visible(x.point));
    if (!hit || hit.faceIndex === undefined || hit.faceIndex === null) return null;
    const point = hit.point.clone();
    if (hit.object === this.back) return { point, thicknessMm: null, region: 'cut face', tint: SECTION_TINT, section: true };
    const t = hit.faceIndex;
    const id = s.regions?.[t];
    const region = id === undefined ? 'wall' : (this.regions.find((r) => r.id === id)?.name ?? `region ${id}`);
    let thicknessMm: number | null = null;
    if (s.thickness) {
      const corner = (k: number) => new THREE.Vector3().fromBufferAttribute(position, t * 3 + k);
      const bary = THREE.Triangle.getBarycoord(point, corner(0), corner(1), corner(2), new THREE.Vector3());
      if (bary) {
        const [a, b, c] = [0, 1, 2].map((k) => s.thickness![s.indices[t * 3 + k]]);
        thicknessMm = a * bary.x + b * bary.y + c * bary.z;
      }
    }
    const byRegion = (id !== undefined ? this.palette.get(id) : undefined) ?? `rgb(${PLAIN_RGB.join(', ')})`;
    const tint = this.mode === 'thickness' && thicknessMm !== null ? cssColorAt(thicknessMm, 0, this.maxMm) : byRegion;
    return { point, thicknessMm, region, tint, section: false };
  }

  dispose(): void {
    this.clear();
    for (const m of this.materials) m.dispose();
  }
}

/** The key's row for the cut faces' colour. */
function sectionRow(): HTMLElement {
  return h('div', { class: 'wall-region-row wall-section-row' }, h('span', { class: 'swatch', style: `background:${SECTION_TINT}` }), 'cut faces (Clip)');
}
