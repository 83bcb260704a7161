/**
 * The typed message protocol between the main thread (CoreClient) and the reconstruction worker.
 *
 * Every message is a discriminated union on `type`; every run-scoped message carries its `runId`
 * so that stale frames of a cancelled run can be dropped. Bulk data travel as flat typed arrays in
 * millimetres, transferred (never copied) between threads; small reports are plain objects whose
 * field names follow the Rust structs (snake_case) they are serialised from.
 */

/** Numeric parameter values by Rust schema name (`Params::schema()`). */
export interface ParamValues {
  [name: string]: number;
}

export type LidsMode = 'auto' | 'none';

/** How the remesh step smooths (the core's `SmoothingMethod::ALL` names). */
export type SmoothingMethodName = 'laplacian-affine' | 'taubin';
export const SMOOTHING_METHODS: readonly SmoothingMethodName[] = ['laplacian-affine', 'taubin'];

/**
 * The reconstruction options that are not numbers (so not in the schema). They travel inside the
 * params JSON object under these names (the binding's convert.rs), for the run, the sweep and
 * leave-one-out alike; absent means the core's default.
 */
export interface ReconOptions {
  smoothing_method: SmoothingMethodName;
  /** Down-weight SAX vs LAX attractors that disagree in the final steps (the core's default). */
  soften_conflicts: boolean;
  /**
   * Breath-hold alignment: shift each short-axis slice and long-axis view in its own plane so the
   * curves agree where planes cross, then reconstruct the shifted contours (off by default: the
   * paper's method takes the contours as given).
   */
  align_slices: boolean;
}

export const DEFAULT_OPTIONS: Readonly<ReconOptions> = { smoothing_method: 'laplacian-affine', soften_conflicts: true, align_slices: false };

/**
 * Options as saved by anything older than one of them (a session, a URL, a test double): the
 * missing ones take the core's default.
 */
export function withDefaultOptions(options: Partial<ReconOptions> | null | undefined): ReconOptions {
  return { ...DEFAULT_OPTIONS, ...(options ?? {}) };
}

/** The params JSON object the binding reads: schema numbers plus the options. */
export function paramsJson(params: ParamValues, options?: ReconOptions): string {
  if (!options) return JSON.stringify(params);
  const o = withDefaultOptions(options);
  return JSON.stringify({ ...params, smoothing_method: o.smoothing_method, soften_conflicts: o.soften_conflicts, align_slices: o.align_slices });
}

/** What a saved heartmesh session file carries besides its contours (applied by the app on load). */
export interface SessionSettings {
  params: ParamValues;
  lids: LidsMode;
  options: ReconOptions;
  surface: string | null;
}

/** One numeric parameter as described by the Rust `Params::schema()`. */
export interface ParamSpec {
  name: string;
  default: number;
  min: number;
  max: number;
  log: boolean;
  integer: boolean;
  unit: string;
  help: string;
}

/** An error that crossed the worker boundary as data, with the core's stable code. */
export interface CoreErrorData {
  code: string;
  message: string;
  file?: string;
  line?: number;
  /** Surfaces to choose from, for `surface_required` / `unknown_surface`. */
  available?: string[];
}

export type ContourKindName = 'SAX' | 'LAX';

export interface ContourInfo {
  id: string;
  surface: string | null;
  /** The core's SAX/LAX split (at load: per surface, null where undecidable; after a run: the run's). */
  kind: ContourKindName | null;
  /** `start`/`count` index points (not floats) into the accompanying point array. */
  pieces: { closed: boolean; start: number; count: number }[];
}

export interface Landmark {
  name: string;
  x: number;
  y: number;
  z: number;
}

export interface LoadedFile {
  fileName: string;
  surfaces: string[];
  contours: ContourInfo[];
  /** xyz of all contour points, mm. */
  points: Float32Array;
  landmarks: Landmark[];
  warnings: string[];
  /** Settings of a saved session file (null or absent for other formats). */
  session?: SessionSettings | null;
}

export type Phase = 'initial_tube' | 'deform' | 'remesh' | 'done';

export interface PhaseTimings {
  attractors_ms: number;
  closest_ms: number;
  solve_ms: number;
  apply_ms: number;
  remesh_ms: number;
  total_ms: number;
}

