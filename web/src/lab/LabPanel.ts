/**
 * The Lab panel (issue 5): the validation protocol of Villard, Grau & Zacur (J. Imaging 2018,
 * section 3) in the browser. Pick a ground truth (the parametric LV, a bundled reference shape or
 * dropped meshes: several are several labelled surfaces of one heart, sliced on one acquisition
 * like the CLI's `heartmesh simulate LV_ENDO=lv.obj RV_ENDO=rv.obj`), slice it like a CMR
 * acquisition, reconstruct with the app's normal animated run, then compare each surface with the
 * truth of the same label; leave-one-out and a parameter sweep run as batches in the worker.
 *
 * Everything heavy happens in the worker through CoreClient's lab calls; this class holds the
 * page-side state, builds the DOM, and listens to the controller's results. Errors (a bad mesh,
 * an impossible acquisition) show in the panel's message line and never stop the app.
 */
import './lab.css';
import type { Controller } from '../app/controller';
import { describeError } from '../app/state';
import type { CoreClient, LabBatchHandle } from '../core-client/CoreClient';
import type {
  AcquisitionSpec, ContourInfo, CoreErrorData, LabAcquisition, LabTruth, LabTruthSource, LooItem, ParametricLvSpec, RunResult, SweepGrid, SweepItem,
} from '../core-client/protocol';
import { download } from '../io/download';
import { h } from '../ui/dom';
import { robustMax } from '../viewer/colormap';
import { Legend } from '../viewer/Legend';
import type { Viewer } from '../viewer/Viewer';
import { button, numberInput, section, slider, textInput } from './forms';
import { LooChart } from './LooChart';
import { MetricsTable } from './MetricsTable';
import { SweepPlot } from './SweepPlot';
import { parseValueList, sweepCsv } from './sweepCsv';
import { labelProblem, labelsForNew, simulateProblem, truthForSurface } from './truthLabels';
import { TruthLayer } from './TruthLayer';
import { TruthList, frameText } from './TruthList';

/** Reference shapes shipped in public/lab/ (licences in public/lab/NOTICE.md). */
export const REFERENCE_SHAPES = [
  { id: 'bivme-lv', file: 'bivme-patient1-ED-LV_ENDO-closed.obj', label: 'biv-me patient 1 LV endo (ED)' },
  { id: 'cardiomesh-lv', file: 'cardiomesh-spasm-LV_endo.obj', label: 'CardioMesh LV endo (open base)' },
] as const;

/** Extensions the Lab takes as a truth surface when dropped while it is open. */
const MESH_EXT = /\.(obj|stl|ply|vtk|vtp)$/i;

export interface LabDeps {
  controller: Controller;
  viewer: Viewer | null;
  legendSlot: HTMLElement;
}

export class LabPanel {
  readonly element: HTMLElement;
  private readonly truthLayer = new TruthLayer();
  private readonly legend = new Legend('truth: distance to mesh', 'legend-truth');
  private readonly message = h('p', { class: 'lab-message', 'data-testid': 'lab-message', role: 'status' });
  private readonly truthInfo = h('p', { class: 'muted', 'data-testid': 'lab-truth-info' }, 'no truth yet');
  private readonly acqInfo = h('p', { class: 'muted', 'data-testid': 'lab-acq-info' }, 'not simulated yet');
  private readonly acqSurfaces = h('ul', { class: 'lab-acq-surfaces', 'data-testid': 'lab-acq-surfaces' });
  private readonly compareInfo = h('p', { class: 'muted', 'data-testid': 'lab-compare-info' });
  private readonly truthList: TruthList;
  private readonly metrics = new MetricsTable();
  private readonly loo: LooChart;
  private readonly looProgress = h('progress', { max: 1, value: 0, 'data-testid': 'lab-loo-progress' });
  private readonly looInfo = h('p', { class: 'muted', 'data-testid': 'lab-loo-info' });
  private readonly sweepPlot = new SweepPlot();
  private readonly sweepProgress = h('progress', { max: 1, value: 0, 'data-testid': 'lab-sweep-progress' });
  private readonly sweepInfo = h('p', { class: 'muted', 'data-testid': 'lab-sweep-info' });
  private readonly sweepBrush = h('span', { class: 'muted small', 'data-testid': 'lab-sweep-brush' });
  private readonly source: HTMLSelectElement;
  private readonly lvBox: HTMLElement;
  private readonly lv;
  private readonly acq;
  private readonly grid;
  private readonly mapToggle: HTMLInputElement;
  private readonly buttons: Record<string, HTMLButtonElement> = {};
  /** The truths, in order (the worker's Lab holds the same; the first plans the acquisition). */
  private truths: LabTruth[] = [];
  /** The truths are dropped or opened meshes (more are added beside them), not a preset. */
  private fromFiles = false;
  /** The truth the last comparison measured (its distance map is drawn). */
  private comparedIndex = 0;
  private truthTimer: ReturnType<typeof setTimeout> | null = null;
  /** The generated contour file, and whether the truth it was cut from is still the current one. */
  private labFile: string | null = null;
  private truthDistances: Float32Array | null = null;
  private truthMaxMm = 1;
  private looRun: { handle: LabBatchHandle; contours: ContourInfo[]; points: Float32Array } | null = null;
  private looContours: { contours: ContourInfo[]; points: Float32Array } | null = null;
  private sweepRun: LabBatchHandle | null = null;
  private sweepRows: SweepItem[] = [];
  private sweepComment: string[] = [];
  private compareSeq = 0;

