/**
 * The worker side of the validation lab (issue 5): owns the wasm `Lab` (truth surface, simulated
 * acquisition, comparison, batches) next to WorkerCore's `Session`, and serves the lab messages
 * of the protocol. A batch (leave-one-out, parameter sweep, the phases of a heart's function: many
 * full reconstructions) advances one
 * pipeline step at a time in slices of a few milliseconds, yielding between slices so that a
 * 'cancel' is seen within one step; progress goes out with every finished item and otherwise at
 * most every `progressMs`. It runs beside a reconstruction run (the slices interleave).
 *
 * Errors are thrown to WorkerCore, which tells core errors (sent as data) from crashes.
 */
import {
  ErrorCodes,
  assertNever,
  paramsJson,
  type ContourInfo,
  type FromWorker,
  type LabBatchRequest,
  type LabProgress,
  type LabRequest,
  type CompareReport,
  type LabAcquisition,
  type LabTruth,
  type LabTruthSummary,
  type PhasesBatchJob,
  type AnatomicalStudy,
  type AnatomicalStudyReport,
  type LabPhasesAnatomicalRequest,
} from './protocol';

/** The part of the wasm `Lab` (heartmesh-wasm/src/lab.rs) the worker uses. */
export interface LabApi {
  make_parametric(lvJson: string): string;
  load_truth(fileName: string, bytes: Uint8Array): string;
  add_truth(fileName: string, label: string | null | undefined, bytes: Uint8Array): string;
  set_truth_label(index: number, label: string | null | undefined): string;
  remove_truth(index: number): string;
  truth_positions(index: number): Float32Array;
  truth_indices(index: number): Uint32Array;
  simulate(acquisitionJson: string): string;
  simulated_csv(): Uint8Array;
  compare(surface: string | null | undefined, positions: Float32Array, indices: Uint32Array): string;
  truth_distances(): Float32Array;
  start_leave_one_out(session: unknown, fileName: string, surface: string | null | undefined, paramsJson: string, lids: string): string;
  start_sweep(
    session: unknown,
    fileName: string,
    surface: string | null | undefined,
    paramsJson: string,
    lids: string,
    sweepJson: string,
  ): string;
  /** `views`: a JS Array of Uint8Arrays, named by `viewNames` (the sequence file's long-axis views). */
  start_phases(
    session: unknown,
    phasesJson: string,
    paramsJson: string,
    lids: string,
    sequence: Uint8Array,
    viewNames: string[],
    views: Uint8Array[],
  ): string;
  batch_step(): string;
  stop_batch(): void;
  batch_points(): Float32Array;
  /**
   * The anatomical meshes of the last finished phases batch on `layout` ("24x48") as `format`:
   * the report's JSON with `files: [{name, index}]` (absent from older cores: 'lab-phases-anatomical'
   * then fails with `anatomical_unavailable`).
   */
  phases_anatomical?(layout: string, format: string): string;
  /** The bytes of file `index` of the last `phases_anatomical`, handed over once. */
  phases_anatomical_file?(index: number): Uint8Array;
}

export interface LabWorkerOptions {
  yieldToEventLoop: (callback: () => void) => void;
  now: () => number;
  sliceMs: number;
  /** Least time between progress messages without a finished item. */
  progressMs?: number;
  /** Reports a failure of a batch step (WorkerCore decides whether it is a crash). */
  fail: (e: unknown, runId: number) => void;
}

interface ActiveBatch {
  runId: number;
  finished: boolean;
  lastProgressMs: number;
}

export class LabWorker {
  private batch: ActiveBatch | null = null;

  constructor(
    private readonly lab: LabApi,
    /** The wasm Session, whose loaded files batches rebuild. */
    private readonly session: unknown,
    private readonly send: (msg: FromWorker) => void,
    private readonly options: LabWorkerOptions,
  ) {}

  /** Handles one lab request; throws what the wasm threw (WorkerCore reports it). */
  handle(msg: LabRequest): void {
    switch (msg.type) {
      case 'lab-truth': {
        const src = msg.source;
        const label = msg.label ?? null;
        let infoJson: string;
        if (src.kind === 'parametric') infoJson = this.lab.make_parametric(JSON.stringify(src.lv));
        else if (msg.add) infoJson = this.lab.add_truth(src.fileName, label, new Uint8Array(src.bytes));
        else {
          infoJson = this.lab.load_truth(src.fileName, new Uint8Array(src.bytes));
          // A lone truth's label only names it (its acquisition has no surface column).
          if (label !== null) this.lab.set_truth_label(0, label);
        }
        const info = JSON.parse(infoJson) as Omit<LabTruth, 'positions' | 'indices'>;
        const index = info.index ?? 0;
        const truth: LabTruth = { ...info, index, label: info.label ?? (src.kind === 'file' && !msg.add ? label : null), positions: this.lab.truth_positions(index), indices: this.lab.truth_indices(index) };
        this.send({ type: 'lab-truth', reqId: msg.reqId, truth });
        break;
      }
      case 'lab-truth-edit': {
        const e = msg.edit;
        const list = 'remove' in e ? this.lab.remove_truth(e.index) : this.lab.set_truth_label(e.index, e.label);
        this.send({ type: 'lab-truths', reqId: msg.reqId, truths: JSON.parse(list) as LabTruthSummary[] });
        break;
      }
      case 'lab-simulate': {
        const info = JSON.parse(this.lab.simulate(JSON.stringify(msg.acquisition))) as Omit<LabAcquisition, 'csv'>;
        const csv = this.lab.simulated_csv();
        const bytes = csv.buffer.byteLength === csv.byteLength ? (csv.buffer as ArrayBuffer) : csv.slice().buffer;
        this.send({ type: 'lab-simulated', reqId: msg.reqId, acquisition: { ...info, csv: bytes } });
        break;
      }
      case 'lab-compare': {
        const { truth_index, truth_label, truth_name, ...report } = JSON.parse(this.lab.compare(msg.surface ?? null, msg.positions, msg.indices)) as CompareReport & {
          truth_index?: number;
          truth_label?: string | null;
          truth_name?: string;
        };
        const comparison = { report, truthIndex: truth_index ?? 0, truthLabel: truth_label ?? null, truthName: truth_name ?? '', truthDistances: this.lab.truth_distances() };
        this.send({ type: 'lab-compared', reqId: msg.reqId, comparison });
        break;
      }
      case 'lab-batch':
        this.startBatch(msg);
        break;
      case 'lab-phases-anatomical':
        this.phasesAnatomical(msg);
        break;
      default:
        assertNever(msg);
    }
  }

