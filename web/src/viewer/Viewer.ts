/**
 * The 3D view: a three.js WebGLRenderer, orbit/zoom/pan (OrbitControls), the layers (mesh,
 * contours, attractors; or, in their place, the myocardium wall the Export panel built), a
 * clipping plane facing the viewer to look inside, a hover read-out of the distance (or the wall
 * thickness) under the pointer (raycast), reset view and PNG screenshots. Renders on demand
 * (`requestRender`) so an idle page costs nothing. Owns GPU resources: call `dispose()`.
 */
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { LandmarkLayer } from './LandmarkLayer';
import { AttractorLayer } from './AttractorLayer';
import { ContourLayer, warmupGeometry } from './ContourLayer';
import { ContourHighlight } from './ContourHighlight';
import { cameraPlacement, dashScale, fitView, type ViewFit } from './fitView';
import { GivenContourLayer } from './GivenContourLayer';
import { MeshLayer } from './MeshLayer';
import { OtherSurfacesLayer } from './OtherSurfacesLayer';
import { SetAsideLayer } from './SetAsideLayer';
import { WallLayer } from './WallLayer';
import { AnatomicalGridLayer } from './AnatomicalGridLayer';
import type { WallColouring } from './wallColours';
import type { WallSolid } from '../io/wallSolid';
import { leftOutLabel } from '../ui/runText';

export interface HoverInfo {
  /** Screen position (px, relative to the viewport). */
  x: number;
  y: number;
  what: 'mesh' | 'contour point' | 'left out' | 'other surface' | 'wall';
  point: THREE.Vector3;
  /**
   * Contour-to-mesh distance in mm when known (after a finished run); for a contour left out, to
   * the mesh built without it.
   */
  distanceMm: number | null;
  /**
   * For a contour the run left out: "left out: speck" and its id; for another surface, its label;
   * for the wall, its region ("epicardium", or "cut face" inside the solid).
   */
  label?: string;
  /** For another surface of the file, or the wall: its colour in the view. */
  tint?: string;
  /** For the wall: its thickness there, mm (null on a cut face). */
  thicknessMm?: number | null;
  /** The contour under the pointer (a contour point, or a contour left out): its id. */
  id?: string;
}

/** Whether WebGL runs on a software rasteriser (SwiftShader, llvmpipe), probed on a scratch canvas. */
export function isSoftwareRenderer(): boolean {
  try {
    const gl = document.createElement('canvas').getContext('webgl2');
    if (!gl) return true;
    const info = gl.getExtension('WEBGL_debug_renderer_info');
    const name = String(info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER));
    gl.getExtension('WEBGL_lose_context')?.loseContext();
    return /swiftshader|llvmpipe|software|softpipe/i.test(name);
  } catch {
    return false;
  }
}

export class Viewer {
  readonly renderer: THREE.WebGLRenderer;
  readonly scene = new THREE.Scene();
  readonly camera = new THREE.PerspectiveCamera(35, 1, 0.5, 5000);
  readonly controls: OrbitControls;
  readonly meshLayer: MeshLayer;
  readonly contourLayer = new ContourLayer();
  /** The file's contours as given, behind the shifted ones after a run with breath-hold alignment. */
  readonly givenLayer = new GivenContourLayer();
  /** The contours the run left out (strays, specks), grey and dashed, with their key. */
  readonly setAsideLayer = new SetAsideLayer();
  readonly attractorLayer = new AttractorLayer();
  /** One contour picked out (the Contours panel's row under the pointer): `highlightContour`. */
  readonly contourHighlight = new ContourHighlight();
  /** The contour asked to be highlighted, and the contour layers' versions its drawing was made of. */
  private highlightWanted: string | null = null;
  private highlightBuiltOf = '';
  /** The file's other surfaces as their last runs left them, faint (a toggle of the view controls). */
  readonly otherSurfacesLayer: OtherSurfacesLayer;
  readonly landmarkLayer = new LandmarkLayer();
  /** The myocardium wall the Export panel built, shown in place of the surface layers (`showWall`). */
  readonly wallLayer: WallLayer;
  /** The anatomical mesh the Export panel built, drawn as lines over the surface (`showGrid`). */
  readonly gridLayer: AnatomicalGridLayer;
  /**
   * The reconstruction's layers (mesh, contours, attractors, other surfaces): hidden as one while
   * a wall is shown, whatever each layer's own visibility (a run's display keeps setting those).
   */
  private readonly surfaceLayers = new THREE.Group();
  /** Which wall is shown (the Export panel row's id: `wall`, `biv-wall`), for the canvas's `data-wall`. */
  private wallId = '';
  /** Clipping plane facing the camera; `clip` in [0, 1] moves it through the model (1 = off). */
  private readonly clipPlane = new THREE.Plane(new THREE.Vector3(0, 0, -1), 1e6);
  private clip = 1;
  private fit: ViewFit | null = null;
  /**
   * The framing before a wall widened it (`showWall`; `wallFramed` while one is shown), restored
   * when the wall goes unless the user moved the camera, so the surface comes back as it was framed.
   */
  private fitBeforeWall: ViewFit | null = null;
  private wallFramed = false;
  private dirty = true;
  /** WebGL runs on the CPU: render animations at reduced resolution (see setAnimating). */
  private readonly software: boolean;
  private animating = false;
  /** The user orbited/zoomed since the last `frame`: automatic re-framing would be rude. */
  private userMoved = false;
  private framePoints: ArrayLike<number> = [];
  private readonly raycaster = new THREE.Raycaster();
  private readonly resizeObserver: ResizeObserver;
  private hoverListener: ((h: HoverInfo | null) => void) | null = null;
  private readonly onPointerMove: (e: PointerEvent) => void;
  private readonly onPointerLeave: () => void;