  constructor(private readonly deps: LabDeps) {
    const { viewer } = deps;
    viewer?.scene.add(this.truthLayer.group);
    deps.legendSlot.append(this.legend.element);

    // ---- 1. truth
    this.source = h(
      'select',
      { id: 'lab-source', 'data-testid': 'lab-source' },
      h('option', { value: 'parametric' }, 'parametric LV'),
      ...REFERENCE_SHAPES.map((r) => h('option', { value: r.id }, r.label)),
      h('option', { value: 'file' }, 'mesh files (OBJ, STL, PLY, VTK)…'),
    );
    const change = () => this.scheduleTruth();
    this.lv = {
      length: slider('lv-length', 'Length (apex to base)', { min: 40, max: 120, step: 1, value: 80, unit: 'mm' }, change),
      radius: slider('lv-radius', 'Radius', { min: 10, max: 40, step: 0.5, value: 25, unit: 'mm' }, change),
      base: slider('lv-base', 'Base opening radius', { min: 4, max: 40, step: 0.5, value: 20, unit: 'mm' }, change),
      bulge: slider('lv-bulge', 'Regional bulge', { min: -8, max: 8, step: 0.5, value: 0, unit: 'mm' }, change),
      height: slider('lv-bulge-height', 'Bulge height (apex 0, base 1)', { min: 0.1, max: 0.9, step: 0.05, value: 0.5 }, change),
    };
    this.lvBox = h('div', {}, ...Object.values(this.lv).map((f) => f.element));
    const fileInput = h('input', { type: 'file', accept: '.obj,.stl,.ply,.vtk,.vtp', multiple: true, 'data-testid': 'lab-truth-file', class: 'visually-hidden', id: 'lab-truth-file' });
    fileInput.addEventListener('change', () => {
      const files = [...(fileInput.files ?? [])];
      if (files.length) void this.truthsFromFiles(files);
      fileInput.value = '';
    });
    this.truthList = new TruthList({ label: (i, text) => void this.relabel(i, text), remove: (i) => void this.removeTruth(i) });
    const openMesh = h('label', { for: 'lab-truth-file', class: 'button small', 'data-testid': 'lab-truth-open' }, 'Open mesh…');
    this.source.addEventListener('change', () => {
      this.lvBox.hidden = this.source.value !== 'parametric';
      if (this.source.value === 'file') fileInput.click();
      else void this.makeTruth();
    });

    // ---- 2. acquisition
    const saxMode = h('select', { id: 'lab-sax-mode', 'data-testid': 'lab-sax-mode' }, h('option', { value: 'count' }, 'SAX count'), h('option', { value: 'spacing' }, 'SAX spacing (mm)'));
    this.acq = {
      saxMode,
      sax: numberInput('sax', 'SAX', { min: 1, max: 60, step: 1, value: 8 }),
      lax: slider('lax', 'LAX planes (0, 90, 45, 135, … deg)', { min: 0, max: 8, step: 1, value: 2 }, () => undefined),
      shift: slider('shift', 'Breath-hold shift (max)', { min: 0, max: 5, step: 0.25, value: 0, unit: 'mm' }, () => undefined),
      tilt: slider('tilt', 'Breath-hold tilt (max)', { min: 0, max: 5, step: 0.25, value: 0, unit: '°' }, () => undefined),
      noise: slider('noise', 'Contour noise (sd)', { min: 0, max: 1, step: 0.05, value: 0, unit: 'mm' }, () => undefined),
      seed: numberInput('seed', 'Seed', { min: 0, max: 1e9, step: 1, value: 1 }),
    };
    saxMode.addEventListener('change', () => {
      const spacing = saxMode.value === 'spacing';
      this.acq.sax.input.step = spacing ? '0.5' : '1';
      this.acq.sax.set(spacing ? 10 : 8);
    });

    // ---- 3. metrics
    this.mapToggle = h('input', { type: 'checkbox', id: 'lab-map', checked: true, 'data-testid': 'lab-map' });
    this.mapToggle.addEventListener('change', () => this.showTruthMap());

    // ---- 4. leave-one-out
    this.loo = new LooChart((i) => this.selectContour(i));

    // ---- 5. sweep
    this.grid = {
      lambda: textInput('grid-lambda', 'λ', '1e3, 1e5'),
      smoothing: textInput('grid-smoothing', 'smoothing iterations', '50, 200'),
      reduction: textInput('grid-reduction', 'target reduction', '0.6, 0.72'),
      spacing: textInput('grid-spacing', 'attractor spacing mm (0 = count)', '0'),
    };

    const b = this.buttons;
    b.simulate = button('Simulate acquisition', 'lab-simulate', () => void this.simulate(), 'button primary');
    b.reconstruct = button('Reconstruct', 'lab-reconstruct', () => this.reconstruct());
    b.looRun = button('Run leave-one-out', 'lab-loo-run', () => void this.runLoo());
    b.looCancel = button('Cancel', 'lab-loo-cancel', () => this.looRun?.handle.cancel());
    b.sweepRun = button('Run sweep', 'lab-sweep-run', () => void this.runSweep());
    b.sweepCancel = button('Cancel', 'lab-sweep-cancel', () => this.sweepRun?.cancel());
    b.sweepCsv = button('Download CSV', 'lab-sweep-csv', () => this.downloadCsv());
    b.looCancel.disabled = b.sweepCancel.disabled = b.sweepCsv.disabled = true;

    this.element = h(
      'div',
      { class: 'lab', 'data-testid': 'lab-panel' },
      this.message,
      section('1 · Truth', 'lab-truth', h('div', { class: 'lab-row' }, this.source, openMesh, fileInput), this.lvBox, this.truthList.element, this.truthInfo),
      section(
        '2 · Acquisition',
        'lab-acquisition',
        h('div', { class: 'lab-row' }, saxMode, this.acq.sax.element),
        this.acq.lax.element,
        this.acq.shift.element,
        this.acq.tilt.element,
        this.acq.noise.element,
        h('div', { class: 'lab-row' }, this.acq.seed.element),
        h('div', { class: 'lab-row' }, b.simulate, b.reconstruct),
        this.acqInfo,
        this.acqSurfaces,
      ),
      section(
        '3 · Against the truth',
        'lab-compare',
        this.compareInfo,
        this.metrics.element,
        h('label', { class: 'check', for: 'lab-map' }, this.mapToggle, ' distance map on the truth (hides the mesh)'),
      ),
      section(
        '4 · Leave-one-out',
        'lab-loo',
        h('p', { class: 'muted' }, 'Rebuild without each contour of the current file; bar = its mean distance to that mesh.'),
        h('div', { class: 'lab-row' }, b.looRun, b.looCancel, this.looProgress),
        this.loo.element,
        this.looInfo,
      ),
      section(
        '5 · Parameter sweep',
        'lab-sweep',
        ...Object.values(this.grid).map((g) => g.element),
        h('div', { class: 'lab-row' }, b.sweepRun, b.sweepCancel, this.sweepProgress),
        this.sweepPlot.element,
        h('div', { class: 'lab-row' }, b.sweepCsv, this.sweepBrush),
        this.sweepInfo,
      ),
      h('p', { class: 'muted small' }, 'Method and protocol: Villard, Grau & Zacur, J. Imaging 2018. Reference shapes: biv-me (Apache-2.0), CardioMesh (MIT); see lab/NOTICE.md.'),
    );

    this.sweepPlot.onBrush = (selected, total) => {
      this.sweepBrush.textContent = total > 0 ? (selected === total ? 'drag along an axis to select' : `${selected} of ${total} runs selected`) : '';
      this.sweepBrush.dataset.selected = String(selected);
    };
    deps.controller.onResult((r) => this.onResult(r));
  }

