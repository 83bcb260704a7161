// The anatomical mesh in the Export panel: the pure parts (the layout typed, checked against the
// core's ranges; the file name after the surface exports'; the header; the figures line; the core's
// refusal as a sentence, and which failures are refusals; the grid's edges for the view), then the
// row on the fake DOM: greyed before a run; once a run finishes it asks the core about the smallest
// layout and, refused, shows the core's reason with no Save, or, accepted, Save builds the layout
// typed in the format chosen, downloads `<file>-<surface>-anatomical-<R>x<K>.<ext>` and fills the
// figures, which a layout edit or a new run takes away; a probe of a run since replaced is ignored;
// a worker restarted under the probe does not grey the row; View draws the grid and a new run takes
// it away.
import { describe, expect, it, vi } from 'vitest';
import type { AnatomicalFormat, AnatomicalSummary } from '../../web/src/core-client/protocol';
import { DEFAULT_OPTIONS } from '../../web/src/core-client/protocol';
import {
  ANATOMICAL_DEFAULT, PROBE_LAYOUT, anatomicalErrorText, anatomicalFigures, anatomicalFiguresText, anatomicalFileName, anatomicalHeaderLines,
  anatomicalReason, checkLayout, isRefusal, layoutVertices, type AnatomicalLayout,
} from '../../web/src/io/export/anatomical';
import { headerLines, type ExportInfo } from '../../web/src/io/export/header';
import type { BuiltAnatomical } from '../../web/src/io/AnatomicalRow';
import { uniqueEdges } from '../../web/src/viewer/AnatomicalGridLayer';
import type { FakeElement } from './fakeDom';
import { exportSource, useFakeDocument } from './panelHarness';

const saved: string[] = [];
vi.mock('../../web/src/io/download', () => ({ download: (_data: unknown, name: string) => saved.push(name) }));
const { ExportPanel } = await import('../../web/src/io/ExportPanel');

const info: ExportInfo = {
  appVersion: '0.1.0', coreVersion: '0.1.0', fileName: 'patient1-ED.csv', surface: 'LV_ENDO', frame: null,
  lids: 'auto', options: { ...DEFAULT_OPTIONS }, params: { iterations: 250 },
};

/** `heartmesh reconstruct patient1-ED.csv --surface LV_ENDO --anatomical-mesh` (the report's figures). */
const SUMMARY: AnatomicalSummary = {
  rings: 24, points: 48, vertices: 1154, triangles: 2304, septum_from: 'the RV contours\' centre (934)',
  septum_direction: [-0.848, -0.508, -0.148], anterior_direction: [0.224, -0.599, 0.769], axis: [-0.480, 0.619, 0.622], apex: [42.34, -20.19, -87.68],
  length_mm: 73.50647109663936, volume_ml: 134.35859976816852, surface_volume_ml: 135.00739402826656, to_surface_mean_mm: 0.07740337546076934, to_surface_max_mm: 0.9643279295855345,
};
const REFUSED = 'the anatomical mesh: the anatomical layout is the LV\'s (LV_ENDO, LV_EPI); RV_ENDO has no centre for its rays';

describe('the anatomical layout typed', () => {
  it('takes whole numbers in the core\'s ranges (2-200 rings, 8-720 points), spaces around them', () => {
    expect(checkLayout('24', '48')).toEqual({ ok: true, layout: { rings: 24, points: 48 } });
    expect(checkLayout(' 10 ', '16')).toEqual({ ok: true, layout: { rings: 10, points: 16 } });
    expect(checkLayout('2', '8')).toEqual({ ok: true, layout: PROBE_LAYOUT });
    expect(checkLayout('200', '720')).toEqual({ ok: true, layout: { rings: 200, points: 720 } });
  });

  it('says which number is wrong and the range it must be in', () => {
    expect(checkLayout('1', '48')).toEqual({ ok: false, message: 'Rings: a whole number from 2 to 200' });
    expect(checkLayout('201', '48')).toEqual({ ok: false, message: 'Rings: a whole number from 2 to 200' });
    expect(checkLayout('24', '7')).toEqual({ ok: false, message: 'Points per ring: a whole number from 8 to 720' });
    expect(checkLayout('24', '721')).toEqual({ ok: false, message: 'Points per ring: a whole number from 8 to 720' });
    for (const bad of ['', '2.5', '1e2', '-24', '24x', 'abc', '0x10']) expect(checkLayout(bad, '48').ok, JSON.stringify(bad)).toBe(false);
    expect(checkLayout('', '')).toEqual({ ok: false, message: 'Rings: a whole number from 2 to 200; Points per ring: a whole number from 8 to 720' });
  });

  it('counts the apex, the rings and the base lid\'s centre', () => {
    expect(layoutVertices(ANATOMICAL_DEFAULT)).toBe(1154);
    expect(layoutVertices({ rings: 10, points: 16 })).toBe(162);
  });
});

