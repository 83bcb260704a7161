/**
 * What a run puts on screen, decided once per animation frame: the recorded steps (history: every
 * step of the run, each frame's `earlier` ones included), the playback cursor over them (the mesh
 * drawn is only the one at the cursor: the newest step when live, however many came since the last
 * display), the final result with its distance colours, the contours (plain, by
 * distance, or the aligned run's own next to the file's as given), the legends, the timeline and
 * the live plot. The controller feeds it frames and results of the active run and asks it to
 * clear; it never talks to the core. Split from controller.ts so run orchestration and display can
 * be read apart.
 */
import { stepsOf, type Frame, type LoadedFile, type RunResult, type StepReport } from '../core-client/protocol';
import { robustMax } from '../viewer/colormap';
import { FrameHistory, HISTORY_BUDGET_BYTES, type HistoryEntry } from './history';
import type { Parts } from './parts';
import * as pb from './playback';
import { showSceneContours } from './sceneContours';

/** What the display reads from the controller. */
export interface DisplayHost {
  currentFile(): LoadedFile | null;
  surface(): string | null;
  /** The iterations parameter (the plot's length before the first report arrives). */
  iterations(): number;
}

interface Shown {
  cursor: number;
  result: boolean;
  historyVersion: number;
  entry: HistoryEntry | undefined;
}

const NOTHING_SHOWN: Shown = { cursor: -2, result: false, historyVersion: -1, entry: undefined };

export class RunDisplay {
  private readonly history: FrameHistory;
  private playback: pb.Playback = pb.initialPlayback;
  private result: RunResult | null = null;
  private latest: StepReport | null = null;
  private indices: Uint32Array | null = null;
  private attractors: Float32Array | null = null;
  /** The running run's own contours when they are not the file's (breath-hold alignment). */
  private runContours: Frame['runContours'] | null = null;
  /** What is on screen: the history index and entry shown, whether the final result is, and the history it saw. */
  private shown: Shown = NOTHING_SHOWN;
  private historyVersion = 0;
  private contourMode: 'plain' | 'distances' | 'none' = 'none';
  /** The view was widened to the first mesh of this run. */
  private framedRun = false;
  /** Top of the colour scales in mm: contour points (to mesh) and mesh vertices (to contours). */
  private pointMaxMm = 1;
  private meshMaxMm = 1;
  private rafHandle = 0;

  constructor(
    private readonly parts: Parts,
    private readonly host: DisplayHost,
    /** Bytes the recorded steps may hold before they are thinned (history.ts). */
    historyBudgetBytes = HISTORY_BUDGET_BYTES,
  ) {
    this.history = new FrameHistory(historyBudgetBytes);
  }

  /** The finished run's result on screen (null while running or after a clear). */
  get currentResult(): RunResult | null {
    return this.result;
  }

  get historyLength(): number {
    return this.history.length;
  }

  /** Top of the colour scale of the mesh (`mesh`) or of the contour points (anything else), mm. */
  colourMax(what: 'mesh' | 'points'): number {
    return what === 'mesh' ? this.meshMaxMm : this.pointMaxMm;
  }

  // ---- feeding ---------------------------------------------------------------------------------

  /**
   * A frame of the active run: every step it carries is recorded (once there is a mesh); the
   * display shows the step at the cursor at the next animation frame (live: only the newest).
   */
  frame(f: Frame): void {
    if (f.runContours) {
      this.runContours = f.runContours;
      this.showContours(null); // the shifted contours the mesh now follows, and the file's as given
    }
    this.latest = f.report;
    this.parts.status.setProgress(f.report.total_iterations > 0 ? f.report.iteration / f.report.total_iterations : 0);
    const shownIteration = this.history.at(this.playback.cursor)?.report.iteration;
    let dropped = 0;
    for (const step of stepsOf(f)) {
      if (step.indices) this.indices = step.indices;
      if (step.attractors) this.attractors = step.attractors;
      if (!this.indices || this.indices.length === 0) continue;
      dropped += this.history.push({ report: step.report, positions: step.positions, indices: this.indices, attractors: this.attractors });
      this.historyVersion++;
    }
    if (dropped > 0 && !this.playback.playing && shownIteration !== undefined) {
      this.playback = { ...this.playback, cursor: this.history.indexOfIteration(shownIteration) };
    }
  }

  /** The active run finished: its result (with the colour scales it sets) is shown at the end. */
  finished(r: RunResult): void {
    this.result = r;
    this.pointMaxMm = robustMax(r.pointDistances);
    this.meshMaxMm = robustMax(r.vertexDistances);
    this.historyVersion++;
  }

  /** Forgets the run on screen (a new run, another file): empty mesh, timeline, plot and legends. */
  clear(): void {
    this.history.clear();
    this.historyVersion++;
    this.result = null;
    this.latest = null;
    this.indices = null;
    this.attractors = null;
    const shifted = this.runContours !== null; // an aligned run's contours are on screen
    this.runContours = null;
    this.playback = pb.restart(this.playback);
    this.framedRun = false;
    this.shown = NOTHING_SHOWN;
    this.parts.viewer?.meshLayer.clear();
    this.parts.viewer?.attractorLayer.clear();
    this.parts.viewer?.givenLayer.clear();
    this.parts.viewer?.setAsideLayer.clear();
    this.parts.view.setAsGivenAvailable(false);
    this.parts.viewer?.requestRender();
    this.parts.legend.hide();
    this.parts.meshLegend.hide();
    this.parts.status.setStep(null);
    this.parts.status.setProgress(0);
    this.parts.plot.set([], 1, null);
    this.parts.exports.setAvailable(false, this.host.currentFile() !== null);
    this.parts.result.clear('no result yet');
    if (this.contourMode === 'distances' || shifted) this.showContours(null);
  }

