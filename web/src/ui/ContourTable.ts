/**
 * The Contours panel (right column, between the result and the exports): one row per contour of
 * the run's surface, with a "use" box, its id, SAX/LAX, its points and the mean and max distance of
 * its points to the mesh (mm, the max with a swatch in the contour legend's colours), so a user
 * sees which contour the mesh misses. Unticking a row leaves that contour out and runs again, as
 * a parameter change does; contours the core left out (strays, specks) are listed greyed with the
 * reason, their box disabled (Keep specks and strays uses them). Hovering a row highlights its
 * contour in the 3D view; the view's hover highlights the row back; a click on an id keeps the
 * highlight until the next click.
 *
 * The rows come from the last finished run; a new run of the same file, frame and surface marks
 * them stale (they stay usable: leaving out a second contour need not wait for the first run),
 * anything else clears them. `[data-testid=contour-table]` (the `<details>`) carries `data-count`
 * (rows), `data-stale` (1/0) and `data-highlight` (the id highlighted, '' for none); each
 * `[data-testid=contour-row]` `data-id`, `data-kind`, `data-state` (used, by_user, stray, speck,
 * lax_speck), `data-count`, and for a used contour `data-mean-mm` and `data-max-mm`.
 */
import type { RunResult } from '../core-client/protocol';
import { cssColorAt } from '../viewer/colormap';
import { contourRows, contourScaleMax, mm2, useTitle, type ContourRow, type FileContour } from './contourRows';
import { h } from './dom';

/** What the panel asks of the app (the controller) and of the 3D view. */
export interface ContourTableHost {
  /**
   * The run on screen's file, frame and surface as one key (rows of another key are cleared, not
   * kept stale), the ids the user left out of it, and its contours in file order (id, kind); null
   * without a file.
   */
  context(): { key: string; leaveOut: readonly string[]; fileContours: readonly FileContour[] } | null;
  /** Leaves `id` out of the current surface (`out`) or puts it back, and runs again. */
  setLeftOut(id: string, out: boolean): void;
  /** Puts every contour the user left out back, in one run. */
  useAll(): void;
  /** Highlights contour `id` in the 3D view (null: none). */
  highlight(id: string | null): void;
}

interface Shown {
  key: string;
  rows: ContourRow[];
  scaleMax: number;
}

const USE_ALL_TITLE = 'Use every contour you left out again (one run)';

export class ContourTable {
  readonly element: HTMLElement;
  private readonly details: HTMLDetailsElement;
  private readonly heading: HTMLElement;
  private readonly note: HTMLElement;
  private readonly useAllButton: HTMLButtonElement;
  private readonly body: HTMLElement;
  private readonly table: HTMLTableElement;
  private shown: Shown | null = null;
  private stale = false;
  /** The id a click keeps highlighted (null: none); a row hovered highlights over it meanwhile. */
  private pinned: string | null = null;
  /** The row the 3D view's pointer is on. */
  private fromView: string | null = null;
  /** The id highlighted from the panel (hovered, or kept by a click). */
  private highlighted: string | null = null;
  private rowElements = new Map<string, HTMLElement[]>();

  constructor(private readonly host: ContourTableHost) {
    this.heading = h('span', { class: 'contours-heading' }, 'Contours');
    this.useAllButton = h('button', { type: 'button', class: 'small', 'data-testid': 'contour-use-all', title: USE_ALL_TITLE, hidden: true }, 'Use all');
    this.useAllButton.addEventListener('click', () => this.host.useAll());
    this.note = h('p', { class: 'muted contours-note', 'data-testid': 'contour-note' }, 'no result yet');
    this.body = h('tbody', {});
    this.table = h(
      'table',
      { class: 'contour-table', hidden: true },
      // The header cells' classes size the columns (table-layout: fixed); the points column goes on a narrow window.
      h(
        'thead',
        {},
        h(
          'tr',
          {},
          h('th', { scope: 'col', class: 'c-use', title: 'used by the reconstruction (untick to leave a contour out)' }, h('span', { class: 'visually-hidden' }, 'use')),
          h('th', { scope: 'col', class: 'c-id' }, 'contour'),
          h('th', { scope: 'col', class: 'c-kind', title: 'short axis (SAX) or long axis (LAX), as the run split them' }, 'kind'),
          h('th', { scope: 'col', class: 'num c-pts', title: 'contour points' }, 'pts'),
          h('th', { scope: 'col', class: 'num c-mean', title: 'mean distance of its points to the mesh, mm' }, 'mean'),
          h('th', { scope: 'col', class: 'num c-max', title: 'largest distance of its points to the mesh, mm (the swatch: its colour on the contour legend)' }, 'max'),
        ),
      ),
      this.body,
    );
    this.details = h(
      'details',
      { class: 'contours-details', open: true, 'data-testid': 'contour-table' },
      h('summary', { class: 'contours-summary' }, h('h2', {}, this.heading), this.useAllButton),
      this.note,
      this.table,
    );
    this.element = h('section', { class: 'panel contours', 'aria-label': 'Contours' }, this.details);
    this.element.addEventListener('mouseleave', () => this.unhover());
    this.details.dataset.count = '0';
    this.details.dataset.stale = '0';
    this.details.dataset.highlight = '';
  }

  /** A run finished: its contours, with the list the next run would use. */
  show(r: RunResult): void {
    const context = this.host.context();
    if (this.shown?.key !== context?.key) this.forgetHighlight();
    // (A highlight kept on the same surface follows the new run's contours by itself: Viewer.highlightContour.)
    this.shown = { key: context?.key ?? '', rows: contourRows(r, context?.fileContours ?? []), scaleMax: contourScaleMax(r) };
    this.stale = false;
    this.render();
  }

