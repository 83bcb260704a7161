/**
 * The public shapes of the CoreClient API (what callers pass in and get back), apart from the
 * class so that tests, the lab and the app can name them without reading the implementation.
 * CoreClient.ts re-exports them.
 */

import type { AnatomicalFormat, CoreErrorData, LabBatchInfo, LidsMode, ParamValues, ReconOptions, RunResult, ToWorker, WallFormat, WallSurfaceMesh } from './protocol';

/** The part of `Worker` the client uses (a fake implements it in unit tests). */
export interface WorkerLike {
  postMessage(message: ToWorker, transfer: Transferable[]): void;
  terminate(): void;
  onmessage: ((ev: { data: unknown }) => void) | null;
  onerror: ((ev: { message?: string; preventDefault?: () => void }) => void) | null;
  onmessageerror?: ((ev: unknown) => void) | null;
}

export interface CoreClientOptions {
  /** Creates the worker; defaults to the bundled reconstruct.worker.ts as a module worker. */
  createWorker?: () => WorkerLike;
  /** Runs a callback at the next display frame; defaults to requestAnimationFrame (with a timer
   * fallback so hidden tabs, where animation frames stop, still finish their runs). */
  schedule?: (callback: () => void) => void;
  /** Told about every worker crash (after pending promises were rejected). */
  onWorkerCrash?: (error: CoreErrorData) => void;
  /** Told when a worker stuck in a long step of a cancelled run was replaced on purpose (no crash). */
  onWorkerRestart?: () => void;
  /** How long a cancel may go unacknowledged before the worker is replaced (CANCEL_GRACE_MS). */
  cancelGraceMs?: number;
}

export interface RunOptions {
  fileName: string;
  surface: string | null;
  params: ParamValues;
  lids: LidsMode;
  /** Missing: the core's defaults. */
  options?: ReconOptions;
  /** Contour ids left out by the user (RunRequest.leaveOut); missing or empty: none. */
  leaveOut?: readonly string[];
}

/** What the LV wall is built of and written as (`CoreClient.wallFile`). */
export interface WallOptions {
  endo: WallSurfaceMesh;
  epi: WallSurfaceMesh;
  /** mm; null: the surfaces as reconstructed. */
  minThicknessMm: number | null;
  format: WallFormat;
  /** Header lines after the command line's comment. */
  header: readonly string[];
}

/** What the biventricular wall is built of and written as (`CoreClient.bivWallFile`). */
export interface BivWallOptions {
  lvEndo: WallSurfaceMesh;
  rvEndo: WallSurfaceMesh;
  /** The biventricular epicardium (BIV_EPI). */
  bivEpi: WallSurfaceMesh;
  /** mm; null: the surfaces as reconstructed. */
  minThicknessMm: number | null;
  format: WallFormat;
  /** Header lines after the command line's comment. */
  header: readonly string[];
}

/** What the anatomical mesh is built of and written as (`CoreClient.anatomicalFile`). */
export interface AnatomicalOptions {
  /** The finished LV surface (LV_ENDO or LV_EPI) and its mesh. */
  mesh: WallSurfaceMesh;
  /** Rings from the apex to the base, vertices per ring. */
  rings: number;
  points: number;
  format: AnatomicalFormat;
  /** Header lines after the command line's comment. */
  header: readonly string[];
}

/** What the hexahedral LV wall is built of (`CoreClient.hexFile`): the LV wall's two meshes, the layout, the layers. */
export interface HexOptions {
  endo: WallSurfaceMesh;
  epi: WallSurfaceMesh;
  /** Each surface's layout: rings from the apex to the base, points per ring. */
  rings: number;
  points: number;
  /** Cells through the wall. */
  layers: number;
  /** Header lines after the command line's comment. */
  header: readonly string[];
}

export interface RunHandle {
  runId: number;
  done: Promise<RunResult>;
  cancel(): void;
}

/** A running lab batch (leave-one-out or sweep); cancel() stops it in the worker. */
export interface LabBatchHandle {
  runId: number;
  /** Resolves when the worker accepted the job (with the contours of a leave-one-out). */
  started: Promise<LabBatchInfo>;
  /** Resolves when every item was reported; rejects with CoreErrorData (also 'cancelled'). */
  done: Promise<void>;
  cancel(): void;
}

/** The settings a run and a session export send: copies, so later edits by the caller do not leak. */
export function settingsOf(opts: RunOptions) {
  return {
    fileName: opts.fileName,
    surface: opts.surface,
    params: { ...opts.params },
    lids: opts.lids,
    ...(opts.options ? { options: { ...opts.options } } : {}),
    // Only when there are any: a request without them is the one it always was.
    ...(opts.leaveOut && opts.leaveOut.length > 0 ? { leaveOut: [...opts.leaveOut] } : {}),
  };
}
