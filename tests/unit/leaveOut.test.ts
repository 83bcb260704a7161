// Contours left out by hand (the Contours panel): the lists per file and frame, how they
// travel (the params JSON's `leave_out`, the client's requests, the worker's calls to the core),
// what the exports and the words say of them, the walls' readiness, the Function panel's note, and
// the viewer's parts (a contour named under the pointer, a left-out one keyed "left out by you",
// the highlight). The real core's `leave_out` is exercised by the e2e test.
import { describe, expect, it } from 'vitest';
import { DEFAULT_OPTIONS, paramsJson, type ContourInfo, type FromWorker, type SetAsideEntry } from '../../web/src/core-client/protocol';
import { settingsOf } from '../../web/src/core-client/coreClientTypes';
import { WorkerCore, type SessionApi, type WasmApi } from '../../web/src/core-client/workerCore';
import { LeaveOutLists, leaveOutKeyPart } from '../../web/src/app/leaveOut';
import { parseUrlState, serializeUrlState } from '../../web/src/app/urlState';
import { headerLines, stlHeader, type ExportInfo } from '../../web/src/io/export/header';
import { writeParamsJson } from '../../web/src/io/export/json';
import { wallReadiness } from '../../web/src/io/export/wall';
import { bivWallReadiness } from '../../web/src/io/export/bivWall';
import { leftOutDetail, leftOutLabel, leftOutText } from '../../web/src/ui/runText';
import { leftOutNote } from '../../web/src/ui/functionText';
import { HoverReadout } from '../../web/src/ui/HoverReadout';
import { ContourLayer } from '../../web/src/viewer/ContourLayer';
import { ContourHighlight } from '../../web/src/viewer/ContourHighlight';
import { SetAsideLayer } from '../../web/src/viewer/SetAsideLayer';
import type { HoverInfo } from '../../web/src/viewer/Viewer';
import type { FakeElement } from './fakeDom';
import { useFakeDocument } from './panelHarness';
import { rustSchema } from './rustSchema';
import { stepReport } from './core-client/fakes';

const LAX: SetAsideEntry = { id: 's07_LAX_LV_ENDOCARDIAL', line: 812, reason: 'by_user' };
const SPECK: SetAsideEntry = { id: 'sax10', line: 1505, reason: 'speck', perimeter_mm: 2.84, next_id: 'sax09', next_perimeter_mm: 210 };

describe('the leave-out lists', () => {
  const ed = { file: 'p1.csv', frame: null };

  it('are kept per file and frame, whatever the surface, in the order left out, each id once', () => {
    const lists = new LeaveOutLists();
    expect(lists.get(ed)).toEqual([]);
    expect(lists.toggle(ed, 'b', true)).toBe(true);
    expect(lists.toggle(ed, 'a', true)).toBe(true);
    expect(lists.toggle(ed, 'a', true)).toBe(false); // already out: no change, no run
    expect(lists.get(ed)).toEqual(['b', 'a']);
    // An RV contour joins the same list; another frame of the same file has a list of its own.
    lists.toggle(ed, 'r1', true);
    lists.toggle({ ...ed, frame: 'ES' }, 'b', true);
    expect(lists.get(ed)).toEqual(['b', 'a', 'r1']);
    expect(lists.get({ ...ed, frame: 'ES' })).toEqual(['b']);
    expect(lists.toggle(ed, 'b', false)).toBe(true);
    expect(lists.get(ed)).toEqual(['a', 'r1']);
    // A copy: the caller cannot change a list behind the lists' back.
    lists.get(ed).push('x');
    expect(lists.get(ed)).toEqual(['a', 'r1']);
    lists.set({ file: 'p2.csv', frame: null }, ['q', 'q']);
    expect(lists.get({ file: 'p2.csv', frame: null })).toEqual(['q']);
    expect(lists.listsOf('p1.csv').map((l) => [l.key.frame, l.ids])).toEqual([[null, ['a', 'r1']], ['ES', ['b']]]);
    // The file read anew: its lists go, another file's stay.
    lists.clearFile('p1.csv');
    expect(lists.listsOf('p1.csv')).toEqual([]);
    expect(lists.get(ed)).toEqual([]);
    expect(lists.get({ file: 'p2.csv', frame: null })).toEqual(['q']);
  });

  it('put back one surface\'s ids and keep the rest (Use all)', () => {
    const lists = new LeaveOutLists();
    lists.set(ed, ['s07', 'r1', 's03']);
    expect(lists.putBack(ed, ['s07', 's03', 's05'])).toBe(true);
    expect(lists.get(ed)).toEqual(['r1']);
    expect(lists.putBack(ed, ['s07'])).toBe(false); // none of them out: no change, no run
    expect(lists.putBack(ed, ['r1'])).toBe(true);
    expect(lists.listsOf('p1.csv')).toEqual([]);
  });

  it('add to a run\'s settings key only when not empty, whatever the order', () => {
    expect(leaveOutKeyPart([])).toBe('');
    expect(leaveOutKeyPart(['b', 'a'])).toBe('\nleave_out=a,b');
    expect(leaveOutKeyPart(['a', 'b'])).toBe(leaveOutKeyPart(['b', 'a']));
  });

  it('are never in the URL', () => {
    const schema = rustSchema();
    const s = parseUrlState('?leave_out=s07_LAX_LV_ENDOCARDIAL&surface=LV_ENDO', schema);
    expect(JSON.stringify(s)).not.toContain('s07');
    expect(serializeUrlState(s, schema)).toBe('?surface=LV_ENDO');
  });
});

