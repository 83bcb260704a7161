/**
 * The worker's logic, independent of the worker global scope so that the Node tests can drive it
 * with the real wasm module (differential test) and the unit tests with a fake one.
 *
 * One run at a time: a run computes in slices of a few milliseconds, yielding to the event loop
 * between slices so that 'ack' and 'cancel' messages are seen. Every step's state (report, its own
 * positions buffer, the indices when the topology changed, the attractors when re-sampled) is kept
 * until it is sent: nothing is skipped, so the main thread can record every step. Back-pressure: at
 * most two frames are unacknowledged; while the limit is reached the worker keeps computing, and
 * once an ack arrives it sends every step computed meanwhile in one frame (the newest step, the
 * others in `earlier`, all buffers transferred). The final frame is always sent, then 'done'.
 *
 * Errors thrown by the wasm Session are JSON strings (CoreErrorData); anything else thrown (a wasm
 * trap, "unreachable" after a Rust panic) is fatal: the worker reports 'worker_crashed' and
 * refuses further work, and the client replaces it. Every 'cancel' is answered with 'cancelled'
 * once handled: a step cannot be interrupted, so a worker that does not answer within the client's
 * grace period is inside a long one, and the client replaces it too (on purpose, not as a crash).
 */

import {
  ErrorCodes,
  assertNever,
  frameOfSteps,
  isCoreErrorData,
  paramsJson,
  transferablesOf,
  withDefaultOptions,
  type ContourInfo,
  type CoreErrorData,
  type FromWorker,
  type LabelMapGrid,
  type LoadedFile,
  type LoadRequest,
  type ParamSpec,
  type RunRequest,
  type RunResult,
  type StepFrame,
  type StepReport,
  type ToWorker,
  type AnatomicalExportRequest,
  type AnatomicalSummary,
  type BivWallExportRequest,
  type HexExportRequest,
  type HexSummary,
  type WallExportRequest,
  type WallSummary,
} from './protocol';
import { LabWorker, type LabApi } from './labWorker';