  constructor(readonly container: HTMLElement) {
    // On a CPU rasteriser (no GPU, or a headless browser) multisampling costs more than the whole
    // reconstruction step: drop it there so the display does not slow the worker down.
    const software = isSoftwareRenderer();
    this.software = software;
    // No preserveDrawingBuffer: it makes the compositor read the frame back every time (a stall on
    // CPU rasterisers); screenshots render and capture within one task instead.
    this.renderer = new THREE.WebGLRenderer({ antialias: !software, alpha: false });
    this.renderer.setPixelRatio(software ? 1 : Math.min(2, window.devicePixelRatio || 1));
    this.renderer.domElement.dataset.software = software ? '1' : '0';
    this.renderer.localClippingEnabled = true;
    this.renderer.setClearColor(0x0d1117, 1);
    this.renderer.domElement.setAttribute('data-testid', 'viewport-canvas');
    container.append(this.renderer.domElement);

    this.meshLayer = new MeshLayer([this.clipPlane]);
    this.otherSurfacesLayer = new OtherSurfacesLayer([this.clipPlane]);
    this.wallLayer = new WallLayer([this.clipPlane]);
    this.gridLayer = new AnatomicalGridLayer([this.clipPlane]);
    this.surfaceLayers.add(this.meshLayer.group, this.gridLayer.group, this.otherSurfacesLayer.group, this.givenLayer.group, this.setAsideLayer.group, this.contourLayer.group, this.attractorLayer.group, this.contourHighlight.group);
    this.scene.add(this.surfaceLayers, this.wallLayer.group, this.landmarkLayer.group);
    this.scene.add(new THREE.HemisphereLight(0xdde6f0, 0x30261f, 1.3));
    const key = new THREE.DirectionalLight(0xffffff, 1.6);
    key.position.set(1, 1.2, 1.5);
    this.camera.add(key); // light follows the camera: the visible side is always lit
    const fill = new THREE.DirectionalLight(0xffffff, 0.5);
    fill.position.set(-1.5, -0.5, 0.5);
    this.camera.add(fill);
    this.scene.add(this.camera);

    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.enableDamping = false;
    this.controls.addEventListener('start', () => (this.userMoved = true));
    this.controls.addEventListener('change', () => {
      this.updateClipPlane();
      this.requestRender();
    });

    this.resizeObserver = new ResizeObserver(() => this.resize());
    this.resizeObserver.observe(container);
    this.resize();

    this.warmUp();

    this.onPointerMove = (e: PointerEvent) => this.hover(e);
    this.onPointerLeave = () => this.hoverListener?.(null);
    this.renderer.domElement.addEventListener('pointermove', this.onPointerMove);
    this.renderer.domElement.addEventListener('pointerleave', this.onPointerLeave);
  }

  /**
   * Compiles and links every shader program the layers will use before the first frame arrives:
   * one draw of each material, placed behind the camera so nothing shows. Without this, a CPU
   * rasteriser (SwiftShader, llvmpipe) stalls the page for about a second on the first frames of a
   * run, in the middle of the animation; here it happens once while the core is loading.
   */
  private warmUp(): void {
    const g = warmupGeometry();
    const group = new THREE.Group();
    for (const m of [...this.meshLayer.materials, ...this.wallLayer.materials]) group.add(new THREE.Mesh(g, m));
    group.add(...this.contourLayer.materialObjects, this.givenLayer.materialObject, ...this.setAsideLayer.materialObjects, this.attractorLayer.materialObject, ...this.contourHighlight.materialObjects);
    group.traverse((o) => (o.frustumCulled = false));
    group.position.set(0, 0, 1e6); // behind the default camera (at the origin, looking down -z)
    this.scene.add(group);
    try {
      this.renderer.render(this.scene, this.camera);
    } finally {
      this.scene.remove(group);
      group.traverse((o) => (o as THREE.Mesh).geometry?.dispose());
      this.requestRender();
    }
  }

