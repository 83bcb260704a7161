/**
 * The Export panel's "Anatomical mesh" row: the finished surface on screen resampled in the worker
 * onto a fixed grid (rings from the apex to the base, each starting at the septum), the same
 * vertices for every heart (export/anatomical.ts). Its layout (rings x points), a format and Save,
 * a line of figures once built; View draws the grid over the surface.
 *
 * Which surfaces and files can have one is the core's to say (an RV surface cannot; a file without
 * RV landmarks or contours cannot say where the septum is): once a run finishes, the row asks the
 * core for the smallest layout and, refused, shows the core's reason greyed, with no Save. The row
 * checks only what would make a call pointless: a finished run, and whole numbers in range.
 */
import { toCoreErrorData, type AnatomicalFormat, type AnatomicalSummary } from '../core-client/protocol';
import { h } from '../ui/dom';
import { probed, showMessage, type Availability } from './derivedRow';
import { download } from './download';
import {
  ANATOMICAL_HINT, PROBE_LAYOUT, anatomicalErrorText, anatomicalFigures, anatomicalFiguresTitle, anatomicalFileName, anatomicalFormatTitle, anatomicalReason, isRefusal, layoutVertices,
  type AnatomicalLayout,
} from './export/anatomical';
import { LayoutFields, formatOf, formatSelect } from './layoutFields';
import type { ExportInfo } from './export/header';

/** A mesh built in the worker: its figures and its file. */
export interface BuiltAnatomical {
  summary: AnatomicalSummary;
  bytes: Uint8Array;
}

export interface AnatomicalRowSource {
  info(): ExportInfo | null;
  /**
   * The current run's finished surface on `layout`, written as `format` (`header`: with the app's
   * header lines; null: there is no finished run). Rejects with the core's error.
   */
  build(layout: AnatomicalLayout, format: AnatomicalFormat, header: boolean): Promise<BuiltAnatomical> | null;
  /** Reports a failed Save (the banner). */
  failed(e: unknown): void;
  /** Draws a layout built as PLY over the surface in the 3D view; throws when it cannot. */
  show(built: BuiltAnatomical): void;
  /** Takes the grid out of the 3D view. */
  hide(): void;
}

/** The format View builds (the viewer reads PLY). */
const VIEW_FORMAT: AnatomicalFormat = 'ply';

const MIME: Record<AnatomicalFormat, string> = { stl: 'model/stl', obj: 'model/obj', ply: 'application/octet-stream', vtk: 'application/octet-stream', vtp: 'application/xml' };

const WHAT = 'The finished LV_ENDO or LV_EPI surface resampled onto a fixed grid: vertex 0 the apex, then rings from the apex to the base plane, each starting at the septum, last the base lid\'s centre';

/** What the row knows of the core's answer for the run on screen. */

export class AnatomicalRow {
  readonly element: HTMLElement;
  private readonly fields: LayoutFields;
  private readonly format: HTMLSelectElement;
  private readonly save: HTMLButtonElement;
  private readonly viewButton: HTMLButtonElement;
  private readonly form: HTMLElement;
  private readonly layoutError: HTMLElement;
  /** The core's reason, greyed, when it refuses the run on screen. */
  private readonly reason: HTMLElement;
  private readonly figures: HTMLElement;
  /** The run the row is for (null: none finished); a probe or build of another is dropped. */
  private key: string | null = null;
  private availability: Availability = { state: 'none' };
  private busy = false;
  /** The grid is drawn in the 3D view (or being built to be). */
  private viewing = false;
  /** Bumped whenever viewing stops: a build still on its way is then not shown. */
  private viewToken = 0;