  /** Puts the panel in the left sidebar behind a "Parameters | Lab" tab bar. */
  mount(sidebar: HTMLElement, paramsElement: HTMLElement): void {
    const tabs = h('div', { class: 'lab-tabs', role: 'tablist' });
    const paramsTab = h('button', { type: 'button', role: 'tab', 'data-testid': 'tab-params', 'aria-selected': 'true' }, 'Parameters');
    const labTab = h('button', { type: 'button', role: 'tab', 'data-testid': 'tab-lab', 'aria-selected': 'false' }, 'Lab');
    tabs.append(paramsTab, labTab);
    this.element.hidden = true;
    sidebar.prepend(tabs);
    sidebar.append(this.element);
    const show = (lab: boolean) => {
      paramsElement.hidden = lab;
      this.element.hidden = !lab;
      paramsTab.setAttribute('aria-selected', String(!lab));
      labTab.setAttribute('aria-selected', String(lab));
      document.body.classList.toggle('lab-open', lab);
      // A first truth to look at, unless contours are already on screen (their coordinates have
      // nothing to do with the truth's: it would only hide them).
      if (lab && this.truths.length === 0 && this.deps.controller.runSettings() === null) void this.makeTruth();
    };
    paramsTab.addEventListener('click', () => show(false));
    labTab.addEventListener('click', () => show(true));
  }

