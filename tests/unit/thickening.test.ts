// The LV wall's systolic thickening in the Function panel (web/src/io/export/thickening.ts, the
// pure part; web/src/ui/ThickeningView.ts, the view): the Thickening CSV (the wall's `#` header
// with the ED and ES phases' files, the phases and the septum's source, the columns of
// `volumes --json`'s segments, a segment without wall left empty), the files' names, the caption,
// the tooltip and the note; and on the fake DOM, the panel's life: the bullseye shown once the
// summary has `wall_thickening` (imported with its own id prefix, not again on each render), its
// two buttons saving the core's SVG text as it is and the CSV, the note alone when the core
// measured none, nothing without LV_EPI; greyed with the table when stale and gone when the table's
// measurement is replaced. The SVG's import (DOMParser, a real DOM) is the e2e test's
// (function-thickening.test.mjs): here it is a stand-in that records what it was given
// (bullseyeFixtures.ts, shared with wallSegments.test.ts).
import { afterEach, beforeEach, describe, expect, it, vi } from 'vitest';
import type { FunctionSummary, LabBatchInfo, LabProgress, LoadedFile, PhasesJob, WallThickening } from '../../web/src/core-client/protocol';
import { DEFAULT_OPTIONS } from '../../web/src/core-client/protocol';
import type { LabBatchHandle } from '../../web/src/core-client/coreClientTypes';
import { phasesOf, type PhasePlan } from '../../web/src/app/phases';
import { wallHeaderLines } from '../../web/src/io/export/wall';
import {
  THICKENING_CSV_COLUMNS, noThickeningText, phasesBaseName, septumText, thickeningCaption, thickeningCsvFileName, thickeningHeaderLines, thickeningSvgFileName,
  thickeningTitle, writeThickeningCsv, type ThickeningProvenance,
} from '../../web/src/io/export/thickening';
import { AHA_NAMES, BULLSEYE_SVG, svgStandIn } from './bullseyeFixtures';
import { FakeElement, fakeDocument } from './fakeDom';

const saved: { data: unknown; name: string; type: string }[] = [];
vi.mock('../../web/src/io/download', () => ({
  download: (data: unknown, name: string, type: string) => saved.push({ data, name, type }),
}));
vi.mock('../../web/src/io/svgImport', () => import('./bullseyeFixtures').then((f) => ({ importSvg: f.svgStandIn.importSvg })));
const { FunctionPanel } = await import('../../web/src/ui/FunctionPanel');
type FunctionContext = import('../../web/src/ui/FunctionPanel').FunctionContext;

/** Patient 1 ED -> ES as the core measures it (segments 1 and 2 its figures, the others made up). */
const THICKENING: WallThickening = {
  ed_phase: 'patient1-ED',
  es_phase: 'patient1-ES',
  septum_from: ["the RV contours' centre (934)", "the RV contours' centre (622)"],
  mean_percent: 60.199734308283624,
  segments: AHA_NAMES.map((name, i) => ({ id: i + 1, name, ed_mm: 6 + i / 10, es_mm: 9 + i / 10, thickening_percent: 50 + i })),
};
THICKENING.segments[0] = { id: 1, name: 'basal anterior', ed_mm: 7.024500510186829, es_mm: 11.710879449943077, thickening_percent: 66.71476403140876 };
THICKENING.segments[1] = { id: 2, name: 'basal anteroseptal', ed_mm: 12.3213017485221, es_mm: 15.403272069307482, thickening_percent: 25.013349917796265 };

const NOTE = 'LV_EPI encloses the RV cavity: a biventricular epicardium';

const file = (fileName: string, frames: string[] | null = null): LoadedFile => ({
  fileName, surfaces: ['LV_ENDO', 'LV_EPI'], contours: [], points: new Float32Array(0), landmarks: [], warnings: [],
  timeFrames: frames === null ? null : { frames, count: frames.length, read: [frames[0]], firsts: [frames[0]], chosen: false, leftOut: 0, sequence: true },
});
const twoFiles: PhasePlan = phasesOf(file('patient1-ED.csv'), [file('patient1-ED.csv'), file('patient1-ES.csv')])!;
const cineFile = file('cine 1.csv', ['ED', 'mid', 'ES']);
const cine: PhasePlan = phasesOf(cineFile, [cineFile])!;

const provenance = (plan: PhasePlan, more: Partial<ThickeningProvenance> = {}): ThickeningProvenance => ({
  plan, params: { iterations: 250, beta: 0.1 }, lids: 'auto', options: { ...DEFAULT_OPTIONS }, appVersion: '0.1.0', coreVersion: '0.2.0', ...more,
});