  constructor(private readonly source: AnatomicalRowSource) {
    this.fields = new LayoutFields({ rings: 'anatomical-rings', points: 'anatomical-points' }, () => this.layoutChanged());
    this.format = formatSelect('anatomical-format', 'Anatomical mesh format', () => this.render());
    this.save = h('button', { type: 'button', class: 'small', 'data-testid': 'export-anatomical', 'aria-label': 'Save the anatomical mesh' }, 'Save');
    this.save.addEventListener('click', () => void this.export());
    this.viewButton = h('button', { type: 'button', class: 'small wall-view', 'data-testid': 'view-anatomical', 'aria-pressed': 'false', 'aria-label': 'View the anatomical mesh' }, 'View');
    this.viewButton.addEventListener('click', () => void this.toggleView());
    this.layoutError = h('p', { class: 'anatomical-layout-error', 'data-testid': 'anatomical-layout-error', hidden: true });
    this.reason = h('p', { class: 'anatomical-reason', 'data-testid': 'anatomical-reason', hidden: true });
    this.figures = h('p', { class: 'wall-figures', 'data-testid': 'anatomical-figures', role: 'status', hidden: true });
    this.form = h(
      'div',
      { class: 'anatomical-form' },
      this.fields.element,
      this.format,
      this.save,
    );
    this.element = h(
      'div',
      { class: 'wall-export anatomical-export', 'data-testid': 'anatomical-export', role: 'group', 'aria-label': 'Anatomical mesh' },
      h('div', { class: 'wall-head' }, h('span', { class: 'wall-label' }, 'Anatomical mesh'), h('span', { class: 'wall-what' }, ANATOMICAL_HINT), this.viewButton),
      this.reason,
      this.form,
      this.layoutError,
      this.figures,
    );
    this.render();
  }

  /**
   * The finished run on screen (`key` identifies it: file, frame, run; null: none). A new one takes
   * the figures and the grid away and asks the core whether it can have a layout at all.
   */
  setRun(key: string | null): void {
    if (key === this.key) return;
    this.key = key;
    this.stopViewing();
    this.showFigures(null);
    this.availability = key === null ? { state: 'none' } : { state: 'checking' };
    this.render();
    if (key !== null) void this.probe(key);
  }

  /** The layout typed, when it is one the core takes. */
  private layout(): AnatomicalLayout | null {
    const c = this.fields.check();
    return c.ok ? c.layout : null;
  }

  private async probe(key: string): Promise<void> {
    const pending = this.source.build(PROBE_LAYOUT, 'obj', false);
    if (!pending) {
      this.availability = { state: 'none' };
      this.render();
      return;
    }
    const next = await probed(pending, isRefusal, anatomicalReason);
    if (key !== this.key) return;
    this.availability = next;
    this.render();
  }

  private layoutChanged(): void {
    // Figures of another layout, or a grid of one, would be taken for this one's.
    this.stopViewing();
    if (this.figures.dataset.state !== 'busy') this.showFigures(null);
    this.render();
  }

  private render(): void {
    const a = this.availability;
    const check = this.fields.check();
    const ready = a.state === 'ready';
    this.element.dataset.state = a.state;
    this.form.hidden = a.state === 'refused';
    this.reason.hidden = a.state !== 'refused';
    this.reason.textContent = a.state === 'refused' ? a.reason : '';
    this.layoutError.hidden = check.ok || a.state === 'refused';
    this.layoutError.textContent = check.ok ? '' : check.message;
    this.fields.disabled = this.format.disabled = !ready;
    this.save.disabled = !ready || !check.ok || this.busy;
    this.viewButton.disabled = !ready || !check.ok || (this.busy && !this.viewing);
    this.viewButton.hidden = a.state === 'refused';
    this.viewButton.setAttribute('aria-pressed', this.viewing ? 'true' : 'false');
    const format = formatOf(this.format);
    const why = a.state === 'none' ? `${WHAT}: once a surface's run has finished` : a.state === 'checking' ? `${WHAT}: asking the core…` : a.state === 'refused' ? a.reason : WHAT;
    this.element.title = why;
    this.save.title = !ready ? why : check.ok ? `Save ${layoutVertices(check.layout)} vertices as ${format.toUpperCase()}: ${anatomicalFormatTitle(format)}` : check.message;
    this.viewButton.title = !ready ? why : this.viewing ? 'Take the grid out of the 3D view' : 'Draw the grid over the surface in the 3D view';
  }