  requestRender(): void {
    this.dirty = true;
  }

  /**
   * Highlights contour `id` of the surface on screen (or of those its run left out), drawn over
   * everything; null: none. The highlight follows the contour layers (a new run's contours) until
   * another id is asked for. The canvas's `data-highlight` says which contour is drawn ('' none:
   * also when `id` is drawn by no layer), for the browser tests.
   */
  highlightContour(id: string | null): void {
    this.highlightWanted = id;
    this.highlightBuiltOf = '';
    this.updateHighlight();
  }

  /** Rebuilds the highlight when the contours it is made of were drawn anew. */
  private updateHighlight(): void {
    const of = `${this.highlightWanted}\n${this.contourLayer.version}\n${this.setAsideLayer.version}`;
    if (of === this.highlightBuiltOf) return;
    this.highlightBuiltOf = of;
    const id = this.highlightWanted;
    this.contourHighlight.show(id, id === null ? null : (this.contourLayer.contourById(id) ?? this.setAsideLayer.contourById(id)));
    this.renderer.domElement.dataset.highlight = this.contourHighlight.id ?? '';
    this.requestRender();
  }

  /** Renders if something changed since the last call (called once per animation frame). */
  renderIfNeeded(): void {
    this.updateHighlight();
    if (!this.dirty) return;
    this.dirty = false;
    this.renderer.render(this.scene, this.camera);
    this.describeShown();
  }

  /**
   * What was drawn, on the canvas's data attributes, for the browser tests (as `data-view-radius`):
   * `data-shown` (surface or wall), the vertices and triangles of the mesh or wall drawn, and for
   * a wall which one (`data-wall`), its colouring and how many colours it is drawn in.
   */
  private describeShown(): void {
    const d = this.renderer.domElement.dataset;
    const wall = this.wallLayer.counts;
    const mesh = this.meshLayer.counts;
    const shown = wall ?? mesh;
    d.shown = wall ? 'wall' : 'surface';
    d.wall = wall ? this.wallId : '';
    d.vertices = String(shown.vertices);
    d.triangles = String(shown.triangles);
    d.wallColouring = wall?.mode ?? '';
    d.wallColours = wall ? String(wall.colours) : '';
    d.grid = String(this.gridLayer.vertices);
  }

  /**
   * Shows the wall `solid` (`id`: which one) coloured by `colouring` in place of the
   * reconstruction's layers (they come back with `hideWall`), widening the framing to hold it
   * unless the user moved the camera.
   */
  showWall(solid: WallSolid, colouring: WallColouring, id: string): void {
    this.wallId = id;
    this.wallLayer.show(solid, colouring);
    this.surfaceLayers.visible = false;
    // One wall replacing another keeps the framing from before the first.
    if (!this.wallFramed) {
      this.fitBeforeWall = this.fit;
      this.wallFramed = true;
    }
    this.extendFrame(solid.positions);
    this.requestRender();
  }

  /**
   * Draws the anatomical mesh (`positions`, `indices`) as lines over the surface, until `hideGrid`
   * (it goes with the surface while a wall is shown). Its vertices lie on the surface: no reframing.
   */
  showGrid(positions: Float32Array, indices: Uint32Array): void {
    this.gridLayer.show(positions, indices);
    this.describeShown();
    this.requestRender();
  }

  hideGrid(): void {
    this.gridLayer.clear();
    this.describeShown();
    this.requestRender();
  }

  /** The wall's colouring (thickness or region), if one is shown. */
  setWallColouring(colouring: WallColouring): void {
    this.wallLayer.setMode(colouring);
    this.requestRender();
  }

  /** Takes the wall away: the reconstruction's layers are drawn again. */
  hideWall(): void {
    this.wallLayer.clear();
    this.surfaceLayers.visible = true;
    if (this.wallFramed) {
      this.wallFramed = false;
      if (this.fitBeforeWall && !this.userMoved) {
        this.fit = this.fitBeforeWall;
        this.resetView();
      }
      this.fitBeforeWall = null;
    }
    this.requestRender();
  }