/** The part of the wasm `Session` (wasm-core/crates/heartmesh-wasm) the worker uses. */
export interface SessionApi {
  /** `frame`: the time frame to read, by its label (undefined: each contour's first). */
  load(fileName: string, bytes: Uint8Array, frame?: string): string;
  /** `load` with companion files: a label-map short-axis stack's long-axis views (single-slice label maps), a cvi42 workspace's DICOM images (`views` a JS Array of Uint8Arrays). */
  load_study?(fileName: string, bytes: Uint8Array, viewNames: string[], views: Uint8Array[], frame?: string): string;
  file_points(fileName: string): Float32Array;
  start(fileName: string, surface: string | null | undefined, paramsJson: string, lids: string): void;
  step(): string;
  /** The core's note for a run that will reach the remesh cap (after the first step). */
  growth_note(): string | undefined;
  attractors_changed(): boolean;
  positions(): Float32Array;
  /** The same vertices in full precision (absent: a test double; the result then has no `positionsF64`). */
  positions_f64?(): Float64Array;
  indices(): Uint32Array;
  attractors(): Float32Array;
  contour_points(): Float32Array;
  point_distances(): Float32Array;
  vertex_distances(): Float32Array;
  /** The same distances in full precision (absent: a test double; the result then has no `vertexDistancesF64`). */
  vertex_distances_f64?(): Float64Array;
  /** xyz of the contours the run left out (`result_json().set_aside_contours` index them). */
  set_aside_points(): Float32Array;
  /** Distance of each of those points to the finished mesh, mm (absent: a test double or an older core). */
  set_aside_point_distances?(): Float32Array;
  result_json(): string;
  session_json(fileName: string, surface: string | null | undefined, paramsJson: string, lids: string, appVersion: string): Uint8Array;
  /**
   * The LV myocardium wall of a loaded file from two finished meshes (the binding's `wall.rs`):
   * `summary` is JSON (`WallSummary`), `bytes` the file in `format`; `minThicknessMm` undefined: off.
   * Absent from test doubles and older cores ('wall-export' then fails with `wall_unavailable`).
   */
  wall?(
    fileName: string,
    paramsJson: string,
    lids: string,
    endoSurface: string,
    endoPositions: Float64Array,
    endoIndices: Uint32Array,
    epiSurface: string,
    epiPositions: Float64Array,
    epiIndices: Uint32Array,
    minThicknessMm: number | undefined,
    format: string,
    header: string,
  ): { summary: string; bytes: Uint8Array };
  /**
   * The biventricular myocardium of a loaded file from three finished meshes (the binding's
   * `wall.rs`, `Session.biventricular_wall`): the LV and RV cavities and the biventricular
   * epicardium; as `wall` otherwise. Absent from older cores ('biv-wall-export' then fails with
   * `wall_unavailable`).
   */
  biventricular_wall?(
    fileName: string,
    paramsJson: string,
    lids: string,
    lvEndoSurface: string,
    lvEndoPositions: Float64Array,
    lvEndoIndices: Uint32Array,
    rvEndoSurface: string,
    rvEndoPositions: Float64Array,
    rvEndoIndices: Uint32Array,
    bivEpiSurface: string,
    bivEpiPositions: Float64Array,
    bivEpiIndices: Uint32Array,
    minThicknessMm: number | undefined,
    format: string,
    header: string,
  ): { summary: string; bytes: Uint8Array };
  /**
   * The anatomical mesh of a finished LV surface (the binding's `anatomical.rs`): `rings` x
   * `points` from the apex to the base, `summary` JSON (`AnatomicalSummary`), `bytes` the file in
   * `format`. Throws the core's reason for a surface or file that can have none ("the anatomical
   * mesh: ..."). Absent from test doubles and older cores ('anatomical-export' then fails with
   * `anatomical_unavailable`).
   */
  anatomical_mesh?(
    fileName: string,
    paramsJson: string,
    lids: string,
    surface: string,
    positions: Float64Array,
    indices: Uint32Array,
    rings: number,
    points: number,
    format: string,
    header: string,
  ): { summary: string; bytes: Uint8Array };
  /**
   * The LV wall as layers of hexahedra (the binding's `hex.rs`, `myocardium --hex-mesh`) between
   * the anatomical layouts of two finished meshes: `rings` x `points` per layout, `layers` cells
   * through the wall; `summary` JSON (`HexSummary`), `bytes` the VTK unstructured grid. Throws the
   * core's reason ("the hexahedral wall: ...": no RV to place the septum by, a value out of range).
   * Absent from test doubles and older cores ('hex-export' then fails with `hex_unavailable`).
   */
  hex_wall?(
    fileName: string,
    paramsJson: string,
    lids: string,
    endoSurface: string,
    endoPositions: Float64Array,
    endoIndices: Uint32Array,
    epiSurface: string,
    epiPositions: Float64Array,
    epiIndices: Uint32Array,
    rings: number,
    points: number,
    layers: number,
    header: string,
  ): { summary: string; bytes: Uint8Array };
}

type RunSettings = Parameters<typeof paramsJson>;

/** What every derived-file binding takes first: the file, its run's parameters and mesh ends. */
function runArgs(msg: { fileName: string; params: RunSettings[0]; options?: RunSettings[1]; leaveOut?: RunSettings[2]; lids: string }): [fileName: string, paramsJson: string, lids: string] {
  return [msg.fileName, paramsJson(msg.params, msg.options, msg.leaveOut), msg.lids];
}

/** A finished mesh as the bindings take it: its surface, positions (mm) and triangle indices. */
function meshArgs(m: { surface: string; positions: Float64Array; indices: Uint32Array }): [surface: string, positions: Float64Array, indices: Uint32Array] {
  return [m.surface, m.positions, m.indices];
}

