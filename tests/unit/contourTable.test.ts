// The Contours panel (web/src/ui/ContourTable.ts, rows from contourRows.ts) on the fake DOM: one
// row per contour of a run with its figures to two decimals, those the core left out greyed with
// their reason and no usable box, those the user left out unticked, both with how far the mesh
// built without them passes (held out, no swatch); the boxes, "Use all" and the hover reach the
// host; a click on a header sorts by its column (again: reversed, a third time: the file's order,
// rows without a figure last); a new run of the same surface marks the rows stale and keeps the
// sort, anything else clears both; the CSV button saves the rows as shown, under the header of the
// run they are of.
import { describe, expect, it, vi } from 'vitest';
import type { ContourInfo, RunResult, SetAsideEntry } from '../../web/src/core-client/protocol';
import type { ExportInfo } from '../../web/src/io/export/header';
import { ContourTable, HELD_OUT_TITLE, type ContourTableHost } from '../../web/src/ui/ContourTable';
import { contourRows, contourScaleMax, nextSort, sortRows, type ContourRow, type SortColumn } from '../../web/src/ui/contourRows';
import { cssColorAt, robustMax } from '../../web/src/viewer/colormap';
import type { FakeElement } from './fakeDom';
import { useFakeDocument } from './panelHarness';
import { runResult } from './runResult';

/** What the CSV button hands the browser: the file's text, name and type. */
const saved = vi.hoisted(() => [] as { data: unknown; name: string; type: string }[]);
vi.mock('../../web/src/io/download', () => ({ download: (data: unknown, name: string, type: string) => saved.push({ data, name, type }) }));

const stats = (mean: number, max: number, count: number, median = mean) => ({ mean, median, p95: max, max, min: 0, count });
// The core's figures null (not finite, as JSON gives them): no figure.
const SPECK: SetAsideEntry = { id: 'sax10', line: 1505, reason: 'speck', perimeter_mm: 2.84, next_id: 's06_SAX', next_perimeter_mm: 210, mean: null, median: null, max: null };
// Held out: the mesh built without it (Patient 1 ED's s07_LAX by the core: 1.831, 1.143, 7.665 mm).
const MINE: SetAsideEntry = { id: 's08_LAX', line: 700, reason: 'by_user', mean: 1.8312, median: 1.143, max: 7.6649 };
const ASIDE: ContourInfo[] = [
  { id: 'sax10', surface: 'LV_ENDO', kind: 'SAX', pieces: [{ closed: true, start: 0, count: 3 }] },
  // The run's geometry of a contour left out may not say its kind: the file's split at load does.
  { id: 's08_LAX', surface: 'LV_ENDO', kind: null, pieces: [{ closed: false, start: 3, count: 40 }] },
];

/** A run of three contours used (a long id among them), a speck the core left out and one the user did. */
function run(extra: Partial<RunResult> = {}): RunResult {
  return runResult({
    perContour: [
      { id: 's02_SAX_LV_ENDOCARDIAL', kind: 'SAX', stats: stats(0.4149, 1.2351, 52, 0.3812) },
      { id: 's06_SAX', kind: 'SAX', stats: stats(0.2, 0.8399, 48) },
      { id: 's07_LAX', kind: 'LAX', stats: stats(0.55, 2.004, 61) },
    ],
    pointDistances: new Float32Array([0.1, 0.5, 0.9, 1.1, 1.9, 2.0]),
    set_aside: [SPECK, MINE],
    set_aside_contours: ASIDE,
    leave_out: ['s08_LAX'],
    ...extra,
  });
}

/** Whether `e` has class `c` (set by its attribute at creation, or toggled since). */
const hasClass = (e: FakeElement, c: string) => (e.attributes.get('class') ?? '').split(' ').includes(c) || e.classList.contains(c);

/** The file order of the surface's contours: the user's one between the used ones, the speck at the end. */
const FILE_ORDER = ['s02_SAX_LV_ENDOCARDIAL', 's06_SAX', 's07_LAX', 's08_LAX', 'sax10'];
/** The file's contours in that order, with the core's split at load (the run gives none for those left out). */
const FILE = FILE_ORDER.map((id) => ({ id, kind: id.includes('LAX') ? ('LAX' as const) : ('SAX' as const) }));

/** The header of the run on screen (the host's `exportInfo`). */
const INFO: ExportInfo = {
  appVersion: '0.1.0', coreVersion: '0.1.0', fileName: 'patient1-ED.csv', surface: 'LV_ENDO', lids: 'auto', params: { iterations: 250 }, leaveOut: ['s08_LAX'],
};

