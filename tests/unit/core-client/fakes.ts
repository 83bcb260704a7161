// Test doubles for the core-client units: a fake Worker transport and a manual frame scheduler;
// for the export requests (wall, biventricular wall, hexahedra, anatomical mesh), a session that
// answers nothing but the call under test, a worker core around it, and a client with a file loaded.
import { CoreClient, type WorkerLike } from '../../../web/src/core-client/CoreClient';
import type { FromWorker, StepReport, ToWorker } from '../../../web/src/core-client/protocol';
import { WorkerCore, type SessionApi, type WasmApi } from '../../../web/src/core-client/workerCore';

export class FakeWorker implements WorkerLike {
  static instances: FakeWorker[] = [];
  sent: ToWorker[] = [];
  transfers: Transferable[][] = [];
  terminated = false;
  /** Like the real worker, acknowledge each cancel soon; false: a worker inside a step that never returns. */
  acksCancels = true;
  onmessage: ((ev: { data: unknown }) => void) | null = null;
  onerror: ((ev: { message?: string; preventDefault?: () => void }) => void) | null = null;
  onmessageerror: ((ev: unknown) => void) | null = null;

  constructor() {
    FakeWorker.instances.push(this);
  }
  postMessage(message: ToWorker, transfer: Transferable[]): void {
    this.sent.push(message);
    this.transfers.push(transfer);
    if (message.type === 'cancel' && this.acksCancels) {
      const { runId } = message;
      queueMicrotask(() => this.emit({ type: 'cancelled', runId }));
    }
  }
  terminate(): void {
    this.terminated = true;
  }
  /** Delivers a worker -> main message. */
  emit(msg: FromWorker): void {
    this.onmessage?.({ data: msg });
  }
  crash(message = 'RuntimeError: unreachable'): void {
    this.onerror?.({ message });
  }
  of<T extends ToWorker['type']>(type: T): Extract<ToWorker, { type: T }>[] {
    return this.sent.filter((m): m is Extract<ToWorker, { type: T }> => m.type === type);
  }
}

/** Collects scheduled callbacks; `tick()` runs them like one animation frame. */
export class ManualScheduler {
  private queue: (() => void)[] = [];
  schedule = (cb: () => void): void => {
    this.queue.push(cb);
  };
  get pending(): number {
    return this.queue.length;
  }
  tick(): void {
    const q = this.queue;
    this.queue = [];
    for (const cb of q) cb();
  }
}

export function stepReport(iteration: number, extra: Partial<StepReport> = {}): StepReport {
  return {
    iteration,
    total_iterations: 10,
    phase: iteration === 0 ? 'initial_tube' : 'deform',
    topology_changed: iteration === 0,
    max_distance_mm: 10 / (iteration + 1),
    mean_distance_mm: 2 / (iteration + 1),
    vertices: 3,
    triangles: 1,
    attractors: 150,
    timings: { attractors_ms: 0, closest_ms: 0, solve_ms: 0, apply_ms: 0, remesh_ms: 0, total_ms: 0 },
    done: false,
    ...extra,
  };
}

export const flush = () => new Promise<void>((r) => setTimeout(r, 0));

/**
 * Just enough of a session for an export request: the methods every session has answer nothing
 * (an export reads none of them), and `extra` adds the binding call under test (left out: a core
 * without that call).
 */
export function stubSession(extra: Partial<SessionApi> = {}): SessionApi {
  return {
    load: () => '{}',
    file_points: () => new Float32Array(0),
    start: () => undefined,
    step: () => '{}',
    growth_note: () => undefined,
    attractors_changed: () => false,
    positions: () => new Float32Array(0),
    indices: () => new Uint32Array(0),
    attractors: () => new Float32Array(0),
    contour_points: () => new Float32Array(0),
    point_distances: () => new Float32Array(0),
    vertex_distances: () => new Float32Array(0),
    set_aside_points: () => new Float32Array(0),
    result_json: () => '{}',
    session_json: () => new Uint8Array(0),
    ...extra,
  };
}

/**
 * A binding call that records its arguments and gives `answer()`, or throws `throws` (a string: the
 * core's refusal as JSON, the way wasm-bindgen hands a Rust error over).
 */
export function recordedCall<A>(answer: () => A, throws: unknown = null) {
  const calls: unknown[][] = [];
  const call = (...args: unknown[]): A => {
    calls.push(args);
    if (throws !== null) throw throws;
    return answer();
  };
  return { call, calls };
}

/** A worker core over `session` (no real yielding, a clock at 0), with every message it posts. */
export function workerFor(session: SessionApi) {
  const out: FromWorker[] = [];
  const wasm: WasmApi = { createSession: () => session, schemaJson: () => '[]', version: () => '9.9.9', takePanicMessage: () => undefined };
  const core = new WorkerCore(wasm, (m) => out.push(m), { yieldToEventLoop: () => undefined, now: () => 0 });
  return { core, out };
}

/**
 * A client over a FakeWorker with `fileName` loaded (its `surfaces` as the core would list them):
 * the export calls refuse a file never loaded, so each of their tests starts from one.
 */
export async function loadedClient(fileName: string, surfaces: string[]) {
  const created = CoreClient.create({ createWorker: () => new FakeWorker(), schedule: new ManualScheduler().schedule });
  const w = FakeWorker.instances.at(-1)!;
  w.emit({ type: 'ready' });
  const client = await created;
  const p = client.load(fileName, new TextEncoder().encode('contour,x,y,z\n').buffer as ArrayBuffer);
  w.emit({ type: 'loaded', reqId: w.of('load')[0].reqId, file: { fileName, surfaces, contours: [], points: new Float32Array(0), landmarks: [], warnings: [] } });
  await p;
  return { client, w };
}
