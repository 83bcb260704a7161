/**
 * Wires the core client, the viewer and the UI together. Owns the application state (the pure
 * machine in state.ts), the loaded files, the parameters (mirrored in the URL), the running
 * reconstruction and the recorded frames. All heavy work happens in the worker; this class only
 * routes data and decides what is on screen, once per animation frame.
 */
import type { CoreClient } from '../core-client/CoreClient';
import type {
  CoreErrorData, Frame, LidsMode, LoadedFile, ParamSpec, ParamValues, ReconOptions, RunResult, SessionSettings, StepReport,
} from '../core-client/protocol';
import { DEFAULT_OPTIONS, withDefaultOptions } from '../core-client/protocol';
import type { ExportInfo } from '../io/export/header';
import type { ExportPanel } from '../io/ExportPanel';
import type { FileBar } from '../io/FileBar';
import { findSample, fetchSample, type Sample } from '../io/samples';
import type { ErrorBanner } from '../ui/ErrorBanner';
import type { HoverReadout } from '../ui/HoverReadout';
import type { LivePlot } from '../ui/LivePlot';
import type { ParamPanel } from '../ui/ParamPanel';
import type { ResultPanel } from '../ui/ResultPanel';
import type { StatusLine } from '../ui/StatusLine';
import type { Timeline } from '../ui/Timeline';
import type { ViewControls } from '../ui/ViewControls';
import { robustMax } from '../viewer/colormap';
import type { Legend } from '../viewer/Legend';
import type { Viewer } from '../viewer/Viewer';
import { FrameHistory } from './history';
import { asCoreError, callSafely, keptText, schemaOrdered } from './errors';
import { showSceneContours, surfacePoints } from './sceneContours';
import * as pb from './playback';
import { currentRunId, initialState, loadedFile, statusWord, transition, type AppEvent, type AppState } from './state';
import { defaultParams, parseUrlState, serializeUrlState, DEFAULT_VIEW, type ViewSettings } from './urlState';

/** Delay between the last parameter change and the restart of the run. */
export const RESTART_DEBOUNCE_MS = 300;

export interface Parts {
  viewer: Viewer | null;
  /** Scale of the contour-point colours (contour-to-mesh distance). */
  legend: Legend;
  /** Scale of the mesh colours (vertex-to-nearest-contour distance). */
  meshLegend: Legend;
  params: ParamPanel;
  timeline: Timeline;
  status: StatusLine;
  plot: LivePlot;
  result: ResultPanel;
  banner: ErrorBanner;
  files: FileBar;
  exports: ExportPanel;
  view: ViewControls;
  hover: HoverReadout;
  warnings: HTMLElement;
}

interface ActiveRun {
  runId: number;
  cancel(): void;
}

export class Controller {
  private state: AppState = initialState;
  private client: CoreClient | null = null;
  private schema: ParamSpec[] = [];
  private coreVersion = '';
  private readonly files = new Map<string, LoadedFile>();
  private params: ParamValues = {};
  private lids: LidsMode = 'auto';
  private options: ReconOptions = { ...DEFAULT_OPTIONS };
  private surface: string | null = null;
  private sampleId: string | null = null;
  private view: ViewSettings = { ...DEFAULT_VIEW };
  private readonly history = new FrameHistory();
  private playback: pb.Playback = pb.initialPlayback;
  private active: ActiveRun | null = null;
  private result: RunResult | null = null;
  private latest: StepReport | null = null;
  private indices: Uint32Array | null = null;
  private attractors: Float32Array | null = null;
  /** The running run's own contours when they are not the file's (breath-hold alignment). */
  private runContours: Frame['runContours'] | null = null;
  private restartTimer: ReturnType<typeof setTimeout> | null = null;
  /** What is on screen: the history index shown, and whether the final result is. */
  private shown = { cursor: -2, result: false, historyVersion: -1 };
  private historyVersion = 0;
  private contourMode: 'plain' | 'distances' | 'none' = 'none';
  /** The view was widened to the first mesh of this run. */
  private framedRun = false;
  /** Top of the colour scales in mm: contour points (to mesh) and mesh vertices (to contours). */
  private pointMaxMm = 1;
  private meshMaxMm = 1;
  private rafHandle = 0;
  /** Resolves once the core answered (true) or failed to start (false); input waits for it. */
  private readonly ready: Promise<boolean>;
  private markReady: (ok: boolean) => void = () => undefined;
  private coreUp = false;
  private readonly resultListeners: ((r: RunResult | null) => void)[] = [];

