/**
 * One wall's row of the export panel (the LV wall, the biventricular wall): a label, its STL, OBJ,
 * PLY and VTK buttons (enabled while the wall can be built, titled with why not otherwise), and a
 * line of figures once built, or why it was not. The wall is built in the worker on a click and
 * saved; figures of a wall whose meshes or settings have since changed are taken away. What the
 * row says comes from its `WallRowSpec` (export/wall.ts, export/bivWall.ts): the row only wires it.
 */
import { WALL_FORMATS, toCoreErrorData, type WallFormat, type WallSummary } from '../core-client/protocol';
import { h } from '../ui/dom';
import { download } from './download';
import type { ExportInfo } from './export/header';

/** Whether a wall can be built now, the title saying why not, and a key of the meshes it would be made of. */
export interface WallRowReadiness {
  ready: boolean;
  title: string;
  key: string;
}

/** A built wall's figures line: the figures (each kept whole), the notes after them, the tooltip, the data attributes. */
export interface WallFiguresView {
  figures: string[];
  notes: string[];
  title: string;
  warn: boolean;
  /** `data-*` attributes of the figures line (tests read the numbers unrounded). */
  data: Record<string, string>;
}

export interface WallRowSpec {
  /** The test-id stem: `<id>-export` (the row), `export-<id>-<fmt>` (its buttons), `<id>-figures`. */
  id: string;
  /** "LV wall": the row's label, and the buttons' accessible names with the format after it. */
  label: string;
  /** What it is made of, beside the label. */
  what: string;
  /** The title before a file is open. */
  initialTitle: string;
  /** The figures line while building. */
  busy: string;
  formatTitle(format: WallFormat): string;
  fileName(info: ExportInfo, format: WallFormat): string;
  errorText(message: string): string;
  view(s: WallSummary): WallFiguresView;
}

export interface WallRowSource {
  info(): ExportInfo | null;
  /** The wall built in the worker and written as `format` (null: it cannot be built now); rejects with the core's error. */
  build(format: WallFormat): Promise<{ summary: WallSummary; bytes: Uint8Array }> | null;
  /** Reports a failed build (the banner). */
  failed(e: unknown): void;
}

const MIME: Record<WallFormat, string> = { stl: 'model/stl', obj: 'model/obj', ply: 'application/octet-stream', vtk: 'application/octet-stream' };

export class WallRow {
  readonly element: HTMLElement;
  private readonly buttons = new Map<WallFormat, HTMLButtonElement>();
  /** The wall's figures once built (or why it was not), while its meshes stay the ones used. */
  private readonly figures: HTMLElement;
  private readiness: WallRowReadiness;
  private busy = false;
  /** The readiness key of the wall the figures line describes (null: it describes none). */
  private figuresKey: string | null = null;
  /** The data attributes the figures line carries now (removed with it). */
  private dataKeys: string[] = [];

  constructor(
    private readonly spec: WallRowSpec,
    private readonly source: WallRowSource,
  ) {
    for (const fmt of WALL_FORMATS) {
      const b = h('button', { type: 'button', class: 'small', 'data-testid': `export-${spec.id}-${fmt}`, title: '' }, fmt.toUpperCase());
      b.addEventListener('click', () => void this.export(fmt));
      // Told apart from the mesh's own STL ... buttons by screen readers (and tests by role).
      b.setAttribute('aria-label', `${spec.label} ${fmt.toUpperCase()}`);
      this.buttons.set(fmt, b);
    }
    this.figures = h('p', { class: 'wall-figures', 'data-testid': `${spec.id}-figures`, role: 'status', hidden: true });
    this.element = h(
      'div',
      { class: 'wall-export', 'data-testid': `${spec.id}-export`, role: 'group', 'aria-label': spec.label },
      h('div', { class: 'wall-head' }, h('span', { class: 'wall-label' }, spec.label), h('span', { class: 'wall-what' }, spec.what)),
      h('div', { class: 'button-grid' }, ...this.buttons.values()),
      this.figures,
    );
    this.readiness = { ready: false, title: spec.initialTitle, key: '' };
    this.render();
  }

  /** Whether the wall can be built now: the buttons and their titles follow; figures of a wall of other meshes (or settings) are taken away. */
  set(readiness: WallRowReadiness): void {
    this.readiness = readiness;
    if (this.figuresKey !== null && (!readiness.ready || readiness.key !== this.figuresKey)) this.show(null);
    this.render();
  }

  private render(): void {
    const w = this.readiness;
    this.element.title = w.title;
    this.element.dataset.ready = w.ready ? '1' : '0';
    for (const [fmt, b] of this.buttons) {
      b.disabled = !w.ready || this.busy;
      b.title = w.ready ? this.spec.formatTitle(fmt) : w.title;
    }
  }

  /** Fills the figures line: a built wall's figures, a message (`state` busy or error), or nothing. */
  private show(content: { summary: WallSummary } | { state: 'busy' | 'error'; text: string } | null, key: string | null = null): void {
    const el = this.figures;
    this.figuresKey = content === null ? null : key;
    for (const k of this.dataKeys) delete el.dataset[k];
    this.dataKeys = [];
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
    const view = this.spec.view(content.summary);
    el.dataset.state = 'done';
    for (const [k, v] of Object.entries(view.data)) el.dataset[k] = v;
    this.dataKeys = Object.keys(view.data);
    // Each figure kept whole on a narrow column; the notes wrap as text.
    const nodes: (HTMLElement | string)[] = [];
    view.figures.forEach((f, i) => nodes.push(...(i > 0 ? [' · '] : []), h('span', { class: 'wall-figure' }, f)));
    for (const n of view.notes) nodes.push(`. ${n}`);
    el.replaceChildren(...nodes);
    el.title = view.title;
    el.classList.toggle('warn', view.warn);
  }

  /** Builds the wall in the worker as `fmt` and saves it; its figures (or why not) below the buttons. */
  private async export(fmt: WallFormat): Promise<void> {
    const info = this.source.info();
    const wall = this.readiness;
    if (!info || !wall.ready || this.busy) return;
    const pending = this.source.build(fmt);
    if (!pending) return;
    this.busy = true;
    this.render();
    this.show({ state: 'busy', text: this.spec.busy }, wall.key);
    try {
      const { summary, bytes } = await pending;
      download(bytes.slice(), this.spec.fileName(info, fmt), MIME[fmt]);
      // Settings changed meanwhile: the file is of the meshes asked for, the figures no longer current.
      this.show(this.readiness.key === wall.key ? { summary } : null, wall.key);
    } catch (e) {
      this.show({ state: 'error', text: this.spec.errorText(toCoreErrorData(e).message) }, wall.key);
      this.source.failed(e);
    } finally {
      this.busy = false;
      this.render();
    }
  }
}
