/**
 * The recorded steps of one run, for the timeline's scrubber and step back/forward, and the
 * distances of every step for the live plot. Pure and tested.
 *
 * Every step is kept while the history fits its byte budget (positions are a Float32Array per step,
 * ~12 bytes per vertex; indices and attractors are shared between steps until they change and
 * counted once). A run too long for the budget is thinned evenly: the history then keeps every
 * `stride`-th step of the run (2, 4, 8, ...; the first step always, the newest step always) and
 * `stride` says so. The plot's series is never thinned: it keeps every step's distances.
 */
import type { StepReport } from '../core-client/protocol';

export interface HistoryEntry {
  report: StepReport;
  positions: Float32Array;
  /** Triangles valid for `positions` (shared between steps until the topology changes). */
  indices: Uint32Array;
  /** Attractor points in force at this step (shared between steps until re-sampled). */
  attractors: Float32Array | null;
}

export interface SeriesPoint {
  iteration: number;
  max: number;
  mean: number;
}

/** The default budget: every step of the longest runs the app allows (2000 iterations of a few thousand vertices) fits. */
export const HISTORY_BUDGET_BYTES = 300 * 1000 * 1000;

interface Slot {
  entry: HistoryEntry;
  /** The step's place in the run (0 for its first step, counting every step pushed). */
  ordinal: number;
}

export class FrameHistory {
  private slots: Slot[] = [];
  private points: SeriesPoint[] = [];
  private bytes = 0;
  private pushed = 0;
  private keepEvery = 1;
  /** How many kept steps hold each shared array (indices, attractors), to count its bytes once. */
  private readonly shared = new Map<ArrayBufferView, number>();

  constructor(
    readonly maxBytes = HISTORY_BUDGET_BYTES,
    /** A cap on the kept steps besides the bytes (thinned the same way). */
    readonly maxFrames = Infinity,
  ) {}

  get length(): number {
    return this.slots.length;
  }

  /** Every `stride`-th step of the run is kept (1: every step). */
  get stride(): number {
    return this.keepEvery;
  }

  /** Steps pushed since the last clear (kept or not). */
  get stepsSeen(): number {
    return this.pushed;
  }

  /** Bytes held: every kept step's positions, each shared array once. */
  get byteLength(): number {
    return this.bytes;
  }

  at(i: number): HistoryEntry | undefined {
    return this.slots[i]?.entry;
  }

  last(): HistoryEntry | undefined {
    return this.slots[this.slots.length - 1]?.entry;
  }

  clear(): void {
    this.slots = [];
    this.points = [];
    this.bytes = 0;
    this.pushed = 0;
    this.keepEvery = 1;
    this.shared.clear();
  }

  /** Records the next step of the run; returns how many kept steps were dropped to stay in bounds. */
  push(entry: HistoryEntry): number {
    const ordinal = this.pushed++;
    this.points.push({ iteration: entry.report.iteration, max: entry.report.max_distance_mm, mean: entry.report.mean_distance_mm });
    let dropped = 0;
    // The newest step is kept even off the stride; it makes room for the next one.
    const newest = this.slots[this.slots.length - 1];
    if (newest && newest.ordinal % this.keepEvery !== 0) {
      this.slots.pop();
      this.release(newest.entry);
      dropped++;
    }
    this.slots.push({ entry, ordinal });
    this.hold(entry);
    while ((this.bytes > this.maxBytes || this.slots.length > this.maxFrames) && this.slots.length > 2) {
      dropped += this.thin();
    }
    return dropped;
  }

  /** Doubles the stride: drops the kept steps off it (never the first nor the newest). */
  private thin(): number {
    this.keepEvery *= 2;
    const n = this.slots.length;
    const kept: Slot[] = [];
    for (let i = 0; i < n; i++) {
      const slot = this.slots[i];
      if (i === n - 1 || slot.ordinal % this.keepEvery === 0) kept.push(slot);
      else this.release(slot.entry);
    }
    const dropped = n - kept.length;
    this.slots = kept;
    return dropped;
  }

  private hold(e: HistoryEntry): void {
    this.bytes += e.positions.byteLength;
    this.share(e.indices, 1);
    if (e.attractors) this.share(e.attractors, 1);
  }

  private release(e: HistoryEntry): void {
    this.bytes -= e.positions.byteLength;
    this.share(e.indices, -1);
    if (e.attractors) this.share(e.attractors, -1);
  }

  private share(a: ArrayBufferView, delta: 1 | -1): void {
    const n = (this.shared.get(a) ?? 0) + delta;
    if (delta > 0 && n === 1) this.bytes += a.byteLength;
    if (n === 0) {
      this.shared.delete(a);
      this.bytes -= a.byteLength;
    } else this.shared.set(a, n);
  }

  /** The kept step whose iteration is closest to `iteration` (for scrubbing by iteration); -1 when empty. */
  indexOfIteration(iteration: number): number {
    // Iterations increase along the history: binary search for the first at or past `iteration`.
    let lo = 0;
    let hi = this.slots.length;
    while (lo < hi) {
      const mid = (lo + hi) >> 1;
      if (this.slots[mid].entry.report.iteration < iteration) lo = mid + 1;
      else hi = mid;
    }
    if (this.slots.length === 0) return -1;
    if (lo === this.slots.length) return lo - 1;
    if (lo > 0 && iteration - this.slots[lo - 1].entry.report.iteration <= this.slots[lo].entry.report.iteration - iteration) return lo - 1;
    return lo;
  }

  /** Distances of every step of the run (never thinned), for the live plot. Do not modify. */
  series(): readonly SeriesPoint[] {
    return this.points;
  }
}