  /** Fills the figures line: a built mesh's figures, a message (busy or error), or nothing. */
  private showFigures(content: { summary: AnatomicalSummary } | { state: 'busy' | 'error'; text: string } | null): void {
    const el = this.figures;
    if (showMessage(el, ['vertices', 'volumeMl', 'meanMm', 'maxMm'], content) || content === null || 'state' in content) return;
    const s = content.summary;
    el.dataset.state = 'done';
    Object.assign(el.dataset, { vertices: String(s.vertices), volumeMl: String(s.volume_ml), meanMm: String(s.to_surface_mean_mm), maxMm: String(s.to_surface_max_mm) });
    const { figures, septum } = anatomicalFigures(s);
    const nodes: (HTMLElement | string)[] = [];
    figures.forEach((f, i) => nodes.push(...(i > 0 ? [' · '] : []), h('span', { class: 'wall-figure' }, f)));
    // A sentence break for the text's readers; the septum's line is a block of its own on screen.
    nodes.push(h('span', { class: 'visually-hidden' }, '. '), h('span', { class: 'anatomical-septum', 'data-testid': 'anatomical-septum' }, septum));
    el.replaceChildren(...nodes);
    el.title = anatomicalFiguresTitle(s);
  }

  /**
   * Builds the layout typed (in `format`) for the run on screen, busy meanwhile; resolves to it, or
   * to null when it failed (said on the figures line and the banner) or the run changed meanwhile.
   */
  private async build(format: AnatomicalFormat): Promise<{ built: BuiltAnatomical; layout: AnatomicalLayout } | null> {
    const layout = this.layout();
    const key = this.key;
    if (!layout || key === null || this.availability.state !== 'ready' || this.busy) return null;
    const pending = this.source.build(layout, format, true);
    if (!pending) return null;
    this.busy = true;
    this.render();
    this.showFigures({ state: 'busy', text: 'building the anatomical mesh…' });
    try {
      const built = await pending;
      if (key !== this.key) return null;
      const current = JSON.stringify(this.layout()) === JSON.stringify(layout);
      this.showFigures(current ? { summary: built.summary } : null);
      return { built, layout };
    } catch (e) {
      if (key !== this.key) return null;
      this.showFigures({ state: 'error', text: anatomicalErrorText(toCoreErrorData(e).message) });
      this.source.failed(e);
      return null;
    } finally {
      this.busy = false;
      this.render();
    }
  }

  /** Save: builds the layout typed in the format chosen and downloads it. */
  private async export(): Promise<void> {
    const info = this.source.info();
    const format = formatOf(this.format);
    if (!info) return;
    const done = await this.build(format);
    if (done) download(done.built.bytes.slice(), anatomicalFileName(info, done.layout, format), MIME[format]);
  }

  /** Takes the grid out of the 3D view if the row drew it. */
  stopViewing(): void {
    if (!this.viewing) return;
    this.viewing = false;
    this.viewToken++;
    this.source.hide();
    this.render();
  }

  /** View: draws the grid (built as PLY) over the surface, or takes it away again. */
  private async toggleView(): Promise<void> {
    if (this.viewing) {
      this.stopViewing();
      return;
    }
    const token = ++this.viewToken;
    this.viewing = true;
    const done = await this.build(VIEW_FORMAT);
    if (token !== this.viewToken) return;
    if (!done) {
      this.viewing = false;
      this.render();
      return;
    }
    try {
      this.source.show(done.built);
    } catch (e) {
      this.viewing = false;
      this.showFigures({ state: 'error', text: anatomicalErrorText(toCoreErrorData(e).message) });
      this.source.failed(e);
    }
    this.render();
  }
}
