/**
 * The messages themselves: requests to the worker (`ToWorker`) and its answers (`FromWorker`),
 * each a discriminated union on `type`. Run-scoped messages carry their `runId` so stale frames of
 * a cancelled run can be dropped; one-shot requests carry a `reqId` their answer echoes.
 */

import type { CoreErrorData } from './protocolErrors';
import type {
  AcquisitionSpec, AnatomicalStudy, LabAcquisition, LabBatchInfo, LabComparison, LabProgress, LabTruth, LabTruthEdit, LabTruthSource, LabTruthSummary, WorkerBatchJob,
} from './protocolLab';
import type { LidsMode, ParamSpec, ParamValues, ReconOptions } from './protocolOptions';
import type { Frame, LabelMapGrid, LoadedFile, RunResult, ViewFile, WallFormat, WallSummary, WallSurfaceMesh } from './protocolResults';
import type { AnatomicalFormat, AnatomicalSummary } from './protocolAnatomical';
import type { HexSummary } from './protocolHex';

export interface LoadRequest {
  type: 'load';
  reqId: number;
  fileName: string;
  bytes: ArrayBuffer;
  /** The time frame to read of a file that holds several, by its label (`9`, `ES`; absent: each contour's first). */
  frame?: string;
  /**
   * Long-axis views read with this short-axis label map, or the DICOM images (headers) of this cvi42
   * workspace (the core's `load_study`; absent or empty: the file alone). A view the core cannot
   * read refuses the load, its file named in the message; images it cannot place are set aside.
   */
  views?: ViewFile[];
}
/** The voxel grid of a label map (NIfTI, NRRD, DICOM SEG), from its header (answered with 'grid'; null: not one). */
export interface GridRequest {
  type: 'grid';
  reqId: number;
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
  /**
   * Contour ids the user left out of this file and frame, any surface's (the Contours panel);
   * missing or empty: none. Sent in the params JSON as `leave_out` (protocolOptions `paramsJson`); a separate field,
   * not an option, because the ids belong to one file while the options hold for any.
   */
  leaveOut?: string[];
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
  /** The contours left out by the user, as `RunRequest.leaveOut`: the session records them. */
  leaveOut?: string[];
  appVersion: string;
}
/**
 * The LV myocardium wall of a loaded file (the command line's `heartmesh myocardium`), built in the
 * worker from the finished LV_ENDO and LV_EPI meshes the app holds, both run with these settings
 * (the base plane comes from the file's contours at them); answered with 'wall-file'.
 */
export interface WallExportRequest {
  type: 'wall-export';
  reqId: number;
  fileName: string;
  params: ParamValues;
  lids: LidsMode;
  options?: ReconOptions;
  /** The file and frame's leave-out list, which both meshes were run with: the base plane's contours. */
  leaveOut?: string[];
  endo: WallSurfaceMesh;
  epi: WallSurfaceMesh;
  /** Endocardial vertices closer to the epicardium than this (mm) are moved under it first; null: off. */
  minThicknessMm: number | null;
  format: WallFormat;
  /** Lines the file's header carries after the command line's comment (app version, settings). */
  header: string[];
}

/**
 * The biventricular myocardium of a loaded file (`heartmesh myocardium --biventricular`), built in
 * the worker from the finished LV_ENDO, RV_ENDO and BIV_EPI meshes the app holds, all run with
 * these settings (the base plane comes from the file's contours at them); answered with 'wall-file'.
 */
export interface BivWallExportRequest {
  type: 'biv-wall-export';
  reqId: number;
  fileName: string;
  params: ParamValues;
  lids: LidsMode;
  options?: ReconOptions;
  /** The file and frame's leave-out list, which the three meshes were run with: the base plane's contours. */
  leaveOut?: string[];
  lvEndo: WallSurfaceMesh;
  rvEndo: WallSurfaceMesh;
  /** The biventricular epicardium (the file's LV_EPI and RV_EPI curves joined). */
  bivEpi: WallSurfaceMesh;
  /** Endocardial vertices closer to the epicardium (or the other cavity) than this (mm) are moved first; null: off. */
  minThicknessMm: number | null;
  format: WallFormat;
  /** Lines the file's header carries after the command line's comment (app version, settings). */
  header: string[];
}

/**
 * The anatomical mesh of a finished LV surface (the command line's `reconstruct --anatomical-mesh`):
 * `mesh` is that surface's finished mesh as the app holds it, run with these settings (the base
 * plane comes from the file's contours at them); answered with 'anatomical-file'.
 */
export interface AnatomicalExportRequest {
  type: 'anatomical-export';
  reqId: number;
  fileName: string;
  params: ParamValues;
  lids: LidsMode;
  options?: ReconOptions;
  /** The contours the mesh's run left out at the user's request: the base plane's contours. */
  leaveOut?: string[];
  /** The surface (LV_ENDO, LV_EPI) and its finished mesh. */
  mesh: WallSurfaceMesh;
  /** The layout: rings from the apex to the base, vertices per ring (the core checks the ranges too). */
  rings: number;
  points: number;
  format: AnatomicalFormat;
  /** Lines the file's header carries after the command line's comment (app version, settings). */
  header: string[];
}

