/**
 * The Contours panel (right column, between the result and the exports): one row per contour of
 * the run's surface, with a "use" box, its id, SAX/LAX, its points and the mean and max distance of
 * its points to the mesh (mm, the max with a swatch in the contour legend's colours), so a user
 * sees which contour the mesh misses. Unticking a row leaves that contour out of the file (every
 * surface's runs, as the CLI's `--leave-out`) and runs again, as a parameter change does; contours the core left out (strays, specks) are listed greyed with the
 * reason, their box disabled (Keep specks and strays uses them). A row left out shows, in italics
 * and without a swatch (the colour scale is that of the contours used), how far the mesh built
 * without it passes: for one the user left out, its held-out figure, whether the others agree
 * with it.
 * Hovering a row highlights its contour in the 3D view; the view's hover highlights the row back;
 * a click on an id keeps the highlight until the next click. A click on a column's header sorts
 * the rows by it (nextSort: again reverses, a third time the file's order). The CSV button beside
 * the heading saves the table as the panel shows it, in its sort (export/contourCsv.ts).
 *
 * The rows come from the last finished run; a new run of the same file, frame and surface marks
 * them stale (they stay usable: leaving out a second contour need not wait for the first run) and
 * keeps their sort, anything else clears them and the sort. `[data-testid=contour-table]` (the
 * `<details>`) carries `data-count` (rows), `data-stale` (1/0) and `data-highlight` (the id
 * highlighted, '' for none); each `[data-testid=contour-row]` `data-id`, `data-kind`, `data-state`
 * (used, by_user, stray, speck, lax_speck), `data-count`, and `data-mean-mm` and `data-max-mm`
 * when it has figures (a contour used, or one left out by a core that measures it); the sorted
 * header `aria-sort`.
 */
import type { RunResult } from '../core-client/protocol';
import { download } from '../io/download';
import { contourCsvFileName, writeContourCsv } from '../io/export/contourCsv';
import type { ExportInfo } from '../io/export/header';
import { cssColorAt } from '../viewer/colormap';
import { contourRows, contourScaleMax, mm2, nextSort, sortRows, sortsDescendingFirst, useTitle, type ContourRow, type FileContour, type RowSort, type SortColumn } from './contourRows';
import { h } from './dom';

/** What the panel asks of the app (the controller) and of the 3D view. */
export interface ContourTableHost {
  /**
   * The run on screen's file, frame and surface as one key (rows of another key are cleared, not
   * kept stale), the ids of its contours the user left out, and its contours in file order (id,
   * kind); null without a file.
   */
  context(): { key: string; leaveOut: readonly string[]; fileContours: readonly FileContour[] } | null;
  /** Leaves `id` out of the file and frame (`out`: every surface's runs) or puts it back, and runs again. */
  setLeftOut(id: string, out: boolean): void;
  /** Puts back, in one run, the contours of this surface the user left out (other surfaces' stay out). */
  useAll(): void;
  /** Highlights contour `id` in the 3D view (null: none). */
  highlight(id: string | null): void;
  /** What the exports' headers say of the run on screen (null without a file). */
  exportInfo(): ExportInfo | null;
}

interface Shown {
  key: string;
  rows: ContourRow[];
  scaleMax: number;
  /**
   * The header of the run the rows are of, taken as it finished: rows kept stale while the next
   * run goes on are not that run's (its parameters and leave_out may differ).
   */
  info: ExportInfo | null;
}

const USE_ALL_TITLE = "Use every contour of this surface you left out again (one run); those you left out of the file's other surfaces stay out";
const CSV_TITLE = 'The table as CSV: one row per contour, distances in mm';

/** The sortable columns: the class that sizes each (table-layout: fixed), its heading and what it holds. */
const COLUMNS: readonly { column: SortColumn; cls: string; label: string; what: string }[] = [
  { column: 'id', cls: 'c-id', label: 'contour', what: 'contour id' },
  { column: 'kind', cls: 'c-kind', label: 'kind', what: 'short axis (SAX) or long axis (LAX), as the run split them' },
  { column: 'count', cls: 'num c-pts', label: 'pts', what: 'contour points' },
  { column: 'mean', cls: 'num c-mean', label: 'mean', what: 'mean distance of its points to the mesh, mm' },
  { column: 'max', cls: 'num c-max', label: 'max', what: 'largest distance of its points to the mesh, mm (the swatch: its colour on the contour legend)' },
];

