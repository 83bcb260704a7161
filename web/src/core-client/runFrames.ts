/**
 * The main thread's side of a run's frame stream: frames are throttled to the display (at most one
 * `onFrame` call per scheduled slot; frames arriving in between are merged by `mergeFrames`, which
 * keeps every step they carry, so the receiver still gets every step of the run), each frame handed
 * over is acknowledged (the worker's back-pressure waits for those acks), and a run's result is held
 * back until its last frame was handed over. Kept out of CoreClient so the worker
 * plumbing and this timing logic can be read (and changed) separately.
 */

import { mergeFrames, type CoreErrorData, type Frame, type RunResult } from './protocol';

interface RunState {
  runId: number;
  onFrame: (f: Frame) => void;
  resolve: (r: RunResult) => void;
  reject: (e: CoreErrorData) => void;
  /** Newest frame not yet handed to onFrame. */
  pending: Frame | undefined;
  flushScheduled: boolean;
  /** Result received while a frame was still waiting for its display slot. */
  result: RunResult | undefined;
}

export class RunFrames {
  private readonly runs = new Map<number, RunState>();

  constructor(
    /** Runs a callback at the next display frame. */
    private readonly schedule: (callback: () => void) => void,
    /** Acknowledges frame `seq` of `runId` to the worker. */
    private readonly ack: (runId: number, seq: number) => void,
  ) {}

  /** Starts tracking a run; its promise is settled through `resolve` / `reject`. */
  add(runId: number, onFrame: (f: Frame) => void, resolve: (r: RunResult) => void, reject: (e: CoreErrorData) => void): void {
    this.runs.set(runId, { runId, onFrame, resolve, reject, pending: undefined, flushScheduled: false, result: undefined });
  }

  has(runId: number): boolean {
    return this.runs.has(runId);
  }

  /** The runs in progress (a copy: finishing them while iterating is fine). */
  ids(): number[] {
    return [...this.runs.keys()];
  }

  onFrameMessage(msg: Frame & { type: 'frame' }): void {
    const run = this.runs.get(msg.runId);
    if (!run) return; // stale frame of a cancelled or finished run
    const frame: Frame = {
      runId: msg.runId,
      seq: msg.seq,
      report: msg.report,
      positions: msg.positions,
    };
    if (msg.indices !== undefined) frame.indices = msg.indices;
    if (msg.attractors !== undefined) frame.attractors = msg.attractors;
    if (msg.runContours !== undefined) frame.runContours = msg.runContours;
    if (msg.growthNote !== undefined) frame.growthNote = msg.growthNote;
    if (msg.earlier?.length) frame.earlier = msg.earlier;
    run.pending = run.pending ? mergeFrames(run.pending, frame) : frame;
    if (!run.flushScheduled) {
      run.flushScheduled = true;
      this.schedule(() => this.flush(run.runId));
    }
  }

  /** Hands the newest pending frame to the renderer (once per display frame) and acks it. */
  private flush(runId: number): void {
    const run = this.runs.get(runId);
    if (!run) return;
    run.flushScheduled = false;
    const frame = run.pending;
    run.pending = undefined;
    if (frame) {
      this.ack(runId, frame.seq);
      try {
        run.onFrame(frame);
      } catch (e) {
        console.error('CoreClient: onFrame threw', e);
      }
    }
    if (run.result && this.runs.get(runId) === run) {
      this.finish(runId, null, run.result);
    }
  }

  onDone(result: RunResult): void {
    const run = this.runs.get(result.runId);
    if (!run) return;
    if (run.pending !== undefined && run.flushScheduled) {
      // Deliver the last frame first; flush() then resolves.
      run.result = result;
      return;
    }
    this.finish(result.runId, null, result);
  }

  /** Settles a run (rejects with `error`, else resolves with `result`) and forgets it. */
  finish(runId: number, error: CoreErrorData | null, result?: RunResult): void {
    const run = this.runs.get(runId);
    if (!run) return;
    this.runs.delete(runId);
    run.pending = undefined;
    if (error) run.reject(error);
    else if (result) run.resolve(result);
  }
}
