/**
 * The validation lab's side of the core client: truth, simulated acquisition, comparison, and the
 * batches with their progress (leave-one-out, sweep, and the phases of a heart's function, which
 * the app's Function panel asks for: one batch at a time, so each replaces the other). It remembers the truth and acquisition it
 * made so a worker recreated after a crash gets them again before the next lab call (the lab
 * should not have to know the worker died). Split from CoreClient.ts because the main app never
 * uses it; CoreClient keeps the worker and forwards the lab's calls and messages here.
 */

import {
  ErrorCodes,
  type AcquisitionSpec,
  type AnatomicalFormat,
  type AnatomicalStudy,
  type CoreErrorData,
  type LabAcquisition,
  type LabBatchInfo,
  type LabBatchJob,
  type LabComparison,
  type LabProgress,
  type LabTruth,
  type LabTruthEdit,
  type LabTruthSource,
  type LabTruthSummary,
  type PhasesJob,
  type ToWorker,
  type ViewFile,
  type WorkerBatchJob,
} from './protocol';
import type { LabBatchHandle } from './coreClientTypes';

/** What the lab needs from the client that owns the worker. */
export interface LabHost {
  /** `make` may be called again (a worker replaced while stuck): each call makes fresh buffers. */
  request<T>(make: (reqId: number) => ToWorker, files?: { needs?: string }): Promise<T>;
  /** Posts a batch, remembered until the worker starts it (moved to a worker that replaces a stuck one). */
  postRun(runId: number, make: () => ToWorker, needs: readonly string[]): void;
  /** Posts a cancel (the client replaces a worker that does not acknowledge it in time). */
  cancel(runId: number): void;
  /** A worker exists now (a cancel is only worth posting then). */
  hasWorker(): boolean;
  /** The next request/run id (shared with the client's own). */
  newId(): number;
  /** The error calls get after dispose(); null while the client is usable. */
  disposedError(): CoreErrorData | null;
  /** Bytes of a loaded file, kept for crash recovery. */
  fileBytes(fileName: string): ArrayBuffer | undefined;
  /** The long-axis views a loaded file is read with (none: empty). */
  fileViews(fileName: string): readonly ViewFile[];
  /** Spawns a worker if there is none (its failure is heard elsewhere). */
  ensureWorker(): void;
  /** Re-sends a file to a recreated worker before the next request; `onError` hears a failed reload. */
  resendIfRecreated(fileName: string, bytes: ArrayBuffer, onError: (e: CoreErrorData) => void): void;
}

interface BatchState {
  onProgress: (p: LabProgress) => void;
  started: { resolve: (i: LabBatchInfo) => void; reject: (e: CoreErrorData) => void };
  resolve: () => void;
  reject: (e: CoreErrorData) => void;
}

export class LabRequests {
  private readonly batches = new Map<number, BatchState>();
  /** The lab's truths (in order) and acquisition, replayed to a recreated worker before the next lab call. */
  private truthSources: { source: LabTruthSource; label: string | null }[] = [];
  private acquisition: AcquisitionSpec | null = null;
  private inWorker = false;

  constructor(private readonly host: LabHost) {}

  /**
   * Makes the lab's ground-truth surface (parametric LV or a mesh file) in the worker: the only
   * one, or (`add`) one more beside those held; `label` is its surface label.
   */
  truth(source: LabTruthSource, opts: { add?: boolean; label?: string | null } = {}): Promise<LabTruth> {
    const kept: LabTruthSource = source.kind === 'file' ? { ...source, bytes: source.bytes.slice(0) } : source;
    // A fresh copy for each worker it goes to (the copy is transferred).
    const sent = (): LabTruthSource => (kept.kind === 'file' ? { ...kept, bytes: kept.bytes.slice(0) } : kept);
    const add = opts.add === true;
    const label = opts.label ?? null;
    // Added beside truths a recreated worker must get back first.
    if (add) this.replay();
    this.acquisition = null;
    const p = this.host.request<LabTruth>((reqId) => ({ type: 'lab-truth', reqId, source: sent(), ...(add ? { add } : {}), ...(label !== null ? { label } : {}) }));
    this.inWorker = true;
    return p.then((t) => {
      const entry = { source: kept, label: t.label ?? null };
      if (add) this.truthSources.push(entry);
      else this.truthSources = [entry];
      return t;
    });
  }

