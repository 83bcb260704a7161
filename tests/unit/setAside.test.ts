// Contours the core leaves out (session 14: strays and specks) in the app: the `keep_specks`
// option's plumbing (params JSON, URL, exports, the panel's checkbox), the result panel's "Left
// out" row, its wording, the viewer layer that draws them grey and dashed with its key, and the
// scene's choice of when to draw them. The real core's set_aside is exercised in tests/node.
import { describe, expect, it } from 'vitest';
import {
  DEFAULT_OPTIONS,
  paramsJson,
  withDefaultOptions,
  type ContourInfo,
  type SetAsideEntry,
} from '../../web/src/core-client/protocol';
import { parseUrlState, serializeUrlState } from '../../web/src/app/urlState';
import { headerLines, type ExportInfo } from '../../web/src/io/export/header';
import { runSummary, writeParamsJson } from '../../web/src/io/export/json';
import { keptSpecksNote, leftOutDetail, leftOutLabel, leftOutText } from '../../web/src/ui/runText';
import { ResultPanel } from '../../web/src/ui/ResultPanel';
import { HoverReadout } from '../../web/src/ui/HoverReadout';
import { SetAsideLayer, pairSetAside } from '../../web/src/viewer/SetAsideLayer';
import { showSceneContours } from '../../web/src/app/sceneContours';
import type { Viewer } from '../../web/src/viewer/Viewer';
import { type FakeElement, dlRows } from './fakeDom';
import { useFakeDocument, optionsPanel } from './panelHarness';
import { rustSchema } from './rustSchema';
import paramsRs from '../../wasm-core/crates/heartmesh-core/src/params.rs?raw';
import { runResult } from './runResult';

const SPECK: SetAsideEntry = { id: 'sax10', line: 1505, reason: 'speck', perimeter_mm: 2.84, next_id: 'sax09', next_perimeter_mm: 210 };
const STRAY: SetAsideEntry = { id: 'far', line: 2251, reason: 'stray', gap_mm: 176.4 };

/** A 3-point loop and a 2-point open curve, as `set_aside_contours` index `setAsidePoints`. */
const CONTOURS: ContourInfo[] = [
  { id: 'sax10', surface: 'LV_ENDO', kind: null, pieces: [{ closed: true, start: 0, count: 3 }] },
  { id: 'far', surface: 'LV_ENDO', kind: null, pieces: [{ closed: false, start: 3, count: 2 }] },
];
const POINTS = new Float32Array([5, 0, 8, 4.4, 0.6, 8, 4.4, -0.6, 8, 200, 0, 0, 210, 0, 0]);

const result = runResult;

describe('keep_specks option', () => {
  it('is off by default, as in the core, and travels in the params JSON; old sessions read as off', () => {
    const defaults = /impl Default for Params[\s\S]*?\n}/.exec(paramsRs)?.[0] ?? '';
    expect(defaults).toMatch(/keep_specks: false,/);
    expect(DEFAULT_OPTIONS.keep_specks).toBe(false);
    expect(JSON.parse(paramsJson({ beta: 0.1 }, DEFAULT_OPTIONS)).keep_specks).toBe(false);
    expect(JSON.parse(paramsJson({}, { ...DEFAULT_OPTIONS, keep_specks: true })).keep_specks).toBe(true);
    expect(withDefaultOptions({ smoothing_method: 'taubin', soften_conflicts: true, align_slices: true, end_caps: 'off' }).keep_specks).toBe(false);
  });

  it('is in the URL only when on; junk reads as off', () => {
    const schema = rustSchema();
    const s = parseUrlState('', schema);
    expect(s.options.keep_specks).toBe(false);
    s.options = { ...s.options, keep_specks: true };
    expect(serializeUrlState(s, schema)).toBe('?keep_specks=1');
    expect(parseUrlState('?keep_specks=1', schema).options.keep_specks).toBe(true);
    expect(parseUrlState('?keep_specks=true', schema).options.keep_specks).toBe(true);
    expect(parseUrlState('?keep_specks=maybe', schema).options.keep_specks).toBe(false);
  });

  it('is recorded in the export header and the parameters JSON, with what the run left out', () => {
    const info: ExportInfo = {
      appVersion: '1.0.0', coreVersion: '0.1.0', fileName: 'p.csv', surface: 'LV_ENDO', lids: 'auto',
      options: { ...DEFAULT_OPTIONS, keep_specks: true }, params: { iterations: 250 },
    };
    expect(headerLines(info)[2]).toMatch(/ end_caps=auto keep_specks=true apex_floor=true$/);
    expect(JSON.parse(writeParamsJson(info, null)).keep_specks).toBe(true);
    const old = { ...info, options: { smoothing_method: 'taubin', soften_conflicts: true } as never };
    expect(headerLines(old)[2]).toMatch(/ keep_specks=false apex_floor=true$/);
    // The result records the contours left out as the CLI report's `set_aside`, only when there are any.
    const left = JSON.parse(writeParamsJson(info, runSummary(result({ set_aside: [SPECK] })))).result;
    expect(left.set_aside).toEqual([SPECK]);
    expect(JSON.parse(writeParamsJson(info, runSummary(result({ set_aside: [] })))).result.set_aside).toBeUndefined();
    expect(JSON.parse(writeParamsJson(info, runSummary(result()))).result.set_aside).toBeUndefined();
  });
});