function table(initial: string[] = ['s08_LAX']) {
  const calls: { leftOut: [string, boolean][]; useAll: number; highlight: (string | null)[] } = { leftOut: [], useAll: 0, highlight: [] };
  const state: { key: string; leaveOut: string[]; info: ExportInfo | null } = { key: 'p1|LV_ENDO', leaveOut: [...initial], info: INFO };
  const host: ContourTableHost = {
    context: () => ({ key: state.key, leaveOut: state.leaveOut, fileContours: FILE }),
    setLeftOut: (id, out) => calls.leftOut.push([id, out]),
    useAll: () => calls.useAll++,
    highlight: (id) => calls.highlight.push(id),
    exportInfo: () => state.info,
  };
  const t = new ContourTable(host);
  const el = t.element as unknown as FakeElement;
  const details = el.byTestId('contour-table')!;
  const rows = () => el.findAll((e) => e.dataset.testid === 'contour-row');
  const row = (id: string) => rows().find((r) => r.dataset.id === id)!;
  const box = (id: string) => row(id).byTestId('contour-use') as FakeElement & { checked: boolean; disabled: boolean };
  /** Each cell's text, its parts (the id and the reason under it) joined by " · ". */
  const cells = (id: string) => row(id).findAll((e) => e.tagName === 'td').map((c) => c.children.map((k) => (typeof k === 'string' ? k : k.textContent)).filter((k) => k !== '').join(' · '));
  const ids = () => rows().map((r) => r.dataset.id);
  const header = (label: string) => el.findAll((e) => e.tagName === 'th').find((th) => th.textContent.startsWith(label))!;
  /** Clicks the sort button of the header `label`. */
  const sortBy = (label: string) => header(label).findAll((e) => e.tagName === 'button')[0].fire('click');
  return { t, el, details, rows, row, box, cells, ids, header, sortBy, calls, state };
}

describe('the rows of the Contours panel', () => {
  it('one per contour, used ones with their figures, in the file\'s order', () => {
    const rows = contourRows(run(), FILE);
    expect(rows.map((r) => [r.id, r.kind, r.state, r.line, r.count, r.meanMm, r.medianMm, r.maxMm])).toEqual([
      ['s02_SAX_LV_ENDOCARDIAL', 'SAX', 'used', null, 52, 0.4149, 0.3812, 1.2351],
      ['s06_SAX', 'SAX', 'used', null, 48, 0.2, 0.2, 0.8399],
      ['s07_LAX', 'LAX', 'used', null, 61, 0.55, 0.55, 2.004],
      ['s08_LAX', 'LAX', 'by_user', 700, 40, 1.8312, 1.143, 7.6649],
      ['sax10', 'SAX', 'speck', 1505, 3, null, null, null],
    ]);
    expect(rows[3].reason).toBe('left out by you');
    expect(rows[3].detail).toBe('"s08_LAX" (line 700): left out by you, the mesh 1.83 mm from it on average, 7.66 mm at most (tick it in the Contours panel to use it again)');
    // Figures absent (a result of an older core) or not finite are none.
    // A line 0: not from a file, no line.
    const old = contourRows(run({ set_aside: [{ id: 'sax10', line: 1505, reason: 'stray', gap_mm: 180 }, { ...MINE, line: 0, mean: Number.POSITIVE_INFINITY }] }), FILE);
    expect(old.filter((r) => r.state !== 'used').map((r) => [r.id, r.line, r.meanMm, r.medianMm, r.maxMm])).toEqual([['s08_LAX', null, null, 1.143, 7.6649], ['sax10', 1505, null, null, null]]);
    expect(rows[4].reason).toBe('left out: speck');
    expect(rows[4].detail).toContain('"sax10" (line 1505): a speck');
    // Without the file's order: the core's order, those left out after the used ones (kind unknown).
    expect(contourRows(run()).map((r) => [r.id, r.kind])).toEqual([['s02_SAX_LV_ENDOCARDIAL', 'SAX'], ['s06_SAX', 'SAX'], ['s07_LAX', 'LAX'], ['sax10', 'SAX'], ['s08_LAX', null]]);
    // The swatches' scale is the contour legend's.
    expect(contourScaleMax(run())).toBe(robustMax(new Float32Array([0.1, 0.5, 0.9, 1.1, 1.9, 2.0])));
    expect(contourScaleMax(run())).toBe(2);
  });
});

