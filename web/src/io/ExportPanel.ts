/**
 * Export buttons: mesh as STL (binary), OBJ, PLY, VTK; contour distances CSV; parameters JSON;
 * the session (contours + settings, the core's format, opens again with the same settings); PNG
 * screenshot; once several surfaces of the file have been run, all of them in one OBJ; and, once
 * LV_ENDO and LV_EPI have both been run with the settings in the panel, the LV wall (one closed
 * solid, built in the worker: export/wall.ts) in STL, OBJ, PLY or VTK, with its figures. Every
 * file records the parameters and the app version (see export/header.ts).
 */
import { WALL_FORMATS, toCoreErrorData, type RunResult, type WallFormat, type WallSummary } from '../core-client/protocol';
import { h } from '../ui/dom';
import { download } from './download';
import { writeDistancesCsv } from './export/csv';
import { exportBaseName, type ExportInfo } from './export/header';
import { runSummary, writeParamsJson } from './export/json';
import { writeObj, writeObjSurfaces } from './export/obj';
import { writePly } from './export/ply';
import { writeStl } from './export/stl';
import { writeVtk } from './export/vtk';
import { wallErrorText, wallFigures, wallFiguresTitle, wallFileName, wallFormatTitle, type WallReadiness } from './export/wall';

const ALL_OFF = 'All surfaces of the file in one OBJ: each surface appears once its own run has finished (pick it in the Surface menu)';

export interface ExportSource {
  info(): ExportInfo | null;
  result(): RunResult | null;
  screenshot(): Promise<Blob>;
  /** The current file and settings as a heartmesh session file (null without a file). */
  session(): Promise<Uint8Array> | null;
  /** The finished meshes of the file's other surfaces (their last runs), for the all-surfaces OBJ. */
  others(): { surface: string; positions: Float32Array; indices: Uint32Array }[];
  /**
   * The LV wall built in the worker and written as `format`, with its figures (null: it cannot be
   * built now). Rejects with the core's error.
   */
  wallFile(format: WallFormat): Promise<{ summary: WallSummary; bytes: Uint8Array }> | null;
  /** Reports a failed export. */
  failed(e: unknown): void;
}

const WALL_MIME: Record<WallFormat, string> = { stl: 'model/stl', obj: 'model/obj', ply: 'application/octet-stream', vtk: 'application/octet-stream' };

export class ExportPanel {
  readonly element: HTMLElement;
  private readonly meshButtons: HTMLButtonElement[] = [];
  private readonly png: HTMLButtonElement;
  private readonly json: HTMLButtonElement;
  private readonly session: HTMLButtonElement;
  private readonly all: HTMLButtonElement;
  private hasResult = false;
  private otherCount = 0;
  private readonly wallGroup: HTMLElement;
  private readonly wallButtons = new Map<WallFormat, HTMLButtonElement>();
  /** The wall's figures once built (or why it was not), while its meshes stay the ones used. */
  private readonly wallFigures: HTMLElement;
  private wall: WallReadiness = { ready: false, title: '', key: '' };
  private wallBusy = false;
  /** The readiness key of the wall the figures line describes (null: it describes none). */
  private figuresKey: string | null = null;

