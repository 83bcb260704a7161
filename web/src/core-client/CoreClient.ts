/**
 * The main thread's only door to the reconstruction core: an async API over the worker protocol
 * (protocol.ts). The wasm module lives in the worker; the main thread never blocks on geometry.
 *
 * - Every step of a run reaches `onFrame`, throttled to the display: at most one call per
 *   animation frame, with the newest step and, in `earlier`, every step since the previous call
 *   (frames that arrive in between are merged, topology and attractors carried over); the client
 *   acknowledges each frame it hands over, which lets the worker send more (back-pressure: the
 *   worker keeps at most two unacknowledged frames in flight and batches the steps meanwhile).
 * - One run at a time: starting a run cancels the previous one; a cancelled run's `done` rejects
 *   with `{ code: 'cancelled' }` and its late frames are dropped by run id.
 * - A worker crash (wasm trap, Rust panic, script error) rejects everything pending with
 *   `{ code: 'worker_crashed' }`; the next call starts a fresh worker and re-sends the loaded files.
 * - A cancel takes effect at once here, but the worker can only see it between two steps, and one
 *   step of a heavy input (a dense spline solve over 5000 attractors) takes seconds: whatever was
 *   asked after the cancel (the next run, a new file) would wait for it. When the worker has not
 *   answered a cancel within CANCEL_GRACE_MS it is replaced through the same teardown as after a
 *   crash, but on purpose: nothing is rejected and nobody hears of a crash; what the old worker had
 *   not answered yet (a load, a run that had not started) is posted again to the new one, the files
 *   it needs re-sent first.
 *
 * The frame throttling lives in runFrames.ts, the validation lab's requests and batches in
 * labRequests.ts, the public API types in coreClientTypes.ts (re-exported here); this module keeps
 * the worker's life cycle, requests, message routing and crash recovery.
 */

import {
  ErrorCodes,
  assertNever,
  stepsOf,
  isFatal,
  isFromWorker,
  toCoreErrorData,
  transferablesOf,
  type CoreErrorData,
  type Frame,
  type FromWorker,
  type AcquisitionSpec,
  type LabAcquisition,
  type LabBatchJob,
  type LabComparison,
  type LabProgress,
  type LabTruth,
  type LabTruthEdit,
  type LabTruthSource,
  type LabTruthSummary,
  type LabelMapGrid,
  type PhasesJob,
  type LoadedFile,
  type ParamSpec,
  type RunResult,
  type ToWorker,
  type ViewFile,
  type AnatomicalFormat,
  type AnatomicalStudy,
  type AnatomicalSummary,
  type HexSummary,
  type WallSummary,
  type WallSurfaceMesh,
} from './protocol';
import {
  settingsOf,
  type AnatomicalOptions,
  type BivWallOptions,
  type CoreClientOptions,
  type HexOptions,
  type LabBatchHandle,
  type RunHandle,
  type RunOptions,
  type WallOptions,
  type WorkerLike,
} from './coreClientTypes';
import { LabRequests } from './labRequests';
import { RunFrames } from './runFrames';
import { mergeViews } from '../io/studyGroups';

export type { AnatomicalOptions, BivWallOptions, CoreClientOptions, HexOptions, LabBatchHandle, RunHandle, RunOptions, WallOptions, WorkerLike } from './coreClientTypes';

interface PendingRequest {
  resolve: (value: unknown) => void;
  reject: (error: CoreErrorData) => void;
}

/**
 * How long a cancelled run may keep the worker busy before the worker is replaced. The worker sees
 * a cancel after the step in progress. On the bundled examples the longest step took 16 ms warm
 * and 42 ms on a page's first run (Chromium, 2 shared cores; Node: 10 and 43 ms), so 300 ms is
 * 7x the slowest: no ordinary Stop pays for a new worker, and a slower machine has room. Above it
 * the wait shows: the user's next action (a run, a file) waits at most this long plus a new
 * worker's start (~45 ms to 'ready' in Chromium) and the re-sent file's parse.
 */
export const CANCEL_GRACE_MS = 300;

/** A message the worker has not answered yet, to post again to a worker that replaces it. */
interface Unanswered {
  make: () => ToWorker;
  type: ToWorker['type'];
  /** The loaded files the message needs in the worker (re-sent first): a phases batch needs every phase's. */
  needs?: readonly string[];
  /** The file this message loads. */
  loads?: string;
}

function defaultCreateWorker(): WorkerLike {
  // Vite recognises this exact pattern and bundles the worker as a separate module chunk.
  const worker = new Worker(new URL('./reconstruct.worker.ts', import.meta.url), { type: 'module' });
  return worker as unknown as WorkerLike;
}