export interface WasmApi {
  createSession(): SessionApi;
  schemaJson(): string;
  version(): string;
  /** `{"dims":[i,j,k],"frames":t}` of a label map (NIfTI-1, NRRD, DICOM SEG) from its header; undefined: not one (absent: no such core). */
  labelMapGrid?(bytes: Uint8Array): string | undefined;
  /** The message of the Rust panic that caused a trap, if any. */
  takePanicMessage(): string | undefined;
  /** The validation lab's state (absent: lab requests fail with 'lab_unavailable'). */
  createLab?(): LabApi;
}

/** The parts of the generated wasm-bindgen module (after its init) that the worker core uses. */
export interface WasmModule {
  Session: new () => SessionApi;
  Lab: new () => unknown;
  schema_json(): string;
  version(): string;
  label_map_grid(bytes: Uint8Array): string | undefined;
  take_panic_message(): string | undefined;
}

/**
 * The worker core's view of the generated module. One place, so that the production worker and
 * the Node tests that drive the real wasm build it the same way.
 */
export function wasmApiOf(m: WasmModule): WasmApi {
  return {
    createSession: () => new m.Session(),
    schemaJson: () => m.schema_json(),
    version: () => m.version(),
    labelMapGrid: (bytes) => m.label_map_grid(bytes),
    takePanicMessage: () => m.take_panic_message() ?? undefined,
    createLab: () => new m.Lab() as LabApi,
  };
}

export interface WorkerCoreOptions {
  /** Runs a callback soon, after pending messages (MessageChannel tick in the worker). */
  yieldToEventLoop: (callback: () => void) => void;
  now: () => number;
  /** Milliseconds of computing between yields. */
  sliceMs?: number;
  /** Unacknowledged frames allowed in flight. */
  maxInFlight?: number;
}

interface ActiveRun {
  runId: number;
  seq: number;
  /** Sequence numbers sent and not yet acknowledged. */
  unacked: number[];
  /** The steps computed since the last frame was sent, oldest first. */
  batch: StepFrame[];
  /** The next step carries the indices (and attractors) whatever it reports: the run's first. */
  indicesDirty: boolean;
  attractorsDirty: boolean;
  /** The run's contours differ from the file's (breath-hold alignment): send them on the first frame. */
  contoursDirty: boolean;
  /** The first frame is still to go (it carries the growth note). */
  firstFrame: boolean;
  report: StepReport | null;
  startedMs: number;
  finished: boolean;
}

/** Resources of a finished run's result, in the shape the protocol sends. */
type ResultJson = Omit<
  RunResult,
  | 'runId'
  | 'contourPoints'
  | 'positions'
  | 'positionsF64'
  | 'vertexDistancesF64'
  | 'indices'
  | 'pointDistances'
  | 'vertexDistances'
  | 'setAsidePoints'
  | 'setAsidePointDistances'
  | 'seconds'
>;

export class WorkerCore {
  private readonly session: SessionApi;
  private readonly sliceMs: number;
  private readonly maxInFlight: number;
  private run: ActiveRun | null = null;
  private crashed = false;
  private readonly lab: LabWorker | null;

  constructor(
    private readonly wasm: WasmApi,
    private readonly post: (msg: FromWorker, transfer: ArrayBuffer[]) => void,
    private readonly options: WorkerCoreOptions,
  ) {
    this.session = wasm.createSession();
    this.sliceMs = options.sliceMs ?? 8;
    this.maxInFlight = options.maxInFlight ?? 2;
    const labApi = wasm.createLab?.();
    this.lab = labApi
      ? new LabWorker(labApi, this.session, (m) => this.send(m), {
          yieldToEventLoop: options.yieldToEventLoop,
          now: options.now,
          sliceMs: this.sliceMs,
          fail: (e, runId) => this.fail(e, { runId }),
        })
      : null;
  }