  constructor(private readonly source: ExportSource) {
    const button = (label: string, testid: string, title: string, fn: () => void | Promise<void>) => {
      const b = h('button', { type: 'button', class: 'small', 'data-testid': testid, title }, label);
      b.addEventListener('click', () => void fn());
      return b;
    };
    const mesh = (fmt: 'stl' | 'obj' | 'ply' | 'vtk', title: string) =>
      button(fmt.toUpperCase(), `export-${fmt}`, title, () => this.exportMesh(fmt));
    this.meshButtons.push(
      mesh('stl', 'Mesh as binary STL'),
      mesh('obj', 'Mesh as Wavefront OBJ'),
      mesh('ply', 'Mesh as binary PLY with per-vertex distance'),
      mesh('vtk', 'Mesh as legacy VTK with per-vertex distance'),
      button('Distances CSV', 'export-csv', 'Contour-to-mesh distance of every contour point', () => this.exportCsv()),
    );
    this.json = button('Parameters JSON', 'export-json', 'Parameters (and result numbers) as JSON', () => this.exportJson());
    this.session = button('Session', 'export-session', 'Contours and settings as a heartmesh session (.json): open it again to get the same settings back', () => this.exportSession());
    this.png = button('PNG', 'export-png', 'Screenshot of the 3D view', () => this.exportPng());
    this.all = button('All surfaces OBJ', 'export-all-obj', ALL_OFF, () => this.exportAll());
    for (const fmt of WALL_FORMATS) {
      const b = button(fmt.toUpperCase(), `export-wall-${fmt}`, '', () => this.exportWall(fmt));
      // Told apart from the mesh's own STL ... buttons by screen readers (and tests by role).
      b.setAttribute('aria-label', `LV wall ${fmt.toUpperCase()}`);
      this.wallButtons.set(fmt, b);
    }
    this.wallFigures = h('p', { class: 'wall-figures', 'data-testid': 'wall-figures', role: 'status', hidden: true });
    this.wallGroup = h(
      'div',
      { class: 'wall-export', 'data-testid': 'wall-export', role: 'group', 'aria-label': 'LV wall' },
      h('div', { class: 'wall-head' }, h('span', { class: 'wall-label' }, 'LV wall'), h('span', { class: 'wall-what' }, 'LV_ENDO + LV_EPI as one closed solid')),
      h('div', { class: 'button-grid' }, ...this.wallButtons.values()),
      this.wallFigures,
    );
    this.element = h('section', { class: 'panel exports', 'aria-label': 'Export' }, h('h2', {}, 'Export'), h('div', { class: 'button-grid' }, ...this.meshButtons, this.json, this.session, this.png, this.all), this.wallGroup);
    this.setAvailable(false, false);
    this.setWall({ ready: false, title: 'The LV wall: open a file with LV_ENDO and LV_EPI contours', key: '' });
  }

  /**
   * Whether the LV wall can be built now (export/wall.ts `wallReadiness`): its buttons and their
   * titles follow; figures of a wall of other meshes (or settings) are taken away.
   */
  setWall(wall: WallReadiness): void {
    this.wall = wall;
    if (this.figuresKey !== null && (!wall.ready || wall.key !== this.figuresKey)) this.showFigures(null);
    this.renderWall();
  }

  private renderWall(): void {
    const w = this.wall;
    this.wallGroup.title = w.title;
    this.wallGroup.dataset.ready = w.ready ? '1' : '0';
    for (const [fmt, b] of this.wallButtons) {
      b.disabled = !w.ready || this.wallBusy;
      b.title = w.ready ? wallFormatTitle(fmt) : w.title;
    }
  }

  /** Fills the figures line: a built wall's figures, a message (`state` busy or error), or nothing. */
  private showFigures(content: { summary: WallSummary } | { state: 'busy' | 'error'; text: string } | null, key: string | null = null): void {
    const el = this.wallFigures;
    this.figuresKey = content === null ? null : key;
    for (const k of ['wallMl', 'massG', 'cavityMl', 'thicknessMm', 'moved', 'triangles']) delete el.dataset[k];
    el.classList.toggle('warn', false);
    if (content === null) {
      el.hidden = true;
      el.textContent = '';
      el.title = '';
      delete el.dataset.state;
      return;
    }
    el.hidden = false;
    if ('state' in content) {
      el.dataset.state = content.state;
      el.textContent = content.text;
      el.title = '';
      el.classList.toggle('warn', content.state === 'error');
      return;
    }
    const s = content.summary;
    el.dataset.state = 'done';
    el.dataset.wallMl = String(s.wall_volume_ml);
    el.dataset.massG = String(s.myocardial_mass_g);
    el.dataset.cavityMl = String(s.cavity_volume_ml);
    el.dataset.thicknessMm = String(s.thickness_mm?.mean ?? '');
    el.dataset.moved = String(s.endocardium_moved.vertices);
    el.dataset.triangles = String(s.triangles);
    // Each figure kept whole on a narrow column; the notes wrap as text.
    const { figures, notes } = wallFigures(s);
    const nodes: (HTMLElement | string)[] = [];
    figures.forEach((f, i) => nodes.push(...(i > 0 ? [' · '] : []), h('span', { class: 'wall-figure' }, f)));
    for (const n of notes) nodes.push(`. ${n}`);
    el.replaceChildren(...nodes);
    el.title = wallFiguresTitle(s);
    el.classList.toggle('warn', s.endo_epi_crossings > 0);
  }