describe('the anatomical mesh file and figures', () => {
  it('is named after the surface exports, the layout after it', () => {
    expect(anatomicalFileName(info, { rings: 24, points: 48 }, 'vtk')).toBe('patient1-ED-LV_ENDO-anatomical-24x48.vtk');
    expect(anatomicalFileName({ ...info, fileName: 'GPFile_000.txt', surface: 'LV_EPI', frame: '9' }, { rings: 10, points: 16 }, 'vtp')).toBe('GPFile_000-LV_EPI-frame9-anatomical-10x16.vtp');
    expect(anatomicalFileName({ ...info, fileName: 'seg a.nii.gz' }, { rings: 3, points: 8 }, 'obj')).toBe('seg_a-LV_ENDO-anatomical-3x8.obj');
  });

  it('carries the exports\' header lines after the command line\'s comment', () => {
    expect(anatomicalHeaderLines(info)).toEqual(headerLines(info));
    expect(anatomicalHeaderLines(info)[1]).toBe('input: patient1-ED.csv surface: LV_ENDO');
  });

  it('says the vertices, the volume, the distance to the surface and where the septum came from', () => {
    expect(anatomicalFigures(SUMMARY)).toEqual({
      figures: ['1154 vertices', '134.4 ml', 'to the surface 0.08 mm mean, 1.0 mm max'],
      septum: 'Septum from the RV contours\' centre (934)',
    });
    expect(anatomicalFiguresText({ ...SUMMARY, vertices: 162, volume_ml: 130.06, to_surface_mean_mm: 0.52, to_surface_max_mm: 2.94 })).toBe(
      '162 vertices · 130.1 ml · to the surface 0.5 mm mean, 2.9 mm max. Septum from the RV contours\' centre (934)',
    );
  });

  it('gives the core\'s reason in its words, without the prefixes the row already says', () => {
    expect(anatomicalReason(REFUSED)).toBe('The anatomical layout is the LV\'s (LV_ENDO, LV_EPI); RV_ENDO has no centre for its rays');
    expect(anatomicalReason('the anatomical mesh: the anatomical layout starts at the septum, and the file has no RV_INSERT landmarks and no RV contours to place it by'))
      .toBe('The anatomical layout starts at the septum, and the file has no RV_INSERT landmarks and no RV contours to place it by');
    expect(anatomicalErrorText('the anatomical mesh: invalid parameter layout: the anatomical layout must have 2-200 rings of 8-720 points (got 1x48)'))
      .toBe('⚠ The anatomical mesh could not be built: Invalid parameter layout: the anatomical layout must have 2-200 rings of 8-720 points (got 1x48)');
  });

  it('takes only the core\'s answers for refusals, not a worker restarted or a file not loaded', () => {
    expect(isRefusal({ code: 'degenerate', message: REFUSED })).toBe(true);
    expect(isRefusal({ code: 'anatomical_unavailable', message: 'this core cannot build the anatomical mesh' })).toBe(true);
    expect(isRefusal({ code: 'worker_crashed', message: 'the worker crashed earlier' })).toBe(false);
    expect(isRefusal({ code: 'not_loaded', message: 'p1.csv has not been loaded' })).toBe(false);
  });

  it('draws each edge of the triangles once', () => {
    // A tetrahedron: 4 triangles, 6 edges.
    const edges = uniqueEdges([0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, 2]);
    expect(edges).toHaveLength(12);
    const pairs = new Set(Array.from({ length: 6 }, (_, i) => [edges[2 * i], edges[2 * i + 1]].sort().join(',')));
    expect([...pairs].sort()).toEqual(['0,1', '0,2', '0,3', '1,2', '1,3', '2,3']);
  });
});