describe('the Thickening CSV', () => {
  it('has the wall files\' header of the ED and ES files, the phases, the septum, the columns and one row per segment', () => {
    const p = provenance(twoFiles);
    const header = thickeningHeaderLines(THICKENING, p);
    const wall = wallHeaderLines({ appVersion: '0.1.0', coreVersion: '0.2.0', fileName: 'patient1-ED.csv, patient1-ES.csv', surface: null, lids: 'auto', options: { ...DEFAULT_OPTIONS }, params: { iterations: 250, beta: 0.1 } }, 'LV_ENDO', 'LV_EPI', 1);
    expect(header.slice(0, wall.length)).toEqual(wall);
    expect(header[0]).toBe('heartmesh 0.1.0 (core 0.2.0), units: mm');
    expect(header[1]).toBe('input: patient1-ED.csv, patient1-ES.csv surface: LV_ENDO + LV_EPI');
    expect(header[2]).toMatch(/^lids: auto iterations=250 beta=0\.1 smoothing_method=/);
    expect(header[3]).toBe('min_thickness=1 mm (endocardial vertices closer to the epicardium moved under it)');
    expect(header.slice(wall.length)).toEqual([
      "thickening: 100 x (ES - ED) / ED of each segment's mean wall thickness; ED patient1-ED (patient1-ED.csv), ES patient1-ES (patient1-ES.csv)",
      "segments: AHA 17, septum from the RV contours' centre (934) at ED, the RV contours' centre (622) at ES",
    ]);

    const lines = writeThickeningCsv(THICKENING, header).split('\n');
    expect(lines.slice(0, header.length)).toEqual(header.map((l) => `# ${l}`));
    expect(lines[header.length]).toBe(THICKENING_CSV_COLUMNS);
    expect(THICKENING_CSV_COLUMNS).toBe('segment,name,ed_mm,es_mm,thickening_percent');
    const rows = lines.slice(header.length + 1);
    expect(rows).toHaveLength(18);
    expect(rows.at(-1)).toBe('');
    expect(rows[0]).toBe('1,basal anterior,7.0245,11.7109,66.71');
    expect(rows[1]).toBe('2,basal anteroseptal,12.3213,15.4033,25.01');
    expect(rows[16]).toBe('17,apex,7.6000,10.6000,66.00');
    expect(rows.slice(0, 17).map((r) => Number(r.split(',')[0]))).toEqual(AHA_NAMES.map((_, i) => i + 1));
  });

  it('leaves a segment without wall empty (missing, not 0), quotes a name with a comma, keeps a header line one line', () => {
    const odd = structuredClone(THICKENING);
    odd.segments[16] = { id: 17, name: 'apex, cap', ed_mm: 4.2, es_mm: null, thickening_percent: null };
    odd.segments[15] = { id: 16, name: 'apical lateral', ed_mm: 5, es_mm: 4, thickening_percent: -20 };
    const csv = writeThickeningCsv(odd, ['a\nb']).split('\n');
    expect(csv[0]).toBe('# a b');
    expect(csv.at(-3)).toBe('16,apical lateral,5.0000,4.0000,-20.00');
    expect(csv.at(-2)).toBe('17,"apex, cap",4.2000,,');
  });

  it('names a sequence\'s frames with their file and frame, the phases\' left-out contours, one septum when both phases say the same; an unknown core version', () => {
    const plan: PhasePlan = { ...cine, phases: cine.phases.map((ph) => (ph.name === 'ES' ? { ...ph, leave_out: ['s1', 's2'] } : ph)) };
    const t: WallThickening = { ...THICKENING, ed_phase: 'ED', es_phase: 'ES', septum_from: ['RV_INSERT landmarks (6)', 'RV_INSERT landmarks (6)'] };
    const header = thickeningHeaderLines(t, provenance(plan, { coreVersion: null }));
    expect(header[0]).toBe('heartmesh 0.1.0 (core unknown), units: mm');
    expect(header[1]).toBe('input: cine 1.csv surface: LV_ENDO + LV_EPI');
    expect(header.slice(-2)).toEqual([
      "thickening: 100 x (ES - ED) / ED of each segment's mean wall thickness; ED ED (cine 1.csv frame ED), ES ES (cine 1.csv frame ES; leave_out=s1,s2)",
      'segments: AHA 17, septum from RV_INSERT landmarks (6)',
    ]);
  });
});