describe('the words for contours left out', () => {
  it('name the kinds, the count and the ids; the tooltip every one with its line and why', () => {
    expect(leftOutText([])).toBeNull();
    const one = leftOutText([SPECK])!;
    expect(one.text).toBe('1 contour (speck) · sax10');
    expect(one.title).toContain('"sax10" (line 1505): a speck, 2.8 mm around, 1 % of the ring of "sax09" one slice away');
    expect(one.title).toContain('Keep specks and strays');
    expect(leftOutText([STRAY])!.text).toBe('1 contour (stray) · far');
    const many = leftOutText([STRAY, SPECK, { ...SPECK, id: 'sax11', line: 1600 }, { ...SPECK, id: 'sax12', line: 1700 }])!;
    expect(many.text).toBe('4 contours (3 specks, 1 stray) · far, sax10, sax11, …');
    expect(many.title).toContain('"sax12" (line 1700)');
    expect(leftOutDetail(STRAY)).toBe('"far" (line 2251): a stray, 176 mm from the nearest contour kept');
    expect(leftOutDetail({ ...STRAY, line: 0 })).toBe('"far": a stray, 176 mm from the nearest contour kept');
    expect(leftOutDetail({ ...SPECK, perimeter_mm: 21, next_perimeter_mm: 210 })).toContain('10 % of the ring');
    // With how far the mesh built without it passes, after the reason (and within the Left out row's list).
    const measured = { ...STRAY, mean: 180.123, median: 179.5, max: 190.004 };
    expect(leftOutDetail(measured)).toBe('"far" (line 2251): a stray, 176 mm from the nearest contour kept, the mesh 180.12 mm from it on average, 190.00 mm at most');
    expect(leftOutDetail({ ...SPECK, mean: 3.456, median: 3, max: 4.5 })).toBe(
      '"sax10" (line 1505): a speck, 2.8 mm around, 1 % of the ring of "sax09" one slice away, the mesh 3.46 mm from it on average, 4.50 mm at most',
    );
    expect(leftOutText([measured, SPECK])!.title).toContain(`${leftOutDetail(measured)}; ${leftOutDetail(SPECK)}.`);
    expect(leftOutLabel('speck')).toBe('left out: speck');
    expect(leftOutLabel('stray')).toBe('left out: stray');
    // A long-axis speck (session 15) counts as a speck, with its own detail.
    const click: SetAsideEntry = { id: 'speck', line: 3016, reason: 'lax_speck', length_mm: 5.196, extent_mm: 99.2 };
    expect(leftOutLabel('lax_speck')).toBe('left out: speck');
    expect(leftOutDetail(click)).toBe('"speck" (line 3016): a speck in a long-axis plane, 5.2 mm long where the data span 99 mm along the axis');
    expect(leftOutText([click])!.text).toBe('1 contour (speck) · speck');
    expect(leftOutText([STRAY, SPECK, click])!.text).toBe('3 contours (2 specks, 1 stray) · far, sax10, speck');
  });
});

