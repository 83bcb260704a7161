/**
 * The Function section of the result column: with two or more phases of one heart open (files, or
 * the frames of one sequence: app/phases.ts), "Measure all phases" reconstructs every surface of
 * every phase at the current settings in the worker, beside the reconstruction on screen, and
 * shows the volumes (ml) in a phases x surfaces table, each cavity's EDV/ESV/SV/EF, the LV mass and
 * a CSV of the cells (the CLI's `heartmesh volumes`); with three phases or more, a curve of each
 * cavity's volume over them (VolumeChart) above the table; with LV_ENDO and LV_EPI, the LV wall's
 * systolic thickening by AHA segment under it all (ThickeningView); with LV_ENDO or LV_EPI, the
 * "Anatomical meshes" row (AnatomicalStudyRow: every phase's LV surfaces on one anatomical layout,
 * saved as a zip, the CLI's `volumes --anatomical-meshes`). A table measured with other
 * settings or other files than those now open is marked stale rather than shown as if it were
 * current, the curve and the thickening with it.
 *
 * `[data-testid=function]` carries `data-state` (idle, measuring, done, stopped, error) and
 * `data-stale` (1 when the settings or files changed since); each cavity's line carries
 * `data-surface`, `data-ef`, `data-edv-ml`, `data-esv-ml`, the mass line `data-ed-g`, `data-es-g`.
 */
import type { LabBatchHandle } from '../core-client/coreClientTypes';
import type { AnatomicalFormat, AnatomicalStudy, CoreErrorData, FunctionSummary, LabProgress, LidsMode, ParamValues, PhaseItem, PhasesJob, ReconOptions } from '../core-client/protocol';
import { download } from '../io/download';
import { surfaceOrder } from '../io/FileBar';
import { phasesBaseName, type ThickeningProvenance } from '../io/export/thickening';
import type { PhasePlan } from '../app/phases';
import { version as APP_VERSION } from '../../../package.json';
import { h } from './dom';
import { cellText, edEsText, massText, singleTexts, ventricleText, volumesCsv } from './functionText';
import { volumeChart } from './VolumeChart';
import { ThickeningView } from './ThickeningView';
import { AnatomicalStudyRow } from './AnatomicalStudyRow';
import { cavities, cavitySeries, curveLayout } from './volumeCurve';

/** What a measurement depends on, as the controller sees it now. */
export interface FunctionContext {
  plan: PhasePlan;
  params: ParamValues;
  lids: LidsMode;
  options: ReconOptions;
  /** Equal while the phases are the same contours (the same files, read the same way). */
  phasesKey: string;
  /** Equal while the parameters, mesh ends, options and the phases' leave-out lists are the same. */
  settingsKey: string;
  /**
   * Said when contours of these phases were left out in the Contours panel (functionText
   * `leftOutNote`): the measurement leaves them out too (each phase's `leave_out`: its file and
   * frame's list, every surface's). Absent or null: none were.
   */
  leftOutNote?: string | null;
}

export interface FunctionHost {
  /** The phases and settings now (null: fewer than two phases open). */
  context(): FunctionContext | null;
  /** Called whenever what `context` returns may have changed. */
  onContextChange(listener: () => void): void;
  /**
   * The core client once it is up; its `schema` (CoreClient's, cached) gives the core's version
   * for the Thickening CSV's header.
   */
  client(): {
    measurePhases(job: PhasesJob, onProgress: (p: LabProgress) => void): LabBatchHandle;
    schema?(): Promise<{ version: string }>;
    /** The anatomical meshes of the last finished measurement (CoreClient.phasesAnatomical). */
    phasesAnatomical?(layout: { rings: number; points: number }, format: AnatomicalFormat): Promise<AnatomicalStudy>;
  } | null;
}

type State = 'measuring' | 'done' | 'stopped' | 'error';