function defaultSchedule(callback: () => void): void {
  let fired = false;
  const once = () => {
    if (fired) return;
    fired = true;
    callback();
  };
  if (typeof requestAnimationFrame === 'function') requestAnimationFrame(once);
  // Animation frames pause in hidden tabs; the timer keeps runs finishing there.
  setTimeout(once, 100);
}

/** A mesh for a wall request, its arrays copied: the worker takes them, the app keeps its own. */
function copyMesh(m: WallSurfaceMesh): WallSurfaceMesh {
  return { surface: m.surface, positions: m.positions.slice(), indices: m.indices.slice() };
}

export class CoreClient {
  private readonly createWorker: () => WorkerLike;
  private readonly schedule: (callback: () => void) => void;
  private readonly onWorkerCrash: ((error: CoreErrorData) => void) | undefined;
  private readonly onWorkerRestart: (() => void) | undefined;
  private readonly cancelGraceMs: number;

  private worker: WorkerLike | null = null;
  private ready: Promise<void> | null = null;
  private readyResolve: (() => void) | null = null;
  private readyReject: ((e: CoreErrorData) => void) | null = null;

  private nextId = 1;
  private readonly requests = new Map<number, PendingRequest>();
  /** The run in progress (at most one), with its display-throttled frames. */
  private readonly runs: RunFrames;
  /** Bytes of every successfully loaded file, kept to re-send them to a recreated worker. */
  private readonly files = new Map<string, ArrayBuffer>();
  /**
   * The companion files each file is read with, kept for frame reloads and re-sends: the long-axis
   * views of a label-map stack, the DICOM image headers of a cvi42 workspace (io/dicomHeaders.ts).
   */
  private readonly views = new Map<string, ViewFile[]>();
  /** The time frame each file is read with, by label (absent: each contour's first), for those re-sends. */
  private readonly frames = new Map<string, string>();
  /** Per file, the id of its latest frame reload: an earlier one that fails must not undo it. */
  private readonly frameLoads = new Map<string, number>();
  /** Files the current worker has been sent. */
  private readonly workerFiles = new Set<string>();
  private schemaCache: { schema: ParamSpec[]; version: string } | null = null;
  /** By request/run id: what the current worker was asked and has not answered (or started) yet. */
  private readonly unanswered = new Map<number, Unanswered>();
  /** Cancels posted to the current worker and not yet acknowledged, with the grace timer. */
  private readonly awaitedCancels = new Set<number>();
  private graceTimer: ReturnType<typeof setTimeout> | null = null;
  /** Requests the worker said it is handling ('started'): it is busy with them, not inside a step. */
  private readonly handling = new Set<number>();
  /** performance.now() of the run's last sign of life from the worker (posted, or a frame), and its last step's cost. */
  private runActivityMs = 0;
  private lastStepMs = 0;
  /** The validation lab's requests and batches (labRequests.ts). */
  private readonly lab: LabRequests;
  private disposed = false;

  /** Use `CoreClient.create()` in the app; the constructor is for tests that inject a worker. */
  constructor(options: CoreClientOptions = {}) {
    this.createWorker = options.createWorker ?? defaultCreateWorker;
    this.schedule = options.schedule ?? defaultSchedule;
    this.onWorkerCrash = options.onWorkerCrash;
    this.onWorkerRestart = options.onWorkerRestart;
    this.cancelGraceMs = options.cancelGraceMs ?? CANCEL_GRACE_MS;
    this.runs = new RunFrames(this.schedule, (runId, seq) => this.post({ type: 'ack', runId, seq }));
    this.lab = new LabRequests({
      request: (make, files) => this.request(make, files),
      postRun: (runId, make, needs) => this.postRun(runId, make, needs),
      cancel: (runId) => this.postCancel(runId),
      hasWorker: () => this.worker !== null,
      newId: () => this.nextId++,
      disposedError: () => (this.disposed ? this.disposedError() : null),
      fileBytes: (fileName) => this.files.get(fileName),
      fileViews: (fileName) => this.views.get(fileName) ?? [],
      ensureWorker: () => void this.ensureWorker().catch(() => undefined),
      resendIfRecreated: (fileName, bytes, onError) => this.resendIfRecreated(fileName, bytes, onError),
    });
  }

  /** Spawns the worker and waits until its wasm module is initialised. */
  static async create(options: CoreClientOptions = {}): Promise<CoreClient> {
    const client = new CoreClient(options);
    await client.ensureWorker();
    return client;
  }

  /** Resolves once the current worker is ready (spawning one if needed). */
  whenReady(): Promise<void> {
    return this.ensureWorker();
  }

