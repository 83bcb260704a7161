// The controller's wiring with a fake core client and recording stand-ins for the DOM parts
// (fakes are fine in unit tests; the e2e tests drive the real worker and page).
import { afterEach, beforeEach, describe, expect, it, vi } from 'vitest';
import { Controller, RESTART_DEBOUNCE_MS, type Parts } from '../../web/src/app/controller';
import type { CoreClient } from '../../web/src/core-client/CoreClient';
import type { Frame, LidsMode, LoadedFile, ParamValues, ReconOptions, RunResult, StepReport } from '../../web/src/core-client/protocol';
import { rustSchema } from './rustSchema';
import { DEFAULT_END_CAPS } from '../../web/src/core-client/protocol';
import { DEFAULT_VIEW } from '../../web/src/app/urlState';
import { zipSync } from 'fflate';

interface FakeRun {
  runId: number;
  opts: { fileName: string; surface: string | null; params: ParamValues; lids: LidsMode; options?: ReconOptions; leaveOut?: readonly string[] };
  onFrame: (f: Frame) => void;
  resolve: (r: RunResult) => void;
  reject: (e: unknown) => void;
  cancelled: boolean;
}

class FakeClient {
  runs: FakeRun[] = [];
  /** The run in progress is inside a step of seconds (CoreClient.isInLongStep). */
  longStep = false;
  loads: string[] = [];
  private next = 1;
  /** Behind a long step, the client calls whenBehindLongStep (CoreClient.load). */
  private behind(whenBehindLongStep?: () => void) {
    if (this.longStep && this.runs.some((r) => !r.cancelled)) whenBehindLongStep?.();
  }
  schema() {
    return Promise.resolve({ schema: rustSchema(), version: 'core-test' });
  }
  /** Each load's long-axis views (by name), and the views added to a loaded stack. */
  studyLoads: [string, string[]][] = [];
  viewAdds: [string, string[]][] = [];
  private readonly views = new Map<string, string[]>();
  /** A label map's grid: the fake NIfTI bytes (gzip magic, then STACK or VIEW) say which. */
  labelMapGrid(bytes: ArrayBuffer): Promise<{ dims: [number, number, number]; frames: number } | null> {
    const text = new TextDecoder().decode(bytes.slice(2));
    return Promise.resolve(text.startsWith('STACK') ? { dims: [100, 108, 10], frames: 1 } : text.startsWith('VIEW') ? { dims: [102, 88, 1], frames: 1 } : null);
  }
  viewsOf(fileName: string): string[] {
    return this.views.get(fileName) ?? [];
  }
  /** A view named cut* is damaged. */
  addViews(fileName: string, views: { name: string }[]): Promise<LoadedFile> {
    this.viewAdds.push([fileName, views.map((v) => v.name)]);
    const cut = views.find((v) => v.name.startsWith('cut'));
    if (cut) return Promise.reject({ code: 'parse', message: `${cut.name}: the gzip data is damaged`, file: fileName });
    this.views.set(fileName, [...this.viewsOf(fileName).filter((n) => !views.some((v) => v.name === n)), ...views.map((v) => v.name)]);
    return Promise.resolve(this.loaded(fileName, null, null));
  }
  load(fileName: string, bytes: ArrayBuffer, whenBehindLongStep?: () => void, views: { name: string }[] = []): Promise<LoadedFile> {
    this.loads.push(fileName);
    this.studyLoads.push([fileName, views.map((v) => v.name)]);
    this.views.set(fileName, views.map((v) => v.name));
    const cut = views.find((v) => v.name.startsWith('cut'));
    if (cut) return Promise.reject({ code: 'parse', message: `${cut.name}: the gzip data is damaged`, file: fileName });
    // A cvi42 workspace (heartmesh-core io::cvi42): refused alone, and with no image (IM_*) among the files.
    if (fileName.endsWith('.cvi42wsx') && views.length === 0) {
      return Promise.reject({ code: 'parse', message: 'cvi42 workspace: a cvi42 workspace holds its contours in the pixels of its images: open it together with the DICOM images it was drawn on (the study\'s folder)' });
    }
    if (fileName.endsWith('.cvi42wsx') && !views.some((v) => v.name.startsWith('IM_'))) {
      return Promise.reject({ code: 'parse', message: `cvi42 workspace: none of the ${views.length} files given with it is a DICOM image with an image plane` });
    }
    this.behind(whenBehindLongStep);
    if (new TextDecoder().decode(bytes).includes('bad')) return Promise.reject({ code: 'parse', message: 'line 2: bad number', line: 2 });
    // The core's refusal of a biv-me SliceInfoFile read as contours (io::read_contours_with).
    if (new TextDecoder().decode(bytes).includes('sliceID')) {
      return Promise.reject({ code: 'parse', message: 'line 1: this is a biv-me SliceInfoFile (image planes), not contours; read the GPFile_*.txt beside it', line: 1 });
    }
    // A saved session: the settings the binding reads from it (convert::session_settings).
    const session = fileName.endsWith('.json')
      ? {
          params: { ...Object.fromEntries(rustSchema().map((p) => [p.name, p.default])), beta: 0.3, smoothing_factor: 0.5 },
          lids: 'none' as const, surface: 'RV_ENDO',
          // As saved before align_slices existed: the app reads the missing option as off. A
          // session with the apex floor off (or saved before sessions stored it: the binding then
          // sends apex_floor false, core io::session) carries it.
          options: (fileName.includes('floor-off')
            ? { smoothing_method: 'taubin', soften_conflicts: false, apex_floor: false }
            : { smoothing_method: 'taubin', soften_conflicts: false }) as unknown as ReconOptions,
          // A session saved with an LV_ENDO and an RV_ENDO contour left out (the binding's `leave_out`).
          ...(fileName.includes('left-out') ? { leave_out: ['c1', 'r1'] } : {}),
        }
      : null;
    return Promise.resolve(this.loaded(fileName, session, null));
  }
  /**
   * A `cine*` file holds frames 0 and 9, a `phase*` file frames ED and ES (the binding's
   * `timeFrames`: the frame read named as the file writes it, whatever the case asked for); others
   * have no frame column. The last point's z is the frame's index in the file. A `wall*` file has
   * LV_EPI too; every file has an LV_ENDO contour c1, an RV_ENDO contour r1 and an LV_EPI one e1.
   */
  private loaded(fileName: string, session: LoadedFile['session'], frame: string | null): LoadedFile {
    const frames = fileName.startsWith('cine') ? ['0', '9'] : fileName.startsWith('phase') ? ['ED', 'ES'] : null;
    const index = frame === null ? 0 : (frames?.findIndex((f) => f.toLowerCase() === frame.toLowerCase()) ?? 0);
    const timeFrames = frames
      ? { frames, count: 2, read: [frames[index]], firsts: [frames[0]], chosen: frame !== null, leftOut: 6, sequence: true }
      : null;
    return {
      fileName, surfaces: fileName.startsWith('heart') ? ['RV_EPI', 'LV_EPI', 'BIV_EPI'] : fileName.startsWith('wall') ? ['LV_ENDO', 'LV_EPI', 'RV_ENDO'] : ['RV_ENDO', 'LV_ENDO'], landmarks: [], warnings: frame === null && timeFrames ? ['the file holds 2 time frames'] : [], session, timeFrames,
      contours: [
        { id: 'c1', surface: 'LV_ENDO', kind: null, pieces: [{ closed: true, start: 0, count: 3 }] },
        { id: 'r1', surface: 'RV_ENDO', kind: null, pieces: [{ closed: true, start: 0, count: 3 }] },
        { id: 'e1', surface: 'LV_EPI', kind: null, pieces: [{ closed: true, start: 0, count: 3 }] },
      ],
      points: new Float32Array([0, 0, 0, 10, 0, 0, 0, 10, frame === null ? 0 : fileName.startsWith('cine') ? Number(frame) : index]),
    };
  }
  frameLoads: [string, string | null][] = [];
  /** Frame 7 cannot be read (a bad number in its rows). */
  loadFrame(fileName: string, frame: string | null): Promise<LoadedFile> {
    this.frameLoads.push([fileName, frame]);
    if (frame === '7') return Promise.reject({ code: 'parse', message: 'line 40: bad number', line: 40, file: fileName });
    return Promise.resolve(this.loaded(fileName, null, frame));
  }
  run(opts: FakeRun['opts'], onFrame: (f: Frame) => void) {
    const runId = this.next++;
    let resolve!: (r: RunResult) => void;
    let reject!: (e: unknown) => void;
    const done = new Promise<RunResult>((a, b) => { resolve = a; reject = b; });
    const run: FakeRun = { runId, opts, onFrame, resolve, reject, cancelled: false };
    this.runs.push(run);
    return { runId, done, cancel: () => { run.cancelled = true; reject({ code: 'cancelled', message: 'cancelled' }); } };
  }
  walls: FakeRun['opts'][] = [];
  wallFile(opts: FakeRun['opts']) {
    this.walls.push(opts);
    return Promise.resolve({ summary: {}, bytes: new Uint8Array(0) });
  }
  sessions: { opts: FakeRun['opts']; appVersion: string }[] = [];
  sessionFile(opts: FakeRun['opts'], appVersion: string) {
    this.sessions.push({ opts, appVersion });
    return Promise.resolve(new Uint8Array([123, 125]));
  }
  dispose() {}
}

function report(iteration: number): StepReport {
  return {
    iteration, total_iterations: 10, phase: iteration === 0 ? 'initial_tube' : 'deform', topology_changed: iteration === 0,
    max_distance_mm: 5, mean_distance_mm: 1, vertices: 4, triangles: 4, attractors: 3,
    timings: { attractors_ms: 0, closest_ms: 0, solve_ms: 0, apply_ms: 0, remesh_ms: 0, total_ms: 0 }, done: false,
  };
}

function result(runId: number): RunResult {
  const stats = { mean: 0.4, median: 0.3, p95: 0.8, max: 0.9, min: 0, count: 3 };
  return {
    runId, surface: 'LV_ENDO', contours: [], contourPoints: new Float32Array(9), positions: new Float32Array(12),
    indices: new Uint32Array([0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3]), pointDistances: new Float32Array(3), vertexDistances: new Float32Array(4),
    perContour: [], overall: stats, volumeMl: 0.2, areaMm2: 200, watertight: true, seconds: 0.5, params: {}, lids: 'auto', options: { smoothing_method: 'laplacian-affine', soften_conflicts: true, align_slices: false, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true, drop_second_loops: false }, version: 'core-test',
  };
}

/** A stand-in whose every method records its calls. */
function recorder() {
  const calls: Record<string, unknown[][]> = {};
  const proxy = new Proxy({} as Record<string, unknown>, {
    get: (_t, key: string) => {
      if (key === 'calls') return calls;
      return (...args: unknown[]) => { (calls[key] ??= []).push(args); };
    },
  });
  return proxy as unknown as Record<string, (...a: unknown[]) => void> & { calls: Record<string, unknown[][]> };
}