  handle(msg: ToWorker): void {
    if (this.crashed) {
      this.send({
        type: 'error',
        ...idsOf(msg),
        error: { code: ErrorCodes.workerCrashed, message: 'the worker crashed earlier' },
      });
      return;
    }
    try {
      this.dispatch(msg);
    } catch (e) {
      const file = msg.type === 'load' || msg.type === 'session-export' || msg.type === 'wall-export' || msg.type === 'biv-wall-export' || msg.type === 'anatomical-export' || msg.type === 'hex-export' ? msg.fileName : msg.type === 'lab-truth' && msg.source.kind === 'file' ? msg.source.fileName : undefined;
      this.fail(e, idsOf(msg), file);
    }
  }

  private dispatch(msg: ToWorker): void {
    switch (msg.type) {
      case 'schema':
        this.send({
          type: 'schema',
          reqId: msg.reqId,
          schema: JSON.parse(this.wasm.schemaJson()) as ParamSpec[],
          version: this.wasm.version(),
        });
        break;
      case 'load':
        // Said first: a parse of seconds is then not taken for a long step (CoreClient.isInLongStep).
        this.send({ type: 'started', reqId: msg.reqId });
        this.load(msg.reqId, msg.fileName, msg.bytes, msg.frame, msg.views);
        break;
      case 'grid':
        this.send({ type: 'grid', reqId: msg.reqId, grid: this.grid(msg.bytes) });
        break;
      case 'run':
        this.startRun(msg);
        break;
      case 'session-export':
        this.send({
          type: 'session-json',
          reqId: msg.reqId,
          bytes: this.session.session_json(msg.fileName, msg.surface, paramsJson(msg.params, msg.options, msg.leaveOut), msg.lids, msg.appVersion),
        });
        break;
      case 'wall-export':
        this.wall(msg);
        break;
      case 'biv-wall-export':
        this.bivWall(msg);
        break;
      case 'anatomical-export':
        this.anatomical(msg);
        break;
      case 'hex-export':
        this.hex(msg);
        break;
      case 'ack':
        this.ack(msg.runId, msg.seq);
        break;
      case 'cancel':
        if (this.run?.runId === msg.runId) this.stopRun();
        else this.lab?.cancel(msg.runId);
        // The client waits for this (a short grace period) before it replaces a worker stuck in a long step.
        this.send({ type: 'cancelled', runId: msg.runId });
        break;
      case 'lab-truth':
      case 'lab-truth-edit':
      case 'lab-simulate':
      case 'lab-compare':
      case 'lab-batch':
      case 'lab-phases-anatomical':
        if (!this.lab) {
          this.send({ type: 'error', ...idsOf(msg), error: { code: 'lab_unavailable', message: 'this core has no validation lab' } });
          break;
        }
        this.lab.handle(msg);
        break;
      default:
        assertNever(msg);
    }
  }

  private load(reqId: number, fileName: string, bytes: ArrayBuffer, frame: string | undefined, views: LoadRequest['views']): void {
    // Only text is a frame label (a foreign message's number or object reads as none: wasm-bindgen
    // would throw on it); the core reads a blank label as none too.
    const wanted = typeof frame === 'string' ? frame : undefined;
    const study = Array.isArray(views) && views.length > 0 && this.session.load_study;
    const json = study
      ? study.call(this.session, fileName, new Uint8Array(bytes), views.map((v) => String(v.name)), views.map((v) => new Uint8Array(v.bytes)), wanted)
      : this.session.load(fileName, new Uint8Array(bytes), wanted);
    const info = JSON.parse(json) as Omit<
      LoadedFile,
      'points'
    >;
    const file: LoadedFile = { ...info, points: this.session.file_points(fileName) };
    // A session saved before an option existed loads with that option at its default (and one
    // saved before the leave-out list, with none).
    if (file.session) file.session = { ...file.session, options: withDefaultOptions(file.session.options), leave_out: stringsOf(file.session.leave_out) };
    this.send({ type: 'loaded', reqId, file });
  }

