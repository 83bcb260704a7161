/**
 * One wall's row of the export panel (the LV wall, the biventricular wall): a label, its View
 * toggle and its STL, OBJ, PLY and VTK buttons (enabled while the wall can be built, titled with
 * why not otherwise), and a line of figures once built, or why it was not. The wall is built in
 * the worker on a click and saved; figures of a wall whose meshes or settings have since changed
 * are taken away. View builds the same wall as PLY (the format that carries the thickness and the
 * regions) and has it shown in the 3D view in place of the surface, until clicked again or until
 * the wall goes stale (`set`) or the panel takes it away (`stopViewing`: a new run, another file);
 * a PLY build of the current meshes is kept and shown again without asking the worker. What the
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

/** What a wall row shows under its figures line of a built wall (the LV wall's bullseye), and takes away with it. */
export interface WallDetails {
  readonly element: HTMLElement;
  /** A built wall's details (its figures line shows its figures). */
  show(summary: WallSummary): void;
  /** Nothing: the figures line is empty, busy or an error. */
  clear(): void;
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
  /**
   * What the row shows under its figures line of a built wall (the LV wall's AHA bullseye), shown
   * and taken away with the figures (`info`: the run the wall is built of). None when absent.
   */
  details?(info: () => ExportInfo | null): WallDetails;
}

/** A wall built in the worker: its figures and its file. */
export interface BuiltWall {
  summary: WallSummary;
  bytes: Uint8Array;
}

export interface WallRowSource {
  info(): ExportInfo | null;
  /** The wall built in the worker and written as `format` (null: it cannot be built now); rejects with the core's error. */
  build(format: WallFormat): Promise<BuiltWall> | null;
  /** Reports a failed build (the banner). */
  failed(e: unknown): void;
  /** Shows the wall (built as PLY) in the 3D view in place of the surface; throws if it cannot. */
  show(wall: BuiltWall): void;
  /** Takes the wall this row shows out of the 3D view: the surface comes back. */
  hide(): void;
}

/** The format View builds: the one that carries both the thickness per vertex and the region per triangle. */
export const VIEW_FORMAT: WallFormat = 'ply';

const MIME: Record<WallFormat, string> = { stl: 'model/stl', obj: 'model/obj', ply: 'application/octet-stream', vtk: 'application/octet-stream' };

