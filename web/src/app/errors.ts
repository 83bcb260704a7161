/**
 * Small helpers of the controller: errors as the protocol's data, the banner's note on a refused
 * file, parameters in schema order for export headers, listeners that may throw.
 */
import type { CoreErrorData, ParamSpec, ParamValues } from '../core-client/protocol';

/** What the banner adds when a file is refused at load: which file the view still shows. */
export function keptText(previous: string | null): string {
  return previous ? ` Not opened; still showing ${previous}.` : ' Not opened.';
}

/** Anything thrown or rejected, as the protocol's error data (with the file when known). */
export function asCoreError(e: unknown, fallback: string, file?: string): CoreErrorData {
  if (e && typeof e === 'object' && 'code' in e && 'message' in e) {
    const d = e as CoreErrorData;
    return { ...d, file: d.file ?? file };
  }
  const message = e instanceof Error ? e.message : typeof e === 'string' ? e : fallback;
  return { code: 'app', message: message || fallback, file };
}

/** Parameters in schema order (iterations, lambda, beta, ...), which reads better in file headers than the core's. */
export function schemaOrdered(params: ParamValues, schema: readonly ParamSpec[]): ParamValues {
  const ordered: ParamValues = {};
  for (const s of schema) if (params[s.name] !== undefined) ordered[s.name] = params[s.name];
  for (const k of Object.keys(params)) if (ordered[k] === undefined) ordered[k] = params[k];
  return ordered;
}

/** Runs a listener; an exception is logged, never propagated into the caller's bookkeeping. */
export function callSafely(f: () => void, what: string): void {
  try {
    f();
  } catch (e) {
    console.error(what, e);
  }
}
