/**
 * Functions over the messages: which buffers to transfer, which run a message belongs to, cheap
 * structural guards against foreign postMessage traffic, and the frame merge the client uses when
 * the display skips a frame. Every switch is exhaustive (assertNever), so a new message type
 * cannot be forgotten here.
 */

import type { FromWorker, ToWorker } from './protocolMessages';
import type { Frame, StepFrame } from './protocolResults';

/** Compile-time exhaustiveness check for switches over a union's `type`. */
export function assertNever(value: never, what = 'message'): never {
  const type = (value as { type?: unknown } | null)?.type;
  throw new Error(`unexpected ${what}: ${JSON.stringify(type ?? value)}`);
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
      for (const v of msg.views ?? []) add(v.bytes);
      break;
    case 'grid':
      if ('bytes' in msg) add(msg.bytes);
      break;
    case 'loaded':
      add(msg.file.points);
      break;
    case 'frame':
      for (const s of msg.earlier ?? []) {
        add(s.positions);
        add(s.indices);
        add(s.attractors);
      }
      add(msg.positions);
      add(msg.indices);
      add(msg.attractors);
      add(msg.runContours?.points);
      break;
    case 'done': {
      const r = msg.result;
      add(r.contourPoints);
      add(r.positions);
      add(r.positionsF64);
      add(r.indices);
      add(r.pointDistances);
      add(r.vertexDistances);
      add(r.vertexDistancesF64);
      add(r.setAsidePoints);
      add(r.setAsidePointDistances);
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
    case 'lab-phases-anatomical':
      if ('study' in msg) for (const f of msg.study.files) add(f.bytes);
      break;
    case 'lab-batch':
      if (msg.job.kind === 'phases' && msg.job.sequence) {
        add(msg.job.sequence.bytes);
        for (const v of msg.job.sequence.views) add(v.bytes);
      }
      break;
    case 'session-json':
    case 'wall-file':
    case 'anatomical-file':
    case 'hex-file':
      add(msg.bytes);
      break;
    case 'anatomical-export':
      add(msg.mesh.positions);
      add(msg.mesh.indices);
      break;
    case 'wall-export':
    case 'hex-export':
      add(msg.endo.positions);
      add(msg.endo.indices);
      add(msg.epi.positions);
      add(msg.epi.indices);
      break;
    case 'biv-wall-export':
      for (const m of [msg.lvEndo, msg.rvEndo, msg.bivEpi]) {
        add(m.positions);
        add(m.indices);
      }
      break;
    case 'session-export':
    case 'run':
    case 'ack':
    case 'cancel':
    case 'schema':
    case 'ready':
    case 'cancelled':
    case 'started':
    case 'error':
    case 'lab-simulate':
    case 'lab-truth-edit':
    case 'lab-truths':
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
    case 'cancelled':
      return msg.runId;
    case 'lab-batch-started':
    case 'lab-progress':
    case 'lab-batch-done':
      return msg.runId;
    case 'ready':
    case 'loaded':
    case 'grid':
    case 'started':
    case 'schema':
    case 'lab-truth':
    case 'lab-truths':
    case 'lab-simulated':
    case 'lab-compared':
    case 'lab-phases-anatomical':
    case 'session-json':
    case 'wall-file':
    case 'anatomical-file':
    case 'hex-file':
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
    case 'grid':
    case 'frame':
    case 'done':
    case 'cancelled':
    case 'started':
    case 'error':
    case 'schema':
    case 'lab-truth':
    case 'lab-truths':
    case 'lab-simulated':
    case 'lab-compared':
    case 'lab-batch-started':
    case 'lab-progress':
    case 'lab-batch-done':
    case 'lab-phases-anatomical':
    case 'session-json':
    case 'wall-file':
    case 'anatomical-file':
    case 'hex-file':
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
    case 'grid':
    case 'run':
    case 'ack':
    case 'cancel':
    case 'schema':
    case 'lab-truth':
    case 'lab-truth-edit':
    case 'lab-simulate':
    case 'lab-compare':
    case 'lab-batch':
    case 'lab-phases-anatomical':
    case 'session-export':
    case 'wall-export':
    case 'biv-wall-export':
    case 'anatomical-export':
    case 'hex-export':
      return true;
    default:
      return false;
  }
}

/**
 * Merges a newer frame over an older one that was never handed to the receiver: the newer step
 * stays the newest, the older frame's steps (its `earlier` and its newest) go before the newer's
 * `earlier`, so no step is lost; topology (indices), attractors, run contours and the growth note of
 * the older frame are carried over when the newer frame does not have its own, so the newest step always comes with
 * what it needs to be drawn.
 */
export function mergeFrames(older: Frame, newer: Frame): Frame {
  const merged: Frame = { ...newer, earlier: [...stepsOf(older), ...(newer.earlier ?? [])] };
  if (merged.indices === undefined && older.indices !== undefined) merged.indices = older.indices;
  if (merged.attractors === undefined && older.attractors !== undefined) {
    merged.attractors = older.attractors;
  }
  if (merged.runContours === undefined && older.runContours !== undefined) merged.runContours = older.runContours;
  if (merged.growthNote === undefined && older.growthNote !== undefined) merged.growthNote = older.growthNote;
  return merged;
}

/** Every step a frame carries, oldest first (its `earlier`, then its newest). */
export function stepsOf(f: Frame): StepFrame[] {
  const newest: StepFrame = { report: f.report, positions: f.positions };
  if (f.indices !== undefined) newest.indices = f.indices;
  if (f.attractors !== undefined) newest.attractors = f.attractors;
  return f.earlier?.length ? [...f.earlier, newest] : [newest];
}

/**
 * The frame that carries `steps` (at least one, oldest first): the last is the newest, and the
 * indices and attractors of the newest are the last ones among the steps (see `Frame`).
 */
export function frameOfSteps(runId: number, seq: number, steps: readonly StepFrame[]): Frame {
  const newest = steps[steps.length - 1];
  if (!newest) throw new Error('a frame carries at least one step');
  const frame: Frame = { runId, seq, report: newest.report, positions: newest.positions };
  const indices = lastDefined(steps, (s) => s.indices);
  const attractors = lastDefined(steps, (s) => s.attractors);
  if (indices !== undefined) frame.indices = indices;
  if (attractors !== undefined) frame.attractors = attractors;
  if (steps.length > 1) frame.earlier = steps.slice(0, -1);
  return frame;
}

function lastDefined<T, U>(items: readonly T[], get: (item: T) => U | undefined): U | undefined {
  for (let i = items.length - 1; i >= 0; i--) {
    const v = get(items[i]);
    if (v !== undefined) return v;
  }
  return undefined;
}
