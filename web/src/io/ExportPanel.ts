/**
 * Export buttons: mesh as STL (binary), OBJ, PLY, VTK; contour distances CSV; parameters JSON;
 * the session (contours + settings, the core's format, opens again with the same settings); PNG
 * screenshot; once several surfaces of the file have been run, all of them in one OBJ; once
 * LV_ENDO and LV_EPI have both been run with the settings in the panel, the LV wall (one closed
 * solid, built in the worker: export/wall.ts) in STL, OBJ, PLY or VTK, with its figures and its
 * thickness by AHA segment (the bullseye, Bullseye.ts), and directly under it the same wall as
 * layers of hexahedra for finite-element simulation (HexRow.ts, export/hexWall.ts); and
 * below them, once LV_ENDO, RV_ENDO and BIV_EPI have been, the biventricular wall
 * (export/bivWall.ts) the same way (each a WallRow, with a View toggle that shows the solid in
 * the 3D view in place of the surface: one wall at a time). Above the walls, the anatomical mesh
 * of the finished surface on screen (AnatomicalRow.ts: the same vertices for every heart). Every
 * file records the parameters and the app version (see export/header.ts).
 */
import type { AnatomicalFormat, RunResult, WallFormat, WallSummary } from '../core-client/protocol';
import { h } from '../ui/dom';
import { download } from './download';
import { writeDistancesCsv } from './export/csv';
import { exportBaseName, type ExportInfo } from './export/header';
import { runSummary, writeParamsJson } from './export/json';
import { writeObj, writeObjSurfaces } from './export/obj';
import { writePly } from './export/ply';
import { writeStl } from './export/stl';
import { writeVtk } from './export/vtk';
import { bivWallErrorText, bivWallFigures, bivWallFiguresTitle, bivWallFileName, bivWallFormatTitle, bivWallReadiness, type BivWallReadiness } from './export/bivWall';
import { wallErrorText, wallFigures, wallFiguresTitle, wallFileName, wallFormatTitle, wallReadiness, type WallReadiness } from './export/wall';
import { WallRow, type BuiltWall, type WallRowSpec } from './WallRow';
import { BullseyeView } from './Bullseye';
import { AnatomicalRow, type BuiltAnatomical } from './AnatomicalRow';
import type { AnatomicalLayout } from './export/anatomical';
import { HexRow, type BuiltHex } from './HexRow';
import type { HexLayout } from './export/hexWall';

const ALL_OFF = 'All surfaces of the file in one OBJ: each surface appears once its own run has finished (pick it in the Surface menu)';

export interface ExportSource {
  info(): ExportInfo | null;
  result(): RunResult | null;
  screenshot(): Promise<Blob>;
  /** The current file and settings as a heartmesh session file (null without a file). */
  session(): Promise<Uint8Array> | null;
  /** The finished meshes of the file's other surfaces (their last runs), for the all-surfaces OBJ. */
  others(): { surface: string; positions: Float32Array; positions64?: Float64Array; indices: Uint32Array; leaveOut?: readonly string[] }[];
  /**
   * The LV wall built in the worker and written as `format`, with its figures (null: it cannot be
   * built now). Rejects with the core's error.
   */
  wallFile(format: WallFormat): Promise<{ summary: WallSummary; bytes: Uint8Array }> | null;
  /** The biventricular wall, as `wallFile` (null: it cannot be built now). */
  bivWallFile(format: WallFormat): Promise<{ summary: WallSummary; bytes: Uint8Array }> | null;
  /** Reports a failed export. */
  failed(e: unknown): void;
  /**
   * Shows a wall built as PLY in the 3D view in place of the surface (`id`: its row's, `wall` or
   * `biv-wall`), replacing any wall shown; throws when it cannot be shown.
   */
  showWall(id: string, wall: BuiltWall): void;
  /** Takes the wall out of the 3D view: the surface comes back. */
  hideWall(): void;
  /**
   * The finished surface on screen resampled onto the anatomical `layout`, written as `format`
   * (`header`: with the app's header lines); null without a finished run. Rejects with the core's
   * error (its refusal says why the surface or file can have none).
   */
  anatomicalFile(layout: AnatomicalLayout, format: AnatomicalFormat, header: boolean): Promise<BuiltAnatomical> | null;
  /** Draws an anatomical mesh built as PLY over the surface in the 3D view; throws when it cannot. */
  showAnatomical(built: BuiltAnatomical): void;
  /** Takes the anatomical mesh out of the 3D view. */
  hideAnatomical(): void;
  /**
   * The LV wall's meshes as layers of hexahedra of `layout` (`header`: with the app's header
   * lines); null when the LV wall cannot be built now. Rejects with the core's error (its refusal
   * says why the file can have none).
   */
  hexFile(layout: HexLayout, header: boolean): Promise<BuiltHex> | null;
}