/** Mirror of the Rust `pipeline::StepReport`. */
export interface StepReport {
  iteration: number;
  total_iterations: number;
  phase: Phase;
  topology_changed: boolean;
  max_distance_mm: number;
  mean_distance_mm: number;
  vertices: number;
  triangles: number;
  attractors: number;
  timings: PhaseTimings;
  done: boolean;
}

export interface Frame {
  runId: number;
  seq: number;
  report: StepReport;
  /** Vertex positions, xyz, mm. Always present. */
  positions: Float32Array;
  /** Triangle indices; only when the topology changed since the last frame the receiver got. */
  indices?: Uint32Array;
  /** Attractor points, xyz, mm; only when they were re-sampled since the last frame sent. */
  attractors?: Float32Array;
  /**
   * The contours the run follows, on its first frame, when they are not the file's as given (the
   * run aligns breath-holds: these are the shifted ones), so the display shows them while it runs.
   */
  runContours?: { contours: ContourInfo[]; points: Float32Array };
}

export interface Stats {
  mean: number;
  median: number;
  p95: number;
  max: number;
  min: number;
  count: number;
}

export interface ContourStats {
  id: string;
  kind: ContourKindName;
  stats: Stats;
}

/** One short-axis slice or long-axis view moved by the breath-hold alignment (the core's `GroupShift`). */
export interface AlignmentGroup {
  kind: ContourKindName;
  /** "SAX 3" (apex to base), or the long-axis contour ids. */
  label: string;
  contour_ids: string[];
  /** In-plane shift applied to every contour of the group, mm. */
  shift_mm: [number, number, number];
}

/** What the breath-hold alignment did (the core's `Alignment`, in `result_json().alignment`). */
export interface Alignment {
  rounds: number;
  /** Mean in-plane distance between crossing curves before and after the shifts, mm. */
  residual_before_mm: number;
  residual_after_mm: number;
  groups: AlignmentGroup[];
  /** Why nothing moved (no long-axis view, no crossings), when the core says so. */
  note?: string | null;
}

/** Contour-to-mesh distance summary (mm). */
export interface DistanceSummary {
  mean: number;
  median: number;
  max: number;
}

export interface RunResult {
  runId: number;
  surface: string | null;
  contours: ContourInfo[];
  contourPoints: Float32Array;
  positions: Float32Array;
  indices: Uint32Array;
  /** Per contour point, mm, same order as contourPoints. */
  pointDistances: Float32Array;
  /** Per mesh vertex, mm. */
  vertexDistances: Float32Array;
  perContour: ContourStats[];
  overall: Stats;
  volumeMl: number;
  areaMm2: number;
  watertight: boolean;
  seconds: number;
  params: ParamValues;
  lids: LidsMode;
  options: ReconOptions;
  version: string;
  /** Breath-hold alignment of the run: null or absent when the option was off. */
  alignment?: Alignment | null;
  /**
   * With alignment on: contour-to-mesh distance to the file's contours as given (`overall` is to
   * the shifted contours the mesh follows).
   */
  contour_to_mesh_as_given?: DistanceSummary | null;
  /** Deformation iterations done (the last step's `iteration`), set by the worker. */
  iterations_done?: number;
  /** The run stopped before `params.iterations` because the attractors were reached (stop threshold). */
  converged?: boolean;
}


// ---------------------------------------------------------------------------------------------
// Validation lab (issue 5; web/src/lab). Field names of reports follow the Rust structs.

/** The built-in parametric LV (truncated prolate spheroid), mm and degrees; missing = defaults. */
export interface ParametricLvSpec {
  length_mm?: number;
  radius_mm?: number;
  base_radius_mm?: number;
  /** Regional bulge: outward displacement at its centre (0 = none). */
  bulge_mm?: number;
  /** Height of the bulge centre, 0 = apex, 1 = base. */
  bulge_height?: number;
  bulge_angle_deg?: number;
  bulge_width_mm?: number;
}

export type LabTruthSource =
  | { kind: 'parametric'; lv: ParametricLvSpec }
  | { kind: 'file'; fileName: string; bytes: ArrayBuffer };

/** A simulated CMR acquisition: SAX count or spacing, LAX count (paper angles), misalignment, noise. */
export interface AcquisitionSpec {
  sax_count?: number;
  sax_spacing_mm?: number;
  lax_count?: number;
  shift_mm?: number;
  tilt_deg?: number;
  noise_mm?: number;
  seed?: number;
}

export interface LabTruth {
  name: string;
  vertices: number;
  triangles: number;
  volumeMl: number;
  closed: boolean;
  positions: Float32Array;
  indices: Uint32Array;
}