  get isOpen(): boolean {
    return !this.element.hidden;
  }

  /**
   * Dropped files: with the Lab open, meshes become truths (true = taken): they replace a preset
   * truth (parametric LV, reference shape) and join earlier dropped ones.
   */
  claimDrop(files: File[]): boolean {
    if (!this.isOpen || files.length === 0 || !files.every((f) => MESH_EXT.test(f.name))) return false;
    void this.truthsFromFiles(files);
    return true;
  }

  // ---- truth ----------------------------------------------------------------------------------

  private client(): CoreClient | null {
    const c = this.deps.controller.coreClient;
    if (!c) this.say('the core is not running yet', true);
    return c;
  }

  private scheduleTruth(): void {
    if (this.truthTimer) clearTimeout(this.truthTimer);
    this.truthTimer = setTimeout(() => void this.makeTruth(), 250);
  }

  private lvSpec(): ParametricLvSpec {
    const radius = this.lv.radius.value();
    return {
      length_mm: this.lv.length.value(),
      radius_mm: radius,
      base_radius_mm: Math.min(this.lv.base.value(), radius),
      bulge_mm: this.lv.bulge.value(),
      bulge_height: this.lv.height.value(),
      bulge_width_mm: 10,
    };
  }

  /** Makes the truth from the chosen source (parametric LV or a bundled shape). */
  async makeTruth(): Promise<boolean> {
    const v = this.source.value;
    if (v === 'file') return false;
    if (v === 'parametric') return this.setTruth({ kind: 'parametric', lv: this.lvSpec() });
    const shape = REFERENCE_SHAPES.find((r) => r.id === v);
    if (!shape) return false;
    try {
      const r = await fetch(new URL(`lab/${shape.file}`, document.baseURI));
      if (!r.ok) throw new Error(`HTTP ${r.status}`);
      return this.setTruth({ kind: 'file', fileName: shape.file, bytes: await r.arrayBuffer() });
    } catch (e) {
      this.say(`could not load ${shape.file}: ${e instanceof Error ? e.message : String(e)}`, true);
      return false;
    }
  }

  /**
   * Mesh files as truths, each labelled from its name where it holds a known surface name: the
   * first replaces a preset truth, the others (and all, when the truths are already files) are
   * added. A file that fails, or whose label another truth has, is said in one message; the
   * truths already held stay.
   */
  async truthsFromFiles(files: File[]): Promise<void> {
    const client = this.client();
    if (!client) return;
    const before = this.source.value;
    this.source.value = 'file';
    this.lvBox.hidden = true;
    let replace = !(this.fromFiles && this.truths.length > 0);
    let changed = false;
    const labels = labelsForNew(files.map((f) => f.name), replace ? [] : this.truths.map((t) => t.label));
    const problems: string[] = [];
    this.say(`reading ${files.length === 1 ? files[0].name : `${files.length} meshes`}…`);
    for (const [i, f] of files.entries()) {
      const { label, clash } = labels[i];
      try {
        const t = await client.labTruth({ kind: 'file', fileName: f.name, bytes: await f.arrayBuffer() }, { add: !replace, label });
        this.truths = replace ? [t] : [...this.truths, t];
        replace = false;
        changed = true;
        this.fromFiles = true;
        if (clash) problems.push(`${f.name}: the label ${clash} is already another truth's; give it its own below`);
      } catch (e) {
        problems.push(errorText(e, f.name));
      }
    }
    // Nothing read: the truths (and their acquisition) are as they were.
    if (!changed) this.source.value = before;
    this.lvBox.hidden = this.source.value !== 'parametric';
    if (changed) this.truthsChanged();
    this.say(problems.join('; '), problems.length > 0);
  }

  private async setTruth(source: LabTruthSource): Promise<boolean> {
    const client = this.client();
    if (!client) return false;
    const name = source.kind === 'file' ? source.fileName : 'parametric LV';
    this.say(`making the truth (${name})…`);
    try {
      const t = await client.labTruth(source);
      this.truths = [t];
      this.fromFiles = false;
      this.truthsChanged();
      this.say('');
      return true;
    } catch (e) {
      this.sayError(e, name);
      return false;
    }
  }