export class WallRow {
  readonly element: HTMLElement;
  private readonly buttons = new Map<WallFormat, HTMLButtonElement>();
  /** View: the wall in the 3D view (pressed) or not. */
  private readonly viewButton: HTMLButtonElement;
  /** The wall's figures once built (or why it was not), while its meshes stay the ones used. */
  private readonly figures: HTMLElement;
  /** The spec's details under the figures (the bullseye), which follow them. */
  private readonly details: WallDetails | null;
  private readiness: WallRowReadiness;
  private busy = false;
  /** The readiness key of the wall the figures line describes (null: it describes none). */
  private figuresKey: string | null = null;
  /** The data attributes the figures line carries now (removed with it). */
  private dataKeys: string[] = [];
  /** The wall is in the 3D view, or being built to be (the View button pressed). */
  private viewing = false;
  /** The readiness key of the wall viewed. */
  private viewKey = '';
  /** This row's wall is the one in the 3D view (handed to `source.show`, not yet taken away). */
  private onScreen = false;
  /** Bumped whenever viewing stops: a build still on its way is then not shown. */
  private viewToken = 0;
  /** The last PLY build and what it was built of (`heldKey`): shown again without asking the worker. */
  private held: { key: string; wall: BuiltWall } | null = null;

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
    this.viewButton = h('button', { type: 'button', class: 'small wall-view', 'data-testid': `view-${spec.id}`, 'aria-pressed': 'false', title: '' }, 'View');
    this.viewButton.addEventListener('click', () => void this.toggleView());
    this.viewButton.setAttribute('aria-label', `View the ${spec.label}`);
    this.figures = h('p', { class: 'wall-figures', 'data-testid': `${spec.id}-figures`, role: 'status', hidden: true });
    this.details = spec.details?.(() => source.info()) ?? null;
    this.element = h(
      'div',
      { class: 'wall-export', 'data-testid': `${spec.id}-export`, role: 'group', 'aria-label': spec.label },
      h('div', { class: 'wall-head' }, h('span', { class: 'wall-label' }, spec.label), h('span', { class: 'wall-what' }, spec.what), this.viewButton),
      h('div', { class: 'button-grid' }, ...this.buttons.values()),
      this.figures,
      this.details?.element,
    );
    this.readiness = { ready: false, title: spec.initialTitle, key: '' };
    this.render();
  }

  /** The spec's id (`wall`, `biv-wall`). */
  get id(): string {
    return this.spec.id;
  }

  /** Whether the wall is in the 3D view (or being built to be). */
  get isViewing(): boolean {
    return this.viewing;
  }

  /**
   * Whether the wall can be built now: the buttons and their titles follow; figures of a wall of
   * other meshes (or settings) are taken away, and so is the wall from the view.
   */
  set(readiness: WallRowReadiness): void {
    this.readiness = readiness;
    const current = readiness.ready ? readiness.key : null;
    if (this.figuresKey !== null && this.figuresKey !== current) this.show(null);
    if (this.viewing && this.viewKey !== current) this.stopViewing();
    if (this.held && this.held.key !== this.heldKey()) this.held = null;
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
    const v = this.viewButton;
    v.disabled = !w.ready || this.busy;
    v.setAttribute('aria-pressed', this.viewing ? 'true' : 'false');
    v.title = !w.ready
      ? w.title
      : this.viewing
        ? `Back to the reconstructed surface (the ${this.spec.label} is shown in the 3D view)`
        : `Show the ${this.spec.label} in the 3D view in place of the surface, coloured by wall thickness or by region (Wall colour in the view panel); Clip cuts it open`;
  }

  /** What a PLY build is of: the meshes and settings (the readiness key), the file and its frame. */
  private heldKey(): string | null {
    const info = this.source.info();
    return this.readiness.ready && info ? JSON.stringify([this.readiness.key, info.fileName, info.frame]) : null;
  }

  /** Takes the wall out of the view (the surface comes back) if this row shows it. */
  stopViewing(): void {
    if (!this.viewing) return;
    const shown = this.onScreen;
    this.release();
    // Still being built: the view shows nothing of this row's (perhaps the other wall) to take away.
    if (shown) this.source.hide();
  }

  /** Another wall took the view (which it fills itself): this row's View is no longer pressed. */
  release(): void {
    if (!this.viewing) return;
    this.viewing = false;
    this.onScreen = false;
    this.viewToken++;
    this.render();
  }

  /** View: shows the wall (built as PLY, or the build held), or takes it away again. */
  private async toggleView(): Promise<void> {
    if (this.viewing) {
      this.stopViewing();
      return;
    }
    const wall = this.readiness;
    const key = this.heldKey();
    if (!wall.ready || this.busy || key === null) return;
    const token = ++this.viewToken;
    if (this.held?.key === key) {
      this.viewing = true;
      this.viewKey = wall.key;
      this.display(this.held.wall, wall.key);
      return;
    }
    const pending = this.source.build(VIEW_FORMAT);
    if (!pending) return;
    this.viewing = true;
    this.viewKey = wall.key;
    this.busy = true;
    this.render();
    this.show({ state: 'busy', text: this.spec.busy }, wall.key);
    try {
      const built = await pending;
      if (this.heldKey() === key) this.held = { key, wall: built };
      const stale = this.readiness.key !== wall.key;
      if (token === this.viewToken && !stale) this.display(built, wall.key);
      else this.show(stale ? null : { summary: built.summary }, wall.key);
    } catch (e) {
      if (token === this.viewToken) this.viewing = false;
      this.show({ state: 'error', text: this.spec.errorText(toCoreErrorData(e).message) }, wall.key);
      this.source.failed(e);
    } finally {
      this.busy = false;
      this.render();
    }
  }

  /** Hands a built wall to the view and fills the figures line; one the view cannot show is an error there. */
  private display(built: BuiltWall, key: string): void {
    try {
      this.source.show(built);
      this.onScreen = true;
      this.show({ summary: built.summary }, key);
    } catch (e) {
      this.viewing = false;
      this.show({ state: 'error', text: this.spec.errorText(toCoreErrorData(e).message) }, key);
      this.source.failed(e);
    }
    this.render();
  }

  /** Fills the figures line: a built wall's figures, a message (`state` busy or error), or nothing. */
  private show(content: { summary: WallSummary } | { state: 'busy' | 'error'; text: string } | null, key: string | null = null): void {
    const el = this.figures;
    this.figuresKey = content === null ? null : key;
    for (const k of this.dataKeys) delete el.dataset[k];
    this.dataKeys = [];
    el.classList.toggle('warn', false);
    // The details are of the wall the figures give, and go with them (busy, an error, stale).
    if (content === null || 'state' in content) this.details?.clear();
    else this.details?.show(content.summary);
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
      const key = this.heldKey();
      if (fmt === VIEW_FORMAT && key !== null && this.readiness.key === wall.key) this.held = { key, wall: { summary, bytes } };
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