  constructor(
    private readonly parts: Parts,
    private readonly appVersion: string,
  ) {
    this.ready = new Promise((resolve) => (this.markReady = resolve));
  }

  // ---- start-up -------------------------------------------------------------------------------

  /** Connects the core; reads the URL; loads the sample the URL names. */
  async start(createClient: () => Promise<CoreClient>): Promise<void> {
    this.parts.view.show(this.view);
    this.setStatus();
    this.loop();
    try {
      this.client = await createClient();
      const { schema, version } = await this.client.schema();
      this.schema = schema;
      this.coreVersion = version;
    } catch (e) {
      const err = asCoreError(e, 'the WebAssembly core could not start');
      this.fail({ ...err, code: err.code === 'worker_crashed' ? 'core_unavailable' : err.code });
      this.markReady(false);
      return;
    }
    this.coreUp = true;
    const url = parseUrlState(location.search, this.schema);
    this.params = url.params;
    this.lids = url.lids;
    this.options = url.options;
    this.view = url.view;
    this.parts.params.setSchema(this.schema);
    this.parts.params.setValues(this.params, this.lids, this.options);
    this.parts.view.show(this.view);
    this.applyView();
    this.setStatus();
    this.markReady(true);
    const sample = findSample(url.sample);
    if (sample) await this.trySample(sample, url.surface);
  }

  // ---- loading --------------------------------------------------------------------------------

  async openFiles(files: File[]): Promise<void> {
    if (files.length === 0) return;
    // Say "loading" at once, before the bytes are read (and before the core is up, if it is not).
    // A run in progress goes on until a file has been read: a refused file leaves the work as it was.
    this.dispatch({ type: 'load', fileName: files[0].name });
    if (!(await this.ready)) return;
    let first: string | null = null;
    for (const file of files) {
      const bytes = await file.arrayBuffer();
      const ok = await this.loadBytes(file.name, bytes);
      if (ok && first === null) first = file.name;
    }
    if (first !== null) {
      this.sampleId = null;
      this.selectFile(first, this.files.get(first)?.session?.surface ?? null);
      this.startRun();
    }
  }

  async trySample(sample: Sample, surface: string | null = null): Promise<void> {
    this.cancelRun();
    this.dispatch({ type: 'load', fileName: sample.file });
    if (!(await this.ready)) return;
    let bytes: ArrayBuffer;
    try {
      bytes = await fetchSample(sample);
    } catch (e) {
      this.fail(asCoreError(e, `could not load ${sample.file}`, sample.file));
      return;
    }
    if (await this.loadBytes(sample.file, bytes)) {
      this.sampleId = sample.id;
      this.selectFile(sample.file, surface ?? sample.surface);
      this.startRun();
    }
  }

  /** Parses a file in the worker; returns whether it worked (errors are shown). */
  private async loadBytes(fileName: string, bytes: ArrayBuffer): Promise<boolean> {
    const client = this.client;
    if (!client) return false;
    this.dispatch({ type: 'load', fileName });
    try {
      const loaded = await client.load(fileName, bytes);
      this.cancelRun(); // read: it replaces what was on screen
      this.files.delete(fileName); // re-insert at the end: newest last in the picker
      this.files.set(fileName, loaded);
      if (loaded.session) this.applySession(loaded.session);
      this.dispatch({ type: 'loaded', fileName });
      this.parts.banner.hide();
      return true;
    } catch (e) {
      // The file is not opened: the previous one (if any) stays current, with its scene and framing.
      const previous = this.currentFile()?.fileName ?? null;
      this.fail(asCoreError(e, 'could not read the file', fileName), undefined, keptText(previous));
      return false;
    }
  }

