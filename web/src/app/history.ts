/**
 * Bounded history of the frames of one run, for the timeline's scrubber and step back/forward.
 * When full, every second older frame is dropped: the history keeps covering the whole run (first
 * to latest step) at a coarser spacing instead of forgetting its beginning, and memory stays
 * bounded (a frame of ~3k vertices is ~36 KB). Pure and tested.
 */
import type { StepReport } from '../core-client/protocol';

export interface HistoryEntry {
  report: StepReport;
  positions: Float32Array;
  /** Triangles valid for `positions` (shared between frames until the topology changes). */
  indices: Uint32Array;
  /** Attractor points in force at this step (shared between frames until re-sampled). */
  attractors: Float32Array | null;
}

export class FrameHistory {
  private entries: HistoryEntry[] = [];
  private bytes = 0;

  constructor(
    readonly maxFrames = 400,
    readonly maxBytes = 96 * 1024 * 1024,
  ) {}

  get length(): number {
    return this.entries.length;
  }

  at(i: number): HistoryEntry | undefined {
    return this.entries[i];
  }

  last(): HistoryEntry | undefined {
    return this.entries[this.entries.length - 1];
  }

  clear(): void {
    this.entries = [];
    this.bytes = 0;
  }

  /** Appends a frame; returns how many entries were dropped to stay within bounds. */
  push(entry: HistoryEntry): number {
    this.entries.push(entry);
    this.bytes += entry.positions.byteLength;
    let dropped = 0;
    while ((this.entries.length > this.maxFrames || this.bytes > this.maxBytes) && this.entries.length > 2) {
      dropped += this.thin();
    }
    return dropped;
  }

  /** Drops every second entry except the first and the last. */
  private thin(): number {
    const kept: HistoryEntry[] = [];
    const n = this.entries.length;
    let dropped = 0;
    for (let i = 0; i < n; i++) {
      if (i === 0 || i === n - 1 || i % 2 === 0) kept.push(this.entries[i]);
      else {
        dropped++;
        this.bytes -= this.entries[i].positions.byteLength;
      }
    }
    this.entries = kept;
    return dropped;
  }

  /** The entry whose iteration is closest to `iteration` (for scrubbing by iteration). */
  indexOfIteration(iteration: number): number {
    let best = -1;
    let bestDist = Infinity;
    for (let i = 0; i < this.entries.length; i++) {
      const d = Math.abs(this.entries[i].report.iteration - iteration);
      if (d < bestDist) {
        best = i;
        bestDist = d;
      }
    }
    return best;
  }

  /** Distances by iteration, for the live plot. */
  series(): { iteration: number; max: number; mean: number }[] {
    return this.entries.map((e) => ({
      iteration: e.report.iteration,
      max: e.report.max_distance_mm,
      mean: e.report.mean_distance_mm,
    }));
  }
}
