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
 *
 * The frame throttling lives in runFrames.ts, the validation lab's requests and batches in
 * labRequests.ts, the public API types in coreClientTypes.ts (re-exported here); this module keeps
 * the worker's life cycle, requests, message routing and crash recovery.
 */

import {
  ErrorCodes,
  assertNever,
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
  type LabTruthSource,
  type LoadedFile,
  type ParamSpec,
  type RunResult,
  type ToWorker,
} from './protocol';
import {
  settingsOf,
  type CoreClientOptions,
  type LabBatchHandle,
  type RunHandle,
  type RunOptions,
  type WorkerLike,
} from './coreClientTypes';
import { LabRequests } from './labRequests';
import { RunFrames } from './runFrames';

export type { CoreClientOptions, LabBatchHandle, RunHandle, RunOptions, WorkerLike } from './coreClientTypes';

interface PendingRequest {
  resolve: (value: unknown) => void;
  reject: (error: CoreErrorData) => void;
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

export class CoreClient {
  private readonly createWorker: () => WorkerLike;
  private readonly schedule: (callback: () => void) => void;
  private readonly onWorkerCrash: ((error: CoreErrorData) => void) | undefined;

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
  /** Files the current worker has been sent. */
  private readonly workerFiles = new Set<string>();
  private schemaCache: { schema: ParamSpec[]; version: string } | null = null;
  /** The validation lab's requests and batches (labRequests.ts). */
  private readonly lab: LabRequests;
  private disposed = false;

  /** Use `CoreClient.create()` in the app; the constructor is for tests that inject a worker. */
  constructor(options: CoreClientOptions = {}) {
    this.createWorker = options.createWorker ?? defaultCreateWorker;
    this.schedule = options.schedule ?? defaultSchedule;
    this.onWorkerCrash = options.onWorkerCrash;
    this.runs = new RunFrames(this.schedule, (runId, seq) => this.post({ type: 'ack', runId, seq }));
    this.lab = new LabRequests({
      request: (make) => this.request(make),
      post: (msg) => this.post(msg),
      hasWorker: () => this.worker !== null,
      newId: () => this.nextId++,
      disposedError: () => (this.disposed ? this.disposedError() : null),
      fileBytes: (fileName) => this.files.get(fileName),
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

  /** Parses a contour file in the worker. Rejects with CoreErrorData (file and line named). */
  load(fileName: string, bytes: ArrayBuffer): Promise<LoadedFile> {
    // One copy stays here for crash recovery; the other is transferred to the worker.
    const kept = bytes.slice(0);
    const sent = bytes.slice(0);
    this.files.set(fileName, kept);
    const promise = this.request<LoadedFile>((reqId) => ({
      type: 'load',
      reqId,
      fileName,
      bytes: sent,
    }));
    this.workerFiles.add(fileName);
    return promise.catch((e: CoreErrorData) => {
      if (this.files.get(fileName) === kept && e.code !== ErrorCodes.workerCrashed) {
        this.files.delete(fileName);
      }
      this.workerFiles.delete(fileName);
      throw e;
    });
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
    this.post({ type: 'run', runId, ...settingsOf(opts) });
    return handle;
  }

  /**
   * A recreated worker has lost the files: re-send this one first (the worker handles messages in
   * order, so a request posted next finds it); `onError` hears if the reload fails.
   */
  private resendIfRecreated(fileName: string, bytes: ArrayBuffer, onError: (e: CoreErrorData) => void): void {
    if (this.workerFiles.has(fileName)) return;
    this.request<LoadedFile>((reqId) => ({ type: 'load', reqId, fileName, bytes: bytes.slice(0) })).catch((e: CoreErrorData) => {
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
    return this.request<Uint8Array>((reqId) => ({ type: 'session-export', reqId, ...settingsOf(opts), appVersion }));
  }

  // ---- validation lab ------------------------------------------------------------------------

  /** Makes the lab's ground-truth surface (parametric LV or a mesh file) in the worker. */
  labTruth(source: LabTruthSource): Promise<LabTruth> {
    return this.lab.truth(source);
  }

  /** Slices the truth like a CMR acquisition; resolves to the contours as CSV bytes. */
  labSimulate(acquisition: AcquisitionSpec): Promise<LabAcquisition> {
    return this.lab.simulate(acquisition);
  }

  /** Compares a mesh with the truth (clipped at the last acquisition's most basal SAX plane). */
  labCompare(positions: Float32Array, indices: Uint32Array): Promise<LabComparison> {
    return this.lab.compare(positions, indices);
  }

  /** Starts a leave-one-out or a parameter sweep on a loaded file; replaces a batch in progress. */
  labBatch(job: LabBatchJob, onProgress: (p: LabProgress) => void): LabBatchHandle {
    return this.lab.batch(job, onProgress);
  }

  /** Terminates the worker and rejects everything pending with `{ code: 'disposed' }`. */
  dispose(): void {
    if (this.disposed) return;
    this.disposed = true;
    const error = this.disposedError();
    this.readyReject?.(error);
    this.teardownWorker(error);
    this.files.clear();
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

  private request<T>(make: (reqId: number) => ToWorker): Promise<T> {
    if (this.disposed) return Promise.reject(this.disposedError());
    const reqId = this.nextId++;
    const promise = new Promise<T>((resolve, reject) => {
      this.requests.set(reqId, { resolve: resolve as (v: unknown) => void, reject });
    });
    void this.ensureWorker().catch(() => undefined);
    this.post(make(reqId));
    return promise;
  }

  private settleRequest(reqId: number, ok: boolean, value: unknown): void {
    const req = this.requests.get(reqId);
    if (!req) return;
    this.requests.delete(reqId);
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
      case 'schema':
        this.settleRequest(msg.reqId, true, { schema: msg.schema, version: msg.version });
        break;
      case 'frame':
        this.runs.onFrameMessage(msg);
        break;
      case 'lab-truth':
        this.settleRequest(msg.reqId, true, msg.truth);
        break;
      case 'lab-simulated':
        this.settleRequest(msg.reqId, true, msg.acquisition);
        break;
      case 'lab-compared':
        this.settleRequest(msg.reqId, true, msg.comparison);
        break;
      case 'session-json':
        this.settleRequest(msg.reqId, true, msg.bytes);
        break;
      case 'lab-batch-started':
        this.lab.onStarted(msg.runId, msg.info);
        break;
      case 'lab-progress':
        this.lab.onProgress(msg.runId, msg.progress);
        break;
      case 'lab-batch-done':
        this.lab.finishBatch(msg.runId, null);
        break;
      case 'done':
        this.runs.onDone(msg.result);
        break;
      case 'error':
        if (isFatal(msg.error)) {
          this.crash(msg.error.message, msg.error);
          break;
        }
        if (msg.reqId !== undefined) this.settleRequest(msg.reqId, false, msg.error);
        if (msg.runId !== undefined) {
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
    if (this.worker) this.post({ type: 'cancel', runId });
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

  private teardownWorker(error: CoreErrorData): void {
    const worker = this.worker;
    this.worker = null;
    this.ready = null;
    this.readyResolve = null;
    this.readyReject = null;
    this.workerFiles.clear();
    this.lab.workerLost();
    worker?.terminate();
    for (const [reqId] of [...this.requests]) this.settleRequest(reqId, false, error);
    for (const runId of this.runs.ids()) this.runs.finish(runId, { ...error });
    this.lab.failAll(error);
  }
}
