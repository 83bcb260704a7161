/**
 * The Export panel's "Hexahedra" control, directly under the LV wall's row: the LV wall as layers
 * of hexahedra for finite-element simulation (export/hexWall.ts), built in the worker of the same
 * two meshes as the wall. Its layout (rings x points) and layers, a Save button "Hexahedra VTK",
 * and a line of figures once built.
 *
 * Enabled when the LV wall's buttons are (both surfaces run with the settings in the panel), its
 * title saying why not otherwise. Whether the file can have one at all is the core's to say (a
 * file without RV landmarks or contours does not say where the septum is): once the wall can be
 * built, the row asks the core for the smallest mesh and, refused, shows the core's reason greyed
 * in place of Save. Figures of other meshes, settings, layout or layers are taken away.
 */
import { toCoreErrorData, type HexSummary } from '../core-client/protocol';
import { h } from '../ui/dom';
import { probed, showMessage, type Availability } from './derivedRow';
import { download } from './download';
import { ANATOMICAL_DEFAULT, ANATOMICAL_POINTS, ANATOMICAL_RINGS } from './export/anatomical';
import {
  HEX_DEFAULT_LAYERS, HEX_HINT, HEX_LAYERS, HEX_PROBE, checkHex, hexErrorText, hexFigures, hexFiguresTitle, hexFileName, hexReason, hexSaveTitle, hexTitle,
  isHexRefusal, type HexLayout,
} from './export/hexWall';
import type { ExportInfo } from './export/header';
import { wallReadiness } from './export/wall';

/** A mesh built in the worker: its figures and its VTK file. */
export interface BuiltHex {
  summary: HexSummary;
  bytes: Uint8Array;
}

export interface HexRowSource {
  info(): ExportInfo | null;
  /**
   * The LV wall's current meshes as hexahedra of `layout` (`header`: with the app's header lines;
   * null: the wall cannot be built now). Rejects with the core's error.
   */
  build(layout: HexLayout, header: boolean): Promise<BuiltHex> | null;
  /** Reports a failed Save (the banner). */
  failed(e: unknown): void;
}

/** What the row knows of the core's answer for the meshes it would be built of. */

export class HexRow {
  readonly element: HTMLElement;
  private readonly rings: HTMLInputElement;
  private readonly points: HTMLInputElement;
  private readonly layers: HTMLInputElement;
  private readonly save: HTMLButtonElement;
  private readonly form: HTMLElement;
  private readonly inputError: HTMLElement;
  /** The core's reason, greyed, when it refuses the file. */
  private readonly reason: HTMLElement;
  private readonly figures: HTMLElement;
  /** The LV wall's readiness: whether it can be built now, why not, and its meshes' key. */
  private wall: { ready: boolean; title: string; key: string } = { ...wallReadiness(null, () => undefined, ''), ready: false };
  /** The meshes the row is for (null: the wall cannot be built); a probe or build of others is dropped. */
  private key: string | null = null;
  private availability: Availability = { state: 'none' };
  private busy = false;

  constructor(private readonly source: HexRowSource) {
    const number = (testid: string, label: string, value: number, range: { min: number; max: number }) => {
      const input = h('input', { type: 'number', class: 'anatomical-number hex-number', 'data-testid': testid, min: range.min, max: range.max, step: 1, value, 'aria-label': label, title: `${label}: ${range.min}-${range.max}` });
      // Set as a property too: what the row reads back (`value`) is the property, not the attribute.
      input.value = String(value);
      input.addEventListener('input', () => this.inputChanged());
      return input;
    };
    this.rings = number('hex-rings', 'Rings from the apex to the base', ANATOMICAL_DEFAULT.rings, ANATOMICAL_RINGS);
    this.points = number('hex-points', 'Points per ring', ANATOMICAL_DEFAULT.points, ANATOMICAL_POINTS);
    this.layers = number('hex-layers', 'Layers of cells through the wall', HEX_DEFAULT_LAYERS, HEX_LAYERS);
    this.save = h('button', { type: 'button', class: 'small', 'data-testid': 'export-hex', 'aria-label': 'Save the LV wall as hexahedra (VTK)' }, 'Hexahedra VTK');
    this.save.addEventListener('click', () => void this.export());
    const times = () => h('span', { class: 'anatomical-times', 'aria-hidden': 'true' }, '×');
    this.inputError = h('p', { class: 'anatomical-layout-error', 'data-testid': 'hex-input-error', hidden: true });
    this.reason = h('p', { class: 'anatomical-reason', 'data-testid': 'hex-reason', hidden: true });
    this.figures = h('p', { class: 'wall-figures', 'data-testid': 'hex-figures', role: 'status', hidden: true });
    this.form = h(
      'div',
      { class: 'hex-form' },
      // The three numbers in a row, each named under it (a grid: the names stay under their fields).
      h(
        'span',
        { class: 'hex-fields' },
        this.rings,
        times(),
        this.points,
        times(),
        this.layers,
        ...['rings', 'points', 'layers'].map((c) => h('span', { class: 'hex-caption', 'aria-hidden': 'true' }, c)),
      ),
      this.save,
    );
    this.element = h(
      'div',
      { class: 'hex-export', 'data-testid': 'hex-export', role: 'group', 'aria-label': 'LV wall as hexahedra' },
      // The name run into its hint: one short paragraph, not a head line and a hint under it.
      h('p', { class: 'hex-head' }, h('span', { class: 'hex-label' }, 'Hexahedra'), h('span', { class: 'hex-what', 'data-testid': 'hex-hint' }, HEX_HINT)),
      this.reason,
      this.form,
      this.inputError,
      this.figures,
    );
    this.render();
  }