describe('the thickening\'s words and files', () => {
  it('caption: the phases and the mean to a whole percent; none when the core has no mean', () => {
    expect(thickeningCaption(THICKENING)).toBe('LV wall thickening patient1-ED → patient1-ES: mean 60 %');
    expect(thickeningCaption({ ...THICKENING, mean_percent: -0.3 })).toBe('LV wall thickening patient1-ED → patient1-ES: mean 0 %');
    expect(thickeningCaption({ ...THICKENING, mean_percent: null })).toBe('LV wall thickening patient1-ED → patient1-ES');
  });

  it('the septum, the tooltip and the note', () => {
    expect(septumText(THICKENING)).toBe("Septum placed from the RV contours' centre (934 points) at ED, the RV contours' centre (622 points) at ES");
    expect(septumText({ ...THICKENING, septum_from: ['RV_INSERT landmarks (1)', 'RV_INSERT landmarks (1)'] })).toBe('Septum placed from RV_INSERT landmarks (1 point)');
    const title = thickeningTitle(THICKENING).split('\n');
    expect(title).toHaveLength(4);
    expect(title[1]).toMatch(/^ED: patient1-ED, ES: patient1-ES \(the phases of the LV's largest and smallest volume\)/);
    expect(title[2]).toBe(septumText(THICKENING));
    expect(noThickeningText(NOTE)).toBe(`No wall thickening: ${NOTE}`);
    expect(noThickeningText(undefined)).toBe('No wall thickening for these phases');
  });

  it('files: `phases-…` for open files, the sequence\'s file name made safe for its frames', () => {
    expect(phasesBaseName(twoFiles)).toBe('phases');
    expect(thickeningSvgFileName(twoFiles)).toBe('phases-LV_wall-thickening.svg');
    expect(thickeningCsvFileName(twoFiles)).toBe('phases-LV_wall-thickening.csv');
    expect(thickeningCsvFileName(cine)).toBe('cine_1-LV_wall-thickening.csv');
  });
});

describe('the thickening in the Function panel', () => {
  beforeEach(() => {
    vi.stubGlobal('document', fakeDocument);
    saved.length = 0;
    svgStandIn.reset();
  });
  afterEach(() => vi.unstubAllGlobals());

  const SUMMARY: FunctionSummary = {
    ventricles: [{ surface: 'LV_ENDO', ed_phase: 'patient1-ED', es_phase: 'patient1-ES', edv_ml: 173.724, esv_ml: 65.86, sv_ml: 107.864, ef_percent: 62.089, phases_used: 2 }],
    single: [],
    lv_mass: { density_g_per_ml: 1.05, per_phase: [{ phase: 'patient1-ED', grams: 134.0 }, { phase: 'patient1-ES', grams: 131.6 }], ed_g: 134.0, es_g: 131.6 },
  };
  const context = (settingsKey = 's1'): FunctionContext => ({ plan: twoFiles, params: { iterations: 250 }, lids: 'auto', options: { ...DEFAULT_OPTIONS }, phasesKey: 'p1', settingsKey });

  /** A Function panel on the fake DOM whose client answers each measurement with `summaries` in turn. */
  function setup() {
    let ctx: FunctionContext | null = null;
    const listeners: (() => void)[] = [];
    let progress: (p: LabProgress) => void = () => undefined;
    let settle: { started: (i: LabBatchInfo) => void; done: () => void } | null = null;
    const client = {
      measurePhases(_job: PhasesJob, onProgress: (p: LabProgress) => void): LabBatchHandle {
        progress = onProgress;
        let started!: (i: LabBatchInfo) => void;
        let done!: () => void;
        let fail!: (e: unknown) => void;
        const handle: LabBatchHandle = {
          runId: 1,
          started: new Promise((r) => (started = r)),
          done: new Promise((r, j) => ((done = r), (fail = j))),
          cancel: () => fail({ code: 'cancelled', message: 'cancelled' }),
        };
        settle = { started, done };
        return handle;
      },
      schema: () => Promise.resolve({ version: '9.9.9' }),
    };
    const panel = new FunctionPanel({ context: () => ctx, onContextChange: (l) => listeners.push(l), client: () => client });
    const root = panel.element as unknown as FakeElement;
    const setContext = (c: FunctionContext | null) => {
      ctx = c;
      for (const l of listeners) l();
    };
    const tick = () => new Promise((r) => setTimeout(r, 0));
    /** Measure all phases, to its end with `summary` on the last progress. */
    const measure = async (summary: FunctionSummary) => {
      root.byTestId('function-measure')!.fire('click');
      settle!.started({ total: 2, phases: ['patient1-ED', 'patient1-ES'], surfaces: ['LV_ENDO', 'LV_EPI'] });
      await tick();
      progress({ completed: 1, total: 2 });
      expect(root.byTestId('function-thickening')!.hidden, 'nothing before the summary').toBe(true);
      progress({ completed: 2, total: 2, summary });
      settle!.done();
      await tick();
    };
    return { root, setContext, measure, tick };
  }

  it('shows the core\'s bullseye once the summary has it, captioned; saves the SVG as it is and the CSV under its header', async () => {
    const p = setup();
    p.setContext(context());
    const box = p.root.byTestId('function-thickening')!;
    expect(box.hidden).toBe(true);
    await p.measure({ ...SUMMARY, wall_thickening: THICKENING, thickening_svg: BULLSEYE_SVG });
    expect([box.hidden, box.dataset.state]).toEqual([false, 'bullseye']);
    // Under the table and the summary's lines.
    const order = (p.root.children as FakeElement[]).map((c) => c.dataset.testid);
    expect(order.indexOf('function-thickening')).toBeGreaterThan(order.indexOf('function-summary'));
    expect(order.indexOf('function-thickening')).toBeGreaterThan(order.indexOf('function-table'));
    expect(svgStandIn.imported).toEqual([{ text: BULLSEYE_SVG, prefix: 'function-thickening' }]);
    expect(p.root.byTestId('function-thickening-svg')!.children.map((c) => (c as FakeElement).getAttribute('data-from'))).toEqual([BULLSEYE_SVG]);
    expect(p.root.byTestId('function-thickening-caption')!.textContent).toBe('LV wall thickening patient1-ED → patient1-ES: mean 60 %');
    expect(p.root.byTestId('function-thickening-bullseye')!.title).toBe(thickeningTitle(THICKENING));
    expect(p.root.byTestId('function-thickening-note')!.hidden).toBe(true);

    p.root.byTestId('function-thickening-save-svg')!.fire('click');
    expect(saved[0]).toEqual({ data: BULLSEYE_SVG, name: 'phases-LV_wall-thickening.svg', type: 'image/svg+xml' });
    p.root.byTestId('function-thickening-save-csv')!.fire('click');
    const csv = saved[1];
    expect([csv.name, csv.type]).toEqual(['phases-LV_wall-thickening.csv', 'text/csv']);
    // The measurement's settings and the core's version (the client's schema) in its header.
    const header = thickeningHeaderLines(THICKENING, { plan: twoFiles, params: { iterations: 250 }, lids: 'auto', options: { ...DEFAULT_OPTIONS }, appVersion: (await import('../../package.json')).version, coreVersion: '9.9.9' });
    expect(csv.data).toBe(writeThickeningCsv(THICKENING, header));
    expect((csv.data as string).split('\n')[0]).toMatch(/^# heartmesh \S+ \(core 9\.9\.9\), units: mm$/);
    expect((csv.data as string).split('\n')).toContain('1,basal anterior,7.0245,11.7109,66.71');
  });

  it('goes stale with the table (greyed, kept, not imported again), and goes when the table\'s measurement is replaced', async () => {
    const p = setup();
    p.setContext(context());
    await p.measure({ ...SUMMARY, wall_thickening: THICKENING, thickening_svg: BULLSEYE_SVG });
    const box = p.root.byTestId('function-thickening')!;
    p.setContext(context('s2'));
    expect([p.root.dataset.stale, p.root.classList.contains('is-stale')]).toEqual(['1', true]);
    expect([box.hidden, box.dataset.state]).toEqual([false, 'bullseye']);
    p.setContext(context('s1'));
    expect(p.root.dataset.stale).toBe('0');
    expect(svgStandIn.imported, 'the same summary is not imported again on each render').toHaveLength(1);

    // Measure again: gone with the table's cells until the new summary comes.
    p.root.byTestId('function-measure')!.fire('click');
    expect([box.hidden, box.dataset.state]).toEqual([true, undefined]);
    expect(p.root.byTestId('function-thickening-svg')!.children).toHaveLength(0);
    expect(p.root.byTestId('function-thickening-caption')!.textContent).toBe('');
  });

  it('says the core\'s reason when it measured none; nothing at all without LV_EPI; the caption says so when the SVG cannot be shown', async () => {
    const p = setup();
    p.setContext(context());
    const box = p.root.byTestId('function-thickening')!;
    await p.measure({ ...SUMMARY, wall_thickening: null, wall_thickening_note: NOTE });
    expect([box.hidden, box.dataset.state]).toEqual([false, 'note']);
    const note = p.root.byTestId('function-thickening-note')!;
    expect([note.hidden, note.textContent]).toEqual([false, `No wall thickening: ${NOTE}`]);
    expect(p.root.byTestId('function-thickening-bullseye')!.hidden).toBe(true);
    expect(p.root.byTestId('function-thickening-save-svg')!.parentElement!.hidden).toBe(true);
    expect(svgStandIn.imported).toHaveLength(0);

    await p.measure(SUMMARY);
    expect([box.hidden, box.dataset.state]).toEqual([true, undefined]);

    svgStandIn.refuse = true;
    await p.measure({ ...SUMMARY, wall_thickening: THICKENING, thickening_svg: 'not svg' });
    expect(box.dataset.state).toBe('bullseye');
    expect(p.root.byTestId('function-thickening-svg')!.hidden).toBe(true);
    expect(p.root.byTestId('function-thickening-caption')!.textContent).toBe('LV wall thickening patient1-ED → patient1-ES: mean 60 % (the bullseye could not be drawn here; Thickening SVG saves it)');
  });
});
