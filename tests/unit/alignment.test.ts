// Breath-hold alignment in the app (session 9): the option's plumbing (params JSON, URL, exports),
// the result panel's numbers, the status line's "converged" wording, and the scene helpers. The
// real core's alignment is exercised end to end in tests/e2e/align.test.mjs.
import { describe, expect, it } from 'vitest';
import { DEFAULT_OPTIONS, paramsJson, withDefaultOptions, type Alignment, type RunResult } from '../../web/src/core-client/protocol';
import { convergence } from '../../web/src/core-client/workerCore';
import { parseUrlState, serializeUrlState } from '../../web/src/app/urlState';
import { keptText } from '../../web/src/app/errors';
import { surfacePoints } from '../../web/src/app/sceneContours';
import { headerLines, type ExportInfo } from '../../web/src/io/export/header';
import { runSummary, writeParamsJson } from '../../web/src/io/export/json';
import { alignmentRows, iterationText, iterationsDoneText, pastDataText, residualText, stepText } from '../../web/src/ui/runText';
import { ResultPanel } from '../../web/src/ui/ResultPanel';
import { givenSegments } from '../../web/src/viewer/GivenContourLayer';
import { type FakeElement, dlRows } from './fakeDom';
import { useFakeDocument } from './panelHarness';
import { stepReport } from './core-client/fakes';
import { rustSchema } from './rustSchema';
import { DEFAULT_END_CAPS } from '../../web/src/core-client/protocol';
import { runResult } from './runResult';

const ALIGNMENT: Alignment = {
  rounds: 17,
  residual_before_mm: 2.345,
  residual_after_mm: 0.612,
  groups: [
    { kind: 'SAX', label: 'SAX 1', contour_ids: ['s1_endo', 's1_epi'], shift_mm: [0.3, 0.4, 0] },
    { kind: 'LAX', label: '4ch', contour_ids: ['4ch_endo'], shift_mm: [0, 1.2, -1.6] },
    { kind: 'SAX', label: 'SAX 2', contour_ids: ['s2_endo'], shift_mm: [-1.2, 0, 0.9], through_plane_mm: -0.85 },
  ],
};

const result = (extra: Partial<RunResult> = {}): RunResult =>
  runResult({ overall: { mean: 0.321, median: 0.25, p95: 0.8, max: 1.234, min: 0, count: 42 }, ...extra });

describe('align_slices option', () => {
  it('is off by default and travels in the params JSON, the URL and every export', () => {
    expect(DEFAULT_OPTIONS.align_slices).toBe(false);
    const on = { ...DEFAULT_OPTIONS, align_slices: true, end_caps: DEFAULT_END_CAPS, keep_specks: false };
    expect(JSON.parse(paramsJson({ beta: 0.1 }, on))).toEqual({ beta: 0.1, smoothing_method: 'laplacian-affine', soften_conflicts: true, align_slices: true, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true, drop_second_loops: false });
    // Options saved before the option existed read as off.
    expect(withDefaultOptions({ smoothing_method: 'taubin', soften_conflicts: false })).toEqual({ smoothing_method: 'taubin', soften_conflicts: false, align_slices: false, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true, drop_second_loops: false });
    expect(withDefaultOptions(null)).toEqual(DEFAULT_OPTIONS);

    const schema = rustSchema();
    const s = parseUrlState('', schema);
    expect(s.options.align_slices).toBe(false);
    s.options = on;
    expect(serializeUrlState(s, schema)).toBe('?align_slices=1');
    expect(parseUrlState('?align_slices=1', schema).options.align_slices).toBe(true);
    expect(parseUrlState('?align_slices=true', schema).options.align_slices).toBe(true);
    expect(parseUrlState('?align_slices=maybe', schema).options.align_slices).toBe(false);

    const info: ExportInfo = { appVersion: '1.0.0', coreVersion: '0.1.0', fileName: 'p.csv', surface: 'LV_ENDO', lids: 'auto', options: on, params: { iterations: 250 } };
    expect(headerLines(info)[2]).toBe(`lids: auto iterations=250 smoothing_method=laplacian-affine soften_conflicts=true align_slices=true end_caps=${DEFAULT_END_CAPS} keep_specks=false apex_floor=true`);
    expect(headerLines({ ...info, options: { smoothing_method: 'taubin', soften_conflicts: true } as never })[2]).toMatch(new RegExp(`align_slices=false end_caps=${DEFAULT_END_CAPS} keep_specks=false apex_floor=true$`));
    const doc = JSON.parse(writeParamsJson(info, runSummary(result({ alignment: ALIGNMENT, contour_to_mesh_as_given: { mean: 0.71, median: 0.6, max: 2.5 }, iterations_done: 243, converged: true }))));
    expect(doc.align_slices).toBe(true);
    expect(doc.result.iterations).toBe(243);
    expect(doc.result.converged).toBe(true);
    expect(doc.result.contourToMeshMm.mean).toBe(0.321);
    expect(doc.result.contourToMeshAsGivenMm).toEqual({ mean: 0.71, median: 0.6, max: 2.5 });
    expect(doc.result.alignment.groups[1].shift_mm).toEqual([0, 1.2, -1.6]);
    const off = JSON.parse(writeParamsJson({ ...info, options: DEFAULT_OPTIONS }, runSummary(result({ iterations_done: 250, converged: false }))));
    expect(off.align_slices).toBe(false);
    expect(off.result.alignment).toBeNull();
    expect(off.result.contourToMeshAsGivenMm).toBeUndefined();
  });
});