describe('leave_out on its way to the core', () => {
  it('rides in the params JSON only when there are ids, after the options', () => {
    expect(JSON.parse(paramsJson({ beta: 0.1 }, DEFAULT_OPTIONS, []))).not.toHaveProperty('leave_out');
    expect(JSON.parse(paramsJson({ beta: 0.1 }, DEFAULT_OPTIONS))).not.toHaveProperty('leave_out');
    const json = JSON.parse(paramsJson({ beta: 0.1 }, DEFAULT_OPTIONS, ['s07', 's03']));
    expect(json.leave_out).toEqual(['s07', 's03']);
    expect(json.beta).toBe(0.1);
    expect(json.drop_second_loops).toBe(false);
    expect(JSON.parse(paramsJson({ beta: 0.1 }, undefined, ['s07']))).toEqual({ beta: 0.1, leave_out: ['s07'] });
  });

  it('the client copies the list into a request only when it has ids', () => {
    const base = { fileName: 'a.csv', surface: 'LV_ENDO', params: { beta: 0.1 }, lids: 'auto' as const };
    expect(settingsOf(base)).not.toHaveProperty('leaveOut');
    expect(settingsOf({ ...base, leaveOut: [] })).not.toHaveProperty('leaveOut');
    const ids = ['s07'];
    const copy = settingsOf({ ...base, leaveOut: ids });
    ids.push('later');
    expect(copy.leaveOut).toEqual(['s07']);
  });

  /** A session that records what the worker hands the core, and answers with a result carrying `resultLeaveOut`. */
  function worker(resultLeaveOut?: string[]) {
    const calls: { start: string[]; session: string[]; wall: string[] } = { start: [], session: [], wall: [] };
    let i = -1;
    const session = {
      load: (fileName: string) => JSON.stringify({ fileName, surfaces: ['LV_ENDO'], contours: [], landmarks: [], warnings: [], session: { params: {}, lids: 'auto', options: {}, surface: 'LV_ENDO' } }),
      file_points: () => new Float32Array(0),
      start: (_f: string, _s: string | null | undefined, params: string) => {
        calls.start.push(params);
        i = -1;
      },
      step: () => JSON.stringify(stepReport(++i, { total_iterations: 1, done: i >= 1, phase: i >= 1 ? 'done' : 'initial_tube', topology_changed: i === 0 })),
      growth_note: () => undefined,
      attractors_changed: () => false,
      positions: () => new Float32Array(9),
      indices: () => new Uint32Array(3),
      attractors: () => new Float32Array(0),
      contour_points: () => new Float32Array(0),
      point_distances: () => new Float32Array(0),
      vertex_distances: () => new Float32Array(3),
      set_aside_points: () => new Float32Array(0),
      result_json: () => JSON.stringify({ surface: 'LV_ENDO', contours: [], perContour: [], overall: { mean: 0, median: 0, p95: 0, max: 0, min: 0, count: 0 }, volumeMl: 1, areaMm2: 1, watertight: true, params: {}, lids: 'auto', version: 'x', options: {}, ...(resultLeaveOut ? { leave_out: resultLeaveOut } : {}) }),
      session_json: (_f: string, _s: string | null | undefined, params: string) => {
        calls.session.push(params);
        return new Uint8Array([123, 125]);
      },
      wall: (_f: string, params: string) => {
        calls.wall.push(params);
        return { summary: '{}', bytes: new Uint8Array(0) };
      },
    } as unknown as SessionApi;
    const wasm: WasmApi = { createSession: () => session, schemaJson: () => '[]', version: () => 'x', takePanicMessage: () => undefined };
    const out: FromWorker[] = [];
    const ticks: (() => void)[] = [];
    const core = new WorkerCore(wasm, (m) => out.push(m), { yieldToEventLoop: (cb) => ticks.push(cb), now: () => 0, sliceMs: 1 });
    const drain = () => {
      while (ticks.length) ticks.shift()!();
    };
    return { core, calls, out, drain };
  }

  it('the worker hands the list to the core in the params JSON of a run, a session and a wall', () => {
    const { core, calls, out, drain } = worker(['s07']);
    const settings = { fileName: 'a.csv', params: { beta: 0.1 }, lids: 'auto' as const, options: { ...DEFAULT_OPTIONS } };
    core.handle({ type: 'run', runId: 1, surface: 'LV_ENDO', ...settings, leaveOut: ['s07'] });
    drain();
    core.handle({ type: 'session-export', reqId: 2, surface: 'LV_ENDO', ...settings, leaveOut: ['s07'], appVersion: '1' });
    const mesh = { surface: 'LV_ENDO', positions: new Float64Array(9), indices: new Uint32Array(3) };
    core.handle({ type: 'wall-export', reqId: 3, ...settings, leaveOut: ['s07', 'e2'], endo: mesh, epi: { ...mesh, surface: 'LV_EPI' }, minThicknessMm: 1, format: 'obj', header: [] });
    core.handle({ type: 'run', runId: 4, surface: 'LV_ENDO', ...settings });
    drain();
    expect(calls.start.map((p) => JSON.parse(p).leave_out)).toEqual([['s07'], undefined]);
    expect(JSON.parse(calls.session[0]).leave_out).toEqual(['s07']);
    expect(JSON.parse(calls.wall[0]).leave_out).toEqual(['s07', 'e2']);
    const done = out.filter((m) => m.type === 'done');
    expect(done.map((m) => m.type === 'done' && m.result.leave_out)).toEqual([['s07'], ['s07']]);
  });

  it('a result or a session from an older core reads as none left out', () => {
    const { core, out, drain } = worker(undefined);
    core.handle({ type: 'run', runId: 1, fileName: 'a.csv', surface: 'LV_ENDO', params: {}, lids: 'auto' });
    drain();
    core.handle({ type: 'load', reqId: 2, fileName: 's.json', bytes: new ArrayBuffer(2) });
    const done = out.find((m) => m.type === 'done');
    expect(done?.type === 'done' && done.result.leave_out).toEqual([]);
    const loaded = out.find((m) => m.type === 'loaded');
    expect(loaded?.type === 'loaded' && loaded.file.session?.leave_out).toEqual([]);
  });
});

