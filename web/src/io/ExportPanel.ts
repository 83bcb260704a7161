/**
 * Export buttons: mesh as STL (binary), OBJ, PLY, VTK; contour distances CSV; parameters JSON;
 * the session (contours + settings, the core's format, opens again with the same settings); PNG
 * screenshot. Every file records the parameters and the app version (see export/header.ts).
 */
import type { RunResult } from '../core-client/protocol';
import { h } from '../ui/dom';
import { download } from './download';
import { writeDistancesCsv } from './export/csv';
import { exportBaseName, type ExportInfo } from './export/header';
import { runSummary, writeParamsJson } from './export/json';
import { writeObj } from './export/obj';
import { writePly } from './export/ply';
import { writeStl } from './export/stl';
import { writeVtk } from './export/vtk';

export interface ExportSource {
  info(): ExportInfo | null;
  result(): RunResult | null;
  screenshot(): Promise<Blob>;
  /** The current file and settings as a heartmesh session file (null without a file). */
  session(): Promise<Uint8Array> | null;
  /** Reports a failed export. */
  failed(e: unknown): void;
}

export class ExportPanel {
  readonly element: HTMLElement;
  private readonly meshButtons: HTMLButtonElement[] = [];
  private readonly png: HTMLButtonElement;
  private readonly json: HTMLButtonElement;
  private readonly session: HTMLButtonElement;

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
    this.element = h('section', { class: 'panel exports', 'aria-label': 'Export' }, h('h2', {}, 'Export'), h('div', { class: 'button-grid' }, ...this.meshButtons, this.json, this.session, this.png));
    this.setAvailable(false, false);
  }

  setAvailable(hasResult: boolean, hasFile: boolean): void {
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