let client: FakeClient;
let parts: Record<string, ReturnType<typeof recorder>>;
let controller: Controller;
let url: string;

beforeEach(() => {
  vi.useFakeTimers();
  url = '/app/?lambda=1e3&lids=none';
  vi.stubGlobal('location', {
    get pathname() { return url.split('?')[0]; },
    get search() { const i = url.indexOf('?'); return i < 0 ? '' : url.slice(i); },
    hash: '',
  });
  vi.stubGlobal('history', { replaceState: (_s: unknown, _t: string, u: string) => { url = u; } });
  vi.stubGlobal('document', { body: { dataset: {} }, baseURI: 'http://x/app/' });
  vi.stubGlobal('requestAnimationFrame', () => 0);
  vi.stubGlobal('cancelAnimationFrame', () => undefined);
  client = new FakeClient();
  parts = {
    legend: recorder(), meshLegend: recorder(), params: recorder(), timeline: recorder(), status: recorder(), plot: recorder(), result: recorder(),
    banner: recorder(), files: recorder(), exports: recorder(), view: recorder(), hover: recorder(), notes: recorder(),
  };
  controller = new Controller({ ...parts, viewer: null, warnings: { textContent: '', hidden: true } } as unknown as Parts, '9.9.9');
});

afterEach(() => {
  controller.dispose();
  vi.useRealTimers();
  vi.unstubAllGlobals();
});

/** A File's parts the controller uses: its bytes, and a slice of them (the first bytes, to tell a label map). */
const readable = (bytes: Uint8Array) => ({
  arrayBuffer: () => Promise.resolve(bytes.slice().buffer),
  slice: (from: number, to: number) => ({ arrayBuffer: () => Promise.resolve(bytes.slice(from, to).buffer) }),
});
/** A File that cannot be read (moved since the drop, a folder): its slices neither. */
const unreadableFile = (props: Record<string, string>, message: string) => {
  const arrayBuffer = () => Promise.reject(new Error(message));
  return { ...props, arrayBuffer, slice: () => ({ arrayBuffer }) } as unknown as File;
};
const file = (name: string, text = 'contour,x,y,z', lastModified?: number) => ({ name, size: text.length, lastModified, ...readable(new TextEncoder().encode(text)) }) as unknown as File;
/** A fake NIfTI label map (gzip's magic, then what the fake client's labelMapGrid reads): a stack or a single-slice view. */
const nifti = (name: string, kind: 'STACK' | 'VIEW') => {
  const bytes = new Uint8Array([0x1f, 0x8b, ...new TextEncoder().encode(kind)]);
  return { name, size: bytes.length, lastModified: 1, ...readable(bytes) } as unknown as File;
};
const lastStatus = () => parts.status.calls.setStatus?.at(-1)?.[0];
/** A ZIP archive (a real File: io/zipArchive.ts reads it in slices) of text members. */
const zip = (name: string, members: Record<string, string>) =>
  new File([zipSync(Object.fromEntries(Object.entries(members).map(([n, t]) => [n, new TextEncoder().encode(t)])))], name, { lastModified: 2 });