describe('what the exports record', () => {
  const info: ExportInfo = {
    appVersion: '1.0.0', coreVersion: '0.1.0', fileName: 'patient1-ED.csv', surface: 'LV_ENDO', lids: 'auto', options: { ...DEFAULT_OPTIONS }, params: { iterations: 250 },
  };

  it('the header lines name the ids only when some were left out', () => {
    expect(headerLines(info)[2]).not.toContain('leave_out');
    expect(headerLines({ ...info, leaveOut: [] })[2]).not.toContain('leave_out');
    expect(headerLines({ ...info, leaveOut: ['s07_LAX_LV_ENDOCARDIAL', 's03_SAX_LV_ENDOCARDIAL'] })[2]).toMatch(/ apex_floor=true leave_out=s07_LAX_LV_ENDOCARDIAL,s03_SAX_LV_ENDOCARDIAL$/);
    // STL's 80 bytes: the list when it fits whole, never cut.
    const stl = stlHeader({ ...info, fileName: 'p.csv', leaveOut: ['s07'] });
    expect(stl).toMatch(/^heartmesh 1\.0\.0 mm LV_ENDO p\.csv lids=auto leave_out=s07 iterations=250/);
    expect(stl.length).toBeLessThanOrEqual(80);
    expect(stlHeader({ ...info, leaveOut: ['x'.repeat(60)] })).not.toContain('leave_out');
  });

  it('the parameters JSON always has leave_out', () => {
    expect(JSON.parse(writeParamsJson(info, null)).leave_out).toEqual([]);
    expect(JSON.parse(writeParamsJson({ ...info, leaveOut: ['s07'] }, null)).leave_out).toEqual(['s07']);
  });
});