  schema(): Promise<{ schema: ParamSpec[]; version: string }> {
    if (this.schemaCache) return Promise.resolve(this.schemaCache);
    return this.request<{ schema: ParamSpec[]; version: string }>((reqId) => ({
      type: 'schema',
      reqId,
    })).then((s) => {
      this.schemaCache = s;
      return s;
    });
  }

  /**
   * Parses a contour file in the worker. Rejects with CoreErrorData (file and line named).
   * `whenBehindLongStep`: called (once) if the file waits in the worker behind a step of the run in
   * progress that has lasted longer than the cancel grace period; the caller may then cancel the
   * run, after which the file is read at once (by a new worker if the step does not end soon).
   */
  load(fileName: string, bytes: ArrayBuffer, whenBehindLongStep?: () => void, views: readonly ViewFile[] = []): Promise<LoadedFile> {
    // One copy stays here for crash recovery; the other is transferred to the worker.
    const kept = bytes.slice(0);
    this.files.set(fileName, kept);
    // A file (re)opened is read as it comes (each contour's first frame), with the views it came with.
    const keptViews = views.map((v) => ({ name: v.name, bytes: v.bytes.slice(0) }));
    this.setViews(fileName, keptViews);
    this.frames.delete(fileName);
    this.frameLoads.delete(fileName);
    const promise = this.request<LoadedFile>(
      (reqId) => ({ type: 'load', reqId, fileName, bytes: kept.slice(0), ...withViews(keptViews) }),
      { loads: fileName },
    );
    this.workerFiles.add(fileName);
    if (whenBehindLongStep) this.watchBehindLongStep(promise, whenBehindLongStep);
    return promise.catch((e: CoreErrorData) => {
      if (this.files.get(fileName) === kept && e.code !== ErrorCodes.workerCrashed) {
        this.files.delete(fileName);
        this.views.delete(fileName);
      }
      this.workerFiles.delete(fileName);
      throw e;
    });
  }

  /**
   * Reads a loaded file again, as time frame `frame` (null: each contour's first, as when it was
   * opened), from the bytes kept here; the worker's file (and what a new worker is re-sent) is
   * then that frame. Rejects with CoreErrorData; the file then stays as it was read before.
   */
  loadFrame(fileName: string, frame: string | null): Promise<LoadedFile> {
    const bytes = this.files.get(fileName);
    if (bytes === undefined) {
      return Promise.reject({ code: ErrorCodes.notLoaded, message: `${fileName} has not been loaded`, file: fileName });
    }
    const previous = this.frames.get(fileName);
    const setFrame = (f: string | null | undefined) => (f === null || f === undefined ? this.frames.delete(fileName) : this.frames.set(fileName, f));
    const withFrame = frame === null ? {} : { frame };
    const views = this.views.get(fileName) ?? [];
    const promise = this.request<LoadedFile>(
      (reqId) => ({ type: 'load', reqId, fileName, bytes: bytes.slice(0), ...withFrame, ...withViews(views) }),
      { loads: fileName },
    );
    const id = this.nextId++;
    this.frameLoads.set(fileName, id);
    setFrame(frame);
    this.workerFiles.add(fileName);
    return promise.catch((e: CoreErrorData) => {
      // The worker keeps its earlier reading of a file it could not read this way.
      if (this.frameLoads.get(fileName) === id) setFrame(previous);
      throw e;
    });
  }

  /**
   * Reads a loaded label-map stack again with long-axis views added to those it has (a view of the
   * same name replaces the older), as the time frame it is read as now. Rejects with CoreErrorData
   * (a view the core cannot read is named in the message); the file then stays as it was read.
   * `whenBehindLongStep`: as for `load`.
   */
  addViews(fileName: string, added: readonly ViewFile[], whenBehindLongStep?: () => void): Promise<LoadedFile> {
    const bytes = this.files.get(fileName);
    if (bytes === undefined) {
      return Promise.reject({ code: ErrorCodes.notLoaded, message: `${fileName} has not been loaded`, file: fileName });
    }
    const previous = this.views.get(fileName) ?? [];
    const views = mergeViews(previous, added.map((v) => ({ name: v.name, bytes: v.bytes.slice(0) })));
    const frame = this.frames.get(fileName);
    const withFrame = frame === undefined ? {} : { frame };
    const promise = this.request<LoadedFile>(
      (reqId) => ({ type: 'load', reqId, fileName, bytes: bytes.slice(0), ...withFrame, ...withViews(views) }),
      { loads: fileName },
    );
    this.setViews(fileName, views);
    this.workerFiles.add(fileName);
    if (whenBehindLongStep) this.watchBehindLongStep(promise, whenBehindLongStep);
    return promise.catch((e: CoreErrorData) => {
      // The worker keeps its earlier reading of the stack.
      if (this.views.get(fileName) === views) this.setViews(fileName, previous);
      throw e;
    });
  }