describe('controller', () => {
  it('label maps opened together: each long-axis view read with the stack of the closest name, none listed on its own', async () => {
    await controller.start(() => Promise.resolve(client as unknown as CoreClient));
    await controller.openFiles([
      nifti('001_LA_ES_gt.nii.gz', 'VIEW'), nifti('001_SA_ED_gt.nii.gz', 'STACK'), nifti('001_LA_ED_gt.nii.gz', 'VIEW'),
      file('notes.csv'), nifti('001_SA_ES_gt.nii.gz', 'STACK'),
    ]);
    expect(client.studyLoads).toEqual([
      ['001_SA_ED_gt.nii.gz', ['001_LA_ED_gt.nii.gz']], ['notes.csv', []], ['001_SA_ES_gt.nii.gz', ['001_LA_ES_gt.nii.gz']],
    ]);
    expect(parts.files.calls.setFiles?.at(-1)).toEqual([['001_SA_ED_gt.nii.gz', 'notes.csv', '001_SA_ES_gt.nii.gz'], '001_SA_ED_gt.nii.gz']);
    expect(client.runs.map((r) => r.opts.fileName)).toEqual(['001_SA_ED_gt.nii.gz']);
    expect(parts.banner.calls.showWarning).toBeUndefined();
    expect(parts.banner.calls.showInfo).toBeUndefined();
  });

  it('views opened alone go onto the NIfTI stack on screen (an info banner says so); onto another file they open alone', async () => {
    await controller.start(() => Promise.resolve(client as unknown as CoreClient));
    await controller.openFiles([nifti('seg_sa.nii.gz', 'STACK')]);
    await controller.openFiles([nifti('seg4_la_4ch.nii.gz', 'VIEW')]);
    expect(client.viewAdds).toEqual([['seg_sa.nii.gz', ['seg4_la_4ch.nii.gz']]]);
    expect(parts.banner.calls.showInfo?.at(-1)).toEqual(['seg4_la_4ch.nii.gz added to seg_sa.nii.gz as a long-axis view.']);
    expect(parts.files.calls.setFiles?.at(-1)).toEqual([['seg_sa.nii.gz'], 'seg_sa.nii.gz']);
    expect(client.runs.map((r) => r.opts.fileName)).toEqual(['seg_sa.nii.gz', 'seg_sa.nii.gz']);
    expect(client.runs[0].cancelled).toBe(true);
    await controller.openFiles([nifti('seg4_la_2ch.nii.gz', 'VIEW'), nifti('seg4_la_3ch.nii.gz', 'VIEW')]);
    expect(client.viewAdds.at(-1)).toEqual(['seg_sa.nii.gz', ['seg4_la_2ch.nii.gz', 'seg4_la_3ch.nii.gz']]);
    expect(parts.banner.calls.showInfo?.at(-1)).toEqual(['seg4_la_2ch.nii.gz, seg4_la_3ch.nii.gz added to seg_sa.nii.gz as long-axis views.']);
    // Opened again alone, the stack is read without views (they are forgotten with its reading).
    await controller.openFiles([nifti('seg_sa.nii.gz', 'STACK')]);
    expect(client.studyLoads.at(-1)).toEqual(['seg_sa.nii.gz', []]);
    // On a contour file: the view is opened as a file of its own (the core then says it needs its stack).
    await controller.openFiles([file('a.csv')]);
    await controller.openFiles([nifti('seg4_la_4ch.nii.gz', 'VIEW')]);
    expect(client.studyLoads.at(-1)).toEqual(['seg4_la_4ch.nii.gz', []]);
    expect(client.viewAdds).toHaveLength(2);
  });

  it('a damaged view: onto the stack on screen, refused with the stack kept and the view named; with its stack, neither opens', async () => {
    await controller.start(() => Promise.resolve(client as unknown as CoreClient));
    await controller.openFiles([nifti('seg_sa.nii.gz', 'STACK')]);
    client.runs[0].resolve(result(client.runs[0].runId));
    await vi.runAllTimersAsync();
    await controller.openFiles([nifti('cut_la.nii.gz', 'VIEW')]);
    expect(parts.banner.calls.showError?.at(-1)).toEqual([
      { code: 'parse', message: 'the gzip data is damaged', file: 'cut_la.nii.gz' }, ' Not added to seg_sa.nii.gz; still showing it as read before.',
    ]);
    expect(controller.currentResult()?.runId).toBe(client.runs[0].runId);
    expect(client.runs).toHaveLength(1);
    // Opened with a stack: the stack is refused with it, the banner names the view.
    await controller.openFiles([nifti('b_sa.nii.gz', 'STACK'), nifti('cut_lb.nii.gz', 'VIEW')]);
    expect(parts.banner.calls.showError?.at(-1)).toEqual([
      { code: 'parse', message: 'the gzip data is damaged', file: 'cut_lb.nii.gz' }, ' None of the 2 files opened: cut_lb.nii.gz: the gzip data is damaged (its stack b_sa.nii.gz is not opened either).',
    ]);
    expect(parts.files.calls.setFiles?.at(-1)?.[0]).toEqual(['seg_sa.nii.gz']);
  });

  it('reads parameters from the URL and runs a dropped file with the preferred surface', async () => {
    await controller.start(() => Promise.resolve(client as unknown as CoreClient));
    await controller.openFiles([file('a.csv')]);
    expect(client.runs).toHaveLength(1);
    expect(client.runs[0].opts.params.lambda).toBe(1000);
    expect(client.runs[0].opts.lids).toBe('none');
    expect(client.runs[0].opts.surface).toBe('LV_ENDO');
    expect(lastStatus()).toBe('running');
    expect(url).toBe('/app/?surface=LV_ENDO&lambda=1e3&lids=none');
  });

  it('sends the smoothing options with every run, keeps them in the URL and resets them', async () => {
    url = '/app/?smoothing_method=taubin&soften_conflicts=0';
    await controller.start(() => Promise.resolve(client as unknown as CoreClient));
    await controller.openFiles([file('a.csv')]);
    expect(client.runs[0].opts.options).toEqual({ smoothing_method: 'taubin', soften_conflicts: false, align_slices: false, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true, drop_second_loops: false });
    expect(parts.params.calls.setValues?.at(-1)?.[2]).toEqual({ smoothing_method: 'taubin', soften_conflicts: false, align_slices: false, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true, drop_second_loops: false });
    expect(controller.runSettings()?.options).toEqual({ smoothing_method: 'taubin', soften_conflicts: false, align_slices: false, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true, drop_second_loops: false });
    controller.setParams({}, 'auto', { smoothing_method: 'laplacian-affine', soften_conflicts: false, align_slices: false, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true, drop_second_loops: false });
    vi.advanceTimersByTime(RESTART_DEBOUNCE_MS + 10);
    expect(client.runs).toHaveLength(2);
    expect(client.runs[1].opts.options).toEqual({ smoothing_method: 'laplacian-affine', soften_conflicts: false, align_slices: false, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true, drop_second_loops: false });
    expect(url).toBe('/app/?surface=LV_ENDO&soften_conflicts=0');
    controller.resetParams();
    vi.advanceTimersByTime(RESTART_DEBOUNCE_MS + 10);
    expect(client.runs[2].opts.options).toEqual({ smoothing_method: 'laplacian-affine', soften_conflicts: true, align_slices: false, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true, drop_second_loops: false });
    expect(parts.params.calls.setValues?.at(-1)?.[2]).toEqual({ smoothing_method: 'laplacian-affine', soften_conflicts: true, align_slices: false, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true, drop_second_loops: false });
    expect(url).toBe('/app/?surface=LV_ENDO');
  });

  it('a session export asks the core with the settings now in the panel', async () => {
    expect(controller.sessionFile()).toBeNull();
    await controller.start(() => Promise.resolve(client as unknown as CoreClient));
    await controller.openFiles([file('a.csv')]);
    controller.setParams({ beta: 0.25 }, 'auto', { smoothing_method: 'taubin', soften_conflicts: false, align_slices: false, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true, drop_second_loops: false });
    expect(await controller.sessionFile()).toEqual(new Uint8Array([123, 125]));
    expect(client.sessions[0].appVersion).toBe('9.9.9');
    expect(client.sessions[0].opts).toMatchObject({
      fileName: 'a.csv', surface: 'LV_ENDO', lids: 'auto', options: { smoothing_method: 'taubin', soften_conflicts: false, align_slices: false, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true, drop_second_loops: false },
    });
    expect(client.sessions[0].opts.params).toMatchObject({ beta: 0.25, lambda: 1000 });
  });

  it('a loaded session file brings its parameters, lids, options and surface', async () => {
    await controller.start(() => Promise.resolve(client as unknown as CoreClient));
    await controller.openFiles([file('saved.json')]);
    const opts = client.runs[0].opts;
    expect(opts.params.beta).toBe(0.3);
    expect(opts.params.lambda).toBe(1e5); // the session's value replaces the URL's 1e3
    expect(opts.lids).toBe('none');
    expect(opts.surface).toBe('RV_ENDO');
    expect(opts.options).toEqual({ smoothing_method: 'taubin', soften_conflicts: false, align_slices: false, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true, drop_second_loops: false });
    expect(url).toContain('smoothing_method=taubin');
    expect(url).toContain('soften_conflicts=0');
    expect(url).not.toContain('apex_floor');
  });

  it('a loaded session with the apex floor off unticks it, runs without it and says so in the URL', async () => {
    await controller.start(() => Promise.resolve(client as unknown as CoreClient));
    await controller.openFiles([file('floor-off.json')]);
    expect(client.runs[0].opts.options?.apex_floor).toBe(false);
    expect((parts.params.calls.setValues?.at(-1)?.[2] as ReconOptions).apex_floor).toBe(false);
    expect(url).toContain('apex_floor=0');
    expect(controller.runSettings()?.options.apex_floor).toBe(false);
    // Saved again, the session keeps it off.
    await controller.sessionFile();
    expect(client.sessions.at(-1)?.opts.options?.apex_floor).toBe(false);
  });

  it('debounces parameter changes into one restart and cancels the old run', async () => {
    await controller.start(() => Promise.resolve(client as unknown as CoreClient));
    await controller.openFiles([file('a.csv')]);
    controller.setParams({ beta: 0.2 }, 'auto');
    vi.advanceTimersByTime(RESTART_DEBOUNCE_MS - 50);
    controller.setParams({ beta: 0.3 }, 'auto');
    vi.advanceTimersByTime(RESTART_DEBOUNCE_MS - 50);
    expect(client.runs).toHaveLength(1);
    vi.advanceTimersByTime(100);
    expect(client.runs).toHaveLength(2);
    expect(client.runs[0].cancelled).toBe(true);
    expect(client.runs[1].opts.params.beta).toBe(0.3);
    expect(url).toContain('beta=0.3');
    await Promise.resolve();
    expect(lastStatus()).toBe('running'); // the cancelled run's rejection is not an error
  });

  it('drops frames and results of a replaced run and shows the current one', async () => {
    await controller.start(() => Promise.resolve(client as unknown as CoreClient));
    await controller.openFiles([file('a.csv')]);
    const old = client.runs[0];
    controller.startRun();
    const cur = client.runs[1];
    old.onFrame({ runId: old.runId, seq: 0, report: report(0), positions: new Float32Array(12), indices: new Uint32Array(12) });
    expect(controller.debug.historyLength).toBe(0);
    cur.onFrame({ runId: cur.runId, seq: 0, report: report(0), positions: new Float32Array(12), indices: new Uint32Array(12) });
    cur.onFrame({ runId: cur.runId, seq: 1, report: report(1), positions: new Float32Array(12) });
    expect(controller.debug.historyLength).toBe(2);
    old.resolve(result(old.runId));
    await Promise.resolve();
    expect(lastStatus()).toBe('running');
    cur.resolve(result(cur.runId));
    await vi.runAllTimersAsync();
    expect(lastStatus()).toBe('done');
    expect(parts.result.calls.show).toHaveLength(1);
    expect(controller.exportInfo()).toMatchObject({ appVersion: '9.9.9', coreVersion: 'core-test', fileName: 'a.csv', surface: 'LV_ENDO' });
  });

  it('a bad file is an error naming the file and line; the previous file stays usable', async () => {
    await controller.start(() => Promise.resolve(client as unknown as CoreClient));
    await controller.openFiles([file('good.csv')]);
    await controller.openFiles([file('bad.csv', 'bad')]);
    expect(lastStatus()).toBe('error: bad.csv, line 2: bad number');
    expect(parts.banner.calls.showError).toHaveLength(1);
    controller.startRun();
    expect(client.runs.at(-1)?.opts.fileName).toBe('good.csv');
    expect(lastStatus()).toBe('running');
  });

  it('Stop ends the computation (and a restart waiting for its debounce); the steps stay, ↻ runs again', async () => {
    await controller.start(() => Promise.resolve(client as unknown as CoreClient));
    expect(parts.timeline.calls.setRunControls?.at(-1)).toEqual([false, false]); // no file: nothing to run yet
    await controller.openFiles([file('a.csv')]);
    const run = client.runs[0];
    expect(parts.timeline.calls.setRunControls?.at(-1)).toEqual([true, true]);
    run.onFrame({ runId: run.runId, seq: 0, report: report(0), positions: new Float32Array(12), indices: new Uint32Array(12) });
    run.onFrame({ runId: run.runId, seq: 1, report: report(1), positions: new Float32Array(12) });
    controller.setParams({ beta: 0.2 }, 'auto'); // a restart is waiting for its debounce ...
    controller.stopRun(); // ... and Stop comes first
    expect(run.cancelled).toBe(true);
    expect(lastStatus()).toBe('stopped');
    expect(parts.status.calls.setStatus?.at(-1)).toEqual(['stopped', 'stopped', run.runId]);
    expect(parts.timeline.calls.setRunControls?.at(-1)).toEqual([false, true]); // nothing to stop; ↻ runs again
    expect(parts.result.calls.clear?.at(-1)).toEqual(['stopped before the end: no result (↻ runs again)']);
    expect(controller.debug.historyLength).toBe(2); // the recorded steps stay to scrub through
    await vi.advanceTimersByTimeAsync(RESTART_DEBOUNCE_MS * 3);
    expect(client.runs).toHaveLength(1); // the pending restart did not start a run
    expect(lastStatus()).toBe('stopped'); // the cancelled run's rejection is not an error
    controller.stopRun(); // nothing going on: nothing happens
    expect(lastStatus()).toBe('stopped');
    controller.startRun();
    expect(client.runs).toHaveLength(2);
    expect(client.runs[1].opts.params.beta).toBe(0.2); // the change made before Stop is kept
    expect(lastStatus()).toBe('running');
  });

  it('several files dropped at once: every file not opened is named, and stays named after the run', async () => {
    await controller.start(() => Promise.resolve(client as unknown as CoreClient));
    const gone = unreadableFile({ name: 'moved.csv' }, 'the file could not be read (moved?)');
    await controller.openFiles([file('bad.csv', 'bad'), file('good.csv'), gone, file('worse.csv', 'bad')]);
    expect(client.runs).toHaveLength(1);
    expect(client.runs[0].opts.fileName).toBe('good.csv');
    expect(lastStatus()).toBe('running');
    const notice = 'bad.csv, line 2: bad number; moved.csv: the file could not be read (moved?); worse.csv, line 2: bad number';
    expect(parts.banner.calls.showWarning?.at(-1)).toEqual([`3 of 4 files not opened: ${notice}. Showing good.csv.`]);
    client.runs[0].resolve(result(client.runs[0].runId));
    await vi.runAllTimersAsync();
    expect(lastStatus()).toBe('done');
    expect(parts.banner.calls.hide ?? []).toHaveLength(1); // once, when good.csv opened; not at the end of its run
    expect(parts.banner.calls.hideError).toHaveLength(1); // ErrorBanner keeps a warning there
    // None opens: the error names them all.
    await controller.openFiles([file('bad.csv', 'bad'), file('worse.csv', 'bad')]);
    expect(lastStatus()).toBe('error: worse.csv, line 2: bad number');
    expect(parts.banner.calls.showError?.at(-1)?.[1]).toBe(' None of the 2 files opened: bad.csv, line 2: bad number; worse.csv, line 2: bad number.');
  });

  it('a cvi42 workspace opened with other files takes them all as its images; DICOM files without one open as before', async () => {
    await controller.start(() => Promise.resolve(client as unknown as CoreClient));
    await controller.openFiles([file('IM_2', 'DICM'), file('Contours.cvi42wsx', '<xml/>'), file('IM_1', 'DICM'), file('notes.txt')]);
    expect(client.studyLoads).toEqual([['Contours.cvi42wsx', ['IM_2', 'IM_1', 'notes.txt']]]);
    expect(client.runs.map((r) => r.opts.fileName)).toEqual(['Contours.cvi42wsx']);
    expect(parts.files.calls.setFiles?.at(-1)).toEqual([['Contours.cvi42wsx'], 'Contours.cvi42wsx']);
    expect(parts.banner.calls.showWarning).toBeUndefined();
    // An RTSTRUCT (a contour file of its own) without a workspace: read alone, as before.
    await controller.openFiles([file('rt.dcm')]);
    expect(client.studyLoads.at(-1)).toEqual(['rt.dcm', []]);
  });

  it('a workspace alone is refused with what to do; the images opened next are read with it', async () => {
    await controller.start(() => Promise.resolve(client as unknown as CoreClient));
    await controller.openFiles([file('Contours.cvi42wsx', '<xml/>')]);
    expect(lastStatus()).toMatch(/^error: Contours\.cvi42wsx: cvi42 workspace: .*open it together with the DICOM images it was drawn on/);
    expect(parts.banner.calls.showError?.at(-1)?.[1]).toBe(' Not opened. Open its images next (drop them, or the folder that holds them): they are read with it.');
    expect(controller.waitsForImages).toBe(true);
    await controller.openFiles([file('IM_1', 'DICM'), file('IM_2', 'DICM')]);
    expect(client.studyLoads.at(-1)).toEqual(['Contours.cvi42wsx', ['IM_1', 'IM_2']]);
    expect(client.runs.map((r) => r.opts.fileName)).toEqual(['Contours.cvi42wsx']);
    expect(controller.waitsForImages).toBe(false);
  });

  it('files opened after a refused workspace that are not its images open as they are, once', async () => {
    await controller.start(() => Promise.resolve(client as unknown as CoreClient));
    await controller.openFiles([file('Contours.cvi42wsx', '<xml/>')]);
    await controller.openFiles([file('rt.dcm')]);
    // Tried as the workspace's images, refused; then read as the contour file it is.
    expect(client.studyLoads.slice(-2)).toEqual([['Contours.cvi42wsx', ['rt.dcm']], ['rt.dcm', []]]);
    expect(client.runs.map((r) => r.opts.fileName)).toEqual(['rt.dcm']);
    expect(parts.files.calls.setFiles?.at(-1)).toEqual([['rt.dcm'], 'rt.dcm']);
    expect(controller.waitsForImages).toBe(false);
    await controller.openFiles([file('IM_1', 'DICM')]);
    expect(client.studyLoads.at(-1)).toEqual(['IM_1', []]);
  });

  it('ZIP archives open as their files: a zipped workspace with its zipped images, a zipped contour file', async () => {
    await controller.start(() => Promise.resolve(client as unknown as CoreClient));
    const workspace = zip('1234_cvi42.zip', { '1234_cvi42.cvi42wsx': '<xml/>' });
    const images = zip('1234_20209_2_0.zip', { 'dicom/IM_1.dcm': 'DICM', 'dicom/IM_2.dcm': 'DICM', 'manifest.cvs': 'x', '__MACOSX/dicom/._IM_1.dcm': 'fork' });
    await controller.openFiles([workspace, images]);
    expect(client.studyLoads).toEqual([['1234_cvi42.cvi42wsx', ['IM_1.dcm', 'IM_2.dcm', 'manifest.cvs']]]);
    expect(client.runs.map((r) => r.opts.fileName)).toEqual(['1234_cvi42.cvi42wsx']);
    expect(parts.files.calls.setFiles?.at(-1)).toEqual([['1234_cvi42.cvi42wsx'], '1234_cvi42.cvi42wsx']);
    expect(parts.banner.calls.showWarning).toBeUndefined();
    // A contour file zipped with a resource fork (macOS' Compress): the file alone.
    await controller.openFiles([zip('patient1-ED.zip', { 'export/patient1-ED.csv': 'contour,x,y,z', '__MACOSX/export/._patient1-ED.csv': 'fork' })]);
    expect(client.studyLoads.at(-1)).toEqual(['patient1-ED.csv', []]);
    expect(parts.files.calls.setFiles?.at(-1)?.[1]).toBe('patient1-ED.csv');
  });

  it('an archive that cannot be read is named: alone an error, beside files that open a warning, beside a workspace with it', async () => {
    await controller.start(() => Promise.resolve(client as unknown as CoreClient));
    const whole = zipSync({ 'a.csv': new TextEncoder().encode('contour,x,y,z') });
    const cut = () => new File([whole.slice(0, 20)], 'cut.zip', { lastModified: 1 });
    const why = 'cut.zip: ZIP archive: no end of central directory: truncated or not an archive';
    await controller.openFiles([cut()]);
    expect(lastStatus()).toBe(`error: ${why}`);
    expect(parts.banner.calls.showError?.at(-1)?.[1]).toBe(' Not opened.');
    expect(client.loads).toEqual([]);
    // Two, both cut: the first is the error, the second named after it.
    await controller.openFiles([cut(), new File([whole.slice(0, 30)], 'cut2.zip')]);
    expect(parts.banner.calls.showError?.at(-1)?.[1]).toBe(' Not opened. 1 archive not opened: cut2.zip: ZIP archive: no end of central directory: truncated or not an archive.');
    // Beside a file that opens: one of two files not opened.
    await controller.openFiles([cut(), file('good.csv')]);
    expect(client.runs.map((r) => r.opts.fileName)).toEqual(['good.csv']);
    expect(parts.banner.calls.showWarning?.at(-1)).toEqual([`1 of 2 files not opened: ${why}. Showing good.csv.`]);
    // A workspace whose images' archive is cut: refused for want of them, the archive named.
    await controller.openFiles([zip('1234_cvi42.zip', { '1234_cvi42.cvi42wsx': '<xml/>' }), cut()]);
    expect(lastStatus()).toMatch(/^error: 1234_cvi42\.cvi42wsx: cvi42 workspace: .*open it together with the DICOM images/);
    expect(parts.banner.calls.showError?.at(-1)?.[1]).toBe(
      ` Not opened; still showing good.csv. Open its images next (drop them, or the folder that holds them): they are read with it. 1 archive not opened: ${why}.`,
    );
    expect(controller.waitsForImages).toBe(true);
    // ... and the images' archive opened next is read with it.
    await controller.openFiles([zip('1234_20209_2_0.zip', { 'dicom/IM_1.dcm': 'DICM' })]);
    expect(client.studyLoads.at(-1)).toEqual(['1234_cvi42.cvi42wsx', ['IM_1.dcm']]);
    expect(client.runs.at(-1)?.opts.fileName).toBe('1234_cvi42.cvi42wsx');
  });

  it('a workspace that opens with its images while another archive is cut: a warning names the archive', async () => {
    await controller.start(() => Promise.resolve(client as unknown as CoreClient));
    const cut = new File([zipSync({ 'a.dcm': new Uint8Array(4) }).slice(0, 25)], 'lax.zip');
    await controller.openFiles([zip('1234_cvi42.zip', { '1234_cvi42.cvi42wsx': '<xml/>' }), zip('sax.zip', { 'IM_1.dcm': 'DICM' }), cut]);
    expect(client.runs.map((r) => r.opts.fileName)).toEqual(['1234_cvi42.cvi42wsx']);
    expect(parts.banner.calls.showWarning?.at(-1)).toEqual(['1 archive not opened: lax.zip: ZIP archive: no end of central directory: truncated or not an archive.']);
  });

  it('a SliceInfoFile dropped with its GPFile is read with it, not opened as contours; set aside beside other files', async () => {
    await controller.start(() => Promise.resolve(client as unknown as CoreClient));
    const info = file('SliceInfoFile.txt', 'IMG01.dcm  sliceID: 2  ImagePositionPatient -41.2 20.3 -13.4 ImageOrientationPatient 1 0 0 0 1 0 PixelSpacing 1.4 1.4');
    const gp = (name: string) => file(name, 'x\ty\tz\tcontour type\tframeID\n1\t2\t3\tSAX_LV_ENDOCARDIAL\t2');
    await controller.openFiles([info, gp('GPFile_000.txt'), gp('GPFile_009.txt')]);
    // Each GPFile goes to the core with the SliceInfoFile as its companion; the SliceInfoFile is not opened alone.
    expect(client.studyLoads).toEqual([['GPFile_000.txt', ['SliceInfoFile.txt']], ['GPFile_009.txt', ['SliceInfoFile.txt']]]);
    expect(client.runs.map((r) => r.opts.fileName)).toEqual(['GPFile_000.txt']);
    expect(parts.banner.calls.showWarning).toBeUndefined();
    expect(parts.banner.calls.showInfo?.at(-1)).toEqual(['SliceInfoFile.txt read with GPFile_000.txt, GPFile_009.txt: each contour checked against its image plane.']);
    // With a file that really was not opened, both are said, and only that one is counted.
    await controller.openFiles([gp('GPFile_000.txt'), info, file('bad.csv', 'bad')]);
    expect(parts.banner.calls.showWarning?.at(-1)?.[0]).toBe(
      '1 of 2 files not opened: bad.csv, line 2: bad number. SliceInfoFile.txt read with GPFile_000.txt: each contour checked against its image plane. Showing GPFile_000.txt.',
    );
    // Beside contours of another format (no GPFile to read it with): set aside, with a note.
    client.studyLoads.length = 0;
    await controller.openFiles([info, file('patient1-ED.csv')]);
    expect(client.studyLoads).toEqual([['SliceInfoFile.txt', []], ['patient1-ED.csv', []]]);
    expect(parts.banner.calls.showInfo?.at(-1)).toEqual([
      'SliceInfoFile.txt set aside: image planes, not contours (the contours come from patient1-ED.csv; a SliceInfoFile is read with the GPFile of its folder, to check that each contour lies in its own plane).',
    ]);
    // Alone (or with nothing that opens) it is refused as before, with what to open instead.
    await controller.openFiles([info]);
    expect(lastStatus()).toMatch(/^error: SliceInfoFile.txt, line 1: this is a biv-me SliceInfoFile .* read the GPFile_\*.txt beside it$/);
  });

  it('a dropped folder (no type, no extension, unreadable) is named as a folder, with what to open instead', async () => {
    await controller.start(() => Promise.resolve(client as unknown as CoreClient));
    const folder = unreadableFile({ name: 'bivme-example-patient1', type: '' }, 'The requested file could not be read, typically due to permission problems');
    await controller.openFiles([folder]);
    expect(lastStatus()).toBe('error: bivme-example-patient1: a folder cannot be opened: open the files inside it (of a biv-me folder, its GPFile_*.txt)');
    // A file with an extension that fails to read keeps the browser's reason.
    const moved = unreadableFile({ name: 'moved.csv', type: 'text/csv' }, 'the file could not be read (moved?)');
    await controller.openFiles([moved]);
    expect(lastStatus()).toBe('error: moved.csv: the file could not be read (moved?)');
  });

  it('a file refused while a run is in progress leaves that run going; a file that reads replaces it', async () => {
    await controller.start(() => Promise.resolve(client as unknown as CoreClient));
    await controller.openFiles([file('good.csv')]);
    const run = client.runs[0];
    await controller.openFiles([file('bad.csv', 'bad')]);
    expect(run.cancelled).toBe(false);
    expect(lastStatus()).toBe('error: bad.csv, line 2: bad number');
    const hidden = parts.banner.calls.hide?.length ?? 0;
    run.resolve(result(run.runId));
    await vi.runAllTimersAsync();
    expect(parts.result.calls.show).toHaveLength(1); // the run's result is shown ...
    expect(parts.banner.calls.hide?.length ?? 0).toBe(hidden); // ... and the refusal stays in the banner,
    // while the status line follows the run that went on: it finished, so it says done (with its run id).
    expect(lastStatus()).toBe('done');
    expect(parts.status.calls.setStatus?.at(-1)).toEqual(['done', 'done', run.runId]);
    expect(parts.exports.calls.setAvailable?.at(-1)).toEqual([true, true]);
    controller.startRun();
    await controller.openFiles([file('other.csv')]);
    expect(client.runs[1].cancelled).toBe(true);
    expect(client.runs.at(-1)?.opts.fileName).toBe('other.csv');
  });

  it('a file opened while the run is inside a step of seconds stops that run at once instead of waiting behind it', async () => {
    await controller.start(() => Promise.resolve(client as unknown as CoreClient));
    await controller.openFiles([file('heavy.csv')]);
    const heavy = client.runs[0];
    client.longStep = true;
    let stoppedFirst = false;
    const load = client.load.bind(client);
    client.load = (name: string, bytes: ArrayBuffer, behind?: () => void) => {
      const p = load(name, bytes, behind);
      // The client called back while the file waited: the run is stopped (its steps stay), still loading.
      stoppedFirst = heavy.cancelled && lastStatus() === 'loading next.csv';
      return p;
    };
    await controller.openFiles([file('next.csv')]);
    expect(stoppedFirst).toBe(true);
    expect(parts.result.calls.clear?.map((c) => c[0])).toContain('stopped before the end: no result (↻ runs again)');
    expect(client.runs.at(-1)?.opts.fileName).toBe('next.csv');
    expect(lastStatus()).toBe('running');
  });

  it('another file of a name already open is kept beside it, told apart by a suffix; the same file again replaces its entry', async () => {
    await controller.start(() => Promise.resolve(client as unknown as CoreClient));
    // Patient 1's GPFile_000.txt, then patient 2's (another file of the same name).
    await controller.openFiles([file('GPFile_000.txt', 'contour,x,y,z\np1', 1000)]);
    await controller.openFiles([file('GPFile_000.txt', 'contour,x,y,z\npatient2', 2000)]);
    expect(client.loads).toEqual(['GPFile_000.txt', 'GPFile_000 (2).txt']);
    expect(parts.files.calls.setFiles?.at(-1)).toEqual([['GPFile_000.txt', 'GPFile_000 (2).txt'], 'GPFile_000 (2).txt']);
    expect(client.runs.at(-1)?.opts.fileName).toBe('GPFile_000 (2).txt');
    expect(parts.banner.calls.showInfo?.at(-1)?.[0]).toBe('A file named GPFile_000.txt was already open: this one is listed as GPFile_000 (2).txt in the File picker.');
    // The first patient is still there to go back to.
    controller.chooseFile('GPFile_000.txt');
    expect(client.runs.at(-1)?.opts.fileName).toBe('GPFile_000.txt');
    // Patient 1's file opened again (same size and time): it replaces its own entry, no third one.
    await controller.openFiles([file('GPFile_000.txt', 'contour,x,y,z\np1', 1000)]);
    expect(parts.files.calls.setFiles?.at(-1)?.[0]).toEqual(['GPFile_000 (2).txt', 'GPFile_000.txt']);
    // Two of one name in a single drop (a search result across patient folders): both are kept.
    await controller.openFiles([file('GPFile_001.txt', 'contour,x,y,z\na', 5), file('GPFile_001.txt', 'contour,x,y,z\nbb', 6)]);
    expect(parts.files.calls.setFiles?.at(-1)).toEqual([['GPFile_000 (2).txt', 'GPFile_000.txt', 'GPFile_001.txt', 'GPFile_001 (2).txt'], 'GPFile_001.txt']);
    expect(parts.banner.calls.showInfo?.at(-1)?.[0]).toBe('A file named GPFile_001.txt was already open: this one is listed as GPFile_001 (2).txt in the File picker.');
  });

  it('a file dropped while the core is starting waits for it instead of being lost', async () => {
    let up!: (c: CoreClient) => void;
    const starting = controller.start(() => new Promise((r) => (up = r)));
    expect(lastStatus()).toBe('starting the core…');
    const opening = controller.openFiles([file('early.csv')]);
    expect(lastStatus()).toBe('loading early.csv');
    up(client as unknown as CoreClient);
    await starting;
    await opening;
    expect(client.runs).toHaveLength(1);
    expect(client.runs[0].opts.fileName).toBe('early.csv');
  });

  it('a failing run and an unavailable core are errors', async () => {
    await controller.start(() => Promise.resolve(client as unknown as CoreClient));
    await controller.openFiles([file('a.csv')]);
    client.runs[0].reject({ code: 'numerical', message: 'factorisation failed' });
    await vi.runAllTimersAsync();
    expect(lastStatus()).toBe('error: a.csv: factorisation failed');
    const c2 = new Controller({ ...parts, viewer: null, warnings: {} } as unknown as Parts, '1');
    await c2.start(() => Promise.reject({ code: 'worker_crashed', message: 'no wasm' }));
    expect(lastStatus()).toBe('error: no wasm');
    c2.dispose();
  });

  it('shows the core\'s growth note on the warning line while the run goes on, and drops it with the next run', async () => {
    const warnings = { textContent: '', hidden: true };
    const c = new Controller({ ...parts, warnings } as unknown as Parts, '9.9.9');
    await c.start(() => Promise.resolve(client as unknown as CoreClient));
    await c.openFiles([file('a.csv')]);
    const run = client.runs[0];
    const note = 'each remesh keeps 1.12x the triangles (x4 subdivision, 28 % kept), so the mesh reaches the 200000-triangle cap by about iteration 980 of 1500';
    run.onFrame({ runId: run.runId, seq: 0, report: report(0), positions: new Float32Array(12), indices: new Uint32Array(12), growthNote: note });
    expect(warnings.hidden).toBe(false);
    expect(warnings.textContent).toBe(`⚠ ${note}`);
    // A later frame without it keeps it; a new run clears it.
    run.onFrame({ runId: run.runId, seq: 1, report: report(1), positions: new Float32Array(12) });
    expect(warnings.textContent).toBe(`⚠ ${note}`);
    c.setParams({ iterations: 250 }, 'auto');
    await vi.runAllTimersAsync();
    expect(client.runs.length).toBe(2);
    expect(warnings.textContent).toBe('');
    expect(warnings.hidden).toBe(true);
    c.dispose();
  });

  it('sends align_slices from the URL; an aligned result shows the contours as given', async () => {
    const viewer = viewerRecorder();
    const c = new Controller({ ...parts, viewer, warnings: { textContent: '', hidden: true } } as unknown as Parts, '9.9.9');
    url = '/app/?align_slices=1';
    await c.start(() => Promise.resolve(client as unknown as CoreClient));
    await c.openFiles([file('a.csv')]);
    const run = client.runs[0];
    expect(run.opts.options).toEqual({ smoothing_method: 'laplacian-affine', soften_conflicts: true, align_slices: true, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true, drop_second_loops: false });
    expect(url).toBe('/app/?surface=LV_ENDO&align_slices=1');
    // While it runs, the first frame brings the shifted contours: they replace the file's on screen.
    const shifted = new Float32Array([1, 0, 0, 11, 0, 0, 1, 10, 0]);
    const contours = [{ id: 'c1', surface: 'LV_ENDO', kind: 'SAX' as const, pieces: [{ closed: true, start: 0, count: 3 }] }];
    run.onFrame({ runId: run.runId, seq: 0, report: report(0), positions: new Float32Array(12), indices: new Uint32Array(12), runContours: { contours, points: shifted } });
    expect(viewer.contourLayer.calls.set?.at(-1)?.[1]).toBe(shifted);
    expect(Array.from(viewer.givenLayer.calls.set?.at(-1)?.[1] as Float32Array)).toEqual([0, 0, 0, 10, 0, 0, 0, 10, 0]);
    expect(parts.view.calls.setAsGivenAvailable?.at(-1)).toEqual([true]);
    const alignment = { rounds: 3, residual_before_mm: 2, residual_after_mm: 0.5, groups: [] };
    run.resolve({ ...result(run.runId), alignment });
    await vi.runAllTimersAsync();
    expect(lastStatus()).toBe('done');
    (c as unknown as { runView: { display(now: number): void } }).runView.display(0); // one animation frame
    const given = viewer.givenLayer.calls.set?.at(-1);
    expect(given?.[2]).toBe('LV_ENDO');
    expect(Array.from(given?.[1] as Float32Array)).toEqual([0, 0, 0, 10, 0, 0, 0, 10, 0]); // the file's points as given
    expect(parts.view.calls.setAsGivenAvailable?.at(-1)).toEqual([true]);
    // Turning the option off and rerunning clears them.
    c.setParams({}, 'auto', { smoothing_method: 'laplacian-affine', soften_conflicts: true, align_slices: false, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true, drop_second_loops: false });
    vi.advanceTimersByTime(RESTART_DEBOUNCE_MS + 10);
    expect(url).toBe('/app/?surface=LV_ENDO');
    expect(client.runs[1].opts.options?.align_slices).toBe(false);
    expect(parts.view.calls.setAsGivenAvailable?.at(-1)).toEqual([false]);
    expect(viewer.givenLayer.calls.clear?.length).toBeGreaterThan(0);
    // ... and the file's own contours are back on screen for the unaligned run.
    expect(Array.from(viewer.contourLayer.calls.set?.at(-1)?.[1] as Float32Array)).toEqual([0, 0, 0, 10, 0, 0, 0, 10, 0]);
    c.dispose();
  });

  it('keeps each finished surface of the file for the other-surfaces view, hides the current one, forgets them with another file', async () => {
    const viewer = viewerRecorder();
    const layer = () => (viewer as unknown as Record<string, { calls: Record<string, unknown[][]> }>).otherSurfacesLayer.calls;
    const c = new Controller({ ...parts, viewer, warnings: { textContent: '', hidden: true } } as unknown as Parts, '9.9.9');
    await c.start(() => Promise.resolve(client as unknown as CoreClient));
    await c.openFiles([file('biv.csv')]);
    client.runs[0].resolve(result(client.runs[0].runId)); // LV_ENDO
    await vi.runAllTimersAsync();
    expect(layer().set?.at(-1)?.[0]).toBe('LV_ENDO');
    expect(layer().show?.at(-1)).toEqual([false, 'LV_ENDO']);
    c.chooseSurface('RV_ENDO');
    expect(layer().show?.at(-1)).toEqual([false, 'RV_ENDO']);
    // The LV's mesh is offered to the view toggle and the all-surfaces export.
    expect(parts.view.calls.setOthersAvailable?.at(-1)).toEqual([['LV_ENDO']]);
    expect(parts.exports.calls.setOthers?.at(-1)).toEqual([['LV_ENDO']]);
    expect(c.otherSurfaceMeshes().map((m) => [m.surface, m.indices.length])).toEqual([['LV_ENDO', 12]]);
    c.setView({ ...DEFAULT_VIEW, others: true });
    expect(layer().show?.at(-1)).toEqual([true, 'RV_ENDO']);
    expect(url).toContain('others_shown=1');
    const run = client.runs.at(-1)!;
    run.resolve({ ...result(run.runId), surface: 'RV_ENDO' });
    await vi.runAllTimersAsync();
    expect(layer().set?.at(-1)?.[0]).toBe('RV_ENDO');
    const clears = layer().clear?.length ?? 0;
    c.chooseSurface('LV_ENDO'); // same file: nothing forgotten
    expect(layer().clear?.length ?? 0).toBe(clears);
    await c.openFiles([file('other.csv')]);
    expect(layer().clear?.length ?? 0).toBe(clears + 1);
    expect(c.otherSurfaceMeshes()).toEqual([]);
    expect(parts.exports.calls.setOthers?.at(-1)).toEqual([[]]);
    c.dispose();
  });

  it('"All" runs every surface in turn, the current one last, with Other surfaces on; picking a surface drops the rest', async () => {
    const c = new Controller({ ...parts, viewer: viewerRecorder(), warnings: { textContent: '', hidden: true } } as unknown as Parts, '9.9.9');
    await c.start(() => Promise.resolve(client as unknown as CoreClient));
    await c.openFiles([file('biv.csv')]);
    expect(client.runs.length).toBe(1);
    expect(client.runs[0].opts.surface).toBe('LV_ENDO');
    c.runAllSurfaces(); // cancels the LV run in progress: RV first, then LV again
    expect(url).toContain('others_shown=1');
    expect(parts.view.calls.show?.at(-1)?.[0]).toMatchObject({ others: true });
    expect(client.runs.map((r) => r.opts.surface)).toEqual(['LV_ENDO', 'RV_ENDO']);
    expect(parts.files.calls.setSurfaces?.at(-1)?.[1]).toBe('RV_ENDO');
    let run = client.runs.at(-1)!;
    run.resolve({ ...result(run.runId), surface: 'RV_ENDO' });
    await vi.runAllTimersAsync();
    expect(client.runs.map((r) => r.opts.surface)).toEqual(['LV_ENDO', 'RV_ENDO', 'LV_ENDO']);
    run = client.runs.at(-1)!;
    run.resolve(result(run.runId));
    await vi.runAllTimersAsync();
    expect(client.runs.length).toBe(3); // done: nothing more queued
    expect(c.otherSurfaceMeshes().map((m) => m.surface)).toEqual(['RV_ENDO']);
    // Queued again, then a surface picked by hand: what was left is dropped.
    c.runAllSurfaces();
    expect(client.runs.at(-1)?.opts.surface).toBe('RV_ENDO');
    c.chooseSurface('LV_ENDO');
    run = client.runs.at(-1)!;
    run.resolve(result(run.runId));
    await vi.runAllTimersAsync();
    expect(client.runs.map((r) => r.opts.surface).slice(3)).toEqual(['RV_ENDO', 'LV_ENDO']);
    c.dispose();
  });

  it('"All" leaves out the biventricular epicardium, which wraps the others, unless it is the one on screen', async () => {
    const c = new Controller({ ...parts, viewer: viewerRecorder(), warnings: { textContent: '', hidden: true } } as unknown as Parts, '9.9.9');
    await c.start(() => Promise.resolve(client as unknown as CoreClient));
    await c.openFiles([file('heart.csv')]);
    const finish = async () => {
      const run = client.runs.at(-1)!;
      run.resolve({ ...result(run.runId), surface: run.opts.surface });
      await vi.runAllTimersAsync();
    };
    await finish();
    const first = client.runs.length;
    const current = client.runs.at(-1)!.opts.surface;
    expect(current).not.toBe('BIV_EPI');
    c.runAllSurfaces();
    await finish();
    await finish();
    const other = current === 'LV_EPI' ? 'RV_EPI' : 'LV_EPI';
    expect(client.runs.slice(first).map((r) => r.opts.surface)).toEqual([other, current]);
    c.chooseSurface('BIV_EPI');
    await finish();
    const before = client.runs.length;
    c.runAllSurfaces();
    for (let k = 0; k < 3; k++) await finish();
    expect(client.runs.slice(before).map((r) => r.opts.surface)).toEqual(['LV_EPI', 'RV_EPI', 'BIV_EPI']);
    c.dispose();
  });

  it('a file refused at load keeps the previous scene and its framing, and says so', async () => {
    const viewer = viewerRecorder();
    const c = new Controller({ ...parts, viewer, warnings: { textContent: '', hidden: true } } as unknown as Parts, '9.9.9');
    await c.start(() => Promise.resolve(client as unknown as CoreClient));
    await c.openFiles([file('good.csv')]);
    const framed = viewer.calls.frame?.length ?? 0;
    expect(framed).toBe(1);
    const contourSets = viewer.contourLayer.calls.set?.length ?? 0;
    await c.openFiles([file('bad.csv', 'bad')]);
    expect(viewer.calls.frame?.length).toBe(framed);
    expect(viewer.contourLayer.calls.set?.length ?? 0).toBe(contourSets);
    expect(parts.banner.calls.showError?.at(-1)?.[1]).toBe(' Not opened; still showing good.csv.');
    expect(c.currentFileData()?.fileName).toBe('good.csv');
    // Refused with nothing open before: the banner says only that.
    const fresh = new Controller({ ...parts, viewer: viewerRecorder(), warnings: {} } as unknown as Parts, '1');
    await fresh.start(() => Promise.resolve(client as unknown as CoreClient));
    await fresh.openFiles([file('bad.csv', 'bad')]);
    expect(parts.banner.calls.showError?.at(-1)?.[1]).toBe(' Not opened.');
    fresh.dispose();
    c.dispose();
  });

  it('a run that fails while a file is being read is reported with the refusal, not lost', async () => {
    await controller.start(() => Promise.resolve(client as unknown as CoreClient));
    await controller.openFiles([file('good.csv')]);
    const run = client.runs[0];
    // The next file takes a while to read; the run goes on meanwhile, and fails.
    const read = client.load.bind(client);
    let release!: () => void;
    client.load = (name: string, bytes: ArrayBuffer) => new Promise<LoadedFile>((ok, no) => { release = () => void read(name, bytes).then(ok, no); });
    const opening = controller.openFiles([file('bad.csv', 'bad')]);
    await vi.advanceTimersByTimeAsync(0);
    expect(lastStatus()).toBe('loading bad.csv');
    run.reject({ code: 'numerical', message: 'factorisation failed' });
    await vi.advanceTimersByTimeAsync(0);
    release();
    await opening;
    expect(lastStatus()).toBe('error: bad.csv, line 2: bad number');
    const [shown, context] = parts.banner.calls.showError?.at(-1) ?? [];
    expect((shown as { file: string }).file).toBe('bad.csv');
    expect(context).toBe(' Not opened; still showing good.csv. Meanwhile the run of good.csv failed: factorisation failed');
    expect(parts.result.calls.clear?.at(-1)?.[0]).toBe('no result (see the error)');
  });

  it('a run that fails while a refusal is showing becomes the error, with the refusal as a note', async () => {
    await controller.start(() => Promise.resolve(client as unknown as CoreClient));
    await controller.openFiles([file('good.csv')]);
    const run = client.runs[0];
    await controller.openFiles([file('bad.csv', 'bad')]);
    expect(run.cancelled).toBe(false);
    run.reject({ code: 'numerical', message: 'factorisation failed' });
    await vi.runAllTimersAsync();
    // Status line and banner agree on the newest problem; the refusal is not forgotten.
    expect(lastStatus()).toBe('error: good.csv: factorisation failed');
    const [shown, context] = parts.banner.calls.showError?.at(-1) ?? [];
    expect((shown as { message: string }).message).toBe('factorisation failed');
    expect(context).toBe(' Earlier: bad.csv, line 2: bad number (not opened).');
    // good.csv is still the file: a new run works on it.
    controller.startRun();
    expect(client.runs.at(-1)?.opts.fileName).toBe('good.csv');
    expect(lastStatus()).toBe('running');
  });

  it('a file read while a run fails replaces the run: no stale failure later', async () => {
    await controller.start(() => Promise.resolve(client as unknown as CoreClient));
    await controller.openFiles([file('one.csv')]);
    const run = client.runs[0];
    const read = client.load.bind(client);
    let release!: () => void;
    client.load = (name: string, bytes: ArrayBuffer) => new Promise<LoadedFile>((ok, no) => { release = () => void read(name, bytes).then(ok, no); });
    const opening = controller.openFiles([file('two.csv')]);
    await vi.advanceTimersByTimeAsync(0);
    run.reject({ code: 'numerical', message: 'factorisation failed' });
    await vi.advanceTimersByTimeAsync(0);
    release();
    await opening;
    expect(lastStatus()).toBe('running');
    expect(client.runs.at(-1)?.opts.fileName).toBe('two.csv');
    client.load = read;
    await controller.openFiles([file('bad.csv', 'bad')]);
    expect(parts.banner.calls.showError?.at(-1)?.[1]).toBe(' Not opened; still showing two.csv.');
  });

  it('the link\'s surface is used for a dropped file when it has it; otherwise the default, with a notice', async () => {
    url = '/app/?surface=RV_ENDO';
    const warnings = { textContent: '', hidden: true };
    const c = new Controller({ ...parts, viewer: null, warnings } as unknown as Parts, '9.9.9');
    await c.start(() => Promise.resolve(client as unknown as CoreClient));
    await c.openFiles([file('biv.csv')]);
    expect(client.runs.at(-1)?.opts.surface).toBe('RV_ENDO');
    expect(warnings.hidden).toBe(true);
    expect(url).toBe('/app/?surface=RV_ENDO');
    c.dispose();

    url = '/app/?surface=LA_ENDO';
    const w2 = { textContent: '', hidden: true };
    const c2 = new Controller({ ...parts, viewer: null, warnings: w2 } as unknown as Parts, '9.9.9');
    await c2.start(() => Promise.resolve(client as unknown as CoreClient));
    await c2.openFiles([file('biv.csv')]);
    expect(client.runs.at(-1)?.opts.surface).toBe('LV_ENDO');
    expect(w2.hidden).toBe(false);
    expect(w2.textContent).toBe('⚠ surface LA_ENDO is not in biv.csv: showing LV_ENDO');
    expect(url).toBe('/app/?surface=LV_ENDO');
    c2.dispose();
  });
});