  /** A saved session brings the settings it was made with: they replace the current ones. */
  private applySession(session: SessionSettings): void {
    this.params = { ...defaultParams(this.schema), ...session.params };
    this.lids = session.lids;
    this.options = withDefaultOptions(session.options);
    this.parts.params.setValues(this.params, this.lids, this.options);
    this.updateUrl();
  }

  chooseFile(fileName: string): void {
    if (!this.files.has(fileName)) return;
    this.sampleId = null;
    this.selectFile(fileName, this.surface);
    this.startRun();
  }

  chooseSurface(surface: string): void {
    const file = this.currentFile();
    if (!file || !file.surfaces.includes(surface)) return;
    this.surface = surface;
    this.showContours(null);
    this.frameSurface(file);
    this.updateUrl();
    this.startRun();
  }

  /** Makes `fileName` current (state -> ready) and shows its contours. */
  private selectFile(fileName: string, preferredSurface: string | null): void {
    const file = this.files.get(fileName);
    if (!file) return;
    if (loadedFile(this.state) !== fileName || this.state.kind === 'loading') {
      this.dispatch({ type: 'load', fileName });
      this.dispatch({ type: 'loaded', fileName });
    }
    const s = file.surfaces;
    this.surface =
      preferredSurface && s.includes(preferredSurface) ? preferredSurface : s.includes('LV_ENDO') ? 'LV_ENDO' : (s[0] ?? null);
    this.parts.files.setFiles([...this.files.keys()], fileName);
    this.parts.files.setSurfaces(s, this.surface);
    const warnings = file.warnings;
    this.parts.warnings.textContent = warnings.length ? `⚠ ${warnings.join(' · ')}` : '';
    this.parts.warnings.hidden = warnings.length === 0;
    this.clearRunDisplay();
    this.showContours(null);
    this.parts.viewer?.landmarkLayer.set(file.landmarks);
    this.frameSurface(file);
    this.updateUrl();
  }

  /**
   * Points the camera at the contours of the chosen surface, at their own scale: a file whose run
   * the core then refuses (a heart in metres, say) stays framed, so the user sees what was refused.
   */
  private frameSurface(file: LoadedFile): void {
    this.parts.viewer?.frame(surfacePoints(file, this.surface));
  }

  private currentFile(): LoadedFile | null {
    const name = loadedFile(this.state);
    return name ? (this.files.get(name) ?? null) : null;
  }

  // ---- hooks for the validation lab (web/src/lab) -----------------------------------------------

  /** The core client once it is up (the lab sends its own requests through it). */
  get coreClient(): CoreClient | null {
    return this.client;
  }

  /** Loads generated contour bytes (a simulated acquisition) and shows them, without a run. */
  async loadGenerated(fileName: string, bytes: ArrayBuffer): Promise<boolean> {
    this.cancelRun();
    if (!(await this.ready)) return false;
    if (!(await this.loadBytes(fileName, bytes))) return false;
    this.sampleId = null;
    this.selectFile(fileName, null);
    return true;
  }

  /** What a run would use now: the current file, surface, parameters, lids and options. */
  runSettings(): { fileName: string; surface: string | null; params: ParamValues; lids: LidsMode; options: ReconOptions } | null {
    const file = this.currentFile();
    if (!file) return null;
    return {
      fileName: file.fileName,
      surface: file.surfaces.length ? this.surface : null,
      params: { ...this.params },
      lids: this.lids,
      options: { ...this.options },
    };
  }

  /** Called with each finished run's result, and with null whenever the shown result is cleared. */
  onResult(listener: (r: RunResult | null) => void): void {
    this.resultListeners.push(listener);
  }