  /** The names of the long-axis views a loaded file is read with (none: empty). */
  viewsOf(fileName: string): string[] {
    return (this.views.get(fileName) ?? []).map((v) => v.name);
  }

  /**
   * The voxel grid of a label map (NIfTI-1, NRRD, DICOM SEG) from its header, read by the core
   * (null: not a label map). A single slice (a dimension of 1) is a long-axis view, to be read
   * with its stack.
   */
  labelMapGrid(bytes: ArrayBuffer): Promise<LabelMapGrid | null> {
    return this.request<LabelMapGrid | null>((reqId) => ({ type: 'grid', reqId, bytes: bytes.slice(0) }));
  }

  private setViews(fileName: string, views: ViewFile[]): void {
    if (views.length > 0) this.views.set(fileName, views);
    else this.views.delete(fileName);
  }

  /** Starts a reconstruction of a loaded file; cancels the run in progress, if any. */
  run(opts: RunOptions, onFrame: (f: Frame) => void): RunHandle {
    const runId = this.nextId++;
    let resolve!: (r: RunResult) => void;
    let reject!: (e: CoreErrorData) => void;
    const done = new Promise<RunResult>((res, rej) => {
      resolve = res;
      reject = rej;
    });
    const handle: RunHandle = { runId, done, cancel: () => this.cancelRun(runId) };

    if (this.disposed) {
      reject(this.disposedError());
      return handle;
    }
    const bytes = this.files.get(opts.fileName);
    if (bytes === undefined) {
      reject({
        code: ErrorCodes.notLoaded,
        message: `${opts.fileName} has not been loaded`,
        file: opts.fileName,
      });
      return handle;
    }
    for (const other of this.runs.ids()) this.cancelRun(other);

    this.runs.add(runId, onFrame, resolve, reject);
    void this.ensureWorker().catch(() => {
      // The crash handler already rejected this run.
    });
    this.resendIfRecreated(opts.fileName, bytes, (e) => this.runs.finish(runId, e));
    const settings = settingsOf(opts);
    this.postRun(runId, () => ({ type: 'run', runId, ...settings }), [opts.fileName]);
    return handle;
  }

  /**
   * Whether the run in progress keeps the worker inside one step for longer than the cancel grace
   * period (its last step took that long, or the worker has been silent that long since): anything
   * asked of the worker now would wait behind the step, so the caller may rather stop the run.
   */
  isInLongStep(now: number = performance.now()): boolean {
    if (this.runs.ids().length === 0 || !this.worker || this.handling.size > 0) return false;
    return this.lastStepMs > this.cancelGraceMs || now - this.runActivityMs > this.cancelGraceMs;
  }

  /** Calls `then` once if the run keeps the worker in a long step while `request` waits. */
  private watchBehindLongStep(request: Promise<unknown>, then: () => void): void {
    let settled = false;
    const check = () => {
      if (settled) return;
      if (this.isInLongStep()) {
        settled = true;
        clearInterval(timer);
        then();
      }
    };
    const timer = setInterval(check, Math.max(10, this.cancelGraceMs / 4));
    const stop = () => {
      settled = true;
      clearInterval(timer);
    };
    request.then(stop, stop);
    check();
  }

  /**
   * A recreated worker has lost the files: re-send this one first (the worker handles messages in
   * order, so a request posted next finds it); `onError` hears if the reload fails.
   */
  private resendIfRecreated(fileName: string, bytes: ArrayBuffer, onError: (e: CoreErrorData) => void): void {
    if (this.workerFiles.has(fileName)) return;
    const frame = this.frames.get(fileName);
    const withFrame = frame === undefined ? {} : { frame };
    const views = this.views.get(fileName) ?? [];
    this.request<LoadedFile>((reqId) => ({ type: 'load', reqId, fileName, bytes: bytes.slice(0), ...withFrame, ...withViews(views) }), { loads: fileName }).catch((e: CoreErrorData) => {
      this.workerFiles.delete(fileName);
      onError(e);
    });
    this.workerFiles.add(fileName);
  }

  /**
   * A heartmesh session file (the core's JSON: the file's contours with these settings), to open
   * again later with the same settings. Rejects with CoreErrorData (a bad setting is named).
   */
  sessionFile(opts: RunOptions, appVersion: string): Promise<Uint8Array> {
    const bytes = this.files.get(opts.fileName);
    if (bytes === undefined) {
      return Promise.reject({ code: ErrorCodes.notLoaded, message: `${opts.fileName} has not been loaded`, file: opts.fileName });
    }
    // A failed reload also fails the export request that follows it, which the caller hears.
    this.resendIfRecreated(opts.fileName, bytes, () => {});
    const settings = settingsOf(opts);
    return this.request<Uint8Array>((reqId) => ({ type: 'session-export', reqId, ...settings, appVersion }), { needs: opts.fileName });
  }