  /**
   * Builds the LV wall between a loaded file's two finished meshes (beside a run in progress, which
   * it leaves alone) and sends its figures and file. A wall the core cannot build (the base plane
   * cuts the epicardium twice, a mesh that is no closed surface) is the core's typed error: the
   * request fails, the worker goes on.
   */
  private wall(msg: WallExportRequest): void {
    const build = this.session.wall;
    if (!build) {
      this.send({ type: 'error', reqId: msg.reqId, error: { code: 'wall_unavailable', message: 'this core cannot build the LV wall', file: msg.fileName } });
      return;
    }
    const out = build.call(
      this.session,
      ...runArgs(msg),
      ...meshArgs(msg.endo),
      ...meshArgs(msg.epi),
      msg.minThicknessMm ?? undefined,
      msg.format,
      msg.header.join('\n'),
    );
    const summary = JSON.parse(out.summary) as WallSummary;
    this.send({ type: 'wall-file', reqId: msg.reqId, summary, bytes: out.bytes });
  }

  /**
   * Builds the biventricular wall (BIV_EPI less the LV and RV cavities) of a loaded file's three
   * finished meshes, as `wall` builds the LV one: a wall the core cannot build is its typed error
   * ("the biventricular wall: ..."), the request fails and the worker goes on.
   */
  private bivWall(msg: BivWallExportRequest): void {
    const build = this.session.biventricular_wall;
    if (!build) {
      this.send({ type: 'error', reqId: msg.reqId, error: { code: 'wall_unavailable', message: 'this core cannot build the biventricular wall', file: msg.fileName } });
      return;
    }
    const out = build.call(
      this.session,
      ...runArgs(msg),
      ...meshArgs(msg.lvEndo),
      ...meshArgs(msg.rvEndo),
      ...meshArgs(msg.bivEpi),
      msg.minThicknessMm ?? undefined,
      msg.format,
      msg.header.join('\n'),
    );
    const summary = JSON.parse(out.summary) as WallSummary;
    this.send({ type: 'wall-file', reqId: msg.reqId, summary, bytes: out.bytes });
  }

  /**
   * Whether a derived-file request (the anatomical mesh, the hexahedra) may go to wasm: the core
   * has the call (`available`) and the request the shapes the binding takes (`malformed` says
   * what is wrong, or null). Otherwise its error is sent, `unavailable` or a protocol error
   * starting with `what`, and the worker goes on: what wasm-bindgen would throw on (not the
   * core's typed error) would take the worker down with it.
   */
  private admitted(msg: { reqId: number; fileName: string }, available: boolean, unavailable: string, what: string, malformed: () => string | null): boolean {
    if (!available) {
      this.send({ type: 'error', reqId: msg.reqId, error: { code: unavailable, message: `this core cannot build ${what}`, file: msg.fileName } });
      return false;
    }
    const bad = malformed();
    if (bad) {
      this.send({ type: 'error', reqId: msg.reqId, error: { code: ErrorCodes.protocol, message: `${what}: ${bad}`, file: msg.fileName } });
      return false;
    }
    return true;
  }

  /**
   * Resamples a loaded file's finished LV mesh onto the anatomical layout (beside a run in
   * progress, which it leaves alone) and sends its figures and file. A surface or file that can
   * have none (an RV surface, no RV landmarks or contours to place the septum by) is the core's
   * typed error, its message saying why: the request fails, the worker goes on.
   */
  private anatomical(msg: AnatomicalExportRequest): void {
    const build = this.session.anatomical_mesh;
    if (!this.admitted(msg, build !== undefined, 'anatomical_unavailable', 'the anatomical mesh', () => malformedAnatomical(msg)) || !build) return;
    const out = build.call(
      this.session,
      ...runArgs(msg),
      ...meshArgs(msg.mesh),
      msg.rings,
      msg.points,
      msg.format,
      msg.header.join('\n'),
    );
    const summary = JSON.parse(out.summary) as AnatomicalSummary;
    this.send({ type: 'anatomical-file', reqId: msg.reqId, summary, bytes: out.bytes });
  }