describe('the sort of the Contours panel\'s rows', () => {
  /** A row with only what the sorts read. */
  const r = (id: string, kind: 'SAX' | 'LAX' | null, count: number, meanMm: number | null, maxMm: number | null): ContourRow => ({ id, kind, state: 'used', count, meanMm, medianMm: meanMm, maxMm, line: null, reason: null, note: null, spikes: 0, far: 0, offPlane: 0, detail: null });
  // Not in any column's order: ids with numbers of one and two digits, a kind unknown, figures missing.
  const ROWS = [r('s10', 'SAX', 30, 0.5, 3), r('s9', 'LAX', 50, null, null), r('s2', null, 10, 2.25, 9), r('a1', 'SAX', 40, 0.1, 1), r('s3', 'LAX', 20, 1, null)];
  const order = (column: SortColumn, descending: boolean) => sortRows(ROWS, { column, descending }).map((x) => x.id);

  it('orders by each column both ways, rows without a value last either way', () => {
    expect(order('mean', true)).toEqual(['s2', 's3', 's10', 'a1', 's9']);
    expect(order('mean', false)).toEqual(['a1', 's10', 's3', 's2', 's9']);
    expect(order('max', true)).toEqual(['s2', 's10', 'a1', 's9', 's3']);
    expect(order('max', false)).toEqual(['a1', 's10', 's2', 's9', 's3']);
    expect(order('count', true)).toEqual(['s9', 'a1', 's10', 's3', 's2']);
    expect(order('count', false)).toEqual(['s2', 's3', 's10', 'a1', 's9']);
    // Ids compare their numbers as numbers: s2, s3, s9, s10.
    expect(order('id', false)).toEqual(['a1', 's2', 's3', 's9', 's10']);
    expect(order('id', true)).toEqual(['s10', 's9', 's3', 's2', 'a1']);
    // Ties keep the file's order; a kind unknown last.
    expect(order('kind', false)).toEqual(['s9', 's3', 's10', 'a1', 's2']);
    expect(order('kind', true)).toEqual(['s10', 'a1', 's9', 's3', 's2']);
    expect(sortRows(ROWS, null).map((x) => x.id)).toEqual(['s10', 's9', 's2', 'a1', 's3']);
    expect(ROWS.map((x) => x.id)).toEqual(['s10', 's9', 's2', 'a1', 's3']);
  });

  it('a click sorts (figures largest first, text A to Z), a second reverses, a third goes back to the file\'s order', () => {
    for (const [column, first] of [['mean', true], ['max', true], ['count', true], ['id', false], ['kind', false]] as const) {
      const one = nextSort(null, column);
      expect(one).toEqual({ column, descending: first });
      const two = nextSort(one, column);
      expect(two).toEqual({ column, descending: !first });
      expect(nextSort(two, column)).toBeNull();
    }
    // Another column starts at its own first order.
    expect(nextSort({ column: 'mean', descending: false }, 'max')).toEqual({ column: 'max', descending: true });
    expect(nextSort({ column: 'max', descending: true }, 'id')).toEqual({ column: 'id', descending: false });
  });
});