  /** Builds the LV wall in the worker as `fmt` and saves it; its figures (or why not) below the buttons. */
  private async exportWall(fmt: WallFormat): Promise<void> {
    const info = this.source.info();
    const wall = this.wall;
    if (!info || !wall.ready || this.wallBusy) return;
    const pending = this.source.wallFile(fmt);
    if (!pending) return;
    this.wallBusy = true;
    this.renderWall();
    this.showFigures({ state: 'busy', text: 'building the LV wall…' }, wall.key);
    try {
      const { summary, bytes } = await pending;
      download(bytes.slice(), wallFileName(info, fmt), WALL_MIME[fmt]);
      // Settings changed meanwhile: the file is of the meshes asked for, the figures no longer current.
      this.showFigures(this.wall.key === wall.key ? { summary } : null, wall.key);
    } catch (e) {
      this.showFigures({ state: 'error', text: wallErrorText(toCoreErrorData(e).message) }, wall.key);
      this.source.failed(e);
    } finally {
      this.wallBusy = false;
      this.renderWall();
    }
  }

  setAvailable(hasResult: boolean, hasFile: boolean): void {
    this.hasResult = hasResult;
    this.all.disabled = !hasResult || this.otherCount === 0;
    for (const b of this.meshButtons) b.disabled = !hasResult;
    this.json.disabled = !hasFile;
    this.session.disabled = !hasFile;
    this.png.disabled = !hasFile;
  }

  private exportMesh(fmt: 'stl' | 'obj' | 'ply' | 'vtk'): void {
    const info = this.source.info();
    const r = this.source.result();
    if (!info || !r) return;
    const mesh = { positions: r.positions, indices: r.indices, vertexDistances: r.vertexDistances };
    const base = exportBaseName(info);
    switch (fmt) {
      case 'stl':
        return download(writeStl(mesh, info), `${base}.stl`, 'model/stl');
      case 'obj':
        return download(writeObj(mesh, info), `${base}.obj`, 'model/obj');
      case 'ply':
        return download(writePly(mesh, info), `${base}.ply`, 'application/octet-stream');
      case 'vtk':
        return download(writeVtk(mesh, info), `${base}.vtk`, 'application/octet-stream');
    }
  }

  /** The file's other surfaces with a finished run (`surfaces`): the all-surfaces OBJ holds them too. */
  setOthers(surfaces: readonly string[]): void {
    this.otherCount = surfaces.length;
    this.all.disabled = !this.hasResult || surfaces.length === 0;
    this.all.title = surfaces.length ? `This surface and ${surfaces.join(', ')} (their last runs) in one OBJ, one named object each` : ALL_OFF;
  }

  /** The current mesh and the other surfaces' last ones in one OBJ, one named object each. */
  private exportAll(): void {
    const info = this.source.info();
    const r = this.source.result();
    if (!info || !r) return;
    const others = this.source.others();
    const current = info.surface ?? 'surface';
    const parts = [
      { name: current, mesh: { positions: r.positions, indices: r.indices } },
      ...others.map((m) => ({ name: m.surface, mesh: m })),
    ];
    const notes = [`objects: ${current} (this run, with the parameters above)${others.map((m) => `, ${m.surface} (its last run)`).join('')}`];
    download(writeObjSurfaces(parts, info, notes), `${exportBaseName({ ...info, surface: null })}-surfaces.obj`, 'model/obj');
  }

  private exportCsv(): void {
    const info = this.source.info();
    const r = this.source.result();
    if (!info || !r) return;
    download(writeDistancesCsv(r.contours, r.contourPoints, r.pointDistances, info), `${exportBaseName(info)}-distances.csv`, 'text/csv');
  }

  private exportJson(): void {
    const info = this.source.info();
    if (!info) return;
    const r = this.source.result();
    download(writeParamsJson(info, r ? runSummary(r) : null), `${exportBaseName(info)}-params.json`, 'application/json');
  }

  private async exportSession(): Promise<void> {
    const info = this.source.info();
    const pending = this.source.session();
    if (!info || !pending) return;
    try {
      const bytes = await pending;
      download(bytes.slice(), `${exportBaseName(info)}-session.json`, 'application/json');
    } catch (e) {
      this.source.failed(e);
    }
  }

  private async exportPng(): Promise<void> {
    const info = this.source.info();
    const blob = await this.source.screenshot();
    download(blob, `${info ? exportBaseName(info) : 'heartmesh'}.png`, 'image/png');
  }
}