type Control = FakeElement & { disabled: boolean; value: string };

/** The panel with a recording anatomical source: each build asked for, each grid shown and each hide. */
function panel(answer: (layout: AnatomicalLayout, format: AnatomicalFormat, header: boolean) => Promise<BuiltAnatomical> | null = () => Promise.resolve({ summary: SUMMARY, bytes: new Uint8Array([1]) })) {
  const asked: string[] = [];
  const shown: BuiltAnatomical[] = [];
  const failed: unknown[] = [];
  let hides = 0;
  const p = new ExportPanel(
    exportSource(info, {
      anatomicalFile: (layout, format, header) => (asked.push(`${layout.rings}x${layout.points}:${format}${header ? '+header' : ''}`), answer(layout, format, header)),
      showAnatomical: (b) => void shown.push(b),
      hideAnatomical: () => void hides++,
      failed: (e) => void failed.push(e),
    }),
  );
  const root = p.element as unknown as FakeElement;
  const get = (testid: string) => root.byTestId(testid) as Control;
  return {
    p, asked, shown, failed,
    hides: () => hides,
    row: get('anatomical-export'), save: get('export-anatomical'), view: get('view-anatomical'), rings: get('anatomical-rings'), points: get('anatomical-points'),
    format: get('anatomical-format'), reason: get('anatomical-reason'), figures: get('anatomical-figures'), layoutError: get('anatomical-layout-error'),
    type(input: Control, value: string) {
      input.value = value;
      input.fire('input');
    },
  };
}
const settle = () => new Promise((r) => setTimeout(r, 0));