  /**
   * Builds the LV wall's hexahedra between a loaded file's two finished LV meshes (beside a run in
   * progress, which it leaves alone) and sends its figures and VTK file. A file that does not say
   * where the septum is, or a value out of range, is the core's typed error with its reason: the
   * request fails, the worker goes on.
   */
  private hex(msg: HexExportRequest): void {
    const build = this.session.hex_wall;
    if (!this.admitted(msg, build !== undefined, 'hex_unavailable', 'the hexahedral wall', () => malformedHex(msg)) || !build) return;
    const out = build.call(
      this.session,
      ...runArgs(msg),
      ...meshArgs(msg.endo),
      ...meshArgs(msg.epi),
      msg.rings,
      msg.points,
      msg.layers,
      msg.header.join('\n'),
    );
    const summary = JSON.parse(out.summary) as HexSummary;
    this.send({ type: 'hex-file', reqId: msg.reqId, summary, bytes: out.bytes });
  }

  /** The label map's grid from its header (null: not a label map, or a core without the call). */
  private grid(bytes: ArrayBuffer): LabelMapGrid | null {
    const json = this.wasm.labelMapGrid?.(new Uint8Array(bytes));
    if (typeof json !== 'string') return null;
    const g = JSON.parse(json) as LabelMapGrid;
    return Array.isArray(g.dims) && g.dims.length === 3 && typeof g.frames === 'number' ? g : null;
  }

  private startRun(msg: RunRequest): void {
    this.stopRun();
    const run: ActiveRun = {
      runId: msg.runId,
      seq: 0,
      unacked: [],
      batch: [],
      indicesDirty: true,
      attractorsDirty: true,
      contoursDirty: msg.options?.align_slices === true,
      firstFrame: true,
      report: null,
      startedMs: this.options.now(),
      finished: false,
    };
    this.run = run;
    try {
      this.session.start(msg.fileName, msg.surface, paramsJson(msg.params, msg.options, msg.leaveOut), msg.lids);
    } catch (e) {
      this.stopRun();
      this.fail(e, { runId: msg.runId }, msg.fileName);
      return;
    }
    this.options.yieldToEventLoop(() => this.compute(run));
  }

  private stopRun(): void {
    if (this.run) this.run.finished = true;
    this.run = null;
  }

  /** One slice of steps, then yield (or finish). */
  private compute(run: ActiveRun): void {
    if (run.finished || this.run !== run || this.crashed) return;
    const sliceEnd = this.options.now() + this.sliceMs;
    try {
      do {
        const report = JSON.parse(this.session.step()) as StepReport;
        run.report = report;
        this.record(run, report);
        if (report.done) {
          this.finish(run);
          return;
        }
        if (run.unacked.length < this.maxInFlight) this.sendFrame(run);
      } while (this.options.now() < sliceEnd);
    } catch (e) {
      this.stopRun();
      this.fail(e, { runId: run.runId });
      return;
    }
    this.options.yieldToEventLoop(() => this.compute(run));
  }

  private ack(runId: number, seq: number): void {
    const run = this.run;
    if (!run || run.runId !== runId) return;
    run.unacked = run.unacked.filter((s) => s > seq);
    // Catch up right away with the steps computed while the frames were in flight.
    if (run.batch.length > 0 && run.unacked.length < this.maxInFlight) this.sendFrame(run);
  }

  /**
   * Keeps the state of the step just computed until it is sent: the positions always (each leaves
   * wasm memory once, into a buffer of its own), the indices when the topology changed and the
   * attractors when they were re-sampled (the display shares them between steps until then).
   */
  private record(run: ActiveRun, report: StepReport): void {
    const step: StepFrame = { report, positions: this.session.positions() };
    if (report.topology_changed || run.indicesDirty) step.indices = this.session.indices();
    if (this.session.attractors_changed() || run.attractorsDirty) step.attractors = this.session.attractors();
    run.indicesDirty = false;
    run.attractorsDirty = false;
    run.batch.push(step);
  }