describe('the words for contours left out by the user', () => {
  it('"left out by you", in the key, the read-out and the result panel\'s row', () => {
    expect(leftOutLabel('by_user')).toBe('left out by you');
    expect(leftOutDetail(LAX)).toBe('"s07_LAX_LV_ENDOCARDIAL" (line 812): left out by you (tick it in the Contours panel to use it again)');
    // With how far the mesh built without it passes (the core's held-out figures, Patient 1 ED): the CLI's words.
    expect(leftOutDetail({ ...LAX, mean: 1.8312, median: 1.143, max: 7.6649 })).toBe(
      '"s07_LAX_LV_ENDOCARDIAL" (line 812): left out by you, the mesh 1.83 mm from it on average, 7.66 mm at most (tick it in the Contours panel to use it again)',
    );
    // A figure the JSON gave as null (not finite) is no figure: the words without them.
    expect(leftOutDetail({ ...LAX, mean: null, median: null, max: null })).toBe(leftOutDetail(LAX));
    expect(leftOutDetail({ ...LAX, mean: 1.8312, median: 1.143, max: null })).toBe(leftOutDetail(LAX));
    const one = leftOutText([LAX])!;
    expect(one.text).toBe('1 contour (by you) · s07_LAX_LV_ENDOCARDIAL');
    expect(one.title).toContain('Tick those left out by you in the Contours panel');
    expect(one.title).not.toContain('Keep specks and strays');
    const both = leftOutText([LAX, SPECK, { ...LAX, id: 's03' }])!;
    expect(both.text).toBe('3 contours (2 by you, 1 speck) · s07_LAX_LV_ENDOCARDIAL, sax10, s03');
    expect(both.title).toContain('Keep specks and strays');
    expect(both.title).toContain('Contours panel');
  });

  it('the Function panel says the phases batch leaves them out too, one list per file and frame', () => {
    expect(leftOutNote([])).toBeNull();
    expect(leftOutNote([{ file: 'a.csv', frame: null, ids: [] }])).toBeNull();
    expect(leftOutNote([{ file: 'patient1-ED.csv', frame: null, ids: ['s07'] }])).toBe('Left out, as in the Contours panel: one contour (patient1-ED.csv: s07)');
    expect(leftOutNote([{ file: 'cine.csv', frame: 'ES', ids: ['s7', 'r1'] }, { file: 'cine.csv', frame: 'ED', ids: [] }, { file: 'cine.csv', frame: '9', ids: ['s8'] }])).toBe(
      'Left out, as in the Contours panel: 3 contours (cine.csv frame ES: s7, r1; cine.csv frame 9: s8)',
    );
  });
});

