// The Function panel's rules (web/src/app/phases.ts, web/src/ui/functionText.ts) and the panel on
// the fake DOM (web/src/ui/FunctionPanel.ts): which phases are measured and how they are named
// (as the CLI's `heartmesh volumes`), the words of a cell, a cavity and the LV mass, the CSV in
// the CLI's columns, and a measurement's life: progress, the summary, stale on a change, Stop,
// an error that leaves the panel usable; over three phases or more, the volume curve.
import { describe, expect, it } from 'vitest';
import type { FunctionSummary, LabBatchInfo, LabProgress, LoadedFile, PhaseItem, PhasesJob, TimeFrames } from '../../web/src/core-client/protocol';
import type { LabBatchHandle } from '../../web/src/core-client/coreClientTypes';
import { phasesOf } from '../../web/src/app/phases';
import { cellText, edEsText, massText, singleTexts, ventricleText, volumesCsv } from '../../web/src/ui/functionText';
import { FunctionPanel, type FunctionContext } from '../../web/src/ui/FunctionPanel';
import type { FakeElement } from './fakeDom';
import { useFakeDocument } from './panelHarness';

const file = (fileName: string, t: Partial<TimeFrames> | null = null): LoadedFile => ({
  fileName, surfaces: ['LV_ENDO'], contours: [], points: new Float32Array(0), landmarks: [], warnings: [],
  timeFrames: t === null ? null : { frames: ['ED', 'ES'], count: 2, read: ['ED'], firsts: ['ED'], chosen: false, leftOut: 10, sequence: true, ...t },
});

const item = (index: number, phase: string, surface: string, volume_ml: number | null, more: Partial<PhaseItem> = {}): PhaseItem => ({
  index, phase, surface, volume_ml, watertight: volume_ml !== null, contour_to_mesh_mean: volume_ml === null ? null : 0.38123456, seconds: 0.5, missing: volume_ml === null ? 'failed' : null, error: null, ...more,
});

const SUMMARY: FunctionSummary = {
  ventricles: [
    { surface: 'RV_ENDO', ed_phase: 'ED', es_phase: 'ES', edv_ml: 180.583, esv_ml: 71.718, sv_ml: 108.865, ef_percent: 60.285, phases_used: 2 },
    { surface: 'LV_ENDO', ed_phase: 'ED', es_phase: 'ES', edv_ml: 173.724, esv_ml: 65.86, sv_ml: 107.864, ef_percent: 62.089, phases_used: 2 },
  ],
  single: [],
  lv_mass: { density_g_per_ml: 1.05, per_phase: [{ phase: 'ED', grams: 134.0 }, { phase: 'ES', grams: 131.6 }], ed_g: 134.0, es_g: 131.6 },
};

describe('the phases measured', () => {
  it('are the frames of the file on screen when it holds a sequence, named by their labels', () => {
    const cine = file('cine.csv', {});
    const plan = phasesOf(cine, [cine, file('other.csv')]);
    expect(plan?.kind).toBe('frames');
    expect(plan?.phases).toEqual([{ name: 'ED', file: 'cine.csv', frame: 'ED' }, { name: 'ES', file: 'cine.csv', frame: 'ES' }]);
    expect(plan?.source).toBe('the 2 frames of cine.csv');
  });

  it('else every open file, named without its extension (whole names where two share one)', () => {
    const open = [file('patient1-ED.csv'), file('GPFile_009.txt'), file('seg.nii.gz'), file('a.csv'), file('a.txt')];
    const plan = phasesOf(open[0], open);
    expect(plan?.kind).toBe('files');
    expect(plan?.phases.map((p) => p.name)).toEqual(['patient1-ED', 'GPFile_009', 'seg', 'a.csv', 'a.txt']);
    expect(plan?.phases.every((p) => p.frame === undefined)).toBe(true);
    expect(plan?.source).toBe('the 5 open files');
  });

  it('leave out the Lab\'s simulated acquisitions: a phantom is no phase of the patient\'s heart', () => {
    const open = [file('patient1-ED.csv'), file('patient1-ES.csv'), file('lab-parametric-LV-8sax-2lax.csv')];
    const simulated = (name: string) => name.startsWith('lab-');
    const plan = phasesOf(open[2], open, simulated);
    expect(plan?.phases.map((p) => p.name)).toEqual(['patient1-ED', 'patient1-ES']);
    expect(plan?.source).toBe('the 2 open files');
    // One patient file beside a simulation: no function to measure.
    expect(phasesOf(open[0], [open[0], open[2]], simulated)).toBeNull();
  });

  it('are none with one phase: one file of one frame, or nothing open', () => {
    expect(phasesOf(file('a.csv'), [file('a.csv')])).toBeNull();
    expect(phasesOf(null, [])).toBeNull();
    // Slices carrying frames of their own (biv-me's GPFile_009 alone): no sequence.
    const one = file('GPFile_009.txt', { frames: ['9', '1'], read: ['9', '1'], firsts: ['9', '1'], sequence: false });
    expect(phasesOf(one, [one])).toBeNull();
  });
});