describe('contours left out in the panels and the viewer', () => {
  useFakeDocument();

  const rows = dlRows;

  it('the checkbox "Keep specks and strays" sits after "Close open ends", shows the option and emits it', () => {
    const { emitted, panel, root } = optionsPanel();
    const box = root.byTestId('param-keep-specks') as FakeElement & { checked: boolean };
    const text = root.textContent;
    expect(text.indexOf('Keep specks and strays')).toBeGreaterThan(text.indexOf('Close open ends'));
    expect(box.getAttribute('aria-describedby')).toBe('param-keep-specks-help');
    panel.setValues({}, 'auto', { ...DEFAULT_OPTIONS });
    expect(box.checked).toBe(false);
    panel.setValues({}, 'auto', { ...DEFAULT_OPTIONS, keep_specks: true });
    expect(box.checked).toBe(true);
    box.checked = false;
    box.fire('change');
    expect(emitted.at(-1)).toEqual({ ...DEFAULT_OPTIONS, keep_specks: false });
    box.checked = true;
    box.fire('change');
    expect(emitted.at(-1)).toEqual({ ...DEFAULT_OPTIONS, keep_specks: true });
  });

  it('the result panel has a "Left out" row only when the run left something out', () => {
    const panel = new ResultPanel();
    const el = panel.element as unknown as FakeElement;
    panel.show(result({ set_aside: [SPECK] }));
    expect(rows(el)['Left out']).toBe('1 contour (speck) · sax10');
    expect(el.byTestId('result-set-aside')?.title).toMatch(/^left out of the reconstruction \(drawn grey and dashed\): "sax10" \(line 1505\)/);
    expect(el.dataset.setAside).toBe('1');
    panel.show(result({ set_aside: [] }));
    expect(rows(el)['Left out']).toBeUndefined();
    expect(el.dataset.setAside).toBe('0');
    // An older core: no row, no attribute.
    panel.show(result());
    expect(rows(el)['Left out']).toBeUndefined();
    expect(el.dataset.setAside).toBeUndefined();
  });

  it('pairs each entry with its contour and the range of its points', () => {
    expect(pairSetAside([SPECK, STRAY], CONTOURS).map((p) => [p.entry.id, p.start, p.count])).toEqual([['sax10', 0, 3], ['far', 3, 2]]);
    // Geometry missing (an older binding): not drawn, and the others keep theirs.
    expect(pairSetAside([SPECK, STRAY], CONTOURS.slice(0, 1)).map((p) => p.entry.id)).toEqual(['sax10']);
    expect(pairSetAside([SPECK, STRAY], CONTOURS.slice(1)).map((p) => [p.entry.id, p.start])).toEqual([['far', 3]]);
    expect(pairSetAside([STRAY], CONTOURS).map((p) => p.contour.id)).toEqual(['far']);
    // Two of one name: each takes its own.
    const twice = [CONTOURS[0], { ...CONTOURS[0], pieces: [{ closed: true, start: 3, count: 2 }] }];
    expect(pairSetAside([SPECK, { ...SPECK, line: 1600 }], twice).map((p) => [p.entry.line, p.start])).toEqual([[1505, 0], [1600, 3]]);
    expect(pairSetAside([SPECK], [{ ...CONTOURS[0], pieces: [] }])).toEqual([]);
    expect(pairSetAside([SPECK], [])).toEqual([]);
  });

  it('the layer draws them, keys each one and names the one under a picked point', () => {
    const layer = new SetAsideLayer();
    const key = layer.legend as unknown as FakeElement;
    expect([layer.count, key.dataset.count, key.hidden]).toEqual([0, '0', true]);
    layer.set([SPECK, STRAY], CONTOURS, POINTS);
    expect([layer.count, key.dataset.count, key.hidden]).toEqual([2, '2', false]);
    expect(key.textContent).toContain('left out: speck · sax10');
    expect(key.textContent).toContain('left out: stray · far');
    expect(key.findAll((e) => e.dataset.testid === 'set-aside-row').map((r) => r.dataset.reason)).toEqual(['speck', 'stray']);
    // Grey dashed lines (three segments of the loop, one of the open curve), a disc per point and a
    // ring at the middle of each contour.
    const [lines, points, rings] = layer.group.children as unknown as { geometry: { getAttribute(n: string): { count: number; array: Float32Array } } }[];
    expect(lines.geometry.getAttribute('position').count).toBe(8);
    expect(points.geometry.getAttribute('position').count).toBe(5);
    expect(Array.from(rings.geometry.getAttribute('position').array)).toEqual([Math.fround(13.8 / 3), 0, 8, 205, 0, 0]);
    expect(layer.entryOfPoint(2)?.id).toBe('sax10');
    expect(layer.entryOfPoint(3)?.id).toBe('far');
    expect(layer.entryOfPoint(5)).toBeNull();
    // Without the run's distances, a picked point has none.
    expect(layer.distanceOfPoint(0)).toBeNull();
    layer.setVisible(false);
    expect(key.hidden).toBe(true);
    layer.setVisible(true);
    expect(key.hidden).toBe(false);
    layer.clear();
    expect([layer.count, key.dataset.count, key.hidden, layer.group.children.length]).toEqual([0, '0', true, 0]);
    layer.dispose();
  });

  it('keeps each point\'s distance to the mesh built without it for the read-out, not for colour', () => {
    const layer = new SetAsideLayer();
    layer.set([SPECK, STRAY], CONTOURS, POINTS, new Float32Array([8.1, 8.2, 8.3, 176.4, 186.4]));
    expect([0, 2, 3, 4].map((i) => layer.distanceOfPoint(i))).toEqual([8.1, 8.3, 176.4, 186.4].map(Math.fround));
    expect(layer.distanceOfPoint(5)).toBeNull();
    // Still grey: no per-point colours on the lines, the discs or the rings.
    const geometries = layer.group.children as unknown as { geometry: { getAttribute(n: string): unknown } }[];
    expect(geometries.map((o) => o.geometry.getAttribute('color'))).toEqual([undefined, undefined, undefined]);
    // A list of another length than the points' is no one's.
    layer.set([SPECK, STRAY], CONTOURS, POINTS, new Float32Array([8.1, 8.2, 8.3]));
    expect(layer.distanceOfPoint(0)).toBeNull();
    layer.set([SPECK, STRAY], CONTOURS, POINTS, new Float32Array([8.1, 8.2, 8.3, 176.4, 186.4]));
    layer.clear();
    expect(layer.distanceOfPoint(0)).toBeNull();
    layer.dispose();
  });

  it('the scene draws them after a run only (before one they are among the file\'s contours)', () => {
    const calls: string[] = [];
    const layer = {
      set: (l: SetAsideEntry[], _c: ContourInfo[], _p: Float32Array, d?: Float32Array) => calls.push(`aside ${l.map((s) => s.id).join(',')}${d ? ` ${Array.from(d).join(',')}` : ''}`),
      clear: () => calls.push('aside clear'),
    };
    const viewer = {
      contourLayer: { set: () => calls.push('contours') },
      givenLayer: { set: () => calls.push('given'), clear: () => undefined },
      setAsideLayer: layer,
    } as unknown as Viewer;
    const file = { fileName: 'p.csv', surfaces: ['LV_ENDO'], contours: [], points: new Float32Array(0), landmarks: [], warnings: [] };
    showSceneContours(viewer, file, 'LV_ENDO', null, 1);
    expect(calls).toEqual(['aside clear', 'contours']);
    calls.length = 0;
    showSceneContours(viewer, file, 'LV_ENDO', result({ set_aside: [SPECK], set_aside_contours: CONTOURS.slice(0, 1), setAsidePoints: POINTS.slice(0, 9) }), 1);
    expect(calls).toEqual(['contours', 'aside sax10']);
    calls.length = 0;
    // With their distances (to the mesh built without them), which the layer keeps for the read-out.
    showSceneContours(viewer, file, 'LV_ENDO', result({ set_aside: [SPECK], set_aside_contours: CONTOURS.slice(0, 1), setAsidePoints: POINTS.slice(0, 9), setAsidePointDistances: new Float32Array([8, 8.5, 9]) }), 1);
    expect(calls).toEqual(['contours', 'aside sax10 8,8.5,9']);
    calls.length = 0;
    showSceneContours(viewer, file, 'LV_ENDO', result(), 1);
    expect(calls).toEqual(['contours', 'aside ']);
  });

  it('the hover read-out names a contour left out, with how far the mesh built without it passes when the run says', () => {
    const readout = new HoverReadout();
    const el = readout.element as unknown as FakeElement & { style: Record<string, string> };
    el.style = {}; // the fake DOM has no style; the placement is tested in hoverReadout.test.ts
    readout.show({ x: 10, y: 10, what: 'left out', point: { x: 5, y: 0, z: 8 } as never, distanceMm: null, label: 'left out: speck', id: 'sax10' }, 2);
    expect(el.hidden).toBe(false);
    expect(el.textContent).toContain('left out: speck · sax10');
    expect(el.textContent).not.toContain('to mesh');
    readout.show({ x: 10, y: 10, what: 'left out', point: { x: 5, y: 0, z: 8 } as never, distanceMm: 8.3149, label: 'left out: speck', id: 'sax10' }, 2);
    expect(el.textContent).toBe(' 8.31 mm to mesh (built without it) · left out: speck · sax10(5.0, 0.0, 8.0) mm');
  });
});

describe('the note when they are kept', () => {
  it('follows the core\'s lines about contours left out only when the option is on', () => {
    const speck = 'contour "s" (line 9, 2.0 mm around, 1 % of the ring of "t" one slice away) is a speck, not a section of the cavity; it is left out of the reconstruction';
    expect(keptSpecksNote([speck], false)).toBeNull();
    expect(keptSpecksNote(['3 points of unknown contour type 9 skipped'], true)).toBeNull();
    expect(keptSpecksNote([speck], true)).toBe('Keep specks and strays is on: the contours named above as left out are used in the reconstruction');
  });
});