/** A header's tooltip: what the column holds and what clicks on it do (nextSort). */
function headerTitle(what: string, column: SortColumn): string {
  const [first, second] = sortsDescendingFirst(column) ? ['largest first', 'smallest first'] : ['A to Z', 'Z to A'];
  return `${what}. Click to sort, ${first}; again: ${second}; a third time: the file's order`;
}

/** What the figures of a row left out are: the mesh was built without that contour. */
export const HELD_OUT_TITLE = 'distance from this contour to the mesh built without it, mm (a held-out contour: how far the others predict it)';

/**
 * A row's mean and max cells. A contour used has its max's swatch on the contour legend's scale
 * (0 to `scaleMax`); one left out is not drawn in those colours (a stray far off would only clamp
 * at the top), so its held-out figures go without, in italics, saying what they are.
 */
function figureCells(row: ContourRow, scaleMax: number): HTMLElement[] {
  if (row.state !== 'used') {
    const title = (which: string, v: number | null) => (v === null ? null : `${which} ${HELD_OUT_TITLE}`);
    return [
      h('td', { class: 'num held-out', title: title('mean', row.meanMm) }, mm2(row.meanMm)),
      h('td', { class: 'num contour-max held-out', title: title('largest', row.maxMm) }, mm2(row.maxMm)),
    ];
  }
  const swatch = h('span', { class: 'swatch' });
  swatch.style.background = cssColorAt(row.maxMm ?? 0, 0, scaleMax);
  return [h('td', { class: 'num' }, mm2(row.meanMm)), h('td', { class: 'num contour-max' }, swatch, mm2(row.maxMm))];
}

export class ContourTable {
  readonly element: HTMLElement;
  private readonly details: HTMLDetailsElement;
  private readonly heading: HTMLElement;
  private readonly note: HTMLElement;
  private readonly useAllButton: HTMLButtonElement;
  private readonly csvButton: HTMLButtonElement;
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
  /** The column the rows are sorted by (null: the file's order). */
  private sort: RowSort | null = null;
  private readonly headers = new Map<SortColumn, { th: HTMLElement; arrow: HTMLElement }>();