  /**
   * While a run animates on a CPU rasteriser, draw at half resolution: full-size frames cost more
   * CPU than the reconstruction step they show and would slow the worker down. Still frames (done,
   * paused) are always drawn at full resolution.
   */
  setAnimating(on: boolean): void {
    if (on === this.animating) return;
    this.animating = on;
    if (this.software) this.resize();
  }

  private resize(): void {
    const ratio = this.software ? (this.animating ? 0.5 : 1) : Math.min(2, window.devicePixelRatio || 1);
    if (this.renderer.getPixelRatio() !== ratio) this.renderer.setPixelRatio(ratio);
    const w = Math.max(1, this.container.clientWidth);
    const hgt = Math.max(1, this.container.clientHeight);
    this.renderer.setSize(w, hgt, false);
    this.renderer.domElement.style.width = `${w}px`;
    this.renderer.domElement.style.height = `${hgt}px`;
    this.camera.aspect = w / hgt;
    this.camera.updateProjectionMatrix();
    this.requestRender();
  }

  /** Frames the given points (xyz, mm): looks from the side with their principal axis up. */
  frame(points: ArrayLike<number>): void {
    this.framePoints = points;
    this.fit = fitView(points);
    // The framed radius (mm), for the browser tests: a refused file in metres is framed at its size.
    this.renderer.domElement.dataset.viewRadius = String(this.fit.radius);
    this.contourLayer.setDashScale(dashScale(this.fit.radius));
    this.givenLayer.setDashScale(dashScale(this.fit.radius));
    this.setAsideLayer.setDashScale(dashScale(this.fit.radius));
    this.userMoved = false;
    // A new framing supersedes the one a shown wall would give back.
    this.wallFramed = false;
    this.fitBeforeWall = null;
    this.resetView();
  }

  /**
   * Widens the framing to also hold `extra` points (the first mesh of a run, whose lids reach past
   * the contours; the file's other surfaces), unless the user has moved the camera since. `keep`:
   * the points join the framed ones, so a later widening (the next run's first mesh) keeps them.
   */
  extendFrame(extra: Float32Array, keep = false): void {
    if (this.userMoved) return;
    const all = new Float32Array(this.framePoints.length + extra.length);
    all.set(Array.from(this.framePoints), 0);
    all.set(extra, this.framePoints.length);
    if (keep) this.framePoints = all;
    const axis = this.fit?.axis;
    const side = this.fit?.side;
    this.fit = fitView(all);
    // Keep the orientation found from the contours (the tube alone would tilt it).
    if (axis && side) this.fit = { ...this.fit, axis, side };
    this.resetView();
  }

  resetView(): void {
    const fit = this.fit ?? fitView([]);
    const center = new THREE.Vector3(...fit.center);
    const up = new THREE.Vector3(...fit.axis);
    const side = new THREE.Vector3(...fit.side);
    // Look along the second principal direction, slightly from above.
    const dir = side.clone().multiplyScalar(-1).addScaledVector(up, 0.35).normalize();
    const { distance, near, far } = cameraPlacement(fit.radius, this.camera.fov, this.camera.aspect);
    this.camera.up.copy(up);
    this.camera.position.copy(center).addScaledVector(dir, distance);
    this.camera.near = near;
    this.camera.far = far;
    this.camera.updateProjectionMatrix();
    this.controls.target.copy(center);
    this.controls.update();
    this.updateClipPlane();
    this.requestRender();
  }

  /** Clipping: 1 = off, 0.5 = the near half cut away at the centre, 0 = everything cut. */
  setClip(t: number): void {
    this.clip = Math.min(1, Math.max(0, t));
    this.updateClipPlane();
    this.requestRender();
  }

  private updateClipPlane(): void {
    const fit = this.fit;
    if (!fit || this.clip >= 1) {
      // three clips where the signed distance is negative: this plane keeps everything.
      this.clipPlane.normal.set(0, 0, 1);
      this.clipPlane.constant = 1e9;
      return;
    }
    // Plane perpendicular to the view direction; keeps what is behind it (away from the camera).
    const view = new THREE.Vector3();
    this.camera.getWorldDirection(view);
    const center = new THREE.Vector3(...fit.center);
    const offset = (this.clip * 2 - 1) * fit.radius; // -R (near side) .. +R (far side)
    const point = center.clone().addScaledVector(view, -offset);
    this.clipPlane.setFromNormalAndCoplanarPoint(view, point);
  }

  setHoverListener(fn: ((h: HoverInfo | null) => void) | null): void {
    this.hoverListener = fn;
  }