describe('the walls and the list', () => {
  const mesh = (surface: string, settings: string) => ({ surface, positions: new Float32Array(9), indices: new Uint32Array(3), settings });
  const key = (ids: string[]) => `base${leaveOutKeyPart(ids)}`;

  it('a mesh run before the file\'s list changed is not used, whichever surface the id is of', () => {
    const surfaces = ['LV_ENDO', 'LV_EPI'];
    const kept = { LV_ENDO: mesh('LV_ENDO', key(['s07'])), LV_EPI: mesh('LV_EPI', key(['s07'])) } as Record<string, ReturnType<typeof mesh>>;
    const ready = wallReadiness(surfaces, (s) => kept[s], key(['s07']));
    expect(ready.ready).toBe(true);
    // An LV_ENDO id left out since: LV_EPI's run is stale too (its alignment and crossing gap saw the contour).
    const stale = wallReadiness(surfaces, (s) => kept[s], key(['s07', 's03']));
    expect(stale).toMatchObject({ ready: false, key: '' });
    expect(stale.title).toMatch(/: LV_ENDO and LV_EPI were last run with other parameters; run them again/);
    // An RV id: neither LV mesh was run without it.
    expect(wallReadiness(surfaces, (s) => kept[s], key(['s07', 'r1'])).title).toMatch(/: LV_ENDO and LV_EPI were last run with other parameters/);
    // One run again with the new list: the other is still stale.
    const half: Record<string, ReturnType<typeof mesh>> = { ...kept, LV_ENDO: mesh('LV_ENDO', key(['s07', 'r1'])) };
    expect(wallReadiness(surfaces, (s) => half[s], key(['r1', 's07'])).title).toMatch(/: LV_EPI was last run with other parameters; run it again/);
    // The key changes with the list (a wall built of other meshes is not shown as this one).
    const kept2: Record<string, ReturnType<typeof mesh>> = { LV_ENDO: mesh('LV_ENDO', key(['s03'])), LV_EPI: mesh('LV_EPI', key(['s03'])) };
    const again = wallReadiness(surfaces, (s) => kept2[s], key(['s03']));
    expect(again.ready && ready.ready && again.key !== ready.key).toBe(true);
    const biv = ['LV_ENDO', 'RV_ENDO', 'BIV_EPI'];
    expect(bivWallReadiness(biv, (s) => mesh(s, key(['s07'])), key(['s07'])).ready).toBe(true);
    expect(bivWallReadiness(biv, (s) => mesh(s, s === 'RV_ENDO' ? key(['s07']) : key([])), key(['s07'])).title).toMatch(/: LV_ENDO and BIV_EPI were last run with other parameters/);
  });
});