export interface LabAcquisition {
  sax: number;
  lax: number;
  points: number;
  /** The most basal SAX plane (both surfaces are clipped there before measuring). */
  clip: { origin: [number, number, number]; normal: [number, number, number] };
  /** The contours as canonical CSV, loaded like a dropped file. */
  csv: ArrayBuffer;
}

/** Mirror of the Rust `metrics::compare::DistanceStats`. */
export interface DistanceStats {
  mean: number;
  median: number;
  p95: number;
  max: number;
  max_at: [number, number, number];
  min: number;
  count: number;
}

/** Mirror of the Rust `metrics::compare::CompareReport`. */
export interface CompareReport {
  mesh_to_truth: DistanceStats;
  truth_to_mesh: DistanceStats;
  hausdorff: number;
  volume_truth_ml: number;
  volume_mesh_ml: number;
  clipped: boolean;
}

export interface LabComparison {
  report: CompareReport;
  /** Per truth vertex, distance to the mesh, mm. */
  truthDistances: Float32Array;
}

/** Which contours, surface and parameters a batch rebuilds. */
export interface LabBatchBase {
  fileName: string;
  surface: string | null;
  params: ParamValues;
  lids: LidsMode;
  /** Missing: the core's defaults. */
  options?: ReconOptions;
}

/** Values per swept parameter (empty or missing: the base value). */
export interface SweepGrid {
  lambda?: number[];
  smoothing_iterations?: number[];
  target_reduction?: number[];
  attractor_spacing?: number[];
}

export type LabBatchJob =
  | ({ kind: 'loo' } & LabBatchBase)
  | ({ kind: 'sweep'; grid: SweepGrid; withTruth: boolean } & LabBatchBase);

export interface LabBatchInfo {
  total: number;
  /** Leave-one-out: the cleaned contours in item order, and their points (xyz mm). */
  contours?: ContourInfo[];
  points?: Float32Array;
}

/** One left-out contour: its points' distance to the mesh rebuilt without it. */
export interface LooItem {
  index: number;
  id: string | null;
  kind: ContourKindName;
  stats: Stats | null;
  error: string | null;
}

/** One point of the parameter sweep. */
export interface SweepItem {
  index: number;
  lambda: number;
  smoothing_iterations: number;
  target_reduction: number;
  attractor_spacing: number;
  error: string | null;
  contour_mean?: number;
  contour_max?: number;
  volume_ml?: number;
  triangles?: number;
  /** Mesh-to-truth mean and Hausdorff (mm), when swept with the truth. */
  truth_mean?: number;
  hausdorff?: number;
}

export interface LabProgress {
  completed: number;
  total: number;
  item?: LooItem | SweepItem;
}

// ---------------------------------------------------------------------------------------------
// Messages

export interface LoadRequest {
  type: 'load';
  reqId: number;
  fileName: string;
  bytes: ArrayBuffer;
}
export interface RunRequest {
  type: 'run';
  runId: number;
  fileName: string;
  surface: string | null;
  params: ParamValues;
  lids: LidsMode;
  /** Missing: the core's defaults. */
  options?: ReconOptions;
}
/** Acknowledges every frame of `runId` up to and including `seq` (cumulative). */
export interface AckRequest {
  type: 'ack';
  runId: number;
  seq: number;
}
export interface CancelRequest {
  type: 'cancel';
  runId: number;
}
export interface SchemaRequest {
  type: 'schema';
  reqId: number;
}
/** A heartmesh session file (contours + settings, the core's format) of a loaded file. */
export interface SessionExportRequest {
  type: 'session-export';
  reqId: number;
  fileName: string;
  surface: string | null;
  params: ParamValues;
  lids: LidsMode;
  options?: ReconOptions;
  appVersion: string;
}

export interface LabTruthRequest {
  type: 'lab-truth';
  reqId: number;
  source: LabTruthSource;
}
export interface LabSimulateRequest {
  type: 'lab-simulate';
  reqId: number;
  acquisition: AcquisitionSpec;
}
/** Positions and indices are copies: they are transferred to the worker. */
export interface LabCompareRequest {
  type: 'lab-compare';
  reqId: number;
  positions: Float32Array;
  indices: Uint32Array;
}
/** Starts a batch under `runId` (cancelled with a 'cancel' of the same id). */
export interface LabBatchRequest {
  type: 'lab-batch';
  runId: number;
  job: LabBatchJob;
}