/** The LV wall's row: LV_ENDO + LV_EPI (its test ids `wall-export`, `export-wall-<fmt>`, `wall-figures`). */
const LV_WALL: WallRowSpec = {
  id: 'wall',
  label: 'LV wall',
  what: 'LV_ENDO + LV_EPI as one closed solid',
  initialTitle: wallReadiness(null, () => undefined, '').title,
  busy: 'building the LV wall…',
  formatTitle: wallFormatTitle,
  fileName: wallFileName,
  errorText: wallErrorText,
  view: (s) => ({
    ...wallFigures(s),
    title: wallFiguresTitle(s),
    warn: s.endo_epi_crossings > 0,
    data: {
      wallMl: String(s.wall_volume_ml),
      massG: String(s.myocardial_mass_g),
      cavityMl: String(s.cavity_volume_ml),
      thicknessMm: String(s.thickness_mm?.mean ?? ''),
      thicknessP95Mm: String(s.thickness_mm?.p95 ?? ''),
      thicknessMaxMm: String(s.thickness_mm?.max ?? ''),
      moved: String(s.endocardium_moved.vertices),
      triangles: String(s.triangles),
    },
  }),
  // The thickness by AHA segment, drawn as the bullseye (the biventricular wall has no segments).
  details: (info) => new BullseyeView(info),
};

/** The biventricular wall's row: BIV_EPI less LV_ENDO and RV_ENDO (`biv-wall-export`, `export-biv-wall-<fmt>`, `biv-wall-figures`). */
const BIV_WALL: WallRowSpec = {
  id: 'biv-wall',
  label: 'Biventricular wall',
  what: 'BIV_EPI less LV_ENDO and RV_ENDO',
  initialTitle: bivWallReadiness(null, () => undefined, '').title,
  busy: 'building the biventricular wall…',
  formatTitle: bivWallFormatTitle,
  fileName: bivWallFileName,
  errorText: bivWallErrorText,
  view: (s) => ({
    ...bivWallFigures(s),
    title: bivWallFiguresTitle(s),
    warn: s.endo_epi_crossings > 0,
    data: {
      wallMl: String(s.wall_volume_ml),
      massG: String(s.myocardial_mass_g),
      lvCavityMl: String(s.cavities?.find((c) => c.region === 'lv_endocardium')?.volume_ml ?? s.cavity_volume_ml),
      rvCavityMl: String(s.cavities?.find((c) => c.region === 'rv_endocardium')?.volume_ml ?? ''),
      thicknessMm: String(s.thickness_mm?.mean ?? ''),
      thicknessP95Mm: String(s.thickness_mm?.p95 ?? ''),
      thicknessMaxMm: String(s.thickness_mm?.max ?? ''),
      moved: String(s.endocardium_moved.vertices),
      crossings: String(s.endo_epi_crossings),
      triangles: String(s.triangles),
    },
  }),
};