describe('the words', () => {
  it('of a cell: the volume, or why there is none', () => {
    expect(cellText(item(0, 'ED', 'LV_ENDO', 173.724))).toEqual({ text: '173.7', title: '173.72 ml; 0.5 s' });
    expect(cellText(item(0, 'ED', 'LV_ENDO', null, { missing: 'open', watertight: false })).text).toBe('open');
    expect(cellText(item(0, 'broken', 'LV_EPI', null, { missing: 'absent' }))).toEqual({ text: '–', title: 'broken has no LV_EPI contours' });
    expect(cellText(item(0, 'broken', 'LV_ENDO', null, { error: 'fewer than 2 usable contours' }))).toEqual({ text: 'failed', title: 'fewer than 2 usable contours' });
    expect(cellText(undefined).text).toBe('…');
  });

  it('of a cavity, its phases and the LV mass', () => {
    const lv = SUMMARY.ventricles[1];
    expect(ventricleText(lv)).toBe('LV_ENDO: EDV 173.7 ml · ESV 65.9 ml · SV 107.9 ml · EF 62.1 %');
    expect(edEsText(lv)).toBe('ED: ED · ES: ES');
    expect(massText(SUMMARY, ['LV_ENDO', 'LV_EPI'])).toBe('LV mass 134.0 g at ED · 131.6 g at ES');
    const biv: FunctionSummary = {
      ...SUMMARY,
      lv_mass: { density_g_per_ml: 1.05, per_phase: [{ phase: 'ED', grams: null, why_none: 'LV_EPI encloses the RV cavity: a biventricular epicardium' }, { phase: 'ES', grams: 131.6 }], ed_g: null, es_g: 131.6 },
    };
    expect(massText(biv, [])).toBe('LV mass none at ED (LV_EPI encloses the RV cavity: a biventricular epicardium) · 131.6 g at ES');
    // Without an LV ejection fraction, each phase's own.
    const noLv: FunctionSummary = { ...SUMMARY, ventricles: [SUMMARY.ventricles[0]] };
    expect(massText(noLv, [])).toBe('LV mass 134.0 g in ED · 131.6 g in ES');
    expect(massText({ ...SUMMARY, lv_mass: null }, ['LV_ENDO'])).toBe('No LV mass: it needs LV_ENDO and LV_EPI');
    expect(massText({ ...SUMMARY, lv_mass: null }, ['RV_ENDO'])).toBeNull();
    expect(singleTexts({ ...SUMMARY, single: [{ surface: 'LV_ENDO', volume_ml: 80 }, { surface: 'RV_ENDO', volume_ml: null }] })).toEqual([
      'LV_ENDO: 80.0 ml in the one phase with a closed mesh: no ejection fraction',
      'RV_ENDO: no phase gave a closed mesh, so no volume',
    ]);
  });

  it('the CSV: the CLI\'s columns and number formats, rows in the batch\'s order, names quoted where needed', () => {
    const csv = volumesCsv([item(1, 'a,b', 'LV_EPI', null, { seconds: 0.0004 }), item(0, 'a,b', 'LV_ENDO', 173.7244)]);
    expect(csv).toBe('phase,surface,volume_ml,watertight,contour_to_mesh_mean_mm,seconds\n"a,b",LV_ENDO,173.724,true,0.3812,0.500\n"a,b",LV_EPI,,false,,0.000\n');
  });
});