describe('the anatomical mesh row', () => {
  useFakeDocument();

  it('is greyed before a run finishes, and asks the core nothing', () => {
    const t = panel();
    expect(t.row.dataset.state).toBe('none');
    expect([t.save.disabled, t.view.disabled, t.rings.disabled]).toEqual([true, true, true]);
    expect(t.row.title).toMatch(/once a surface's run has finished$/);
    expect([t.rings.value, t.points.value, t.format.value]).toEqual(['24', '48', 'vtk']);
    t.p.setAnatomical(null);
    expect(t.asked).toEqual([]);
  });

  it('a finished run: the smallest layout asked for once; accepted, Save builds the layout typed, saves it, fills the figures', async () => {
    const t = panel();
    t.p.setAnatomical('run-1');
    t.p.setAnatomical('run-1');
    expect(t.asked).toEqual(['2x8:obj']);
    expect(t.row.dataset.state).toBe('checking');
    expect(t.save.disabled).toBe(true);
    await settle();
    expect(t.row.dataset.state).toBe('ready');
    expect(t.save.disabled).toBe(false);
    expect(t.reason.hidden).toBe(true);
    expect(t.save.title).toMatch(/^Save 1154 vertices as VTK: /);

    t.type(t.rings, '10');
    t.type(t.points, '16');
    t.format.value = 'ply';
    t.format.fire('change');
    saved.length = 0;
    t.save.fire('click');
    expect(t.figures.dataset.state).toBe('busy');
    await settle();
    expect(t.asked.at(-1)).toBe('10x16:ply+header');
    expect(saved).toEqual(['patient1-ED-LV_ENDO-anatomical-10x16.ply']);
    expect(t.figures.dataset.state).toBe('done');
    expect(t.figures.textContent).toBe('1154 vertices · 134.4 ml · to the surface 0.08 mm mean, 1.0 mm max. Septum from the RV contours\' centre (934)');
    expect(t.figures.dataset.vertices).toBe('1154');
    expect(t.figures.title).toMatch(/^24 rings of 48 from the apex to the base plane: 1154 vertices/);

    // Another layout typed: the figures (of the last one) go; a new run: they go too, and it is asked about.
    t.type(t.points, '17');
    expect(t.figures.hidden).toBe(true);
    t.save.fire('click');
    await settle();
    expect(t.figures.hidden).toBe(false);
    t.p.setAnatomical('run-2');
    expect(t.figures.hidden).toBe(true);
    expect(t.asked.at(-1)).toBe('2x8:obj');
  });

  it('a layout out of range: no Save, the range said; no call', async () => {
    const t = panel();
    t.p.setAnatomical('run-1');
    await settle();
    t.type(t.rings, '1');
    expect(t.save.disabled).toBe(true);
    expect(t.view.disabled).toBe(true);
    expect(t.layoutError.hidden).toBe(false);
    expect(t.layoutError.textContent).toBe('Rings: a whole number from 2 to 200');
    t.save.fire('click');
    await settle();
    expect(t.asked).toEqual(['2x8:obj']);
    t.type(t.rings, '2');
    expect([t.save.disabled, t.layoutError.hidden]).toEqual([false, true]);
  });

  it('refused: the core\'s reason greyed in place of the form, no Save, no View, no banner', async () => {
    const t = panel(() => Promise.reject({ code: 'degenerate', message: REFUSED }));
    t.p.setAnatomical('run-rv');
    await settle();
    expect(t.row.dataset.state).toBe('refused');
    expect(t.reason.hidden).toBe(false);
    expect(t.reason.textContent).toBe('The anatomical layout is the LV\'s (LV_ENDO, LV_EPI); RV_ENDO has no centre for its rays');
    expect(t.row.title).toBe(t.reason.textContent);
    expect(t.save.parentElement?.hidden).toBe(true);
    expect(t.view.hidden).toBe(true);
    expect(t.failed).toEqual([]);
  });

  it('a probe answered after its run was replaced is ignored; a worker restarted under it does not grey the row', async () => {
    let reject: (e: unknown) => void = () => undefined;
    let calls = 0;
    const t = panel(() => (++calls === 1 ? new Promise((_, r) => (reject = r)) : Promise.reject({ code: 'worker_crashed', message: 'the worker crashed' })));
    t.p.setAnatomical('run-rv');
    t.p.setAnatomical('run-lv');
    reject({ code: 'degenerate', message: REFUSED });
    await settle();
    expect(t.row.dataset.state).toBe('ready');
    expect(t.reason.hidden).toBe(true);
  });

  it('a Save the core refuses says why on the figures line and the banner; the row stays usable', async () => {
    let n = 0;
    const t = panel(() => (n++ === 0 ? Promise.resolve({ summary: SUMMARY, bytes: new Uint8Array(0) }) : Promise.reject({ code: 'degenerate', message: 'the anatomical mesh: the surface has no part below its base plane' })));
    t.p.setAnatomical('run-1');
    await settle();
    t.save.fire('click');
    await settle();
    expect(t.figures.dataset.state).toBe('error');
    expect(t.figures.textContent).toBe('⚠ The anatomical mesh could not be built: The surface has no part below its base plane');
    expect(t.failed).toHaveLength(1);
    expect(t.save.disabled).toBe(false);
  });

  it('View draws the grid built as PLY; pressed again, a layout edit or a new run takes it away', async () => {
    const t = panel();
    t.p.setAnatomical('run-1');
    await settle();
    t.view.fire('click');
    await settle();
    expect(t.asked.at(-1)).toBe('24x48:ply+header');
    expect(t.shown).toHaveLength(1);
    expect(t.view.getAttribute('aria-pressed')).toBe('true');
    expect(t.figures.dataset.state).toBe('done');
    t.view.fire('click');
    expect([t.hides(), t.view.getAttribute('aria-pressed')]).toEqual([1, 'false']);
    t.view.fire('click');
    await settle();
    t.type(t.points, '16');
    expect(t.hides()).toBe(2);
    t.view.fire('click');
    await settle();
    t.p.setAnatomical(null);
    expect(t.hides()).toBe(3);
    expect(t.row.dataset.state).toBe('none');
  });
});
