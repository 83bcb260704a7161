// Test doubles for the core-client units: a fake Worker transport and a manual frame scheduler.
import type { WorkerLike } from '../../../web/src/core-client/CoreClient';
import type { FromWorker, StepReport, ToWorker } from '../../../web/src/core-client/protocol';

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