  constructor(private readonly host: ContourTableHost) {
    this.heading = h('span', { class: 'contours-heading' }, 'Contours');
    this.useAllButton = h('button', { type: 'button', class: 'small', 'data-testid': 'contour-use-all', title: USE_ALL_TITLE, hidden: true }, 'Use all');
    this.useAllButton.addEventListener('click', () => this.host.useAll());
    this.csvButton = h('button', { type: 'button', class: 'small', 'data-testid': 'contour-csv', title: CSV_TITLE }, 'CSV');
    this.csvButton.addEventListener('click', () => this.exportCsv());
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
          ...COLUMNS.map((c) => this.headerCell(c)),
        ),
      ),
      this.body,
    );
    this.details = h(
      'details',
      { class: 'contours-details', open: true, 'data-testid': 'contour-table' },
      h('summary', { class: 'contours-summary' }, h('h2', {}, this.heading), h('span', { class: 'contours-actions' }, this.useAllButton, this.csvButton)),
      this.note,
      this.table,
    );
    this.element = h('section', { class: 'panel contours', 'aria-label': 'Contours' }, this.details);
    this.element.addEventListener('mouseleave', () => this.unhover());
    this.details.dataset.count = '0';
    this.details.dataset.stale = '0';
    this.details.dataset.highlight = '';
    this.csvButton.disabled = true;
  }

  /** A run finished: its contours, with the list the next run would use. */
  show(r: RunResult): void {
    const context = this.host.context();
    if (this.shown?.key !== context?.key) this.forgetKey();
    // (A highlight kept on the same surface follows the new run's contours by itself: Viewer.highlightContour.)
    this.shown = { key: context?.key ?? '', rows: contourRows(r, context?.fileContours ?? []), scaleMax: contourScaleMax(r), info: this.host.exportInfo() };
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
      this.forgetKey();
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
    this.csvButton.disabled = !s?.info || s.rows.length === 0;
    this.note.hidden = s !== null && !this.stale;
    // Stale: a run started since (it may go on, or have been stopped or failed): say whose figures these are.
    this.note.textContent = !s ? 'no result yet' : 'the figures are of the last finished run';
    this.table.hidden = !s;
    this.rowElements = new Map();
    this.body.replaceChildren(...(s ? this.sortedRows().map((row) => this.rowElement(row, !leaveOut.has(row.id), s.scaleMax)) : []));
    this.markHeaders();
    this.markRows();
  }

  /** The rows in the order shown: the CSV follows the sort the user chose, as the table reads. */
  private sortedRows(): ContourRow[] {
    return this.shown ? sortRows(this.shown.rows, this.sort) : [];
  }

  private exportCsv(): void {
    const info = this.shown?.info;
    if (!info) return;
    download(writeContourCsv(this.sortedRows(), info), contourCsvFileName(info), 'text/csv');
  }

  /** A column's header: a button that sorts by it, and the arrow of the sort. */
  private headerCell(c: (typeof COLUMNS)[number]): HTMLElement {
    const arrow = h('span', { class: 'sort-arrow', 'aria-hidden': 'true' });
    const button = h('button', { type: 'button', class: 'sort-button' }, c.label, arrow);
    button.addEventListener('click', () => {
      this.sort = nextSort(this.sort, c.column);
      this.render();
    });
    const th = h('th', { scope: 'col', class: c.cls, title: headerTitle(c.what, c.column) }, button);
    this.headers.set(c.column, { th, arrow });
    return th;
  }

  private markHeaders(): void {
    for (const [column, { th, arrow }] of this.headers) {
      const sorted = this.sort?.column === column ? this.sort : null;
      if (sorted) th.setAttribute('aria-sort', sorted.descending ? 'descending' : 'ascending');
      else th.removeAttribute('aria-sort');
      arrow.textContent = sorted ? (sorted.descending ? '▾' : '▴') : '';
    }
  }

  private rowElement(row: ContourRow, on: boolean, scaleMax: number): HTMLElement {
    const userRow = row.state === 'used' || row.state === 'by_user';
    const box = h('input', { type: 'checkbox', 'data-testid': 'contour-use', 'aria-label': `use ${row.id}`, title: useTitle(row.state, on) });
    box.checked = userRow && on;
    box.disabled = !userRow;
    box.addEventListener('change', () => this.host.setLeftOut(row.id, !box.checked));
    // The id is cut with an ellipsis in the narrow column: the whole id (why it is left out, how far the mesh passes) in its tooltip.
    const id = h(
      'td',
      { class: 'contour-id', title: row.detail ?? row.id },
      h('span', { class: 'contour-name' }, row.id),
      row.reason === null ? null : h('span', { class: 'contour-reason' }, row.reason),
      row.note === null ? null : h('span', { class: 'contour-reason contour-spikes', 'data-testid': 'contour-spikes' }, row.note),
    );
    id.addEventListener('click', () => this.pin(row.id));
    const tr = h(
      'tr',
      {
        class: `contour-row state-${row.state}${userRow ? '' : ' core-left-out'}${!userRow || on ? '' : ' user-left-out'}`,
        'data-testid': 'contour-row',
        'data-id': row.id,
        'data-kind': row.kind ?? '',
        'data-state': row.state,
        'data-count': row.count,
        'data-spikes': row.spikes > 0 ? row.spikes : undefined,
        'data-far': row.far > 0 ? row.far : undefined,
        'data-off-plane': row.offPlane > 0 ? row.offPlane : undefined,
        'data-mean-mm': row.meanMm ?? undefined,
        'data-max-mm': row.maxMm ?? undefined,
      },
      h('td', { class: 'contour-use' }, box),
      id,
      h('td', { class: `contour-kind ${(row.kind ?? '').toLowerCase()}` }, row.kind ?? '–'),
      h('td', { class: 'num c-pts' }, String(row.count)),
      ...figureCells(row, scaleMax),
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

  /**
   * Another file, frame or surface: nothing of the last one stays highlighted, in the panel or the
   * view, and its sort goes (a sort is chosen for one list of contours).
   */
  private forgetKey(): void {
    this.sort = null;
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