  /**
   * The anatomical meshes of the last finished phases batch: the report and each file's bytes
   * (transferred). A request in shapes the binding does not take is refused as data before wasm
   * sees it; the core's refusals (no finished batch, no LV surface, no septum) are its typed
   * errors, thrown to WorkerCore: the request fails, the worker goes on.
   */
  private phasesAnatomical(msg: LabPhasesAnatomicalRequest): void {
    const build = this.lab.phases_anatomical;
    const take = this.lab.phases_anatomical_file;
    if (!build || !take) {
      this.send({ type: 'error', reqId: msg.reqId, error: { code: 'anatomical_unavailable', message: 'this core cannot build the anatomical meshes of a study' } });
      return;
    }
    const whole = (v: unknown) => typeof v === 'number' && Number.isInteger(v) && v >= 0 && v <= 0xffff_ffff;
    if (!whole(msg.rings) || !whole(msg.points) || typeof msg.format !== 'string') {
      const got = `${String(msg.rings)}x${String(msg.points)}, ${String(msg.format)}`;
      this.send({ type: 'error', reqId: msg.reqId, error: { code: ErrorCodes.protocol, message: `the anatomical meshes: the layout must be two whole numbers and the format a name (got ${got})` } });
      return;
    }
    const report = JSON.parse(build.call(this.lab, `${msg.rings}x${msg.points}`, msg.format)) as AnatomicalStudyReport;
    const files = report.files.map(({ name, index }) => {
      const bytes = take.call(this.lab, index);
      // The binding's copy is this array's own buffer: transferred as it is.
      const buffer = bytes.buffer.byteLength === bytes.byteLength ? (bytes.buffer as ArrayBuffer) : bytes.slice().buffer;
      return { name, bytes: buffer };
    });
    const study: AnatomicalStudy = { report, files };
    this.send({ type: 'lab-phases-anatomical', reqId: msg.reqId, study });
  }

  /** True when `runId` was this worker's batch (then it is stopped). */
  cancel(runId: number): boolean {
    if (this.batch?.runId !== runId) return false;
    this.stop();
    return true;
  }

  stop(): void {
    if (this.batch) {
      this.batch.finished = true;
      this.lab.stop_batch();
    }
    this.batch = null;
  }

  private startBatch(msg: LabBatchRequest): void {
    this.stop();
    const j = msg.job;
    const params = paramsJson(j.params, j.options, j.kind === 'phases' ? undefined : j.leaveOut);
    const infoJson =
      j.kind === 'loo'
        ? this.lab.start_leave_one_out(this.session, j.fileName, j.surface, params, j.lids)
        : j.kind === 'sweep'
          ? this.lab.start_sweep(this.session, j.fileName, j.surface, params, j.lids, JSON.stringify({ grid: j.grid, with_truth: j.withTruth }))
          : this.startPhases(j, params);
    const info = JSON.parse(infoJson) as { total: number; contours?: ContourInfo[]; phases?: string[]; surfaces?: string[] };
    const batch: ActiveBatch = { runId: msg.runId, finished: false, lastProgressMs: this.options.now() };
    this.batch = batch;
    this.send({
      type: 'lab-batch-started',
      runId: msg.runId,
      info: j.kind === 'loo' ? { ...info, points: this.lab.batch_points() } : j.kind === 'phases' ? info : { total: info.total },
    });
    this.options.yieldToEventLoop(() => this.compute(batch));
  }

  private startPhases(j: PhasesBatchJob, params: string): string {
    const views = j.sequence?.views ?? [];
    const bytes = j.sequence ? new Uint8Array(j.sequence.bytes) : new Uint8Array(0);
    return this.lab.start_phases(this.session, JSON.stringify(j.phases), params, j.lids, bytes, views.map((v) => String(v.name)), views.map((v) => new Uint8Array(v.bytes)));
  }

  private compute(batch: ActiveBatch): void {
    if (batch.finished || this.batch !== batch) return;
    const end = this.options.now() + this.options.sliceMs;
    try {
      do {
        const p = JSON.parse(this.lab.batch_step()) as LabProgress & { done: boolean };
        const now = this.options.now();
        const progress: LabProgress = { completed: p.completed, total: p.total };
        if (p.item) progress.item = p.item;
        if (p.summary) progress.summary = p.summary;
        if (p.item || p.done || now - batch.lastProgressMs >= (this.options.progressMs ?? 100)) {
          batch.lastProgressMs = now;
          this.send({ type: 'lab-progress', runId: batch.runId, progress });
        }
        if (p.done) {
          this.batch = null;
          batch.finished = true;
          this.send({ type: 'lab-batch-done', runId: batch.runId });
          return;
        }
      } while (this.options.now() < end);
    } catch (e) {
      this.stop();
      this.options.fail(e, batch.runId);
      return;
    }
    this.options.yieldToEventLoop(() => this.compute(batch));
  }
}