export type LabRequest = LabTruthRequest | LabSimulateRequest | LabCompareRequest | LabBatchRequest;

export type ToWorker = LoadRequest | RunRequest | AckRequest | CancelRequest | SchemaRequest | SessionExportRequest | LabRequest;

export interface ReadyMessage {
  type: 'ready';
}
export interface LoadedMessage {
  type: 'loaded';
  reqId: number;
  file: LoadedFile;
}
export interface FrameMessage extends Frame {
  type: 'frame';
}
export interface DoneMessage {
  type: 'done';
  result: RunResult;
}
export interface ErrorMessage {
  type: 'error';
  reqId?: number;
  runId?: number;
  error: CoreErrorData;
}
export interface SessionJsonMessage {
  type: 'session-json';
  reqId: number;
  /** UTF-8 JSON. */
  bytes: Uint8Array;
}
export interface SchemaMessage {
  type: 'schema';
  reqId: number;
  schema: ParamSpec[];
  version: string;
}

export interface LabTruthMessage {
  type: 'lab-truth';
  reqId: number;
  truth: LabTruth;
}
export interface LabSimulatedMessage {
  type: 'lab-simulated';
  reqId: number;
  acquisition: LabAcquisition;
}
export interface LabComparedMessage {
  type: 'lab-compared';
  reqId: number;
  comparison: LabComparison;
}
export interface LabBatchStartedMessage {
  type: 'lab-batch-started';
  runId: number;
  info: LabBatchInfo;
}
export interface LabProgressMessage {
  type: 'lab-progress';
  runId: number;
  progress: LabProgress;
}
export interface LabBatchDoneMessage {
  type: 'lab-batch-done';
  runId: number;
}

export type LabMessage =
  | LabTruthMessage
  | LabSimulatedMessage
  | LabComparedMessage
  | LabBatchStartedMessage
  | LabProgressMessage
  | LabBatchDoneMessage;

export type FromWorker =
  | LabMessage
  | ReadyMessage
  | LoadedMessage
  | FrameMessage
  | DoneMessage
  | ErrorMessage
  | SchemaMessage
  | SessionJsonMessage;

// ---------------------------------------------------------------------------------------------
// Helpers

/** Error codes produced outside the Rust core. */
export const ErrorCodes = {
  /** The worker died (wasm trap, Rust panic, script error): it is discarded and recreated. */
  workerCrashed: 'worker_crashed',
  /** The run was cancelled (explicitly, or superseded by a newer run). */
  cancelled: 'cancelled',
  /** `run` named a file that was never loaded. */
  notLoaded: 'not_loaded',
  /** The client was disposed while the request was pending. */
  disposed: 'disposed',
  /** A message that does not match the protocol. */
  protocol: 'protocol',
} as const;

/** Compile-time exhaustiveness check for switches over a union's `type`. */
export function assertNever(value: never, what = 'message'): never {
  const type = (value as { type?: unknown } | null)?.type;
  throw new Error(`unexpected ${what}: ${JSON.stringify(type ?? value)}`);
}

/** True for errors after which the worker must be discarded. */
export function isFatal(error: CoreErrorData): boolean {
  return error.code === ErrorCodes.workerCrashed;
}

/** Normalises anything thrown (an Error, a CoreErrorData, a JSON string from wasm) into data. */
export function toCoreErrorData(e: unknown, file?: string): CoreErrorData {
  let data: CoreErrorData;
  if (isCoreErrorData(e)) {
    data = { ...e };
  } else if (typeof e === 'string') {
    data = parseErrorJson(e) ?? { code: 'internal', message: e };
  } else if (e instanceof Error) {
    data = parseErrorJson(e.message) ?? { code: 'internal', message: e.message || String(e) };
  } else {
    data = { code: 'internal', message: String(e) };
  }
  if (file !== undefined && data.file === undefined) data.file = file;
  return data;
}

function parseErrorJson(text: string): CoreErrorData | null {
  if (!text.startsWith('{')) return null;
  try {
    const v: unknown = JSON.parse(text);
    return isCoreErrorData(v) ? v : null;
  } catch {
    return null;
  }
}

export function isCoreErrorData(v: unknown): v is CoreErrorData {
  return (
    typeof v === 'object' &&
    v !== null &&
    typeof (v as CoreErrorData).code === 'string' &&
    typeof (v as CoreErrorData).message === 'string'
  );
}