  /**
   * The LV myocardium wall of a loaded file, built in the worker from its finished endo- and
   * epicardial meshes (both run with the settings `opts`), as a file in `wall.format` with its
   * figures. Rejects with CoreErrorData: a wall the core cannot build says why (the worker goes on).
   */
  wallFile(opts: RunOptions, wall: WallOptions): Promise<{ summary: WallSummary; bytes: Uint8Array }> {
    return this.wallRequest(opts, (settings, reqId) => ({
      type: 'wall-export',
      reqId,
      ...settings,
      endo: copyMesh(wall.endo),
      epi: copyMesh(wall.epi),
      minThicknessMm: wall.minThicknessMm,
      format: wall.format,
      header: [...wall.header],
    }));
  }

  /**
   * The biventricular myocardium of a loaded file, built in the worker from its finished LV_ENDO,
   * RV_ENDO and BIV_EPI meshes (all run with the settings `opts`), as a file in `wall.format` with
   * its figures. Rejects with CoreErrorData ("the biventricular wall: ..."; the worker goes on).
   */
  bivWallFile(opts: RunOptions, wall: BivWallOptions): Promise<{ summary: WallSummary; bytes: Uint8Array }> {
    return this.wallRequest(opts, (settings, reqId) => ({
      type: 'biv-wall-export',
      reqId,
      ...settings,
      lvEndo: copyMesh(wall.lvEndo),
      rvEndo: copyMesh(wall.rvEndo),
      bivEpi: copyMesh(wall.bivEpi),
      minThicknessMm: wall.minThicknessMm,
      format: wall.format,
      header: [...wall.header],
    }));
  }

  /**
   * The anatomical mesh of a loaded file's finished LV surface (`a.mesh`, run with the settings
   * `opts`): `a.rings` x `a.points` from the apex to the base, as a file in `a.format` with its
   * figures. Rejects with CoreErrorData: a surface or file that can have none says why ("the
   * anatomical mesh: ..."; the worker goes on).
   */
  anatomicalFile(opts: RunOptions, a: AnatomicalOptions): Promise<{ summary: AnatomicalSummary; bytes: Uint8Array }> {
    return this.wallRequest<AnatomicalSummary>(opts, (settings, reqId) => ({
      type: 'anatomical-export',
      reqId,
      ...settings,
      mesh: copyMesh(a.mesh),
      rings: a.rings,
      points: a.points,
      format: a.format,
      header: [...a.header],
    }));
  }

  /**
   * The LV wall of a loaded file as layers of hexahedra (`myocardium --hex-mesh`), built in the
   * worker between the anatomical layouts of its finished LV_ENDO and LV_EPI meshes (both run with
   * the settings `opts`): a VTK unstructured grid with its figures. Rejects with CoreErrorData: a
   * file that does not say where the septum is, or a value out of range, says why ("the hexahedral
   * wall: ..."; the worker goes on).
   */
  hexFile(opts: RunOptions, hex: HexOptions): Promise<{ summary: HexSummary; bytes: Uint8Array }> {
    return this.wallRequest<HexSummary>(opts, (settings, reqId) => ({
      type: 'hex-export',
      reqId,
      ...settings,
      endo: copyMesh(hex.endo),
      epi: copyMesh(hex.epi),
      rings: hex.rings,
      points: hex.points,
      layers: hex.layers,
      header: [...hex.header],
    }));
  }

  /**
   * A wall (or anatomical mesh) request for a loaded file (the file sent again if the worker was
   * recreated), with the run settings of `opts` but no surface: the request names its meshes' own.
   */
  private wallRequest<S = WallSummary>(
    opts: RunOptions,
    message: (settings: Omit<ReturnType<typeof settingsOf>, 'surface'>, reqId: number) => ToWorker,
  ): Promise<{ summary: S; bytes: Uint8Array }> {
    const bytes = this.files.get(opts.fileName);
    if (bytes === undefined) {
      return Promise.reject({ code: ErrorCodes.notLoaded, message: `${opts.fileName} has not been loaded`, file: opts.fileName });
    }
    this.resendIfRecreated(opts.fileName, bytes, () => {});
    const { surface: _surface, ...settings } = settingsOf(opts);
    return this.request<{ summary: S; bytes: Uint8Array }>((reqId) => message(settings, reqId), { needs: opts.fileName });
  }

  // ---- validation lab ------------------------------------------------------------------------