describe('converged runs', () => {
  it('say where they converged in the status line and the result', () => {
    expect(iterationText({ iteration: 120, total_iterations: 250, done: false })).toBe('iteration 120 / 250');
    expect(iterationText({ iteration: 243, total_iterations: 250, done: true })).toBe('converged at iteration 243 (of 250)');
    expect(iterationText({ iteration: 250, total_iterations: 250, done: true })).toBe('iteration 250 / 250');
    expect(stepText(stepReport(243, { total_iterations: 250, done: true, max_distance_mm: 0.0314, mean_distance_mm: 0.012 }))).toBe(
      'converged at iteration 243 (of 250) · deform · max 0.03 mm · mean 0.01 mm · 3 vertices',
    );
    expect(convergence(stepReport(243, { total_iterations: 250, done: true }))).toEqual({ iterations_done: 243, converged: true });
    expect(convergence(stepReport(250, { total_iterations: 250, done: true }))).toEqual({ iterations_done: 250, converged: false });
    expect(convergence(null)).toEqual({});
    expect(iterationsDoneText(243, 250, true)).toBe('243 (converged)');
    expect(iterationsDoneText(250, 250, false)).toBe('250');
  });
});

describe('result panel', () => {
  useFakeDocument();

  const rows = dlRows;

  it('shows the alignment: residual before -> after, as-given distance, groups largest shift first', () => {
    const panel = new ResultPanel();
    const el = panel.element as unknown as FakeElement;
    panel.show(result({ alignment: ALIGNMENT, contour_to_mesh_as_given: { mean: 0.7125, median: 0.6, max: 2.5 }, iterations_done: 243, converged: true }));
    const r = rows(el);
    expect(r['Contour→mesh mean']).toBe('0.321 mm');
    expect(r['as given: mean']).toBe('0.713 mm');
    expect(r['as given: max']).toBe('2.500 mm');
    expect(r['Iterations']).toBe('243 (converged)');
    expect(el.byTestId('result-iterations')?.title).toBe('the attractors were reached (stop threshold) before the last iteration (250)');
    expect(el.dataset).toMatchObject({ residualBeforeMm: '2.345', residualAfterMm: '0.612', givenMeanMm: '0.7125', iterations: '243', converged: '1', meanMm: '0.321' });
    const box = el.byTestId('result-alignment')!;
    expect(box.hidden).toBe(false);
    expect(el.byTestId('result-residual')?.textContent).toBe('2.35 → 0.61 mm (17 rounds)');
    const table = el.byTestId('alignment-groups')!;
    const body = table.findAll((e) => e.tagName === 'tr').slice(1).map((tr) => (tr.children as FakeElement[]).map((td) => td.textContent));
    // |(0,1.2,-1.6)| = 2.0, |(-1.2,0,0.9)| = 1.5, |(0.3,0.4,0)| = 0.5
    expect(body).toEqual([['4ch', 'LAX', '2.00'], ['SAX 2', 'SAX', '1.50'], ['SAX 1', 'SAX', '0.50']]);
    expect(table.findAll((e) => e.tagName === 'tr')[3].title).toBe('SAX 1 (SAX: s1_endo, s1_epi): moved by (0.30, 0.40, 0.00) mm in its own plane (scanner coordinates)');
    // A slice that also moved along its normal says how much of the shift that was.
    expect(table.findAll((e) => e.tagName === 'tr')[2].title).toBe('SAX 2 (SAX: s2_endo): moved by (-1.20, 0.00, 0.90) mm (scanner coordinates), −0.8 mm of it along the long axis');

    // A run without alignment: no alignment box, no as-given rows, and a clear() forgets the numbers.
    panel.show(result({ iterations_done: 250, converged: false }));
    expect(box.hidden).toBe(true);
    expect(rows(el)['as given: mean']).toBeUndefined();
    expect(el.dataset.residualBeforeMm).toBeUndefined();
    expect(el.dataset.converged).toBe('0');
    panel.show(result({ alignment: ALIGNMENT, contour_to_mesh_as_given: { mean: 0.7, median: 0.6, max: 2.5 } }));
    panel.clear('running…');
    expect(el.dataset.residualAfterMm).toBeUndefined();
    expect(el.dataset.givenMeanMm).toBeUndefined();
    expect(box.hidden).toBe(true);
  });

  it('says how far apart the images cross (the crossing gap), and suggests the alignment when they disagree', () => {
    let aligned = 0;
    const panel = new ResultPanel(() => aligned++);
    const el = panel.element as unknown as FakeElement;
    panel.show(result({ crossing_residual_mm: 1.8771, suggest_alignment: true }));
    // The figure, then a one-click "align" that ticks the option (here: counts the calls).
    expect(rows(el)['Crossing gap']).toBe('1.88 mm align');
    el.byTestId('result-align-suggest')?.fire('click');
    expect(aligned).toBe(1);
    const cell = el.byTestId('result-crossing');
    expect(cell?.getAttribute('class')).toBe('warn');
    expect(cell?.title).toMatch(/Align breath-holds/);
    expect(el.dataset).toMatchObject({ crossingResidualMm: '1.8771', suggestAlignment: '1' });
    // Consistent contours: the figure, no warning, no hint.
    panel.show(result({ crossing_residual_mm: 0.011, suggest_alignment: false }));
    expect(rows(el)['Crossing gap']).toBe('0.01 mm');
    expect(el.byTestId('result-crossing')?.getAttribute('class')).toBeNull();
    expect(el.byTestId('result-crossing')?.title).not.toMatch(/Align breath-holds/);
    expect(el.dataset.suggestAlignment).toBe('0');
    expect(el.byTestId('result-align-suggest')).toBeUndefined();
    // With the alignment on, its own box shows the residual before -> after instead; no crossings: no row.
    panel.show(result({ crossing_residual_mm: 1.8771, suggest_alignment: false, alignment: ALIGNMENT }));
    expect(rows(el)['Crossing gap']).toBeUndefined();
    expect(el.dataset.crossingResidualMm).toBeUndefined();
    panel.show(result({ crossing_residual_mm: null }));
    expect(rows(el)['Crossing gap']).toBeUndefined();
  });

  it('says how far the mesh runs past the data, and flags an extrapolated end', () => {
    const panel = new ResultPanel();
    const el = panel.element as unknown as FakeElement;
    panel.show(result({ pastData: { base_mm: 14.3032, apex_mm: 0.0838 } }));
    expect(rows(el)['Past the data']).toBe('+14.3 / +0.1 mm');
    expect(el.byTestId('result-past-data')?.getAttribute('class')).toBe('warn');
    expect(el.byTestId('result-past-data')?.title).toMatch(/^base \/ apex/);
    expect(el.byTestId('result-past-data')?.title).toMatch(/extrapolated/);
    expect(el.dataset).toMatchObject({ pastBaseMm: '14.3032', pastApexMm: '0.0838' });
    // Ends within 5 mm of the data (the lid rounds a little past closing curves): no warning sign.
    panel.show(result({ pastData: { base_mm: 2.26, apex_mm: 0.24 } }));
    expect(el.byTestId('result-past-data')?.getAttribute('class')).toBeNull();
    expect(pastDataText({ base_mm: 1.2, apex_mm: -0.44 })).toEqual({ text: '+1.2 / −0.4 mm', extrapolated: false, modelled: false, ceiling: false });
    expect(pastDataText({ base_mm: 2.3, apex_mm: 5.01 }).extrapolated).toBe(true);
    expect(pastDataText({ base_mm: 4.9, apex_mm: 0 }).extrapolated).toBe(false);
    // Within 0.05 mm of the data is no overrun either way: no sign (was "−0.0 / +1.7 mm" on patient 2 ES).
    expect(pastDataText({ base_mm: -0.04, apex_mm: 1.7 }).text).toBe('0.0 / +1.7 mm');
    expect(pastDataText({ base_mm: 0.049, apex_mm: -0.05 }).text).toBe('0.0 / −0.1 mm');
    // Older cores send no figure: no row, no stale attributes.
    panel.show(result());
    expect(rows(el)['Past the data']).toBeUndefined();
    expect(el.dataset.pastBaseMm).toBeUndefined();
  });

  it('shows why nothing moved (no long-axis view) and no table', () => {
    const panel = new ResultPanel();
    const el = panel.element as unknown as FakeElement;
    panel.show(result({ alignment: { rounds: 0, residual_before_mm: 0, residual_after_mm: 0, groups: [], note: 'no long-axis views: nothing to align to' } }));
    const box = el.byTestId('result-alignment')!;
    expect(box.hidden).toBe(false);
    expect(box.textContent).toContain('no long-axis views: nothing to align to');
    expect(el.byTestId('alignment-groups')).toBeUndefined();
    expect(el.dataset.residualAfterMm).toBe('0');
  });

  it('formats the residual and sorts rows by shift length, stable on ties', () => {
    expect(residualText({ ...ALIGNMENT, rounds: 1 })).toBe('2.35 → 0.61 mm (1 round)');
    const tie = alignmentRows({ ...ALIGNMENT, groups: [ALIGNMENT.groups[0], { ...ALIGNMENT.groups[0], label: 'SAX 9' }] });
    expect(tie.map((g) => g.label)).toEqual(['SAX 1', 'SAX 9']);
    expect(tie[0].magnitudeMm).toBeCloseTo(0.5, 12);
  });
});