  /**
   * The result on screen went (a new run, another file or surface): rows of the same file, frame
   * and surface stay, marked stale; others go.
   */
  resultCleared(): void {
    const context = this.host.context();
    if (!this.shown || this.shown.key !== context?.key) {
      this.shown = null;
      this.fromView = null;
      this.forgetHighlight();
    }
    this.stale = this.shown !== null;
    this.render();
  }

  /** The user's list changed (ticked, unticked, Use all, a session opened): the boxes follow at once. */
  leaveOutChanged(): void {
    this.render();
  }

  /** The 3D view's pointer is on contour `id` (null: on none): its row is highlighted. */
  hoverFromView(id: string | null): void {
    if (id === this.fromView) return;
    this.fromView = id;
    this.markRows();
  }

  private render(): void {
    const context = this.host.context();
    const leaveOut = new Set(context?.leaveOut ?? []);
    const s = this.shown;
    const d = this.details.dataset;
    d.count = String(s?.rows.length ?? 0);
    d.stale = this.stale ? '1' : '0';
    this.heading.textContent = s ? `Contours (${s.rows.length})` : 'Contours';
    this.element.classList.toggle('is-stale', this.stale);
    this.useAllButton.hidden = leaveOut.size === 0;
    this.note.hidden = s !== null && !this.stale;
    // Stale: a run started since (it may go on, or have been stopped or failed): say whose figures these are.
    this.note.textContent = !s ? 'no result yet' : 'the figures are of the last finished run';
    this.table.hidden = !s;
    this.rowElements = new Map();
    this.body.replaceChildren(...(s ? s.rows.map((row) => this.rowElement(row, !leaveOut.has(row.id), s.scaleMax)) : []));
    this.markRows();
  }

  private rowElement(row: ContourRow, on: boolean, scaleMax: number): HTMLElement {
    const userRow = row.state === 'used' || row.state === 'by_user';
    const box = h('input', { type: 'checkbox', 'data-testid': 'contour-use', 'aria-label': `use ${row.id}`, title: useTitle(row.state, on) });
    box.checked = userRow && on;
    box.disabled = !userRow;
    box.addEventListener('change', () => this.host.setLeftOut(row.id, !box.checked));
    // The id is cut with an ellipsis in the narrow column: the whole id (and why it is left out) in its tooltip.
    const id = h('td', { class: 'contour-id', title: row.detail ?? row.id }, row.id);
    id.addEventListener('click', () => this.pin(row.id));
    const figures: HTMLElement[] = [];
    if (row.maxMm !== null) {
      const swatch = h('span', { class: 'swatch' });
      swatch.style.background = cssColorAt(row.maxMm, 0, scaleMax);
      figures.push(h('td', { class: 'num' }, mm2(row.meanMm)), h('td', { class: 'num contour-max' }, swatch, mm2(row.maxMm)));
    } else {
      // A contour left out has no distances: its reason takes both figure cells.
      figures.push(h('td', { class: 'contour-reason', colspan: 2, title: useTitle(row.state, on) }, row.reason ?? '–'));
    }
    const tr = h(
      'tr',
      {
        class: `contour-row state-${row.state}${userRow ? '' : ' core-left-out'}${!userRow || on ? '' : ' user-left-out'}`,
        'data-testid': 'contour-row',
        'data-id': row.id,
        'data-kind': row.kind ?? '',
        'data-state': row.state,
        'data-count': row.count,
        'data-mean-mm': row.meanMm ?? undefined,
        'data-max-mm': row.maxMm ?? undefined,
      },
      h('td', { class: 'contour-use' }, box),
      id,
      h('td', { class: `contour-kind ${(row.kind ?? '').toLowerCase()}` }, row.kind ?? '–'),
      h('td', { class: 'num c-pts' }, String(row.count)),
      ...figures,
    );
    tr.addEventListener('mouseenter', () => this.hover(row.id));
    this.rowElements.set(row.id, [...(this.rowElements.get(row.id) ?? []), tr]);
    return tr;
  }

  private hover(id: string): void {
    this.host.highlight(id);
    this.setHighlight(id);
  }

  /** The pointer left the panel: the highlight goes back to the clicked contour, if any. */
  private unhover(): void {
    this.host.highlight(this.pinned);
    this.setHighlight(this.pinned);
  }

  /** A click on an id keeps its highlight (a second click on it lets it go). */
  private pin(id: string): void {
    this.pinned = this.pinned === id ? null : id;
    this.host.highlight(this.pinned ?? id);
    this.setHighlight(this.pinned ?? id);
  }

  /** Another file, frame or surface: nothing of the last one stays highlighted, in the panel or the view. */
  private forgetHighlight(): void {
    if (this.highlighted === null && this.pinned === null) return;
    this.pinned = null;
    this.highlighted = null;
    this.details.dataset.highlight = '';
    this.host.highlight(null);
  }

  private setHighlight(id: string | null): void {
    this.highlighted = id;
    this.details.dataset.highlight = id ?? '';
    this.markRows();
  }

  private markRows(): void {
    for (const [id, rows] of this.rowElements) {
      for (const tr of rows) {
        tr.classList.toggle('highlighted', id === this.highlighted || id === this.fromView);
        tr.classList.toggle('pinned', id === this.pinned);
      }
    }
  }
}
