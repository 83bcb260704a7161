/**
 * Errors as data: the shape every failure takes when it crosses the worker boundary, the codes
 * made outside the Rust core, and the normalisation of anything thrown into that shape (so the
 * UI only ever shows one kind of error).
 */

/** An error that crossed the worker boundary as data, with the core's stable code. */
export interface CoreErrorData {
  code: string;
  message: string;
  file?: string;
  line?: number;
  /** Surfaces to choose from, for `surface_required` / `unknown_surface`. */
  available?: string[];
}

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