  private hover(e: PointerEvent): void {
    if (!this.hoverListener || e.buttons !== 0) return;
    const rect = this.renderer.domElement.getBoundingClientRect();
    const x = e.clientX - rect.left;
    const y = e.clientY - rect.top;
    const ndc = new THREE.Vector2((x / rect.width) * 2 - 1, -(y / rect.height) * 2 + 1);
    this.raycaster.setFromCamera(ndc, this.camera);
    const fitRadius = this.fit?.radius ?? 50;
    this.raycaster.params.Points = { threshold: fitRadius * 0.012 };
    if (this.wallLayer.shown) {
      // The wall alone is drawn: nothing else is under the pointer.
      const wall = this.wallLayer.pick(this.raycaster, (p) => this.isVisiblePoint(p));
      this.hoverListener(wall && { x, y, what: 'wall', point: wall.point, distanceMm: null, label: wall.region, tint: wall.tint, thicknessMm: wall.thicknessMm });
      return;
    }
    const aside = this.setAsideLayer.pickable;
    if (aside && this.setAsideLayer.group.visible) {
      const hit = this.raycaster.intersectObject(aside, false)[0];
      const index = hit?.index;
      const entry = index !== undefined ? this.setAsideLayer.entryOfPoint(index) : null;
      if (hit && index !== undefined && entry && this.isVisiblePoint(hit.point)) {
        const distanceMm = this.setAsideLayer.distanceOfPoint(index);
        this.hoverListener({ x, y, what: 'left out', point: hit.point.clone(), distanceMm, label: leftOutLabel(entry.reason), id: entry.id });
        return;
      }
    }
    const points = this.contourLayer.pickable;
    if (points && points.visible) {
      const hit = this.raycaster.intersectObject(points, false)[0];
      if (hit && hit.index !== undefined && this.isVisiblePoint(hit.point)) {
        const id = this.contourLayer.contourOfPoint(hit.index);
        this.hoverListener({ x, y, what: 'contour point', point: hit.point.clone(), distanceMm: this.contourLayer.distanceOfPoint(hit.index), ...(id !== null ? { id } : {}) });
        return;
      }
    }
    const mesh = this.meshLayer.pickable;
    if (this.meshLayer.group.visible) {
      const hits = this.raycaster.intersectObject(mesh, false).filter((h) => this.isVisiblePoint(h.point));
      const hit = hits[0];
      if (hit && hit.face) {
        const d = this.meshLayer.distanceAt(hit.face.a, hit.face.b, hit.face.c, hit.point);
        this.hoverListener({ x, y, what: 'mesh', point: hit.point.clone(), distanceMm: d });
        return;
      }
    }
    const other = this.otherSurfacesLayer.pick(this.raycaster, (p) => this.isVisiblePoint(p));
    if (other) {
      this.hoverListener({ x, y, what: 'other surface', point: other.point, distanceMm: null, label: other.surface, tint: other.tint });
      return;
    }
    this.hoverListener(null);
  }

  /** Where the point (mm) is drawn, px relative to the viewport (the browser tests point at it). */
  screenPosition(x: number, y: number, z: number): { x: number; y: number } {
    const p = new THREE.Vector3(x, y, z).project(this.camera);
    const rect = this.renderer.domElement.getBoundingClientRect();
    return { x: ((p.x + 1) / 2) * rect.width, y: ((1 - p.y) / 2) * rect.height };
  }

  private isVisiblePoint(p: THREE.Vector3): boolean {
    return this.clip >= 1 || this.clipPlane.distanceToPoint(p) >= 0;
  }

  /** PNG of the current view. */
  screenshot(): Promise<Blob> {
    this.renderer.render(this.scene, this.camera);
    return new Promise((resolve, reject) =>
      this.renderer.domElement.toBlob((b) => (b ? resolve(b) : reject(new Error('screenshot failed'))), 'image/png'),
    );
  }

  dispose(): void {
    this.resizeObserver.disconnect();
    this.renderer.domElement.removeEventListener('pointermove', this.onPointerMove);
    this.renderer.domElement.removeEventListener('pointerleave', this.onPointerLeave);
    this.controls.dispose();
    this.meshLayer.dispose();
    this.contourLayer.dispose();
    this.givenLayer.dispose();
    this.setAsideLayer.dispose();
    this.otherSurfacesLayer.dispose();
    this.wallLayer.dispose();
    this.gridLayer.dispose();
    this.attractorLayer.dispose();
    this.contourHighlight.dispose();
    this.landmarkLayer.dispose();
    this.renderer.dispose();
    this.renderer.domElement.remove();
  }
}