export class ExportPanel {
  readonly element: HTMLElement;
  private readonly meshButtons: HTMLButtonElement[] = [];
  private readonly png: HTMLButtonElement;
  private readonly json: HTMLButtonElement;
  private readonly session: HTMLButtonElement;
  private readonly all: HTMLButtonElement;
  private hasResult = false;
  private otherCount = 0;
  private readonly lvWall: WallRow;
  private readonly bivWall: WallRow;
  private readonly anatomical: AnatomicalRow;
  private readonly hex: HexRow;

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
    const failed = (e: unknown) => source.failed(e);
    const view = (id: string) => ({
      // One wall in the view at a time: the other row's View is released as this one's shows.
      show: (w: BuiltWall) => {
        for (const row of this.walls) if (row.id !== id) row.release();
        source.showWall(id, w);
      },
      hide: () => source.hideWall(),
    });
    this.lvWall = new WallRow(LV_WALL, { info: () => source.info(), build: (f) => source.wallFile(f), failed, ...view(LV_WALL.id) });
    this.bivWall = new WallRow(BIV_WALL, { info: () => source.info(), build: (f) => source.bivWallFile(f), failed, ...view(BIV_WALL.id) });
    this.anatomical = new AnatomicalRow({
      info: () => source.info(),
      build: (layout, format, header) => source.anatomicalFile(layout, format, header),
      failed,
      show: (built) => source.showAnatomical(built),
      hide: () => source.hideAnatomical(),
    });
    this.hex = new HexRow({ info: () => source.info(), build: (layout, header) => source.hexFile(layout, header), failed });
    this.element = h(
      'section',
      { class: 'panel exports', 'aria-label': 'Export' },
      h('h2', {}, 'Export'),
      h('div', { class: 'button-grid' }, ...this.meshButtons, this.json, this.session, this.png, this.all),
      this.anatomical.element,
      this.lvWall.element,
      this.hex.element,
      this.bivWall.element,
    );
    this.setAvailable(false, false);
  }

  /**
   * Whether the LV wall can be built now (export/wall.ts `wallReadiness`): its buttons and their
   * titles follow; figures of a wall of other meshes (or settings) are taken away. The hexahedra
   * are built of the same meshes, and follow too.
   */
  setWall(wall: WallReadiness): void {
    this.lvWall.set(wall);
    this.hex.set(wall);
  }

  /** Whether the biventricular wall can be built now (export/bivWall.ts `bivWallReadiness`), as `setWall`. */
  setBivWall(wall: BivWallReadiness): void {
    this.bivWall.set(wall);
  }

  /**
   * The finished run on screen, for the anatomical mesh (`key` names it: file, frame, run; null:
   * none): a new one takes the row's figures and grid away and has the core asked about it.
   */
  setAnatomical(key: string | null): void {
    this.anatomical.setRun(key);
  }

  private get walls(): WallRow[] {
    return [this.lvWall, this.bivWall];
  }

  /**
   * Takes a wall shown from its View out of the 3D view (a new run, another file or surface): the
   * surface comes back; the anatomical mesh drawn over the old one goes too.
   */
  hideWall(): void {
    for (const row of this.walls) row.stopViewing();
    this.anatomical.stopViewing();
  }

  /** The row whose wall is in the 3D view (or being built to be), if any: `wall` or `biv-wall`. */
  get viewing(): string | null {
    return this.walls.find((r) => r.isViewing)?.id ?? null;
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
    const mesh = { positions: r.positions, positions64: r.positionsF64, indices: r.indices, vertexDistances: r.vertexDistances, vertexDistances64: r.vertexDistancesF64 };
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
      { name: current, mesh: { positions: r.positions, positions64: r.positionsF64, indices: r.indices } },
      ...others.map((m) => ({ name: m.surface, mesh: m })),
    ];
    // What each surface's last run left out (the header's leave_out is this run's; an older run may predate a change to the list).
    const leftOut = (m: { leaveOut?: readonly string[] }) => (m.leaveOut?.length ? `, leave_out=${m.leaveOut.join(',')}` : '');
    const notes = [`objects: ${current} (this run, with the parameters above)${others.map((m) => `, ${m.surface} (its last run${leftOut(m)})`).join('')}`];
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