/** Buffers of a message that can be transferred instead of copied (each listed once). */
export function transferablesOf(msg: ToWorker | FromWorker): ArrayBuffer[] {
  const out = new Set<ArrayBuffer>();
  const add = (a: ArrayBufferView | ArrayBuffer | undefined) => {
    if (a === undefined) return;
    const buf = a instanceof ArrayBuffer ? a : a.buffer;
    if (buf instanceof ArrayBuffer && buf.byteLength > 0) out.add(buf);
  };
  switch (msg.type) {
    case 'load':
      add(msg.bytes);
      break;
    case 'loaded':
      add(msg.file.points);
      break;
    case 'frame':
      add(msg.positions);
      add(msg.indices);
      add(msg.attractors);
      add(msg.runContours?.points);
      break;
    case 'done': {
      const r = msg.result;
      add(r.contourPoints);
      add(r.positions);
      add(r.indices);
      add(r.pointDistances);
      add(r.vertexDistances);
      break;
    }
    case 'lab-truth':
      if ('truth' in msg) {
        add(msg.truth.positions);
        add(msg.truth.indices);
      } else if (msg.source.kind === 'file') {
        add(msg.source.bytes);
      }
      break;
    case 'lab-simulated':
      add(msg.acquisition.csv);
      break;
    case 'lab-compare':
      add(msg.positions);
      add(msg.indices);
      break;
    case 'lab-compared':
      add(msg.comparison.truthDistances);
      break;
    case 'lab-batch-started':
      add(msg.info.points);
      break;
    case 'session-json':
      add(msg.bytes);
      break;
    case 'session-export':
    case 'run':
    case 'ack':
    case 'cancel':
    case 'schema':
    case 'ready':
    case 'error':
    case 'lab-simulate':
    case 'lab-batch':
    case 'lab-progress':
    case 'lab-batch-done':
      break;
    default:
      return assertNever(msg);
  }
  return [...out];
}

/** The run a message belongs to, if any. */
export function runIdOf(msg: FromWorker): number | undefined {
  switch (msg.type) {
    case 'frame':
      return msg.runId;
    case 'done':
      return msg.result.runId;
    case 'error':
      return msg.runId;
    case 'lab-batch-started':
    case 'lab-progress':
    case 'lab-batch-done':
      return msg.runId;
    case 'ready':
    case 'loaded':
    case 'schema':
    case 'lab-truth':
    case 'lab-simulated':
    case 'lab-compared':
    case 'session-json':
      return undefined;
    default:
      return assertNever(msg);
  }
}

/** Cheap structural check of an incoming worker message (guards against foreign postMessage). */
export function isFromWorker(v: unknown): v is FromWorker {
  if (typeof v !== 'object' || v === null) return false;
  switch ((v as { type?: unknown }).type) {
    case 'ready':
    case 'loaded':
    case 'frame':
    case 'done':
    case 'error':
    case 'schema':
    case 'lab-truth':
    case 'lab-simulated':
    case 'lab-compared':
    case 'lab-batch-started':
    case 'lab-progress':
    case 'lab-batch-done':
    case 'session-json':
      return true;
    default:
      return false;
  }
}

/** Cheap structural check of an incoming request on the worker side. */
export function isToWorker(v: unknown): v is ToWorker {
  if (typeof v !== 'object' || v === null) return false;
  switch ((v as { type?: unknown }).type) {
    case 'load':
    case 'run':
    case 'ack':
    case 'cancel':
    case 'schema':
    case 'lab-truth':
    case 'lab-simulate':
    case 'lab-compare':
    case 'lab-batch':
    case 'session-export':
      return true;
    default:
      return false;
  }
}

/**
 * Merges a newer frame over an older one that was never handed to the renderer: the newer
 * positions win, but topology (indices), attractors and run contours of the skipped frame are carried over when
 * the newer frame does not have its own, so the receiver never misses a topology change.
 */
export function mergeFrames(older: Frame, newer: Frame): Frame {
  const merged: Frame = { ...newer };
  if (merged.indices === undefined && older.indices !== undefined) merged.indices = older.indices;
  if (merged.attractors === undefined && older.attractors !== undefined) {
    merged.attractors = older.attractors;
  }
  if (merged.runContours === undefined && older.runContours !== undefined) merged.runContours = older.runContours;
  return merged;
}