  /**
   * The LV wall's readiness (export/wall.ts `wallReadiness`): the button follows; other meshes or
   * settings take the figures away and, when the wall can be built, have the core asked whether
   * the file can have hexahedra at all.
   */
  set(wall: { ready: boolean; title: string; key: string }): void {
    this.wall = { ready: wall.ready, title: wall.title, key: wall.key };
    const key = wall.ready ? wall.key : null;
    if (key !== this.key) {
      this.key = key;
      this.showFigures(null);
      this.availability = key === null ? { state: 'none' } : { state: 'checking' };
      if (key !== null) void this.probe(key);
    }
    this.render();
  }

  /** The layout and layers typed, when the core takes them. */
  private typed(): HexLayout | null {
    const c = checkHex(this.rings.value, this.points.value, this.layers.value);
    return c.ok ? c.layout : null;
  }

  private async probe(key: string): Promise<void> {
    const pending = this.source.build(HEX_PROBE, false);
    if (!pending) {
      if (key === this.key) this.availability = { state: 'none' };
      this.render();
      return;
    }
    const next = await probed(pending, isHexRefusal, hexReason);
    if (key !== this.key) return;
    this.availability = next;
    this.render();
  }

  private inputChanged(): void {
    // Figures of other layers or another layout would be taken for these.
    if (this.figures.dataset.state !== 'busy') this.showFigures(null);
    this.render();
  }

  private render(): void {
    const a = this.availability;
    const check = checkHex(this.rings.value, this.points.value, this.layers.value);
    const ready = a.state === 'ready';
    this.element.dataset.state = a.state;
    this.form.hidden = a.state === 'refused';
    this.reason.hidden = a.state !== 'refused';
    this.reason.textContent = a.state === 'refused' ? a.reason : '';
    this.inputError.hidden = check.ok || a.state === 'refused';
    this.inputError.textContent = check.ok ? '' : check.message;
    this.rings.disabled = this.points.disabled = this.layers.disabled = !ready;
    this.save.disabled = !ready || !check.ok || this.busy;
    const why = !this.wall.ready ? hexTitle(this.wall) : a.state === 'checking' ? `${hexTitle(this.wall)}: asking the core…` : a.state === 'refused' ? a.reason : hexTitle(this.wall);
    this.element.title = why;
    this.save.title = !ready ? why : check.ok ? hexSaveTitle(check.layout) : check.message;
  }

  /** Fills the figures line: a built mesh's figures, a message (busy or error), or nothing. */
  private showFigures(content: { summary: HexSummary } | { state: 'busy' | 'error'; text: string } | null): void {
    const el = this.figures;
    if (showMessage(el, ['hexahedra', 'wedges', 'points', 'volumeMl', 'minJacobian', 'inverted'], content) || content === null || 'state' in content) return;
    const s = content.summary;
    el.dataset.state = 'done';
    Object.assign(el.dataset, {
      hexahedra: String(s.hexahedra), wedges: String(s.wedges), points: String(s.points), volumeMl: String(s.volume_ml), minJacobian: String(s.min_scaled_jacobian), inverted: String(s.inverted_cells),
    });
    const { figures, notes } = hexFigures(s);
    const nodes: (HTMLElement | string)[] = [];
    figures.forEach((f, i) => nodes.push(...(i > 0 ? [' · '] : []), h('span', { class: 'wall-figure' }, f)));
    for (const n of notes) nodes.push(`. ${n}`);
    el.replaceChildren(...nodes);
    el.title = hexFiguresTitle(s);
    el.classList.toggle('warn', s.inverted_cells > 0);
  }

  /** Save: builds the layout and layers typed of the wall's current meshes and downloads the VTK file. */
  private async export(): Promise<void> {
    const info = this.source.info();
    const layout = this.typed();
    const key = this.key;
    if (!info || !layout || key === null || this.availability.state !== 'ready' || this.busy) return;
    const pending = this.source.build(layout, true);
    if (!pending) return;
    this.busy = true;
    this.render();
    this.showFigures({ state: 'busy', text: 'building the hexahedra…' });
    try {
      const built = await pending;
      download(built.bytes.slice(), hexFileName(info, layout), 'application/octet-stream');
      // Other meshes, layout or layers meanwhile: the file is of those asked for, the figures no longer current.
      const current = key === this.key && JSON.stringify(this.typed()) === JSON.stringify(layout);
      this.showFigures(current ? { summary: built.summary } : null);
    } catch (e) {
      if (key === this.key) this.showFigures({ state: 'error', text: hexErrorText(toCoreErrorData(e).message) });
      this.source.failed(e);
    } finally {
      this.busy = false;
      this.render();
    }
  }
}