  /**
   * Makes the lab's ground-truth surface (parametric LV or a mesh file) in the worker, replacing
   * the truths held, or (`add`) a mesh beside them; `label`: its surface label.
   */
  labTruth(source: LabTruthSource, opts: { add?: boolean; label?: string | null } = {}): Promise<LabTruth> {
    return this.lab.truth(source, opts);
  }

  /** Relabels or removes one of the lab's truths; resolves to the truths left, in order. */
  labEditTruth(edit: LabTruthEdit): Promise<LabTruthSummary[]> {
    return this.lab.edit(edit);
  }

  /** Slices the truth like a CMR acquisition; resolves to the contours as CSV bytes. */
  labSimulate(acquisition: AcquisitionSpec): Promise<LabAcquisition> {
    return this.lab.simulate(acquisition);
  }

  /**
   * Compares a mesh of `surface` with the truth of that label (one truth: that one), clipped at
   * the last acquisition's most basal SAX plane.
   */
  labCompare(positions: Float32Array, indices: Uint32Array, surface: string | null = null): Promise<LabComparison> {
    return this.lab.compare(positions, indices, surface);
  }

  /** Starts a leave-one-out or a parameter sweep on a loaded file; replaces a batch in progress. */
  labBatch(job: LabBatchJob, onProgress: (p: LabProgress) => void): LabBatchHandle {
    return this.lab.batch(job, onProgress);
  }

  /**
   * Reconstructs every surface of every phase of one heart at these settings, for its function
   * (EDV/ESV/SV/EF, LV mass): one cell per progress item, the summary with the last progress.
   * It runs beside the reconstruction on screen; it replaces a lab batch in progress (and a lab
   * batch started later replaces it).
   */
  measurePhases(job: PhasesJob, onProgress: (p: LabProgress) => void): LabBatchHandle {
    return this.lab.phases(job, onProgress);
  }

  /**
   * The anatomical meshes of the last finished phases batch (`measurePhases`), as the command
   * line's `volumes --anatomical-meshes` writes them: every phase's LV surfaces on `layout` (rings
   * x points), one septum for the study, each file with its vertices' displacement from the LV's
   * end-diastole. Rejects with the core's error, its message saying why ("the anatomical meshes:
   * ..."; no finished phases batch, no LV surface, no phase saying where the septum is); the worker
   * goes on.
   */
  phasesAnatomical(layout: { rings: number; points: number }, format: AnatomicalFormat): Promise<AnatomicalStudy> {
    return this.lab.phasesAnatomical(layout, format);
  }

  /** Terminates the worker and rejects everything pending with `{ code: 'disposed' }`. */
  dispose(): void {
    if (this.disposed) return;
    this.disposed = true;
    const error = this.disposedError();
    this.readyReject?.(error);
    this.teardownWorker(error);
    this.files.clear();
    this.views.clear();
    this.frames.clear();
  }

  // -------------------------------------------------------------------------------------------

  private disposedError(): CoreErrorData {
    return { code: ErrorCodes.disposed, message: 'the core client was disposed' };
  }

  private ensureWorker(): Promise<void> {
    if (this.disposed) return Promise.reject(this.disposedError());
    if (this.worker && this.ready) return this.ready;
    const worker = this.createWorker();
    this.worker = worker;
    this.workerFiles.clear();
    this.ready = new Promise<void>((resolve, reject) => {
      this.readyResolve = resolve;
      this.readyReject = reject;
    });
    // Avoid unhandled-rejection noise when nobody awaits readiness.
    this.ready.catch(() => undefined);
    worker.onmessage = (ev) => {
      if (this.worker !== worker) return;
      this.onMessage(ev.data);
    };
    worker.onerror = (ev) => {
      if (this.worker !== worker) return;
      ev.preventDefault?.();
      this.crash(ev.message ? `worker error: ${ev.message}` : 'the worker failed');
    };
    worker.onmessageerror = () => {
      if (this.worker !== worker) return;
      this.crash('a worker message could not be deserialised');
    };
    return this.ready;
  }

  private post(msg: ToWorker): void {
    if (!this.worker) {
      void this.ensureWorker().catch(() => undefined);
    }
    this.worker?.postMessage(msg, transferablesOf(msg));
  }

  /**
   * `make` builds the message (again, with fresh copies of its buffers, if it has to go to a
   * worker that replaces a stuck one); `files` names the file it needs or loads.
   */
  private request<T>(make: (reqId: number) => ToWorker, files: { needs?: string; loads?: string } = {}): Promise<T> {
    if (this.disposed) return Promise.reject(this.disposedError());
    const reqId = this.nextId++;
    const promise = new Promise<T>((resolve, reject) => {
      this.requests.set(reqId, { resolve: resolve as (v: unknown) => void, reject });
    });
    void this.ensureWorker().catch(() => undefined);
    const msg = make(reqId);
    const needs = files.needs === undefined ? {} : { needs: [files.needs] };
    const loads = files.loads === undefined ? {} : { loads: files.loads };
    this.unanswered.set(reqId, { make: () => make(reqId), type: msg.type, ...needs, ...loads });
    this.post(msg);
    return promise;
  }