describe('scene helpers', () => {
  const file = {
    fileName: 'f.csv', surfaces: ['LV_ENDO', 'RV_ENDO'], landmarks: [], warnings: [],
    contours: [
      { id: 'a', surface: 'LV_ENDO', kind: null, pieces: [{ closed: true, start: 0, count: 3 }] },
      { id: 'b', surface: 'RV_ENDO', kind: null, pieces: [{ closed: false, start: 3, count: 2 }] },
    ],
    points: new Float32Array([0, 0, 0, 1, 0, 0, 0, 1, 0, 5, 5, 5, 6, 5, 5]),
  };
  it('frames the chosen surface and draws the as-given contours of the run surface only', () => {
    expect(Array.from(surfacePoints(file, 'RV_ENDO'))).toEqual([5, 5, 5, 6, 5, 5]);
    expect(surfacePoints(file, 'LA_ENDO')).toBe(file.points);
    // Closed triangle: 3 segments; open 2-point curve: 1 segment; 2 ends x 3 coordinates each.
    expect(givenSegments(file.contours, file.points, 'LV_ENDO').length).toBe(3 * 6);
    expect(givenSegments(file.contours, file.points, null).length).toBe(4 * 6);
    expect(Array.from(givenSegments(file.contours, file.points, 'RV_ENDO'))).toEqual([5, 5, 5, 6, 5, 5]);
  });
  it('says which file the view still shows when a file is refused at load', () => {
    expect(keptText('patient1-ED.csv')).toBe(' Not opened; still showing patient1-ED.csv.');
    expect(keptText(null)).toBe(' Not opened.');
  });
});