  /** Relabels or removes one truth; resolves to the truths left, in order. */
  edit(edit: LabTruthEdit): Promise<LabTruthSummary[]> {
    this.replay();
    return this.host.request<LabTruthSummary[]>((reqId) => ({ type: 'lab-truth-edit', reqId, edit: { ...edit } })).then((list) => {
      this.acquisition = null;
      if ('remove' in edit) this.truthSources.splice(edit.index, 1);
      else if (this.truthSources[edit.index]) this.truthSources[edit.index].label = edit.label;
      return list;
    });
  }

  /** Slices the truth like a CMR acquisition; resolves to the contours as CSV bytes. */
  simulate(acquisition: AcquisitionSpec): Promise<LabAcquisition> {
    this.replay();
    return this.host.request<LabAcquisition>((reqId) => ({ type: 'lab-simulate', reqId, acquisition: { ...acquisition } })).then((a) => {
      this.acquisition = { ...acquisition };
      return a;
    });
  }

  /**
   * Compares a mesh of `surface` with the truth of that label (one truth: that one), clipped at
   * the last acquisition's most basal SAX plane.
   */
  compare(positions: Float32Array, indices: Uint32Array, surface: string | null = null): Promise<LabComparison> {
    this.replay();
    // Copies: the caller keeps displaying its arrays, these are transferred.
    return this.host.request<LabComparison>((reqId) => ({ type: 'lab-compare', reqId, positions: positions.slice(), indices: indices.slice(), surface }));
  }

  /** Starts a leave-one-out or a parameter sweep on a loaded file; replaces a batch in progress. */
  batch(job: LabBatchJob, onProgress: (p: LabProgress) => void): LabBatchHandle {
    const options = job.options ? { options: { ...job.options } } : {};
    const copy: LabBatchJob = job.kind === 'sweep' ? { ...job, grid: { ...job.grid }, params: { ...job.params }, ...options } : { ...job, params: { ...job.params }, ...options };
    return this.start([job.fileName], () => copy, onProgress);
  }

  /**
   * Starts the phases of a heart's function (every surface of every phase) on loaded files;
   * replaces a batch in progress. Phases that are time frames are read in the worker from the
   * bytes (and views) kept here, so the frame the worker holds for the view stays as it is.
   */
  phases(job: PhasesJob, onProgress: (p: LabProgress) => void): LabBatchHandle {
    const files = [...new Set(job.phases.map((p) => p.file))];
    const framed = job.phases.find((p) => p.frame !== undefined)?.file;
    const copy: PhasesJob = { ...job, phases: job.phases.map((p) => ({ ...p })), params: { ...job.params }, ...(job.options ? { options: { ...job.options } } : {}) };
    // Fresh copies for each message (they are transferred).
    const make = (): WorkerBatchJob => {
      const bytes = framed === undefined ? undefined : this.host.fileBytes(framed);
      if (bytes === undefined) return copy;
      const views = this.host.fileViews(framed as string).map((v) => ({ name: v.name, bytes: v.bytes.slice(0) }));
      return { ...copy, sequence: { bytes: bytes.slice(0), views } };
    };
    return this.start(files, make, onProgress);
  }

  /**
   * The anatomical meshes of the worker's last finished phases batch on `layout`, as `format`
   * (a worker recreated since holds none: the core's error says so).
   */
  phasesAnatomical(layout: { rings: number; points: number }, format: AnatomicalFormat): Promise<AnatomicalStudy> {
    return this.host.request<AnatomicalStudy>((reqId) => ({ type: 'lab-phases-anatomical', reqId, rings: layout.rings, points: layout.points, format }));
  }