  /** Posts a run or lab batch, remembered until the worker starts it (see restartStuckWorker). */
  private postRun(runId: number, make: () => ToWorker, needs: readonly string[]): void {
    const msg = make();
    this.unanswered.set(runId, { make, type: msg.type, needs });
    if (msg.type === 'run') {
      this.runActivityMs = performance.now();
      this.lastStepMs = 0;
    }
    this.post(msg);
  }

  /**
   * Asks the worker to cancel `runId`; when it has not acknowledged within the grace period (it is
   * inside a long step), it is replaced. The period starts once the worker is ready: one still
   * loading its wasm handles the cancel right after.
   */
  private postCancel(runId: number): void {
    if (!this.worker) return;
    const worker = this.worker;
    this.unanswered.delete(runId);
    this.awaitedCancels.add(runId);
    this.post({ type: 'cancel', runId });
    if (this.graceTimer !== null) return;
    void this.ready?.then(() => {
      if (this.worker !== worker || this.graceTimer !== null || this.awaitedCancels.size === 0) return;
      const expire = () => {
        this.graceTimer = null;
        if (this.worker !== worker || this.awaitedCancels.size === 0) return;
        // Busy reading a file (it said so), not inside a step: give it another period.
        if (this.handling.size > 0) this.graceTimer = setTimeout(expire, this.cancelGraceMs);
        else this.restartStuckWorker();
      };
      this.graceTimer = setTimeout(expire, this.cancelGraceMs);
    }, () => undefined);
  }

  private onCancelled(runId: number): void {
    this.awaitedCancels.delete(runId);
    if (this.awaitedCancels.size === 0) this.clearGraceTimer();
  }

  private clearGraceTimer(): void {
    if (this.graceTimer !== null) clearTimeout(this.graceTimer);
    this.graceTimer = null;
    this.awaitedCancels.clear();
  }

  /** Whether `id` is a request, run or lab batch still waiting for its answer. */
  private isPending(id: number): boolean {
    return this.requests.has(id) || this.runs.has(id) || this.lab.has(id);
  }

  /**
   * The worker did not acknowledge a cancel in time: it is computing one long step of a run nobody
   * wants any more. It is replaced (the teardown of a crash, without rejecting anything or telling
   * onWorkerCrash); everything it had not answered yet goes to the new worker in the order it was
   * asked, each after the file it needs. A run or batch it had already started (one that was not
   * cancelled) cannot be moved: it fails with `worker_crashed`, as if the worker had died.
   */
  private restartStuckWorker(): void {
    const moved = [...this.unanswered].filter(([id]) => this.isPending(id)).sort((a, b) => a[0] - b[0]);
    const movedIds = new Set(moved.map(([id]) => id));
    const started = [...this.runs.ids(), ...this.lab.ids()].filter((id) => !movedIds.has(id));
    this.unanswered.clear();
    this.teardownWorker(null);
    for (const id of started) {
      this.failPending(id, { code: ErrorCodes.workerCrashed, message: 'the engine was restarted to end a long step of another run' });
    }
    this.onWorkerRestart?.();
    void this.ensureWorker().catch(() => undefined);
    if (moved.some(([, u]) => u.type.startsWith('lab-') && u.type !== 'lab-truth')) this.lab.restoreInWorker();
    for (const [id, u] of moved) {
      for (const file of u.needs ?? []) {
        const bytes = this.files.get(file);
        if (bytes !== undefined) this.resendIfRecreated(file, bytes, (e) => this.failPending(id, e));
      }
      if (u.loads !== undefined) this.workerFiles.add(u.loads);
      this.unanswered.set(id, u);
      this.post(u.make());
    }
    this.runActivityMs = performance.now();
  }

  /** Rejects a request, run or batch by id. */
  private failPending(id: number, error: CoreErrorData): void {
    this.settleRequest(id, false, error);
    this.runs.finish(id, error);
    this.lab.finishBatch(id, error);
  }

  private settleRequest(reqId: number, ok: boolean, value: unknown): void {
    const req = this.requests.get(reqId);
    if (!req) return;
    this.requests.delete(reqId);
    this.unanswered.delete(reqId);
    this.handling.delete(reqId);
    if (ok) req.resolve(value);
    else req.reject(value as CoreErrorData);
  }