describe('Frame picker', () => {
  const picker = () => parts.files.calls.setFrames?.at(-1)?.[0] as { value: string; options: { value: string }[] } | null;

  it('a file holding a sequence shows the picker; a frame picked reads the file again and runs, and goes in the link and the exports', async () => {
    await controller.start(() => Promise.resolve(client as unknown as CoreClient));
    await controller.openFiles([file('cine.txt')]);
    expect(picker()?.options.map((o) => o.value)).toEqual(['0', '9']);
    expect(picker()?.value).toBe('0');
    expect(client.runs).toHaveLength(1);
    expect(controller.exportInfo()?.frame).toBe('0');
    controller.chooseFrame('9');
    // Cancelled at once, as for a surface picked; the file is read again, then runs.
    expect(client.runs[0].cancelled).toBe(true);
    expect(lastStatus()).toBe('loading cine.txt');
    await vi.advanceTimersByTimeAsync(0);
    expect(client.frameLoads).toEqual([['cine.txt', '9']]);
    expect(client.runs).toHaveLength(2);
    expect(lastStatus()).toBe('running');
    expect(picker()?.value).toBe('9');
    expect(controller.currentFileData()?.points[8]).toBe(9);
    expect(controller.exportInfo()?.frame).toBe('9');
    expect(url).toBe('/app/?surface=LV_ENDO&frame=9&lambda=1e3&lids=none');
    // A file of one frame: no picker, nothing named; the choice stays for the next sequence.
    await controller.openFiles([file('a.csv')]);
    expect(picker()).toBeNull();
    expect(controller.exportInfo()?.frame).toBeNull();
    expect(client.frameLoads).toHaveLength(1);
    await controller.openFiles([file('cine-2.txt')]);
    await vi.advanceTimersByTimeAsync(0);
    expect(client.frameLoads.at(-1)).toEqual(['cine-2.txt', '9']);
    expect(client.runs.at(-1)?.opts.fileName).toBe('cine-2.txt');
    expect(client.runs.filter((r) => r.opts.fileName === 'cine-2.txt')).toHaveLength(1);
    expect(picker()?.value).toBe('9');
    // Back to the file's own reading.
    controller.chooseFrame('');
    await vi.advanceTimersByTimeAsync(0);
    expect(client.frameLoads.at(-1)).toEqual(['cine-2.txt', null]);
    expect(url).toBe('/app/?surface=LV_ENDO&lambda=1e3&lids=none');
  });

  it('the answer of a frame overtaken by another is not shown; a frame that cannot be read leaves the file as it was', async () => {
    await controller.start(() => Promise.resolve(client as unknown as CoreClient));
    await controller.openFiles([file('cine.txt')]);
    controller.chooseFrame('9');
    controller.chooseFrame('0');
    await vi.advanceTimersByTimeAsync(0);
    expect(client.runs).toHaveLength(2);
    expect(picker()?.value).toBe('0');
    controller.chooseFrame('7');
    await vi.advanceTimersByTimeAsync(0);
    expect(parts.banner.calls.showError?.at(-1)?.[0]).toMatchObject({ message: 'line 40: bad number', file: 'cine.txt' });
    expect(parts.banner.calls.showError?.at(-1)?.[1]).toBe(' Still showing cine.txt as read before.');
    expect(picker()?.value).toBe('0');
    expect(controller.runSettings()?.fileName).toBe('cine.txt');
    expect(controller.debug.state).toMatchObject({ kind: 'error', fileName: 'cine.txt' });
    expect(controller.debug.state).not.toHaveProperty('during');
  });

  it('another frame keeps the camera (the same heart: the phases compare on screen); another file is framed', async () => {
    const viewer = viewerRecorder();
    const c = new Controller({ ...parts, viewer, warnings: { textContent: '', hidden: true } } as unknown as Parts, '9.9.9');
    await c.start(() => Promise.resolve(client as unknown as CoreClient));
    await c.openFiles([file('cine.txt')]);
    expect(viewer.calls.frame).toHaveLength(1);
    c.chooseFrame('9');
    await vi.advanceTimersByTimeAsync(0);
    expect(client.runs.at(-1)?.opts.fileName).toBe('cine.txt');
    expect(viewer.calls.frame).toHaveLength(1);
    await c.openFiles([file('a.csv')]);
    expect(viewer.calls.frame).toHaveLength(2);
    c.dispose();
  });

  it("the link's frame is read of a sequence that has it; one that lacks it says so", async () => {
    url = '/app/?frame=9';
    await controller.start(() => Promise.resolve(client as unknown as CoreClient));
    await controller.openFiles([file('cine.txt')]);
    await vi.advanceTimersByTimeAsync(0);
    expect(client.frameLoads).toEqual([['cine.txt', '9']]);
    expect(client.runs).toHaveLength(1);
    url = '/app/?frame=5';
    const warnings = { textContent: '', hidden: true };
    const c = new Controller({ ...parts, viewer: null, warnings } as unknown as Parts, '9.9.9');
    await c.start(() => Promise.resolve(client as unknown as CoreClient));
    await c.openFiles([file('cine.txt')]);
    expect(warnings.textContent).toBe('⚠ frame 5 is not in cine.txt: showing frame 0 · the file holds 2 time frames');
    expect(client.frameLoads).toHaveLength(1);
    c.dispose();
  });

  it('frames written as text are chosen like numbers: in the picker, the link, the exports; the link\'s in any case', async () => {
    await controller.start(() => Promise.resolve(client as unknown as CoreClient));
    await controller.openFiles([file('phase.csv')]);
    expect(picker()?.options).toEqual([
      { value: 'ED', label: 'frame ED', disabled: false },
      { value: 'ES', label: 'frame ES', disabled: false },
    ]);
    expect(picker()?.value).toBe('ED');
    controller.chooseFrame('ES');
    await vi.advanceTimersByTimeAsync(0);
    expect(client.frameLoads).toEqual([['phase.csv', 'ES']]);
    expect(client.runs.at(-1)?.opts.fileName).toBe('phase.csv');
    expect(picker()?.value).toBe('ES');
    expect(controller.currentFileData()?.points[8]).toBe(1);
    expect(controller.exportInfo()?.frame).toBe('ES');
    expect(url).toBe('/app/?surface=LV_ENDO&frame=ES&lambda=1e3&lids=none');
    // A link's frame=es reads the file's ES (named as the file writes it), not a missing frame.
    url = '/app/?frame=es';
    const warnings = { textContent: '', hidden: true };
    const c = new Controller({ ...parts, viewer: null, warnings } as unknown as Parts, '9.9.9');
    await c.start(() => Promise.resolve(client as unknown as CoreClient));
    await c.openFiles([file('phase-2.csv')]);
    await vi.advanceTimersByTimeAsync(0);
    expect(client.frameLoads.at(-1)).toEqual(['phase-2.csv', 'ES']);
    expect(c.exportInfo()?.frame).toBe('ES');
    expect(warnings.textContent).toBe('');
    c.dispose();
  });
});