interface Measurement {
  handle: LabBatchHandle;
  plan: PhasePlan;
  phasesKey: string;
  settingsKey: string;
  /** The settings measured with (the Thickening CSV's header). */
  params: ParamValues;
  lids: LidsMode;
  options: ReconOptions;
  coreVersion: string | null;
  phases: string[];
  /** The batch's order (the CLI's: first appearance in the files). */
  surfaces: string[];
  items: PhaseItem[];
  completed: number;
  total: number;
  summary: FunctionSummary | null;
  state: State;
  error: string | null;
}

const MEASURE_HELP = 'Reconstruct every surface of every phase at the current parameters, in the background (the view keeps working), for the volumes, ejection fractions and LV mass';

export class FunctionPanel {
  readonly element: HTMLElement;
  private readonly source: HTMLElement;
  private readonly measure: HTMLButtonElement;
  private readonly stop: HTMLButtonElement;
  private readonly csv: HTMLButtonElement;
  private readonly progressText: HTMLElement;
  private readonly bar: HTMLElement;
  private readonly progress: HTMLElement;
  private readonly stale: HTMLElement;
  private readonly leftOut: HTMLElement;
  private readonly curve: HTMLElement;
  private readonly table: HTMLTableElement;
  private readonly summary: HTMLElement;
  private readonly thickening: ThickeningView;
  private readonly anatomical: AnatomicalStudyRow;
  private readonly error: HTMLElement;
  private m: Measurement | null = null;

  constructor(private readonly host: FunctionHost) {
    const button = (label: string, testid: string, title: string, fn: () => void) => {
      const b = h('button', { type: 'button', class: 'small', 'data-testid': testid, title }, label);
      b.addEventListener('click', fn);
      return b;
    };
    this.measure = button('Measure all phases', 'function-measure', MEASURE_HELP, () => this.start());
    this.stop = button('Stop', 'function-stop', 'Stop measuring (the cells measured so far stay)', () => this.cancel());
    this.csv = button('CSV', 'function-csv', 'The volumes as CSV, one row per phase and surface (the columns of heartmesh volumes --csv)', () => this.downloadCsv());
    this.progressText = h('span', { class: 'function-progress muted', 'data-testid': 'function-progress' });
    this.bar = h('div', { class: 'progress-bar' });
    this.progress = h('div', { class: 'progress', hidden: true }, this.bar);
    this.source = h('p', { class: 'function-source muted' });
    this.stale = h('p', { class: 'function-stale', 'data-testid': 'function-stale', hidden: true });
    this.leftOut = h('p', { class: 'function-left-out', 'data-testid': 'function-left-out', hidden: true });
    this.curve = h('div', { class: 'function-curve-box', hidden: true });
    this.table = h('table', { class: 'function-table', 'data-testid': 'function-table', hidden: true });
    this.summary = h('ul', { class: 'function-summary', 'data-testid': 'function-summary' });
    this.thickening = new ThickeningView(() => this.provenance());
    this.anatomical = new AnatomicalStudyRow({
      build: (layout, format) => {
        const client = this.host.client();
        return client?.phasesAnatomical ? client.phasesAnatomical(layout, format) : null;
      },
    });
    this.error = h('p', { class: 'function-error', 'data-testid': 'function-error', hidden: true });
    this.element = h(
      'section',
      { class: 'panel function', 'data-testid': 'function', 'aria-label': 'Function', hidden: true },
      h('h2', {}, 'Function'),
      this.source,
      h('div', { class: 'function-actions' }, this.measure, this.stop, this.csv, this.progressText),
      this.leftOut,
      this.progress,
      this.stale,
      this.curve,
      this.table,
      this.summary,
      this.thickening.element,
      this.anatomical.element,
      this.error,
    );
    host.onContextChange(() => this.render());
    this.render();
  }