  /** Posts a batch that needs `files` loaded in the worker (re-sent to a recreated one first). */
  private start(files: readonly string[], make: () => WorkerBatchJob, onProgress: (p: LabProgress) => void): LabBatchHandle {
    const runId = this.host.newId();
    let started!: BatchState['started'];
    const startedP = new Promise<LabBatchInfo>((resolve, reject) => (started = { resolve, reject }));
    let resolve!: () => void;
    let reject!: (e: CoreErrorData) => void;
    const done = new Promise<void>((res, rej) => {
      resolve = res;
      reject = rej;
    });
    startedP.catch(() => undefined);
    const handle: LabBatchHandle = { runId, started: startedP, done, cancel: () => this.cancelBatch(runId) };
    const disposed = this.host.disposedError();
    if (disposed) {
      started.reject(disposed);
      reject({ ...disposed });
      return handle;
    }
    const missing = files.find((f) => this.host.fileBytes(f) === undefined);
    if (missing !== undefined || files.length === 0) {
      const e = { code: ErrorCodes.notLoaded, message: `${missing ?? 'no file'} has not been loaded`, file: missing };
      started.reject(e);
      reject(e);
      return handle;
    }
    for (const other of [...this.batches.keys()]) this.cancelBatch(other);
    this.batches.set(runId, { onProgress, started, resolve, reject });
    this.host.ensureWorker();
    this.replay();
    for (const f of files) this.host.resendIfRecreated(f, this.host.fileBytes(f) as ArrayBuffer, (e) => this.finishBatch(runId, e));
    this.host.postRun(runId, () => ({ type: 'lab-batch', runId, job: make() }), files);
    return handle;
  }

  // ---- messages from the worker (routed by CoreClient) -----------------------------------------

  onStarted(runId: number, info: LabBatchInfo): void {
    this.batches.get(runId)?.started.resolve(info);
  }

  onProgress(runId: number, progress: LabProgress): void {
    try {
      this.batches.get(runId)?.onProgress(progress);
    } catch (e) {
      console.error('CoreClient: onProgress threw', e);
    }
  }

  /** Settles a batch (rejects with `error`, else resolves) and forgets it; no-op for other ids. */
  finishBatch(runId: number, error: CoreErrorData | null): void {
    const b = this.batches.get(runId);
    if (!b) return;
    this.batches.delete(runId);
    if (error) {
      b.started.reject(error);
      b.reject(error);
    } else {
      b.resolve();
    }
  }

  /** The worker is gone: the next lab call replays the truth and acquisition to a new one. */
  workerLost(): void {
    this.inWorker = false;
  }

  /** Replays the truth and acquisition now (a replaced worker gets lab requests that need them). */
  restoreInWorker(): void {
    this.replay();
  }

  has(runId: number): boolean {
    return this.batches.has(runId);
  }

  /** The batches in progress. */
  ids(): number[] {
    return [...this.batches.keys()];
  }

  /** Fails every batch in progress (the worker crashed, or the client was disposed). */
  failAll(error: CoreErrorData): void {
    for (const runId of [...this.batches.keys()]) this.finishBatch(runId, { ...error });
  }

  // -------------------------------------------------------------------------------------------

  /** Re-sends the truths (and acquisition) to a worker that does not have them (after a crash). */
  private replay(): void {
    if (this.inWorker || this.truthSources.length === 0) return;
    this.truthSources.forEach(({ source: src, label }, i) => {
      const source: LabTruthSource = src.kind === 'file' ? { ...src, bytes: src.bytes.slice(0) } : src;
      const extra = { ...(i > 0 ? { add: true } : {}), ...(label !== null ? { label } : {}) };
      this.host.request<LabTruth>((reqId) => ({ type: 'lab-truth', reqId, source, ...extra })).catch(() => undefined);
    });
    const acq = this.acquisition;
    if (acq) this.host.request<LabAcquisition>((reqId) => ({ type: 'lab-simulate', reqId, acquisition: { ...acq } })).catch(() => undefined);
    this.inWorker = true;
  }

  private cancelBatch(runId: number): void {
    if (!this.batches.has(runId)) return;
    if (this.host.hasWorker()) this.host.cancel(runId);
    this.finishBatch(runId, { code: ErrorCodes.cancelled, message: 'the batch was cancelled' });
  }
}