  // ---- timeline --------------------------------------------------------------------------------

  /** Play/pause; returns whether it now plays. */
  togglePlay(): boolean {
    this.playback = pb.togglePlaying(this.playback, this.history.length, performance.now());
    return this.playback.playing;
  }

  step(delta: number): void {
    this.playback = pb.step(this.playback, this.history.length, delta);
  }

  seek(index: number): void {
    this.playback = pb.seek(this.playback, this.history.length, index);
  }

  /** Jumps to the newest step (and follows it when the speed is live). */
  toLatest(): void {
    this.playback = { ...this.playback, playing: true, speed: this.playback.speed, cursor: this.history.length - 1 };
    if (this.playback.speed !== 'live') this.playback = { ...this.playback, playing: false };
  }

  setSpeed(speed: pb.Speed): void {
    this.playback = { ...this.playback, speed, lastAdvanceMs: performance.now() };
  }

  /** The timeline as the history and cursor stand (after a state change, outside the display). */
  updateTimeline(): void {
    const report = this.history.at(this.playback.cursor)?.report ?? null;
    this.timelineAt(this.playback.cursor, report, this.latest?.total_iterations ?? null);
  }

  private timelineAt(cursor: number, report: StepReport | null, total: number | null): void {
    this.parts.timeline.update({
      length: this.history.length,
      cursor,
      playing: this.playback.playing,
      iteration: report?.iteration ?? null,
      total,
      done: report?.done ?? false,
      stride: this.history.stride,
    });
  }

  /** The plot of every step's distances so far, marked at the step on screen. */
  private plotAt(report: StepReport | null): void {
    const total = report?.total_iterations ?? this.latest?.total_iterations ?? (this.host.iterations() || 1);
    this.parts.plot.set(this.history.series(), total, report?.iteration ?? null);
  }

  // ---- display (once per animation frame) -----------------------------------------------------

  startLoop(): void {
    const frame = (now: number) => {
      this.rafHandle = requestAnimationFrame(frame);
      this.display(now);
    };
    this.rafHandle = requestAnimationFrame(frame);
  }

  stopLoop(): void {
    cancelAnimationFrame(this.rafHandle);
  }

  private display(now: number): void {
    this.playback = pb.tick(this.playback, this.history.length, now);
    const cursor = this.playback.cursor;
    const atEnd = cursor === this.history.length - 1;
    const showResult = this.result !== null && (atEnd || this.history.length === 0);
    const s = this.shown;
    const entry = this.history.at(cursor);
    if (s.cursor !== cursor || s.result !== showResult || s.entry !== entry) {
      this.shown = { cursor, result: showResult, historyVersion: this.historyVersion, entry };
      this.showStep(cursor, showResult);
    } else if (s.historyVersion !== this.historyVersion) {
      // New steps while the display stays where it is (paused, or replaying): the scrubber's
      // range and the plot grow; the mesh on screen does not change.
      this.shown = { ...s, historyVersion: this.historyVersion };
      const report = this.history.at(cursor)?.report ?? null;
      this.timelineAt(cursor, report, report?.total_iterations ?? null);
      this.plotAt(report);
    }
    this.parts.viewer?.renderIfNeeded();
  }

  private showStep(cursor: number, showResult: boolean): void {
    const viewer = this.parts.viewer;
    const entry = this.history.at(cursor);
    const r = this.result;
    if (showResult && r) {
      viewer?.meshLayer.update(r.positions, r.indices);
      viewer?.meshLayer.setDistances(r.vertexDistances, 0, this.meshMaxMm);
      viewer?.attractorLayer.set(entry?.attractors ?? this.attractors);
      this.showContours(r);
      this.parts.legend.show(this.pointMaxMm);
      this.parts.meshLegend.show(this.meshMaxMm);
    } else if (entry) {
      if (!this.framedRun) {
        this.framedRun = true;
        viewer?.extendFrame(entry.positions);
      }
      viewer?.meshLayer.update(entry.positions, entry.indices);
      viewer?.meshLayer.setDistances(null, 0, 1);
      viewer?.attractorLayer.set(entry.attractors);
      if (this.contourMode === 'distances') this.showContours(null);
      this.parts.legend.hide();
      this.parts.meshLegend.hide();
    }
    viewer?.requestRender();
    const report = entry?.report ?? null;
    this.parts.status.setStep(report);
    this.timelineAt(cursor, report, report?.total_iterations ?? null);
    this.plotAt(report);
  }

  /** Contours of the current file; with a result, its points coloured by distance (and, aligned, the file's as given). */
  showContours(r: RunResult | null): void {
    const viewer = this.parts.viewer;
    const file = this.host.currentFile();
    if (!viewer || !file) return;
    this.parts.view.setAsGivenAvailable(showSceneContours(viewer, file, this.host.surface(), r, this.pointMaxMm, this.runContours));
    this.contourMode = r ? 'distances' : 'plain';
    viewer.requestRender();
  }
}