/** A Viewer stand-in: its layers and its own methods record their calls. */
function viewerRecorder() {
  const layers: Record<string, ReturnType<typeof recorder>> = {};
  const own = recorder();
  return new Proxy({} as Record<string, unknown>, {
    get: (_t, key: string) => (key.endsWith('Layer') ? (layers[key] ??= recorder()) : (own as unknown as Record<string, unknown>)[key]),
  }) as unknown as { calls: Record<string, unknown[][]> } & Record<'givenLayer' | 'contourLayer', { calls: Record<string, unknown[][]> }>;
}

describe('Keep specks and strays', () => {
  it('reaches the run, and the warning line says the contours it names as left out are used', async () => {
    const warnings = { textContent: '', hidden: true };
    const c = new Controller({ ...parts, viewer: null, warnings } as unknown as Parts, '9.9.9');
    await c.start(() => Promise.resolve(client as unknown as CoreClient));
    const read = client.load.bind(client);
    const line = 'contour "speck" (line 1793, 2.0 mm around, 1 % of the ring of "s02" one slice away) is a speck, not a section of the cavity; it is left out of the reconstruction';
    client.load = async (...args: Parameters<FakeClient['load']>) => ({ ...(await read(...args)), warnings: [line] });
    await c.openFiles([file('speck.csv')]);
    expect(warnings.textContent).toBe(`⚠ ${line}`);
    expect(client.runs.at(-1)?.opts.options?.keep_specks).toBe(false);
    const on: ReconOptions = { smoothing_method: 'laplacian-affine', soften_conflicts: true, align_slices: false, end_caps: DEFAULT_END_CAPS, keep_specks: true, apex_floor: true, drop_second_loops: false };
    c.setParams({}, 'auto', on);
    expect(warnings.textContent).toBe(`⚠ ${line} · Keep specks and strays is on: the contours named above as left out are used in the reconstruction`);
    await vi.advanceTimersByTimeAsync(RESTART_DEBOUNCE_MS + 10);
    expect(client.runs.at(-1)?.opts.options?.keep_specks).toBe(true);
    expect(url).toContain('keep_specks=1');
    c.setParams({}, 'auto', { ...on, keep_specks: false });
    expect(warnings.textContent).toBe(`⚠ ${line}`);
    c.dispose();
  });
});