  /** Measures every phase now open at the current settings (a measurement in progress is replaced). */
  start(): void {
    const context = this.host.context();
    const client = this.host.client();
    if (!context || !client) return;
    this.m?.handle.cancel();
    const { plan } = context;
    const job: PhasesJob = { kind: 'phases', phases: plan.phases, params: context.params, lids: context.lids, options: context.options };
    const handle = client.measurePhases(job, (p) => this.onProgress(m, p));
    const m: Measurement = {
      handle,
      plan,
      phasesKey: context.phasesKey,
      settingsKey: context.settingsKey,
      params: context.params,
      lids: context.lids,
      options: context.options,
      coreVersion: null,
      phases: plan.phases.map((p) => p.name),
      surfaces: [],
      items: [],
      completed: 0,
      total: 0,
      summary: null,
      state: 'measuring',
      error: null,
    };
    this.m = m;
    client.schema?.().then(
      (s) => (m.coreVersion = s.version),
      () => undefined,
    );
    handle.started.then(
      (info) => {
        m.surfaces = info.surfaces ?? [];
        m.phases = info.phases ?? m.phases;
        m.total = info.total;
        this.render();
      },
      () => undefined,
    );
    handle.done.then(
      () => this.settle(m, 'done', null),
      (e: CoreErrorData) => this.settle(m, e.code === 'cancelled' ? 'stopped' : 'error', e.code === 'cancelled' ? null : (e.message ?? String(e))),
    );
    this.render();
  }

  /** Stops the measurement in progress; the cells measured so far stay. */
  cancel(): void {
    this.m?.handle.cancel();
  }

  private onProgress(m: Measurement, p: LabProgress): void {
    if (this.m !== m) return;
    m.completed = p.completed;
    m.total = p.total;
    if (p.item && 'phase' in p.item) m.items[p.item.index] = p.item;
    if (p.summary) m.summary = p.summary;
    this.render();
  }

  private settle(m: Measurement, state: State, error: string | null): void {
    if (this.m !== m || m.state !== 'measuring') return;
    m.state = state;
    m.error = error;
    this.render();
  }

  private downloadCsv(): void {
    const m = this.m;
    if (!m) return;
    download(volumesCsv(m.items.filter(Boolean)), `${phasesBaseName(m.plan)}-volumes.csv`, 'text/csv');
  }

  /** What the measurement shown was made of and with, for the thickening's files. */
  private provenance(): ThickeningProvenance | null {
    const m = this.m;
    return m ? { plan: m.plan, params: m.params, lids: m.lids, options: m.options, appVersion: APP_VERSION, coreVersion: m.coreVersion } : null;
  }

  private render(): void {
    const context = this.host.context();
    const m = this.m;
    this.element.hidden = context === null && m === null;
    const d = this.element.dataset;
    d.state = m?.state ?? 'idle';
    const measuring = m?.state === 'measuring';
    const plan = context?.plan ?? m?.plan;
    this.source.textContent = plan ? `${plan.phases.length} phases: ${plan.source}` : '';
    this.measure.disabled = context === null;
    this.measure.textContent = m ? 'Measure again' : 'Measure all phases';
    this.stop.hidden = !measuring;
    this.csv.hidden = !m || m.items.filter(Boolean).length === 0;
    this.progress.hidden = !measuring;
    this.bar.style.width = m && m.total > 0 ? `${(100 * m.completed) / m.total}%` : '0';
    this.progressText.textContent = m && (measuring || m.state === 'stopped') ? `${m.completed} / ${m.total || '…'}${m.state === 'stopped' ? ' (stopped)' : ''}` : '';
    const staleWhy = m && context ? (m.phasesKey !== context.phasesKey ? 'the open phases changed' : m.settingsKey !== context.settingsKey ? 'parameters changed' : null) : null;
    d.stale = staleWhy ? '1' : '0';
    this.stale.hidden = staleWhy === null;
    this.stale.textContent = staleWhy ? `${staleWhy} — measure again` : '';
    this.element.classList.toggle('is-stale', staleWhy !== null);
    const note = context?.leftOutNote ?? null;
    this.leftOut.hidden = note === null;
    this.leftOut.textContent = note ?? '';
    this.error.hidden = !m?.error;
    this.error.textContent = m?.error ? `Not measured: ${m.error}` : '';
    this.renderTable(m);
    this.renderCurve(m);
    this.renderSummary(m);
    // Of the same summary as the lines above: replaced and greyed (styles.css, bullseye.css) with them.
    this.thickening.show(m?.summary ?? null);
    // The worker holds the finished batch's meshes: the layouts are of the table shown, current only.
    const lv = m?.items.some((it) => it && (it.surface === 'LV_ENDO' || it.surface === 'LV_EPI') && it.volume_ml !== null) ?? false;
    this.anatomical.setMeasurement(m && m.state === 'done' && staleWhy === null && lv ? m : null, m ? phasesBaseName(m.plan) : 'phases');
  }