  /** Labels truth `index` (empty: no label) unless the label is invalid or another truth's. */
  private async relabel(index: number, text: string): Promise<void> {
    const t = this.truths[index];
    const client = this.client();
    if (!t || !client) return;
    const label = text.trim() === '' ? null : text.trim();
    const problem = label === null ? null : labelProblem(label, index, this.truths.map((x) => x.label));
    if (problem) {
      this.say(`${t.name}: ${problem}`, true);
      this.renderTruths();
      return;
    }
    try {
      await client.labEditTruth({ index, label });
      this.truths = this.truths.map((x, k) => (k === index ? { ...x, label } : x));
      this.truthsChanged(false);
      this.say('');
    } catch (e) {
      this.sayError(e, t.name);
      this.renderTruths();
    }
  }

  private async removeTruth(index: number): Promise<void> {
    const t = this.truths[index];
    const client = this.client();
    if (!t || !client) return;
    try {
      await client.labEditTruth({ index, remove: true });
      this.truths = this.truths.filter((_, k) => k !== index);
      if (this.truths.length === 0) {
        this.fromFiles = false;
        this.source.value = 'parametric';
        this.lvBox.hidden = false;
      }
      this.truthsChanged();
      this.say('');
    } catch (e) {
      this.sayError(e, t.name);
    }
  }

  /** The truths changed: draw them, forget the acquisition and measures of the old ones. */
  private truthsChanged(frame = true): void {
    this.labFile = null;
    this.truthDistances = null;
    this.comparedIndex = 0;
    this.truthLayer.setSurfaces(this.truths);
    this.truthLayer.setHighlight(null);
    this.legend.hide();
    this.metrics.clear('simulate an acquisition, then reconstruct');
    this.compareInfo.textContent = '';
    this.acqSurfaces.replaceChildren();
    this.renderTruths();
    if (frame && this.truths.length) this.deps.viewer?.frame(concat(this.truths.map((t) => t.positions)));
    this.deps.viewer?.requestRender();
  }

  private renderTruths(): void {
    const ts = this.truths;
    this.truthList.render(ts, this.fromFiles);
    const vertices = ts.reduce((n, t) => n + t.vertices, 0);
    if (ts.length === 0) {
      this.truthInfo.textContent = 'no truth yet: pick one above or drop meshes';
      delete this.truthInfo.dataset.vertices;
    } else if (ts.length === 1) {
      const t = ts[0];
      this.truthInfo.textContent = `${t.name}: ${t.vertices} vertices, ${t.triangles} triangles, ${t.volumeMl.toFixed(1)} ml${t.closed ? '' : ' (open)'}${frameText(t)}`;
      this.truthInfo.dataset.vertices = String(vertices);
    } else {
      const converted = ts.filter((t) => t.convertedFrom && t.frame).map((t) => `${t.label ?? t.name}'s file is in ${t.convertedFrom}: taken into ${t.frame}, the first's frame (x and y negated)`);
      this.truthInfo.textContent = `${ts.length} surfaces of one heart (${ts.map((t) => t.label ?? '?').join(', ')}), sliced on one acquisition planned on the first${converted.map((c) => `; ${c}`).join('')}`;
      this.truthInfo.dataset.vertices = String(vertices);
    }
    this.truthInfo.dataset.count = String(ts.length);
  }

  /** How the truths are named in file names and the sweep's comment. */
  private truthTitle(): string {
    return this.truths.length > 1 ? this.truths.map((t) => t.label ?? t.name).join('-') : (this.truths[0]?.name ?? 'truth');
  }

  // ---- acquisition and reconstruction -----------------------------------------------------------

  private acquisitionSpec(): AcquisitionSpec {
    const a = this.acq;
    const spec: AcquisitionSpec = {
      lax_count: a.lax.value(),
      shift_mm: a.shift.value(),
      tilt_deg: a.tilt.value(),
      noise_mm: a.noise.value(),
      seed: Math.max(0, Math.round(a.seed.value()) || 0),
    };
    if (a.saxMode.value === 'spacing') spec.sax_spacing_mm = a.sax.value();
    else spec.sax_count = Math.round(a.sax.value());
    return spec;
  }