describe('the Contours panel', () => {
  useFakeDocument();

  it('shows each contour\'s kind, points and mean / max to two decimals; those left out greyed with why', () => {
    const { t, details, rows, row, box, cells } = table();
    expect(details.dataset.count).toBe('0');
    expect(details.textContent).toContain('no result yet');
    t.show(run());
    expect(details.getAttribute('open')).toBe('');
    expect(details.dataset.count).toBe('5');
    expect(details.findAll((e) => e.tagName === 'h2')[0].textContent).toBe('Contours (5)');
    expect(rows().map((r) => r.dataset.id)).toEqual(FILE_ORDER);
    expect(cells('s02_SAX_LV_ENDOCARDIAL')).toEqual(['', 's02_SAX_LV_ENDOCARDIAL', 'SAX', '52', '0.41', '1.24']);
    expect(cells('s06_SAX')).toEqual(['', 's06_SAX', 'SAX', '48', '0.20', '0.84']);
    expect(cells('s07_LAX')).toEqual(['', 's07_LAX', 'LAX', '61', '0.55', '2.00']);
    expect(row('s07_LAX').dataset.maxMm).toBe('2.004');
    // The long id is cut by the column (CSS): the whole id in the cell's tooltip.
    expect(row('s02_SAX_LV_ENDOCARDIAL').findAll((e) => e.tagName === 'td')[1].title).toBe('s02_SAX_LV_ENDOCARDIAL');
    // The max cell's swatch: its colour on the contour legend (scale 0 to 2 mm).
    const swatch = row('s06_SAX').findAll((e) => e.attributes.get('class') === 'swatch')[0];
    expect(swatch.style.background).toBe(cssColorAt(0.8399, 0, 2));
    expect(swatch.style.background).not.toBe(cssColorAt(2.004, 0, 2));
    // Used: ticked, usable.
    expect([box('s06_SAX').checked, box('s06_SAX').disabled]).toEqual([true, false]);
    // The user's: unticked, usable, greyed, "left out by you".
    expect(row('s08_LAX').dataset.state).toBe('by_user');
    expect([box('s08_LAX').checked, box('s08_LAX').disabled]).toEqual([false, false]);
    expect(hasClass(row('s08_LAX'), 'user-left-out')).toBe(true);
    expect(hasClass(row('s06_SAX'), 'user-left-out')).toBe(false);
    // Its held-out figures, in italics, saying what they are; no swatch (the scale is the contours used').
    expect(cells('s08_LAX')).toEqual(['', 's08_LAX · left out by you', 'LAX', '40', '1.83', '7.66']);
    expect([row('s08_LAX').dataset.meanMm, row('s08_LAX').dataset.maxMm]).toEqual(['1.8312', '7.6649']);
    const held = row('s08_LAX').findAll((e) => e.tagName === 'td').slice(4);
    expect(held.map((c) => [hasClass(c, 'held-out'), c.title])).toEqual([
      [true, `mean ${HELD_OUT_TITLE}`],
      [true, `largest ${HELD_OUT_TITLE}`],
    ]);
    expect(HELD_OUT_TITLE).toContain('distance from this contour to the mesh built without it');
    expect(row('s08_LAX').findAll((e) => hasClass(e, 'swatch'))).toEqual([]);
    expect(row('s07_LAX').findAll((e) => e.tagName === 'td').some((c) => hasClass(c, 'held-out'))).toBe(false);
    // Its tooltip says why and how far, in full.
    expect(row('s08_LAX').findAll((e) => e.tagName === 'td')[1].title).toMatch(/^"s08_LAX" \(line 700\): left out by you, the mesh 1\.83 mm from it on average, 7\.66 mm at most/);
    // The core's: greyed, the reason in its words, the box disabled and saying what uses it.
    expect(row('sax10').dataset.state).toBe('speck');
    expect(hasClass(row('sax10'), 'core-left-out')).toBe(true);
    // Without figures: dashes, no data attributes.
    expect(cells('sax10')).toEqual(['', 'sax10 · left out: speck', 'SAX', '3', '–', '–']);
    expect([row('sax10').dataset.meanMm, row('sax10').dataset.maxMm]).toEqual([undefined, undefined]);
    expect([box('sax10').checked, box('sax10').disabled]).toEqual([false, true]);
    expect(box('sax10').getAttribute('title')).toMatch(/Keep specks and strays/);
    expect(row('sax10').findAll((e) => e.tagName === 'td')[1].title).toMatch(/^"sax10" \(line 1505\): a speck/);
  });

  it('a contour with points left out as spikes (damaged values): used, ticked, the note under its id and the core\'s words in its tooltip', () => {
    const { t, row, box, cells } = table([]);
    const spiked = run({
      perContour: [
        { id: 's02_SAX_LV_ENDOCARDIAL', kind: 'SAX', stats: stats(0.4149, 1.2351, 52, 0.3812), spikes: { points: 1, reach_mm: 58.9953 } },
        { id: 's06_SAX', kind: 'SAX', stats: stats(0.2, 0.8399, 48), spikes: { points: 3, reach_mm: 300 } },
        { id: 's07_LAX', kind: 'LAX', stats: stats(0.55, 2.004, 61) },
      ],
      set_aside: [],
      set_aside_contours: [],
      leave_out: [],
    });
    const rows = contourRows(spiked, FILE);
    expect(rows.map((r) => [r.id, r.state, r.note, r.spikes])).toEqual([
      ['s02_SAX_LV_ENDOCARDIAL', 'used', '1 point left out: spike', 1],
      ['s06_SAX', 'used', '3 points left out: spikes', 3],
      ['s07_LAX', 'used', null, 0],
    ]);
    expect(rows[0].reason).toBeNull();
    expect(rows[0].detail).toBe('"s02_SAX_LV_ENDOCARDIAL": 1 point up to 59.0 mm out of the curve and straight back, left out of the fit (a damaged value?)');
    t.show(spiked);
    expect(cells('s02_SAX_LV_ENDOCARDIAL')).toEqual(['', 's02_SAX_LV_ENDOCARDIAL · 1 point left out: spike', 'SAX', '52', '0.41', '1.24']);
    expect([row('s06_SAX').dataset.spikes, row('s07_LAX').dataset.spikes]).toEqual(['3', undefined]);
    expect([box('s06_SAX').checked, box('s06_SAX').disabled]).toEqual([true, false]);
    expect(hasClass(row('s06_SAX'), 'core-left-out')).toBe(false);
    expect(row('s06_SAX').findAll((e) => e.tagName === 'td')[1].title).toMatch(/^"s06_SAX": 3 points up to 300\.0 mm out of the curve/);
    expect(row('s07_LAX').findAll((e) => e.tagName === 'td')[1].title).toBe('s07_LAX');
  });

  it('a contour with a piece left out as far from its surface: the note under its id (with its spikes\' when both) and the core\'s words', () => {
    const { t, row, cells } = table([]);
    const damaged = run({
      perContour: [
        { id: 's02_SAX_LV_ENDOCARDIAL', kind: 'SAX', stats: stats(0.4149, 1.2351, 52, 0.3812) },
        { id: 's06_SAX', kind: 'SAX', stats: stats(0.2, 0.8399, 48), spikes: { points: 1, reach_mm: 40 }, far: { points: 2, gap_mm: 51.04, span_mm: 96.2 } },
        { id: 's07_LAX', kind: 'LAX', stats: stats(0.55, 2.004, 61), far: { points: 1, gap_mm: 45.94, span_mm: 60 } },
      ],
      set_aside: [],
      set_aside_contours: [],
      leave_out: [],
    });
    const rows = contourRows(damaged, FILE);
    expect(rows.map((r) => [r.id, r.note, r.spikes, r.far])).toEqual([
      ['s02_SAX_LV_ENDOCARDIAL', null, 0, 0],
      ['s06_SAX', '1 point left out: spike · 2 points left out: far off', 1, 2],
      ['s07_LAX', '1 point left out: far off', 0, 1],
    ]);
    expect(rows[2].detail).toBe('"s07_LAX": 1 point 45.9 mm from every other point of its surface, which spans 60 mm, left out of the fit (a damaged value?)');
    expect(rows[1].detail).toBe(
      '"s06_SAX": 1 point up to 40.0 mm out of the curve and straight back, left out of the fit (a damaged value?)\n' +
        '"s06_SAX": 2 points 51.0 mm from every other point of its surface, which spans 96 mm, left out of the fit (a damaged value?)',
    );
    t.show(damaged);
    expect(cells('s07_LAX')).toEqual(['', 's07_LAX · 1 point left out: far off', 'LAX', '61', '0.55', '2.00']);
    expect([row('s07_LAX').dataset.far, row('s06_SAX').dataset.far, row('s06_SAX').dataset.spikes, row('s02_SAX_LV_ENDOCARDIAL').dataset.far]).toEqual(['1', '2', '1', undefined]);
  });

  it('a contour with a piece left out as off its plane: the note under its id, after the others, and the core\'s words', () => {
    const { t, row, cells } = table([]);
    const damaged = run({
      perContour: [
        { id: 's02_SAX_LV_ENDOCARDIAL', kind: 'SAX', stats: stats(0.4149, 1.2351, 52, 0.3812) },
        { id: 's06_SAX', kind: 'SAX', stats: stats(0.2, 0.8399, 48), far: { points: 1, gap_mm: 51.04, span_mm: 96.2 }, off_plane: { points: 2, off_mm: 12.34 } },
        { id: 's07_LAX', kind: 'LAX', stats: stats(0.55, 2.004, 61), off_plane: { points: 1, off_mm: 26.44 } },
      ],
      set_aside: [],
      set_aside_contours: [],
      leave_out: [],
    });
    const rows = contourRows(damaged, FILE);
    expect(rows.map((r) => [r.id, r.note, r.far, r.offPlane])).toEqual([
      ['s02_SAX_LV_ENDOCARDIAL', null, 0, 0],
      ['s06_SAX', '1 point left out: far off · 2 points left out: off its plane', 1, 2],
      ['s07_LAX', '1 point left out: off its plane', 0, 1],
    ]);
    expect(rows[2].detail).toBe('"s07_LAX": 1 point up to 26.4 mm off the plane of the rest of the curve, left out of the fit (a damaged value?)');
    expect(rows[1].detail).toBe(
      '"s06_SAX": 1 point 51.0 mm from every other point of its surface, which spans 96 mm, left out of the fit (a damaged value?)\n' +
        '"s06_SAX": 2 points up to 12.3 mm off the plane of the rest of the curve, left out of the fit (a damaged value?)',
    );
    t.show(damaged);
    expect(cells('s07_LAX')).toEqual(['', 's07_LAX · 1 point left out: off its plane', 'LAX', '61', '0.55', '2.00']);
    expect([row('s07_LAX').dataset.offPlane, row('s06_SAX').dataset.offPlane, row('s06_SAX').dataset.far, row('s02_SAX_LV_ENDOCARDIAL').dataset.offPlane]).toEqual(['1', '2', '1', undefined]);
  });

  it('unticking or ticking a box asks the app; "Use all" shows while any is left out', () => {
    const { t, el, box, calls, state } = table([]);
    t.show(run({ set_aside: [SPECK], leave_out: [] }));
    const useAll = el.byTestId('contour-use-all')!;
    expect(useAll.hidden).toBe(true);
    const b = box('s07_LAX');
    b.checked = false;
    b.fire('change');
    expect(calls.leftOut).toEqual([['s07_LAX', true]]);
    // The app's list now has it: the box follows at once, before the run.
    state.leaveOut = ['s07_LAX'];
    t.leaveOutChanged();
    expect(box('s07_LAX').checked).toBe(false);
    expect(useAll.hidden).toBe(false);
    // It puts back this surface's contours only: the file's one list keeps the others'.
    expect(useAll.getAttribute('title')).toBe("Use every contour of this surface you left out again (one run); those you left out of the file's other surfaces stay out");
    useAll.fire('click');
    expect(calls.useAll).toBe(1);
    const again = box('s07_LAX');
    again.checked = true;
    again.fire('change');
    expect(calls.leftOut.at(-1)).toEqual(['s07_LAX', false]);
  });

  it('a new run of the same surface keeps the rows, stale; another surface or file clears them', () => {
    const { t, details, rows, state } = table();
    t.show(run());
    t.resultCleared();
    expect([details.dataset.stale, details.dataset.count, rows().length]).toEqual(['1', '5', 5]);
    expect(details.textContent).toContain('the figures are of the last finished run');
    t.show(run());
    expect(details.dataset.stale).toBe('0');
    state.key = 'p1|RV_ENDO';
    t.resultCleared();
    expect([details.dataset.stale, details.dataset.count, rows().length]).toEqual(['0', '0', 0]);
    expect(details.textContent).toContain('no result yet');
  });

  it('a row hovered highlights its contour, a click keeps it; the view\'s pointer highlights the row', () => {
    const { t, el, details, row, calls, state } = table();
    t.show(run());
    row('s06_SAX').fire('mouseenter');
    expect(calls.highlight.at(-1)).toBe('s06_SAX');
    expect(details.dataset.highlight).toBe('s06_SAX');
    expect(row('s06_SAX').classList.contains('highlighted')).toBe(true);
    el.fire('mouseleave');
    expect(calls.highlight.at(-1)).toBeNull();
    expect(row('s06_SAX').classList.contains('highlighted')).toBe(false);
    // A click on an id keeps it after the pointer leaves, until another click.
    row('s07_LAX').findAll((e) => e.attributes.get('class') === 'contour-id')[0].fire('click');
    row('s06_SAX').fire('mouseenter');
    el.fire('mouseleave');
    expect(calls.highlight.at(-1)).toBe('s07_LAX');
    expect(row('s07_LAX').classList.contains('pinned')).toBe(true);
    row('s07_LAX').findAll((e) => e.attributes.get('class') === 'contour-id')[0].fire('click');
    el.fire('mouseleave');
    expect(calls.highlight.at(-1)).toBeNull();
    // The 3D view's pointer on a contour point: its row lights up, and goes dark off it.
    t.hoverFromView('s02_SAX_LV_ENDOCARDIAL');
    expect(row('s02_SAX_LV_ENDOCARDIAL').classList.contains('highlighted')).toBe(true);
    t.hoverFromView(null);
    expect(row('s02_SAX_LV_ENDOCARDIAL').classList.contains('highlighted')).toBe(false);
    // A click kept through a new run of the surface; another surface lets it go, in the view too.
    row('s06_SAX').findAll((e) => e.attributes.get('class') === 'contour-id')[0].fire('click');
    const calls0 = calls.highlight.length;
    t.resultCleared();
    t.show(run());
    expect(calls.highlight.length).toBe(calls0);
    expect(details.dataset.highlight).toBe('s06_SAX');
    expect(row('s06_SAX').classList.contains('pinned')).toBe(true);
    state.key = 'p1|RV_ENDO';
    t.resultCleared();
    expect(calls.highlight.at(-1)).toBeNull();
    expect(details.dataset.highlight).toBe('');
  });

  it('a header clicked sorts the rows by its column, with its arrow and aria-sort; a third click gives the file\'s order', () => {
    const { t, ids, header, sortBy } = table();
    t.show(run());
    const sorted = () => ['contour', 'kind', 'pts', 'mean', 'max'].map((l) => [header(l).getAttribute('aria-sort'), header(l).textContent.slice(l.length)]).filter(([a]) => a !== null);
    expect(sorted()).toEqual([]);
    expect(header('max').title).toMatch(/Click to sort, largest first; again: smallest first; a third time: the file's order$/);
    expect(header('contour').title).toMatch(/Click to sort, A to Z; again: Z to A; a third time: the file's order$/);
    // mean: s08_LAX 1.83 (held out), s07_LAX 0.55, s02 0.41, s06 0.20; the speck has no figure: last.
    sortBy('mean');
    expect(ids()).toEqual(['s08_LAX', 's07_LAX', 's02_SAX_LV_ENDOCARDIAL', 's06_SAX', 'sax10']);
    expect(sorted()).toEqual([['descending', '▾']]);
    sortBy('mean');
    expect(ids()).toEqual(['s06_SAX', 's02_SAX_LV_ENDOCARDIAL', 's07_LAX', 's08_LAX', 'sax10']);
    expect(sorted()).toEqual([['ascending', '▴']]);
    sortBy('mean');
    expect(ids()).toEqual(FILE_ORDER);
    expect(sorted()).toEqual([]);
    // max: 7.66, 2.00, 1.24, 0.84, none.
    sortBy('max');
    expect(ids()).toEqual(['s08_LAX', 's07_LAX', 's02_SAX_LV_ENDOCARDIAL', 's06_SAX', 'sax10']);
    sortBy('max');
    expect(ids()).toEqual(['s06_SAX', 's02_SAX_LV_ENDOCARDIAL', 's07_LAX', 's08_LAX', 'sax10']);
    // Another column: its own first order, the arrow moves.
    sortBy('pts');
    expect(ids()).toEqual(['s07_LAX', 's02_SAX_LV_ENDOCARDIAL', 's06_SAX', 's08_LAX', 'sax10']);
    expect(sorted()).toEqual([['descending', '▾']]);
    expect(header('pts').getAttribute('aria-sort')).toBe('descending');
    sortBy('pts');
    expect(ids()).toEqual(['sax10', 's08_LAX', 's06_SAX', 's02_SAX_LV_ENDOCARDIAL', 's07_LAX']);
    sortBy('kind');
    expect(ids()).toEqual(['s07_LAX', 's08_LAX', 's02_SAX_LV_ENDOCARDIAL', 's06_SAX', 'sax10']);
    sortBy('kind');
    expect(ids()).toEqual(['s02_SAX_LV_ENDOCARDIAL', 's06_SAX', 'sax10', 's07_LAX', 's08_LAX']);
    sortBy('contour');
    expect(ids()).toEqual(FILE_ORDER);
    expect(header('contour').getAttribute('aria-sort')).toBe('ascending');
    sortBy('contour');
    expect(ids()).toEqual([...FILE_ORDER].reverse());
    sortBy('contour');
    expect(ids()).toEqual(FILE_ORDER);
    expect(sorted()).toEqual([]);
  });

  it('the sort stays through a new run of the same surface and goes with another; the boxes, the hover and the stale mark work sorted', () => {
    const { t, el, details, row, box, ids, header, sortBy, calls, state } = table();
    const BY_MAX = ['s08_LAX', 's07_LAX', 's02_SAX_LV_ENDOCARDIAL', 's06_SAX', 'sax10'];
    t.show(run());
    sortBy('max');
    row('s06_SAX').findAll((e) => e.attributes.get('class') === 'contour-id')[0].fire('click');
    // A run starts: stale, still sorted; a click on a header sorts the stale rows, still stale.
    t.resultCleared();
    expect([details.dataset.stale, ids()]).toEqual(['1', BY_MAX]);
    sortBy('max');
    expect([details.dataset.stale, ids()]).toEqual(['1', [...BY_MAX.slice(0, 4)].reverse().concat('sax10')]);
    sortBy('max');
    sortBy('max');
    expect(ids()).toEqual(BY_MAX);
    // The new run: its figures, in the same sort (s02's max now the largest of those used).
    t.show(run({ perContour: [
      { id: 's02_SAX_LV_ENDOCARDIAL', kind: 'SAX', stats: stats(0.4149, 3.5, 52) },
      { id: 's06_SAX', kind: 'SAX', stats: stats(0.2, 0.8399, 48) },
      { id: 's07_LAX', kind: 'LAX', stats: stats(0.55, 2.004, 61) },
    ] }));
    expect(details.dataset.stale).toBe('0');
    expect(ids()).toEqual(['s08_LAX', 's02_SAX_LV_ENDOCARDIAL', 's07_LAX', 's06_SAX', 'sax10']);
    expect(header('max').getAttribute('aria-sort')).toBe('descending');
    // Sorted, the click kept its row, the hover and the boxes reach the right contour.
    expect(row('s06_SAX').classList.contains('pinned')).toBe(true);
    row('s07_LAX').fire('mouseenter');
    expect([calls.highlight.at(-1), details.dataset.highlight, row('s07_LAX').classList.contains('highlighted')]).toEqual(['s07_LAX', 's07_LAX', true]);
    el.fire('mouseleave');
    t.hoverFromView('s02_SAX_LV_ENDOCARDIAL');
    expect(row('s02_SAX_LV_ENDOCARDIAL').classList.contains('highlighted')).toBe(true);
    const b = box('s07_LAX');
    b.checked = false;
    b.fire('change');
    expect(calls.leftOut.at(-1)).toEqual(['s07_LAX', true]);
    state.leaveOut = ['s08_LAX', 's07_LAX'];
    t.leaveOutChanged();
    expect([box('s07_LAX').checked, box('s08_LAX').checked, box('s06_SAX').checked]).toEqual([false, false, true]);
    expect(ids()[0]).toBe('s08_LAX');
    // Another surface: rows and sort go; its first rows in the file's order.
    state.key = 'p1|RV_ENDO';
    t.resultCleared();
    t.show(run());
    expect(ids()).toEqual(FILE_ORDER);
    expect(header('max').getAttribute('aria-sort')).toBeNull();
    // A run of another surface shown without a clear in between lets the sort go too.
    sortBy('mean');
    state.key = 'p1|LV_EPI';
    t.show(run());
    expect(ids()).toEqual(FILE_ORDER);
  });

  it('the CSV button: enabled while there are rows; saves them in the order shown, under the header of the run they are of', () => {
    const { t, el, details, sortBy, state } = table();
    const csv = el.byTestId('contour-csv') as FakeElement & { disabled: boolean };
    expect([csv.textContent, csv.title]).toEqual(['CSV', 'The table as CSV: one row per contour, distances in mm']);
    // Beside the heading: in the summary, after "Use all".
    expect(details.findAll((e) => e.tagName === 'summary')[0].findAll((e) => e.tagName === 'button').map((b) => b.dataset.testid)).toEqual(['contour-use-all', 'contour-csv']);
    expect(csv.disabled).toBe(true);
    t.show(run());
    expect(csv.disabled).toBe(false);
    sortBy('max');
    // A new run starts (other parameters, another list): the rows stay, stale, and so does the header of their run.
    state.info = { ...INFO, params: { iterations: 300 }, leaveOut: ['s08_LAX', 's07_LAX'] };
    t.resultCleared();
    expect(csv.disabled).toBe(false);
    saved.length = 0;
    csv.fire('click');
    expect(saved.map((f) => [f.name, f.type])).toEqual([['patient1-ED-LV_ENDO-contours.csv', 'text/csv']]);
    expect(String(saved[0].data).split('\n')).toEqual([
      '# heartmesh 0.1.0 (core 0.1.0), units: mm',
      '# input: patient1-ED.csv surface: LV_ENDO',
      '# lids: auto iterations=250 leave_out=s08_LAX',
      'contour,kind,state,line,points,mean_mm,median_mm,max_mm,spike_points,far_points,off_plane_points',
      's08_LAX,LAX,by_user,700,40,1.8312,1.1430,7.6649,0,0,0',
      's07_LAX,LAX,used,,61,0.5500,0.5500,2.0040,0,0,0',
      's02_SAX_LV_ENDOCARDIAL,SAX,used,,52,0.4149,0.3812,1.2351,0,0,0',
      's06_SAX,SAX,used,,48,0.2000,0.2000,0.8399,0,0,0',
      'sax10,SAX,speck,1505,3,,,,0,0,0',
      '',
    ]);
    // No rows (a run without contours), no header known, or another surface's clear: nothing to save.
    t.show(run({ perContour: [], set_aside: [], set_aside_contours: [] }));
    expect([details.dataset.count, csv.disabled]).toEqual(['0', true]);
    state.info = null;
    t.show(run());
    expect(csv.disabled).toBe(true);
    csv.fire('click');
    expect(saved.length).toBe(1);
    state.info = INFO;
    t.show(run());
    expect(csv.disabled).toBe(false);
    state.key = 'p1|RV_ENDO';
    t.resultCleared();
    expect(csv.disabled).toBe(true);
  });
});