describe('contours left out by hand (the Contours panel)', () => {
  const start = async () => {
    const c = new Controller({ ...parts, viewer: null, warnings: { textContent: '', hidden: true } } as unknown as Parts, '9.9.9');
    await c.start(() => Promise.resolve(client as unknown as CoreClient));
    return c;
  };
  /** Lets the debounced restart go (as after a parameter change). */
  const settle = () => vi.advanceTimersByTimeAsync(RESTART_DEBOUNCE_MS + 10);
  const finish = async (extra: Partial<RunResult> = {}) => {
    const run = client.runs.at(-1)!;
    run.resolve({ ...result(run.runId), surface: run.opts.surface, ...(run.opts.leaveOut ? { leave_out: [...run.opts.leaveOut] } : { leave_out: [] }), ...extra });
    await vi.runAllTimersAsync();
  };

  it('unticking one starts a new run without it, as a parameter change does; ticking it back runs with it again', async () => {
    const c = await start();
    await c.openFiles([file('a.csv')]);
    expect(client.runs[0].opts).not.toHaveProperty('leaveOut');
    const heard: string[][] = [];
    c.onLeaveOutChange(() => heard.push(c.leaveOutNow()));
    c.setLeftOut('c1', true);
    expect(heard).toEqual([['c1']]);
    expect(client.runs).toHaveLength(1); // debounced
    await settle();
    expect(client.runs).toHaveLength(2);
    expect(client.runs[0].cancelled).toBe(true);
    expect(client.runs[1].opts.leaveOut).toEqual(['c1']);
    expect(client.runs[1].opts.surface).toBe('LV_ENDO');
    expect(url).not.toContain('c1');
    expect(url).not.toContain('leave');
    // Left out already: nothing to run.
    c.setLeftOut('c1', true);
    await settle();
    expect(client.runs).toHaveLength(2);
    await finish();
    expect(c.exportInfo()?.leaveOut).toEqual(['c1']);
    c.setLeftOut('c1', false);
    await settle();
    expect(client.runs).toHaveLength(3);
    expect(client.runs[2].opts).not.toHaveProperty('leaveOut');
    expect(c.leaveOutNow()).toEqual([]);
    c.dispose();
  });

  it('"Use all" puts back this surface\'s contours (and ids no contour has) in one run; another surface\'s stay out', async () => {
    const c = await start();
    await c.openFiles([file('a.csv')]);
    c.setLeftOut('c1', true);
    c.setLeftOut('c2', true); // no contour of the file: no surface's choice to keep
    await settle();
    expect(client.runs.map((r) => r.opts.leaveOut)).toEqual([undefined, ['c1', 'c2']]);
    c.useAllContours();
    await settle();
    expect(client.runs).toHaveLength(3);
    expect(client.runs[2].opts).not.toHaveProperty('leaveOut');
    c.useAllContours(); // nothing left out: no run
    await settle();
    expect(client.runs).toHaveLength(3);
    // An RV_ENDO contour left out in the RV panel stays out when Use all is pressed on LV_ENDO.
    c.setLeftOut('c1', true);
    c.chooseSurface('RV_ENDO');
    c.setLeftOut('r1', true);
    c.chooseSurface('LV_ENDO');
    expect(client.runs.at(-1)?.opts).toMatchObject({ surface: 'LV_ENDO', leaveOut: ['c1', 'r1'] });
    const runs = client.runs.length;
    c.useAllContours();
    await settle();
    expect(client.runs).toHaveLength(runs + 1);
    expect(client.runs.at(-1)?.opts).toMatchObject({ surface: 'LV_ENDO', leaveOut: ['r1'] });
    expect(c.contourContext()?.leaveOut).toEqual([]); // none of the LV panel's rows: its Use all hides
    c.useAllContours(); // only another surface's left out: no run
    await settle();
    expect(client.runs).toHaveLength(runs + 1);
    c.dispose();
  });

  it('one list per file and frame: every surface\'s run leaves out every id, "All" too; the panel shows its own surface\'s', async () => {
    const c = await start();
    await c.openFiles([file('biv.csv')]);
    c.setLeftOut('c1', true);
    await settle();
    // An LV_ENDO contour left out, then RV_ENDO run: its run leaves the LV id out (the core takes
    // it out of the file: out of RV_ENDO's alignment and crossing gap, as the CLI's --leave-out).
    c.chooseSurface('RV_ENDO');
    expect(client.runs.at(-1)?.opts).toMatchObject({ surface: 'RV_ENDO', leaveOut: ['c1'] });
    expect(c.contourContext()).toEqual({ key: JSON.stringify({ file: 'biv.csv', frame: null, surface: 'RV_ENDO' }), leaveOut: [], fileContours: [{ id: 'r1', kind: null }] });
    c.setLeftOut('r1', true);
    await settle();
    expect(client.runs.at(-1)?.opts).toMatchObject({ surface: 'RV_ENDO', leaveOut: ['c1', 'r1'] });
    expect(c.contourContext()?.leaveOut).toEqual(['r1']);
    c.chooseSurface('LV_ENDO');
    expect(client.runs.at(-1)?.opts).toMatchObject({ surface: 'LV_ENDO', leaveOut: ['c1', 'r1'] });
    expect(c.contourContext()).toEqual({ key: JSON.stringify({ file: 'biv.csv', frame: null, surface: 'LV_ENDO' }), leaveOut: ['c1'], fileContours: [{ id: 'c1', kind: null }] });
    expect(c.leaveOutNow()).toEqual(['c1', 'r1']);
    const before = client.runs.length;
    c.runAllSurfaces();
    await finish();
    await finish();
    expect(client.runs.slice(before).map((r) => [r.opts.surface, r.opts.leaveOut])).toEqual([['RV_ENDO', ['c1', 'r1']], ['LV_ENDO', ['c1', 'r1']]]);
    // The all-surfaces OBJ names what the other surface's last run left out; the header, this run's.
    expect(c.otherSurfaceMeshes().map((m) => [m.surface, m.leaveOut])).toEqual([['RV_ENDO', ['c1', 'r1']]]);
    expect(c.exportInfo()?.leaveOut).toEqual(['c1', 'r1']);
    c.dispose();
  });

  it('a changed list leaves every surface\'s kept run stale for the wall, as a changed parameter does; the wall gets the whole list', async () => {
    const c = await start();
    await c.openFiles([file('wall.csv')]);
    await finish();
    c.chooseSurface('LV_EPI');
    await finish();
    expect(c.wallReadiness().ready).toBe(true);
    // An RV_ENDO contour left out: neither LV mesh was run without it.
    c.chooseSurface('RV_ENDO');
    c.setLeftOut('r1', true);
    expect(c.wallReadiness()).toMatchObject({ ready: false, title: expect.stringMatching(/: LV_ENDO and LV_EPI were last run with other parameters; run them again/) });
    expect(parts.exports.calls.setWall?.at(-1)?.[0]).toMatchObject({ ready: false });
    await settle();
    await finish();
    c.chooseSurface('LV_ENDO');
    await finish();
    expect(c.wallReadiness().title).toMatch(/: LV_EPI was last run with other parameters; run it again/);
    c.chooseSurface('LV_EPI');
    await finish();
    expect(c.wallReadiness().ready).toBe(true);
    expect(parts.exports.calls.setWall?.at(-1)?.[0]).toMatchObject({ ready: true });
    await c.wallFile('obj');
    expect(client.walls.map((w) => w.leaveOut)).toEqual([['r1']]);
    // Put back: stale again, whichever surface is on screen.
    c.chooseSurface('RV_ENDO');
    await finish();
    c.useAllContours();
    expect(c.wallReadiness().title).toMatch(/: LV_ENDO and LV_EPI were last run with other parameters/);
    c.dispose();
  });

  it('reading a file again forgets its lists; another file, and another frame, keep their own', async () => {
    const c = await start();
    await c.openFiles([file('a.csv')]);
    c.setLeftOut('c1', true);
    await c.openFiles([file('b.csv')]);
    c.setLeftOut('x', true);
    c.chooseFile('a.csv');
    expect(c.leaveOutNow()).toEqual(['c1']);
    expect(client.runs.at(-1)?.opts).toMatchObject({ fileName: 'a.csv', leaveOut: ['c1'] });
    await c.openFiles([file('a.csv')]); // the same name read anew
    expect(c.leaveOutNow()).toEqual([]);
    expect(client.runs.at(-1)?.opts).toMatchObject({ fileName: 'a.csv' });
    expect(client.runs.at(-1)?.opts).not.toHaveProperty('leaveOut');
    c.chooseFile('b.csv');
    expect(c.leaveOutNow()).toEqual(['x']);
    // A sequence: each frame's drawing is its own, so each frame has its own list.
    await c.openFiles([file('cine.csv')]);
    c.setLeftOut('c1', true);
    await settle();
    expect(client.runs.at(-1)?.opts.leaveOut).toEqual(['c1']);
    c.chooseFrame('9');
    await vi.runAllTimersAsync();
    expect(client.runs.at(-1)?.opts).not.toHaveProperty('leaveOut');
    c.chooseFrame('0');
    await vi.runAllTimersAsync();
    expect(client.runs.at(-1)?.opts.leaveOut).toEqual(['c1']);
    c.dispose();
  });

  it('a saved session carries every surface\'s ids; one opened brings them back as its file\'s list', async () => {
    const c = await start();
    await c.openFiles([file('a.csv')]);
    c.setLeftOut('c1', true);
    c.chooseSurface('RV_ENDO');
    c.setLeftOut('r1', true);
    await c.sessionFile();
    expect(client.sessions.at(-1)?.opts).toMatchObject({ fileName: 'a.csv', surface: 'RV_ENDO', leaveOut: ['c1', 'r1'] });
    // Saved on RV_ENDO with c1 (LV_ENDO) and r1 out: the RV run leaves both out, each panel shows its own.
    await c.openFiles([file('left-out.json')]);
    const run = client.runs.at(-1)!;
    expect(run.opts).toMatchObject({ fileName: 'left-out.json', surface: 'RV_ENDO', leaveOut: ['c1', 'r1'] });
    expect(c.leaveOutNow()).toEqual(['c1', 'r1']);
    expect(c.contourContext()?.leaveOut).toEqual(['r1']);
    c.chooseSurface('LV_ENDO');
    expect(client.runs.at(-1)?.opts).toMatchObject({ surface: 'LV_ENDO', leaveOut: ['c1', 'r1'] });
    expect(c.contourContext()?.leaveOut).toEqual(['c1']);
    // Its own list only: a.csv's is still a.csv's, a session without one brings none.
    await c.openFiles([file('saved.json')]);
    expect(client.runs.at(-1)?.opts).not.toHaveProperty('leaveOut');
    c.chooseFile('a.csv');
    expect(client.runs.at(-1)?.opts).toMatchObject({ fileName: 'a.csv', surface: 'RV_ENDO', leaveOut: ['c1', 'r1'] });
    c.dispose();
  });

  it('an id the core does not know fails the run in the banner, like any run error', async () => {
    const c = await start();
    await c.openFiles([file('a.csv')]);
    c.setLeftOut('nope', true);
    await settle();
    const error = { code: 'unknown_contour', message: 'leave_out: no contour "nope" in a.csv' };
    client.runs.at(-1)!.reject(error);
    await vi.runAllTimersAsync();
    expect(parts.banner.calls.showError?.at(-1)?.[0]).toMatchObject(error);
    expect(lastStatus()).toMatch(/^error: a\.csv: leave_out: no contour "nope"/);
    c.dispose();
  });

  it('the phases batch leaves out of each phase its file\'s list, the ids its contours have, and says so', async () => {
    const c = await start();
    await c.openFiles([file('a.csv')]);
    await c.openFiles([file('b.csv')]);
    const before = c.functionContext();
    expect(before?.leftOutNote).toBeNull();
    expect(before?.plan.phases.map((p) => p.leave_out)).toEqual([undefined, undefined]);
    c.setLeftOut('c1', true);
    c.setLeftOut('nope', true); // no contour of b.csv: it would fail the phase's every cell
    c.chooseSurface('RV_ENDO');
    c.setLeftOut('r1', true);
    const after = c.functionContext();
    expect(after?.leftOutNote).toBe('Left out, as in the Contours panel: 2 contours (b.csv: c1, r1)');
    // Only b.csv's phase carries them; the measurement taken before is stale (other settings).
    expect(after?.plan.phases.map((p) => [p.file, p.leave_out])).toEqual([['a.csv', undefined], ['b.csv', ['c1', 'r1']]]);
    expect(after?.settingsKey).not.toBe(before?.settingsKey);
    expect(after?.phasesKey).toBe(before?.phasesKey);
    c.useAllContours(); // RV_ENDO's r1 back ('nope' with it); LV_ENDO's c1 stays out
    expect(c.functionContext()?.plan.phases.map((p) => p.leave_out)).toEqual([undefined, ['c1']]);
    c.setLeftOut('c1', false);
    expect(c.functionContext()?.leftOutNote).toBeNull();
    expect(c.functionContext()?.settingsKey).toBe(before?.settingsKey);
    c.dispose();
  });

  it('the frames of a sequence: each phase its own frame\'s list', async () => {
    const c = await start();
    await c.openFiles([file('cine.csv')]);
    await vi.runAllTimersAsync();
    c.setLeftOut('c1', true);
    c.chooseFrame('9');
    await vi.runAllTimersAsync();
    c.chooseSurface('RV_ENDO');
    c.setLeftOut('r1', true);
    const ctx = c.functionContext();
    expect(ctx?.plan.phases.map((p) => [p.frame, p.leave_out])).toEqual([['0', ['c1']], ['9', ['r1']]]);
    expect(ctx?.leftOutNote).toBe('Left out, as in the Contours panel: 2 contours (cine.csv frame 0: c1; cine.csv frame 9: r1)');
    c.dispose();
  });
});