  /** Slices the truth and loads the contours as the current file (shown, not yet reconstructed). */
  async simulate(): Promise<boolean> {
    const client = this.client();
    if (!client) return false;
    if (this.truths.length === 0 && !(await this.makeTruth())) return false;
    const problem = simulateProblem(this.truths);
    if (problem) {
      this.say(problem, true);
      return false;
    }
    const spec = this.acquisitionSpec();
    this.say('simulating the acquisition…');
    try {
      const acq = await client.labSimulate(spec);
      const base = this.truthTitle().replace(/\.[^.]+$/, '').replace(/[^\w-]+/g, '-');
      const fileName = `lab-${base}-${acq.sax}sax-${acq.lax}lax.csv`;
      this.labFile = fileName;
      if (!(await this.deps.controller.loadGenerated(fileName, acq.csv))) {
        this.labFile = null;
        this.say('the simulated contours could not be loaded (see the banner)', true);
        return false;
      }
      this.truthLayer.setVisible(true);
      this.truthLayer.setDistances(null, 1);
      const several = this.truths.length > 1;
      this.acqInfo.textContent = `${acq.sax} SAX + ${acq.lax} LAX ${several ? `images, ${acq.surfaces.length} surfaces` : 'contours'}, ${acq.points} points${imperfections(spec)} → ${fileName}`;
      this.acqSurfaces.replaceChildren(...(several ? surfaceRows(acq) : []));
      this.say(several ? 'reconstruct each surface (or All); each is compared with its own truth' : '');
      return true;
    } catch (e) {
      this.sayError(e, this.truths.length === 1 ? this.truths[0].name : undefined);
      return false;
    }
  }

  private reconstruct(): void {
    if (!this.labFile || this.deps.controller.runSettings()?.fileName !== this.labFile) {
      void this.simulate().then((ok) => ok && this.deps.controller.startRun());
      return;
    }
    this.deps.controller.startRun();
  }

  /** A run finished (compare with the truth when it was cut from it) or the result was cleared. */
  private onResult(r: RunResult | null): void {
    const onLabFile = this.labFile !== null && this.deps.controller.runSettings()?.fileName === this.labFile;
    const seq = ++this.compareSeq;
    if (!onLabFile) {
      this.truthLayer.setVisible(false);
      this.legend.hide();
      if (r === null) this.metrics.clear('the current contours were not simulated from this truth');
      this.compareInfo.textContent = '';
      return;
    }
    this.truthLayer.setVisible(true);
    if (!r) {
      this.truthDistances = null;
      this.showTruthMap();
      this.metrics.clear('reconstruct to compare with the truth');
      return;
    }
    const client = this.client();
    if (!client) return;
    const several = this.truths.length > 1;
    const k = truthForSurface(r.surface, this.truths.map((t) => t.label));
    this.compareInfo.dataset.surface = r.surface ?? '';
    if (k === null) {
      // Never against another surface's truth: say there is none.
      this.truthDistances = null;
      this.showTruthMap();
      const labels = this.truths.map((t) => t.label ?? '?').join(', ');
      this.metrics.clear(`no truth for ${r.surface ?? 'this surface'}: the Lab's truths are ${labels}; nothing to compare`);
      this.compareInfo.textContent = '';
      this.compareInfo.dataset.truth = '';
      return;
    }
    this.metrics.clear('measuring against the truth…');
    client.labCompare(r.positions, r.indices, several ? r.surface : null).then(
      (c) => {
        if (seq !== this.compareSeq) return;
        this.metrics.show(c.report);
        this.comparedIndex = c.truthIndex;
        this.compareInfo.textContent = several ? `${r.surface} against the ${c.truthLabel} truth (${c.truthName})` : '';
        this.compareInfo.dataset.truth = c.truthLabel ?? c.truthName;
        this.truthDistances = c.truthDistances;
        this.truthMaxMm = Math.max(0.5, robustMax(c.truthDistances));
        this.showTruthMap();
      },
      (e) => {
        if (seq === this.compareSeq) this.sayError(e);
      },
    );
  }

  private showTruthMap(): void {
    const viewer = this.deps.viewer;
    const on = this.mapToggle.checked && this.truthDistances !== null;
    this.truthLayer.setDistances(on ? this.truthDistances : null, this.truthMaxMm, this.comparedIndex);
    if (viewer) viewer.meshLayer.group.visible = !on && viewer.meshLayer.group.children.length > 0 && this.hasMesh();
    if (on) this.legend.show(this.truthMaxMm);
    else this.legend.hide();
    viewer?.requestRender();
  }

  private hasMesh(): boolean {
    return this.deps.controller.currentResult() !== null || this.deps.controller.debug.historyLength > 0;
  }

  // ---- leave-one-out --------------------------------------------------------------------------