  private renderTable(m: Measurement | null): void {
    if (!m || m.surfaces.length === 0) {
      this.table.hidden = true;
      this.table.replaceChildren();
      return;
    }
    this.table.hidden = false;
    const shown = surfaceOrder(m.surfaces);
    // Surface names break after their underscore in a narrow column (LV_ / ENDO).
    const head = (s: string) => h('th', { scope: 'col', title: `${s}: volume, ml` }, ...s.split(/(?<=_)/).flatMap((part, i) => (i === 0 ? [part] : [h('wbr'), part])));
    const rows = m.phases.map((phase, i) =>
      h(
        'tr',
        {},
        h('th', { scope: 'row', title: phase }, phase),
        ...shown.map((s) => {
          const item = cellOf(m, i, s);
          const { text, title } = cellText(item);
          const kind = item ? (item.volume_ml !== null ? 'volume' : (item.missing ?? 'failed')) : 'pending';
          return h('td', { class: `num ${kind}`, title, 'data-surface': s, 'data-phase': phase, 'data-volume-ml': item?.volume_ml ?? undefined }, text);
        }),
      ),
    );
    this.table.replaceChildren(h('caption', { class: 'visually-hidden' }, 'Volumes (ml) by phase and surface'), h('thead', {}, h('tr', {}, h('th', { scope: 'col', class: 'corner' }, 'ml'), ...shown.map(head))), h('tbody', {}, ...rows));
  }

  /** Each cavity's volume over the phases, once the summary says which surfaces are cavities. */
  private renderCurve(m: Measurement | null): void {
    const s = m?.summary;
    const layout = m && s ? curveLayout(m.phases, cavitySeries(s, surfaceOrder(cavities(s)), m.phases.length, (i, surface) => cellOf(m, i, surface)?.volume_ml ?? null)) : null;
    this.curve.hidden = layout === null;
    this.curve.replaceChildren(...(layout ? volumeChart(layout) : []));
  }

  private renderSummary(m: Measurement | null): void {
    const s = m?.summary;
    if (!m || !s) {
      this.summary.replaceChildren();
      return;
    }
    const order = surfaceOrder(s.ventricles.map((v) => v.surface));
    const lines: HTMLElement[] = order.map((surface) => {
      const v = s.ventricles.find((x) => x.surface === surface);
      if (!v) return h('li', {});
      return h(
        'li',
        { 'data-testid': 'function-ventricle', 'data-surface': v.surface, 'data-ef': v.ef_percent, 'data-edv-ml': v.edv_ml, 'data-esv-ml': v.esv_ml, title: `end-diastole: the phase of largest volume; end-systole: of smallest (${v.phases_used} phases with a volume)` },
        ventricleText(v),
        h('span', { class: 'muted function-phases' }, edEsText(v)),
      );
    });
    for (const text of singleTexts(s)) lines.push(h('li', { class: 'muted', 'data-testid': 'function-single' }, text));
    const mass = massText(s, m.surfaces);
    if (mass) {
      const lv = s.lv_mass;
      lines.push(
        h('li', { 'data-testid': 'function-mass', 'data-ed-g': lv?.ed_g ?? undefined, 'data-es-g': lv?.es_g ?? undefined, title: `${lv?.density_g_per_ml ?? 1.05} g/ml x (LV_EPI − LV_ENDO)` }, mass),
      );
    }
    this.summary.replaceChildren(...lines);
  }
}

/** The cell of phase `i` and `surface` (the batch measures each phase's surfaces in turn). */
function cellOf(m: Measurement, i: number, surface: string): PhaseItem | undefined {
  const k = m.surfaces.indexOf(surface);
  return k < 0 ? undefined : m.items[i * m.surfaces.length + k];
}