  /** Sends every step not yet sent, in one frame. */
  private sendFrame(run: ActiveRun): void {
    if (run.batch.length === 0) return;
    run.seq += 1;
    const msg: FromWorker = { type: 'frame', ...frameOfSteps(run.runId, run.seq, run.batch) };
    run.batch = [];
    if (run.contoursDirty) {
      const { contours } = JSON.parse(this.session.result_json()) as { contours: ContourInfo[] };
      msg.runContours = { contours, points: this.session.contour_points() };
    }
    run.contoursDirty = false;
    if (run.firstFrame) {
      const note = this.session.growth_note();
      if (note) msg.growthNote = note;
    }
    run.firstFrame = false;
    run.unacked.push(run.seq);
    this.send(msg);
  }

  private finish(run: ActiveRun): void {
    this.sendFrame(run); // the final frame goes out whatever the back-pressure
    const small = JSON.parse(this.session.result_json()) as ResultJson;
    const last = run.report;
    const result: RunResult = {
      ...small,
      options: withDefaultOptions(small.options),
      alignment: small.alignment ?? null,
      end_caps: small.end_caps ?? null,
      set_aside: small.set_aside ?? [],
      leave_out: stringsOf(small.leave_out),
      set_aside_contours: small.set_aside_contours ?? [],
      contour_to_mesh_as_given: small.contour_to_mesh_as_given ?? null,
      ...convergence(last),
      runId: run.runId,
      contours: small.contours as ContourInfo[],
      contourPoints: this.session.contour_points(),
      positions: this.session.positions(),
      ...fullPrecision(this.session),
      indices: this.session.indices(),
      pointDistances: this.session.point_distances(),
      vertexDistances: this.session.vertex_distances(),
      setAsidePoints: this.session.set_aside_points(),
      ...setAsideDistances(this.session),
      seconds: (this.options.now() - run.startedMs) / 1000,
    };
    this.stopRun();
    this.send({ type: 'done', result });
  }

  private send(msg: FromWorker): void {
    this.post(msg, transferablesOf(msg));
  }

  /** Reports an error; a non-CoreError (trap, panic, bug) marks the worker as crashed. */
  private fail(e: unknown, ids: { reqId?: number; runId?: number }, file?: string): void {
    const data = wasmErrorData(e);
    if (data) {
      if (file !== undefined && data.file === undefined) data.file = file;
      this.send({ type: 'error', ...ids, error: data });
      return;
    }
    this.crashed = true;
    this.stopRun();
    this.lab?.stop();
    const panic = safe(() => this.wasm.takePanicMessage());
    const detail = e instanceof Error ? `${e.name}: ${e.message}` : String(e);
    const error: CoreErrorData = {
      code: ErrorCodes.workerCrashed,
      message: panic ? `${panic} (${detail})` : detail,
    };
    if (file !== undefined) error.file = file;
    this.send({ type: 'error', ...ids, error });
  }
}

/**
 * How many deformation iterations the run did and whether it stopped early because the attractors
 * were reached (the core's stop threshold): the final step's report says `done` before its
 * `iteration` reaches `total_iterations`.
 */
export function convergence(last: StepReport | null): { iterations_done?: number; converged?: boolean } {
  if (!last) return {};
  return { iterations_done: last.iteration, converged: last.done && last.iteration < last.total_iterations };
}

/** The CoreErrorData in a value thrown by the wasm Session, or null if it is not one. */
export function wasmErrorData(e: unknown): CoreErrorData | null {
  if (typeof e !== 'string' || !e.startsWith('{')) return null;
  try {
    const v: unknown = JSON.parse(e);
    return isCoreErrorData(v) ? { ...v } : null;
  } catch {
    return null;
  }
}