  private async runLoo(): Promise<void> {
    const client = this.client();
    const settings = this.deps.controller.runSettings();
    if (!client) return;
    if (!settings) {
      this.say('load contours or simulate an acquisition first', true);
      return;
    }
    this.looRun?.handle.cancel();
    const leftOut = this.leftOutNote();
    const b = this.buttons;
    b.looRun.disabled = true;
    b.looCancel.disabled = false;
    this.looProgress.value = 0;
    this.looInfo.textContent = 'starting…';
    delete this.looInfo.dataset.done;
    delete this.looInfo.dataset.selected;
    this.truthLayer.setHighlight(null);
    this.deps.viewer?.requestRender();
    const handle = client.labBatch({ kind: 'loo', ...settings, leaveOut: this.leaveOutNow() }, (p) => {
      this.looProgress.max = Math.max(1, p.total);
      this.looProgress.value = p.completed;
      this.looInfo.textContent = `${p.completed} / ${p.total} contours`;
      if (p.item) this.loo.add(p.item as LooItem);
    });
    // Cancel is enabled from now on: it must reach this batch before the worker says it started.
    this.looRun = { handle, contours: [], points: new Float32Array() };
    try {
      const info = await handle.started;
      const contours = info.contours ?? [];
      this.looRun = { handle, contours, points: info.points ?? new Float32Array() };
      this.looContours = { contours, points: info.points ?? new Float32Array() };
      this.loo.reset(info.total);
      this.looProgress.max = Math.max(1, info.total);
      await handle.done;
      const worst = this.loo.worst();
      if (worst >= 0) this.selectContour(worst);
      this.looInfo.textContent = `done: ${info.total} contours; worst ${worst >= 0 ? (contours[worst]?.id ?? `#${worst + 1}`) : '–'}${leftOut}`;
      this.looInfo.dataset.done = '1';
    } catch (e) {
      const err = e as CoreErrorData;
      if (err.code === 'cancelled') this.looInfo.textContent = 'cancelled';
      else this.sayError(e, settings.fileName);
    } finally {
      if (this.looRun?.handle === handle || this.looRun === null) {
        this.looRun = null;
        b.looRun.disabled = false;
        b.looCancel.disabled = true;
      }
    }
  }

  /** Highlights contour `index` of the last leave-one-out in the chart and in 3D. */
  selectContour(index: number): void {
    const lc = this.looContours;
    const c = lc?.contours[index];
    if (!lc || !c) return;
    this.loo.select(index);
    const xyz: number[] = [];
    for (const p of c.pieces) for (let k = 0; k < p.count; k++) {
      const i = (p.start + k) * 3;
      xyz.push(lc.points[i], lc.points[i + 1], lc.points[i + 2]);
    }
    this.truthLayer.setHighlight(new Float32Array(xyz), c.pieces.length === 1 && c.pieces[0].closed);
    this.looInfo.dataset.selected = String(index);
    const label = c.id || `#${index + 1}`;
    this.looInfo.textContent = `selected ${label} (${c.kind ?? '?'})`;
    this.deps.viewer?.requestRender();
  }

  // ---- parameter sweep ------------------------------------------------------------------------

  private sweepGrid(): SweepGrid {
    return {
      lambda: parseValueList(this.grid.lambda.input.value, 'λ'),
      smoothing_iterations: parseValueList(this.grid.smoothing.input.value, 'smoothing iterations'),
      target_reduction: parseValueList(this.grid.reduction.input.value, 'target reduction'),
      attractor_spacing: parseValueList(this.grid.spacing.input.value, 'attractor spacing'),
    };
  }

  private async runSweep(): Promise<void> {
    const client = this.client();
    const settings = this.deps.controller.runSettings();
    if (!client) return;
    if (!settings) {
      this.say('load contours or simulate an acquisition first', true);
      return;
    }
    let grid: SweepGrid;
    try {
      grid = this.sweepGrid();
    } catch (e) {
      this.say(e instanceof Error ? e.message : String(e), true);
      return;
    }
    this.sweepRun?.cancel();
    const leftOut = this.leftOutNote();
    // Against the truth of the surface swept (never another's), when the file was cut from them.
    const truthIndex = truthForSurface(settings.surface, this.truths.map((t) => t.label));
    const withTruth = this.labFile !== null && settings.fileName === this.labFile && truthIndex !== null;
    const b = this.buttons;
    b.sweepRun.disabled = true;
    b.sweepCancel.disabled = false;
    delete this.sweepInfo.dataset.done;
    this.sweepRows = [];
    this.sweepPlot.render([]);
    this.sweepComment = [
      `heartmesh parameter sweep of ${settings.fileName}${settings.surface ? ` (${settings.surface})` : ''}${withTruth && truthIndex !== null ? ` against ${this.truths[truthIndex].name}` : ''}`,
      `base parameters ${JSON.stringify(settings.params)} lids ${settings.lids} smoothing_method ${settings.options.smoothing_method} soften_conflicts ${settings.options.soften_conflicts} align_slices ${settings.options.align_slices} end_caps ${settings.options.end_caps} keep_specks ${settings.options.keep_specks} apex_floor ${settings.options.apex_floor}${settings.options.drop_second_loops ? ' drop_second_loops true' : ''}${this.leaveOutNow().length > 0 ? ` leave_out ${this.leaveOutNow().join(',')}` : ''}`,
      'distances in mm (contour_*: contour points to mesh; truth_mean: mesh to truth, clipped), volume in ml',
    ];
    const handle = client.labBatch({ kind: 'sweep', ...settings, grid, withTruth, leaveOut: this.leaveOutNow() }, (p) => {
      this.sweepProgress.max = Math.max(1, p.total);
      this.sweepProgress.value = p.completed;
      this.sweepInfo.textContent = `${p.completed} / ${p.total} runs`;
      if (p.item) {
        this.sweepRows.push(p.item as SweepItem);
        this.sweepPlot.render(this.sweepRows);
        b.sweepCsv.disabled = false;
      }
    });
    this.sweepRun = handle;
    try {
      const info = await handle.started;
      this.sweepInfo.textContent = `0 / ${info.total} runs`;
      await handle.done;
      const best = [...this.sweepRows].sort((x, y) => (x.truth_mean ?? x.contour_mean ?? Infinity) - (y.truth_mean ?? y.contour_mean ?? Infinity))[0];
      this.sweepInfo.textContent = `done: ${this.sweepRows.length} runs${best ? `; best λ ${best.lambda}, smoothing ${best.smoothing_iterations}, reduction ${best.target_reduction}, spacing ${best.attractor_spacing}` : ''}${leftOut}`;
      this.sweepInfo.dataset.done = '1';
    } catch (e) {
      const err = e as CoreErrorData;
      if (err.code === 'cancelled') this.sweepInfo.textContent = `cancelled after ${this.sweepRows.length} runs`;
      else this.sayError(e, settings.fileName);
    } finally {
      if (this.sweepRun === handle) {
        this.sweepRun = null;
        b.sweepRun.disabled = false;
        b.sweepCancel.disabled = true;
      }
    }
  }