/**
 * The LV wall as layers of hexahedra (the command line's `myocardium --hex-mesh`), built in the
 * worker from the finished LV_ENDO and LV_EPI meshes the app holds, both run with these settings
 * (the base plane comes from the file's contours at them); answered with 'hex-file'.
 */
export interface HexExportRequest {
  type: 'hex-export';
  reqId: number;
  fileName: string;
  params: ParamValues;
  lids: LidsMode;
  options?: ReconOptions;
  /** The file and frame's leave-out list, which both meshes were run with: the base plane's contours. */
  leaveOut?: string[];
  endo: WallSurfaceMesh;
  epi: WallSurfaceMesh;
  /** Each surface's layout (rings from the apex to the base, points per ring) and the cells through the wall (the core checks the ranges too). */
  rings: number;
  points: number;
  layers: number;
  /** Lines the file's header carries after the command line's comment (app version, settings). */
  header: string[];
}

export interface LabTruthRequest {
  type: 'lab-truth';
  reqId: number;
  source: LabTruthSource;
  /** Beside the truths held (a file only); absent: replaces them all. */
  add?: boolean;
  /** Its surface label (absent or null: none). */
  label?: string | null;
}
/** Relabels or removes one truth (answered with 'lab-truths'). */
export interface LabTruthEditRequest {
  type: 'lab-truth-edit';
  reqId: number;
  edit: LabTruthEdit;
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
  /** The reconstructed surface: measured against the truth of that label (one truth: that one). */
  surface?: string | null;
}
/** Starts a batch under `runId` (cancelled with a 'cancel' of the same id). */
export interface LabBatchRequest {
  type: 'lab-batch';
  runId: number;
  job: WorkerBatchJob;
}

/**
 * The anatomical meshes of the worker's last finished phases batch (the command line's `volumes
 * --anatomical-meshes`): every phase's LV surfaces on `rings` x `points`, one septum for all;
 * answered with 'lab-phases-anatomical', or an error saying why there are none.
 */
export interface LabPhasesAnatomicalRequest {
  type: 'lab-phases-anatomical';
  reqId: number;
  rings: number;
  points: number;
  format: AnatomicalFormat;
}
export type LabRequest = LabTruthRequest | LabTruthEditRequest | LabSimulateRequest | LabCompareRequest | LabBatchRequest | LabPhasesAnatomicalRequest;

export type ToWorker = LoadRequest | GridRequest | RunRequest | AckRequest | CancelRequest | SchemaRequest | SessionExportRequest | WallExportRequest | BivWallExportRequest | AnatomicalExportRequest | HexExportRequest | LabRequest;

export interface ReadyMessage {
  type: 'ready';
}
export interface LoadedMessage {
  type: 'loaded';
  reqId: number;
  file: LoadedFile;
}
export interface GridMessage {
  type: 'grid';
  reqId: number;
  grid: LabelMapGrid | null;
}
export interface FrameMessage extends Frame {
  type: 'frame';
}
export interface DoneMessage {
  type: 'done';
  result: RunResult;
}
/**
 * The worker has handled a 'cancel' (sent whether or not the run was still going). The client
 * waits a short grace period for it; a worker that does not answer is inside one long step, and
 * the client replaces it (CoreClient.ts, CANCEL_GRACE_MS).
 */
export interface CancelledMessage {
  type: 'cancelled';
  runId: number;
}
/**
 * The worker begins reading a file (sent before the parse, which may take seconds): the client
 * then knows that the worker is busy with its request, not inside a step of a run.
 */
export interface StartedMessage {
  type: 'started';
  reqId: number;
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
/** A wall built (the LV one or the biventricular one): its figures and the file in the format asked for. */
export interface WallFileMessage {
  type: 'wall-file';
  reqId: number;
  summary: WallSummary;
  bytes: Uint8Array;
}
/** An anatomical mesh built: its figures and the file in the format asked for. */
export interface AnatomicalFileMessage {
  type: 'anatomical-file';
  reqId: number;
  summary: AnatomicalSummary;
  bytes: Uint8Array;
}
/** The hexahedral wall built: its figures and the VTK unstructured grid. */
export interface HexFileMessage {
  type: 'hex-file';
  reqId: number;
  summary: HexSummary;
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
export interface LabTruthsMessage {
  type: 'lab-truths';
  reqId: number;
  truths: LabTruthSummary[];
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

/** The anatomical meshes of the last finished phases batch: the report and the files. */
export interface LabPhasesAnatomicalMessage {
  type: 'lab-phases-anatomical';
  reqId: number;
  study: AnatomicalStudy;
}

export type LabMessage =
  | LabPhasesAnatomicalMessage
  | LabTruthMessage
  | LabTruthsMessage
  | LabSimulatedMessage
  | LabComparedMessage
  | LabBatchStartedMessage
  | LabProgressMessage
  | LabBatchDoneMessage;

export type FromWorker =
  | LabMessage
  | ReadyMessage
  | LoadedMessage
  | GridMessage
  | FrameMessage
  | DoneMessage
  | CancelledMessage
  | StartedMessage
  | ErrorMessage
  | SchemaMessage
  | SessionJsonMessage
  | WallFileMessage
  | AnatomicalFileMessage
  | HexFileMessage;