  private emitResult(r: RunResult | null): void {
    for (const l of this.resultListeners) callSafely(() => l(r), 'result listener failed');
  }

  // ---- runs -----------------------------------------------------------------------------------

  /** (Re)starts the reconstruction of the current file with the current parameters. */
  startRun(): void {
    if (this.restartTimer) clearTimeout(this.restartTimer);
    this.restartTimer = null;
    const client = this.client;
    const settings = this.runSettings();
    if (!client || !settings || this.state.kind === 'loading') return;
    this.cancelRun();
    this.clearRunDisplay();
    this.parts.result.clear('running…');
    const handle = client.run(settings, (f) => this.onFrame(f));
    this.active = { runId: handle.runId, cancel: () => handle.cancel() };
    this.dispatch({ type: 'run', runId: handle.runId });
    handle.done.then(
      (r) => this.onDone(r),
      (e) => {
        if (this.active?.runId !== handle.runId) return; // cancelled or replaced: not an error
        this.active = null;
        this.parts.result.clear('no result (see the error)');
        this.fail(asCoreError(e, 'the reconstruction failed', settings.fileName), handle.runId);
      },
    );
  }

  private cancelRun(): void {
    const a = this.active;
    this.active = null;
    a?.cancel();
  }

  /** A parameter changed: debounce, then restart (cancelling the run in progress). */
  setParams(values: ParamValues, lids: LidsMode, options: ReconOptions = this.options): void {
    this.params = { ...this.params, ...values };
    this.lids = lids;
    this.options = { ...options };
    this.updateUrl();
    if (this.restartTimer) clearTimeout(this.restartTimer);
    this.restartTimer = setTimeout(() => this.startRun(), RESTART_DEBOUNCE_MS);
  }

  resetParams(): void {
    this.params = defaultParams(this.schema);
    this.lids = 'auto';
    this.options = { ...DEFAULT_OPTIONS };
    this.parts.params.setValues(this.params, this.lids, this.options);
    this.setParams(this.params, this.lids, this.options);
  }

  private onFrame(f: Frame): void {
    if (!this.active || f.runId !== this.active.runId) return;
    if (f.indices) this.indices = f.indices;
    if (f.attractors) this.attractors = f.attractors;
    if (f.runContours) {
      this.runContours = f.runContours;
      this.showContours(null); // the shifted contours the mesh now follows, and the file's as given
    }
    this.latest = f.report;
    this.parts.status.setProgress(f.report.total_iterations > 0 ? f.report.iteration / f.report.total_iterations : 0);
    if (!this.indices || this.indices.length === 0) return;
    const shownIteration = this.history.at(this.playback.cursor)?.report.iteration;
    const dropped = this.history.push({ report: f.report, positions: f.positions, indices: this.indices, attractors: this.attractors });
    this.historyVersion++;
    if (dropped > 0 && !this.playback.playing && shownIteration !== undefined) {
      this.playback = { ...this.playback, cursor: this.history.indexOfIteration(shownIteration) };
    }
  }

  private onDone(r: RunResult): void {
    if (!this.active || r.runId !== this.active.runId) return;
    this.active = null;
    this.result = r;
    this.pointMaxMm = robustMax(r.pointDistances);
    this.meshMaxMm = robustMax(r.vertexDistances);
    this.parts.status.setProgress(1);
    this.parts.result.show(r);
    // A run finished: whatever error was shown has been dealt with (not a file refused meanwhile).
    if (this.state.kind !== 'error') this.parts.banner.hide();
    this.parts.exports.setAvailable(true, true);
    this.historyVersion++;
    this.dispatch({ type: 'finished', runId: r.runId });
    this.emitResult(r);
  }