function idsOf(msg: ToWorker): { reqId?: number; runId?: number } {
  switch (msg.type) {
    case 'load':
    case 'grid':
    case 'schema':
    case 'lab-truth':
    case 'lab-truth-edit':
    case 'lab-simulate':
    case 'lab-compare':
    case 'lab-phases-anatomical':
    case 'session-export':
    case 'wall-export':
    case 'biv-wall-export':
    case 'anatomical-export':
    case 'hex-export':
      return { reqId: msg.reqId };
    case 'run':
    case 'ack':
    case 'cancel':
    case 'lab-batch':
      return { runId: msg.runId };
    default:
      return assertNever(msg);
  }
}

/**
 * What is wrong with an 'anatomical-export' request in the shapes the binding takes (null: nothing):
 * a foreign or buggy message is refused as data instead of reaching wasm-bindgen's conversions.
 * The layout's ranges are the core's to check: it says them in its message.
 */
export function malformedAnatomical(msg: AnatomicalExportRequest): string | null {
  const m = msg.mesh as Partial<AnatomicalExportRequest['mesh']> | undefined;
  if (!m || typeof m.surface !== 'string') return 'the request names no surface';
  if (!(m.positions instanceof Float64Array) || !(m.indices instanceof Uint32Array)) return 'the mesh must be a Float64Array of positions and a Uint32Array of indices';
  const count = (v: unknown) => typeof v === 'number' && Number.isInteger(v) && v >= 0 && v <= 0xffff_ffff;
  if (!count(msg.rings) || !count(msg.points)) return `the layout must be two whole numbers (got ${String(msg.rings)}x${String(msg.points)})`;
  if (typeof msg.format !== 'string' || !Array.isArray(msg.header)) return 'the request has no format or no header';
  return null;
}

/**
 * What is wrong with a 'hex-export' request in the shapes the binding takes (null: nothing), as
 * `malformedAnatomical`: refused as data before wasm-bindgen's conversions. The ranges (rings,
 * points, layers) are the core's to check: it says them in its message.
 */
export function malformedHex(msg: HexExportRequest): string | null {
  for (const [what, m] of [['endocardium', msg.endo], ['epicardium', msg.epi]] as const) {
    const mesh = m as Partial<HexExportRequest['endo']> | undefined;
    if (!mesh || typeof mesh.surface !== 'string') return `the request names no ${what} surface`;
    if (!(mesh.positions instanceof Float64Array) || !(mesh.indices instanceof Uint32Array)) return `the ${what} mesh must be a Float64Array of positions and a Uint32Array of indices`;
  }
  const count = (v: unknown) => typeof v === 'number' && Number.isInteger(v) && v >= 0 && v <= 0xffff_ffff;
  if (!count(msg.rings) || !count(msg.points) || !count(msg.layers)) {
    return `the layout and layers must be whole numbers (got ${String(msg.rings)}x${String(msg.points)}x${String(msg.layers)})`;
  }
  if (!Array.isArray(msg.header)) return 'the request has no header';
  return null;
}

/** The finished mesh's vertices and their distances in full precision, where the core gives them. */
function fullPrecision(session: SessionApi): { positionsF64?: Float64Array; vertexDistancesF64?: Float64Array } {
  const p = session.positions_f64?.();
  const d = session.vertex_distances_f64?.();
  return {
    ...(p instanceof Float64Array ? { positionsF64: p } : {}),
    ...(d instanceof Float64Array ? { vertexDistancesF64: d } : {}),
  };
}

/** How far the finished mesh passes each point left out, where the core says (an older one does not). */
function setAsideDistances(session: SessionApi): { setAsidePointDistances?: Float32Array } {
  const d = session.set_aside_point_distances?.();
  return d instanceof Float32Array ? { setAsidePointDistances: d } : {};
}

/** A list of ids from the core's JSON: [] when absent (an older core) or not a list of strings. */
function stringsOf(v: unknown): string[] {
  return Array.isArray(v) ? v.filter((x): x is string => typeof x === 'string') : [];
}

function safe<T>(f: () => T): T | undefined {
  try {
    return f();
  } catch {
    return undefined;
  }
}