  private downloadCsv(): void {
    if (this.sweepRows.length === 0) return;
    download(sweepCsv(this.sweepRows, this.sweepComment), 'heartmesh-sweep.csv', 'text/csv');
  }

  // ---- messages -------------------------------------------------------------------------------

  /** The contours left out of the file and frame in the Contours panel: out of the lab's rebuilds too, as of the run on screen. */
  private leaveOutNow(): string[] {
    return this.deps.controller.leaveOutNow?.() ?? [];
  }

  /**
   * Said after a leave-one-out or a sweep that left contours out as the Contours panel does (none
   * of them is held out in turn): its figures are of the contours the surface was run with.
   */
  private leftOutNote(): string {
    const n = this.leaveOutNow().length;
    return n > 0 ? `; without the ${n === 1 ? 'contour' : `${n} contours`} you left out in the Contours panel` : '';
  }

  private say(text: string, error = false): void {
    this.message.textContent = text;
    this.message.classList.toggle('error', error);
    this.message.hidden = text === '';
  }

  private sayError(e: unknown, file?: string): void {
    this.say(errorText(e, file), true);
  }

  dispose(): void {
    this.looRun?.handle.cancel();
    this.sweepRun?.cancel();
    this.deps.viewer?.scene.remove(this.truthLayer.group);
    this.truthLayer.dispose();
  }
}

/** How the simulated acquisition departs from ideal planes, for the summary line ('' when ideal). */
function imperfections(spec: AcquisitionSpec): string {
  const parts: string[] = [];
  if (spec.shift_mm) parts.push(`shift ≤ ${spec.shift_mm} mm`);
  if (spec.tilt_deg) parts.push(`tilt ≤ ${spec.tilt_deg}°`);
  if (spec.noise_mm) parts.push(`noise sd ${spec.noise_mm} mm`);
  return parts.length ? ` (${parts.join(', ')}, seed ${spec.seed ?? 0})` : '';
}

/** One line of an error: the file it is about, its line, the message. */
function errorText(e: unknown, file?: string): string {
  const d = (e && typeof e === 'object' && 'message' in e ? e : { message: String(e) }) as CoreErrorData;
  return describeError({ ...d, file: d.file ?? file });
}

/** The acquisition's rows per surface (several truths). */
function surfaceRows(acq: LabAcquisition): HTMLElement[] {
  return acq.surfaces.map((s) =>
    h('li', { 'data-testid': 'lab-acq-surface', 'data-label': s.label ?? '', 'data-sax': s.sax, 'data-lax': s.lax, 'data-points': s.points }, `${s.label ?? 'surface'}: ${s.sax} SAX + ${s.lax} LAX, ${s.points} points`),
  );
}

/** The truths' vertices end to end (to frame them all). */
function concat(parts: readonly Float32Array[]): Float32Array {
  const out = new Float32Array(parts.reduce((n, p) => n + p.length, 0));
  let at = 0;
  for (const p of parts) {
    out.set(p, at);
    at += p.length;
  }
  return out;
}