  private clearRunDisplay(): void {
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
    this.shown = { cursor: -2, result: false, historyVersion: -1 };
    this.parts.viewer?.meshLayer.clear();
    this.parts.viewer?.attractorLayer.clear();
    this.parts.viewer?.givenLayer.clear();
    this.parts.view.setAsGivenAvailable(false);
    this.parts.viewer?.requestRender();
    this.parts.legend.hide();
    this.parts.meshLegend.hide();
    this.parts.status.setStep(null);
    this.parts.status.setProgress(0);
    this.parts.plot.set([], 1, null);
    this.parts.exports.setAvailable(false, this.currentFile() !== null);
    this.parts.result.clear('no result yet');
    if (this.contourMode === 'distances' || shifted) this.showContours(null);
    this.emitResult(null);
  }

  // ---- timeline -------------------------------------------------------------------------------

  togglePlay(): void {
    this.playback = pb.togglePlaying(this.playback, this.history.length, performance.now());
    if (!this.playback.playing) this.dispatch({ type: 'pause' });
    else this.dispatch({ type: 'resume' });
  }

  step(delta: number): void {
    this.playback = pb.step(this.playback, this.history.length, delta);
    this.dispatch({ type: 'pause' });
  }

  seek(index: number): void {
    this.playback = pb.seek(this.playback, this.history.length, index);
    this.dispatch({ type: 'pause' });
  }

  first(): void {
    this.seek(0);
  }

  latestStep(): void {
    this.playback = { ...this.playback, playing: true, speed: this.playback.speed, cursor: this.history.length - 1 };
    if (this.playback.speed !== 'live') this.playback = { ...this.playback, playing: false };
    this.dispatch({ type: 'resume' });
  }

  setSpeed(speed: pb.Speed): void {
    this.playback = { ...this.playback, speed, lastAdvanceMs: performance.now() };
  }

  // ---- view -----------------------------------------------------------------------------------

  setView(v: ViewSettings): void {
    this.view = v;
    this.applyView();
    this.updateUrl();
  }

  resetView(): void {
    this.parts.viewer?.resetView();
  }

  private applyView(): void {
    const viewer = this.parts.viewer;
    if (!viewer) return;
    viewer.meshLayer.setWireframe(this.view.wireframe);
    viewer.meshLayer.setOpacity(this.view.opacity);
    viewer.attractorLayer.setVisible(this.view.attractors);
    viewer.landmarkLayer.setVisible(this.view.landmarks);
    viewer.givenLayer.setVisible(this.view.asGiven);
    viewer.setClip(this.view.clip);
    viewer.requestRender();
  }

  onHover(info: Parameters<HoverReadout['show']>[0]): void {
    this.parts.hover.show(info, info?.what === 'mesh' ? this.meshMaxMm : this.pointMaxMm);
  }

  screenshot(): Promise<Blob> {
    const viewer = this.parts.viewer;
    return viewer ? viewer.screenshot() : Promise.reject(new Error('no 3D view'));
  }

  exportInfo(): ExportInfo | null {
    const file = this.currentFile();
    if (!file) return null;
    const r = this.result;
    return {
      appVersion: this.appVersion,
      coreVersion: r?.version ?? this.coreVersion,
      fileName: file.fileName,
      surface: r ? r.surface : this.surface,
      lids: r ? r.lids : this.lids,
      options: r?.options ?? this.options,
      params: schemaOrdered(r ? r.params : this.params, this.schema),
    };
  }

  /**
   * The current file as a heartmesh session (its contours with the settings now in the panel:
   * parameters, mesh ends, options, surface), to open again later; null without a file.
   */
  sessionFile(): Promise<Uint8Array> | null {
    const settings = this.runSettings();
    return settings && this.client ? this.client.sessionFile(settings, this.appVersion) : null;
  }

  /** An export that failed (a bad setting, say): the banner says why; the state does not change. */
  showExportError(e: unknown): void {
    this.parts.banner.showError(asCoreError(e, 'the export failed', this.currentFile()?.fileName));
  }

  currentResult(): RunResult | null {
    return this.result;
  }