describe('the viewer and the read-out name contours', () => {
  useFakeDocument();

  /** Two contours of the surface (3 and 2 points) and one of another surface. */
  const CONTOURS: ContourInfo[] = [
    { id: 's05_SAX_LV_ENDOCARDIAL', surface: 'LV_ENDO', kind: 'SAX', pieces: [{ closed: true, start: 0, count: 3 }] },
    { id: 's07_LAX_LV_ENDOCARDIAL', surface: 'LV_ENDO', kind: 'LAX', pieces: [{ closed: false, start: 3, count: 2 }] },
    { id: 'rv', surface: 'RV_ENDO', kind: 'SAX', pieces: [{ closed: true, start: 5, count: 3 }] },
  ];
  const POINTS = new Float32Array([0, 0, 0, 10, 0, 0, 0, 10, 0, 0, 0, 5, 0, 0, 15, 50, 0, 0, 60, 0, 0, 50, 10, 0]);

  it('a picked contour point names its contour; the surface\'s contours are found by id, others not', () => {
    const layer = new ContourLayer();
    const v0 = layer.version;
    layer.set(CONTOURS, POINTS, 'LV_ENDO', new Float32Array([0.1, 0.2, 0.3, 0.84, 0.5, 0, 0, 0]), 1);
    expect(layer.version).toBeGreaterThan(v0);
    expect([0, 2, 3, 4, 5].map((i) => layer.contourOfPoint(i))).toEqual(['s05_SAX_LV_ENDOCARDIAL', 's05_SAX_LV_ENDOCARDIAL', 's07_LAX_LV_ENDOCARDIAL', 's07_LAX_LV_ENDOCARDIAL', null]);
    expect(layer.distanceOfPoint(3)).toBeCloseTo(0.84, 6);
    expect(layer.contourById('s07_LAX_LV_ENDOCARDIAL')?.contour.pieces).toEqual([{ closed: false, start: 3, count: 2 }]);
    expect(layer.contourById('rv')).toBeNull();
    layer.clear();
    expect(layer.contourOfPoint(0)).toBeNull();
    layer.dispose();
  });

  it('the read-out says "0.84 mm to mesh · ID" on a contour point and "1.92 mm to mesh (built without it) · left out by you · ID" on one left out', () => {
    const readout = new HoverReadout();
    const el = readout.element as unknown as FakeElement;
    const at = { x: 10, y: 10, point: { x: 1, y: 2, z: 3 } } as unknown as HoverInfo;
    readout.show({ ...at, what: 'contour point', distanceMm: 0.8412, id: 's05_SAX_LV_ENDOCARDIAL' }, 2);
    expect(el.textContent).toMatch(/^0\.84 mm to mesh · s05_SAX_LV_ENDOCARDIAL\(1\.0, 2\.0, 3\.0\) mm$/);
    readout.show({ ...at, what: 'mesh', distanceMm: 1.5 }, 2);
    expect(el.textContent).toMatch(/^1\.50 mm to nearest contour\(/);
    readout.show({ ...at, what: 'left out', distanceMm: null, label: leftOutLabel('by_user'), id: LAX.id }, 2);
    expect(el.textContent).toBe(' left out by you · s07_LAX_LV_ENDOCARDIAL(1.0, 2.0, 3.0) mm');
    // With its distance to the mesh built without it: the figure first, as on a contour used, and
    // grey, not coloured on the used contours' scale (1.92 is within the 2 mm scale).
    readout.show({ ...at, what: 'left out', distanceMm: 1.9237, label: leftOutLabel('by_user'), id: LAX.id }, 2);
    expect(el.textContent).toBe(' 1.92 mm to mesh (built without it) · left out by you · s07_LAX_LV_ENDOCARDIAL(1.0, 2.0, 3.0) mm');
    expect(el.findAll((e) => e.tagName === 'strong').map((e) => e.textContent)).toEqual(['1.92 mm']);
    const swatches = el.findAll((e) => e.tagName === 'span' && e.getAttribute('class')?.includes('swatch') === true);
    expect(swatches.map((e) => [e.getAttribute('class'), e.style.background ?? ''])).toEqual([['swatch set-aside-swatch', '']]);
  });

  it('the key of contours not used names those left out by the user; the highlight draws one contour', () => {
    const layer = new SetAsideLayer();
    layer.set([LAX], [CONTOURS[1]], POINTS);
    const key = layer.legend as unknown as FakeElement;
    expect(key.textContent).toContain('left out by you · s07_LAX_LV_ENDOCARDIAL');
    expect(key.findAll((e) => e.dataset.testid === 'set-aside-row').map((r) => [r.dataset.reason, r.title])).toEqual([['by_user', leftOutDetail(LAX)]]);
    expect(layer.entryOfPoint(3)?.reason).toBe('by_user');
    expect(layer.contourById(LAX.id)?.contour.id).toBe(LAX.id);

    const highlight = new ContourHighlight();
    highlight.show(LAX.id, layer.contourById(LAX.id));
    expect(highlight.id).toBe(LAX.id);
    const [lines, discs] = highlight.group.children as unknown as { geometry: { getAttribute(n: string): { count: number; array: Float32Array } } }[];
    expect(lines.geometry.getAttribute('position').count).toBe(2); // one segment of the open curve
    expect(Array.from(discs.geometry.getAttribute('position').array)).toEqual([0, 0, 5, 0, 0, 15]);
    highlight.show('nowhere', null);
    expect([highlight.id, highlight.group.children.length]).toEqual([null, 0]);
    highlight.dispose();
    layer.dispose();
  });
});