  private onMessage(data: unknown): void {
    if (!isFromWorker(data)) {
      console.warn('CoreClient: ignoring a message outside the protocol', data);
      return;
    }
    const msg: FromWorker = data;
    switch (msg.type) {
      case 'ready':
        this.readyResolve?.();
        break;
      case 'loaded':
        this.settleRequest(msg.reqId, true, msg.file);
        break;
      case 'grid':
        this.settleRequest(msg.reqId, true, msg.grid);
        break;
      case 'schema':
        this.settleRequest(msg.reqId, true, { schema: msg.schema, version: msg.version });
        break;
      case 'frame':
        if (this.runs.has(msg.runId)) {
          this.unanswered.delete(msg.runId); // started: it can no longer move to another worker
          this.runActivityMs = performance.now();
          this.lastStepMs = Math.max(0, ...stepsOf(msg).map((st) => st.report.timings.total_ms));
        }
        this.runs.onFrameMessage(msg);
        break;
      case 'cancelled':
        this.onCancelled(msg.runId);
        break;
      case 'started':
        if (this.requests.has(msg.reqId)) this.handling.add(msg.reqId);
        break;
      case 'lab-truth':
        this.settleRequest(msg.reqId, true, msg.truth);
        break;
      case 'lab-truths':
        this.settleRequest(msg.reqId, true, msg.truths);
        break;
      case 'lab-simulated':
        this.settleRequest(msg.reqId, true, msg.acquisition);
        break;
      case 'lab-compared':
        this.settleRequest(msg.reqId, true, msg.comparison);
        break;
      case 'lab-phases-anatomical':
        this.settleRequest(msg.reqId, true, msg.study);
        break;
      case 'session-json':
        this.settleRequest(msg.reqId, true, msg.bytes);
        break;
      case 'wall-file':
      case 'anatomical-file':
      case 'hex-file':
        this.settleRequest(msg.reqId, true, { summary: msg.summary, bytes: msg.bytes });
        break;
      case 'lab-batch-started':
        this.unanswered.delete(msg.runId);
        this.lab.onStarted(msg.runId, msg.info);
        break;
      case 'lab-progress':
        this.lab.onProgress(msg.runId, msg.progress);
        break;
      case 'lab-batch-done':
        this.lab.finishBatch(msg.runId, null);
        break;
      case 'done':
        this.unanswered.delete(msg.result.runId);
        this.runs.onDone(msg.result);
        break;
      case 'error':
        if (isFatal(msg.error)) {
          this.crash(msg.error.message, msg.error);
          break;
        }
        if (msg.reqId !== undefined) this.settleRequest(msg.reqId, false, msg.error);
        if (msg.runId !== undefined) {
          this.unanswered.delete(msg.runId);
          this.runs.finish(msg.runId, msg.error);
          this.lab.finishBatch(msg.runId, msg.error);
        }
        if (msg.reqId === undefined && msg.runId === undefined) {
          // Not tied to a request: the worker could not start (e.g. the wasm failed to load).
          this.crash(msg.error.message, msg.error);
        }
        break;
      default:
        assertNever(msg);
    }
  }

  private cancelRun(runId: number): void {
    if (!this.runs.has(runId)) return;
    this.postCancel(runId);
    this.runs.finish(runId, { code: ErrorCodes.cancelled, message: 'the run was cancelled' });
  }

  /** Discards the worker after a fatal error; the next call starts a new one. */
  private crash(message: string, data?: CoreErrorData): void {
    const error = toCoreErrorData(data ?? { code: ErrorCodes.workerCrashed, message });
    error.code = ErrorCodes.workerCrashed;
    this.readyReject?.(error);
    this.teardownWorker(error);
    this.onWorkerCrash?.(error);
  }

  /**
   * Terminates the worker. `error`: everything pending is rejected with it (a crash, dispose());
   * null: a worker replaced on purpose (restartStuckWorker), whose caller moves what is pending.
   */
  private teardownWorker(error: CoreErrorData | null): void {
    const worker = this.worker;
    this.worker = null;
    this.ready = null;
    this.readyResolve = null;
    this.readyReject = null;
    this.workerFiles.clear();
    this.handling.clear();
    this.clearGraceTimer();
    this.lab.workerLost();
    worker?.terminate();
    if (!error) return;
    this.unanswered.clear();
    for (const [reqId] of [...this.requests]) this.settleRequest(reqId, false, error);
    for (const runId of this.runs.ids()) this.runs.finish(runId, { ...error });
    this.lab.failAll(error);
  }
}

/** A load message's views (fresh copies of their bytes, to transfer); none: no field. */
function withViews(views: readonly ViewFile[]): { views?: ViewFile[] } {
  return views.length > 0 ? { views: views.map((v) => ({ name: v.name, bytes: v.bytes.slice(0) })) } : {};
}