  /** The current file as loaded (its points as given), for the e2e tests and the console. */
  currentFileData(): LoadedFile | null {
    return this.currentFile();
  }

  // ---- display (once per animation frame) -----------------------------------------------------

  private loop(): void {
    const frame = (now: number) => {
      this.rafHandle = requestAnimationFrame(frame);
      this.display(now);
    };
    this.rafHandle = requestAnimationFrame(frame);
  }

  private display(now: number): void {
    this.playback = pb.tick(this.playback, this.history.length, now);
    const cursor = this.playback.cursor;
    const atEnd = cursor === this.history.length - 1;
    const showResult = this.result !== null && (atEnd || this.history.length === 0);
    const s = this.shown;
    if (s.cursor !== cursor || s.result !== showResult || (s.historyVersion !== this.historyVersion && showResult !== s.result)) {
      this.shown = { cursor, result: showResult, historyVersion: this.historyVersion };
      this.showStep(cursor, showResult);
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
    const total = report?.total_iterations ?? this.latest?.total_iterations ?? (this.params.iterations || 1);
    this.parts.timeline.update({
      length: this.history.length,
      cursor,
      playing: this.playback.playing,
      iteration: report?.iteration ?? null,
      total: report?.total_iterations ?? null,
    });
    this.parts.plot.set(this.history.series(), total, report?.iteration ?? null);
  }

  /** Contours of the current file; with a result, its points coloured by distance (and, aligned, the file's as given). */
  private showContours(r: RunResult | null): void {
    const viewer = this.parts.viewer;
    const file = this.currentFile();
    if (!viewer || !file) return;
    this.parts.view.setAsGivenAvailable(showSceneContours(viewer, file, this.surface, r, this.pointMaxMm, this.runContours));
    this.contourMode = r ? 'distances' : 'plain';
    viewer.requestRender();
  }

  // ---- state ----------------------------------------------------------------------------------

  private dispatch(e: AppEvent): void {
    const next = transition(this.state, e);
    if (next === this.state) return;
    this.state = next;
    this.setStatus();
  }

  private fail(error: CoreErrorData, runId?: number, context = ''): void {
    this.dispatch({ type: 'failed', error, runId });
    if (this.state.kind === 'error') this.parts.banner.showError(error, context);
  }

  private setStatus(): void {
    const s = this.state;
    const starting = !this.coreUp && s.kind === 'empty';
    this.parts.status.setStatus(starting ? 'starting the core…' : statusWord(s), starting ? 'starting' : s.kind, currentRunId(s));
    this.parts.viewer?.setAnimating(s.kind === 'running');
    document.body.dataset.state = s.kind;
    document.body.dataset.hasFile = this.currentFile() ? '1' : '0';
    this.parts.timeline.update({
      length: this.history.length,
      cursor: this.playback.cursor,
      playing: this.playback.playing,
      iteration: this.history.at(this.playback.cursor)?.report.iteration ?? null,
      total: this.latest?.total_iterations ?? null,
    });
    this.parts.exports.setAvailable(this.result !== null, this.currentFile() !== null);
  }

  private updateUrl(): void {
    if (this.schema.length === 0) return;
    const query = serializeUrlState(
      { params: this.params, lids: this.lids, options: this.options, surface: this.surface, sample: this.sampleId, view: this.view },
      this.schema,
    );
    const url = `${location.pathname}${query}${location.hash}`;
    if (url !== `${location.pathname}${location.search}${location.hash}`) history.replaceState(null, '', url);
  }

  /** For tests and the console. */
  get debug(): { state: AppState; historyLength: number; runId: number | null } {
    return { state: this.state, historyLength: this.history.length, runId: this.active?.runId ?? currentRunId(this.state) };
  }

  dispose(): void {
    cancelAnimationFrame(this.rafHandle);
    this.cancelRun();
    this.client?.dispose();
    this.parts.viewer?.dispose();
  }
}

export { asCoreError } from './errors';