describe('the panel', () => {
  useFakeDocument();

  function setup() {
    let context: FunctionContext | null = null;
    const listeners: (() => void)[] = [];
    const jobs: PhasesJob[] = [];
    let progress: (p: LabProgress) => void = () => undefined;
    let settle: { started: (i: LabBatchInfo) => void; done: () => void; fail: (e: unknown) => void } | null = null;
    let cancelled = 0;
    const client = {
      measurePhases(job: PhasesJob, onProgress: (p: LabProgress) => void): LabBatchHandle {
        jobs.push(job);
        progress = onProgress;
        let started!: (i: LabBatchInfo) => void;
        let done!: () => void;
        let fail!: (e: unknown) => void;
        const handle: LabBatchHandle = {
          runId: jobs.length,
          started: new Promise((r) => (started = r)),
          done: new Promise((r, j) => ((done = r), (fail = j))),
          cancel: () => {
            cancelled += 1;
            fail({ code: 'cancelled', message: 'the batch was cancelled' });
          },
        };
        settle = { started, done, fail };
        return handle;
      },
    };
    const panel = new FunctionPanel({ context: () => context, onContextChange: (l) => listeners.push(l), client: () => client });
    const root = panel.element as unknown as FakeElement;
    const setContext = (c: FunctionContext | null) => {
      context = c;
      for (const l of listeners) l();
    };
    const tick = () => new Promise((r) => setTimeout(r, 0));
    return { root, setContext, jobs, tick, progress: (p: LabProgress) => progress(p), settle: () => settle!, cancelled: () => cancelled };
  }

  const plan = phasesOf(file('patient1-ED.csv'), [file('patient1-ED.csv'), file('patient1-ES.csv')])!;
  const context = (settingsKey = 's1', phasesKey = 'p1'): FunctionContext => ({ plan, params: { iterations: 250 }, lids: 'auto', options: {} as FunctionContext['options'], phasesKey, settingsKey });

  it('is hidden without two phases; measures with the current settings; shows the cells as they come and the summary', async () => {
    const p = setup();
    expect(p.root.hidden).toBe(true);
    p.setContext(context());
    expect(p.root.hidden).toBe(false);
    expect(p.root.dataset.state).toBe('idle');
    p.root.byTestId('function-measure')!.fire('click');
    expect(p.jobs[0]).toEqual({ kind: 'phases', phases: plan.phases, params: { iterations: 250 }, lids: 'auto', options: {} });
    expect(p.root.dataset.state).toBe('measuring');
    p.settle().started({ total: 4, phases: ['patient1-ED', 'patient1-ES'], surfaces: ['LV_EPI', 'LV_ENDO'] });
    await p.tick();
    p.progress({ completed: 1, total: 4, item: item(0, 'patient1-ED', 'LV_EPI', 301.3) });
    expect(p.root.byTestId('function-progress')!.textContent).toBe('1 / 4');
    const cells = () => p.root.findAll((e) => e.tagName === 'td').map((td) => `${td.dataset.phase} ${td.dataset.surface} ${td.textContent}`);
    // Columns in the Surface menu's order; cells not measured yet say so.
    expect(cells()).toEqual(['patient1-ED LV_ENDO …', 'patient1-ED LV_EPI 301.3', 'patient1-ES LV_ENDO …', 'patient1-ES LV_EPI …']);
    p.progress({ completed: 2, total: 4, item: item(1, 'patient1-ED', 'LV_ENDO', 173.7) });
    p.progress({ completed: 3, total: 4, item: item(2, 'patient1-ES', 'LV_EPI', 191.2) });
    p.progress({ completed: 4, total: 4, item: item(3, 'patient1-ES', 'LV_ENDO', 65.9), summary: SUMMARY });
    p.settle().done();
    await p.tick();
    expect(p.root.dataset.state).toBe('done');
    expect(p.root.byTestId('function-stop')!.hidden).toBe(true);
    const lines = p.root.findAll((e) => e.dataset.testid === 'function-ventricle');
    expect(lines.map((l) => l.dataset.surface)).toEqual(['LV_ENDO', 'RV_ENDO']);
    expect(lines[0].dataset.ef).toBe('62.089');
    expect(p.root.byTestId('function-mass')!.textContent).toBe('LV mass 134.0 g at ED · 131.6 g at ES');
    expect(p.root.byTestId('function-mass')!.dataset.edG).toBe('134');
    expect(p.root.byTestId('function-curve'), 'two phases: no curve').toBeUndefined();

    // Another setting: stale, and current again when it comes back; other phases: stale too.
    p.setContext(context('s2'));
    expect([p.root.dataset.stale, p.root.byTestId('function-stale')!.textContent]).toEqual(['1', 'parameters changed — measure again']);
    p.setContext(context('s1'));
    expect([p.root.dataset.stale, p.root.byTestId('function-stale')!.hidden]).toEqual(['0', true]);
    p.setContext(context('s1', 'p2'));
    expect(p.root.byTestId('function-stale')!.textContent).toBe('the open phases changed — measure again');
  });

  it('says what the Contours panel left out and sends each phase its list, another surface\'s ids with it', () => {
    const p = setup();
    p.setContext(context());
    const note = p.root.byTestId('function-left-out')!;
    expect(note.hidden).toBe(true);
    const phases = [{ ...plan.phases[0], leave_out: ['s07_LAX_LV_ENDOCARDIAL', 's02_SAX_RV_ENDOCARDIAL'] }, plan.phases[1]];
    const leftOutNote = 'Left out, as in the Contours panel: 2 contours (patient1-ED.csv: s07_LAX_LV_ENDOCARDIAL, s02_SAX_RV_ENDOCARDIAL)';
    p.setContext({ ...context('s2'), plan: { ...plan, phases }, leftOutNote });
    expect([note.hidden, note.textContent]).toEqual([false, leftOutNote]);
    p.root.byTestId('function-measure')!.fire('click');
    expect(p.jobs[0].phases.map((ph) => [ph.name, ph.leave_out])).toEqual([['patient1-ED', ['s07_LAX_LV_ENDOCARDIAL', 's02_SAX_RV_ENDOCARDIAL']], ['patient1-ES', undefined]]);
    p.setContext(context());
    expect(note.hidden).toBe(true);
  });

  it('draws each cavity\'s volume over three phases or more, a failed phase a gap in its line, greyed when stale', async () => {
    const p = setup();
    const cine = file('cine.csv', { frames: ['0', '1', '2'], count: 3 });
    const frames = { ...context(), plan: phasesOf(cine, [cine])! };
    p.setContext(frames);
    p.root.byTestId('function-measure')!.fire('click');
    p.settle().started({ total: 6, phases: ['0', '1', '2'], surfaces: ['LV_EPI', 'LV_ENDO'] });
    await p.tick();
    const volumes = [[301.3, 173.7], [250.1, null], [191.2, 65.9]];
    volumes.forEach(([epi, endo], i) => {
      p.progress({ completed: 2 * i + 1, total: 6, item: item(2 * i, String(i), 'LV_EPI', epi) });
      p.progress({ completed: 2 * i + 2, total: 6, item: item(2 * i + 1, String(i), 'LV_ENDO', endo), summary: i === 2 ? { ...SUMMARY, ventricles: [{ ...SUMMARY.ventricles[1], ed_phase: '0', es_phase: '2' }] } : undefined });
      if (i < 2) expect(p.root.byTestId('function-curve'), 'no curve before the summary names the cavities').toBeUndefined();
    });
    p.settle().done();
    await p.tick();
    const svg = p.root.byTestId('function-curve')!;
    expect(svg.parentElement!.hidden).toBe(false);
    // The cavity only (no LV_EPI line), its dots where it has a volume: phase 1 failed, so no line joins 0 and 2.
    const dots = svg.findAll((e) => e.tagName === 'circle' && e.dataset.ml !== undefined).map((c) => `${c.dataset.surface} ${c.dataset.phase} ${c.dataset.ml}`);
    expect(dots).toEqual(['LV_ENDO 0 173.7', 'LV_ENDO 2 65.9']);
    expect(svg.findAll((e) => e.tagName === 'polyline')).toHaveLength(0);
    expect(svg.findAll((e) => e.tagName === 'title').map((t) => t.textContent)).toContain('2 · LV_ENDO 65.9 ml');
    expect(svg.findAll((e) => e.dataset.testid === 'function-curve-marker').map((r) => `${r.dataset.kind} ${r.dataset.phase}`)).toEqual(['ED 0', 'ES 2']);
    p.setContext({ ...frames, settingsKey: 's2' });
    // Greyed with the table (styles.css: .function.is-stale), not taken away.
    expect(p.root.classList.contains('is-stale')).toBe(true);
    expect(p.root.byTestId('function-curve')!.parentElement!.hidden).toBe(false);
  });

  it('Stop keeps the cells measured so far; an error says why and the panel measures again', async () => {
    const p = setup();
    p.setContext(context());
    p.root.byTestId('function-measure')!.fire('click');
    p.settle().started({ total: 4, phases: ['patient1-ED', 'patient1-ES'], surfaces: ['LV_EPI', 'LV_ENDO'] });
    await p.tick();
    p.progress({ completed: 1, total: 4, item: item(0, 'patient1-ED', 'LV_EPI', 301.3) });
    p.root.byTestId('function-stop')!.fire('click');
    await p.tick();
    expect(p.cancelled()).toBe(1);
    expect(p.root.dataset.state).toBe('stopped');
    expect(p.root.byTestId('function-progress')!.textContent).toBe('1 / 4 (stopped)');
    expect(p.root.findAll((e) => e.tagName === 'td').map((td) => td.textContent)).toEqual(['…', '301.3', '…', '…']);
    expect(p.root.byTestId('function-csv')!.hidden).toBe(false);

    p.root.byTestId('function-measure')!.fire('click');
    p.settle().fail({ code: 'worker_crashed', message: 'the engine stopped' });
    await p.tick();
    expect(p.root.dataset.state).toBe('error');
    expect(p.root.byTestId('function-error')!.textContent).toBe('Not measured: the engine stopped');
    p.root.byTestId('function-measure')!.fire('click');
    expect(p.jobs).toHaveLength(3);
    expect(p.root.dataset.state).toBe('measuring');
  });
});
